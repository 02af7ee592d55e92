//! The Lemma 5.1 compensators for a plant b / (a_n sⁿ + … + a_1 s + 1), n ≤ 4, before the
//! hysteresis, in caller memory: of the plain operator H(k1, k2) (`hyst_compensator_*`) and of
//! a shaped model (`hyst_shaped_compensator_*`), the same functions for the two models.
//!
//! Its `float` twin is generated from this file by `scripts/gen-capi-f32`: edit this one.

use hyst_core::{AnyK2Law, ConstantK2, Identity, InverseHysteresis, ShapedModel};

use crate::api_f64::checks::{done, read_array};
use crate::api_f64::memory::hyst_memory;
use crate::api_f64::shaped_model::hyst_shaped_model_params;
use crate::engine::{self, Comp, MemoryFields, PlainComp, ShapedComp};
use crate::slot;
use crate::status::{self, HYST_ERR_LENGTH, HYST_ERR_NULL_POINTER, HYST_OK};

/// The Lemma 5.1 compensator of the plain operator H(k1, k2) for a plant
/// b / (a_n sⁿ + … + a_1 s + 1), n ≤ 4, before the hysteresis: an opaque block of 320 bytes,
/// 8-byte aligned, plain data.
#[repr(C)]
pub struct hyst_compensator {
    opaque: [u64; 40],
}

/// The Lemma 5.1 compensator of a shaped model (`hyst_shaped_model_params`), n ≤ 4: an opaque
/// block of 512 bytes, 8-byte aligned, plain data.
#[repr(C)]
pub struct hyst_shaped_compensator {
    opaque: [u64; 64],
}

impl slot::Block for hyst_compensator {
    type Value = PlainComp<f64>;
    const TAG: u32 = 0x4859_4364; // "HYCd"
}

impl slot::Block for hyst_shaped_compensator {
    type Value = ShapedComp<f64>;
    const TAG: u32 = 0x4859_6364; // "HYcd"
}

/// Reads the plant (a_1 … a_n) and the optional start of the integrators (n values each).
///
/// # Safety
/// `a` and `v0` are NULL or hold n values.
pub(crate) unsafe fn plant(
    a: *const f64,
    v0: *const f64,
    n: usize,
) -> Result<
    (
        [f64; engine::HYST_MAX_ORDER + 1],
        Option<[f64; engine::HYST_MAX_ORDER + 1]>,
    ),
    i32,
> {
    if n > engine::HYST_MAX_ORDER {
        return Err(HYST_ERR_LENGTH);
    }
    // SAFETY: `a` is NULL or holds n values (caller's contract).
    let coefficients = unsafe { read_array(a, n) }?;
    let state = if v0.is_null() {
        None
    } else {
        // SAFETY: `v0` holds n values (caller's contract).
        Some(unsafe { read_array(v0, n) }?)
    };
    Ok((coefficients, state))
}

/// Builds the compensator of `inverse` for the plant read by [`plant`].
pub(crate) fn build<I, K, O>(
    inverse: hyst_core::InverseShapedModel<f64, I, K, O>,
    b: f64,
    plant: &(
        [f64; engine::HYST_MAX_ORDER + 1],
        Option<[f64; engine::HYST_MAX_ORDER + 1]>,
    ),
    n: usize,
) -> Result<Comp<f64, I, K, O>, hyst_core::Error>
where
    I: hyst_core::Shaping<f64> + Clone,
    K: hyst_core::K2Law<f64> + Clone,
    O: hyst_core::Shaping<f64> + Clone,
{
    let (a, v0) = plant;
    engine::compensator(
        inverse,
        b,
        a.get(..n).unwrap_or(&[]),
        v0.as_ref().and_then(|v| v.get(..n)),
    )
}

