//! Forward-mode dual numbers: exact derivatives of the operator's output with respect to its
//! parameters (k1, the k2 law's coefficients, the shaping functions' coefficients, the initial
//! state).
//!
//! A [`Dual<T, N>`] is a value x and its gradient ∂x/∂p with respect to `N` parameters p
//! (x + Σ ∂x/∂p_i ε_i, ε_i ε_j = 0). It implements [`Real`], so every operator, k2 law, shaping
//! function and memory of the core runs on it through the *same* code as on `f64`: build a
//! [`Hysteresis<Dual<f64, N>>`](crate::Hysteresis) whose parameters are seeded with
//! [`Dual::variable`], step it, and each output carries ∂output/∂p, through every reversal point
//! the memory has stored (the reversal point (α0, β0) of Definition 2.1 is a dual too).
//!
//! Rules, so that the value part is bit-identical to the plain run:
//! - the value of every operation is the plain operation on the values (the same rounding);
//! - comparisons (`==`, `<`, `max`, `min`, `abs`, …) and every branch go by the value only;
//! - elementary functions have their analytic derivatives (`exp`, `ln`, Lambert W0 with
//!   W0'(x) = W / (x (1 + W))); the core's iterative solves (the Wright omega function for large
//!   arguments, the overflow-free form of eq. (2), the shaping inverses) converge on the values
//!   and then take their derivatives from the implicit-function theorem
//!   ([`Real::implicit_root`]), never by differentiating the iterations.
//!
//! Derivatives through a kink (the band clamp, a clamped k2 law, a tangent extension's end
//! point) are those of the branch the value took. Time derivatives and parameter derivatives
//! combine: `Jet<Dual<f64, N>, M>` is a jet whose coefficients carry their gradients.
//!
//! # Examples
//! ∂u/∂k1 and ∂u/∂k2 of the direct operator u = H(k1, k2)\[v\] along a history with a reversal,
//! checked against central finite differences:
//! ```
//! use hyst_core::{Dual, Hysteresis, Operator};
//! # fn main() -> Result<(), hyst_core::Error> {
//! let inputs = [0.0, 0.6, 1.0, 0.3, -0.2, 0.5];
//! let (k1, k2) = (0.14, 8.0);
//! // Seed: k1 is parameter 0, k2 is parameter 1.
//! let mut h = Hysteresis::new(Dual::<f64, 2>::variable(k1, 0), Dual::variable(k2, 1))?;
//! let mut u = Dual::constant(0.0);
//! for &v in &inputs {
//!     u = h.step(Dual::constant(v));
//! }
//! let [du_dk1, du_dk2] = u.gradient();
//!
//! // The same with plain numbers, k1 moved by ±h.
//! let run = |k1: f64| -> Result<f64, hyst_core::Error> {
//!     let mut h = Hysteresis::new(k1, k2)?;
//!     Ok(inputs.iter().fold(0.0, |_, &v| h.step(v)))
//! };
//! let step = 1e-6;
//! let fd = (run(k1 + step)? - run(k1 - step)?) / (2.0 * step);
//! assert!((du_dk1 - fd).abs() < 1e-8);
//! assert_eq!(u.value(), run(k1)?); // the value is the plain run's, bit for bit
//! assert!(du_dk2.is_finite());
//! # Ok(())
//! # }
//! ```

use core::cmp::Ordering;
use core::fmt;
use core::num::FpCategory;
use core::ops::{Div, Mul, Rem};

use num_traits::{Float, FloatConst, Num, NumCast, One, ToPrimitive, Zero};

use crate::real::Real;

/// A value and its gradient with respect to `N` parameters: x + Σ ∂x/∂p_i ε_i (forward-mode
/// automatic differentiation, first order). `T` is `f64` or `f32`; the gradient is in units of
/// x per unit of each parameter.
///
/// Equality and order compare the values only (see the [module docs](self)).
#[derive(Clone, Copy, Debug)]
pub struct Dual<T, const N: usize> {
    v: T,
    d: [T; N],
}

