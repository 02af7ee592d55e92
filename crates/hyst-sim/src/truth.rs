//! The "true" hysteresis inside a simulated plant (the paper's Hyst(x1) of eq. 18), beside the
//! operators of `hyst_core` that serve as truths as they are:
//!
//! - [`Drifting`]: a member of a family RH(k1, Δk1, k2, Δk2) (Definition 2.8) whose parameters
//!   drift inside the family from sample to sample — the synthetic truth of Examples 1 and 2;
//! - [`Preisach`]: a discrete Preisach model, a truth with a structure different from the
//!   paper's operator; [`forc_input`] gives the first-order reversal curve input it is measured
//!   with (Fig. 3).
//!
//! Every truth is a [`hyst_core::Operator`]`<f64>`, like the exact model
//! ([`hyst_core::ShapedModel`]), a fitted model and the hard backlash ([`hyst_core::Play`], Example 3)
//! that the simulator also takes as truths.

use hyst_core::{ConstantK2, Error, Family, K2Law, Memory, Operator, Sample, Shaping};

use crate::error::{finite, positive, SimError};

/// The memory of a [`Drifting`] truth ([`Operator::memory`]): the operator's memory and the
/// number of evaluations so far.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DriftingMemory {
    /// The memory of Definition 2.1 on the operator's input and output (after ψ_in, before
    /// ψ_out); `None` before the first sample.
    pub operator: Option<Memory<f64>>,
    /// The number of accepted evaluations: the sample index the drift sees next.
    pub evaluations: usize,
}

/// A family member whose parameters drift inside the family RH(k1, Δk1, k2, Δk2)
/// (Definition 2.8, eq. 9), wrapped in input and output shaping: y = ψ_out(H(k̄1, k̄2)[ψ_in(x)]).
///
/// At each evaluation `drift(index, v)` gives the member's position (a, b) ∈ [−1, 1]² in the
/// family (values outside are clamped) from the evaluation index and the operator input
/// v = ψ_in(x), and the member is [`Family::member`]`(a, b)`: k̄1 = k1 + a Δk1 and
/// k̄2 = φ(v) + b Δk2 (φ the family's nominal k2 law, a constant for [`Family::new`]). So k̄2
/// can depend on the input, as in Example 2 (higher near zero magnetisation, lower near
/// saturation). The memory is carried over from one member to the next, clamped into the band
/// |output − input| ≤ k̄1 of the new member. Propositions 3.2–3.3 bound the distance from the
/// nominal model by Δa (eqs. 12–13).
///
/// `index` counts every accepted evaluation: [`Operator::step`] and [`Operator::try_step`]
/// alike, including the extra evaluations at turning points that
/// [`simulate_compensated`](crate::simulate_compensated) makes between samples (for n ≥ 2).
/// The paper's examples never pass turning points to a `Drifting` truth (Example 1 steps it
/// directly, Example 2 has n = 1), so there the index is the sample index.
///
/// With a [`hyst_core::Jet`] input the output's derivatives are those of the member of that
/// evaluation, (a, b) held fixed: the drift is treated as constant over the sample.
///
/// # Examples
/// ```
/// use hyst_core::{Family, Identity, Operator};
/// use hyst_sim::Drifting;
/// // Example 2's family, k̄1 at its lower corner, k̄2 at its upper corner: H(0.055, 7.5).
/// let family = Family::new(0.06, 0.005, 5.0, 2.5)?;
/// let mut truth = Drifting::new(Identity, Identity, family, |_k: usize, _v: f64| (-1.0, 1.0));
/// let _ = truth.step(-1.0);
/// let y = truth.step(1.0); // far up the ascending branch: y → x − k̄1
/// assert!((y - (1.0 - 0.055)).abs() < 1e-6);
/// let (k1, k2) = truth.last_params();
/// assert!((k1 - 0.055).abs() < 1e-15 && k2 == 7.5);
/// # Ok::<(), hyst_core::Error>(())
/// ```
#[derive(Clone, Debug)]
pub struct Drifting<I, O, F, K = ConstantK2<f64>> {
    input: I,
    output: O,
    family: Family<f64, K>,
    drift: F,
    memory: DriftingMemory,
    last_params: (f64, f64),
}

