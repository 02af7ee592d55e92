//! Fitting the smooth model to a dataset: the least-squares problem (output error over the
//! training records, each simulated from its own initial state), the multi-start driver, and
//! the parameter standard errors from the covariance.
//!
//! Derivatives: exact, by forward-mode duals. θ is seeded as [`Dual`] variables, the model
//! is built from them by the same [`Layout::model`] (so the log transforms, the data-dependent
//! shaping domains and the k2 law's clamps carry their derivatives) and run by the same
//! [`SmoothModel::run_with`] as the residuals: the core's operator, memory (every reversal
//! point carries its gradient forward), k2 law and shaping functions are evaluated on duals
//! through their one code path. One dual run per record gives every column at the cost of a
//! few plain runs; any structure `Layout::model` builds gets its Jacobian this way.

use std::time::Instant;

use hyst_core::{Dual, Shaping};
use rayon::prelude::*;

use hyst_io::number::sig;
use hyst_model::smooth::FitReal;
use hyst_model::{ErrorStats, Estimate, FamilyWidths, Form, K2Kind, ShapingKind};
use hyst_model::{SmoothModel, Structure};

use crate::data::{Dataset, History};
use crate::error::FitError;
use crate::layout::{
    Layout, Normalisation, IN_ARG_AT_CENTRE, IN_SCALE, OUT_ARG_AT_CENTRE, OUT_SCALE,
};
use crate::linalg::{cholesky_solve, spd_inverse};
use crate::lm::{Infeasible, LevenbergMarquardt, Observer, Problem, Termination};
use crate::race::{best_of, threads};
use crate::reduction::reduce;
use crate::widths::{confirm, family_widths};

/// Options of the fit.
#[derive(Clone, Copy, Debug)]
pub struct FitOptions {
    /// Number of starts refined by the least-squares method, at least 1: the best of a grid over
    /// (k1, k2), and for a richer structure first the optimum of the simpler one it contains
    /// ([`simpler`]), which counts as one of them.
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
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            starts: 3,
            method: LevenbergMarquardt::default(),
            coverage: 0.99,
            widths: true,
            estimate_starts: false,
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
    /// Parameters with standard errors.
    pub estimates: Vec<Estimate>,
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
    /// The estimated start of each history ([`Dataset::histories`]) as a band fraction in
    /// [−1, 1] ([`SmoothModel::simulate_from`]); `None` when the start rule was used.
    pub starts: Option<Vec<f64>>,
    /// Wall time of the fit (s).
    pub seconds: f64,
    /// The fitted model's output on every record of the data it was fitted to (one vector per
    /// record, in output units), as the fit ran it (segments running on, estimated starts):
    /// the run the error statistics came from, kept for the degeneracy check and the plots.
    pub outputs: Vec<Vec<f64>>,
}

/// The least-squares problem of one structure on one dataset.
struct SmoothProblem<'a> {
    layout: &'a Layout,
    data: &'a Dataset,
    /// The records as uninterrupted histories (segments of one measurement run on from each
    /// other), each with the offset of its training samples in residual order.
    histories: Vec<(History, Vec<Option<usize>>)>,
    /// Estimate each history's start ([`FitOptions::estimate_starts`]).
    estimate: bool,
    input_range: (f64, f64),
    /// √w / output half-span per training sample, in residual order.
    scale: Vec<f64>,
    n: usize,
}

impl<'a> SmoothProblem<'a> {
    fn new(layout: &'a Layout, data: &'a Dataset, estimate: bool) -> Self {
        let inv = 1.0 / layout.norm.output_half_span;
        let scale: Vec<f64> = data
            .training()
            .flat_map(|r| r.weight.iter().map(move |w| w.sqrt() * inv))
            .collect();
        // Residual offsets: training records in order.
        let mut offsets = vec![None; data.records.len()];
        let mut at = 0;
        for (i, r) in data.records.iter().enumerate() {
            if !r.validation {
                offsets[i] = Some(at);
                at += r.len();
            }
        }
        let histories = data
            .histories()
            .into_iter()
            .map(|h| {
                let o = h.parts.iter().map(|(i, _, _)| offsets[*i]).collect();
                (h, o)
            })
            .collect();
        Self {
            layout,
            data,
            histories,
            estimate,
            input_range: data.input_range(),
            n: scale.len(),
            scale,
        }
    }

    fn model<T: FitReal>(&self, theta: &[T]) -> Result<SmoothModel<T>, Infeasible> {
        self.layout
            .model(theta, self.input_range)
            .map_err(|_| Infeasible)
    }

    /// The estimated start of each history for the model `m` (`None` without estimation):
    /// the band fraction b ∈ [−1, 1] that minimises the history's weighted squared error, by
    /// Brent's method, compared with the ends b = ±1 (the asymptotes, where the minimum often
    /// lies).
    fn bands(&self, m: &SmoothModel) -> Option<Vec<f64>> {
        if !self.estimate {
            return None;
        }
        let mut y = Vec::new();
        let bands = self
            .histories
            .iter()
            .map(|(h, _)| {
                y.resize(h.input.len(), 0.0);
                let mut cost = |b: f64| -> f64 {
                    if m.simulate_from(&h.input, Some(b), None, &mut y).is_err() {
                        return f64::INFINITY;
                    }
                    y.iter()
                        .zip(&h.output)
                        .zip(&h.weight)
                        .map(|((p, o), w)| w * (p - o) * (p - o))
                        .sum()
                };
                let inner = brent_minimum(&mut cost, -1.0, 1.0, 1e-7);
                [(-1.0, cost(-1.0)), (1.0, cost(1.0)), inner]
                    .into_iter()
                    .min_by(|p, q| p.1.total_cmp(&q.1))
                    .map_or(0.0, |p| p.0)
            })
            .collect();
        Some(bands)
    }

    /// Simulates the training records (each history whole, validation segments included, so
    /// that a segment starts where the one before it ended), from the estimated starts when
    /// the fit estimates them; `z` receives the operator output when given.
    fn simulate(
        &self,
        m: &SmoothModel,
        y: &mut [f64],
        z: Option<&mut [f64]>,
    ) -> Result<(), Infeasible> {
        self.simulate_with(m, self.bands(m).as_deref(), y, z)
    }

