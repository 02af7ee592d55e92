//! The standard errors of a smooth fit's parameters, from the covariance at the optimum: the
//! larger, parameter by parameter, of the white-noise estimate cov θ = s² (JᵀJ)⁻¹,
//! s² = Σ r² / (n − p), and the block sandwich (JᵀJ)⁻¹ M (JᵀJ)⁻¹ · G/(G − 1) with M the
//! score's outer product over G blocks ([`Correlation`](crate::smooth::fit::Correlation)),
//! which stays valid when the residuals are correlated; value = f(θ), its standard error
//! |f′(θ)| σ_θ.

use hyst_model::{Estimate, SmoothModel};

use crate::data::Dataset;
use crate::error::FitError;
use crate::layout::Layout;
use crate::linalg::spd_inverse;
use crate::lm::Solution;
use crate::smooth::allowance::{self, Added};
use crate::smooth::allowance::{Allowance, Creep, CREEP_TIME_CONSTANTS, MAX_ROWS};
use crate::smooth::fit::{Correlation, FitOptions, BLOCK_TIMES};
use crate::smooth::limits::{linear_limit_parameters, ParameterLimit};
use crate::smooth::problem::{LeftOut, SmoothProblem, CORRELATION_SAMPLES, MIN_BLOCKS};
use hyst_model::Hold;

/// The parameters with their standard errors at the optimum `best` (`model` the model there),
/// the same with the noise's standard errors alone (what the fit's decisions look at), how
/// those allow for correlated residuals, and, for a timed fit, what else they allow for
/// ([`allowance`](crate::smooth::allowance)).
pub(super) fn estimates_at(
    problem: &SmoothProblem<'_>,
    model: &SmoothModel,
    best: &Solution,
    options: &FitOptions,
) -> Result<EstimatesAt, FitError> {
    let (correlation, meat) = correlation(problem, best)?;
    let timed = model.is_timed();
    let other_hold = match model.dynamics.map(|d| d.hold()) {
        Some(Hold::Zoh) if !options.hold_stated => Some(Hold::Foh),
        Some(Hold::Foh) if !options.hold_stated => Some(Hold::Zoh),
        _ => None,
    };
    let creep: Vec<f64> = longest_duration(problem.data).map_or(Vec::new(), |t| {
        CREEP_TIME_CONSTANTS.iter().map(|f| f * t).collect()
    });
    let skipped = timed && problem.n > MAX_ROWS;
    let left = if timed && !skipped {
        problem.left_out(&best.theta, other_hold, &creep).ok()
    } else {
        None
    };
    let (estimates, statistical, added) = estimates(
        problem.layout,
        model,
        best,
        problem.data.training_samples(),
        meat.as_ref().map(|m| (m.as_slice(), correlation.blocks)),
        left.as_ref().map(|l| (l, other_hold.is_some())),
    );
    let allowance = timed.then(|| {
        let mut a = Allowance {
            skipped,
            ..Allowance::default()
        };
        if let Some(d) = added {
            a.hold = other_hold.zip(d.hold).map(|(h, shifts)| {
                let names = problem.layout.params.iter().map(|p| p.name.clone());
                (h, names.zip(shifts).collect())
            });
            a.creep = creep
                .iter()
                .zip(d.creep)
                .map(|(&time_constant, (coefficient, std_error))| Creep {
                    time_constant,
                    coefficient,
                    std_error,
                })
                .collect();
        }
        a
    });
    Ok((estimates, statistical, correlation, allowance))
}

/// What [`estimates_at`] gives: the parameters with their standard errors, the same with
/// the noise's alone, the correlation, and the allowance.
type EstimatesAt = (
    Vec<hyst_model::Estimate>,
    Vec<hyst_model::Estimate>,
    Correlation,
    Option<Allowance>,
);

/// The duration (s) of the longest history of `data` with a sample period.
fn longest_duration(data: &Dataset) -> Option<f64> {
    data.histories()
        .iter()
        .filter_map(|h| h.period.map(|p| p.nominal() * h.input.len() as f64))
        .fold(None, |m: Option<f64>, t| Some(m.map_or(t, |m| m.max(t))))
}

