//! Banks of operators in `double` (host part: the bank allocates its channels).
//! Its `float` twin is generated from this file by `scripts/gen-capi-f32`: edit this one.
//!
//! A bank is N operators H(k1[c], k2[c]) (or H⁻¹), each with its own memory, stepped together
//! in SIMD lanes (`hyst_bank::BankVec`): the actuators of a deformable mirror, the axes of a
//! stage. Its outputs agree with `hyst_operator_step` on each channel to a few ulp, not bit for
//! bit (the bank has its own `exp`, `ln` and ω). A call that fails names the channel in
//! `*channel` (when `channel` is not NULL) and leaves every channel's memory as it was.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr;

use ::hyst_bank::{BankError, BankFormula, BankVec};
use hyst_core::{Direct, Error, Inverse, Real as _};

use crate::api_f64::memory::hyst_memory;
use crate::engine::MemoryFields;
use crate::status::{self, HYST_ERR_INTERNAL, HYST_ERR_LENGTH, HYST_ERR_NULL_POINTER, HYST_OK};

/// A bank of operators (opaque; create with `hyst_bank_create`, release with `hyst_bank_free`).
pub struct hyst_bank {
    inner: Channels,
}

/// The bank of either formula.
enum Channels {
    Direct(BankVec<f64, Direct>),
    Inverse(BankVec<f64, Inverse>),
}

/// Runs `$e` with `$b` bound to the bank, whichever formula it has.
macro_rules! each {
    ($channels:expr, $b:ident => $e:expr) => {
        match $channels {
            Channels::Direct($b) => $e,
            Channels::Inverse($b) => $e,
        }
    };
}

/// Writes `value` to `channel` when it is not NULL.
///
/// # Safety
/// `channel` is NULL or writable.
unsafe fn tell(channel: *mut usize, value: usize) {
    if !channel.is_null() {
        // SAFETY: non-NULL and writable (caller's contract).
        unsafe { channel.write(value) };
    }
}

/// The status of a bank error, its channel told through `channel`.
///
/// # Safety
/// `channel` is NULL or writable.
unsafe fn failed(e: &BankError, channel: *mut usize) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { tell(channel, e.channel) };
    status::of(&e.error)
}