    /// [`SmoothProblem::simulate`] from the given starts (`None`: the start rule).
    fn simulate_with(
        &self,
        m: &SmoothModel,
        bands: Option<&[f64]>,
        y: &mut [f64],
        mut z: Option<&mut [f64]>,
    ) -> Result<(), Infeasible> {
        let (mut hy, mut hz) = (Vec::new(), Vec::new());
        for (index, (h, offsets)) in self.histories.iter().enumerate() {
            hy.resize(h.input.len(), 0.0);
            hz.resize(h.input.len(), 0.0);
            let zs = z.is_some().then_some(&mut hz[..]);
            let band = bands.and_then(|b| b.get(index).copied());
            m.simulate_from(&h.input, band, zs, &mut hy)
                .map_err(|_| Infeasible)?;
            for ((_, start, len), at) in h.parts.iter().zip(offsets) {
                let Some(at) = *at else { continue };
                y[at..at + len].copy_from_slice(&hy[*start..start + len]);
                if let Some(z) = z.as_deref_mut() {
                    z[at..at + len].copy_from_slice(&hz[*start..start + len]);
                }
            }
        }
        Ok(())
    }

    fn to_residuals(&self, y: &[f64], r: &mut [f64]) -> Result<(), Infeasible> {
        let mut i = 0;
        for rec in self.data.training() {
            for obs in &rec.output {
                let v = (y[i] - obs) * self.scale[i];
                if !v.is_finite() {
                    return Err(Infeasible);
                }
                r[i] = v;
                i += 1;
            }
        }
        Ok(())
    }
}

impl SmoothProblem<'_> {
    /// Σ r² at θ given the operator output `z` = H[ψ_in(in)] per residual of a point with the
    /// same k1, k2 law and ψ_in (θ differs only in ψ_out and the linear term): the residuals
    /// [`Problem::residuals`] computes, from the same per-sample arithmetic
    /// ([`SmoothModel::output`] of ψ_in(in) and z), without running the operator again.
    /// `None` when θ is infeasible (as `residuals` says).
    fn cost_from_operator(&self, theta: &[f64], z: &[f64]) -> Option<f64> {
        let m = self.model(theta).ok()?;
        let mut y = vec![0.0; self.n];
        let inputs = self.data.training().flat_map(|r| r.input.iter());
        for ((slot, x), u) in y.iter_mut().zip(inputs).zip(z) {
            let out = m.output(m.input_shaping.apply(*x), *u);
            if !out.is_finite() {
                return None;
            }
            *slot = out;
        }
        let mut r = vec![0.0; self.n];
        self.to_residuals(&y, &mut r).ok()?;
        Some(r.iter().map(|v| v * v).sum())
    }
}

impl Problem for SmoothProblem<'_> {
    fn parameters(&self) -> usize {
        self.layout.len()
    }
    fn residual_count(&self) -> usize {
        self.n
    }
    fn residuals(&self, theta: &[f64], r: &mut [f64]) -> Result<(), Infeasible> {
        let m = self.model(theta)?;
        let mut y = vec![0.0; self.n];
        self.simulate(&m, &mut y, None)?;
        self.to_residuals(&y, r)
    }
    /// Exact derivatives: one run of the model on [`Dual`] numbers seeded in θ (through the
    /// transforms of [`Layout::model`]) per training record, up to 16 parameters at a time
    /// (the dual's width is the next of 4, 6, 8, 12, 16: unused lanes cost time).
    fn jacobian(&self, theta: &[f64], _r: &[f64], jac: &mut [f64]) -> Result<(), Infeasible> {
        match theta.len() {
            0..=4 => self.dual_columns::<4>(theta, 0, jac),
            5..=6 => self.dual_columns::<6>(theta, 0, jac),
            7..=8 => self.dual_columns::<8>(theta, 0, jac),
            9..=12 => self.dual_columns::<12>(theta, 0, jac),
            p => (0..p)
                .step_by(16)
                .try_for_each(|offset| self.dual_columns::<16>(theta, offset, jac)),
        }
    }
}

impl SmoothProblem<'_> {
    /// Columns `offset..offset + N` of the Jacobian (those that exist) from one dual run over
    /// each history (as [`SmoothProblem::simulate`] runs them): θ_j seeded as the dual variable
    /// j − offset, the others constant.
    fn dual_columns<const N: usize>(
        &self,
        theta: &[f64],
        offset: usize,
        jac: &mut [f64],
    ) -> Result<(), Infeasible> {
        let n = self.n;
        let seeded: Vec<Dual<f64, N>> = theta
            .iter()
            .enumerate()
            .map(|(j, t)| Dual::variable(*t, j.wrapping_sub(offset)))
            .collect();
        let m = self.model(&seeded)?;
        // Estimated starts stay those of the base point: at the optimum over them, the
        // derivative of the cost with respect to θ is the partial one (variable projection).
        let bands = self.bands(&self.model(theta)?);
        let columns = N.min(theta.len().saturating_sub(offset));
        let jac = jac
            .get_mut(offset * n..(offset + columns) * n)
            .ok_or(Infeasible)?;
        let mut finite = true;
        // Each history whole, as `simulate` runs it; a sample of a training part lands at its
        // residual's row (parts are in sample order, so one cursor walks them).
        for (index, (h, offsets)) in self.histories.iter().enumerate() {
            let mut parts = h.parts.iter().zip(offsets).peekable();
            let band = bands.as_ref().and_then(|b| b.get(index).copied());
            m.run_with(&h.input, band, |i, _, y| {
                while parts
                    .peek()
                    .is_some_and(|((_, start, len), _)| i >= start + len)
                {
                    parts.next();
                }
                let Some(&((_, start, _), Some(at))) = parts.peek() else {
                    return;
                };
                let Some(k) = i.checked_sub(*start).map(|d| at + d) else {
                    return;
                };
                let scale = self.scale.get(k).copied().unwrap_or(0.0);
                for (c, g) in y.gradient().iter().take(columns).enumerate() {
                    let d = g * scale;
                    finite &= d.is_finite();
                    if let Some(slot) = jac.get_mut(c * n + k) {
                        *slot = d;
                    }
                }
            })
            .map_err(|_| Infeasible)?;
        }
        if finite {
            Ok(())
        } else {
            Err(Infeasible)
        }
    }
}

