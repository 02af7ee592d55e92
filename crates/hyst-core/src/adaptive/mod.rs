//! Online adaptation: a recursive estimator that follows a drifting actuator's parameters from
//! each new pair of command x and measured output y, and the compensator that uses them.
//!
//! The model is a shaped model y = ψ_out(H(k1, k2)\[ψ_in(x)\]) (Section 4.3) with
//! ψ = `post_gain` · shape(`pre_gain` · x + `pre_offset`) + `post_offset` ([`ScaledShaping`]).
//! The estimator follows up to six of its parameters ([`Parameter`]): k1, k2 (a constant k2, or
//! an input-dependent law scaled as a whole), the output gain and offset (ψ_out's `post_gain`
//! and `post_offset`) and, where asked, the input gain and offset (ψ_in's).
//!
//! # Method: an extended Kalman filter on the exact sensitivities
//!
//! The parameters are a random walk θ\[k\] = θ\[k−1\] + w, in relative units (each parameter is
//! its fitted value times 1 + θ_i; an offset is its fitted value plus θ_i times the loop's
//! half-width). Each sample:
//!
//! 1. **Prediction.** The model steps once on [`Dual`] numbers: the one-step prediction ŷ with
//!    parameters before the update, and φ = ∂ŷ/∂θ, exact, through the operator's memory (the
//!    reversal point carries its own sensitivities: Definition 2.1 on duals).
//! 2. **Start.** Until the model meets its first reversal after a start (its first sample, or
//!    [`Adaptive::restart`] for a new record), its state is the start rule's guess and the
//!    prediction error says as much about that guess as about the parameters: nothing is
//!    updated.
//! 3. **Excitation gate.** The input's travel since the last update, |Δv| summed in operator
//!    units, must reach `rest` · k1. Until it does, nothing is updated and nothing grows: at a
//!    constant input the parameters do not move at all, and a slowly creeping input updates
//!    them as often as it moves (a rest of 10⁶ samples leaves them bit-identical).
//! 4. **Time update.** P ← P + (`drift`² · travel / k1) I on the adapted parameters: the
//!    uncertainty grows with the input travel since the last update, not with time, so the
//!    sample rate does not change the behaviour.
//! 5. **Measurement update.** With R = `noise`², h = P φ, d = R + φᵀh: the innovation
//!    e = y − ŷ is clipped to ±5 √d (one wild sample cannot throw the parameters), a dead zone
//!    |e| ≤ `dead_zone` skips the update, θ ← θ + h e / d with the step scaled so that no
//!    parameter moves by more than `step` (relative) per update, P ← P − h hᵀ / d.
//! 6. **Ranges.** Each gain, k1 and k2 stays in \[fitted / `range`, fitted · `range`\] (so > 0),
//!    each offset within ± `range` half-widths of its fitted value, and P's diagonal never
//!    exceeds the cap, max(`uncertainty`, 0.1)² (a congruence scaling, which keeps P positive semidefinite): no
//!    burst when excitation returns after a long rest. A change that the core refuses (k1 k2
//!    below the float resolution) is not taken.
//!
//! The memory stays in operator units across an update. Before a compensator computes a
//! command the memory is re-anchored for the current parameters (`anchor`): the last point
//! stays (moved onto the band's edge if a smaller k1 leaves it outside) and the reversal output
//! moves so that the new branch passes through it. The command for the desired output last met
//! is then the last command wherever the branch still depends on its reversal point: switching
//! parameters adds no jump to the command ([`AdaptiveCompensator`]).
//!
//! Bad samples: a non-finite x, or one outside `input_range`, skips the update (and a
//! non-finite x leaves the memory unchanged); a non-finite y skips it too; each is counted
//! ([`Counts`]). Nothing is corrupted.

mod anchor;
mod compensator;
mod covariance;
mod estimator;

pub use compensator::AdaptiveCompensator;
pub use estimator::{Adaptive, AdaptiveModel};

use crate::real::Real;

/// The most parameters an estimator follows.
pub const MAX_PARAMETERS: usize = 6;

/// One parameter an [`Adaptive`] estimator can follow. The names ([`Parameter::name`]) are the
/// command line's, Python's and the CSV columns'.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Parameter {
    /// k1, the loop's half-width (operator units), > 0.
    K1,
    /// k2 (1 / operator units), > 0; an input-dependent law is scaled as a whole.
    K2,
    /// ψ_out's `post_gain` (output units), > 0.
    Gain,
    /// ψ_out's `post_offset` (output units).
    Offset,
    /// ψ_in's `post_gain` (operator units), > 0.
    InputGain,
    /// ψ_in's `post_offset` (operator units).
    InputOffset,
}

