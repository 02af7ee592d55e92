//! What a timed fit's standard errors allow for beyond the noise: behaviour the model leaves out
//! that the records cannot tell apart from its parameters.
//!
//! A variance estimate from the residuals (white noise, or the block sandwich of
//! [`Correlation`](crate::smooth::fit::Correlation)) sees only the part of a mismatch the model
//! could not absorb. What it absorbs moves the parameters and leaves no trace: records of a
//! first-order-hold actuator fitted with the zero-order hold give every residual at the noise
//! and a₁ half a sample long, 10 to 40 of its standard errors away. So the standard errors
//! also allow, parameter by parameter, for two such effects, from the columns D of
//! [`SmoothProblem::left_out`](super::problem) (the change of the output each makes) and the
//! partitioned normal equations with the Jacobian J at the optimum, B = (JᵀJ)⁻¹ JᵀD:
//!
//! - **the hold**, when the fit was not told it (`--hold`): the records cannot tell the holds
//!   apart (the other hold is nearly a half-sample delay, which a₁ absorbs). The shift −B_hold
//!   of each parameter that the other hold makes, the others refitted, is added in full:
//!   variance += B_hold².
//! - **creep**, a slow lag of the command (time constants 0.03, 0.1 and 0.3 times the longest
//!   record's duration) that no part of the model represents: its coefficients ĉ = S⁻¹ Dᵀr with
//!   S = DᵀD − DᵀJ B (the data's estimate of how much creep there is) and the shift −B ĉ they
//!   make: variance += (B ĉ)² + s² (B S⁻¹ Bᵀ), the square of the shift creep of that size
//!   makes and the variance of estimating it. Records without creep pay about twice the
//!   second term (ĉ is then noise); records with creep get the shift it makes.

use hyst_io::number::sig;
use hyst_model::{Estimate, Hold};

use crate::linalg::spd_inverse;
use crate::smooth::problem::LeftOut;

/// Creep's time constants as fractions of the longest record's duration.
pub const CREEP_TIME_CONSTANTS: [f64; 3] = [0.03, 0.1, 0.3];

/// The most residuals the allowance is computed on: its columns take 8 bytes a residual each.
/// Longer records get no allowance, and the report says so.
pub const MAX_ROWS: usize = 1 << 22;

/// What a fit's standard errors allow for beyond the noise (see the module docs).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Allowance {
    /// The hold the fit was not told and the other hold, with what the other hold moves each
    /// parameter by, the others refitted (parameter name, shift in its units).
    pub hold: Option<(Hold, Vec<(String, f64)>)>,
    /// Creep, one per time constant.
    pub creep: Vec<Creep>,
    /// Whether the records were too long for the allowance ([`MAX_ROWS`]): none was made.
    pub skipped: bool,
}

/// One slow lag of the command the standard errors allow for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Creep {
    /// Its time constant (s).
    pub time_constant: f64,
    /// Its estimated size: output units per command unit of the lag.
    pub coefficient: f64,
    /// The coefficient's standard error.
    pub std_error: f64,
}

/// The variance the allowance adds to each kept parameter (θ units), and each kept parameter's
/// hold shift (θ units, when `hold`), from the products `left` (columns: the hold's first when
/// `hold`, then one per creep time constant), the kept parameters `kept` (indices into θ), the
/// inverse `inv` of JᵀJ on them, the residual variance `s2` and each kept
/// parameter's factor `ratio` (≥ 1) by which correlated residuals widen its variance; and each
/// creep column's coefficient with its standard error.
pub(super) struct Added {
    pub(super) variance: Vec<f64>,
    pub(super) hold: Option<Vec<f64>>,
    pub(super) creep: Vec<(f64, f64)>,
}

