//! FMU states: fmi2GetFMUstate, fmi2SetFMUstate and fmi2FreeFMUstate (copies of the whole
//! instance state), and their serialised form (fmi2SerializedFMUstateSize,
//! fmi2SerializeFMUstate, fmi2DeSerializeFMUstate).

use std::ptr;

use crate::api::boundary::{get, input, output, put, with_instance, LIVE};
#[cfg(doc)]
use crate::api::lifecycle::fmi2FreeInstance;
use crate::fmi2::*;

/// `fmi2GetFMUstate`: a copy of the instance state (x, k1, k2, time, history) in a new FMU state
/// (`*FMUstate` NULL) or in one of this instance's (`*FMUstate` from an earlier call).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `FMUstate` is NULL or points to an `fmi2FMUstate`.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2GetFMUstate", LIVE, |inst| {
            let existing = get(FMUstate.cast_const(), "FMUstate")?;
            let handle = inst.store_state(existing, inst.snapshot())?;
            put(FMUstate, handle, "FMUstate")?;
            Ok(fmi2Status::fmi2OK)
        })
    }
}

/// `fmi2SetFMUstate`: restores a state of this instance (checked again by the core; the mode
/// is kept; a state with a history needs step mode or Terminated).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `FMUstate` is any value (only this instance's states are
/// accepted; it is never dereferenced).
#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, FMUstate: fmi2FMUstate) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2SetFMUstate", LIVE, |inst| {
            let state = inst.state(FMUstate)?.clone();
            inst.apply(&state)?;
            Ok(fmi2Status::fmi2OK)
        })
    }
}

/// `fmi2FreeFMUstate`: frees a state of this instance and sets `*FMUstate` to NULL (a NULL
/// `FMUstate` or `*FMUstate` is ignored).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `FMUstate` is NULL or points to an `fmi2FMUstate`.
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2FreeFMUstate", LIVE, |inst| {
            if FMUstate.is_null() {
                return Ok(fmi2Status::fmi2OK);
            }
            let handle = get(FMUstate.cast_const(), "FMUstate")?;
            if handle.is_null() {
                return Ok(fmi2Status::fmi2OK);
            }
            inst.free_state(handle)?;
            put(FMUstate, ptr::null_mut(), "FMUstate")?;
            Ok(fmi2Status::fmi2OK)
        })
    }
}

/// `fmi2SerializedFMUstateSize`: the byte length of the state's serialised form.
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `size` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2SerializedFMUstateSize", LIVE, |inst| {
            let bytes = inst.serialize(inst.state(FMUstate)?)?;
            put(size, bytes.len(), "size")?;
            Ok(fmi2Status::fmi2OK)
        })
    }
}

/// `fmi2SerializeFMUstate`: writes the serialised form (version 1, see `state`) into
/// `serializedState`, which must hold at least fmi2SerializedFMUstateSize bytes.
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `serializedState` is NULL or writable for `size` bytes.
#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    serializedState: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2SerializeFMUstate", LIVE, |inst| {
            let bytes = inst.serialize(inst.state(FMUstate)?)?;
            if size < bytes.len() {
                return Err(format!(
                    "size = {size}: the serialised state needs {} bytes \
                     (fmi2SerializedFMUstateSize)",
                    bytes.len()
                ));
            }
            let out = output(serializedState.cast::<u8>(), bytes.len(), "serializedState")?;
            out.copy_from_slice(&bytes);
            Ok(fmi2Status::fmi2OK)
        })
    }
}

/// `fmi2DeSerializeFMUstate`: reads a serialised state, checking everything (length, version,
/// checksum, GUID, kind, finite values, the memory through the core), into a new FMU state (or
/// into `*FMUstate` when it is one of this instance's).
///
/// # Safety
/// `c` as in [`fmi2FreeInstance`]; `serializedState` is NULL or readable for `size` bytes;
/// `FMUstate` is NULL or points to an `fmi2FMUstate`.
#[no_mangle]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: fmi2Component,
    serializedState: *const fmi2Byte,
    size: usize,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    // SAFETY: the caller's contract.
    unsafe {
        with_instance(c, "fmi2DeSerializeFMUstate", LIVE, |inst| {
            let existing = get(FMUstate.cast_const(), "FMUstate")?;
            let bytes = input(serializedState.cast::<u8>(), size, "serializedState")?;
            let state = inst
                .deserialize(bytes)
                .map_err(|e| format!("the serialised state is refused: {e}"))?;
            let existing = if inst.state(existing).is_ok() {
                existing
            } else {
                ptr::null_mut()
            };
            let handle = inst.store_state(existing, state)?;
            put(FMUstate, handle, "FMUstate")?;
            Ok(fmi2Status::fmi2OK)
        })
    }
}