/// Runs `f` on the live bank `b`, catching a panic (`HYST_ERR_INTERNAL`).
///
/// # Safety
/// `b` is NULL or a bank from `hyst_bank_create` not yet freed, not aliased during the call.
unsafe fn with_bank(b: *mut hyst_bank, f: impl FnOnce(&mut Channels) -> i32) -> i32 {
    if b.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: a live bank (caller's contract).
    let bank = unsafe { &mut *b };
    catch_unwind(AssertUnwindSafe(|| f(&mut bank.inner))).unwrap_or(HYST_ERR_INTERNAL)
}

/// The most values an array can hold: no array holds more than isize::MAX bytes, so a count
/// beyond this is a wrong length (checked before any slice is made of it).
const MAX_VALUES: usize = isize::MAX.unsigned_abs() / std::mem::size_of::<f64>();

/// `n` values at `p` as a slice (NULL only when n = 0).
///
/// # Safety
/// `p` is NULL or valid for `n` reads, and the values are not written during the slice's life.
unsafe fn slice<'a>(p: *const f64, n: usize) -> Result<&'a [f64], i32> {
    if n == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(HYST_ERR_NULL_POINTER);
    }
    if n > MAX_VALUES {
        return Err(HYST_ERR_LENGTH);
    }
    // SAFETY: non-NULL, valid for n reads (caller's contract), n values within isize::MAX bytes.
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

/// Creates a bank of `channels` operators: channel c is H(`k1[c]`, `k2[c]`) (eq. 2), or
/// H⁻¹(`k1[c]`, `k2[c]`) (eq. 4: the inverses) when `inverse` ≠ 0, each with no history.
/// On success `*bank` receives it (release it with `hyst_bank_free`).
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER` (`bank`, `k1` or `k2` NULL), `HYST_ERR_LENGTH`
/// (`channels` = 0), or `HYST_ERR_INVALID_PARAMETER` unless every k1 and k2 is finite and > 0:
/// `*channel` (when `channel` is not NULL) then receives the first invalid channel. On failure
/// `*bank` is set to NULL.
///
/// # Safety
/// `k1` and `k2` are NULL or hold `channels` values; `bank` is NULL or writable; `channel` is
/// NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_bank_create(
    k1: *const f64,
    k2: *const f64,
    channels: usize,
    inverse: i32,
    bank: *mut *mut hyst_bank,
    channel: *mut usize,
) -> i32 {
    if bank.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: non-NULL and writable (caller's contract).
    unsafe { bank.write(ptr::null_mut()) };
    if channels == 0 {
        return HYST_ERR_LENGTH;
    }
    let made = catch_unwind(|| {
        // SAFETY: NULL or `channels` values (caller's contract).
        let (k1, k2) = match unsafe { (slice(k1, channels), slice(k2, channels)) } {
            (Ok(a), Ok(b)) => (a.to_vec(), b.to_vec()),
            _ => return Err(Err(HYST_ERR_NULL_POINTER)),
        };
        if inverse != 0 {
            BankVec::from_vecs(k1, k2).map(Channels::Inverse)
        } else {
            BankVec::from_vecs(k1, k2).map(Channels::Direct)
        }
        .map_err(Ok)
    });
    match made {
        Ok(Ok(inner)) => {
            // SAFETY: as above.
            unsafe { bank.write(Box::into_raw(Box::new(hyst_bank { inner }))) };
            HYST_OK
        }
        // SAFETY: `channel` is NULL or writable (caller's contract).
        Ok(Err(Ok(e))) => unsafe { failed(&e, channel) },
        Ok(Err(Err(status))) => status,
        Err(_) => HYST_ERR_INTERNAL,
    }
}

/// The number of channels of `bank` (0 for NULL).
///
/// # Safety
/// `bank` is NULL or a bank from `hyst_bank_create` not yet freed.
#[no_mangle]
pub unsafe extern "C" fn hyst_bank_channels(bank: *const hyst_bank) -> usize {
    if bank.is_null() {
        return 0;
    }
    // SAFETY: a live bank (caller's contract).
    each!(unsafe { &(*bank).inner }, b => b.channels())
}

/// `process`, and an output beyond the float range refused as `hyst_operator_step`
/// refuses it (`HYST_ERR_OVERFLOW`), with every memory as before the call on any error. The
/// core stops a block at its first failing tick with the ticks before it processed, and only a
/// non-finite sample, or an input or k1 near the float range (outputs lie within k1 of a line
/// through earlier samples), can fail: only then are the memories saved first.
fn process<F: BankFormula>(
    b: &mut BankVec<f64, F>,
    x: &[f64],
    y: &mut [f64],
) -> Result<(), BankError> {
    // NaN, infinite, or near the float range.
    let risky = |v: &f64| !v.is_finite() || v.abs() > f64::MAX / 8.0;
    let saved: Option<Vec<_>> = (x.iter().any(risky) || b.k1().iter().any(risky))
        .then(|| (0..b.channels()).map(|c| b.memory(c)).collect());
    let restore = |b: &mut BankVec<f64, F>, saved: Option<Vec<_>>| {
        for (c, m) in saved.into_iter().flatten().enumerate() {
            // Memories the channels were in: valid.
            let _ = b.set_memory(c, m);
        }
    };
    if let Err(e) = b.process(x, y) {
        restore(b, saved);
        return Err(e);
    }
    let Some(i) = y.iter().position(|v| !v.is_finite()) else {
        return Ok(());
    };
    restore(b, saved);
    Err(BankError {
        channel: i % b.channels().max(1),
        error: Error::NonFiniteOutput {
            input: x.get(i).map_or(0.0, |v| v.as_f64()),
            output: y.get(i).map_or(0.0, |v| v.as_f64()),
        },
    })
}

/// Runs `ticks` ticks through the bank: `x` holds them time-major (`x[t * channels + c]` is
/// channel c's sample at tick t, each tick's samples contiguous, as a controller produces
/// them) and `y` receives the outputs in the same layout (`y` may be `x`). `ticks` = 1 is one
/// control period: see `hyst_bank_step`.
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, `HYST_ERR_LENGTH` (channels × ticks values would
/// take more bytes than an array can hold),
/// `HYST_ERR_NON_FINITE` for a NaN or infinite sample (nothing is processed), or
/// `HYST_ERR_OVERFLOW` for a finite sample whose output is beyond the float range: `*channel`
/// (when `channel` is not NULL) receives its channel, and every memory is as before the call.
///
/// # Safety
/// `bank` is NULL or a bank from `hyst_bank_create` not yet freed; `x` and `y` are NULL or hold
/// channels × `ticks` values; `channel` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_bank_process(
    bank: *mut hyst_bank,
    x: *const f64,
    y: *mut f64,
    ticks: usize,
    channel: *mut usize,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe {
        with_bank(bank, |c| {
            let channels = each!(&*c, b => b.channels());
            let Some(n) = channels.checked_mul(ticks).filter(|&n| n <= MAX_VALUES) else {
                return HYST_ERR_LENGTH;
            };
            if n == 0 {
                return HYST_OK;
            }
            if x.is_null() || y.is_null() {
                return HYST_ERR_NULL_POINTER;
            }
            // `y` may be `x` (or overlap it): then the inputs are copied first. Otherwise they
            // are read in place, so a control loop's tick allocates nothing.
            let bytes = n * std::mem::size_of::<f64>();
            let (xs, ys) = (x as usize, y as usize);
            let overlap = xs < ys.saturating_add(bytes) && ys < xs.saturating_add(bytes);
            let copy;
            let input = if overlap {
                copy = std::slice::from_raw_parts(x, n).to_vec();
                &copy[..]
            } else {
                std::slice::from_raw_parts(x, n)
            };
            let output = std::slice::from_raw_parts_mut(y, n);
            match each!(c, b => process(b, input, output)) {
                Ok(()) => HYST_OK,
                Err(e) => failed(&e, channel),
            }
        })
    }
}

/// One tick: `x[c]` is channel c's new sample and `y[c]` receives its output (`channels`
/// values each; `y` may be `x`). As `hyst_bank_process` with `ticks` = 1.
///
/// # Safety
/// As `hyst_bank_process` with `ticks` = 1.
#[no_mangle]
pub unsafe extern "C" fn hyst_bank_step(
    bank: *mut hyst_bank,
    x: *const f64,
    y: *mut f64,
    channel: *mut usize,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { hyst_bank_process(bank, x, y, 1, channel) }
}

/// Forgets every channel's history (the next sample of each lies on the line output = input).
///
/// # Safety
/// `bank` is NULL or a bank from `hyst_bank_create` not yet freed.
#[no_mangle]
pub unsafe extern "C" fn hyst_bank_reset(bank: *mut hyst_bank) -> i32 {
    // SAFETY: forwarded contract.
    unsafe {
        with_bank(bank, |c| {
            each!(c, b => b.reset());
            HYST_OK
        })
    }
}

/// Writes the memory of Definition 2.1 of channel `channel` into `*memory` (`has_history` = 0
/// before its first sample).
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, or `HYST_ERR_LENGTH` for a channel beyond the bank.
///
/// # Safety
/// `bank` is NULL or a bank from `hyst_bank_create` not yet freed; `memory` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_bank_get_memory(
    bank: *mut hyst_bank,
    channel: usize,
    memory: *mut hyst_memory,
) -> i32 {
    if memory.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: forwarded contract.
    unsafe {
        with_bank(bank, |c| {
            if channel >= each!(&*c, b => b.channels()) {
                return HYST_ERR_LENGTH;
            }
            let m = each!(&*c, b => b.memory(channel));
            memory.write(hyst_memory::of(MemoryFields::of(m)));
            HYST_OK
        })
    }
}

/// Restores the memory of channel `channel` from `*memory` (`has_history` = 0: no history), as
/// saved by `hyst_bank_get_memory` (or `hyst_operator_get_memory`: the same memory).
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, `HYST_ERR_LENGTH` for a channel beyond the bank,
/// `HYST_ERR_INVALID_PARAMETER` (non-finite values, a direction other than ±1) or
/// `HYST_ERR_STATE_OUTSIDE_BAND` (a point outside the band |output − input| ≤ k1) for a memory
/// the channel cannot be in, as `hyst_operator_set_memory` (nothing changes then).
///
/// # Safety
/// `bank` is NULL or a bank from `hyst_bank_create` not yet freed; `memory` is NULL or readable.
#[no_mangle]
pub unsafe extern "C" fn hyst_bank_set_memory(
    bank: *mut hyst_bank,
    channel: usize,
    memory: *const hyst_memory,
) -> i32 {
    if memory.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    // SAFETY: non-NULL, readable (caller's contract).
    let fields = unsafe { memory.read() }.fields();
    // SAFETY: forwarded contract.
    unsafe {
        with_bank(bank, |c| {
            let m = match fields.to_core() {
                Ok(m) => m,
                Err(e) => return status::of(&e),
            };
            match each!(c, b => b.set_memory(channel, m)) {
                Ok(()) => HYST_OK,
                Err(BankError {
                    error: Error::LengthMismatch { .. },
                    ..
                }) => HYST_ERR_LENGTH,
                Err(e) => status::of(&e.error),
            }
        })
    }
}

/// Releases a bank from `hyst_bank_create` (NULL is ignored).
///
/// # Safety
/// `bank` is NULL or a bank from `hyst_bank_create` not yet freed; it must not be used afterwards.
#[no_mangle]
pub unsafe extern "C" fn hyst_bank_free(bank: *mut hyst_bank) {
    if !bank.is_null() {
        // SAFETY: from `Box::into_raw` in `hyst_bank_create`, freed once (caller's contract).
        drop(unsafe { Box::from_raw(bank) });
    }
}
