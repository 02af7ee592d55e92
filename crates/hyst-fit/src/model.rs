//! The fitted smooth model out = ψ_out(H(k1, k2)[ψ_in(in)]) (Section 4.3) as plain data: built
//! from the core's types, run over records, and turned into the core's exact compensator.

use hyst_core::{
    AffineK2, ConstantK2, Direction, Error, Hysteresis, InverseModel, K2Law, Model, Operator,
    Sample, Shaping,
};
use serde::{Deserialize, Serialize};

use crate::ScaledShaping;

/// The k2 law of a fitted model: constant (Definition 2.2) or affine in the operator input
/// (Proposition 4.3), in 1 / (operator input units).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "law", rename_all = "kebab-case")]
pub enum K2Spec {
    /// k2 constant.
    Constant {
        /// k2 > 0.
        value: f64,
    },
    /// k2 = φ(v) = at_zero + slope · v, clamped to [min, max] (see [`AffineK2`]).
    Affine {
        /// φ(0).
        at_zero: f64,
        /// dφ/dv.
        slope: f64,
        /// Lower clamp (> 0).
        min: f64,
        /// Upper clamp.
        max: f64,
    },
}

impl K2Spec {
    /// The same law with k2 shifted by `delta` (a member of the family RH(k1, Δk1, k2, Δk2)).
    #[must_use]
    pub fn shifted(&self, delta: f64) -> Self {
        match *self {
            K2Spec::Constant { value } => K2Spec::Constant {
                value: value + delta,
            },
            K2Spec::Affine {
                at_zero,
                slope,
                min,
                max,
            } => K2Spec::Affine {
                at_zero: at_zero + delta,
                slope,
                min: min + delta,
                max: max + delta,
            },
        }
    }

    /// k2 at the operator input 0 (the constant, or φ(0)).
    #[must_use]
    pub fn nominal(&self) -> f64 {
        match *self {
            K2Spec::Constant { value } => value,
            K2Spec::Affine { at_zero, .. } => at_zero,
        }
    }
}

impl K2Law<f64> for K2Spec {
    #[inline]
    fn k2<S: Sample<f64>>(&self, input: S) -> S {
        match *self {
            K2Spec::Constant { value } => S::constant(value),
            K2Spec::Affine {
                at_zero,
                slope,
                min,
                max,
            } => AffineK2 {
                at_zero,
                slope,
                min,
                max,
            }
            .k2(input),
        }
    }
    fn validate(&self) -> Result<(), Error> {
        match *self {
            K2Spec::Constant { value } => ConstantK2(value).validate(),
            K2Spec::Affine {
                at_zero,
                slope,
                min,
                max,
            } => AffineK2::new(at_zero, slope, min, max).map(|_| ()),
        }
    }
    fn range(&self, lo: f64, hi: f64) -> (f64, f64) {
        let a = self.k2(lo);
        let b = self.k2(hi);
        (a.min(b), a.max(b))
    }
    fn max_slope(&self, _lo: f64, _hi: f64) -> f64 {
        match *self {
            K2Spec::Constant { .. } => 0.0,
            K2Spec::Affine { slope, .. } => slope.abs(),
        }
    }
}

/// Where each record starts (Definition 2.1 needs a first reversal point).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum InitialState {
    /// No history: the first sample is a reversal point on the line output = input of the
    /// operator (the anhysteretic curve).
    Line,
    /// As after a long rise: on the lower asymptote, output = input − k1, heading up. The
    /// default: a device switched on and driven up to its first value, a loop or FORC record
    /// that starts from positive saturation.
    #[default]
    Rising,
    /// As after a long fall: on the upper asymptote, output = input + k1, heading down.
    Falling,
}

/// v + d rounded towards v until |(v + d) − v| ≤ |d| holds in floating point (the band check
/// of the core), so a start on the asymptote is never refused for an ulp.
fn on_asymptote(v: f64, d: f64) -> f64 {
    let mut u = v + d;
    for _ in 0..64 {
        if (u - v).abs() <= d.abs() {
            break;
        }
        // One ulp towards v.
        let bits = u.to_bits();
        u = f64::from_bits(if (u > v) == (u > 0.0) {
            bits - 1
        } else {
            bits + 1
        });
    }
    u
}

