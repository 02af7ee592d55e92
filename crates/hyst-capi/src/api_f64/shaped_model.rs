//! The shaped model ψ_out ∘ H ∘ ψ_in (Section 4.3) and its exact inverse
//! ψ_in⁻¹ ∘ H⁻¹ ∘ ψ_out⁻¹ with their memory, in caller memory (`hyst_shaped_model_*`), and
//! its parameters (`hyst_shaped_model_params`: k1, the k2 law, ψ_in and ψ_out).
//!
//! Its `float` twin is generated from this file by `scripts/gen-capi-f32`: edit this one.

use crate::api_f64::checks::done;
use crate::api_f64::memory::{get_memory, hyst_memory, reset, set_memory};
use crate::engine::{self, Shaped};
use crate::slot;
use crate::status::{self, HYST_ERR_NULL_POINTER};
use hyst_core::{AnyK2Law, Hysteresis, ShapedModel};

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
pub struct hyst_shaping {
    /// Which shape (`HYST_SHAPING_*`).
    pub kind: i32,
    /// The shape's parameters (see the table).
    pub p: [f64; 6],
    /// Scale applied to x before the shape, > 0.
    pub pre_gain: f64,
    /// Offset added after that scale.
    pub pre_offset: f64,
    /// Scale of the shape's value, > 0.
    pub post_gain: f64,
    /// Offset of ψ.
    pub post_offset: f64,
}

/// The k2 law (1 / operator-input units): `HYST_K2_CONSTANT` (0): k2 = `value`;
/// `HYST_K2_AFFINE` (1): k2 = φ(v) = `value` + `slope` · v clamped to [`min`, `max`]
/// (Proposition 4.3; 0 < min ≤ max).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct hyst_k2_law {
    /// `HYST_K2_CONSTANT` or `HYST_K2_AFFINE`.
    pub kind: i32,
    /// k2 (constant), or φ(0) (affine).
    pub value: f64,
    /// dφ/dv (affine only).
    pub slope: f64,
    /// Lower clamp, > 0 (affine only).
    pub min: f64,
    /// Upper clamp, ≥ min (affine only).
    pub max: f64,
}

/// The parameters of the shaped model y = ψ_out(H(k1, k2)[ψ_in(x)]) (Section 4.3), or of its
/// stop form y = ψ_out(v − H[v]) + c·v, v = ψ_in(x), with its start rule, for
/// `hyst_shaped_model_init_direct`, `hyst_shaped_model_init_inverse` and
/// `hyst_shaped_compensator_init`. A zeroed `initial_state`, `form` and `linear` give the
/// shaped model with no history.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct hyst_shaped_model_params {
    /// k1 > 0: the half-width of the loop, in the units of ψ_in's value.
    pub k1: f64,
    /// The k2 law.
    pub k2: hyst_k2_law,
    /// ψ_in: from input units to the operator's units.
    pub input: hyst_shaping,
    /// ψ_out: from the operator's units to output units.
    pub output: hyst_shaping,
    /// The start rule (`HYST_INITIAL_STATE_*`): without history (after init or reset) the model
    /// starts at its next sample on the line, or at rest on the lower (`_RISING`) or upper
    /// (`_FALLING`) asymptote through it, as `hyst run --model` starts a record. The inverse
    /// starts where the rule puts the model that produces its first desired output.
    pub initial_state: i32,
    /// `HYST_FORM_OPERATOR` or `HYST_FORM_STOP` (direct only: the stop form has no inverse).
    pub form: i32,
    /// c of the stop form's linear term (output units per operator unit); 0 for the operator
    /// form.
    pub linear: f64,
}

impl hyst_shaped_model_params {
    /// The model these parameters describe in its form and with its start rule, direct or
    /// inverse, checked by the core.
    pub(crate) fn shaped(&self, inverse: bool) -> Result<Shaped<f64>, hyst_core::Error> {
        let model = self.model()?;
        engine::shaped(model, self.form, self.linear, self.initial_state, inverse)
    }

    /// The shaped model these parameters describe (operator form, no start rule), checked by
    /// the core.
    pub(crate) fn model(&self) -> Result<engine::AnyShapedModel<f64>, hyst_core::Error> {
        self.model_with(engine::shaping)
    }

    /// The shaped model these parameters describe with each shaping built by `shaping` (kind,
    /// p, pre_gain, pre_offset, post_gain, post_offset): [`engine::shaping`] for every kind,
    /// [`engine::linear_shaping`] for the affine ones only.
    pub(crate) fn model_with<S: hyst_core::Shaping<f64>>(
        &self,
        shaping: engine::ShapingFn<f64, S>,
    ) -> Result<ShapedModel<f64, S, AnyK2Law<f64>, S>, hyst_core::Error> {
        let k2 = &self.k2;
        let law = engine::k2_law(k2.kind, k2.value, k2.slope, k2.min, k2.max)?;
        let s = |s: &hyst_shaping| {
            shaping(
                s.kind,
                s.p,
                s.pre_gain,
                s.pre_offset,
                s.post_gain,
                s.post_offset,
            )
        };
        ShapedModel::new(
            s(&self.input)?,
            Hysteresis::with_k2_law(self.k1, law)?,
            s(&self.output)?,
        )
    }
}

