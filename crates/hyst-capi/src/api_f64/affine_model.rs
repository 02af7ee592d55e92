//! The shaped model whose shapings are affine (identity or affine shape, with their scalings:
//! what `hyst fit` writes by default), its inverse and stop form (`hyst_affine_model_*`), and
//! its Lemma 5.1 compensator (`hyst_affine_compensator_*`). The same parameters, arithmetic and
//! results as `hyst_shaped_model_*` and `hyst_shaped_compensator_*`, bit for bit, but a
//! firmware that uses them links none of the nonlinear shapes (tanh, Langevin, polynomial,
//! quadratic-exp and their inverses), which the run-time choice of `hyst_shaping.kind` brings.
//! `hyst export c` uses them for models with affine shapings.
//!
//! Its `float` twin is generated from this file by `scripts/gen-capi-f32`: edit this one.

use crate::api_f64::checks::done;
use crate::api_f64::compensator::{comp_state, comp_step, init_from_params};
use crate::api_f64::memory::{get_memory, hyst_memory, reset, set_memory};
use crate::api_f64::shaped_model::hyst_shaped_model_params;
use crate::engine::{self, Comp, Linear, Shaped};
use crate::slot;
use crate::status::{self, HYST_ERR_NULL_POINTER, HYST_OK};
use hyst_core::AnyK2Law;

/// The shaped model of `hyst_shaped_model_params` whose shapings are affine, as
/// `hyst_shaped_model`: an opaque block of 320 bytes, 8-byte aligned, plain data.
#[repr(C)]
pub struct hyst_affine_model {
    opaque: [u64; 40],
}

/// The Lemma 5.1 compensator of such a model, as `hyst_shaped_compensator`: an opaque
/// block of 448 bytes, 8-byte aligned, plain data.
#[repr(C)]
pub struct hyst_affine_compensator {
    opaque: [u64; 56],
}

/// The model inside.
type LinearShaped = Shaped<f64, Linear<f64>>;
/// The compensator inside.
type LinearComp = Comp<f64, Linear<f64>, AnyK2Law<f64>, Linear<f64>>;

impl slot::Block for hyst_affine_model {
    type Value = LinearShaped;
    const TAG: u32 = 0x4859_4c64; // "HYLd"
}

impl slot::Block for hyst_affine_compensator {
    type Value = LinearComp;
    const TAG: u32 = 0x4859_6c64; // "HYld"
}

/// `hyst_affine_model_init_direct` / `_inverse`.
///
/// # Safety
/// `m` is NULL or points to a writable `hyst_affine_model`; `params` is NULL or readable.
unsafe fn init_linear(
    m: *mut hyst_affine_model,
    params: *const hyst_shaped_model_params,
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
/// `hyst_shaped_model_init_direct`; also `HYST_ERR_INVALID_PARAMETER` when a shaping's kind is
/// not `HYST_SHAPING_IDENTITY` or `HYST_SHAPING_AFFINE` (use `hyst_shaped_model_*` then).
///
/// # Safety
/// `m` is NULL or points to a writable `hyst_affine_model`; `params` is NULL or readable.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_model_init_direct(
    m: *mut hyst_affine_model,
    params: *const hyst_shaped_model_params,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { init_linear(m, params, false) }
}

/// Initialises `m` as the exact inverse of the model of `params`, as
/// `hyst_shaped_model_init_inverse` (the same refusals as `hyst_affine_model_init_direct`).
///
/// # Safety
/// As `hyst_affine_model_init_direct`.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_model_init_inverse(
    m: *mut hyst_affine_model,
    params: *const hyst_shaped_model_params,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { init_linear(m, params, true) }
}

/// One sample, as `hyst_shaped_model_step`.
///
/// # Safety
/// `m` is NULL or an initialised `hyst_affine_model`; `y` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_model_step(
    m: *mut hyst_affine_model,
    x: f64,
    y: *mut f64,
) -> i32 {
    // SAFETY: `y` is NULL or writable (caller's contract).
    done(slot::get_mut(m).map(|o| unsafe { engine::step(o, x, y) }))
}

/// Copies the memory of the model's operator into `*memory`, as
/// `hyst_shaped_model_get_memory`.
///
/// # Safety
/// `m` is NULL or an initialised `hyst_affine_model`; `memory` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_model_get_memory(
    m: *mut hyst_affine_model,
    memory: *mut hyst_memory,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { get_memory(slot::get_mut(m), memory) }
}

/// Restores the memory of the model's operator, as `hyst_shaped_model_set_memory`.
///
/// # Safety
/// `m` is NULL or an initialised `hyst_affine_model`; `memory` is NULL or readable.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_model_set_memory(
    m: *mut hyst_affine_model,
    memory: *const hyst_memory,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { set_memory(slot::get_mut(m), memory) }
}

/// Forgets the history: the start rule applies again at the next sample.
///
/// # Safety
/// `m` is NULL or an initialised `hyst_affine_model`.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_model_reset(m: *mut hyst_affine_model) -> i32 {
    reset(slot::get_mut(m))
}

/// Initialises `c` as the Lemma 5.1 compensator of the model of `params`, as
/// `hyst_shaped_compensator_init` (the same refusals, and those of
/// `hyst_affine_model_init_direct`).
///
/// # Safety
/// `c` is NULL or points to a writable `hyst_affine_compensator`; `params` is NULL or
/// readable; `a` and `v0` are NULL or hold n values.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_compensator_init(
    c: *mut hyst_affine_compensator,
    params: *const hyst_shaped_model_params,
    b: f64,
    a: *const f64,
    v0: *const f64,
    n: usize,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { init_from_params(c, params, b, a, v0, n, engine::linear_shaping) }
}

/// One sample, as `hyst_shaped_compensator_step`.
///
/// # Safety
/// `c` is NULL or an initialised `hyst_affine_compensator`; `u` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_compensator_step(
    c: *mut hyst_affine_compensator,
    u_new: f64,
    dt: f64,
    u: *mut f64,
) -> i32 {
    // SAFETY: `u` is NULL or writable (caller's contract).
    done(slot::get_mut(c).map(|comp| unsafe { comp_step(comp, u_new, dt, u) }))
}

/// The integrators and the inverse model's memory, as `hyst_shaped_compensator_get_state`.
///
/// # Safety
/// `c` is NULL or an initialised `hyst_affine_compensator`; `v` is NULL or holds n values;
/// `memory` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_compensator_get_state(
    c: *mut hyst_affine_compensator,
    v: *mut f64,
    memory: *mut hyst_memory,
) -> i32 {
    // SAFETY: forwarded contract.
    done(slot::get_mut(c).map(|comp| unsafe { comp_state(comp, v, memory) }))
}

/// Back to the initial integrator state, and the inverse model's memory forgotten.
///
/// # Safety
/// `c` is NULL or an initialised `hyst_affine_compensator`.
#[no_mangle]
pub unsafe extern "C" fn hyst_affine_compensator_reset(c: *mut hyst_affine_compensator) -> i32 {
    done(slot::get_mut(c).map(|comp| {
        comp.reset();
        HYST_OK
    }))
}
