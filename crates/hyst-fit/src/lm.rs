//! Nonlinear least squares: the problem (residuals and Jacobian), the method (a Levenberg–
//! Marquardt with infeasible-step rejection) and observers (progress, cancellation), kept
//! apart in the manner of argmin.
//!
//! Bounds are handled in two ways that compose: positive parameters are optimised as their
//! logarithm (so k1, k2, gains stay > 0), and any other constraint (a monotone shaping
//! function, a positive k2 law on the data) makes the problem report the point infeasible; the
//! method then rejects the step and increases the damping, so it never leaves the feasible set.

use std::ops::ControlFlow;

use crate::error::FitError;
use crate::gauss_newton::{
    damped_step, fading, negligible_gain, predicted_decrease, relative_offset,
};

/// A point the problem cannot evaluate (parameters outside their bounds).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Infeasible;

/// A least-squares problem: minimise Σ r_i(θ)².
pub trait Problem {
    /// Number of parameters.
    fn parameters(&self) -> usize;
    /// Number of residuals.
    fn residual_count(&self) -> usize;
    /// The residuals at θ into `r` (length [`Problem::residual_count`]).
    ///
    /// # Errors
    /// [`Infeasible`] when θ is outside the feasible set.
    fn residuals(&self, theta: &[f64], r: &mut [f64]) -> Result<(), Infeasible>;
    /// The Jacobian at θ, column-major (`jac[j * n + i]` = ∂r_i/∂θ_j), given r at θ.
    ///
    /// # Errors
    /// [`Infeasible`] if it cannot be evaluated.
    fn jacobian(&self, theta: &[f64], r: &[f64], jac: &mut [f64]) -> Result<(), Infeasible>;

    /// JᵀJ (row-major, p × p) and g = Jᵀr at θ, whose residuals are `r`. The provided method
    /// stores the Jacobian ([`Problem::jacobian`], n × p numbers) and sums each entry over the
    /// rows in order; a problem with many residuals may accumulate the same sums in one pass
    /// without it.
    ///
    /// # Errors
    /// [`Infeasible`] as [`Problem::jacobian`].
    fn normal_equations(
        &self,
        theta: &[f64],
        r: &[f64],
        jtj: &mut [f64],
        g: &mut [f64],
    ) -> Result<(), Infeasible> {
        jacobian_normal_equations(self, theta, r, jtj, g)
    }

    /// Whether the method keeps the residual vectors (the point's and a trial's, n numbers
    /// each) or asks for their sums only ([`Problem::cost`], [`Problem::sums_at`]): a problem
    /// with many residuals may say no (8 bytes a residual less, twice); its
    /// [`Solution::residuals`] are then empty.
    fn keeps_residuals(&self) -> bool {
        true
    }

    /// Σ r² at θ, as the sum of [`Problem::residuals`] in order. The provided method stores
    /// them; a problem that keeps no residuals sums them as it computes them.
    ///
    /// # Errors
    /// [`Infeasible`] as [`Problem::residuals`].
    fn cost(&self, theta: &[f64]) -> Result<f64, Infeasible> {
        let mut r = vec![0.0; self.residual_count()];
        self.residuals(theta, &mut r)?;
        Ok(sum_sq(&r))
    }

    /// JᵀJ and g = Jᵀr at θ ([`Problem::normal_equations`]) with the residuals computed on
    /// the way, for a problem that keeps none. The provided method stores them.
    ///
    /// # Errors
    /// [`Infeasible`] as [`Problem::normal_equations`].
    fn sums_at(&self, theta: &[f64], jtj: &mut [f64], g: &mut [f64]) -> Result<(), Infeasible> {
        stored_sums(self, theta, jtj, g)
    }
}

/// [`Problem::sums_at`] from stored residuals: [`Problem::residuals`] into a vector, then
/// [`Problem::normal_equations`].
///
/// # Errors
/// [`Infeasible`] as those.
pub fn stored_sums<P: Problem + ?Sized>(
    problem: &P,
    theta: &[f64],
    jtj: &mut [f64],
    g: &mut [f64],
) -> Result<(), Infeasible> {
    let mut r = vec![0.0; problem.residual_count()];
    problem.residuals(theta, &mut r)?;
    problem.normal_equations(theta, &r, jtj, g)
}

/// The stage of a fit a [`Progress`] belongs to (what `hyst fit` shows on a terminal).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Stage {
    /// The search for the optimum: multi-start descents (on a long record's reduction), the
    /// nested fits of simpler structures they start from.
    #[default]
    Search,
    /// The descent on the full data from the search's optimum.
    Polish,
    /// The search for the family widths (Δk1, Δk2) that cover the data.
    Widths,
}

/// What an observer sees after each accepted (or final) iteration.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    /// Iteration number (0 is the starting point), or step of the width search.
    pub iteration: usize,
    /// The method's limit on iterations (`usize::MAX` when it has none).
    pub max_iterations: usize,
    /// Σ r² at the current point (NaN in the width search).
    pub cost: f64,
    /// The damping λ (NaN in the width search).
    pub lambda: f64,
    /// Which start of a multi-start fit (0-based; 0 for a single run; `usize::MAX` in the width
    /// search).
    pub start: usize,
    /// How many starts the multi-start fit runs (1 for a single run).
    pub starts: usize,
    /// How many of them have ended.
    pub finished: usize,
    /// The stage.
    pub stage: Stage,
}

