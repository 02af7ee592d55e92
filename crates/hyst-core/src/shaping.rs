//! Shaping functions (Section 4.3): smooth, strictly increasing, invertible maps applied to the
//! input or output of the operator, so the affine asymptotes of H can follow curved boundaries.
//!
//! Every shaping function has a domain [lo, hi] on which its formula is used and strictly
//! increasing (checked when it is built). Outside, it continues along its tangent at the end
//! point, so a shaped model stays monotone and exactly invertible on the whole real line. With an
//! infinite domain and a bounded range (tanh, Langevin), values outside the range have no inverse
//! and [`Shaping::invert`] says so.

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use crate::error::{finite, positive_normal, Error};
use crate::jet::Jet;
use crate::real::Real;
use crate::sample::Sample;

/// A smooth, strictly increasing shaping function ψ with its inverse.
///
/// Implementors provide the formula [`Shaping::eval`] (generic over [`Sample`], so it works on
/// jets) and its domain; the provided methods add the tangent extension, the inverse (closed form
/// where the implementor gives one, otherwise safeguarded Newton) and the inverse on jets.
pub trait Shaping<T: Real> {
    /// A short name for messages ("affine", "tanh", …).
    fn name(&self) -> &'static str;

    /// ψ(x) by its formula (valid on [`Shaping::domain`]).
    fn eval<S: Sample<T>>(&self, x: S) -> S;

    /// The interval on which the formula holds and is strictly increasing (ends may be infinite).
    fn domain(&self) -> (T, T) {
        (T::neg_infinity(), T::infinity())
    }

    /// ψ⁻¹(y) for y in ψ(domain). The default is safeguarded Newton on the domain.
    ///
    /// # Errors
    /// [`Error::OutOfRange`] when y is not a value of ψ on its domain.
    fn invert_in_domain(&self, y: T) -> Result<T, Error> {
        let (lo, hi) = self.domain();
        solve_increasing(|x| self.value_and_slope(x), y, lo, hi, self.name())
    }

    /// Checks the parameters and strict monotonicity on the domain.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] or [`Error::NotMonotone`].
    fn validate(&self) -> Result<(), Error> {
        Ok(())
    }

    /// ψ and ψ' at a point of the domain.
    fn value_and_slope(&self, x: T) -> (T, T) {
        let j = self.eval(Jet::<T, 1>::variable(x));
        (
            j.value(),
            j.taylor().first().copied().unwrap_or_else(T::zero),
        )
    }

    /// ψ(x) and ψ'(x) on the whole line (as [`Shaping::apply`]): what a chain rule through ψ
    /// needs (the adaptive estimator's, [`crate::adaptive`]). The value is `apply`'s, bit for
    /// bit.
    fn apply_with_slope(&self, x: T) -> (T, T) {
        let slope = self
            .apply(Jet::<T, 1>::variable(x))
            .taylor()
            .first()
            .copied()
            .unwrap_or_else(T::zero);
        (self.apply(x), slope)
    }

    /// ψ(x) on the whole line: the formula on the domain, the tangent beyond its ends.
    fn apply<S: Sample<T>>(&self, x: S) -> S {
        let (lo, hi) = self.domain();
        let v = x.value();
        if v < lo {
            let (y0, s0) = self.value_and_slope(lo);
            (x - lo) * s0 + y0
        } else if v > hi {
            let (y0, s0) = self.value_and_slope(hi);
            (x - hi) * s0 + y0
        } else {
            self.eval(x)
        }
    }

    /// dψ/dx at x (on the whole line).
    fn slope(&self, x: T) -> T {
        let j = self.apply(Jet::<T, 1>::variable(x));
        j.taylor().first().copied().unwrap_or_else(T::zero)
    }

    /// ψ⁻¹(y) on the whole line (the inverse of [`Shaping::apply`]).
    ///
    /// # Errors
    /// [`Error::NonFiniteInput`] for a non-finite y; [`Error::OutOfRange`] when y is outside
    /// the range of ψ.
    fn invert(&self, y: T) -> Result<T, Error> {
        if !y.is_finite() {
            return Err(Error::NonFiniteInput { value: y.as_f64() });
        }
        let (lo, hi) = self.domain();
        if lo.is_finite() {
            let (y0, s0) = self.value_and_slope(lo);
            if y < y0 {
                return Ok(lo + (y - y0) / s0);
            }
        }
        if hi.is_finite() {
            let (y0, s0) = self.value_and_slope(hi);
            if y > y0 {
                return Ok(hi + (y - y0) / s0);
            }
        }
        self.invert_in_domain(y)
    }

