//! The memory of Definition 2.1 as C reads and writes it (`hyst_memory_f32`), and the
//! `_get_memory`, `_set_memory` and `_reset` that the operator and the shaped model share.
//!
//! GENERATED from `api_f64/memory.rs` by `scripts/gen-capi-f32`: do not edit.

use crate::api_f32::checks::{done, status_of};
use crate::engine::{self, MemoryFields};
use crate::status::{HYST_ERR_NULL_POINTER, HYST_OK};

/// The memory of Definition 2.1 (save it with `_get_memory`, restore it with `_set_memory`):
/// the last reversal point (α0, β0) = (`reversal_input`, `reversal_output`), the last sample,
/// and the direction of the input. Values in the units of the operator's input and output.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct hyst_memory_f32 {
    /// α0: the operator input at the last reversal.
    pub reversal_input: f32,
    /// β0: the operator output at the last reversal.
    pub reversal_output: f32,
    /// The last input sample.
    pub last_input: f32,
    /// The last output sample.
    pub last_output: f32,
    /// +1: the input is rising; −1: falling.
    pub direction: i32,
    /// 0: no sample yet (the operator starts on the line output = input; the other fields are
    /// ignored); 1: the fields above hold the memory.
    pub has_history: i32,
}

impl hyst_memory_f32 {
    /// The memory as C sees it.
    pub(crate) fn of(fields: MemoryFields<f32>) -> Self {
        Self {
            reversal_input: fields.reversal_input,
            reversal_output: fields.reversal_output,
            last_input: fields.last_input,
            last_output: fields.last_output,
            direction: fields.direction,
            has_history: fields.has_history,
        }
    }

    /// The memory as the engine takes it.
    pub(crate) fn fields(&self) -> MemoryFields<f32> {
        MemoryFields {
            reversal_input: self.reversal_input,
            reversal_output: self.reversal_output,
            last_input: self.last_input,
            last_output: self.last_output,
            direction: self.direction,
            has_history: self.has_history,
        }
    }
}

/// `_get_memory` of an operator or a shaped model.
///
/// # Safety
/// `memory` is NULL or writable.
pub(crate) unsafe fn get_memory(
    op: Result<&mut impl engine::Dyn<f32>, i32>,
    memory: *mut hyst_memory_f32,
) -> i32 {
    if memory.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    done(op.map(|o| {
        let m = hyst_memory_f32::of(MemoryFields::of(o.memory()));
        // SAFETY: non-NULL (checked), writable (caller's contract).
        unsafe { memory.write(m) };
        HYST_OK
    }))
}

/// `_set_memory` of an operator or a shaped model.
///
/// # Safety
/// `memory` is NULL or readable.
pub(crate) unsafe fn set_memory(
    op: Result<&mut impl engine::Dyn<f32>, i32>,
    memory: *const hyst_memory_f32,
) -> i32 {
    if memory.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: non-NULL (checked), readable (caller's contract).
    let fields = unsafe { memory.read() }.fields();
    done(op.and_then(|o| {
        status_of(o.set_memory(status_of(fields.to_core())?))?;
        Ok(HYST_OK)
    }))
}

/// `_reset` of an operator or a shaped model.
pub(crate) fn reset(op: Result<&mut impl engine::Dyn<f32>, i32>) -> i32 {
    done(op.map(|o| {
        o.reset();
        HYST_OK
    }))
}