impl Progress {
    /// The fraction of the stage done, in [0, 1]: the starts ended plus the running one's
    /// iterations over its limit (an upper bound on the work left: a descent usually ends
    /// earlier); the width search's steps over its usual count.
    #[must_use]
    pub fn fraction(&self) -> f64 {
        let part = |done: usize, of: usize| {
            if of == 0 || of == usize::MAX {
                0.0
            } else {
                (done as f64 / of as f64).min(1.0)
            }
        };
        let f = match self.stage {
            Stage::Widths => part(self.iteration, WIDTH_STEPS),
            Stage::Search | Stage::Polish => {
                let starts = self.starts.max(1);
                (self.finished.min(starts) as f64 + part(self.iteration, self.max_iterations))
                    / starts as f64
            }
        };
        f.clamp(0.0, 1.0)
    }
}

/// The most steps of a width search (five rays, each one step and a bisection of ten), after
/// which the confirmation's steps are counted.
pub const WIDTH_SEARCH_STEPS: usize = 55;

/// The scale of [`Progress::fraction`] for [`Stage::Widths`]: the search's steps and about 15 of
/// the confirmation (fewer when rays end early: the fraction then jumps ahead at the
/// confirmation, never back).
pub const WIDTH_STEPS: usize = WIDTH_SEARCH_STEPS + 15;

/// Passes progress on to `inner` as progress of `stage` (a stage of an outer fit holds the
/// stages of the fits nested in it).
pub struct Staged<'a> {
    /// Where the progress goes.
    pub inner: &'a mut dyn Observer,
    /// The stage it is tagged with.
    pub stage: Stage,
}

impl Observer for Staged<'_> {
    fn observe(&mut self, progress: &Progress) -> ControlFlow<()> {
        self.inner.observe(&Progress {
            stage: self.stage,
            ..*progress
        })
    }
}

/// Watches the iterations; returning `ControlFlow::Break` stops the method (Ctrl-C).
pub trait Observer {
    /// Called at the start and after every iteration.
    fn observe(&mut self, progress: &Progress) -> ControlFlow<()>;
}

/// An observer that does nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Observer for Silent {
    fn observe(&mut self, _progress: &Progress) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}

/// Why the method stopped (stopping is not an error).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Termination {
    /// The relative step fell below the tolerance.
    SmallStep,
    /// The relative cost decrease fell below the tolerance.
    SmallDecrease,
    /// The gradient vanished (a zero-residual fit, say).
    SmallGradient,
    /// Bates and Watts' relative offset fell below its tolerance: what a full Gauss–Newton
    /// step could still gain is negligible against the residuals' noise (see
    /// [`LevenbergMarquardt::with_relative_offset`]).
    SmallOffset,
    /// The cost decreases of the last three accepted steps shrink geometrically so fast that
    /// all the steps to come, fading at the same rate, could not lower the cost by what the
    /// relative-offset test counts as negligible (see [`LevenbergMarquardt::with_relative_offset`]):
    /// the crawl toward a parameter at infinity, where the Gauss–Newton prediction behind the
    /// offset test stays large but is never realised.
    FadingDecrease,
    /// The iteration limit was reached.
    MaxIterations,
    /// No damping made a feasible step that lowers the cost.
    Stalled,
}

/// The result of a run of the method.
#[derive(Clone, Debug)]
pub struct Solution {
    /// The parameters.
    pub theta: Vec<f64>,
    /// Σ r² there.
    pub cost: f64,
    /// Residuals there.
    pub residuals: Vec<f64>,
    /// JᵀJ there (row-major p × p), for the covariance.
    pub jtj: Vec<f64>,
    /// Iterations done.
    pub iterations: usize,
    /// Why it stopped.
    pub termination: Termination,
}

/// Levenberg–Marquardt with Marquardt's diagonal scaling (invariant to the units of each
/// parameter) and Nielsen's damping update. The settings are checked when set, so a method
/// that exists is a valid one:
///
/// ```
/// use hyst_fit::lm::LevenbergMarquardt;
/// let method = LevenbergMarquardt::new().with_max_iterations(50)?.with_xtol(1e-10)?;
/// assert_eq!((method.max_iterations(), method.xtol()), (50, 1e-10));
/// assert!(LevenbergMarquardt::new().with_ftol(f64::NAN).is_err());
/// # Ok::<(), hyst_fit::FitError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LevenbergMarquardt {
    max_iterations: usize,
    xtol: f64,
    ftol: f64,
    gtol: f64,
    offset: f64,
}

impl Default for LevenbergMarquardt {
    /// 200 iterations, `xtol` 1e-12, `ftol` 1e-14, `gtol` 1e-300, relative offset 1e-3 (Bates
    /// and Watts' own choice: the remaining numerical error is a thousandth of the statistical
    /// one).
    fn default() -> Self {
        Self {
            max_iterations: 200,
            xtol: 1e-12,
            ftol: 1e-14,
            gtol: 1e-300,
            offset: 1e-3,
        }
    }
}

/// `value` unless it is outside [0, `below`) (or not a number), then the error naming `name`.
fn tolerance(name: &'static str, value: f64, below: f64) -> Result<f64, FitError> {
    if value >= 0.0 && value < below {
        Ok(value)
    } else {
        Err(FitError::InvalidSetting {
            name,
            value,
            expected: if below == 1.0 {
                "a relative tolerance in [0, 1) (0 disables the test)".into()
            } else {
                "a finite number >= 0 (0 disables the test)".into()
            },
        })
    }
}

