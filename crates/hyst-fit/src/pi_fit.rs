//! Fitting the Prandtl–Ishlinskii baseline ([`crate::pi`]): thresholds spread evenly over half
//! the input span, weights by weighted non-negative least squares (w0 ≥ ε > 0, w_i ≥ 0, c free),
//! which keeps the operator monotone and its analytic inverse valid.
//!
//! With an output polynomial P of degree 2 or 3 (y = P(PI[x])): the PI output is linear in the
//! weights, so the fit alternates two exact sub-problems: the polynomial by weighted linear least
//! squares given the PI output (kept increasing on the data), and the weights by non-negative
//! least squares on the Gauss–Newton linearisation around the current polynomial (with a
//! backtracking step, which keeps the weights feasible because the constraint set is convex).

use std::time::Instant;

use hyst_core::{play, Polynomial, Shaping};

use crate::linalg::{cholesky_solve, nnls, spd_inverse};
use hyst_model::pi::MAX_PLAYS;
use hyst_model::{Choice, ErrorStats, Estimate, PiModel, PiOutput};

use crate::data::{Dataset, Record};
use crate::error::FitError;
use crate::smooth::stats::{check_finite, error_stats};

/// Which output polynomial follows the Prandtl–Ishlinskii sum (`none`, `poly2`, `poly3`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum PiOutputKind {
    /// No output polynomial: y = PI[x].
    #[default]
    None,
    /// y = P(PI[x]), P quadratic and increasing on the data.
    Poly2,
    /// y = P(PI[x]), P cubic and increasing on the data.
    Poly3,
}

impl Choice for PiOutputKind {
    const WHAT: &'static str = "output polynomial";
    const CHOICES: &'static [(Self, &'static str, &'static str)] = &[
        (
            PiOutputKind::None,
            "none",
            "No output polynomial: y = PI[x]",
        ),
        (
            PiOutputKind::Poly2,
            "poly2",
            "y = P(PI[x]), P quadratic and increasing on the data",
        ),
        (
            PiOutputKind::Poly3,
            "poly3",
            "y = P(PI[x]), P cubic and increasing on the data",
        ),
    ];
}

impl PiOutputKind {
    /// The polynomial degree (1 for none: the PI's own affine output).
    #[must_use]
    pub fn degree(self) -> usize {
        match self {
            PiOutputKind::None => 1,
            PiOutputKind::Poly2 => 2,
            PiOutputKind::Poly3 => 3,
        }
    }
}

/// A fitted Prandtl–Ishlinskii model.
#[derive(Clone, Debug)]
pub struct PiFit {
    /// The model.
    pub model: PiModel,
    /// w0, offset and weights with standard errors (from the unconstrained covariance of the
    /// free set; weights at the bound 0 get 0).
    pub estimates: Vec<Estimate>,
    /// Training errors.
    pub training: ErrorStats,
    /// Validation errors.
    pub validation: Option<ErrorStats>,
    /// Wall time (s).
    pub seconds: f64,
}

/// Play outputs of one record for thresholds `r` (plays at rest at the first sample), by the
/// core's play update.
fn play_outputs(input: &[f64], r: &[f64]) -> Vec<Vec<f64>> {
    let mut state: Vec<f64> = r
        .iter()
        .map(|_| input.first().copied().unwrap_or(0.0))
        .collect();
    let mut cols = vec![Vec::with_capacity(input.len()); r.len()];
    for x in input {
        for ((p, ri), col) in state.iter_mut().zip(r).zip(cols.iter_mut()) {
            *p = play::update(*p, *x, *ri);
            col.push(*p);
        }
    }
    cols
}

/// Fits a Prandtl–Ishlinskii model with `plays` plays (no output polynomial) to the
/// training records.
///
/// # Errors
/// As [`fit_pi_with`].
pub fn fit_pi(data: &Dataset, plays: usize) -> Result<PiFit, FitError> {
    fit_pi_with(data, plays, PiOutputKind::None)
}

