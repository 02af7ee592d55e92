//! A smooth model with dynamics or a rate term ([`SmoothModel::is_timed`]) run over a timed
//! record, sample by sample: [`TimedRun`] (the model's output) and [`TimedCompensator`]
//! (Lemma 5.1's compensator of its plant). Both use the one discretisation of
//! [`crate::dynamics`], for each step's own length ([`crate::time`]); a static model runs
//! through them exactly as through [`SmoothModel::run_with`].

// Dense matrix kernels read best with explicit indices.
#![allow(clippy::needless_range_loop)]

use hyst_core::compensator::{Compensator, MAX_ORDER};
use hyst_core::{AnyK2Law, Error, Hysteresis, Jet, K2Law, Operator, ScaledShaping, Shaping};

use std::collections::HashMap;

use crate::dynamics::{Discrete, Dynamics, PlantState};
use crate::error::ModelError;
use crate::smooth::{FitReal, Form, SmoothModel};
use crate::time::{is_nominal, TimeSteps};

/// The most discretisations of steps other than the nominal one a run keeps: 4096. A record
/// with more distinct steps computes the others again (the cache is emptied when full).
const CACHE: usize = 4096;

/// A plant's discretisation for each step a run takes ([`crate::time`]): the nominal step's,
/// computed once, and any other step's, computed on first use and kept. With the inverse of
/// each step, for the rate term's backward difference. Without a plant, only the inverses.
#[derive(Clone, Debug)]
struct Discretisations<T> {
    dynamics: Option<Dynamics<T>>,
    nominal: f64,
    at_nominal: Option<Discrete<T>>,
    inverse_nominal: T,
    other: HashMap<u64, (Option<Discrete<T>>, T)>,
}

impl<T: FitReal> Discretisations<T> {
    /// The discretisations of `dynamics` (if any) around the nominal step `nominal` (s).
    fn new(dynamics: Option<Dynamics<T>>, nominal: f64) -> Result<Self, Error> {
        if !(nominal.is_finite() && nominal > 0.0) {
            return Err(Error::InvalidParameter {
                name: "period",
                value: nominal,
                expected: "a finite, positive sample period (s)",
            });
        }
        Ok(Self {
            at_nominal: dynamics.map(|d| d.discretise(nominal)).transpose()?,
            dynamics,
            nominal,
            inverse_nominal: T::from_f64(1.0 / nominal),
            other: HashMap::new(),
        })
    }

    /// The plant's discretisation for a step `h` (s) and 1/h: the nominal step's for a step
    /// taken as it ([`is_nominal`]).
    fn at(&mut self, h: f64) -> Result<(Option<&Discrete<T>>, T), Error> {
        if is_nominal(h, self.nominal) {
            return Ok((self.at_nominal.as_ref(), self.inverse_nominal));
        }
        if !(h.is_finite() && h > 0.0) {
            return Err(Error::InvalidParameter {
                name: "time step",
                value: h,
                expected: "a finite, positive time step (s): time stamps that increase",
            });
        }
        let key = h.to_bits();
        if !self.other.contains_key(&key) {
            let d = self.dynamics.map(|d| d.discretise(h)).transpose()?;
            if self.other.len() >= CACHE {
                self.other.clear();
            }
            self.other.insert(key, (d, T::from_f64(1.0 / h)));
        }
        match self.other.get(&key) {
            Some((d, inverse)) => Ok((d.as_ref(), *inverse)),
            None => Err(Error::InvalidParameter {
                name: "time step",
                value: h,
                expected: "a step whose discretisation is kept",
            }),
        }
    }
}

/// One sample of a [`TimedRun`]: the hysteresis input v (input units, after the plant), the
/// operator output z = H\[ψ_in(v)\] and the model output y.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimedSample<T> {
    /// The hysteresis input v (the plant's output; the command itself without dynamics).
    pub v: T,
    /// The operator output H\[ψ_in(v)\].
    pub z: T,
    /// The model output ψ_out(z) (or the stop form's), plus c·v̇ with a rate term.
    pub y: T,
}

/// A smooth model running over one timed record: the plant (if any) turns each command into v,
/// discretised for each step's length, the hysteresis and shapings give the static output, and
/// the rate term (if any) adds c·v̇ with v̇ the backward difference over the step.
#[derive(Clone, Debug)]
pub struct TimedRun<T = f64> {
    model: SmoothModel<T>,
    operator: Hysteresis<T, AnyK2Law<T>>,
    steps: Discretisations<T>,
    state: PlantState<T>,
    previous: Option<T>,
}

impl<T: FitReal> TimedRun<T> {
    /// The run of `model` over a record of nominal step `period` (s; every step for
    /// [`TimedRun::step`], the steps within [`crate::time::STEP_TOLERANCE`] of it for
    /// [`TimedRun::step_after`]) whose first command is `first`: the plant at rest there, the
    /// operator started by the model's start rule at v = b·first.
    ///
    /// # Errors
    /// A period that is not finite and positive, parameters the core refuses, a first sample
    /// whose start is not finite.
    pub fn new(model: &SmoothModel<T>, period: f64, first: T) -> Result<Self, Error> {
        Self::started(model, period, &[first.as_f64()], None)
    }

