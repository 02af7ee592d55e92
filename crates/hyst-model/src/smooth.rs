//! The fitted smooth model out = ψ_out(H(k1, k2)\[ψ_in(in)\]) (Section 4.3), or its stop form
//! out = ψ_out(v − H(k1, k2)\[v\]) + c·v, v = ψ_in(in), for clockwise loops, as plain data: built
//! from the core's types, run over records, and turned into the core's exact compensator.

use hyst_core::shaped_model::unreachable_output;
pub use hyst_core::InitialState;
use hyst_core::{
    on_asymptote, AnyK2Law, Direction, Dual, Error, Hysteresis, InverseShapedModel, K2Law,
    Operator, Real, ShapedModel, Shaping, Stop,
};
use hyst_core::{AnyShaping, ScaledShaping};
use serde::{Deserialize, Serialize};

use crate::choice::Choice;

use crate::dynamics::{Dynamics, Rate};
use crate::error::ModelError;

/// Which way the model's loop runs, and so its equation. The kebab-case name (`operator`,
/// `stop`) is the model file's and the command line's.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Form {
    /// out = ψ_out(H\[ψ_in(in)\]): the operator's counterclockwise loop (the output lags the
    /// input: piezo stacks, magnetisation, most actuators).
    #[default]
    Operator,
    /// out = ψ_out(v − H\[v\]) + c·v, v = ψ_in(in): the smooth stop operator's clockwise loop
    /// (friction against position, a Dahl-like model; any loop whose output leads the input).
    Stop,
}

impl Choice for Form {
    const WHAT: &'static str = "form";
    const CHOICES: &'static [(Self, &'static str, &'static str)] = &[
        (
            Form::Operator,
            "operator",
            "out = ψ_out(H[ψ_in(in)]): the operator's counterclockwise loop (the output lags the \
             input: piezo stacks, magnetisation, most actuators)",
        ),
        (
            Form::Stop,
            "stop",
            "out = ψ_out(v − H[v]) + c·v, v = ψ_in(in): the smooth stop operator's clockwise loop \
             (friction against position, a Dahl-like model; any loop whose output leads the input)",
        ),
    ];
}

impl Form {
    /// Whether this is the default [`Form::Operator`] (the model file then omits it).
    #[must_use]
    pub fn is_operator(&self) -> bool {
        *self == Form::Operator
    }
}

// serde's `skip_serializing_if` takes a reference.
#[allow(clippy::trivially_copy_pass_by_ref)]
fn is_zero<T: Default + PartialEq>(x: &T) -> bool {
    *x == T::default()
}

/// The numbers a [`SmoothModel`] is evaluated on: `f64` (the fit's values, model files) and
/// [`Dual<f64, N>`] (the same evaluation with the gradient with respect to N parameters: the
/// fit's Jacobian).
pub trait FitReal: Real {}

impl FitReal for f64 {}

impl<const N: usize> FitReal for Dual<f64, N> {}

/// A smooth model out = ψ_out(H(k1, k2)\[ψ_in(in)\]) (or its stop form, [`Form::Stop`]) with its
/// start rule.
///
/// `T` is `f64` for a model as such; the fit evaluates the same model on [`Dual`] numbers
/// ([`FitReal`]) for its Jacobian.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(bound(
    serialize = "T: Serialize + Default + PartialEq",
    deserialize = "T: Deserialize<'de> + Default + PartialEq"
))]
pub struct SmoothModel<T = f64> {
    /// Hysteresis half-width k1 (operator units: those of ψ_in's value), > 0.
    pub k1: T,
    /// The k2 law (1 / operator units).
    pub k2: AnyK2Law<T>,
    /// Input shaping ψ_in: from input units to operator units.
    pub input_shaping: ScaledShaping<T>,
    /// Output shaping ψ_out: from operator units to output units.
    pub output_shaping: ScaledShaping<T>,
    /// How each record starts.
    pub initial_state: InitialState,
    /// The form: the operator itself (default) or its stop form.
    #[serde(default, skip_serializing_if = "Form::is_operator")]
    pub form: Form,
    /// c of the stop form's linear term c·v (output units per operator unit; 0 for the operator
    /// form).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub linear: T,
    /// Lemma 5.1's plant between the command and the hysteresis input, if the model has one:
    /// the model then runs on timed records ([`crate::timed`]). The model file holds it in its
    /// own section `[dynamics]` ([`crate::dynamics::DynamicsSection`]), with its standard
    /// errors.
    #[serde(skip)]
    pub dynamics: Option<Dynamics<T>>,
    /// The viscous rate term c·v̇ added to the output, if the model has one (the model file's
    /// `[rate]`).
    #[serde(skip)]
    pub rate: Option<Rate<T>>,
}

