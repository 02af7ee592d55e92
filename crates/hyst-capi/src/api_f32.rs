//! The firmware API in `float`: GENERATED from `api_f64.rs` by `scripts/gen-capi-f32` (do not
//! edit; edit api_f64.rs and run the script). No allocation, no standard library; every state lives in
//! caller memory.

use hyst_core::{ConstantK2, Identity, InverseHysteresis, ShapedModel};

use crate::engine::{self, Comp, MemoryFields, Pair, PlainComp, Shaped, ShapedComp};
use crate::slot;
use crate::status::{self, HYST_ERR_LENGTH, HYST_ERR_NULL_POINTER, HYST_OK};

// ---------------------------------------------------------------------------------------------
// Plain data the caller reads and writes.

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

/// A shaping function (Section 4.3) with the scale and offsets of measured data:
/// ψ(x) = `post_gain` · shape(`pre_gain` · x + `pre_offset`) + `post_offset`, the form of a
/// fitted model's ψ_in and ψ_out. `kind` and the shape's parameters `p`:
///
/// | kind | shape | p |
/// |---|---|---|
/// | `HYST_SHAPING_IDENTITY` (0) | z | – |
/// | `HYST_SHAPING_AFFINE` (1) | p0 z + p1 | gain > 0, offset |
/// | `HYST_SHAPING_POLYNOMIAL` (2) | p0 + p1 z + p2 z² + p3 z³ on [p4, p5], tangents outside | c0…c3, lo, hi (±INFINITY allowed), increasing |
/// | `HYST_SHAPING_TANH` (3) | p0 tanh(z / p1) | gain > 0, scale > 0 |
/// | `HYST_SHAPING_LANGEVIN` (4) | p0 L(z / p1) | gain > 0, scale > 0 |
/// | `HYST_SHAPING_QUADRATIC_EXP` (5) | z − p0 z² − e^(−(p1 + p2 z)) on [p3, p4] | a ≥ 0, b, c ≥ 0, lo, hi |
///
/// Unused entries of `p` are ignored. Both gains must be > 0 (use 1 and 0 for no scaling).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct hyst_shaping_f32 {
    /// Which shape (`HYST_SHAPING_*`).
    pub kind: i32,
    /// The shape's parameters (see the table).
    pub p: [f32; 6],
    /// Scale applied to x before the shape, > 0.
    pub pre_gain: f32,
    /// Offset added after that scale.
    pub pre_offset: f32,
    /// Scale of the shape's value, > 0.
    pub post_gain: f32,
    /// Offset of ψ.
    pub post_offset: f32,
}

/// The k2 law (1 / operator-input units): `HYST_K2_CONSTANT` (0): k2 = `value`;
/// `HYST_K2_AFFINE` (1): k2 = φ(v) = `value` + `slope` · v clamped to [`min`, `max`]
/// (Proposition 4.3; 0 < min ≤ max).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct hyst_k2_law_f32 {
    /// `HYST_K2_CONSTANT` or `HYST_K2_AFFINE`.
    pub kind: i32,
    /// k2 (constant), or φ(0) (affine).
    pub value: f32,
    /// dφ/dv (affine only).
    pub slope: f32,
    /// Lower clamp, > 0 (affine only).
    pub min: f32,
    /// Upper clamp, ≥ min (affine only).
    pub max: f32,
}

/// The shaped model out = ψ_out(H(k1, k2)[ψ_in(in)]) (Section 4.3).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct hyst_model_params_f32 {
    /// k1 > 0: the half-width of the loop, in the units of ψ_in's value.
    pub k1: f32,
    /// The k2 law.
    pub k2: hyst_k2_law_f32,
    /// ψ_in: from input units to the operator's units.
    pub input: hyst_shaping_f32,
    /// ψ_out: from the operator's units to output units.
    pub output: hyst_shaping_f32,
}

impl hyst_model_params_f32 {
    fn model(&self) -> Result<engine::AnyShapedModel<f32>, hyst_core::Error> {
        let k2 = &self.k2;
        let law = engine::k2_law(k2.kind, k2.value, k2.slope, k2.min, k2.max)?;
        let s = |s: &hyst_shaping_f32| {
            engine::shaping(
                s.kind,
                s.p,
                s.pre_gain,
                s.pre_offset,
                s.post_gain,
                s.post_offset,
            )
        };
        engine::shaped_model(self.k1, law, s(&self.input)?, s(&self.output)?)
    }
}

