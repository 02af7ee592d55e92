//! Models with dynamics or a rate term (`SmoothModel::is_timed`) in the FMU: what such
//! an FMU needs ([`Timing`], which `hyst fmu` asks too, so that it packs only what this binary
//! runs) and what it steps ([`TimedEngine`]: hyst-model's `TimedRun` or `TimedCompensator`,
//! exactly as `hyst run --model M [--inverse]` runs a timed record; no formula is written here).
//!
//! - Direct: each communication step size is the time step h from one sample to the next, and
//!   the plant is discretised for it (`hyst_model::time`): the sample committed by an
//!   fmi2DoStep is one step of the previous fmi2DoStep's size after the one before. The first
//!   fmi2DoStep's size is the nominal step (a later step within
//!   `hyst_model::time::STEP_TOLERANCE` of it is taken as it, as `hyst run` takes a record's
//!   mean step), so communication points at a record's time stamps give `hyst run`'s outputs.
//!   A step must be > 0. The model description says
//!   canHandleVariableCommunicationStepSize = true.
//! - Inverse: Lemma 5.1's compensator of the plant, for the desired output x and its first n
//!   time derivatives, the inputs x_d1 … x_dn (n the plant order). The step size does not
//!   enter (the derivatives are inputs), so any steps are fine, as for a static model.
//! - Either way, the instance's state is a clone of the engine: FMU states can be got and set,
//!   but not serialised (canSerializeFMUstate = false), since hyst-model does not expose the
//!   state of a `TimedRun` or `TimedCompensator`.

use hyst_model::{
    Corner, Dynamics, ModelFile, SmoothModel, TimedCompensator, TimedRun, MAX_DYNAMICS,
};

/// The nominal step of the engine that computes y before the first fmi2DoStep gives it: the
/// first sample of a `TimedRun` does not depend on it (the plant starts at rest,
/// v = b·x, and the rate term is 0), so y there is the first doStep's, whatever its step.
const PERIOD_BEFORE_THE_FIRST_STEP: f64 = 1.0;

/// What an FMU of a model with dynamics or a rate term needs beyond a static model's.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Timing {
    /// The number n of x's time derivatives the FMU takes as inputs x_d1 … x_dn: the plant
    /// order for the inverse (the compensator), 0 for the direct model.
    pub derivatives: usize,
    /// What the model has, in words ("dynamics of order 2", "a rate term", or both).
    pub what: String,
}

impl Timing {
    /// The timing of an FMU of `file` (its inverse with `inverse`; `saturate`: desired outputs
    /// are clamped), `None` for a model without dynamics or a rate term.
    ///
    /// # Errors
    /// Why the FMU cannot run it: the inverse of a model without a compensator
    /// (`TimedCompensator::check`'s reason: a rate term, the stop form), or `saturate`
    /// (`hyst run --saturate` refuses a timed model too).
    pub fn of(file: &ModelFile, inverse: bool, saturate: bool) -> Result<Option<Self>, String> {
        let Some(model) = file.smooth.as_ref().filter(|m| m.is_timed()) else {
            return Ok(None);
        };
        let order = model.dynamics.map_or(0, |d| d.order());
        let what = model.timed_parts();
        if saturate {
            return Err(format!(
                "--saturate (saturate = true): the model has {what}, and desired outputs are \
                 not clamped for it (`hyst run --saturate` refuses it too)"
            ));
        }
        if inverse {
            // `check` names a missing plant before a rate term, and then suggests the exact
            // inverse, which for a model with a rate term alone is not its inverse: ask it about
            // the rate term (and the form) with a stand-in plant.
            let mut asked = *model;
            if asked.dynamics.is_none() {
                asked.dynamics = Dynamics::new(1.0, &[1.0]).ok();
            }
            TimedCompensator::check(&asked)
                .map_err(|e| format!("the inverse of a model with {what}: {e}"))?;
        }
        Ok(Some(Self {
            derivatives: if inverse { order } else { 0 },
            what,
        }))
    }
}

impl Timing {
    /// The description of the input x_d`k` (k ≥ 1) of the inverse of the model `file`: the
    /// k-th time derivative of its output (named by its column and unit).
    #[must_use]
    pub fn derivative_description(k: usize, file: &ModelFile) -> String {
        let (column, unit) = (&file.columns.output, file.units.output.as_str());
        let unit = if unit.is_empty() {
            "output units"
        } else {
            unit
        };
        format!(
            "time derivative {k} of the desired model output x ({unit}/s^{k}; the column \
             {column}_d{k} of `hyst run --model M --inverse`)"
        )
    }

    /// What the FMU does with the time, in a sentence or two (its documentation).
    #[must_use]
    fn summary(&self) -> String {
        let use_of_time = if self.derivatives == 0 {
            "each communication step size is the time step to the next sample, for which its \
             plant is discretised exactly (under the model file's hold); steps may vary, and \
             must be > 0"
                .to_string()
        } else {
            format!(
                "its compensator takes the desired output's first {} time derivatives as the \
                 inputs x_d1 ... x_d{0}, and the step size does not enter",
                self.derivatives
            )
        };
        format!(
            "The model has {}: {use_of_time}. The FMU state is saved and restored in memory, \
             not serialised (canSerializeFMUstate = false).",
            self.what
        )
    }
}