/// A smooth model out = ψ_out(H(k1, k2)[ψ_in(in)]) with its start rule.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SmoothModel {
    /// Hysteresis half-width k1 (operator units: those of ψ_in's value), > 0.
    pub k1: f64,
    /// The k2 law (1 / operator units).
    pub k2: K2Spec,
    /// Input shaping ψ_in: from input units to operator units.
    pub input_shaping: ScaledShaping,
    /// Output shaping ψ_out: from operator units to output units.
    pub output_shaping: ScaledShaping,
    /// How each record starts.
    pub initial_state: InitialState,
}

/// The core model type a [`SmoothModel`] becomes.
pub type CoreModel = Model<f64, ScaledShaping, K2Spec, ScaledShaping>;
/// Its exact compensator.
pub type CoreInverse = InverseModel<f64, ScaledShaping, K2Spec, ScaledShaping>;

impl SmoothModel {
    /// Checks every parameter through the core's constructors.
    ///
    /// # Errors
    /// The core's error for the first invalid value.
    pub fn validate(&self) -> Result<(), Error> {
        self.core(0.0).map(|_| ())
    }

    /// The core operator for a record whose first input sample is `first_input`.
    ///
    /// # Errors
    /// Invalid parameters.
    pub fn operator(&self, first_input: f64) -> Result<Hysteresis<f64, K2Spec>, Error> {
        let h = Hysteresis::with_k2_law(self.k1, self.k2)?;
        let v0 = self.input_shaping.apply(first_input);
        match self.initial_state {
            InitialState::Line => Ok(h),
            InitialState::Rising => {
                h.with_initial_state(v0, on_asymptote(v0, -self.k1), Direction::Rising)
            }
            InitialState::Falling => {
                h.with_initial_state(v0, on_asymptote(v0, self.k1), Direction::Falling)
            }
        }
    }

    /// The core model for a record starting at `first_input` (use it to run the model).
    ///
    /// # Errors
    /// Invalid parameters.
    pub fn core(&self, first_input: f64) -> Result<CoreModel, Error> {
        Model::new(
            self.input_shaping,
            self.operator(first_input)?,
            self.output_shaping,
        )
    }

    /// The exact compensator (desired output → command) for a record whose first *command*
    /// would be `first_input`; with [`InitialState::Line`] the start is immaterial.
    ///
    /// # Errors
    /// Invalid parameters.
    pub fn compensator(&self, first_input: f64) -> Result<CoreInverse, Error> {
        Ok(self.core(first_input)?.inverse())
    }

    /// Runs the model over one record: `operator_out` receives H's output (before ψ_out) when
    /// given, `output` the model output. Same arithmetic as [`hyst_core::Model::eval`].
    ///
    /// # Errors
    /// Invalid parameters, or a non-finite value on the way (the fit treats it as infeasible).
    pub fn simulate(
        &self,
        input: &[f64],
        mut operator_out: Option<&mut [f64]>,
        output: &mut [f64],
    ) -> Result<(), Error> {
        let Some(&first) = input.first() else {
            return Ok(());
        };
        let mut h = self.operator(first)?;
        for (i, (x, y)) in input.iter().zip(output.iter_mut()).enumerate() {
            let v = self.input_shaping.apply(*x);
            let u = h.try_step(v)?;
            if let Some(z) = operator_out.as_deref_mut() {
                if let Some(slot) = z.get_mut(i) {
                    *slot = u;
                }
            }
            *y = self.output_shaping.apply(u);
        }
        Ok(())
    }

    /// Runs the model over one record into a new vector.
    ///
    /// # Errors
    /// As [`SmoothModel::simulate`].
    pub fn run(&self, input: &[f64]) -> Result<Vec<f64>, Error> {
        let mut out = vec![0.0; input.len()];
        self.simulate(input, None, &mut out)?;
        Ok(out)
    }

    /// The same model with k1 and k2 moved by (d1, d2): a member of the family.
    #[must_use]
    pub fn member(&self, d1: f64, d2: f64) -> Self {
        Self {
            k1: self.k1 + d1,
            k2: self.k2.shifted(d2),
            ..*self
        }
    }
}
