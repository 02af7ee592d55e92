//! Saturation of a model whose output shaping is bounded (tanh, Langevin): the open range of
//! its output, the limits a compensator clamps desired outputs to ([`Saturation`]), and the
//! wrapper that clamps them ([`Saturated`]).

use hyst_core::{Error, Operator, Sample};

/// The fraction of a saturating output shaping's range, about its centre, that
/// [`ModelFile::saturation`](crate::file::ModelFile::saturation) lets the compensator ask for: a tanh reaches 99.9 % of its
/// saturation level at atanh(0.999) ≈ 3.8 times its scale, so the command stays finite and
/// moderate, while the last 0.1 % would need a command growing without bound.
pub const SATURATION_FRACTION: f64 = 0.999;

/// What a saturating output shaping lets the compensator reach (see [`ModelFile::saturation`](crate::file::ModelFile::saturation)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Saturation {
    /// The output shaping function ("tanh", "langevin").
    pub shaping: &'static str,
    /// The open range (lo, hi) of the model's output: no command produces lo, hi or beyond.
    pub range: (f64, f64),
    /// The desired outputs a compensator may be asked for: [`SATURATION_FRACTION`] of `range`
    /// about its centre, widened to the outputs over the model's fitted input range
    /// (`widened`). Clamping a desired output into these limits keeps the command finite and
    /// the map from desired output to command monotone.
    pub limits: (f64, f64),
    /// Whether the limits were widened beyond [`SATURATION_FRACTION`] of the range to cover
    /// the outputs the model gives over its fitted input range.
    pub widened: bool,
}

impl Saturation {
    /// How the limits were chosen, for messages: "99.9 % of the range about its centre", and
    /// when widened, that they cover the model's outputs over its fitted input range.
    #[must_use]
    pub fn rule(&self) -> String {
        let fraction = format!(
            "{} % of the range about its centre",
            100.0 * SATURATION_FRACTION
        );
        if self.widened {
            format!(
                "{fraction}, widened to every output the model gives over its fitted input range"
            )
        } else {
            fraction
        }
    }
}

/// A compensator whose desired outputs are clamped into a saturating model's limits
/// ([`Saturation::limits`]) before `inner` sees them, as `hyst run --saturate`
/// clamps them: a finite value beyond the limits steps `inner` with the nearer limit (a jet
/// with zero derivatives: a clamped desired output stands still); non-finite values reach
/// `inner`, which refuses them. With `limits` `None` it is `inner` unchanged.
#[derive(Clone, Debug)]
pub struct Saturated<O> {
    /// The compensator.
    pub inner: O,
    /// The clamp limits (lo, hi), lo < hi; `None`: nothing is clamped.
    pub limits: Option<(f64, f64)>,
    /// How many accepted samples were clamped since the wrapper was made or reset.
    pub clamped: u64,
}

impl<O> Saturated<O> {
    /// `inner` with desired outputs clamped into `limits` (`None`: not clamped).
    #[must_use]
    pub fn new(inner: O, limits: Option<(f64, f64)>) -> Self {
        Self {
            inner,
            limits,
            clamped: 0,
        }
    }

    /// `x` clamped into the limits when it is finite and beyond them; `None` otherwise.
    #[must_use]
    pub fn clamp(&self, x: f64) -> Option<f64> {
        let (lo, hi) = self.limits?;
        (x.is_finite() && (x < lo || x > hi)).then(|| x.clamp(lo, hi))
    }
}

impl<O: Operator<f64>> Operator<f64> for Saturated<O> {
    type Memory = O::Memory;

    /// One sample of `inner`, clamped first when it is beyond the limits.
    ///
    /// # Errors
    /// `inner`'s error for this sample (the memory and the count are then unchanged).
    fn try_step<S: Sample<f64>>(&mut self, x: S) -> Result<S, Error> {
        match self.clamp(x.value()) {
            Some(v) => {
                let y = self.inner.try_step(S::constant(v))?;
                self.clamped += 1;
                Ok(y)
            }
            None => self.inner.try_step(x),
        }
    }

    fn last_output(&self) -> Option<f64> {
        self.inner.last_output()
    }

    /// `inner` back to its initial state, and the count to 0.
    fn reset(&mut self) {
        self.inner.reset();
        self.clamped = 0;
    }

    fn memory(&self) -> O::Memory {
        self.inner.memory()
    }

    /// # Errors
    /// `inner`'s check of the memory.
    fn set_memory(&mut self, memory: O::Memory) -> Result<(), Error> {
        self.inner.set_memory(memory)
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use hyst_core::InverseHysteresis;

    #[test]
    fn values_beyond_the_limits_step_the_compensator_with_the_limit() {
        let plain = InverseHysteresis::new(0.2, 8.0).unwrap();
        let mut clamped = Saturated::new(plain, Some((-1.0, 1.0)));
        let mut reference = plain;
        for (x, seen) in [(0.5, 0.5), (3.0, 1.0), (-7.0, -1.0), (1.0, 1.0), (0.2, 0.2)] {
            assert_eq!(
                clamped.try_step(x).unwrap().to_bits(),
                reference.try_step(seen).unwrap().to_bits()
            );
        }
        assert_eq!(clamped.clamped, 2);
        // Non-finite values are refused by the compensator, not clamped; nothing changes.
        let before = clamped.memory();
        assert!(clamped.try_step(f64::INFINITY).is_err());
        assert_eq!((clamped.memory(), clamped.clamped), (before, 2));
        clamped.reset();
        assert_eq!((clamped.memory(), clamped.clamped), (None, 0));
        // Without limits: the compensator unchanged.
        let mut open = Saturated::new(plain, None);
        assert_eq!(
            open.try_step(3.0).unwrap(),
            plain.clone().try_step(3.0).unwrap()
        );
        assert_eq!(open.clamped, 0);
    }
}
