//! The Python side of a model with dynamics or a rate term (`Model.process(x, t=...)`,
//! `Model.compensate`): its time steps from the time stamps (a gap splits the record, with a
//! `UserWarning`), the run and the compensator of `hyst_model::timed`, as `hyst run --model`
//! runs a timed record (bit-identical results).

use std::ffi::CString;
use std::ops::Range;

use hyst_io::number::{shortest, sig};
use hyst_model::time::split;
use hyst_model::ModelFile;
use hyst_model::ModelKind;

use hyst_model::{
    Corner, Hold, Prefilter, Provenance, SmoothModel, TimeSteps, TimedCompensator, TimedRun,
};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;

use crate::arrays::{
    as_dtype, each_dtype, non_finite_derivative, samples, samples_f64, shape_of, signals, to_numpy,
    Samples, Stop, CHUNK,
};
use crate::errors::{self, value_error};
use hyst_core::Real as _;

/// A record's parts between gaps: their samples and time steps.
pub(crate) type Parts = Vec<(Range<usize>, TimeSteps)>;

/// Where a timed run's model comes from: its file's name (for messages) and what the file
/// records of its fit (the sample periods it was fitted at).
pub(crate) struct Origin<'a> {
    /// The model file, as messages name it.
    pub source: &'a str,
    /// The file's provenance.
    pub provenance: &'a Provenance,
}

impl<'a> Origin<'a> {
    /// The origin of a model read from `source`, with its file's `provenance`.
    pub fn of(source: &'a str, provenance: &'a Provenance) -> Self {
        Self { source, provenance }
    }
}

/// A `UserWarning` with `text`.
fn warn(py: Python<'_>, text: String) -> PyResult<()> {
    let message = CString::new(text).unwrap_or_default();
    let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
    PyErr::warn(py, &category, &message, 1)
}

/// Warns of the first part of a record sampled far from the periods the model of `origin` was
/// fitted at (a time axis in milliseconds runs without error, and wrong), as `hyst run` notes.
fn warn_periods(py: Python<'_>, origin: &Origin<'_>, parts: &Parts) -> PyResult<()> {
    let off = parts.iter().find_map(|(range, steps)| {
        origin
            .provenance
            .period_note(steps.nominal())
            .map(|note| (range.start, note))
    });
    match off {
        Some((start, note)) => warn(
            py,
            format!("{} (from sample {start}): {note}", origin.source),
        ),
        None => Ok(()),
    }
}

/// `Model.process` of a timed model `m` (from the file `source`): the whole of `x` as one
/// record starting at rest (each part after a gap afresh), at the steps of `time` or `period`,
/// under `hold` (the model file's when `None`).
#[allow(clippy::too_many_arguments)]
pub(crate) fn process<'py>(
    py: Python<'py>,
    m: &SmoothModel,
    origin: &Origin<'_>,
    x: &Bound<'py, PyAny>,
    derivatives: Option<&Bound<'py, PyAny>>,
    t: Option<&Bound<'py, PyAny>>,
    period: Option<f64>,
    hold: Option<&str>,
) -> PyResult<Bound<'py, PyAny>> {
    let source = origin.source;
    if derivatives.is_some() {
        return Err(value_error(format!(
            "derivatives: the model {} has {}: it runs without derivatives (give the \
             time stamps as time=..., or the sample period as period=...)",
            source,
            m.timed_parts()
        )));
    }
    let mut m = *m;
    if let Some(name) = hold {
        let hold: Hold = crate::errors::choice("hold", name)?;
        let Some(d) = m.dynamics else {
            return Err(value_error(format!(
                "hold = {name:?}: the model {source} has no dynamics (a rate term alone takes no \
                 hold)"
            )));
        };
        m.dynamics = Some(d.with_hold(hold));
    }
    let (x, f32) = values_of(x, "x")?;
    let what = format!("the model {} has {}", source, m.timed_parts());
    let Some(parts) = steps_of(py, t, period, x.len(), &what)? else {
        return Ok(as_array_of(py, x, f32));
    };
    warn_periods(py, origin, &parts)?;
    let y = py
        .detach(|| run_timed(&m, &x, &parts))
        .map_err(|e| e.into_err("x"))?;
    Ok(as_array_of(py, y, f32))
}

