//! The start rule: where a model with no history starts. Definition 2.1 needs a first reversal
//! point; a fitted model names the one its records start from ([`InitialState`]), and
//! [`Started`] applies it at the first sample, so a model runs exactly from sample 1 without
//! knowing that sample beforehand.

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use crate::error::Error;
use crate::k2law::K2Law;
use crate::memory::{Direction, Memory};
use crate::operator::Operator;
use crate::parametric::Hysteresis;
use crate::real::Real;
use crate::sample::Sample;
use crate::shaped_model::{unreachable_output, InverseShapedModel, ShapedModel};
use crate::shaping::Shaping;
use crate::stop::Stop;

/// Where a record starts (the first reversal point of Definition 2.1). The default,
/// [`InitialState::Rising`], suits a device switched on and driven up to its first value, and a
/// loop or FORC record that starts from positive saturation. Its kebab-case name (`rising`,
/// `falling`, `line`) is the model file's.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum InitialState {
    /// As after a long rise: on the lower asymptote output = input − k1, heading up.
    #[default]
    Rising,
    /// As after a long fall: on the upper asymptote output = input + k1, heading down.
    Falling,
    /// No history: the first sample is a reversal point on the anhysteretic line output = input.
    Line,
}

/// v + d with its value rounded towards v until |(v + d) − v| ≤ |d| holds in floating point
/// (the band check of [`Memory::at_rest`]), so a start on an asymptote is never refused for an
/// ulp. A [`Dual`](crate::Dual) keeps the gradient of v + d.
#[must_use]
pub fn on_asymptote<T: Real>(v: T, d: T) -> T {
    let mut u = v + d;
    for _ in 0..64 {
        if (u - v).abs() <= d.abs() {
            break;
        }
        u = u.ulp_toward(v);
    }
    u
}

impl InitialState {
    /// The memory at rest that this rule gives an operator H(k1, ·) whose first input is `v0`
    /// (operator units): on the lower asymptote heading up, on the upper one heading down, or
    /// none (the line: the first sample becomes the reversal point).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a non-finite `v0`.
    pub fn memory<T: Real>(self, v0: T, k1: T) -> Result<Option<Memory<T>>, Error> {
        let (d, direction) = match self {
            InitialState::Line => return Ok(None),
            InitialState::Rising => (-k1, Direction::Rising),
            InitialState::Falling => (k1, Direction::Falling),
        };
        Memory::at_rest(v0, on_asymptote(v0, d), direction, k1).map(Some)
    }

    /// The memory at rest that this rule gives H(k1, ·) when its first *output* is `u0`: what
    /// an inverse needs, whose first sample is a desired output. The input is built from `u0`,
    /// so the memory holds `u0` exactly and the inverse's first step lies on the reversal.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a non-finite `u0`.
    pub fn memory_from_output<T: Real>(self, u0: T, k1: T) -> Result<Option<Memory<T>>, Error> {
        let (d, direction) = match self {
            InitialState::Line => return Ok(None),
            InitialState::Rising => (k1, Direction::Rising),
            InitialState::Falling => (-k1, Direction::Falling),
        };
        Memory::at_rest(on_asymptote(u0, d), u0, direction, k1).map(Some)
    }

    /// `operator` started by this rule for the first operator input `v0` (see
    /// [`InitialState::memory`]); its reset returns to this start.
    ///
    /// # Errors
    /// As [`InitialState::memory`].
    pub fn start<T: Real, K: K2Law<T>>(
        self,
        operator: Hysteresis<T, K>,
        v0: T,
    ) -> Result<Hysteresis<T, K>, Error> {
        let memory = self.memory(v0, operator.k1())?;
        Self::start_with(operator, memory)
    }

    /// `operator` started by this rule for the first operator output `u0` (see
    /// [`InitialState::memory_from_output`]); its reset returns to this start.
    ///
    /// # Errors
    /// As [`InitialState::memory_from_output`].
    pub fn start_from_output<T: Real, K: K2Law<T>>(
        self,
        operator: Hysteresis<T, K>,
        u0: T,
    ) -> Result<Hysteresis<T, K>, Error> {
        let memory = self.memory_from_output(u0, operator.k1())?;
        Self::start_with(operator, memory)
    }