impl<I, O, F, K> Drifting<I, O, F, K>
where
    I: Shaping<f64>,
    O: Shaping<f64>,
    F: FnMut(usize, f64) -> (f64, f64),
    K: K2Law<f64> + Clone,
{
    /// A drifting member of `family` (k1 in the units of the operator input, k2 in their
    /// inverse) between the input shaping ψ_in and the output shaping ψ_out, with no history.
    /// `drift(index, v)` → (a, b): the member's position at the evaluation `index` (0, 1, …)
    /// for the operator input v = ψ_in(x). The family has checked its parameters (every member
    /// has k̄1 > 0), so this cannot fail.
    #[must_use]
    pub fn new(input: I, output: O, family: Family<f64, K>, drift: F) -> Self {
        Self {
            input,
            output,
            last_params: (family.k1(), f64::NAN),
            family,
            drift,
            memory: DriftingMemory::default(),
        }
    }

    /// The family the member drifts in.
    #[must_use]
    pub fn family(&self) -> &Family<f64, K> {
        &self.family
    }

    /// The (k̄1, k̄2) of the last accepted evaluation ((k1, NaN) before the first); k̄1 in the
    /// units of the operator input, k̄2 in their inverse.
    #[must_use]
    pub fn last_params(&self) -> (f64, f64) {
        self.last_params
    }
}

impl<I, O, F, K> Operator<f64> for Drifting<I, O, F, K>
where
    I: Shaping<f64>,
    O: Shaping<f64>,
    F: FnMut(usize, f64) -> (f64, f64),
    K: K2Law<f64> + Clone,
{
    type Memory = DriftingMemory;

    /// One evaluation: v = ψ_in(x), (a, b) = drift(index, v), the member
    /// [`Family::member`]`(a, b)` started from the carried-over memory, y = ψ_out(H̄\[v\]).
    ///
    /// # Errors
    /// [`Error::NonFiniteInput`] for a non-finite sample (before the drift is asked),
    /// [`Error::InvalidParameter`] for a non-finite position (a, b) from the drift,
    /// [`Error::InvalidK2`] when the law's k̄2 at v is not > 0, and the memory's own check
    /// ([`Memory::validate`]). The memory and the index are then unchanged.
    fn try_step<S: Sample<f64>>(&mut self, x: S) -> Result<S, Error> {
        if !x.all_finite() {
            return Err(Error::NonFiniteInput { value: x.value() });
        }
        let v = self.input.apply(x);
        let (a, b) = (self.drift)(self.memory.evaluations, v.value());
        let mut member = self.family.member(a, b)?;
        let k1 = member.k1();
        if let Some(mut m) = self.memory.operator {
            let clamp = |inp: f64, out: f64| out.max(inp - k1).min(inp + k1);
            m.reversal_output = clamp(m.reversal_input, m.reversal_output);
            m.last_output = clamp(m.last_input, m.last_output);
            member.set_memory(Some(m))?;
        }
        let u = member.try_step(v)?;
        self.last_params = (k1, member.k2_law().k2(v.value()));
        self.memory = DriftingMemory {
            operator: member.memory(),
            evaluations: self.memory.evaluations + 1,
        };
        Ok(self.output.apply(u))
    }

    fn last_output(&self) -> Option<f64> {
        self.memory
            .operator
            .map(|m| self.output.apply(m.last_output))
    }

    /// Back to no history and evaluation index 0.
    fn reset(&mut self) {
        self.memory = DriftingMemory::default();
        self.last_params = (self.family.k1(), f64::NAN);
    }

    fn memory(&self) -> DriftingMemory {
        self.memory
    }

    /// # Errors
    /// As [`Memory::validate`] with the widest member's k̄1 = k1 + Δk1 (the next evaluation
    /// clamps the memory into its member's band); the truth is then unchanged.
    fn set_memory(&mut self, memory: DriftingMemory) -> Result<(), Error> {
        if let Some(m) = &memory.operator {
            m.validate(self.family.k1() + self.family.dk1())?;
        }
        self.memory = memory;
        Ok(())
    }
}

