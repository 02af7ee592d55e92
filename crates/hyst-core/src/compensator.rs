//! Feed-forward compensation of hysteresis preceded by linear dynamics (Lemma 5.1).
//!
//! The plant is x1(s) / u(s) = b / (a_n sⁿ + … + a_1 s + 1) (eq. 18) followed by the hysteresis
//! x2 = Hyst(x1), modelled as ψ_out(H(k1, k2)[ψ_in(x1)]). The compensator integrates the new
//! input n times, v⁽ⁿ⁾ = u_new, evaluates the exact inverse model on the jet (v, v̇, …, v⁽ⁿ⁾) —
//! which gives x = ψ_in⁻¹(H⁻¹[ψ_out⁻¹(v)]) and its first n time derivatives by Taylor arithmetic
//! — and outputs eq. (19):
//!
//! u = (1/b) (x + a_1 ẋ + … + a_n x⁽ⁿ⁾).
//!
//! With the exact model the plant then follows x1 = x and x2 = v: n pure integrators from u_new to
//! x2 (eq. 20 with Δ = 0). With a hysteresis that is only reproducible by a family, the error
//! stays within the family's Δa (Propositions 3.2, 3.3).
//!
//! No allocation, no panics, `f32` or `f64`, `no_std`; one [`Compensator::step`] per sample.

use crate::error::Error;
use crate::jet::Jet;
use crate::k2law::{ConstantK2, K2Law};
use crate::memory::Memory;
use crate::operator::Operator;
use crate::real::Real;
use crate::shaped_model::{InverseShapedModel, ShapedModel};
use crate::shaping::{Identity, Shaping};

/// The highest plant order n (Lemma 5.1) and the highest time-derivative order that hyst's
/// bindings and tools take: the C API (`HYST_MAX_ORDER`), Python (`hyst.MAX_ORDER`), `hyst run
/// --derivatives`. It covers the plants of the paper's examples (n ≤ 2) and the model files'
/// dynamics (n ≤ 4), and sizes the jets of the firmware's compensator state. Rust code chooses
/// any `N` itself.
pub const MAX_ORDER: usize = 4;

/// The Lemma 5.1 compensator for a plant of order n ≤ `N` (the paper's Example 2 has n = 1,
/// Example 3 has n = 2). [`Compensator::from_shaped_model`] and [`Compensator::new`] take n = N;
/// [`Compensator::with_order`] takes any n ≤ N chosen at run time, with the same results for
/// the first n derivatives (jets carry N, the derivatives above n of v are 0), so one type
/// serves every order up to N (the bindings use N = [`MAX_ORDER`]).
///
/// # Examples
/// Example 3's compensator, F = Ḧ⁻¹ + 0.9 Ḣ⁻¹ + H⁻¹ for m ẍ = F − 0.9 ẋ − x:
/// ```
/// use hyst_core::{compensator::Compensator, Hysteresis, Identity, ShapedModel, Operator};
/// let model = ShapedModel::new(Identity, Hysteresis::new(0.2_f64, 8.0)?, Identity)?;
/// let mut comp = Compensator::from_shaped_model(&model, 1.0, [0.9, 1.0])?;
/// // Start at rest at v = 0: F = H⁻¹ + 0.9 Ḣ⁻¹ + Ḧ⁻¹ = 0 + 0 + (dH⁻¹/dv) v̈. On the line
/// // (first sample) dH⁻¹/dv = 1 + k1 k2 = 2.6 (eq. 4 at ũd = 0), so u_new = v̈ = 0.5 gives 1.3.
/// let force = comp.step(0.5, 1e-3);
/// assert!((force - 1.3).abs() < 1e-12);
/// // After 1 ms of v̈ = 0.5: v = 0.25e-6, v̇ = 0.5e-3, exactly (the integrators are exact).
/// let [v, v_dot] = comp.state();
/// assert!((v - 0.25e-6).abs() < 1e-18 && (v_dot - 0.5e-3).abs() < 1e-15);
/// // The compensated plant output is v: the model driven by the target x gives v back.
/// let mut plant = model;
/// assert!((plant.step(comp.last_target().value()) - comp.last_reference()).abs() < 1e-15);
/// # Ok::<(), hyst_core::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Compensator<T, const N: usize, I = Identity, K = ConstantK2<T>, O = Identity> {
    inverse: InverseShapedModel<T, I, K, O>,
    b: T,
    a: [T; N],
    order: usize,
    v: [T; N],
    initial_v: [T; N],
    last_command: T,
    last_reference: T,
    last_target: Jet<T, N>,
}

