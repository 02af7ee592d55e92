//! The two optional parts of a model beyond the hysteresis, and the one discretisation every
//! surface runs them with:
//!
//! - [`Dynamics`]: Lemma 5.1's linear plant between the command u and the hysteresis input v,
//!   a_n v⁽ⁿ⁾ + … + a_1 v̇ + v = b u (eq. 18), order n = 1 … [`MAX_DYNAMICS`], driven through a
//!   [`Hold`];
//! - [`Rate`]: a viscous term c·v̇ of the hysteresis input added to the model output
//!   (friction, dampers).
//!
//! **Discretisation.** Each step h = t_{k+1} − t_k of a record (its time column, module
//! [`crate::time`]) advances the plant's state exactly for the command between the two
//! samples, which the [`Hold`] says: held at u_k (zero-order hold, [`Hold::Zoh`]: a DAC) or
//! linear from u_k to u_{k+1} (first-order hold, [`Hold::Foh`]). With the augmented matrix
//! M = [[A, B, 0], [0, 0, 1], [0, 0, 0]] of the plant's companion form (without the last row
//! and column for the zero-order hold), e^{Mh} = [[Φ, Γ0, Γ1], …] and
//! x_{k+1} = Φ x_k + Γ0 u_k + Γ1 (u_{k+1} − u_k) / h (Γ1 = 0 for the zero-order hold).
//! v_k is the state's first component at t_k, so a plant whose time constants are far below h
//! gives v_k = b u_k (first-order hold) or b u_{k−1} (zero-order hold): a static model is the
//! limit a_i → 0 of a dynamic one. A record starts at rest (v = b u_0, every derivative 0). The
//! matrix exponential is computed by scaling and squaring of its Taylor series, generically over
//! [`Real`], so the fit differentiates it exactly with duals.
//!
//! **Rate.** v̇_k is the backward difference (v_k − v_{k−1}) / h_k over the step's own h, 0 at a
//! record's first sample (at rest): causal, so a compensator can use it sample by sample.

// Dense matrix kernels read best with explicit indices.
#![allow(clippy::needless_range_loop)]

use hyst_core::{Error, Real};
use serde::{Deserialize, Serialize};

use crate::choice::Choice;

/// The highest plant order a model file holds (the core's `MAX_ORDER`, 4).
pub const MAX_DYNAMICS: usize = hyst_core::compensator::MAX_ORDER;

/// What the command does between two samples, for the plant's discretisation: the model
/// file's `[dynamics] hold`, `hyst fit --hold`. A plant driven by a DAC sees its command held
/// (zero-order hold); a command that is itself a sampled smooth signal is closer to linear
/// between samples (first-order hold). A model file without the key was fitted with the
/// first-order hold, and runs with it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Hold {
    /// Zero-order hold: u(t) = u_k on [t_k, t_{k+1}) (MATLAB's `c2d` default). What a fit
    /// writes unless asked otherwise.
    Zoh,
    /// First-order hold: u linear from u_k to u_{k+1} (the model files without `hold`).
    Foh,
}

impl Choice for Hold {
    const WHAT: &'static str = "hold";
    const CHOICES: &'static [(Self, &'static str, &'static str)] = &[
        (
            Hold::Zoh,
            "zoh",
            "Zero-order hold: u(t) = u_k on [t_k, t_{k+1}) (MATLAB's `c2d` default). What a fit \
             writes unless asked otherwise",
        ),
        (
            Hold::Foh,
            "foh",
            "First-order hold: u linear from u_k to u_{k+1} (the model files without `hold`)",
        ),
    ];
}

impl Hold {
    /// The hold of a model file's `[dynamics]` without the key: [`Hold::Foh`].
    pub const UNRECORDED: Hold = Hold::Foh;

    /// The hold of a new fit: [`Hold::Zoh`].
    pub const FIT_DEFAULT: Hold = Hold::Zoh;

    /// In words, for reports: "zero-order hold (the command held over each step)" or
    /// "first-order hold (the command linear between samples)".
    #[must_use]
    pub fn describe(self) -> &'static str {
        match self {
            Hold::Zoh => "zero-order hold (the command held over each step)",
            Hold::Foh => "first-order hold (the command linear between samples)",
        }
    }
}