/// The polish of a long record on its full data stops once a Gauss–Newton step would lower χ²
/// by less than this (see [`fit_smooth`]).
const POLISH_CHI2: f64 = 0.1;

/// The normalisation of a dataset (from all its records, so that validation data uses the
/// same polynomial domains).
#[must_use]
pub fn normalisation(data: &Dataset) -> Normalisation {
    let (lo, hi) = data.input_range();
    let (ylo, yhi) = data.output_range();
    Normalisation {
        centre: 0.5 * (lo + hi),
        half_span: (0.5 * (hi - lo)).max(f64::MIN_POSITIVE),
        output_centre: 0.5 * (ylo + yhi),
        output_half_span: (0.5 * (yhi - ylo)).max(f64::MIN_POSITIVE),
    }
}

/// Fits `structure` to the training records of `data`.
///
/// # Errors
/// Bad data ([`Dataset::check`]), [`FitError::Interrupted`] when the observer stops the fit,
/// [`FitError::NoConvergence`] when no start gives a finite cost.
pub fn fit_smooth(
    data: &Dataset,
    structure: Structure,
    options: &FitOptions,
    observer: &mut dyn Observer,
) -> Result<SmoothFit, FitError> {
    fit_smooth_with(data, structure, options, observer, &mut Vec::new()).map(|(fit, _)| fit)
}

/// The fits of the structures a richer one contains, on one dataset with one set of options
/// (each with its cost Σ r²), so that a structure reached along two paths of the lattice
/// (`--k2 affine` with two shapings) is fitted once.
type Contained = Vec<(Structure, SmoothFit, f64)>;

/// Points θ, each with a cost (NaN when not known).
type Starts = Vec<(f64, Vec<f64>)>;