// ---------------------------------------------------------------------------------------------
// State blocks in caller memory (opaque: initialise with `_init_*`, then pass by pointer).

/// The parametric operator H(k1, k2) (eq. 2) or H⁻¹(k1, k2) (eq. 4) with its memory: an opaque
/// block of 64 bytes, 8-byte aligned, plain data (copyable with memcpy).
#[repr(C)]
pub struct hyst_operator_f32 {
    opaque: [u64; 8],
}

/// The shaped model ψ_out ∘ H ∘ ψ_in, or its exact inverse ψ_in⁻¹ ∘ H⁻¹ ∘ ψ_out⁻¹, with its
/// memory: an opaque block of 192 bytes, 8-byte aligned, plain data.
#[repr(C)]
pub struct hyst_shaped_model_f32 {
    opaque: [u64; 24],
}

/// The Lemma 5.1 compensator of the plain operator H(k1, k2) for a plant
/// b / (a_n sⁿ + … + a_1 s + 1), n ≤ 4, before the hysteresis: an opaque block of 160 bytes,
/// 8-byte aligned, plain data.
#[repr(C)]
pub struct hyst_compensator_f32 {
    opaque: [u64; 20],
}

/// The Lemma 5.1 compensator of a shaped model (`hyst_model_params_f32`), n ≤ 4: an opaque block of
/// 512 bytes, 8-byte aligned, plain data.
#[repr(C)]
pub struct hyst_shaped_compensator_f32 {
    opaque: [u64; 32],
}

const TAG_OPERATOR: u32 = 0x4859_5f66; // "HY_f"
const TAG_SHAPED: u32 = 0x4859_5366; // "HYSf"
const TAG_COMPENSATOR: u32 = 0x4859_4366; // "HYCf"
const TAG_SHAPED_COMPENSATOR: u32 = 0x4859_6366; // "HYcf"

const _: () = assert!(slot::fits::<hyst_operator_f32, Pair<f32>>());
const _: () = assert!(slot::fits::<hyst_shaped_model_f32, Shaped<f32>>());
const _: () = assert!(slot::fits::<hyst_compensator_f32, PlainComp<f32>>());
const _: () = assert!(slot::fits::<hyst_shaped_compensator_f32, ShapedComp<f32>>());

fn operator<'a>(op: *mut hyst_operator_f32) -> Result<&'a mut dyn engine::Dyn<f32>, i32> {
    // SAFETY: the caller of the C function passes NULL, an initialised block, or any other
    // readable block of the type's size (whose tag then does not match).
    unsafe { slot::value_mut::<_, Pair<f32>>(op, TAG_OPERATOR) }.map(Pair::as_dyn)
}

fn shaped<'a>(m: *mut hyst_shaped_model_f32) -> Result<&'a mut dyn engine::Dyn<f32>, i32> {
    // SAFETY: as in `operator`.
    unsafe { slot::value_mut::<_, Shaped<f32>>(m, TAG_SHAPED) }.map(Shaped::as_dyn)
}

/// `_get_memory` of an operator or a shaped model.
///
/// # Safety
/// `memory` is NULL or writable.
unsafe fn get_memory(
    op: Result<&mut dyn engine::Dyn<f32>, i32>,
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
unsafe fn set_memory(
    op: Result<&mut dyn engine::Dyn<f32>, i32>,
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
fn reset(op: Result<&mut dyn engine::Dyn<f32>, i32>) -> i32 {
    done(op.map(|o| {
        o.reset();
        HYST_OK
    }))
}

fn compensator<'a>(c: *mut hyst_compensator_f32) -> Result<&'a mut PlainComp<f32>, i32> {
    // SAFETY: as in `operator`.
    unsafe { slot::value_mut(c, TAG_COMPENSATOR) }
}

fn shaped_compensator<'a>(
    c: *mut hyst_shaped_compensator_f32,
) -> Result<&'a mut ShapedComp<f32>, i32> {
    // SAFETY: as in `operator`.
    unsafe { slot::value_mut(c, TAG_SHAPED_COMPENSATOR) }
}

fn status_of<T>(result: Result<T, hyst_core::Error>) -> Result<T, i32> {
    result.map_err(|e| status::of(&e))
}