/// The smooth model of a model with dynamics or a rate term; `None` for a static model.
pub(crate) fn timed_model(file: &ModelFile) -> Option<&SmoothModel> {
    file.smooth
        .as_ref()
        .filter(|m| file.kind == ModelKind::Smooth && m.is_timed())
}

/// `ValueError` refusing a model with dynamics or a rate term for `what` (the model's own
/// words, [`ModelFile::untimed`]); `Ok` for a static model.
pub(crate) fn untimed(file: &ModelFile, what: &str) -> PyResult<()> {
    file.untimed(what).map_err(errors::model)
}

/// The parts and time steps of a timed record of `n` samples: from its time stamps `time` (each
/// step as measured; a gap of more than 10 median steps splits the record, with a
/// `UserWarning`; a bad stamp is named as `t[i]`) or every step `period` (s). Exactly one of
/// them. `None` for an empty record (with as many stamps, or a valid period): there is nothing
/// to run.
pub(crate) fn steps_of(
    py: Python<'_>,
    t: Option<&Bound<'_, PyAny>>,
    period: Option<f64>,
    n: usize,
    what: &str,
) -> PyResult<Option<Parts>> {
    match (t, period) {
        (Some(_), Some(_)) => Err(value_error(
            "time and period: give one (the time stamps, or the sample period of evenly sampled \
             ones)",
        )),
        (None, None) => Err(value_error(format!(
            "{what}: it needs the record's time stamps time (s), one per sample, or its sample \
             period (period=h, s)"
        ))),
        (None, Some(h)) => {
            if h.is_finite() && h > 0.0 {
                Ok((n > 0).then(|| vec![(0..n, TimeSteps::even(h))]))
            } else {
                Err(value_error(format!(
                    "period = {}: expected a finite, positive sample period (s)",
                    shortest(h)
                )))
            }
        }
        (Some(t), None) => {
            let t = samples_f64(t, "time")?;
            if t.len() != n {
                return Err(value_error(format!(
                    "time has {} samples but the record has {n}",
                    t.len()
                )));
            }
            if n == 0 {
                return Ok(None);
            }
            let (parts, gaps) = split(&t).map_err(|(i, message)| {
                let value = t.get(i).map_or_else(|| "?".into(), |v| shortest(*v));
                value_error(format!("time[{i}] = {value}: {message}"))
            })?;
            for gap in gaps {
                warn(py, format!("time[{}]: {}", gap.at, gap.describe()))?;
            }
            Ok(Some(parts))
        }
    }
}

/// The samples of a 1-D array as float64 values, and whether they were float32 (the result
/// then goes back to float32).
pub(crate) fn values_of(x: &Bound<'_, PyAny>, name: &str) -> PyResult<(Vec<f64>, bool)> {
    let xs = samples(x, name)?;
    let f32 = matches!(xs, Samples::F32(_));
    let values = each_dtype!(xs, a => a.as_array().iter().map(|v| v.as_f64()).collect());
    Ok((values, f32))
}

