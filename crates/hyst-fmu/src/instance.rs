//! One FMU instance: its mode, variables, committed history and saved states, in safe Rust.
//! `api` checks the C arguments and the mode, calls these methods and logs their errors.
//!
//! Semantics (FMI 2.0 Co-Simulation, direct feedthrough): each communication point is one
//! sample, its inputs the values set there. After fmi2SetReal of an input, y is the output for
//! the committed history followed by the current inputs, computed on a copy; fmi2DoStep commits
//! that sample, once, and y keeps its output (the output at the communication point, held)
//! until an input is set for the next point. So y read before and after fmi2DoStep is the same
//! number, and the history advances once per communication point with the inputs set there. The
//! time only matters for fmi2GetRealStatus(fmi2LastSuccessfulTime), and the step size only for
//! a model with dynamics or a rate term (`crate::timed`: each communication step is the direct
//! model's time step to the next sample).

use std::fmt;

use hyst_model::MAX_DYNAMICS;

use crate::config::{Config, Kind};
use crate::engine::Engine;
use crate::fmi2::fmi2FMUstate;
use crate::layout::{DERIVATIVE_NAMES, VR_K1, VR_K2, VR_X, VR_X_D1, VR_Y};
use crate::logger::Logger;
use crate::state::{self, FmuState, History, Owner};

/// The mode of an instance (the FMI 2.0 Co-Simulation state machine; this FMU never has a step
/// in progress, so stepComplete, stepFailed and stepCanceled are one `StepMode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// After fmi2Instantiate or fmi2Reset.
    Instantiated,
    /// Between fmi2EnterInitializationMode and fmi2ExitInitializationMode.
    InitializationMode,
    /// After fmi2ExitInitializationMode: fmi2DoStep may be called.
    StepMode,
    /// After fmi2Terminate.
    Terminated,
    /// A panic was caught: only fmi2FreeInstance is allowed.
    Fatal,
}

impl fmt::Display for Phase {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Phase::Instantiated => "Instantiated",
            Phase::InitializationMode => "InitializationMode",
            Phase::StepMode => "StepMode",
            Phase::Terminated => "Terminated",
            Phase::Fatal => "Fatal",
        })
    }
}

/// A variable of this FMU.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Variable {
    X,
    Y,
    K1,
    K2,
    /// x_d(k + 1), the (k + 1)-th time derivative of x (a timed model's compensator).
    Derivative(usize),
}

impl Variable {
    fn name(self) -> &'static str {
        match self {
            Variable::X => "x",
            Variable::Y => "y",
            Variable::K1 => "k1",
            Variable::K2 => "k2",
            Variable::Derivative(k) => DERIVATIVE_NAMES.get(k).copied().unwrap_or("x_d"),
        }
    }
}

/// One instance.
#[derive(Debug)]
pub struct Instance {
    config: Config,
    owner: Owner,
    /// The master's logger.
    pub log: Logger,
    logging_at_instantiation: bool,
    /// The current mode.
    pub phase: Phase,
    x: f64,
    /// x_d1 … x_dn: the inputs of a timed model's compensator (n = `Timing::derivatives`; the
    /// rest stay 0).
    derivatives: [f64; MAX_DYNAMICS],
    parameters: Option<(f64, f64)>,
    /// `None` until fmi2ExitInitializationMode (operator) or the first fmi2DoStep (model).
    engine: Option<Engine>,
    time: f64,
    /// The output of the sample the last fmi2DoStep committed, which y keeps until an input is
    /// set (`None` before the first step, after fmi2Reset and once an input is set).
    held: Option<f64>,
    /// Whether the compensator's warning that the communication step does not resolve the
    /// loop's corners was sent (once per instance, until fmi2Reset).
    corner_warned: bool,
    /// Whether the last committed x was clamped (`saturate = true`): a warning is sent when
    /// the desired output enters saturation, not at every step it stays there.
    saturated: bool,
    /// The FMU states handed out (fmi2GetFMUstate, fmi2DeSerializeFMUstate); a handle is the
    /// address of its box, and only handles found here are accepted.
    #[allow(clippy::vec_box)]
    // the box keeps a state's address (its handle) fixed as the Vec grows
    states: Vec<Box<FmuState>>,
}