/// Lemma 5.1's plant b / (a_n sⁿ + … + a_1 s + 1) (eq. 18) between the command u (input units)
/// and the hysteresis input v, with a_i in seconds to the power i. A fitted model has b = 1:
/// the gain of ψ_in (the input's normalisation) already scales v, and a plant gain beside it
/// would say the same thing twice; v is then in command units at steady state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dynamics<T = f64> {
    /// The plant gain b (hysteresis-input units per command unit), non-zero.
    pub b: T,
    a: [T; MAX_DYNAMICS],
    order: usize,
    hold: Hold,
}

impl<T: Real> Dynamics<T> {
    /// The plant with gain `b` and `a = [a_1, …, a_n]`, 1 ≤ n ≤ [`MAX_DYNAMICS`], driven
    /// through a first-order hold ([`Hold::UNRECORDED`]; [`Dynamics::with_hold`] sets another).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for an order outside 1…4, a non-finite or zero b, a
    /// non-finite a_i, or a plant that is not stable (every a_i > 0, and the Routh–Hurwitz
    /// conditions for n = 3, 4): a fitted model never has one, and running an unstable plant
    /// forward would diverge.
    pub fn new(b: T, a: &[T]) -> Result<Self, Error> {
        if a.is_empty() || a.len() > MAX_DYNAMICS {
            return Err(Error::InvalidParameter {
                name: "dynamics.a",
                value: a.len() as f64,
                expected: "1 to 4 coefficients [a_1, ..., a_n]",
            });
        }
        if !(b.is_finite() && b != T::zero()) {
            return Err(Error::InvalidParameter {
                name: "dynamics.b",
                value: b.as_f64(),
                expected: "a finite, non-zero plant gain",
            });
        }
        for c in a {
            if !(c.is_finite() && *c > T::zero()) {
                return Err(Error::InvalidParameter {
                    name: "dynamics.a",
                    value: c.as_f64(),
                    expected: "finite, positive coefficients (a stable plant)",
                });
            }
        }
        let get = |i: usize| a.get(i).copied().unwrap_or_else(T::zero);
        let (a1, a2, a3, a4) = (get(0), get(1), get(2), get(3));
        let stable = match a.len() {
            3 => a2 * a1 > a3,
            4 => a3 * a2 > a4 * a1 && a3 * a2 * a1 > a4 * a1 * a1 + a3 * a3,
            _ => true,
        };
        if !stable {
            return Err(Error::InvalidParameter {
                name: "dynamics.a",
                value: a.last().map_or(f64::NAN, |c| c.as_f64()),
                expected: "a stable plant (Routh-Hurwitz: a_2 a_1 > a_3 for n = 3; \
                           a_3 a_2 > a_4 a_1 and a_3 a_2 a_1 > a_4 a_1^2 + a_3^2 for n = 4)",
            });
        }
        Ok(Self {
            b,
            a: core::array::from_fn(get),
            order: a.len(),
            hold: Hold::UNRECORDED,
        })
    }

    /// The same plant driven through `hold`.
    #[must_use]
    pub fn with_hold(self, hold: Hold) -> Self {
        Self { hold, ..self }
    }

    /// The hold the plant is discretised with.
    #[must_use]
    pub fn hold(&self) -> Hold {
        self.hold
    }

    /// The order n.
    #[must_use]
    pub fn order(&self) -> usize {
        self.order
    }

    /// [a_1, …, a_n] (s, s², …).
    #[must_use]
    pub fn a(&self) -> &[T] {
        self.a.get(..self.order).unwrap_or(&[])
    }

    /// The plant discretised for one step of `period` (s) by its [`Hold`].
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a period that is not finite and positive, or a
    /// discretisation that is not finite.
    pub fn discretise(&self, period: f64) -> Result<Discrete<T>, Error> {
        if !(period.is_finite() && period > 0.0) {
            return Err(Error::InvalidParameter {
                name: "period",
                value: period,
                expected: "a finite, positive sample period (s)",
            });
        }
        let n = self.order;
        let h = T::from_f64(period);
        let an = self.a.get(n - 1).copied().unwrap_or_else(T::one);
        // M h, size n + 2: companion A (x_i' = x_{i+1}; a_n x_n' = b u − x_1 − Σ a_i x_{i+1}),
        // B = b / a_n in the last row, then u' = w, w' = 0 (first-order hold); size n + 1,
        // u' = 0, for the zero-order hold.
        let foh = self.hold == Hold::Foh;
        let mut m = [[T::zero(); AUG]; AUG];
        for i in 0..n.saturating_sub(1) {
            m[i][i + 1] = h;
        }
        m[n - 1][0] = -h / an;
        for i in 1..n {
            m[n - 1][i] = -(self.a[i - 1] * h) / an;
        }
        m[n - 1][n] = self.b * h / an;
        if foh {
            m[n][n + 1] = T::one();
        }
        let e = expm(&m, if foh { n + 2 } else { n + 1 });
        let mut d = Discrete {
            phi: [[T::zero(); MAX_DYNAMICS]; MAX_DYNAMICS],
            g0: [T::zero(); MAX_DYNAMICS],
            g1: [T::zero(); MAX_DYNAMICS],
            b: self.b,
            order: n,
        };
        for i in 0..n {
            for j in 0..n {
                d.phi[i][j] = e[i][j];
            }
            d.g0[i] = e[i][n];
            if foh {
                d.g1[i] = e[i][n + 1];
            }
        }
        let finite = d.phi.iter().flatten().chain(&d.g0).chain(&d.g1);
        if let Some(bad) = finite.copied().find(|x| !x.is_finite()) {
            return Err(Error::InvalidParameter {
                name: "dynamics.a",
                value: bad.as_f64(),
                expected: "coefficients whose discretisation at this period is finite",
            });
        }
        Ok(d)
    }
}

