//! The shaped model whose shapings are affine (identity or affine shape, with their scalings:
//! what `hyst fit` writes by default), its inverse and stop form (`hyst_affine_model_*`), and
//! its Lemma 5.1 compensator (`hyst_affine_compensator_*`). The same parameters, arithmetic and
//! results as `hyst_shaped_model_*` and `hyst_shaped_compensator_*`, bit for bit, but a
//! firmware that uses them links none of the nonlinear shapes (tanh, Langevin, polynomial,
//! quadratic-exp and their inverses), which the run-time choice of `hyst_shaping_f32.kind` brings.
//! `hyst export c` uses them for models with affine shapings.
//!
//! GENERATED from `api_f64/affine_model.rs` by `scripts/gen-capi-f32`: do not edit.

use crate::api_f32::checks::done;
use crate::api_f32::compensator::{comp_state, comp_step, init_from_params};
use crate::api_f32::memory::{get_memory, hyst_memory_f32, reset, set_memory};
use crate::api_f32::shaped_model::hyst_shaped_model_params_f32;
use crate::engine::{self, Comp, Linear, Shaped};
use crate::slot;
use crate::status::{self, HYST_ERR_NULL_POINTER, HYST_OK};
use hyst_core::AnyK2Law;

/// The shaped model of `hyst_shaped_model_params_f32` whose shapings are affine, as
/// `hyst_shaped_model_f32`: an opaque block of 160 bytes, 8-byte aligned, plain data.
#[repr(C)]
pub struct hyst_affine_model_f32 {
    opaque: [u64; 20],
}

/// The Lemma 5.1 compensator of such a model, as `hyst_shaped_compensator_f32`: an opaque
/// block of 224 bytes, 8-byte aligned, plain data.
#[repr(C)]
pub struct hyst_affine_compensator_f32 {
    opaque: [u64; 28],
}

/// The model inside.
type LinearShaped = Shaped<f32, Linear<f32>>;
/// The compensator inside.
type LinearComp = Comp<f32, Linear<f32>, AnyK2Law<f32>, Linear<f32>>;

impl slot::Block for hyst_affine_model_f32 {
    type Value = LinearShaped;
    const TAG: u32 = 0x4859_4c66; // "HYLf"
}

impl slot::Block for hyst_affine_compensator_f32 {
    type Value = LinearComp;
    const TAG: u32 = 0x4859_6c66; // "HYlf"
}

/// `hyst_affine_model_init_direct_f32` / `_inverse`.
///
/// # Safety
/// `m` is NULL or points to a writable `hyst_affine_model_f32`; `params` is NULL or readable.
unsafe fn init_linear(
    m: *mut hyst_affine_model_f32,
    params: *const hyst_shaped_model_params_f32,
    inverse: bool,
) -> i32 {
    if params.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: non-NULL (checked), readable (caller's contract).
    let p = unsafe { params.read() };
    let built = p
        .model_with(engine::linear_shaping)
        .and_then(|model| engine::shaped(model, p.form, p.linear, p.initial_state, inverse));
    match built {
        // SAFETY: `m` is NULL or a writable block of the type's size.
        Ok(shaped) => unsafe { slot::put(m, shaped) },
        Err(e) => status::of(&e),
    }
}

/// Initialises `m` as the model of `params` (form and start rule included), as
/// `hyst_shaped_model_init_direct_f32`; also `HYST_ERR_INVALID_PARAMETER` when a shaping's kind is
/// not `HYST_SHAPING_IDENTITY` or `HYST_SHAPING_AFFINE` (use `hyst_shaped_model_*` then).
///
/// # Safety
/// `m` is NULL or points to a writable `hyst_affine_model_f32`; `params` is NULL or readable.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_model_init_direct_f32(
    m: *mut hyst_affine_model_f32,
    params: *const hyst_shaped_model_params_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { init_linear(m, params, false) }
}