/// The core model type a [`SmoothModel`] becomes.
pub type CoreShapedModel<T = f64> = ShapedModel<T, ScaledShaping<T>, AnyK2Law<T>, ScaledShaping<T>>;
/// The core type of a stop-form [`SmoothModel`].
pub type CoreStop<T = f64> = Stop<T, ScaledShaping<T>, AnyK2Law<T>, ScaledShaping<T>>;
/// A model of either form around an operator with any k2 law (a family member, say): what
/// [`SmoothModel::shaped`] builds, run through the core's [`Operator`] trait.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shaped<K> {
    /// ψ_out(H\[ψ_in(·)\]).
    Operator(ShapedModel<f64, ScaledShaping<f64>, K, ScaledShaping<f64>>),
    /// ψ_out(v − H\[v\]) + c·v.
    Stop(Stop<f64, ScaledShaping<f64>, K, ScaledShaping<f64>>),
}

impl<K: K2Law<f64>> Operator<f64> for Shaped<K> {
    type Memory = Option<hyst_core::Memory<f64>>;

    fn try_step<S: hyst_core::Sample<f64>>(&mut self, x: S) -> Result<S, Error> {
        match self {
            Shaped::Operator(m) => m.try_step(x),
            Shaped::Stop(m) => m.try_step(x),
        }
    }
    fn last_output(&self) -> Option<f64> {
        match self {
            Shaped::Operator(m) => m.last_output(),
            Shaped::Stop(m) => m.last_output(),
        }
    }
    fn reset(&mut self) {
        match self {
            Shaped::Operator(m) => m.reset(),
            Shaped::Stop(m) => m.reset(),
        }
    }
    fn memory(&self) -> Self::Memory {
        match self {
            Shaped::Operator(m) => m.memory(),
            Shaped::Stop(m) => m.memory(),
        }
    }
    fn set_memory(&mut self, memory: Self::Memory) -> Result<(), Error> {
        match self {
            Shaped::Operator(m) => m.set_memory(memory),
            Shaped::Stop(m) => m.set_memory(memory),
        }
    }
}

/// Its exact compensator.
pub type CoreInverseShapedModel =
    InverseShapedModel<f64, ScaledShaping<f64>, AnyK2Law<f64>, ScaledShaping<f64>>;

impl<T: FitReal> SmoothModel<T> {
    /// Whether the model has dynamics or a rate term: it then runs on timed records only
    /// ([`crate::timed`]), and the surfaces that run models sample by sample without time
    /// refuse it.
    #[must_use]
    pub fn is_timed(&self) -> bool {
        self.dynamics.is_some() || self.rate.is_some()
    }

    /// What makes the model timed, in words: "dynamics of order 2", "a rate term", or both.
    #[must_use]
    pub fn timed_parts(&self) -> String {
        match (&self.dynamics, &self.rate) {
            (Some(d), Some(_)) => format!("dynamics of order {} and a rate term", d.order()),
            (Some(d), None) => format!("dynamics of order {}", d.order()),
            _ => "a rate term".into(),
        }
    }