impl<T: Real, const N: usize> Dual<T, N> {
    /// A constant: the value, gradient zero (data, fixed settings).
    #[must_use]
    #[inline]
    pub fn constant(value: T) -> Self {
        Self {
            v: value,
            d: [T::zero(); N],
        }
    }

    /// Parameter number `index` (0-based, < `N`) at `value`: gradient 1 in that slot, 0
    /// elsewhere. An `index` ≥ `N` gives a constant.
    #[must_use]
    pub fn variable(value: T, index: usize) -> Self {
        let mut x = Self::constant(value);
        if let Some(slot) = x.d.get_mut(index) {
            *slot = T::one();
        }
        x
    }

    /// A value with a given gradient `[∂x/∂p_0, …, ∂x/∂p_(N−1)]` (e.g. a parameter that is a
    /// function of others: x = e^θ is `Dual::new(e^θ, [e^θ, 0, …])` for p_0 = θ).
    #[must_use]
    #[inline]
    pub fn new(value: T, gradient: [T; N]) -> Self {
        Self {
            v: value,
            d: gradient,
        }
    }

    /// The value.
    #[must_use]
    #[inline]
    pub fn value(&self) -> T {
        self.v
    }

    /// The gradient `[∂x/∂p_0, …, ∂x/∂p_(N−1)]`.
    #[must_use]
    #[inline]
    pub fn gradient(&self) -> [T; N] {
        self.d
    }

    /// True when the value and every partial derivative are finite (the [`Float::is_finite`]
    /// of a dual looks at the value only).
    #[must_use]
    pub fn all_finite(&self) -> bool {
        self.v.is_finite() && self.d.iter().all(|g| g.is_finite())
    }

    /// f(x) from f(value) = `value` and f'(value) = `slope`: the chain rule.
    #[inline]
    fn chain(self, value: T, slope: T) -> Self {
        let mut d = self.d;
        for g in &mut d {
            *g = *g * slope;
        }
        Self { v: value, d }
    }

    /// The linear combination a·self + b·other of the gradients, with the given value.
    #[inline]
    fn combine(self, a: T, other: Self, b: T, value: T) -> Self {
        let mut d = self.d;
        for (g, h) in d.iter_mut().zip(other.d.iter()) {
            *g = *g * a + *h * b;
        }
        Self { v: value, d }
    }
}

impl<T: Real, const N: usize> Default for Dual<T, N> {
    fn default() -> Self {
        Self::constant(T::zero())
    }
}

impl<T: Real, const N: usize> fmt::Display for Dual<T, N> {
    /// The value, then the gradient: `0.5 [1, 0]`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(&self.v, f)?;
        f.write_str(" [")?;
        for (i, g) in self.d.iter().enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            fmt::Display::fmt(g, f)?;
        }
        f.write_str("]")
    }
}

impl<T: Real, const N: usize> PartialEq for Dual<T, N> {
    /// By the value only.
    #[inline]
    fn eq(&self, other: &Self) -> bool {
        self.v == other.v
    }
}

impl<T: Real, const N: usize> PartialOrd for Dual<T, N> {
    /// By the value only.
    #[inline]
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        self.v.partial_cmp(&other.v)
    }
}

linear_ops!(Dual);

impl<T: Real, const N: usize> Mul for Dual<T, N> {
    type Output = Self;
    /// (a + a'ε)(b + b'ε) = ab + (a'b + ab')ε.
    #[inline]
    fn mul(self, rhs: Self) -> Self {
        let (a, b) = (self.v, rhs.v);
        self.combine(b, rhs, a, a * b)
    }
}

impl<T: Real, const N: usize> Div for Dual<T, N> {
    type Output = Self;
    /// (a + a'ε)/(b + b'ε) = a/b + (a' − (a/b) b')/b ε.
    #[inline]
    fn div(self, rhs: Self) -> Self {
        let q = self.v / rhs.v;
        let inv = T::one() / rhs.v;
        self.combine(inv, rhs, -q * inv, q)
    }
}