/// Results as a numpy array of the input's dtype (float32 when `f32`, else float64).
pub(crate) fn as_array_of(py: Python<'_>, values: Vec<f64>, f32: bool) -> Bound<'_, PyAny> {
    if f32 {
        #[allow(clippy::cast_possible_truncation)]
        to_numpy(
            py,
            values.into_iter().map(|v| v as f32).collect::<Vec<f32>>(),
        )
    } else {
        to_numpy(py, values)
    }
}

/// The desired output's first `order` time derivatives, one row per desired output: shape
/// (n, order) (1-D of length n for order 1), finite.
pub(crate) fn desired_derivatives(
    d: &Bound<'_, PyAny>,
    n: usize,
    order: usize,
) -> PyResult<Vec<Vec<f64>>> {
    use numpy::PyUntypedArrayMethods;
    let a = as_dtype(d, "derivatives", "float64")?;
    let expected = || {
        format!(
            "derivatives: the plant has order {order}: give the desired output's first {order} \
             time derivatives, shape ({n}, {order}){}, got shape {}",
            if order == 1 { " or (n,)" } else { "" },
            shape_of(&a)
        )
    };
    let one_d = a.cast::<PyArray1<f64>>().is_ok();
    let rows: Vec<Vec<f64>> = if let Ok(a1) = a.cast::<PyArray1<f64>>() {
        if order != 1 || a1.len() != n {
            return Err(value_error(expected()));
        }
        let ro = a1
            .try_readonly()
            .map_err(|e| value_error(format!("derivatives: the array cannot be read: {e}")))?;
        ro.as_array().iter().map(|v| vec![*v]).collect()
    } else if let Ok(a2) = a.cast::<PyArray2<f64>>() {
        if a2.shape() != [n, order] {
            return Err(value_error(expected()));
        }
        let ro = a2
            .try_readonly()
            .map_err(|e| value_error(format!("derivatives: the array cannot be read: {e}")))?;
        ro.as_array()
            .rows()
            .into_iter()
            .map(|r| r.to_vec())
            .collect()
    } else {
        return Err(value_error(expected()));
    };
    for (i, row) in rows.iter().enumerate() {
        if let Some((k, v)) = row.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(non_finite_derivative(i, k, *v, one_d));
        }
    }
    Ok(rows)
}

/// What `compensate` was given for the desired output's derivatives.
pub(crate) enum Given<'a, 'py> {
    /// The derivatives themselves (an array, checked later against the record).
    Derivatives(&'a Bound<'py, PyAny>),
    /// The bandwidth (Hz, finite and positive) of the reference prefilter that makes them.
    Prefilter(f64),
}

/// Exactly one of `derivatives` and `prefilter_hz` (a finite, positive bandwidth: its bound
/// for the record's sample period is [`bandwidth`]'s, once the period is known), for a plant
/// of order `order`.
pub(crate) fn derivatives_from<'a, 'py>(
    derivatives: Option<&'a Bound<'py, PyAny>>,
    prefilter_hz: Option<f64>,
    order: usize,
) -> PyResult<Given<'a, 'py>> {
    match (derivatives, prefilter_hz) {
        (Some(d), None) => Ok(Given::Derivatives(d)),
        (None, Some(hz)) => {
            bandwidth(hz, None)?;
            Ok(Given::Prefilter(hz))
        }
        (Some(_), Some(_)) => Err(value_error(
            "derivatives and prefilter_hz: give one (the desired output's derivatives, or the \
             bandwidth of the prefilter that makes them)",
        )),
        (None, None) => Err(value_error(format!(
            "the compensator of a plant of order {order} needs the desired output's first \
             {order} time derivatives: give derivatives (shape (n, {order})) or a reference \
             prefilter (prefilter_hz=F, the bandwidth in Hz the commands then track)"
        ))),
    }
}

/// `prefilter_hz` checked as `hyst run` checks `--prefilter-hz`: a finite, positive frequency,
/// and with the nominal step `period` (s) of a part of the record, at most 1/20 of its Nyquist
/// frequency (`hyst_model::Prefilter::check_bandwidth`).
pub(crate) fn bandwidth(hz: f64, period: Option<f64>) -> PyResult<()> {
    Prefilter::check_bandwidth(hz, period)
        .map_err(|e| value_error(format!("prefilter_hz = {}: {e}", shortest(hz))))
}

/// Where the desired output's derivatives come from: given, or a reference prefilter of this
/// bandwidth (Hz), started afresh with each part of the record.
pub(crate) enum Reference {
    Given(Vec<Vec<f64>>),
    Prefilter(f64),
}