/// A discrete Preisach model (a truth with a different structure from the paper's operator):
/// relays on a triangular grid α ≥ β over [lo, hi] with weights μ(α, β) h² (h the grid
/// spacing); output = Σ μ γ̂αβ\[x\] with relays ±1, all at −1 initially (negative saturation).
/// Input in the units of lo and hi; output in the units of μ h².
///
/// The output is piecewise constant in the input (it changes only when a relay switches): a
/// [`hyst_core::Jet`] input gets the exact value and derivatives 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Preisach {
    alphas: Vec<f64>,
    betas: Vec<f64>,
    weights: Vec<f64>,
    /// Relay states (true: +1, switched up); all false before the first sample.
    up: Vec<bool>,
    started: bool,
}

impl Preisach {
    /// An `n` × `n` grid (n ≥ 2; smaller values use 2) over [lo, hi] with weights
    /// `mu(alpha, beta)` (switch-up threshold α, switch-down threshold β ≤ α, input units).
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] when lo or hi is not finite or lo ≥ hi.
    pub fn new(lo: f64, hi: f64, n: usize, mu: impl Fn(f64, f64) -> f64) -> Result<Self, SimError> {
        finite("Preisach lo", lo)?;
        finite("Preisach hi", hi)?;
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
        let up = vec![false; weights.len()];
        Ok(Self {
            alphas,
            betas,
            weights,
            up,
            started: false,
        })
    }

    /// A Gaussian Preisach density centred on coercive field `hc` (spread `sh`) and interaction
    /// field 0 (spread `si`), on [−range, range] (all in input units): μ = exp(−((c − hc)/sh)²
    /// − (i/si)²) with c = (α − β)/2, i = (α + β)/2. The output then lies in
    /// [−Σ μ h², Σ μ h²].
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] when range, sh or si is not finite and > 0.
    pub fn gaussian(range: f64, n: usize, hc: f64, sh: f64, si: f64) -> Result<Self, SimError> {
        positive("Preisach range", range)?;
        positive("Preisach sh", sh)?;
        positive("Preisach si", si)?;
        Self::new(-range, range, n, move |a, b| {
            let c = 0.5 * (a - b);
            let i = 0.5 * (a + b);
            (-((c - hc) / sh).powi(2) - (i / si).powi(2)).exp()
        })
    }

    /// The number of relays (n (n + 1) / 2 for an n × n grid).
    #[must_use]
    pub fn relays(&self) -> usize {
        self.weights.len()
    }

    /// Σ μ γ̂ over the relays in their current states.
    fn output(&self) -> f64 {
        self.weights
            .iter()
            .zip(&self.up)
            .fold(0.0, |y, (w, up)| y + if *up { *w } else { -*w })
    }
}

impl Operator<f64> for Preisach {
    /// The relay states (true: switched up, +1), one per relay in grid order; `None` before the
    /// first sample (all relays at −1).
    type Memory = Option<Vec<bool>>;

    /// One sample: every relay with α ≤ x switches up, every relay with β ≥ x down, and the
    /// output is the weighted sum. A jet gets the exact value and derivatives 0 (the output is
    /// piecewise constant).
    ///
    /// # Errors
    /// [`Error::NonFiniteInput`]; the relays are then unchanged.
    fn try_step<S: Sample<f64>>(&mut self, x: S) -> Result<S, Error> {
        let x = x.value();
        if !x.is_finite() {
            return Err(Error::NonFiniteInput { value: x });
        }
        for ((up, a), b) in self.up.iter_mut().zip(&self.alphas).zip(&self.betas) {
            if x >= *a {
                *up = true;
            } else if x <= *b {
                *up = false;
            }
        }
        self.started = true;
        Ok(S::constant(self.output()))
    }