    /// The run of `model` over a record of nominal step `period` (s) whose commands are
    /// `input` (the first is enough for the start rule; the first move's direction is read
    /// for an estimated start): the plant at rest at the first command, the operator started
    /// by the model's start rule, or with `band` = Some(b), b ∈ [−1, 1], at a reversal at the
    /// first sample with the operator output v0 + b · k1 heading the way the input first
    /// moves ([`SmoothModel::start_in`]: the record's memory estimated by the fit).
    ///
    /// # Errors
    /// As [`TimedRun::new`]; an empty `input`.
    pub fn started(
        model: &SmoothModel<T>,
        period: f64,
        input: &[f64],
        band: Option<f64>,
    ) -> Result<Self, Error> {
        let Some(&first) = input.first() else {
            return Err(Error::InvalidParameter {
                name: "input",
                value: f64::NAN,
                expected: "a record of at least one sample",
            });
        };
        let first = T::from_f64(first);
        let steps = Discretisations::new(model.dynamics, period)?;
        let state = steps.at_nominal.map_or(
            PlantState {
                x: [first; crate::dynamics::MAX_DYNAMICS],
                u: first,
            },
            |p| p.at_rest(first),
        );
        let v0 = model.dynamics.map_or(first, |d| d.b * first);
        let operator = match band {
            // At rest, v = b u0: the estimated start at v0 (a fitted plant has b = 1).
            Some(_) => {
                let scaled: Vec<f64> = input
                    .iter()
                    .map(|u| model.dynamics.map_or(*u, |d| d.b.as_f64() * u))
                    .collect();
                model.start_in(Hysteresis::with_k2_law(model.k1, model.k2)?, &scaled, band)?
            }
            None => model.initial_state.start(
                Hysteresis::with_k2_law(model.k1, model.k2)?,
                model.input_shaping.apply(v0),
            )?,
        };
        Ok(Self {
            model: *model,
            operator,
            steps,
            state,
            previous: None,
        })
    }

    /// The next sample, for the command `u`, one nominal step after the last.
    ///
    /// # Errors
    /// [`Error::NonFiniteOutput`] (naming the command) when the output is not finite, or the
    /// core's error for the step; the run is then unchanged.
    pub fn step(&mut self, u: T) -> Result<TimedSample<T>, Error> {
        self.step_after(u, self.steps.nominal)
    }

    /// The next sample, for the command `u`, a step of `h` (s) after the last (t_k − t_{k−1};
    /// ignored at the record's first sample, where the run starts at rest).
    ///
    /// # Errors
    /// As [`TimedRun::step`], and a step that is not finite and positive.
    pub fn step_after(&mut self, u: T, h: f64) -> Result<TimedSample<T>, Error> {
        // The plant's state is committed only once the sample succeeds.
        let mut state = self.state;
        let (plant, inverse_step) = match self.previous {
            Some(_) => self.steps.at(h)?,
            None => (None, T::zero()),
        };
        let v = match (plant, self.previous) {
            (Some(d), Some(_)) => d.step(&mut state, u),
            (None, _) if self.model.dynamics.is_some() => state.x[0],
            _ => u,
        };
        let w = self.model.input_shaping.apply(v);
        let before = self.operator.memory();
        let z = self.operator.try_step(w)?;
        let mut y = self.model.output(w, z);
        if let Some(r) = self.model.rate {
            let rate = self
                .previous
                .map_or_else(T::zero, |p| (v - p) * inverse_step);
            y = y + r.c * rate;
        }
        if !y.is_finite() {
            let _ = self.operator.set_memory(before);
            return Err(Error::NonFiniteOutput {
                input: u.as_f64(),
                output: y.as_f64(),
            });
        }
        self.state = state;
        self.previous = Some(v);
        Ok(TimedSample { v, z, y })
    }
}

impl<T: FitReal> SmoothModel<T> {
    /// Runs the model over one record of time steps `steps` (`None` for a record without
    /// time, which only a static model runs) and hands each sample's index and
    /// [`TimedSample`] to `each`. A static model runs exactly as [`SmoothModel::run_with`]
    /// (an estimated start `band` starts the operator's memory, the plant at rest:
    /// [`TimedRun::started`]).
    ///
    /// # Errors
    /// A model with dynamics or a rate term without time steps; otherwise as
    /// [`SmoothModel::simulate`].
    pub fn run_timed(
        &self,
        input: &[f64],
        steps: Option<&TimeSteps>,
        band: Option<f64>,
        mut each: impl FnMut(usize, TimedSample<T>),
    ) -> Result<(), Error> {
        if !self.is_timed() {
            return self.run_with(input, band, |i, z, y| {
                let v = T::from_f64(input.get(i).copied().unwrap_or(f64::NAN));
                each(i, TimedSample { v, z, y });
            });
        }
        let Some(steps) = steps else {
            return Err(Error::InvalidParameter {
                name: "period",
                value: f64::NAN,
                expected: "a timed record (the model has dynamics or a rate term)",
            });
        };
        if input.is_empty() {
            return Ok(());
        }
        let mut run = TimedRun::started(self, steps.nominal(), input, band)?;
        for ((i, x), h) in input
            .iter()
            .enumerate()
            .zip(std::iter::once(steps.nominal()).chain(steps.walk()))
        {
            each(i, run.step_after(T::from_f64(*x), h)?);
        }
        Ok(())
    }
}