/// Fits a Prandtl–Ishlinskii model with `plays` plays and the chosen output polynomial to
/// the training records (see the module docs for the method).
///
/// # Errors
/// [`FitError::InvalidSetting`] naming `plays` when it is outside 1..=[`MAX_PLAYS`];
/// bad data ([`Dataset::check`]); [`FitError::NoConvergence`] when the output polynomial cannot
/// be fitted.
pub fn fit_pi_with(data: &Dataset, plays: usize, output: PiOutputKind) -> Result<PiFit, FitError> {
    let started = Instant::now();
    if plays == 0 || plays > MAX_PLAYS {
        return Err(FitError::InvalidSetting {
            name: "plays",
            value: plays as f64,
            expected: format!("1 to {MAX_PLAYS} plays"),
        });
    }
    data.check(plays + 1 + output.degree(), true)?;
    let r = thresholds(data, plays);
    let normal = Centred::new(data, &r);
    let (w, offset) = normal.weights();
    // With an output polynomial its own fit gives the model and estimates; without, the plain
    // sum and its standard errors. Both then go through the same checks.
    let (model, estimates) = if output != PiOutputKind::None {
        let design = Design::new(&normal.columns, normal.m);
        fit_output(&design, &r, &w, offset, output.degree(), n_of(data))?
    } else {
        normal.plain(data, r, w, offset)
    };
    let (training, validation) = error_stats(data, |x| model.run(x).ok())?;
    check_finite(
        &data.source,
        &training,
        validation.as_ref(),
        estimates.iter().map(|e| (e.name.as_str(), e.value)),
    )?;
    Ok(PiFit {
        model,
        estimates,
        training,
        validation,
        seconds: started.elapsed().as_secs_f64(),
    })
}

/// The thresholds of `plays` plays, spread evenly over half the input span of `data`.
fn thresholds(data: &Dataset, plays: usize) -> Vec<f64> {
    let (lo, hi) = data.input_range();
    let span = hi - lo;
    (1..=plays)
        .map(|i| span * i as f64 / (2.0 * (plays + 1) as f64))
        .collect()
}

/// The weighted least-squares problem of the plain sum on the training records, centred: the
/// free offset is eliminated exactly by the weighted means.
struct Centred<'a> {
    /// Columns of the sum: the identity, then the plays.
    m: usize,
    /// Σ w over the training samples.
    sw: f64,
    /// Weighted mean of each column.
    mean: Vec<f64>,
    /// Weighted mean of the output.
    ymean: f64,
    /// The centred Gram matrix Σ w (x_a − x̄_a)(x_b − x̄_b) (m × m, row-major).
    gram: Vec<f64>,
    /// Σ w (x_a − x̄_a)(y − ȳ).
    rhs: Vec<f64>,
    /// Σ w (y − ȳ)².
    syy: f64,
    /// Per training record, its columns (the input, then each play's output).
    columns: Vec<(Vec<Vec<f64>>, &'a Record)>,
}

impl<'a> Centred<'a> {
    /// The centred problem of the plays of thresholds `r` on the training records of `data`.
    fn new(data: &'a Dataset, r: &[f64]) -> Self {
        let m = r.len() + 1; // identity + plays
                             // Weighted means, then the centred Gram matrix (the free offset is eliminated exactly).
        let mut sw = 0.0;
        let mut mean = vec![0.0; m];
        let mut ymean = 0.0;
        let mut columns: Vec<(Vec<Vec<f64>>, &Record)> = Vec::new();
        for rec in data.training() {
            let mut cols = vec![rec.input.to_vec()];
            cols.extend(play_outputs(&rec.input, r));
            for (i, w) in rec.weight.iter().enumerate() {
                sw += w;
                ymean += w * rec.output[i];
                for (j, c) in cols.iter().enumerate() {
                    mean[j] += w * c[i];
                }
            }
            columns.push((cols, rec));
        }
        for v in mean.iter_mut() {
            *v /= sw;
        }
        ymean /= sw;
        let mut gram = vec![0.0; m * m];
        let mut rhs = vec![0.0; m];
        let mut syy = 0.0;
        for (cols, rec) in &columns {
            for (i, w) in rec.weight.iter().enumerate() {
                let yc = rec.output[i] - ymean;
                syy += w * yc * yc;
                for a in 0..m {
                    let xa = cols[a][i] - mean[a];
                    rhs[a] += w * xa * yc;
                    for b in a..m {
                        gram[a * m + b] += w * xa * (cols[b][i] - mean[b]);
                    }
                }
            }
        }
        for a in 0..m {
            for b in 0..a {
                gram[a * m + b] = gram[b * m + a];
            }
        }
        Self {
            m,
            sw,
            mean,
            ymean,
            gram,
            rhs,
            syy,
            columns,
        }
    }