/// [`fit_smooth`], with the fits of contained structures done so far, and the cost Σ r² of
/// the fit's training residuals (in units of the output half-span).
fn fit_smooth_with(
    data: &Dataset,
    structure: Structure,
    options: &FitOptions,
    observer: &mut dyn Observer,
    contained: &mut Contained,
) -> Result<(SmoothFit, f64), FitError> {
    let started = Instant::now();
    if options.starts == 0 {
        return Err(FitError::InvalidSetting {
            name: "starts",
            value: 0.0,
            expected: "at least 1 start".into(),
        });
    }
    if !(options.coverage > 0.0 && options.coverage <= 1.0) {
        return Err(FitError::Invalid(format!(
            "coverage {} must be in (0, 1]",
            options.coverage
        )));
    }
    let layout = Layout::new(structure, normalisation(data));
    data.check(layout.len(), structure.form == Form::Operator)?;
    let problem = SmoothProblem::new(&layout, data, options.estimate_starts);

    // A long record is searched on its reduction (turning points and every k-th sample, exact
    // where kept: `crate::reduction`), then polished here on the full data from that optimum.
    let reduced = if options.estimate_starts {
        None
    } else {
        reduce(data)
    };
    let mut limits = Vec::new();
    let candidates = if let Some(small) = &reduced {
        let search = FitOptions {
            widths: false,
            ..*options
        };
        let f = fit_smooth(small, structure, &search, observer)?;
        vec![(f64::NAN, f.theta)]
    } else if options.estimate_starts {
        // The fit from the start rule first (grid, nested starts and all), then the estimated
        // starts refine its optimum: each trial of θ costs a search per history, so it runs
        // from one good start only.
        let rule = FitOptions {
            widths: false,
            estimate_starts: false,
            ..*options
        };
        let f = fit_smooth(data, structure, &rule, observer)?;
        vec![(f64::NAN, f.theta)]
    } else {
        let (candidates, at_limit) = start_candidates(
            data, structure, &layout, &problem, options, observer, contained,
        )?;
        limits = at_limit;
        candidates
    };
    // The polish after a search on the reduction stops once a full Gauss–Newton step would
    // lower χ² = cost / s² by less than 0.1 (Bates and Watts' relative offset below
    // √(0.1 / p): the step gains p · offset² in units of s² = cost / (n − p)). The test is a
    // prediction, made from the Jacobian each iteration computes anyway, so the polish stops
    // without the confirming iterations a cost-decrease rule needs (each a pass over the full
    // record). Not for every fit: where the optimum lies at the end of a long crawl of small
    // steps (k2 → ∞, the stop form's Dahl limit) a tolerance this loose stops far too early
    // (MnZn with Langevin ψ_out: 2.45 % of span instead of 1.22 %; a seal record: 8.5 % instead
    // of 5.8 %, with the equivalent cost-decrease rule); the polish starts at an optimum.
    let method = match &reduced {
        Some(_) => {
            let loose = (POLISH_CHI2 / layout.len().max(1) as f64).sqrt();
            options
                .method
                .with_relative_offset(loose.max(options.method.relative_offset()))?
        }
        None => options.method,
    };
    // The starts on the machine's threads, with the result of running them in order (each
    // raced against the best before it: `crate::race`).
    let starts: Vec<Vec<f64>> = candidates.into_iter().map(|(_, theta)| theta).collect();
    let best = best_of(&method, &problem, &starts, threads(), observer)?;
    let mut best = best
        .filter(|b| b.cost.is_finite())
        .ok_or_else(|| FitError::NoConvergence("no starting point gave a finite cost".into()))?;
    // A contained structure that fitted better than every start of this one did: its optimum
    // is (up to a saturating shape's limit of infinite scale) a point of this structure, but
    // the starts from it ended higher (the limit's start at scale 30 costs more than the
    // contained fit, and the descent from there crawls toward the infinite scale and stops
    // on its statistical tests before it gets back to the contained cost). Then the fit
    // descends from the contained optimum placed at that limit, where it costs the same to
    // rounding, and keeps the result if it is lower: a richer structure never ends worse than
    // one it contains.
    for (cost, theta) in limits {
        if cost < best.cost {
            let f = best_of(&method, &problem, &[theta], 1, observer)?;
            if let Some(f) = f.filter(|f| f.cost < best.cost) {
                best = f;
            }
        }
    }
    let model = layout.model(&best.theta, problem.input_range)?;

    // Standard errors: cov θ = s² (JᵀJ)⁻¹, s² = Σ r² / (n − p); value = f(θ). In a parameter
    // limit (the stop form's Dahl limit, the backlash limit) the unidentified parameter carries
    // no information (its column of J vanishes): the covariance of the others is taken without
    // it, and its standard error is NaN.
    let p = layout.len();
    let dof = (problem.n - p).max(1) as f64;
    let s2 = best.cost / dof * layout.norm.output_half_span.powi(2);
    let mut unidentified: Vec<&str> = ParameterLimit::of(&model)
        .map_or(&[][..], ParameterLimit::unidentified)
        .to_vec();
    // A saturating shape at its linear limit (the fallback above, or a start from a contained
    // fit that ended there) is a line on the data: its scale and its argument at the centre
    // have no effect there (their columns of J vanish).
    unidentified.extend(linear_limit_parameters(&layout, &best.theta));
    let mut kept: Vec<usize> = (0..p)
        .filter(|&j| !unidentified.contains(&layout.params[j].name.as_str()))
        .collect();
    let mut inv = reduced_inverse(&best.jtj, p, &kept);
    if inv.is_none() {
        // Singular: the parameters whose removal makes it invertible span the direction the
        // data does not see; they get NaN, the others their standard errors without them.
        let lost: Vec<usize> = kept
            .iter()
            .copied()
            .filter(|&j| {
                let without: Vec<usize> = kept.iter().copied().filter(|&k| k != j).collect();
                reduced_inverse(&best.jtj, p, &without).is_some()
            })
            .collect();
        if let Some(&first) = lost.first() {
            let without: Vec<usize> = kept.iter().copied().filter(|&k| k != first).collect();
            inv = reduced_inverse(&best.jtj, p, &without);
            kept = without.into_iter().filter(|k| !lost.contains(k)).collect();
            // Standard errors of the kept ones come from the matrix without `first` only.
            let with_first_removed: Vec<usize> = (0..p)
                .filter(|&j| j != first && !unidentified.contains(&layout.params[j].name.as_str()))
                .collect();
            inv = inv.map(|full| {
                let q = with_first_removed.len();
                let mut out = vec![f64::NAN; kept.len() * kept.len()];
                for (a, &i) in kept.iter().enumerate() {
                    for (b, &j) in kept.iter().enumerate() {
                        let (Some(x), Some(y)) = (
                            with_first_removed.iter().position(|&k| k == i),
                            with_first_removed.iter().position(|&k| k == j),
                        ) else {
                            continue;
                        };
                        out[a * kept.len() + b] = full[x * q + y];
                    }
                }
                out
            });
        }
    }
    let q = kept.len();
    let scale2 = layout.norm.output_half_span.powi(2);
    let estimates: Vec<Estimate> = layout
        .params
        .iter()
        .enumerate()
        .map(|(j, spec)| {
            let value = spec.transform.value(best.theta[j]);
            // NaN (not identifiable) propagates: NaN.max(0.0) would hide it.
            let var = match (kept.iter().position(|&k| k == j), inv.as_ref()) {
                (Some(a), Some(inv)) => inv[a * q + a] * s2 / scale2,
                _ => f64::NAN,
            };
            let var = if var < 0.0 { 0.0 } else { var };
            Estimate {
                name: spec.name.clone(),
                value,
                std_error: spec.transform.derivative(best.theta[j]).abs() * var.sqrt(),
                unit: spec.unit.clone(),
            }
        })
        .collect();

    let starts = problem.bands(&model);
    let outputs = run_records(data, &model, starts.as_deref())
        .ok_or_else(|| FitError::NoConvergence("the fitted model cannot run the records".into()))?;
    let (training, validation) = error_stats_of(data, &outputs);
    let widths = match (options.widths, &reduced) {
        (false, _) => None,
        (true, None) => Some(family_widths(
            data,
            &model,
            starts.as_deref(),
            options.coverage,
            observer,
        )?),
        // Searched on the reduction, then checked (and widened if need be) on the full data.
        (true, Some(small)) => {
            let found = family_widths(small, &model, None, options.coverage, observer)?;
            Some(confirm(data, &model, found, observer)?)
        }
    };
    check_finite(
        &data.source,
        &training,
        validation.as_ref(),
        estimates.iter().map(|e| (e.name.as_str(), e.value)),
    )?;
    let cost = best.cost;
    let fit = SmoothFit {
        model,
        layout,
        theta: best.theta.clone(),
        estimates,
        training,
        validation,
        widths,
        iterations: best.iterations,
        termination: best.termination,
        starts,
        seconds: started.elapsed().as_secs_f64(),
        outputs,
    };
    Ok((fit, cost))
}

/// The minimum of `f` on [a, b] by Brent's method (golden sections with parabolic steps),
/// to an absolute tolerance `tol` in x: (x, f(x)). About 10–15 evaluations for a smooth
/// function, where golden sections alone need 40.
fn brent_minimum(f: &mut impl FnMut(f64) -> f64, a: f64, b: f64, tol: f64) -> (f64, f64) {
    let golden = 0.5 * (3.0 - 5.0_f64.sqrt());
    let (mut a, mut b) = (a, b);
    let mut x = a + golden * (b - a);
    let (mut w, mut v) = (x, x);
    let mut fx = f(x);
    let (mut fw, mut fv) = (fx, fx);
    let (mut d, mut e) = (0.0_f64, 0.0_f64);
    for _ in 0..60 {
        let m = 0.5 * (a + b);
        if (x - m).abs() <= 2.0 * tol - 0.5 * (b - a) {
            break;
        }
        let mut golden_step = true;
        if e.abs() > tol {
            // Parabola through (v, fv), (w, fw), (x, fx).
            let r = (x - w) * (fx - fv);
            let q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            let mut q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            }
            q = q.abs();
            if p.abs() < (0.5 * q * e).abs() && p > q * (a - x) && p < q * (b - x) {
                e = d;
                d = p / q;
                golden_step = false;
            }
        }
        if golden_step {
            e = if x >= m { a - x } else { b - x };
            d = golden * e;
        }
        let u = if d.abs() >= tol {
            x + d
        } else {
            x + tol.copysign(d)
        };
        let fu = f(u);
        if fu <= fx {
            if u >= x {
                a = x;
            } else {
                b = x;
            }
            (v, fv, w, fw, x, fx) = (w, fw, x, fx, u, fu);
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if fu <= fw || w == x {
                (v, fv, w, fw) = (w, fw, u, fu);
            } else if fu <= fv || v == x || v == w {
                (v, fv) = (u, fu);
            }
        }
    }
    (x, fx)
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

