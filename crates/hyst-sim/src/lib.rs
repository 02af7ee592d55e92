//! Simulation for hyst: linear plants (transfer function or state space), fixed-step RK4 and an
//! adaptive Dormand–Prince 5(4) integrator, the "true" hysteresis inside a simulated plant
//! (the smooth operator or a fitted model, a family member whose parameters drift inside the
//! family, a hard backlash, a Preisach model), the Lemma 5.1 closed loop (eqs. 18–20 of the
//! paper), and the paper's Examples 1–3 (Section 6).
//!
//! Every function that takes user input checks it and returns a [`SimError`] naming the
//! parameter and the value; nothing here panics on user input.

use hyst_core::{
    Compensator, ConstantK2, Direction, Error, Hysteresis, K2Law, Memory, Model, Operator, Shaping,
};

pub mod examples;

/// Everything that can go wrong in a simulation. Each message names the parameter and the value.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SimError {
    /// A transfer function with no denominator coefficients.
    #[error(
        "transfer function denominator is empty: give [a_n, …, a_1, a_0], highest power first"
    )]
    EmptyDenominator,
    /// The highest-power coefficient of the denominator is zero.
    #[error(
        "transfer function denominator: leading coefficient a_n = {a_n} (the coefficient of the \
         highest power of s must be non-zero; drop leading zeros)"
    )]
    LeadingCoefficientZero {
        /// The leading coefficient given.
        a_n: f64,
    },
    /// The numerator has a higher degree than the denominator.
    #[error(
        "transfer function is improper: numerator degree {num_degree} > denominator degree \
         {den_degree} (needs deg num ≤ deg den)"
    )]
    Improper {
        /// Degree of the numerator (its length − 1).
        num_degree: usize,
        /// Degree of the denominator (its length − 1).
        den_degree: usize,
    },
    /// A coefficient, state entry or sample is NaN or infinite.
    #[error("{name}[{index}] = {value} is not finite")]
    NonFinite {
        /// Which array, e.g. "transfer function numerator", "state-space A".
        name: &'static str,
        /// The position in it (row-major for matrices).
        index: usize,
        /// The value given.
        value: f64,
    },
    /// The state matrix A is not n × n.
    #[error("state-space A is {rows}×{cols}, must be square")]
    NotSquare {
        /// Number of rows of A.
        rows: usize,
        /// Length of the first row whose length differs from the number of rows.
        cols: usize,
    },
    /// A vector has the wrong length for the state dimension n.
    #[error("{name} has {len} entries, the state dimension is n = {order}")]
    DimensionMismatch {
        /// Which vector: "state-space B", "state-space C", "x0", "right-hand side f(t, x)".
        name: &'static str,
        /// Its length.
        len: usize,
        /// The state dimension n.
        order: usize,
    },
    /// A scalar parameter outside its valid range.
    #[error("invalid parameter {name} = {value}: must be {expected}")]
    InvalidParameter {
        /// The parameter's name, e.g. "dt", "tol", "backlash width".
        name: &'static str,
        /// The value given.
        value: f64,
        /// What it must be.
        expected: &'static str,
    },
    /// The adaptive integrator's right-hand side returned NaN or infinity.
    #[error("non-finite right-hand side f(t, x) at t = {t}")]
    NonFiniteDerivative {
        /// The time of the failing evaluation.
        t: f64,
    },
    /// The adaptive integrator needed a step below 1e-14 of the span (a stiff or singular
    /// right-hand side).
    #[error("step size underflow at t = {t} (step {h})")]
    StepSizeUnderflow {
        /// The time reached.
        t: f64,
        /// The step size that was too small.
        h: f64,
    },
    /// An error of the hysteresis core (a model parameter, a reference outside a shaping
    /// function's range, …), passed through unchanged.
    #[error(transparent)]
    Core(#[from] Error),
}

/// A linear time-invariant single-input single-output plant ẋ = A x + B u, y = C x + D u
/// (state x ∈ ℝⁿ; u and y in the units of the plant's input and output). Eq. (18)'s
/// b / (a_n sⁿ + … + a_1 s + 1) is built with [`StateSpace::from_transfer_function`].
#[derive(Clone, Debug, PartialEq)]
pub struct StateSpace {
    a: Vec<Vec<f64>>,
    b: Vec<f64>,
    c: Vec<f64>,
    d: f64,
}

fn check_finite(name: &'static str, values: &[f64]) -> Result<(), SimError> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(SimError::NonFinite {
            name,
            index,
            value: values.get(index).copied().unwrap_or(f64::NAN),
        }),
        None => Ok(()),
    }
}