    /// ψ⁻¹ on a jet: the value by [`Shaping::invert`], the derivatives by Newton's method on jets
    /// with the slope at the solution (one order per step).
    ///
    /// # Errors
    /// As [`Shaping::invert`].
    fn invert_sample<S: Sample<T>>(&self, y: S) -> Result<S, Error> {
        let x0 = self.invert(y.value())?;
        let slope = self.slope(x0);
        let mut x = S::constant(x0);
        for _ in 0..S::ORDER {
            x = (x - (self.apply(x) - y) / slope).with_value(x0);
        }
        Ok(x)
    }

    /// An upper bound of ψ' on [lo, hi] (the Lipschitz constant that scales an error bound
    /// through an output shaping function). The default samples 2049 points.
    fn lipschitz(&self, lo: T, hi: T) -> T {
        const POINTS: usize = 2049;
        (0..POINTS)
            .map(|i| self.slope(lo + (hi - lo) * T::from_f64(i as f64 / (POINTS - 1) as f64)))
            .fold(T::zero(), T::max)
    }
}

/// Solves f(x) = y for a strictly increasing f on [lo, hi] (ends may be infinite) by Newton's
/// method, safeguarded by bisection on a bracket, to full precision. On a
/// [`Dual`](crate::Dual) the root's gradient is −(∂f/∂p − ∂y/∂p) / f'(x)
/// ([`Real::implicit_root`]).
///
/// # Errors
/// [`Error::OutOfRange`] when no bracket contains y.
pub fn solve_increasing<T: Real>(
    f: impl Fn(T) -> (T, T),
    y: T,
    lo: T,
    hi: T,
    name: &'static str,
) -> Result<T, Error> {
    // Derivatives (duals) from f(x) − y = 0 at the root, not through the iterations.
    bracketed_root(&f, y, lo, hi, name).map(|x| {
        x.implicit_root(|x| {
            let (fx, slope) = f(x);
            (fx - y, slope)
        })
    })
}

/// The iteration of [`solve_increasing`] on the values.
fn bracketed_root<T: Real>(
    f: &impl Fn(T) -> (T, T),
    y: T,
    lo: T,
    hi: T,
    name: &'static str,
) -> Result<T, Error> {
    let out_of_range = || {
        let at = |x: T| {
            if x.is_finite() {
                f(x).0.as_f64()
            } else {
                x.as_f64()
            }
        };
        Error::OutOfRange {
            name,
            value: y.as_f64(),
            min: at(lo),
            max: at(hi),
        }
    };
    // Finite bracket [a, b] with f(a) ≤ y ≤ f(b), expanding geometrically into infinite ends.
    let start = if lo.is_finite() && hi.is_finite() {
        (lo + hi) / T::from_f64(2.0)
    } else if lo.is_finite() {
        lo
    } else if hi.is_finite() {
        hi
    } else {
        T::zero()
    };
    let (mut a, mut b) = (start, start);
    let mut step = T::one();
    let mut fa = f(a).0;
    while fa.is_nan() || fa > y {
        if a <= lo || !step.is_finite() {
            return Err(out_of_range());
        }
        a = (a - step).max(lo);
        step = step + step;
        fa = f(a).0;
    }
    step = T::one();
    let mut fb = f(b).0;
    while fb.is_nan() || fb < y {
        if b >= hi || !step.is_finite() {
            return Err(out_of_range());
        }
        b = (b + step).min(hi);
        step = step + step;
        fb = f(b).0;
    }
    if !fa.is_finite() || !fb.is_finite() {
        return Err(out_of_range());
    }
    // Safeguarded Newton inside [a, b].
    let mut x = if fb > fa {
        a + (b - a) * ((y - fa) / (fb - fa))
    } else {
        a
    };
    for _ in 0..200 {
        let (fx, dfx) = f(x);
        let r = fx - y;
        if r == T::zero() {
            return Ok(x);
        }
        if r < T::zero() {
            a = x;
        } else {
            b = x;
        }
        let newton = x - r / dfx;
        let next = if newton > a && newton < b && newton.is_finite() {
            newton
        } else {
            a + (b - a) / T::from_f64(2.0)
        };
        if (next - x).abs() <= T::epsilon() * x.abs()
            || b - a <= T::epsilon() * a.abs().max(b.abs())
        {
            return Ok(next);
        }
        x = next;
    }
    Ok(x)
}