impl Parameter {
    /// Every parameter, in the order of their index.
    pub const ALL: [Parameter; MAX_PARAMETERS] = [
        Parameter::K1,
        Parameter::K2,
        Parameter::Gain,
        Parameter::Offset,
        Parameter::InputGain,
        Parameter::InputOffset,
    ];

    /// The name: `k1`, `k2`, `gain`, `offset`, `input_gain`, `input_offset`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Parameter::K1 => "k1",
            Parameter::K2 => "k2",
            Parameter::Gain => "gain",
            Parameter::Offset => "offset",
            Parameter::InputGain => "input_gain",
            Parameter::InputOffset => "input_offset",
        }
    }

    /// The parameter of a name ([`Parameter::name`]).
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|p| p.name() == name)
    }

    /// Its index, 0 to 5 (the order of [`Parameter::ALL`]).
    #[must_use]
    pub fn index(self) -> usize {
        self as usize
    }

    /// Whether the parameter is an offset (moved by a multiple of a scale, not relatively).
    fn is_offset(self) -> bool {
        matches!(self, Parameter::Offset | Parameter::InputOffset)
    }
}

/// A set of [`Parameter`]s.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Parameters(u8);

impl Parameters {
    /// k1, k2, the output gain and the output offset: the default.
    pub const DEFAULT: Parameters = Parameters(0b1111);
    /// None.
    pub const NONE: Parameters = Parameters(0);

    /// This set with `p` added.
    #[must_use]
    pub fn with(self, p: Parameter) -> Self {
        Parameters(self.0 | (1 << p.index()))
    }

    /// Whether `p` is in the set.
    #[must_use]
    pub fn contains(self, p: Parameter) -> bool {
        self.0 & (1 << p.index()) != 0
    }

    /// The parameters in the set, in the order of [`Parameter::ALL`].
    pub fn iter(self) -> impl Iterator<Item = Parameter> {
        Parameter::ALL
            .into_iter()
            .filter(move |p| self.contains(*p))
    }

    /// How many.
    #[must_use]
    pub fn len(self) -> usize {
        self.0.count_ones() as usize
    }

    /// Whether the set is empty.
    #[must_use]
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }
}

impl Default for Parameters {
    fn default() -> Self {
        Parameters::DEFAULT
    }
}

impl FromIterator<Parameter> for Parameters {
    fn from_iter<I: IntoIterator<Item = Parameter>>(iter: I) -> Self {
        iter.into_iter().fold(Parameters::NONE, Parameters::with)
    }
}

/// The estimator's settings. [`AdaptiveConfig::new`] gives the defaults for a noise level.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdaptiveConfig<T> {
    /// The parameters that adapt (default: k1, k2, gain, offset).
    pub parameters: Parameters,
    /// σ of the measurement noise (output units), > 0: the filter's R = noise².
    pub noise: T,
    /// How fast the parameters may drift: the σ of their relative random walk per k1 of input
    /// travel (default 1e-3: about 1 % over 100 loops of ±5 k1), ≥ 0.
    pub drift: T,
    /// σ of the fitted parameters' relative error at the start (default 0.01: a model fitted
    /// on the actuator, whose parameters the fit's standard errors put well within 1 %), > 0.
    /// Later σ grow with the drift up to a cap ([`AdaptiveConfig::cap`]).
    pub uncertainty: T,
    /// The input travel (in units of k1) that must accumulate before an update (default 1e-3),
    /// ≥ 0. At a constant input nothing moves.
    pub rest: T,
    /// The largest relative change of any parameter in one update (default 0.01), > 0.
    pub step: T,
    /// Each gain, k1 and k2 stays within \[fitted / range, fitted · range\], each offset within
    /// ± range half-widths of the loop of its fitted value (default 4), > 1.
    pub range: T,
    /// Prediction errors of at most this size (output units) do not update (default 0), ≥ 0.
    pub dead_zone: T,
    /// Commands outside \[min, max\] (input units) do not update (default: the whole line).
    pub input_range: (T, T),
}