impl StateSpace {
    /// A plant from its matrices: A (n × n, a vector of rows), B and C (n entries each), D.
    ///
    /// # Errors
    /// [`SimError::NotSquare`] when a row of A does not have n entries,
    /// [`SimError::DimensionMismatch`] when B or C does not have n entries,
    /// [`SimError::NonFinite`] for a NaN or infinite entry.
    pub fn new(a: Vec<Vec<f64>>, b: Vec<f64>, c: Vec<f64>, d: f64) -> Result<Self, SimError> {
        let n = a.len();
        if let Some(row) = a.iter().find(|r| r.len() != n) {
            return Err(SimError::NotSquare {
                rows: n,
                cols: row.len(),
            });
        }
        for (name, v) in [("state-space B", &b), ("state-space C", &c)] {
            if v.len() != n {
                return Err(SimError::DimensionMismatch {
                    name,
                    len: v.len(),
                    order: n,
                });
            }
        }
        let flat: Vec<f64> = a.iter().flatten().copied().collect();
        check_finite("state-space A", &flat)?;
        check_finite("state-space B", &b)?;
        check_finite("state-space C", &c)?;
        check_finite("state-space D", &[d])?;
        Ok(Self { a, b, c, d })
    }

    /// The controllable canonical form of num(s) / den(s), coefficients from the highest power
    /// down: eq. (18)'s b / (a_n sⁿ + … + a_1 s + 1) is `num = [b]`, `den = [a_n, …, a_1, 1]`
    /// (e.g. Example 3's 1 / (s² + 0.9 s + 1) is `[1.0]` over `[1.0, 0.9, 1.0]`). Needs
    /// deg num ≤ deg den; a proper (not strictly proper) function gets a feed-through D.
    ///
    /// # Errors
    /// [`SimError::EmptyDenominator`], [`SimError::LeadingCoefficientZero`] (a_n = 0),
    /// [`SimError::Improper`] (deg num > deg den), [`SimError::NonFinite`] for a NaN or
    /// infinite coefficient.
    pub fn from_transfer_function(num: &[f64], den: &[f64]) -> Result<Self, SimError> {
        check_finite("transfer function numerator", num)?;
        check_finite("transfer function denominator", den)?;
        let Some(&lead) = den.first() else {
            return Err(SimError::EmptyDenominator);
        };
        if lead == 0.0 {
            return Err(SimError::LeadingCoefficientZero { a_n: lead });
        }
        let n = den.len() - 1;
        if num.len() > den.len() {
            return Err(SimError::Improper {
                num_degree: num.len().saturating_sub(1),
                den_degree: n,
            });
        }
        let den: Vec<f64> = den.iter().map(|x| x / lead).collect();
        let mut nump = vec![0.0; den.len() - num.len()];
        nump.extend(num.iter().map(|x| x / lead));
        // Strictly proper part: num = d den + r.
        let d = nump.first().copied().unwrap_or(0.0);
        let r: Vec<f64> = nump.iter().zip(&den).map(|(p, q)| p - d * q).collect();
        // x = [z, ż, …, z^(n−1)], z^(n) = u − Σ den[n−i] z^(i); y = Σ r[n−i] z^(i) + d u.
        let a: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                if i + 1 < n {
                    (0..n).map(|j| if j == i + 1 { 1.0 } else { 0.0 }).collect()
                } else {
                    den.iter().skip(1).rev().map(|x| -x).collect()
                }
            })
            .collect();
        let b: Vec<f64> = (0..n).map(|i| if i + 1 == n { 1.0 } else { 0.0 }).collect();
        let c: Vec<f64> = r.iter().skip(1).rev().copied().collect();
        Self::new(a, b, c, d)
    }

    /// The state matrix A (n × n, rows).
    #[must_use]
    pub fn a(&self) -> &[Vec<f64>] {
        &self.a
    }

    /// The input vector B (n entries).
    #[must_use]
    pub fn b(&self) -> &[f64] {
        &self.b
    }

    /// The output vector C (n entries).
    #[must_use]
    pub fn c(&self) -> &[f64] {
        &self.c
    }

    /// The feed-through D (0 for a strictly proper plant such as eq. 18).
    #[must_use]
    pub fn d(&self) -> f64 {
        self.d
    }

    /// The state dimension n (the order of eq. 18's denominator).
    #[must_use]
    pub fn order(&self) -> usize {
        self.b.len()
    }

    /// ẋ = A x + B u for the state `x` (n entries; missing entries count as 0, extra ones are
    /// ignored) and the input `u`.
    #[must_use]
    pub fn derivative(&self, x: &[f64], u: f64) -> Vec<f64> {
        self.a
            .iter()
            .zip(&self.b)
            .map(|(row, b)| row.iter().zip(x).map(|(a, x)| a * x).sum::<f64>() + b * u)
            .collect()
    }

    /// y = C x + D u (as [`StateSpace::derivative`] for the length of `x`).
    #[must_use]
    pub fn output(&self, x: &[f64], u: f64) -> f64 {
        self.c.iter().zip(x).map(|(c, x)| c * x).sum::<f64>() + self.d * u
    }

    /// The steady state for a constant input u: the solution of A x = −B u (Gaussian elimination
    /// with partial pivoting), `None` when A is singular (a pure integrator, say).
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
            let magnitude = |r: &Vec<f64>| r.get(col).map_or(0.0, |x| x.abs());
            let pivot = (col..n).max_by(|&i, &j| {
                let (a, b) = (
                    m.get(i).map_or(0.0, magnitude),
                    m.get(j).map_or(0.0, magnitude),
                );
                a.total_cmp(&b)
            })?;
            m.swap(col, pivot);
            let pivot_row = m.get(col)?.clone();
            let p = *pivot_row.get(col)?;
            if p.abs() < 1e-300 {
                return None;
            }
            for (r, row) in m.iter_mut().enumerate() {
                if r != col {
                    let f = row.get(col).copied().unwrap_or(0.0) / p;
                    for (x, q) in row.iter_mut().zip(&pivot_row).skip(col) {
                        *x -= f * q;
                    }
                }
            }
        }
        m.iter()
            .enumerate()
            .map(|(i, row)| Some(row.get(n)? / row.get(i)?))
            .collect()
    }
}