/// The identity ψ(x) = x.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Identity;

impl<T: Real> Shaping<T> for Identity {
    fn name(&self) -> &'static str {
        "identity"
    }
    #[inline]
    fn eval<S: Sample<T>>(&self, x: S) -> S {
        x
    }
    fn invert_in_domain(&self, y: T) -> Result<T, Error> {
        Ok(y)
    }
    #[inline]
    fn apply<S: Sample<T>>(&self, x: S) -> S {
        x
    }
    fn invert_sample<S: Sample<T>>(&self, y: S) -> Result<S, Error> {
        Ok(y)
    }
}

/// Affine ψ(x) = gain · x + offset, gain finite, > 0 and a normal float (Example 1: ψ_in = 0.2 in,
/// ψ_out = 1.4 out).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Affine<T> {
    /// Slope, > 0 (output units per input unit).
    pub gain: T,
    /// Value at 0 (output units).
    pub offset: T,
}

impl<T: Real> Affine<T> {
    /// Builds and validates ψ(x) = gain · x + offset.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] unless gain is finite, > 0 and a normal float (not
    /// subnormal: the inverse divides by it) and offset finite.
    pub fn new(gain: T, offset: T) -> Result<Self, Error> {
        let s = Self { gain, offset };
        s.validate()?;
        Ok(s)
    }
}

impl<T: Real> Shaping<T> for Affine<T> {
    fn name(&self) -> &'static str {
        "affine"
    }
    #[inline]
    fn eval<S: Sample<T>>(&self, x: S) -> S {
        x * self.gain + self.offset
    }
    fn invert_in_domain(&self, y: T) -> Result<T, Error> {
        Ok((y - self.offset) / self.gain)
    }
    fn validate(&self) -> Result<(), Error> {
        positive_normal("affine gain", self.gain)?;
        finite("affine offset", self.offset).map(|_| ())
    }
    fn lipschitz(&self, _lo: T, _hi: T) -> T {
        self.gain
    }
}

/// Polynomial ψ(x) = c0 + c1 x + c2 x² + c3 x³ on a domain [lo, hi] where it is strictly
/// increasing (checked exactly: ψ' is a quadratic), continued by tangents outside
/// (Example 1: ψ_in(in) = in − 0.098 in², increasing for in < 5.1).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Polynomial<T> {
    /// Coefficients c0..c3 (use 0 for unused higher terms).
    pub coefficients: [T; 4],
    /// Lower end of the domain (may be −∞ if ψ' > 0 there).
    pub lo: T,
    /// Upper end of the domain (may be +∞ if ψ' > 0 there).
    pub hi: T,
}

impl<T: Real> Polynomial<T> {
    /// Builds and validates the polynomial on [lo, hi].
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for non-finite coefficients or lo ≥ hi;
    /// [`Error::NotMonotone`] when ψ' ≤ 0 somewhere on [lo, hi].
    pub fn new(coefficients: [T; 4], lo: T, hi: T) -> Result<Self, Error> {
        let s = Self {
            coefficients,
            lo,
            hi,
        };
        s.validate()?;
        Ok(s)
    }

    fn derivative(&self, x: T) -> T {
        let [_, c1, c2, c3] = self.coefficients;
        c1 + x * (T::from_f64(2.0) * c2 + x * T::from_f64(3.0) * c3)
    }
}