/// Runs the model with dynamics or a rate term `m` over the commands `x` (one record, each of
/// its `parts` started at rest at its first command): `hyst run --model M` on a timed record.
/// Checks for Ctrl-C every [`CHUNK`] samples.
pub(crate) fn run_timed(m: &SmoothModel, x: &[f64], parts: &Parts) -> Result<Vec<f64>, Stop> {
    let refused = |index: usize, value: f64, error| {
        Stop::Refused(crate::arrays::Refused {
            index,
            value,
            error,
        })
    };
    let mut y = Vec::with_capacity(x.len());
    for (range, steps) in parts {
        let start = range.start;
        let first = x.get(start).copied().unwrap_or(0.0);
        let mut run =
            TimedRun::new(m, steps.nominal(), first).map_err(|e| refused(start, first, e))?;
        let walk = std::iter::once(steps.nominal()).chain(steps.walk());
        for ((i, u), h) in x.iter().enumerate().take(range.end).skip(start).zip(walk) {
            if i > 0 && i % CHUNK == 0 {
                signals()?;
            }
            y.push(run.step_after(*u, h).map_err(|e| refused(i, *u, e))?.y);
        }
    }
    Ok(y)
}

/// A model error's reason after the sample that caused it: the core's own words for a refused
/// value (as the static model's `x[i] = v: …`), else the message of [`errors::model`].
pub(crate) fn reason(e: hyst_model::ModelError) -> String {
    match e {
        hyst_model::ModelError::Core(e) => e.to_string(),
        e => hyst_fit::FitError::from(e).to_string(),
    }
}

/// Why a compensator run stopped: the desired output it refused (index, value, reason) or a
/// signal handler's exception.
pub(crate) enum Halt {
    At(usize, f64, String),
    Interrupted(PyErr),
}

/// Lemma 5.1's compensator of `m` over the desired outputs `desired` (one record, each of its
/// `parts` started afresh), their derivatives from `reference`: the computation of
/// `hyst run --model M --inverse` on a timed record, command by command. Returns the commands
/// and the reference each was computed for (the prefiltered one with a prefilter, as
/// `hyst run` writes it in `<column>_filtered`; else the desired output itself).
pub(crate) fn run_compensator(
    m: &SmoothModel,
    desired: &[f64],
    reference: &Reference,
    parts: &Parts,
) -> Result<Compensated, Halt> {
    let order = m.dynamics.map_or(0, |d| d.order());
    let mut out = Vec::with_capacity(desired.len());
    let mut followed = Vec::with_capacity(desired.len());
    let mut unresolved = None;
    for (range, steps) in parts {
        let start = range.start;
        let first = desired.get(start).copied().unwrap_or(0.0);
        let mut c = TimedCompensator::new(m, first).map_err(|e| {
            Halt::At(
                start,
                first,
                format!("the compensator cannot start here: {}", reason(e)),
            )
        })?;
        let mut prefilter = match reference {
            Reference::Prefilter(hz) => Some(
                Prefilter::new(order, *hz, steps.nominal(), first)
                    .map_err(|e| Halt::At(start, first, reason(e)))?,
            ),
            Reference::Given(_) => None,
        };
        let walk = std::iter::once(steps.nominal()).chain(steps.walk());
        for ((i, value), h) in desired
            .iter()
            .enumerate()
            .take(range.end)
            .skip(start)
            .zip(walk)
        {
            if i > 0 && i % CHUNK == 0 {
                if let Err(Stop::Interrupted(e)) = signals() {
                    return Err(Halt::Interrupted(e));
                }
            }
            let jet: Vec<f64> = match (&mut prefilter, reference) {
                (Some(p), _) => p
                    .step_after(*value, h)
                    .map_err(|e| Halt::At(i, *value, reason(e)))?
                    .get(..=order)
                    .unwrap_or(&[])
                    .to_vec(),
                (None, Reference::Given(d)) => std::iter::once(*value)
                    .chain(d.get(i).into_iter().flatten().copied())
                    .collect(),
                (None, Reference::Prefilter(_)) => vec![*value],
            };
            let (u, _) = c.step(&jet).map_err(|e| Halt::At(i, *value, reason(e)))?;
            out.push(u);
            followed.push(jet.first().copied().unwrap_or(*value));
        }
        if unresolved.is_none() {
            unresolved = c
                .fastest_corner()
                .filter(|corner| !corner.resolved_by(steps.nominal()))
                .map(|corner| (start + corner.sample, corner, steps.nominal()));
        }
    }
    Ok(Compensated {
        commands: out,
        followed,
        unresolved,
    })
}

