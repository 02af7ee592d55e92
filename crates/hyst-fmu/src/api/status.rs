//! The status functions (fmi2GetStatus and its typed twins): this FMU's steps are synchronous,
//! so only fmi2LastSuccessfulTime and fmi2Terminated have an answer.

use crate::api::boundary::{put, with_instance, STATUS};
#[cfg(doc)]
use crate::api::lifecycle::fmi2FreeInstance;
use crate::fmi2::*;
use crate::instance::Instance;

/// The status functions: `answer` gives the value for a status kind this FMU has, `None` for a
/// defined kind it cannot answer (fmi2Discard, as FMI 2.0 prescribes); undefined kinds are
/// fmi2Error.
///
/// # Safety
/// As [`fmi2GetStatus`], for `T`.
unsafe fn status<T>(
    c: fmi2Component,
    function: &str,
    kind: fmi2StatusKind,
    value: *mut T,
    answer: impl FnOnce(&Instance) -> Option<T>,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, function, STATUS, |inst| {
            if !(fmi2DoStepStatus..=fmi2Terminated).contains(&kind) {
                return Err(format!("status kind {kind} is not an fmi2StatusKind"));
            }
            if value.is_null() {
                return Err("value is NULL".into());
            }
            match answer(inst) {
                Some(v) => {
                    put(value, v, "value")?;
                    Ok(fmi2Status::fmi2OK)
                }
                None => {
                    inst.log.send(
                        fmi2Status::fmi2Discard,
                        c"logStatusDiscard",
                        &format!(
                            "{function}: status kind {kind} is not available (fmi2DoStep is \
                             synchronous: there is never a pending step)"
                        ),
                    );
                    Ok(fmi2Status::fmi2Discard)
                }
            }
        })
    }
}

/// `fmi2GetStatus`: fmi2Discard (no asynchronous step, so no fmi2DoStepStatus).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `value` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Status,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe { status(c, "fmi2GetStatus", s, value, |_| None) }
}

/// `fmi2GetRealStatus`: fmi2LastSuccessfulTime is the end of the last successful fmi2DoStep
/// (the start time before the first); other kinds give fmi2Discard.
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `value` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Real,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        status(c, "fmi2GetRealStatus", s, value, |inst| {
            (s == fmi2LastSuccessfulTime).then(|| inst.time())
        })
    }
}

/// `fmi2GetIntegerStatus`: fmi2Discard (FMI 2.0 defines no Integer status).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `value` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Integer,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe { status(c, "fmi2GetIntegerStatus", s, value, |_| None) }
}

/// `fmi2GetBooleanStatus`: fmi2Terminated is fmi2False (the FMU never asks to stop); other
/// kinds give fmi2Discard.
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `value` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        status(c, "fmi2GetBooleanStatus", s, value, |_| {
            (s == fmi2Terminated).then_some(fmi2False)
        })
    }
}

/// `fmi2GetStringStatus`: fmi2Discard (fmi2PendingStatus needs a pending step).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `value` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2String,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe { status(c, "fmi2GetStringStatus", s, value, |_| None) }
}