    /// The weights (w0 first) by non-negative least squares with w0 ≥ ε > 0, and the offset.
    fn weights(&self) -> (Vec<f64>, f64) {
        let (m, gram, rhs) = (self.m, &self.gram, &self.rhs);
        // w0 ≥ ε: shift the variable.
        let eps = 1e-6 * (rhs[0] / gram[0].max(f64::MIN_POSITIVE)).abs().max(1e-12);
        let shifted: Vec<f64> = (0..m).map(|a| rhs[a] - gram[a * m] * eps).collect();
        let mut w = nnls(gram, &shifted, m);
        w[0] += eps;
        let offset = self.ymean - w.iter().zip(&self.mean).map(|(a, b)| a * b).sum::<f64>();
        (w, offset)
    }

    /// The plain sum (no output polynomial) of thresholds `r`, weights `w` and `offset`, with
    /// its estimates: standard errors on the free set (weights away from 0), the offset's from
    /// the centred model.
    fn plain(
        &self,
        data: &Dataset,
        r: Vec<f64>,
        w: Vec<f64>,
        offset: f64,
    ) -> (PiModel, Vec<Estimate>) {
        let (m, gram, rhs) = (self.m, &self.gram, &self.rhs);
        let model = PiModel {
            identity_weight: w[0],
            thresholds: r,
            weights: w[1..].to_vec(),
            offset,
            output: None,
        };
        let cost = (self.syy - 2.0 * w.iter().zip(rhs).map(|(a, b)| a * b).sum::<f64>()
            + (0..m)
                .map(|a| (0..m).map(|b| w[a] * gram[a * m + b] * w[b]).sum::<f64>())
                .sum::<f64>())
        .max(0.0);
        let n = data.training_samples();
        let free = free_set(&w);
        let s2 = cost / (n.saturating_sub(free.len() + 1).max(1)) as f64;
        let se = std_errors(gram, m, &free, s2);
        let mut estimates = vec![
            Estimate {
                name: "w0".into(),
                value: w[0],
                std_error: se[0],
                unit: "output/input".into(),
            },
            Estimate {
                name: "offset".into(),
                value: offset,
                std_error: (s2 / self.sw).sqrt(),
                unit: "output units".into(),
            },
        ];
        for j in 1..m {
            estimates.push(Estimate {
                name: format!("w{j} (r = {:.4})", model.thresholds[j - 1]),
                value: w[j],
                std_error: se[j],
                unit: "output/input".into(),
            });
        }
        (model, estimates)
    }
}

fn n_of(data: &Dataset) -> usize {
    data.training_samples()
}

/// The training samples as a dense design: row i holds (x, p_1, …, p_n) of sample i.
struct Design {
    a: Vec<f64>,
    y: Vec<f64>,
    wt: Vec<f64>,
    m: usize,
}

impl Design {
    fn new(columns: &[(Vec<Vec<f64>>, &Record)], m: usize) -> Self {
        let mut d = Design {
            a: Vec::new(),
            y: Vec::new(),
            wt: Vec::new(),
            m,
        };
        for (cols, rec) in columns {
            for i in 0..rec.output.len() {
                for c in cols.iter().take(m) {
                    d.a.push(c[i]);
                }
                d.y.push(rec.output[i]);
                d.wt.push(rec.weight[i]);
            }
        }
        d
    }

    fn rows(&self) -> impl Iterator<Item = (&[f64], f64, f64)> {
        self.a
            .chunks_exact(self.m)
            .zip(&self.y)
            .zip(&self.wt)
            .map(|((a, y), w)| (a, *y, *w))
    }