/// The model file's `[dynamics]` section: the plant of a smooth model with the fit's standard
/// errors (the report's `model.dynamics`). b is 1 in a fitted model and not estimated (see
/// [`Dynamics`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DynamicsSection {
    /// The plant gain b.
    pub b: f64,
    /// [a_1, …, a_n] (s, s², …).
    pub a: Vec<f64>,
    /// The standard error of each a_i (NaN where the data does not identify it).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub a_std_error: Vec<f64>,
    /// Whether the records identify each a_i (the fit's report says why not).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub identified: Vec<bool>,
    /// The hold the plant was fitted with and runs with (format version 5); absent:
    /// [`Hold::UNRECORDED`], the first-order hold. [`Hold::recorded`] gives what to write.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hold: Option<Hold>,
}

impl DynamicsSection {
    /// The plant it describes.
    ///
    /// # Errors
    /// As [`Dynamics::new`], and standard errors or flags that do not match the coefficients.
    pub fn dynamics(&self) -> Result<Dynamics, Error> {
        for (name, len) in [
            ("dynamics.a_std_error", self.a_std_error.len()),
            ("dynamics.identified", self.identified.len()),
        ] {
            if len != 0 && len != self.a.len() {
                return Err(Error::InvalidParameter {
                    name,
                    value: len as f64,
                    expected: "one entry per coefficient of a (or none)",
                });
            }
        }
        Ok(Dynamics::new(self.b, &self.a)?.with_hold(self.hold.unwrap_or(Hold::UNRECORDED)))
    }
}

impl Hold {
    /// What a model file's `[dynamics] hold` holds for this hold: `None` (no key, format
    /// version 4) for the first-order hold, which a file without the key means, so that files
    /// readable by earlier versions stay so; the zero-order hold otherwise (version 5).
    #[must_use]
    pub fn recorded(self) -> Option<Hold> {
        (self != Hold::UNRECORDED).then_some(self)
    }
}

/// The model file's `[rate]` section: the rate term's c with its standard error (the report's
/// `model.rate`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RateSection {
    /// c (output units · s / input unit).
    pub c: f64,
    /// Its standard error.
    #[serde(default = "nan")]
    pub c_std_error: f64,
}

fn nan() -> f64 {
    f64::NAN
}

/// The size of the augmented matrix of [`Dynamics::discretise`].
const AUG: usize = MAX_DYNAMICS + 2;

/// e^M for the leading `m` × `m` block of `a` (the rest is 0), by scaling and squaring: M is
/// halved s times until its ∞-norm is at most ½, its Taylor series is summed to degree 18
/// (remainder below 2⁻¹⁹ / 19! ≈ 1.6e-23 relative), and the result squared s times.
fn expm<T: Real>(a: &[[T; AUG]; AUG], m: usize) -> [[T; AUG]; AUG] {
    let norm = a
        .iter()
        .take(m)
        .map(|row| row.iter().take(m).map(|x| x.as_f64().abs()).sum::<f64>())
        .fold(0.0, f64::max);
    // s = ⌈log₂(2‖M‖)⌉ halvings bring the norm to ½ (a non-finite norm gives a non-finite
    // result, which the caller refuses).
    let s: i32 = if norm.is_finite() && norm > 0.5 {
        (2.0 * norm).log2().ceil().clamp(0.0, 1100.0) as i32
    } else {
        0
    };
    let scale = T::from_f64(0.5_f64.powi(s));
    let mut x = [[T::zero(); AUG]; AUG];
    for i in 0..m {
        for j in 0..m {
            x[i][j] = a[i][j] * scale;
        }
    }
    // Horner: e^X ≈ I + X (I + X/2 (I + X/3 (… (I + X/18)))).
    let mut e = identity(m);
    for k in (1..=18_usize).rev() {
        let p = mul(&x, &e, m);
        let inv = T::one() / T::from_usize(k);
        e = identity(m);
        for i in 0..m {
            for j in 0..m {
                e[i][j] = e[i][j] + p[i][j] * inv;
            }
        }
    }
    for _ in 0..s {
        e = mul(&e, &e, m);
    }
    e
}