impl Instance {
    /// A new instance of `config` (in the mode Instantiated, variables at their start values).
    #[must_use]
    pub fn new(config: Config, log: Logger) -> Self {
        let owner = Owner::new(
            &config.guid,
            matches!(config.kind, Kind::Model(_)),
            config.inverse,
        );
        let logging_at_instantiation = log.debug;
        let mut instance = Self {
            config,
            owner,
            log,
            logging_at_instantiation,
            phase: Phase::Instantiated,
            x: 0.0,
            derivatives: [0.0; MAX_DYNAMICS],
            parameters: None,
            engine: None,
            time: 0.0,
            held: None,
            corner_warned: false,
            saturated: false,
            states: Vec::new(),
        };
        instance.reset();
        instance
    }

    /// fmi2Reset: back to the state after fmi2Instantiate (parameters at their start values,
    /// no history). Saved FMU states stay valid.
    pub fn reset(&mut self) {
        self.phase = Phase::Instantiated;
        self.x = 0.0;
        self.derivatives = [0.0; MAX_DYNAMICS];
        self.parameters = match self.config.kind {
            Kind::Operator { k1, k2 } => Some((k1, k2)),
            Kind::Model(_) => None,
        };
        self.engine = None;
        self.time = 0.0;
        self.held = None;
        self.corner_warned = false;
        self.saturated = false;
        self.log.debug = self.logging_at_instantiation;
    }

    /// The number n of derivative inputs x_d1 … x_dn.
    fn order(&self) -> usize {
        self.config.timing.as_ref().map_or(0, |t| t.derivatives)
    }

    fn variable(&self, vr: u32) -> Result<Variable, String> {
        let derivative = vr
            .checked_sub(VR_X_D1)
            .and_then(|k| usize::try_from(k).ok())
            .filter(|k| *k < self.order());
        match (vr, self.parameters.is_some(), derivative) {
            (VR_X, _, _) => Ok(Variable::X),
            (VR_Y, _, _) => Ok(Variable::Y),
            (VR_K1, true, _) => Ok(Variable::K1),
            (VR_K2, true, _) => Ok(Variable::K2),
            (_, false, Some(k)) => Ok(Variable::Derivative(k)),
            _ => Err(format!("no Real variable has value reference {vr}")),
        }
    }

    /// fmi2SetupExperiment: the start time.
    ///
    /// # Errors
    /// A non-finite start time.
    pub fn setup_experiment(&mut self, start_time: f64) -> Result<(), String> {
        if !start_time.is_finite() {
            return Err(format!("startTime = {start_time}: must be finite"));
        }
        self.time = start_time;
        Ok(())
    }

    /// fmi2ExitInitializationMode: the operator is built from k1, k2 (a model's evaluator waits
    /// for the first fmi2DoStep); the mode becomes StepMode.
    ///
    /// # Errors
    /// Invalid k1 or k2 (the core's message names the parameter and the value); the mode stays
    /// InitializationMode.
    pub fn exit_initialization(&mut self) -> Result<(), String> {
        if let Some((k1, k2)) = self.parameters {
            let engine =
                Engine::operator(k1, k2, self.config.inverse).map_err(|e| e.to_string())?;
            self.engine = Some(engine);
        }
        self.phase = Phase::StepMode;
        Ok(())
    }

