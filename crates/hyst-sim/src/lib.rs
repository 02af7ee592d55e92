//! Simulation for hyst: linear plants (transfer function or state space), fixed-step RK4 and an
//! adaptive Dormand–Prince 5(4) integrator, the "true" hysteresis inside a simulated plant
//! (the smooth operator or a fitted model, a family member whose parameters drift inside the
//! family, a hard backlash, a Preisach model), the Lemma 5.1 closed loop, and the paper's
//! Examples 2 and 3.

use hyst_core::{
    Compensator, ConstantK2, Direction, Error, Hysteresis, K2Law, Memory, Model, Shaping,
};

pub mod examples;

/// A linear time-invariant plant ẋ = A x + B u, y = C x + D u (single input, single output).
#[derive(Clone, Debug, PartialEq)]
pub struct StateSpace {
    /// A, n × n, row-major.
    pub a: Vec<Vec<f64>>,
    /// B, n.
    pub b: Vec<f64>,
    /// C, n.
    pub c: Vec<f64>,
    /// D.
    pub d: f64,
}

impl StateSpace {
    /// Checks the dimensions.
    ///
    /// # Errors
    /// When A is not n × n or B, C do not have n entries.
    pub fn new(a: Vec<Vec<f64>>, b: Vec<f64>, c: Vec<f64>, d: f64) -> Result<Self, String> {
        let n = a.len();
        if a.iter().any(|r| r.len() != n) || b.len() != n || c.len() != n {
            return Err(format!(
                "state space dimensions do not agree: A {n} rows, B {}, C {}",
                b.len(),
                c.len()
            ));
        }
        Ok(Self { a, b, c, d })
    }

    /// The controllable canonical form of num(s) / den(s), coefficients from the highest power
    /// down (e.g. `[b]` over `[a_n, …, a_1, 1]` for eq. 18). Needs deg num ≤ deg den.
    ///
    /// # Errors
    /// When den is empty or its leading coefficient is 0, or num has a higher degree.
    pub fn from_transfer_function(num: &[f64], den: &[f64]) -> Result<Self, String> {
        let lead = *den.first().ok_or("empty denominator")?;
        if lead == 0.0 || !lead.is_finite() {
            return Err("the denominator's leading coefficient must be finite and non-zero".into());
        }
        let n = den.len() - 1;
        if num.len() > den.len() {
            return Err("improper transfer function (deg num > deg den)".into());
        }
        let den: Vec<f64> = den.iter().map(|x| x / lead).collect();
        let mut nump = vec![0.0; den.len() - num.len()];
        nump.extend(num.iter().map(|x| x / lead));
        // Strictly proper part: num = d den + r.
        let d = nump[0];
        let r: Vec<f64> = (0..=n).map(|i| nump[i] - d * den[i]).collect();
        // x = [z, ż, …, z^(n−1)], z^(n) = u − Σ den[n−i] z^(i); y = Σ r[n−i] z^(i) + d u.
        let mut a = vec![vec![0.0; n]; n];
        for (i, row) in a.iter_mut().enumerate().take(n.saturating_sub(1)) {
            row[i + 1] = 1.0;
        }
        if n > 0 {
            for i in 0..n {
                a[n - 1][i] = -den[n - i];
            }
        }
        let mut b = vec![0.0; n];
        if n > 0 {
            b[n - 1] = 1.0;
        }
        let c: Vec<f64> = (0..n).map(|i| r[n - i]).collect();
        Self::new(a, b, c, d)
    }

    /// The state dimension n.
    #[must_use]
    pub fn order(&self) -> usize {
        self.b.len()
    }

    /// ẋ = A x + B u.
    #[must_use]
    pub fn derivative(&self, x: &[f64], u: f64) -> Vec<f64> {
        self.a
            .iter()
            .zip(&self.b)
            .map(|(row, b)| row.iter().zip(x).map(|(a, x)| a * x).sum::<f64>() + b * u)
            .collect()
    }

    /// y = C x + D u.
    #[must_use]
    pub fn output(&self, x: &[f64], u: f64) -> f64 {
        self.c.iter().zip(x).map(|(c, x)| c * x).sum::<f64>() + self.d * u
    }

