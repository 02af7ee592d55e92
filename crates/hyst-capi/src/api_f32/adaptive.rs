//! The adaptive compensator of online adaptation, in caller memory
//! (`hyst_adaptive_*`): the exact inverse of a shaped model whose parameters (k1, k2, the output
//! gain and offset, and where asked the input gain and offset) an extended Kalman filter follows
//! from each pair of command and measured output (`hyst_core::adaptive`), and its settings
//! (`hyst_adaptive_config_f32`).
//!
//! A control loop calls `hyst_adaptive_step_f32` with the desired output, sends the command to
//! the actuator, and calls `hyst_adaptive_measure_f32` with the output it measured for it.
//!
//! GENERATED from `api_f64/adaptive.rs` by `scripts/gen-capi-f32`: do not edit.

use hyst_core::adaptive::{
    Adaptive, AdaptiveConfig, AdaptiveInverse, Parameter, Parameters, Status, Update,
    MAX_PARAMETERS,
};
use hyst_core::{AnyShaping, ScaledShaping, Shaping};

use crate::api_f32::checks::{done, done_into};
use crate::api_f32::shaped_model::hyst_shaped_model_params_f32;
use crate::engine;
use crate::slot;
use crate::status::{self, HYST_ERR_INVALID_PARAMETER, HYST_ERR_NO_COMMAND};
use crate::status::{HYST_ERR_NULL_POINTER, HYST_OK};
use crate::{
    hyst_adaptive_sample_counts, HYST_ADAPT_BAD_INPUT, HYST_ADAPT_BAD_OUTPUT, HYST_ADAPT_DEAD_ZONE,
    HYST_ADAPT_OUT_OF_RANGE, HYST_ADAPT_REFUSED, HYST_ADAPT_REST, HYST_ADAPT_STARTING,
    HYST_ADAPT_UPDATED, HYST_FORM_OPERATOR,
};

/// The settings of an adaptive compensator (`hyst_adaptive_init_f32`).
/// `hyst_adaptive_config_default_f32` fills them for a noise level; change the fields you need
/// after it.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct hyst_adaptive_config_f32 {
    /// The parameters that adapt: a bit mask of `HYST_ADAPT_K1`, `HYST_ADAPT_K2`,
    /// `HYST_ADAPT_GAIN`, `HYST_ADAPT_OFFSET`, `HYST_ADAPT_INPUT_GAIN` and
    /// `HYST_ADAPT_INPUT_OFFSET`, at least one (default: k1, k2, gain and offset, 0x0f).
    pub parameters: u32,
    /// σ of the measurement noise (output units), finite and > 0: the filter's R = noise².
    pub noise: f32,
    /// How fast the parameters may drift: σ of their relative random walk per k1 of input
    /// travel (default 1e-3: about 1 % over 100 loops of ±5 k1), finite and ≥ 0.
    pub drift: f32,
    /// σ of the fitted parameters' relative error at the start (default 0.01), finite and > 0;
    /// later σ grow with the drift up to max(uncertainty, 0.1).
    pub uncertainty: f32,
    /// The input travel, in units of k1, that must accumulate before an update (default 1e-3),
    /// finite and ≥ 0: at a constant command nothing moves.
    pub rest: f32,
    /// The largest relative change of any parameter in one update (default 0.01), finite and
    /// > 0.
    pub step: f32,
    /// k1, k2 and each gain stay within [fitted / range, fitted · range], each offset within
    /// ± range half-widths of the loop of its fitted value (default 4), finite and > 1.
    pub range: f32,
    /// Prediction errors of at most this size (output units) do not update (default 0),
    /// finite and ≥ 0.
    pub dead_zone: f32,
    /// Commands below this (input units) do not update (default -INFINITY); ≤ `input_max`.
    pub input_min: f32,
    /// Commands above this (input units) do not update (default INFINITY).
    pub input_max: f32,
}

