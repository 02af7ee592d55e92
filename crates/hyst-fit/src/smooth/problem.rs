//! The least-squares problem of one structure on one dataset ([`SmoothProblem`]): the output
//! error over the training records, each history simulated from the start rule or from its
//! estimated start, and its Jacobian.
//!
//! Derivatives: exact, by forward-mode duals. θ is seeded as [`Dual`] variables, the model
//! is built from them by the same [`Layout::model`] (so the log transforms, the data-dependent
//! shaping domains and the k2 law's clamps carry their derivatives) and run by the same
//! [`SmoothModel::run_with`] as the residuals: the core's operator, memory (every reversal
//! point carries its gradient forward), k2 law and shaping functions are evaluated on duals
//! through their one code path. One dual run per record gives every column at the cost of a
//! few plain runs; any structure `Layout::model` builds gets its Jacobian this way.

use hyst_core::{Dual, Shaping};
use hyst_model::smooth::FitReal;
use hyst_model::timed::TimedSample;
use hyst_model::{Hold, SmoothModel};

use crate::data::{Dataset, History};
use crate::layout::Layout;
use crate::lm::{Infeasible, Problem};

/// The least-squares problem of one structure on one dataset.
pub(super) struct SmoothProblem<'a> {
    /// The structure, laid out as parameters.
    pub(super) layout: &'a Layout,
    /// The data.
    pub(super) data: &'a Dataset,
    /// The records as uninterrupted histories (segments of one measurement run on from each
    /// other), each with the offset of its training samples in residual order.
    histories: Vec<(History<'a>, Vec<Option<usize>>)>,
    /// Estimate each history's start
    /// ([`FitOptions::estimate_starts`](crate::smooth::FitOptions::estimate_starts)).
    estimate: bool,
    /// The input range of all the records ([`Dataset::input_range`]), for the shaping domains.
    pub(super) input_range: (f64, f64),
    /// 1 / output half-span: a residual is (model − measured) · √w / output half-span, its
    /// scale computed from the sample's weight where it is used (a vector of scales took 8
    /// bytes a sample).
    inv_span: f64,
    /// Number of residuals: the training samples.
    pub(super) n: usize,
}

