//! The fitted smooth model out = ψ_out(H(k1, k2)[ψ_in(in)]) (Section 4.3) as plain data: built
//! from the core's types, run over records, and turned into the core's exact compensator.

use hyst_core::{
    AnyK2Law, Direction, Error, Hysteresis, InverseModel, K2Law, Model, Operator, Shaping,
};
use serde::{Deserialize, Serialize};

use hyst_core::ScaledShaping;

/// Where each record starts (Definition 2.1 needs a first reversal point). The default,
/// [`InitialState::Rising`], suits a device switched on and driven up to its first value, and a
/// loop or FORC record that starts from positive saturation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "kebab-case")]
pub enum InitialState {
    /// As after a long rise: on the lower asymptote output = input − k1, heading up.
    #[default]
    Rising,
    /// As after a long fall: on the upper asymptote output = input + k1, heading down.
    Falling,
    /// No history: the first sample is a reversal point on the anhysteretic line output = input.
    Line,
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
    pub k2: AnyK2Law<f64>,
    /// Input shaping ψ_in: from input units to operator units.
    pub input_shaping: ScaledShaping<f64>,
    /// Output shaping ψ_out: from operator units to output units.
    pub output_shaping: ScaledShaping<f64>,
    /// How each record starts.
    pub initial_state: InitialState,
}

/// The core model type a [`SmoothModel`] becomes.
pub type CoreModel = Model<f64, ScaledShaping<f64>, AnyK2Law<f64>, ScaledShaping<f64>>;
/// Its exact compensator.
pub type CoreInverse = InverseModel<f64, ScaledShaping<f64>, AnyK2Law<f64>, ScaledShaping<f64>>;

impl SmoothModel {
    /// Checks every parameter through the core's constructors.
    ///
    /// # Errors
    /// The core's error for the first invalid value.
    pub fn validate(&self) -> Result<(), Error> {
        self.core(0.0).map(|_| ())
    }

    /// The core operator H(k1, k2) for a record whose first input sample is `first_input`,
    /// started by the model's start rule.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for an invalid k1 or k2 law (the core's checks), or for a
    /// `first_input` whose start point is not finite.
    pub fn operator(&self, first_input: f64) -> Result<Hysteresis<f64, AnyK2Law<f64>>, Error> {
        self.start(Hysteresis::with_k2_law(self.k1, self.k2)?, first_input)
    }

    /// `operator` started by the model's start rule ([`SmoothModel::initial_state`]) for a
    /// record whose first input sample is `first_input`: on the line, or on the asymptote of
    /// `operator`'s own k1.
    fn start<K: K2Law<f64>>(
        &self,
        operator: Hysteresis<f64, K>,
        first_input: f64,
    ) -> Result<Hysteresis<f64, K>, Error> {
        let v0 = self.input_shaping.apply(first_input);
        let k1 = operator.k1();
        match self.initial_state {
            InitialState::Line => Ok(operator),
            InitialState::Rising => {
                operator.with_initial_state(v0, on_asymptote(v0, -k1), Direction::Rising)
            }
            InitialState::Falling => {
                operator.with_initial_state(v0, on_asymptote(v0, k1), Direction::Falling)
            }
        }
    }

    /// The core model ψ_out(H[ψ_in(·)]) for a record starting at `first_input` (use it to run
    /// the model).
    ///
    /// # Errors
    /// As [`SmoothModel::operator`], and the shaping functions' own validation errors.
    pub fn core(&self, first_input: f64) -> Result<CoreModel, Error> {
        self.shaped(Hysteresis::with_k2_law(self.k1, self.k2)?, first_input)
    }

    /// Any operator with no history (a member of a family around this model, say) inside this
    /// model's shaping, ψ_out(operator[ψ_in(·)]), started by this model's start rule for a
    /// record whose first input sample is `first_input` (on the asymptotes of the operator's
    /// own k1).
    ///
    /// # Errors
    /// As [`SmoothModel::core`].
    pub fn shaped<K: K2Law<f64>>(
        &self,
        operator: Hysteresis<f64, K>,
        first_input: f64,
    ) -> Result<Model<f64, ScaledShaping<f64>, K, ScaledShaping<f64>>, Error> {
        Model::new(
            self.input_shaping,
            self.start(operator, first_input)?,
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

    /// The exact compensator for a record whose first *desired output* is `first_desired`,
    /// started where the model's start rule puts the model that produces it: the command x0
    /// with ψ_out(H[ψ_in(x0)]) = `first_desired` on the start rule's asymptote (or line).
    ///
    /// # Errors
    /// A desired output beyond a saturating output shaping's range, or invalid parameters.
    pub fn compensator_from_desired(&self, first_desired: f64) -> Result<CoreInverse, Error> {
        let u0 = self.output_shaping.invert(first_desired)?;
        let v0 = match self.initial_state {
            InitialState::Line => u0,
            InitialState::Rising => u0 + self.k1,
            InitialState::Falling => u0 - self.k1,
        };
        let x0 = self.input_shaping.invert(v0)?;
        self.compensator(x0)
    }

    /// The open range (lo, hi) of the model's output when ψ_out saturates (tanh, Langevin): the
    /// outputs approach lo and hi but never reach them, so a desired output outside has no
    /// command. `None` when ψ_out is unbounded (at either end).
    #[must_use]
    pub fn output_range(&self) -> Option<(f64, f64)> {
        let psi = &self.output_shaping;
        // The shape names its range when asked to invert a value beyond it.
        let end = |probe: f64, pick: fn(f64, f64) -> f64| match psi.shape.invert(probe) {
            Err(Error::OutOfRange { min, max, .. }) => {
                psi.post_gain * pick(min, max) + psi.post_offset
            }
            _ => probe * f64::INFINITY,
        };
        let lo = end(-f64::MAX, |min, _| min);
        let hi = end(f64::MAX, |_, max| max);
        (lo.is_finite() && hi.is_finite()).then_some((lo, hi))
    }

    /// Runs the model over one record: `operator_out` receives H's output (before ψ_out) when
    /// given, `output` the model output. Same arithmetic as stepping [`SmoothModel::core`].
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
}