impl<T: Real, const N: usize> Rem for Dual<T, N> {
    type Output = Self;
    /// a − trunc(a/b)·b (the gradient of the remainder where it is smooth).
    fn rem(self, rhs: Self) -> Self {
        let r = self.v % rhs.v;
        let k = (self.v / rhs.v).trunc();
        self.combine(T::one(), rhs, -k, r)
    }
}

impl<T: Real, const N: usize> Zero for Dual<T, N> {
    fn zero() -> Self {
        Self::constant(T::zero())
    }
    fn is_zero(&self) -> bool {
        self.v == T::zero()
    }
}

impl<T: Real, const N: usize> One for Dual<T, N> {
    fn one() -> Self {
        Self::constant(T::one())
    }
}

impl<T: Real, const N: usize> Num for Dual<T, N> {
    type FromStrRadixErr = T::FromStrRadixErr;
    /// A constant parsed from a string.
    fn from_str_radix(s: &str, radix: u32) -> Result<Self, Self::FromStrRadixErr> {
        T::from_str_radix(s, radix).map(Self::constant)
    }
}

impl<T: Real, const N: usize> ToPrimitive for Dual<T, N> {
    fn to_i64(&self) -> Option<i64> {
        self.v.to_i64()
    }
    fn to_u64(&self) -> Option<u64> {
        self.v.to_u64()
    }
    fn to_f64(&self) -> Option<f64> {
        self.v.to_f64()
    }
}

impl<T: Real, const N: usize> NumCast for Dual<T, N> {
    /// A constant from a number.
    fn from<P: ToPrimitive>(n: P) -> Option<Self> {
        <T as NumCast>::from(n).map(Self::constant)
    }
}

macro_rules! constants {
    ($($name:ident),* $(,)?) => {
        $(
            #[inline]
            fn $name() -> Self {
                Self::constant(T::$name())
            }
        )*
    };
}

macro_rules! by_value {
    ($($name:ident -> $out:ty),* $(,)?) => {
        $(
            #[inline]
            fn $name(self) -> $out {
                self.v.$name()
            }
        )*
    };
}

/// Functions that are piecewise constant (their derivative is 0 where it exists).
macro_rules! piecewise_constant {
    ($($name:ident),* $(,)?) => {
        $(
            #[inline]
            fn $name(self) -> Self {
                Self::constant(self.v.$name())
            }
        )*
    };
}

impl<T: Real, const N: usize> FloatConst for Dual<T, N> {
    constants!(
        E,
        FRAC_1_PI,
        FRAC_1_SQRT_2,
        FRAC_2_PI,
        FRAC_2_SQRT_PI,
        FRAC_PI_2,
        FRAC_PI_3,
        FRAC_PI_4,
        FRAC_PI_6,
        FRAC_PI_8,
        LN_10,
        LN_2,
        LOG10_E,
        LOG2_E,
        PI,
        SQRT_2,
        TAU,
        LOG10_2,
        LOG2_10,
    );
}

impl<T: Real, const N: usize> Float for Dual<T, N> {
    constants!(
        nan,
        infinity,
        neg_infinity,
        neg_zero,
        min_value,
        min_positive_value,
        max_value,
        epsilon,
    );
    by_value!(
        is_nan -> bool,
        is_infinite -> bool,
        is_finite -> bool,
        is_normal -> bool,
        is_subnormal -> bool,
        classify -> FpCategory,
        is_sign_positive -> bool,
        is_sign_negative -> bool,
        integer_decode -> (u64, i16, i8),
    );
    piecewise_constant!(floor, ceil, round, trunc, signum);

    fn fract(self) -> Self {
        self.chain(self.v.fract(), T::one())
    }

    /// |x| by the sign of the value (at 0 the gradient is kept as it is).
    #[inline]
    fn abs(self) -> Self {
        if self.v < T::zero() {
            -self
        } else {
            self
        }
    }