/// The shaped model ψ_out ∘ H ∘ ψ_in, or its exact inverse ψ_in⁻¹ ∘ H⁻¹ ∘ ψ_out⁻¹, with its
/// memory: an opaque block of 384 bytes, 8-byte aligned, plain data.
#[repr(C)]
pub struct hyst_shaped_model {
    opaque: [u64; 48],
}

impl slot::Block for hyst_shaped_model {
    type Value = Shaped<f64>;
    const TAG: u32 = 0x4859_5364; // "HYSd"
}

/// `hyst_shaped_model_init_direct` / `_inverse`.
///
/// # Safety
/// `m` is NULL or points to a writable `hyst_shaped_model`; `params` is NULL or readable.
unsafe fn init_shaped(
    m: *mut hyst_shaped_model,
    params: *const hyst_shaped_model_params,
    inverse: bool,
) -> i32 {
    if params.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: non-NULL (checked), readable (caller's contract).
    match unsafe { params.read() }.shaped(inverse) {
        // SAFETY: `m` is NULL or a writable block of the type's size.
        Ok(shaped) => unsafe { slot::put(m, shaped) },
        Err(e) => status::of(&e),
    }
}

/// Initialises `m` as the shaped model y = ψ_out(H(k1, k2)[ψ_in(x)]) of `params`, with no
/// history.
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, `HYST_ERR_MISALIGNED`,
/// `HYST_ERR_INVALID_PARAMETER` or `HYST_ERR_NOT_MONOTONE` (`m` is then untouched).
///
/// # Safety
/// `m` is NULL or points to a writable `hyst_shaped_model`; `params` is NULL or readable.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_model_init_direct(
    m: *mut hyst_shaped_model,
    params: *const hyst_shaped_model_params,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { init_shaped(m, params, false) }
}

/// Initialises `m` as the exact inverse x = ψ_in⁻¹(H⁻¹(k1, k2)[ψ_out⁻¹(y_d)]) of the shaped
/// model of `params` (a desired output y_d in, the command x out), with no history.
///
/// Returns as `hyst_shaped_model_init_direct`.
///
/// # Safety
/// As `hyst_shaped_model_init_direct`.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_model_init_inverse(
    m: *mut hyst_shaped_model,
    params: *const hyst_shaped_model_params,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { init_shaped(m, params, true) }
}

/// One sample, as `hyst_operator_step`; the inverse also returns `HYST_ERR_OUT_OF_RANGE` for a
/// desired output beyond a saturating shaping function (and holds the last command).
///
/// # Safety
/// `m` is NULL or an initialised `hyst_shaped_model`; `y` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_model_step(
    m: *mut hyst_shaped_model,
    x: f64,
    y: *mut f64,
) -> i32 {
    // SAFETY: `y` is NULL or writable (caller's contract).
    done(slot::get_mut(m).map(|o| unsafe { engine::step(o, x, y) }))
}

/// One sample with time derivatives, as `hyst_operator_step_derivatives` (order ≤ 4).
///
/// # Safety
/// `m` is NULL or an initialised `hyst_shaped_model`; `x` and `y` are NULL or hold
/// `order + 1` values.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_model_step_derivatives(
    m: *mut hyst_shaped_model,
    x: *const f64,
    y: *mut f64,
    order: usize,
) -> i32 {
    // SAFETY: `x`, `y` are NULL or hold order + 1 values (caller's contract).
    done(slot::get_mut(m).map(|o| unsafe { engine::step_derivatives(o, x, y, order) }))
}

/// `n` samples, as `hyst_operator_process`.
///
/// # Safety
/// `m` is NULL or an initialised `hyst_shaped_model`; when n > 0, `x` and `y` are NULL or hold
/// `n` values.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_model_process(
    m: *mut hyst_shaped_model,
    x: *const f64,
    y: *mut f64,
    n: usize,
) -> i32 {
    // SAFETY: `x`, `y` are NULL or hold n values (caller's contract).
    done(slot::get_mut(m).map(|o| unsafe { engine::process(o, x, y, n) }))
}

/// Copies the memory of the model's operator H (or H⁻¹) into `*memory`.
///
/// # Safety
/// `m` is NULL or an initialised `hyst_shaped_model`; `memory` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_model_get_memory(
    m: *mut hyst_shaped_model,
    memory: *mut hyst_memory,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { get_memory(slot::get_mut(m), memory) }
}

/// Restores the memory of the model's operator, as `hyst_operator_set_memory` (values in the
/// operator's units: after ψ_in for the direct model, after ψ_out⁻¹ for the inverse).
///
/// # Safety
/// `m` is NULL or an initialised `hyst_shaped_model`; `memory` is NULL or readable.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_model_set_memory(
    m: *mut hyst_shaped_model,
    memory: *const hyst_memory,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { set_memory(slot::get_mut(m), memory) }
}

/// Forgets the history.
///
/// # Safety
/// `m` is NULL or an initialised `hyst_shaped_model`.
#[no_mangle]
pub unsafe extern "C" fn hyst_shaped_model_reset(m: *mut hyst_shaped_model) -> i32 {
    reset(slot::get_mut(m))
}
