//! A fitted model ready to run sample by sample: the smooth model or the Prandtl–Ishlinskii
//! baseline (with or without its output polynomial), direct or as its exact compensator, behind
//! the core's one stepping interface [`Operator`].

use hyst_core::{
    AnyK2Law, Error, InverseShapedPrandtlIshlinskii, Memory, Operator, PlayMemory,
    PrandtlIshlinskii, Sample, ShapedPrandtlIshlinskii,
};

use crate::model::{CoreInverse, Shaped};
use crate::pi::MAX_OPERATORS;

/// The core Prandtl–Ishlinskii sum used for the baseline.
pub type CorePi = PrandtlIshlinskii<f64, MAX_OPERATORS>;
/// The core type of a PI model with an output polynomial, y = P(PI[x]).
pub type CoreShapedPi = ShapedPrandtlIshlinskii<f64, MAX_OPERATORS>;
/// Its exact inverse PI⁻¹ ∘ P⁻¹.
pub type CoreShapedPiInverse = InverseShapedPrandtlIshlinskii<f64, MAX_OPERATORS>;

/// A fitted model, runnable on plain numbers or jets (see `ModelFile::evaluator`).
#[derive(Clone, Debug)]
pub enum Evaluator {
    /// The smooth model ψ_out(H[ψ_in(x)]), or its stop form ψ_out(v − H[v]) + c·v,
    /// v = ψ_in(x) (friction; no inverse).
    Smooth(Box<Shaped<AnyK2Law<f64>>>),
    /// The smooth model's exact compensator ψ_in⁻¹(H⁻¹[ψ_out⁻¹(y)]).
    SmoothInverse(Box<CoreInverse>),
    /// The Prandtl–Ishlinskii sum PI[x]; as its own inverse type, PI⁻¹[y] too.
    Pi(Box<CorePi>),
    /// P(PI[x]).
    ShapedPi(Box<CoreShapedPi>),
    /// PI⁻¹[P⁻¹(y)].
    ShapedPiInverse(Box<CoreShapedPiInverse>),
}

/// The memory of an [`Evaluator`]: Definition 2.1's for the smooth model, the plays for PI.
#[derive(Clone, Debug, PartialEq)]
pub enum EvaluatorMemory {
    /// The memory of the smooth model's operator (`None` before the first sample).
    Smooth(Option<Memory<f64>>),
    /// The play outputs of a Prandtl–Ishlinskii model.
    Plays(Box<PlayMemory<f64, MAX_OPERATORS>>),
}

/// Forwards one call to whichever core operator the evaluator holds.
macro_rules! each {
    ($self:expr, $op:ident => $e:expr) => {
        match $self {
            Evaluator::Smooth($op) => $e,
            Evaluator::SmoothInverse($op) => $e,
            Evaluator::Pi($op) => $e,
            Evaluator::ShapedPi($op) => $e,
            Evaluator::ShapedPiInverse($op) => $e,
        }
    };
}

impl Operator<f64> for Evaluator {
    type Memory = EvaluatorMemory;

    /// One sample: the model output (or command), with time derivatives when `x` is a jet.
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

    fn memory(&self) -> EvaluatorMemory {
        match self {
            Evaluator::Smooth(op) => EvaluatorMemory::Smooth(op.memory()),
            Evaluator::SmoothInverse(op) => EvaluatorMemory::Smooth(op.memory()),
            Evaluator::Pi(op) => EvaluatorMemory::Plays(Box::new(op.memory())),
            Evaluator::ShapedPi(op) => EvaluatorMemory::Plays(Box::new(op.memory())),
            Evaluator::ShapedPiInverse(op) => EvaluatorMemory::Plays(Box::new(op.memory())),
        }
    }

    /// # Errors
    /// The core's check of the memory, or [`Error::InvalidParameter`] for the memory of the
    /// other model kind.
    fn set_memory(&mut self, memory: EvaluatorMemory) -> Result<(), Error> {
        match (self, memory) {
            (Evaluator::Smooth(op), EvaluatorMemory::Smooth(m)) => op.set_memory(m),
            (Evaluator::SmoothInverse(op), EvaluatorMemory::Smooth(m)) => op.set_memory(m),
            (Evaluator::Pi(op), EvaluatorMemory::Plays(m)) => op.set_memory(*m),
            (Evaluator::ShapedPi(op), EvaluatorMemory::Plays(m)) => op.set_memory(*m),
            (Evaluator::ShapedPiInverse(op), EvaluatorMemory::Plays(m)) => op.set_memory(*m),
            _ => Err(Error::InvalidParameter {
                name: "memory",
                value: f64::NAN,
                expected: "the memory of the same kind of model (smooth or Prandtl-Ishlinskii)",
            }),
        }
    }
}

/// A compensator whose desired outputs are clamped into a saturating model's limits
/// ([`crate::modelfile::Saturation::limits`]) before `inner` sees them, as `hyst run --saturate`
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