    /// self · a + b, the value by the plain fused multiply-add.
    fn mul_add(self, a: Self, b: Self) -> Self {
        let mut out = self.combine(a.v, a, self.v, self.v.mul_add(a.v, b.v));
        for (g, h) in out.d.iter_mut().zip(b.d.iter()) {
            *g = *g + *h;
        }
        out
    }

    fn recip(self) -> Self {
        let r = self.v.recip();
        self.chain(r, -r * r)
    }

    fn powi(self, n: i32) -> Self {
        let slope = if n == 0 {
            T::zero()
        } else {
            T::from_f64(<f64 as From<i32>>::from(n)) * self.v.powi(n - 1)
        };
        self.chain(self.v.powi(n), slope)
    }

    /// x^n: ∂ = n x^(n−1) ∂x + x^n ln x ∂n (the second term only when n carries a gradient).
    fn powf(self, n: Self) -> Self {
        let value = self.v.powf(n.v);
        let dx = if n.v == T::zero() {
            T::zero()
        } else {
            n.v * self.v.powf(n.v - T::one())
        };
        let dn = if n.d.iter().all(|g| *g == T::zero()) {
            T::zero()
        } else {
            value * self.v.ln()
        };
        self.combine(dx, n, dn, value)
    }

    fn sqrt(self) -> Self {
        let s = self.v.sqrt();
        self.chain(s, T::one() / (s + s))
    }

    #[inline]
    fn exp(self) -> Self {
        let e = self.v.exp();
        self.chain(e, e)
    }

    fn exp2(self) -> Self {
        let e = self.v.exp2();
        self.chain(e, e * T::LN_2())
    }

    #[inline]
    fn ln(self) -> Self {
        self.chain(self.v.ln(), T::one() / self.v)
    }

    fn log(self, base: Self) -> Self {
        self.ln() / base.ln()
    }

    fn log2(self) -> Self {
        self.chain(self.v.log2(), T::one() / (self.v * T::LN_2()))
    }

    fn log10(self) -> Self {
        self.chain(self.v.log10(), T::one() / (self.v * T::LN_10()))
    }

    /// The larger by value (NaN loses, as for floats), with its gradient.
    #[inline]
    fn max(self, other: Self) -> Self {
        if self.v.is_nan() || other.v > self.v {
            other
        } else {
            self
        }
    }

    /// The smaller by value (NaN loses, as for floats), with its gradient.
    #[inline]
    fn min(self, other: Self) -> Self {
        if self.v.is_nan() || other.v < self.v {
            other
        } else {
            self
        }
    }

    fn abs_sub(self, other: Self) -> Self {
        if self.v <= other.v {
            Self::zero()
        } else {
            self - other
        }
    }

    fn cbrt(self) -> Self {
        let c = self.v.cbrt();
        self.chain(c, T::one() / (T::from_f64(3.0) * c * c))
    }

    fn hypot(self, other: Self) -> Self {
        let h = self.v.hypot(other.v);
        self.combine(self.v / h, other, other.v / h, h)
    }

    fn sin(self) -> Self {
        self.chain(self.v.sin(), self.v.cos())
    }

    fn cos(self) -> Self {
        self.chain(self.v.cos(), -self.v.sin())
    }

    fn tan(self) -> Self {
        let t = self.v.tan();
        self.chain(t, T::one() + t * t)
    }

    fn asin(self) -> Self {
        self.chain(
            self.v.asin(),
            T::one() / (T::one() - self.v * self.v).sqrt(),
        )
    }

    fn acos(self) -> Self {
        self.chain(
            self.v.acos(),
            -T::one() / (T::one() - self.v * self.v).sqrt(),
        )
    }

    fn atan(self) -> Self {
        self.chain(self.v.atan(), T::one() / (T::one() + self.v * self.v))
    }

    /// atan2(y = self, x = other).
    fn atan2(self, other: Self) -> Self {
        let r2 = self.v * self.v + other.v * other.v;
        self.combine(other.v / r2, other, -self.v / r2, self.v.atan2(other.v))
    }