/// The residuals' correlation at the optimum `best` and the middle of the block sandwich
/// (`None` when the Jacobian cannot be evaluated there): see [`Correlation`].
fn correlation(
    problem: &SmoothProblem<'_>,
    best: &Solution,
) -> Result<(Correlation, Option<Vec<f64>>), FitError> {
    let first = if best.residuals.is_empty() {
        match problem.first_residuals(&best.theta, CORRELATION_SAMPLES) {
            Ok(r) => r,
            Err(_) => return Ok((Correlation::default(), None)),
        }
    } else {
        best.residuals[..best.residuals.len().min(CORRELATION_SAMPLES)].to_vec()
    };
    let time = SmoothProblem::correlation_time(&first);
    let samples = problem.data.training_samples().max(1);
    let wanted = (BLOCK_TIMES * time).ceil().max(1.0) as usize;
    let most = (samples / MIN_BLOCKS).max(1);
    let block = wanted.min(most);
    let Ok((meat, blocks)) = problem.scores(&best.theta, block) else {
        return Ok((Correlation::default(), None));
    };
    Ok((
        Correlation {
            time,
            block,
            blocks,
            capped: wanted > most,
        },
        Some(meat),
    ))
}

/// The parameters of `layout` with their values and standard errors at the optimum `best` of a
/// fit to `n` residuals (`model` is the model at `best.theta`), with the block sandwich's
/// middle `meat` (p × p) over its number of blocks when there is one.
///
/// In a parameter limit (the stop form's Dahl limit, the backlash limit) the unidentified
/// parameter carries no information (its column of J vanishes): the covariance of the others is
/// taken without it, and its standard error is NaN.
fn estimates(
    layout: &Layout,
    model: &SmoothModel,
    best: &Solution,
    n: usize,
    meat: Option<(&[f64], usize)>,
    left: Option<(&LeftOut, bool)>,
) -> (Vec<Estimate>, Vec<Estimate>, Option<Added>) {
    let p = layout.len();
    let dof = (n - p).max(1) as f64;
    let s2 = best.cost / dof * layout.norm.output_half_span.powi(2);
    let unidentified = unidentified(layout, model, &best.theta);
    let (kept, inv) = covariance(layout, &best.jtj, &unidentified);
    let q = kept.len();
    let sandwich = sandwich_diagonal(meat, inv.as_deref(), &kept, p);
    let scale2 = layout.norm.output_half_span.powi(2);
    // Each kept parameter's white-noise variance and the sandwich's (θ units).
    let white: Vec<f64> = (0..q)
        .map(|a| {
            inv.as_ref()
                .map_or(f64::NAN, |inv| inv[a * q + a] * s2 / scale2)
        })
        .collect();
    let robust: Vec<f64> = (0..q)
        .map(|a| sandwich.as_ref().map_or(0.0, |d| d[a]))
        .collect();
    let added = match (left, inv.as_ref()) {
        (Some((left, hold)), Some(inv)) => {
            let ratio: Vec<f64> = white
                .iter()
                .zip(&robust)
                .map(|(w, r)| if *w > 0.0 { r / w } else { 1.0 })
                .collect();
            Some(allowance::added(
                left,
                hold,
                &kept,
                inv,
                s2 / scale2,
                &ratio,
            ))
        }
        _ => None,
    };
    // Each parameter with the standard error of the noise alone, and with the allowance.
    let with = |allow: bool| -> Vec<Estimate> {
        layout
            .params
            .iter()
            .enumerate()
            .map(|(j, spec)| {
                let value = spec.transform.value(best.theta[j]);
                let var = match kept.iter().position(|&k| k == j) {
                    Some(a) => {
                        let extra = match (&added, allow) {
                            (Some(d), true) => d.variance[a],
                            _ => 0.0,
                        };
                        // NaN (not identifiable) stays NaN: NaN.max(x) would hide it.
                        if white[a].is_nan() || robust[a].is_nan() {
                            f64::NAN
                        } else {
                            white[a].max(robust[a]) + extra
                        }
                    }
                    None => f64::NAN,
                };
                let var = if var < 0.0 { 0.0 } else { var };
                Estimate {
                    name: spec.name.clone(),
                    value,
                    std_error: spec.transform.derivative(best.theta[j]).abs() * var.sqrt(),
                    unit: spec.unit.clone(),
                }
            })
            .collect()
    };
    let (estimates, statistical) = (with(true), with(false));
    // The hold's shifts in the parameters' own units.
    let added = added.map(|mut d| {
        if let Some(shift) = d.hold.as_mut() {
            for (s, &j) in shift.iter_mut().zip(&kept) {
                *s *= layout.params[j].transform.derivative(best.theta[j]);
            }
        }
        d
    });
    (estimates, statistical, added)
}

