//! The adaptive compensator of a model with affine shapings (`hyst_affine_adaptive_*`): the
//! same estimator and compensator as `hyst_adaptive_*` on duals of width 4 (up to four
//! parameters) and with no nonlinear shape linked, for firmware where code size counts (as
//! `hyst_affine_model_*` is to `hyst_shaped_model_*`).
//!
//! GENERATED from `api_f64/affine_adaptive.rs` by `scripts/gen-capi-f32`: do not edit.

use hyst_core::AffineShaping;

use crate::api_f32::adaptive::{hyst_adaptive_config_f32, State};
use crate::api_f32::checks::{done, done_into};
use crate::api_f32::shaped_model::hyst_shaped_model_params_f32;
use crate::engine;
use crate::hyst_adaptive_sample_counts;
use crate::slot;

/// The adaptive compensator of a model with affine shapings (identity or affine ψ_in and
/// ψ_out), adapting up to four parameters: an opaque block of 768 bytes, 8-byte aligned,
/// plain data (copyable with memcpy).
#[repr(C)]
pub struct hyst_affine_adaptive_f32 {
    opaque: [u64; 96],
}

/// Its state: duals of width 4, affine shapes.
type LinearState = State<4, AffineShaping<f32>>;

impl slot::Block for hyst_affine_adaptive_f32 {
    type Value = LinearState;
    const TAG: u32 = 0x4859_6166; // "HYaf"
}

/// As `hyst_adaptive_init_f32`; also `HYST_ERR_INVALID_PARAMETER` when a shaping's kind is not
/// `HYST_SHAPING_IDENTITY` or `HYST_SHAPING_AFFINE`, or more than four parameters adapt (use
/// `hyst_adaptive_*` then).
///
/// # Safety
/// `a` is NULL or points to a writable `hyst_affine_adaptive_f32`; `params` and `cfg` are NULL or
/// readable.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_adaptive_init_f32(
    a: *mut hyst_affine_adaptive_f32,
    params: *const hyst_shaped_model_params_f32,
    cfg: *const hyst_adaptive_config_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { LinearState::init(a, params, cfg, engine::linear_shaping) }
}

/// As `hyst_adaptive_step_f32`.
///
/// # Safety
/// `a` is NULL or an initialised `hyst_affine_adaptive_f32`; `x` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_adaptive_step_f32(
    a: *mut hyst_affine_adaptive_f32,
    desired: f32,
    x: *mut f32,
) -> i32 {
    // SAFETY: `x` is non-NULL (checked by `done_into`) and writable (caller's contract).
    done_into(x, || {
        slot::get_mut(a).map(|s| unsafe { s.step(desired, x) })
    })
}

/// As `hyst_adaptive_measure_f32`.
///
/// # Safety
/// `a` is NULL or an initialised `hyst_affine_adaptive_f32`; `prediction` and `status` are NULL or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_adaptive_measure_f32(
    a: *mut hyst_affine_adaptive_f32,
    y: f32,
    prediction: *mut f32,
    status: *mut i32,
) -> i32 {
    // SAFETY: forwarded contract.
    done(slot::get_mut(a).map(|s| unsafe { s.measure(y, prediction, status) }))
}

/// As `hyst_adaptive_update_f32`.
///
/// # Safety
/// `a` is NULL or an initialised `hyst_affine_adaptive_f32`; `prediction` and `status` are NULL or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_adaptive_update_f32(
    a: *mut hyst_affine_adaptive_f32,
    x: f32,
    y: f32,
    prediction: *mut f32,
    status: *mut i32,
) -> i32 {
    // SAFETY: forwarded contract.
    done(slot::get_mut(a).map(|s| unsafe { s.update(x, y, prediction, status) }))
}

/// As `hyst_adaptive_parameter_f32`.
///
/// # Safety
/// `a` is NULL or an initialised `hyst_affine_adaptive_f32`; `value` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_adaptive_parameter_f32(
    a: *const hyst_affine_adaptive_f32,
    which: i32,
    value: *mut f32,
) -> i32 {
    // SAFETY: `value` is non-NULL (checked by `done_into`) and writable (caller's contract).
    done_into(value, || {
        slot::get(a).map(|s| unsafe { s.parameter(which, value) })
    })
}

/// As `hyst_adaptive_counts_f32`.
///
/// # Safety
/// `a` is NULL or an initialised `hyst_affine_adaptive_f32`; `counts` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_adaptive_counts_f32(
    a: *const hyst_affine_adaptive_f32,
    counts: *mut hyst_adaptive_sample_counts,
) -> i32 {
    // SAFETY: `counts` is non-NULL (checked by `done_into`) and writable (caller's contract).
    done_into(counts, || slot::get(a).map(|s| unsafe { s.counts(counts) }))
}