/// Reads `n` values from `p` (NULL only when n = 0) into a fixed array.
///
/// # Safety
/// `p` is NULL or valid for `n` reads.
unsafe fn read_array(p: *const f32, n: usize) -> Result<[f32; engine::HYST_MAX_ORDER + 1], i32> {
    let mut out = [0.0_f32; engine::HYST_MAX_ORDER + 1];
    if n > out.len() {
        return Err(HYST_ERR_LENGTH);
    }
    if n > 0 && p.is_null() {
        return Err(HYST_ERR_NULL_POINTER);
    }
    for (k, slot) in out.iter_mut().enumerate().take(n) {
        // SAFETY: k < n, within the caller's array.
        *slot = unsafe { p.add(k).read() };
    }
    Ok(out)
}

/// `hyst_operator_init_direct_f32` / `_inverse`.
///
/// # Safety
/// `op` is NULL or points to a writable `hyst_operator_f32`.
unsafe fn init_operator(op: *mut hyst_operator_f32, k1: f32, k2: f32, inverse: bool) -> i32 {
    match engine::pair(k1, k2, inverse) {
        // SAFETY: `op` is NULL or a writable block of the type's size; `fits` holds (asserted).
        Ok(p) => unsafe { slot::write(op, TAG_OPERATOR, p) },
        Err(e) => status::of(&e),
    }
}

/// `hyst_shaped_model_init_direct_f32` / `_inverse`.
///
/// # Safety
/// `m` is NULL or points to a writable `hyst_shaped_model_f32`; `params` is NULL or readable.
unsafe fn init_shaped(
    m: *mut hyst_shaped_model_f32,
    params: *const hyst_model_params_f32,
    inverse: bool,
) -> i32 {
    if params.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: non-NULL (checked), readable (caller's contract).
    match unsafe { params.read() }.model() {
        Ok(model) => {
            let shaped = if inverse {
                Shaped::Inverse(model.inverse())
            } else {
                Shaped::Direct(model)
            };
            // SAFETY: `m` is NULL or a writable block of the type's size; `fits` holds.
            unsafe { slot::write(m, TAG_SHAPED, shaped) }
        }
        Err(e) => status::of(&e),
    }
}

fn done(result: Result<i32, i32>) -> i32 {
    result.unwrap_or_else(|status| status)
}

// ---------------------------------------------------------------------------------------------
// hyst_operator_f32

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

/// Initialises `op` as the inverse operator v = H⁻¹(k1, k2)[u_d] (eq. 4), the exact
/// compensator of `hyst_operator_init_direct_f32`'s operator, with no history.
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
    done(operator(op).map(|o| unsafe { engine::step(o, x, y) }))
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
    done(operator(op).map(|o| unsafe { engine::step_derivatives(o, x, y, order) }))
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
    done(operator(op).map(|o| unsafe { engine::process(o, x, y, n) }))
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
    unsafe { get_memory(operator(op), memory) }
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
    unsafe { set_memory(operator(op), memory) }
}

/// Forgets the history: the next sample starts on the line output = input.
///
/// # Safety
/// `op` is NULL or an initialised `hyst_operator_f32`.
#[no_mangle]
pub unsafe extern "C" fn hyst_operator_reset_f32(op: *mut hyst_operator_f32) -> i32 {
    reset(operator(op))
}

// ---------------------------------------------------------------------------------------------
// hyst_shaped_model_f32

/// Initialises `m` as the shaped model out = ψ_out(H(k1, k2)[ψ_in(in)]) of `params`, with no
/// history.
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, `HYST_ERR_MISALIGNED`,
/// `HYST_ERR_INVALID_PARAMETER` or `HYST_ERR_NOT_MONOTONE` (`m` is then untouched).
///
/// # Safety
/// `m` is NULL or points to a writable `hyst_shaped_model_f32`; `params` is NULL or readable.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_model_init_direct_f32(
    m: *mut hyst_shaped_model_f32,
    params: *const hyst_model_params_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { init_shaped(m, params, false) }
}

/// Initialises `m` as the exact compensator in = ψ_in⁻¹(H⁻¹(k1, k2)[ψ_out⁻¹(out)]) of the shaped
/// model of `params` (desired output in, command out), with no history.
///
/// Returns as `hyst_shaped_model_init_direct_f32`.
///
/// # Safety
/// As `hyst_shaped_model_init_direct_f32`.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_model_init_inverse_f32(
    m: *mut hyst_shaped_model_f32,
    params: *const hyst_model_params_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { init_shaped(m, params, true) }
}