/// The starts of the least-squares method: first the optimum of the simpler structure
/// `structure` contains ([`simpler`]), then the best points of a grid over (k1, k2), each with
/// the least-squares output gain and offset (`options.starts` in all), then the optima of the
/// other structures it contains ([`contained`]). Also, for each contained structure, its cost
/// and its optimum at the limit where this structure reproduces it to rounding (for the
/// fallback of [`fit_smooth_with`]).
#[allow(clippy::too_many_arguments)]
fn start_candidates(
    data: &Dataset,
    structure: Structure,
    layout: &Layout,
    problem: &SmoothProblem<'_>,
    options: &FitOptions,
    observer: &mut dyn Observer,
    contained_fits: &mut Contained,
) -> Result<(Starts, Starts), FitError> {
    // Starting points: a grid over (k1, k2), each with the least-squares output gain and offset,
    // evaluated on the machine's threads (in grid order, as one after the other).
    let grid: Vec<(f64, f64)> = [0.02_f64, 0.05, 0.1, 0.2, 0.4]
        .into_iter()
        .flat_map(|k1| [1.0_f64, 3.0, 10.0, 30.0].map(|k2| (k1, k2)))
        .collect();
    let mut candidates: Vec<(f64, Vec<f64>)> = grid
        .par_iter()
        .filter_map(|&(k1, k2)| {
            let mut theta = layout.start();
            if let Some(i) = layout.index("k1") {
                theta[i] = k1.ln();
            }
            if let Some(i) = layout.index("k2") {
                theta[i] = k2.ln();
            }
            let (theta, z) = linear_output_start(problem, theta)?;
            let cost = problem.cost_from_operator(&theta, &z)?;
            cost.is_finite().then_some((cost, theta))
        })
        .collect();
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
    // The optima of the simpler structures this one contains: the first (along the chain of
    // [`simpler`]) is the first start, the others follow the grid's. The fit then never ends
    // worse than those simpler fits (local minima of the richer one aside; the limits below
    // take care of a saturating shape's). The first counts as one of the `starts`, the best of
    // the grid fill the rest.
    let inner = FitOptions {
        widths: false,
        ..*options
    };
    let mut nested = Vec::new();
    let mut limits = Vec::new();
    for simple in contained(structure) {
        let known = contained_fits.iter().position(|(s, _, _)| *s == simple);
        let at = if let Some(at) = known {
            at
        } else {
            let (f, cost) = fit_smooth_with(data, simple, &inner, observer, contained_fits)?;
            contained_fits.push((simple, f, cost));
            contained_fits.len() - 1
        };
        let Some((_, f, cost)) = contained_fits.get(at) else {
            continue;
        };
        if let Some(theta) = embed(layout, f, problem.input_range, NESTED_SCALE) {
            nested.push(theta);
        }
        if let Some(theta) = embed(layout, f, problem.input_range, LIMIT_SCALE) {
            limits.push((*cost, theta));
        }
    }
    let first = !nested.is_empty();
    candidates.truncate(options.starts - usize::from(first && options.starts > 1));
    let mut nested = nested.into_iter();
    if let Some(theta) = nested.next() {
        candidates.insert(0, (f64::NAN, theta));
    }
    candidates.extend(nested.map(|theta| (f64::NAN, theta)));
    Ok((candidates, limits))
}

/// The scale (in units of its argument's reach on the data) of a saturating shape in the
/// nested start from an affine one: linear to 1 part in 2,700 there, yet curved enough for the
/// descent to find a curvature the data calls for.
const NESTED_SCALE: f64 = 30.0;

/// The parameters of the saturating shapes of θ that sit at their linear limit (a scale of at
/// least a hundredth of [`LIMIT_SCALE`]): the scale and the argument at the centre, which the
/// data cannot tell apart there.
fn linear_limit_parameters(layout: &Layout, theta: &[f64]) -> Vec<&'static str> {
    let mut out = Vec::new();
    for (scale, arg) in [(IN_SCALE, IN_ARG_AT_CENTRE), (OUT_SCALE, OUT_ARG_AT_CENTRE)] {
        let wide = layout
            .index(scale)
            .and_then(|i| Some(layout.params.get(i)?.transform.value(*theta.get(i)?)))
            .is_some_and(|v| v >= 0.01 * LIMIT_SCALE);
        if wide {
            out.push(scale);
            if layout.index(arg).is_some() {
                out.push(arg);
            }
        }
    }
    out
}

/// The scale of a saturating shape at the limit where it reproduces an affine one to rounding:
/// its deviation from the line, (reach / scale)² / 3 relative (tanh; Langevin /15), is 3e-17.
const LIMIT_SCALE: f64 = 1e8;

/// The structures `structure` contains one step down the lattice: constant k2 for affine k2,
/// the next simpler ψ_in, the next simpler ψ_out (those that exist, in this order; the first is
/// [`simpler`]'s). A structure with affine k2 and two shapings contains three; each of them is
/// also contained in others, so the fit of one structure fits each structure below it once.
#[must_use]
pub fn contained(structure: Structure) -> Vec<Structure> {
    [
        simpler_k2(structure),
        simpler_input(structure),
        simpler_output(structure),
    ]
    .into_iter()
    .flatten()
    .collect()
}

