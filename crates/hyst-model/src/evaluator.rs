//! A fitted model ready to run sample by sample: the smooth model or the Prandtl–Ishlinskii
//! baseline (with or without its output polynomial), direct or as its exact compensator, behind
//! the core's one stepping interface [`Operator`].

use hyst_core::{AnyK2Law, Error, Memory, Operator, PlayMemory, Sample};

use crate::pi::{PiOperator, MAX_PLAYS};
use crate::smooth::{CoreInverseShapedModel, Shaped};

/// A fitted model, runnable on plain numbers or jets (see `ModelFile::evaluator`).
#[derive(Clone, Debug)]
pub enum Evaluator {
    /// The smooth model ψ_out(H\[ψ_in(x)\]), or its stop form ψ_out(v − H\[v\]) + c·v,
    /// v = ψ_in(x) (friction; no inverse).
    Smooth(Box<Shaped<AnyK2Law<f64>>>),
    /// The smooth model's exact compensator ψ_in⁻¹(H⁻¹\[ψ_out⁻¹(y)\]).
    SmoothInverse(Box<CoreInverseShapedModel>),
    /// A Prandtl–Ishlinskii model or its exact inverse.
    Pi(Box<PiOperator>),
}

/// The memory of an [`Evaluator`]: Definition 2.1's for the smooth model, the plays for PI.
#[derive(Clone, Debug, PartialEq)]
pub enum EvaluatorMemory {
    /// The memory of the smooth model's operator (`None` before the first sample).
    Smooth(Option<Memory<f64>>),
    /// The play outputs of a Prandtl–Ishlinskii model.
    Plays(Box<PlayMemory<f64, MAX_PLAYS>>),
}

/// Forwards one call to whichever core operator the evaluator holds.
macro_rules! each {
    ($self:expr, $op:ident => $e:expr) => {
        match $self {
            Evaluator::Smooth($op) => $e,
            Evaluator::SmoothInverse($op) => $e,
            Evaluator::Pi($op) => $e,
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
            _ => Err(Error::InvalidParameter {
                name: "memory",
                value: f64::NAN,
                expected: "the memory of the same kind of model (smooth or Prandtl-Ishlinskii)",
            }),
        }
    }
}
