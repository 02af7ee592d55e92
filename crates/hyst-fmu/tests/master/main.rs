//! The FMU driven as a master drives it: resources written to a temporary folder, every exported
//! function called through its C signature, and the results compared bit for bit with the core
//! (`Hysteresis`, `InverseHysteresis`) and the model file's `Evaluator` run over the same inputs.
//!
//! The test logger is a non-variadic Rust function called through the variadic
//! `fmi2CallbackLogger` type; that is sound on the platforms this test runs on (see `logger`),
//! which are the FMU's platform (linux64).
#![cfg(all(
    target_os = "linux",
    any(target_arch = "x86_64", target_arch = "aarch64")
))]
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]
// The tests call the FMI functions through raw pointers, as a C program does.
#![allow(unsafe_code)]

use std::cell::{Cell, RefCell};
use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::path::Path;
use std::ptr;

use hyst_core::{
    AnyK2Law, AnyShaping, Hysteresis, InverseHysteresis, Operator, ScaledShaping, Tanh,
};
use hyst_fmu::fmi2::*;
use hyst_fmu::layout::{VR_K1, VR_K2, VR_X, VR_Y};
use hyst_fmu::*;
use hyst_model::PiModel;
use hyst_model::{file::fnv1a64, file::FORMAT, ModelKind};
use hyst_model::{InitialState, ModelFile, SmoothModel};

use fmi2Status::{
    fmi2Discard as DISCARD, fmi2Error as ERROR, fmi2OK as OK, fmi2Warning as WARNING,
};

const GUID: &str = "{6f1c2a3e-hyst-test}";

mod harness;
mod interface;
mod outputs;
mod states;
mod timed;