    /// Checks every parameter through the core's constructors.
    ///
    /// # Errors
    /// The core's error for the first invalid value.
    pub fn validate(&self) -> Result<(), Error> {
        self.core(T::zero())?;
        if let Some(r) = self.rate.filter(|r| !r.c.is_finite()) {
            return Err(Error::InvalidParameter {
                name: "rate.c",
                value: r.c.as_f64(),
                expected: "a finite rate coefficient",
            });
        }
        if self.form == Form::Stop {
            self.stop(T::zero())?;
        } else if self.linear != T::zero() {
            return Err(Error::InvalidParameter {
                name: "linear",
                value: self.linear.as_f64(),
                expected: "0 for the operator form (the linear term belongs to form = \"stop\")",
            });
        }
        Ok(())
    }

    /// The stop form ψ_out(v − H\[v\]) + c·v of this model's parts, for a record whose first
    /// input sample is `first_input` (whatever [`SmoothModel::form`] says).
    ///
    /// # Errors
    /// As [`SmoothModel::core`], and a non-finite `linear`.
    pub fn stop(&self, first_input: T) -> Result<CoreStop<T>, Error> {
        Stop::new(
            self.input_shaping,
            self.start(Hysteresis::with_k2_law(self.k1, self.k2)?, first_input)?,
            self.output_shaping,
            self.linear,
        )
    }

    /// The model output for the operator input v = ψ_in(in) and the operator output u = H\[v\]:
    /// ψ_out(u), or ψ_out(v − u) + c·v in the stop form.
    #[must_use]
    #[inline]
    pub fn output(&self, v: T, u: T) -> T {
        match self.form {
            Form::Operator => self.output_shaping.apply(u),
            Form::Stop => self.output_shaping.apply(v - u) + v * self.linear,
        }
    }

    /// The envelope of the outputs [`SmoothModel::output`] from the envelope [`lower`, `upper`]
    /// of operator outputs u at the operator inputs `v`, in place: ψ_out is strictly increasing
    /// (every shaping function is, with positive gains), so the output is increasing in u in the
    /// operator form, ψ_out(u), and decreasing in the stop form, ψ_out(v − u) + c v; the
    /// smallest and largest outputs of any set of operators at a sample are those of its
    /// smallest and largest u. Non-finite u (a non-finite input) stay NaN.
    ///
    /// # Errors
    /// [`Error::NonFiniteOutput`] (naming the operator input v) when an output of a finite u is
    /// not finite (ψ_out beyond the float range, as stepping the shaped model reports it).
    pub fn output_envelope(&self, v: &[T], lower: &mut [T], upper: &mut [T]) -> Result<(), Error> {
        for ((v, lo), hi) in v.iter().zip(lower.iter_mut()).zip(upper.iter_mut()) {
            if !(lo.is_finite() && hi.is_finite()) {
                (*lo, *hi) = (T::nan(), T::nan());
                continue;
            }
            let (at_lo, at_hi) = (self.output(*v, *lo), self.output(*v, *hi));
            if let Some(y) = [at_lo, at_hi].into_iter().find(|y| !y.is_finite()) {
                return Err(Error::NonFiniteOutput {
                    input: v.as_f64(),
                    output: y.as_f64(),
                });
            }
            (*lo, *hi) = match self.form {
                Form::Operator => (at_lo, at_hi),
                Form::Stop => (at_hi, at_lo),
            };
        }
        Ok(())
    }

    /// The range of ψ_out's argument over the operator inputs [v_lo, v_hi]: the operator output
    /// (within k1 of its input), or the stop value v − H\[v\] ∈ [−k1, k1].
    #[must_use]
    pub fn output_argument_range(form: Form, k1: T, v_lo: T, v_hi: T) -> (T, T) {
        match form {
            Form::Operator => (v_lo - k1, v_hi + k1),
            Form::Stop => (-k1, k1),
        }
    }

