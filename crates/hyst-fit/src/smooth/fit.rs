//! What a smooth fit takes and gives: its options ([`FitOptions`]) and its result
//! ([`SmoothFit`]).

use crate::smooth::allowance::Allowance;
use hyst_model::{ErrorStats, Estimate, FamilyWidths, SmoothModel};

use crate::layout::Layout;
use crate::lm::{LevenbergMarquardt, Termination};
use crate::timed::TimedFindings;

/// Options of the fit.
#[derive(Clone, Copy, Debug)]
pub struct FitOptions {
    /// Number of starts refined by the least-squares method, at least 1: the best of a grid over
    /// (k1, k2), and for a richer structure first the optimum of the simpler one it contains
    /// ([`simpler`](crate::smooth::simpler)), which counts as one of them.
    pub starts: usize,
    /// The method.
    pub method: LevenbergMarquardt,
    /// Coverage for the family widths (fraction of samples inside the envelope), in (0, 1].
    pub coverage: f64,
    /// Compute family widths (a few hundred extra simulations).
    pub widths: bool,
    /// Estimate each history's initial state (a record, or a record cut into segments) from its
    /// data instead of the start rule: a reversal at its first sample with the operator output
    /// anywhere in the band ([`SmoothModel::simulate_from`]), chosen by least squares for every
    /// trial of the parameters (variable projection). The start rule stays the model's rule for
    /// new data.
    pub estimate_starts: bool,
    /// Count every sample from each record's first in a fit with dynamics or a rate term,
    /// trusting the start rule (and the plant at rest there); by default each record's start
    /// is discounted until its input has swept its range ([`crate::settling`]).
    pub fit_from_start: bool,
    /// Pick the plant order (`--dynamics auto`): [`crate::identify`] fits orders 0, 1, … up to
    /// [`crate::timed::MAX_AUTO_ORDER`] (with the structure's rate term) and keeps the one the
    /// validation records, or else an information criterion, prefer; the structure's own
    /// `dynamics` is then ignored.
    pub auto_dynamics: bool,
    /// Whether the caller stated the plant's hold (`--hold`): a timed fit's standard errors
    /// then make no allowance for the other hold ([`crate::smooth::allowance`]).
    pub hold_stated: bool,
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            starts: 3,
            method: LevenbergMarquardt::default(),
            coverage: 0.99,
            widths: true,
            estimate_starts: false,
            fit_from_start: false,
            auto_dynamics: false,
            hold_stated: false,
        }
    }
}

/// A fitted smooth model with everything the report needs.
#[derive(Clone, Debug)]
pub struct SmoothFit {
    /// The model.
    pub model: SmoothModel,
    /// The structure and its parameters.
    pub layout: Layout,
    /// θ at the optimum.
    pub theta: Vec<f64>,
    /// Parameters with standard errors (the noise's and the [`allowance`](Self::allowance)).
    pub estimates: Vec<Estimate>,
    /// The same with the noise's standard errors alone (white noise or the block sandwich):
    /// what the fit's decisions on support, identification and degeneracy look at, since the
    /// allowance widens what the records cannot pin down, not whether a part is there.
    pub statistical: Vec<Estimate>,
    /// Errors on the training records.
    pub training: ErrorStats,
    /// Errors on the validation records (`None` without validation records).
    pub validation: Option<ErrorStats>,
    /// Family widths and the bound Δa.
    pub widths: Option<FamilyWidths>,
    /// Iterations of the best start.
    pub iterations: usize,
    /// Why the best start stopped.
    pub termination: Termination,
    /// The estimated start of each history ([`Dataset::histories`](crate::data::Dataset::histories)) as a band fraction in
    /// [−1, 1] ([`SmoothModel::simulate_from`]); `None` when the start rule was used.
    pub starts: Option<Vec<f64>>,
    /// Wall time of the fit (s).
    pub seconds: f64,
    /// What the fit found of its plant and rate term (a structure with dynamics or a rate
    /// term; [`crate::timed`]).
    pub timed: Option<TimedFindings>,
    /// How the standard errors allow for correlated residuals.
    pub correlation: Correlation,
    /// What a timed fit's standard errors allow for beyond the noise (`None`: a static fit).
    pub allowance: Option<Allowance>,
}

/// How a fit's standard errors allow for correlated residuals: each is the larger of the
/// white-noise estimate s² (JᵀJ)⁻¹ and the block sandwich (JᵀJ)⁻¹ (Σ_b s_b s_bᵀ) (JᵀJ)⁻¹ with
/// the score s_b = Σ J_kᵀ r_k over blocks of consecutive residuals of one history, long against
/// the residuals' correlation time (batch means; with uncorrelated residuals it is White's
/// heteroskedasticity-consistent estimate).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Correlation {
    /// The residuals' integrated correlation time (samples, ≥ 1).
    pub time: f64,
    /// The block length (samples).
    pub block: usize,
    /// The blocks the score was summed over.
    pub blocks: usize,
    /// Whether the block had to be cut short of [`BLOCK_TIMES`] correlation times to keep
    /// enough blocks: the standard errors are then lower bounds.
    pub capped: bool,
}

/// The block length of [`Correlation`] in units of the residuals' correlation time.
pub const BLOCK_TIMES: f64 = 5.0;
