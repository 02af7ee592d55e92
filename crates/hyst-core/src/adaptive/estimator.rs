//! [`Adaptive`]: the recursive estimator (the method is in the module's documentation).

use crate::adaptive::anchor::reanchor;
use crate::adaptive::covariance::Covariance;
use crate::adaptive::settings::{AdaptiveConfig, Parameter, MAX_PARAMETERS as N};
use crate::adaptive::status::{Counts, Status, Tally, Update};

use crate::any_shaping::AnyShaping;
use crate::dual::Dual;
use crate::error::Error;
use crate::k2law::{AffineK2, AnyK2Law, K2Law};
use crate::memory::Memory;
use crate::operator::Operator;
use crate::parametric::Hysteresis;
use crate::real::Real;
use crate::scaled_shaping::ScaledShaping;
use crate::shaped_model::ShapedModel;
use crate::shaping::Shaping;
use crate::start::InitialState;

/// The shaped model an [`Adaptive`] estimator follows: ψ_out ∘ H ∘ ψ_in with scaled shaping
/// functions and any built-in k2 law (a fitted smooth model of the operator form). The shapes
/// are any of the built-in ones (`S` = [`AnyShaping`], the default), or only the affine ones
/// ([`AffineShaping`](crate::AffineShaping): a firmware then links no nonlinear shape).
pub type AdaptiveModel<T, S = AnyShaping<T>> =
    ShapedModel<T, ScaledShaping<T, S>, AnyK2Law<T>, ScaledShaping<T, S>>;

/// The dual numbers of an estimator of width `W`.
type D<T, const W: usize> = Dual<T, W>;

/// A recursive estimator of a shaped model's parameters (k1, k2, output gain and offset; input
/// gain and offset where asked), updated from each pair of command x and measured output y by
/// an extended Kalman filter on the exact sensitivities (see [the module](super)).
///
/// `no_std`, no allocation, `f32` or `f64`. `W` is the width of the dual numbers: at least the
/// number of adapted parameters (the default, [`MAX_PARAMETERS`](super::MAX_PARAMETERS) = 6,
/// takes any set; `Adaptive<T, 4>` takes up to four, the default set, a quarter faster and
/// smaller).
///
/// # Examples
/// A truth whose output gain is 20 % above the fitted model's: the estimator finds it.
/// ```
/// use hyst_core::adaptive::{Adaptive, AdaptiveConfig, AdaptiveModel, Parameter};
/// use hyst_core::{AnyK2Law, Hysteresis, InitialState, Operator, ScaledShaping, ShapedModel};
/// # fn main() -> Result<(), hyst_core::Error> {
/// let fitted: AdaptiveModel<f64> = ShapedModel::new(
///     ScaledShaping::identity(),
///     Hysteresis::with_k2_law(0.2, AnyK2Law::Constant { value: 8.0 })?,
///     ScaledShaping::identity(),
/// )?;
/// let mut out = *fitted.output_shaping();
/// out.post_gain = 1.2;
/// let mut truth: AdaptiveModel<f64> =
///     ShapedModel::new(ScaledShaping::identity(), *fitted.operator(), out)?;
///
/// let mut a = Adaptive::new(&fitted, InitialState::Line, AdaptiveConfig::new(1e-3))?;
/// for k in 0..20_000 {
///     let x = (k as f64 * 0.01).sin();
///     let y = truth.step(x);
///     a.update(x, y);
/// }
/// assert!((a.value(Parameter::Gain) - 1.2).abs() < 0.01);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Adaptive<T: Real, const W: usize = N, S = AnyShaping<T>> {
    fitted: AdaptiveModel<T, S>,
    config: AdaptiveConfig<T>,
    /// The slot (0 to W − 1) of each adapted parameter in θ, the duals and P; W for one that
    /// does not adapt (every lookup of that slot then finds nothing).
    slot: [usize; N],
    /// The parameter in each slot.
    kind: [Parameter; W],
    /// Relative parameters, by slot: value = fitted · (1 + θ), or fitted + θ · scale for an
    /// offset.
    theta: [T; W],
    /// The scale of each parameter's θ (by parameter): the fitted value, or a half-width for
    /// an offset.
    scale: [T; N],
    p: Covariance<T, W>,
    operator: Hysteresis<D<T, W>, AnyK2Law<D<T, W>>>,
    start: InitialState,
    last_v: Option<T>,
    travel: T,
    /// Whether the model has met a reversal since it started (before, its state is the start
    /// rule's guess, and a prediction error says as much about that guess as about θ).
    settled: bool,
    /// Whether the memory is anchored for the current parameters ([`Adaptive::anchor`]).
    anchored: bool,
    counts: Tally,
}