    /// The core operator H(k1, k2) for a record whose first input sample is `first_input`,
    /// started by the model's start rule.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for an invalid k1 or k2 law (the core's checks), or for a
    /// `first_input` whose start point is not finite.
    pub fn operator(&self, first_input: T) -> Result<Hysteresis<T, AnyK2Law<T>>, Error> {
        self.start(Hysteresis::with_k2_law(self.k1, self.k2)?, first_input)
    }

    /// `operator` started by the model's start rule ([`SmoothModel::initial_state`]) for a
    /// record whose first input sample is `first_input`: on the line, or on the asymptote of
    /// `operator`'s own k1.
    fn start<K: K2Law<T>>(
        &self,
        operator: Hysteresis<T, K>,
        first_input: T,
    ) -> Result<Hysteresis<T, K>, Error> {
        self.initial_state
            .start(operator, self.input_shaping.apply(first_input))
    }

    /// `operator` started for a record with inputs `input`: by the start rule, or, with a
    /// `band` fraction b ∈ [−1, 1] (an estimated start), at rest at a reversal at the first
    /// sample with the operator output v0 + b · k1, heading the way the input first moves.
    pub fn start_in<K: K2Law<T>>(
        &self,
        operator: Hysteresis<T, K>,
        input: &[f64],
        band: Option<f64>,
    ) -> Result<Hysteresis<T, K>, Error> {
        let first = input.first().copied().unwrap_or(0.0);
        let Some(b) = band else {
            return self.start(operator, T::from_f64(first));
        };
        let v0 = self.input_shaping.apply(T::from_f64(first));
        let rising = input
            .iter()
            .find(|x| **x != first)
            .is_none_or(|x| *x > first);
        let direction = if rising {
            Direction::Rising
        } else {
            Direction::Falling
        };
        let b = if b.is_finite() {
            b.clamp(-1.0, 1.0)
        } else {
            0.0
        };
        let k1 = operator.k1();
        operator.with_initial_state(v0, on_asymptote(v0, k1 * T::from_f64(b)), direction)
    }

    /// The core model ψ_out(H\[ψ_in(·)\]) for a record starting at `first_input` (use it to run
    /// the model).
    ///
    /// # Errors
    /// As [`SmoothModel::operator`], and the shaping functions' own validation errors.
    pub fn core(&self, first_input: T) -> Result<CoreShapedModel<T>, Error> {
        ShapedModel::new(
            self.input_shaping,
            self.operator(first_input)?,
            self.output_shaping,
        )
    }

    /// Runs the model over one record: `operator_out` receives H's output u when given, `output`
    /// the model output ([`SmoothModel::output`]). Same arithmetic as stepping
    /// [`SmoothModel::core`] (or [`SmoothModel::stop`]).
    ///
    /// # Errors
    /// Invalid parameters, or a non-finite value on the way (the fit treats it as infeasible).
    pub fn simulate(
        &self,
        input: &[f64],
        operator_out: Option<&mut [T]>,
        output: &mut [T],
    ) -> Result<(), Error> {
        self.simulate_from(input, None, operator_out, output)
    }

    /// [`SmoothModel::simulate`] from an estimated start: with `band` = Some(b), b ∈ [−1, 1],
    /// the record starts at rest at a reversal at its first sample with the operator output
    /// v0 + b · k1 (−1: the lower asymptote, 0: the line, 1: the upper one), heading the way the
    /// input first moves; with `None`, by the start rule.
    ///
    /// # Errors
    /// As [`SmoothModel::simulate`].
    pub fn simulate_from(
        &self,
        input: &[f64],
        band: Option<f64>,
        mut operator_out: Option<&mut [T]>,
        output: &mut [T],
    ) -> Result<(), Error> {
        self.run_with(input, band, |i, u, y| {
            if let Some(slot) = operator_out.as_deref_mut().and_then(|z| z.get_mut(i)) {
                *slot = u;
            }
            if let Some(slot) = output.get_mut(i) {
                *slot = y;
            }
        })
    }