fn axpy(x: &[f64], h: f64, d: &[f64]) -> Vec<f64> {
    x.iter().zip(d).map(|(x, d)| x + h * d).collect()
}

/// One classical fourth-order Runge–Kutta step of ẋ = f(t, x) from time `t` over `h` (same
/// time unit as f's). Fourth-order accurate when f is smooth over [t, t + h]; a simulator must
/// therefore start a new step at every kink or jump of the input (see
/// [`simulate_compensated`]).
///
/// # Errors
/// [`SimError::DimensionMismatch`] when f returns a vector whose length is not that of `x`.
pub fn rk4_step(
    f: &mut impl FnMut(f64, &[f64]) -> Vec<f64>,
    t: f64,
    x: &[f64],
    h: f64,
) -> Result<Vec<f64>, SimError> {
    let n = x.len();
    let mut checked = |s: f64, y: &[f64]| {
        let k = f(s, y);
        if k.len() == n {
            Ok(k)
        } else {
            Err(SimError::DimensionMismatch {
                name: "right-hand side f(t, x)",
                len: k.len(),
                order: n,
            })
        }
    };
    let k1 = checked(t, x)?;
    let k2 = checked(t + 0.5 * h, &axpy(x, 0.5 * h, &k1))?;
    let k3 = checked(t + 0.5 * h, &axpy(x, 0.5 * h, &k2))?;
    let k4 = checked(t + h, &axpy(x, h, &k3))?;
    Ok(x.iter()
        .zip(k1.iter().zip(&k2).zip(k3.iter().zip(&k4)))
        .map(|(x, ((a, b), (c, d)))| x + h / 6.0 * (a + 2.0 * b + 2.0 * c + d))
        .collect())
}

/// Statistics of an adaptive integration ([`integrate_adaptive`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AdaptiveStats {
    /// Accepted steps.
    pub accepted: usize,
    /// Rejected steps (error estimate above the tolerance; retried with a smaller step).
    pub rejected: usize,
}

/// Integrates ẋ = f(t, x) from `t0` to `t1` (t1 ≤ t0 returns `x0` unchanged) with the
/// Dormand–Prince 5(4) pair and step-size control on the mixed error tolerance `tol`
/// (absolute and relative, per component: |error| ≤ tol (1 + |x|)). Used as the reference
/// solution for fixed-step runs.
///
/// # Errors
/// [`SimError::InvalidParameter`] for a non-finite t0 or t1 or a tol that is not finite and
/// positive, [`SimError::NonFinite`] for a non-finite entry of `x0`,
/// [`SimError::DimensionMismatch`] when f returns a vector of the wrong length,
/// [`SimError::NonFiniteDerivative`] and [`SimError::StepSizeUnderflow`] for a singular or
/// non-finite right-hand side.
pub fn integrate_adaptive(
    f: &mut impl FnMut(f64, &[f64]) -> Vec<f64>,
    t0: f64,
    t1: f64,
    x0: &[f64],
    tol: f64,
) -> Result<(Vec<f64>, AdaptiveStats), SimError> {
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
    for (name, value) in [("t0", t0), ("t1", t1)] {
        if !value.is_finite() {
            return Err(SimError::InvalidParameter {
                name,
                value,
                expected: "finite",
            });
        }
    }
    if !(tol.is_finite() && tol > 0.0) {
        return Err(SimError::InvalidParameter {
            name: "tol",
            value: tol,
            expected: "finite and > 0",
        });
    }
    check_finite("x0", x0)?;
    let n = x0.len();
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
        for (c, a) in C.iter().zip(&A) {
            let mut xs = x.clone();
            for (aj, kj) in a.iter().zip(&k) {
                for (xi, kji) in xs.iter_mut().zip(kj) {
                    *xi += h * aj * kji;
                }
            }
            let ks = f(t + c * h, &xs);
            if ks.len() != n {
                return Err(SimError::DimensionMismatch {
                    name: "right-hand side f(t, x)",
                    len: ks.len(),
                    order: n,
                });
            }
            k.push(ks);
        }
        let mut err = 0.0_f64;
        let mut x5 = x.clone();
        for (i, (xi, x5i)) in x.iter().zip(x5.iter_mut()).enumerate() {
            let stage = |s: &Vec<f64>| s.get(i).copied().unwrap_or(0.0);
            let d5: f64 = B5.iter().zip(&k).map(|(b, s)| b * stage(s)).sum();
            let d4: f64 = B4.iter().zip(&k).map(|(b, s)| b * stage(s)).sum();
            *x5i += h * d5;
            let scale = tol * (1.0 + xi.abs().max(x5i.abs()));
            err = err.max((h * (d5 - d4)).abs() / scale);
        }
        if !err.is_finite() {
            return Err(SimError::NonFiniteDerivative { t });
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
            return Err(SimError::StepSizeUnderflow { t, h });
        }
    }
    Ok((x, stats))
}