/// The block sandwich's diagonal on the kept parameters `kept` (θ units; the residuals are
/// scaled) from its middle `meat` (p × p) over its number of blocks and `inv`, the inverse of
/// JᵀJ on them; `None` without a middle or with one block.
fn sandwich_diagonal(
    meat: Option<(&[f64], usize)>,
    inv: Option<&[f64]>,
    kept: &[usize],
    p: usize,
) -> Option<Vec<f64>> {
    let q = kept.len();
    match (meat, inv) {
        (Some((m, blocks)), Some(inv)) if blocks > 1 => {
            let correction = blocks as f64 / (blocks - 1) as f64;
            Some(
                (0..q)
                    .map(|a| {
                        let mut v = 0.0;
                        for (x, &i) in kept.iter().enumerate() {
                            for (y, &j) in kept.iter().enumerate() {
                                v += inv[a * q + x] * m[i * p + j] * inv[y * q + a];
                            }
                        }
                        correction * v
                    })
                    .collect(),
            )
        }
        _ => None,
    }
}

/// The parameters the data cannot identify at θ (`model` is the model there): those a parameter
/// limit leaves unidentified ([`ParameterLimit::unidentified`]), and those of a saturating shape
/// at its linear limit.
fn unidentified(layout: &Layout, model: &SmoothModel, theta: &[f64]) -> Vec<&'static str> {
    let mut unidentified: Vec<&str> = ParameterLimit::of(model)
        .map_or(&[][..], ParameterLimit::unidentified)
        .to_vec();
    // A saturating shape at its linear limit (the fallback of the fit, or a start from a
    // contained fit that ended there) is a line on the data: its scale and its argument at the
    // centre have no effect there (their columns of J vanish).
    unidentified.extend(linear_limit_parameters(layout, theta));
    unidentified
}

/// The parameters that get a standard error (indices into θ, in order) and the inverse of the
/// p × p matrix `jtj` (JᵀJ) on their rows and columns; the inverse is `None` when no such set
/// makes it invertible. The parameters named `unidentified` are left out; when the rest is
/// singular, so are the parameters whose removal makes it invertible.
fn covariance(
    layout: &Layout,
    jtj: &[f64],
    unidentified: &[&str],
) -> (Vec<usize>, Option<Vec<f64>>) {
    let p = layout.len();
    let mut kept: Vec<usize> = (0..p)
        .filter(|&j| !unidentified.contains(&layout.params[j].name.as_str()))
        .collect();
    let mut inv = reduced_inverse(jtj, p, &kept);
    if inv.is_none() {
        // Singular: the parameters whose removal makes it invertible span the direction the
        // data does not see; they get NaN, the others their standard errors without them.
        let lost: Vec<usize> = kept
            .iter()
            .copied()
            .filter(|&j| {
                let without: Vec<usize> = kept.iter().copied().filter(|&k| k != j).collect();
                reduced_inverse(jtj, p, &without).is_some()
            })
            .collect();
        if let Some(&first) = lost.first() {
            let without: Vec<usize> = kept.iter().copied().filter(|&k| k != first).collect();
            inv = reduced_inverse(jtj, p, &without);
            kept = without.into_iter().filter(|k| !lost.contains(k)).collect();
            // Standard errors of the kept ones come from the matrix without `first` only.
            let with_first_removed: Vec<usize> = (0..p)
                .filter(|&j| j != first && !unidentified.contains(&layout.params[j].name.as_str()))
                .collect();
            inv = inv.map(|full| restrict(&full, &with_first_removed, &kept));
        }
    }
    (kept, inv)
}

/// The rows and columns `kept` (indices into θ) of the matrix `full`, whose rows and columns
/// are the parameters `rows` (indices into θ, in order); NaN where a kept one is not among
/// them.
fn restrict(full: &[f64], rows: &[usize], kept: &[usize]) -> Vec<f64> {
    let q = rows.len();
    let mut out = vec![f64::NAN; kept.len() * kept.len()];
    for (a, &i) in kept.iter().enumerate() {
        for (b, &j) in kept.iter().enumerate() {
            let (Some(x), Some(y)) = (
                rows.iter().position(|&k| k == i),
                rows.iter().position(|&k| k == j),
            ) else {
                continue;
            };
            out[a * kept.len() + b] = full[x * q + y];
        }
    }
    out
}

/// The inverse of the rows and columns `kept` of the p × p matrix `a`.
fn reduced_inverse(a: &[f64], p: usize, kept: &[usize]) -> Option<Vec<f64>> {
    let q = kept.len();
    let mut reduced = vec![0.0; q * q];
    for (x, &i) in kept.iter().enumerate() {
        for (y, &j) in kept.iter().enumerate() {
            reduced[x * q + y] = a[i * p + j];
        }
    }
    spd_inverse(&reduced, q)
}
