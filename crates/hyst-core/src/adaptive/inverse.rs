//! [`AdaptiveInverse`]: the exact inverse of the estimator's current model, in a loop with
//! the estimator.

use crate::adaptive::estimator::Adaptive;
use crate::adaptive::settings::MAX_PARAMETERS;
use crate::adaptive::status::Update;
use crate::any_shaping::AnyShaping;
use crate::error::Error;
use crate::operator::Operator;
use crate::real::Real;
use crate::shaping::Shaping;
use crate::start::Start;

/// The exact inverse of a model that follows a drifting actuator: each command is the exact
/// inverse (eq. 4 through the shaping) of the estimator's current model, from the estimator's memory; each
/// measurement updates the estimator ([`Adaptive`]).
///
/// A control loop calls [`AdaptiveInverse::step`] with the desired output, sends the
/// command to the actuator, and calls [`AdaptiveInverse::measure`] with the output it
/// measured for that command. The memory is the estimator's, re-anchored at each update so that
/// the state does not jump (see [the module](super)): the inverse and the model never
/// disagree on where the actuator is.
///
/// # Examples
/// ```
/// use hyst_core::adaptive::{Adaptive, AdaptiveInverse, AdaptiveConfig, AdaptiveModel};
/// use hyst_core::{AnyK2Law, Hysteresis, InitialState, Operator, ScaledShaping, ShapedModel};
/// # fn main() -> Result<(), hyst_core::Error> {
/// let fitted: AdaptiveModel<f64> = ShapedModel::new(
///     ScaledShaping::identity(),
///     Hysteresis::with_k2_law(0.2, AnyK2Law::Constant { value: 8.0 })?,
///     ScaledShaping::identity(),
/// )?;
/// let estimator = Adaptive::new(&fitted, InitialState::Line, AdaptiveConfig::new(1e-3))?;
/// let mut inverse = AdaptiveInverse::new(estimator);
/// let mut actuator = fitted; // the truth, here equal to the model
/// for k in 0..1000 {
///     let desired = 0.8 * (k as f64 * 0.02).sin();
///     let command = inverse.step(desired)?;
///     let measured = actuator.step(command);
///     assert!((measured - desired).abs() < 1e-9);
///     inverse.measure(measured);
/// }
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug)]
pub struct AdaptiveInverse<T: Real, const W: usize = MAX_PARAMETERS, S = AnyShaping<T>> {
    estimator: Adaptive<T, W, S>,
    /// The last command, waiting for its measurement.
    pending: Option<T>,
}

impl<T: Real, const W: usize, S: Shaping<T> + Copy> AdaptiveInverse<T, W, S> {
    /// The inverse of `estimator`'s model, following it.
    #[must_use]
    pub fn new(estimator: Adaptive<T, W, S>) -> Self {
        Self {
            estimator,
            pending: None,
        }
    }

    /// The command x that gives the desired output `desired` (output units) with the current
    /// parameters. A command whose measurement never came is given to the estimator first as
    /// unmeasured ([`Status::BadOutput`](crate::adaptive::Status::BadOutput)), so that the model still follows the actuator.
    ///
    /// # Errors
    /// As the inverse model's step: a non-finite desired output, or one beyond a saturating
    /// ψ_out's range ([`Error::OutOfRange`]); the state is then unchanged.
    pub fn step(&mut self, desired: T) -> Result<T, Error> {
        if let Some(x) = self.pending.take() {
            self.estimator.update(x, T::nan());
        }
        self.estimator.anchor();
        let model = self.estimator.model()?;
        let mut inverse = model.inverse();
        if model.memory().is_none() {
            inverse.start_at(desired, self.estimator.start())?;
        }
        let x = inverse.try_step(desired)?;
        self.pending = Some(x);
        Ok(x)
    }

    /// Updates the estimator with the output `measured` for the last command: its prediction
    /// and status, `None` when no command is waiting for a measurement.
    pub fn measure(&mut self, measured: T) -> Option<Update<T>> {
        let x = self.pending.take()?;
        Some(self.estimator.update(x, measured))
    }

    /// A sample this inverse did not command (a record played back, a command from
    /// elsewhere): the estimator's update for command `x` and output `y`, after any command
    /// still waiting for its measurement (given as unmeasured).
    pub fn update(&mut self, x: T, y: T) -> Update<T> {
        if let Some(p) = self.pending.take() {
            self.estimator.update(p, T::nan());
        }
        self.estimator.update(x, y)
    }

    /// The last command, if its measurement has not come yet.
    #[must_use]
    pub fn pending(&self) -> Option<T> {
        self.pending
    }

    /// The estimator (its parameters, counts and memory).
    #[must_use]
    pub fn estimator(&self) -> &Adaptive<T, W, S> {
        &self.estimator
    }
}