    /// fmi2SetReal: all values or none (every value reference and mode is checked first).
    /// x may be set before and after initialisation, k1 and k2 only before
    /// fmi2ExitInitializationMode; y never. Setting an input (x, x_d1 …) starts the sample of
    /// the next communication point: y is then computed for it, no longer held.
    ///
    /// # Errors
    /// An unknown value reference, an output, a parameter after initialisation.
    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), String> {
        let mut targets = Vec::with_capacity(vrs.len());
        for (vr, value) in vrs.iter().zip(values) {
            let v = self.variable(*vr)?;
            match v {
                Variable::X | Variable::Derivative(_) => {}
                Variable::Y => return Err("y (value reference 1) is an output".into()),
                Variable::K1 | Variable::K2 => {
                    if !matches!(self.phase, Phase::Instantiated | Phase::InitializationMode) {
                        return Err(format!(
                            "{} = {value}: {} is a fixed parameter and can be set only before \
                             fmi2ExitInitializationMode (the mode is {})",
                            v.name(),
                            v.name(),
                            self.phase
                        ));
                    }
                }
            }
            targets.push((v, *value));
        }
        for (v, value) in targets {
            if matches!(v, Variable::X | Variable::Derivative(_)) {
                self.held = None;
            }
            match (v, &mut self.parameters) {
                (Variable::X, _) => self.x = value,
                (Variable::Derivative(k), _) => {
                    if let Some(d) = self.derivatives.get_mut(k) {
                        *d = value;
                    }
                }
                (Variable::K1, Some((k1, _))) => *k1 = value,
                (Variable::K2, Some((_, k2))) => *k2 = value,
                _ => {}
            }
        }
        Ok(())
    }

    /// The x the operator sees: the current x, clamped into the saturation limits with
    /// `saturate = true` (then also whether it was clamped).
    fn input(&self) -> (f64, bool) {
        match self.config.saturation {
            Some(s) => {
                let (lo, hi) = s.limits;
                let x = self.x.clamp(lo, hi);
                (x, x != self.x)
            }
            None => (self.x, false),
        }
    }

    /// A sample for messages: "x = …", and ", x_d1 = …" … for a compensator (`derivatives`:
    /// x_d1 … x_dn).
    fn sample(x: f64, derivatives: &[f64]) -> String {
        let mut text = format!("x = {x}");
        for (name, d) in DERIVATIVE_NAMES.iter().zip(derivatives) {
            text.push_str(&format!(", {name} = {d}"));
        }
        text
    }

    /// y for the committed history followed by the current x, without committing anything.
    /// Before the operator is built (initialisation) a fresh operator with the current k1, k2
    /// is used; before a model's first fmi2DoStep, an evaluator started at x.
    fn output(&self) -> Result<f64, String> {
        let (x, _) = self.input();
        let d = self.derivatives.get(..self.order()).unwrap_or(&[]);
        let refused = |e: &dyn fmt::Display| format!("{}: {e}", Self::sample(self.x, d));
        match (&self.engine, &self.config.kind, self.parameters) {
            (Some(engine), _, _) => engine.peek(x, d).map_err(|e| refused(&e)),
            (None, Kind::Operator { .. }, Some((k1, k2))) => {
                Engine::operator(k1, k2, self.config.inverse)
                    .map_err(|e| e.to_string())?
                    .peek(x, d)
                    .map_err(|e| refused(&e))
            }
            (None, Kind::Model(file), _) => Engine::model(file, x, self.config.inverse, None)
                .map_err(|e| refused(&e))?
                .peek(x, d)
                .map_err(|e| refused(&e)),
            (None, Kind::Operator { .. }, None) => {
                Err("internal error: an operator without parameters".into())
            }
        }
    }

    /// fmi2GetReal. y is the output held since the last fmi2DoStep while no input has been set
    /// since, else the output for the committed history followed by the current inputs.
    ///
    /// # Errors
    /// An unknown value reference, or y for a sample the operator refuses (non-finite x, a
    /// desired output beyond a saturating shaping function, invalid parameters during
    /// initialisation). Values before the failing one are written.
    pub fn get_real(&self, vrs: &[u32], values: &mut [f64]) -> Result<(), String> {
        let mut y = None;
        for (vr, value) in vrs.iter().zip(values.iter_mut()) {
            *value = match (self.variable(*vr)?, self.parameters) {
                (Variable::X, _) => self.x,
                (Variable::Y, _) => match y.or(self.held) {
                    Some(y) => y,
                    None => {
                        let v = self.output().map_err(|e| format!("y: {e}"))?;
                        y = Some(v);
                        v
                    }
                },
                (Variable::K1, Some((k1, _))) => k1,
                (Variable::K2, Some((_, k2))) => k2,
                (Variable::Derivative(k), _) => self.derivatives.get(k).copied().unwrap_or(0.0),
                (v, None) => return Err(format!("{} does not exist", v.name())),
            };
        }
        Ok(())
    }

    /// fmi2DoStep: commits the current x (and x_d1 …) as the sample of the communication point
    /// `current`, and holds its output as y until an input is set (a model's evaluator is created at the first step,
    /// started at x as `hyst run --model` starts a record). Any step size ≥ 0 is fine, but for
    /// the direct model of a model with dynamics or a rate term: each step's size is the time
    /// step to the next sample, > 0, and the first is its nominal step (`crate::timed`). With
    /// `saturate = true` a desired output beyond the limits is clamped into them; the step
    /// then returns the warning to send when it is the first clamped step after an unclamped
    /// one (the desired output enters saturation).
    ///
    /// # Errors
    /// A negative or non-finite step, a timed model's step that is not > 0, or x refused;
    /// nothing changes then.
    pub fn do_step(&mut self, current: f64, step: f64) -> Result<Option<String>, String> {
        if !(current.is_finite() && step.is_finite() && step >= 0.0) {
            return Err(format!(
                "currentCommunicationPoint = {current}, communicationStepSize = {step}: \
                 must be finite and the step >= 0"
            ));
        }
        let (x, clamped) = self.input();
        let d = self.derivatives.get(..self.order()).unwrap_or(&[]);
        let raw = self.x;
        let refused = |e: &dyn fmt::Display| format!("{}: {e}", Self::sample(raw, d));
        let y = match (&mut self.engine, &self.config.kind) {
            (Some(engine), _) => {
                engine.check_step(step)?;
                let y = engine.step(x, d).map_err(|e| refused(&e))?;
                engine.set_next(step);
                y
            }
            (None, Kind::Model(file)) => {
                let mut engine = Engine::model(file, x, self.config.inverse, Some(step))
                    .map_err(|e| refused(&e))?;
                let y = engine.step(x, d).map_err(|e| refused(&e))?;
                self.engine = Some(engine);
                y
            }
            (None, Kind::Operator { .. }) => {
                return Err("internal error: no operator in step mode".into());
            }
        };
        self.held = Some(y);
        self.time = current + step;
        let warning = match self.config.saturation {
            Some(s) if clamped && !self.saturated => Some(format!(
                "x = {}: beyond the range ({}, {}) of the model's {} output shaping: clamped \
                 to {x} (saturate = true; no further warning until x is back within [{}, {}])",
                self.x, s.range.0, s.range.1, s.shaping, s.limits.0, s.limits.1
            )),
            _ => None,
        };
        self.saturated = clamped;
        Ok(warning.or_else(|| self.corner_warning(step)))
    }

    /// The compensator's warning, once, when the communication step `step` (the time the
    /// command is applied for) does not resolve the fastest corner of the loop it has met.
    fn corner_warning(&mut self, step: f64) -> Option<String> {
        let corner = self.engine.as_ref()?.fastest_corner()?;
        if self.corner_warned || corner.resolved_by(step) {
            return None;
        }
        self.corner_warned = true;
        Some(format!(
            "the desired output crosses a corner of the model's loop (1/k2 wide in the \
             operator's output units) in {:.4e} s at this instance's sample {}, less than {} \
             communication steps of {step} s: the commands spike near the loop's corners, and \
             the plant driven by them strays from the desired output in proportion to the \
             step; step at most every {:.4e} s (no further warning from this instance)",
            corner.time,
            corner.sample,
            hyst_model::CORNER_SAMPLES,
            corner.needed_period()
        ))
    }

    /// The end of the last successful communication step (the start time before the first).
    #[must_use]
    pub fn time(&self) -> f64 {
        self.time
    }

    /// The current state.
    #[must_use]
    pub fn snapshot(&self) -> FmuState {
        FmuState {
            x: self.x,
            derivatives: self.derivatives,
            parameters: self.parameters,
            time: self.time,
            held: self.held,
            history: self.engine.as_ref().map_or(History::Empty, Engine::history),
        }
    }

    /// The engine a state needs in step mode (`stepping`) or before it, checked: parameters
    /// through the core's constructor, the memory through `Operator::set_memory`. A history
    /// can only be restored in step mode (or Terminated).
    fn engine_for(&self, state: &FmuState, stepping: bool) -> Result<Option<Engine>, String> {
        if state.parameters.is_some() != self.parameters.is_some() {
            return Err("the state is of another kind of FMU".into());
        }
        let has_history = !matches!(state.history, History::Empty);
        if !stepping {
            if has_history {
                return Err(format!(
                    "a state with a history can be restored only after \
                     fmi2ExitInitializationMode (the mode is {})",
                    self.phase
                ));
            }
            return Ok(None);
        }
        let mut engine = match (&self.config.kind, state.parameters, &state.history) {
            (Kind::Operator { .. }, Some((k1, k2)), _) => {
                Engine::operator(k1, k2, self.config.inverse).map_err(|e| e.to_string())?
            }
            (Kind::Model(file), _, History::Model { first, .. }) => {
                Engine::model(file, *first, self.config.inverse, None)?
            }
            (Kind::Model(_), _, History::Empty) => return Ok(None),
            // A copy of this instance's own engine (timed states are never deserialised).
            (Kind::Model(_), _, History::Timed(engine)) if self.config.timing.is_some() => {
                return Ok(Some(Engine::Timed(engine.clone())));
            }
            _ => return Err("the state is of another kind of FMU".into()),
        };
        engine.restore(&state.history)?;
        Ok(Some(engine))
    }

    /// Replaces the instance's state by `state` (the mode is kept).
    ///
    /// # Errors
    /// As `engine_for`; the instance is then unchanged.
    pub fn apply(&mut self, state: &FmuState) -> Result<(), String> {
        let stepping = matches!(self.phase, Phase::StepMode | Phase::Terminated);
        let engine = self.engine_for(state, stepping)?;
        self.engine = engine;
        self.x = state.x;
        self.derivatives = state.derivatives;
        self.parameters = state.parameters;
        self.time = state.time;
        self.held = state.held;
        Ok(())
    }

    fn find_state(&self, handle: fmi2FMUstate) -> Option<usize> {
        self.states
            .iter()
            .position(|s| std::ptr::eq(&**s, handle.cast::<FmuState>().cast_const()))
    }

    /// Stores `state` in the FMU state `existing` (one of this instance's, or NULL for a new
    /// one) and returns its handle.
    ///
    /// # Errors
    /// `existing` is neither NULL nor a state of this instance.
    pub fn store_state(
        &mut self,
        existing: fmi2FMUstate,
        state: FmuState,
    ) -> Result<fmi2FMUstate, String> {
        if existing.is_null() {
            let boxed = Box::new(state);
            let handle: fmi2FMUstate = std::ptr::from_ref::<FmuState>(&*boxed).cast_mut().cast();
            self.states.push(boxed);
            return Ok(handle);
        }
        let index = self
            .find_state(existing)
            .ok_or_else(|| "*FMUstate is neither NULL nor a state of this instance".to_string())?;
        if let Some(slot) = self.states.get_mut(index) {
            **slot = state;
        }
        Ok(existing)
    }

    /// The FMU state `handle` of this instance.
    ///
    /// # Errors
    /// `handle` is not a state of this instance (or was freed).
    pub fn state(&self, handle: fmi2FMUstate) -> Result<&FmuState, String> {
        self.find_state(handle)
            .and_then(|i| self.states.get(i))
            .map(|s| &**s)
            .ok_or_else(|| "the FMU state is not one of this instance (or was freed)".into())
    }

    /// fmi2FreeFMUstate.
    ///
    /// # Errors
    /// As [`Instance::state`].
    pub fn free_state(&mut self, handle: fmi2FMUstate) -> Result<(), String> {
        let index = self.find_state(handle).ok_or_else(|| {
            "the FMU state is not one of this instance (or was freed)".to_string()
        })?;
        self.states.remove(index);
        Ok(())
    }

    /// Whether this FMU's states are serialised: not for a model with dynamics or a rate term
    /// (canSerializeFMUstate = false; `crate::timed`).
    fn serialisable(&self) -> Result<(), String> {
        match &self.config.timing {
            Some(t) => Err(format!(
                "the model has {}: its FMU states are saved and restored in memory \
                 (fmi2GetFMUstate, fmi2SetFMUstate) but not serialised \
                 (canSerializeFMUstate = false)",
                t.what
            )),
            None => Ok(()),
        }
    }

    /// The serialised form of `state`, refused when it could not be read back (a non-finite x,
    /// k1 or k2: such a state can be restored in memory but not serialised).
    ///
    /// # Errors
    /// What [`Instance::deserialize`] would refuse.
    pub fn serialize(&self, state: &FmuState) -> Result<Vec<u8>, String> {
        self.serialisable()?;
        let bytes = state::encode(state, &self.owner)?;
        self.deserialize(&bytes)
            .map_err(|e| format!("the state cannot be serialised: {e}"))?;
        Ok(bytes)
    }

    /// Reads a serialised state and checks it completely: the bytes (see `state`), then the
    /// parameters and memory through the core, as a restore in step mode would.
    ///
    /// # Errors
    /// A message naming what is wrong.
    pub fn deserialize(&self, bytes: &[u8]) -> Result<FmuState, String> {
        self.serialisable()?;
        let state = state::decode(bytes, &self.owner)?;
        if !matches!(state.history, History::Empty) {
            self.engine_for(&state, true)?;
        }
        Ok(state)
    }
}