impl<T: Real> Shaping<T> for Polynomial<T> {
    fn name(&self) -> &'static str {
        "polynomial"
    }
    #[inline]
    fn eval<S: Sample<T>>(&self, x: S) -> S {
        let [c0, c1, c2, c3] = self.coefficients;
        ((x * c3 + c2) * x + c1) * x + c0
    }
    fn domain(&self) -> (T, T) {
        (self.lo, self.hi)
    }
    fn validate(&self) -> Result<(), Error> {
        for c in self.coefficients {
            finite("polynomial coefficient", c)?;
        }
        if self.lo.is_nan() || self.hi.is_nan() || self.lo >= self.hi {
            return Err(Error::InvalidParameter {
                name: "polynomial domain",
                value: self.hi.as_f64(),
                expected: "an upper end greater than the lower end",
            });
        }
        let [_, c1, c2, c3] = self.coefficients;
        let not_monotone = |at: T| Error::NotMonotone {
            name: "polynomial",
            at: at.as_f64(),
            slope: if at.is_finite() {
                self.derivative(at).as_f64()
            } else {
                f64::NEG_INFINITY
            },
        };
        // The minimum of the quadratic ψ' on [lo, hi]: at an end, or at its vertex.
        for end in [self.lo, self.hi] {
            if end.is_finite() {
                if self.derivative(end) <= T::zero() {
                    return Err(not_monotone(end));
                }
            } else {
                let leading_ok = if c3 != T::zero() {
                    c3 > T::zero()
                } else if c2 != T::zero() {
                    (c2 > T::zero()) == (end > T::zero())
                } else {
                    c1 > T::zero()
                };
                if !leading_ok {
                    return Err(not_monotone(end));
                }
            }
        }
        if c3 > T::zero() {
            let vertex = -c2 / (T::from_f64(3.0) * c3);
            if vertex > self.lo && vertex < self.hi && self.derivative(vertex) <= T::zero() {
                return Err(not_monotone(vertex));
            }
        }
        Ok(())
    }
}

/// ψ(x) = gain · tanh(x / scale): a saturating boundary. gain, scale finite, > 0 and normal
/// floats (not subnormal: the function and its inverse divide by them). Its range
/// is (−gain, gain).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Tanh<T> {
    /// Saturation level (output units).
    pub gain: T,
    /// Input scale (input units): slope at 0 is gain / scale.
    pub scale: T,
}

impl<T: Real> Tanh<T> {
    /// Builds and validates the tanh shaping.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] unless gain and scale are finite, > 0 and normal floats.
    pub fn new(gain: T, scale: T) -> Result<Self, Error> {
        let s = Self { gain, scale };
        s.validate()?;
        Ok(s)
    }
}

/// tanh written through e^(−2|x|) − 1, so jets never overflow: one transcendental
/// (tanh |x| = −(e^m − 1) / ((e^m − 1) + 2), m = −2|x|).
fn tanh_scalar<T: Real, S: Sample<T>>(x: S) -> S {
    let ax = x.abs();
    let m = ax * T::from_f64(-2.0);
    let e = m.exp_m1();
    let t = -e / (e + T::from_f64(2.0));
    if x.value() < T::zero() {
        -t
    } else {
        t
    }
}

impl<T: Real> Shaping<T> for Tanh<T> {
    fn name(&self) -> &'static str {
        "tanh"
    }
    fn eval<S: Sample<T>>(&self, x: S) -> S {
        tanh_scalar(x / self.scale) * self.gain
    }
    fn invert_in_domain(&self, y: T) -> Result<T, Error> {
        let t = y / self.gain;
        if t.abs() >= T::one() {
            return Err(Error::OutOfRange {
                name: "tanh",
                value: y.as_f64(),
                min: -self.gain.as_f64(),
                max: self.gain.as_f64(),
            });
        }
        // atanh t = ½ ln((1 + t)/(1 − t)) = ½ ln1p(2t / (1 − t))
        Ok(self.scale * T::from_f64(0.5) * (T::from_f64(2.0) * t / (T::one() - t)).ln_1p())
    }
    fn validate(&self) -> Result<(), Error> {
        positive_normal("tanh gain", self.gain)?;
        positive_normal("tanh scale", self.scale).map(|_| ())
    }
    fn lipschitz(&self, lo: T, hi: T) -> T {
        if lo <= T::zero() && hi >= T::zero() {
            self.gain / self.scale
        } else {
            self.slope(if lo > T::zero() { lo } else { hi })
        }
    }
}