impl LevenbergMarquardt {
    /// The default settings ([`LevenbergMarquardt::default`]).
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// The same method with at most `max_iterations` iterations (≥ 1).
    ///
    /// # Errors
    /// [`FitError::InvalidSetting`] naming `max_iterations` for 0.
    pub fn with_max_iterations(self, max_iterations: usize) -> Result<Self, FitError> {
        if max_iterations == 0 {
            return Err(FitError::InvalidSetting {
                name: "max_iterations",
                value: 0.0,
                expected: "at least 1 iteration".into(),
            });
        }
        Ok(Self {
            max_iterations,
            ..self
        })
    }

    /// The same method stopping when an accepted step δ is small: ‖δ‖ ≤ `xtol` (‖θ‖ + `xtol`),
    /// relative, in [0, 1).
    ///
    /// # Errors
    /// [`FitError::InvalidSetting`] naming `xtol` for a value outside [0, 1) or NaN.
    pub fn with_xtol(self, xtol: f64) -> Result<Self, FitError> {
        Ok(Self {
            xtol: tolerance("xtol", xtol, 1.0)?,
            ..self
        })
    }

    /// The same method stopping when the relative cost decrease of an accepted step is below
    /// `ftol` twice running, in [0, 1).
    ///
    /// # Errors
    /// [`FitError::InvalidSetting`] naming `ftol` for a value outside [0, 1) or NaN.
    pub fn with_ftol(self, ftol: f64) -> Result<Self, FitError> {
        Ok(Self {
            ftol: tolerance("ftol", ftol, 1.0)?,
            ..self
        })
    }

    /// The same method stopping when the gradient is small against the cost:
    /// max |Jᵀr| ≤ `gtol` · (Σ r² + 1e-300), finite and ≥ 0.
    ///
    /// # Errors
    /// [`FitError::InvalidSetting`] naming `gtol` for a negative, infinite or NaN value.
    pub fn with_gtol(self, gtol: f64) -> Result<Self, FitError> {
        Ok(Self {
            gtol: tolerance("gtol", gtol, f64::INFINITY)?,
            ..self
        })
    }

    /// The same method stopping when Bates and Watts' relative offset
    /// √(‖P r‖² / p) / √(‖r‖² / (n − p)) is below `offset` (P the projection onto the
    /// Jacobian's columns, n residuals, p parameters; ‖P r‖² = (Jᵀr)ᵀ(JᵀJ)⁻¹Jᵀr is what a full
    /// Gauss–Newton step would gain). It compares the distance to the least-squares point with
    /// the radius of the parameters' confidence region: below 1e-3 the remaining change of the
    /// cost is ‖r‖² · p / (n − p) · 1e-6, negligible against the residuals' noise, so the fit
    /// stops instead of crawling along a valley the data does not resolve (a saturating shape
    /// tending to its exponential or hyperbolic limit, say). In [0, 1); 0 disables the test,
    /// which also needs n > p.
    ///
    /// The same tolerance also ends a crawl the prediction misses ([`Termination::FadingDecrease`]):
    /// toward a parameter at infinity (a saturating shape tending to its linear limit, say) the
    /// linearisation keeps promising a gain that the steps never realise, and the offset stays
    /// large while each step gains less than the one before. When the last three accepted
    /// steps' decreases d₁ > d₂ > d₃ shrink by at most q = max(d₂/d₁, d₃/d₂) < 1 per step, the
    /// steps to come, fading at that rate, gain d₃ q / (1 − q) in all; once that is below the
    /// negligible gain ‖r‖² p/(n − p) · `offset`², the method stops. A crawl whose steps keep
    /// their size (q near 1) goes on.
    ///
    /// Reference: D. M. Bates and D. G. Watts, "A relative offset orthogonality convergence
    /// criterion for nonlinear least squares", Technometrics 23 (1981) 179–183.
    ///
    /// # Errors
    /// [`FitError::InvalidSetting`] naming `relative_offset` for a value outside [0, 1) or NaN.
    pub fn with_relative_offset(self, offset: f64) -> Result<Self, FitError> {
        Ok(Self {
            offset: tolerance("relative_offset", offset, 1.0)?,
            ..self
        })
    }

    /// The relative offset tolerance (see [`LevenbergMarquardt::with_relative_offset`]).
    #[must_use]
    pub fn relative_offset(&self) -> f64 {
        self.offset
    }

    /// The iteration limit.
    #[must_use]
    pub fn max_iterations(&self) -> usize {
        self.max_iterations
    }

    /// The relative step tolerance (see [`LevenbergMarquardt::with_xtol`]).
    #[must_use]
    pub fn xtol(&self) -> f64 {
        self.xtol
    }

    /// The relative cost-decrease tolerance (see [`LevenbergMarquardt::with_ftol`]).
    #[must_use]
    pub fn ftol(&self) -> f64 {
        self.ftol
    }

    /// The gradient tolerance (see [`LevenbergMarquardt::with_gtol`]).
    #[must_use]
    pub fn gtol(&self) -> f64 {
        self.gtol
    }

