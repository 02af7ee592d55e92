//! The memory of Definition 2.1: the last reversal point (α0, β0) and the direction of the input.
//!
//! In discrete time (Section 4.2, "Causality") the direction is the sign of the last non-zero input
//! step x\[k\] − x[k−1]; a zero step keeps the current direction, and at a change of direction the
//! previous sample becomes the reversal point. For a [`Jet`](crate::Jet) input whose value does
//! not move, the sign of its lowest-order non-zero derivative decides instead, so that a
//! continuous-time trajectory starting at a turning point gets the right mode from the start.

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use core::ops::Neg;

use crate::error::Error;
use crate::real::Real;
use crate::sample::Sample;

/// The mode of the operator (Fig. 2): rising input (α̇ ≥ 0) or falling input (α̇ < 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum Direction {
    /// The input is rising (or has not moved yet): s = +1 in the transformation T of Definition 2.1.
    #[default]
    Rising,
    /// The input is falling: s = −1.
    Falling,
}

impl Direction {
    /// s = +1 for [`Direction::Rising`], −1 for [`Direction::Falling`].
    #[must_use]
    #[inline]
    pub fn sign<T: Real>(self) -> T {
        match self {
            Direction::Rising => T::one(),
            Direction::Falling => -T::one(),
        }
    }

    /// s · x for s = [`Direction::sign`], written as a negation when falling: the same value
    /// as the product (multiplying by ±1 is exact), without a ±1 to keep in a register.
    #[must_use]
    #[inline(always)]
    pub(crate) fn apply<X: Neg<Output = X>>(self, x: X) -> X {
        match self {
            Direction::Rising => x,
            Direction::Falling => -x,
        }
    }

    /// The other direction.
    #[must_use]
    pub fn reversed(self) -> Self {
        match self {
            Direction::Rising => Direction::Falling,
            Direction::Falling => Direction::Rising,
        }
    }

    fn from_rising(rising: bool) -> Self {
        if rising {
            Direction::Rising
        } else {
            Direction::Falling
        }
    }
}

/// The state of one operator: Definition 2.1's reversal point (α0, β0) and direction, plus the
/// last input and output sample (the causal, discrete-time form of Section 4.2).
///
/// α is the operator's input and β its output: for the direct operator (eq. 2) α = v, β = u;
/// for the inverse (eq. 4) α = u_d, β = v. The same type serves both. A controller that restarts
/// saves this value and restores it with `set_memory` to resume exactly where it stopped.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Memory<T> {
    /// α0: the operator input at the last reversal.
    pub reversal_input: T,
    /// β0: the operator output at the last reversal.
    pub reversal_output: T,
    /// The current mode.
    pub direction: Direction,
    /// The last input sample.
    pub last_input: T,
    /// The last output sample.
    pub last_output: T,
}

impl<T: Real> Memory<T> {
    /// A memory at rest at the point (input, output), heading in `direction`: that point is the
    /// reversal point. Checks that the point lies in the band |output − input| ≤ k1.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for non-finite values, [`Error::StateOutsideBand`] outside the
    /// band.
    pub fn at_rest(input: T, output: T, direction: Direction, k1: T) -> Result<Self, Error> {
        crate::error::finite("initial input", input)?;
        crate::error::finite("initial output", output)?;
        if (output - input).abs() > k1 {
            return Err(Error::StateOutsideBand {
                input: input.as_f64(),
                output: output.as_f64(),
                k1: k1.as_f64(),
            });
        }
        Ok(Self {
            reversal_input: input,
            reversal_output: output,
            direction,
            last_input: input,
            last_output: output,
        })
    }

    /// Checks a memory that comes from outside (a saved state): all values finite, the reversal
    /// point inside the band of half-width k1 and the last point inside the band (both with a
    /// relative tolerance of 1e-9 for rounding), and the last input on the branch that leaves
    /// the reversal point in the memory's direction (at or above the reversal input when
    /// rising, at or below it when falling: the operator never produces another memory).
    ///
    /// # Errors
    /// As [`Memory::at_rest`]; [`Error::InvalidParameter`] for a last input on the wrong side
    /// of the reversal input.
    pub fn validate(&self, k1: T) -> Result<(), Error> {
        let tol = k1 * T::from_f64(1e-9);
        for (name, value) in [
            ("reversal_input", self.reversal_input),
            ("reversal_output", self.reversal_output),
            ("last_input", self.last_input),
            ("last_output", self.last_output),
        ] {
            crate::error::finite(name, value)?;
        }
        for (input, output) in [
            (self.reversal_input, self.reversal_output),
            (self.last_input, self.last_output),
        ] {
            if (output - input).abs() > k1 + tol {
                return Err(Error::StateOutsideBand {
                    input: input.as_f64(),
                    output: output.as_f64(),
                    k1: k1.as_f64(),
                });
            }
        }
        let slack =
            T::from_f64(1e-9) * self.reversal_input.abs().max(self.last_input.abs()).max(k1);
        let on_branch = match self.direction {
            Direction::Rising => self.last_input >= self.reversal_input - slack,
            Direction::Falling => self.last_input <= self.reversal_input + slack,
        };
        if !on_branch {
            return Err(Error::InvalidParameter {
                name: "last_input",
                value: self.last_input.as_f64(),
                expected: "on the branch from the reversal point: at or above reversal_input when \
                           rising, at or below it when falling",
            });
        }
        Ok(())
    }

