//! The memory of a fitted model's run (`hyst_model_get_memory`, `hyst_model_set_memory`): a
//! caller that keeps the state itself (a simulator's state vector, a checkpoint) saves a run
//! after any sample and resumes it exactly, in the same model or in another one loaded from
//! the same file.

use std::panic::{catch_unwind, AssertUnwindSafe};

use ::hyst_model::{ModelError, Saturated};
use hyst_core::Operator;

use crate::api_f64::hyst_memory;
use crate::engine::MemoryFields;
use crate::host::hyst_model;
use crate::status::{
    self, HYST_ERR_INTERNAL, HYST_ERR_NULL_POINTER, HYST_ERR_UNSUPPORTED, HYST_OK,
};

/// Why a model's run has no memory of Definition 2.1 to save: a Prandtl–Ishlinskii model (its
/// memory is its plays) or a model with dynamics or a rate term (its state holds the plant's).
fn unsupported(model: &hyst_model) -> bool {
    model.timed_model().is_some() || model.file.smooth.is_none()
}

/// Writes the memory of Definition 2.1 of the model's direct run (`inverse` = 0) or of its
/// exact inverse's run (`inverse` ≠ 0) into `*memory`, in the units of the model's operator
/// (after the input shaping, before the output shaping). A run that has not started
/// (`has_history` = 0) starts from the model's start rule at its next sample.
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, or `HYST_ERR_UNSUPPORTED` for a
/// Prandtl–Ishlinskii model or a model with dynamics or a rate term (nothing is written).
///
/// # Safety
/// `m` is NULL or a model from `hyst_model_load` or `hyst_model_load_timed` not yet freed;
/// `memory` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_model_get_memory(
    m: *const hyst_model,
    inverse: i32,
    memory: *mut hyst_memory,
) -> i32 {
    if m.is_null() || memory.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: a live model (caller's contract).
    let model = unsafe { &*m };
    if unsupported(model) {
        return HYST_ERR_UNSUPPORTED;
    }
    let run = if inverse != 0 {
        &model.inverse
    } else {
        &model.direct
    };
    let saved = match run.as_ref().map(Operator::memory) {
        Some(::hyst_model::EvaluatorMemory::Smooth(m)) => m,
        Some(::hyst_model::EvaluatorMemory::Plays(_)) => return HYST_ERR_UNSUPPORTED,
        None => None,
    };
    // SAFETY: non-NULL (checked) and writable (caller's contract).
    unsafe { memory.write(hyst_memory::of(MemoryFields::of(saved))) };
    HYST_OK
}

/// Resumes the model's direct run (`inverse` = 0) or its inverse's run (`inverse` ≠ 0) at a
/// memory saved by `hyst_model_get_memory` from a model of the same file: the next
/// `hyst_model_process` of that kind continues it, bit for bit as the saved run would have
/// gone on. A memory with `has_history` = 0 forgets the run (its next sample starts from the
/// model's start rule, as after `hyst_model_reset`).
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, `HYST_ERR_UNSUPPORTED` (as
/// `hyst_model_get_memory`), or `HYST_ERR_STATE_OUTSIDE_BAND` / `HYST_ERR_INVALID_PARAMETER`
/// for a memory the model's operator cannot be in (non-finite values, a point outside its band,
/// a direction other than ±1, `has_history` other than 0 and 1); the model is then unchanged.
///
/// # Safety
/// `m` is NULL or a model from `hyst_model_load` or `hyst_model_load_timed` not yet freed;
/// `memory` is NULL or readable.
#[no_mangle]
pub unsafe extern "C" fn hyst_model_set_memory(
    m: *mut hyst_model,
    inverse: i32,
    memory: *const hyst_memory,
) -> i32 {
    if m.is_null() || memory.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: a live model (caller's contract), not aliased during the call.
    let model = unsafe { &mut *m };
    if unsupported(model) {
        return HYST_ERR_UNSUPPORTED;
    }
    // SAFETY: non-NULL (checked), readable (caller's contract).
    let fields = unsafe { memory.read() }.fields();
    catch_unwind(AssertUnwindSafe(|| {
        let saved = match fields.to_core() {
            Ok(saved) => saved,
            Err(e) => return status::of(&e),
        };
        let inverse = inverse != 0;
        let run = match saved {
            None => None,
            Some(saved) => match model.file.evaluator_at(saved, inverse) {
                Ok(e) => Some(Saturated::new(e, model.limits.filter(|_| inverse))),
                Err(ModelError::Core(e)) => return status::of(&e),
                Err(_) => return HYST_ERR_UNSUPPORTED,
            },
        };
        if inverse {
            model.inverse = run;
        } else {
            model.direct = run;
        }
        HYST_OK
    }))
    .unwrap_or(HYST_ERR_INTERNAL)
}
