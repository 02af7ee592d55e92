//! The shaped model out = ψ_out(H(k1, k2)[ψ_in(in)]) (Section 4.3) and its exact inverse
//! in = ψ_in⁻¹(H⁻¹(k1, k2)[ψ_out⁻¹(out_desired)]).

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use crate::error::Error;
use crate::k2law::{ConstantK2, K2Law};
use crate::memory::Memory;
use crate::operator::Operator;
use crate::parametric::{Hysteresis, InverseHysteresis};
use crate::real::Real;
use crate::sample::Sample;
use crate::shaping::{Identity, Shaping};

/// A shaped hysteresis model: input shaping `I`, the direct operator with k2 law `K`, output
/// shaping `O`. With k2 = φ(·), φ takes the operator's input ψ_in(in).
///
/// # Examples
/// Example 1 of the paper with linear shaping, out = 1.4 · H(0.14, 8)[0.2 · in]:
/// ```
/// use hyst_core::{Affine, Hysteresis, ShapedModel, Operator};
/// let mut model = ShapedModel::new(
///     Affine::new(0.2_f64, 0.0)?,
///     Hysteresis::new(0.14, 8.0)?,
///     Affine::new(1.4, 0.0)?,
/// )?;
/// let mut inverse = model.inverse();
/// for k in 0..200 {
///     let desired = 1.2 * (k as f64 * 0.05).sin();
///     let command = inverse.step(desired);
///     assert!((model.step(command) - desired).abs() < 1e-12);
/// }
/// # Ok::<(), hyst_core::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct ShapedModel<T, I = Identity, K = ConstantK2<T>, O = Identity> {
    input: I,
    operator: Hysteresis<T, K>,
    output: O,
}

/// The exact inverse ψ_in⁻¹ ∘ H⁻¹ ∘ ψ_out⁻¹ of a [`ShapedModel`] (Section 4.3): it turns a
/// desired output into the command that produces it.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct InverseShapedModel<T, I = Identity, K = ConstantK2<T>, O = Identity> {
    input: I,
    operator: InverseHysteresis<T, K>,
    output: O,
}

impl<T: Real, I: Shaping<T>, K: K2Law<T>, O: Shaping<T>> ShapedModel<T, I, K, O> {
    /// Composes ψ_out ∘ H ∘ ψ_in.
    ///
    /// # Errors
    /// The shaping functions' own validation errors.
    pub fn new(input: I, operator: Hysteresis<T, K>, output: O) -> Result<Self, Error> {
        input.validate()?;
        output.validate()?;
        Ok(Self {
            input,
            operator,
            output,
        })
    }

    /// Composes parts already checked (a model whose gains and offsets were changed within
    /// their valid ranges: [`crate::adaptive`]).
    pub(crate) fn from_parts(input: I, operator: Hysteresis<T, K>, output: O) -> Self {
        Self {
            input,
            operator,
            output,
        }
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
    /// The direct operator (with its memory).
    #[must_use]
    pub fn operator(&self) -> &Hysteresis<T, K> {
        &self.operator
    }

    /// Sets the operator's memory as it is (a start rule's, checked by its maker).
    pub(crate) fn restore(&mut self, memory: Option<Memory<T>>) {
        self.operator.restore(memory);
    }
}

impl<T: Real, I: Shaping<T>, K: K2Law<T>, O: Shaping<T>> Operator<T> for ShapedModel<T, I, K, O> {
    /// The memory of the operator H (Definition 2.1, on the operator's input and output).
    type Memory = Option<Memory<T>>;

    /// One sample (plain or jet): ψ_out(H[ψ_in(x)]).
    ///
    /// # Errors
    /// As [`Hysteresis`]'s [`Operator::try_step`] (ψ_in(x) beyond the float range is
    /// [`Error::NonFiniteInput`]), and [`Error::NonFiniteOutput`] when ψ_out overflows; the
    /// memory is then unchanged.
    #[inline]
    fn try_step<S: Sample<T>>(&mut self, x: S) -> Result<S, Error> {
        let v = self.input.apply(x);
        let output = &self.output;
        self.operator.step_into(x, v, |u| output.apply(u))
    }

    fn last_output(&self) -> Option<T> {
        self.operator.last_output().map(|u| self.output.apply(u))
    }

    forward_memory!(operator, Option<Memory<T>>);
}

impl<T: Real, I: Shaping<T> + Clone, K: K2Law<T> + Clone, O: Shaping<T> + Clone>
    ShapedModel<T, I, K, O>
{
    /// The exact inverse of this model, with the operator's memory mirrored so that from here
    /// on `model.step(inverse.step(y))` = y (Proposition 4.1 through the shaping).
    #[must_use]
    pub fn inverse(&self) -> InverseShapedModel<T, I, K, O> {
        InverseShapedModel {
            input: self.input.clone(),
            operator: self.operator.inverse(),
            output: self.output.clone(),
        }
    }
}

impl<T: Real, I: Shaping<T>, K: K2Law<T>, O: Shaping<T>> InverseShapedModel<T, I, K, O> {
    /// Puts back a memory saved from this inverse (no check: it was its own).
    pub(crate) fn restore(&mut self, memory: Option<Memory<T>>) {
        self.operator.restore(memory);
    }

