//! hyst as an FMI 2.0 Co-Simulation FMU (linux64): the binary `binaries/linux64/hyst.so` of an
//! FMU packaged by `hyst fmu` (the shared library of this crate, `libhyst_fmu.so`, renamed).
//!
//! The FMU runs the parametric operator H(k1, k2) or H⁻¹ (kind = "operator"), or a fitted model
//! file or its exact inverse (kind = "model"), as `hyst run` runs them, configured by
//! `resources/fmu.toml` ([`config`]). Its variables are all Real ([`layout`]): x (value
//! reference 0, input), y (1, output), and for the operator k1 (2) and k2 (3), fixed parameters.
//! The FMU's `modelDescription.xml`, `fmu.toml` and documentation are written here too
//! ([`description`]: the rlib's part that `hyst fmu` calls before it zips them with this binary),
//! so the variables an FMU declares and the ones its binary serves have one home.
//!
//! Semantics (FMI 2.0 Co-Simulation, direct feedthrough, rate independent):
//! - each communication point is one sample, its inputs the values set there: after
//!   fmi2SetReal(x), fmi2GetReal(y) is the operator applied to the committed input history
//!   followed by x (a copy steps; nothing is committed); fmi2DoStep commits x once, and y keeps
//!   that sample's output until an input is set again. So y read before and after fmi2DoStep is
//!   the same number, and y at the communication points equals `hyst run` on the inputs set at
//!   those points, bit for bit, whatever the times and step sizes (≥ 0);
//! - k1, k2 may be set in Instantiated and InitializationMode; the operator is built at
//!   fmi2ExitInitializationMode (invalid values: fmi2Error naming the parameter and value);
//! - a model's evaluator is created at the first fmi2DoStep from the x current then, exactly as
//!   `hyst run --model` starts a record (before that, y comes from an evaluator started at x);
//! - a refused sample (non-finite x, a desired output beyond a saturating shaping function)
//!   makes fmi2GetReal(y) / fmi2DoStep return fmi2Error with a logged message, and changes
//!   nothing;
//! - a model with dynamics or a rate term ([`timed`]) runs as `hyst run` runs a timed record:
//!   each communication step is the direct model's time step to the next sample (steps may
//!   vary), the inverse is Lemma 5.1's compensator with the inputs x_d1 … x_dn (the
//!   desired output's derivatives); its states are kept in memory, not serialised;
//! - FMU states copy the whole instance state; their serialised form is versioned and checked
//!   completely when read ([`state`]);
//! - instances are independent (no global state); every function checks its pointers and
//!   nothing panics across the boundary ([`api`]).
//!
//! Everything steps through `hyst_core::Operator` or hyst-model's timed runs ([`engine`]); no
//! formula is written here.
#![allow(non_camel_case_types, non_snake_case, non_upper_case_globals)]
#![deny(unsafe_op_in_unsafe_fn)]
#![cfg_attr(not(test), deny(clippy::indexing_slicing))]

// The FMI functions read and write through the master's raw pointers and are exported
// `#[no_mangle]`: the module allows unsafe code (denied in the workspace), each block with its
// SAFETY argument. The logger's call of the master's callback allows it on that function.
#[allow(unsafe_code)]
pub mod api;
pub mod config;
pub mod description;
pub mod engine;
pub mod fmi2;
pub mod instance;
pub mod layout;
pub mod logger;
pub mod state;
pub mod timed;

pub use api::*;