    /// The PI output β + Σ a_j w_j of every sample.
    fn pi_output(&self, w: &[f64], beta: f64) -> Vec<f64> {
        self.a
            .chunks_exact(self.m)
            .map(|row| beta + row.iter().zip(w).map(|(a, b)| a * b).sum::<f64>())
            .collect()
    }

    /// Weighted sum of squared output errors of y = P(s) (P with its tangent extension).
    fn cost(&self, s: &[f64], p: &Polynomial<f64>) -> f64 {
        s.iter()
            .zip(&self.y)
            .zip(&self.wt)
            .map(|((s, y), w)| {
                let e = y - p.apply(*s);
                w * e * e
            })
            .sum()
    }

    /// Range of s over the samples with weight > 0.
    fn range(&self, s: &[f64]) -> (f64, f64) {
        s.iter()
            .zip(&self.wt)
            .filter(|(_, w)| **w > 0.0)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (v, _)| {
                (a.min(*v), b.max(*v))
            })
    }
}

/// Coefficients of t ↦ P(α t + γ) for P(s) = Σ c_k s^k.
fn compose_affine(c: &[f64; 4], alpha: f64, gamma: f64) -> [f64; 4] {
    const BINOM: [[f64; 4]; 4] = [
        [1.0, 0.0, 0.0, 0.0],
        [1.0, 1.0, 0.0, 0.0],
        [1.0, 2.0, 1.0, 0.0],
        [1.0, 3.0, 3.0, 1.0],
    ];
    let mut out = [0.0; 4];
    for k in 0..4 {
        for j in 0..=k {
            out[j] += c[k] * BINOM[k][j] * alpha.powi(j as i32) * gamma.powi((k - j) as i32);
        }
    }
    out
}

/// The smallest slope of P on [lo, hi] (P' is a quadratic: ends and vertex).
fn min_slope(c: &[f64; 4], lo: f64, hi: f64) -> f64 {
    let d = |x: f64| c[1] + x * (2.0 * c[2] + 3.0 * c[3] * x);
    let mut m = d(lo).min(d(hi));
    if c[3] != 0.0 {
        let v = -c[2] / (3.0 * c[3]);
        if v > lo && v < hi {
            m = m.min(d(v));
        }
    }
    m
}

/// P as a core polynomial on [lo, hi] when it is increasing there with a margin (its smallest
/// slope at least 1e-6 of its mean slope, so the inverse stays well conditioned).
fn feasible(c: &[f64; 4], lo: f64, hi: f64) -> Option<Polynomial<f64>> {
    let p = Polynomial::new(*c, lo, hi).ok()?;
    let mean = (p.eval(hi) - p.eval(lo)) / (hi - lo);
    (mean > 0.0 && min_slope(c, lo, hi) >= 1e-6 * mean).then_some(p)
}

/// Weighted least-squares polynomial of the given degree through (s, y), in monomials of s.
fn poly_ls(d: &Design, s: &[f64], degree: usize) -> Option<[f64; 4]> {
    let k = degree + 1;
    let mut g = vec![0.0; k * k];
    let mut b = vec![0.0; k];
    for ((sv, y), w) in s.iter().zip(&d.y).zip(&d.wt) {
        let mut pw = [1.0; 4];
        for j in 1..k {
            pw[j] = pw[j - 1] * sv;
        }
        for i in 0..k {
            b[i] += w * pw[i] * y;
            for j in 0..k {
                g[i * k + j] += w * pw[i] * pw[j];
            }
        }
    }
    let sol = cholesky_solve(&g, &b, k)?;
    let mut c = [0.0; 4];
    c[..k].copy_from_slice(&sol);
    Some(c)
}