    /// Minimises Σ r² from `theta0`, never leaving the feasible set: steps to infeasible points
    /// are rejected and the damping increased. Stopping is not an error:
    /// [`Solution::termination`] says why it stopped. A start that is infeasible or gives a
    /// non-finite cost returns at once with an infinite cost and [`Termination::Stalled`].
    ///
    /// # Errors
    /// [`FitError::Interrupted`] when the observer returns `ControlFlow::Break`;
    /// [`FitError::InvalidSetting`] naming `theta0` when its length is not the problem's
    /// number of parameters.
    pub fn minimize<P: Problem + ?Sized>(
        &self,
        problem: &P,
        theta0: &[f64],
        observer: &mut dyn Observer,
    ) -> Result<Solution, FitError> {
        let p = problem.parameters();
        let n = problem.residual_count();
        if theta0.len() != p {
            return Err(FitError::InvalidSetting {
                name: "theta0",
                value: theta0.len() as f64,
                expected: format!("{p} starting values, one per parameter"),
            });
        }
        let theta = theta0.to_vec();
        let keeps = problem.keeps_residuals();
        let mut r = vec![0.0; if keeps { n } else { 0 }];
        let cost = if keeps {
            problem.residuals(&theta, &mut r).map(|()| sum_sq(&r))
        } else {
            problem.cost(&theta)
        };
        let Some(cost) = cost.ok().filter(|c| c.is_finite()) else {
            return Ok(Solution {
                theta,
                cost: f64::INFINITY,
                residuals: r,
                jtj: vec![0.0; p * p],
                iterations: 0,
                termination: Termination::Stalled,
            });
        };
        let mut state = Iterate::new(theta, r, cost, (n, p));
        observe(observer, 0, self.max_iterations, state.cost, state.lambda)?;
        let mut termination = Termination::MaxIterations;
        let mut iterations = 0;
        for it in 1..=self.max_iterations {
            iterations = it;
            if let Some(stop) = self.iteration(problem, &mut state, it, observer)? {
                termination = stop;
                break;
            }
        }
        // JᵀJ at the final point, for the covariance.
        if state.need_jacobian {
            state.normal_equations(problem);
        }
        Ok(Solution {
            theta: state.theta,
            cost: state.cost,
            residuals: state.r,
            jtj: state.jtj,
            iterations,
            termination,
        })
    }

    /// Iteration `it` from the state `s`: the Jacobian at a new point and the tests on it, then
    /// steps with growing damping until one is feasible and lowers the cost (accepted), or a
    /// test stops the method. Why the method stops, `None` when it goes on.
    fn iteration<P: Problem + ?Sized>(
        &self,
        problem: &P,
        s: &mut Iterate,
        it: usize,
        observer: &mut dyn Observer,
    ) -> Result<Option<Termination>, FitError> {
        let (n, p) = (s.n, s.theta.len());
        if s.need_jacobian {
            if !s.normal_equations(problem) {
                return Ok(Some(Termination::Stalled));
            }
            s.need_jacobian = false;
        }
        let gmax = s.g.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        if gmax <= self.gtol * (s.cost + 1e-300) || s.cost == 0.0 {
            return Ok(Some(Termination::SmallGradient));
        }
        if relative_offset(&s.jtj, &s.g, s.cost, n, p) < self.offset {
            return Ok(Some(Termination::SmallOffset));
        }
        // Try steps with growing damping until one is feasible and lowers the cost.
        loop {
            let Some(delta) = damped_step(&s.jtj, &s.g, s.lambda, p) else {
                if s.more_damping() {
                    return Ok(Some(Termination::Stalled));
                }
                continue;
            };
            for j in 0..p {
                s.trial[j] = s.theta[j] + delta[j];
            }
            let step = norm(&delta);
            let size = norm(&s.theta);
            let new_cost = if s.r_trial.len() == n {
                problem
                    .residuals(&s.trial, &mut s.r_trial)
                    .map_or(f64::INFINITY, |()| sum_sq(&s.r_trial))
            } else {
                problem.cost(&s.trial).unwrap_or(f64::INFINITY)
            };
            if new_cost.is_finite() && new_cost < s.cost {
                return self.accept(s, &delta, new_cost, (step, size), it, observer);
            }
            if step <= self.xtol * (size + self.xtol) {
                return Ok(Some(Termination::SmallStep));
            }
            if s.more_damping() {
                return Ok(Some(Termination::Stalled));
            }
        }
    }

    /// Accepts the step `delta` (of norm `step` from a point of norm `size`) to the trial
    /// point of cost `new_cost` at iteration `it`: moves there, updates the damping by
    /// Nielsen's rule, reports to `observer`, and tests the step, the cost decrease and the
    /// fading of the decreases. Why the method stops, `None` when it goes on.
    fn accept(
        &self,
        s: &mut Iterate,
        delta: &[f64],
        new_cost: f64,
        (step, size): (f64, f64),
        it: usize,
        observer: &mut dyn Observer,
    ) -> Result<Option<Termination>, FitError> {
        let (n, p) = (s.n, s.theta.len());
        let rho =
            (s.cost - new_cost) / predicted_decrease(delta, &s.jtj, &s.g, s.lambda).max(1e-300);
        let decrease = (s.cost - new_cost) / s.cost.max(1e-300);
        std::mem::swap(&mut s.theta, &mut s.trial);
        std::mem::swap(&mut s.r, &mut s.r_trial);
        s.decreases = [s.decreases[1], s.decreases[2], s.cost - new_cost];
        s.cost = new_cost;
        s.need_jacobian = true;
        let f = 1.0 - (2.0 * rho - 1.0).powi(3);
        s.lambda *= f.max(1.0 / 3.0);
        s.nu = 2.0;
        observe(observer, it, self.max_iterations, s.cost, s.lambda)?;
        if step <= self.xtol * (size + self.xtol) {
            return Ok(Some(Termination::SmallStep));
        }
        if decrease < self.ftol {
            s.small_decreases += 1;
            if s.small_decreases >= 2 {
                return Ok(Some(Termination::SmallDecrease));
            }
        } else {
            s.small_decreases = 0;
        }
        if fading(s.decreases, negligible_gain(s.cost, n, p, self.offset)) {
            return Ok(Some(Termination::FadingDecrease));
        }
        Ok(None)
    }
}

