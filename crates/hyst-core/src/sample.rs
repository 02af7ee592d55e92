//! One numeric interface for plain numbers and jets, so each formula of the paper is written once.

use core::ops::{Add, Div, Mul, Neg, Sub};

use crate::jet::Jet;
use crate::lambert;
use crate::real::Real;

/// A number the operator formulas can be evaluated on: a plain [`Real`] (`f32`, `f64`) or a
/// [`Jet`] of one (value and time derivatives).
///
/// The direct operator (eq. 2), the inverse (eq. 4), the shaping functions and the k2 laws are
/// written once, generically over `Sample`; evaluating them on a jet gives the time derivatives of
/// the result (Proposition 2.7 and beyond) with no second copy of any formula.
pub trait Sample<T: Real>:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<T, Output = Self>
    + Sub<T, Output = Self>
    + Mul<T, Output = Self>
    + Div<T, Output = Self>
{
    /// How many time derivatives the type carries (0 for plain numbers).
    const ORDER: usize;
    /// A constant (all derivatives zero).
    fn constant(x: T) -> Self;
    /// The value (order 0).
    fn value(&self) -> T;
    /// The same derivatives with another value.
    #[must_use]
    fn with_value(self, v: T) -> Self;
    /// Whether the signal rises (`Some(true)`) or falls (`Some(false)`) according to its
    /// lowest-order non-zero derivative; `None` for plain numbers or when all derivatives are 0.
    fn trend(&self) -> Option<bool>;
    /// True when the value and all derivatives are finite.
    fn all_finite(&self) -> bool;
    /// e^x.
    #[must_use]
    fn exp(self) -> Self;
    /// e^x − 1.
    #[must_use]
    fn exp_m1(self) -> Self;
    /// ln x.
    #[must_use]
    fn ln(self) -> Self;
    /// |x| (for jets, the sign of the value decides).
    #[must_use]
    fn abs(self) -> Self;
    /// Lambert W0(x) for finite x ≥ 0 (use [`lambert::w0`] for +∞).
    #[must_use]
    fn w0(self) -> Self;
    /// Wright omega ω(x) = W0(e^x).
    #[must_use]
    fn omega(self) -> Self;
    /// A root w of g(w) = 0 whose parameter gradient (if the number type carries one) should
    /// come from the implicit-function theorem: [`Real::implicit_root`] for plain numbers
    /// (identity on `f32`/`f64`, the gradient of a [`Dual`](crate::Dual)); a jet keeps its
    /// Taylor-arithmetic derivatives.
    #[must_use]
    #[inline(always)]
    fn implicit(self, residual_and_slope: impl FnOnce(Self) -> (Self, Self)) -> Self {
        let _ = residual_and_slope;
        self
    }
}

impl<T: Real> Sample<T> for T {
    const ORDER: usize = 0;
    #[inline]
    fn constant(x: T) -> Self {
        x
    }
    #[inline]
    fn value(&self) -> T {
        *self
    }
    #[inline]
    fn with_value(self, v: T) -> Self {
        v
    }
    #[inline]
    fn trend(&self) -> Option<bool> {
        None
    }
    #[inline]
    fn all_finite(&self) -> bool {
        num_traits::Float::is_finite(*self)
    }
    #[inline]
    fn exp(self) -> Self {
        num_traits::Float::exp(self)
    }
    #[inline]
    fn exp_m1(self) -> Self {
        num_traits::Float::exp_m1(self)
    }
    #[inline]
    fn ln(self) -> Self {
        num_traits::Float::ln(self)
    }
    #[inline]
    fn abs(self) -> Self {
        num_traits::Float::abs(self)
    }
    #[inline]
    fn w0(self) -> Self {
        lambert::w0_finite(self)
    }
    #[inline]
    fn omega(self) -> Self {
        lambert::omega(self)
    }
    #[inline(always)]
    fn implicit(self, residual_and_slope: impl FnOnce(Self) -> (Self, Self)) -> Self {
        Real::implicit_root(self, residual_and_slope)
    }
}

/// The exact test behind `all_finite` for jets, out of line (rarely reached).
#[cold]
#[inline(never)]
fn derivatives_finite<T: Real, const N: usize>(jet: &Jet<T, N>) -> bool {
    jet.is_finite() && jet.derivatives().iter().all(|d| d.is_finite())
}