impl<T: Real> Adaptive<T> {
    /// An estimator of any set of parameters (width 6) starting from `fitted`'s parameters and
    /// memory (a model with no history starts by `start`, the model file's start rule, at its
    /// first sample). [`Adaptive::of_width`] builds a narrower one.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a bad setting ([`AdaptiveConfig::validate`]) or for no
    /// parameter to adapt.
    pub fn new(
        fitted: &AdaptiveModel<T>,
        start: InitialState,
        config: AdaptiveConfig<T>,
    ) -> Result<Self, Error> {
        Self::of_width(fitted, start, config)
    }
}

impl<T: Real, const W: usize, S: Shaping<T> + Copy> Adaptive<T, W, S> {
    /// As [`Adaptive::new`], with duals of width `W`: `Adaptive::<f64, 4>::of_width(…)` for
    /// up to four parameters (the default set k1, k2, gain, offset).
    ///
    /// # Errors
    /// As [`Adaptive::new`]; also [`Error::InvalidParameter`] for more parameters than `W`.
    pub fn of_width(
        fitted: &AdaptiveModel<T, S>,
        start: InitialState,
        config: AdaptiveConfig<T>,
    ) -> Result<Self, Error> {
        config.validate()?;
        let n = config.parameters.len();
        if n == 0 || n > W {
            return Err(Error::InvalidParameter {
                name: "parameters",
                // Through T: a usize to f64 conversion is soft double on an f32-only FPU.
                value: T::from_usize(n).as_f64(),
                expected: "1 to W (the width; 6 for Adaptive::new) of k1, k2, gain, offset, \
                           input_gain, input_offset",
            });
        }
        let mut slot = [W; N];
        let mut kind = [Parameter::K1; W];
        for (j, p) in config.parameters.iter().enumerate() {
            if let (Some(s), Some(k)) = (slot.get_mut(p.index()), kind.get_mut(j)) {
                *s = j;
                *k = p;
            }
        }
        let scale = scales(fitted, config.noise);
        let u = config.uncertainty;
        let mut a = Self {
            fitted: *fitted,
            config,
            slot,
            kind,
            theta: [T::zero(); W],
            scale,
            p: Covariance::diagonal(u * u, n),
            operator: Hysteresis::with_k2_law(D::constant(T::one()), constant_law(T::one()))?,
            start,
            last_v: None,
            travel: T::zero(),
            settled: fitted.operator().memory().is_some(),
            anchored: true,
            counts: Tally::default(),
        };
        let memory = fitted.operator().memory().map(|m| lift(&m));
        a.operator = a.dual_operator(&a.theta, memory)?;
        Ok(a)
    }

    /// One sample: the prediction of `y` from `x` with the current parameters, then the update
    /// from the measured `y`. Never fails: a sample that cannot update says why in its
    /// [`Status`] and its count.
    pub fn update(&mut self, x: T, y: T) -> Update<T> {
        let (prediction, status) = self.sample(x, y);
        self.counts.add(status);
        Update { prediction, status }
    }