/// A rate-independent hysteresis inside a simulated plant (the paper's "true" Hyst(x1) of
/// eq. 18's plant): one output sample per input sample, in the units of the plant's output.
pub trait TrueHysteresis {
    /// The output for the next input sample.
    fn step(&mut self, input: f64) -> f64;
    /// Forgets the history.
    fn reset(&mut self);
    /// Shows the hysteresis an input between two samples (the plant's x1 at a turning point of
    /// the reference, see [`simulate_compensated`]) so that its reversal point is the true
    /// extremum, not the nearest sample. The default runs [`TrueHysteresis::step`] and drops
    /// the output, right for any rate-independent operator; a truth that counts samples
    /// (such as [`Drifting`]) overrides it so the count is unchanged.
    fn pass(&mut self, input: f64) {
        let _ = self.step(input);
    }
}

/// The smooth operator with shaping (a [`Model`]: ψ_out(H(k1, k2)[ψ_in(x)]), eqs. 2–4 with the
/// shaping of Section 4), also the form of a model fitted to data.
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

/// A family member whose parameters drift inside the family RH(k1, Δk1, k2, Δk2)
/// (Definition 3.1): at each sample k̄1 = k1 + a Δk1 and k̄2 = k2 + b Δk2, with (a, b) ∈
/// [−1, 1]² given by `drift` as a function of the sample index and the operator input (so k̄2
/// can depend on the input, as in Example 2: higher near zero magnetisation, lower near
/// saturation). Wrapped in input and output shaping. The memory is carried over between
/// parameter changes (clamped into the band of the new k̄1). Propositions 3.2–3.3 bound its
/// distance from the nominal model by Δa (eqs. 12–13).
pub struct Drifting<I, O, F, K = ConstantK2<f64>> {
    /// Input shaping ψ_in.
    pub input: I,
    /// Output shaping ψ_out.
    pub output: O,
    k1: f64,
    dk1: f64,
    k2: K,
    dk2: f64,
    /// (sample index, operator input) → (a, b); values outside [−1, 1] are clamped.
    pub drift: F,
    memory: Option<Memory<f64>>,
    index: usize,
    last_params: (f64, f64),
}

/// `value` if it is finite and ≥ 0, else an error naming it.
fn non_negative(name: &'static str, value: f64) -> Result<f64, SimError> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(SimError::InvalidParameter {
            name,
            value,
            expected: "finite and ≥ 0",
        })
    }
}

fn check_width(name: &'static str, value: f64, nominal: f64) -> Result<(), SimError> {
    if value.is_finite() && value >= 0.0 && value < nominal {
        Ok(())
    } else {
        Err(SimError::InvalidParameter {
            name,
            value,
            expected: "finite, ≥ 0 and below the nominal value (so every member is valid)",
        })
    }
}

