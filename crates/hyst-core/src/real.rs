//! The floating-point types the core works with.

use core::fmt::{Debug, Display};

/// A real floating-point type: implemented for `f32` and `f64`, and for
/// [`Dual<f32 or f64, N>`](crate::Dual) (a value with its gradient with respect to N parameters,
/// for parameter sensitivities through the same code).
///
/// All maths goes through [`num_traits::Float`]: without the `std` feature its functions are
/// `libm`'s, with `std` they are the platform's (the standard library's `exp`, `ln`, …), so
/// results may differ in the last bit between the two builds. The Lambert W approximation is
/// always Fukushima's, from the `lambert_w` crate, whose square roots and logarithms are likewise
/// the platform's with `std` and `libm`'s without (so W0 too may differ in the last bit between
/// the two builds). The extra items here are the constants and the
/// Lambert W approximation the operator needs at each precision.
pub trait Real:
    num_traits::Float + num_traits::FloatConst + Debug + Display + Default + Send + Sync + 'static
{
    /// Converts an `f64` literal to this type (rounding to nearest for `f32`).
    fn from_f64(x: f64) -> Self;
    /// Converts this value to `f64` (exact for both implementations).
    fn as_f64(self) -> f64;
    /// Converts a small count (a derivative order, a factorial factor) to this type without
    /// going through `f64` (an `f32`-only FPU has no double arithmetic); exact below 2^24.
    fn from_usize(n: usize) -> Self;
    /// Principal branch of the Lambert W function for `x ≥ 0`, by Fukushima's minimax method
    /// (the `lambert_w` crate's `lambert_w0` and `lambert_w0f`): 50 bits for `f64`, 24 bits for
    /// `f32`.
    fn lambert_w0_fukushima(self) -> Self;
    /// The next representable value after `self` in the direction of `target` (one ulp;
    /// `self` when they are equal or either is NaN). A [`Dual`](crate::Dual) steps its value
    /// and keeps its gradient.
    #[must_use]
    fn ulp_toward(self, target: Self) -> Self;
    /// The largest `y` for which `exp(y)` is finite, less a safety margin: above it the Wright
    /// omega function is evaluated in the log domain.
    const EXP_ARG_MAX: Self;
    /// Zero, as a constant (for constants of composite types such as [`Dual`](crate::Dual)).
    const ZERO: Self;

    /// The derivatives of a root w of g(w; p) = 0 that an iteration has converged to on the
    /// values: `residual_and_slope(w)` returns (g(w), ∂g/∂w) at w. A plain float has no
    /// derivatives and returns `self` without calling it (no cost on the plain path); a
    /// [`Dual`](crate::Dual) keeps its value and takes its gradient from the implicit-function
    /// theorem, ∂w/∂p = −(∂g/∂p) / (∂g/∂w) (g evaluated at the value held constant), so no
    /// iteration is ever differentiated.
    #[inline(always)]
    #[must_use]
    fn implicit_root(self, residual_and_slope: impl FnOnce(Self) -> (Self, Self)) -> Self {
        let _ = residual_and_slope;
        self
    }
}

impl Real for f64 {
    #[inline]
    fn from_f64(x: f64) -> Self {
        x
    }
    #[inline]
    fn as_f64(self) -> f64 {
        self
    }
    #[inline]
    fn from_usize(n: usize) -> Self {
        n as f64
    }
    #[inline]
    fn lambert_w0_fukushima(self) -> Self {
        lambert_w::lambert_w0(self)
    }
    #[inline]
    fn ulp_toward(self, target: Self) -> Self {
        if self.is_nan() || target.is_nan() || self == target {
            return self;
        }
        if self == 0.0 {
            // The smallest subnormal with the target's sign.
            return f64::from_bits(1).copysign(target);
        }
        let bits = self.to_bits();
        // Away from zero when the target is further out on the same side, else toward it.
        f64::from_bits(if (target > self) == (self > 0.0) {
            bits + 1
        } else {
            bits - 1
        })
    }
    const EXP_ARG_MAX: Self = 700.0;
    const ZERO: Self = 0.0;
}

impl Real for f32 {
    #[inline]
    fn from_f64(x: f64) -> Self {
        x as f32
    }
    #[inline]
    fn as_f64(self) -> f64 {
        f64::from(self)
    }
    #[inline]
    fn from_usize(n: usize) -> Self {
        n as f32
    }
    #[inline]
    fn lambert_w0_fukushima(self) -> Self {
        lambert_w::lambert_w0f(self)
    }
    #[inline]
    fn ulp_toward(self, target: Self) -> Self {
        if self.is_nan() || target.is_nan() || self == target {
            return self;
        }
        if self == 0.0 {
            // The smallest subnormal with the target's sign.
            return f32::from_bits(1).copysign(target);
        }
        let bits = self.to_bits();
        // Away from zero when the target is further out on the same side, else toward it.
        f32::from_bits(if (target > self) == (self > 0.0) {
            bits + 1
        } else {
            bits - 1
        })
    }
    const EXP_ARG_MAX: Self = 85.0;
    const ZERO: Self = 0.0;
}