/// The simpler structure that `structure` contains, whose optimum is an exact (or, for a
/// saturating shaping, a close) point of `structure`: affine k2 ⊃ constant k2; polynomial ψ_in
/// ⊃ affine ψ_in; tanh and Langevin ψ_in ⊃ affine in the limit of a wide scale (a saturating
/// ψ_in has slope 1 at the input's centre, so k1 and k2 carry over); poly3 ψ_out ⊃ poly2 ⊃
/// affine; tanh and Langevin ψ_out ⊃ affine in the limit of a wide scale. `None` for the
/// simplest structures (and for a quadratic-exp ψ_in, whose limit rescales k1 and k2).
#[must_use]
pub fn simpler(structure: Structure) -> Option<Structure> {
    simpler_k2(structure)
        .or_else(|| simpler_input(structure))
        .or_else(|| simpler_output(structure))
}

/// `structure` with constant k2, if its k2 is affine.
fn simpler_k2(structure: Structure) -> Option<Structure> {
    (structure.k2 == K2Kind::Affine).then_some(Structure {
        k2: K2Kind::Constant,
        ..structure
    })
}

/// `structure` with the next simpler ψ_in, if there is one.
fn simpler_input(structure: Structure) -> Option<Structure> {
    let input_shaping = match structure.input_shaping {
        ShapingKind::Poly3 => ShapingKind::Poly2,
        ShapingKind::Poly2 | ShapingKind::Tanh | ShapingKind::Langevin => ShapingKind::Affine,
        ShapingKind::Affine | ShapingKind::QuadraticExp => return None,
    };
    let saturating = matches!(
        structure.input_shaping,
        ShapingKind::Tanh | ShapingKind::Langevin
    );
    Some(Structure {
        input_shaping,
        // A saturating ψ_in's offset (its argument at the centre) has no affine
        // counterpart: the affine ψ_in gets its default (none).
        input_offset: if saturating {
            None
        } else {
            structure.input_offset
        },
        ..structure
    })
}

/// `structure` with the next simpler ψ_out, if there is one.
fn simpler_output(structure: Structure) -> Option<Structure> {
    let output_shaping = match structure.output_shaping {
        ShapingKind::Poly3 => ShapingKind::Poly2,
        ShapingKind::Poly2 | ShapingKind::Tanh | ShapingKind::Langevin => ShapingKind::Affine,
        ShapingKind::Affine | ShapingKind::QuadraticExp => return None,
    };
    Some(Structure {
        output_shaping,
        ..structure
    })
}

/// The fit `simple` of a structure `layout`'s contains ([`contained`]), as θ of `layout`:
/// shared parameters keep their values, the new ones take the values that reproduce the simpler
/// model (a k2 slope and polynomial coefficients of 0; a tanh or Langevin ψ_in of scale `wide`
/// (normalised input units) with its argument 0 at the centre; a tanh or Langevin ψ_out of a
/// scale `wide` times its argument's reach, argument 0 at the centre, with the affine ψ_out's
/// slope and its level at the centre; `wide` is [`NESTED_SCALE`] for a start, [`LIMIT_SCALE`]
/// at the limit). `None` when the point is not feasible.
fn embed(
    layout: &Layout,
    simple: &SmoothFit,
    input_range: (f64, f64),
    wide: f64,
) -> Option<Vec<f64>> {
    let value = |name: &str| {
        simple
            .estimates
            .iter()
            .find(|e| e.name == name)
            .map(|e| e.value)
    };
    let saturating = matches!(
        layout.structure.output_shaping,
        ShapingKind::Tanh | ShapingKind::Langevin
    ) && simple.layout.structure.output_shaping == ShapingKind::Affine;
    let saturating_input = matches!(
        layout.structure.input_shaping,
        ShapingKind::Tanh | ShapingKind::Langevin
    ) && simple.layout.structure.input_shaping == ShapingKind::Affine;
    let (v_lo, v_hi) = (
        simple.model.input_shaping.apply(input_range.0),
        simple.model.input_shaping.apply(input_range.1),
    );
    let (a_lo, a_hi) =
        SmoothModel::output_argument_range(simple.model.form, simple.model.k1, v_lo, v_hi);
    // In the stop form ψ_out sees (v − H[v]) / k1 ∈ [−1, 1].
    let reach = match simple.model.form {
        Form::Operator => a_lo.abs().max(a_hi.abs()),
        Form::Stop => 1.0,
    };
    let scale = wide * reach;
    // The affine ψ_out's level at the centre of its argument's range.
    let level = simple.model.output_shaping.apply(0.5 * (a_lo + a_hi));
    let mut theta = Vec::with_capacity(layout.len());
    for spec in &layout.params {
        let v = match (spec.name.as_str(), saturating, saturating_input) {
            (IN_SCALE, _, true) => wide,
            (IN_ARG_AT_CENTRE, _, true) | (OUT_ARG_AT_CENTRE, true, _) => 0.0,
            (OUT_SCALE, true, _) => scale,
            ("out.slope", true, _) => value("out.gain")?,
            ("out.level_at_centre", true, _) => level,
            (name, _, _) => value(name).unwrap_or(0.0),
        };
        theta.push(spec.transform.theta(v));
    }
    layout.model(&theta, input_range).ok()?;
    Some(theta)
}

/// Below this k1 · k2 the stop form is in its Dahl limit: its transition after a reversal is
/// the exponential 1 − e^(−k2 Δv) of Dahl's friction model, the same for every smaller k1.
pub const DAHL_LIMIT: f64 = 1e-3;

/// Above this k1 · k2 the operator is in its backlash limit: the corners of its loop (a travel
/// of about 1/k2 after each reversal) are below a millionth of its half-width k1, the same
/// play for every larger k2.
pub const BACKLASH_LIMIT: f64 = 1e6;

/// A limit of the parameter space where the model stays a good model but a parameter is no
/// longer identified (every value beyond gives the same model).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParameterLimit {
    /// The stop form's Dahl limit (k1 · k2 < [`DAHL_LIMIT`], with the largest k2 of the law):
    /// k1 is not identified.
    Dahl {
        /// The (largest) k2.
        k2: f64,
    },
    /// The backlash limit (k1 · k2 > [`BACKLASH_LIMIT`], with the smallest k2 of the law): a
    /// play of half-width k1; k2 (and its slope) are not identified.
    Backlash {
        /// The (smallest) k2.
        k2: f64,
    },
}