/// Taylor coefficients of the Langevin function, L(x) = Σ_{n≥1} c_n x^(2n−1),
/// c_n = 2^(2n) B_(2n) / (2n)! (B: Bernoulli numbers; computed with mpmath, see
/// `tests/data/langevin_series.txt`). 20 terms reach full f64 precision for |x| < 1.
const LANGEVIN_SERIES: [f64; 20] = [
    0.333_333_333_333_333_3,
    -0.022_222_222_222_222_223,
    0.002_116_402_116_402_116_5,
    -0.000_211_640_211_640_211_65,
    2.137_779_915_557_693_5e-5,
    -2.164_404_280_806_397_2e-6,
    2.192_594_785_187_377_8e-7,
    -2.221_460_878_997_967_8e-8,
    2.250_784_651_680_899_4e-9,
    -2.280_515_120_459_218_3e-10,
    2.310_643_259_900_262_4e-11,
    -2.341_170_681_982_488_2e-12,
    2.372_101_740_023_365_3e-13,
    -2.403_441_533_330_770_5e-14,
    2.435_195_402_918_336_7e-15,
    -2.467_368_804_517_207_5e-16,
    2.499_967_277_122_081e-17,
    -2.532_996_435_740_635e-18,
    2.566_461_970_282_629e-19,
    -2.600_369_646_013_727_4e-20,
];

/// The Langevin function L(x) = coth x − 1/x on plain values or jets: its series for |x| < 1
/// (no cancellation near 0), coth through exp(−2|x|) beyond.
pub fn langevin_scalar<T: Real, S: Sample<T>>(x: S) -> S {
    let v = x.value();
    if v.abs() < T::one() {
        let x2 = x * x;
        let mut acc = S::constant(T::zero());
        for c in LANGEVIN_SERIES.iter().rev() {
            acc = acc * x2 + T::from_f64(*c);
        }
        acc * x
    } else {
        // coth |x| = ((e^m − 1) + 2) / −(e^m − 1), m = −2|x|: one transcendental.
        let e = (x.abs() * T::from_f64(-2.0)).exp_m1();
        let coth = (e + T::from_f64(2.0)) / (-e);
        let coth = if v < T::zero() { -coth } else { coth };
        coth - S::constant(T::one()) / x
    }
}

/// The Langevin function L(x) = coth x − 1/x (L(0) = 0), the classical anhysteretic curve of
/// magnetic materials. Relative error ≤ 4e-15 for f64.
///
/// # Examples
/// ```
/// use hyst_core::shaping::langevin;
/// assert_eq!(langevin(0.0_f64), 0.0);
/// assert!((langevin(1e-8_f64) - 1e-8 / 3.0).abs() < 1e-24);
/// assert!((langevin(2.0_f64) - (1.0 / 2.0_f64.tanh() - 0.5)).abs() < 1e-15);
/// ```
#[must_use]
pub fn langevin<T: Real>(x: T) -> T {
    langevin_scalar::<T, T>(x)
}

/// ψ(x) = gain · L(x / scale), with L the [Langevin function](langevin); slope gain/(3 scale)
/// at 0, range (−gain, gain).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Langevin<T> {
    /// Saturation level (output units).
    pub gain: T,
    /// Input scale (input units).
    pub scale: T,
}

impl<T: Real> Langevin<T> {
    /// Builds and validates the Langevin shaping.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] unless gain and scale are finite, > 0 and normal floats.
    pub fn new(gain: T, scale: T) -> Result<Self, Error> {
        let s = Self { gain, scale };
        s.validate()?;
        Ok(s)
    }
}

impl<T: Real> Shaping<T> for Langevin<T> {
    fn name(&self) -> &'static str {
        "langevin"
    }
    fn eval<S: Sample<T>>(&self, x: S) -> S {
        langevin_scalar(x / self.scale) * self.gain
    }
    fn invert_in_domain(&self, y: T) -> Result<T, Error> {
        if (y / self.gain).abs() >= T::one() {
            return Err(Error::OutOfRange {
                name: "langevin",
                value: y.as_f64(),
                min: -self.gain.as_f64(),
                max: self.gain.as_f64(),
            });
        }
        solve_increasing(
            |x| self.value_and_slope(x),
            y,
            T::neg_infinity(),
            T::infinity(),
            "langevin",
        )
    }
    fn validate(&self) -> Result<(), Error> {
        positive_normal("langevin gain", self.gain)?;
        positive_normal("langevin scale", self.scale).map(|_| ())
    }
    fn lipschitz(&self, lo: T, hi: T) -> T {
        if lo <= T::zero() && hi >= T::zero() {
            self.gain / (T::from_f64(3.0) * self.scale)
        } else {
            self.slope(if lo > T::zero() { lo } else { hi })
        }
    }
}