/// One sample, as `hyst_operator_step_f32`; the inverse also returns `HYST_ERR_OUT_OF_RANGE` for a
/// desired output beyond a saturating shaping function (and holds the last command).
///
/// # Safety
/// `m` is NULL or an initialised `hyst_shaped_model_f32`; `y` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_model_step_f32(
    m: *mut hyst_shaped_model_f32,
    x: f32,
    y: *mut f32,
) -> i32 {
    // SAFETY: `y` is NULL or writable (caller's contract).
    done(shaped(m).map(|o| unsafe { engine::step(o, x, y) }))
}

/// One sample with time derivatives, as `hyst_operator_step_derivatives_f32` (order ≤ 4).
///
/// # Safety
/// `m` is NULL or an initialised `hyst_shaped_model_f32`; `x` and `y` are NULL or hold
/// `order + 1` values.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_model_step_derivatives_f32(
    m: *mut hyst_shaped_model_f32,
    x: *const f32,
    y: *mut f32,
    order: usize,
) -> i32 {
    // SAFETY: `x`, `y` are NULL or hold order + 1 values (caller's contract).
    done(shaped(m).map(|o| unsafe { engine::step_derivatives(o, x, y, order) }))
}

/// `n` samples, as `hyst_operator_process_f32`.
///
/// # Safety
/// `m` is NULL or an initialised `hyst_shaped_model_f32`; when n > 0, `x` and `y` are NULL or hold
/// `n` values.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_model_process_f32(
    m: *mut hyst_shaped_model_f32,
    x: *const f32,
    y: *mut f32,
    n: usize,
) -> i32 {
    // SAFETY: `x`, `y` are NULL or hold n values (caller's contract).
    done(shaped(m).map(|o| unsafe { engine::process(o, x, y, n) }))
}

/// Copies the memory of the model's operator H (or H⁻¹) into `*memory`.
///
/// # Safety
/// `m` is NULL or an initialised `hyst_shaped_model_f32`; `memory` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_model_get_memory_f32(
    m: *mut hyst_shaped_model_f32,
    memory: *mut hyst_memory_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { get_memory(shaped(m), memory) }
}

/// Restores the memory of the model's operator, as `hyst_operator_set_memory_f32` (values in the
/// operator's units: after ψ_in for the direct model, after ψ_out⁻¹ for the inverse).
///
/// # Safety
/// `m` is NULL or an initialised `hyst_shaped_model_f32`; `memory` is NULL or readable.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_model_set_memory_f32(
    m: *mut hyst_shaped_model_f32,
    memory: *const hyst_memory_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { set_memory(shaped(m), memory) }
}

/// Forgets the history.
///
/// # Safety
/// `m` is NULL or an initialised `hyst_shaped_model_f32`.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_model_reset_f32(m: *mut hyst_shaped_model_f32) -> i32 {
    reset(shaped(m))
}

// ---------------------------------------------------------------------------------------------
// hyst_compensator_f32 and hyst_shaped_compensator_f32: the same functions for two models.

