//! Truncated Taylor series ("jets") for time derivatives of any order.
//!
//! A [`Jet<T, N>`] carries a value and its first `N` time derivatives. Feeding the jet of an input
//! signal through the operator's formulas gives the jet of the output: the same code computes the
//! output and, by Taylor arithmetic, every derivative up to order `N`. This replaces
//! Proposition 2.7's hand-differentiated eqs. (7)–(8) (whose eq. (8) is misprinted; see
//! `docs/errata.md`) and extends them to any order, as the Lemma 5.1 compensator needs.
//!
//! Internally the coefficients are normalised Taylor coefficients `f^(k)(t)/k!`; use
//! [`Jet::from_derivatives`] and [`Jet::derivatives`] at the boundary.

use core::ops::{Div, Mul};

use crate::real::Real;

/// A value and its first `N` time derivatives, as a truncated Taylor series (no allocation).
///
/// # Examples
/// The jet of t ↦ sin-like input: value 1, rate 2, acceleration −3, through `exp`:
/// ```
/// use hyst_core::{Jet, Sample};
/// let x = Jet::<f64, 2>::from_derivatives(1.0, [2.0, -3.0]);
/// let y = x.exp(); // d/dt e^x = x' e^x, d²/dt² e^x = (x'' + x'^2) e^x
/// let e = 1.0_f64.exp();
/// let [d1, d2] = y.derivatives();
/// assert!((y.value() - e).abs() < 1e-15);
/// assert!((d1 - 2.0 * e).abs() < 1e-14);
/// assert!((d2 - (-3.0 + 4.0) * e).abs() < 1e-14);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jet<T, const N: usize> {
    v: T,
    d: [T; N],
}

impl<T: Real, const N: usize> Default for Jet<T, N> {
    fn default() -> Self {
        Self::constant(T::zero())
    }
}

impl<T: Real, const N: usize> Jet<T, N> {
    /// A constant: the given value, all derivatives zero.
    #[must_use]
    pub fn constant(value: T) -> Self {
        Self {
            v: value,
            d: [T::zero(); N],
        }
    }

    /// The independent variable at `value`: first derivative 1, higher ones 0.
    #[must_use]
    pub fn variable(value: T) -> Self {
        let mut j = Self::constant(value);
        if let Some(d1) = j.d.first_mut() {
            *d1 = T::one();
        }
        j
    }

    /// A jet from a value and its time derivatives `[x', x'', …, x^(N)]` (in units per second^k).
    #[must_use]
    pub fn from_derivatives(value: T, derivatives: [T; N]) -> Self {
        let mut d = derivatives;
        let mut factorial = T::one();
        for (k, c) in d.iter_mut().enumerate() {
            factorial = factorial * T::from_usize(k + 1);
            *c = *c / factorial;
        }
        Self { v: value, d }
    }

    /// A jet from a value and normalised Taylor coefficients `[x', x''/2!, …, x^(N)/N!]`.
    #[must_use]
    pub fn from_taylor(value: T, coefficients: [T; N]) -> Self {
        Self {
            v: value,
            d: coefficients,
        }
    }

    /// The value (order 0).
    #[must_use]
    #[inline]
    pub fn value(&self) -> T {
        self.v
    }

    /// The time derivatives `[x', x'', …, x^(N)]`.
    #[must_use]
    pub fn derivatives(&self) -> [T; N] {
        let mut d = self.d;
        let mut factorial = T::one();
        for (k, c) in d.iter_mut().enumerate() {
            factorial = factorial * T::from_usize(k + 1);
            *c = *c * factorial;
        }
        d
    }

    /// The normalised Taylor coefficients `[x', x''/2!, …, x^(N)/N!]`.
    #[must_use]
    pub fn taylor(&self) -> [T; N] {
        self.d
    }

    /// The jet with its value replaced and its derivatives kept.
    #[must_use]
    pub fn with_value(mut self, value: T) -> Self {
        self.v = value;
        self
    }

    /// True when the value and every derivative are finite.
    #[must_use]
    pub fn is_finite(&self) -> bool {
        self.v.is_finite() && self.d.iter().all(|c| c.is_finite())
    }

    /// True when every Taylor coefficient (not the value) has magnitude ≤ `limit` (false for
    /// NaN).
    #[inline]
    pub(crate) fn coefficients_below(&self, limit: T) -> bool {
        self.d.iter().all(|c| c.abs() <= limit)
    }

    /// Coefficient of order `i` (0 = value). `i ≤ N` always holds at the call sites.
    #[inline(always)]
    fn c(&self, i: usize) -> T {
        if i == 0 {
            self.v
        } else {
            self.d.get(i - 1).copied().unwrap_or_else(T::zero)
        }
    }

    /// Sets coefficient `k ≥ 1`.
    #[inline(always)]
    fn set(&mut self, k: usize, x: T) {
        if let Some(c) = self.d.get_mut(k.wrapping_sub(1)) {
            *c = x;
        }
    }