impl<I, O, F> Drifting<I, O, F, ConstantK2<f64>>
where
    I: Shaping<f64>,
    O: Shaping<f64>,
    F: FnMut(usize, f64) -> (f64, f64),
{
    /// A drifting member of RH(k1, Δk1, k2, Δk2), `family = (k1, Δk1, k2, Δk2)` (constant
    /// nominal k2; k1 in the units of the operator input, k2 in its inverse).
    ///
    /// # Errors
    /// [`SimError::Core`] for k1 or k2 not finite and > 0; [`SimError::InvalidParameter`] for a
    /// width Δk1 or Δk2 that is negative, non-finite or not below its nominal value.
    pub fn new(
        input: I,
        output: O,
        family: (f64, f64, f64, f64),
        drift: F,
    ) -> Result<Self, SimError> {
        let _ = Hysteresis::<f64, ConstantK2<f64>>::new(family.0, family.2)?;
        check_width("Δk2", family.3, family.2)?;
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
    /// A drifting member of RH(k1, Δk1, φ(·), Δk2), `k1 = (k1, Δk1)`: k̄2 = φ(v) + b Δk2 with v
    /// the operator input (after ψ_in). A k̄2 ≤ 0 reached by the law gives a NaN output.
    ///
    /// # Errors
    /// [`SimError::Core`] for k1 not finite and > 0; [`SimError::InvalidParameter`] for Δk1
    /// not in [0, k1) or Δk2 not finite and ≥ 0.
    pub fn with_law(
        input: I,
        output: O,
        k1: (f64, f64),
        k2: K,
        dk2: f64,
        drift: F,
    ) -> Result<Self, SimError> {
        let _ = Hysteresis::<f64, ConstantK2<f64>>::new(k1.0, 1.0)?;
        check_width("Δk1", k1.1, k1.0)?;
        non_negative("Δk2", dk2)?;
        Ok(Self {
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
        })
    }

    /// The (k̄1, k̄2) used at the last sample ((k1, NaN) before the first).
    #[must_use]
    pub fn last_params(&self) -> (f64, f64) {
        self.last_params
    }

    /// One evaluation; `count` advances the sample index seen by `drift`.
    fn advance(&mut self, input: f64, count: bool) -> f64 {
        let v = self.input.apply(input);
        let (a, b) = (self.drift)(self.index, v);
        if count {
            self.index += 1;
        }
        let k1 = self.k1 + a.clamp(-1.0, 1.0) * self.dk1;
        let k2 = self.k2.k2(v) + b.clamp(-1.0, 1.0) * self.dk2;
        self.last_params = (k1, k2);
        let op: Result<Hysteresis<f64, ConstantK2<f64>>, Error> = Hysteresis::new(k1, k2);
        let Ok(mut op) = op else {
            return f64::NAN;
        };
        if let Some(mut m) = self.memory {
            let clamp = |inp: f64, out: f64| out.max(inp - k1).min(inp + k1);
            m.reversal_output = clamp(m.reversal_input, m.reversal_output);
            m.last_output = clamp(m.last_input, m.last_output);
            let _ = op.set_memory(Some(m));
        }
        let u = op.step(v);
        self.memory = op.memory();
        self.output.apply(u)
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
        self.advance(input, true)
    }
    fn reset(&mut self) {
        self.memory = None;
        self.index = 0;
    }
    fn pass(&mut self, input: f64) {
        let _ = self.advance(input, false);
    }
}

/// A hard backlash (play operator, Example 3's truth) of total width `2 r`: the output follows
/// the input at a distance r once the play is taken up, y ← clamp(y, x − r, x + r); input and
/// output in the same unit (m in Example 3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Backlash {
    half_width: f64,
    state: Option<f64>,
}

impl Backlash {
    /// A backlash of total width `width` (Example 3: 0.4 m, so r = 0.2 m), starting on the line
    /// y = x at the first sample.
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] when the width is not finite and ≥ 0.
    pub fn new(width: f64) -> Result<Self, SimError> {
        non_negative("backlash width", width)?;
        Ok(Self {
            half_width: 0.5 * width,
            state: None,
        })
    }

    /// The half-width r.
    #[must_use]
    pub fn half_width(&self) -> f64 {
        self.half_width
    }

    /// The output; `None` before the first sample.
    #[must_use]
    pub fn state(&self) -> Option<f64> {
        self.state
    }
}

impl TrueHysteresis for Backlash {
    fn step(&mut self, x: f64) -> f64 {
        let y = self.state.unwrap_or(x);
        let y = y.max(x - self.half_width).min(x + self.half_width);
        self.state = Some(y);
        y
    }
    fn reset(&mut self) {
        self.state = None;
    }
}

/// A discrete Preisach model (a truth with a different structure from the paper's operator):
/// relays on a triangular grid α ≥ β over [lo, hi] with weights μ(α, β) h² (h the grid
/// spacing); output = Σ μ γ̂αβ[x] with relays ±1, all at −1 initially (negative saturation).
#[derive(Clone, Debug, PartialEq)]
pub struct Preisach {
    alphas: Vec<f64>,
    betas: Vec<f64>,
    weights: Vec<f64>,
    states: Vec<f64>,
}

impl Preisach {
    /// An `n` × `n` grid (n ≥ 2; smaller values use 2) over [lo, hi] with weights
    /// `mu(alpha, beta)` (switch-up threshold α, switch-down threshold β ≤ α, input units).
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] when lo or hi is not finite or lo ≥ hi.
    pub fn new(lo: f64, hi: f64, n: usize, mu: impl Fn(f64, f64) -> f64) -> Result<Self, SimError> {
        for (name, value) in [("Preisach lo", lo), ("Preisach hi", hi)] {
            if !value.is_finite() {
                return Err(SimError::InvalidParameter {
                    name,
                    value,
                    expected: "finite",
                });
            }
        }
        if lo >= hi {
            return Err(SimError::InvalidParameter {
                name: "Preisach hi",
                value: hi,
                expected: "greater than lo",
            });
        }
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
        Ok(Self {
            alphas,
            betas,
            weights,
            states,
        })
    }

    /// A Gaussian Preisach density centred on coercive field `hc` (spread `sh`) and interaction
    /// field 0 (spread `si`), on [−range, range]: μ = exp(−((c − hc)/sh)² − (i/si)²) with
    /// c = (α − β)/2, i = (α + β)/2.
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] when range, sh or si is not finite and > 0.
    pub fn gaussian(range: f64, n: usize, hc: f64, sh: f64, si: f64) -> Result<Self, SimError> {
        for (name, value) in [
            ("Preisach range", range),
            ("Preisach sh", sh),
            ("Preisach si", si),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(SimError::InvalidParameter {
                    name,
                    value,
                    expected: "finite and > 0",
                });
            }
        }
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
        for (((s, a), b), w) in self
            .states
            .iter_mut()
            .zip(&self.alphas)
            .zip(&self.betas)
            .zip(&self.weights)
        {
            if x >= *a {
                *s = 1.0;
            } else if x <= *b {
                *s = -1.0;
            }
            y += w * *s;
        }
        y
    }
    fn reset(&mut self) {
        self.states.iter_mut().for_each(|s| *s = -1.0);
    }
}