    /// Runs the model over one record, started by the rule or from the estimated `band` (as
    /// [`SmoothModel::simulate_from`]), and hands each sample's index, operator output u and
    /// model output to `each` (in order): the one loop behind [`SmoothModel::simulate`] and the
    /// fit's Jacobian.
    ///
    /// # Errors
    /// As [`SmoothModel::simulate`].
    #[inline]
    pub fn run_with(
        &self,
        input: &[f64],
        band: Option<f64>,
        mut each: impl FnMut(usize, T, T),
    ) -> Result<(), Error> {
        if input.is_empty() {
            return Ok(());
        }
        let mut h = self.start_in(Hysteresis::with_k2_law(self.k1, self.k2)?, input, band)?;
        for (i, x) in input.iter().enumerate() {
            let v = self.input_shaping.apply(T::from_f64(*x));
            let u = h.try_step(v)?;
            let y = self.output(v, u);
            if !y.is_finite() {
                return Err(Error::NonFiniteOutput {
                    input: *x,
                    output: y.as_f64(),
                });
            }
            each(i, u, y);
        }
        Ok(())
    }
}

/// The open range of a shaping function bounded at both ends (tanh, Langevin), read from the
/// range its shape names when asked to invert a value beyond it; `None` otherwise.
fn bounded_range(psi: &ScaledShaping<f64>) -> Option<(f64, f64)> {
    let end = |probe: f64, pick: fn(f64, f64) -> f64| match psi.shape.invert(probe) {
        Err(Error::OutOfRange { min, max, .. }) => psi.post_gain * pick(min, max) + psi.post_offset,
        _ => probe * f64::INFINITY,
    };
    let lo = end(-f64::MAX, |min, _| min);
    let hi = end(f64::MAX, |_, max| max);
    (lo.is_finite() && hi.is_finite()).then_some((lo, hi))
}

impl SmoothModel {
    /// As [`SmoothModel::shaped`] for a record with inputs `input`, started by the rule or at
    /// the estimated band fraction `band` (see [`SmoothModel::simulate_from`]).
    ///
    /// # Errors
    /// As [`SmoothModel::core`].
    pub fn shaped_from<K: K2Law<f64>>(
        &self,
        operator: Hysteresis<f64, K>,
        input: &[f64],
        band: Option<f64>,
    ) -> Result<Shaped<K>, Error> {
        let operator = self.start_in(operator, input, band)?;
        Ok(match self.form {
            Form::Operator => Shaped::Operator(ShapedModel::new(
                self.input_shaping,
                operator,
                self.output_shaping,
            )?),
            Form::Stop => Shaped::Stop(Stop::new(
                self.input_shaping,
                operator,
                self.output_shaping,
                self.linear,
            )?),
        })
    }

    /// Any operator with no history (a member of a family around this model, say) inside this
    /// model's shaping and form, ψ_out(operator\[ψ_in(·)\]) or its stop form, started by this
    /// model's start rule for a record whose first input sample is `first_input` (on the
    /// asymptotes of the operator's own k1).
    ///
    /// # Errors
    /// As [`SmoothModel::core`].
    pub fn shaped<K: K2Law<f64>>(
        &self,
        operator: Hysteresis<f64, K>,
        first_input: f64,
    ) -> Result<Shaped<K>, Error> {
        self.shaped_from(operator, &[first_input], None)
    }

    /// Whether the model has an inverse: the operator form does; the stop form does not.
    ///
    /// # Errors
    /// [`ModelError::Invalid`] for the stop form, saying how friction is compensated instead
    /// (feed-forward of its predicted force, docs/fitting.md).
    pub fn invertible(&self) -> Result<(), ModelError> {
        match self.form {
            Form::Operator => Ok(()),
            Form::Stop => Err(ModelError::Invalid(
                "this is a stop-form (friction) model: it predicts the output (force) from the \
                 input (position) and has no inverse; compensate by feeding the predicted force \
                 forward (docs/fitting.md)"
                    .into(),
            )),
        }
    }

