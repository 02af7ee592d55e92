//! The shaped model out = ψ_out(H(k1, k2)[ψ_in(in)]) (Section 4.3) and its exact compensator
//! in = ψ_in⁻¹(H⁻¹(k1, k2)[ψ_out⁻¹(out_desired)]).

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use crate::{
    ConstantK2, Error, Hysteresis, Identity, InverseHysteresis, Jet, K2Law, Real, Scalar, Shaping,
};

/// A shaped hysteresis model: input shaping `I`, the direct operator with k2 law `K`, output
/// shaping `O`. With k2 = φ(·), φ takes the operator's input ψ_in(in).
///
/// # Examples
/// Example 1 of the paper with linear shaping, out = 1.4 · H(0.14, 8)[0.2 · in]:
/// ```
/// use hyst_core::{Affine, Hysteresis, Model};
/// let mut model = Model::new(
///     Affine::new(0.2_f64, 0.0)?,
///     Hysteresis::new(0.14, 8.0)?,
///     Affine::new(1.4, 0.0)?,
/// )?;
/// let mut compensator = model.inverse();
/// for k in 0..200 {
///     let desired = 1.2 * (k as f64 * 0.05).sin();
///     let command = compensator.step(desired);
///     assert!((model.step(command) - desired).abs() < 1e-12);
/// }
/// # Ok::<(), hyst_core::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Model<T, I = Identity, K = ConstantK2<T>, O = Identity> {
    input: I,
    operator: Hysteresis<T, K>,
    output: O,
}

/// The exact inverse of a [`Model`]: the feed-forward compensator that turns a desired output
/// into the command that produces it.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct InverseModel<T, I = Identity, K = ConstantK2<T>, O = Identity> {
    input: I,
    operator: InverseHysteresis<T, K>,
    output: O,
}

impl<T: Real, I: Shaping<T>, K: K2Law<T>, O: Shaping<T>> Model<T, I, K, O> {
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
    /// The direct operator, mutable (to restore a memory, say).
    pub fn operator_mut(&mut self) -> &mut Hysteresis<T, K> {
        &mut self.operator
    }

    /// One sample (plain or jet): ψ_out(H[ψ_in(x)]).
    ///
    /// # Errors
    /// As [`crate::Operator::try_step`]; the memory is then unchanged.
    #[inline]
    pub fn eval<S: Scalar<T>>(&mut self, x: S) -> Result<S, Error> {
        let v = self.input.apply(x);
        let u = self.operator.eval(v)?;
        Ok(self.output.apply(u))
    }

    /// One sample.
    ///
    /// # Errors
    /// As [`Model::eval`].
    #[inline]
    pub fn try_step(&mut self, x: T) -> Result<T, Error> {
        self.eval(x)
    }

    /// One sample; non-finite input holds the last output (the input itself before any output).
    #[inline]
    pub fn step(&mut self, x: T) -> T {
        match self.eval(x) {
            Ok(y) => y,
            Err(_) => self
                .operator
                .memory()
                .map_or(x, |m| self.output.apply(m.last_output)),
        }
    }

    /// One sample of a jet: output and its first `N` time derivatives.
    ///
    /// # Errors
    /// As [`Model::eval`].
    pub fn step_jet<const N: usize>(&mut self, x: Jet<T, N>) -> Result<Jet<T, N>, Error> {
        self.eval(x)
    }

    /// Forgets the history of the operator.
    pub fn reset(&mut self) {
        self.operator.reset();
    }
}

impl<T: Real, I: Shaping<T> + Clone, K: K2Law<T> + Clone, O: Shaping<T> + Clone> Model<T, I, K, O> {
    /// The exact compensator of this model, with the operator's memory mirrored so that from
    /// here on `model.step(compensator.step(y))` = y (Proposition 4.1 through the shaping).
    #[must_use]
    pub fn inverse(&self) -> InverseModel<T, I, K, O> {
        InverseModel {
            input: self.input.clone(),
            operator: self.operator.inverse(),
            output: self.output.clone(),
        }
    }
}

impl<T: Real, I: Shaping<T>, K: K2Law<T>, O: Shaping<T>> InverseModel<T, I, K, O> {
    /// The inverse operator (with its memory).
    #[must_use]
    pub fn operator(&self) -> &InverseHysteresis<T, K> {
        &self.operator
    }
    /// The inverse operator, mutable.
    pub fn operator_mut(&mut self) -> &mut InverseHysteresis<T, K> {
        &mut self.operator
    }

    /// One sample (plain or jet): ψ_in⁻¹(H⁻¹[ψ_out⁻¹(y)]). With a jet of the desired output it
    /// gives the command and its time derivatives.
    ///
    /// # Errors
    /// [`Error::OutOfRange`] when y (or the operator's output) has no preimage under a saturating
    /// shaping function, or as [`crate::Operator::try_step`]. The memory is then unchanged.
    pub fn eval<S: Scalar<T>>(&mut self, y: S) -> Result<S, Error> {
        let ud = self.output.invert_scalar(y)?;
        let (v, memory) = self.operator.compute(ud)?;
        let x = self.input.invert_scalar(v)?;
        self.operator.commit(memory);
        Ok(x)
    }

    /// One sample.
    ///
    /// # Errors
    /// As [`InverseModel::eval`].
    #[inline]
    pub fn try_step(&mut self, y: T) -> Result<T, Error> {
        self.eval(y)
    }

    /// One sample; a desired output that cannot be produced (non-finite, or beyond a saturating
    /// shaping function) holds the last command.
    pub fn step(&mut self, y: T) -> T {
        match self.eval(y) {
            Ok(x) => x,
            Err(_) => self
                .operator
                .memory()
                .and_then(|m| self.input.invert(m.last_output).ok())
                .unwrap_or(y),
        }
    }

    /// One sample of a jet.
    ///
    /// # Errors
    /// As [`InverseModel::eval`].
    pub fn step_jet<const N: usize>(&mut self, y: Jet<T, N>) -> Result<Jet<T, N>, Error> {
        self.eval(y)
    }

    /// Forgets the history of the operator.
    pub fn reset(&mut self) {
        self.operator.reset();
    }
}
