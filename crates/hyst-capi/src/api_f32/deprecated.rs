//! The old names of the affine model, its compensator and its adaptive estimator
//! (`hyst_linear_*`): "linear" names Lemma 5.1's plant, and their shapings are affine. Each old
//! function calls its `hyst_affine_*` namesake and is declared deprecated in the header
//! (docs/formats.md, "Deprecated names"); each old type is the new one.
//!
//! GENERATED from `api_f64/deprecated.rs` by `scripts/gen-capi-f32`: do not edit.
#![allow(deprecated)]

use crate::api_f32::adaptive::hyst_adaptive_config_f32;
use crate::api_f32::affine_adaptive::*;
use crate::api_f32::affine_model::*;
use crate::api_f32::memory::hyst_memory_f32;
use crate::api_f32::shaped_model::hyst_shaped_model_params_f32;
use crate::hyst_adaptive_sample_counts;

/// Deprecated: renamed `hyst_affine_model_f32`.
pub type hyst_linear_model_f32 = hyst_affine_model_f32;
/// Deprecated: renamed `hyst_affine_compensator_f32`.
pub type hyst_linear_compensator_f32 = hyst_affine_compensator_f32;
/// Deprecated: renamed `hyst_affine_adaptive_f32`.
pub type hyst_linear_adaptive_f32 = hyst_affine_adaptive_f32;

/// Deprecated: renamed [`hyst_affine_model_init_direct_f32`].
///
/// # Safety
/// As [`hyst_affine_model_init_direct_f32`].
#[deprecated(note = "renamed hyst_affine_model_init_direct_f32")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_model_init_direct_f32(
    m: *mut hyst_linear_model_f32,
    params: *const hyst_shaped_model_params_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_model_init_direct_f32(m, params) }
}

/// Deprecated: renamed [`hyst_affine_model_init_inverse_f32`].
///
/// # Safety
/// As [`hyst_affine_model_init_inverse_f32`].
#[deprecated(note = "renamed hyst_affine_model_init_inverse_f32")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_model_init_inverse_f32(
    m: *mut hyst_linear_model_f32,
    params: *const hyst_shaped_model_params_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_model_init_inverse_f32(m, params) }
}

/// Deprecated: renamed [`hyst_affine_model_step_f32`].
///
/// # Safety
/// As [`hyst_affine_model_step_f32`].
#[deprecated(note = "renamed hyst_affine_model_step_f32")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_model_step_f32(
    m: *mut hyst_linear_model_f32,
    x: f32,
    y: *mut f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_model_step_f32(m, x, y) }
}

/// Deprecated: renamed [`hyst_affine_model_get_memory_f32`].
///
/// # Safety
/// As [`hyst_affine_model_get_memory_f32`].
#[deprecated(note = "renamed hyst_affine_model_get_memory_f32")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_model_get_memory_f32(
    m: *mut hyst_linear_model_f32,
    memory: *mut hyst_memory_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_model_get_memory_f32(m, memory) }
}

/// Deprecated: renamed [`hyst_affine_model_set_memory_f32`].
///
/// # Safety
/// As [`hyst_affine_model_set_memory_f32`].
#[deprecated(note = "renamed hyst_affine_model_set_memory_f32")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_model_set_memory_f32(
    m: *mut hyst_linear_model_f32,
    memory: *const hyst_memory_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_model_set_memory_f32(m, memory) }
}

/// Deprecated: renamed [`hyst_affine_model_reset_f32`].
///
/// # Safety
/// As [`hyst_affine_model_reset_f32`].
#[deprecated(note = "renamed hyst_affine_model_reset_f32")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_model_reset_f32(m: *mut hyst_linear_model_f32) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_model_reset_f32(m) }
}

/// Deprecated: renamed [`hyst_affine_compensator_init_f32`].
///
/// # Safety
/// As [`hyst_affine_compensator_init_f32`].
#[deprecated(note = "renamed hyst_affine_compensator_init_f32")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_compensator_init_f32(
    c: *mut hyst_linear_compensator_f32,
    params: *const hyst_shaped_model_params_f32,
    b: f32,
    a: *const f32,
    v0: *const f32,
    n: usize,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_compensator_init_f32(c, params, b, a, v0, n) }
}