/// The state of a run of [`LevenbergMarquardt::minimize`].
struct Iterate {
    /// The current point.
    theta: Vec<f64>,
    /// The residuals there (empty when the problem keeps none: [`Problem::keeps_residuals`]).
    r: Vec<f64>,
    /// Number of residuals.
    n: usize,
    /// Σ r² there.
    cost: f64,
    /// JᵀJ (row-major) and g = Jᵀr from it.
    jtj: Vec<f64>,
    g: Vec<f64>,
    /// The damping λ and its growth factor ν (Nielsen).
    lambda: f64,
    nu: f64,
    /// A trial point and its residuals.
    trial: Vec<f64>,
    r_trial: Vec<f64>,
    /// Accepted steps in a row whose relative cost decrease was below `ftol`.
    small_decreases: usize,
    /// Whether the point moved since the Jacobian was computed.
    need_jacobian: bool,
    /// The cost decreases of the last three accepted steps, oldest first (0: none yet).
    decreases: [f64; 3],
}

impl Iterate {
    /// The state at the feasible start `theta` of cost `cost` with its residuals `r` (empty
    /// when the problem keeps none), for `n` residuals and `p` parameters.
    fn new(theta: Vec<f64>, r: Vec<f64>, cost: f64, (n, p): (usize, usize)) -> Self {
        let kept = r.len();
        Self {
            cost,
            theta,
            r,
            n,
            jtj: vec![0.0; p * p],
            g: vec![0.0; p],
            lambda: 1e-3,
            nu: 2.0,
            trial: vec![0.0; p],
            r_trial: vec![0.0; kept],
            small_decreases: 0,
            need_jacobian: true,
            decreases: [0.0; 3],
        }
    }

    /// JᵀJ and g = Jᵀr at the current point ([`Problem::normal_equations`]); whether the
    /// problem could compute them (if not, both stay those of the last point where it could).
    fn normal_equations<P: Problem + ?Sized>(&mut self, problem: &P) -> bool {
        let p = self.theta.len();
        let mut jtj = vec![0.0; p * p];
        let mut g = vec![0.0; p];
        let ok = if self.r.len() == self.n {
            problem.normal_equations(&self.theta, &self.r, &mut jtj, &mut g)
        } else {
            problem.sums_at(&self.theta, &mut jtj, &mut g)
        }
        .is_ok();
        if ok {
            (self.jtj, self.g) = (jtj, g);
        }
        ok
    }

    /// Increases the damping after a step that failed; whether it is now too large (1e20) for
    /// any step to matter, so that the method stalls.
    fn more_damping(&mut self) -> bool {
        self.lambda *= self.nu;
        self.nu *= 2.0;
        self.lambda > 1e20
    }
}

/// Reports an iteration to `observer`; [`FitError::Interrupted`] when it stops the method.
fn observe(
    observer: &mut dyn Observer,
    iteration: usize,
    max_iterations: usize,
    cost: f64,
    lambda: f64,
) -> Result<(), FitError> {
    if observer
        .observe(&Progress {
            iteration,
            max_iterations,
            cost,
            lambda,
            start: 0,
            starts: 1,
            finished: 0,
            stage: Stage::Search,
        })
        .is_break()
    {
        return Err(FitError::Interrupted);
    }
    Ok(())
}