impl<T: Real, const N: usize> Sample<T> for Jet<T, N> {
    const ORDER: usize = N;
    #[inline]
    fn constant(x: T) -> Self {
        Jet::constant(x)
    }
    #[inline]
    fn value(&self) -> T {
        Jet::value(self)
    }
    #[inline]
    fn with_value(self, v: T) -> Self {
        Jet::with_value(self, v)
    }
    fn trend(&self) -> Option<bool> {
        self.taylor()
            .iter()
            .find(|c| **c != T::zero())
            .map(|c| *c > T::zero())
    }
    /// The stored Taylor coefficients and the derivatives they stand for (coefficient × k!,
    /// which can overflow where the coefficient does not).
    #[inline]
    fn all_finite(&self) -> bool {
        // Fast test: every coefficient at most MAX / N! (then no derivative can overflow);
        // the exact one only when that fails.
        let mut factorial = T::one();
        for k in 1..=N {
            factorial = factorial * T::from_usize(k);
        }
        let limit = T::max_value() / factorial;
        (self.value().is_finite() && self.coefficients_below(limit)) || derivatives_finite(self)
    }
    fn exp(self) -> Self {
        Jet::exp(self)
    }
    fn exp_m1(self) -> Self {
        Jet::exp_m1(self)
    }
    fn ln(self) -> Self {
        Jet::ln(self)
    }
    fn abs(self) -> Self {
        Jet::abs(self)
    }
    /// Newton's method on jets for w e^w = x, started at the exact value W0(x0): each step
    /// doubles the number of correct Taylor coefficients.
    fn w0(self) -> Self {
        let w_value = lambert::w0(self.value());
        let mut w = Jet::constant(w_value);
        let mut correct = 0;
        while correct < N {
            let e = w.exp();
            w = (w - (w * e - self) / (e * (w + T::one()))).with_value(w_value);
            correct = 2 * correct + 1;
        }
        w
    }
    /// Newton's method on jets for ω + ln ω = x (for ω > 1; below, W0(e^x)).
    fn omega(self) -> Self {
        let w_value = lambert::omega(self.value());
        if w_value <= T::one() {
            return Sample::w0(Jet::exp(self)).with_value(w_value);
        }
        let mut w = Jet::constant(w_value);
        let mut correct = 0;
        while correct < N {
            w = (w - (w + w.ln() - self) * w / (w + T::one())).with_value(w_value);
            correct = 2 * correct + 1;
        }
        w
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// d/dx W(x) = W / (x (1 + W)); d/dy ω(y) = ω / (1 + ω); compare orders 1..3 with the
    /// closed forms of the derivatives of W.
    #[test]
    fn lambert_jets_match_closed_form_derivatives() {
        for &x0 in &[0.0_f64, 1e-3, 0.5, 1.0, 3.0, 50.0, 1e6] {
            let j = Sample::w0(Jet::<f64, 3>::variable(x0));
            let w = j.value();
            let d = j.derivatives();
            // W' = 1 / (e^W (1 + W)), W'' = −W'^2 (2 + W) / (1 + W), (valid at 0 too)
            let w1 = 1.0 / (w.exp() * (1.0 + w));
            let w2 = -w1 * w1 * (2.0 + w) / (1.0 + w);
            assert!((d[0] - w1).abs() <= 1e-14 * w1.abs().max(1e-300), "x {x0}");
            assert!((d[1] - w2).abs() <= 1e-13 * w2.abs().max(1e-300), "x {x0}");
        }
        for &y0 in &[-30.0_f64, -1.0, 0.0, 2.0, 40.0, 800.0, 1e9] {
            let j = Sample::omega(Jet::<f64, 3>::variable(y0));
            let w = j.value();
            let d = j.derivatives();
            let w1 = w / (1.0 + w);
            let w2 = w / (1.0 + w).powi(3);
            let w3 = w * (1.0 - 2.0 * w) / (1.0 + w).powi(5);
            assert!((d[0] - w1).abs() <= 1e-14 * w1, "y {y0}");
            assert!((d[1] - w2).abs() <= 1e-13 * w2, "y {y0}");
            assert!((d[2] - w3).abs() <= 1e-12 * w3.abs(), "y {y0}");
        }
    }
}
