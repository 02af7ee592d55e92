//! The timed model on arbitrary bytes: Lemma 5.1's plant before the hysteresis (order 1…4,
//! arbitrary coefficients), the rate term, either form, any sample period, any commands; and
//! the compensator of a model with dynamics on any desired outputs and derivatives.
//!
//! Invariants:
//! - `Dynamics::new`, `Dynamics::discretise`, `TimedRun::new`, `TimedCompensator::new` accept or
//!   refuse with a one-line error; an accepted plant's discretisation is finite;
//! - a run over finite commands gives finite v, z and y at every sample, or stops with a one-line
//!   error;
//! - a compensator step gives a finite command and hysteresis input, or a one-line error;
//! - a model file with the plant and rate term reads back with the same plant and rate term.

use crate::message::one_line;
use crate::operators::Bytes;
use hyst_model::dynamics::{DynamicsSection, RateSection};
use hyst_model::{Dynamics, Form, ModelFile, Rate, SmoothModel, TimedCompensator, TimedRun};
use std::path::Path;
use std::sync::OnceLock;

/// The static model the plant and rate term are added to (the fixture of the model tests).
const BASE: &str = include_str!("../../hyst-model/testdata/static-model.toml");

/// At most this many commands per input (the fuzzer's time goes to variety, not length).
const MAX_SAMPLES: usize = 64;

/// The timed model's checks on arbitrary bytes (see the module's documentation).
///
/// # Errors
/// A description of the broken invariant.
pub fn check_timed(data: &[u8]) -> Result<(), String> {
    let mut bytes = Bytes(data);
    let Some(mode) = bytes.u8() else {
        return Ok(());
    };
    let order = usize::from(mode % 4) + 1;
    let mut a = Vec::with_capacity(order);
    for _ in 0..order {
        let Some(x) = bytes.number::<f64>() else {
            return Ok(());
        };
        a.push(x);
    }
    let (Some(b), Some(c), Some(period), Some(k1)) = (
        bytes.number::<f64>(),
        bytes.number::<f64>(),
        bytes.number::<f64>(),
        bytes.number::<f64>(),
    ) else {
        return Ok(());
    };
    let b = if mode & 0x10 == 0 { 1.0 } else { b };
    let hold = if mode & 0x40 == 0 {
        hyst_model::Hold::Foh
    } else {
        hyst_model::Hold::Zoh
    };
    let dynamics = match Dynamics::new(b, &a) {
        Ok(d) => Some(d.with_hold(hold)),
        Err(e) => {
            one_line("Dynamics::new", &e.to_string())?;
            None
        }
    };
    if let Some(d) = &dynamics {
        match d.discretise(period) {
            Ok(discrete) => {
                let mut state = discrete.at_rest(1.0);
                let v = discrete.step(&mut state, -1.0);
                if !v.is_finite() {
                    return Err(format!(
                        "accepted discretisation of a = {a:?}, b = {b}, h = {period} gives v = {v}"
                    ));
                }
            }
            Err(e) => one_line("Dynamics::discretise", &e.to_string())?,
        }
    }
    let mut base = base()?;
    let Some(model) = base.smooth.as_mut() else {
        return Err("the base model is not smooth".into());
    };
    model.k1 = k1;
    model.dynamics = dynamics;
    if mode & 4 != 0 {
        model.rate = Some(Rate { c });
    }
    if mode & 8 != 0 {
        model.form = Form::Stop;
        model.linear = 0.5;
    }
    let model = *model;
    let mut commands = Vec::with_capacity(MAX_SAMPLES);
    let mut last = 0.0;
    while commands.len() < MAX_SAMPLES {
        let Some(x) = bytes.sample::<f64>(last, 1.0) else {
            break;
        };
        commands.push(x);
        last = x;
    }
    check_run(&model, period, &commands)?;
    check_compensator(&model, &commands)?;
    // The file round trip (TOML both ways) costs more than the rest: one input in two.
    if mode & 0x20 != 0 {
        check_file(&mut base, &model)?;
    }
    Ok(())
}

/// The base model, read once.
fn base() -> Result<ModelFile, String> {
    static BASE_FILE: OnceLock<Result<ModelFile, String>> = OnceLock::new();
    BASE_FILE
        .get_or_init(|| {
            ModelFile::from_toml(BASE, Path::new("base.toml"))
                .map_err(|e| format!("the base model does not read: {e}"))
        })
        .clone()
}