/// `_step`: the command, or the held one with the status.
///
/// # Safety
/// `u` is NULL or writable.
pub(crate) unsafe fn comp_step<I, K, O>(
    comp: &mut Comp<f64, I, K, O>,
    u_new: f64,
    dt: f64,
    u: *mut f64,
) -> i32
where
    I: hyst_core::Shaping<f64> + Clone,
    K: hyst_core::K2Law<f64> + Clone,
    O: hyst_core::Shaping<f64> + Clone,
{
    if u.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    let (value, status) = match comp.step(u_new, dt) {
        Ok(v) => (v, HYST_OK),
        Err((e, held)) => (held, status::of(&e)),
    };
    // SAFETY: non-NULL (checked), writable (caller's contract).
    unsafe { u.write(value) };
    status
}

/// `_track`: the command for the reference [v, v̇, …, v⁽ⁿ⁾].
///
/// # Safety
/// `reference` is NULL or holds n + 1 values; `u` is NULL or writable.
pub(crate) unsafe fn comp_track<I, K, O>(
    comp: &mut Comp<f64, I, K, O>,
    reference: *const f64,
    u: *mut f64,
) -> i32
where
    I: hyst_core::Shaping<f64> + Clone,
    K: hyst_core::K2Law<f64> + Clone,
    O: hyst_core::Shaping<f64> + Clone,
{
    if u.is_null() || reference.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: `reference` holds n + 1 values (caller's contract).
    let r = match unsafe { read_array(reference, comp.order() + 1) } {
        Ok(r) => r,
        Err(s) => return s,
    };
    match comp.track(r.get(..=comp.order()).unwrap_or(&[])) {
        Ok(value) => {
            // SAFETY: non-NULL (checked), writable (caller's contract).
            unsafe { u.write(value) };
            HYST_OK
        }
        Err(e) => status::of(&e),
    }
}

/// `_get_state`: the integrators into `v` (n values) and the memory into `*memory` (if given).
///
/// # Safety
/// `v` is NULL or holds n values; `memory` is NULL or writable.
pub(crate) unsafe fn comp_state<I, K, O>(
    comp: &Comp<f64, I, K, O>,
    v: *mut f64,
    memory: *mut hyst_memory,
) -> i32
where
    I: hyst_core::Shaping<f64> + Clone,
    K: hyst_core::K2Law<f64> + Clone,
    O: hyst_core::Shaping<f64> + Clone,
{
    let n = comp.order();
    if n > 0 && v.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    let mut state = [0.0; engine::HYST_MAX_ORDER];
    comp.state(&mut state);
    for (k, value) in state.iter().enumerate().take(n) {
        // SAFETY: k < n, within the caller's array.
        unsafe { v.add(k).write(*value) };
    }
    if !memory.is_null() {
        // SAFETY: non-NULL (checked), writable (caller's contract).
        unsafe { memory.write(hyst_memory::of(MemoryFields::of(comp.memory()))) };
    }
    HYST_OK
}

/// Initialises `c` as the Lemma 5.1 compensator of the plain operator H(k1, k2) for the plant
/// b / (a_n sⁿ + … + a_1 s + 1) before the hysteresis: `a` = [a_1, …, a_n], n ≤ 4 (NULL when
/// n = 0). The integrators v, v̇, …, v⁽ⁿ⁻¹⁾ start at `v0` (n values), or at 0 when `v0` is NULL;
/// `hyst_compensator_reset` returns there.
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, `HYST_ERR_MISALIGNED`, `HYST_ERR_LENGTH` (n > 4), or
/// `HYST_ERR_INVALID_PARAMETER` (k1, k2 not finite and > 0, b zero or not finite, a non-finite
/// coefficient or start); `c` is then untouched.
///
/// # Safety
/// `c` is NULL or points to a writable `hyst_compensator`; `a` and `v0` are NULL or hold n
/// values.
#[no_mangle]
pub unsafe extern "C" fn hyst_compensator_init(
    c: *mut hyst_compensator,
    k1: f64,
    k2: f64,
    b: f64,
    a: *const f64,
    v0: *const f64,
    n: usize,
) -> i32 {
    // SAFETY: `a`, `v0` are NULL or hold n values (caller's contract).
    let plant = match unsafe { plant(a, v0, n) } {
        Ok(p) => p,
        Err(s) => return s,
    };
    let built = InverseHysteresis::new(k1, k2)
        .and_then(|h| ShapedModel::new(Identity, h.direct(), Identity))
        .and_then(|m: ShapedModel<f64, Identity, ConstantK2<f64>, Identity>| {
            build(m.inverse(), b, &plant, n)
        });
    match built {
        // SAFETY: `c` is NULL or a writable block of the type's size.
        Ok(comp) => unsafe { slot::put(c, comp) },
        Err(e) => status::of(&e),
    }
}

/// One sample: `*u` = the command u(t) of eq. (19) for the new input v⁽ⁿ⁾ = `u_new`, then the
/// integrators advance by `dt` seconds (exactly, with u_new held). With the exact model the
/// plant's hysteresis output follows v, n integrators behind u_new (eq. 20). A non-finite
/// `u_new` or `dt` (or dt < 0) returns `HYST_ERR_NON_FINITE`, leaves the state unchanged and
/// writes the last command to `*u`.
///
/// # Safety
/// `c` is NULL or an initialised `hyst_compensator`; `u` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_compensator_step(
    c: *mut hyst_compensator,
    u_new: f64,
    dt: f64,
    u: *mut f64,
) -> i32 {
    // SAFETY: `u` is NULL or writable (caller's contract).
    done(slot::get_mut(c).map(|comp| unsafe { comp_step(comp, u_new, dt, u) }))
}