/// Example 2's shaping ψ(v) = v − a v² − e^(−(b + c v)) on a domain [lo, hi] where it is
/// strictly increasing (a ≥ 0, c ≥ 0 make ψ' decreasing, so ψ'(hi) > 0 is the check).
/// Example 2 uses a = 0.088, b = 9.6, c = 6.6: see [`QuadraticExp::example2`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct QuadraticExp<T> {
    /// Quadratic coefficient a ≥ 0.
    pub a: T,
    /// Exponential offset b.
    pub b: T,
    /// Exponential rate c ≥ 0.
    pub c: T,
    /// Lower end of the domain (finite).
    pub lo: T,
    /// Upper end of the domain (finite), where ψ' must still be > 0.
    pub hi: T,
}

impl<T: Real> QuadraticExp<T> {
    /// Builds and validates the shaping.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] or [`Error::NotMonotone`].
    pub fn new(a: T, b: T, c: T, lo: T, hi: T) -> Result<Self, Error> {
        let s = Self { a, b, c, lo, hi };
        s.validate()?;
        Ok(s)
    }

    /// Example 2's ψ(v) = v − 0.088 v² − e^(−(9.6 + 6.6 v)) on [−1, 5].
    ///
    /// # Errors
    /// As [`QuadraticExp::new`]; these constants pass its checks (a unit test pins that).
    pub fn example2() -> Result<Self, Error> {
        Self::new(
            T::from_f64(0.088),
            T::from_f64(9.6),
            T::from_f64(6.6),
            T::from_f64(-1.0),
            T::from_f64(5.0),
        )
    }
}