    /// Applies the discrete direction rule to a new input sample: a non-zero step sets the
    /// direction (a zero step defers to `trend`, the sign of the input's first non-zero
    /// derivative when it has one); a change of direction makes the last sample the reversal point.
    ///
    /// Returns whether the direction changed. The previous reversal point then waits in
    /// `last_input` and `last_output`, which the caller overwrites with the new sample when it
    /// accepts it, or from where [`Memory::unobserve`] puts it back when it refuses the sample:
    /// so nothing needs saving on the common path.
    #[inline]
    pub(crate) fn observe(&mut self, x: T, trend: Option<bool>) -> bool {
        let direction = if x > self.last_input {
            Some(Direction::Rising)
        } else if x < self.last_input {
            Some(Direction::Falling)
        } else {
            trend.map(Direction::from_rising)
        };
        match direction {
            Some(d) if d != self.direction => {
                self.swap_reversal_and_last();
                self.direction = d;
                true
            }
            _ => false,
        }
    }

    /// Undoes [`Memory::observe`], which returned `reversed`, before the caller wrote the
    /// sample: the memory is then as it was before `observe`.
    #[inline]
    pub(crate) fn unobserve(&mut self, reversed: bool) {
        if reversed {
            self.swap_reversal_and_last();
            self.direction = self.direction.reversed();
        }
    }

    /// Exchanges the reversal point and the last sample (plain moves: `core::mem::swap` of
    /// two fields became a byte-swapping loop in a firmware build for size).
    #[inline(always)]
    fn swap_reversal_and_last(&mut self) {
        (self.reversal_input, self.last_input) = (self.last_input, self.reversal_input);
        (self.reversal_output, self.last_output) = (self.last_output, self.reversal_output);
    }

    /// The first sample of an operator with no history: a reversal point on the line
    /// output = input, heading the way the input's derivatives say (rising if they say nothing).
    #[must_use]
    pub fn first_sample(x: T, trend: Option<bool>) -> Self {
        Self {
            reversal_input: x,
            reversal_output: x,
            direction: trend.map_or(Direction::Rising, Direction::from_rising),
            last_input: x,
            last_output: x,
        }
    }

    /// The transformed input α̃ = s (α − α0) of Definition 2.1.
    #[inline]
    pub fn transform<S: Sample<T>>(&self, alpha: S) -> S {
        self.direction.apply(alpha - self.reversal_input)
    }

    /// The output from its transformed value: β = β0 + s β̃ (Definition 2.1 solved for β).
    #[inline]
    pub fn untransform<S: Sample<T>>(&self, beta_tilde: S) -> S {
        self.direction.apply(beta_tilde) + self.reversal_output
    }

    /// M(α, β) = s (β0 − α0) of Definition 2.1: the signed distance of the reversal point from
    /// the line β = α.
    #[must_use]
    #[inline]
    pub fn m(&self) -> T {
        self.direction
            .apply(self.reversal_output - self.reversal_input)
    }

    /// The same memory seen from the other side of the operator pair (input and output swapped):
    /// the memory of the inverse operator that undoes this operator exactly (Proposition 4.1).
    #[must_use]
    pub fn swapped(&self) -> Self {
        Self {
            reversal_input: self.reversal_output,
            reversal_output: self.reversal_input,
            direction: self.direction,
            last_input: self.last_output,
            last_output: self.last_input,
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn direction_rule() {
        let mut m = Memory::first_sample(0.0_f64, None);
        assert_eq!(m.direction, Direction::Rising);
        m.last_input = 1.0;
        m.last_output = 0.9;
        m.observe(1.0, None); // zero step keeps the direction
        assert_eq!(m.direction, Direction::Rising);
        assert_eq!(m.reversal_input, 0.0);
        m.observe(0.5, None); // falls: (1.0, 0.9) becomes the reversal point
        assert_eq!(m.direction, Direction::Falling);
        assert_eq!((m.reversal_input, m.reversal_output), (1.0, 0.9));
        assert!((m.m() - 0.1).abs() < 1e-15);
    }

    #[test]
    fn band_is_checked() {
        assert!(Memory::at_rest(0.0, 0.2, Direction::Rising, 0.1_f64).is_err());
        assert!(Memory::at_rest(0.0, 0.1, Direction::Rising, 0.1_f64).is_ok());
        assert!(Memory::at_rest(f64::NAN, 0.0, Direction::Rising, 0.1_f64).is_err());
    }

    /// A memory no operator produces, the last input on the wrong side of
    /// the reversal for its direction, is refused; what operators produce is accepted.
    #[test]
    fn a_last_input_off_the_branch_is_refused() {
        let mut m = Memory::at_rest(0.5, 0.45, Direction::Rising, 0.1_f64).unwrap();
        assert!(m.validate(0.1).is_ok());
        m.reversal_input = 1e300;
        m.reversal_output = 1e300;
        assert!(matches!(
            m.validate(0.1),
            Err(Error::InvalidParameter {
                name: "last_input",
                ..
            })
        ));
        let mut m = Memory::at_rest(0.5, 0.55, Direction::Falling, 0.1_f64).unwrap();
        m.last_input = 0.7;
        m.last_output = 0.65;
        assert!(m.validate(0.1).is_err());
        // Every memory an operator leaves behind is accepted.
        let mut h = crate::Hysteresis::new(0.1_f64, 8.0).unwrap();
        for k in 0..2000 {
            let x = (f64::from(k) * 0.013).sin() * (1.0 + 0.3 * (f64::from(k) * 0.002).cos());
            crate::Operator::step(&mut h, x);
            let memory = crate::Operator::memory(&h).unwrap();
            assert!(memory.validate(0.1).is_ok(), "{memory:?} at {k}");
        }
    }
}
