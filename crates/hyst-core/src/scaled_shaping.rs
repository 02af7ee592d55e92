//! A shaping function with gains and offsets around it, so that any of the core's shapes can
//! carry the input/output offsets and the scale of measured data:
//! ψ(x) = post_gain · shape(pre_gain · x + pre_offset) + post_offset.

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use crate::any_shaping::{AffineShaping, AnyShaping};
use crate::error::{finite, positive_normal, Error};
use crate::real::Real;
use crate::sample::Sample;
use crate::shaping::Shaping;

/// ψ(x) = `post_gain` · shape(`pre_gain` · x + `pre_offset`) + `post_offset`, strictly
/// increasing when both gains are > 0 and the shape is valid (Section 4.3's shaping functions
/// with the scale and offsets of measured data; the form of a fitted model's ψ_in and ψ_out,
/// serialized in model files).
///
/// The shape is any of the built-in ones ([`AnyShaping`], the default), or only the affine
/// ones ([`AffineShaping`]: the same arithmetic, and a firmware links no nonlinear shape).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct ScaledShaping<T, S = AnyShaping<T>> {
    /// Scale applied to x before the shape (1 / units of x), > 0 and a normal float (the
    /// inverse divides by it).
    pub pre_gain: T,
    /// Offset added after that scale (dimensionless shape units).
    pub pre_offset: T,
    /// The core shaping function.
    pub shape: S,
    /// Scale of the shape's value (units of ψ), > 0 and a normal float (the inverse divides
    /// by it: a subnormal gain turns every desired output into an infinite command).
    pub post_gain: T,
    /// Offset of ψ (units of ψ).
    pub post_offset: T,
}

impl<T: Real, S: Shaping<T> + Default> ScaledShaping<T, S> {
    /// The identity.
    #[must_use]
    pub fn identity() -> Self {
        Self {
            pre_gain: T::one(),
            pre_offset: T::zero(),
            shape: S::default(),
            post_gain: T::one(),
            post_offset: T::zero(),
        }
    }
}

impl<T: Real> ScaledShaping<T, AffineShaping<T>> {
    /// The same function with its shape as a [`AffineShaping`].
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] when the shape is not identity or affine.
    pub fn linear(s: &ScaledShaping<T>) -> Result<Self, Error> {
        Ok(Self {
            pre_gain: s.pre_gain,
            pre_offset: s.pre_offset,
            shape: AffineShaping::try_from(s.shape)?,
            post_gain: s.post_gain,
            post_offset: s.post_offset,
        })
    }
}

impl<T: Real, S: Shaping<T>> ScaledShaping<T, S> {
    /// Builds and validates a scaled shaping function.
    ///
    /// # Errors
    /// As [`Shaping::validate`].
    pub fn new(
        pre_gain: T,
        pre_offset: T,
        shape: S,
        post_gain: T,
        post_offset: T,
    ) -> Result<Self, Error> {
        let w = Self {
            pre_gain,
            pre_offset,
            shape,
            post_gain,
            post_offset,
        };
        w.validate()?;
        Ok(w)
    }

    /// The shape's refusal to invert `y` told in the units of ψ: the value given and ψ's range,
    /// not the shape's own (a desired output 2 beyond 1.32 · tanh(·) is "2 is outside the range
    /// (-1.32, 1.32)", not "1.51 is outside the range (-1, 1)").
    fn in_own_units(&self, y: T, e: Error) -> Error {
        match e {
            // In T: f64 arithmetic would link soft double-precision maths into an f32
            // firmware (the Cortex-M4F has no double FPU) for an error message.
            Error::OutOfRange { name, min, max, .. } => {
                let own = |m: f64| (self.post_gain * T::from_f64(m) + self.post_offset).as_f64();
                Error::OutOfRange {
                    name,
                    value: y.as_f64(),
                    min: own(min),
                    max: own(max),
                }
            }
            other => other,
        }
    }

    /// The shape's argument for x.
    fn inner(&self, x: T) -> T {
        self.pre_gain * x + self.pre_offset
    }
}

impl<T: Real, S: Shaping<T>> Shaping<T> for ScaledShaping<T, S> {
    fn name(&self) -> &'static str {
        self.shape.name()
    }
    fn eval<X: Sample<T>>(&self, x: X) -> X {
        self.shape.eval(x * self.pre_gain + self.pre_offset) * self.post_gain + self.post_offset
    }
    fn domain(&self) -> (T, T) {
        let (lo, hi) = self.shape.domain();
        (
            (lo - self.pre_offset) / self.pre_gain,
            (hi - self.pre_offset) / self.pre_gain,
        )
    }
    fn apply<X: Sample<T>>(&self, x: X) -> X {
        self.shape.apply(x * self.pre_gain + self.pre_offset) * self.post_gain + self.post_offset
    }
    fn invert_in_domain(&self, y: T) -> Result<T, Error> {
        let z = self
            .shape
            .invert_in_domain((y - self.post_offset) / self.post_gain)
            .map_err(|e| self.in_own_units(y, e))?;
        Ok((z - self.pre_offset) / self.pre_gain)
    }
    fn invert(&self, y: T) -> Result<T, Error> {
        if !y.is_finite() {
            return Err(Error::NonFiniteInput { value: y.as_f64() });
        }
        let z = self
            .shape
            .invert((y - self.post_offset) / self.post_gain)
            .map_err(|e| self.in_own_units(y, e))?;
        Ok((z - self.pre_offset) / self.pre_gain)
    }
    fn validate(&self) -> Result<(), Error> {
        positive_normal("pre_gain", self.pre_gain)?;
        finite("pre_offset", self.pre_offset)?;
        positive_normal("post_gain", self.post_gain)?;
        finite("post_offset", self.post_offset)?;
        self.shape.validate()
    }
    fn lipschitz(&self, lo: T, hi: T) -> T {
        self.post_gain * self.pre_gain * self.shape.lipschitz(self.inner(lo), self.inner(hi))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shaping::Tanh;

    #[test]
    fn out_of_range_is_told_in_the_units_of_psi() -> Result<(), Error> {
        // ψ(x) = 2 · tanh(x) + 1: range (-1, 3).
        let psi = ScaledShaping::new(1.0, 0.0, AnyShaping::Tanh(Tanh::new(1.0, 1.0)?), 2.0, 1.0)?;
        let expected = Err(Error::OutOfRange {
            name: "tanh",
            value: 3.5,
            min: -1.0,
            max: 3.0,
        });
        assert_eq!(psi.invert(3.5), expected);
        assert_eq!(psi.invert_in_domain(3.5), expected);
        assert!((psi.invert(2.0)? - 0.5_f64.atanh()).abs() < 1e-15);
        Ok(())
    }
}