/// The core compensator type of a fitted model with dynamics (jets of [`MAX_ORDER`]).
pub type CoreCompensator =
    Compensator<f64, MAX_ORDER, ScaledShaping<f64>, AnyK2Law<f64>, ScaledShaping<f64>>;

/// The samples a compensator needs in the time its desired output takes to cross a corner of
/// the model's loop: 3. With fewer, its commands are no longer what the sampled plant needs:
/// the inverse's derivatives change within a sample near the corners, the commands spike, and
/// the plant driven by them strays from the desired output, in proportion to the sample period
/// (`hyst run --inverse` warns, naming the sample period it needs: [`Corner::needed_period`]).
pub const CORNER_SAMPLES: f64 = 3.0;

/// The fastest corner of the model's loop a [`TimedCompensator`] has met. After a reversal (or
/// at the start rule's reversal point) the slope of H⁻¹ exceeds its asymptote's by
/// k2 M* e^(−k2 ũd) (eq. 4): a corner 1/k2 wide in the operator's output units. Its time is
/// that width over the desired output's rate in those units (through ψ_out⁻¹):
/// τ = 1 / (k2 |d/dt ψ_out⁻¹(y_d)|).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Corner {
    /// τ (s).
    pub time: f64,
    /// The compensator's sample (counted from 0) where it was met.
    pub sample: usize,
}

impl Corner {
    /// The longest sample period that resolves it: τ / [`CORNER_SAMPLES`] (s).
    #[must_use]
    pub fn needed_period(&self) -> f64 {
        self.time / CORNER_SAMPLES
    }

    /// Whether the sample period `h` (s) resolves it (h ≤ [`Corner::needed_period`]).
    #[must_use]
    pub fn resolved_by(&self, h: f64) -> bool {
        h <= self.needed_period()
    }

    /// The warning of a compensator whose sample period `h` (s), named `period` ("the period"),
    /// does not resolve it: the period it needs. `number` writes each value (4 significant
    /// digits, as every report).
    #[must_use]
    pub fn warning(&self, h: f64, period: &str, number: impl Fn(f64) -> String) -> String {
        format!(
            "the desired output crosses a corner of the model's loop (1/k2 wide in the \
             operator's output units) in {} s there, less than {CORNER_SAMPLES} samples of \
             {period} {} s: the commands spike near the loop's corners, and the plant driven by \
             them strays from the desired output in proportion to the period; sample at most \
             every {} s (or slow the desired output down)",
            number(self.time),
            number(h),
            number(self.needed_period()),
        )
    }
}

/// Lemma 5.1's compensator of a model with dynamics: for the desired output y_d and its first
/// n time derivatives, the command u = (1/b) Σ a_i dⁱ/dtⁱ x, x = ψ_in⁻¹(H⁻¹\[ψ_out⁻¹(y_d)\])
/// (a_0 = 1), with the derivatives of x by Taylor arithmetic through the inverse. It keeps the
/// fastest corner of the loop it met ([`TimedCompensator::fastest_corner`]), which a sample
/// period must resolve for the commands to be exact near corners.
#[derive(Clone, Debug)]
pub struct TimedCompensator {
    compensator: CoreCompensator,
    order: usize,
    samples: usize,
    fastest: Option<Corner>,
}

impl TimedCompensator {
    /// The compensator of `model` for a record whose first desired output is `first`, started
    /// from the state the model's start rule implies for it.
    ///
    /// # Errors
    /// [`ModelError::Invalid`] for a model without dynamics, with a rate term or of the stop
    /// form (with the reason), and the core's errors for the first desired output.
    pub fn new(model: &SmoothModel, first: f64) -> Result<Self, ModelError> {
        Self::check(model)?;
        let Some(dynamics) = model.dynamics else {
            return Err(ModelError::Invalid("the model has no dynamics".into()));
        };
        let inverse = model.inverse_from_desired(first)?;
        let compensator = Compensator::with_order(inverse, dynamics.b, dynamics.a())?;
        Ok(Self {
            compensator,
            order: dynamics.order(),
            samples: 0,
            fastest: None,
        })
    }