/// Reads the plant (a_1 … a_n) and the optional start of the integrators (n values each).
///
/// # Safety
/// `a` and `v0` are NULL or hold n values.
unsafe fn plant(
    a: *const f32,
    v0: *const f32,
    n: usize,
) -> Result<
    (
        [f32; engine::HYST_MAX_ORDER + 1],
        Option<[f32; engine::HYST_MAX_ORDER + 1]>,
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
fn build<I, K, O>(
    inverse: hyst_core::InverseShapedModel<f32, I, K, O>,
    b: f32,
    plant: &(
        [f32; engine::HYST_MAX_ORDER + 1],
        Option<[f32; engine::HYST_MAX_ORDER + 1]>,
    ),
    n: usize,
) -> Result<Comp<f32, I, K, O>, hyst_core::Error>
where
    I: hyst_core::Shaping<f32> + Clone,
    K: hyst_core::K2Law<f32> + Clone,
    O: hyst_core::Shaping<f32> + Clone,
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
unsafe fn comp_step<I, K, O>(comp: &mut Comp<f32, I, K, O>, u_new: f32, dt: f32, u: *mut f32) -> i32
where
    I: hyst_core::Shaping<f32> + Clone,
    K: hyst_core::K2Law<f32> + Clone,
    O: hyst_core::Shaping<f32> + Clone,
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
unsafe fn comp_track<I, K, O>(
    comp: &mut Comp<f32, I, K, O>,
    reference: *const f32,
    u: *mut f32,
) -> i32
where
    I: hyst_core::Shaping<f32> + Clone,
    K: hyst_core::K2Law<f32> + Clone,
    O: hyst_core::Shaping<f32> + Clone,
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
unsafe fn comp_state<I, K, O>(
    comp: &Comp<f32, I, K, O>,
    v: *mut f32,
    memory: *mut hyst_memory_f32,
) -> i32
where
    I: hyst_core::Shaping<f32> + Clone,
    K: hyst_core::K2Law<f32> + Clone,
    O: hyst_core::Shaping<f32> + Clone,
{
    let n = comp.order();
    if n > 0 && v.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    let mut state = [0.0_f32; engine::HYST_MAX_ORDER];
    comp.state(&mut state);
    for (k, value) in state.iter().enumerate().take(n) {
        // SAFETY: k < n, within the caller's array.
        unsafe { v.add(k).write(*value) };
    }
    if !memory.is_null() {
        // SAFETY: non-NULL (checked), writable (caller's contract).
        unsafe { memory.write(hyst_memory_f32::of(MemoryFields::of(comp.memory()))) };
    }
    HYST_OK
}

/// Initialises `c` as the Lemma 5.1 compensator of the plain operator H(k1, k2) for the plant
/// b / (a_n sⁿ + … + a_1 s + 1) before the hysteresis: `a` = [a_1, …, a_n], n ≤ 4 (NULL when
/// n = 0). The integrators v, v̇, …, v⁽ⁿ⁻¹⁾ start at `v0` (n values), or at 0 when `v0` is NULL;
/// `hyst_compensator_reset_f32` returns there.
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, `HYST_ERR_MISALIGNED`, `HYST_ERR_LENGTH` (n > 4), or
/// `HYST_ERR_INVALID_PARAMETER` (k1, k2 not finite and > 0, b zero or not finite, a non-finite
/// coefficient or start); `c` is then untouched.
///
/// # Safety
/// `c` is NULL or points to a writable `hyst_compensator_f32`; `a` and `v0` are NULL or hold n
/// values.
#[no_mangle]
pub unsafe extern "C" fn hyst_compensator_init_f32(
    c: *mut hyst_compensator_f32,
    k1: f32,
    k2: f32,
    b: f32,
    a: *const f32,
    v0: *const f32,
    n: usize,
) -> i32 {
    // SAFETY: `a`, `v0` are NULL or hold n values (caller's contract).
    let plant = match unsafe { plant(a, v0, n) } {
        Ok(p) => p,
        Err(s) => return s,
    };
    let built = InverseHysteresis::new(k1, k2)
        .and_then(|h| ShapedModel::new(Identity, h.direct(), Identity))
        .and_then(|m: ShapedModel<f32, Identity, ConstantK2<f32>, Identity>| {
            build(m.inverse(), b, &plant, n)
        });
    match built {
        // SAFETY: `c` is NULL or a writable block of the type's size; `fits` holds.
        Ok(comp) => unsafe { slot::write(c, TAG_COMPENSATOR, comp) },
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
/// `c` is NULL or an initialised `hyst_compensator_f32`; `u` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_compensator_step_f32(
    c: *mut hyst_compensator_f32,
    u_new: f32,
    dt: f32,
    u: *mut f32,
) -> i32 {
    // SAFETY: `u` is NULL or writable (caller's contract).
    done(compensator(c).map(|comp| unsafe { comp_step(comp, u_new, dt, u) }))
}

/// Reference-trajectory mode: `*u` = the command for the reference `reference` =
/// [v, v̇, …, v⁽ⁿ⁾] (n + 1 values; the integrators are set to it). On an error `*u` and the
/// state are untouched.
///
/// # Safety
/// `c` is NULL or an initialised `hyst_compensator_f32`; `reference` is NULL or holds n + 1 values;
/// `u` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_compensator_track_f32(
    c: *mut hyst_compensator_f32,
    reference: *const f32,
    u: *mut f32,
) -> i32 {
    // SAFETY: forwarded contract.
    done(compensator(c).map(|comp| unsafe { comp_track(comp, reference, u) }))
}

/// Copies the integrators (v, v̇, …, v⁽ⁿ⁻¹⁾) into `v` (n values; may be NULL when n = 0) and the
/// memory of the compensator's inverse operator into `*memory` (when not NULL).
///
/// # Safety
/// `c` is NULL or an initialised `hyst_compensator_f32`; `v` is NULL or holds n values; `memory` is
/// NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_compensator_get_state_f32(
    c: *mut hyst_compensator_f32,
    v: *mut f32,
    memory: *mut hyst_memory_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    done(compensator(c).map(|comp| unsafe { comp_state(comp, v, memory) }))
}

