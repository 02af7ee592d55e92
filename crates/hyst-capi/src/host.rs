//! The host part: fitted model files (the CLI's TOML, docs/formats.md), run exactly as
//! `hyst run --model` runs them. A model with dynamics or a rate term needs the time steps of
//! its record: `hyst_model_load` refuses it, `hyst_model_load_timed` takes its nominal step and
//! runs it as `hyst run --model` runs a timed record (`hyst_model_process` at that step,
//! `hyst_model_process_steps` with each sample's own step), under the model file's hold
//! (`hyst_model_hold`, `hyst_model_set_hold`), with Lemma 5.1's compensator from the desired
//! output's derivatives (`hyst_model_compensate`).

use std::ffi::{c_char, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;
use std::ptr;

use ::hyst_model::{
    Evaluator, Hold, ModelError, ModelFile, Saturated, SmoothModel, TimedCompensator, TimedRun,
};
use hyst_core::Operator;

use crate::status::{
    self, HYST_ERR_INTERNAL, HYST_ERR_INVALID_PARAMETER, HYST_ERR_LENGTH, HYST_ERR_MODEL_FILE,
    HYST_ERR_NULL_POINTER, HYST_ERR_UNSUPPORTED, HYST_OK,
};

/// A fitted model loaded from a model file, with the state of its direct run and of its
/// inverse run (opaque; create with `hyst_model_load` or `hyst_model_load_timed`, release with
/// `hyst_model_free`).
pub struct hyst_model {
    pub(crate) file: ModelFile,
    /// The sample period (s) of `hyst_model_load_timed`; `None` from `hyst_model_load`.
    period: Option<f64>,
    pub(crate) direct: Option<Saturated<Evaluator>>,
    pub(crate) inverse: Option<Saturated<Evaluator>>,
    /// The direct run of a model with dynamics or a rate term.
    timed: Option<TimedRun>,
    /// Lemma 5.1's compensator of a model with dynamics (`hyst_model_compensate`).
    compensator: Option<TimedCompensator>,
    /// The inverse's clamp limits (`hyst_model_saturate`); `None`: nothing is clamped.
    pub(crate) limits: Option<(f64, f64)>,
}

impl hyst_model {
    /// The smooth model with dynamics or a rate term, if the file holds one.
    pub(crate) fn timed_model(&self) -> Option<&SmoothModel> {
        self.file.smooth.as_ref().filter(|m| m.is_timed())
    }
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
/// A model with dynamics or a rate term (a model file's `[dynamics]` or `[rate]`) is refused
/// with the reason: it needs the sample period of its record, which this function does not
/// take (`hyst_model_load_timed` does); its plant or rate term is never dropped.
///
/// # Safety
/// `path` is NULL or a NUL-terminated string; `error` is NULL or writable for `error_len` bytes.
#[no_mangle]
pub unsafe extern "C" fn hyst_model_load(
    path: *const c_char,
    error: *mut c_char,
    error_len: usize,
) -> *mut hyst_model {
    // SAFETY: the caller's contract.
    unsafe { load(path, None, error, error_len) }
}

/// Loads and checks a model file whose records are sampled at the period `period` (seconds,
/// finite and > 0), as `hyst_model_load` does otherwise. A model with dynamics or a rate term
/// then runs as `hyst run --model` runs a timed record of that period (the period `hyst run`
/// takes from the record's time stamps: their mean step): `hyst_model_process` (direct only)
/// gives its output, `hyst_model_process_steps` its output at uneven steps (this period their
/// nominal step), `hyst_model_compensate` Lemma 5.1's command. A model without them runs
/// exactly as from `hyst_model_load` (the period is not used). Returns NULL on failure, with
/// the reason in `error` as `hyst_model_load`.
///
/// # Safety
/// As `hyst_model_load`.
#[no_mangle]
pub unsafe extern "C" fn hyst_model_load_timed(
    path: *const c_char,
    period: f64,
    error: *mut c_char,
    error_len: usize,
) -> *mut hyst_model {
    // SAFETY: the caller's contract.
    unsafe { load(path, Some(period), error, error_len) }
}

/// `hyst_model_load` (`period` = `None`) and `hyst_model_load_timed`.
///
/// # Safety
/// As `hyst_model_load`.
unsafe fn load(
    path: *const c_char,
    period: Option<f64>,
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
        if let Some(p) = period.filter(|p| !(p.is_finite() && *p > 0.0)) {
            return Err(format!(
                "{path}: sample period {p}: must be finite and > 0 (seconds)"
            ));
        }
        let file = ModelFile::read(Path::new(path)).map_err(|e| e.to_string())?;
        if period.is_none() {
            file.untimed(
                "the C host API without a sample period (load it with hyst_model_load_timed)",
            )
            .map_err(|e| format!("{path}: {e}"))?;
        }
        Ok(Box::new(hyst_model {
            file,
            period,
            direct: None,
            inverse: None,
            timed: None,
            compensator: None,
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

/// `hyst_model_column`'s `which`: the model file's input column (`[columns]` `input`), the
/// command: what the direct model takes and its inverse gives.
pub const HYST_COLUMN_INPUT: i32 = 0;
/// `hyst_model_column`'s `which`: the model file's output column (`[columns]` `output`), the
/// measured output: what the direct model gives and its inverse takes.
pub const HYST_COLUMN_OUTPUT: i32 = 1;

/// Writes the name of one of the model's data columns, as the model file's `[columns]` names it
/// (the columns `hyst fit` fitted it on), into `name`: `which` = `HYST_COLUMN_INPUT` (0) the
/// input column (the command), `HYST_COLUMN_OUTPUT` (1) the output column. These are the names
/// `hyst run --model` uses: its default input column (the input column, the output column with
/// `--inverse`) and the name of the column it computes (the output column, the input column
/// with `--inverse`). The name is UTF-8, written NUL-terminated into `name` (`name_len` bytes);
/// `*needed` gets the bytes it takes with its NUL (`needed` may be NULL), so a call with
/// `name` = NULL and `name_len` = 0 sizes the buffer.
///
/// Returns `HYST_OK` when the whole name was written; `HYST_ERR_LENGTH` when it does not fit
/// (`name` then holds as much of it as fits, cut at a character boundary and NUL-terminated when
/// `name_len` > 0; `*needed` says the size to give); `HYST_ERR_NULL_POINTER` when `m` is NULL,
/// or `name` is NULL and `name_len` > 0; `HYST_ERR_INVALID_PARAMETER` for another `which`;
/// `HYST_ERR_MODEL_FILE` for a name holding a NUL byte, which a C string cannot hold. Nothing
/// is written on the last three.
///
/// # Safety
/// `m` is NULL or a model from `hyst_model_load` or `hyst_model_load_timed` not yet freed;
/// `name` is NULL or writable for `name_len` bytes; `needed` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_model_column(
    m: *const hyst_model,
    which: i32,
    name: *mut c_char,
    name_len: usize,
    needed: *mut usize,
) -> i32 {
    if m.is_null() || (name.is_null() && name_len > 0) {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: a live model (caller's contract).
    let model = unsafe { &*m };
    let column = match which {
        HYST_COLUMN_INPUT => model.file.columns.input.as_str(),
        HYST_COLUMN_OUTPUT => model.file.columns.output.as_str(),
        _ => return HYST_ERR_INVALID_PARAMETER,
    };
    if column.contains('\0') {
        return HYST_ERR_MODEL_FILE;
    }
    let size = column.len().saturating_add(1);
    if !needed.is_null() {
        // SAFETY: non-NULL and writable (caller's contract).
        unsafe { needed.write(size) };
    }
    // SAFETY: `name` is NULL (then `name_len` is 0) or writable for `name_len` bytes.
    unsafe { copy_message(name, name_len, column) };
    if name_len < size {
        HYST_ERR_LENGTH
    } else {
        HYST_OK
    }
}

/// Runs the model over `n` samples from `x` into `y` (which may be the same array): the direct
/// model (`inverse` = 0: input → output) or its exact inverse (`inverse` ≠ 0: desired output →
/// command). The first call of each kind after `hyst_model_load` or `hyst_model_reset` starts a
/// record from the model's start rule at `x[0]`, exactly as `hyst run --model`; later calls
/// continue it, so a signal may be fed in blocks. Results are bit-identical to
/// `hyst run --model FILE [--inverse]` on the same samples.
///
/// A model with dynamics or a rate term (loaded by `hyst_model_load_timed`) runs its direct
/// model over samples of the period given there, bit-identical to `hyst run --model FILE` on a
/// timed record of that period (`hyst_model_process_steps` takes each sample's step); its
/// inverse is `hyst_model_compensate`, and `inverse` ≠ 0 gives
/// `HYST_ERR_UNSUPPORTED`.
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, `HYST_ERR_UNSUPPORTED`, or the status of the first
/// sample the model refuses (non-finite, beyond a saturating shaping function:
/// `HYST_ERR_OUT_OF_RANGE`); `y` then holds the outputs before it, and the run stops there with
/// its state unchanged by that sample.
///
/// # Safety
/// `m` is NULL or a model from `hyst_model_load` or `hyst_model_load_timed` not yet freed; when
/// n > 0, `x` and `y` are NULL or hold `n` values.
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
    // SAFETY: a live model (caller's contract), not aliased during the call.
    let model = unsafe { &mut *m };
    if model.timed_model().is_some() {
        if inverse != 0 {
            return HYST_ERR_UNSUPPORTED;
        }
        // SAFETY: n > 0, and `x` and `y` hold n values (caller's contract).
        return catch_unwind(AssertUnwindSafe(|| unsafe {
            process_timed(model, x, None, y, n)
        }))
        .unwrap_or(HYST_ERR_INTERNAL);
    }
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

/// The direct run of a model with dynamics or a rate term: `hyst_model_process` with
/// `inverse` = 0 (`step` NULL: every step the nominal one), `hyst_model_process_steps`.
///
/// # Safety
/// n > 0; `x` and `y` hold `n` values, `step` (when not `None`) too.
unsafe fn process_timed(
    model: &mut hyst_model,
    x: *const f64,
    step: Option<*const f64>,
    y: *mut f64,
    n: usize,
) -> i32 {
    let (Some(smooth), Some(period)) = (model.timed_model(), model.period) else {
        return HYST_ERR_UNSUPPORTED;
    };
    if model.timed.is_none() {
        // SAFETY: n > 0 and `x` holds n values.
        let first = unsafe { x.read() };
        match TimedRun::new(smooth, period, first) {
            Ok(run) => model.timed = Some(run),
            Err(e) => return status::of(&e),
        }
    }
    let Some(run) = model.timed.as_mut() else {
        return HYST_ERR_INTERNAL;
    };
    for i in 0..n {
        // SAFETY: i < n, within the caller's arrays; read before write, so x == y is fine.
        let xi = unsafe { x.add(i).read() };
        let sample = match step {
            // SAFETY: i < n, within the caller's array.
            Some(step) => run.step_after(xi, unsafe { step.add(i).read() }),
            None => run.step(xi),
        };
        match sample {
            // SAFETY: as above.
            Ok(s) => unsafe { y.add(i).write(s.y) },
            Err(e) => return status::of(&e),
        }
    }
    HYST_OK
}

/// `hyst_model_process` of a model with dynamics or a rate term (loaded by
/// `hyst_model_load_timed`) over samples at uneven time steps: `step[i]` is the time (s) from
/// the sample before to sample `i` (t_i − t_{i−1}, the difference of the raw stamps; ignored
/// for the first sample of a record, which starts at rest). The plant is discretised for each
/// step's own length, and a step within 1e-9 (relative) of the period given to
/// `hyst_model_load_timed` is taken as it: with that period the record's mean step, results are
/// bit-identical to `hyst run --model FILE` on a record with those time stamps. A gap that
/// `hyst run` would split the record at is the caller's to see (`hyst_model_reset` starts the
/// next record at rest).
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, `HYST_ERR_UNSUPPORTED` (a model without dynamics
/// or a rate term, which takes no time: `hyst_model_process`), or the status of the first sample
/// refused (`HYST_ERR_INVALID_PARAMETER` for a step that is not finite and > 0); `y` then holds
/// the outputs before it, and the run stops there with its state unchanged by that sample.
///
/// # Safety
/// `m` is NULL or a model from `hyst_model_load_timed` not yet freed; when n > 0, `x`, `step`
/// and `y` are NULL or hold `n` values (`x` and `y` may be the same array).
#[no_mangle]
pub unsafe extern "C" fn hyst_model_process_steps(
    m: *mut hyst_model,
    x: *const f64,
    step: *const f64,
    y: *mut f64,
    n: usize,
) -> i32 {
    if m.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: a live model (caller's contract), not aliased during the call.
    let model = unsafe { &mut *m };
    if model.timed_model().is_none() {
        return HYST_ERR_UNSUPPORTED;
    }
    if n == 0 {
        return HYST_OK;
    }
    if x.is_null() || step.is_null() || y.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: n > 0, and `x`, `step` and `y` hold n values (caller's contract).
    catch_unwind(AssertUnwindSafe(|| unsafe {
        process_timed(model, x, Some(step), y, n)
    }))
    .unwrap_or(HYST_ERR_INTERNAL)
}

/// `hyst_model_hold`, `hyst_model_set_hold`: the zero-order hold, the command held over each
/// step (a model file's `[dynamics] hold = "zoh"`).
pub const HYST_HOLD_ZOH: i32 = 0;
/// `hyst_model_hold`, `hyst_model_set_hold`: the first-order hold, the command linear between
/// samples (`hold = "foh"`, or no `hold`).
pub const HYST_HOLD_FOH: i32 = 1;

/// Writes the hold of the model's plant (`HYST_HOLD_ZOH` or `HYST_HOLD_FOH`: the model file's
/// `[dynamics] hold`, or what `hyst_model_set_hold` set) into `*hold`.
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, or `HYST_ERR_UNSUPPORTED` for a model without
/// dynamics (nothing is written).
///
/// # Safety
/// `m` is NULL or a model not yet freed; `hold` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_model_hold(m: *const hyst_model, hold: *mut i32) -> i32 {
    if m.is_null() || hold.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: a live model (caller's contract).
    let model = unsafe { &*m };
    let Some(d) = model.file.smooth.as_ref().and_then(|s| s.dynamics) else {
        return HYST_ERR_UNSUPPORTED;
    };
    let value = match d.hold() {
        Hold::Zoh => HYST_HOLD_ZOH,
        Hold::Foh => HYST_HOLD_FOH,
    };
    // SAFETY: non-NULL and writable (caller's contract).
    unsafe { hold.write(value) };
    HYST_OK
}

/// Runs the model's plant under `hold` (`HYST_HOLD_ZOH` or `HYST_HOLD_FOH`) instead of the
/// model file's, as `hyst run --hold`; the direct run starts a new record at the next
/// `hyst_model_process` (as after `hyst_model_reset`). The compensator
/// (`hyst_model_compensate`) does not depend on the hold.
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, `HYST_ERR_INVALID_PARAMETER` for another `hold`,
/// or `HYST_ERR_UNSUPPORTED` for a model without dynamics; nothing changes on an error.
///
/// # Safety
/// `m` is NULL or a model not yet freed.
#[no_mangle]
pub unsafe extern "C" fn hyst_model_set_hold(m: *mut hyst_model, hold: i32) -> i32 {
    if m.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    let hold = match hold {
        HYST_HOLD_ZOH => Hold::Zoh,
        HYST_HOLD_FOH => Hold::Foh,
        _ => return HYST_ERR_INVALID_PARAMETER,
    };
    // SAFETY: a live model (caller's contract), not aliased during the call.
    let model = unsafe { &mut *m };
    let Some(smooth) = model.file.smooth.as_mut() else {
        return HYST_ERR_UNSUPPORTED;
    };
    let Some(d) = smooth.dynamics else {
        return HYST_ERR_UNSUPPORTED;
    };
    smooth.dynamics = Some(d.with_hold(hold));
    model.timed = None;
    HYST_OK
}

/// Lemma 5.1's compensator of a model with dynamics (loaded by `hyst_model_load_timed`): for
/// `n` samples of the desired output and its first `order` time derivatives, the commands that
/// make the plant and the hysteresis give that output, bit-identical to
/// `hyst run --model FILE --inverse` on a timed record whose columns `NAME`, `NAME_d1`, …,
/// `NAME_dN` hold them. `desired` holds `n` rows of `order` + 1 values, one sample after the
/// other: `desired[i * (order + 1) + k]` is the k-th derivative of sample i (k = 0: the desired
/// output itself); `order` must be the plant order N (the model file's `[dynamics]` a has N
/// coefficients). Writes `n` commands into `command`. The first call after
/// `hyst_model_load_timed` or `hyst_model_reset` starts the compensator from the model's start
/// rule at `desired[0]`; later calls continue it, so a signal may be fed in blocks.
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, `HYST_ERR_LENGTH` (`order` is not the plant
/// order), `HYST_ERR_UNSUPPORTED` (a model without dynamics, whose compensator is its exact
/// inverse, `hyst_model_process`; or with a rate term, or of the stop form: they have no
/// compensator), or the status of the first sample the compensator refuses; `command` then
/// holds the commands before it, and the compensator stops there, unchanged by that sample.
///
/// # Safety
/// `m` is NULL or a model from `hyst_model_load_timed` not yet freed; when n > 0, `desired` is
/// NULL or holds `n * (order + 1)` values and `command` is NULL or holds `n` values; they do not
/// overlap.
#[no_mangle]
pub unsafe extern "C" fn hyst_model_compensate(
    m: *mut hyst_model,
    desired: *const f64,
    order: usize,
    command: *mut f64,
    n: usize,
) -> i32 {
    if m.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: a live model (caller's contract), not aliased during the call.
    let model = unsafe { &mut *m };
    let Some(smooth) = model.timed_model() else {
        return HYST_ERR_UNSUPPORTED;
    };
    if TimedCompensator::check(smooth).is_err() {
        return HYST_ERR_UNSUPPORTED;
    }
    if smooth.dynamics.map(|d| d.order()) != Some(order) {
        return HYST_ERR_LENGTH;
    }
    if n == 0 {
        return HYST_OK;
    }
    if desired.is_null() || command.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    let Some(len) = n.checked_mul(order + 1) else {
        return HYST_ERR_LENGTH;
    };
    // SAFETY: non-NULL, `len` values (caller's contract), not written during the call.
    let desired = unsafe { std::slice::from_raw_parts(desired, len) };
    // SAFETY: non-NULL, `n` values (caller's contract), not overlapping `desired`.
    let command = unsafe { std::slice::from_raw_parts_mut(command, n) };
    catch_unwind(AssertUnwindSafe(|| {
        compensate(model, desired, order, command)
    }))
    .unwrap_or(HYST_ERR_INTERNAL)
}

/// The body of `hyst_model_compensate` on checked slices.
fn compensate(model: &mut hyst_model, desired: &[f64], order: usize, command: &mut [f64]) -> i32 {
    let Some(smooth) = model.timed_model() else {
        return HYST_ERR_UNSUPPORTED;
    };
    if model.compensator.is_none() {
        let first = desired.first().copied().unwrap_or(f64::NAN);
        match TimedCompensator::new(smooth, first) {
            Ok(c) => model.compensator = Some(c),
            Err(ModelError::Core(e)) => return status::of(&e),
            Err(_) => return HYST_ERR_UNSUPPORTED,
        }
    }
    let Some(compensator) = model.compensator.as_mut() else {
        return HYST_ERR_INTERNAL;
    };
    for (row, u) in desired.chunks_exact(order + 1).zip(command.iter_mut()) {
        match compensator.step(row) {
            Ok((value, _)) => *u = value,
            Err(ModelError::Core(e)) => return status::of(&e),
            Err(_) => return HYST_ERR_INTERNAL,
        }
    }
    HYST_OK
}

/// Makes the inverse (`hyst_model_process` with `inverse` ≠ 0) clamp every desired output
/// beyond the limits of a model whose output is bounded (by a tanh or Langevin output or input
/// shaping: the outputs reachable from every state within 99.9 % of each saturating shaping's
/// range, widened to every output over the model's fitted input range; `hyst_model_saturation`
/// gives them) instead of refusing it with `HYST_ERR_OUT_OF_RANGE`, as
/// `hyst run --inverse --saturate` does; `on` = 0 turns it off. Takes effect at once, also in
/// an inverse run already started. `hyst_model_saturated` counts the clamped values.
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, `HYST_ERR_INVALID_PARAMETER` when `on` ≠ 0
/// and the model's output is unbounded (nothing could need clamping; nothing changes), or
/// `HYST_ERR_UNSUPPORTED` when `on` ≠ 0 for a model with dynamics or a rate term (as
/// `hyst run --saturate` refuses it).
///
/// # Safety
/// `m` is NULL or a model from `hyst_model_load` or `hyst_model_load_timed` not yet freed.
#[no_mangle]
pub unsafe extern "C" fn hyst_model_saturate(m: *mut hyst_model, on: i32) -> i32 {
    if m.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: a live model (caller's contract).
    let model = unsafe { &mut *m };
    if on != 0 && model.timed_model().is_some() {
        return HYST_ERR_UNSUPPORTED;
    }
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

/// Writes the open range of a bounded model's outputs into `range[0]`, `range[1]` (no command,
/// from any state, gives them or beyond) and the limits `hyst_model_saturate` clamps desired
/// outputs into into `limits[0]`, `limits[1]`: the figures `hyst run --inverse` names when it
/// refuses a desired output out of reach (`HYST_ERR_OUT_OF_RANGE` here).
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, `HYST_ERR_INVALID_PARAMETER` when the model's
/// output is unbounded (nothing is written), or `HYST_ERR_UNSUPPORTED` for a model with
/// dynamics or a rate term.
///
/// # Safety
/// `m` is NULL or a model from `hyst_model_load` or `hyst_model_load_timed` not yet freed;
/// `range` and `limits` are NULL or writable for 2 values each.
#[no_mangle]
pub unsafe extern "C" fn hyst_model_saturation(
    m: *const hyst_model,
    range: *mut f64,
    limits: *mut f64,
) -> i32 {
    if m.is_null() || range.is_null() || limits.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: a live model (caller's contract).
    let model = unsafe { &*m };
    if model.timed_model().is_some() {
        return HYST_ERR_UNSUPPORTED;
    }
    let Some(s) = model.file.saturation() else {
        return HYST_ERR_INVALID_PARAMETER;
    };
    // SAFETY: both writable for 2 values (caller's contract).
    unsafe {
        range.write(s.range.0);
        range.add(1).write(s.range.1);
        limits.write(s.limits.0);
        limits.add(1).write(s.limits.1);
    }
    HYST_OK
}

/// Writes into `*count` how many desired outputs the inverse saturated (clamped into the
/// limits, `hyst_model_saturate`) since the model was loaded or reset.
///
/// Returns `HYST_OK` or `HYST_ERR_NULL_POINTER`.
///
/// # Safety
/// `m` is NULL or a model from `hyst_model_load` or `hyst_model_load_timed` not yet freed;
/// `count` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_model_saturated(m: *const hyst_model, count: *mut u64) -> i32 {
    if m.is_null() || count.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: a live model (caller's contract).
    let model = unsafe { &*m };
    // SAFETY: non-NULL and writable (caller's contract).
    unsafe { count.write(model.inverse.as_ref().map_or(0, |r| r.saturated)) };
    HYST_OK
}

/// Deprecated: renamed [`hyst_model_saturated`].
///
/// # Safety
/// As [`hyst_model_saturated`].
#[deprecated(note = "renamed hyst_model_saturated")]
#[no_mangle]
pub unsafe extern "C" fn hyst_model_clamped(m: *const hyst_model, count: *mut u64) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_model_saturated(m, count) }
}

/// Writes into `*period` the longest sample period (s) that resolves the fastest corner of the
/// loop `hyst_model_compensate` has met since the model was loaded or reset: τ/3, where τ is the
/// time the desired output takes to cross a corner 1/k2 wide (docs/fitting.md); +∞ before it has met one. A longer period than this, given to
/// `hyst_model_load_timed`, makes commands near reversals inexact (they are still written):
/// sample faster, or slow the reference.
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, or `HYST_ERR_UNSUPPORTED` for a model without
/// Lemma 5.1's compensator (no dynamics; as `hyst_model_compensate`).
///
/// # Safety
/// `m` is NULL or a model from `hyst_model_load` or `hyst_model_load_timed` not yet freed;
/// `period` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_model_corner_period(m: *const hyst_model, period: *mut f64) -> i32 {
    if m.is_null() || period.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: a live model (caller's contract).
    let model = unsafe { &*m };
    let Some(smooth) = model.timed_model() else {
        return HYST_ERR_UNSUPPORTED;
    };
    if TimedCompensator::check(smooth).is_err() {
        return HYST_ERR_UNSUPPORTED;
    }
    let needed = model
        .compensator
        .as_ref()
        .and_then(TimedCompensator::fastest_corner)
        .map_or(f64::INFINITY, |c| c.needed_period());
    // SAFETY: non-NULL and writable (caller's contract).
    unsafe { period.write(needed) };
    HYST_OK
}

/// Forgets every run: the next `hyst_model_process` of each kind (and the next
/// `hyst_model_compensate`) starts a new record.
///
/// # Safety
/// `m` is NULL or a model from `hyst_model_load` or `hyst_model_load_timed` not yet freed.
#[no_mangle]
pub unsafe extern "C" fn hyst_model_reset(m: *mut hyst_model) -> i32 {
    if m.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: a live model (caller's contract).
    let model = unsafe { &mut *m };
    model.direct = None;
    model.inverse = None;
    model.timed = None;
    model.compensator = None;
    HYST_OK
}

/// Releases a model from `hyst_model_load` or `hyst_model_load_timed` (NULL is ignored).
///
/// # Safety
/// `m` is NULL or a model from `hyst_model_load` or `hyst_model_load_timed` not yet freed; it
/// must not be used afterwards.
#[no_mangle]
pub unsafe extern "C" fn hyst_model_free(m: *mut hyst_model) {
    if !m.is_null() {
        // SAFETY: from `Box::into_raw` in `hyst_model_load`, freed once (caller's contract).
        drop(unsafe { Box::from_raw(m) });
    }
}