fn sum_sq(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

fn norm(v: &[f64]) -> f64 {
    sum_sq(v).sqrt()
}

/// [`Problem::normal_equations`] from the stored Jacobian of [`Problem::jacobian`].
///
/// # Errors
/// [`Infeasible`] as [`Problem::jacobian`].
pub fn jacobian_normal_equations<P: Problem + ?Sized>(
    problem: &P,
    theta: &[f64],
    r: &[f64],
    jtj: &mut [f64],
    g: &mut [f64],
) -> Result<(), Infeasible> {
    let (n, p) = (r.len(), theta.len());
    let mut jac = vec![0.0; n * p];
    problem.jacobian(theta, r, &mut jac)?;
    normal_equations(&jac, r, n, p, jtj, g);
    Ok(())
}

/// JᵀJ (row-major) and Jᵀr from a column-major J.
///
/// Each entry is a dot product summed in row order, as `iter().sum()` sums it; the products
/// are taken four dot products at a time over the rows, so that four independent sums are in
/// flight instead of one sum waiting on the previous addition (same numbers, bit for bit).
fn normal_equations(jac: &[f64], r: &[f64], n: usize, p: usize, jtj: &mut [f64], g: &mut [f64]) {
    let column = |a: usize| jac.get(a * n..(a + 1) * n).unwrap_or(&[]);
    // (row of JᵀJ or p for g, column, the two vectors).
    let mut pairs: Vec<(usize, usize, &[f64], &[f64])> = Vec::with_capacity(p * (p + 3) / 2);
    for a in 0..p {
        pairs.push((p, a, column(a), r));
        for b in a..p {
            pairs.push((a, b, column(a), column(b)));
        }
    }
    for group in pairs.chunks(4) {
        // −0 is the neutral element of a float sum (as `Sum` starts).
        let mut sums = [-0.0_f64; 4];
        match group {
            [(.., x0, y0), (.., x1, y1), (.., x2, y2), (.., x3, y3)] => {
                let rows = x0
                    .iter()
                    .zip(*y0)
                    .zip(x1.iter().zip(*y1))
                    .zip(x2.iter().zip(*y2).zip(x3.iter().zip(*y3)));
                for (((a0, b0), (a1, b1)), ((a2, b2), (a3, b3))) in rows {
                    sums[0] += a0 * b0;
                    sums[1] += a1 * b1;
                    sums[2] += a2 * b2;
                    sums[3] += a3 * b3;
                }
            }
            _ => {
                for (sum, (.., x, y)) in sums.iter_mut().zip(group) {
                    *sum = x.iter().zip(*y).map(|(u, v)| u * v).sum();
                }
            }
        }
        for (&(a, b, ..), s) in group.iter().zip(sums) {
            if a == p {
                g[b] = s;
            } else {
                jtj[a * p + b] = s;
                jtj[b * p + a] = s;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// y = a e^(b x): a classical small problem with a known optimum.
    struct Exp {
        x: Vec<f64>,
        y: Vec<f64>,
    }
    impl Problem for Exp {
        fn parameters(&self) -> usize {
            2
        }
        fn residual_count(&self) -> usize {
            self.x.len()
        }
        fn residuals(&self, t: &[f64], r: &mut [f64]) -> Result<(), Infeasible> {
            for i in 0..self.x.len() {
                r[i] = t[0] * (t[1] * self.x[i]).exp() - self.y[i];
            }
            Ok(())
        }
        fn jacobian(&self, t: &[f64], _r: &[f64], j: &mut [f64]) -> Result<(), Infeasible> {
            let n = self.x.len();
            for i in 0..n {
                let e = (t[1] * self.x[i]).exp();
                j[i] = e;
                j[n + i] = t[0] * self.x[i] * e;
            }
            Ok(())
        }
    }

    #[test]
    fn recovers_an_exponential() -> Result<(), FitError> {
        let x: Vec<f64> = (0..20).map(|i| i as f64 * 0.1).collect();
        let y = x.iter().map(|v| 2.5 * (-1.3 * v).exp()).collect();
        let s = LevenbergMarquardt::default().minimize(&Exp { x, y }, &[1.0, 0.0], &mut Silent)?;
        assert!((s.theta[0] - 2.5).abs() < 1e-10, "{:?}", s.theta);
        assert!((s.theta[1] + 1.3).abs() < 1e-10, "{:?}", s.theta);
        Ok(())
    }

    /// A curved valley whose floor falls toward infinity: r = (10 (θ1 − θ0²), e^(−θ0), and
    /// ten residuals of 0.3 that no parameter moves). The infimum 0.9 lies at θ0 → ∞ along the
    /// parabola θ1 = θ0², approached by ever smaller gains while the valley's curvature keeps
    /// the Gauss–Newton prediction from coming true (a parameter at infinity with a curved
    /// valley, as a saturating shape's scale and centre give).
    struct FallingValley;
    impl FallingValley {
        const INFIMUM: f64 = 0.9;
    }
    impl Problem for FallingValley {
        fn parameters(&self) -> usize {
            2
        }
        fn residual_count(&self) -> usize {
            12
        }
        fn residuals(&self, t: &[f64], r: &mut [f64]) -> Result<(), Infeasible> {
            r[0] = 10.0 * (t[1] - t[0] * t[0]);
            r[1] = (-t[0]).exp();
            r[2..].fill(0.3);
            Ok(())
        }
        fn jacobian(&self, t: &[f64], _r: &[f64], j: &mut [f64]) -> Result<(), Infeasible> {
            // Column-major: column 0 is ∂r/∂θ0, column 1 is ∂r/∂θ1.
            j.fill(0.0);
            j[0] = -20.0 * t[0];
            j[1] = -(-t[0]).exp();
            j[12] = 10.0;
            Ok(())
        }
    }

    #[test]
    fn a_crawl_whose_gains_keep_their_size_is_not_cut_short() -> Result<(), FitError> {
        // Each step along the falling valley gains a little less than the one before (q near 1)
        // but more than the negligible gain: the rule must let it go on, exactly as the method
        // without any offset test does.
        let method = LevenbergMarquardt::new();
        let s = method.minimize(&FallingValley, &[0.0, 1.0], &mut Silent)?;
        let without =
            method
                .with_relative_offset(0.0)?
                .minimize(&FallingValley, &[0.0, 1.0], &mut Silent)?;
        assert_ne!(s.termination, Termination::FadingDecrease, "{s:?}");
        assert_eq!(
            (s.iterations, s.cost.to_bits()),
            (without.iterations, without.cost.to_bits())
        );
        assert!(s.cost - FallingValley::INFIMUM < 1e-4, "{s:?}");
        Ok(())
    }

    #[test]
    fn only_geometrically_fading_decreases_stop_the_method() {
        // Halving: the rest gains d₃ = 1 in all.
        assert!(fading([4.0, 2.0, 1.0], 1.0));
        assert!(!fading([4.0, 2.0, 1.0], 0.99));
        // The slower ratio counts: q = 0.9 gives 9 d₃ = 8.1.
        assert!(!fading([10.0, 1.0, 0.9], 8.0));
        assert!(fading([10.0, 1.0, 0.9], 8.2));
        // Steps that keep their size, or grow, never stop it; nor fewer than three steps.
        assert!(!fading([1.0, 1.0, 1.0], 1e300));
        assert!(!fading([1.0, 2.0, 1.0], 1e300));
        assert!(!fading([0.0, 2.0, 1.0], 1e300));
        // Off when the offset test is.
        assert!(!fading([4.0, 2.0, 1e-300], 0.0));
        assert_eq!(negligible_gain(2.0, 10, 2, 1e-3), 2.0 * 2.0 / 8.0 * 1e-6);
        assert_eq!(negligible_gain(2.0, 2, 2, 1e-3), 0.0);
    }

    /// Rosenbrock's valley as least squares: r = (10 (θ1 − θ0²), 1 − θ0), minimum 0 at (1, 1).
    struct Rosenbrock;
    impl Problem for Rosenbrock {
        fn parameters(&self) -> usize {
            2
        }
        fn residual_count(&self) -> usize {
            2
        }
        fn residuals(&self, t: &[f64], r: &mut [f64]) -> Result<(), Infeasible> {
            r[0] = 10.0 * (t[1] - t[0] * t[0]);
            r[1] = 1.0 - t[0];
            Ok(())
        }
        fn jacobian(&self, t: &[f64], _r: &[f64], j: &mut [f64]) -> Result<(), Infeasible> {
            // Column-major: column 0 is ∂r/∂θ0, column 1 is ∂r/∂θ1.
            j.copy_from_slice(&[-20.0 * t[0], -1.0, 10.0, 0.0]);
            Ok(())
        }
    }

    #[test]
    fn solves_rosenbrock_to_1e_10() -> Result<(), FitError> {
        let s = LevenbergMarquardt::new().minimize(&Rosenbrock, &[-1.2, 1.0], &mut Silent)?;
        assert!((s.theta[0] - 1.0).abs() < 1e-10, "{s:?}");
        assert!((s.theta[1] - 1.0).abs() < 1e-10, "{s:?}");
        assert!(s.cost < 1e-20, "{s:?}");
        assert!(s.iterations > 5 && s.iterations < 200, "{s:?}");
        assert_ne!(s.termination, Termination::MaxIterations);
        Ok(())
    }

    /// The straight line y ≈ a + b x: a linear least-squares problem.
    struct Line {
        x: Vec<f64>,
        y: Vec<f64>,
    }
    impl Problem for Line {
        fn parameters(&self) -> usize {
            2
        }
        fn residual_count(&self) -> usize {
            self.x.len()
        }
        fn residuals(&self, t: &[f64], r: &mut [f64]) -> Result<(), Infeasible> {
            for ((r, x), y) in r.iter_mut().zip(&self.x).zip(&self.y) {
                *r = t[0] + t[1] * x - y;
            }
            Ok(())
        }
        fn jacobian(&self, _t: &[f64], _r: &[f64], j: &mut [f64]) -> Result<(), Infeasible> {
            let n = self.x.len();
            j[..n].fill(1.0);
            j[n..].copy_from_slice(&self.x);
            Ok(())
        }
    }

    #[test]
    fn linear_least_squares_match_the_closed_form() -> Result<(), FitError> {
        let x: Vec<f64> = (0..30).map(|i| f64::from(i) * 0.25 - 2.0).collect();
        // A line plus a deterministic misfit, so the residuals at the optimum are not 0.
        let y: Vec<f64> = x
            .iter()
            .enumerate()
            .map(|(i, v)| 0.7 - 1.9 * v + 0.3 * (f64::from(i as u8) * 1.7).sin())
            .collect();
        let n = x.len() as f64;
        let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
        let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
        let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
        let slope = sxy / sxx;
        let intercept = my - slope * mx;
        let cost: f64 = x
            .iter()
            .zip(&y)
            .map(|(a, b)| (intercept + slope * a - b).powi(2))
            .sum();
        let line = Line { x: x.clone(), y };
        // Bates and Watts' test stops where the cost is within p/(n − p) · 1e-6 of its minimum
        // (relative): for a linear problem exactly the offset's promise.
        let early = LevenbergMarquardt::new().minimize(&line, &[0.0, 0.0], &mut Silent)?;
        assert!(
            early.cost - cost <= 1e-6 * 2.0 / (n - 2.0) * cost,
            "{} vs {cost}",
            early.cost
        );
        // Without it, the method reaches the closed form.
        let s = LevenbergMarquardt::new()
            .with_relative_offset(0.0)?
            .minimize(&line, &[0.0, 0.0], &mut Silent)?;
        assert!(
            (s.theta[0] - intercept).abs() < 1e-12,
            "{s:?} vs {intercept}"
        );
        assert!((s.theta[1] - slope).abs() < 1e-12, "{s:?} vs {slope}");
        assert!((s.cost - cost).abs() < 1e-12 * cost, "{} vs {cost}", s.cost);
        // JᵀJ at the solution: [[n, Σx], [Σx, Σx²]].
        let sx: f64 = x.iter().sum();
        let sx2: f64 = x.iter().map(|v| v * v).sum();
        for (got, want) in s.jtj.iter().zip([n, sx, sx, sx2]) {
            assert!(
                (got - want).abs() < 1e-12 * want.abs().max(1.0),
                "{:?}",
                s.jtj
            );
        }
        Ok(())
    }

    /// r = θ − 2, but every θ > 1 is infeasible: the constrained minimum is the boundary θ = 1.
    struct Fenced;
    impl Problem for Fenced {
        fn parameters(&self) -> usize {
            1
        }
        fn residual_count(&self) -> usize {
            1
        }
        fn residuals(&self, t: &[f64], r: &mut [f64]) -> Result<(), Infeasible> {
            if t[0] > 1.0 {
                return Err(Infeasible);
            }
            r[0] = t[0] - 2.0;
            Ok(())
        }
        fn jacobian(&self, _t: &[f64], _r: &[f64], j: &mut [f64]) -> Result<(), Infeasible> {
            j[0] = 1.0;
            Ok(())
        }
    }

    #[test]
    fn stops_at_the_boundary_of_the_feasible_set() -> Result<(), FitError> {
        // An observer that checks every accepted point is feasible.
        struct Feasible(usize);
        impl Observer for Feasible {
            fn observe(&mut self, p: &Progress) -> ControlFlow<()> {
                self.0 += 1;
                assert!(
                    p.cost >= 1.0,
                    "cost {} below the constrained minimum",
                    p.cost
                );
                ControlFlow::Continue(())
            }
        }
        let mut seen = Feasible(0);
        let s = LevenbergMarquardt::new().minimize(&Fenced, &[-3.0], &mut seen)?;
        assert!(s.theta[0] <= 1.0, "{s:?}");
        assert!(1.0 - s.theta[0] < 1e-9, "{s:?}");
        assert!((s.cost - 1.0).abs() < 1e-8, "{s:?}");
        assert!(seen.0 > 2, "{} observations", seen.0);
        assert_ne!(s.termination, Termination::MaxIterations, "{s:?}");
        Ok(())
    }

    #[test]
    fn an_observer_break_cancels() {
        struct StopAt(usize, Vec<usize>);
        impl Observer for StopAt {
            fn observe(&mut self, p: &Progress) -> ControlFlow<()> {
                self.1.push(p.iteration);
                if p.iteration >= self.0 {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            }
        }
        let mut stop = StopAt(3, Vec::new());
        let r = LevenbergMarquardt::new().minimize(&Rosenbrock, &[-1.2, 1.0], &mut stop);
        assert!(matches!(r, Err(FitError::Interrupted)), "{r:?}");
        assert_eq!(stop.1.first(), Some(&0));
        assert_eq!(stop.1.last(), Some(&3));
        // Breaking at the start point stops before any iteration.
        let mut stop = StopAt(0, Vec::new());
        let r = LevenbergMarquardt::new().minimize(&Rosenbrock, &[-1.2, 1.0], &mut stop);
        assert!(matches!(r, Err(FitError::Interrupted)), "{r:?}");
        assert_eq!(stop.1, [0]);
    }

    #[test]
    fn the_iteration_limit_is_honoured() -> Result<(), FitError> {
        let method = LevenbergMarquardt::new().with_max_iterations(2)?;
        let s = method.minimize(&Rosenbrock, &[-1.2, 1.0], &mut Silent)?;
        assert_eq!(
            (s.iterations, s.termination),
            (2, Termination::MaxIterations)
        );
        assert!(s.cost > 1e-3, "{s:?}");
        Ok(())
    }

    #[test]
    fn invalid_settings_are_refused_by_name() {
        let m = LevenbergMarquardt::new();
        let refused = |r: Result<LevenbergMarquardt, FitError>, field: &str, shown: &str| {
            let e = r.err().map(|e| e.to_string()).unwrap_or_default();
            assert!(
                e.starts_with(&format!("{field} = {shown}: expected")),
                "{e}"
            );
        };
        refused(m.with_max_iterations(0), "max_iterations", "0");
        for (bad, shown) in [(f64::NAN, "NaN"), (-1e-9, "-0.000000001"), (1.0, "1")] {
            refused(m.with_xtol(bad), "xtol", shown);
            refused(m.with_ftol(bad), "ftol", shown);
            refused(m.with_relative_offset(bad), "relative_offset", shown);
        }
        refused(m.with_gtol(f64::INFINITY), "gtol", "inf");
        refused(m.with_gtol(-1.0), "gtol", "-1");
        refused(m.with_gtol(f64::NAN), "gtol", "NaN");
        // Valid values are kept, 0 included (it disables the test).
        let ok = m
            .with_max_iterations(7)
            .and_then(|m| m.with_xtol(0.0))
            .and_then(|m| m.with_ftol(1e-6))
            .and_then(|m| m.with_gtol(5.0));
        assert!(
            matches!(ok, Ok(m) if (m.max_iterations(), m.xtol(), m.ftol(), m.gtol()) == (7, 0.0, 1e-6, 5.0)),
            "{ok:?}"
        );
    }

    #[test]
    fn bad_starts_are_reported_not_run() -> Result<(), FitError> {
        let m = LevenbergMarquardt::new();
        // An infeasible start: no iteration, infinite cost.
        let s = m.minimize(&Fenced, &[1.5], &mut Silent)?;
        assert_eq!((s.iterations, s.termination), (0, Termination::Stalled));
        assert_eq!((s.cost, s.theta[0]), (f64::INFINITY, 1.5));
        // A start whose cost is not finite: the same.
        let s = m.minimize(&Rosenbrock, &[f64::NAN, 1.0], &mut Silent)?;
        assert_eq!((s.iterations, s.cost), (0, f64::INFINITY));
        // A start of the wrong length is refused, naming it.
        let e = m.minimize(&Rosenbrock, &[1.0], &mut Silent).err();
        assert!(
            matches!(e, Some(FitError::InvalidSetting { name: "theta0", value, .. }) if value == 1.0),
            "{e:?}"
        );
        Ok(())
    }
}