/// See [`Added`].
pub(super) fn added(
    left: &LeftOut,
    hold: bool,
    kept: &[usize],
    inv: &[f64],
    s2: f64,
    ratio: &[f64],
) -> Added {
    let q = kept.len();
    let m = left.dtr.len();
    // B = (JᵀJ)⁻¹ JᵀD on the kept rows: q × m.
    let mut b = vec![0.0; q * m];
    for a in 0..q {
        for c in 0..m {
            b[a * m + c] = kept
                .iter()
                .enumerate()
                .map(|(x, &i)| inv[a * q + x] * left.jtd[i * m + c])
                .sum();
        }
    }
    let mut variance = vec![0.0; q];
    let first_creep = usize::from(hold);
    let hold = (hold && m > 0).then(|| {
        let shift: Vec<f64> = (0..q).map(|a| -b[a * m]).collect();
        for (v, s) in variance.iter_mut().zip(&shift) {
            *v += s * s;
        }
        shift
    });
    let creep_columns: Vec<usize> = (first_creep..m).collect();
    let mc = creep_columns.len();
    let mut creep = Vec::new();
    if mc > 0 {
        // S = DᵀD − DᵀJ B on the creep columns (J's kept columns).
        let mut schur = vec![0.0; mc * mc];
        for (x, &c) in creep_columns.iter().enumerate() {
            for (y, &d) in creep_columns.iter().enumerate() {
                let projected: f64 = kept
                    .iter()
                    .enumerate()
                    .map(|(a, &i)| left.jtd[i * m + c] * b[a * m + d])
                    .sum();
                schur[x * mc + y] = left.dtd[c * m + d] - projected;
            }
        }
        if let Some(s_inv) = spd_inverse(&schur, mc) {
            let coef: Vec<f64> = (0..mc)
                .map(|x| {
                    (0..mc)
                        .map(|y| s_inv[x * mc + y] * left.dtr[creep_columns[y]])
                        .sum()
                })
                .collect();
            for a in 0..q {
                let shift: f64 = creep_columns
                    .iter()
                    .zip(&coef)
                    .map(|(&c, k)| b[a * m + c] * k)
                    .sum();
                let mut spread = 0.0;
                for (x, &c) in creep_columns.iter().enumerate() {
                    for (y, &d) in creep_columns.iter().enumerate() {
                        spread += b[a * m + c] * s_inv[x * mc + y] * b[a * m + d];
                    }
                }
                variance[a] += shift * shift + s2 * spread * ratio[a].max(1.0);
            }
            creep = (0..mc)
                .map(|x| (coef[x], (s2 * s_inv[x * mc + x]).max(0.0).sqrt()))
                .collect();
        }
    }
    Added {
        variance,
        hold,
        creep,
    }
}

/// A creep coefficient this many standard errors from 0 is one the records show.
pub const CREEP_SHOWN: f64 = 3.0;

impl Allowance {
    /// The report's note on what the standard errors of `estimates` allow for (`None` when
    /// nothing); the hold's shifts are named for the parameters they widen (a shift above a
    /// third of the standard error).
    #[must_use]
    pub fn note(&self, estimates: &[Estimate]) -> Option<String> {
        if self.skipped {
            return Some(format!(
                "the standard errors allow for the noise only: more than {MAX_ROWS} training \
                 samples are too many for their allowance for the hold and creep"
            ));
        }
        let mut parts = Vec::new();
        if let Some((hold, shifts)) = &self.hold {
            let moved: Vec<String> = shifts
                .iter()
                .filter(|(name, shift)| {
                    estimates
                        .iter()
                        .find(|e| e.name == *name)
                        .is_some_and(|e| shift.abs() > e.std_error / 3.0)
                })
                .map(|(name, shift)| format!("{name} by {}", sig(*shift, 2)))
                .collect();
            if !moved.is_empty() {
                parts.push(format!(
                    "the hold, which the records cannot tell (--hold states it): the {} would \
                     move {}",
                    hold.describe(),
                    moved.join(", ")
                ));
            }
        }
        if !self.creep.is_empty() {
            let shown = self
                .creep
                .iter()
                .any(|c| c.coefficient.abs() > CREEP_SHOWN * c.std_error);
            parts.push(format!(
                "creep, a slow lag of the command the model leaves out (time constants {} s): \
                 {} output units per command unit{}",
                self.creep
                    .iter()
                    .map(|c| sig(c.time_constant, 2))
                    .collect::<Vec<_>>()
                    .join(", "),
                self.creep
                    .iter()
                    .map(|c| format!("{} ± {}", sig(c.coefficient, 2), sig(c.std_error, 2)))
                    .collect::<Vec<_>>()
                    .join(", "),
                if shown {
                    "; the records show creep: its bias is in the standard errors, and \
                     records that start at other levels, or longer ones, tell it from the \
                     offset and the loop"
                } else {
                    ""
                }
            ));
        }
        (!parts.is_empty()).then(|| {
            format!(
                "besides the noise, the standard errors allow for what the records cannot \
                 tell apart from the parameters: {}",
                parts.join("; and ")
            )
        })
    }
}