/// Deprecated: renamed [`hyst_affine_compensator_step_f32`].
///
/// # Safety
/// As [`hyst_affine_compensator_step_f32`].
#[deprecated(note = "renamed hyst_affine_compensator_step_f32")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_compensator_step_f32(
    c: *mut hyst_linear_compensator_f32,
    u_new: f32,
    dt: f32,
    u: *mut f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_compensator_step_f32(c, u_new, dt, u) }
}

/// Deprecated: renamed [`hyst_affine_compensator_get_state_f32`].
///
/// # Safety
/// As [`hyst_affine_compensator_get_state_f32`].
#[deprecated(note = "renamed hyst_affine_compensator_get_state_f32")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_compensator_get_state_f32(
    c: *mut hyst_linear_compensator_f32,
    v: *mut f32,
    memory: *mut hyst_memory_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_compensator_get_state_f32(c, v, memory) }
}

/// Deprecated: renamed [`hyst_affine_compensator_reset_f32`].
///
/// # Safety
/// As [`hyst_affine_compensator_reset_f32`].
#[deprecated(note = "renamed hyst_affine_compensator_reset_f32")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_compensator_reset_f32(
    c: *mut hyst_linear_compensator_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_compensator_reset_f32(c) }
}

/// Deprecated: renamed [`hyst_affine_adaptive_init_f32`].
///
/// # Safety
/// As [`hyst_affine_adaptive_init_f32`].
#[deprecated(note = "renamed hyst_affine_adaptive_init_f32")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_adaptive_init_f32(
    a: *mut hyst_linear_adaptive_f32,
    params: *const hyst_shaped_model_params_f32,
    cfg: *const hyst_adaptive_config_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_adaptive_init_f32(a, params, cfg) }
}

/// Deprecated: renamed [`hyst_affine_adaptive_step_f32`].
///
/// # Safety
/// As [`hyst_affine_adaptive_step_f32`].
#[deprecated(note = "renamed hyst_affine_adaptive_step_f32")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_adaptive_step_f32(
    a: *mut hyst_linear_adaptive_f32,
    desired: f32,
    x: *mut f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_adaptive_step_f32(a, desired, x) }
}

/// Deprecated: renamed [`hyst_affine_adaptive_measure_f32`].
///
/// # Safety
/// As [`hyst_affine_adaptive_measure_f32`].
#[deprecated(note = "renamed hyst_affine_adaptive_measure_f32")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_adaptive_measure_f32(
    a: *mut hyst_linear_adaptive_f32,
    y: f32,
    prediction: *mut f32,
    status: *mut i32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_adaptive_measure_f32(a, y, prediction, status) }
}

/// Deprecated: renamed [`hyst_affine_adaptive_update_f32`].
///
/// # Safety
/// As [`hyst_affine_adaptive_update_f32`].
#[deprecated(note = "renamed hyst_affine_adaptive_update_f32")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_adaptive_update_f32(
    a: *mut hyst_linear_adaptive_f32,
    x: f32,
    y: f32,
    prediction: *mut f32,
    status: *mut i32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_adaptive_update_f32(a, x, y, prediction, status) }
}

/// Deprecated: renamed [`hyst_affine_adaptive_parameter_f32`].
///
/// # Safety
/// As [`hyst_affine_adaptive_parameter_f32`].
#[deprecated(note = "renamed hyst_affine_adaptive_parameter_f32")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_adaptive_parameter_f32(
    a: *const hyst_linear_adaptive_f32,
    which: i32,
    value: *mut f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_adaptive_parameter_f32(a, which, value) }
}

/// Deprecated: renamed [`hyst_affine_adaptive_counts_f32`].
///
/// # Safety
/// As [`hyst_affine_adaptive_counts_f32`].
#[deprecated(note = "renamed hyst_affine_adaptive_counts_f32")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_adaptive_counts_f32(
    a: *const hyst_linear_adaptive_f32,
    counts: *mut hyst_adaptive_sample_counts,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_adaptive_counts_f32(a, counts) }
}
