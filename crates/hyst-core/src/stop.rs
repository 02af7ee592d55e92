//! The stop form out = ψ_out(v − H(k1, k2)\[v\]) + c·v, v = ψ_in(in): the operator's distance
//! from its own input, a smooth stop (elastic–plastic) operator bounded by |v − H\[v\]| ≤ k1.
//!
//! Where H's loop runs counterclockwise (its output lags the input), v − H\[v\] runs clockwise:
//! positive while the input rises, negative while it falls, reaching ±k1 after a travel of a few
//! 1/k2 past each reversal. That is friction against position (a Dahl-like model: pre-sliding
//! displacement, then sliding at the Coulomb level), and any clockwise loop; the linear term c·v
//! carries a stiffness or a trend (with c = −gain it is −gain · H\[v\], the operator loop upside
//! down).

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use crate::error::Error;
use crate::k2law::{ConstantK2, K2Law};
use crate::memory::Memory;
use crate::operator::Operator;
use crate::parametric::Hysteresis;
use crate::real::Real;
use crate::sample::Sample;
use crate::shaping::{Identity, Shaping};

/// The stop form of a shaped model: input shaping `I`, the direct operator with k2 law `K`,
/// output shaping `O` and the linear coefficient c (output units per operator unit).
///
/// # Examples
/// Coulomb-like friction of level 2 N (gain × k1 = 200 N/mm × 0.01 mm), reached after a
/// pre-sliding travel of about 2 k1 = 0.02 mm past a reversal:
/// ```
/// use hyst_core::{Affine, Hysteresis, Identity, Operator, Stop};
/// let mut friction = Stop::new(Identity, Hysteresis::new(0.01_f64, 1000.0)?, Affine::new(200.0, 0.0)?, 0.0)?;
/// let mut force = [0.0; 101];
/// for (k, f) in force.iter_mut().enumerate() {
///     *f = friction.step(0.01 * k as f64); // extending from 0 to 1 mm
/// }
/// assert!((force[100] - 2.0).abs() < 1e-12); // sliding: the Coulomb level
/// let retracting = friction.step(0.99);
/// assert!(retracting < force[100]); // the force turns with the motion
/// # Ok::<(), hyst_core::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Stop<T, I = Identity, K = ConstantK2<T>, O = Identity> {
    input: I,
    operator: Hysteresis<T, K>,
    output: O,
    linear: T,
}

impl<T: Real, I: Shaping<T>, K: K2Law<T>, O: Shaping<T>> Stop<T, I, K, O> {
    /// Composes ψ_out(v − H\[v\]) + c·v with v = ψ_in(in).
    ///
    /// # Errors
    /// The shaping functions' own validation errors; [`Error::InvalidParameter`] for a
    /// non-finite `linear`.
    pub fn new(input: I, operator: Hysteresis<T, K>, output: O, linear: T) -> Result<Self, Error> {
        input.validate()?;
        output.validate()?;
        if !linear.is_finite() {
            return Err(Error::InvalidParameter {
                name: "linear",
                value: linear.as_f64(),
                expected: "a finite coefficient of the linear term",
            });
        }
        Ok(Self {
            input,
            operator,
            output,
            linear,
        })
    }

    /// The input shaping ψ_in.
    #[must_use]
    pub fn input_shaping(&self) -> &I {
        &self.input
    }
    /// The output shaping ψ_out.
    #[must_use]
    pub fn output_shaping(&self) -> &O {
        &self.output
    }
    /// The direct operator H (with its memory).
    #[must_use]
    pub fn operator(&self) -> &Hysteresis<T, K> {
        &self.operator
    }
    /// The coefficient c of the linear term (output units per operator unit).
    #[must_use]
    pub fn linear(&self) -> T {
        self.linear
    }

    /// Sets the operator's memory as it is (a start rule's, checked by its maker).
    pub(crate) fn restore(&mut self, memory: Option<Memory<T>>) {
        self.operator.restore(memory);
    }
}

impl<T: Real, I: Shaping<T>, K: K2Law<T>, O: Shaping<T>> Operator<T> for Stop<T, I, K, O> {
    /// The memory of the operator H (Definition 2.1, on the operator's input and output).
    type Memory = Option<Memory<T>>;