    fn start_with<T: Real, K: K2Law<T>>(
        operator: Hysteresis<T, K>,
        memory: Option<Memory<T>>,
    ) -> Result<Hysteresis<T, K>, Error> {
        match memory {
            None => Ok(operator),
            Some(m) => {
                operator.with_initial_state(m.reversal_input, m.reversal_output, m.direction)
            }
        }
    }
}

/// A model that a start rule can start at its first sample: the shaped model, its stop form
/// and its inverse. (The start of the inverse is the state the rule gives the direct model that
/// produces the first desired output.)
pub trait Start<T: Real> {
    /// Sets the memory the rule gives for the first sample `first` (the model's own input: an
    /// input for a direct model, a desired output for an inverse). The memory is not kept as
    /// an initial state: after a reset, the rule applies again at the next sample.
    ///
    /// # Errors
    /// A non-finite `first`, or one an inverse cannot reach (beyond a saturating ψ_out).
    fn start_at(&mut self, first: T, rule: InitialState) -> Result<(), Error>;
}

impl<T: Real, I: Shaping<T>, K: K2Law<T>, O: Shaping<T>> Start<T> for ShapedModel<T, I, K, O> {
    fn start_at(&mut self, first: T, rule: InitialState) -> Result<(), Error> {
        let v0 = self.input_shaping().apply(first);
        let memory = rule.memory(v0, self.operator().k1())?;
        self.restore(memory);
        Ok(())
    }
}

impl<T: Real, I: Shaping<T>, K: K2Law<T>, O: Shaping<T>> Start<T> for Stop<T, I, K, O> {
    fn start_at(&mut self, first: T, rule: InitialState) -> Result<(), Error> {
        let v0 = self.input_shaping().apply(first);
        let memory = rule.memory(v0, self.operator().k1())?;
        self.restore(memory);
        Ok(())
    }
}

impl<T: Real, I: Shaping<T> + Clone, K: K2Law<T> + Clone, O: Shaping<T> + Clone> Start<T>
    for InverseShapedModel<T, I, K, O>
{
    fn start_at(&mut self, first: T, rule: InitialState) -> Result<(), Error> {
        let u0 = self.output_shaping().invert(first)?;
        let memory = rule.memory_from_output(u0, self.operator().k1())?;
        // The command exists (a saturating ψ_in has a bounded range): the rule puts the first
        // operator input at u0 − d, so the first outputs it can reach are ψ_out((a + d, b + d)).
        if let Some(m) = memory {
            let d = m.last_output - m.last_input;
            self.input_shaping()
                .invert(m.last_input)
                .map_err(|e| unreachable_output(first, e, self.output_shaping(), |w| Ok(w + d)))?;
        }
        self.restore_direct(memory);
        Ok(())
    }
}

/// A model run by its start rule: whenever it has no history (before its first sample and
/// after a reset), the rule sets its memory from the sample about to be stepped, then the
/// sample is stepped. So a fitted model runs exactly as `hyst run --model` runs a record, from
/// its first sample, without knowing that sample beforehand.
///
/// # Examples
/// ```
/// use hyst_core::{Hysteresis, Identity, InitialState, Operator, ShapedModel, Started};
/// let model = ShapedModel::new(Identity, Hysteresis::new(0.2_f64, 6.0)?, Identity)?;
/// let mut started = Started::new(model, InitialState::Rising);
/// // On the lower asymptote at the first sample: y = x − k1.
/// assert!((started.step(1.0) - 0.8).abs() < 1e-15);
/// # Ok::<(), hyst_core::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Started<M> {
    model: M,
    rule: InitialState,
}

impl<M> Started<M> {
    /// `model` (with no history, or with the history it has) run by `rule`.
    pub fn new(model: M, rule: InitialState) -> Self {
        Self { model, rule }
    }

    /// The model inside.
    #[must_use]
    pub fn model(&self) -> &M {
        &self.model
    }