    /// Whether `model` has a compensator: a model with dynamics, of the operator form, without
    /// a rate term.
    ///
    /// # Errors
    /// [`ModelError::Invalid`] saying why not, the first that applies of: the stop form (no
    /// inverse at all), a rate term (none hyst can compute), no dynamics (the exact inverse is
    /// the compensator: only then is that the advice).
    pub fn check(model: &SmoothModel) -> Result<(), ModelError> {
        if model.form == Form::Stop {
            return Err(ModelError::Invalid(
                "a stop-form (friction) model has no inverse: it predicts the force from the \
                 position. Compensate friction by feed-forward of the predicted force: run the \
                 model without --inverse on the desired motion (the rate term's force included)"
                    .into(),
            ));
        }
        if model.rate.is_some() {
            return Err(ModelError::Invalid(
                "an operator-form model with a rate term has no inverse hyst can compute: its \
                 output depends on the rate of the command that the inverse would have to \
                 compute. Fit without --rate-term to compensate it"
                    .into(),
            ));
        }
        if model.dynamics.is_none() {
            return Err(ModelError::Invalid(
                "the model has no dynamics: its compensator is the exact inverse \
                 (`hyst run --model M --inverse` without time)"
                    .into(),
            ));
        }
        Ok(())
    }

    /// The plant order n: the number of derivatives of the desired output a step takes.
    #[must_use]
    pub fn order(&self) -> usize {
        self.order
    }

    /// The command for the desired output `desired[0]` and its time derivatives
    /// `desired[1..=n]` (missing ones are 0), and the hysteresis input x the plant must
    /// follow.
    ///
    /// # Errors
    /// The core's error for a desired output the model cannot produce, or a non-finite command
    /// (the compensator is then unchanged).
    pub fn step(&mut self, desired: &[f64]) -> Result<(f64, f64), ModelError> {
        let value = desired.first().copied().unwrap_or(f64::NAN);
        let d: [f64; MAX_ORDER] =
            core::array::from_fn(|k| desired.get(k + 1).copied().unwrap_or(0.0));
        let u = self.compensator.track(Jet::from_derivatives(value, d))?;
        if let Some(time) = self.corner_time(value, d[0]) {
            if self.fastest.is_none_or(|c| time < c.time) {
                self.fastest = Some(Corner {
                    time,
                    sample: self.samples,
                });
            }
        }
        self.samples += 1;
        Ok((u, self.compensator.last_target().value()))
    }

    /// The fastest corner of the model's loop met so far (`None` while the desired output has
    /// not moved: no rate, or no derivative given).
    #[must_use]
    pub fn fastest_corner(&self) -> Option<Corner> {
        self.fastest
    }

    /// The corner time τ ([`Corner`]) at the sample just stepped, whose desired output and
    /// rate are `value` and `rate`; `None` when it does not move.
    fn corner_time(&self, value: f64, rate: f64) -> Option<f64> {
        let inverse = self.compensator.inverse();
        let ud = inverse
            .output_shaping()
            .invert_sample(Jet::<f64, 1>::from_derivatives(value, [rate]))
            .ok()?;
        let [r] = ud.derivatives();
        let k2 = inverse.operator().k2_law().k2(ud.value());
        let time = 1.0 / (k2 * r.abs());
        (time.is_finite() && time > 0.0).then_some(time)
    }
}

/// The largest bandwidth of a [`Prefilter`] as a fraction of the Nyquist frequency 1/(2h) of
/// the record's nominal step h: 1/20, so 1/(40 h) (25 Hz at 1 kHz).
///
/// The commands are samples, and the plant sees them linear between samples; the compensator
/// computes them from the prefiltered reference's derivatives as if the plant saw the
/// continuous command. The difference grows with the bandwidth against the sample rate:
/// measured with a plant of order 2 (and 1) at 1 kHz and 10 kHz on a step, the plant driven by
/// the commands follows the prefiltered reference within 0.15–0.22 % of its span at 1/20 of
/// the Nyquist frequency, 0.7–0.9 % at 1/10, 3–3.6 % at 1/5, 19 % at 1/2 and 54 % at the
/// Nyquist frequency; beyond it the commands grow without bound (5e11 Hz at 1 kHz: commands of
/// 4e10 for outputs of 20, errors of 3e12 % of the span). Plants of order 3 and 4 at 1 kHz stay at their error
/// at low bandwidths (0.3–0.9 %) up to 1/20 and reach 1.9 % and 11 % at 1/10.
pub const PREFILTER_NYQUIST_FRACTION: f64 = 0.05;

/// A reference prefilter of order n and bandwidth f (Hz): n equal real poles at ω = 2πf,
/// y_r / r = 1 / (s/ω + 1)ⁿ, run by the discretisation of [`crate::dynamics`] (the
/// reference linear between samples). It gives y_r and its first n derivatives, so that a
/// compensator of a plant of order n tracks y_r exactly. Its bandwidth is at most
/// [`PREFILTER_NYQUIST_FRACTION`] of the Nyquist frequency of the record's sample period
/// ([`Prefilter::check_bandwidth`]).
#[derive(Clone, Debug)]
pub struct Prefilter {
    steps: Discretisations<f64>,
    state: PlantState<f64>,
    started: bool,
    omega: f64,
    order: usize,
}