impl<T: Real> Shaping<T> for QuadraticExp<T> {
    fn name(&self) -> &'static str {
        "quadratic-exp"
    }
    fn eval<S: Sample<T>>(&self, x: S) -> S {
        x - x * x * self.a - (-(x * self.c + self.b)).exp()
    }
    fn domain(&self) -> (T, T) {
        (self.lo, self.hi)
    }
    fn validate(&self) -> Result<(), Error> {
        let a = finite("quadratic-exp a", self.a)?;
        finite("quadratic-exp b", self.b)?;
        let c = finite("quadratic-exp c", self.c)?;
        finite("quadratic-exp lo", self.lo)?;
        finite("quadratic-exp hi", self.hi)?;
        if a < T::zero() || c < T::zero() {
            return Err(Error::InvalidParameter {
                name: if a < T::zero() {
                    "quadratic-exp a"
                } else {
                    "quadratic-exp c"
                },
                value: a.min(c).as_f64(),
                expected: ">= 0",
            });
        }
        if self.lo >= self.hi {
            return Err(Error::InvalidParameter {
                name: "quadratic-exp hi",
                value: self.hi.as_f64(),
                expected: "greater than lo",
            });
        }
        let slope = self.value_and_slope(self.hi).1;
        if slope.is_nan() || slope <= T::zero() {
            return Err(Error::NotMonotone {
                name: "quadratic-exp",
                at: self.hi.as_f64(),
                slope: slope.as_f64(),
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::any_shaping::AnyShaping;

    fn round_trip<S: Shaping<f64>>(s: &S, xs: &[f64]) {
        for &x in xs {
            let y = s.apply(x);
            let back = s.invert(y).unwrap_or(f64::NAN);
            // forward error, or backward error where ψ is ill-conditioned (saturation)
            let forward = (back - x).abs() <= 1e-12 * x.abs().max(1.0);
            let backward = (s.apply(back) - y).abs() <= 4.0 * f64::EPSILON * y.abs().max(1.0);
            assert!(forward || backward, "{}: x {x} -> {y} -> {back}", s.name());
        }
    }

    const XS: [f64; 11] = [
        -50.0, -7.0, -1.5, -0.3, -1e-9, 0.0, 1e-7, 0.4, 1.9, 6.0, 40.0,
    ];

    /// The one-transcendental forms of tanh and coth against the standard library's tanh.
    #[test]
    fn tanh_and_langevin_are_accurate() {
        for k in -4000..=4000 {
            let x = f64::from(k) * 0.005;
            let t = tanh_scalar::<f64, f64>(x);
            assert!(
                (t - x.tanh()).abs() <= 4.0 * f64::EPSILON * x.tanh().abs(),
                "tanh {x}"
            );
            if x.abs() >= 1.0 {
                let l = langevin(x);
                let reference = 1.0 / x.tanh() - 1.0 / x;
                assert!(
                    (l - reference).abs() <= 8.0 * f64::EPSILON * l.abs(),
                    "L {x}"
                );
            }
        }
    }

    #[test]
    fn built_ins_invert_exactly() -> Result<(), Error> {
        round_trip(&Affine::new(2.02, 0.1)?, &XS);
        round_trip(&Polynomial::new([0.0, 1.0, -0.098, 0.0], -1e9, 5.0)?, &XS);
        round_trip(
            &Polynomial::new([0.1, 1.0, 0.0, 0.5], f64::NEG_INFINITY, f64::INFINITY)?,
            &XS,
        );
        round_trip(&Tanh::new(2.0, 3.0)?, &[-20.0, -1.0, 0.0, 0.3, 5.0, 20.0]);
        round_trip(
            &Langevin::new(1.5, 0.7)?,
            &[-9.0, -1.0, -0.2, 0.0, 0.5, 0.69, 0.71, 3.0, 9.0],
        );
        round_trip(&QuadraticExp::example2()?, &XS);
        round_trip(&AnyShaping::Tanh(Tanh::new(1.0, 1.0)?), &[-2.0, 0.0, 2.0]);
        Ok(())
    }

    #[test]
    fn non_monotone_polynomials_are_refused() {
        // in − 0.098 in² turns at in = 5.10
        assert!(matches!(
            Polynomial::new([0.0, 1.0, -0.098, 0.0], 0.0, 6.0),
            Err(Error::NotMonotone { .. })
        ));
        assert!(Polynomial::new([0.0, 1.0, -0.098, 0.0], 0.0, f64::INFINITY).is_err());
        // x³ − x: slope −1 at 0
        assert!(Polynomial::new([0.0, -1.0, 0.0, 1.0], -1.0, 1.0).is_err());
        // x³ + x is monotone everywhere
        assert!(Polynomial::new([0.0, 1.0, 0.0, 1.0], f64::NEG_INFINITY, f64::INFINITY).is_ok());
        assert!(QuadraticExp::new(0.088, 9.6, 6.6, -1.0, 6.0).is_err());
    }

    #[test]
    fn saturating_shapes_report_their_range() -> Result<(), Error> {
        let t = Tanh::new(2.0, 1.0)?;
        assert_eq!(
            t.invert(2.0),
            Err(Error::OutOfRange {
                name: "tanh",
                value: 2.0,
                min: -2.0,
                max: 2.0
            })
        );
        assert!(matches!(
            t.invert(f64::NAN),
            Err(Error::NonFiniteInput { .. })
        ));
        // Just inside the range the inverse exists and round-trips.
        let x = t.invert(1.999)?;
        assert!((t.apply(x) - 1.999).abs() < 1e-12, "{x}");
        let l = Langevin::new(1.0, 1.0)?;
        assert_eq!(
            l.invert(-1.0),
            Err(Error::OutOfRange {
                name: "langevin",
                value: -1.0,
                min: -1.0,
                max: 1.0
            })
        );
        assert!(Tanh::new(0.0, 1.0).is_err() && Langevin::new(1.0, f64::NAN).is_err());
        Ok(())
    }

    #[test]
    fn tangent_extension_is_c1() -> Result<(), Error> {
        let p = Polynomial::new([0.0, 1.0, -0.098, 0.0], -2.0, 5.0)?;
        let h = 1e-7;
        for end in [-2.0, 5.0] {
            let left = p.slope(end - h);
            let right = p.slope(end + h);
            assert!((left - right).abs() < 1e-6);
            assert!((p.apply(end - h) - p.apply(end + h)).abs() < 2.0 * h * (left.abs() + 1e-3));
        }
        Ok(())
    }

    #[test]
    fn inverse_on_jets_matches_derivatives() -> Result<(), Error> {
        let s = QuadraticExp::example2()?;
        let x = Jet::<f64, 3>::from_derivatives(0.3, [0.7, -0.2, 1.1]);
        let y = s.apply(x);
        let back = s.invert_sample(y)?;
        for (a, b) in x.derivatives().iter().zip(back.derivatives().iter()) {
            assert!((a - b).abs() < 1e-12, "{a} {b}");
        }
        Ok(())
    }
}