/// Everything a [`Compensator`] changes as it steps, as plain data: read it with
/// [`Compensator::saved_state`] and give it back (to the same compensator or to one built with
/// the same model, b and a) with [`Compensator::restore_state`], and the compensator goes on
/// bit for bit as the one it was read from. A controller that restarts, a simulator that
/// keeps the state outside (python-control's state vector) or a firmware that stores it in
/// its own memory use it. `Copy`, no allocation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompensatorState<T, const N: usize> {
    /// The integrator chain (v, v̇, …, v⁽ⁿ⁻¹⁾) (Lemma 5.1: v⁽ⁿ⁾ = u_new), in output units and
    /// their time derivatives (units/sⁱ); entries from n on are 0.
    pub integrators: [T; N],
    /// The inverse model's memory (Definition 2.1, of H⁻¹ in operator units: inputs
    /// ψ_out⁻¹(v), outputs ψ_in of the target); `None` before any history.
    pub memory: Option<Memory<T>>,
    /// The command u of the last sample (eq. 19): what [`Compensator::step`] holds on a
    /// refused sample.
    pub last_command: T,
    /// The reference v of the last sample.
    pub last_reference: T,
    /// The target x1 and its n time derivatives at the last sample.
    pub last_target: Jet<T, N>,
}

impl<T: Real, const N: usize, I, K, O> Compensator<T, N, I, K, O>
where
    I: Shaping<T> + Clone,
    K: K2Law<T> + Clone,
    O: Shaping<T> + Clone,
{
    /// The compensator of `model` for the plant gain `b` and denominator coefficients
    /// `a = [a_1, …, a_n]` of eq. (18) (the constant term is 1), at rest at v = 0.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] when b is zero or not finite, or a coefficient is not finite.
    pub fn from_shaped_model(
        model: &ShapedModel<T, I, K, O>,
        b: T,
        a: [T; N],
    ) -> Result<Self, Error> {
        Self::new(model.inverse(), b, a)
    }

    /// As [`Compensator::from_shaped_model`], from the inverse model directly.
    ///
    /// # Errors
    /// As [`Compensator::from_shaped_model`].
    pub fn new(inverse: InverseShapedModel<T, I, K, O>, b: T, a: [T; N]) -> Result<Self, Error> {
        Self::with_order(inverse, b, &a)
    }

    /// The compensator of the inverse model `inverse` for a plant of order n = `a.len()` ≤ N,
    /// `a = [a_1, …, a_n]`, at rest at v = 0.
    ///
    /// # Errors
    /// [`Error::LengthMismatch`] when n > N; otherwise as [`Compensator::from_shaped_model`].
    pub fn with_order(
        inverse: InverseShapedModel<T, I, K, O>,
        b: T,
        a: &[T],
    ) -> Result<Self, Error> {
        if a.len() > N {
            return Err(Error::LengthMismatch {
                input: a.len(),
                output: N,
            });
        }
        crate::error::finite("b", b)?;
        if b == T::zero() {
            return Err(Error::InvalidParameter {
                name: "b",
                value: 0.0,
                expected: "non-zero",
            });
        }
        for c in a.iter() {
            crate::error::finite("a_i", *c)?;
        }
        Ok(Self {
            inverse,
            b,
            a: core::array::from_fn(|k| a.get(k).copied().unwrap_or_else(T::zero)),
            order: a.len(),
            v: [T::zero(); N],
            initial_v: [T::zero(); N],
            last_command: T::zero(),
            last_reference: T::zero(),
            last_target: Jet::constant(T::zero()),
        })
    }

    /// Starts the integrator chain at (v, v̇, …, v⁽ⁿ⁻¹⁾) = the first n values of `state` (the
    /// rest are ignored); [`Compensator::reset`] returns here.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a non-finite value among the first n.
    pub fn with_state(mut self, state: [T; N]) -> Result<Self, Error> {
        for x in state.iter().take(self.order) {
            crate::error::finite("integrator state", *x)?;
        }
        let n = self.order;
        let state = core::array::from_fn(|k| {
            if k < n {
                state.get(k).copied().unwrap_or_else(T::zero)
            } else {
                T::zero()
            }
        });
        self.v = state;
        self.initial_v = state;
        Ok(self)
    }

    /// The plant order n (the number of integrators and of coefficients a_i).
    #[must_use]
    pub fn order(&self) -> usize {
        self.order
    }

    /// The integrator chain (v, v̇, …, v⁽ⁿ⁻¹⁾) at the current time (entries from n on are 0).
    #[must_use]
    pub fn state(&self) -> [T; N] {
        self.v
    }

    /// The inverse model (with its memory).
    #[must_use]
    pub fn inverse(&self) -> &InverseShapedModel<T, I, K, O> {
        &self.inverse
    }

    /// v at the last evaluated sample: the output x2 the compensated plant should show.
    #[must_use]
    pub fn last_reference(&self) -> T {
        self.last_reference
    }

    /// x = ψ_in⁻¹(H⁻¹[ψ_out⁻¹(v)]) and its n time derivatives at the last evaluated sample: the
    /// plant state x1 the command drives it to.
    #[must_use]
    pub fn last_target(&self) -> Jet<T, N> {
        self.last_target
    }

    /// The last command returned.
    #[must_use]
    pub fn last_command(&self) -> T {
        self.last_command
    }

    /// The jet (v, v̇, …, v⁽ⁿ⁾, 0, …) of the state `v` of a chain of `n` integrators with
    /// v⁽ⁿ⁾ = `u_new`. For n = 0 there is no integrator: v = u_new itself.
    fn jet_of(n: usize, v: &[T; N], u_new: T) -> Jet<T, N> {
        let value = if n == 0 {
            u_new
        } else {
            v.first().copied().unwrap_or_else(T::zero)
        };
        let d: [T; N] = core::array::from_fn(|i| {
            if i + 1 < n {
                v.get(i + 1).copied().unwrap_or_else(T::zero)
            } else if i + 1 == n {
                u_new
            } else {
                T::zero()
            }
        });
        Jet::from_derivatives(value, d)
    }

    /// Eq. (19) on a jet x of the plant input target: (1/b)(x + Σ a_i x⁽ⁱ⁾).
    fn law(&self, x: &Jet<T, N>) -> T {
        let mut u = x.value();
        for (a, d) in self.a.iter().zip(x.derivatives().iter()).take(self.order) {
            u = u + *a * *d;
        }
        u / self.b
    }

    /// The chain of `n` integrators advanced by `dt` with v⁽ⁿ⁾ = `u_new` held constant (exact);
    /// entries from n on stay 0.
    ///
    /// v^(k)(t + dt) = Σ_{j=0}^{n−1−k} v^(k+j) dt^j / j! + u_new dt^(n−k) / (n−k)!, with the
    /// factors dt^j / j! formed once (as the same running products, so the sums are the same
    /// numbers as forming them anew for every k). Plain loops: on the Cortex-M4F the
    /// `core::array::from_fn` form compiled to a 3.7 kB function, this one to a fraction of that
    /// (the firmware size probe of scripts/test-firmware).
    fn advanced(n: usize, v: &[T; N], u_new: T, dt: T) -> [T; N] {
        // powers[j] = dt^j / j! for j < N; `last` = dt^N / N!.
        let mut powers = [T::one(); N];
        let mut last = T::one();
        for (j, p) in powers.iter_mut().enumerate() {
            *p = last;
            last = last * dt / T::from_usize(j + 1);
        }
        let power = |j: usize| powers.get(j).copied().unwrap_or(last);
        let mut out = [T::zero(); N];
        for (k, slot) in out.iter_mut().enumerate().take(n) {
            let mut sum = T::zero();
            for j in 0..(n - k) {
                sum = sum + v.get(k + j).copied().unwrap_or_else(T::zero) * power(j);
            }
            *slot = sum + u_new * power(n - k);
        }
        out
    }

    /// One sample: evaluates the command u(t) for the current state with v⁽ⁿ⁾ = `u_new`, then
    /// advances the integrators to t + `dt`.
    ///
    /// # Errors
    /// [`Error::NonFiniteInput`] for a non-finite `u_new` or `dt` (or dt < 0), the inverse
    /// model's errors (a reference outside the range of a saturating shaping function), and
    /// [`Error::NonFiniteOutput`] when the command of eq. (19) or the integrator state overflows.
    /// The compensator is then unchanged.
    pub fn try_step(&mut self, u_new: T, dt: T) -> Result<T, Error> {
        if !(u_new.is_finite() && dt.is_finite() && dt >= T::zero()) {
            let bad = if u_new.is_finite() { dt } else { u_new };
            return Err(Error::NonFiniteInput {
                value: bad.as_f64(),
            });
        }
        let n = self.order;
        let jet = Self::jet_of(n, &self.v, u_new);
        let before = self.inverse.memory();
        let x = self.inverse.try_step(jet)?;
        let u = self.law(&x);
        let next = Self::advanced(n, &self.v, u_new, dt);
        if !(u.is_finite() && next.iter().all(|v| v.is_finite())) {
            // Eq. (19) or the integrators overflow: refuse, state unchanged.
            self.inverse.restore(before);
            return Err(Error::NonFiniteOutput {
                input: u_new.as_f64(),
                output: u.as_f64(),
            });
        }
        self.last_command = u;
        self.last_reference = jet.value();
        self.last_target = x;
        // A turning point of v inside the sample becomes the reversal point exactly there.
        Self::pass_turning_points(n, &mut self.inverse, &self.v, u_new, dt);
        self.v = next;
        Ok(u)
    }

    /// The first time τ in (from, to] where v̇ has changed sign (v̇ is a polynomial of degree
    /// n − 1 in τ while u_new is held), by a scan of 16 sub-intervals and bisection; the point
    /// returned is the first one, to rounding, on the new side of the extremum.
    fn turning_point_between(n: usize, v: &[T; N], u_new: T, from: T, to: T) -> Option<T> {
        if n < 2 || to.partial_cmp(&from) != Some(core::cmp::Ordering::Greater) {
            return None;
        }
        let rate = |tau: T| {
            Self::advanced(n, v, u_new, tau)
                .get(1)
                .copied()
                .unwrap_or_else(T::zero)
        };
        let r0 = rate(from);
        if r0 == T::zero() {
            return None;
        }
        const SCAN: usize = 16;
        let mut lo = from;
        for i in 1..=SCAN {
            let hi = from + (to - from) * (T::from_usize(i) / T::from_usize(SCAN));
            let r = rate(hi);
            if r * r0 < T::zero() {
                let mut a = lo;
                let mut b = hi;
                for _ in 0..64 {
                    let mid = (a + b) / T::from_f64(2.0);
                    if mid <= a || mid >= b {
                        break;
                    }
                    if rate(mid) * r0 > T::zero() {
                        a = mid;
                    } else {
                        b = mid;
                    }
                }
                let _ = a;
                return Some(b);
            }
            lo = hi;
        }
        None
    }

    /// Commits to `inverse` the turning points of v in (0, `until`) (at most 4 per sample), so
    /// that the reversal point of Definition 2.1 is the true extremum of v and not the sample
    /// after it.
    fn pass_turning_points(
        n: usize,
        inverse: &mut InverseShapedModel<T, I, K, O>,
        v: &[T; N],
        u_new: T,
        until: T,
    ) {
        let mut from = T::zero();
        for _ in 0..4 {
            match Self::turning_point_between(n, v, u_new, from, until) {
                Some(tau) => {
                    let state = Self::advanced(n, v, u_new, tau);
                    let at = Self::jet_of(n, &state, u_new);
                    // Evaluate at the extremum without its derivatives, so the direction rule
                    // sees a continuation of the current run.
                    let _ = inverse.try_step(Jet::<T, N>::constant(at.value()));
                    if tau <= from {
                        break;
                    }
                    from = tau + (until - tau) * T::from_f64(1e-9);
                }
                None => break,
            }
        }
    }

    /// One sample; on error (see [`Compensator::try_step`]) the last command is held and the
    /// state is unchanged.
    pub fn step(&mut self, u_new: T, dt: T) -> T {
        self.try_step(u_new, dt).unwrap_or(self.last_command)
    }

    /// The first turning point of v (v̇ = 0 with a change of sign) inside the coming sample of
    /// length `dt` with `u_new` held, as a time offset τ ∈ (0, dt] (only for n ≥ 2: for n ≤ 1
    /// v̇ is constant within a sample). The operator's reversal happens there; a simulator
    /// should split its integration step at τ, because the command's n-th derivative term
    /// jumps (Proposition 2.7: second and higher derivatives are discontinuous at reversals).
    #[must_use]
    pub fn turning_point(&self, u_new: T, dt: T) -> Option<T> {
        Self::turning_point_between(self.order, &self.v, u_new, T::zero(), dt)
    }

    /// The command at t + `tau` (0 ≤ tau ≤ the sample time) if `u_new` is held, without changing
    /// anything: for integrating a continuous plant between samples (the stages of a Runge–Kutta
    /// step).
    ///
    /// # Errors
    /// As [`Compensator::try_step`].
    pub fn peek(&self, u_new: T, tau: T) -> Result<T, Error> {
        if !(u_new.is_finite() && tau.is_finite()) {
            return Err(Error::NonFiniteInput {
                value: u_new.as_f64(),
            });
        }
        let n = self.order;
        let v = Self::advanced(n, &self.v, u_new, tau);
        let mut inverse = self.inverse.clone();
        Self::pass_turning_points(n, &mut inverse, &self.v, u_new, tau);
        let x = inverse.try_step(Self::jet_of(n, &v, u_new))?;
        let u = self.law(&x);
        if !u.is_finite() {
            return Err(Error::NonFiniteOutput {
                input: u_new.as_f64(),
                output: u.as_f64(),
            });
        }
        Ok(u)
    }

    /// Reference-trajectory mode: the command for a given reference v and its first n time
    /// derivatives (in a jet), bypassing the integrator chain (whose state is set to the
    /// reference's so that integrator mode can continue from here).
    ///
    /// # Errors
    /// As [`Compensator::try_step`].
    pub fn track(&mut self, reference: Jet<T, N>) -> Result<T, Error> {
        let before = self.inverse.memory();
        let x = self.inverse.try_step(reference)?;
        let u = self.law(&x);
        if !u.is_finite() {
            self.inverse.restore(before);
            return Err(Error::NonFiniteOutput {
                input: reference.value().as_f64(),
                output: u.as_f64(),
            });
        }
        let d = reference.derivatives();
        let n = self.order;
        self.v = core::array::from_fn(|k| {
            if k >= n {
                T::zero()
            } else if k == 0 {
                reference.value()
            } else {
                d.get(k - 1).copied().unwrap_or_else(T::zero)
            }
        });
        self.last_command = u;
        self.last_reference = reference.value();
        self.last_target = x;
        Ok(u)
    }

    /// The whole state: integrators, the inverse model's memory and the last sample's values
    /// ([`CompensatorState`]).
    #[must_use]
    pub fn saved_state(&self) -> CompensatorState<T, N> {
        CompensatorState {
            integrators: self.v,
            memory: self.inverse.memory(),
            last_command: self.last_command,
            last_reference: self.last_reference,
            last_target: self.last_target,
        }
    }

    /// Puts back a whole state read by [`Compensator::saved_state`] (of this compensator or of
    /// one with the same model, b and a): the next [`Compensator::step`] is the one that
    /// followed the state when it was read, bit for bit. Integrator entries from n on are
    /// ignored (set to 0). [`Compensator::reset`] still returns to the start state.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the field for a non-finite value (among the first n
    /// integrators, the last command, reference or target), and the inverse model's refusal of
    /// the memory (a non-finite value, a memory outside the band |output − input| ≤ k1); the
    /// compensator is then unchanged.
    pub fn restore_state(&mut self, state: &CompensatorState<T, N>) -> Result<(), Error> {
        for x in state.integrators.iter().take(self.order) {
            crate::error::finite("integrator state", *x)?;
        }
        crate::error::finite("last_command", state.last_command)?;
        crate::error::finite("last_reference", state.last_reference)?;
        crate::error::finite("last_target", state.last_target.value())?;
        for d in state.last_target.derivatives().iter() {
            crate::error::finite("last_target", *d)?;
        }
        let mut inverse = self.inverse.clone();
        inverse.set_memory(state.memory)?;
        let n = self.order;
        self.inverse = inverse;
        self.v = core::array::from_fn(|k| {
            if k < n {
                state.integrators.get(k).copied().unwrap_or_else(T::zero)
            } else {
                T::zero()
            }
        });
        self.last_command = state.last_command;
        self.last_reference = state.last_reference;
        self.last_target = state.last_target;
        Ok(())
    }

    /// Back to the initial integrator state, and the inverse model's memory forgotten.
    pub fn reset(&mut self) {
        self.v = self.initial_v;
        self.inverse.reset();
        self.last_command = T::zero();
        self.last_reference = T::zero();
        self.last_target = Jet::constant(T::zero());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parametric::Hysteresis;
    use crate::shaping::Identity;

    #[test]
    fn integrator_chain_is_exact_for_polynomials() -> Result<(), Error> {
        let model = ShapedModel::new(Identity, Hysteresis::new(0.2_f64, 8.0)?, Identity)?;
        let mut c = Compensator::from_shaped_model(&model, 1.0, [0.0, 0.0, 0.0])?;
        // v''' = 6 from rest: v = t³, v' = 3t², v'' = 6t.
        for _ in 0..10 {
            let _ = c.try_step(6.0, 0.1)?;
        }
        let [v, v1, v2] = c.state();
        assert!((v - 1.0).abs() < 1e-12 && (v1 - 3.0).abs() < 1e-12 && (v2 - 6.0).abs() < 1e-12);
        Ok(())
    }

    #[test]
    fn static_case_is_the_inverse_model() -> Result<(), Error> {
        let model = ShapedModel::new(Identity, Hysteresis::new(0.2_f64, 8.0)?, Identity)?;
        let mut c = Compensator::from_shaped_model(&model, 2.0, [])?;
        let mut inv = model.inverse();
        for k in 0..50 {
            let r = (k as f64 * 0.2).sin();
            let u = c.track(Jet::constant(r))?;
            assert!((u - inv.step(r) / 2.0).abs() < 1e-15);
        }
        Ok(())
    }

    #[test]
    fn a_run_time_order_equals_the_const_order() -> Result<(), Error> {
        // Compensator<_, 4> with n = 1 or 2 chosen at run time gives the const-order results bit
        // for bit (jets of order 4 whose derivatives above n are 0 leave the first n unchanged).
        let model = ShapedModel::new(Identity, Hysteresis::new(0.2_f64, 8.0)?, Identity)?;
        let mut c2 =
            Compensator::from_shaped_model(&model, 1.5, [0.9, 1.0])?.with_state([0.1, 0.0])?;
        let mut c4 = Compensator::<f64, 4>::with_order(model.inverse(), 1.5, &[0.9, 1.0])?
            .with_state([0.1, 0.0, 7.0, 7.0])?;
        let mut c1 = Compensator::from_shaped_model(&model, 1.5, [0.9])?;
        let mut c4_1 = Compensator::<f64, 4>::with_order(model.inverse(), 1.5, &[0.9])?;
        assert_eq!((c4.order(), c4_1.order()), (2, 1));
        assert_eq!(c4.state(), [0.1, 0.0, 0.0, 0.0]); // entries from n on are ignored
        for k in 0..4000 {
            let u_new = 3.0 * (k as f64 * 0.003).sin() + (k as f64 * 0.021).cos();
            let (a, b) = (c2.try_step(u_new, 1e-3)?, c4.try_step(u_new, 1e-3)?);
            assert_eq!(a.to_bits(), b.to_bits(), "n = 2, sample {k}");
            let (a, b) = (c1.try_step(u_new, 1e-3)?, c4_1.try_step(u_new, 1e-3)?);
            assert_eq!(a.to_bits(), b.to_bits(), "n = 1, sample {k}");
        }
        assert_eq!(&c4.state()[..2], &c2.state()[..]);
        assert!(matches!(
            Compensator::<f64, 2>::with_order(model.inverse(), 1.0, &[1.0, 2.0, 3.0]),
            Err(Error::LengthMismatch {
                input: 3,
                output: 2
            })
        ));
        Ok(())
    }

    #[test]
    fn order_zero_is_the_static_inverse_of_u_new() -> Result<(), Error> {
        // n = 0: no integrator, v = u_new, u = H⁻¹[v] / b, through step() as well as track().
        let model = ShapedModel::new(Identity, Hysteresis::new(0.2_f64, 8.0)?, Identity)?;
        let mut c = Compensator::from_shaped_model(&model, 2.0, [])?;
        let mut inv = model.inverse();
        for k in 0..50 {
            let r = 0.7 * (k as f64 * 0.2).sin() + 0.1;
            let u = c.try_step(r, 1e-3)?;
            let expected = inv.step(r) / 2.0;
            assert!((u - expected).abs() < 1e-15, "{k}: {u} vs {expected}");
            assert_eq!(c.last_reference(), r);
        }
        Ok(())
    }

    #[test]
    fn a_restored_state_goes_on_bit_for_bit() -> Result<(), Error> {
        // Read mid-run (after reversals of v), given to a fresh compensator of the same model,
        // b and a: both then give the same commands, bit for bit; f32 as f64.
        fn run<T: Real>() -> Result<(), Error> {
            let model = ShapedModel::new(
                Identity,
                Hysteresis::new(T::from_f64(0.2), T::from_f64(8.0))?,
                Identity,
            )?;
            let a = [T::from_f64(0.9), T::from_f64(1.0)];
            let mut c = Compensator::from_shaped_model(&model, T::from_f64(1.5), a)?;
            let u_new = |k: usize| T::from_f64(30.0 * (k as f64 * 0.01).sin());
            for k in 0..700 {
                let _ = c.try_step(u_new(k), T::from_f64(1e-2))?;
            }
            let saved = c.saved_state();
            assert!(saved.memory.is_some());
            let mut d = Compensator::from_shaped_model(&model, T::from_f64(1.5), a)?;
            assert_ne!(d.saved_state(), saved);
            d.restore_state(&saved)?;
            assert_eq!(d.saved_state(), saved);
            assert_eq!(d.last_command(), c.last_command());
            for k in 700..1400 {
                let (x, y) = (
                    c.try_step(u_new(k), T::from_f64(1e-2))?,
                    d.try_step(u_new(k), T::from_f64(1e-2))?,
                );
                assert_eq!(x.as_f64().to_bits(), y.as_f64().to_bits(), "sample {k}");
            }
            // A bad state is refused, naming it, and changes nothing.
            let before = d.saved_state();
            let mut bad = before;
            bad.integrators[1] = T::nan();
            assert!(matches!(
                d.restore_state(&bad),
                Err(Error::InvalidParameter {
                    name: "integrator state",
                    ..
                })
            ));
            let mut bad = before;
            if let Some(m) = bad.memory.as_mut() {
                m.last_output = m.last_input + T::from_f64(5.0); // outside the band (k1 = 0.2)
            }
            assert!(d.restore_state(&bad).is_err());
            assert_eq!(d.saved_state(), before);
            Ok(())
        }
        run::<f64>()?;
        run::<f32>()
    }

    #[test]
    fn bad_input_leaves_state_alone() -> Result<(), Error> {
        let model = ShapedModel::new(Identity, Hysteresis::new(0.2_f32, 8.0)?, Identity)?;
        let mut c = Compensator::from_shaped_model(&model, 1.0, [0.1])?;
        let u = c.step(1.0, 0.01);
        let s = c.state();
        assert!(c.try_step(f32::NAN, 0.01).is_err());
        assert_eq!(c.step(f32::INFINITY, 0.01), u);
        assert_eq!(c.state(), s);
        assert!(Compensator::from_shaped_model(&model, 0.0, [0.1]).is_err());
        Ok(())
    }
}
