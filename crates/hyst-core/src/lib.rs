#![doc = include_str!("../README.md")]
#![no_std]
#![forbid(unsafe_code)]
#![deny(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
#![warn(missing_docs)]

#[cfg(feature = "std")]
extern crate std;

pub mod compensator;
pub mod error;
pub mod family;
pub mod jet;
pub mod k2law;
pub mod lambert;
pub mod memory;
pub mod model;
pub mod operator;
pub mod prandtl_ishlinskii;
pub mod real;
pub mod scalar;
pub mod shaping;

pub use compensator::Compensator;
pub use error::Error;
pub use family::{Bound, Family, Reproducibility, ShiftedK2};
pub use jet::Jet;
pub use k2law::{AffineK2, ConstantK2, K2Law};
pub use memory::{Direction, Memory};
pub use model::{InverseModel, Model};
pub use operator::{Branch, Direct, Hysteresis, Inverse, InverseHysteresis, Operator};
pub use prandtl_ishlinskii::{
    InverseShapedPrandtlIshlinskii, PrandtlIshlinskii, ShapedPrandtlIshlinskii,
};
pub use real::Real;
pub use scalar::Scalar;
pub use shaping::{Affine, Identity, Langevin, Polynomial, QuadraticExp, Shape, Shaping, Tanh};

/// The Rust examples of the project's README and guide, compiled and run as doctests so the
/// documentation cannot drift from the code.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
#[doc = include_str!("../../../docs/guide.md")]
pub struct ProjectDocsDoctests;