impl hyst_adaptive_config_f32 {
    /// The settings as C gives them.
    fn of(c: &AdaptiveConfig<f32>) -> Self {
        let mut parameters = 0;
        for p in c.parameters.iter() {
            parameters |= 1 << p.index();
        }
        Self {
            parameters,
            noise: c.noise,
            drift: c.drift,
            uncertainty: c.uncertainty,
            rest: c.rest,
            step: c.step,
            range: c.range,
            dead_zone: c.dead_zone,
            input_min: c.input_range.0,
            input_max: c.input_range.1,
        }
    }

    /// The settings as the core takes them (checked by `Adaptive::new`), or
    /// `HYST_ERR_INVALID_PARAMETER` for a bit beyond `HYST_ADAPT_INPUT_OFFSET`.
    pub(crate) fn config(&self) -> Result<AdaptiveConfig<f32>, i32> {
        if self.parameters >> Parameter::ALL.len() != 0 {
            return Err(HYST_ERR_INVALID_PARAMETER);
        }
        let parameters = Parameter::ALL
            .into_iter()
            .filter(|p| self.parameters & (1 << p.index()) != 0)
            .collect::<Parameters>();
        Ok(AdaptiveConfig {
            parameters,
            noise: self.noise,
            drift: self.drift,
            uncertainty: self.uncertainty,
            rest: self.rest,
            step: self.step,
            range: self.range,
            dead_zone: self.dead_zone,
            input_range: (self.input_min, self.input_max),
        })
    }
}

/// An adaptive compensator: the estimator of a shaped model's drifting parameters and the exact
/// inverse of its current model, with the command waiting for its measurement: an opaque
/// block of 1024 bytes, 8-byte aligned, plain data (copyable with memcpy).
#[repr(C)]
pub struct hyst_adaptive_f32 {
    opaque: [u64; 128],
}

/// The compensator (duals of width `W`, shapes `S`) and the last command it gave or was told
/// about (what `*x` holds when a command is refused): the value behind `hyst_adaptive_f32` and
/// `hyst_affine_adaptive_f32`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct State<const W: usize, S> {
    compensator: AdaptiveInverse<f32, W, S>,
    held: Option<f32>,
}

/// The state of `hyst_adaptive_f32`: any shapes, any parameters.
type AnyState = State<MAX_PARAMETERS, AnyShaping<f32>>;

impl slot::Block for hyst_adaptive_f32 {
    type Value = AnyState;
    const TAG: u32 = 0x4859_4166; // "HYAf"
}

impl<const W: usize, S: Shaping<f32> + Copy> State<W, S> {
    /// `hyst_*adaptive_init`: writes into `a` the state of the model `params` with the settings
    /// `cfg` (`shaping` builds its shapes), or returns the status that refuses them.
    ///
    /// # Safety
    /// `a` is NULL or points to a writable block of its type; `params` and `cfg` are NULL or
    /// readable.
    pub(crate) unsafe fn init<B: slot::Block<Value = Self>>(
        a: *mut B,
        params: *const hyst_shaped_model_params_f32,
        cfg: *const hyst_adaptive_config_f32,
        shaping: engine::ShapingFn<f32, ScaledShaping<f32, S>>,
    ) -> i32 {
        if params.is_null() || cfg.is_null() {
            return HYST_ERR_NULL_POINTER;
        }
        // SAFETY: non-NULL (checked), readable (caller's contract).
        let (p, c) = unsafe { (params.read(), cfg.read()) };
        let config = match c.config() {
            Ok(config) => config,
            Err(s) => return s,
        };
        if p.form != HYST_FORM_OPERATOR || p.linear != 0.0 {
            return HYST_ERR_INVALID_PARAMETER;
        }
        let built = engine::initial_state(p.initial_state).and_then(|start| {
            let model = p.model_with(shaping)?;
            Adaptive::<f32, W, S>::of_width(&model, start, config)
        });
        let estimator = match built {
            Ok(estimator) => estimator,
            Err(e) => return status::of(&e),
        };
        let compensator = AdaptiveInverse::new(estimator);
        let held = None;
        // SAFETY: `a` is NULL or a writable block of its type (caller's contract).
        unsafe { slot::put(a, Self { compensator, held }) }
    }

