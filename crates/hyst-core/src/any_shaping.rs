//! The shaping functions chosen at run time: any of the built-in ones ([`AnyShaping`]: model
//! files, the CLI, fitting), or only the affine ones ([`AffineShaping`]: the same arithmetic for
//! them, and a firmware links no nonlinear shape).

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use crate::error::Error;
use crate::real::Real;
use crate::sample::Sample;
use crate::shaping::{Affine, Identity, Langevin, Polynomial, QuadraticExp, Shaping, Tanh};

/// Any of the built-in shaping functions, chosen at run time (model files, the CLI, fitting).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum AnyShaping<T> {
    /// [`Identity`].
    #[default]
    Identity,
    /// [`Affine`].
    Affine(Affine<T>),
    /// [`Polynomial`].
    Polynomial(Polynomial<T>),
    /// [`Tanh`].
    Tanh(Tanh<T>),
    /// [`Langevin`].
    Langevin(Langevin<T>),
    /// [`QuadraticExp`].
    QuadraticExp(QuadraticExp<T>),
}

macro_rules! dispatch {
    ($self:ident, $s:ident => $e:expr) => {
        match $self {
            AnyShaping::Identity => {
                let $s = &Identity;
                $e
            }
            AnyShaping::Affine($s) => $e,
            AnyShaping::Polynomial($s) => $e,
            AnyShaping::Tanh($s) => $e,
            AnyShaping::Langevin($s) => $e,
            AnyShaping::QuadraticExp($s) => $e,
        }
    };
}

impl<T: Real> Shaping<T> for AnyShaping<T> {
    fn name(&self) -> &'static str {
        dispatch!(self, s => Shaping::<T>::name(s))
    }
    fn eval<S: Sample<T>>(&self, x: S) -> S {
        dispatch!(self, s => s.eval(x))
    }
    fn domain(&self) -> (T, T) {
        dispatch!(self, s => Shaping::<T>::domain(s))
    }
    fn invert_in_domain(&self, y: T) -> Result<T, Error> {
        dispatch!(self, s => s.invert_in_domain(y))
    }
    fn validate(&self) -> Result<(), Error> {
        dispatch!(self, s => Shaping::<T>::validate(s))
    }
    fn apply<S: Sample<T>>(&self, x: S) -> S {
        dispatch!(self, s => s.apply(x))
    }
    fn lipschitz(&self, lo: T, hi: T) -> T {
        dispatch!(self, s => s.lipschitz(lo, hi))
    }
    fn apply_with_slope(&self, x: T) -> (T, T) {
        match self {
            AnyShaping::Identity => (x, T::one()),
            AnyShaping::Affine(a) => (a.apply(x), a.lipschitz(x, x)),
            other => dispatch!(other, s => s.apply_with_slope(x)),
        }
    }
}

/// The affine shapes alone, identity or [`Affine`]: [`AnyShaping`]'s arithmetic for them, and
/// no code of the nonlinear shapes (a firmware that runs a model with affine shapings links
/// only these).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum AffineShaping<T> {
    /// [`Identity`].
    #[default]
    Identity,
    /// [`Affine`].
    Affine(Affine<T>),
}

/// The old name of [`AffineShaping`]: its shapes are affine, and "linear" names Lemma 5.1's
/// plant (docs/formats.md, "Deprecated names").
#[deprecated(note = "renamed AffineShaping")]
pub type LinearShaping<T> = AffineShaping<T>;

impl<T: Real> TryFrom<AnyShaping<T>> for AffineShaping<T> {
    type Error = Error;

    /// # Errors
    /// [`Error::InvalidParameter`] for a shape that is not identity or affine.
    fn try_from(shape: AnyShaping<T>) -> Result<Self, Error> {
        match shape {
            AnyShaping::Identity => Ok(AffineShaping::Identity),
            AnyShaping::Affine(a) => Ok(AffineShaping::Affine(a)),
            other => Err(Error::InvalidParameter {
                name: "shaping kind",
                value: f64::NAN,
                expected: match other {
                    AnyShaping::Polynomial(_) => "identity or affine (not polynomial)",
                    AnyShaping::Tanh(_) => "identity or affine (not tanh)",
                    AnyShaping::Langevin(_) => "identity or affine (not langevin)",
                    _ => "identity or affine (not quadratic-exp)",
                },
            }),
        }
    }
}

macro_rules! linear_dispatch {
    ($self:ident, $s:ident => $e:expr) => {
        match $self {
            AffineShaping::Identity => {
                let $s = &Identity;
                $e
            }
            AffineShaping::Affine($s) => $e,
        }
    };
}

impl<T: Real> Shaping<T> for AffineShaping<T> {
    fn name(&self) -> &'static str {
        linear_dispatch!(self, s => Shaping::<T>::name(s))
    }
    fn eval<S: Sample<T>>(&self, x: S) -> S {
        linear_dispatch!(self, s => s.eval(x))
    }
    fn domain(&self) -> (T, T) {
        linear_dispatch!(self, s => Shaping::<T>::domain(s))
    }
    fn invert_in_domain(&self, y: T) -> Result<T, Error> {
        linear_dispatch!(self, s => s.invert_in_domain(y))
    }
    fn validate(&self) -> Result<(), Error> {
        linear_dispatch!(self, s => Shaping::<T>::validate(s))
    }
    fn apply<S: Sample<T>>(&self, x: S) -> S {
        linear_dispatch!(self, s => s.apply(x))
    }
    fn lipschitz(&self, lo: T, hi: T) -> T {
        linear_dispatch!(self, s => s.lipschitz(lo, hi))
    }
    fn apply_with_slope(&self, x: T) -> (T, T) {
        match self {
            AffineShaping::Identity => (x, T::one()),
            AffineShaping::Affine(a) => (a.apply(x), a.lipschitz(x, x)),
        }
    }
}