/// The polynomial step: the least-squares polynomial if it is increasing on [lo, hi], else the
/// best point on the segment from a feasible anchor towards it (the cost is a convex quadratic
/// minimised at the end of the segment and the feasible set is convex, so that point is the
/// largest feasible step, found by bisection).
fn poly_step(
    d: &Design,
    s: &[f64],
    degree: usize,
    anchor: &[f64; 4],
    lo: f64,
    hi: f64,
) -> Option<([f64; 4], Polynomial<f64>)> {
    let target = poly_ls(d, s, degree)?;
    if let Some(p) = feasible(&target, lo, hi) {
        return Some((target, p));
    }
    let anchor = if feasible(anchor, lo, hi).is_some() {
        *anchor
    } else {
        poly_ls(d, s, 1)?
    };
    let mut best = (anchor, feasible(&anchor, lo, hi)?);
    let (mut a, mut b) = (0.0_f64, 1.0_f64);
    for _ in 0..50 {
        let t = 0.5 * (a + b);
        let c: [f64; 4] = std::array::from_fn(|i| anchor[i] + t * (target[i] - anchor[i]));
        match feasible(&c, lo, hi) {
            Some(p) => {
                best = (c, p);
                a = t;
            }
            None => b = t,
        }
    }
    Some(best)
}

/// The state of the alternating fit: PI weights (w0 first) and offset β normalised so that the
/// PI output spans [−1, 1] on the training data, and P in monomials of that output.
#[derive(Clone)]
struct State {
    w: Vec<f64>,
    beta: f64,
    c: [f64; 4],
    poly: Polynomial<f64>,
    s: Vec<f64>,
    cost: f64,
}

/// Rescales (w, β) so that the PI output spans [−1, 1]; returns the map s_new = a s_old + b.
fn normalise(d: &Design, w: &mut [f64], beta: &mut f64) -> Option<(f64, f64)> {
    let s = d.pi_output(w, *beta);
    let (lo, hi) = d.range(&s);
    if hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let a = 2.0 / (hi - lo);
    let b = -(hi + lo) / (hi - lo);
    for v in w.iter_mut() {
        *v *= a;
    }
    *beta = a * *beta + b;
    Some((a, b))
}

/// The Gauss–Newton weight step around the current polynomial: NNLS (w0 ≥ ε, w_i ≥ 0, β free)
/// on the linearisation y ≈ P(s_k) + P'(s_k)(s − s_k). Returns the proposed (w, β) and the
/// reduced Gram matrix (for standard errors).
fn weight_step(d: &Design, st: &State) -> Option<(Vec<f64>, f64, Vec<f64>, f64)> {
    let m = d.m;
    let mut sff = 0.0;
    let mut sft = 0.0;
    let mut sfb = vec![0.0; m];
    let mut g = vec![0.0; m * m];
    let mut rhs = vec![0.0; m];
    for ((row, y, wt), s) in d.rows().zip(&st.s) {
        let slope = st.poly.slope(*s);
        let t = y - st.poly.apply(*s) + slope * s;
        let f2 = wt * slope * slope;
        sff += f2;
        sft += wt * slope * t;
        for a in 0..m {
            sfb[a] += f2 * row[a];
            rhs[a] += wt * slope * row[a] * t;
            for b in a..m {
                g[a * m + b] += f2 * row[a] * row[b];
            }
        }
    }
    if sff.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    for a in 0..m {
        for b in a..m {
            g[a * m + b] -= sfb[a] * sfb[b] / sff;
            g[b * m + a] = g[a * m + b];
        }
        rhs[a] -= sfb[a] * sft / sff;
    }
    let eps = 1e-6 * st.w[0].abs().max(1e-300);
    let shifted: Vec<f64> = (0..m).map(|a| rhs[a] - g[a * m] * eps).collect();
    let mut w = nnls(&g, &shifted, m);
    w[0] += eps;
    let beta = (sft - w.iter().zip(&sfb).map(|(a, b)| a * b).sum::<f64>()) / sff;
    Some((w, beta, g, sff))
}

/// Alternating fit of y = P(PI[x]) from the plain PI fit (w, offset); returns the model and its
/// estimates (standard errors conditional on the other block: weights given P, P given the
/// weights).
fn fit_output(
    d: &Design,
    thresholds: &[f64],
    w_plain: &[f64],
    offset: f64,
    degree: usize,
    n: usize,
) -> Result<(PiModel, Vec<Estimate>), FitError> {
    let mut st = start_state(d, w_plain, offset, degree).ok_or_else(no_fit)?;
    for _round in 0..200 {
        let Some((next, done)) = alternate(d, &st, degree) else {
            break;
        };
        st = next;
        if done {
            break;
        }
    }
    let model = output_model(d, thresholds, &st, degree)?;
    // Conditional standard errors.
    let p = model.parameter_count();
    let s2 = st.cost / (n.saturating_sub(p).max(1)) as f64;
    let mut estimates = weight_estimates(d, &st, thresholds, s2)?;
    estimates.extend(polynomial_estimates(d, &st, degree, s2));
    Ok((model, estimates))
}