/// What an FMU does with the time, in a sentence or two (its documentation/index.html): the
/// timing of a model with dynamics or a rate term, or rate independence.
#[must_use]
pub fn summary(timing: Option<&Timing>) -> String {
    timing.map_or_else(
        || {
            "Rate independence: y does not depend on the step size. The state (the memory) can \
             be saved, restored and serialised."
                .into()
        },
        Timing::summary,
    )
}

/// What an instance of a timed model steps.
#[derive(Clone, Debug)]
pub enum TimedEngine {
    /// The direct model over samples one communication step apart.
    Run {
        /// The step (s) to the next sample: the last fmi2DoStep's communicationStepSize.
        next: f64,
        /// The run, started at the first fmi2DoStep's x, its nominal step the first
        /// fmi2DoStep's.
        run: Box<TimedRun>,
    },
    /// Lemma 5.1's compensator (the inverse), started at the first fmi2DoStep's x.
    Compensator(Box<TimedCompensator>),
}

impl TimedEngine {
    /// The engine of `model` (its compensator with `inverse`) for a record whose first sample
    /// is `first`, with the nominal step `period` (the first fmi2DoStep's step), or `None`
    /// before the first fmi2DoStep (for y only: see `PERIOD_BEFORE_THE_FIRST_STEP`).
    ///
    /// # Errors
    /// A period that is not > 0, or the model cannot start at `first`.
    pub fn new(
        model: &SmoothModel,
        first: f64,
        inverse: bool,
        period: Option<f64>,
    ) -> Result<Self, String> {
        let cannot = |e: &dyn std::fmt::Display| format!("the model cannot start at {first}: {e}");
        if inverse {
            let compensator = TimedCompensator::new(model, first).map_err(|e| cannot(&e))?;
            return Ok(TimedEngine::Compensator(Box::new(compensator)));
        }
        if let Some(p) = period.filter(|p| !(p.is_finite() && *p > 0.0)) {
            return Err(format!(
                "communicationStepSize = {p}: the time step to the next sample of the model's \
                 dynamics or rate term must be > 0"
            ));
        }
        let period = period.unwrap_or(PERIOD_BEFORE_THE_FIRST_STEP);
        let run = TimedRun::new(model, period, first).map_err(|e| cannot(&e))?;
        Ok(TimedEngine::Run {
            next: period,
            run: Box::new(run),
        })
    }

    /// Checks the communication step `step` of an fmi2DoStep after the first: the direct
    /// model's must be > 0 (the next sample comes that much later).
    ///
    /// # Errors
    /// A step of the direct model that is not finite and > 0 (the message names it).
    pub fn check_step(&self, step: f64) -> Result<(), String> {
        match self {
            TimedEngine::Run { .. } if !(step.is_finite() && step > 0.0) => Err(format!(
                "communicationStepSize = {step}: the time step to the next sample of a model \
                 with dynamics or a rate term must be > 0 (time stamps that increase)"
            )),
            _ => Ok(()),
        }
    }

    /// Takes the communication step `step` of the fmi2DoStep that committed the last sample:
    /// the step to the next sample (checked by [`TimedEngine::check_step`]).
    pub fn set_next(&mut self, step: f64) {
        if let TimedEngine::Run { next, .. } = self {
            *next = step;
        }
    }

    /// Steps the sample `x` with x's time derivatives `derivatives` (the compensator's; missing
    /// ones are 0) and commits it; on error nothing changes.
    ///
    /// # Errors
    /// The model's refusal of the sample (its message).
    pub fn step(&mut self, x: f64, derivatives: &[f64]) -> Result<f64, String> {
        match self {
            TimedEngine::Run { run, next } => run
                .step_after(x, *next)
                .map(|s| s.y)
                .map_err(|e| e.to_string()),
            TimedEngine::Compensator(c) => {
                let desired: [f64; MAX_DYNAMICS + 1] = core::array::from_fn(|k| match k {
                    0 => x,
                    _ => derivatives.get(k - 1).copied().unwrap_or(0.0),
                });
                c.step(&desired).map(|(u, _)| u).map_err(|e| e.to_string())
            }
        }
    }

    /// The fastest corner of the model's loop a compensator has met (`None` for the direct
    /// model): a sample period must resolve it ([`Corner::resolved_by`]).
    #[must_use]
    pub fn fastest_corner(&self) -> Option<Corner> {
        match self {
            TimedEngine::Run { .. } => None,
            TimedEngine::Compensator(c) => c.fastest_corner(),
        }
    }

    /// The output [`TimedEngine::step`] would give, without committing anything.
    ///
    /// # Errors
    /// As [`TimedEngine::step`].
    pub fn peek(&self, x: f64, derivatives: &[f64]) -> Result<f64, String> {
        self.clone().step(x, derivatives)
    }
}