/// Reference-trajectory mode: `*u` = the command for the reference `reference` =
/// [v, v̇, …, v⁽ⁿ⁾] (n + 1 values; the integrators are set to it). On an error `*u` and the
/// state are untouched.
///
/// # Safety
/// `c` is NULL or an initialised `hyst_compensator`; `reference` is NULL or holds n + 1 values;
/// `u` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_compensator_track(
    c: *mut hyst_compensator,
    reference: *const f64,
    u: *mut f64,
) -> i32 {
    // SAFETY: forwarded contract.
    done(slot::get_mut(c).map(|comp| unsafe { comp_track(comp, reference, u) }))
}

/// Copies the integrators (v, v̇, …, v⁽ⁿ⁻¹⁾) into `v` (n values; may be NULL when n = 0) and the
/// memory of the compensator's inverse operator into `*memory` (when not NULL).
///
/// # Safety
/// `c` is NULL or an initialised `hyst_compensator`; `v` is NULL or holds n values; `memory` is
/// NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_compensator_get_state(
    c: *mut hyst_compensator,
    v: *mut f64,
    memory: *mut hyst_memory,
) -> i32 {
    // SAFETY: forwarded contract.
    done(slot::get_mut(c).map(|comp| unsafe { comp_state(comp, v, memory) }))
}

/// Back to the initial integrator state, and the inverse operator's memory forgotten.
///
/// # Safety
/// `c` is NULL or an initialised `hyst_compensator`.
#[no_mangle]
pub unsafe extern "C" fn hyst_compensator_reset(c: *mut hyst_compensator) -> i32 {
    done(slot::get_mut(c).map(|comp| {
        comp.reset();
        HYST_OK
    }))
}

/// Initialises `c` as the Lemma 5.1 compensator of the shaped model `params`, as
/// `hyst_compensator_init` (which it equals for identity shaping and constant k2). Also returns
/// `HYST_ERR_NOT_MONOTONE` for a shaping function that is not increasing, and
/// `HYST_ERR_INVALID_PARAMETER` for the stop form or a start rule other than
/// `HYST_INITIAL_STATE_LINE` (the integrators' state `v0` sets the history).
///
/// # Safety
/// `c` is NULL or points to a writable `hyst_shaped_compensator`; `params` is NULL or readable;
/// `a` and `v0` are NULL or hold n values.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_compensator_init(
    c: *mut hyst_shaped_compensator,
    params: *const hyst_shaped_model_params,
    b: f64,
    a: *const f64,
    v0: *const f64,
    n: usize,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { init_from_params(c, params, b, a, v0, n, engine::shaping) }
}