/// Back to the initial integrator state, and the inverse operator's memory forgotten.
///
/// # Safety
/// `c` is NULL or an initialised `hyst_compensator_f32`.
#[no_mangle]
pub unsafe extern "C" fn hyst_compensator_reset_f32(c: *mut hyst_compensator_f32) -> i32 {
    done(compensator(c).map(|comp| {
        comp.reset();
        HYST_OK
    }))
}

/// Initialises `c` as the Lemma 5.1 compensator of the shaped model `params`, as
/// `hyst_compensator_init_f32` (which it equals for identity shaping and constant k2). Also returns
/// `HYST_ERR_NOT_MONOTONE` for a shaping function that is not increasing.
///
/// # Safety
/// `c` is NULL or points to a writable `hyst_shaped_compensator_f32`; `params` is NULL or readable;
/// `a` and `v0` are NULL or hold n values.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_compensator_init_f32(
    c: *mut hyst_shaped_compensator_f32,
    params: *const hyst_model_params_f32,
    b: f32,
    a: *const f32,
    v0: *const f32,
    n: usize,
) -> i32 {
    if params.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: `a`, `v0` are NULL or hold n values (caller's contract).
    let plant = match unsafe { plant(a, v0, n) } {
        Ok(p) => p,
        Err(s) => return s,
    };
    // SAFETY: non-NULL (checked), readable (caller's contract).
    let built = unsafe { params.read() }
        .model()
        .and_then(|model| build(model.inverse(), b, &plant, n));
    match built {
        // SAFETY: `c` is NULL or a writable block of the type's size; `fits` holds.
        Ok(comp) => unsafe { slot::write(c, TAG_SHAPED_COMPENSATOR, comp) },
        Err(e) => status::of(&e),
    }
}

/// One sample, as `hyst_compensator_step_f32`; also `HYST_ERR_OUT_OF_RANGE` for a reference beyond a
/// saturating output shaping function.
///
/// # Safety
/// `c` is NULL or an initialised `hyst_shaped_compensator_f32`; `u` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_compensator_step_f32(
    c: *mut hyst_shaped_compensator_f32,
    u_new: f32,
    dt: f32,
    u: *mut f32,
) -> i32 {
    // SAFETY: `u` is NULL or writable (caller's contract).
    done(shaped_compensator(c).map(|comp| unsafe { comp_step(comp, u_new, dt, u) }))
}

/// Reference-trajectory mode, as `hyst_compensator_track_f32`.
///
/// # Safety
/// `c` is NULL or an initialised `hyst_shaped_compensator_f32`; `reference` is NULL or holds n + 1
/// values; `u` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_compensator_track_f32(
    c: *mut hyst_shaped_compensator_f32,
    reference: *const f32,
    u: *mut f32,
) -> i32 {
    // SAFETY: forwarded contract.
    done(shaped_compensator(c).map(|comp| unsafe { comp_track(comp, reference, u) }))
}

/// The integrators and the inverse model's memory, as `hyst_compensator_get_state_f32`.
///
/// # Safety
/// `c` is NULL or an initialised `hyst_shaped_compensator_f32`; `v` is NULL or holds n values;
/// `memory` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_compensator_get_state_f32(
    c: *mut hyst_shaped_compensator_f32,
    v: *mut f32,
    memory: *mut hyst_memory_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    done(shaped_compensator(c).map(|comp| unsafe { comp_state(comp, v, memory) }))
}

/// Back to the initial integrator state, and the inverse model's memory forgotten.
///
/// # Safety
/// `c` is NULL or an initialised `hyst_shaped_compensator_f32`.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_compensator_reset_f32(
    c: *mut hyst_shaped_compensator_f32,
) -> i32 {
    done(shaped_compensator(c).map(|comp| {
        comp.reset();
        HYST_OK
    }))
}
