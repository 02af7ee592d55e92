//! The model structure the user chooses: the k2 law, the shaping functions ψ_in and ψ_out,
//! the offsets, the start rule and the form. A model file records it (`[structure]`); the fit
//! (hyst-fit's `Layout`) turns it into free parameters.

use serde::{Deserialize, Serialize};

use crate::choice::Choice;
use crate::dynamics::Hold;
use crate::smooth::{Form, InitialState};

/// A shaping function family for ψ_in or ψ_out. Its kebab-case name (`affine`, `poly2`, `poly3`,
/// `tanh`, `langevin`, `quadratic-exp`) is the model file's and the command line's. Files and
/// command lines of hyst before 0.1 wrote `quad-exp`; it still reads as `quadratic-exp`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShapingKind {
    /// Affine (ψ_in: the fixed normalisation of the input; ψ_out: gain and offset).
    #[default]
    Affine,
    /// Quadratic polynomial x + p2 x², monotone on the data.
    Poly2,
    /// Cubic polynomial x + p2 x² + p3 x³, monotone on the data.
    Poly3,
    /// tanh(x / σ + c): saturation.
    Tanh,
    /// Langevin function L(x / σ + c): the classical anhysteretic curve.
    Langevin,
    /// Example 2's x − a x² − e^(−(b + c x)).
    #[serde(alias = "quad-exp")]
    QuadraticExp,
}

impl Choice for ShapingKind {
    const WHAT: &'static str = "shaping";
    const CHOICES: &'static [(Self, &'static str, &'static str)] = &[
        (
            ShapingKind::Affine,
            "affine",
            "Affine (ψ_in: the fixed normalisation of the input; ψ_out: gain and offset)",
        ),
        (
            ShapingKind::Poly2,
            "poly2",
            "Quadratic polynomial x + p2 x², monotone on the data",
        ),
        (
            ShapingKind::Poly3,
            "poly3",
            "Cubic polynomial x + p2 x² + p3 x³, monotone on the data",
        ),
        (ShapingKind::Tanh, "tanh", "tanh(x / σ + c): saturation"),
        (
            ShapingKind::Langevin,
            "langevin",
            "Langevin function L(x / σ + c): the classical anhysteretic curve",
        ),
        (
            ShapingKind::QuadraticExp,
            "quadratic-exp",
            "Example 2's x − a x² − e^(−(b + c x))",
        ),
    ];
    const ALIASES: &'static [(&'static str, Self)] = &[("quad-exp", ShapingKind::QuadraticExp)];
}

impl ShapingKind {
    /// Whether the shape saturates (tanh, Langevin): its range is bounded.
    #[must_use]
    pub fn saturating(self) -> bool {
        matches!(self, ShapingKind::Tanh | ShapingKind::Langevin)
    }
}

/// The k2 law to fit: constant, or affine in the operator input (Proposition 4.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum K2Kind {
    /// k2 constant.
    #[default]
    Constant,
    /// k2 = a + b v, affine in the operator input v (Proposition 4.3).
    Affine,
}

impl Choice for K2Kind {
    const WHAT: &'static str = "k2 law";
    const CHOICES: &'static [(Self, &'static str, &'static str)] = &[
        (K2Kind::Constant, "constant", "k2 constant"),
        (
            K2Kind::Affine,
            "affine",
            "k2 = a + b v, affine in the operator input v (Proposition 4.3)",
        ),
    ];
}

/// The model structure chosen by the user.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Structure {
    /// k2 law.
    pub k2: K2Kind,
    /// ψ_in family.
    pub input_shaping: ShapingKind,
    /// ψ_out family.
    pub output_shaping: ShapingKind,
    /// Fit an offset of the input before ψ_in (`None`: only where it is identifiable, i.e. for
    /// tanh and Langevin input shaping).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub input_offset: Option<bool>,
    /// Fit an offset of the output (a sensor offset).
    pub output_offset: bool,
    /// How each record starts.
    pub initial_state: InitialState,
    /// The form: the operator (counterclockwise loops) or its stop form (clockwise loops,
    /// friction), with the linear term `out.linear`.
    #[serde(default, skip_serializing_if = "Form::is_operator")]
    pub form: Form,
    /// The order n of the plant before the hysteresis (`--dynamics N`, 1…4; 0: none).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub dynamics: u8,
    /// The rate term (`--rate-term`), if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rate: Option<RateTerm>,
    /// The hold the plant is fitted with (`--hold`, which asks for [`Hold::FIT_DEFAULT`] unless
    /// told otherwise; [`Hold::UNRECORDED`] by default here, as in a file without it). The
    /// model file holds it in `[dynamics]` (where the runtime reads it), not in
    /// `[structure]`: a structure read from a file takes it from there.
    #[serde(skip, default = "unrecorded")]
    pub hold: Hold,
}

fn unrecorded() -> Hold {
    Hold::UNRECORDED
}

// serde's `skip_serializing_if` takes a reference.
#[allow(clippy::trivially_copy_pass_by_ref)]
fn is_zero(n: &u8) -> bool {
    *n == 0
}

/// The rate term of a model: the command line's `--rate-term` and the structure's `rate`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RateTerm {
    /// c·v̇: a force proportional to the hysteresis input's rate (viscous friction, dampers).
    Viscous,
}

impl Choice for RateTerm {
    const WHAT: &'static str = "rate term";
    const CHOICES: &'static [(Self, &'static str, &'static str)] = &[(
        RateTerm::Viscous,
        "viscous",
        "c·v̇: a force proportional to the hysteresis input's rate (viscous friction, dampers)",
    )];
}

impl Default for Structure {
    /// k1, constant k2, affine shaping (normalised input, output gain), output offset, records
    /// starting as after a rise, no dynamics (a plant, when one is asked for, under the
    /// first-order hold of a file without `hold`; `hyst fit` and `hyst.fit` ask for the
    /// zero-order hold).
    fn default() -> Self {
        Self {
            k2: K2Kind::Constant,
            input_shaping: ShapingKind::Affine,
            output_shaping: ShapingKind::Affine,
            input_offset: None,
            output_offset: true,
            initial_state: InitialState::Rising,
            form: Form::Operator,
            dynamics: 0,
            rate: None,
            hold: Hold::UNRECORDED,
        }
    }
}