/// An input history for first-order reversal curves (the measurement behind the paper's
/// Fig. 3): from `hi` (positive saturation) down to each reversal field, then back up to `hi`,
/// for `curves` reversal fields spread over [lo, hi); `points_per_unit` samples per unit of
/// input (at least 1). Returns (input, curve index; −1 on descents). Empty for non-finite
/// bounds.
#[must_use]
pub fn forc_input(lo: f64, hi: f64, curves: usize, points_per_unit: f64) -> Vec<(f64, i64)> {
    let mut out = Vec::new();
    if !(lo.is_finite() && hi.is_finite()) {
        return out;
    }
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

/// One sampled trace of a compensated plant (Lemma 5.1), one entry per sample.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trace {
    /// Sample times t_k = k dt (s).
    pub t: Vec<f64>,
    /// The new input u_new = v⁽ⁿ⁾, held over the sample.
    pub u_new: Vec<f64>,
    /// The reference v(t_k): what the compensated output x2 should be (eq. 20 with Δ = 0).
    pub reference: Vec<f64>,
    /// The plant-input target x(t_k) = ψ_in⁻¹(H⁻¹[ψ_out⁻¹(v)]) that x1 should follow.
    pub target: Vec<f64>,
    /// The command u (eq. 19) sent to the plant just after t_k (the right limit: at a reversal
    /// of v at t_k it is the new branch's value).
    pub command: Vec<f64>,
    /// The plant output x1(t_k) before the hysteresis.
    pub x1: Vec<f64>,
    /// The hysteresis output x2(t_k) = truth[x1].
    pub output: Vec<f64>,
}

/// The most integration pieces per sample: the compensator itself commits at most 4 turning
/// points of v per sample.
const MAX_PIECES: usize = 5;