/// The error of an output polynomial that cannot be fitted.
fn no_fit() -> FitError {
    FitError::NoConvergence("the PI output polynomial could not be fitted".into())
}

/// The start of the alternating fit: the plain fit (w, offset) normalised, and P mapping the
/// normalised PI output back to it (the same cost), made increasing on the data if need be.
fn start_state(d: &Design, w_plain: &[f64], offset: f64, degree: usize) -> Option<State> {
    let mut w = w_plain.to_vec();
    let mut beta = offset;
    // Start: P maps the normalised PI output back to the plain fit (same cost).
    let (a, b) = normalise(d, &mut w, &mut beta)?;
    let start = compose_affine(&[0.0, 1.0, 0.0, 0.0], 1.0 / a, -b / a);
    let s = d.pi_output(&w, beta);
    let (lo, hi) = d.range(&s);
    let (c, poly) = poly_step(d, &s, degree, &start, lo, hi)?;
    let cost = d.cost(&s, &poly);
    Some(State {
        w,
        beta,
        c,
        poly,
        s,
        cost,
    })
}

/// One round of the alternating fit from `st`: the weight step (backtracked until it lowers
/// the cost), normalised, then the polynomial step. The new state and whether the round's
/// decrease was negligible (at most 1e-10 of the cost); `None` when the round cannot lower the
/// cost.
fn alternate(d: &Design, st: &State, degree: usize) -> Option<(State, bool)> {
    let (wn, bn, _, _) = weight_step(d, st)?;
    let (mut w, mut beta) = backtrack(d, st, &wn, bn)?;
    let (a, b) = normalise(d, &mut w, &mut beta)?;
    let anchor = compose_affine(&st.c, 1.0 / a, -b / a);
    let s = d.pi_output(&w, beta);
    let (lo, hi) = d.range(&s);
    let (c, poly) = poly_step(d, &s, degree, &anchor, lo, hi)?;
    let cost = d.cost(&s, &poly);
    if cost.partial_cmp(&st.cost) != Some(std::cmp::Ordering::Less) {
        return None;
    }
    let done = st.cost - cost <= 1e-10 * st.cost;
    let next = State {
        w,
        beta,
        c,
        poly,
        s,
        cost,
    };
    Some((next, done))
}

/// The first point on the segment from (w, β) of `st` towards the weight step's (`wn`, `bn`),
/// halving from its end, that lowers the cost under the current polynomial (feasible: the
/// constraints are convex); `None` after 30 halvings.
fn backtrack(d: &Design, st: &State, wn: &[f64], bn: f64) -> Option<(Vec<f64>, f64)> {
    let mut t = 1.0;
    for _ in 0..30 {
        let w: Vec<f64> = st.w.iter().zip(wn).map(|(a, b)| a + t * (b - a)).collect();
        let beta = st.beta + t * (bn - st.beta);
        let s = d.pi_output(&w, beta);
        if d.cost(&s, &st.poly) < st.cost {
            return Some((w, beta));
        }
        t *= 0.5;
    }
    None
}

/// The model of the state `st`: the PI sum with its output polynomial, whose domain is the PI
/// output range over the training samples.
///
/// # Errors
/// [`FitError::NoConvergence`] when the core refuses the polynomial.
fn output_model(
    d: &Design,
    thresholds: &[f64],
    st: &State,
    degree: usize,
) -> Result<PiModel, FitError> {
    let pi = PiModel {
        identity_weight: st.w[0],
        thresholds: thresholds.to_vec(),
        weights: st.w[1..].to_vec(),
        offset: st.beta,
        output: None,
    };
    let (lo, hi) = d.range(&st.s);
    let model = PiModel {
        output: Some(PiOutput {
            degree: u8::try_from(degree).unwrap_or(3),
            coefficients: st.c,
            lo,
            hi,
        }),
        ..pi
    };
    model
        .operator()
        .map_err(|e| FitError::NoConvergence(format!("the fitted PI output polynomial: {e}")))?;
    Ok(model)
}