/// `hyst_shaped_compensator_init` and `hyst_affine_compensator_init`: the compensator of the
/// model of `params`, its shapings built by `shaping`, written into `c`.
///
/// # Safety
/// `c` is NULL or a writable block of its type; `params` is NULL or readable; `a` and `v0` are
/// NULL or hold n values.
pub(crate) unsafe fn init_from_params<C, S>(
    c: *mut C,
    params: *const hyst_shaped_model_params,
    b: f64,
    a: *const f64,
    v0: *const f64,
    n: usize,
    shaping: engine::ShapingFn<f64, S>,
) -> i32
where
    C: slot::Block<Value = Comp<f64, S, AnyK2Law<f64>, S>>,
    S: hyst_core::Shaping<f64> + Clone,
{
    if params.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: `a`, `v0` are NULL or hold n values (caller's contract).
    let plant = match unsafe { plant(a, v0, n) } {
        Ok(p) => p,
        Err(s) => return s,
    };
    // SAFETY: non-NULL (checked), readable (caller's contract).
    let params = unsafe { params.read() };
    let built = engine::compensated_form(params.form, params.initial_state)
        .and_then(|()| params.model_with(shaping))
        .and_then(|model| build(model.inverse(), b, &plant, n));
    match built {
        // SAFETY: `c` is NULL or a writable block of its type (caller's contract).
        Ok(comp) => unsafe { slot::put(c, comp) },
        Err(e) => status::of(&e),
    }
}

/// One sample, as `hyst_compensator_step`; also `HYST_ERR_OUT_OF_RANGE` for a reference beyond a
/// saturating output shaping function.
///
/// # Safety
/// `c` is NULL or an initialised `hyst_shaped_compensator`; `u` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_compensator_step(
    c: *mut hyst_shaped_compensator,
    u_new: f64,
    dt: f64,
    u: *mut f64,
) -> i32 {
    // SAFETY: `u` is NULL or writable (caller's contract).
    done(slot::get_mut(c).map(|comp| unsafe { comp_step(comp, u_new, dt, u) }))
}

/// Reference-trajectory mode, as `hyst_compensator_track`.
///
/// # Safety
/// `c` is NULL or an initialised `hyst_shaped_compensator`; `reference` is NULL or holds n + 1
/// values; `u` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_compensator_track(
    c: *mut hyst_shaped_compensator,
    reference: *const f64,
    u: *mut f64,
) -> i32 {
    // SAFETY: forwarded contract.
    done(slot::get_mut(c).map(|comp| unsafe { comp_track(comp, reference, u) }))
}

/// The integrators and the inverse model's memory, as `hyst_compensator_get_state`.
///
/// # Safety
/// `c` is NULL or an initialised `hyst_shaped_compensator`; `v` is NULL or holds n values;
/// `memory` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_compensator_get_state(
    c: *mut hyst_shaped_compensator,
    v: *mut f64,
    memory: *mut hyst_memory,
) -> i32 {
    // SAFETY: forwarded contract.
    done(slot::get_mut(c).map(|comp| unsafe { comp_state(comp, v, memory) }))
}

/// Back to the initial integrator state, and the inverse model's memory forgotten.
///
/// # Safety
/// `c` is NULL or an initialised `hyst_shaped_compensator`.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_compensator_reset(c: *mut hyst_shaped_compensator) -> i32 {
    done(slot::get_mut(c).map(|comp| {
        comp.reset();
        HYST_OK
    }))
}