/// Simulates eq. (18)'s plant b / (a_n sⁿ + … + 1) (here `plant`, a [`StateSpace`] whose output
/// is x1) followed by the hysteresis `truth` on x1, driven by the Lemma 5.1 compensator `comp`
/// (eq. 19) with the new input `u_new(t, [v, v̇, …])` (evaluated mid-sample and held over each
/// sample), for `samples` samples of `dt` (s), starting from the plant state `x0`.
///
/// Between samples the plant is integrated with RK4, with the command evaluated at the stage
/// times ([`Compensator::peek`]). The command is smooth only between reversals of v (it has a
/// kink for n = 1 and a jump for n ≥ 2 there, Proposition 2.7), so each step is split at the
/// reversal instants: at the sample instant (n = 1: v̇ = u_new changes sign between samples;
/// the stages use the new branch's command) and at the turning points inside the sample
/// ([`Compensator::turning_point`], n ≥ 2; the piece before one ends on the old branch's command,
/// the piece after it starts on the new one). RK4's fourth order is kept that way: with the exact
/// model as the truth, x1 − x and x2 − v shrink 16-fold when dt is halved (n = 1, 2). The truth is
/// also shown x1 at each turning point ([`TrueHysteresis::pass`]), so its reversal point is the
/// extremum and not the nearest sample.
///
/// # Errors
/// [`SimError::InvalidParameter`] for a `dt` that is not finite and > 0,
/// [`SimError::DimensionMismatch`] when `x0` does not have the plant's order,
/// [`SimError::NonFinite`] for a non-finite entry of `x0`, and the compensator's errors as
/// [`SimError::Core`] (a non-finite u_new, a reference outside a shaping function's range).
#[allow(clippy::too_many_arguments)]
pub fn simulate_compensated<const N: usize, I, K, O>(
    plant: &StateSpace,
    comp: &mut Compensator<f64, N, I, K, O>,
    truth: &mut dyn TrueHysteresis,
    u_new: &mut dyn FnMut(f64, &[f64]) -> f64,
    x0: &[f64],
    dt: f64,
    samples: usize,
) -> Result<Trace, SimError>
where
    I: Shaping<f64> + Clone,
    K: K2Law<f64> + Clone,
    O: Shaping<f64> + Clone,
{
    if !(dt.is_finite() && dt > 0.0) {
        return Err(SimError::InvalidParameter {
            name: "dt",
            value: dt,
            expected: "finite and > 0 (s)",
        });
    }
    if x0.len() != plant.order() {
        return Err(SimError::DimensionMismatch {
            name: "x0",
            len: x0.len(),
            order: plant.order(),
        });
    }
    check_finite("x0", x0)?;
    let mut x = x0.to_vec();
    let mut trace = Trace::default();
    for k in 0..samples {
        let t = k as f64 * dt;
        let un = u_new(t + 0.5 * dt, &comp.state());
        // `piece` is the compensator at the start of the current integration piece with the value
        // there committed, so that a reversal exactly there is seen through the trend of the jet:
        // its `peek(un, 0)` is the right limit of the command.
        let mut piece = comp.clone();
        let _ = piece.try_step(un, 0.0)?;
        let command = piece.peek(un, 0.0)?;
        let x1 = plant.output(&x, command);
        let _ = comp.try_step(un, dt)?;
        trace.t.push(t);
        trace.u_new.push(un);
        trace.reference.push(comp.last_reference());
        trace.target.push(comp.last_target().value());
        trace.command.push(command);
        trace.x1.push(x1);
        trace.output.push(truth.step(x1));

        let mut t0 = 0.0;
        for index in 0..MAX_PIECES {
            let rest = dt - t0;
            let turning = match piece.turning_point(un, rest) {
                Some(tau) if index + 1 < MAX_PIECES && tau < rest => Some(tau),
                _ => None,
            };
            let h = turning.unwrap_or(rest);
            // The last stage ends on the current branch: just before a turning point (the left
            // limit; 1e-9 of the step changes the command by O(1e-9 dt)).
            let end = if turning.is_some() || piece.turning_point(un, rest).is_some() {
                (h - 1e-9 * dt).max(0.0)
            } else {
                h
            };
            let us = [
                piece.peek(un, 0.0)?,
                piece.peek(un, 0.5 * h)?,
                piece.peek(un, end)?,
            ];
            let mut f = |s: f64, xs: &[f64]| {
                let u = if s <= 0.0 {
                    us[0]
                } else if s < h {
                    us[1]
                } else {
                    us[2]
                };
                plant.derivative(xs, u)
            };
            x = rk4_step(&mut f, 0.0, &x, h)?;
            match turning {
                Some(tau) => {
                    truth.pass(plant.output(&x, us[2]));
                    // Advance to the turning point (committing it as the reversal point) and
                    // commit the value there; the next piece starts on the new branch.
                    let _ = piece.try_step(un, tau)?;
                    let _ = piece.try_step(un, 0.0)?;
                    t0 += tau;
                }
                None => break,
            }
        }
    }
    Ok(trace)
}

/// The direction type of the operator's memory (rising or falling input, Section 4.2),
/// re-exported for users building initial states.
pub type InitialDirection = Direction;

#[cfg(test)]
mod tests {
    use super::*;
    use hyst_core::Identity;

    #[test]
    fn transfer_function_realisation() -> Result<(), SimError> {
        // 1 / (s² + 0.9 s + 1): A = [[0, 1], [−1, −0.9]], C = [1, 0].
        let p = StateSpace::from_transfer_function(&[1.0], &[1.0, 0.9, 1.0])?;
        assert_eq!(p.a(), &[vec![0.0, 1.0], vec![-1.0, -0.9]][..]);
        assert_eq!(p.c(), &[1.0, 0.0][..]);
        let eq = p.equilibrium(2.0).unwrap_or_default();
        assert!((p.output(&eq, 2.0) - 2.0).abs() < 1e-12);
        // (s + 3) / (s + 1): D = 1, and the DC gain is 3.
        let q = StateSpace::from_transfer_function(&[1.0, 3.0], &[1.0, 1.0])?;
        let e = q.equilibrium(1.0).unwrap_or_default();
        assert!((q.output(&e, 1.0) - 3.0).abs() < 1e-12);
        // A pure integrator 1 / s has no equilibrium.
        let i = StateSpace::from_transfer_function(&[1.0], &[1.0, 0.0])?;
        assert_eq!(i.equilibrium(1.0), None);
        Ok(())
    }