impl Prefilter {
    /// The prefilter of order `order` (1…4) and bandwidth `hz`, for a record of nominal step
    /// `period` (s) starting at rest at `first`. It takes the reference linear between samples
    /// (first-order hold), whatever the model's hold: it shapes the reference, not the
    /// command.
    ///
    /// # Errors
    /// A bandwidth that [`Prefilter::check_bandwidth`] refuses for `period`, or the
    /// discretisation's errors.
    pub fn new(order: usize, hz: f64, period: f64, first: f64) -> Result<Self, ModelError> {
        Self::check_bandwidth(hz, Some(period)).map_err(|e| {
            ModelError::Invalid(format!("a reference prefilter of bandwidth {hz} Hz: {e}"))
        })?;
        let omega = 2.0 * core::f64::consts::PI * hz;
        // (s/ω + 1)ⁿ = Σ C(n, i) sⁱ / ωⁱ.
        let a: Vec<f64> = (1..=order)
            .map(|i| binomial(order, i) / omega.powi(i as i32))
            .collect();
        let steps = Discretisations::new(Some(Dynamics::new(1.0, &a)?), period)?;
        let state = PlantState {
            x: core::array::from_fn(|i| if i == 0 { first } else { 0.0 }),
            u: first,
        };
        Ok(Self {
            steps,
            state,
            started: false,
            omega,
            order,
        })
    }

    /// The largest bandwidth (Hz) for a record of nominal step `period` (s):
    /// [`PREFILTER_NYQUIST_FRACTION`] of its Nyquist frequency, 1/(40 `period`).
    #[must_use]
    pub fn max_hz(period: f64) -> f64 {
        PREFILTER_NYQUIST_FRACTION / (2.0 * period)
    }

    /// Checks a bandwidth `hz` (Hz): a finite, positive frequency, and with the nominal step
    /// `period` (s) of a record, at most [`Prefilter::max_hz`]. Every surface calls it wherever
    /// the bandwidth is given, and names its own flag and the value before the message
    /// (`--prefilter-hz 1e12: above 25 Hz, …`).
    ///
    /// # Errors
    /// [`ModelError::Invalid`] saying why, with the bound and the sample period.
    pub fn check_bandwidth(hz: f64, period: Option<f64>) -> Result<(), ModelError> {
        if !(hz.is_finite() && hz > 0.0) {
            return Err(ModelError::Invalid(
                "the bandwidth must be a finite, positive frequency (Hz)".into(),
            ));
        }
        match period {
            Some(h) if h.is_finite() && h > 0.0 && hz > Self::max_hz(h) => {
                Err(ModelError::Invalid(format!(
                    "above {} Hz, the largest bandwidth at this record's sample period of {} s \
                     (1/20 of its Nyquist frequency, {} Hz): the commands are samples, and the \
                     plant, seeing them linear between samples, follows the prefiltered \
                     reference ever less closely above it (about 1 % of the span at 1/10 of the \
                     Nyquist frequency, half of it at the Nyquist frequency, without bound \
                     beyond); choose a bandwidth of at most {} Hz, or sample faster",
                    rounded(Self::max_hz(h)),
                    rounded(h),
                    rounded(0.5 / h),
                    rounded(Self::max_hz(h)),
                )))
            }
            _ => Ok(()),
        }
    }

    /// The prefiltered reference and its first n derivatives, for the next reference sample
    /// one nominal step after the last.
    pub fn step(&mut self, reference: f64) -> [f64; MAX_ORDER + 1] {
        let h = self.steps.nominal;
        self.step_after(reference, h)
            .unwrap_or([f64::NAN; MAX_ORDER + 1])
    }

    /// The prefiltered reference and its first n derivatives, for the next reference sample a
    /// step of `h` (s) after the last (ignored at the first sample).
    ///
    /// # Errors
    /// A step that is not finite and positive, or whose discretisation is not finite.
    pub fn step_after(
        &mut self,
        reference: f64,
        h: f64,
    ) -> Result<[f64; MAX_ORDER + 1], ModelError> {
        if self.started {
            if let (Some(d), _) = self.steps.at(h)? {
                d.step(&mut self.state, reference);
            }
        }
        self.started = true;
        let n = self.order;
        let mut out = [0.0; MAX_ORDER + 1];
        out[..n].copy_from_slice(&self.state.x[..n]);
        // The n-th derivative from the filter's equation at this sample:
        // y⁽ⁿ⁾ = ωⁿ (r − Σ_{i<n} C(n, i) y⁽ⁱ⁾ / ωⁱ).
        let mut acc = reference;
        for i in 0..n {
            acc -= binomial(n, i) * out[i] / self.omega.powi(i as i32);
        }
        out[n] = acc * self.omega.powi(n as i32);
        Ok(out)
    }
}

