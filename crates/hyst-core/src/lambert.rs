//! The Lambert W function on `[0, ∞)` and the Wright omega function ω(y) = W(e^y).
//!
//! The direct operator (eq. 2) needs `W(k2 M* e^(k2 (M* − ṽ)))`. The argument overflows an `f64`
//! as soon as `k2 M*` exceeds about 700 (k1 = 0.2 with k2 = 2000 already does, and Example 3 wants
//! k2 → ∞), so the operator evaluates it as ω(ln(k2 M*) + k2 (M* − ṽ)) whenever the plain
//! argument is not finite.
//!
//! Accuracy (checked against mpmath tables in `tests/special_functions.rs`): relative error
//! ≤ 2e-15 for `f64` on x ∈ [0, 1e300] and y ∈ [−700, 1e20] (ω is then the correctly rounded
//! value to within a few ulps for every finite y); about 1e-6 for `f32`.
//!
//! # Reference
//! - T. Fukushima, "Precise and fast computation of Lambert W-functions without transcendental
//!   function evaluations", J. Comput. Appl. Math. 244 (2013), via the `lambert_w` crate.
//! - F. N. Fritsch, R. E. Shafer, W. P. Crowley, "Algorithm 443: Solution of the transcendental
//!   equation w e^w = x", Comm. ACM 16 (1973): the fourth-order iteration used for large y.
//! - P. W. Lawrence, R. M. Corless, D. J. Jeffrey, "Algorithm 917: Complex double-precision
//!   evaluation of the Wright ω function", ACM TOMS 38 (2012): the asymptotic start y − ln y.

use crate::real::Real;

/// Principal branch W0(x) of the Lambert W function, the solution w ≥ 0 of w e^w = x, for x ≥ 0.
///
/// Returns NaN for NaN or negative x below −1/e, and +∞ for x = +∞. Exact at 0.
///
/// # Examples
/// ```
/// use hyst_core::lambert::w0;
/// assert_eq!(w0(0.0_f64), 0.0);
/// let omega = w0(1.0_f64); // the omega constant
/// assert!((omega - 0.567_143_290_409_783_8).abs() < 1e-15);
/// assert!((w0(core::f64::consts::E) - 1.0).abs() < 1e-15);
/// ```
#[must_use]
#[inline]
pub fn w0<T: Real>(x: T) -> T {
    if x == T::infinity() {
        return x;
    }
    w0_finite(x)
}

/// Below this argument W0 is evaluated by its series (see [`w0_finite`]).
const SERIES_MAX: f64 = 1e-4;

/// W0(x) for finite x ≥ −1/e. For 0 ≤ x < 1e-4 (far from a reversal point, the direct
/// operator's usual case) five terms of the series W(x) = Σ (−n)^(n−1) xⁿ / n! are exact to
/// rounding (the first omitted term is 10.8 x⁶ < 1.1e-19 x) and cheaper than the minimax
/// evaluation; elsewhere Fukushima's method.
#[must_use]
#[inline]
pub(crate) fn w0_finite<T: Real>(x: T) -> T {
    // The upper bound first: above it (most arguments near a reversal point) one compare.
    if x < T::from_f64(SERIES_MAX) && x >= T::zero() {
        let c = |v: f64| T::from_f64(v);
        x * (T::one() - x * (T::one() - x * (c(1.5) - x * (c(8.0 / 3.0) - x * c(125.0 / 24.0)))))
    } else {
        x.lambert_w0_fukushima()
    }
}

/// The Wright omega function ω(y) = W0(e^y) for every real y, without overflow.
///
/// ω is the solution of ω + ln ω = y. ω(−∞) = 0, ω(+∞) = +∞, NaN gives NaN.
/// For y ≤ [`Real::EXP_ARG_MAX`] it is `W0(exp(y))`; above, it starts from the asymptotic
/// expansion y − ln y + ln y / y and applies two Fritsch–Shafer–Crowley steps (fourth order);
/// on a [`Dual`](crate::Dual) the gradient is ω'(y) = ω / (1 + ω) times y's, for every y
/// ([`Real::implicit_root`]).
///
/// # Examples
/// ```
/// use hyst_core::lambert::omega;
/// assert_eq!(omega(f64::NEG_INFINITY), 0.0);
/// assert!((omega(1.0_f64) - 1.0).abs() < 1e-15); // W(e) = 1
/// let y = 1.0e6_f64;
/// let w = omega(y); // W(e^1000000), far beyond f64's range of e^y
/// assert!(((w + w.ln()) - y).abs() <= 1e-15 * y);
/// ```
#[must_use]
pub fn omega<T: Real>(y: T) -> T {
    // Derivatives (duals) from ω + ln ω − y = 0, i.e. ω' = ω / (1 + ω): neither through the
    // iterations nor through e^y (whose derivative overflows long before ω does).
    omega_value(y).implicit_root(|w| (w + w.ln() - y, T::one() + w.recip()))
}

/// ω(y) on the values (see [`omega`]).
fn omega_value<T: Real>(y: T) -> T {
    if y <= T::EXP_ARG_MAX {
        // exp(−∞) = 0 and W0(0) = 0; NaN propagates.
        return w0(y.exp());
    }
    if y == T::infinity() {
        return y;
    }
    let ln_y = y.ln();
    let mut w = y - ln_y + ln_y / y;
    for _ in 0..2 {
        w = fsc_step(w, y);
    }
    w
}

/// One Fritsch–Shafer–Crowley step for ω + ln ω = y, written so that nothing overflows for
/// large ω (the textbook form multiplies (1 + w)² terms).
#[inline]
fn fsc_step<T: Real>(w: T, y: T) -> T {
    let one = T::one();
    let r = y - w - w.ln();
    let q = one + w;
    let t = one + T::from_f64(2.0 / 3.0) * r / q;
    let num = t - r / (T::from_f64(2.0) * q * q);
    let den = t - r / (q * q);
    w * (one + (r / q) * (num / den))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn special_values() {
        assert_eq!(w0(0.0_f64), 0.0);
        assert_eq!(w0(f64::INFINITY), f64::INFINITY);
        assert!(w0(f64::NAN).is_nan());
        assert_eq!(omega(f64::NEG_INFINITY), 0.0);
        assert_eq!(omega(f64::INFINITY), f64::INFINITY);
        assert!(omega(f64::NAN).is_nan());
        assert_eq!(omega(-1000.0_f64), 0.0);
    }

    #[test]
    fn omega_is_continuous_across_the_switch() {
        for &t in &[700.0_f64, 85.0] {
            let below = omega(t);
            let above = omega(t.next_up_compat());
            assert!(
                (above - below).abs() <= 4.0 * f64::EPSILON * below,
                "{below} {above}"
            );
        }
        let below = omega(85.0_f32);
        let above = omega(85.0001_f32);
        assert!((above - below).abs() <= 1e-5 * below);
    }

    #[test]
    fn omega_satisfies_its_equation_for_huge_arguments() {
        for &y in &[701.0_f64, 1e4, 1e10, 1e20, 1e100, 1e300, f64::MAX] {
            let w = omega(y);
            assert!(w.is_finite() && w > 0.0);
            let residual = (w + w.ln() - y).abs();
            assert!(
                residual <= 4.0 * f64::EPSILON * y,
                "y = {y}: residual {residual}"
            );
        }
    }

    trait NextUp {
        fn next_up_compat(self) -> Self;
    }
    impl NextUp for f64 {
        fn next_up_compat(self) -> Self {
            f64::from_bits(self.to_bits() + 1)
        }
    }
}