    #[test]
    fn bad_plants_are_refused_with_the_parameter_and_value() {
        let msg = |r: Result<StateSpace, SimError>| r.err().map(|e| e.to_string());
        let m = msg(StateSpace::from_transfer_function(&[1.0], &[0.0, 1.0, 1.0]));
        assert!(
            m.as_deref()
                .is_some_and(|m| m.contains("leading coefficient a_n = 0")),
            "{m:?}"
        );
        let m = msg(StateSpace::from_transfer_function(&[1.0], &[]));
        assert!(m.is_some_and(|m| m.contains("empty")));
        let m = msg(StateSpace::from_transfer_function(
            &[1.0, 0.0, 0.0],
            &[1.0, 1.0],
        ));
        assert!(m.is_some_and(|m| m.contains("numerator degree 2 > denominator degree 1")));
        let m = msg(StateSpace::from_transfer_function(&[1.0], &[1.0, f64::NAN]));
        assert!(
            m.as_deref()
                .is_some_and(|m| m.contains("denominator[1] = NaN is not finite")),
            "{m:?}"
        );
        let m = msg(StateSpace::new(
            vec![vec![0.0, 1.0], vec![0.0, 1.0], vec![1.0, 0.0]],
            vec![0.0; 3],
            vec![0.0; 3],
            0.0,
        ));
        assert_eq!(m.as_deref(), Some("state-space A is 3×2, must be square"));
        let m = msg(StateSpace::new(
            vec![vec![1.0]],
            vec![1.0, 2.0],
            vec![1.0],
            0.0,
        ));
        assert_eq!(
            m.as_deref(),
            Some("state-space B has 2 entries, the state dimension is n = 1")
        );
        let m = msg(StateSpace::new(
            vec![vec![f64::INFINITY]],
            vec![1.0],
            vec![1.0],
            0.0,
        ));
        assert_eq!(m.as_deref(), Some("state-space A[0] = inf is not finite"));
        assert!(matches!(
            Backlash::new(-0.4),
            Err(SimError::InvalidParameter { value, .. }) if value == -0.4
        ));
        assert!(Preisach::new(1.0, 1.0, 10, |_, _| 1.0).is_err());
        assert!(Preisach::gaussian(2.0, 10, 0.5, 0.0, 0.3).is_err());
        let bad_width = Drifting::new(
            Identity,
            Identity,
            (0.1, 0.2, 5.0, 1.0),
            |_: usize, _: f64| (0.0, 0.0),
        );
        assert!(bad_width
            .err()
            .is_some_and(|e| e.to_string().contains("Δk1 = 0.2")),);
        let core = Drifting::new(
            Identity,
            Identity,
            (-0.1, 0.0, 5.0, 1.0),
            |_: usize, _: f64| (0.0, 0.0),
        );
        assert!(matches!(core, Err(SimError::Core(_))));
    }

    #[test]
    fn integrators_agree_with_the_exponential() -> Result<(), SimError> {
        let mut f = |_t: f64, x: &[f64]| vec![-x[0], x[0] - 2.0 * x[1]];
        let mut x = vec![1.0, 0.0];
        for k in 0..100 {
            x = rk4_step(&mut f, k as f64 * 0.01, &x, 0.01)?;
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
        // A right-hand side of the wrong length and a bad tolerance are errors, not panics.
        let mut short = |_t: f64, _x: &[f64]| vec![1.0];
        assert!(matches!(
            rk4_step(&mut short, 0.0, &[1.0, 2.0], 0.1),
            Err(SimError::DimensionMismatch {
                len: 1,
                order: 2,
                ..
            })
        ));
        assert!(integrate_adaptive(&mut short, 0.0, 1.0, &[1.0, 2.0], 1e-6).is_err());
        assert!(integrate_adaptive(&mut f, 0.0, 1.0, &[1.0, 0.0], -1.0).is_err());
        Ok(())
    }

    #[test]
    fn backlash_and_preisach_are_hysteretic() -> Result<(), SimError> {
        let mut b = Backlash::new(0.4)?;
        assert_eq!(b.step(0.0), 0.0);
        assert!((b.step(1.0) - 0.8).abs() < 1e-15);
        assert!((b.step(0.9) - 0.8).abs() < 1e-15); // inside the play
        assert!((b.step(0.0) - 0.2).abs() < 1e-15);
        let mut p = Preisach::gaussian(2.0, 40, 0.5, 0.2, 0.3)?;
        let up: Vec<f64> = [-2.0, 0.0, 2.0].iter().map(|x| p.step(*x)).collect();
        let down = p.step(0.0);
        assert!(down > up[1] + 0.1, "no loop: {up:?} {down}");
        assert!(forc_input(-1.0, 1.0, 5, 10.0).len() > 50);
        assert!(forc_input(f64::NAN, 1.0, 5, 10.0).is_empty());
        Ok(())
    }

    #[test]
    fn drifting_member_stays_in_its_band() -> Result<(), SimError> {
        let mut d = Drifting::new(
            Identity,
            Identity,
            (0.1, 0.02, 5.0, 2.0),
            |k: usize, _v: f64| ((k as f64 * 0.01).sin(), (k as f64 * 0.003).cos()),
        )?;
        for k in 0..5000 {
            let x = (k as f64 * 0.004).sin() * 2.0;
            let y = d.step(x);
            assert!((y - x).abs() <= 0.12 + 1e-12);
            let (k1, k2) = d.last_params();
            assert!((0.08..=0.12).contains(&k1) && (3.0..=7.0).contains(&k2));
        }
        Ok(())
    }
}
