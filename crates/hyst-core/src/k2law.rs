//! The transition-rate parameter k2: constant, or a function of the operator input (Section 4.3).
//!
//! With k2 = φ(v) the direct operator uses φ of its input v, and the inverse uses φ of its input
//! u_d (Proposition 4.3): the pair is then inverse only up to a parameter deviation
//! Δk2 ≤ sup |φ'| k1, which [`K2Law::max_slope`] provides for the error bound.

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use crate::error::{positive_normal, Error};
use crate::jet::Jet;
use crate::real::Real;
use crate::sample::Sample;

/// How k2 depends on the operator's input. Implement it for any smooth function: write `k2`
/// generically over [`Sample`] and the operator gets its time derivatives for free.
pub trait K2Law<T: Real> {
    /// True when [`K2Law::k2`] is finite and > 0 for every finite input once
    /// [`K2Law::validate`] has passed, so the operator may skip its per-sample check. Leave it
    /// `false` (the default) for laws that can return an invalid k2.
    const ALWAYS_VALID: bool = false;

    /// True when [`K2Law::k2`] may be called with any input, NaN and ±∞ included (it returns
    /// some value and never panics). With [`K2Law::ALWAYS_VALID`], the operator then tests a
    /// plain sample for finiteness only after the formula, on its rare path (its band test
    /// fails for every non-finite input), instead of before it. Leave it `false` (the default)
    /// unless the law is total.
    const ANY_INPUT: bool = false;

    /// k2 at the operator input `input` (a plain value or a jet). Must be finite and > 0.
    fn k2<S: Sample<T>>(&self, input: S) -> S;

    /// Checks the law's own parameters (called when an operator is built).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the bad parameter.
    fn validate(&self) -> Result<(), Error>;

    /// The smallest k2 the law can give over all inputs, if known (1 / input units). The
    /// operator's constructor checks k1 · k2 against it (see
    /// [`ParametricHysteresis::with_k2_law`](crate::ParametricHysteresis::with_k2_law)). The
    /// default, `None`, skips that check.
    fn min_k2(&self) -> Option<T> {
        None
    }

    /// (min, max) of k2 over inputs in [lo, hi]. The default samples 1025 points.
    fn range(&self, lo: T, hi: T) -> (T, T) {
        let mut min = T::infinity();
        let mut max = T::neg_infinity();
        for x in grid(lo, hi) {
            let k = self.k2(x);
            min = min.min(k);
            max = max.max(k);
        }
        (min, max)
    }

    /// sup |dφ/dv| over [lo, hi] (Proposition 4.3). The default samples 1025 points with jets.
    fn max_slope(&self, lo: T, hi: T) -> T {
        grid(lo, hi)
            .map(|x| {
                let d = self.k2(Jet::<T, 1>::variable(x)).derivatives();
                d.first().map_or(T::zero(), |s| s.abs())
            })
            .fold(T::zero(), T::max)
    }
}

fn grid<T: Real>(lo: T, hi: T) -> impl Iterator<Item = T> {
    const POINTS: usize = 1025;
    (0..POINTS).map(move |i| lo + (hi - lo) * T::from_f64(i as f64 / (POINTS - 1) as f64))
}

/// A constant k2 (Definition 2.2): the rate of the smooth transition towards the asymptotes,
/// in 1 / (units of the operator input). Finite and > 0.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct ConstantK2<T>(pub T);

impl<T: Real> K2Law<T> for ConstantK2<T> {
    const ALWAYS_VALID: bool = true;
    const ANY_INPUT: bool = true;
    #[inline]
    fn k2<S: Sample<T>>(&self, _input: S) -> S {
        S::constant(self.0)
    }
    /// k2 must be finite and > 0, a normal float (a subnormal k2 loses precision).
    fn validate(&self) -> Result<(), Error> {
        positive_normal("k2", self.0).map(|_| ())
    }
    fn min_k2(&self) -> Option<T> {
        Some(self.0)
    }
    fn range(&self, _lo: T, _hi: T) -> (T, T) {
        (self.0, self.0)
    }
    fn max_slope(&self, _lo: T, _hi: T) -> T {
        T::zero()
    }
}

/// An affine k2 = φ(v) = `at_zero` + `slope` · v, clamped to [`min`, `max`] so it stays positive
/// on every input (Example 1 uses φ(in) = 9 − 2 in with k2 ∈ [5, 12]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct AffineK2<T> {
    /// φ(0).
    pub at_zero: T,
    /// dφ/dv, in 1 / (input units)².
    pub slope: T,
    /// Lower clamp, finite and > 0.
    pub min: T,
    /// Upper clamp, finite and ≥ `min`.
    pub max: T,
}