/// The estimates of w0, the offset and the weights of `st`, with their standard errors given
/// the polynomial (`s2`: the residual variance).
fn weight_estimates(
    d: &Design,
    st: &State,
    thresholds: &[f64],
    s2: f64,
) -> Result<Vec<Estimate>, FitError> {
    let m = d.m;
    let (g, sff) = weight_step(d, st)
        .map(|(_, _, g, sff)| (g, sff))
        .ok_or_else(no_fit)?;
    let se = std_errors(&g, m, &free_set(&st.w), s2);
    let unit = "PI output (normalised to [-1, 1]) per input unit";
    let mut estimates = vec![
        Estimate {
            name: "w0".into(),
            value: st.w[0],
            std_error: se[0],
            unit: unit.into(),
        },
        Estimate {
            name: "offset".into(),
            value: st.beta,
            std_error: (s2 / sff).sqrt(),
            unit: "PI output (normalised)".into(),
        },
    ];
    for j in 1..m {
        estimates.push(Estimate {
            name: format!("w{j} (r = {:.4})", thresholds[j - 1]),
            value: st.w[j],
            std_error: se[j],
            unit: unit.into(),
        });
    }
    Ok(estimates)
}

/// The estimates of the polynomial's coefficients of `st`, with their standard errors given
/// the weights (`s2`: the residual variance).
fn polynomial_estimates(d: &Design, st: &State, degree: usize, s2: f64) -> Vec<Estimate> {
    let kp = degree + 1;
    let mut gp = vec![0.0; kp * kp];
    for (sv, w) in st.s.iter().zip(&d.wt) {
        let pw: [f64; 4] = [1.0, *sv, sv * sv, sv * sv * sv];
        for i in 0..kp {
            for j in 0..kp {
                gp[i * kp + j] += w * pw[i] * pw[j];
            }
        }
    }
    let pinv = spd_inverse(&gp, kp);
    (0..kp)
        .map(|i| Estimate {
            name: format!("P.c{i}"),
            value: st.c[i],
            std_error: pinv
                .as_ref()
                .map_or(f64::NAN, |v| (v[i * kp + i] * s2).max(0.0).sqrt()),
            unit: "output units".into(),
        })
        .collect()
}

/// The free set of the weights (w0 first): w0 and every weight away from its bound 0.
fn free_set(w: &[f64]) -> Vec<usize> {
    (0..w.len()).filter(|&j| j == 0 || w[j] > 0.0).collect()
}

