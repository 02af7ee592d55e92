//! The one error type of the core.

use core::fmt;

/// Everything that can go wrong in the core. Every variant names the offending parameter or value.
///
/// Values are carried as `f64` (exact for `f32` too) so the type does not depend on the precision.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// A parameter is outside its valid range (not finite, not positive, …).
    InvalidParameter {
        /// The parameter's name, as in the paper where it has one (`k1`, `k2`, …).
        name: &'static str,
        /// The value that was given.
        value: f64,
        /// What the value must be, e.g. "finite and > 0".
        expected: &'static str,
    },
    /// k1 times the smallest k2 is too small (below `T::MIN_POSITIVE / T::EPSILON`): k2 M* in
    /// eq. (2) would be subnormal and the output would lose its precision. The product may lie
    /// beyond the float range (1e-300 × 1e-300), so both factors are carried.
    SmallK1K2 {
        /// k1.
        k1: f64,
        /// k2 (the smallest k2 of an input-dependent law).
        k2: f64,
    },
    /// An input sample is NaN or infinite. The operator's memory is left untouched.
    NonFiniteInput {
        /// The sample.
        value: f64,
    },
    /// A finite input sample whose output is not representable: it lies beyond the float range
    /// (e.g. input −1.79e308 with k1 = 1e300 on a rising branch), or the input is a jet whose
    /// derivatives overflow. The operator's memory is left untouched.
    NonFiniteOutput {
        /// The input sample.
        input: f64,
        /// The output the operator computed (±∞ or NaN; NaN when the value is finite and a
        /// time derivative of a jet is not).
        output: f64,
    },
    /// An initial state lies outside the band |output − input| ≤ k1 where the operator is defined.
    StateOutsideBand {
        /// The operator input of the state.
        input: f64,
        /// The operator output of the state.
        output: f64,
        /// The hysteresis half-width k1.
        k1: f64,
    },
    /// A shaping function is not strictly increasing on its domain, so it has no inverse.
    NotMonotone {
        /// The shaping function, e.g. "polynomial".
        name: &'static str,
        /// A point of the domain where the slope is ≤ 0.
        at: f64,
        /// The slope there.
        slope: f64,
    },
    /// A value is outside the range of a shaping function, so its inverse does not exist.
    OutOfRange {
        /// The shaping function, e.g. "tanh".
        name: &'static str,
        /// The value to invert.
        value: f64,
        /// Lower end of the range (exclusive or inclusive as documented by the function).
        min: f64,
        /// Upper end of the range.
        max: f64,
    },
    /// A desired output that an inverse model cannot produce from its state: the operator input
    /// it needs lies beyond the bounded range of the input shaping (tanh, Langevin). Told in the
    /// model's output units: the value given and the open range of outputs the model reaches
    /// from its state (its start rule's state at a first sample).
    Unreachable {
        /// The desired output.
        value: f64,
        /// Lower end of the outputs reachable from the state (exclusive).
        min: f64,
        /// Upper end (exclusive).
        max: f64,
    },
    /// The input-dependent k2 law returned a value that is not finite and positive.
    InvalidK2 {
        /// The operator input at which the law was evaluated.
        input: f64,
        /// The value the law returned.
        k2: f64,
    },
    /// Two slices that must have the same length do not.
    LengthMismatch {
        /// Length of the input slice.
        input: usize,
        /// Length of the output slice.
        output: usize,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::InvalidParameter {
                name,
                value,
                expected,
            } => write!(
                f,
                "invalid parameter {name} = {}: must be {expected}",
                Num(value)
            ),
            Error::SmallK1K2 { k1, k2 } => write!(
                f,
                "invalid parameters k1 = {} and k2 = {}: their product k1·k2 = {} is below \
                 2.0e-292 for f64 (9.9e-32 for f32), where k2 M* turns subnormal and the output \
                 loses its precision; express the input in other units",
                Num(k1),
                Num(k2),
                Product(k1, k2)
            ),
            Error::NonFiniteInput { value } => {
                write!(f, "input sample {} is not finite", Num(value))
            }
            Error::NonFiniteOutput { input, output } => write!(
                f,
                "input sample {}: the output or one of its time derivatives is beyond the \
                 float range ({})",
                Num(input),
                Num(output)
            ),
            Error::StateOutsideBand { input, output, k1 } => write!(
                f,
                "state (input {}, output {}) is outside the band |output - input| <= k1 = {}",
                Num(input),
                Num(output),
                Num(k1)
            ),
            Error::NotMonotone { name, at, slope } => write!(
                f,
                "{name} shaping function is not strictly increasing: slope {} at {}",
                Num(slope),
                Num(at)
            ),
            Error::OutOfRange {
                name,
                value,
                min,
                max,
            } => write!(
                f,
                "{} is outside the range ({}, {}) of the {name} shaping function",
                Num(value),
                Num(min),
                Num(max)
            ),
            Error::Unreachable { value, min, max } => write!(
                f,
                "desired output {} is outside the range ({}, {}) of outputs the model can reach \
                 from its state (its input shaping's range is bounded)",
                Num(value),
                Sig7(min),
                Sig7(max)
            ),
            Error::InvalidK2 { input, k2 } => write!(
                f,
                "the k2 law gave k2 = {} at input {}: must be finite and > 0",
                Num(k2),
                Num(input)
            ),
            Error::LengthMismatch { input, output } => write!(
                f,
                "input has {input} samples but the output buffer has {output}"
            ),
        }
    }
}

