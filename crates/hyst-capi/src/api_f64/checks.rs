//! What the C functions share to check their arguments and report: an array read from a
//! caller's pointer (its NULL and length checked), a core error as a status, and the status of
//! a call.
//!
//! Its `float` twin is generated from this file by `scripts/gen-capi-f32`: edit this one.

use crate::engine;
use crate::status::{self, HYST_ERR_LENGTH, HYST_ERR_NULL_POINTER};

/// A core error as its status.
pub(crate) fn status_of<T>(result: Result<T, hyst_core::Error>) -> Result<T, i32> {
    result.map_err(|e| status::of(&e))
}

/// Reads `n` values from `p` (NULL only when n = 0) into a fixed array.
///
/// # Safety
/// `p` is NULL or valid for `n` reads.
pub(crate) unsafe fn read_array(
    p: *const f64,
    n: usize,
) -> Result<[f64; engine::HYST_MAX_ORDER + 1], i32> {
    let mut out = [0.0; engine::HYST_MAX_ORDER + 1];
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

/// The status of a call: `HYST_OK` or what it returned, or the status of a failed check.
pub(crate) fn done(result: Result<i32, i32>) -> i32 {
    result.unwrap_or_else(|status| status)
}

/// As [`done`], with the pointer `out` the call writes to checked first:
/// `HYST_ERR_NULL_POINTER` when it is NULL, before `call` looks the state up.
pub(crate) fn done_into<T>(out: *mut T, call: impl FnOnce() -> Result<i32, i32>) -> i32 {
    if out.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    done(call())
}