fn identity<T: Real>(m: usize) -> [[T; AUG]; AUG] {
    let mut e = [[T::zero(); AUG]; AUG];
    for (i, row) in e.iter_mut().enumerate().take(m) {
        row[i] = T::one();
    }
    e
}

fn mul<T: Real>(a: &[[T; AUG]; AUG], b: &[[T; AUG]; AUG], m: usize) -> [[T; AUG]; AUG] {
    let mut c = [[T::zero(); AUG]; AUG];
    for i in 0..m {
        for k in 0..m {
            let aik = a[i][k];
            if aik == T::zero() {
                continue;
            }
            for j in 0..m {
                c[i][j] = c[i][j] + aik * b[k][j];
            }
        }
    }
    c
}

/// A plant discretised for one sample period ([`Dynamics::discretise`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Discrete<T = f64> {
    phi: [[T; MAX_DYNAMICS]; MAX_DYNAMICS],
    g0: [T; MAX_DYNAMICS],
    g1: [T; MAX_DYNAMICS],
    b: T,
    order: usize,
}

/// The state of a [`Discrete`] plant between samples: (v, v̇, …, v⁽ⁿ⁻¹⁾) and the last command.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlantState<T = f64> {
    /// (v, v̇, …, v⁽ⁿ⁻¹⁾) at the last sample.
    pub x: [T; MAX_DYNAMICS],
    /// The last command.
    pub u: T,
}

impl<T: Real> Discrete<T> {
    /// The state at rest for the first command `u0`: v = b u0, every derivative 0.
    #[must_use]
    pub fn at_rest(&self, u0: T) -> PlantState<T> {
        let mut x = [T::zero(); MAX_DYNAMICS];
        x[0] = self.b * u0;
        PlantState { x, u: u0 }
    }

    /// Advances `state` to the next sample, whose command is `u`, and returns v there.
    #[inline]
    pub fn step(&self, state: &mut PlantState<T>, u: T) -> T {
        // Over all MAX_DYNAMICS rows and columns, whatever the order: the entries beyond it are
        // 0 (and stay 0 in the state), and fixed bounds let the compiler unroll the loops.
        let du = u - state.u;
        let mut next = [T::zero(); MAX_DYNAMICS];
        for i in 0..MAX_DYNAMICS {
            let mut acc = self.g0[i] * state.u + self.g1[i] * du;
            for j in 0..MAX_DYNAMICS {
                acc = acc + self.phi[i][j] * state.x[j];
            }
            next[i] = acc;
        }
        state.x = next;
        state.u = u;
        next[0]
    }
}

