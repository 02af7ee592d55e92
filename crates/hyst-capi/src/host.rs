//! The host part: fitted model files (the CLI's TOML, docs/formats.md), run exactly as
//! `hyst run --model` runs them.

use std::ffi::{c_char, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;
use std::ptr;

use ::hyst_model::{Evaluator, ModelError, ModelFile, Saturated};
use hyst_core::Operator;

use crate::status::{
    self, HYST_ERR_INTERNAL, HYST_ERR_INVALID_PARAMETER, HYST_ERR_MODEL_FILE,
    HYST_ERR_NULL_POINTER, HYST_OK,
};

/// A fitted model loaded from a model file, with the state of its direct run and of its
/// inverse run (opaque; create with `hyst_model_load`, release with `hyst_model_free`).
pub struct hyst_model {
    file: ModelFile,
    direct: Option<Saturated<Evaluator>>,
    inverse: Option<Saturated<Evaluator>>,
    /// The inverse's clamp limits (`hyst_model_saturate`); `None`: nothing is clamped.
    limits: Option<(f64, f64)>,
}

/// Copies `message` into the caller's buffer (truncated at a character boundary, always
/// NUL-terminated when `len` > 0).
///
/// # Safety
/// `buffer` is NULL or writable for `len` bytes.
unsafe fn copy_message(buffer: *mut c_char, len: usize, message: &str) {
    if buffer.is_null() || len == 0 {
        return;
    }
    let mut end = message.len().min(len - 1);
    while !message.is_char_boundary(end) {
        end -= 1;
    }
    // SAFETY: `end` < len bytes fit the buffer, plus the NUL at `end`.
    unsafe {
        ptr::copy_nonoverlapping(message.as_ptr().cast::<c_char>(), buffer, end);
        buffer.add(end).write(0);
    }
}

/// Loads and checks a model file. Returns NULL on failure and writes the reason (naming the
/// file, and the line and key where the file is wrong) into `error` (`error_len` bytes,
/// NUL-terminated, truncated if needed; `error` may be NULL).
///
/// # Safety
/// `path` is NULL or a NUL-terminated string; `error` is NULL or writable for `error_len` bytes.
#[no_mangle]
pub unsafe extern "C" fn hyst_model_load(
    path: *const c_char,
    error: *mut c_char,
    error_len: usize,
) -> *mut hyst_model {
    let result = catch_unwind(|| {
        if path.is_null() {
            return Err("the path is NULL".to_string());
        }
        // SAFETY: non-NULL and NUL-terminated (caller's contract).
        let path = unsafe { CStr::from_ptr(path) };
        let path = path
            .to_str()
            .map_err(|_| format!("the path {path:?} is not UTF-8"))?;
        let file = ModelFile::read(Path::new(path)).map_err(|e| e.to_string())?;
        Ok(Box::new(hyst_model {
            file,
            direct: None,
            inverse: None,
            limits: None,
        }))
    });
    let message = match result {
        Ok(Ok(model)) => return Box::into_raw(model),
        Ok(Err(message)) => message,
        Err(_) => "internal error while loading the model file".to_string(),
    };
    // SAFETY: `error` is NULL or writable for `error_len` bytes (caller's contract).
    unsafe { copy_message(error, error_len, &message) };
    ptr::null_mut()
}

/// Runs the model over `n` samples from `x` into `y` (which may be the same array): the direct
/// model (`inverse` = 0: input → output) or its exact inverse (`inverse` ≠ 0: desired output →
/// command). The first call of each kind after `hyst_model_load` or `hyst_model_reset` starts a
/// record from the model's start rule at `x[0]`, exactly as `hyst run --model`; later calls
/// continue it, so a signal may be fed in blocks. Results are bit-identical to
/// `hyst run --model FILE [--inverse]` on the same samples.
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, or the status of the first sample the model
/// refuses (non-finite, beyond a saturating shaping function: `HYST_ERR_OUT_OF_RANGE`); `y` then
/// holds the outputs before it, and the run stops there with its state unchanged by that sample.
///
/// # Safety
/// `m` is NULL or a model from `hyst_model_load` not yet freed; when n > 0, `x` and `y` are NULL
/// or hold `n` values.
#[no_mangle]
pub unsafe extern "C" fn hyst_model_process(
    m: *mut hyst_model,
    inverse: i32,
    x: *const f64,
    y: *mut f64,
    n: usize,
) -> i32 {
    if m.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    if n == 0 {
        return HYST_OK;
    }
    if x.is_null() || y.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: a live model from `hyst_model_load` (caller's contract), not aliased during the call.
    let model = unsafe { &mut *m };
    catch_unwind(AssertUnwindSafe(|| {
        let inverse = inverse != 0;
        let (slot, limits) = if inverse {
            (&mut model.inverse, model.limits)
        } else {
            (&mut model.direct, None)
        };
        if slot.is_none() {
            // SAFETY: n > 0 and `x` holds n values.
            let first = unsafe { x.read() };
            let first = Saturated::new((), limits).clamp(first).unwrap_or(first);
            match model.file.evaluator(first, inverse) {
                Ok(e) => *slot = Some(Saturated::new(e, limits)),
                Err(ModelError::Core(e)) => return status::of(&e),
                Err(_) => return HYST_ERR_MODEL_FILE,
            }
        }
        let Some(evaluator) = slot.as_mut() else {
            return HYST_ERR_INTERNAL;
        };
        for i in 0..n {
            // SAFETY: i < n, within the caller's arrays; read before write, so x == y is fine.
            let xi = unsafe { x.add(i).read() };
            match evaluator.try_step(xi) {
                // SAFETY: as above.
                Ok(v) => unsafe { y.add(i).write(v) },
                Err(e) => return status::of(&e),
            }
        }
        HYST_OK
    }))
    .unwrap_or(HYST_ERR_INTERNAL)
}

/// Makes the inverse (`hyst_model_process` with `inverse` ≠ 0) clamp every desired output
/// beyond a saturating model's limits (tanh or Langevin output shaping, whose range itself is
/// unreachable: 99.9 % of the range about its centre, widened to every output over the model's
/// fitted input range) to them instead of refusing it with `HYST_ERR_OUT_OF_RANGE`, as
/// `hyst run --inverse --saturate` does; `on` = 0 turns it off. Takes effect at once, also in
/// an inverse run already started. `hyst_model_clamped` counts the clamped values.
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, or `HYST_ERR_INVALID_PARAMETER` when `on` ≠ 0
/// and the model's output is unbounded (nothing could need clamping; nothing changes).
///
/// # Safety
/// `m` is NULL or a model from `hyst_model_load` not yet freed.
#[no_mangle]
pub unsafe extern "C" fn hyst_model_saturate(m: *mut hyst_model, on: i32) -> i32 {
    if m.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: a live model (caller's contract).
    let model = unsafe { &mut *m };
    let limits = if on != 0 {
        match model.file.saturation() {
            Some(s) => Some(s.limits),
            None => return HYST_ERR_INVALID_PARAMETER,
        }
    } else {
        None
    };
    model.limits = limits;
    if let Some(run) = model.inverse.as_mut() {
        run.limits = limits;
    }
    HYST_OK
}

/// Writes into `*count` how many desired outputs the inverse clamped
/// (`hyst_model_saturate`) since the model was loaded or reset.
///
/// Returns `HYST_OK` or `HYST_ERR_NULL_POINTER`.
///
/// # Safety
/// `m` is NULL or a model from `hyst_model_load` not yet freed; `count` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_model_clamped(m: *const hyst_model, count: *mut u64) -> i32 {
    if m.is_null() || count.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: a live model (caller's contract).
    let model = unsafe { &*m };
    // SAFETY: non-NULL and writable (caller's contract).
    unsafe { count.write(model.inverse.as_ref().map_or(0, |r| r.clamped)) };
    HYST_OK
}

/// Forgets both runs: the next `hyst_model_process` of each kind starts a new record.
///
/// # Safety
/// `m` is NULL or a model from `hyst_model_load` not yet freed.
#[no_mangle]
pub unsafe extern "C" fn hyst_model_reset(m: *mut hyst_model) -> i32 {
    if m.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: a live model (caller's contract).
    let model = unsafe { &mut *m };
    model.direct = None;
    model.inverse = None;
    HYST_OK
}

/// Releases a model from `hyst_model_load` (NULL is ignored).
///
/// # Safety
/// `m` is NULL or a model from `hyst_model_load` not yet freed; it must not be used afterwards.
#[no_mangle]
pub unsafe extern "C" fn hyst_model_free(m: *mut hyst_model) {
    if !m.is_null() {
        // SAFETY: from `Box::into_raw` in `hyst_model_load`, freed once (caller's contract).
        drop(unsafe { Box::from_raw(m) });
    }
}
