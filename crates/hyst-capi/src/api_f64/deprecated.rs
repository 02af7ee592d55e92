//! The old names of the affine model, its compensator and its adaptive estimator
//! (`hyst_linear_*`): "linear" names Lemma 5.1's plant, and their shapings are affine. Each old
//! function calls its `hyst_affine_*` namesake and is declared deprecated in the header
//! (docs/formats.md, "Deprecated names"); each old type is the new one.
//!
//! Its `float` twin is generated from this file by `scripts/gen-capi-f32`: edit this one.
#![allow(deprecated)]

use crate::api_f64::adaptive::hyst_adaptive_config;
use crate::api_f64::affine_adaptive::*;
use crate::api_f64::affine_model::*;
use crate::api_f64::memory::hyst_memory;
use crate::api_f64::shaped_model::hyst_shaped_model_params;
use crate::hyst_adaptive_sample_counts;

/// Deprecated: renamed `hyst_affine_model`.
pub type hyst_linear_model = hyst_affine_model;
/// Deprecated: renamed `hyst_affine_compensator`.
pub type hyst_linear_compensator = hyst_affine_compensator;
/// Deprecated: renamed `hyst_affine_adaptive`.
pub type hyst_linear_adaptive = hyst_affine_adaptive;

/// Deprecated: renamed [`hyst_affine_model_init_direct`].
///
/// # Safety
/// As [`hyst_affine_model_init_direct`].
#[deprecated(note = "renamed hyst_affine_model_init_direct")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_model_init_direct(
    m: *mut hyst_linear_model,
    params: *const hyst_shaped_model_params,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_model_init_direct(m, params) }
}

/// Deprecated: renamed [`hyst_affine_model_init_inverse`].
///
/// # Safety
/// As [`hyst_affine_model_init_inverse`].
#[deprecated(note = "renamed hyst_affine_model_init_inverse")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_model_init_inverse(
    m: *mut hyst_linear_model,
    params: *const hyst_shaped_model_params,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_model_init_inverse(m, params) }
}

/// Deprecated: renamed [`hyst_affine_model_step`].
///
/// # Safety
/// As [`hyst_affine_model_step`].
#[deprecated(note = "renamed hyst_affine_model_step")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_model_step(
    m: *mut hyst_linear_model,
    x: f64,
    y: *mut f64,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_model_step(m, x, y) }
}

/// Deprecated: renamed [`hyst_affine_model_get_memory`].
///
/// # Safety
/// As [`hyst_affine_model_get_memory`].
#[deprecated(note = "renamed hyst_affine_model_get_memory")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_model_get_memory(
    m: *mut hyst_linear_model,
    memory: *mut hyst_memory,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_model_get_memory(m, memory) }
}

/// Deprecated: renamed [`hyst_affine_model_set_memory`].
///
/// # Safety
/// As [`hyst_affine_model_set_memory`].
#[deprecated(note = "renamed hyst_affine_model_set_memory")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_model_set_memory(
    m: *mut hyst_linear_model,
    memory: *const hyst_memory,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_model_set_memory(m, memory) }
}

/// Deprecated: renamed [`hyst_affine_model_reset`].
///
/// # Safety
/// As [`hyst_affine_model_reset`].
#[deprecated(note = "renamed hyst_affine_model_reset")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_model_reset(m: *mut hyst_linear_model) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_model_reset(m) }
}

/// Deprecated: renamed [`hyst_affine_compensator_init`].
///
/// # Safety
/// As [`hyst_affine_compensator_init`].
#[deprecated(note = "renamed hyst_affine_compensator_init")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_compensator_init(
    c: *mut hyst_linear_compensator,
    params: *const hyst_shaped_model_params,
    b: f64,
    a: *const f64,
    v0: *const f64,
    n: usize,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_compensator_init(c, params, b, a, v0, n) }
}

/// Deprecated: renamed [`hyst_affine_compensator_step`].
///
/// # Safety
/// As [`hyst_affine_compensator_step`].
#[deprecated(note = "renamed hyst_affine_compensator_step")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_compensator_step(
    c: *mut hyst_linear_compensator,
    u_new: f64,
    dt: f64,
    u: *mut f64,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_compensator_step(c, u_new, dt, u) }
}

/// Deprecated: renamed [`hyst_affine_compensator_get_state`].
///
/// # Safety
/// As [`hyst_affine_compensator_get_state`].
#[deprecated(note = "renamed hyst_affine_compensator_get_state")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_compensator_get_state(
    c: *mut hyst_linear_compensator,
    v: *mut f64,
    memory: *mut hyst_memory,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_compensator_get_state(c, v, memory) }
}

/// Deprecated: renamed [`hyst_affine_compensator_reset`].
///
/// # Safety
/// As [`hyst_affine_compensator_reset`].
#[deprecated(note = "renamed hyst_affine_compensator_reset")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_compensator_reset(c: *mut hyst_linear_compensator) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_compensator_reset(c) }
}

/// Deprecated: renamed [`hyst_affine_adaptive_init`].
///
/// # Safety
/// As [`hyst_affine_adaptive_init`].
#[deprecated(note = "renamed hyst_affine_adaptive_init")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_adaptive_init(
    a: *mut hyst_linear_adaptive,
    params: *const hyst_shaped_model_params,
    cfg: *const hyst_adaptive_config,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_adaptive_init(a, params, cfg) }
}

/// Deprecated: renamed [`hyst_affine_adaptive_step`].
///
/// # Safety
/// As [`hyst_affine_adaptive_step`].
#[deprecated(note = "renamed hyst_affine_adaptive_step")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_adaptive_step(
    a: *mut hyst_linear_adaptive,
    desired: f64,
    x: *mut f64,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_adaptive_step(a, desired, x) }
}

/// Deprecated: renamed [`hyst_affine_adaptive_measure`].
///
/// # Safety
/// As [`hyst_affine_adaptive_measure`].
#[deprecated(note = "renamed hyst_affine_adaptive_measure")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_adaptive_measure(
    a: *mut hyst_linear_adaptive,
    y: f64,
    prediction: *mut f64,
    status: *mut i32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_adaptive_measure(a, y, prediction, status) }
}

/// Deprecated: renamed [`hyst_affine_adaptive_update`].
///
/// # Safety
/// As [`hyst_affine_adaptive_update`].
#[deprecated(note = "renamed hyst_affine_adaptive_update")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_adaptive_update(
    a: *mut hyst_linear_adaptive,
    x: f64,
    y: f64,
    prediction: *mut f64,
    status: *mut i32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_adaptive_update(a, x, y, prediction, status) }
}

/// Deprecated: renamed [`hyst_affine_adaptive_parameter`].
///
/// # Safety
/// As [`hyst_affine_adaptive_parameter`].
#[deprecated(note = "renamed hyst_affine_adaptive_parameter")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_adaptive_parameter(
    a: *const hyst_linear_adaptive,
    which: i32,
    value: *mut f64,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_adaptive_parameter(a, which, value) }
}

/// Deprecated: renamed [`hyst_affine_adaptive_counts`].
///
/// # Safety
/// As [`hyst_affine_adaptive_counts`].
#[deprecated(note = "renamed hyst_affine_adaptive_counts")]
#[no_mangle]
pub unsafe extern "C" fn hyst_linear_adaptive_counts(
    a: *const hyst_linear_adaptive,
    counts: *mut hyst_adaptive_sample_counts,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_affine_adaptive_counts(a, counts) }
}
