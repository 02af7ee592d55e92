//! The limits of the parameter space where the model stays a good model but a parameter is no
//! longer identified: the stop form's Dahl limit and the backlash limit ([`ParameterLimit`],
//! with the report's note), and a saturating shape at its linear limit
//! ([`linear_limit_parameters`]).

use hyst_io::number::sig;
use hyst_model::{Form, SmoothModel};

use crate::layout::{Layout, IN_ARG_AT_CENTRE, IN_SCALE, OUT_ARG_AT_CENTRE, OUT_SCALE};

/// Below this k1 · k2 the stop form is in its Dahl limit: its transition after a reversal is
/// the exponential 1 − e^(−k2 Δv) of Dahl's friction model, the same for every smaller k1.
pub const DAHL_LIMIT: f64 = 1e-3;

/// Above this k1 · k2 the operator is in its backlash limit: the corners of its loop (a travel
/// of about 1/k2 after each reversal) are below a millionth of its half-width k1, the same
/// play for every larger k2.
pub const BACKLASH_LIMIT: f64 = 1e6;

/// A limit of the parameter space where the model stays a good model but a parameter is no
/// longer identified (every value beyond gives the same model).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParameterLimit {
    /// The stop form's Dahl limit (k1 · k2 < [`DAHL_LIMIT`], with the largest k2 of the law):
    /// k1 is not identified.
    Dahl {
        /// The (largest) k2.
        k2: f64,
    },
    /// The backlash limit (k1 · k2 > [`BACKLASH_LIMIT`], with the smallest k2 of the law): a
    /// play of half-width k1; k2 (and its slope) are not identified.
    Backlash {
        /// The (smallest) k2.
        k2: f64,
    },
}

impl ParameterLimit {
    /// The limit `model` is in, if any.
    #[must_use]
    pub fn of(model: &SmoothModel) -> Option<Self> {
        let (lo, hi) = match model.k2 {
            hyst_core::AnyK2Law::Constant { value } => (value, value),
            hyst_core::AnyK2Law::Affine(law) => (law.min, law.max),
        };
        if model.form == Form::Stop && model.k1 * hi < DAHL_LIMIT {
            Some(Self::Dahl { k2: hi })
        } else if model.k1 * lo > BACKLASH_LIMIT {
            Some(Self::Backlash { k2: lo })
        } else {
            None
        }
    }

    /// The parameters the limit leaves unidentified.
    #[must_use]
    pub fn unidentified(self) -> &'static [&'static str] {
        match self {
            Self::Dahl { .. } => &["k1"],
            Self::Backlash { .. } => &["k2", "k2.slope"],
        }
    }

    /// The report's note on the limit for a model of half-width `k1`.
    #[must_use]
    pub fn note(self, k1: f64) -> String {
        match self {
            Self::Dahl { k2 } => format!(
                "k1 · k2 = {} < {DAHL_LIMIT}: the stop form's Dahl limit (after each reversal the \
                 output approaches its level as 1 − e^(−k2 Δv), over a travel of about 3/k2 = {} \
                 normalised input units); every smaller k1 gives the same model, so k1 is not \
                 identified",
                sig(k1 * k2, 2),
                sig(3.0 / k2, 3),
            ),
            Self::Backlash { k2 } => format!(
                "k1 · k2 = {} > {}: the backlash limit (a play of half-width k1 = {} whose \
                 corners are sharper than a millionth of k1); every larger k2 gives the same \
                 model, so k2 is not identified",
                sig(k1 * k2, 2),
                sig(BACKLASH_LIMIT, 1),
                sig(k1, 4),
            ),
        }
    }
}

/// The scale of a saturating shape at the limit where it reproduces an affine one to rounding:
/// its deviation from the line, (reach / scale)² / 3 relative (tanh; Langevin /15), is 3e-17.
pub(super) const LIMIT_SCALE: f64 = 1e8;

/// The parameters of the saturating shapes of θ that sit at their linear limit (a scale of at
/// least a hundredth of [`LIMIT_SCALE`]): the scale and the argument at the centre, which the
/// data cannot tell apart there.
pub(super) fn linear_limit_parameters(layout: &Layout, theta: &[f64]) -> Vec<&'static str> {
    let mut out = Vec::new();
    for (scale, arg) in [(IN_SCALE, IN_ARG_AT_CENTRE), (OUT_SCALE, OUT_ARG_AT_CENTRE)] {
        let wide = layout
            .index(scale)
            .and_then(|i| Some(layout.params.get(i)?.transform.value(*theta.get(i)?)))
            .is_some_and(|v| v >= 0.01 * LIMIT_SCALE);
        if wide {
            out.push(scale);
            if layout.index(arg).is_some() {
                out.push(arg);
            }
        }
    }
    out
}