    /// The start rule.
    #[must_use]
    pub fn rule(&self) -> InitialState {
        self.rule
    }
}

impl<T, M> Operator<T> for Started<M>
where
    T: Real,
    M: Operator<T, Memory = Option<Memory<T>>> + Start<T> + Clone,
{
    /// The memory of the model inside (`None`: the rule applies at the next sample).
    type Memory = Option<Memory<T>>;

    /// One sample (plain or jet); without history, the rule starts the model at this sample's
    /// value first.
    ///
    /// # Errors
    /// The rule's or the model's error for this sample; the model is then unchanged (still
    /// without history after a refused first sample).
    #[inline]
    fn try_step<S: Sample<T>>(&mut self, x: S) -> Result<S, Error> {
        if self.rule == InitialState::Line || self.model.memory().is_some() {
            return self.model.try_step(x);
        }
        let mut started = self.model.clone();
        started.start_at(x.value(), self.rule)?;
        let y = started.try_step(x)?;
        self.model = started;
        Ok(y)
    }

    fn last_output(&self) -> Option<T> {
        self.model.last_output()
    }

    forward_memory!(model, Option<Memory<T>>);
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::shaping::{Affine, Identity};

    #[test]
    fn on_asymptote_stays_inside_the_band() {
        for &(v, d) in &[(0.1_f64, -0.3), (1e6, 0.1), (-3.7, 0.2), (0.3, -0.1)] {
            let u = on_asymptote(v, d);
            assert!((u - v).abs() <= d.abs());
            assert!((u - (v + d)).abs() <= 4.0 * f64::EPSILON * (v.abs() + d.abs()));
        }
    }

    #[test]
    fn a_started_model_equals_one_started_beforehand() {
        let x: [f64; 6] = [0.4, 0.9, 0.2, -0.5, 0.1, 0.6];
        for rule in [
            InitialState::Rising,
            InitialState::Falling,
            InitialState::Line,
        ] {
            let operator = Hysteresis::new(0.2, 6.0).unwrap();
            let psi_in = Affine::new(1.3, 0.1).unwrap();
            let before = rule.start(operator, psi_in.apply(x[0])).unwrap();
            let mut before = ShapedModel::new(psi_in, before, Identity).unwrap();
            let mut started =
                Started::new(ShapedModel::new(psi_in, operator, Identity).unwrap(), rule);
            for xi in x {
                assert_eq!(started.step(xi).to_bits(), before.step(xi).to_bits());
            }
            // A reset forgets: the rule applies again at the next sample.
            started.reset();
            assert_eq!(started.memory(), None);
            let first = started.step(x[3]);
            let again = rule.start(operator, psi_in.apply(x[3])).unwrap();
            let mut again = ShapedModel::new(psi_in, again, Identity).unwrap();
            assert_eq!(first.to_bits(), again.step(x[3]).to_bits());
        }
    }

    #[test]
    fn a_started_inverse_inverts_the_started_model() {
        let psi_out = Affine::new(2.0, -0.3).unwrap();
        let model =
            ShapedModel::new(Identity, Hysteresis::new(0.2, 6.0).unwrap(), psi_out).unwrap();
        for rule in [InitialState::Rising, InitialState::Falling] {
            let mut inverse = Started::new(model.inverse(), rule);
            let mut direct = Started::new(model, rule);
            for k in 0..200 {
                let desired = 0.8 * (f64::from(k) * 0.07).sin() + 0.1;
                let command = inverse.step(desired);
                assert!(
                    (direct.step(command) - desired).abs() < 1e-12,
                    "{rule:?} at {k}"
                );
            }
        }
    }

    #[test]
    fn a_refused_first_sample_leaves_no_history() {
        let model =
            ShapedModel::new(Identity, Hysteresis::new(0.2, 6.0).unwrap(), Identity).unwrap();
        let mut started = Started::new(model, InitialState::Rising);
        assert!(started.try_step(f64::NAN).is_err());
        assert_eq!(started.memory(), None);
        assert!((started.step(1.0) - 0.8).abs() < 1e-15);
    }
}