/// Initialises `m` as the exact inverse of the model of `params`, as
/// `hyst_shaped_model_init_inverse_f32` (the same refusals as `hyst_affine_model_init_direct_f32`).
///
/// # Safety
/// As `hyst_affine_model_init_direct_f32`.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_model_init_inverse_f32(
    m: *mut hyst_affine_model_f32,
    params: *const hyst_shaped_model_params_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { init_linear(m, params, true) }
}

/// One sample, as `hyst_shaped_model_step_f32`.
///
/// # Safety
/// `m` is NULL or an initialised `hyst_affine_model_f32`; `y` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_model_step_f32(
    m: *mut hyst_affine_model_f32,
    x: f32,
    y: *mut f32,
) -> i32 {
    // SAFETY: `y` is NULL or writable (caller's contract).
    done(slot::get_mut(m).map(|o| unsafe { engine::step(o, x, y) }))
}

/// Copies the memory of the model's operator into `*memory`, as
/// `hyst_shaped_model_get_memory_f32`.
///
/// # Safety
/// `m` is NULL or an initialised `hyst_affine_model_f32`; `memory` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_model_get_memory_f32(
    m: *mut hyst_affine_model_f32,
    memory: *mut hyst_memory_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { get_memory(slot::get_mut(m), memory) }
}

/// Restores the memory of the model's operator, as `hyst_shaped_model_set_memory_f32`.
///
/// # Safety
/// `m` is NULL or an initialised `hyst_affine_model_f32`; `memory` is NULL or readable.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_model_set_memory_f32(
    m: *mut hyst_affine_model_f32,
    memory: *const hyst_memory_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { set_memory(slot::get_mut(m), memory) }
}

/// Forgets the history: the start rule applies again at the next sample.
///
/// # Safety
/// `m` is NULL or an initialised `hyst_affine_model_f32`.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_model_reset_f32(m: *mut hyst_affine_model_f32) -> i32 {
    reset(slot::get_mut(m))
}

/// Initialises `c` as the Lemma 5.1 compensator of the model of `params`, as
/// `hyst_shaped_compensator_init_f32` (the same refusals, and those of
/// `hyst_affine_model_init_direct_f32`).
///
/// # Safety
/// `c` is NULL or points to a writable `hyst_affine_compensator_f32`; `params` is NULL or
/// readable; `a` and `v0` are NULL or hold n values.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_compensator_init_f32(
    c: *mut hyst_affine_compensator_f32,
    params: *const hyst_shaped_model_params_f32,
    b: f32,
    a: *const f32,
    v0: *const f32,
    n: usize,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { init_from_params(c, params, b, a, v0, n, engine::linear_shaping) }
}

/// One sample, as `hyst_shaped_compensator_step_f32`.
///
/// # Safety
/// `c` is NULL or an initialised `hyst_affine_compensator_f32`; `u` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_compensator_step_f32(
    c: *mut hyst_affine_compensator_f32,
    u_new: f32,
    dt: f32,
    u: *mut f32,
) -> i32 {
    // SAFETY: `u` is NULL or writable (caller's contract).
    done(slot::get_mut(c).map(|comp| unsafe { comp_step(comp, u_new, dt, u) }))
}

/// The integrators and the inverse model's memory, as `hyst_shaped_compensator_get_state_f32`.
///
/// # Safety
/// `c` is NULL or an initialised `hyst_affine_compensator_f32`; `v` is NULL or holds n values;
/// `memory` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_compensator_get_state_f32(
    c: *mut hyst_affine_compensator_f32,
    v: *mut f32,
    memory: *mut hyst_memory_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    done(slot::get_mut(c).map(|comp| unsafe { comp_state(comp, v, memory) }))
}

/// Back to the initial integrator state, and the inverse model's memory forgotten.
///
/// # Safety
/// `c` is NULL or an initialised `hyst_affine_compensator_f32`.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_compensator_reset_f32(
    c: *mut hyst_affine_compensator_f32,
) -> i32 {
    done(slot::get_mut(c).map(|comp| {
        comp.reset();
        HYST_OK
    }))
}