    fn sample(&mut self, x: T, y: T) -> (T, Status) {
        if !x.is_finite() {
            return (T::nan(), Status::BadInput);
        }
        let reversal = self.operator.memory_ref().map(|m| m.reversal_input.value());
        let Ok((prediction, phi, v)) = self.predict(x) else {
            return (T::nan(), Status::Refused);
        };
        if !self.settled {
            let now = self.operator.memory_ref().map(|m| m.reversal_input.value());
            self.settled = reversal.is_some() && now != reversal;
        }
        if let Some(last) = self.last_v {
            self.travel = self.travel + (v - last).abs();
        }
        self.last_v = Some(v);
        let (lo, hi) = self.config.input_range;
        let status = if x < lo || x > hi {
            Status::OutOfRange
        } else if !y.is_finite() {
            Status::BadOutput
        } else if !self.settled {
            self.travel = T::zero();
            Status::Starting
        } else if self.travel < self.config.rest * self.k1_fitted() {
            Status::Rest
        } else if let Some(phi) = phi {
            self.correct(y - prediction, &phi)
        } else {
            Status::Refused
        };
        (prediction, status)
    }

    /// Steps the dual model on `x`: (ŷ, ∂ŷ/∂θ, v), the gradient `None` when it is beyond the
    /// float range. On error the memory is unchanged.
    fn predict(&mut self, x: T) -> Result<(T, Option<[T; W]>, T), Error> {
        let input = &self.fitted.input_shaping();
        let s_in = input.shape.apply(x * input.pre_gain + input.pre_offset);
        let (gi, ci) = (
            self.value(Parameter::InputGain),
            self.value(Parameter::InputOffset),
        );
        let mut dv = [T::zero(); W];
        self.seed(&mut dv, Parameter::InputGain, s_in);
        self.seed(&mut dv, Parameter::InputOffset, T::one());
        let v = D::new(s_in * gi + ci, dv);
        if self.operator.memory_ref().is_none() {
            let memory = self.start.memory(v, self.operator.k1())?;
            self.operator.restore(memory);
        }
        let before = self.operator.memory();
        let u = self.operator.try_step(v)?;
        let out = self.fitted.output_shaping();
        let z = u.value() * out.pre_gain + out.pre_offset;
        let (s, slope) = out.shape.apply_with_slope(z);
        let (g, c) = (self.value(Parameter::Gain), self.value(Parameter::Offset));
        let prediction = s * g + c;
        if !prediction.is_finite() {
            self.operator.restore(before);
            return Err(Error::NonFiniteOutput {
                input: x.as_f64(),
                output: prediction.as_f64(),
            });
        }
        let dy_du = g * slope * out.pre_gain;
        let mut phi = u.gradient().map(|d| dy_du * d);
        self.seed(&mut phi, Parameter::Gain, s);
        self.seed(&mut phi, Parameter::Offset, T::one());
        if !phi.iter().all(|p| p.is_finite()) {
            // Sensitivities beyond the float range: no update from this sample.
            self.forget_sensitivities();
            return Ok((prediction, None, v.value()));
        }
        Ok((prediction, Some(phi), v.value()))
    }

    /// The memory keeps its values and starts its gradients afresh (the next reversals rebuild
    /// them): after sensitivities beyond the float range.
    #[inline(never)]
    fn forget_sensitivities(&mut self) {
        if let Some(m) = self.operator.memory_mut() {
            *m = lift(&lower(m));
        }
    }

    /// Adds ∂/∂θ_p = `d` · (p's scale) to `grad` if p adapts.
    fn seed(&self, grad: &mut [T; W], p: Parameter, d: T) {
        let i = p.index();
        let j = self.slot.get(i).copied().unwrap_or(W);
        if let (Some(g), Some(s)) = (grad.get_mut(j), self.scale.get(i)) {
            *g = *g + d * *s;
        }
    }