    /// The steady state for a constant input u (solves A x = −B u by Gaussian elimination).
    #[must_use]
    pub fn equilibrium(&self, u: f64) -> Option<Vec<f64>> {
        let n = self.order();
        let mut m: Vec<Vec<f64>> = self
            .a
            .iter()
            .zip(&self.b)
            .map(|(row, b)| {
                let mut r = row.clone();
                r.push(-b * u);
                r
            })
            .collect();
        for col in 0..n {
            let pivot = (col..n).max_by(|&i, &j| m[i][col].abs().total_cmp(&m[j][col].abs()))?;
            if m[pivot][col].abs() < 1e-300 {
                return None;
            }
            m.swap(col, pivot);
            let pivot_row = m[col].clone();
            for (r, row) in m.iter_mut().enumerate() {
                if r != col {
                    let f = row[col] / pivot_row[col];
                    for (x, p) in row.iter_mut().zip(&pivot_row).skip(col) {
                        *x -= f * p;
                    }
                }
            }
        }
        Some((0..n).map(|i| m[i][n] / m[i][i]).collect())
    }
}

fn axpy(x: &[f64], h: f64, d: &[f64]) -> Vec<f64> {
    x.iter().zip(d).map(|(x, d)| x + h * d).collect()
}

/// One classical RK4 step of ẋ = f(t, x) from t over h.
pub fn rk4_step(
    f: &mut impl FnMut(f64, &[f64]) -> Vec<f64>,
    t: f64,
    x: &[f64],
    h: f64,
) -> Vec<f64> {
    let k1 = f(t, x);
    let k2 = f(t + 0.5 * h, &axpy(x, 0.5 * h, &k1));
    let k3 = f(t + 0.5 * h, &axpy(x, 0.5 * h, &k2));
    let k4 = f(t + h, &axpy(x, h, &k3));
    x.iter()
        .enumerate()
        .map(|(i, x)| x + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
        .collect()
}

/// Statistics of an adaptive integration.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AdaptiveStats {
    /// Accepted steps.
    pub accepted: usize,
    /// Rejected steps.
    pub rejected: usize,
}