    /// The exact compensator (desired output → command) for a record whose first *command*
    /// would be `first_input`; with [`InitialState::Line`] the start is immaterial.
    ///
    /// # Errors
    /// Invalid parameters ([`ModelError::Core`]); the stop form's refusal
    /// ([`SmoothModel::invertible`]).
    pub fn inverse(&self, first_input: f64) -> Result<CoreInverseShapedModel, ModelError> {
        self.invertible()?;
        Ok(self.core(first_input)?.inverse())
    }

    /// The exact compensator for a record whose first *desired output* is `first_desired`,
    /// started where the model's start rule puts the model that produces it: the command x0
    /// with ψ_out(H\[ψ_in(x0)\]) = `first_desired` on the start rule's asymptote (or line).
    ///
    /// # Errors
    /// A desired output beyond a saturating output shaping's range, or invalid parameters
    /// ([`ModelError::Core`]); the stop form's refusal ([`SmoothModel::invertible`]).
    pub fn inverse_from_desired(
        &self,
        first_desired: f64,
    ) -> Result<CoreInverseShapedModel, ModelError> {
        self.invertible()?;
        let u0 = self.output_shaping.invert(first_desired)?;
        // The start point in operator units, built from u0 itself: the compensator's memory then
        // holds exactly the ψ_out⁻¹ of the first desired output, whose first step is then
        // exactly at the reversal (a round trip through ψ_in would leave it an ulp off, a tiny
        // step the wrong way that turns the branch).
        let operator = Hysteresis::with_k2_law(self.k1, self.k2)?;
        let operator = self.initial_state.start_from_output(operator, u0)?;
        // Checks the command exists (a saturating ψ_in has a bounded range), as the core's
        // start of an inverse does: refused in output units, with the first desired outputs
        // the start rule's state reaches.
        if let Some(m) = operator.memory() {
            let d = m.last_output - m.last_input;
            self.input_shaping.invert(m.last_input).map_err(|e| {
                unreachable_output(first_desired, e, &self.output_shaping, |w| Ok(w + d))
            })?;
        }
        Ok(ShapedModel::new(self.input_shaping, operator, self.output_shaping)?.inverse())
    }

    /// The open range (lo, hi) of the model's output when ψ_out saturates (tanh, Langevin): the
    /// outputs approach lo and hi but never reach them, so a desired output outside has no
    /// command. `None` when ψ_out is unbounded (at either end), and for the stop form, whose
    /// linear term is unbounded and which has no inverse.
    #[must_use]
    pub fn output_range(&self) -> Option<(f64, f64)> {
        if self.form == Form::Stop {
            return None;
        }
        bounded_range(&self.output_shaping)
    }

    /// The open range (a, b) of the operator input v = ψ_in(x) when ψ_in saturates (tanh,
    /// Langevin), in operator units: no command gives a or b or beyond, so the operator's
    /// outputs, within k1 of v, lie in (a − k1, b + k1). `None` when ψ_in is unbounded (at
    /// either end).
    #[must_use]
    pub fn input_range(&self) -> Option<(f64, f64)> {
        bounded_range(&self.input_shaping)
    }

