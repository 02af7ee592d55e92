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
