//! A shaping function with gains and offsets around it, so that any of the core's shapes can
//! carry the input/output offsets and the scale of measured data:
//! ψ(x) = post_gain · shape(pre_gain · x + pre_offset) + post_offset.

use hyst_core::{AnyShaping, Error, Sample, Shaping};
use serde::{Deserialize, Serialize};

/// ψ(x) = `post_gain` · shape(`pre_gain` · x + `pre_offset`) + `post_offset`, strictly
/// increasing when both gains are > 0 and the shape is valid. Serialized in model files.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ScaledShaping {
    /// Scale applied to x before the shape (1 / units of x), > 0.
    pub pre_gain: f64,
    /// Offset added after that scale (dimensionless shape units).
    pub pre_offset: f64,
    /// The core shaping function.
    pub shape: AnyShaping<f64>,
    /// Scale of the shape's value (units of ψ), > 0.
    pub post_gain: f64,
    /// Offset of ψ (units of ψ).
    pub post_offset: f64,
}

impl ScaledShaping {
    /// The identity.
    #[must_use]
    pub fn identity() -> Self {
        Self {
            pre_gain: 1.0,
            pre_offset: 0.0,
            shape: AnyShaping::Identity,
            post_gain: 1.0,
            post_offset: 0.0,
        }
    }

    /// Builds and validates a scaled shaping function.
    ///
    /// # Errors
    /// As [`Shaping::validate`].
    pub fn new(
        pre_gain: f64,
        pre_offset: f64,
        shape: AnyShaping<f64>,
        post_gain: f64,
        post_offset: f64,
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

    /// The shape's argument for x.
    fn inner(&self, x: f64) -> f64 {
        self.pre_gain * x + self.pre_offset
    }
}

fn check(name: &'static str, value: f64, positive: bool) -> Result<(), Error> {
    if value.is_finite() && (!positive || value > 0.0) {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            name,
            value,
            expected: if positive { "finite and > 0" } else { "finite" },
        })
    }
}

impl Shaping<f64> for ScaledShaping {
    fn name(&self) -> &'static str {
        self.shape.name()
    }
    fn eval<S: Sample<f64>>(&self, x: S) -> S {
        self.shape.eval(x * self.pre_gain + self.pre_offset) * self.post_gain + self.post_offset
    }
    fn domain(&self) -> (f64, f64) {
        let (lo, hi) = self.shape.domain();
        (
            (lo - self.pre_offset) / self.pre_gain,
            (hi - self.pre_offset) / self.pre_gain,
        )
    }
    fn apply<S: Sample<f64>>(&self, x: S) -> S {
        self.shape.apply(x * self.pre_gain + self.pre_offset) * self.post_gain + self.post_offset
    }
    fn invert_in_domain(&self, y: f64) -> Result<f64, Error> {
        let z = self
            .shape
            .invert_in_domain((y - self.post_offset) / self.post_gain)?;
        Ok((z - self.pre_offset) / self.pre_gain)
    }
    fn invert(&self, y: f64) -> Result<f64, Error> {
        if !y.is_finite() {
            return Err(Error::NonFiniteInput { value: y });
        }
        let z = self.shape.invert((y - self.post_offset) / self.post_gain)?;
        Ok((z - self.pre_offset) / self.pre_gain)
    }
    fn validate(&self) -> Result<(), Error> {
        check("pre_gain", self.pre_gain, true)?;
        check("pre_offset", self.pre_offset, false)?;
        check("post_gain", self.post_gain, true)?;
        check("post_offset", self.post_offset, false)?;
        self.shape.validate()
    }
    fn lipschitz(&self, lo: f64, hi: f64) -> f64 {
        self.post_gain * self.pre_gain * self.shape.lipschitz(self.inner(lo), self.inner(hi))
    }
}
