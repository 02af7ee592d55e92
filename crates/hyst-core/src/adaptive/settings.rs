//! The estimator's settings: which parameters adapt ([`Parameter`], [`Parameters`]) and how
//! ([`AdaptiveConfig`]).

use crate::real::Real;

/// The most parameters an estimator follows.
pub const MAX_PARAMETERS: usize = 6;

/// One parameter an [`Adaptive`](crate::adaptive::Adaptive) estimator can follow. The names ([`Parameter::name`]) are the
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
    pub(crate) fn is_offset(self) -> bool {
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
    /// [`crate::error::Error::InvalidParameter`] naming the field and its value.
    pub fn validate(&self) -> Result<(), crate::error::Error> {
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
            return Err(invalid("input_range", lo, "min <= max"));
        }
        Ok(())
    }
}

fn non_negative<T: Real>(name: &'static str, x: T) -> Result<(), crate::error::Error> {
    if x >= T::zero() && x.is_finite() {
        Ok(())
    } else {
        Err(invalid(name, x, "finite and ≥ 0"))
    }
}

fn invalid<T: Real>(name: &'static str, x: T, expected: &'static str) -> crate::error::Error {
    crate::error::Error::InvalidParameter {
        name,
        value: x.as_f64(),
        expected,
    }
}