    /// The Kalman filter's time and measurement update for the prediction error `e`.
    fn correct(&mut self, e: T, phi: &[T; W]) -> Status {
        let c = self.config;
        let q = c.drift * c.drift * self.travel / self.k1_fitted();
        self.travel = T::zero();
        self.p.grow(q, self.config.parameters.len());
        let h = self.p.times(phi);
        let d = c.noise * c.noise + dot(phi, &h);
        if d <= T::zero() || !d.is_finite() {
            // Sensitivities too large to square.
            self.forget_sensitivities();
            return Status::Refused;
        }
        // Clipped at 5 σ of the innovation (the square root only for a sample beyond it).
        let e = if e * e > T::from_f64(25.0) * d {
            let bound = T::from_f64(5.0) * d.sqrt();
            e.max(-bound).min(bound)
        } else {
            e
        };
        if e.abs() <= c.dead_zone {
            return Status::DeadZone;
        }
        let gain = e / d;
        let mut delta = h.map(|hi| hi * gain);
        let largest = delta.iter().fold(T::zero(), |m, x| m.max(x.abs()));
        if largest > c.step {
            let f = c.step / largest;
            delta = delta.map(|x| x * f);
        }
        let mut theta = self.theta;
        for (i, (t, dt)) in theta.iter_mut().zip(delta.iter()).enumerate() {
            *t = self.clamp(i, *t + *dt);
        }
        if self.take(&theta).is_err() {
            return Status::Refused;
        }
        self.theta = theta;
        let cap = c.cap();
        let cap = cap * cap;
        self.p.update(&h, d, cap);
        Status::Updated
    }

    /// θ of slot `j` kept in its range.
    fn clamp(&self, j: usize, t: T) -> T {
        let r = self.config.range;
        let offset = self.kind.get(j).is_some_and(|p| p.is_offset());
        let (lo, hi) = if offset {
            (-r, r)
        } else {
            (r.recip() - T::one(), r - T::one())
        };
        if t.is_nan() {
            T::zero()
        } else {
            t.max(lo).min(hi)
        }
    }

    /// k1 and the k2 law at θ, as duals seeded for the adapted parameters.
    fn dual_parameters(&self, theta: &[T; W]) -> (D<T, W>, AnyK2Law<D<T, W>>) {
        let op = self.fitted.operator();
        let mut gk1 = [T::zero(); W];
        self.seed(&mut gk1, Parameter::K1, T::one());
        let k1 = D::new(self.at(theta, Parameter::K1), gk1);
        let f = T::one() + self.theta_of(theta, Parameter::K2);
        // Each coefficient c of the law is c · (1 + θ_k2): its gradient is c in that slot.
        let mut gk2 = [T::zero(); W];
        if let Some(g) = self
            .slot
            .get(Parameter::K2.index())
            .and_then(|&j| gk2.get_mut(j))
        {
            *g = T::one();
        }
        (k1, scaled_law(op.k2_law(), f, gk2))
    }

    /// The dual operator at θ with `memory` (as given: it is the fitted one or none).
    fn dual_operator(
        &self,
        theta: &[T; W],
        memory: Option<Memory<D<T, W>>>,
    ) -> Result<Hysteresis<D<T, W>, AnyK2Law<D<T, W>>>, Error> {
        let (k1, law) = self.dual_parameters(theta);
        let mut h = Hysteresis::with_k2_law(k1, law)?;
        h.restore(memory);
        Ok(h)
    }

    /// Takes θ into the dual operator; its memory is re-anchored when a compensator next asks
    /// for a command ([`Adaptive::anchor`]).
    fn take(&mut self, theta: &[T; W]) -> Result<(), Error> {
        let (k1, law) = self.dual_parameters(theta);
        self.operator.set_parameters(k1, law)?;
        self.anchored = false;
        Ok(())
    }

    /// Re-anchors the memory for the current parameters, if they changed since it was last:
    /// the reversal output moves so that the branch passes through the last point
    /// (`anchor::reanchor`), so that the command a compensator computes from it does not jump. The
    /// estimate alone does not need it (its predictions are as good either way): only
    /// [`AdaptiveInverse::step`](super::AdaptiveInverse::step) calls it, once per
    /// command.
    pub fn anchor(&mut self) {
        if self.anchored {
            return;
        }
        self.anchored = true;
        let k1 = self.operator.k1();
        let k2 = self
            .operator
            .memory_ref()
            .map(|m| self.operator.k2_law().k2(m.last_input));
        if let (Some(m), Some(k2)) = (self.operator.memory_mut(), k2) {
            reanchor(m, k1, k2);
        }
    }

