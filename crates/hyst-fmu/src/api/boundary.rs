//! The C boundary that every exported function passes: the instance handle (`fmi2Component`,
//! checked by its tag), the modes a function may be called in, `catch_unwind` and the logging of
//! errors, and the checked reading and writing of the caller's pointers.

use std::ffi::CStr;
use std::panic::{catch_unwind, AssertUnwindSafe};

use crate::fmi2::*;
use crate::instance::{Instance, Phase};
use crate::logger::CATEGORY_FATAL;

/// "hystFMUi": the tag at the start of a live instance (cleared when it is freed).
const INSTANCE_TAG: u64 = u64::from_le_bytes(*b"hystFMUi");

/// What an `fmi2Component` points to.
#[repr(C)]
struct Slot {
    tag: u64,
    instance: Instance,
}

use Phase::{InitializationMode, Instantiated, StepMode, Terminated};

/// Every mode but Fatal.
pub(crate) const LIVE: &[Phase] = &[Instantiated, InitializationMode, StepMode, Terminated];
/// Where values may be read (not Instantiated: y is "calculated").
pub(crate) const GET: &[Phase] = &[InitializationMode, StepMode, Terminated];
/// Where values may be set (which ones: see `Instance::set_real`).
pub(crate) const SET: &[Phase] = &[Instantiated, InitializationMode, StepMode];
/// Where the status functions answer.
pub(crate) const STATUS: &[Phase] = &[StepMode, Terminated];

/// A new instance's handle for the master (released by [`free_component`]).
pub(crate) fn new_component(instance: Instance) -> fmi2Component {
    Box::into_raw(Box::new(Slot {
        tag: INSTANCE_TAG,
        instance,
    }))
    .cast()
}

/// Releases the instance behind `c` (NULL, a misaligned pointer or a wrong tag is ignored).
///
/// # Safety
/// As [`slot`]; `c` is not used afterwards.
pub(crate) unsafe fn free_component(c: fmi2Component) {
    // SAFETY: the caller's contract.
    if let Some(slot) = unsafe { slot(c) } {
        slot.tag = 0;
        // SAFETY: from Box::into_raw in `new_component`; the tag was live, so not freed yet.
        drop(unsafe { Box::from_raw(c.cast::<Slot>()) });
    }
}

/// The live instance `c` points to, or `None` for NULL, a misaligned pointer or a wrong tag.
///
/// # Safety
/// `c` is NULL or a pointer returned by `fmi2Instantiate` (the tag check is a safety net for a
/// freed or foreign pointer, not a guarantee), not used by another thread during the call.
unsafe fn slot<'a>(c: fmi2Component) -> Option<&'a mut Slot> {
    let p = c.cast::<Slot>();
    if p.is_null() || !p.is_aligned() {
        return None;
    }
    // SAFETY: non-NULL and aligned, and by the caller's contract an instance from
    // fmi2Instantiate, whose first field (repr(C)) is the u64 tag.
    let tag = unsafe { p.cast::<u64>().read() };
    if tag != INSTANCE_TAG {
        return None;
    }
    // SAFETY: a live Slot (tag set by fmi2Instantiate, cleared by fmi2FreeInstance), used by
    // one thread at a time (FMI 2.0 forbids concurrent calls on one instance).
    Some(unsafe { &mut *p })
}