    /// e^x, by the recurrence e_k = (1/k) Σ_{j=1..k} j a_j e_{k−j}.
    #[must_use]
    pub fn exp(self) -> Self {
        let mut e = Self::constant(self.v.exp());
        for k in 1..=N {
            let mut s = T::zero();
            for j in 1..=k {
                s = s + T::from_usize(j) * self.c(j) * e.c(k - j);
            }
            e.set(k, s / T::from_usize(k));
        }
        e
    }

    /// e^x − 1, accurate for small x (value by `exp_m1`, derivatives as for `exp`).
    #[must_use]
    pub fn exp_m1(self) -> Self {
        let e = self.exp();
        e.with_value(self.v.exp_m1())
    }

    /// ln x for x > 0, by l_k = (a_k − (1/k) Σ_{j=1..k−1} j l_j a_{k−j}) / a_0.
    #[must_use]
    pub fn ln(self) -> Self {
        let mut l = Self::constant(self.v.ln());
        for k in 1..=N {
            let mut s = T::zero();
            for j in 1..k {
                s = s + T::from_usize(j) * l.c(j) * self.c(k - j);
            }
            l.set(k, (self.c(k) - s / T::from_usize(k)) / self.v);
        }
        l
    }

    /// 1 / x.
    #[must_use]
    pub fn recip(self) -> Self {
        Self::constant(T::one()) / self
    }

    /// |x|, taking the sign of the value (the derivative of |x| at 0 is taken as that of x).
    #[must_use]
    pub fn abs(self) -> Self {
        if self.v < T::zero() {
            -self
        } else {
            self
        }
    }
}

linear_ops!(Jet);

impl<T: Real, const N: usize> Mul for Jet<T, N> {
    type Output = Self;
    /// Cauchy product c_k = Σ_{i=0..k} a_i b_{k−i}.
    #[inline]
    fn mul(self, rhs: Self) -> Self {
        let mut out = Self::constant(self.v * rhs.v);
        for k in 1..=N {
            let mut s = T::zero();
            for i in 0..=k {
                s = s + self.c(i) * rhs.c(k - i);
            }
            out.set(k, s);
        }
        out
    }
}

impl<T: Real, const N: usize> Div for Jet<T, N> {
    type Output = Self;
    /// q_k = (a_k − Σ_{i=0..k−1} q_i b_{k−i}) / b_0.
    #[inline]
    fn div(self, rhs: Self) -> Self {
        let mut q = Self::constant(self.v / rhs.v);
        for k in 1..=N {
            let mut s = self.c(k);
            for i in 0..k {
                s = s - q.c(i) * rhs.c(k - i);
            }
            q.set(k, s / rhs.v);
        }
        q
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derivatives_round_trip() {
        let j = Jet::<f64, 4>::from_derivatives(0.5, [1.0, 2.0, 6.0, 24.0]);
        assert_eq!(j.taylor(), [1.0, 1.0, 1.0, 1.0]);
        assert_eq!(j.derivatives(), [1.0, 2.0, 6.0, 24.0]);
    }

    #[test]
    fn arithmetic_matches_known_series() {
        // x = t (variable at 0.3): 1/(1 − x) has Taylor coefficients 1/(1−a)^(k+1).
        let x = Jet::<f64, 4>::variable(0.3);
        let one = Jet::constant(1.0);
        let r = one / (one - x);
        for (k, c) in r.taylor().iter().enumerate() {
            let expected = 1.0 / 0.7_f64.powi(k as i32 + 2);
            assert!((c - expected).abs() < 1e-12 * expected, "order {}", k + 1);
        }
        // ln(exp(x)) = x, exp(ln(x)) = x.
        let y = Jet::<f64, 5>::from_derivatives(0.7, [0.3, -1.1, 2.0, 0.5, -4.0]);
        let back = y.exp().ln();
        let back2 = y.ln().exp();
        for (a, (b, c)) in y
            .taylor()
            .iter()
            .zip(back.taylor().iter().zip(back2.taylor()))
        {
            assert!((a - b).abs() < 1e-13 && (a - c).abs() < 1e-13);
        }
        assert!((y.exp_m1().value() - 0.7_f64.exp_m1()).abs() < 1e-16);
    }

    #[test]
    fn product_rule() {
        let a = Jet::<f64, 2>::from_derivatives(2.0, [3.0, 5.0]);
        let b = Jet::<f64, 2>::from_derivatives(7.0, [11.0, 13.0]);
        let p = (a * b).derivatives();
        assert_eq!(p[0], 3.0 * 7.0 + 2.0 * 11.0);
        assert_eq!(p[1], 5.0 * 7.0 + 2.0 * 3.0 * 11.0 + 2.0 * 13.0);
    }
}