    fn sin_cos(self) -> (Self, Self) {
        let (s, c) = self.v.sin_cos();
        (self.chain(s, c), self.chain(c, -s))
    }

    /// e^x − 1, with the derivative e^x taken as (e^x − 1) + 1 (no second transcendental;
    /// absolute error ≤ 2 ε e^x + ε, i.e. a relative error ≤ 3 ε wherever e^x ≥ 1/2).
    fn exp_m1(self) -> Self {
        let e = self.v.exp_m1();
        self.chain(e, e + T::one())
    }

    fn ln_1p(self) -> Self {
        self.chain(self.v.ln_1p(), T::one() / (T::one() + self.v))
    }

    fn sinh(self) -> Self {
        self.chain(self.v.sinh(), self.v.cosh())
    }

    fn cosh(self) -> Self {
        self.chain(self.v.cosh(), self.v.sinh())
    }

    fn tanh(self) -> Self {
        let t = self.v.tanh();
        self.chain(t, T::one() - t * t)
    }

    fn asinh(self) -> Self {
        self.chain(
            self.v.asinh(),
            T::one() / (self.v * self.v + T::one()).sqrt(),
        )
    }

    fn acosh(self) -> Self {
        self.chain(
            self.v.acosh(),
            T::one() / (self.v * self.v - T::one()).sqrt(),
        )
    }

    fn atanh(self) -> Self {
        self.chain(self.v.atanh(), T::one() / (T::one() - self.v * self.v))
    }
}

impl<T: Real, const N: usize> Real for Dual<T, N> {
    const ZERO: Self = Self {
        v: T::ZERO,
        d: [T::ZERO; N],
    };
    const EXP_ARG_MAX: Self = Self {
        v: T::EXP_ARG_MAX,
        d: [T::ZERO; N],
    };

    #[inline]
    fn from_f64(x: f64) -> Self {
        Self::constant(T::from_f64(x))
    }

    /// The value as `f64` (the gradient is dropped).
    #[inline]
    fn as_f64(self) -> f64 {
        self.v.as_f64()
    }

    #[inline]
    fn from_usize(n: usize) -> Self {
        Self::constant(T::from_usize(n))
    }

    /// The value one ulp toward `target`'s value; the gradient is kept.
    #[inline]
    fn ulp_toward(self, target: Self) -> Self {
        Self {
            v: self.v.ulp_toward(target.v),
            d: self.d,
        }
    }

    /// W0 of the value by Fukushima's method; gradient by W0'(x) = W / (x (1 + W)) (1 at x = 0).
    #[inline]
    fn lambert_w0_fukushima(self) -> Self {
        let w = self.v.lambert_w0_fukushima();
        let slope = if self.v == T::zero() {
            T::one()
        } else {
            w / (self.v * (T::one() + w))
        };
        self.chain(w, slope)
    }

