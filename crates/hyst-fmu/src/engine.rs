//! The committed stepping state of an instance: the parametric operator or the model file's
//! evaluator, run through `hyst_core::Operator` only, or a model with dynamics or a rate term,
//! run by hyst-model's `TimedRun` or `TimedCompensator` ([`TimedEngine`]); no formula is
//! written here.

use hyst_core::{Error, Hysteresis, InverseHysteresis, Operator};
use hyst_model::{Evaluator, ModelFile};

use crate::state::History;
use crate::timed::TimedEngine;

/// What an instance steps once it has one.
#[derive(Clone, Debug)]
pub enum Engine {
    /// H(k1, k2), eq. (2).
    Direct(Hysteresis<f64>),
    /// H⁻¹(k1, k2), eq. (4).
    Inverse(InverseHysteresis<f64>),
    /// A model file's evaluator, started (as `hyst run --model` starts a record) at `first`.
    Model {
        /// The input the evaluator was created with (`ModelFile::evaluator(first, inverse)`).
        first: f64,
        /// The evaluator.
        evaluator: Evaluator,
    },
    /// A model with dynamics or a rate term.
    Timed(Box<TimedEngine>),
}

/// Forwards one call to the operator the engine holds (`$timed` for a timed model).
macro_rules! each {
    ($self:expr, $op:ident => $e:expr, $t:ident => $timed:expr) => {
        match $self {
            Engine::Direct($op) => $e,
            Engine::Inverse($op) => $e,
            Engine::Model { evaluator: $op, .. } => $e,
            Engine::Timed($t) => $timed,
        }
    };
}

/// The output `op` would give for the next sample `x`, without committing it: a copy steps.
fn peek<O: Operator<f64> + Clone>(op: &O, x: f64) -> Result<f64, Error> {
    op.clone().try_step(x)
}

impl Engine {
    /// The parametric operator H(k1, k2) (or H⁻¹), without history.
    ///
    /// # Errors
    /// The core's error for an invalid k1 or k2 (it names the parameter and the value).
    pub fn operator(k1: f64, k2: f64, inverse: bool) -> Result<Self, Error> {
        Ok(if inverse {
            Engine::Inverse(InverseHysteresis::new(k1, k2)?)
        } else {
            Engine::Direct(Hysteresis::new(k1, k2)?)
        })
    }

    /// The model file's evaluator for a record whose first sample is `first`; for a model with
    /// dynamics or a rate term its [`TimedEngine`], with the nominal step `period` (the first
    /// fmi2DoStep's step; `None` before it).
    ///
    /// # Errors
    /// The model cannot start at `first` (a desired output beyond a saturating shaping function,
    /// a non-finite value), or `period` is not > 0.
    pub fn model(
        file: &ModelFile,
        first: f64,
        inverse: bool,
        period: Option<f64>,
    ) -> Result<Self, String> {
        if let Some(model) = file.smooth.as_ref().filter(|m| m.is_timed()) {
            let engine = TimedEngine::new(model, first, inverse, period)?;
            return Ok(Engine::Timed(Box::new(engine)));
        }
        let evaluator = file
            .evaluator(first, inverse)
            .map_err(|e| format!("the model cannot start at {first}: {e}"))?;
        Ok(Engine::Model { first, evaluator })
    }

    /// The output for the committed history followed by `x` (with x's time derivatives
    /// `derivatives`, which only a timed model's compensator uses); nothing is committed.
    ///
    /// # Errors
    /// The refusal of `x` (non-finite, beyond a saturating shaping function), its message.
    pub fn peek(&self, x: f64, derivatives: &[f64]) -> Result<f64, String> {
        each!(self, op => peek(op, x).map_err(|e| e.to_string()), t => t.peek(x, derivatives))
    }

    /// Steps `x` (with `derivatives`, as [`Engine::peek`]) and commits it; on error nothing
    /// changes (the `Operator` contract).
    ///
    /// # Errors
    /// As [`Engine::peek`].
    pub fn step(&mut self, x: f64, derivatives: &[f64]) -> Result<f64, String> {
        each!(self, op => op.try_step(x).map_err(|e| e.to_string()), t => t.step(x, derivatives))
    }

    /// Checks the communication step of an fmi2DoStep after the first ([`TimedEngine::check_step`];
    /// any step ≥ 0 for the others).
    ///
    /// # Errors
    /// A timed model's step that is not > 0.
    pub fn check_step(&self, step: f64) -> Result<(), String> {
        match self {
            Engine::Timed(t) => t.check_step(step),
            _ => Ok(()),
        }
    }

    /// Takes the communication step of the fmi2DoStep that committed the last sample: a timed
    /// model's step to the next sample ([`TimedEngine::set_next`]).
    pub fn set_next(&mut self, step: f64) {
        if let Engine::Timed(t) = self {
            t.set_next(step);
        }
    }

    /// The fastest corner of the model's loop a timed model's compensator has met
    /// ([`TimedEngine::fastest_corner`]; `None` for every other engine).
    #[must_use]
    pub fn fastest_corner(&self) -> Option<hyst_model::Corner> {
        match self {
            Engine::Timed(t) => t.fastest_corner(),
            _ => None,
        }
    }

    /// The history to save.
    #[must_use]
    pub fn history(&self) -> History {
        match self {
            Engine::Direct(op) => op.memory().map_or(History::Empty, History::Operator),
            Engine::Inverse(op) => op.memory().map_or(History::Empty, History::Operator),
            Engine::Model { first, evaluator } => History::Model {
                first: *first,
                memory: evaluator.memory(),
            },
            Engine::Timed(t) => History::Timed(t.clone()),
        }
    }

    /// Restores a saved operator or model memory through `Operator::set_memory` (which checks
    /// it); `History::Empty` leaves the engine as built.
    ///
    /// # Errors
    /// The core's refusal of the memory (non-finite values, a point outside the band), or a
    /// history of the other kind.
    pub fn restore(&mut self, history: &History) -> Result<(), String> {
        let result = match (self, history) {
            (_, History::Empty) => Ok(()),
            (Engine::Direct(op), History::Operator(m)) => op.set_memory(Some(*m)),
            (Engine::Inverse(op), History::Operator(m)) => op.set_memory(Some(*m)),
            (Engine::Model { evaluator, .. }, History::Model { memory, .. }) => {
                evaluator.set_memory(memory.clone())
            }
            (Engine::Timed(t), History::Timed(saved)) => {
                t.clone_from(saved);
                Ok(())
            }
            _ => return Err("the saved history is of another kind of FMU".into()),
        };
        result.map_err(|e| format!("the saved memory is refused: {e}"))
    }
}