/// Integrates ẋ = f(t, x) from t0 to t1 with the Dormand–Prince 5(4) pair and step-size
/// control on the mixed error tolerance `tol` (absolute and relative).
///
/// # Errors
/// When the step size underflows (a singular or non-finite right-hand side).
pub fn integrate_adaptive(
    f: &mut impl FnMut(f64, &[f64]) -> Vec<f64>,
    t0: f64,
    t1: f64,
    x0: &[f64],
    tol: f64,
) -> Result<(Vec<f64>, AdaptiveStats), String> {
    const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
    const A: [[f64; 6]; 7] = [
        [0.0; 6],
        [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
        [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
        [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
        [
            19372.0 / 6561.0,
            -25360.0 / 2187.0,
            64448.0 / 6561.0,
            -212.0 / 729.0,
            0.0,
            0.0,
        ],
        [
            9017.0 / 3168.0,
            -355.0 / 33.0,
            46732.0 / 5247.0,
            49.0 / 176.0,
            -5103.0 / 18656.0,
            0.0,
        ],
        [
            35.0 / 384.0,
            0.0,
            500.0 / 1113.0,
            125.0 / 192.0,
            -2187.0 / 6784.0,
            11.0 / 84.0,
        ],
    ];
    const B5: [f64; 7] = [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
        0.0,
    ];
    const B4: [f64; 7] = [
        5179.0 / 57600.0,
        0.0,
        7571.0 / 16695.0,
        393.0 / 640.0,
        -92097.0 / 339200.0,
        187.0 / 2100.0,
        1.0 / 40.0,
    ];
    let mut stats = AdaptiveStats::default();
    let mut t = t0;
    let mut x = x0.to_vec();
    let span = t1 - t0;
    if span <= 0.0 {
        return Ok((x, stats));
    }
    let mut h = span.min(0.01 * span.max(1e-6));
    while t < t1 {
        if t + h > t1 {
            h = t1 - t;
        }
        let mut k: Vec<Vec<f64>> = Vec::with_capacity(7);
        for s in 0..7 {
            let mut xs = x.clone();
            for (j, kj) in k.iter().enumerate() {
                for (xi, kji) in xs.iter_mut().zip(kj) {
                    *xi += h * A[s][j] * kji;
                }
            }
            k.push(f(t + C[s] * h, &xs));
        }
        let mut err = 0.0_f64;
        let mut x5 = x.clone();
        for i in 0..x.len() {
            let d5: f64 = (0..7).map(|s| B5[s] * k[s][i]).sum();
            let d4: f64 = (0..7).map(|s| B4[s] * k[s][i]).sum();
            x5[i] += h * d5;
            let scale = tol * (1.0 + x[i].abs().max(x5[i].abs()));
            err = err.max((h * (d5 - d4)).abs() / scale);
        }
        if !err.is_finite() {
            return Err(format!("non-finite right-hand side at t = {t}"));
        }
        if err <= 1.0 {
            t += h;
            x = x5;
            stats.accepted += 1;
        } else {
            stats.rejected += 1;
        }
        let factor = if err == 0.0 {
            5.0
        } else {
            (0.9 * err.powf(-0.2)).clamp(0.2, 5.0)
        };
        h *= factor;
        if h < 1e-14 * span.max(1.0) {
            return Err(format!("step size underflow at t = {t}"));
        }
    }
    Ok((x, stats))
}

/// A rate-independent hysteresis inside a simulated plant: one output sample per input sample.
pub trait TrueHysteresis {
    /// The output for the next input sample.
    fn step(&mut self, input: f64) -> f64;
    /// Forgets the history.
    fn reset(&mut self);
}

/// The smooth operator with shaping (a [`Model`]), also the form of a model fitted to data.
#[derive(Clone, Debug)]
pub struct Smooth<I, K, O> {
    /// The model.
    pub model: Model<f64, I, K, O>,
}

impl<I: Shaping<f64>, K: K2Law<f64>, O: Shaping<f64>> TrueHysteresis for Smooth<I, K, O> {
    fn step(&mut self, input: f64) -> f64 {
        self.model.step(input)
    }
    fn reset(&mut self) {
        self.model.reset();
    }
}

/// A family member whose parameters drift inside the family RH(k1, Δk1, k2, Δk2): at each
/// sample k̄1 = k1 + a Δk1 and k̄2 = k2 + b Δk2, with (a, b) ∈ [−1, 1]² given by `drift` as a
/// function of the sample index and the operator input (so k̄2 can depend on the input, as in
/// Example 2: higher near zero magnetisation, lower near saturation). Wrapped in input and
/// output shaping. The memory is carried over between parameter changes (clamped into the
/// band of the new k̄1).
pub struct Drifting<I, O, F, K = ConstantK2<f64>> {
    /// Input shaping ψ_in.
    pub input: I,
    /// Output shaping ψ_out.
    pub output: O,
    /// Nominal k1.
    pub k1: f64,
    /// Δk1.
    pub dk1: f64,
    /// Nominal k2 law (constant, or φ of the operator input).
    pub k2: K,
    /// Δk2.
    pub dk2: f64,
    /// (sample index, operator input) → (a, b) ∈ [−1, 1]².
    pub drift: F,
    memory: Option<Memory<f64>>,
    index: usize,
    /// The (k̄1, k̄2) used at the last sample.
    pub last_params: (f64, f64),
}

impl<I, O, F> Drifting<I, O, F, ConstantK2<f64>>
where
    I: Shaping<f64>,
    O: Shaping<f64>,
    F: FnMut(usize, f64) -> (f64, f64),
{
    /// A drifting member of RH(k1, Δk1, k2, Δk2) (constant nominal k2).
    pub fn new(input: I, output: O, family: (f64, f64, f64, f64), drift: F) -> Self {
        Self::with_law(
            input,
            output,
            (family.0, family.1),
            ConstantK2(family.2),
            family.3,
            drift,
        )
    }
}

impl<I, O, F, K> Drifting<I, O, F, K>
where
    I: Shaping<f64>,
    O: Shaping<f64>,
    F: FnMut(usize, f64) -> (f64, f64),
    K: K2Law<f64>,
{
    /// A drifting member of RH(k1, Δk1, φ(·), Δk2): k̄2 = φ(v) + b Δk2.
    pub fn with_law(input: I, output: O, k1: (f64, f64), k2: K, dk2: f64, drift: F) -> Self {
        Self {
            input,
            output,
            k1: k1.0,
            dk1: k1.1,
            k2,
            dk2,
            drift,
            memory: None,
            index: 0,
            last_params: (k1.0, f64::NAN),
        }
    }
}

impl<I, O, F, K> TrueHysteresis for Drifting<I, O, F, K>
where
    I: Shaping<f64>,
    O: Shaping<f64>,
    F: FnMut(usize, f64) -> (f64, f64),
    K: K2Law<f64>,
{
    fn step(&mut self, input: f64) -> f64 {
        let v = self.input.apply(input);
        let (a, b) = (self.drift)(self.index, v);
        self.index += 1;
        let k1 = self.k1 + a.clamp(-1.0, 1.0) * self.dk1;
        let k2 = self.k2.k2(v) + b.clamp(-1.0, 1.0) * self.dk2;
        self.last_params = (k1, k2);
        let op: Result<Hysteresis<f64, ConstantK2<f64>>, Error> = Hysteresis::new(k1, k2);
        let Ok(mut op) = op else {
            return f64::NAN;
        };
        if let Some(mut m) = self.memory {
            let clamp = |inp: f64, out: f64| out.clamp(inp - k1, inp + k1);
            m.reversal_output = clamp(m.reversal_input, m.reversal_output);
            m.last_output = clamp(m.last_input, m.last_output);
            let _ = op.set_memory(m);
        }
        let u = op.step(v);
        self.memory = op.memory();
        self.output.apply(u)
    }
    fn reset(&mut self) {
        self.memory = None;
        self.index = 0;
    }
}

/// A hard backlash (play operator) of total width `2 r`: the output follows the input at a
/// distance r once the play is taken up: y ← clamp(y, x − r, x + r).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Backlash {
    /// Half-width r (Example 3: width 0.4, r = 0.2).
    pub half_width: f64,
    /// The output; `None` before the first sample (which starts on the line y = x).
    pub state: Option<f64>,
}

impl Backlash {
    /// A backlash of total width `width`.
    #[must_use]
    pub fn new(width: f64) -> Self {
        Self {
            half_width: 0.5 * width,
            state: None,
        }
    }
}

impl TrueHysteresis for Backlash {
    fn step(&mut self, x: f64) -> f64 {
        let y = self.state.unwrap_or(x);
        let y = y.clamp(x - self.half_width, x + self.half_width);
        self.state = Some(y);
        y
    }
    fn reset(&mut self) {
        self.state = None;
    }
}

/// A discrete Preisach model: relays on a triangular grid α ≥ β over [lo, hi] with weights
/// μ(α, β); output = Σ μ γ̂αβ[x] with relays ±1 (all at −1 initially: negative saturation).
#[derive(Clone, Debug, PartialEq)]
pub struct Preisach {
    alphas: Vec<f64>,
    betas: Vec<f64>,
    weights: Vec<f64>,
    states: Vec<f64>,
}

impl Preisach {
    /// An `n` × `n` grid over [lo, hi] with weights `mu(alpha, beta)` (switch-up threshold α,
    /// switch-down threshold β ≤ α).
    pub fn new(lo: f64, hi: f64, n: usize, mu: impl Fn(f64, f64) -> f64) -> Self {
        let n = n.max(2);
        let h = (hi - lo) / n as f64;
        let (mut alphas, mut betas, mut weights) = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..n {
            for j in 0..=i {
                let alpha = lo + (i as f64 + 0.5) * h;
                let beta = lo + (j as f64 + 0.5) * h;
                alphas.push(alpha);
                betas.push(beta);
                weights.push(mu(alpha, beta) * h * h);
            }
        }
        let states = vec![-1.0; weights.len()];
        Self {
            alphas,
            betas,
            weights,
            states,
        }
    }

    /// A Gaussian Preisach density centred on coercive field `hc` (spread `sh`) and interaction
    /// field 0 (spread `si`), on [−range, range].
    pub fn gaussian(range: f64, n: usize, hc: f64, sh: f64, si: f64) -> Self {
        Self::new(-range, range, n, move |a, b| {
            let c = 0.5 * (a - b);
            let i = 0.5 * (a + b);
            (-((c - hc) / sh).powi(2) - (i / si).powi(2)).exp()
        })
    }
}

impl TrueHysteresis for Preisach {
    fn step(&mut self, x: f64) -> f64 {
        let mut y = 0.0;
        for k in 0..self.states.len() {
            if x >= self.alphas[k] {
                self.states[k] = 1.0;
            } else if x <= self.betas[k] {
                self.states[k] = -1.0;
            }
            y += self.weights[k] * self.states[k];
        }
        y
    }
    fn reset(&mut self) {
        self.states.iter_mut().for_each(|s| *s = -1.0);
    }
}

/// An input history for first-order reversal curves: from `hi` (positive saturation) down to
/// each reversal field, then back up to `hi`, for `curves` reversal fields spread over
/// [lo, hi); `points` samples per unit of input. Returns (input, curve index; −1 on descents).
#[must_use]
pub fn forc_input(lo: f64, hi: f64, curves: usize, points_per_unit: f64) -> Vec<(f64, i64)> {
    let mut out = Vec::new();
    let step = 1.0 / points_per_unit.max(1.0);
    for c in 0..curves {
        let reversal = hi - (hi - lo) * (c + 1) as f64 / curves as f64;
        let mut x = hi;
        while x > reversal {
            out.push((x, -1));
            x -= step;
        }
        let mut x = reversal;
        while x <= hi {
            out.push((x, c as i64));
            x += step;
        }
    }
    out
}

/// One sampled trace of a compensated plant (Lemma 5.1).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trace {
    /// Sample times (s).
    pub t: Vec<f64>,
    /// The new input u_new.
    pub u_new: Vec<f64>,
    /// The reference v (what the compensated output should be).
    pub reference: Vec<f64>,
    /// The command u sent to the plant.
    pub command: Vec<f64>,
    /// The plant state x1 before the hysteresis.
    pub x1: Vec<f64>,
    /// The hysteresis output x2.
    pub output: Vec<f64>,
}

/// Simulates `plant` (b / (a_n sⁿ + … + 1), here as a [`StateSpace`] whose output is x1)
/// driven by the Lemma 5.1 compensator `comp` with new input `u_new(t, [v, v̇, …])` (held over
/// each sample), the hysteresis `truth`
/// on x1, for `samples` samples of `dt`. Between samples the plant is integrated with RK4, the
/// command evaluated at the stage times ([`Compensator::peek`]) and the step split at a turning
/// point of v. The plant starts at `x0`.
///
/// # Errors
/// The compensator's errors (a reference outside a shaping function's range).
#[allow(clippy::too_many_arguments)]
pub fn simulate_compensated<const N: usize, I, K, O>(
    plant: &StateSpace,
    comp: &mut Compensator<f64, N, I, K, O>,
    truth: &mut dyn TrueHysteresis,
    u_new: &mut dyn FnMut(f64, &[f64]) -> f64,
    x0: &[f64],
    dt: f64,
    samples: usize,
) -> Result<Trace, Error>
where
    I: Shaping<f64> + Clone,
    K: K2Law<f64> + Clone,
    O: Shaping<f64> + Clone,
{
    let mut x = x0.to_vec();
    let mut trace = Trace::default();
    for k in 0..samples {
        let t = k as f64 * dt;
        let un = u_new(t + 0.5 * dt, &comp.state());
        let split = comp.turning_point(un, dt);
        let mut next = x.clone();
        let mut t0 = 0.0;
        for t1 in [split.unwrap_or(dt), dt] {
            if t1 > t0 {
                let end = if Some(t1) == split {
                    t1 - 1e-9 * dt
                } else {
                    t1
                };
                let us = [
                    comp.peek(un, t0)?,
                    comp.peek(un, 0.5 * (t0 + t1))?,
                    comp.peek(un, end)?,
                ];
                let mut f = |s: f64, xs: &[f64]| {
                    let u = if s <= 0.0 {
                        us[0]
                    } else if s < t1 - t0 {
                        us[1]
                    } else {
                        us[2]
                    };
                    plant.derivative(xs, u)
                };
                next = rk4_step(&mut f, 0.0, &next, t1 - t0);
                t0 = t1;
            }
        }
        let u = comp.try_step(un, dt)?;
        let x1 = plant.output(&x, u);
        trace.t.push(t);
        trace.u_new.push(un);
        trace.reference.push(comp.last_reference());
        trace.command.push(u);
        trace.x1.push(x1);
        trace.output.push(truth.step(x1));
        x = next;
    }
    Ok(trace)
}

/// The direction type, re-exported for users building initial states.
pub type InitialDirection = Direction;

#[cfg(test)]
mod tests {
    use super::*;
    use hyst_core::Identity;

    #[test]
    fn transfer_function_realisation() -> Result<(), String> {
        // 1 / (s² + 0.9 s + 1): A = [[0, 1], [−1, −0.9]], C = [1, 0].
        let p = StateSpace::from_transfer_function(&[1.0], &[1.0, 0.9, 1.0])?;
        assert_eq!(p.a, vec![vec![0.0, 1.0], vec![-1.0, -0.9]]);
        assert_eq!(p.c, vec![1.0, 0.0]);
        let eq = p.equilibrium(2.0).ok_or("singular")?;
        assert!((p.output(&eq, 2.0) - 2.0).abs() < 1e-12);
        // (s + 3) / (s + 1): D = 1, and the DC gain is 3.
        let q = StateSpace::from_transfer_function(&[1.0, 3.0], &[1.0, 1.0])?;
        let e = q.equilibrium(1.0).ok_or("singular")?;
        assert!((q.output(&e, 1.0) - 3.0).abs() < 1e-12);
        Ok(())
    }

    #[test]
    fn integrators_agree_with_the_exponential() -> Result<(), String> {
        let mut f = |_t: f64, x: &[f64]| vec![-x[0], x[0] - 2.0 * x[1]];
        let mut x = vec![1.0, 0.0];
        for k in 0..100 {
            x = rk4_step(&mut f, k as f64 * 0.01, &x, 0.01);
        }
        let exact0 = (-1.0_f64).exp();
        let exact1 = (-1.0_f64).exp() - (-2.0_f64).exp();
        assert!((x[0] - exact0).abs() < 1e-9 && (x[1] - exact1).abs() < 1e-9);
        let (y, stats) = integrate_adaptive(&mut f, 0.0, 1.0, &[1.0, 0.0], 1e-10)?;
        assert!(
            (y[0] - exact0).abs() < 1e-8 && (y[1] - exact1).abs() < 1e-8,
            "{y:?}"
        );
        assert!(stats.accepted > 3);
        Ok(())
    }

    #[test]
    fn backlash_and_preisach_are_hysteretic() {
        let mut b = Backlash::new(0.4);
        assert_eq!(b.step(0.0), 0.0);
        assert!((b.step(1.0) - 0.8).abs() < 1e-15);
        assert!((b.step(0.9) - 0.8).abs() < 1e-15); // inside the play
        assert!((b.step(0.0) - 0.2).abs() < 1e-15);
        let mut p = Preisach::gaussian(2.0, 40, 0.5, 0.2, 0.3);
        let up: Vec<f64> = [-2.0, 0.0, 2.0].iter().map(|x| p.step(*x)).collect();
        let down = p.step(0.0);
        assert!(down > up[1] + 0.1, "no loop: {up:?} {down}");
        assert!(forc_input(-1.0, 1.0, 5, 10.0).len() > 50);
    }

    #[test]
    fn drifting_member_stays_in_its_band() {
        let mut d = Drifting::new(
            Identity,
            Identity,
            (0.1, 0.02, 5.0, 2.0),
            |k: usize, _v: f64| ((k as f64 * 0.01).sin(), (k as f64 * 0.003).cos()),
        );
        for k in 0..5000 {
            let x = (k as f64 * 0.004).sin() * 2.0;
            let y = d.step(x);
            assert!((y - x).abs() <= 0.12 + 1e-12);
            let (k1, k2) = d.last_params;
            assert!((0.08..=0.12).contains(&k1) && (3.0..=7.0).contains(&k2));
        }
    }
}
