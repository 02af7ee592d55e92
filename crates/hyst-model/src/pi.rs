//! The Prandtl–Ishlinskii baseline model: y = c + w0 x + Σ w_i play_{r_i}\[x\] (play operators of
//! half-widths r_i, see `hyst_core::prandtl_ishlinskii`), optionally followed by a monotone
//! output polynomial P: y = P(PI\[x\]), whose inverse PI⁻¹ ∘ P⁻¹ is still exact. Here the model
//! is plain data (model files) that becomes the core's runnable operators ([`PiOperator`]);
//! hyst-fit's `pi_fit` identifies it from data.

use hyst_core::{
    Error, InverseShapedPrandtlIshlinskii, Operator, PlayMemory, Polynomial, PrandtlIshlinskii,
    Sample, ShapedPrandtlIshlinskii,
};
use serde::{Deserialize, Serialize};

/// The largest number of plays (the core type's capacity).
pub const MAX_PLAYS: usize = 128;

/// The core Prandtl–Ishlinskii sum used for the baseline.
pub type CorePi = PrandtlIshlinskii<f64, MAX_PLAYS>;
/// The core type of a PI model with an output polynomial, y = P(PI\[x\]).
pub type CoreShapedPi = ShapedPrandtlIshlinskii<f64, MAX_PLAYS>;
/// Its exact inverse PI⁻¹ ∘ P⁻¹.
pub type CoreShapedPiInverse = InverseShapedPrandtlIshlinskii<f64, MAX_PLAYS>;

/// A Prandtl–Ishlinskii model or its exact inverse, ready to run (see [`PiModel::operator`]).
#[derive(Clone, Debug)]
pub enum PiOperator {
    /// The Prandtl–Ishlinskii sum PI\[x\]; as its own inverse type, PI⁻¹\[y\] too.
    Plain(CorePi),
    /// P(PI\[x\]).
    Shaped(CoreShapedPi),
    /// PI⁻¹\[P⁻¹(y)\].
    ShapedInverse(CoreShapedPiInverse),
}

/// Forwards one call to whichever core operator a [`PiOperator`] holds.
macro_rules! each {
    ($self:expr, $op:ident => $e:expr) => {
        match $self {
            PiOperator::Plain($op) => $e,
            PiOperator::Shaped($op) => $e,
            PiOperator::ShapedInverse($op) => $e,
        }
    };
}

impl Operator<f64> for PiOperator {
    type Memory = PlayMemory<f64, MAX_PLAYS>;

    /// One sample: the output (or command), with time derivatives when `x` is a jet.
    ///
    /// # Errors
    /// The core's error for this sample (the memory is then unchanged).
    fn try_step<S: Sample<f64>>(&mut self, x: S) -> Result<S, Error> {
        each!(self, op => op.try_step(x))
    }

    fn last_output(&self) -> Option<f64> {
        each!(self, op => op.last_output())
    }

    fn reset(&mut self) {
        each!(self, op => op.reset());
    }

    fn memory(&self) -> Self::Memory {
        each!(self, op => op.memory())
    }

    /// # Errors
    /// The core's check of the memory.
    fn set_memory(&mut self, memory: Self::Memory) -> Result<(), Error> {
        each!(self, op => op.set_memory(memory))
    }
}

/// The output polynomial of a Prandtl–Ishlinskii model (model files, `[prandtl-ishlinskii.output]`):
/// P(s) = c0 + c1 s + c2 s² + c3 s³ on [lo, hi] (the PI output range over the training data),
/// where it is strictly increasing; outside it continues along its tangents.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PiOutput {
    /// 2 or 3; coefficients above the degree are 0.
    pub degree: u8,
    /// c0..c3 (output units per PI-output unit to the power k).
    pub coefficients: [f64; 4],
    /// Lower end of the domain (PI-output units).
    pub lo: f64,
    /// Upper end of the domain.
    pub hi: f64,
}

impl PiOutput {
    /// The core polynomial, checked (degree 2 or 3, higher coefficients 0, strictly increasing
    /// on [lo, hi]).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the degree or the coefficient; the core's
    /// [`Polynomial::new`] errors.
    pub fn polynomial(&self) -> Result<Polynomial<f64>, Error> {
        if !(2..=3).contains(&self.degree) {
            return Err(Error::InvalidParameter {
                name: "output polynomial degree",
                value: f64::from(self.degree),
                expected: "2 or 3",
            });
        }
        for (k, c) in self.coefficients.iter().enumerate() {
            if k > usize::from(self.degree) && *c != 0.0 {
                return Err(Error::InvalidParameter {
                    name: "output polynomial coefficient above the degree",
                    value: *c,
                    expected: "0",
                });
            }
        }
        Polynomial::new(self.coefficients, self.lo, self.hi)
    }
}