/// What [`run_compensator`] gives: the commands, the reference each was computed for, and the
/// first part's fastest corner its sample period does not resolve (with the sample where it
/// was met and that period, s).
pub(crate) struct Compensated {
    /// The commands.
    pub commands: Vec<f64>,
    /// The reference each command was computed for.
    pub followed: Vec<f64>,
    /// The first unresolved corner: its sample, the corner and the part's period (s).
    pub unresolved: Option<(usize, Corner, f64)>,
}

/// `Model.compensate` of the smooth model `m` (from the file `source`) with dynamics: the
/// commands for `desired` at the steps of `timing` (the time stamps t or the period), the
/// derivatives given or from a prefilter of `prefilter_hz`; with the prefilter, the pair
/// (commands, prefiltered reference).
pub(crate) fn compensate<'py>(
    py: Python<'py>,
    m: &SmoothModel,
    origin: &Origin<'_>,
    desired: &Bound<'py, PyAny>,
    timing: (Option<&Bound<'py, PyAny>>, Option<f64>),
    derivatives: Option<&Bound<'py, PyAny>>,
    prefilter_hz: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    TimedCompensator::check(m).map_err(errors::model)?;
    let source = origin.source;
    let order = m.dynamics.map_or(0, |d| d.order());
    let (desired, f32) = values_of(desired, "desired")?;
    let given = derivatives_from(derivatives, prefilter_hz, order)?;
    let what = format!("the compensator of the model {source} (dynamics of order {order})");
    let filtered = matches!(given, Given::Prefilter(_));
    let answer = |commands: Vec<f64>, followed: Vec<f64>| -> PyResult<Bound<'py, PyAny>> {
        let commands = as_array_of(py, commands, f32);
        if filtered {
            let reference = as_array_of(py, followed, f32);
            Ok(pyo3::types::PyTuple::new(py, [commands, reference])?.into_any())
        } else {
            Ok(commands)
        }
    };
    let Some(parts) = steps_of(py, timing.0, timing.1, desired.len(), &what)? else {
        return answer(desired.clone(), desired);
    };
    warn_periods(py, origin, &parts)?;
    let reference = match given {
        Given::Derivatives(d) => Reference::Given(desired_derivatives(d, desired.len(), order)?),
        Given::Prefilter(hz) => {
            // Every part's sample period carries the bandwidth, or nothing runs.
            for (_, steps) in &parts {
                bandwidth(hz, Some(steps.nominal()))?;
            }
            let first = desired.first().copied().unwrap_or(0.0);
            let nominal = parts.first().map_or(1.0, |(_, s)| s.nominal());
            Prefilter::new(order, hz, nominal, first).map_err(errors::model)?;
            Reference::Prefilter(hz)
        }
    };
    let run = py
        .detach(|| run_compensator(m, &desired, &reference, &parts))
        .map_err(|halt| match halt {
            Halt::At(i, value, message) => {
                value_error(format!("desired[{i}] = {}: {message}", shortest(value)))
            }
            Halt::Interrupted(e) => e,
        })?;
    if let Some((i, corner, h)) = run.unresolved {
        let warning = corner.warning(h, "the period", |v| sig(v, 4));
        warn(py, format!("desired[{i}]: {warning}"))?;
    }
    answer(run.commands, run.followed)
}