    /// The input interval the model was fitted on (input units), read from ψ_in as `hyst fit`
    /// builds it on the normalised input x̂ = (x − centre) / half-span: a saturating ψ_in
    /// (tanh, Langevin) has value 0 and slope 1 per unit of x̂ at the centre, so the interval
    /// is centre ± 1 / ψ_in'(centre); any other ψ_in takes x̂ itself as its shape's argument,
    /// so the interval is the one ψ_in's scaling (`pre_gain`, `pre_offset`) maps to \[−1, 1\].
    /// A saturating ψ_in that never takes the value 0 (written by hand) falls back on the
    /// latter. Every surface that needs the model's range of validity (the saturation limits,
    /// the default input range of adaptation) reads it here.
    #[must_use]
    pub fn fitted_input_interval(&self) -> (f64, f64) {
        let psi = &self.input_shaping;
        if matches!(psi.shape, AnyShaping::Tanh(_) | AnyShaping::Langevin(_)) {
            if let Ok(centre) = psi.invert(0.0) {
                let half = 1.0 / psi.slope(centre);
                if half.is_finite() && half > 0.0 {
                    return (centre - half, centre + half);
                }
            }
        }
        let x = |z: f64| (z - psi.pre_offset) / psi.pre_gain;
        (x(-1.0), x(1.0))
    }

    /// The outputs the model gives over the input interval it was fitted on
    /// ([`SmoothModel::fitted_input_interval`]): ψ_out of every operator output within k1 of
    /// ψ_in over that interval, (lo, hi). `None` for the stop form, and when they are not
    /// finite.
    #[must_use]
    pub fn fitted_output_range(&self) -> Option<(f64, f64)> {
        if self.form == Form::Stop {
            return None;
        }
        let psi = &self.input_shaping;
        let (x_lo, x_hi) = self.fitted_input_interval();
        let (v_lo, v_hi) = (psi.apply(x_lo), psi.apply(x_hi));
        let lo = self.output_shaping.apply(v_lo - self.k1);
        let hi = self.output_shaping.apply(v_hi + self.k1);
        (lo.is_finite() && hi.is_finite() && lo < hi).then_some((lo, hi))
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

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use hyst_core::Langevin;

    #[test]
    fn the_output_envelope_is_the_envelope_of_the_outputs() {
        let psi_out = ScaledShaping::new(
            0.8,
            0.3,
            AnyShaping::Langevin(Langevin::new(1.0, 1.0).unwrap()),
            2.5,
            -1.0,
        )
        .unwrap();
        for form in [Form::Operator, Form::Stop] {
            let model = SmoothModel {
                k1: 0.2,
                k2: AnyK2Law::Constant { value: 6.0 },
                input_shaping: ScaledShaping::identity(),
                output_shaping: psi_out,
                initial_state: InitialState::Rising,
                form,
                linear: if form == Form::Stop { 0.7 } else { 0.0 },
                dynamics: None,
                rate: None,
            };
            let v: Vec<f64> = (0..50).map(|i| (f64::from(i) * 0.37).sin()).collect();
            // Five operator outputs per sample around v.
            let members: Vec<Vec<f64>> = (0..5)
                .map(|m| {
                    v.iter()
                        .enumerate()
                        .map(|(i, x)| x + 0.2 * ((f64::from(m) * 1.3 + i as f64 * 0.7).cos()))
                        .collect()
                })
                .collect();
            let mut lower: Vec<f64> = (0..v.len())
                .map(|i| members.iter().map(|u| u[i]).fold(f64::INFINITY, f64::min))
                .collect();
            let mut upper: Vec<f64> = (0..v.len())
                .map(|i| {
                    members
                        .iter()
                        .map(|u| u[i])
                        .fold(f64::NEG_INFINITY, f64::max)
                })
                .collect();
            lower[3] = f64::NAN;
            model.output_envelope(&v, &mut lower, &mut upper).unwrap();
            for i in 0..v.len() {
                let outputs = members.iter().map(|u| model.output(v[i], u[i]));
                let (lo, hi) = outputs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| {
                    (a.min(y), b.max(y))
                });
                if i == 3 {
                    assert!(lower[i].is_nan() && upper[i].is_nan());
                } else {
                    assert_eq!((lower[i], upper[i]), (lo, hi), "{form:?}, sample {i}");
                }
            }
        }
    }
}