impl<T: Real> AffineK2<T> {
    /// Builds and validates an affine law.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a non-finite coefficient, `min` ≤ 0 or `max` < `min`.
    pub fn new(at_zero: T, slope: T, min: T, max: T) -> Result<Self, Error> {
        let law = Self {
            at_zero,
            slope,
            min,
            max,
        };
        law.validate()?;
        Ok(law)
    }
}

impl<T: Real> K2Law<T> for AffineK2<T> {
    // Clamped to [min, max] with 0 < min ≤ max finite, and the input is finite.
    const ALWAYS_VALID: bool = true;
    // Arithmetic and comparisons only (a NaN input gives a NaN k2).
    const ANY_INPUT: bool = true;
    #[inline]
    fn k2<S: Sample<T>>(&self, input: S) -> S {
        let k = input * self.slope + self.at_zero;
        let v = k.value();
        if v < self.min {
            S::constant(self.min)
        } else if v > self.max {
            S::constant(self.max)
        } else {
            k
        }
    }
    fn validate(&self) -> Result<(), Error> {
        crate::error::finite("k2 law at_zero", self.at_zero)?;
        crate::error::finite("k2 law slope", self.slope)?;
        positive_normal("k2 law min", self.min)?;
        crate::error::finite("k2 law max", self.max)?;
        if self.max < self.min {
            return Err(Error::InvalidParameter {
                name: "k2 law max",
                value: self.max.as_f64(),
                expected: ">= k2 law min",
            });
        }
        Ok(())
    }
    fn min_k2(&self) -> Option<T> {
        Some(self.min)
    }
    fn range(&self, lo: T, hi: T) -> (T, T) {
        let a = self.k2(lo);
        let b = self.k2(hi);
        (a.min(b), a.max(b))
    }
    fn max_slope(&self, _lo: T, _hi: T) -> T {
        self.slope.abs()
    }
}

/// Any of the built-in k2 laws, chosen at run time (model files, fitting). Serialized with a
/// `law` tag: `{ law = "constant", value = … }` or
/// `{ law = "affine", at_zero = …, slope = …, min = …, max = … }`. (Reading a tagged enum needs
/// an allocator, so `Deserialize` comes with the `std` feature; `Serialize` with `serde` alone.)
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
#[cfg_attr(all(feature = "serde", feature = "std"), derive(Deserialize))]
#[cfg_attr(feature = "serde", serde(tag = "law", rename_all = "kebab-case"))]
pub enum AnyK2Law<T> {
    /// A constant k2 ([`ConstantK2`]), 1 / (input units), finite and > 0.
    Constant {
        /// k2.
        value: T,
    },
    /// An affine k2 = φ(v), clamped ([`AffineK2`]).
    Affine(AffineK2<T>),
}

impl<T: Real> AnyK2Law<T> {
    /// k2 at the operator input 0: the constant, or φ(0) (1 / input units).
    #[must_use]
    pub fn at_zero(&self) -> T {
        match self {
            AnyK2Law::Constant { value } => *value,
            AnyK2Law::Affine(law) => law.at_zero,
        }
    }
}

impl<T: Real> K2Law<T> for AnyK2Law<T> {
    // Both built-in laws give a finite k2 > 0 for every finite input once validated.
    const ALWAYS_VALID: bool = true;
    const ANY_INPUT: bool = true;
    #[inline]
    fn k2<S: Sample<T>>(&self, input: S) -> S {
        match self {
            AnyK2Law::Constant { value } => S::constant(*value),
            AnyK2Law::Affine(law) => law.k2(input),
        }
    }
    fn validate(&self) -> Result<(), Error> {
        match self {
            AnyK2Law::Constant { value } => ConstantK2(*value).validate(),
            AnyK2Law::Affine(law) => law.validate(),
        }
    }
    fn min_k2(&self) -> Option<T> {
        match self {
            AnyK2Law::Constant { value } => Some(*value),
            AnyK2Law::Affine(law) => law.min_k2(),
        }
    }
    fn range(&self, lo: T, hi: T) -> (T, T) {
        match self {
            AnyK2Law::Constant { value } => (*value, *value),
            AnyK2Law::Affine(law) => law.range(lo, hi),
        }
    }
    fn max_slope(&self, lo: T, hi: T) -> T {
        match self {
            AnyK2Law::Constant { .. } => T::zero(),
            AnyK2Law::Affine(law) => law.max_slope(lo, hi),
        }
    }
}
