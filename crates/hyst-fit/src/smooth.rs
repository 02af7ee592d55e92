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

use std::ops::ControlFlow;
use std::time::Instant;

use hyst_core::{Dual, Shaping};
use serde::Serialize;

use crate::lm::{
    Infeasible, LevenbergMarquardt, Observer, Problem, Progress, Solution, Termination,
};
use crate::model::FitReal;
use crate::structure::{Layout, Normalisation, Structure};
use crate::widths::{family_widths, FamilyWidths};
use crate::{Dataset, FitError, SmoothModel};

/// Options of the fit.
#[derive(Clone, Copy, Debug)]
pub struct FitOptions {
    /// Number of starts refined by the least-squares method (the best of a grid over k1, k2).
    pub starts: usize,
    /// The method.
    pub method: LevenbergMarquardt,
    /// Coverage for the family widths (fraction of samples inside the envelope), in (0, 1].
    pub coverage: f64,
    /// Compute family widths (a few hundred extra simulations).
    pub widths: bool,
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            starts: 3,
            method: LevenbergMarquardt::default(),
            coverage: 0.99,
            widths: true,
        }
    }
}

/// A fitted parameter with its standard error.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct Estimate {
    /// Name ("k1", "out.gain", …).
    pub name: String,
    /// Value.
    pub value: f64,
    /// Standard error from the covariance σ² (JᵀJ)⁻¹ (NaN when the parameter is not
    /// identifiable from the data). Assumes independent residuals: correlated measurement
    /// noise makes it optimistic.
    pub std_error: f64,
    /// Units.
    pub unit: String,
}

/// Error statistics of a model on a set of records.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, serde::Deserialize, Default)]
pub struct ErrorStats {
    /// Samples used (weight > 0).
    pub samples: usize,
    /// Root mean square error (output units).
    pub rms: f64,
    /// Largest absolute error (output units).
    pub max_abs: f64,
    /// RMS as % of the output span of the whole dataset.
    pub rms_pct_span: f64,
    /// Max error as % of the output span.
    pub max_pct_span: f64,
}

