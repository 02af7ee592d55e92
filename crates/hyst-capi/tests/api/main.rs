//! The C API called as C would call it: results equal the core's bit for bit, states resume
//! from a saved memory, and every bad argument (NULL, misaligned, uninitialised, non-finite, out
//! of range) returns its status without touching anything.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]
// The tests call the C API through raw pointers, as a C program does.
#![allow(unsafe_code)]

use std::ffi::{CStr, CString};
use std::ptr;

use hyst::api_f32::*;
use hyst::api_f64::*;
use hyst::host::*;
use hyst::model_memory::*;
use hyst::status::*;
use hyst::{HYST_K2_CONSTANT, HYST_SHAPING_AFFINE, HYST_SHAPING_IDENTITY, HYST_SHAPING_POLYNOMIAL};
use hyst_core::{
    Affine, AnyShaping, Compensator, Hysteresis, InverseHysteresis, Jet, Operator, Polynomial,
    ScaledShaping, ShapedModel,
};

mod host;
mod model_memory;
mod operator;
mod shaped;