impl ParameterLimit {
    /// The limit `model` is in, if any.
    #[must_use]
    pub fn of(model: &SmoothModel) -> Option<Self> {
        let (lo, hi) = match model.k2 {
            hyst_core::AnyK2Law::Constant { value } => (value, value),
            hyst_core::AnyK2Law::Affine(law) => (law.min, law.max),
        };
        if model.form == Form::Stop && model.k1 * hi < DAHL_LIMIT {
            Some(Self::Dahl { k2: hi })
        } else if model.k1 * lo > BACKLASH_LIMIT {
            Some(Self::Backlash { k2: lo })
        } else {
            None
        }
    }

    /// The parameters the limit leaves unidentified.
    #[must_use]
    pub fn unidentified(self) -> &'static [&'static str] {
        match self {
            Self::Dahl { .. } => &["k1"],
            Self::Backlash { .. } => &["k2", "k2.slope"],
        }
    }

    /// The report's note on the limit for a model of half-width `k1`.
    #[must_use]
    pub fn note(self, k1: f64) -> String {
        match self {
            Self::Dahl { k2 } => format!(
                "k1 · k2 = {} < {DAHL_LIMIT}: the stop form's Dahl limit (after each reversal the \
                 output approaches its level as 1 − e^(−k2 Δv), over a travel of about 3/k2 = {} \
                 normalised input units); every smaller k1 gives the same model, so k1 is not \
                 identified",
                sig(k1 * k2, 2),
                sig(3.0 / k2, 3),
            ),
            Self::Backlash { k2 } => format!(
                "k1 · k2 = {} > {}: the backlash limit (a play of half-width k1 = {} whose \
                 corners are sharper than a millionth of k1); every larger k2 gives the same \
                 model, so k2 is not identified",
                sig(k1 * k2, 2),
                sig(BACKLASH_LIMIT, 1),
                sig(k1, 4),
            ),
        }
    }
}

/// Sets the output gain (and offset, and the stop form's linear term) of θ by linear least
/// squares on the shaped operator output (the rest of θ fixed), and returns it with the
/// operator output H[ψ_in(in)] per residual (which the new θ leaves as it is). `None` when the
/// point is infeasible.
fn linear_output_start(
    problem: &SmoothProblem<'_>,
    mut theta: Vec<f64>,
) -> Option<(Vec<f64>, Vec<f64>)> {
    let layout = problem.layout;
    // The overall gain: ψ_out's, a saturating ψ_out's slope at the centre, or the stop form's
    // level (gain × k1); the offset: ψ_out's, or a saturating ψ_out's level at the centre
    // (ψ_out is linear in both).
    let gi = layout
        .index("out.gain")
        .or_else(|| layout.index("out.slope"))
        .or_else(|| layout.index("out.level"))?;
    let oi = layout
        .index("out.offset")
        .or_else(|| layout.index("out.level_at_centre"));
    let li = layout.index("out.linear");
    theta[gi] = 0.0; // gain 1
    for k in [oi, li].into_iter().flatten() {
        theta[k] = 0.0;
    }
    let m = problem.model(&theta).ok()?;
    let (mut s, mut z) = (vec![0.0; problem.n], vec![0.0; problem.n]);
    problem.simulate(&m, &mut s, Some(&mut z)).ok()?;
    // Columns: the shaped output (gain 1), then v = ψ_in(in) for the linear term, then 1.
    let p = 1 + usize::from(li.is_some()) + usize::from(oi.is_some());
    let (mut a, mut b) = (vec![0.0; p * p], vec![0.0; p]);
    let mut i = 0;
    for rec in problem.data.training() {
        for ((x, obs), w) in rec.input.iter().zip(&rec.output).zip(&rec.weight) {
            let mut row = [s[i], 0.0, 0.0];
            let mut k = 1;
            if li.is_some() {
                row[k] = m.input_shaping.apply(*x);
                k += 1;
            }
            if oi.is_some() {
                row[k] = 1.0;
            }
            for r in 0..p {
                b[r] += w * row[r] * obs;
                for c in 0..p {
                    a[r * p + c] += w * row[r] * row[c];
                }
            }
            i += 1;
        }
    }
    let coef = cholesky_solve(&a, &b, p).unwrap_or_else(|| vec![f64::NAN; p]);
    let gain = coef[0];
    let gain = if gain.is_finite() && gain > 0.0 {
        gain
    } else {
        1e-3 * layout.norm.output_half_span
    };
    theta[gi] = gain.ln();
    for (k, index) in (1..).zip([li, oi].into_iter().flatten()) {
        theta[index] = if coef[k].is_finite() { coef[k] } else { 0.0 };
    }
    Some((theta, z))
}

/// The output of `model` on every record of `data` (record order), each history run from its
/// estimated start `starts` (per history, [`SmoothFit::starts`]) or the start rule.
#[must_use]
pub fn run_records(
    data: &Dataset,
    model: &SmoothModel,
    starts: Option<&[f64]>,
) -> Option<Vec<Vec<f64>>> {
    data.run_histories_with(|index, input| {
        let mut y = vec![0.0; input.len()];
        let band = starts.and_then(|s| s.get(index).copied());
        model.simulate_from(input, band, None, &mut y).ok()?;
        Some(y)
    })
}

/// Training and validation error statistics of any model (`run` maps a record's input to its
/// output, `None` when the model cannot run it).
///
/// # Errors
/// [`FitError::NoConvergence`] when the model cannot run a record.
pub fn error_stats(
    data: &Dataset,
    run: impl Fn(&[f64]) -> Option<Vec<f64>>,
) -> Result<(ErrorStats, Option<ErrorStats>), FitError> {
    let outputs = data
        .run_histories(run)
        .ok_or_else(|| FitError::NoConvergence("the fitted model cannot run the records".into()))?;
    Ok(error_stats_of(data, &outputs))
}