impl ErrorStats {
    /// Statistics of `errors` against an output span.
    #[must_use]
    pub fn new(errors: &[f64], span: f64) -> Self {
        if errors.is_empty() {
            return Self::default();
        }
        let n = errors.len();
        let rms = (errors.iter().map(|e| e * e).sum::<f64>() / n as f64).sqrt();
        let max_abs = errors.iter().fold(0.0_f64, |m, e| m.max(e.abs()));
        Self {
            samples: n,
            rms,
            max_abs,
            rms_pct_span: 100.0 * rms / span,
            max_pct_span: 100.0 * max_abs / span,
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
    /// Wall time of the fit (s).
    pub seconds: f64,
}

/// The least-squares problem of one structure on one dataset.
struct SmoothProblem<'a> {
    layout: &'a Layout,
    data: &'a Dataset,
    input_range: (f64, f64),
    /// √w / output half-span per training sample, in residual order.
    scale: Vec<f64>,
    n: usize,
}

impl<'a> SmoothProblem<'a> {
    fn new(layout: &'a Layout, data: &'a Dataset) -> Self {
        let inv = 1.0 / layout.norm.output_half_span;
        let scale: Vec<f64> = data
            .training()
            .flat_map(|r| r.weight.iter().map(move |w| w.sqrt() * inv))
            .collect();
        Self {
            layout,
            data,
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

    /// Simulates the training records; `z` receives the operator output when given.
    fn simulate(
        &self,
        m: &SmoothModel,
        y: &mut [f64],
        mut z: Option<&mut [f64]>,
    ) -> Result<(), Infeasible> {
        let mut at = 0;
        for r in self.data.training() {
            let end = at + r.len();
            let zs = z.as_deref_mut().map(|z| &mut z[at..end]);
            m.simulate(&r.input, zs, &mut y[at..end])
                .map_err(|_| Infeasible)?;
            at = end;
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
    /// the training records: θ_j seeded as the dual variable j − offset, the others constant.
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
        let columns = N.min(theta.len().saturating_sub(offset));
        let jac = jac
            .get_mut(offset * n..(offset + columns) * n)
            .ok_or(Infeasible)?;
        let mut at = 0;
        let mut finite = true;
        for rec in self.data.training() {
            m.run_with(&rec.input, |i, _, y| {
                let k = at + i;
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
            at += rec.len();
        }
        if finite {
            Ok(())
        } else {
            Err(Infeasible)
        }
    }
}

/// Tags progress with the start number.
struct Tagged<'a> {
    inner: &'a mut dyn Observer,
    start: usize,
}

impl Observer for Tagged<'_> {
    fn observe(&mut self, progress: &Progress) -> ControlFlow<()> {
        self.inner.observe(&Progress {
            start: self.start,
            ..*progress
        })
    }
}

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
    let started = Instant::now();
    if !(options.coverage > 0.0 && options.coverage <= 1.0) {
        return Err(FitError::Invalid(format!(
            "coverage {} must be in (0, 1]",
            options.coverage
        )));
    }
    let layout = Layout::new(structure, normalisation(data));
    data.check(layout.len(), structure.form == crate::Form::Operator)?;
    let problem = SmoothProblem::new(&layout, data);

    // Starting points: a grid over (k1, k2), each with the least-squares output gain and offset.
    let mut candidates: Vec<(f64, Vec<f64>)> = Vec::new();
    for k1 in [0.02_f64, 0.05, 0.1, 0.2, 0.4] {
        for k2 in [1.0_f64, 3.0, 10.0, 30.0] {
            let mut theta = layout.start();
            if let Some(i) = layout.index("k1") {
                theta[i] = k1.ln();
            }
            if let Some(i) = layout.index("k2") {
                theta[i] = k2.ln();
            }
            if let Some(theta) = linear_output_start(&problem, theta) {
                let mut r = vec![0.0; problem.n];
                if problem.residuals(&theta, &mut r).is_ok() {
                    let cost: f64 = r.iter().map(|v| v * v).sum();
                    if cost.is_finite() {
                        candidates.push((cost, theta));
                    }
                }
            }
        }
    }
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut best: Option<Solution> = None;
    for (start, (_, theta0)) in candidates.iter().take(options.starts.max(1)).enumerate() {
        let mut tagged = Tagged {
            inner: &mut *observer,
            start,
        };
        let s = options.method.minimize(&problem, theta0, &mut tagged)?;
        if best.as_ref().is_none_or(|b| s.cost < b.cost) {
            best = Some(s);
        }
    }
    let best = best
        .filter(|b| b.cost.is_finite())
        .ok_or_else(|| FitError::NoConvergence("no starting point gave a finite cost".into()))?;
    let model = layout.model(&best.theta, problem.input_range)?;

    // Standard errors: cov θ = s² (JᵀJ)⁻¹, s² = Σ r² / (n − p); value = f(θ). In the stop
    // form's Dahl limit k1 carries no information (its column of J vanishes): the covariance
    // of the others is taken without it, and k1's standard error is NaN.
    let p = layout.len();
    let dof = (problem.n - p).max(1) as f64;
    let s2 = best.cost / dof * layout.norm.output_half_span.powi(2);
    let dahl = dahl_limit(&model).is_some();
    let kept: Vec<usize> = (0..p)
        .filter(|&j| !(dahl && layout.params[j].name == "k1"))
        .collect();
    let q = kept.len();
    let mut reduced = vec![0.0; q * q];
    for (a, &i) in kept.iter().enumerate() {
        for (b, &j) in kept.iter().enumerate() {
            reduced[a * q + b] = best.jtj[i * p + j];
        }
    }
    let inv = crate::linalg::spd_inverse(&reduced, q);
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

    let (training, validation) = error_stats(data, |input| model.run(input).ok())?;
    let widths = if options.widths {
        Some(family_widths(data, &model, options.coverage, observer)?)
    } else {
        None
    };
    check_finite(
        &data.source,
        &training,
        validation.as_ref(),
        estimates.iter().map(|e| (e.name.as_str(), e.value)),
    )?;
    Ok(SmoothFit {
        model,
        layout,
        theta: best.theta.clone(),
        estimates,
        training,
        validation,
        widths,
        iterations: best.iterations,
        termination: best.termination,
        seconds: started.elapsed().as_secs_f64(),
    })
}

/// Below this k1 · k2 the stop form is in its Dahl limit: its transition after a reversal is
/// the exponential 1 − e^(−k2 Δv) of Dahl's friction model, the same for every smaller k1.
pub const DAHL_LIMIT: f64 = 1e-3;

/// When `model` is a stop form in its Dahl limit (k1 · k2 < [`DAHL_LIMIT`] for the largest k2
/// of its law), where k1 is not identified: that largest k2.
#[must_use]
pub fn dahl_limit(model: &SmoothModel) -> Option<f64> {
    let k2 = match model.k2 {
        hyst_core::AnyK2Law::Constant { value } => value,
        hyst_core::AnyK2Law::Affine(law) => law.max,
    };
    (model.form == crate::Form::Stop && model.k1 * k2 < DAHL_LIMIT).then_some(k2)
}

/// Sets the output gain (and offset, and the stop form's linear term) of θ by linear least
/// squares on the shaped operator output (the rest of θ fixed). `None` when the point is
/// infeasible.
fn linear_output_start(problem: &SmoothProblem<'_>, mut theta: Vec<f64>) -> Option<Vec<f64>> {
    let layout = problem.layout;
    // The overall gain: ψ_out's, or the stop form's level (gain × k1).
    let gi = layout
        .index("out.gain")
        .or_else(|| layout.index("out.level"))?;
    let oi = layout.index("out.offset");
    let li = layout.index("out.linear");
    theta[gi] = 0.0; // gain 1
    for k in [oi, li].into_iter().flatten() {
        theta[k] = 0.0;
    }
    let m = problem.model(&theta).ok()?;
    let mut s = vec![0.0; problem.n];
    problem.simulate(&m, &mut s, None).ok()?;
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
    let coef = crate::linalg::cholesky_solve(&a, &b, p).unwrap_or_else(|| vec![f64::NAN; p]);
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
    Some(theta)
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
    let (lo, hi) = data.output_range();
    let span = (hi - lo).max(f64::MIN_POSITIVE);
    let mut train = Vec::new();
    let mut val = Vec::new();
    for r in &data.records {
        let y = run(&r.input).ok_or_else(|| {
            FitError::NoConvergence(format!("the fitted model cannot run record {}", r.id))
        })?;
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
    Ok((ErrorStats::new(&train, span), v))
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
