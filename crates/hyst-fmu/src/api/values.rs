//! The variables' values: fmi2GetReal and fmi2SetReal (x, y, k1, k2), the Integer, Boolean and
//! String functions (this FMU has no such variables), and the derivative functions it does not
//! support.

use crate::api::boundary::{input, output, with_instance, GET, LIVE, SET};
#[cfg(doc)]
use crate::api::lifecycle::fmi2FreeInstance;
use crate::fmi2::*;
use crate::instance::Phase;

/// `fmi2GetReal`: x (0), y (1), k1 (2), k2 (3). y is the output for the committed history
/// followed by the current x.
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `vr` and `value` are NULL or hold `nvr` values.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Real,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2GetReal", GET, |inst| {
            let vrs = input(vr, nvr, "vr")?;
            let values = output(value, nvr, "value")?;
            inst.get_real(vrs, values)?;
            Ok(fmi2Status::fmi2OK)
        })
    }
}

/// The common part of the Get/Set functions of types this FMU has no variables of.
///
/// # Safety
/// As [`fmi2GetReal`], for `T`.
unsafe fn no_variables<T>(
    c: fmi2Component,
    function: &str,
    allowed: &[Phase],
    type_name: &str,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const T,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, function, allowed, |_| {
            let vrs = input(vr, nvr, "vr")?;
            input(value, nvr, "value")?;
            match vrs.first() {
                None => Ok(fmi2Status::fmi2OK),
                Some(v) => Err(format!(
                    "no {type_name} variable has value reference {v} (this FMU has Real variables only)"
                )),
            }
        })
    }
}

/// `fmi2GetInteger`: this FMU has no Integer variables (nvr = 0 is fine).
///
/// # Safety
/// As [`fmi2GetReal`].
#[no_mangle]
pub unsafe extern "C" fn fmi2GetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Integer,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        no_variables(
            c,
            "fmi2GetInteger",
            GET,
            "Integer",
            vr,
            nvr,
            value.cast_const(),
        )
    }
}

/// `fmi2GetBoolean`: no Boolean variables.
///
/// # Safety
/// As [`fmi2GetReal`].
#[no_mangle]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        no_variables(
            c,
            "fmi2GetBoolean",
            GET,
            "Boolean",
            vr,
            nvr,
            value.cast_const(),
        )
    }
}

/// `fmi2GetString`: no String variables.
///
/// # Safety
/// As [`fmi2GetReal`].
#[no_mangle]
pub unsafe extern "C" fn fmi2GetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2String,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        no_variables(
            c,
            "fmi2GetString",
            GET,
            "String",
            vr,
            nvr,
            value.cast_const(),
        )
    }
}

/// `fmi2SetReal`: x (any mode before Terminated), k1 and k2 (before
/// fmi2ExitInitializationMode). All values or none are set.
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `vr` and `value` are NULL or hold `nvr` values.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Real,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2SetReal", SET, |inst| {
            let vrs = input(vr, nvr, "vr")?;
            let values = input(value, nvr, "value")?;
            inst.set_real(vrs, values)?;
            Ok(fmi2Status::fmi2OK)
        })
    }
}

/// `fmi2SetInteger`: no Integer variables (nvr = 0 is fine).
///
/// # Safety
/// As [`fmi2SetReal`].
#[no_mangle]
pub unsafe extern "C" fn fmi2SetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Integer,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe { no_variables(c, "fmi2SetInteger", SET, "Integer", vr, nvr, value) }
}

/// `fmi2SetBoolean`: no Boolean variables.
///
/// # Safety
/// As [`fmi2SetReal`].
#[no_mangle]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Boolean,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe { no_variables(c, "fmi2SetBoolean", SET, "Boolean", vr, nvr, value) }
}

/// `fmi2SetString`: no String variables.
///
/// # Safety
/// As [`fmi2SetReal`].
#[no_mangle]
pub unsafe extern "C" fn fmi2SetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2String,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe { no_variables(c, "fmi2SetString", SET, "String", vr, nvr, value) }
}

/// `fmi2GetDirectionalDerivative`: not supported (providesDirectionalDerivative = false).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`] (no other argument is read).
#[no_mangle]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: fmi2Component,
    vUnknown_ref: *const fmi2ValueReference,
    nUnknown: usize,
    vKnown_ref: *const fmi2ValueReference,
    nKnown: usize,
    dvKnown: *const fmi2Real,
    dvUnknown: *mut fmi2Real,
) -> fmi2Status {
    let _ = (
        vUnknown_ref,
        nUnknown,
        vKnown_ref,
        nKnown,
        dvKnown,
        dvUnknown,
    );
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2GetDirectionalDerivative", LIVE, |_| {
            Err("not supported (providesDirectionalDerivative = false)".into())
        })
    }
}

/// `fmi2SetRealInputDerivatives`: not supported (canInterpolateInputs = false).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`] (no other argument is read).
#[no_mangle]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    order: *const fmi2Integer,
    value: *const fmi2Real,
) -> fmi2Status {
    let _ = (vr, nvr, order, value);
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2SetRealInputDerivatives", LIVE, |_| {
            Err("not supported (canInterpolateInputs = false)".into())
        })
    }
}

/// `fmi2GetRealOutputDerivatives`: not supported (maxOutputDerivativeOrder = 0).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`] (no other argument is read).
#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    order: *const fmi2Integer,
    value: *mut fmi2Real,
) -> fmi2Status {
    let _ = (vr, nvr, order, value);
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2GetRealOutputDerivatives", LIVE, |_| {
            Err("not supported (maxOutputDerivativeOrder = 0)".into())
        })
    }
}