/// Training and validation error statistics of the model `outputs` (one per record).
#[must_use]
pub fn error_stats_of(data: &Dataset, outputs: &[Vec<f64>]) -> (ErrorStats, Option<ErrorStats>) {
    let (lo, hi) = data.output_range();
    let span = (hi - lo).max(f64::MIN_POSITIVE);
    let mut train = Vec::new();
    let mut val = Vec::new();
    for (r, y) in data.records.iter().zip(outputs) {
        let errs = if r.validation { &mut val } else { &mut train };
        for ((m, o), w) in y.iter().zip(&r.output).zip(&r.weight) {
            if *w > 0.0 {
                errs.push(m - o);
            }
        }
    }
    let v = if val.is_empty() {
        None
    } else {
        Some(ErrorStats::new(&val, span))
    };
    (ErrorStats::new(&train, span), v)
}

/// Refuses a fit whose error statistics or parameter values are not finite
/// ([`FitError::NonFiniteResult`]). Standard errors may be NaN (a parameter the data does not
/// identify) and are not checked.
///
/// # Errors
/// [`FitError::NonFiniteResult`] naming the first non-finite number.
pub fn check_finite<'a>(
    file: &str,
    training: &ErrorStats,
    validation: Option<&ErrorStats>,
    parameters: impl IntoIterator<Item = (&'a str, f64)>,
) -> Result<(), FitError> {
    let stats = [("training", Some(training)), ("validation", validation)];
    let mut numbers: Vec<(String, f64)> = Vec::new();
    for (set, s) in stats {
        if let Some(s) = s {
            numbers.push((format!("the {set} RMS"), s.rms));
            numbers.push((format!("the {set} max error"), s.max_abs));
        }
    }
    numbers.extend(
        parameters
            .into_iter()
            .map(|(name, v)| (format!("parameter {name}"), v)),
    );
    match numbers.into_iter().find(|(_, v)| !v.is_finite()) {
        Some((what, value)) => Err(FitError::NonFiniteResult {
            file: file.to_string(),
            what,
            value,
        }),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::indexing_slicing)]
    use super::*;
    use crate::data::Record;
    use hyst_model::{Columns, Form, K2Kind, ShapingKind};

    /// Three records: the second continues the first (one history), the third is held out in
    /// between so the residual rows skip it, and a fourth starts afresh.
    fn data() -> Dataset {
        let record = |id: i64, phase: f64, validation: bool, continues: bool| {
            let input: Vec<f64> = (0..300)
                .map(|k| {
                    let t = f64::from(k) * 0.03 + phase;
                    2.0 + 1.5 * t.sin() * (1.0 + 0.3 * (0.31 * t).cos())
                })
                .collect();
            let output = input
                .iter()
                .map(|x| 3.0 * x + 0.4 * (x * 1.7).sin())
                .collect();
            Record {
                id,
                weight: vec![1.0; input.len()],
                rows: (0..input.len()).collect(),
                output,
                input,
                validation,
                continues,
            }
        };
        let records = vec![
            record(0, 0.0, false, false),
            record(1, 9.0, true, true),
            record(2, 18.0, false, true),
            record(3, 2.0, false, false),
        ];
        Dataset::from_records("test", Columns::default(), records)
    }

    /// The dual Jacobian equals central differences of the residuals (the same evaluation), for
    /// structures with every kind of parameter: k2 law, ψ_in, ψ_out, offsets, the stop form.
    #[test]
    fn dual_jacobian_equals_central_differences() {
        let data = data();
        let structures = [
            (
                K2Kind::Constant,
                ShapingKind::Affine,
                ShapingKind::Tanh,
                Form::Operator,
            ),
            (
                K2Kind::Affine,
                ShapingKind::Poly2,
                ShapingKind::Langevin,
                Form::Operator,
            ),
            (
                K2Kind::Constant,
                ShapingKind::Langevin,
                ShapingKind::Poly3,
                Form::Operator,
            ),
            (
                K2Kind::Constant,
                ShapingKind::Tanh,
                ShapingKind::Affine,
                Form::Stop,
            ),
        ];
        for (k2, input_shaping, output_shaping, form) in structures {
            let structure = Structure {
                k2,
                input_shaping,
                output_shaping,
                form,
                ..Structure::default()
            };
            let layout = Layout::new(structure, normalisation(&data));
            let problem = SmoothProblem::new(&layout, &data, false);
            let (n, p) = (problem.n, layout.len());
            // A point away from the neutral start (k1 0.3, k2 4, small shape parameters).
            let mut theta = layout.start();
            theta[0] = 0.3_f64.ln();
            theta[1] = 4.0_f64.ln();
            for (j, spec) in layout.params.iter().enumerate().skip(2) {
                if spec.transform == crate::layout::Transform::Linear && spec.start == 0.0 {
                    theta[j] = 0.01 * (j as f64);
                }
            }
            let mut r = vec![0.0; n];
            problem.residuals(&theta, &mut r).unwrap();
            let mut jac = vec![0.0; n * p];
            problem.jacobian(&theta, &r, &mut jac).unwrap();
            let (mut up, mut down) = (vec![0.0; n], vec![0.0; n]);
            for j in 0..p {
                let h = 1e-6 * theta[j].abs().max(1.0);
                let mut t = theta.clone();
                t[j] = theta[j] + h;
                problem.residuals(&t, &mut up).unwrap();
                t[j] = theta[j] - h;
                problem.residuals(&t, &mut down).unwrap();
                for i in 0..n {
                    let fd = (up[i] - down[i]) / (2.0 * h);
                    let d = jac[j * n + i];
                    assert!(
                        (d - fd).abs() <= 1e-5 * (1.0 + fd.abs()),
                        "{structure:?} {} row {i}: dual {d} vs central difference {fd}",
                        layout.params[j].name
                    );
                }
            }
        }
    }

    #[test]
    fn brent_finds_inner_and_edge_minima_in_few_evaluations() {
        let mut calls = 0;
        let mut f = |x: f64| {
            calls += 1;
            (x - 0.3).powi(2) + 0.1 * (x - 0.3).powi(4)
        };
        let (x, _) = brent_minimum(&mut f, -1.0, 1.0, 1e-7);
        assert!(
            (x - 0.3).abs() < 1e-6 && calls < 30,
            "{x} after {calls} calls"
        );
        let (x, _) = brent_minimum(&mut |x: f64| x, -1.0, 1.0, 1e-7);
        assert!(x < -1.0 + 1e-6, "{x}");
    }
}