    fn last_output(&self) -> Option<f64> {
        self.started.then(|| self.output())
    }

    /// All relays back to −1 (negative saturation).
    fn reset(&mut self) {
        self.up.iter_mut().for_each(|s| *s = false);
        self.started = false;
    }

    fn memory(&self) -> Option<Vec<bool>> {
        self.started.then(|| self.up.clone())
    }

    /// # Errors
    /// [`Error::InvalidParameter`] naming `Preisach relay states` when the number of states is
    /// not [`Preisach::relays`]; the model is then unchanged.
    fn set_memory(&mut self, memory: Option<Vec<bool>>) -> Result<(), Error> {
        match memory {
            None => self.reset(),
            Some(up) => {
                if up.len() != self.relays() {
                    return Err(Error::InvalidParameter {
                        name: "Preisach relay states",
                        value: up.len() as f64,
                        expected: "one state per relay (Preisach::relays)",
                    });
                }
                self.up = up;
                self.started = true;
            }
        }
        Ok(())
    }
}

/// An input history for first-order reversal curves (the measurement behind the paper's
/// Fig. 3): from `hi` (positive saturation) down to each reversal field, then back up to `hi`,
/// for `curves` reversal fields spread over [lo, hi); `points_per_unit` samples per unit of
/// input (at least 1). Returns (input, curve index; −1 on descents), input in the units of lo
/// and hi. Empty for non-finite bounds or a non-finite `points_per_unit`.
#[must_use]
pub fn forc_input(lo: f64, hi: f64, curves: usize, points_per_unit: f64) -> Vec<(f64, i64)> {
    let mut out = Vec::new();
    if !(lo.is_finite() && hi.is_finite() && points_per_unit.is_finite()) {
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

#[cfg(test)]
mod tests {
    use super::*;
    use hyst_core::{AffineK2, Hysteresis, Identity, Jet};

    /// (a, b) held at (−0.5, 0.25) whatever the sample.
    fn fixed(_k: usize, _v: f64) -> (f64, f64) {
        (-0.5, 0.25)
    }

    #[test]
    fn a_fixed_position_is_exactly_that_member() -> Result<(), SimError> {
        let family = Family::new(0.14, 0.1, 8.0, 5.0)?;
        let mut truth = Drifting::new(Identity, Identity, family, fixed);
        // k̄1 = 0.14 − 0.5 · 0.1, k̄2 = 8 + 0.25 · 5.
        let mut member = Hysteresis::new(0.14 + -0.5 * 0.1, 8.0 + 0.25 * 5.0)?;
        for k in 0..400 {
            let x = (k as f64 * 0.05).sin() * (1.0 + k as f64 * 0.002);
            assert_eq!(truth.step(x).to_bits(), member.step(x).to_bits(), "k = {k}");
        }
        assert_eq!(truth.last_params(), (0.14 + -0.5 * 0.1, 8.0 + 0.25 * 5.0));
        assert_eq!(truth.memory().evaluations, 400);
        assert_eq!(truth.memory().operator, member.memory());
        // Positions outside [−1, 1] are clamped to the corners.
        let mut corner = Drifting::new(Identity, Identity, family, |_: usize, _: f64| (-7.0, 3.0));
        let _ = corner.step(0.5);
        assert_eq!(corner.last_params(), (0.14 - 0.1, 8.0 + 5.0));
        Ok(())
    }

    #[test]
    fn the_law_and_the_shaping_enter_as_documented() -> Result<(), SimError> {
        // k̄2 = φ(v) + b Δk2 with φ(v) = 9 − 2 v, v = ψ_in(x) = 0.5 x, y = 3 u.
        let phi = AffineK2::new(9.0, -2.0, 5.0, 12.0)?;
        let family = Family::with_k2_law(0.1, 0.02, phi, 0.5)?;
        let (psi_in, psi_out) = (
            hyst_core::Affine::new(0.5, 0.0)?,
            hyst_core::Affine::new(3.0, 0.0)?,
        );
        let mut truth = Drifting::new(psi_in, psi_out, family, |_: usize, _: f64| (1.0, -1.0));
        let mut model = hyst_core::ShapedModel::new(
            psi_in,
            Hysteresis::with_k2_law(
                0.12,
                hyst_core::ShiftedK2 {
                    law: phi,
                    shift: -0.5,
                },
            )?,
            psi_out,
        )?;
        for x in [0.0, 1.0, 2.0, 0.4, -1.0, 0.7] {
            assert_eq!(truth.step(x), model.step(x));
            let (k1, k2) = truth.last_params();
            assert_eq!((k1, k2), (0.1 + 0.02, phi.k2(0.5 * x) - 0.5));
        }
        assert_eq!(truth.last_output(), model.last_output());
        Ok(())
    }

    #[test]
    fn drifting_member_stays_in_its_band() -> Result<(), SimError> {
        let family = Family::new(0.1, 0.02, 5.0, 2.0)?;
        let mut d = Drifting::new(Identity, Identity, family, |k: usize, _v: f64| {
            ((k as f64 * 0.01).sin(), (k as f64 * 0.003).cos())
        });
        let mut widest = 0.0_f64;
        for k in 0..5000 {
            let x = (k as f64 * 0.004).sin() * 2.0;
            let y = d.step(x);
            let (k1, k2) = d.last_params();
            // The memory is clamped into the band of each new k̄1.
            assert!((y - x).abs() <= k1 * (1.0 + 1e-12), "k = {k}: {y} {x} {k1}");
            assert!((0.08..=0.12).contains(&k1) && (3.0..=7.0).contains(&k2));
            widest = widest.max((y - x).abs());
        }
        // The loop is open: the output does leave the line y = x by most of k1.
        assert!(widest > 0.09, "{widest}");
        Ok(())
    }

    #[test]
    fn the_drift_index_counts_evaluations_and_the_memory_resumes() -> Result<(), SimError> {
        let family = Family::new(0.06, 0.005, 5.0, 2.5)?;
        let drift = |k: usize, v: f64| ((k as f64 * 0.3).sin(), v.cos());
        let mut truth = Drifting::new(Identity, Identity, family, drift);
        let input: Vec<f64> = (0..60).map(|k| (k as f64 * 0.2).sin()).collect();
        let first: Vec<f64> = input.iter().map(|x| truth.step(*x)).collect();
        assert_eq!(truth.memory().evaluations, 60);
        truth.reset();
        assert_eq!(truth.memory(), DriftingMemory::default());
        assert_eq!(truth.last_output(), None);
        let half = 25;
        let again: Vec<f64> = input.iter().take(half).map(|x| truth.step(*x)).collect();
        assert_eq!(again[..], first[..half]);
        let saved = truth.memory();
        let mut other = Drifting::new(Identity, Identity, family, drift);
        other.set_memory(saved)?;
        for (x, y) in input.iter().zip(&first).skip(half) {
            assert_eq!(other.step(*x), *y);
        }
        // A refused sample changes nothing, and does not count.
        assert!(other.try_step(f64::NAN).is_err());
        assert_eq!(other.memory().evaluations, 60);
        let mut bad = Drifting::new(Identity, Identity, family, |_: usize, _: f64| {
            (f64::NAN, 0.0)
        });
        let e = bad.try_step(0.1).err().map(|e| e.to_string());
        assert!(
            e.as_deref()
                .is_some_and(|e| e.contains("member position a")),
            "{e:?}"
        );
        assert_eq!(bad.memory(), DriftingMemory::default());
        // A memory outside the widest member's band (k1 + Δk1 = 0.065) is refused.
        let mut far = saved;
        if let Some(m) = far.operator.as_mut() {
            m.last_output = m.last_input + 0.07;
        }
        assert!(other.set_memory(far).is_err());
        Ok(())
    }

    #[test]
    fn a_jet_gets_the_members_derivatives() -> Result<(), SimError> {
        let family = Family::new(0.2, 0.05, 8.0, 2.0)?;
        let mut truth = Drifting::new(Identity, Identity, family, fixed);
        let mut member = family.member(-0.5, 0.25)?;
        for k in 0..50 {
            let t = k as f64 * 0.1;
            let x = Jet::<f64, 2>::from_derivatives(t.sin(), [t.cos(), -t.sin()]);
            let (y, z) = (truth.try_step(x)?, member.try_step(x)?);
            assert_eq!(y.value(), z.value());
            assert_eq!(y.derivatives(), z.derivatives());
        }
        Ok(())
    }

    #[test]
    fn preisach_is_hysteretic_and_piecewise_constant() -> Result<(), SimError> {
        let mut p = Preisach::gaussian(2.0, 40, 0.5, 0.2, 0.3)?;
        assert_eq!(p.relays(), 40 * 41 / 2);
        assert_eq!(p.last_output(), None);
        let up: Vec<f64> = [-2.0, 0.0, 2.0].iter().map(|x| p.step(*x)).collect();
        // Saturated at both ends: ∓ the total weight.
        let total: f64 = p.weights.iter().sum();
        assert!((up[0] + total).abs() < 1e-12 && (up[2] - total).abs() < 1e-12);
        let down = p.step(0.0);
        assert!(down > up[1] + 0.1, "no loop: {up:?} {down}");
        // The output is piecewise constant: a jet's derivatives are 0.
        let y = p.try_step(Jet::<f64, 1>::from_derivatives(0.01, [5.0]))?;
        assert_eq!(y.derivatives(), [0.0]);
        assert_eq!(y.value(), p.step(0.01));
        // Memory round trip, and a memory of the wrong size is refused.
        let saved = p.memory();
        let after = p.step(-0.6);
        p.set_memory(saved.clone())?;
        assert_eq!(p.step(-0.6), after);
        assert!(p.set_memory(Some(vec![true; 3])).is_err());
        assert!(p.try_step(f64::NAN).is_err());
        p.reset();
        assert_eq!(p.memory(), None);
        assert_eq!(p.step(0.0), up[1]);
        Ok(())
    }

    #[test]
    fn bad_preisach_parameters_are_refused() {
        let e = Preisach::new(1.0, 1.0, 10, |_, _| 1.0).err();
        assert!(matches!(
            e,
            Some(SimError::InvalidParameter { name: "Preisach hi", value, .. }) if value == 1.0
        ));
        let e = Preisach::gaussian(2.0, 10, 0.5, 0.0, 0.3).err();
        assert!(matches!(
            e,
            Some(SimError::InvalidParameter { name: "Preisach sh", value, .. }) if value == 0.0
        ));
    }

    #[test]
    fn forc_input_descends_to_each_reversal_and_climbs_back() {
        let h = forc_input(-1.0, 1.0, 5, 10.0);
        for c in 0..5_i64 {
            let reversal = 1.0 - 2.0 * (c + 1) as f64 / 5.0;
            let ascent: Vec<f64> = h.iter().filter(|p| p.1 == c).map(|p| p.0).collect();
            assert_eq!(ascent.first().copied(), Some(reversal), "curve {c}");
            let last = ascent.last().copied().unwrap_or(f64::NAN);
            assert!(last <= 1.0 && last > 1.0 - 0.1 - 1e-12, "curve {c}: {last}");
            // 10 points per unit of input.
            let expected = (1.0 - reversal) * 10.0;
            assert!((ascent.len() as f64 - expected).abs() <= 1.0, "curve {c}");
        }
        assert_eq!(h.first(), Some(&(1.0, -1)));
        assert!(forc_input(f64::NAN, 1.0, 5, 10.0).is_empty());
        assert!(forc_input(-1.0, 1.0, 5, f64::INFINITY).is_empty());
    }
}