/// A Prandtl–Ishlinskii model as plain data (model files).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PiModel {
    /// w0, the weight of the identity (output units per input unit).
    pub identity_weight: f64,
    /// Play thresholds r_i (input units), strictly increasing.
    pub thresholds: Vec<f64>,
    /// Play weights w_i (output units per input unit), ≥ 0 when fitted.
    pub weights: Vec<f64>,
    /// Output offset c (output units).
    pub offset: f64,
    /// The optional output polynomial P: y = P(PI\[x\]) (model file format version 2).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub output: Option<PiOutput>,
}

impl PiModel {
    /// The core PI sum (no history: the plays start at rest at the first sample), without the
    /// output polynomial.
    ///
    /// # Errors
    /// Invalid parameters (the core's checks), more than [`MAX_PLAYS`] plays.
    pub fn core(&self) -> Result<CorePi, Error> {
        CorePi::new(
            self.identity_weight,
            &self.thresholds,
            &self.weights,
            self.offset,
        )
    }

    /// The whole model, checked, ready to run: the PI sum and, when present, the output
    /// polynomial (no history: the plays start at rest at the first sample).
    ///
    /// # Errors
    /// As [`PiModel::core`] and [`PiOutput::polynomial`].
    pub fn operator(&self) -> Result<PiOperator, Error> {
        let pi = self.core()?;
        match &self.output {
            None => Ok(PiOperator::Plain(pi)),
            Some(o) => Ok(PiOperator::Shaped(CoreShapedPi::new(pi, o.polynomial()?)?)),
        }
    }

    /// The exact compensator (plays at rest at the first sample).
    ///
    /// # Errors
    /// As [`PiModel::operator`].
    pub fn inverse_operator(&self) -> Result<PiOperator, Error> {
        let pi = self.core()?;
        match &self.output {
            None => Ok(PiOperator::Plain(pi.inverse()?)),
            Some(o) => Ok(PiOperator::ShapedInverse(
                CoreShapedPi::new(pi, o.polynomial()?)?.inverse()?,
            )),
        }
    }

    /// Runs the model over one record.
    ///
    /// # Errors
    /// As [`PiModel::operator`], or a non-finite input.
    pub fn run(&self, input: &[f64]) -> Result<Vec<f64>, Error> {
        let mut op = self.operator()?;
        input.iter().map(|x| op.try_step(*x)).collect()
    }

    /// Runs the compensator (desired output → command) over one record; the plays start at
    /// rest at the first command.
    ///
    /// # Errors
    /// As [`PiModel::operator`], or a non-finite desired output.
    pub fn run_inverse(&self, desired: &[f64]) -> Result<Vec<f64>, Error> {
        let mut op = self.inverse_operator()?;
        desired.iter().map(|y| op.try_step(*y)).collect()
    }

    /// Number of free parameters: w0, the weights and the offset; with an output polynomial of
    /// degree d, d − 1 more (its c0 and c1 duplicate the PI's offset and scale, which are then
    /// fixed by normalising the PI output to the data's output range).
    #[must_use]
    pub fn parameter_count(&self) -> usize {
        self.weights.len() + 2 + self.output.map_or(0, |o| usize::from(o.degree) - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn output_polynomial_inverse_is_exact() -> Result<(), Error> {
        let model = PiModel {
            identity_weight: 0.3,
            thresholds: vec![0.1, 0.2, 0.4],
            weights: vec![0.5, 0.2, 0.1],
            offset: -0.2,
            output: Some(PiOutput {
                degree: 2,
                coefficients: [0.5, 1.0, 0.3, 0.0],
                lo: -1.0,
                hi: 1.0,
            }),
        };
        // A growing, wandering desired output over and beyond P's domain [−1, 1].
        let desired: Vec<f64> = (0..3000)
            .map(|k| {
                let t = k as f64 * 0.01;
                0.2 + (0.3 + 0.04 * t) * (1.7 * t).sin() + 0.1 * (4.1 * t).cos()
            })
            .collect();
        let command = model.run_inverse(&desired)?;
        let back = model.run(&command)?;
        for (k, (a, b)) in back.iter().zip(&desired).enumerate() {
            assert!((a - b).abs() < 1e-12, "{k}: {a} vs {b}");
        }
        // A bad degree or a non-monotone polynomial is refused, naming it.
        let mut bad = model.clone();
        if let Some(o) = bad.output.as_mut() {
            o.degree = 4;
        }
        assert!(bad
            .operator()
            .is_err_and(|e| e.to_string().contains("degree")));
        if let Some(o) = bad.output.as_mut() {
            o.degree = 2;
            o.coefficients = [0.0, 1.0, -0.8, 0.0];
        }
        assert!(bad.operator().is_err());
        Ok(())
    }
}