    /// Sets the memory that mirrors the direct operator's `memory` (a start rule's).
    pub(crate) fn restore_direct(&mut self, memory: Option<Memory<T>>) {
        self.operator.restore(memory.map(|m| m.swapped()));
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

    /// The inverse operator (with its memory).
    #[must_use]
    pub fn operator(&self) -> &InverseHysteresis<T, K> {
        &self.operator
    }
}

impl<T: Real, I: Shaping<T>, K: K2Law<T> + Clone, O: Shaping<T>> Operator<T>
    for InverseShapedModel<T, I, K, O>
{
    /// The memory of the inverse operator H⁻¹ (on its input u_d and output v).
    type Memory = Option<Memory<T>>;

    /// One sample (plain or jet): ψ_in⁻¹(H⁻¹[ψ_out⁻¹(y)]). With a jet of the desired output it
    /// gives the command and its time derivatives.
    ///
    /// # Errors
    /// [`Error::OutOfRange`] when y has no preimage under a saturating ψ_out;
    /// [`Error::Unreachable`] when the operator output v it needs lies beyond a saturating
    /// ψ_in's range (told in output units: y and the outputs reachable from the state); as
    /// [`InverseHysteresis`]'s [`Operator::try_step`]. The memory is then unchanged.
    /// [`Error::NonFiniteOutput`] when the command ψ_in⁻¹(v) is beyond the float range.
    fn try_step<S: Sample<T>>(&mut self, y: S) -> Result<S, Error> {
        let ud = self.output.invert_sample(y)?;
        let (v, memory) = self.operator.compute(ud)?;
        let x = self.input.invert_sample(v).map_err(|e| {
            let direct = self.operator.direct();
            unreachable_output(y.value(), e, &self.output, |w| direct.peek(w))
        })?;
        if !x.all_finite() {
            return Err(Error::NonFiniteOutput {
                input: y.value().as_f64(),
                output: x.value().as_f64(),
            });
        }
        self.operator.commit(memory);
        Ok(x)
    }

    /// The last command (ψ_in⁻¹ of the operator's last output).
    fn last_output(&self) -> Option<T> {
        self.operator
            .last_output()
            .and_then(|v| self.input.invert(v).ok())
    }

    forward_memory!(operator, Option<Memory<T>>);
}

/// ψ_in's refusal `e` of the operator output an inverse needs for the desired output `y`, told
/// in the model's output units: an [`Error::OutOfRange`] of ψ_in (range (a, b) in operator
/// units) becomes [`Error::Unreachable`] with the outputs ψ_out(`reach`(a)) and
/// ψ_out(`reach`(b)), where `reach` is the direct operator's output for an input from the state
/// the inverse is in (the ends of what it can reach: the branches are monotone). An end where
/// `reach` fails, or that is infinite, is ψ_out of the end itself. Other errors pass unchanged.
pub fn unreachable_output<T: Real, O: Shaping<T>>(
    y: T,
    e: Error,
    output: &O,
    reach: impl Fn(T) -> Result<T, Error>,
) -> Error {
    let Error::OutOfRange { min, max, .. } = e else {
        return e;
    };
    let end = |w: f64| {
        let w = T::from_f64(w);
        let u = if w.is_finite() {
            reach(w).unwrap_or(w)
        } else {
            w
        };
        let out = output.apply(u);
        // ψ_out of an infinite end (a Langevin's limit): the end itself.
        if out.is_nan() { w } else { out }.as_f64()
    };
    Error::Unreachable {
        value: y.as_f64(),
        min: end(min),
        max: end(max),
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::panic)]
    use super::*;
    use crate::shaping::{Affine, Tanh};
    use std::string::ToString;

    /// y = 10 · H(0.1, 8)[tanh(x)]: the operator input lies in (−1, 1), so from a state on the
    /// lower asymptote (rising) the outputs stay below 10 · (1 − 0.1) = 9. A desired output
    /// beyond is refused in output units, with what the state reaches; the memory is unchanged.
    #[test]
    fn beyond_a_saturating_input_shaping_is_refused_in_output_units() {
        let model = ShapedModel::new(
            Tanh::new(1.0_f64, 1.0).unwrap(),
            Hysteresis::new(0.1, 8.0)
                .unwrap()
                .with_initial_state(0.1, 0.0, crate::memory::Direction::Rising)
                .unwrap(),
            Affine::new(10.0, 0.0).unwrap(),
        )
        .unwrap();
        let mut inverse = model.inverse();
        for y in [0.0, 5.0, 8.5] {
            inverse.try_step(y).unwrap();
        }
        let before = inverse.memory();
        let Err(Error::Unreachable { value, min, max }) = inverse.try_step(9.5) else {
            panic!("not refused as unreachable");
        };
        assert_eq!(value, 9.5);
        assert!(
            (max - 9.0).abs() < 1e-9 && (min + 9.0).abs() < 1e-5,
            "{min} {max}"
        );
        assert_eq!(inverse.memory(), before);
        let text = Error::Unreachable { value, min, max }.to_string();
        assert_eq!(
            text,
            "desired output 9.5 is outside the range (-9.000002, 9.000000) of outputs the model \
             can reach from its state (its input shaping's range is bounded)"
        );
        // Inside the reach: a command.
        assert!(inverse.try_step(8.9).unwrap().is_finite());
    }
}
