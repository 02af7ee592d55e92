//! The parametric operator H(k1, k2) (eq. 2) and its inverse H⁻¹(k1, k2) (eq. 4) with their
//! memory, in caller memory (`hyst_operator_*`).
//!
//! GENERATED from `api_f64/operator.rs` by `scripts/gen-capi-f32`: do not edit.

use crate::api_f32::checks::done;
use crate::api_f32::memory::{get_memory, hyst_memory_f32, reset, set_memory};
use crate::engine::{self, Pair};
use crate::slot;
use crate::status;

/// The parametric operator H(k1, k2) (eq. 2) or H⁻¹(k1, k2) (eq. 4) with its memory: an opaque
/// block of 64 bytes, 8-byte aligned, plain data (copyable with memcpy).
#[repr(C)]
pub struct hyst_operator_f32 {
    opaque: [u64; 8],
}

impl slot::Block for hyst_operator_f32 {
    type Value = Pair<f32>;
    const TAG: u32 = 0x4859_5f66; // "HY_f"
}

/// `hyst_operator_init_direct_f32` / `_inverse`.
///
/// # Safety
/// `op` is NULL or points to a writable `hyst_operator_f32`.
unsafe fn init_operator(op: *mut hyst_operator_f32, k1: f32, k2: f32, inverse: bool) -> i32 {
    match engine::pair(k1, k2, inverse) {
        // SAFETY: `op` is NULL or a writable block of the type's size.
        Ok(p) => unsafe { slot::put(op, p) },
        Err(e) => status::of(&e),
    }
}

/// Initialises `op` as the direct operator u = H(k1, k2)[v] (eq. 2), with no history (its first
/// sample is a reversal point on the line u = v).
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, `HYST_ERR_MISALIGNED`, or
/// `HYST_ERR_INVALID_PARAMETER` unless k1 and k2 are finite and > 0 (`op` is then untouched).
///
/// # Safety
/// `op` is NULL or points to a writable `hyst_operator_f32`.
#[no_mangle]
pub unsafe extern "C" fn hyst_operator_init_direct_f32(
    op: *mut hyst_operator_f32,
    k1: f32,
    k2: f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { init_operator(op, k1, k2, false) }
}

/// Initialises `op` as the inverse operator v = H⁻¹(k1, k2)[u_d] (eq. 4), the exact inverse of
/// `hyst_operator_init_direct_f32`'s operator, with no history.
///
/// Returns as `hyst_operator_init_direct_f32`.
///
/// # Safety
/// `op` is NULL or points to a writable `hyst_operator_f32`.
#[no_mangle]
pub unsafe extern "C" fn hyst_operator_init_inverse_f32(
    op: *mut hyst_operator_f32,
    k1: f32,
    k2: f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { init_operator(op, k1, k2, true) }
}

/// One sample: `*y` = the output for the input `x`. A non-finite `x` returns
/// `HYST_ERR_NON_FINITE`, leaves the memory untouched and writes the last output (or `x` before
/// any) to `*y`, so a control loop can carry on.
///
/// # Safety
/// `op` is NULL or an initialised `hyst_operator_f32`; `y` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_operator_step_f32(
    op: *mut hyst_operator_f32,
    x: f32,
    y: *mut f32,
) -> i32 {
    // SAFETY: `y` is NULL or writable (caller's contract).
    done(slot::get_mut(op).map(|o| unsafe { engine::step(o, x, y) }))
}

/// One sample with time derivatives: `x` holds the input and its first `order` time derivatives
/// [x, ẋ, ẍ, …] (order ≤ 4), `y` receives the output's [y, ẏ, ÿ, …] (Proposition 2.7 and
/// beyond, exact by Taylor arithmetic). On an error `y` and the memory are untouched.
///
/// # Safety
/// `op` is NULL or an initialised `hyst_operator_f32`; `x` and `y` are NULL or hold `order + 1`
/// values.
#[no_mangle]
pub unsafe extern "C" fn hyst_operator_step_derivatives_f32(
    op: *mut hyst_operator_f32,
    x: *const f32,
    y: *mut f32,
    order: usize,
) -> i32 {
    // SAFETY: `x`, `y` are NULL or hold order + 1 values (caller's contract).
    done(slot::get_mut(op).map(|o| unsafe { engine::step_derivatives(o, x, y, order) }))
}

/// `n` samples from `x` into `y` (which may be the same array), each as `hyst_operator_step_f32`;
/// returns `HYST_OK`, or the status of the first refused sample (the others are still
/// processed, a refused one holds the last output).
///
/// # Safety
/// `op` is NULL or an initialised `hyst_operator_f32`; when n > 0, `x` and `y` are NULL or hold `n`
/// values.
#[no_mangle]
pub unsafe extern "C" fn hyst_operator_process_f32(
    op: *mut hyst_operator_f32,
    x: *const f32,
    y: *mut f32,
    n: usize,
) -> i32 {
    // SAFETY: `x`, `y` are NULL or hold n values (caller's contract).
    done(slot::get_mut(op).map(|o| unsafe { engine::process(o, x, y, n) }))
}

/// Copies the operator's memory into `*memory` (to save it, e.g. across a controller restart).
///
/// # Safety
/// `op` is NULL or an initialised `hyst_operator_f32`; `memory` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_operator_get_memory_f32(
    op: *mut hyst_operator_f32,
    memory: *mut hyst_memory_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { get_memory(slot::get_mut(op), memory) }
}

/// Restores a memory saved by `hyst_operator_get_memory_f32`. `HYST_ERR_STATE_OUTSIDE_BAND` or
/// `HYST_ERR_INVALID_PARAMETER` for a memory the operator cannot be in (non-finite values, a
/// point outside the band |output − input| ≤ k1, a direction other than ±1); the operator is
/// then unchanged.
///
/// # Safety
/// `op` is NULL or an initialised `hyst_operator_f32`; `memory` is NULL or readable.
#[no_mangle]
pub unsafe extern "C" fn hyst_operator_set_memory_f32(
    op: *mut hyst_operator_f32,
    memory: *const hyst_memory_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { set_memory(slot::get_mut(op), memory) }
}

/// Forgets the history: the next sample starts on the line output = input.
///
/// # Safety
/// `op` is NULL or an initialised `hyst_operator_f32`.
#[no_mangle]
pub unsafe extern "C" fn hyst_operator_reset_f32(op: *mut hyst_operator_f32) -> i32 {
    reset(slot::get_mut(op))
}
