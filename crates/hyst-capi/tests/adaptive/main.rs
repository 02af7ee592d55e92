//! The adaptive compensator of the C API (`hyst_adaptive_*`) called as C would call it: the
//! `double` one equals `hyst_core::adaptive::AdaptiveInverse` bit for bit, the `float` twin
//! follows a truth whose output gain is 20 % above the fitted model's, and every bad argument
//! returns its status without touching anything.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]
// The tests call the C API through raw pointers, as a C program does.
#![allow(unsafe_code)]

use std::ffi::CStr;
use std::ptr;

use hyst_test_support::rng::{Lcg64, Random};

use hyst::api_f32::*;
use hyst::api_f64::*;
use hyst::status::*;
use hyst::*;
use hyst_core::adaptive::{
    Adaptive, AdaptiveConfig, AdaptiveInverse, AdaptiveModel, Parameter, Status,
};
use hyst_core::{
    Affine, AffineK2, AnyK2Law, AnyShaping, Hysteresis, InitialState, Operator, Polynomial,
    ScaledShaping, ShapedModel,
};

mod agreement;
mod arguments;
mod common;