/// A viscous term c·v̇ of the hysteresis input, added to the model output (output units per
/// input unit per second; v̇ is the module's backward difference).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rate<T = f64> {
    /// c (output units · s / input unit).
    pub c: T,
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::indexing_slicing)]
    use super::*;
    use hyst_core::Dual;

    /// First order: a step from rest follows 1 − e^{−t/τ} at the samples (exact for a
    /// command that is constant after its first sample... which the hold makes linear over the
    /// first interval: compare with the closed form of a ramp then a constant).
    #[test]
    fn first_order_matches_the_closed_form() {
        let tau = 0.1;
        let h = 0.01;
        let d = Dynamics::new(1.0, &[tau]).unwrap().discretise(h).unwrap();
        // Ramp input u = t: v(t) = t − τ (1 − e^{−t/τ}).
        let mut s = d.at_rest(0.0);
        for k in 1..=50 {
            let t = f64::from(k) * h;
            let v = d.step(&mut s, t);
            let exact = t - tau * (1.0 - (-t / tau).exp());
            assert!((v - exact).abs() < 1e-14, "{k}: {v} vs {exact}");
        }
    }

    /// Second order: m ẍ + c ẋ + k x = k u (a_2 = m/k, a_1 = c/k) against a fine RK4 run of the
    /// same linearly interpolated command.
    #[test]
    fn second_order_matches_a_fine_integration() {
        let (a1, a2) = (0.9, 1.0 / 4.0);
        let h = 0.05;
        let d = Dynamics::new(2.0, &[a1, a2])
            .unwrap()
            .discretise(h)
            .unwrap();
        let u = |t: f64| (3.0 * t).sin() + 0.5 * (7.0 * t).cos();
        let mut s = d.at_rest(u(0.0));
        let (mut x, mut xd) = (2.0 * u(0.0), 0.0);
        let f = |t0: f64, u0: f64, u1: f64, t: f64, x: f64, xd: f64| {
            let uu = u0 + (u1 - u0) * (t - t0) / h;
            (xd, (2.0 * uu - x - a1 * xd) / a2)
        };
        for k in 0..100 {
            let t0 = f64::from(k) * h;
            let (u0, u1) = (u(t0), u(t0 + h));
            let steps = 2000;
            let dt = h / f64::from(steps);
            for j in 0..steps {
                let t = t0 + f64::from(j) * dt;
                let k1 = f(t0, u0, u1, t, x, xd);
                let k2 = f(
                    t0,
                    u0,
                    u1,
                    t + dt / 2.0,
                    x + dt / 2.0 * k1.0,
                    xd + dt / 2.0 * k1.1,
                );
                let k3 = f(
                    t0,
                    u0,
                    u1,
                    t + dt / 2.0,
                    x + dt / 2.0 * k2.0,
                    xd + dt / 2.0 * k2.1,
                );
                let k4 = f(t0, u0, u1, t + dt, x + dt * k3.0, xd + dt * k3.1);
                x += dt / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
                xd += dt / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
            }
            let v = d.step(&mut s, u1);
            assert!((v - x).abs() < 1e-10, "{k}: {v} vs {x}");
            assert!((s.x[1] - xd).abs() < 1e-9, "{k}: {} vs {xd}", s.x[1]);
        }
    }

    /// Time constants far below the period: v follows b u at once (the static limit), to the
    /// hold's lag τ·du/dt.
    #[test]
    fn fast_plant_is_static() {
        let d = Dynamics::new(1.0, &[1e-8, 1e-17])
            .unwrap()
            .discretise(1e-3)
            .unwrap();
        let mut s = d.at_rest(0.3);
        for u in [0.5_f64, -1.0, 2.0] {
            // The hold's lag τ du/dt: 1e-8 s × 3000 /s.
            let v: f64 = d.step(&mut s, u);
            assert!((v - u).abs() < 5e-5, "{v} vs {u}");
        }
    }

    /// The dual derivative of the discretisation equals a central difference.
    #[test]
    fn discretisation_differentiates_exactly() {
        let run = |a1: Dual<f64, 1>| {
            let d = Dynamics::new(Dual::constant(1.0), &[a1, Dual::constant(0.02)])
                .unwrap()
                .discretise(0.01)
                .unwrap();
            let mut s = d.at_rest(Dual::constant(0.0));
            let mut v = Dual::constant(0.0);
            for k in 1..40 {
                v = d.step(&mut s, Dual::constant((0.3 * f64::from(k)).sin()));
            }
            v
        };
        let g = run(Dual::variable(0.3, 0)).gradient()[0];
        let e = 1e-6;
        let fd = (run(Dual::constant(0.3 + e)).value() - run(Dual::constant(0.3 - e)).value())
            / (2.0 * e);
        assert!((g - fd).abs() < 1e-7, "{g} vs {fd}");
    }

    #[test]
    fn unstable_and_malformed_plants_are_refused() {
        assert!(Dynamics::new(1.0, &[]).is_err());
        assert!(Dynamics::new(1.0, &[1.0; 5]).is_err());
        assert!(Dynamics::new(0.0, &[1.0]).is_err());
        assert!(Dynamics::new(1.0, &[-1.0]).is_err());
        // a_2 a_1 = 1 < a_3 = 2.
        assert!(Dynamics::new(1.0, &[1.0, 1.0, 2.0]).is_err());
        assert!(Dynamics::new(1.0, &[3.0, 3.0, 1.0]).is_ok());
        // (s + 1)^4: a = [4, 6, 4, 1] is stable; a_4 = 10 is not.
        assert!(Dynamics::new(1.0, &[4.0, 6.0, 4.0, 1.0]).is_ok());
        assert!(Dynamics::new(1.0, &[4.0, 6.0, 4.0, 10.0]).is_err());
    }

    /// The zero-order hold of a first-order plant is the closed form
    /// v_{k+1} = e^{−h/τ} v_k + (1 − e^{−h/τ}) u_k, for any h.
    #[test]
    fn zero_order_hold_matches_the_closed_form() {
        let tau = 0.1;
        let plant = Dynamics::new(1.0, &[tau]).unwrap().with_hold(Hold::Zoh);
        let u = |k: usize| (0.7 * k as f64).sin() + 0.3;
        for h in [1e-4, 0.01, 0.1, 0.37, 5.0] {
            let d = plant.discretise(h).unwrap();
            let e = (-h / tau).exp();
            let mut s = d.at_rest(u(0));
            let mut exact = u(0);
            for k in 1..60 {
                exact = e * exact + (1.0 - e) * u(k - 1);
                let v = d.step(&mut s, u(k));
                assert!((v - exact).abs() < 1e-14, "h = {h}, {k}: {v} vs {exact}");
            }
        }
    }

    /// A second-order plant under the zero-order hold against a fine RK4 run of the held
    /// command; the hold is part of the file's section, which writes it only when it is not
    /// the first-order hold.
    #[test]
    fn zero_order_hold_matches_a_fine_integration() {
        let (a1, a2, h) = (0.9, 0.25, 0.05);
        let d = Dynamics::new(2.0, &[a1, a2])
            .unwrap()
            .with_hold(Hold::Zoh)
            .discretise(h)
            .unwrap();
        let u = |t: f64| (3.0 * t).sin() + 0.5 * (7.0 * t).cos();
        let mut s = d.at_rest(u(0.0));
        let (mut x, mut xd) = (2.0 * u(0.0), 0.0);
        for k in 0..100 {
            let held = u(f64::from(k) * h);
            let f = |x: f64, xd: f64| (xd, (2.0 * held - x - a1 * xd) / a2);
            let steps = 2000;
            let dt = h / f64::from(steps);
            for _ in 0..steps {
                let k1 = f(x, xd);
                let k2 = f(x + dt / 2.0 * k1.0, xd + dt / 2.0 * k1.1);
                let k3 = f(x + dt / 2.0 * k2.0, xd + dt / 2.0 * k2.1);
                let k4 = f(x + dt * k3.0, xd + dt * k3.1);
                x += dt / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
                xd += dt / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
            }
            let v = d.step(&mut s, u(f64::from(k + 1) * h));
            assert!((v - x).abs() < 1e-10, "{k}: {v} vs {x}");
            assert!((s.x[1] - xd).abs() < 1e-9, "{k}: {} vs {xd}", s.x[1]);
        }
    }

    #[test]
    fn the_hold_reads_and_writes() {
        let text = "b = 1.0\na = [0.1]\nhold = \"zoh\"\n";
        let section: DynamicsSection = toml::from_str(text).unwrap();
        assert_eq!(section.dynamics().unwrap().hold(), Hold::Zoh);
        let old: DynamicsSection = toml::from_str("b = 1.0\na = [0.1]\n").unwrap();
        assert_eq!(old.dynamics().unwrap().hold(), Hold::Foh);
        assert!(toml::from_str::<DynamicsSection>("b = 1.0\na = [0.1]\nhold = \"x\"").is_err());
        assert_eq!(Hold::Foh.recorded(), None);
        assert_eq!(Hold::Zoh.recorded(), Some(Hold::Zoh));
        assert_eq!(Hold::parse("zoh", false), Ok(Hold::Zoh));
        assert_eq!(Hold::Foh.name(), "foh");
    }

    #[test]
    fn file_section_checks_its_plant() {
        let section = |a: Vec<f64>, se: Vec<f64>| DynamicsSection {
            b: 1.0,
            a,
            a_std_error: se,
            identified: Vec::new(),
            hold: None,
        };
        assert!(section(vec![0.1, 0.002], vec![]).dynamics().is_ok());
        assert!(section(vec![0.1, 0.002], vec![0.01]).dynamics().is_err());
        assert!(section(vec![-0.1], vec![]).dynamics().is_err());
        let text = toml::to_string(&section(vec![0.1], vec![0.01])).unwrap();
        assert!(text.contains("a = [0.1]"), "{text}");
        assert!(toml::from_str::<DynamicsSection>("b = 1.0\na = [0.1]\nc = 2").is_err());
    }
}
