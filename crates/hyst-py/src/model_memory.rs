//! `Model.memory`: the memory of a model's evaluator (`hyst_model::EvaluatorMemory`) as a
//! Python object and back, and the evaluator a memory is restored into when the model has not
//! started yet.
//!
//! A smooth model's memory is its operator's (H, or H⁻¹ for the inverse): a `hyst.Memory` in
//! operator units. A Prandtl–Ishlinskii model's is its plays': the pair `(plays, last_output)`.
//! `None` is no history: the next sample starts the model by its start rule.

use hyst_core::{PlayMemory, Shaping};
use hyst_model::pi::MAX_PLAYS;
use hyst_model::{Evaluator, EvaluatorMemory, InitialState, ModelError, ModelFile, ModelKind};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::errors::value_error;
use crate::operator::Memory;

/// `repr(memory)`, for messages.
pub(crate) fn shown(memory: &Bound<'_, PyAny>) -> String {
    memory
        .repr()
        .map_or_else(|_| "?".to_string(), |r| r.to_string())
}

/// The number of plays of a Prandtl–Ishlinskii model (0 for a smooth one).
fn plays_of(file: &ModelFile) -> usize {
    file.prandtl_ishlinskii
        .as_ref()
        .map_or(0, |p| p.thresholds.len())
}

/// What `Model.memory` returns for the evaluator's memory `memory` (`None`: no history).
///
/// # Errors
/// Only if Python cannot make the objects.
pub(crate) fn to_python<'py>(
    py: Python<'py>,
    file: &ModelFile,
    memory: Option<EvaluatorMemory>,
) -> PyResult<Option<Bound<'py, PyAny>>> {
    match memory {
        None | Some(EvaluatorMemory::Smooth(None)) => Ok(None),
        Some(EvaluatorMemory::Smooth(Some(inner))) => {
            Ok(Some(Bound::new(py, Memory { inner })?.into_any()))
        }
        Some(EvaluatorMemory::Plays(p)) => {
            let Some(last) = p.last_output else {
                return Ok(None);
            };
            let plays = p.plays.get(..plays_of(file)).unwrap_or(&[]);
            let plays = PyTuple::new(py, plays)?;
            Ok(Some((plays, last).into_pyobject(py)?.into_any()))
        }
    }
}

/// The evaluator memory that `memory` (not None) gives a model of `file`: a `hyst.Memory` for a
/// smooth model, `(plays, last_output)` with one finite play output per play for a
/// Prandtl–Ishlinskii model. The values themselves are checked when the evaluator takes it.
///
/// # Errors
/// `TypeError` for an object of the other kind of model or of neither; `ValueError` for the
/// wrong number of play outputs.
pub(crate) fn from_python(
    file: &ModelFile,
    memory: &Bound<'_, PyAny>,
) -> PyResult<EvaluatorMemory> {
    let shown = || self::shown(memory);
    match file.kind {
        ModelKind::Smooth => match memory.cast::<Memory>() {
            Ok(m) => Ok(EvaluatorMemory::Smooth(Some(m.get().inner))),
            Err(_) => Err(PyTypeError::new_err(format!(
                "memory = {}: a smooth model's memory is a hyst.Memory (its operator's, in \
                 operator units) or None",
                shown()
            ))),
        },
        ModelKind::PrandtlIshlinskii => {
            let n = plays_of(file);
            let Ok((values, last)) = memory.extract::<(Vec<f64>, f64)>() else {
                return Err(PyTypeError::new_err(format!(
                    "memory = {}: a Prandtl-Ishlinskii model's memory is (plays, last_output): \
                     its {n} play outputs and its last output, or None",
                    shown()
                )));
            };
            if values.len() != n {
                return Err(value_error(format!(
                    "memory = {}: {} play outputs for a model of {n} plays",
                    shown(),
                    values.len()
                )));
            }
            let mut plays = [0.0; MAX_PLAYS];
            for (slot, v) in plays.iter_mut().zip(&values) {
                *slot = *v;
            }
            Ok(EvaluatorMemory::Plays(Box::new(PlayMemory {
                plays,
                last_output: Some(last),
            })))
        }
    }
}

/// An evaluator of the model `file` (the inverse with `inverse`) for `memory` to be restored
/// into: built as at a first sample but with no start rule (the memory replaces its start), at
/// a first sample the memory itself gives (the inverse of a smooth model needs a desired output
/// within its output shaping's range: ψ_out of the memory's last operator input).
///
/// # Errors
/// The model's refusal (a model with dynamics or a rate term; a memory whose last input gives
/// no desired output).
pub(crate) fn blank(
    file: &ModelFile,
    inverse: bool,
    memory: &EvaluatorMemory,
) -> Result<Evaluator, ModelError> {
    let mut file = file.clone();
    let mut first = 0.0;
    if let Some(m) = file.smooth.as_mut() {
        m.initial_state = InitialState::Line;
        if let (true, EvaluatorMemory::Smooth(Some(at))) = (inverse, memory) {
            first = m.output_shaping.apply(at.last_input);
        }
    }
    file.evaluator(first, inverse)
}