    /// One sample (plain or jet): ψ_out(v − H\[v\]) + c·v, v = ψ_in(x).
    ///
    /// # Errors
    /// As [`Hysteresis`]'s [`Operator::try_step`], and [`Error::NonFiniteOutput`] when the
    /// output overflows; the memory is then unchanged.
    #[inline]
    fn try_step<S: Sample<T>>(&mut self, x: S) -> Result<S, Error> {
        let v = self.input.apply(x);
        let (output, linear) = (&self.output, self.linear);
        self.operator
            .step_into(x, v, |u| output.apply(v - u) + v * linear)
    }

    fn last_output(&self) -> Option<T> {
        let m = self.operator.memory()?;
        let (v, u) = (m.last_input, m.last_output);
        Some(self.output.apply(v - u) + v * self.linear)
    }

    forward_memory!(operator, Option<Memory<T>>);
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::jet::Jet;
    use crate::shaping::Affine;
    extern crate std;
    use std::vec::Vec;

    fn input() -> impl Iterator<Item = f64> {
        (0..3000).map(|k| {
            let t = k as f64 * 0.01;
            (0.5 + 0.02 * t) * (1.7 * t).sin() + 0.3 * (0.4 * t).cos()
        })
    }

    #[test]
    fn equals_the_input_minus_the_operator_through_the_shaping() {
        let h = Hysteresis::new(0.2, 6.0).unwrap();
        let mut stop = Stop::new(
            Affine::new(1.5, 0.1).unwrap(),
            h,
            Affine::new(3.0, -1.0).unwrap(),
            0.4,
        )
        .unwrap();
        let mut op = h;
        for x in input() {
            let v = 1.5 * x + 0.1;
            let expected = 3.0 * (v - op.step(v)) - 1.0 + 0.4 * v;
            assert_eq!(stop.step(x), expected);
            assert_eq!(stop.last_output(), Some(expected));
        }
    }

    #[test]
    fn the_loop_runs_clockwise_and_stays_in_the_band() {
        let mut stop =
            Stop::new(Identity, Hysteresis::new(0.2, 6.0).unwrap(), Identity, 0.0).unwrap();
        let xs: Vec<f64> = input().collect();
        let mut ys = xs.clone();
        stop.process_in_place(&mut ys);
        // ∮ y dx > 0 for a clockwise loop.
        let area: f64 = xs
            .windows(2)
            .zip(ys.windows(2))
            .map(|(x, y)| 0.5 * (y[0] + y[1]) * (x[1] - x[0]))
            .sum();
        assert!(area > 0.0, "{area}");
        assert!(ys.iter().all(|y| y.abs() <= 0.2 + 1e-15));
    }

    #[test]
    fn jets_carry_the_time_derivative() {
        let mut a = Stop::new(
            Identity,
            Hysteresis::new(0.2, 6.0).unwrap(),
            Affine::new(2.0, 0.0).unwrap(),
            0.5,
        )
        .unwrap();
        let mut b = a;
        let (x, dx, h) = (0.3, 1.0, 1e-6);
        a.step(0.0);
        b.step(0.0);
        let j = a
            .try_step(Jet::<f64, 1>::from_derivatives(x, [dx]))
            .unwrap();
        let y1 = b.step(x + h * dx);
        let mut c = Stop::new(
            Identity,
            Hysteresis::new(0.2, 6.0).unwrap(),
            Affine::new(2.0, 0.0).unwrap(),
            0.5,
        )
        .unwrap();
        c.step(0.0);
        let y0 = c.step(x);
        assert_eq!(j.value(), y0);
        assert!((j.derivatives()[0] - (y1 - y0) / h).abs() < 1e-4);
    }

    #[test]
    fn a_non_finite_linear_term_is_refused() {
        let h = Hysteresis::new(0.2, 6.0).unwrap();
        assert!(Stop::new(Identity, h, Identity, f64::NAN).is_err());
    }

    #[test]
    fn an_overflowing_output_leaves_the_memory() {
        let mut stop = Stop::new(
            Identity,
            Hysteresis::new(0.2, 6.0).unwrap(),
            Identity,
            1e300,
        )
        .unwrap();
        stop.step(0.1);
        let before = stop.memory();
        assert!(matches!(
            stop.try_step(1e10),
            Err(Error::NonFiniteOutput { .. })
        ));
        assert_eq!(stop.memory(), before);
    }
}
