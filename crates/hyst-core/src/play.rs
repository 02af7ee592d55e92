//! The play operator (a hard backlash): the limit of the parametric operator as k2 → ∞, the
//! truth of the paper's Example 3, and the building block of the Prandtl–Ishlinskii operator.
//!
//! play_r\[x\](k) = max(x(k) − r, min(x(k) + r, play_r\[x\](k − 1))), the first sample at rest on the
//! line output = input. The output follows the input at a distance r once the play is taken up,
//! and holds still while the input moves inside the gap.

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use crate::error::Error;
use crate::operator::Operator;
use crate::real::Real;
use crate::sample::Sample;

/// The play update: the previous output `previous` clamped into [x − r, x + r] (r ≥ 0).
#[inline]
#[must_use]
pub fn update<T: Real>(previous: T, x: T, r: T) -> T {
    (x - r).max((x + r).min(previous))
}

/// Whether a play at `output` for the input `x` moves with the input: it sits on the edge of
/// its band that the input pushes (`rising`: the lower edge x − r; falling: the upper edge
/// x + r). Then every time derivative of the play's output is the input's; otherwise the play
/// is stuck and its derivatives are 0. `None` (an input that does not move) never pushes.
#[inline]
#[must_use]
pub fn is_pushed<T: Real>(output: T, x: T, r: T, trend: Option<bool>) -> bool {
    match trend {
        Some(true) => output == x - r,
        Some(false) => output == x + r,
        None => false,
    }
}

/// A play (backlash) operator of half-width r: the output follows the input at a distance r
/// once the play is taken up (input and output in the same unit). Total width of the gap 2 r.
///
/// # Examples
/// ```
/// use hyst_core::{Operator, Play};
/// let mut play = Play::new(0.5_f64)?;
/// assert_eq!(play.step(0.0), 0.0); // at rest on the line
/// assert_eq!(play.step(1.0), 0.5); // taken up: follows at 0.5 below
/// assert_eq!(play.step(0.6), 0.5); // inside the gap: holds
/// assert_eq!(play.step(-1.0), -0.5);
/// # Ok::<(), hyst_core::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Play<T> {
    half_width: T,
    output: Option<T>,
}

impl<T: Real> Play<T> {
    /// A play of half-width `half_width` = r (input units, finite and ≥ 0; 0 is the identity),
    /// with no history.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `play half-width` otherwise.
    pub fn new(half_width: T) -> Result<Self, Error> {
        if !(half_width.is_finite() && half_width >= T::zero()) {
            return Err(Error::InvalidParameter {
                name: "play half-width",
                value: half_width.as_f64(),
                expected: "finite and >= 0",
            });
        }
        Ok(Self {
            half_width,
            output: None,
        })
    }

    /// The half-width r (input units).
    #[must_use]
    pub fn half_width(&self) -> T {
        self.half_width
    }
}

impl<T: Real> Operator<T> for Play<T> {
    /// The play's output, `None` before the first sample.
    type Memory = Option<T>;

    /// One sample: the play update; a jet's derivatives pass through when the play is pushed
    /// ([`is_pushed`]) and are 0 while it is stuck.
    ///
    /// # Errors
    /// [`Error::NonFiniteInput`]; the state is then unchanged.
    fn try_step<S: Sample<T>>(&mut self, x: S) -> Result<S, Error> {
        let v = x.value();
        if !x.all_finite() {
            return Err(Error::NonFiniteInput { value: v.as_f64() });
        }
        let r = self.half_width;
        let y = update(self.output.unwrap_or(v), v, r);
        self.output = Some(y);
        Ok(if is_pushed(y, v, r, x.trend()) {
            x.with_value(y)
        } else {
            S::constant(y)
        })
    }

    fn last_output(&self) -> Option<T> {
        self.output
    }

    fn reset(&mut self) {
        self.output = None;
    }

    fn memory(&self) -> Option<T> {
        self.output
    }

    /// # Errors
    /// [`Error::InvalidParameter`] for a non-finite output.
    fn set_memory(&mut self, memory: Option<T>) -> Result<(), Error> {
        if let Some(y) = memory {
            crate::error::finite("play output", y)?;
        }
        self.output = memory;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::jet::Jet;

    #[test]
    fn derivatives_pass_only_while_pushed() -> Result<(), Error> {
        let mut play = Play::new(0.25_f64)?;
        let y = play.try_step(Jet::<f64, 2>::from_derivatives(0.0, [1.0, 2.0]))?;
        assert_eq!(y.value(), 0.0);
        assert_eq!(y.derivatives(), [0.0, 0.0]); // at rest in the middle of the gap
        let y = play.try_step(Jet::<f64, 2>::from_derivatives(1.0, [1.0, 2.0]))?;
        assert_eq!(y.value(), 0.75);
        assert_eq!(y.derivatives(), [1.0, 2.0]); // dragged up
        let y = play.try_step(Jet::<f64, 2>::from_derivatives(0.9, [-1.0, 0.0]))?;
        assert_eq!(y.value(), 0.75);
        assert_eq!(y.derivatives(), [0.0, 0.0]); // reversed: stuck
        assert!(play.try_step(f64::NAN).is_err());
        assert_eq!(play.memory(), Some(0.75));
        assert_eq!(play.step(f64::INFINITY), 0.75);
        assert!(Play::new(-1.0_f64).is_err());
        assert!(play.set_memory(Some(f64::NAN)).is_err());
        Ok(())
    }
}