    /// `hyst_*adaptive_step` on this state.
    ///
    /// # Safety
    /// `x` is non-NULL and writable.
    pub(crate) unsafe fn step(&mut self, desired: f32, x: *mut f32) -> i32 {
        let (value, result) = match self.compensator.step(desired) {
            Ok(command) => {
                self.held = Some(command);
                (Some(command), HYST_OK)
            }
            Err(e) => (self.held, status::of(&e)),
        };
        if let Some(v) = value {
            // SAFETY: non-NULL, writable (caller's contract).
            unsafe { x.write(v) };
        }
        result
    }

    /// `hyst_*adaptive_measure` on this state.
    ///
    /// # Safety
    /// `prediction` and `status` are NULL or writable.
    pub(crate) unsafe fn measure(&mut self, y: f32, prediction: *mut f32, status: *mut i32) -> i32 {
        match self.compensator.measure(y) {
            // SAFETY: forwarded contract.
            Some(u) => unsafe { report(u, prediction, status) },
            None => HYST_ERR_NO_COMMAND,
        }
    }

    /// `hyst_*adaptive_update` on this state.
    ///
    /// # Safety
    /// `prediction` and `status` are NULL or writable.
    pub(crate) unsafe fn update(
        &mut self,
        x: f32,
        y: f32,
        prediction: *mut f32,
        status: *mut i32,
    ) -> i32 {
        let u = self.compensator.update(x, y);
        if x.is_finite() {
            self.held = Some(x);
        }
        // SAFETY: forwarded contract.
        unsafe { report(u, prediction, status) }
    }

    /// `hyst_*adaptive_parameter` on this state.
    ///
    /// # Safety
    /// `value` is non-NULL and writable.
    pub(crate) unsafe fn parameter(&self, which: i32, value: *mut f32) -> i32 {
        let Some(p) = usize::try_from(which)
            .ok()
            .and_then(|i| Parameter::ALL.get(i))
        else {
            return HYST_ERR_INVALID_PARAMETER;
        };
        // SAFETY: non-NULL, writable (caller's contract).
        unsafe { value.write(self.compensator.estimator().value(*p)) };
        HYST_OK
    }

    /// `hyst_*adaptive_counts` on this state.
    ///
    /// # Safety
    /// `counts` is non-NULL and writable.
    pub(crate) unsafe fn counts(&self, counts: *mut hyst_adaptive_sample_counts) -> i32 {
        let c = self.compensator.estimator().counts();
        // SAFETY: non-NULL, writable (caller's contract).
        unsafe { counts.write(hyst_adaptive_sample_counts::of(&c)) };
        HYST_OK
    }
}

/// The `HYST_ADAPT_*` code of a sample's status: the codes are the statuses in the order of
/// `Status` (checked below at compile time), so the code is the discriminant.
fn code(s: Status) -> i32 {
    s as i32
}

const _: () = assert!(
    Status::Updated as i32 == HYST_ADAPT_UPDATED
        && Status::Rest as i32 == HYST_ADAPT_REST
        && Status::Starting as i32 == HYST_ADAPT_STARTING
        && Status::DeadZone as i32 == HYST_ADAPT_DEAD_ZONE
        && Status::BadInput as i32 == HYST_ADAPT_BAD_INPUT
        && Status::OutOfRange as i32 == HYST_ADAPT_OUT_OF_RANGE
        && Status::BadOutput as i32 == HYST_ADAPT_BAD_OUTPUT
        && Status::Refused as i32 == HYST_ADAPT_REFUSED
);