/// Standard errors √(s² (G_F⁻¹)_jj) of the m weights from the m × m Gram matrix `g` restricted
/// to the free set F (the unconstrained covariance there): 0 for a weight at its bound, NaN
/// when G_F is singular.
fn std_errors(g: &[f64], m: usize, free: &[usize], s2: f64) -> Vec<f64> {
    let k = free.len();
    let sub: Vec<f64> = free
        .iter()
        .flat_map(|&a| free.iter().map(move |&b| (a, b)))
        .map(|(a, b)| g[a * m + b])
        .collect();
    let inv = spd_inverse(&sub, k);
    (0..m)
        .map(|j| match (free.iter().position(|&f| f == j), &inv) {
            (Some(p), Some(inv)) => (inv[p * k + p] * s2).max(0.0).sqrt(),
            (Some(_), None) => f64::NAN,
            (None, _) => 0.0,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_a_known_pi_model() -> Result<(), FitError> {
        let x: Vec<f64> = (0..3000)
            .map(|k| {
                let t = k as f64 * 0.01;
                (0.2 + 0.03 * t).min(1.0) * (2.0 * t).sin()
            })
            .collect();
        let r = four_thresholds(&x);
        let truth = PiModel {
            identity_weight: 0.8,
            thresholds: r,
            weights: vec![0.5, 0.0, 0.3, 0.1],
            offset: -2.0,
            output: None,
        };
        let y = truth.run(&x)?;
        let fit = fit_pi(&Dataset::single(&x, &y), 4)?;
        assert!(
            (fit.model.identity_weight - 0.8).abs() < 1e-8,
            "{:?}",
            fit.model
        );
        for (a, b) in fit.model.weights.iter().zip(&truth.weights) {
            assert!((a - b).abs() < 1e-8, "{:?}", fit.model);
        }
        assert!((fit.model.offset + 2.0).abs() < 1e-8);
        assert!(fit.training.rms < 1e-8);
        Ok(())
    }

    /// (min, max) of `v`.
    fn range(v: &[f64]) -> (f64, f64) {
        v.iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(*v), b.max(*v))
            })
    }

    /// The thresholds the fit uses for 4 plays on the range of `x`.
    fn four_thresholds(x: &[f64]) -> Vec<f64> {
        let (lo, hi) = range(x);
        (1..=4).map(|i| (hi - lo) * i as f64 / 10.0).collect()
    }

    fn sweep(n: usize) -> Vec<f64> {
        (0..n)
            .map(|k| {
                let t = k as f64 * 0.01;
                (0.2 + 0.03 * t).min(1.0) * (2.0 * t).sin() + 0.1 * (5.3 * t).cos()
            })
            .collect()
    }

    #[test]
    fn compose_affine_is_substitution() {
        let c = [0.3, -1.2, 0.7, 0.25];
        let q = compose_affine(&c, 1.7, -0.4);
        for x in [-2.0, -0.3, 0.0, 1.1] {
            let p = |c: &[f64; 4], s: f64| c[0] + s * (c[1] + s * (c[2] + s * c[3]));
            assert!((p(&q, x) - p(&c, 1.7 * x - 0.4)).abs() < 1e-12);
        }
    }

    #[test]
    fn recovers_a_pi_model_with_an_output_polynomial() -> Result<(), FitError> {
        let x = sweep(4000);
        let r = four_thresholds(&x);
        let plain = PiModel {
            identity_weight: 0.8,
            thresholds: r,
            weights: vec![0.5, 0.0, 0.3, 0.1],
            offset: 0.1,
            output: None,
        };
        let s = plain.run(&x)?;
        let (slo, shi) = range(&s);
        // A clearly curved, increasing cubic on the PI output range.
        let truth = PiModel {
            output: Some(PiOutput {
                degree: 3,
                coefficients: [1.0, 2.0, 0.6, 0.4],
                lo: slo,
                hi: shi,
            }),
            ..plain.clone()
        };
        truth.operator()?;
        let y = truth.run(&x)?;
        let data = Dataset::single(&x, &y);
        // Without the polynomial the PI baseline cannot follow the curvature …
        let base = fit_pi(&data, 4)?;
        assert!(base.training.rms_pct_span > 0.5, "{:?}", base.training);
        // … with it, the model is recovered up to the PI's normalisation.
        let fit = fit_pi_with(&data, 4, PiOutputKind::Poly3)?;
        assert!(fit.training.rms_pct_span < 1e-6, "{:?}", fit.training);
        assert_eq!(fit.model.parameter_count(), 4 + 2 + 2);
        // The PI weights are the truth's up to one scale factor (normalisation).
        let scale = fit.model.identity_weight / 0.8;
        for (a, b) in fit.model.weights.iter().zip(&truth.weights) {
            assert!((a - scale * b).abs() < 1e-6 * scale, "{:?}", fit.model);
        }
        // The fitted P is increasing on its domain and the model runs on new input identically
        // to the truth.
        let fresh = sweep(5000);
        let a = fit.model.run(&fresh[1000..])?;
        let b = truth.run(&fresh[1000..])?;
        let worst = a
            .iter()
            .zip(&b)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-6, "{worst}");
        // A quadratic cannot represent the cubic exactly, but improves on the plain PI.
        let quad = fit_pi_with(&data, 4, PiOutputKind::Poly2)?;
        assert!(
            quad.training.rms < base.training.rms,
            "{:?} vs {:?}",
            quad.training,
            base.training
        );
        Ok(())
    }
}