/// The run over `commands`: finite samples for finite commands, or a one-line error.
fn check_run(model: &SmoothModel, period: f64, commands: &[f64]) -> Result<(), String> {
    let Some(&first) = commands.first() else {
        return Ok(());
    };
    let mut run = match TimedRun::new(model, period, first) {
        Ok(run) => run,
        Err(e) => return one_line("TimedRun::new", &e.to_string()),
    };
    let mut stepped = Vec::with_capacity(commands.len());
    for (i, &u) in commands.iter().enumerate() {
        match run.step(u) {
            Ok(s) => {
                stepped.push(s.y.to_bits());
                if u.is_finite() && !(s.v.is_finite() && s.z.is_finite() && s.y.is_finite()) {
                    return Err(format!(
                        "sample {i}: the finite command {u} gives v = {}, z = {}, y = {}",
                        s.v, s.z, s.y
                    ));
                }
            }
            Err(e) => return one_line("TimedRun::step", &e.to_string()),
        }
    }
    // The whole-record entry point gives the same samples.
    let mut whole = Vec::with_capacity(commands.len());
    model
        .run_timed(
            commands,
            Some(&hyst_model::TimeSteps::even(period)),
            None,
            |_, s| whole.push(s.y.to_bits()),
        )
        .map_err(|e| format!("run_timed refused what TimedRun ran: {e}"))?;
    if whole != stepped {
        return Err(format!(
            "run_timed gave {whole:?}, TimedRun gave {stepped:?} (bits of y)"
        ));
    }
    Ok(())
}

/// The compensator on desired outputs and derivatives taken from `values`.
fn check_compensator(model: &SmoothModel, values: &[f64]) -> Result<(), String> {
    if let Err(e) = TimedCompensator::check(model) {
        return one_line("TimedCompensator::check", &e.to_string());
    }
    let Some(&first) = values.first() else {
        return Ok(());
    };
    let mut compensator = match TimedCompensator::new(model, first) {
        Ok(c) => c,
        Err(e) => return one_line("TimedCompensator::new", &e.to_string()),
    };
    let n = compensator.order();
    for (i, desired) in values.chunks(n + 1).enumerate() {
        match compensator.step(desired) {
            Ok((u, x)) if !(u.is_finite() && x.is_finite()) => {
                return Err(format!(
                    "step {i}: desired {desired:?} gives the command {u} and input {x}"
                ));
            }
            Ok(_) => {}
            Err(e) => one_line("TimedCompensator::step", &e.to_string())?,
        }
    }
    Ok(())
}

/// The model file with the plant and rate term reads back with both.
fn check_file(file: &mut ModelFile, model: &SmoothModel) -> Result<(), String> {
    if model.form == Form::Stop || !model.k1.is_finite() || model.k1 <= 0.0 {
        return Ok(());
    }
    file.dynamics = model.dynamics.map(|d| DynamicsSection {
        b: d.b,
        a: d.a().to_vec(),
        a_std_error: Vec::new(),
        identified: Vec::new(),
        hold: d.hold().recorded(),
    });
    file.rate = model.rate.filter(|r| r.c.is_finite()).map(|r| RateSection {
        c: r.c,
        c_std_error: f64::NAN,
    });
    if file.dynamics.is_some() || file.rate.is_some() {
        file.version = hyst_model::file::VERSION;
    }
    let text = match file.to_toml() {
        Ok(text) => text,
        Err(e) => return one_line("ModelFile::to_toml", &e.to_string()),
    };
    let again = match ModelFile::from_toml(&text, Path::new("again.toml")) {
        Ok(again) => again,
        Err(e) => return one_line("ModelFile::from_toml of a written file", &e.to_string()),
    };
    let back = again.smooth.as_ref();
    let same = back.map(|m| (m.dynamics, m.rate.map(|r| r.c.to_bits())))
        == Some((model.dynamics, model.rate.map(|r| r.c.to_bits())));
    if !same && file.rate.is_some() == model.rate.is_some() {
        return Err(format!(
            "the plant or rate term did not read back: wrote {:?} {:?}, read {:?}",
            model.dynamics,
            model.rate,
            back.map(|m| (m.dynamics, m.rate))
        ));
    }
    Ok(())
}
