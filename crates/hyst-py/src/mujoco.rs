//! MuJoCo's actuator plugins `hyst.backlash` and `hyst.compensator` (docs/mujoco.md): the C
//! plugins of crates/hyst-capi/mujoco, compiled into this extension by build.rs when MuJoCo's
//! headers were there, registered with the libmujoco whose functions `hyst.mujoco.load()`
//! passes (the one the `mujoco` package loaded).

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

/// The MuJoCo version the plugins were compiled for, as `mj_version()` gives it (4000001 for
/// 4.0.1; build.rs reads mujoco.h's `mjVERSION_HEADER`); 0 when the extension was built without
/// them.
pub fn version() -> i32 {
    option_env!("HYST_MUJOCO_VERSION")
        .and_then(|v| v.parse().ok())
        .unwrap_or(0)
}

#[allow(unsafe_code)]
mod ffi {
    use std::ffi::{c_char, c_int};

    // The C API the plugins call, linked into the extension. Without MuJoCo's headers,
    // build.rs compiles hyst_mujoco_absent.c: its `hyst_mujoco_register` refuses, saying why.
    extern crate hyst as _;

    /// `hyst_mujoco_api` (hyst_mujoco.h): the addresses of mj_getPluginConfig, mju_warning,
    /// mjp_defaultPlugin, mjp_registerPlugin and mj_version, in this order.
    #[repr(C)]
    pub struct Api {
        pub functions: [usize; 5],
    }

    extern "C" {
        pub fn hyst_mujoco_register(api: *const Api, error: *mut c_char, error_len: usize)
            -> c_int;
    }

    /// Registers the plugins; the reason on failure.
    pub fn register(functions: [usize; 5]) -> Result<(), String> {
        let api = Api { functions };
        let mut error = [0 as c_char; 512];
        // SAFETY: `api` holds the addresses of those five functions of one loaded libmujoco
        // (the caller, `hyst.mujoco.load()`, takes them from it by name; a zero address is
        // refused by the C side), and `error` is writable for its length.
        let status = unsafe { hyst_mujoco_register(&api, error.as_mut_ptr(), error.len()) };
        if status == 0 {
            return Ok(());
        }
        // SAFETY: the C side wrote a NUL-terminated message within the buffer.
        let message = unsafe { std::ffi::CStr::from_ptr(error.as_ptr()) };
        Err(message.to_string_lossy().into_owned())
    }
}

/// `_mujoco_register(functions)`: registers `hyst.backlash` and `hyst.compensator` with the
/// libmujoco whose `mj_getPluginConfig`, `mju_warning`, `mjp_defaultPlugin`,
/// `mjp_registerPlugin` and `mj_version` are at these addresses (`hyst.mujoco.load()` takes
/// them with ctypes). Raises `RuntimeError` when that MuJoCo's version is not the one the
/// plugins were built for, or the extension was built without them.
#[pyfunction]
#[pyo3(name = "_mujoco_register")]
pub fn register(functions: [usize; 5]) -> PyResult<()> {
    ffi::register(functions).map_err(PyRuntimeError::new_err)
}