impl<T: Real> AdaptiveConfig<T> {
    /// The defaults (see each field) for measurements with noise σ `noise` (output units).
    #[must_use]
    pub fn new(noise: T) -> Self {
        Self {
            parameters: Parameters::DEFAULT,
            noise,
            drift: T::from_f64(1e-3),
            uncertainty: T::from_f64(0.01),
            rest: T::from_f64(1e-3),
            step: T::from_f64(0.01),
            range: T::from_f64(4.0),
            dead_zone: T::zero(),
            input_range: (T::neg_infinity(), T::infinity()),
        }
    }

    /// The cap of every parameter's σ (relative): the larger of `uncertainty` and 0.1.
    #[must_use]
    pub fn cap(&self) -> T {
        self.uncertainty.max(T::from_f64(0.1))
    }

    /// Checks every field.
    ///
    /// # Errors
    /// [`crate::Error::InvalidParameter`] naming the field and its value.
    pub fn validate(&self) -> Result<(), crate::Error> {
        use crate::error::positive;
        positive("noise", self.noise)?;
        positive("uncertainty", self.uncertainty)?;
        positive("step", self.step)?;
        non_negative("drift", self.drift)?;
        non_negative("rest", self.rest)?;
        non_negative("dead_zone", self.dead_zone)?;
        if self.range <= T::one() || !self.range.is_finite() {
            return Err(invalid("range", self.range, "finite and > 1"));
        }
        let (lo, hi) = self.input_range;
        if lo.is_nan() || hi.is_nan() || lo > hi {
            return Err(invalid("input_range", lo, "min ≤ max, not NaN"));
        }
        Ok(())
    }
}

fn non_negative<T: Real>(name: &'static str, x: T) -> Result<(), crate::Error> {
    if x >= T::zero() && x.is_finite() {
        Ok(())
    } else {
        Err(invalid(name, x, "finite and ≥ 0"))
    }
}

fn invalid<T: Real>(name: &'static str, x: T, expected: &'static str) -> crate::Error {
    crate::Error::InvalidParameter {
        name,
        value: x.as_f64(),
        expected,
    }
}

/// What one sample did to the estimator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Status {
    /// The parameters were updated.
    Updated,
    /// The input has not travelled `rest` · k1 since the last update: nothing changed.
    Rest,
    /// The model has not met a reversal since it started (at its first sample, or after
    /// [`Adaptive::restart`]): its state is still the start rule's guess, so nothing is learnt.
    Starting,
    /// The prediction error was within the dead zone: nothing changed.
    DeadZone,
    /// The command was not finite: the sample was skipped, the memory is unchanged.
    BadInput,
    /// The command was outside `input_range`: the model stepped, the parameters did not.
    OutOfRange,
    /// The measurement was not finite: the model stepped, the parameters did not.
    BadOutput,
    /// The model could not evaluate the sample or take the update (a float overflow, a
    /// product k1 k2 below the float resolution): the parameters did not change.
    Refused,
}

/// One sample's result: the one-step prediction (parameters before the update) and what
/// happened.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Update<T> {
    /// ŷ, the prediction of the measured output (output units); NaN for [`Status::BadInput`].
    pub prediction: T,
    /// What the sample did.
    pub status: Status,
}

/// How many samples had each [`Status`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Counts {
    /// [`Status::Updated`].
    pub updated: u64,
    /// [`Status::Rest`].
    pub rest: u64,
    /// [`Status::Starting`].
    pub starting: u64,
    /// [`Status::DeadZone`].
    pub dead_zone: u64,
    /// [`Status::BadInput`].
    pub bad_input: u64,
    /// [`Status::OutOfRange`].
    pub out_of_range: u64,
    /// [`Status::BadOutput`].
    pub bad_output: u64,
    /// [`Status::Refused`].
    pub refused: u64,
}

impl Counts {
    fn add(&mut self, s: Status) {
        let c = match s {
            Status::Updated => &mut self.updated,
            Status::Rest => &mut self.rest,
            Status::Starting => &mut self.starting,
            Status::DeadZone => &mut self.dead_zone,
            Status::BadInput => &mut self.bad_input,
            Status::OutOfRange => &mut self.out_of_range,
            Status::BadOutput => &mut self.bad_output,
            Status::Refused => &mut self.refused,
        };
        *c = c.saturating_add(1);
    }

    /// The samples skipped for bad data: [`Status::BadInput`], [`Status::OutOfRange`],
    /// [`Status::BadOutput`].
    #[must_use]
    pub fn skipped(&self) -> u64 {
        self.bad_input
            .saturating_add(self.out_of_range)
            .saturating_add(self.bad_output)
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used, clippy::panic)]
mod tests;