    /// Starts a new record: the model forgets its history (it starts again by its start rule
    /// at the next sample), the parameters and their covariance stay.
    pub fn restart(&mut self) {
        self.operator.restore(None);
        self.last_v = None;
        self.travel = T::zero();
        self.settled = false;
    }

    /// Back to the fitted parameters, their initial uncertainty and no history (a separate
    /// experiment); the counts stay.
    pub fn reset(&mut self) {
        let u = self.config.uncertainty;
        self.theta = [T::zero(); W];
        self.p = Covariance::diagonal(u * u, self.config.parameters.len());
        self.restart();
        // The fitted parameters were taken before: the operator at θ = 0 is valid.
        if let Ok(op) = self.dual_operator(&self.theta, None) {
            self.operator = op;
        }
    }

    /// The fitted value of parameter `p`: where the estimator started.
    #[must_use]
    pub fn fitted_value(&self, p: Parameter) -> T {
        self.at(&[T::zero(); W], p)
    }

    /// The current value of parameter `p` (its fitted value if it does not adapt).
    #[must_use]
    pub fn value(&self, p: Parameter) -> T {
        self.at(&self.theta, p)
    }

    /// θ of parameter `p` (0 if it does not adapt).
    fn theta_of(&self, theta: &[T; W], p: Parameter) -> T {
        let j = self.slot.get(p.index()).copied().unwrap_or(W);
        theta.get(j).copied().unwrap_or_else(T::zero)
    }

    fn at(&self, theta: &[T; W], p: Parameter) -> T {
        let t = self.theta_of(theta, p);
        let s = self.scale.get(p.index()).copied().unwrap_or_else(T::zero);
        let (input, output) = (self.fitted.input_shaping(), self.fitted.output_shaping());
        match p {
            Parameter::K1 => self.k1_fitted() * (T::one() + t),
            Parameter::K2 => self.fitted.operator().k2_law().at_zero() * (T::one() + t),
            Parameter::Gain => output.post_gain * (T::one() + t),
            Parameter::Offset => output.post_offset + t * s,
            Parameter::InputGain => input.post_gain * (T::one() + t),
            Parameter::InputOffset => input.post_offset + t * s,
        }
    }

    /// The old name of [`Adaptive::std_error`].
    #[deprecated(note = "renamed std_error")]
    #[must_use]
    pub fn sigma(&self, p: Parameter) -> T {
        self.std_error(p)
    }

    /// The standard error σ of parameter `p`'s estimate (its units), from the filter's
    /// covariance.
    #[must_use]
    pub fn std_error(&self, p: Parameter) -> T {
        let i = p.index();
        let j = self.slot.get(i).copied().unwrap_or(W);
        self.p.sigma(j) * self.scale.get(i).copied().unwrap_or_else(T::zero)
    }

    fn k1_fitted(&self) -> T {
        self.fitted.operator().k1()
    }

    /// The model with the current parameters and memory: what the compensator inverts.
    ///
    /// # Errors
    /// None in practice (the parameters were checked when they were taken); the core's own
    /// checks of a model's parameters.
    pub fn model(&self) -> Result<AdaptiveModel<T, S>, Error> {
        let op = self.fitted.operator();
        let f = T::one() + self.theta_of(&self.theta, Parameter::K2);
        let law = scaled_law(op.k2_law(), f, [T::zero(); W]);
        let law = plain_law(&law);
        let mut h = Hysteresis::with_k2_law(self.value(Parameter::K1), law)?;
        h.restore(self.operator.memory().map(|m| lower(&m)));
        let mut input = *self.fitted.input_shaping();
        input.post_gain = self.value(Parameter::InputGain);
        input.post_offset = self.value(Parameter::InputOffset);
        let mut output = *self.fitted.output_shaping();
        output.post_gain = self.value(Parameter::Gain);
        output.post_offset = self.value(Parameter::Offset);
        Ok(ShapedModel::from_parts(input, h, output))
    }