/// Writes a sample's prediction and status where the caller asked for them.
///
/// # Safety
/// `prediction` and `status` are NULL or writable.
unsafe fn report(u: Update<f32>, prediction: *mut f32, status: *mut i32) -> i32 {
    if !prediction.is_null() {
        // SAFETY: non-NULL (checked), writable (caller's contract).
        unsafe { prediction.write(u.prediction) };
    }
    if !status.is_null() {
        // SAFETY: non-NULL (checked), writable (caller's contract).
        unsafe { status.write(code(u.status)) };
    }
    HYST_OK
}

/// Fills `*cfg` with the default settings for measurements with noise σ `noise` (output units):
/// k1, k2, the output gain and offset adapt, and the core's defaults for the rest (see each
/// field of `hyst_adaptive_config_f32`): no dead zone, every command taken.
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, or `HYST_ERR_INVALID_PARAMETER` unless `noise` is
/// finite and > 0 (`*cfg` is then untouched).
///
/// # Safety
/// `cfg` is NULL or points to a writable `hyst_adaptive_config_f32`.
#[no_mangle]
pub unsafe extern "C" fn hyst_adaptive_config_default_f32(
    cfg: *mut hyst_adaptive_config_f32,
    noise: f32,
) -> i32 {
    if cfg.is_null() {
        return HYST_ERR_NULL_POINTER;
    }
    let c = AdaptiveConfig::new(noise);
    if let Err(e) = c.validate() {
        return status::of(&e);
    }
    // SAFETY: non-NULL (checked), writable (caller's contract).
    unsafe { cfg.write(hyst_adaptive_config_f32::of(&c)) };
    HYST_OK
}

/// Initialises `a` as the adaptive compensator of the shaped model `params` (the fitted model:
/// its parameters are where the estimator starts; operator form only, its start rule applies
/// at the first command) with the settings `cfg`.
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, `HYST_ERR_MISALIGNED`, `HYST_ERR_NOT_MONOTONE`
/// (a shaping function that is not increasing), or `HYST_ERR_INVALID_PARAMETER`: a bad model
/// parameter, the stop form (`HYST_FORM_STOP`: it has no inverse), a bad setting (see each
/// field of `hyst_adaptive_config_f32`), no parameter to adapt or an unknown bit in its mask, k2
/// asked of a k2 law that cannot be scaled. `a` is then untouched.
///
/// # Safety
/// `a` is NULL or points to a writable `hyst_adaptive_f32`; `params` and `cfg` are NULL or
/// readable.
#[no_mangle]
pub unsafe extern "C" fn hyst_adaptive_init_f32(
    a: *mut hyst_adaptive_f32,
    params: *const hyst_shaped_model_params_f32,
    cfg: *const hyst_adaptive_config_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { AnyState::init(a, params, cfg, engine::shaping) }
}

/// The command: `*x` (input units) = the exact inverse of the current model for the desired
/// output `desired` (output units), from the model's memory. Send it to the actuator, then give
/// its measured output to `hyst_adaptive_measure_f32`. A command still waiting for its measurement
/// is first taken as unmeasured (`HYST_ADAPT_BAD_OUTPUT`: the model follows the actuator, the
/// parameters do not move).
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, `HYST_ERR_MISALIGNED`, `HYST_ERR_NOT_INITIALISED`,
/// or for a desired output the model cannot produce `HYST_ERR_NON_FINITE` (NaN, infinite) or
/// `HYST_ERR_OUT_OF_RANGE` (beyond a saturating ψ_out): then no command waits for a
/// measurement, the model stays where the last command left it, and `*x` receives that command
/// (the actuator holds still), or is untouched before the first.
///
/// # Safety
/// `a` is NULL or an initialised `hyst_adaptive_f32`; `x` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_adaptive_step_f32(
    a: *mut hyst_adaptive_f32,
    desired: f32,
    x: *mut f32,
) -> i32 {
    // SAFETY: `x` is non-NULL (checked by `done_into`) and writable (caller's contract).
    done_into(x, || {
        slot::get_mut(a).map(|s| unsafe { s.step(desired, x) })
    })
}