impl<'a> SmoothProblem<'a> {
    pub(super) fn new(layout: &'a Layout, data: &'a Dataset, estimate: bool) -> Self {
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
            n: at,
            inv_span: 1.0 / layout.norm.output_half_span,
        }
    }

    pub(super) fn model<T: FitReal>(&self, theta: &[T]) -> Result<SmoothModel<T>, Infeasible> {
        self.layout
            .model(theta, self.input_range)
            .map_err(|_| Infeasible)
    }

    /// The estimated start of each history for the model `m` (`None` without estimation):
    /// the band fraction b ∈ [−1, 1] that minimises the history's weighted squared error, by
    /// Brent's method, compared with the ends b = ±1 (the asymptotes, where the minimum often
    /// lies).
    pub(super) fn bands(&self, m: &SmoothModel) -> Option<Vec<f64>> {
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
                    // The timed run, which is the static one for a static model.
                    let ran = m.run_timed(&h.input, h.period, Some(b), |i, s| {
                        if let Some(slot) = y.get_mut(i) {
                            *slot = s.y;
                        }
                    });
                    if ran.is_err() {
                        return f64::INFINITY;
                    }
                    y.iter()
                        .zip(h.output.iter())
                        .zip(h.weight.iter())
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
    pub(super) fn simulate(
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
        // Each sample of a training part straight into its residual's row (no copy of the
        // history's outputs: 16 bytes a sample of a long record).
        self.run_rows(m, bands, |k, _, _, s| {
            if let Some(slot) = y.get_mut(k) {
                *slot = s.y;
            }
            if let Some(slot) = z.as_deref_mut().and_then(|z| z.get_mut(k)) {
                *slot = s.z;
            }
        })
    }

    /// Runs `m` over each history whole (a segment starts where the one before it ended), from
    /// the starts `bands` (`None`: the start rule), and hands every sample of a training part
    /// to `each(k, h, i, s)`: its residual row `k`, its history `h`, its index `i` there and
    /// the model's sample `s`, rows in order (parts are in sample order, so one cursor walks
    /// them). The one loop behind the residuals, their sum and the dual run.
    fn run_rows<T: FitReal>(
        &self,
        m: &SmoothModel<T>,
        bands: Option<&[f64]>,
        mut each: impl FnMut(usize, &History<'_>, usize, TimedSample<T>),
    ) -> Result<(), Infeasible> {
        for (index, (h, offsets)) in self.histories.iter().enumerate() {
            let band = bands.and_then(|b| b.get(index).copied());
            let mut rows = ResidualRows::new(&h.parts, offsets);
            m.run_timed(&h.input, h.period, band, |i, s| {
                if let Some(k) = rows.row(i) {
                    each(k, h, i, s);
                }
            })
            .map_err(|_| Infeasible)?;
        }
        Ok(())
    }

    /// A residual's scale √w / output half-span, for a sample of weight `w`.
    fn scale(&self, w: f64) -> f64 {
        w.sqrt() * self.inv_span
    }

    fn to_residuals(&self, y: &[f64], r: &mut [f64]) -> Result<(), Infeasible> {
        let mut i = 0;
        for rec in self.data.training() {
            for (obs, w) in rec.output.iter().zip(&rec.weight) {
                let v = (y[i] - obs) * self.scale(w);
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
    pub(super) fn cost_from_operator(&self, theta: &[f64], z: &[f64]) -> Option<f64> {
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

impl SmoothProblem<'_> {
    /// The rate term's column v̇ = (v_k − v_{k−1}) / h per residual (0 at a history's first
    /// sample), v the hysteresis input of `m` (the plant's output): the rate term's c is
    /// linear in the output, so a start can take it from least squares. `None` when `m`
    /// cannot run a record.
    pub(super) fn rate_column(&self, m: &SmoothModel) -> Option<Vec<f64>> {
        let mut out = vec![0.0; self.n];
        for (h, offsets) in &self.histories {
            let steps = h.period?;
            let mut rows = ResidualRows::new(&h.parts, offsets);
            let mut previous: Option<f64> = None;
            m.run_timed(&h.input, h.period, None, |i, s| {
                // Each step's own h (the run's v̇).
                let rate = previous.map_or(0.0, |p| (s.v - p) / steps.step(i));
                previous = Some(s.v);
                if let Some(slot) = rows.row(i).and_then(|k| out.get_mut(k)) {
                    *slot = rate;
                }
            })
            .ok()?;
        }
        Some(out)
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
        let n = self.n;
        match theta.len() {
            0..=12 => self.one_dual_run(theta, columns(jac, n, 0)),
            p => (0..p).step_by(16).try_for_each(|offset| {
                self.dual_rows::<16>(theta, offset, columns(&mut *jac, n, offset))
            }),
        }
    }

    /// JᵀJ and Jᵀr in the one dual run of [`Problem::jacobian`] (up to 12 parameters), without
    /// the n × p Jacobian: each entry summed over the rows in order, as the provided method
    /// sums the stored columns (the same numbers, bit for bit). A long record's polish then
    /// needs 8 bytes a sample per parameter less (320 MB for 4 parameters at 10 M samples).
    fn normal_equations(
        &self,
        theta: &[f64],
        r: &[f64],
        jtj: &mut [f64],
        g: &mut [f64],
    ) -> Result<(), Infeasible> {
        if theta.len() > 12 {
            return crate::lm::jacobian_normal_equations(self, theta, r, jtj, g);
        }
        self.dual_sums(theta, jtj, g, |k, _| r.get(k).copied().unwrap_or(0.0))
    }

    /// A long record's problem keeps no residual vectors (8 bytes a sample each, two of them
    /// alive in a polish): from [`KEEP_RESIDUALS_BELOW`] residuals on.
    fn keeps_residuals(&self) -> bool {
        self.n < KEEP_RESIDUALS_BELOW
    }

    /// Σ r² of [`Problem::residuals`], summed in their order as they are computed (the same
    /// number, bit for bit).
    fn cost(&self, theta: &[f64]) -> Result<f64, Infeasible> {
        let m = self.model(theta)?;
        // −0 is the neutral element of a float sum (as `Sum` starts).
        let mut sum = -0.0;
        let mut finite = true;
        self.run_rows(&m, self.bands(&m).as_deref(), |_, h, i, s| {
            let (Some(obs), Some(w)) = (h.output.get(i), h.weight.get(i)) else {
                return;
            };
            let v = (s.y - obs) * self.scale(w);
            finite &= v.is_finite();
            sum += v * v;
        })?;
        if finite {
            Ok(sum)
        } else {
            Err(Infeasible)
        }
    }

    /// JᵀJ and Jᵀr in one dual run, each residual the value part of the run's output.
    fn sums_at(&self, theta: &[f64], jtj: &mut [f64], g: &mut [f64]) -> Result<(), Infeasible> {
        if theta.len() > 12 {
            return crate::lm::stored_sums(self, theta, jtj, g);
        }
        self.dual_sums(theta, jtj, g, |_, rk| rk)?;
        if g.iter().all(|v| v.is_finite()) {
            Ok(())
        } else {
            Err(Infeasible)
        }
    }
}

/// From this many residuals on, [`SmoothProblem`] keeps no residual vectors
/// ([`Problem::keeps_residuals`]): 8 MB each, where a vector costs more than the sums computed
/// again.
const KEEP_RESIDUALS_BELOW: usize = 1 << 20;

impl SmoothProblem<'_> {
    /// JᵀJ and g = Jᵀr (up to 12 parameters) from one dual run, each entry summed over the rows
    /// in order; `residual(k, value)` gives r_k from the row and the residual of the run's
    /// value part.
    fn dual_sums(
        &self,
        theta: &[f64],
        jtj: &mut [f64],
        g: &mut [f64],
        residual: impl Fn(usize, f64) -> f64,
    ) -> Result<(), Infeasible> {
        let p = theta.len();
        // −0 is the neutral element of a float sum (as `Sum` starts).
        jtj.fill(-0.0);
        g.fill(-0.0);
        let accumulate = |k: usize, value: f64, row: &[f64]| {
            let rk = residual(k, value);
            for (a, ja) in row.iter().enumerate() {
                if let Some(ga) = g.get_mut(a) {
                    *ga += ja * rk;
                }
                for (b, jb) in row.iter().enumerate().skip(a) {
                    if let Some(e) = jtj.get_mut(a * p + b) {
                        *e += ja * jb;
                    }
                }
            }
        };
        self.one_dual_run(theta, accumulate)?;
        for a in 0..p {
            for b in 0..a {
                jtj[a * p + b] = jtj[b * p + a];
            }
        }
        Ok(())
    }

    /// Every column of the Jacobian of up to 12 parameters from one dual run
    /// ([`SmoothProblem::dual_rows`]), the dual's width the next of 4, 6, 8, 12 (unused lanes
    /// cost time).
    fn one_dual_run(
        &self,
        theta: &[f64],
        row: impl FnMut(usize, f64, &[f64]),
    ) -> Result<(), Infeasible> {
        match theta.len() {
            0..=4 => self.dual_rows::<4>(theta, 0, row),
            5..=6 => self.dual_rows::<6>(theta, 0, row),
            7..=8 => self.dual_rows::<8>(theta, 0, row),
            _ => self.dual_rows::<12>(theta, 0, row),
        }
    }

    /// Columns `offset..offset + N` of the Jacobian (those that exist) from one dual run over
    /// each history (as [`SmoothProblem::simulate`] runs them): θ_j seeded as the dual variable
    /// j − offset, the others constant. `row(k, r, d)` receives residual `k` as the run's value
    /// part gives it and its derivatives `d`, rows in order; `Err` when a derivative is not
    /// finite.
    fn dual_rows<const N: usize>(
        &self,
        theta: &[f64],
        offset: usize,
        mut row: impl FnMut(usize, f64, &[f64]),
    ) -> Result<(), Infeasible> {
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
        let mut finite = true;
        let mut d = [0.0; N];
        self.run_rows(&m, bands.as_deref(), |k, h, i, s| {
            let y = s.y;
            let scale = h.weight.get(i).map_or(0.0, |w| self.scale(w));
            for (slot, g) in d.iter_mut().zip(y.gradient().iter().take(columns)) {
                *slot = g * scale;
                finite &= slot.is_finite();
            }
            let obs = h.output.get(i).copied().unwrap_or(f64::NAN);
            row(k, (y.value() - obs) * scale, &d[..columns]);
        })?;
        if finite {
            Ok(())
        } else {
            Err(Infeasible)
        }
    }
}

/// The residuals' correlation, for standard errors that stay valid when it is not white
/// ([`SmoothProblem::scores`]): at most this many residuals (the first) are looked at.
pub(super) const CORRELATION_SAMPLES: usize = 1 << 20;

/// The fewest blocks of [`SmoothProblem::scores`] the block length leaves (a longer correlation
/// caps the block, and the standard errors then say so); also the fewest blocks the
/// correlation time is measured over.
pub(super) const MIN_BLOCKS: usize = 20;

impl SmoothProblem<'_> {
    /// The first residual row of each history that has training rows, in order: where the
    /// blocks of [`SmoothProblem::scores`] are cut, besides every `block` rows.
    fn history_starts(&self) -> Vec<usize> {
        self.histories
            .iter()
            .filter_map(|(_, offsets)| offsets.iter().flatten().next().copied())
            .collect()
    }

    /// The integrated correlation time of the residuals `r` (in samples, at least 1), by
    /// blocking: for block lengths B = 1, 2, 4, … (at least [`MIN_BLOCKS`] blocks), B times the
    /// variance of the blocks' means over the residuals' variance, which rises to the
    /// correlation time once B outlasts the correlation; the largest. O(n log n), over the
    /// first [`CORRELATION_SAMPLES`] residuals. Residuals of weight 0 are 0 and count as such.
    pub(super) fn correlation_time(r: &[f64]) -> f64 {
        let n = r.len().min(CORRELATION_SAMPLES);
        let r = &r[..n];
        let var: f64 = r.iter().map(|v| v * v).sum::<f64>() / n.max(1) as f64;
        if var.is_nan() || var <= 0.0 {
            return 1.0;
        }
        let mut sums: Vec<f64> = r.to_vec();
        let (mut block, mut tau) = (1usize, 1.0_f64);
        while sums.len() / 2 >= MIN_BLOCKS {
            sums = sums.chunks_exact(2).map(|p| p[0] + p[1]).collect();
            block *= 2;
            // Var(block mean) · B / var = mean(S_b²) / (B var).
            let ms = sums.iter().map(|s| s * s).sum::<f64>() / sums.len() as f64;
            tau = tau.max(ms / (block as f64 * var));
        }
        tau
    }

    /// The first `count` residuals (at most) at θ, in order, from one run: the residuals the
    /// correlation is measured on, without a vector of every residual of a long record.
    ///
    /// # Errors
    /// [`Infeasible`] as [`Problem::residuals`].
    pub(super) fn first_residuals(
        &self,
        theta: &[f64],
        count: usize,
    ) -> Result<Vec<f64>, Infeasible> {
        let m = self.model(theta)?;
        self.residuals_of(&m, self.bands(&m).as_deref(), count)
    }

    /// The first `count` residuals (at most) of the model `m` run from the starts `bands`, in
    /// order.
    ///
    /// # Errors
    /// [`Infeasible`] when `m` cannot run the records.
    fn residuals_of(
        &self,
        m: &SmoothModel,
        bands: Option<&[f64]>,
        count: usize,
    ) -> Result<Vec<f64>, Infeasible> {
        let mut out = vec![0.0; count.min(self.n)];
        self.run_rows(m, bands, |k, h, i, s| {
            let (Some(obs), Some(w)) = (h.output.get(i), h.weight.get(i)) else {
                return;
            };
            if let Some(slot) = out.get_mut(k) {
                *slot = (s.y - obs) * self.scale(w);
            }
        })?;
        Ok(out)
    }

    /// Hands every residual row to `row(k, r_k, J_k)` in order: its residual and its row of
    /// the Jacobian at θ (one dual run up to 12 parameters; above, the Jacobian is stored,
    /// since its runs of up to 16 columns each need every row at once).
    ///
    /// # Errors
    /// [`Infeasible`] when the Jacobian cannot be evaluated at θ.
    pub(super) fn jacobian_rows(
        &self,
        theta: &[f64],
        mut row: impl FnMut(usize, f64, &[f64]),
    ) -> Result<(), Infeasible> {
        let p = theta.len();
        if p <= 12 {
            return self.one_dual_run(theta, row);
        }
        let n = self.n;
        let mut jac = vec![0.0; n * p];
        let mut r = vec![0.0; n];
        self.residuals(theta, &mut r)?;
        self.jacobian(theta, &r, &mut jac)?;
        let mut d = vec![0.0; p];
        for k in 0..n {
            for j in 0..p {
                d[j] = jac[j * n + k];
            }
            row(k, r[k], &d);
        }
        Ok(())
    }

    /// The columns of what the model leaves out ([`crate::smooth::allowance`]) at θ, each in
    /// residual units and residual order, with their products: JᵀD (p × m, row-major), DᵀD
    /// (m × m) and Dᵀr. `other_hold`: the change of the model's output (the others held) when
    /// its plant runs with that hold instead; `creep`: for each time constant (s), a slow lag
    /// of the command, w′ = (u − w)/τ from w = u at each history's start, exact for a held
    /// command.
    ///
    /// # Errors
    /// [`Infeasible`] when the model, its other hold, or its Jacobian cannot run at θ.
    pub(super) fn left_out(
        &self,
        theta: &[f64],
        other_hold: Option<Hold>,
        creep: &[f64],
    ) -> Result<LeftOut, Infeasible> {
        let n = self.n;
        let m = self.model(theta)?;
        let bands = self.bands(&m);
        let r = self.residuals_of(&m, bands.as_deref(), n)?;
        let mut columns: Vec<Vec<f64>> = Vec::new();
        if let (Some(hold), Some(d)) = (other_hold, m.dynamics) {
            let mut other = m;
            other.dynamics = Some(d.with_hold(hold));
            let mut c = self.residuals_of(&other, bands.as_deref(), n)?;
            for (c, r) in c.iter_mut().zip(&r) {
                *c -= r;
            }
            columns.push(c);
        }
        for &tau in creep {
            let mut c = vec![0.0; n];
            for (h, offsets) in &self.histories {
                let mut rows = ResidualRows::new(&h.parts, offsets);
                let mut w = h.input.first().copied().unwrap_or(0.0);
                let (mut step, mut a) = (f64::NAN, 0.0);
                let mut before = w;
                for (i, &u) in h.input.iter().enumerate() {
                    if i > 0 {
                        let dt = h.period.map_or(1.0, |p| p.step(i));
                        if dt != step {
                            step = dt;
                            a = (-dt / tau).exp();
                        }
                        w = a * w + (1.0 - a) * before;
                    }
                    before = u;
                    if let (Some(k), Some(weight)) = (rows.row(i), h.weight.get(i)) {
                        if let Some(slot) = c.get_mut(k) {
                            *slot = w * self.scale(weight);
                        }
                    }
                }
            }
            columns.push(c);
        }
        let (p, q) = (theta.len(), columns.len());
        let mut jtd = vec![0.0; p * q];
        self.jacobian_rows(theta, |k, _, d| {
            for (j, dj) in d.iter().enumerate() {
                for (c, col) in columns.iter().enumerate() {
                    if let (Some(slot), Some(v)) = (jtd.get_mut(j * q + c), col.get(k)) {
                        *slot += dj * v;
                    }
                }
            }
        })?;
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let mut dtd = vec![0.0; q * q];
        for (a, ca) in columns.iter().enumerate() {
            for (b, cb) in columns.iter().enumerate() {
                dtd[a * q + b] = dot(ca, cb);
            }
        }
        let dtr = columns.iter().map(|c| dot(c, &r)).collect();
        Ok(LeftOut { jtd, dtd, dtr })
    }

    /// The outer product of the score over blocks of `block` consecutive residual rows (cut
    /// at every history's start as well): Σ_b s_b s_bᵀ, s_b = Σ_{k ∈ b} J_kᵀ r_k (row-major
    /// p × p), and the number of blocks. The middle of the sandwich estimate of the
    /// covariance (JᵀJ)⁻¹ (Σ_b s_b s_bᵀ) (JᵀJ)⁻¹, which holds for residuals correlated over
    /// less than a block (batch means; without the correlation it is White's estimate).
    ///
    /// # Errors
    /// [`Infeasible`] when the Jacobian cannot be evaluated at θ.
    pub(super) fn scores(
        &self,
        theta: &[f64],
        block: usize,
    ) -> Result<(Vec<f64>, usize), Infeasible> {
        let p = theta.len();
        let block = block.max(1);
        let starts = self.history_starts();
        let mut meat = vec![0.0; p * p];
        let mut s = vec![0.0; p];
        let (mut blocks, mut in_block, mut next_start) = (0usize, 0usize, 0usize);
        let flush = |s: &mut [f64], meat: &mut [f64], blocks: &mut usize| {
            if s.iter().any(|v| *v != 0.0) {
                for a in 0..p {
                    for b in 0..p {
                        meat[a * p + b] += s[a] * s[b];
                    }
                }
                *blocks += 1;
            }
            s.fill(0.0);
        };
        let mut row = |k: usize, rk: f64, d: &[f64]| {
            if next_start < starts.len() && k >= starts[next_start] {
                while next_start < starts.len() && k >= starts[next_start] {
                    next_start += 1;
                }
                flush(&mut s, &mut meat, &mut blocks);
                in_block = 0;
            }
            for (j, dj) in d.iter().enumerate() {
                if let Some(slot) = s.get_mut(j) {
                    *slot += dj * rk;
                }
            }
            in_block += 1;
            if in_block == block {
                flush(&mut s, &mut meat, &mut blocks);
                in_block = 0;
            }
        };
        self.jacobian_rows(theta, &mut row)?;
        flush(&mut s, &mut meat, &mut blocks);
        Ok((meat, blocks))
    }
}

/// The products of [`SmoothProblem::left_out`]'s columns D with the Jacobian J and the
/// residuals r (all in residual units): JᵀD (p × m, row-major), DᵀD (m × m), Dᵀr (m).
pub(super) struct LeftOut {
    pub(super) jtd: Vec<f64>,
    pub(super) dtd: Vec<f64>,
    pub(super) dtr: Vec<f64>,
}

/// Where the samples of a history land among the residuals: its parts (record, first sample,
/// length) in sample order, with each part's first residual row (`None`: held out), walked by
/// one cursor as the history runs.
struct ResidualRows<'p> {
    parts: &'p [(usize, usize, usize)],
    offsets: &'p [Option<usize>],
    /// The part the last sample was in.
    at: usize,
}

impl<'p> ResidualRows<'p> {
    fn new(parts: &'p [(usize, usize, usize)], offsets: &'p [Option<usize>]) -> Self {
        Self {
            parts,
            offsets,
            at: 0,
        }
    }

    /// The residual row of sample `i` of the history (`None`: a sample of a held-out part);
    /// `i` never decreases from one call to the next.
    fn row(&mut self, i: usize) -> Option<usize> {
        while self
            .parts
            .get(self.at)
            .is_some_and(|(_, start, len)| i >= start + len)
        {
            self.at += 1;
        }
        let (_, start, _) = self.parts.get(self.at)?;
        Some((*self.offsets.get(self.at)?)? + i.checked_sub(*start)?)
    }
}

/// Writes a row of derivatives (columns `offset..`) into the column-major Jacobian `jac` of
/// `n` rows.
fn columns(jac: &mut [f64], n: usize, offset: usize) -> impl FnMut(usize, f64, &[f64]) + '_ {
    move |k, _, row| {
        for (c, d) in row.iter().enumerate() {
            if let Some(slot) = jac.get_mut((offset + c) * n + k) {
                *slot = *d;
            }
        }
    }
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

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::indexing_slicing)]
    use super::*;
    use crate::data::Record;
    use crate::layout::Transform;
    use crate::smooth::driver::normalisation;
    use hyst_model::{Columns, Form, K2Kind, ShapingKind, Structure};

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
            let output: Vec<f64> = input
                .iter()
                .map(|x| 3.0 * x + 0.4 * (x * 1.7).sin())
                .collect();
            Record {
                id,
                weight: crate::Weights::Unit(input.len()),
                rows: (0..input.len()).collect(),
                output: output.into(),
                input: input.into(),
                validation,
                continues,
                period: None,
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
                if spec.transform == Transform::Linear && spec.start == 0.0 {
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

    /// The sums a long record's polish asks for (no residual vectors) are those of the stored
    /// residuals, bit for bit: Σ r², JᵀJ and Jᵀr.
    #[test]
    fn sums_without_residual_vectors_are_the_stored_ones() {
        let data = data();
        for estimate in [false, true] {
            let structure = Structure {
                output_shaping: ShapingKind::Tanh,
                ..Structure::default()
            };
            let layout = Layout::new(structure, normalisation(&data));
            let problem = SmoothProblem::new(&layout, &data, estimate);
            let p = layout.len();
            let mut theta = layout.start();
            theta[0] = 0.3_f64.ln();
            theta[1] = 4.0_f64.ln();
            let mut r = vec![0.0; problem.n];
            problem.residuals(&theta, &mut r).unwrap();
            let cost: f64 = r.iter().map(|v| v * v).sum();
            assert_eq!(problem.cost(&theta).unwrap().to_bits(), cost.to_bits());
            let (mut jtj, mut g) = (vec![0.0; p * p], vec![0.0; p]);
            problem
                .normal_equations(&theta, &r, &mut jtj, &mut g)
                .unwrap();
            let (mut jtj2, mut g2) = (vec![0.0; p * p], vec![0.0; p]);
            problem.sums_at(&theta, &mut jtj2, &mut g2).unwrap();
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(
                (bits(&jtj), bits(&g)),
                (bits(&jtj2), bits(&g2)),
                "{estimate}"
            );
            // Infeasible stays infeasible.
            let mut bad = theta.clone();
            bad[0] = f64::NAN;
            assert!(
                problem.cost(&bad).is_err() && problem.sums_at(&bad, &mut jtj2, &mut g2).is_err()
            );
        }
    }

    /// A problem that keeps no residual vectors: the same problem otherwise.
    struct Sums<'a>(&'a SmoothProblem<'a>);

    impl Problem for Sums<'_> {
        fn parameters(&self) -> usize {
            self.0.parameters()
        }
        fn residual_count(&self) -> usize {
            self.0.residual_count()
        }
        fn residuals(&self, theta: &[f64], r: &mut [f64]) -> Result<(), Infeasible> {
            self.0.residuals(theta, r)
        }
        fn jacobian(&self, theta: &[f64], r: &[f64], jac: &mut [f64]) -> Result<(), Infeasible> {
            self.0.jacobian(theta, r, jac)
        }
        fn keeps_residuals(&self) -> bool {
            false
        }
        fn cost(&self, theta: &[f64]) -> Result<f64, Infeasible> {
            self.0.cost(theta)
        }
        fn sums_at(&self, theta: &[f64], jtj: &mut [f64], g: &mut [f64]) -> Result<(), Infeasible> {
            self.0.sums_at(theta, jtj, g)
        }
    }

    /// Levenberg–Marquardt without residual vectors takes the same steps to the same optimum.
    #[test]
    fn the_method_without_residual_vectors_takes_the_same_steps() {
        let data = data();
        let layout = Layout::new(Structure::default(), normalisation(&data));
        let problem = SmoothProblem::new(&layout, &data, false);
        let method = crate::lm::LevenbergMarquardt::default();
        let start = layout.start();
        let kept = method
            .minimize(&problem, &start, &mut crate::lm::Silent)
            .unwrap();
        let summed = method
            .minimize(&Sums(&problem), &start, &mut crate::lm::Silent)
            .unwrap();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert!(kept.iterations > 3 && kept.residuals.len() == problem.n);
        assert!(summed.residuals.is_empty());
        assert_eq!(
            (
                bits(&kept.theta),
                kept.cost.to_bits(),
                bits(&kept.jtj),
                kept.iterations
            ),
            (
                bits(&summed.theta),
                summed.cost.to_bits(),
                bits(&summed.jtj),
                summed.iterations
            )
        );
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