/// `x` to four significant digits, without trailing zeros: 25.000000000000004 → "25",
/// 0.0009765625 → "0.0009766".
fn rounded(x: f64) -> String {
    if !(x.is_finite() && x > 0.0) {
        return format!("{x}");
    }
    let digits = (3 - x.log10().floor() as i32).max(0) as usize;
    let text = format!("{x:.digits$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

fn binomial(n: usize, k: usize) -> f64 {
    (0..k).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::indexing_slicing)]
    use super::*;
    use crate::dynamics::{Dynamics, Rate};
    use crate::time::TimeSteps;
    use hyst_core::{AnyShaping, Tanh};

    fn model() -> SmoothModel {
        SmoothModel {
            k1: 0.06,
            k2: AnyK2Law::Constant { value: 5.0 },
            input_shaping: ScaledShaping::identity(),
            output_shaping: ScaledShaping::new(
                1.0,
                0.0,
                AnyShaping::Tanh(Tanh::new(1.0, 1.0).unwrap()),
                1.0,
                0.0,
            )
            .unwrap(),
            initial_state: crate::InitialState::Line,
            form: Form::Operator,
            linear: 0.0,
            dynamics: None,
            rate: None,
        }
    }

    /// A static model runs through `run_timed` bit for bit as through `run_with`.
    #[test]
    fn static_model_runs_as_before() {
        let m = model();
        let input: Vec<f64> = (0..200).map(|k| (0.05 * f64::from(k)).sin()).collect();
        let mut a = Vec::new();
        m.run_with(&input, None, |_, _, y| a.push(y)).unwrap();
        let mut b = Vec::new();
        m.run_timed(&input, None, None, |_, s| b.push(s.y)).unwrap();
        assert_eq!(a, b);
    }

    /// The compensator of a first-order plant, driven by a smooth reference with its exact
    /// derivative, gives a command that the forward model (plant and hysteresis) turns back
    /// into the reference, to the discretisation's accuracy.
    #[test]
    fn compensator_inverts_the_timed_model() {
        let mut m = model();
        m.dynamics = Some(Dynamics::new(1.0, &[0.1]).unwrap());
        let h = 1e-4;
        // From rest (ṙ(0) = 0), so that the plant at rest at the first command starts where
        // the compensator wants it.
        let r = |t: f64| 0.8 * t.sin().powi(2) - 0.4;
        let rd = |t: f64| 0.8 * (2.0 * t).sin();
        let mut c = TimedCompensator::new(&m, r(0.0)).unwrap();
        let command: Vec<f64> = (0..20_000)
            .map(|k| {
                let t = f64::from(k) * h;
                c.step(&[r(t), rd(t)]).unwrap().0
            })
            .collect();
        let mut worst: f64 = 0.0;
        m.run_timed(&command, Some(&TimeSteps::even(h)), None, |i, s| {
            worst = worst.max((s.y - r(i as f64 * h)).abs());
        })
        .unwrap();
        assert!(worst < 1e-3, "{worst}");
    }

    /// The desired output 1.5 sin³(4πt) (at rest at t = 0, so the plant at rest at the first
    /// command starts on it) and its first two time derivatives.
    fn cubed_sine(t: f64) -> [f64; 3] {
        let w = 4.0 * core::f64::consts::PI;
        let (s, c) = (w * t).sin_cos();
        [
            1.5 * s * s * s,
            4.5 * w * s * s * c,
            4.5 * w * w * s * (2.0 * c * c - s * s),
        ]
    }

    /// The compensator of an order-2 plant at k2 (1 kHz, 2 s of `cubed_sine`): the fastest
    /// corner it reports, and the largest error of the model driven by its commands, as a
    /// fraction of the desired output's span (3).
    fn corner_run(k2: f64, h: f64) -> (Corner, f64) {
        let mut m = model();
        m.k1 = 0.2;
        m.k2 = AnyK2Law::Constant { value: k2 };
        m.output_shaping = ScaledShaping::identity();
        m.dynamics = Some(Dynamics::new(1.0, &[0.05, 0.001]).unwrap());
        let mut c = TimedCompensator::new(&m, 0.0).unwrap();
        let n = (2.0 / h).round() as usize;
        let desired: Vec<[f64; 3]> = (0..n).map(|k| cubed_sine(k as f64 * h)).collect();
        let commands: Vec<f64> = desired.iter().map(|d| c.step(d).unwrap().0).collect();
        let mut worst: f64 = 0.0;
        m.run_timed(&commands, Some(&TimeSteps::even(h)), None, |i, s| {
            worst = worst.max((s.y - desired[i][0]).abs());
        })
        .unwrap();
        // The corner time is 1/(k2 |ẏ_d|) at the fastest sample (identity shapings).
        let (fastest, rate) = desired.iter().enumerate().fold((0, 0.0), |(i, r), (k, d)| {
            if d[1].abs() > r {
                (k, d[1].abs())
            } else {
                (i, r)
            }
        });
        let corner = c.fastest_corner().unwrap();
        assert_eq!(corner.sample, fastest);
        assert!((corner.time * k2 * rate - 1.0).abs() < 1e-12, "{corner:?}");
        (corner, worst / 3.0)
    }

    /// The plant driven by the commands strays from the desired output in proportion to the
    /// sample period against the corner time: within 1 % of the span where the period resolves
    /// the corners (h ≤ τ / CORNER_SAMPLES), far beyond where it does not. The figures are
    /// docs/fitting.md's.
    #[test]
    fn the_sample_period_must_resolve_the_loops_corners() {
        let h = 1e-3;
        // k2 with h just within τ / CORNER_SAMPLES, and k2 below and above.
        let rate = (0..2000)
            .map(|k| cubed_sine(f64::from(k) * h)[1].abs())
            .fold(0.0, f64::max);
        let at_the_bound = 0.999 / (CORNER_SAMPLES * h * rate);
        let mut errors = Vec::new();
        for k2 in [2.0, 8.0, at_the_bound, 100.0, 1e3, 1e4] {
            let (corner, error) = corner_run(k2, h);
            println!(
                "k2 = {k2:.4}: corner time {:.4e} s, h = {:.3} τ, largest error {:.2} % of the span{}",
                corner.time,
                h / corner.time,
                100.0 * error,
                if corner.resolved_by(h) { "" } else { " (not resolved)" }
            );
            assert_eq!(corner.resolved_by(h), k2 <= at_the_bound, "{k2}");
            errors.push((h / corner.time, error));
        }
        // h / τ: 0.044, 0.17, 1/3, 2.2, 22, 218.
        let ratios = [0.0436, 0.174, 0.333, 2.18, 21.8, 218.0];
        for ((ratio, _), want) in errors.iter().zip(ratios) {
            assert!((ratio / want - 1.0).abs() < 0.01, "{ratio} vs {want}");
        }
        // Resolved: 0.1 %, 0.5 %, 0.9 % at the bound; not: 6.5 %, 61 %, 224 %.
        let within = [0.002, 0.006, 0.01, 0.07, 0.65, 2.3];
        let beyond = [0.0005, 0.004, 0.007, 0.06, 0.55, 2.0];
        for (k, (_, e)) in errors.iter().enumerate() {
            assert!(*e < within[k] && *e > beyond[k], "case {k}: {e}");
        }
        assert!((corner_run(100.0, h).0.needed_period() - 1.0 / (300.0 * rate)).abs() < 1e-15);
    }

    #[test]
    fn compensator_refuses_what_it_cannot_invert() {
        let mut m = model();
        assert!(TimedCompensator::new(&m, 0.0).is_err());
        m.dynamics = Some(Dynamics::new(1.0, &[0.1]).unwrap());
        m.rate = Some(Rate { c: 0.1 });
        let e = TimedCompensator::new(&m, 0.0).unwrap_err().to_string();
        assert!(e.contains("rate term"), "{e}");
        // Without dynamics too: the advice to run the exact inverse would send the user back
        // to the command that refused.
        m.dynamics = None;
        let e = TimedCompensator::check(&m).unwrap_err().to_string();
        assert!(e.contains("rate term") && !e.contains("no dynamics"), "{e}");
    }

    /// The rate term adds c times the backward difference of v, 0 at the first sample.
    #[test]
    fn rate_term_is_the_backward_difference() {
        let mut m = model();
        let input = [0.0, 0.1, 0.3, 0.2];
        let mut plain = Vec::new();
        m.run_with(&input, None, |_, _, y| plain.push(y)).unwrap();
        m.rate = Some(Rate { c: 2.0 });
        let mut with = Vec::new();
        m.run_timed(&input, Some(&TimeSteps::even(0.5)), None, |_, s| {
            with.push(s.y)
        })
        .unwrap();
        let expected = [0.0, 0.4, 0.8, -0.4];
        for k in 0..4 {
            assert!((with[k] - plain[k] - expected[k]).abs() < 1e-15, "{k}");
        }
        assert!(m.run_timed(&input, None, None, |_, _| {}).is_err());
    }

    /// Uneven steps: each step discretised for its own h, against a fine integration of the
    /// plant under either hold; an even record runs bit for bit as `TimedRun::step` at its
    /// period, stamps rounded or not.
    #[test]
    fn uneven_steps_match_a_fine_integration() {
        use crate::dynamics::Hold;
        let tau = 0.05;
        let mut t = vec![3.0];
        for k in 0..400 {
            let h = [0.010, 0.013, 0.063, 0.011, 0.0105][k % 5];
            t.push(t[k] + h);
        }
        let u = |t: f64| (2.0 * t).sin() + 0.3 * (11.0 * t).cos();
        let command: Vec<f64> = t.iter().map(|t| u(*t)).collect();
        for hold in [Hold::Zoh, Hold::Foh] {
            let mut m = model();
            m.output_shaping = ScaledShaping::identity();
            m.k1 = 1e-9;
            m.dynamics = Some(Dynamics::new(1.0, &[tau]).unwrap().with_hold(hold));
            let (parts, gaps) = crate::time::split(&t).unwrap();
            assert!(gaps.is_empty());
            let mut v = Vec::new();
            m.run_timed(&command, Some(&parts[0].1), None, |_, s| v.push(s.v))
                .unwrap();
            // RK4 with 1,000 substeps a step, of the held or interpolated command.
            let mut x = command[0];
            for k in 1..t.len() {
                let h = t[k] - t[k - 1];
                let c = |s: f64| match hold {
                    Hold::Zoh => command[k - 1],
                    Hold::Foh => command[k - 1] + s / h * (command[k] - command[k - 1]),
                };
                let f = |s: f64, x: f64| (c(s) - x) / tau;
                let n = 1000;
                let dt = h / f64::from(n);
                for j in 0..n {
                    let s = f64::from(j) * dt;
                    let k1 = f(s, x);
                    let k2 = f(s + dt / 2.0, x + dt / 2.0 * k1);
                    let k3 = f(s + dt / 2.0, x + dt / 2.0 * k2);
                    let k4 = f(s + dt, x + dt * k3);
                    x += dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
                }
                assert!((v[k] - x).abs() < 1e-12, "{hold:?} {k}: {} vs {x}", v[k]);
            }
        }
        // An even record with rounded stamps: the nominal discretisation, bit for bit.
        let mut m = model();
        m.dynamics = Some(Dynamics::new(1.0, &[0.02, 1e-4]).unwrap());
        m.rate = Some(Rate { c: 0.2 });
        let t: Vec<f64> = (0..500).map(|k| 1234.5 + f64::from(k) * 0.001).collect();
        let x: Vec<f64> = t.iter().map(|t| (5.0 * t).sin()).collect();
        let (parts, _) = crate::time::split(&t).unwrap();
        let (_, steps) = &parts[0];
        assert!(steps.is_even());
        let mut a = Vec::new();
        m.run_timed(&x, Some(steps), None, |_, s| a.push(s.y.to_bits()))
            .unwrap();
        let mut run = TimedRun::new(&m, steps.nominal(), x[0]).unwrap();
        let b: Vec<u64> = x
            .iter()
            .map(|x| run.step(*x).unwrap().y.to_bits())
            .collect();
        assert_eq!(a, b);
    }

    /// A bandwidth is finite and positive, and at most 1/20 of the Nyquist frequency of the
    /// record's sample period; the message says the bound and the period.
    #[test]
    fn prefilter_bandwidth_is_bounded_by_the_sample_rate() {
        assert!((Prefilter::max_hz(1e-3) - 25.0).abs() < 1e-9);
        assert!(Prefilter::check_bandwidth(24.9, Some(1e-3)).is_ok());
        assert!(Prefilter::check_bandwidth(1e12, None).is_ok());
        for (hz, period) in [(26.0, 1e-3), (1e12, 1e-3), (0.5, 1.0)] {
            let message = Prefilter::check_bandwidth(hz, Some(period))
                .unwrap_err()
                .to_string();
            let bound = rounded(1.0 / (40.0 * period));
            assert!(
                message.starts_with(&format!("above {bound} Hz")),
                "{message}"
            );
            assert!(
                message.contains(&format!("sample period of {period} s")),
                "{message}"
            );
            assert!(Prefilter::new(2, hz, period, 0.0).is_err());
        }
        for bad in [f64::NAN, -1.0, 0.0, f64::INFINITY, f64::NEG_INFINITY] {
            for period in [None, Some(1e-3)] {
                let message = Prefilter::check_bandwidth(bad, period)
                    .unwrap_err()
                    .to_string();
                assert!(message.contains("finite, positive"), "{message}");
            }
        }
        assert_eq!(rounded(1.0 / (40.0 * 1e-3)), "25");
        assert_eq!(rounded(1.0 / 1024.0), "0.0009766");
        assert_eq!(rounded(512.0), "512");
    }

    /// The prefilter's derivatives are those of its output: integrating them gives it back.
    #[test]
    fn prefilter_derivatives_are_consistent() {
        let h = 1e-4;
        let mut p = Prefilter::new(2, 5.0, h, 0.0).unwrap();
        let mut last = p.step(0.0);
        for k in 1..5000 {
            let now = p.step(if k > 100 { 1.0 } else { 0.0 });
            // Trapezoid on y' and y''.
            let dy = 0.5 * h * (now[1] + last[1]);
            assert!((now[0] - last[0] - dy).abs() < 1e-6, "{k}");
            last = now;
        }
        assert!((last[0] - 1.0).abs() < 1e-3, "{}", last[0]);
    }
}