/// A number in an error message: as `{}` prints it (shortest round trip) for magnitudes in
/// [1e-5, 1e16) and zero, in exponent form (`1e-320`, `1e300`) otherwise, so that extreme
/// values stay readable.
struct Num(f64);

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let a = self.0.abs();
        if a == 0.0 || (1e-5..1e16).contains(&a) || !a.is_finite() {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

/// A computed number in an error message (the ends of a range): 7 significant digits, fixed
/// for magnitudes in [1e-3, 1e6), in exponent form otherwise (as `hyst_io::number::sig`).
struct Sig7(f64);

impl fmt::Display for Sig7 {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.0;
        if !x.is_finite() || x == 0.0 {
            return write!(f, "{x}");
        }
        let magnitude = libm::floor(libm::log10(x.abs()));
        if (-3.0..6.0).contains(&magnitude) {
            // 1 to 9 decimals (magnitude is an integer in [−3, 5]).
            let decimals = (6.0 - magnitude) as usize;
            // Rounding may carry into a new digit (9.9999996 → 10.000000): one decimal fewer.
            let scaled = libm::round(libm::fabs(x) * libm::pow(10.0, 6.0 - magnitude));
            let decimals = if scaled >= 1e7 {
                decimals - 1
            } else {
                decimals
            };
            write!(f, "{x:.decimals$}")
        } else {
            write!(f, "{x:.6e}")
        }
    }
}

/// The product of two positive numbers in an error message, even where it lies beyond the
/// float range (1e-300 × 1e-300 = "1e-600"): a mantissa of 4 significant digits (trailing
/// zeros dropped) and a decimal exponent.
struct Product(f64, f64);

impl fmt::Display for Product {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (a, b) = (self.0, self.1);
        if !(a.is_normal() && b.is_normal()) {
            return write!(f, "{}", Num(a * b));
        }
        // Each factor as m · 10^e with m in [1, 10), then the product of the mantissas.
        let split = |x: f64| {
            let e = libm::floor(libm::log10(x.abs()));
            (x / libm::pow(10.0, e), e)
        };
        let (ma, ea) = split(a);
        let (mb, eb) = split(b);
        let (mut m, mut e) = (ma * mb, ea + eb);
        while m.abs() >= 10.0 {
            m /= 10.0;
            e += 1.0;
        }
        while m.abs() < 1.0 {
            m *= 10.0;
            e -= 1.0;
        }
        // 4 significant digits; the rounding may carry into a new digit (9.9996 → 10).
        let mut m = libm::round(m * 1000.0) / 1000.0;
        if m.abs() >= 10.0 {
            m /= 10.0;
            e += 1.0;
        }
        write!(f, "{m}e{e}")
    }
}

impl core::error::Error for Error {}

/// Checks that `value` is finite and strictly positive, naming it in the error otherwise.
pub(crate) fn positive<T: crate::real::Real>(name: &'static str, value: T) -> Result<T, Error> {
    if value.is_finite() && value > T::zero() {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            name,
            value: value.as_f64(),
            expected: "finite and > 0",
        })
    }
}

/// Checks that `value` is a normal (not subnormal), finite and strictly positive float, naming
/// it in the error otherwise. Subnormal values carry fewer significant bits: a subnormal k2 gives
/// outputs off by 1e-4 relative, so the operator's parameters must be normal.
pub(crate) fn positive_normal<T: crate::real::Real>(
    name: &'static str,
    value: T,
) -> Result<T, Error> {
    if value.is_normal() && value > T::zero() {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            name,
            value: value.as_f64(),
            expected: "finite and > 0, a normal float (>= 2.2e-308 for f64, >= 1.2e-38 for f32; \
                       subnormal values lose precision)",
        })
    }
}

/// Checks that `value` is finite, naming it in the error otherwise.
pub(crate) fn finite<T: crate::real::Real>(name: &'static str, value: T) -> Result<T, Error> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            name,
            value: value.as_f64(),
            expected: "finite",
        })
    }
}
