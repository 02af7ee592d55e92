#![doc = include_str!("../README.md")]
#![no_std]
#![forbid(unsafe_code)]
#![deny(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
// No indexing that could panic in library code (unit tests may index).
#![cfg_attr(not(test), deny(clippy::indexing_slicing))]
#![warn(missing_docs)]

#[cfg(feature = "std")]
extern crate std;

/// Inside an `impl Operator<T> for Outer`: forwards `reset`, `memory` and `set_memory` to the
/// operator in `self.$field`, whose `Memory` type is `$memory` (a composition's history is its
/// inner operator's).
macro_rules! forward_memory {
    ($field:ident, $memory:ty) => {
        fn reset(&mut self) {
            self.$field.reset();
        }

        fn memory(&self) -> $memory {
            self.$field.memory()
        }

        fn set_memory(&mut self, memory: $memory) -> Result<(), $crate::error::Error> {
            self.$field.set_memory(memory)
        }
    };
}

/// The linear operations of a value-plus-coefficients type (`Jet`, `Dual`: fields `v: T` and
/// `d: [T; N]`): `+`, `-` and negation act on every part; adding or subtracting a plain number
/// moves the value only; multiplying or dividing by one scales every part.
macro_rules! linear_ops {
    ($ty:ident) => {
        impl<T: $crate::real::Real, const N: usize> core::ops::Add for $ty<T, N> {
            type Output = Self;
            #[inline]
            fn add(mut self, rhs: Self) -> Self {
                self.v = self.v + rhs.v;
                for (a, b) in self.d.iter_mut().zip(rhs.d.iter()) {
                    *a = *a + *b;
                }
                self
            }
        }

        impl<T: $crate::real::Real, const N: usize> core::ops::Sub for $ty<T, N> {
            type Output = Self;
            #[inline]
            fn sub(mut self, rhs: Self) -> Self {
                self.v = self.v - rhs.v;
                for (a, b) in self.d.iter_mut().zip(rhs.d.iter()) {
                    *a = *a - *b;
                }
                self
            }
        }

        impl<T: $crate::real::Real, const N: usize> core::ops::Neg for $ty<T, N> {
            type Output = Self;
            #[inline]
            fn neg(mut self) -> Self {
                self.v = -self.v;
                for a in self.d.iter_mut() {
                    *a = -*a;
                }
                self
            }
        }

        impl<T: $crate::real::Real, const N: usize> core::ops::Add<T> for $ty<T, N> {
            type Output = Self;
            #[inline]
            fn add(mut self, rhs: T) -> Self {
                self.v = self.v + rhs;
                self
            }
        }

        impl<T: $crate::real::Real, const N: usize> core::ops::Sub<T> for $ty<T, N> {
            type Output = Self;
            #[inline]
            fn sub(mut self, rhs: T) -> Self {
                self.v = self.v - rhs;
                self
            }
        }

        impl<T: $crate::real::Real, const N: usize> core::ops::Mul<T> for $ty<T, N> {
            type Output = Self;
            #[inline]
            fn mul(mut self, rhs: T) -> Self {
                self.v = self.v * rhs;
                for a in self.d.iter_mut() {
                    *a = *a * rhs;
                }
                self
            }
        }

        impl<T: $crate::real::Real, const N: usize> core::ops::Div<T> for $ty<T, N> {
            type Output = Self;
            #[inline]
            fn div(mut self, rhs: T) -> Self {
                self.v = self.v / rhs;
                for a in self.d.iter_mut() {
                    *a = *a / rhs;
                }
                self
            }
        }
    };
}

pub mod adaptive;
pub mod any_shaping;
pub mod compensator;
pub mod dual;
pub mod error;
pub mod family;
pub mod jet;
pub mod k2law;
pub mod lambert;
pub mod memory;
pub mod operator;
pub mod parametric;
pub mod play;
pub mod prandtl_ishlinskii;
pub mod real;
pub mod sample;
pub mod scaled_shaping;
pub mod shaped_model;
pub mod shaping;
pub mod start;
pub mod stop;

#[allow(deprecated)]
pub use adaptive::AdaptiveCompensator;
pub use adaptive::{Adaptive, AdaptiveConfig, AdaptiveInverse};
#[allow(deprecated)]
pub use any_shaping::LinearShaping;
pub use any_shaping::{AffineShaping, AnyShaping};
pub use compensator::{Compensator, CompensatorState};
pub use dual::Dual;
pub use error::Error;
pub use family::{Bound, Family, RangeBound, Reproducibility, ShiftedK2};
pub use jet::Jet;
pub use k2law::{AffineK2, AnyK2Law, ConstantK2, K2Law};
pub use memory::{Direction, Memory};
pub use operator::Operator;
pub use parametric::{
    Direct, Formula, Hysteresis, Inverse, InverseHysteresis, ParametricHysteresis,
};
pub use play::Play;
pub use prandtl_ishlinskii::{
    InverseShapedPrandtlIshlinskii, PlayMemory, PrandtlIshlinskii, ShapedPrandtlIshlinskii,
};
pub use real::Real;
pub use sample::Sample;
pub use scaled_shaping::ScaledShaping;
pub use shaped_model::{InverseShapedModel, ShapedModel};
pub use shaping::{Affine, Identity, Langevin, Polynomial, QuadraticExp, Shaping, Tanh};
pub use start::{on_asymptote, InitialState, Start, Started};
pub use stop::Stop;

/// The Rust examples of the project's README and guide, compiled and run as doctests so the
/// documentation cannot drift from the code.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
#[doc = include_str!("../../../docs/guide.md")]
pub struct ProjectDocsDoctests;
