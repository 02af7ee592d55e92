//! The firmware API in `double`, one module per concept: the memory of Definition 2.1, the
//! operator H / H⁻¹, the shaped model and its inverse, the Lemma 5.1 compensators, the adaptive
//! compensator (online adaptation), and the argument checks they share. No allocation, no
//! standard library; every state lives in caller memory.
//!
//! Its `float` twin is generated from this file by `scripts/gen-capi-f32`: edit this one.

// In the order of include/hyst.h (cbindgen reads the modules in this order): the memory, the
// operator, the shaped model, the compensators, the shaped model with affine shapings, the
// adaptive compensator.
pub mod memory;

pub mod operator;

pub mod shaped_model;

pub mod compensator;

pub mod affine_model;
pub mod deprecated;

pub mod adaptive;

pub mod affine_adaptive;

pub(crate) mod checks;

pub use adaptive::*;
pub use affine_adaptive::*;
pub use affine_model::*;
pub use compensator::*;
pub use memory::hyst_memory;
pub use operator::*;
pub use shaped_model::*;