/// Runs `body` on the instance `c` if its mode is one of `allowed`: errors are logged with the
/// function's name; a panic makes the instance Fatal.
///
/// # Safety
/// As [`slot`].
pub(crate) unsafe fn with_instance(
    c: fmi2Component,
    function: &str,
    allowed: &[Phase],
    body: impl FnOnce(&mut Instance) -> Result<fmi2Status, String>,
) -> fmi2Status {
    let result = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the caller's contract.
        let Some(slot) = (unsafe { slot(c) }) else {
            return fmi2Status::fmi2Error;
        };
        let instance = &mut slot.instance;
        if !allowed.contains(&instance.phase) {
            instance.log.error(&format!(
                "{function}: illegal call sequence: not allowed in the mode {}",
                instance.phase
            ));
            return fmi2Status::fmi2Error;
        }
        match body(instance) {
            Ok(status) => status,
            Err(message) => {
                instance.log.error(&format!("{function}: {message}"));
                fmi2Status::fmi2Error
            }
        }
    }));
    result.unwrap_or_else(|_| {
        let _ = catch_unwind(AssertUnwindSafe(|| {
            // SAFETY: the caller's contract.
            if let Some(slot) = unsafe { slot(c) } {
                slot.instance.phase = Phase::Fatal;
                slot.instance.log.send(
                    fmi2Status::fmi2Fatal,
                    CATEGORY_FATAL,
                    &format!("{function}: internal error (a panic was caught); only fmi2FreeInstance may follow"),
                );
            }
        }));
        fmi2Status::fmi2Fatal
    })
}

/// `n` elements of the caller's array `ptr` (empty when `n` = 0).
///
/// # Safety
/// When `n` > 0, `ptr` is NULL or valid for reading `n` values of `T` for `'a`.
pub(crate) unsafe fn input<'a, T>(ptr: *const T, n: usize, what: &str) -> Result<&'a [T], String> {
    if n == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() {
        return Err(format!("{what} is NULL"));
    }
    if !ptr.is_aligned() || n > isize::MAX.unsigned_abs() / std::mem::size_of::<T>().max(1) {
        return Err(format!("{what} is misaligned or {n} is too long"));
    }
    // SAFETY: non-NULL, aligned, n values readable (caller's contract), size within isize.
    Ok(unsafe { std::slice::from_raw_parts(ptr, n) })
}

/// `n` elements of the caller's writable array `ptr` (empty when `n` = 0).
///
/// # Safety
/// When `n` > 0, `ptr` is NULL or valid for writing `n` values of `T` for `'a`, not aliased.
pub(crate) unsafe fn output<'a, T>(
    ptr: *mut T,
    n: usize,
    what: &str,
) -> Result<&'a mut [T], String> {
    if n == 0 {
        return Ok(&mut []);
    }
    if ptr.is_null() {
        return Err(format!("{what} is NULL"));
    }
    if !ptr.is_aligned() || n > isize::MAX.unsigned_abs() / std::mem::size_of::<T>().max(1) {
        return Err(format!("{what} is misaligned or {n} is too long"));
    }
    // SAFETY: non-NULL, aligned, n values writable and not aliased (caller's contract).
    Ok(unsafe { std::slice::from_raw_parts_mut(ptr, n) })
}

/// Writes `value` to the caller's `*ptr`.
///
/// # Safety
/// `ptr` is NULL or valid for writing one `T`.
pub(crate) unsafe fn put<T>(ptr: *mut T, value: T, what: &str) -> Result<(), String> {
    if ptr.is_null() || !ptr.is_aligned() {
        return Err(format!("{what} is NULL or misaligned"));
    }
    // SAFETY: non-NULL, aligned, writable (caller's contract).
    unsafe { ptr.write(value) };
    Ok(())
}

/// Reads the caller's `*ptr`.
///
/// # Safety
/// `ptr` is NULL or valid for reading one `T`.
pub(crate) unsafe fn get<T: Copy>(ptr: *const T, what: &str) -> Result<T, String> {
    if ptr.is_null() || !ptr.is_aligned() {
        return Err(format!("{what} is NULL or misaligned"));
    }
    // SAFETY: non-NULL, aligned, readable (caller's contract).
    Ok(unsafe { ptr.read() })
}

/// A C string argument as UTF-8.
///
/// # Safety
/// `s` is NULL or NUL-terminated.
pub(crate) unsafe fn text<'a>(s: fmi2String, what: &str) -> Result<&'a str, String> {
    if s.is_null() {
        return Err(format!("{what} is NULL"));
    }
    // SAFETY: non-NULL and NUL-terminated (caller's contract).
    unsafe { CStr::from_ptr(s) }
        .to_str()
        .map_err(|_| format!("{what} is not UTF-8"))
}