    /// The gradient of the root of g(w; p) = 0 by the implicit-function theorem,
    /// ∂w/∂p = −(∂g/∂p) / (∂g/∂w): g is evaluated at the root's value held constant (so its
    /// gradient is ∂g/∂p alone), whatever gradient the iterations left in `self` (even an
    /// overflowed one).
    #[inline]
    fn implicit_root(self, residual_and_slope: impl FnOnce(Self) -> (Self, Self)) -> Self {
        let (g, slope) = residual_and_slope(Self::constant(self.v));
        let inv = -T::one() / slope.v;
        let mut d = g.d;
        for w in &mut d {
            *w = *w * inv;
        }
        Self { v: self.v, d }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    type D = Dual<f64, 2>;
    type Unary = (&'static str, fn(D) -> D);

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * (1.0 + b.abs())
    }

    /// Every elementary function's gradient against a central difference of its value.
    #[test]
    fn elementary_functions_match_central_differences() {
        let fs: [Unary; 22] = [
            ("exp", |x| x.exp()),
            ("exp_m1", |x| x.exp_m1()),
            ("exp2", |x| x.exp2()),
            ("ln", |x| x.ln()),
            ("ln_1p", |x| x.ln_1p()),
            ("log2", |x| x.log2()),
            ("log10", |x| x.log10()),
            ("sqrt", |x| x.sqrt()),
            ("cbrt", |x| x.cbrt()),
            ("recip", |x| x.recip()),
            ("powi", |x| x.powi(3)),
            ("powf", |x| x.powf(x)),
            ("sin", |x| x.sin()),
            ("cos", |x| x.cos()),
            ("tan", |x| x.tan()),
            ("atan", |x| x.atan()),
            ("asin", |x| (x * 0.5).asin()),
            ("tanh", |x| x.tanh()),
            ("sinh", |x| x.sinh()),
            ("asinh", |x| x.asinh()),
            ("w0", |x| x.lambert_w0_fukushima()),
            ("mixed", |x| {
                (x * x + x.exp()) / (x + 2.0).ln() - x % D::from_f64(0.7)
            }),
        ];
        for (name, f) in fs {
            for &x0 in &[0.3_f64, 0.9, 1.7] {
                let y = f(D::variable(x0, 1));
                let h = 1e-6;
                let fd =
                    (f(D::constant(x0 + h)).value() - f(D::constant(x0 - h)).value()) / (2.0 * h);
                assert!(
                    close(y.gradient()[1], fd, 1e-7),
                    "{name} at {x0}: {} vs {fd}",
                    y.gradient()[1]
                );
                assert_eq!(y.gradient()[0], 0.0, "{name}");
            }
        }
    }

    #[test]
    fn two_argument_functions() {
        let x = D::variable(0.7, 0);
        let y = D::variable(-1.3, 1);
        let a = x.atan2(y);
        let h = x.hypot(y);
        let m = x.mul_add(y, x);
        let r2 = 0.7_f64 * 0.7 + 1.3 * 1.3;
        assert!(close(a.gradient()[0], -1.3 / r2, 1e-15));
        assert!(close(a.gradient()[1], -0.7 / r2, 1e-15));
        assert!(close(h.gradient()[0], 0.7 / r2.sqrt(), 1e-15));
        assert_eq!(m.gradient(), [-1.3 + 1.0, 0.7]);
        assert_eq!(m.value(), 0.7_f64.mul_add(-1.3, 0.7));
    }

    #[test]
    fn comparisons_and_branches_use_the_value() {
        let a = D::new(1.0, [5.0, 0.0]);
        let b = D::new(1.0, [0.0, 7.0]);
        assert_eq!(a, b);
        assert_eq!(a.max(D::constant(0.5)).gradient(), [5.0, 0.0]);
        assert_eq!(a.min(D::constant(2.0)).gradient(), [5.0, 0.0]);
        assert_eq!((-a).abs().gradient(), [5.0, 0.0]);
        assert_eq!(D::nan().max(b).gradient(), [0.0, 7.0]);
        assert!(D::EXP_ARG_MAX == D::from_f64(700.0));
        assert!(!D::new(1.0, [f64::NAN, 0.0]).all_finite());
        assert!(D::new(1.0, [f64::NAN, 0.0]).is_finite());
    }

    /// The implicit-function step recovers ∂w/∂x of w e^w = x from any leftover gradient.
    #[test]
    fn implicit_root_ignores_the_iterations_gradient() {
        let x = D::variable(2.0, 0);
        let w0 = 2.0_f64.lambert_w0_fukushima();
        let junk = D::new(w0, [f64::INFINITY, f64::NAN]);
        let w = junk.implicit_root(|w| (w * w.exp() - x, (w + 1.0) * w.exp()));
        let exact = w0 / (2.0 * (1.0 + w0));
        assert_eq!(w.value(), w0);
        assert!(close(w.gradient()[0], exact, 1e-15), "{}", w.gradient()[0]);
        assert_eq!(w.gradient()[1], 0.0);
    }
}