/// The measurement: the output `y` (output units) measured for the last command updates the
/// estimator. `*prediction` receives the model's prediction of `y` (parameters before the
/// update) and `*status` what the sample did (`HYST_ADAPT_*`); either may be NULL. A non-finite
/// `y` is not an error: `HYST_OK` with `HYST_ADAPT_BAD_OUTPUT` (the model follows the command,
/// the parameters do not move).
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, `HYST_ERR_MISALIGNED`, `HYST_ERR_NOT_INITIALISED`,
/// or `HYST_ERR_NO_COMMAND` when no command waits for a measurement (nothing is written then).
///
/// # Safety
/// `a` is NULL or an initialised `hyst_adaptive_f32`; `prediction` and `status` are NULL or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_adaptive_measure_f32(
    a: *mut hyst_adaptive_f32,
    y: f32,
    prediction: *mut f32,
    status: *mut i32,
) -> i32 {
    // SAFETY: forwarded contract.
    done(slot::get_mut(a).map(|s| unsafe { s.measure(y, prediction, status) }))
}

/// A recorded sample, not commanded here (a record played back, a command from elsewhere):
/// the estimator's update for command `x` (input units) and measured output `y` (output units),
/// after any command still waiting for its measurement (taken as unmeasured). `*prediction` and
/// `*status` as in `hyst_adaptive_measure_f32`. A non-finite `x` or `y` is not an error: `HYST_OK`
/// with `HYST_ADAPT_BAD_INPUT` (the sample is skipped, the memory unchanged) or
/// `HYST_ADAPT_BAD_OUTPUT`.
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, `HYST_ERR_MISALIGNED` or
/// `HYST_ERR_NOT_INITIALISED`.
///
/// # Safety
/// `a` is NULL or an initialised `hyst_adaptive_f32`; `prediction` and `status` are NULL or
/// writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_adaptive_update_f32(
    a: *mut hyst_adaptive_f32,
    x: f32,
    y: f32,
    prediction: *mut f32,
    status: *mut i32,
) -> i32 {
    // SAFETY: forwarded contract.
    done(slot::get_mut(a).map(|s| unsafe { s.update(x, y, prediction, status) }))
}

/// `*value` = the current value of parameter `which`: the index of its `HYST_ADAPT_*` bit, 0 k1
/// (operator units), 1 k2 (at v = 0 for an affine law; 1 / operator units), 2 the output gain
/// and 3 the output offset (ψ_out's `post_gain`, `post_offset`; output units), 4 the input gain
/// and 5 the input offset (ψ_in's; operator units). A parameter that does not adapt keeps its
/// fitted value.
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, `HYST_ERR_MISALIGNED`, `HYST_ERR_NOT_INITIALISED`
/// or `HYST_ERR_INVALID_PARAMETER` for `which` outside 0 … 5 (`*value` untouched).
///
/// # Safety
/// `a` is NULL or an initialised `hyst_adaptive_f32`; `value` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_adaptive_parameter_f32(
    a: *const hyst_adaptive_f32,
    which: i32,
    value: *mut f32,
) -> i32 {
    // SAFETY: `value` is non-NULL (checked by `done_into`) and writable (caller's contract).
    done_into(value, || {
        slot::get(a).map(|s| unsafe { s.parameter(which, value) })
    })
}

/// `*counts` = how many samples had each `HYST_ADAPT_*` status since `hyst_adaptive_init_f32`.
///
/// Returns `HYST_OK`, `HYST_ERR_NULL_POINTER`, `HYST_ERR_MISALIGNED` or
/// `HYST_ERR_NOT_INITIALISED`.
///
/// # Safety
/// `a` is NULL or an initialised `hyst_adaptive_f32`; `counts` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn hyst_adaptive_counts_f32(
    a: *const hyst_adaptive_f32,
    counts: *mut hyst_adaptive_sample_counts,
) -> i32 {
    // SAFETY: `counts` is non-NULL (checked by `done_into`) and writable (caller's contract).
    done_into(counts, || slot::get(a).map(|s| unsafe { s.counts(counts) }))
}