    /// The model as fitted (with the memory it was given).
    #[must_use]
    pub fn fitted(&self) -> &AdaptiveModel<T, S> {
        &self.fitted
    }

    /// The start rule of a model with no history.
    #[must_use]
    pub fn start(&self) -> InitialState {
        self.start
    }

    /// The settings.
    #[must_use]
    pub fn config(&self) -> &AdaptiveConfig<T> {
        &self.config
    }

    /// How many samples had each status.
    #[must_use]
    pub fn counts(&self) -> Counts {
        self.counts.counts()
    }

    /// The operator's memory (operator units), `None` before the first sample.
    #[must_use]
    pub fn memory(&self) -> Option<Memory<T>> {
        self.operator.memory().map(|m| lower(&m))
    }
}

/// The scale of each θ: the fitted value for k1, k2 and the gains; for the output offset the
/// loop's half-width in output units, |ψ_out(k1) − ψ_out(−k1)| / 2 (at least `noise`); for
/// the input offset k1.
fn scales<T: Real, S: Shaping<T>>(m: &AdaptiveModel<T, S>, noise: T) -> [T; N] {
    let k1 = m.operator().k1();
    let out = m.output_shaping();
    let half = ((out.apply(k1) - out.apply(-k1)) / T::from_f64(2.0)).abs();
    let half = if half.is_finite() && half > noise {
        half
    } else {
        noise
    };
    [
        k1,
        m.operator().k2_law().at_zero(),
        out.post_gain,
        half,
        m.input_shaping().post_gain,
        k1,
    ]
}

fn dot<T: Real, const W: usize>(a: &[T; W], b: &[T; W]) -> T {
    a.iter()
        .zip(b.iter())
        .fold(T::zero(), |s, (x, y)| s + *x * *y)
}

fn constant_law<T: Real, const W: usize>(k2: T) -> AnyK2Law<D<T, W>> {
    AnyK2Law::Constant {
        value: D::constant(k2),
    }
}

/// The law scaled by `f` (its value at θ), each coefficient c with gradient c · `grad`.
fn scaled_law<T: Real, const W: usize>(law: &AnyK2Law<T>, f: T, grad: [T; W]) -> AnyK2Law<D<T, W>> {
    let scaled = |c: T| D::new(c * f, grad.map(|g| g * c));
    match law {
        AnyK2Law::Constant { value } => AnyK2Law::Constant {
            value: scaled(*value),
        },
        AnyK2Law::Affine(a) => AnyK2Law::Affine(AffineK2 {
            at_zero: scaled(a.at_zero),
            slope: scaled(a.slope),
            min: scaled(a.min),
            max: scaled(a.max),
        }),
    }
}

fn plain_law<T: Real, const W: usize>(law: &AnyK2Law<D<T, W>>) -> AnyK2Law<T> {
    match law {
        AnyK2Law::Constant { value } => AnyK2Law::Constant {
            value: value.value(),
        },
        AnyK2Law::Affine(a) => AnyK2Law::Affine(AffineK2 {
            at_zero: a.at_zero.value(),
            slope: a.slope.value(),
            min: a.min.value(),
            max: a.max.value(),
        }),
    }
}

fn lift<T: Real, const W: usize>(m: &Memory<T>) -> Memory<D<T, W>> {
    Memory {
        reversal_input: D::constant(m.reversal_input),
        reversal_output: D::constant(m.reversal_output),
        direction: m.direction,
        last_input: D::constant(m.last_input),
        last_output: D::constant(m.last_output),
    }
}

fn lower<T: Real, const W: usize>(m: &Memory<D<T, W>>) -> Memory<T> {
    Memory {
        reversal_input: m.reversal_input.value(),
        reversal_output: m.reversal_output.value(),
        direction: m.direction,
        last_input: m.last_input.value(),
        last_output: m.last_output.value(),
    }
}
