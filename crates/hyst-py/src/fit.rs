//! `hyst.fit(x, y, **options)` and `hyst.FitResult`: the identification of `hyst fit`
//! (`hyst_fit::identify`) on arrays, with the same options, numbers and report.

use std::ops::ControlFlow;
use std::path::Path;
use std::time::{Duration, Instant};

use hyst_fit::identify::Request;
use hyst_fit::lm::{Observer, Progress};
use hyst_fit::pi_fit::PiOutputKind;
use hyst_fit::report::{text_report, Findings, Report, Summary};
use hyst_fit::{identify, DataOptions, Dataset, FitError, FitOptions, FormChoice, StartChoice};
use hyst_io::number::shortest;
use hyst_io::Table;
use hyst_model::{file::fnv1a64, Choice, ModelKind, Provenance, Units};
use hyst_model::{Hold, K2Kind, ModelFile, RateTerm, ShapingKind, Structure};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::samples_f64;
use crate::dicts::{by_parameter, reached, to_python};
use crate::errors::{self, choice, value_error};
use crate::model::Model;

/// Lets Ctrl-C (KeyboardInterrupt) stop a fit that runs without the GIL: every 50 ms the
/// observer asks Python for pending signals and stops the least squares if one raised.
struct Signals {
    last: Instant,
    raised: Option<PyErr>,
}

impl Observer for Signals {
    fn observe(&mut self, _progress: &Progress) -> ControlFlow<()> {
        if self.raised.is_some() {
            return ControlFlow::Break(());
        }
        if self.last.elapsed() < Duration::from_millis(50) {
            return ControlFlow::Continue(());
        }
        self.last = Instant::now();
        match Python::attach(|py| py.check_signals()) {
            Ok(()) => ControlFlow::Continue(()),
            Err(e) => {
                self.raised = Some(e);
                ControlFlow::Break(())
            }
        }
    }
}

/// Identifies a hysteresis model from the model's input samples `x` and the measured output
/// `y` (1-D arrays of the same length), as `hyst fit` does, and returns a `FitResult`.
///
/// The options mirror `hyst fit`'s flags, with the same names and values (docs/fitting.md):
/// `output_shaping`, `input_shaping` ("affine", "poly2", "poly3", "tanh", "langevin",
/// "quadratic-exp"), `k2` ("constant", "affine"), `model_kind` ("smooth",
/// "prandtl-ishlinskii"), `starts`, `segment` (cut every
/// record into segments of that many samples), `record` (an array of record ids, one per
/// sample: each record starts from its own initial state), `weight` (an array of weights
/// ≥ 0), `validate` (record ids held out), `validate_every`, `coverage`, `plays` (of a
/// Prandtl–Ishlinskii model), `pi_output`, `compare`, `input_offset`, `output_offset`,
/// `initial_state` ("auto": "falling" when every record only rises, as first-order reversal
/// curves, else "rising"; "rising", "falling", "line"), `estimate_initial_states` (estimate
/// each record's start from its data), `form` ("auto": the stop form for clockwise loops
/// such as friction, else the operator form; "operator"; "stop"), `keep_degenerate` (keep a
/// fit that found no hysteresis instead of raising ValueError), `input_name`, `output_name`
/// (the columns' names in the model file), `input_unit`, `output_unit`.
///
/// Dynamics and rate (`hyst fit --dynamics N --rate-term viscous --time COLUMN`): `dynamics`
/// (1 to 4) identifies Lemma 5.1's plant of order N between the input x (the command) and the
/// hysteresis, a_N v⁽ᴺ⁾ + … + a_1 v̇ + v = x, jointly with the hysteresis; `rate_term`
/// ("viscous") adds c·v̇ to the output. Both need `time`, the samples' time stamps in seconds
/// (one per sample, increasing within each record; each step is taken as measured, and a gap
/// of more than 10 times a record's median step splits it, with a note); `time` is refused
/// without them. `hold` ("zoh", the default, or "foh"; only with `dynamics`): the command held
/// over each step or linear between samples (`hyst fit --hold`). `dynamics="auto"` fits
/// orders 0 to 4 and keeps the best (`--dynamics auto`). Each record's start is discounted
/// until the fitted operator has forgotten its memory and the plant has settled
/// (`fit_from_start=True` counts every sample, trusting `initial_state`;
/// `estimate_initial_states=True` estimates each record's memory).
///
/// Raises ValueError with the CLI's words for bad options or data (a bad time stamp is named
/// as `t[i]`); Ctrl-C stops the fit with KeyboardInterrupt. The GIL is released while it runs.
#[pyfunction]
#[pyo3(signature = (
    x, y, *,
    output_shaping = "affine", input_shaping = "affine", k2 = "constant",
    model_kind = "smooth", starts = 3, segment = None, segments = None, record = None,
    weight = None, validate = None, validate_every = None, coverage = 0.99, plays = 16,
    pi_output = "none", compare = false, input_offset = None, output_offset = true,
    initial_state = "auto", estimate_initial_states = false, form = "auto",
    keep_degenerate = false, input_name = "x", output_name = "y", input_unit = "",
    output_unit = "", time = None, dynamics = None, rate_term = None, hold = None,
    fit_from_start = false, t = None
))]
#[allow(clippy::too_many_arguments)]
pub fn fit(
    py: Python<'_>,
    x: &Bound<'_, PyAny>,
    y: &Bound<'_, PyAny>,
    output_shaping: &str,
    input_shaping: &str,
    k2: &str,
    model_kind: &str,
    starts: usize,
    segment: Option<usize>,
    segments: Option<usize>,
    record: Option<&Bound<'_, PyAny>>,
    weight: Option<&Bound<'_, PyAny>>,
    validate: Option<Vec<i64>>,
    validate_every: Option<usize>,
    coverage: f64,
    plays: usize,
    pi_output: &str,
    compare: bool,
    input_offset: Option<bool>,
    output_offset: bool,
    initial_state: &str,
    estimate_initial_states: bool,
    form: &str,
    keep_degenerate: bool,
    input_name: &str,
    output_name: &str,
    input_unit: &str,
    output_unit: &str,
    time: Option<&Bound<'_, PyAny>>,
    dynamics: Option<&Bound<'_, PyAny>>,
    rate_term: Option<&str>,
    hold: Option<&str>,
    fit_from_start: bool,
    t: Option<&Bound<'_, PyAny>>,
) -> PyResult<FitResult> {
    if starts == 0 {
        return Err(value_error("starts = 0: expected at least 1 start"));
    }
    let t = errors::renamed(py, ("time", time), ("t", t))?;
    let t = t.as_ref();
    let (dynamics, auto_dynamics) = dynamics_arg(dynamics)?;
    let timed = timed(dynamics, auto_dynamics, rate_term, t.is_some())?;
    let hold_stated = hold.is_some();
    let hold = start_and_hold(fit_from_start, estimate_initial_states, hold, dynamics)?;
    let mut data = DataOptions {
        input: input_name.into(),
        output: output_name.into(),
        segment: one_segment(py, segment, segments)?,
        validate: validate.unwrap_or_default(),
        validate_every,
        timed: timed.is_some(),
        ..DataOptions::default()
    };
    // What to identify, as `hyst fit` builds it from its flags: the choices by their
    // command-line names (ValueError naming the option for another name).
    let request = Request {
        structure: Structure {
            k2: choice::<K2Kind>("k2", k2)?,
            input_shaping: choice::<ShapingKind>("input_shaping", input_shaping)?,
            output_shaping: choice::<ShapingKind>("output_shaping", output_shaping)?,
            input_offset,
            output_offset,
            dynamics: timed.map_or(0, |(order, _)| order),
            rate: timed.and_then(|(_, rate)| rate),
            hold,
            ..Structure::default()
        },
        kind: choice::<ModelKind>("model_kind", model_kind)?,
        compare,
        form: choice::<FormChoice>("form", form)?,
        start: choice::<StartChoice>("initial_state", initial_state)?,
        keep_degenerate,
        options: FitOptions {
            starts,
            coverage,
            estimate_starts: estimate_initial_states,
            fit_from_start,
            auto_dynamics,
            hold_stated,
            ..FitOptions::default()
        },
        plays,
        pi_output: choice::<PiOutputKind>("pi_output", pi_output)?,
        units: Units {
            input: input_unit.into(),
            output: output_unit.into(),
        },
    };
    let columns = Columns::read(x, y, record, weight, t, &mut data)?;
    identify_columns(py, columns, &data, &request)
}

/// Identifies the model from the arrays `columns` as `data` and `request` say (see
/// [`identify_without_gil`]): the `FitResult`, or ValueError naming a bad time stamp as the
/// sample `time[i]`.
fn identify_columns(
    py: Python<'_>,
    columns: Columns,
    data: &DataOptions,
    request: &Request,
) -> PyResult<FitResult> {
    let provenance = provenance(&columns.values);
    let has_record = data.record.is_some();
    let table = Table::new(columns.names, columns.values).map_err(|e| errors::fit(e.into()))?;
    // The time stamps, shared (not copied) for an error's message: the table moves into the
    // dataset.
    let time = table.samples(TIME).unwrap_or_default();
    let report =
        identify_without_gil(py, table, data, request, provenance).map_err(|e| match e {
            // A time stamp is named as the sample of `time`, not as the line of the in-memory table.
            Failed::Fit(FitError::BadTime {
                line,
                record,
                message,
                ..
            }) => bad_time(&time, line, has_record.then_some(record), &message),
            e => e.into_err(),
        })?;
    FitResult::new(py, report)
}

/// The hold of a fit (`hold`, the fit's default when not given; only with `dynamics`), after
/// checking that a record's start is not both trusted (`fit_from_start`) and estimated.
fn start_and_hold(
    fit_from_start: bool,
    estimate_initial_states: bool,
    hold: Option<&str>,
    dynamics: Option<i64>,
) -> PyResult<Hold> {
    if fit_from_start && estimate_initial_states {
        return Err(value_error(
            "fit_from_start=True and estimate_initial_states=True: a record's start is either \
             trusted or estimated, give one",
        ));
    }
    match hold {
        None => Ok(Hold::FIT_DEFAULT),
        Some(_) if dynamics.is_none() => Err(value_error(
            "hold: the hold is how the plant of a fit with dynamics sees its command; give \
             dynamics=N, or leave hold out",
        )),
        Some(name) => choice::<Hold>("hold", name),
    }
}

/// `dynamics`: None, a plant order (an int), or "auto" (the order picked from 0 to 4: order
/// 0 here, and `true`).
fn dynamics_arg(dynamics: Option<&Bound<'_, PyAny>>) -> PyResult<(Option<i64>, bool)> {
    let Some(d) = dynamics.filter(|d| !d.is_none()) else {
        return Ok((None, false));
    };
    if let Ok(text) = d.extract::<String>() {
        return if text == "auto" {
            Ok((Some(0), true))
        } else {
            Err(value_error(format!(
                "dynamics = {text:?}: the plant order 1 to 4, or \"auto\" (orders 0 to 4, the \
                 best kept)"
            )))
        };
    }
    d.extract::<i64>().map(|n| (Some(n), false)).map_err(|_| {
        value_error("dynamics: the plant order 1 to 4, or \"auto\" (orders 0 to 4, the best kept)")
    })
}

/// The plant order and rate term of a fit with dynamics or a rate term (`None` for a static
/// fit), checked: an order of 1 to 4 (as `hyst fit --dynamics`), a rate term by its CLI name,
/// and `time` given exactly when one of them is.
fn timed(
    dynamics: Option<i64>,
    auto_dynamics: bool,
    rate_term: Option<&str>,
    has_time: bool,
) -> PyResult<Option<(u8, Option<RateTerm>)>> {
    let order = match dynamics {
        None => 0,
        Some(0) if auto_dynamics => 0,
        Some(n) => match u8::try_from(n) {
            Ok(n) if (1..=4).contains(&n) => n,
            _ => {
                return Err(value_error(format!(
                    "dynamics = {n}: the plant order must be 1 to 4 (None: no dynamics)"
                )))
            }
        },
    };
    let rate = rate_term
        .map(|r| choice::<RateTerm>("rate_term", r))
        .transpose()?;
    if order == 0 && rate.is_none() && !auto_dynamics {
        if has_time {
            return Err(value_error(
                "time: time stamps apply to a fit with dynamics or rate_term; a static fit does not \
                 use them (leave time out, or give dynamics=N or rate_term=\"viscous\")",
            ));
        }
        return Ok(None);
    }
    if !has_time {
        return Err(value_error(
            "time: a fit with dynamics or rate_term needs the samples' time stamps time (s), one per \
             sample of x",
        ));
    }
    Ok(Some((order, rate)))
}

/// `ValueError` for the time stamp on `line` of the in-memory table (row `line − 2`), named as
/// the sample `t[i]` (and its record when the fit was given record ids).
fn bad_time(t: &[f64], line: usize, record: Option<i64>, message: &str) -> PyErr {
    let i = line.saturating_sub(2);
    let value = t.get(i).map_or_else(|| "?".into(), |v| shortest(*v));
    let record = record.map_or_else(String::new, |r| format!(" (record {r})"));
    value_error(format!("time[{i}] = {value}{record}: {message}"))
}

/// `segment` and its old name `segments` (a DeprecationWarning): the one given, or ValueError
/// when both are, apart.
fn one_segment(
    py: Python<'_>,
    segment: Option<usize>,
    segments: Option<usize>,
) -> PyResult<Option<usize>> {
    match (segment, segments) {
        (Some(a), Some(b)) if a != b => Err(value_error(format!(
            "segment = {a} and segments = {b}: give one (they are the same option)"
        ))),
        (a, Some(b)) => {
            errors::deprecated(py, "segments", "segment")?;
            Ok(a.or(Some(b)))
        }
        (a, None) => Ok(a),
    }
}

/// The names of the columns that hold the arrays `record`, `weight` and `t`.
const RECORD: &str = "record";
const WEIGHT: &str = "weight";
const TIME: &str = "time";

/// The arrays of a fit as the named columns of a table, as `hyst fit` reads them from a CSV
/// file: x and y under the input and output columns' names, then the record ids, the weights
/// and the time stamps when given.
struct Columns {
    names: Vec<String>,
    values: Vec<Vec<f64>>,
}

impl Columns {
    /// Reads the arrays (1-D, finite or not: the dataset checks the values) and checks their
    /// names apart and their lengths equal; time stamps must be finite (named `t[i]`). The
    /// columns are named as `data` names x and y, and `data` learns those of the other arrays.
    fn read(
        x: &Bound<'_, PyAny>,
        y: &Bound<'_, PyAny>,
        record: Option<&Bound<'_, PyAny>>,
        weight: Option<&Bound<'_, PyAny>>,
        t: Option<&Bound<'_, PyAny>>,
        data: &mut DataOptions,
    ) -> PyResult<Self> {
        let x = samples_f64(x, "x")?;
        let y = samples_f64(y, "y")?;
        let mut names = vec![data.input.clone(), data.output.clone()];
        if names[0] == names[1] {
            return Err(value_error(format!(
                "input_name and output_name are both {:?}: name the columns apart",
                data.input
            )));
        }
        let mut values = vec![x, y];
        for (array, name) in [(record, RECORD), (weight, WEIGHT), (t, TIME)] {
            if let Some(v) = array.filter(|v| !v.is_none()) {
                if names.iter().any(|n| n == name) {
                    return Err(value_error(format!(
                        "{name}: the column name {name:?} is taken by x or y; rename them"
                    )));
                }
                names.push(name.to_string());
                values.push(samples_f64(v, name)?);
            }
        }
        let n = values[0].len();
        // The arrays by their argument names ("record" and "weight" are also their columns').
        let arguments = ["x", "y"]
            .into_iter()
            .chain(names.iter().skip(2).map(String::as_str));
        for (name, c) in arguments.zip(&values).skip(1) {
            if c.len() != n {
                return Err(value_error(format!(
                    "{name} has {} samples but x has {n}",
                    c.len()
                )));
            }
        }
        // The time stamps (always after x and y): a non-finite one is named here as `t[i]`.
        let time = names.iter().skip(2).position(|n| n == TIME);
        let stamps = time
            .and_then(|i| values.get(i + 2))
            .map_or(&[][..], Vec::as_slice);
        if let Some((i, v)) = stamps.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(value_error(format!(
                "time[{i}] = {}: the time stamp is not a finite number",
                shortest(*v)
            )));
        }
        let named = |name: &str| names.iter().any(|n| n == name).then(|| name.to_string());
        data.record = named(RECORD);
        data.no_record = data.record.is_none();
        data.weight = named(WEIGHT);
        data.time = time.map(|_| TIME.to_string());
        Ok(Self { names, values })
    }
}

/// The model file's provenance of data given as arrays: the size and FNV-1a hash of the
/// columns' bytes (little-endian float64, column after column) and the number of rows.
fn provenance(columns: &[Vec<f64>]) -> Provenance {
    let mut bytes = Vec::with_capacity(8 * columns.len() * columns.first().map_or(0, Vec::len));
    for c in columns {
        for v in c {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    let rows = columns.first().map_or(0, Vec::len);
    Provenance {
        bytes: bytes.len() as u64,
        fnv1a64: format!("{:016x}", fnv1a64(&bytes)),
        ..hyst_fit::identify::provenance("<arrays>".into(), rows, "hyst.fit (Python)".into())
    }
}

/// Why a fit failed: the fit's error, or the exception a signal handler raised (Ctrl-C).
enum Failed {
    Fit(FitError),
    Raised(PyErr),
}

impl Failed {
    /// The Python exception: KeyboardInterrupt for an interrupted fit, the handler's own
    /// exception, else as [`errors::fit`].
    fn into_err(self) -> PyErr {
        match self {
            Failed::Raised(e) => e,
            Failed::Fit(e @ FitError::Interrupted) => {
                pyo3::exceptions::PyKeyboardInterrupt::new_err(e.to_string())
            }
            Failed::Fit(e) => errors::fit(e),
        }
    }
}

/// Reads the dataset from `table` and identifies the model without the GIL, as `hyst fit`
/// does; the report. A signal (Ctrl-C) during the fit stops it and raises its exception. The
/// table's columns move into the dataset (one copy of the data, not two).
fn identify_without_gil(
    py: Python<'_>,
    table: Table,
    options: &DataOptions,
    request: &Request,
    provenance: Provenance,
) -> Result<Report, Failed> {
    let (result, raised) = py.detach(|| {
        let data = match Dataset::from_table_owned(table, options) {
            Ok(d) => d,
            Err(e) => return (Err(e), None),
        };
        let mut observer = Signals {
            last: Instant::now(),
            raised: None,
        };
        let result = identify(&data, request, &mut observer, &|| false, provenance);
        (result, observer.raised)
    });
    if let Some(e) = raised {
        return Err(Failed::Raised(e));
    }
    result
        .map(|identified| identified.report)
        .map_err(Failed::Fit)
}

/// The result of `hyst.fit`: the model, its parameters with standard errors, the errors of the
/// fit, the family that reproduces the data with its bound, and the report `hyst fit` prints.
#[pyclass(module = "hyst")]
pub struct FitResult {
    report: Report,
    model: Py<Model>,
}

impl FitResult {
    fn new(py: Python<'_>, report: Report) -> PyResult<Self> {
        let model = Py::new(py, Model::new(report.model.clone(), false, "<fit>".into()))?;
        Ok(Self { report, model })
    }

    fn file(&self) -> &ModelFile {
        &self.report.model
    }
}

#[pymethods]
impl FitResult {
    /// The fitted model (a `Model`, as `hyst.load_model` gives): `.process`, `.inverse()`,
    /// `.save(path)`.
    #[getter]
    fn model(&self, py: Python<'_>) -> Py<Model> {
        self.model.clone_ref(py)
    }

    /// The parameters by name ("k1", "k2", "out.gain", "out.offset", …). k1 and k2 are in
    /// normalised input units (the input range maps to [−1, 1]); see `units`.
    #[getter]
    fn params<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        by_parameter(py, self.file(), |e| e.value)
    }

    /// The standard errors by name, from σ² (JᵀJ)⁻¹ (NaN where the data do not identify a
    /// parameter; they assume independent residuals).
    #[getter]
    fn std_errors<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        by_parameter(py, self.file(), |e| e.std_error)
    }

    /// The old name of `std_errors` (a DeprecationWarning).
    #[getter]
    fn stderr<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        errors::deprecated(py, "FitResult.stderr", "FitResult.std_errors")?;
        self.std_errors(py)
    }

    /// The parameters' units by name.
    #[getter]
    fn units<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        by_parameter(py, self.file(), |e| e.unit.clone())
    }

    /// RMS error on the training records (output units).
    #[getter]
    fn rms(&self) -> f64 {
        self.file().metrics.training.rms
    }

    /// RMS error as % of the output span.
    #[getter]
    fn rms_percent(&self) -> f64 {
        self.file().metrics.training.rms_pct_span
    }

    /// Largest absolute error on the training records (output units).
    #[getter]
    fn max_abs(&self) -> f64 {
        self.file().metrics.training.max_abs
    }

    /// The error statistics on the validation records (a dict), or None without them.
    #[getter]
    fn validation<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.file()
            .metrics
            .validation
            .as_ref()
            .map(|v| to_python(py, v))
            .transpose()
    }

    /// The family RH(k1, Δk1, k2, Δk2) that reproduces the data at the coverage asked
    /// (Definition 2.8), with its bound, as a dict (delta_k1, delta_k2, coverage, delta_a,
    /// output_bound, …); None when no family within Δk1 < k1, Δk2 < k2 reaches the coverage
    /// (or for a Prandtl–Ishlinskii model).
    #[getter]
    fn family<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        reached(self.file()).map(|w| to_python(py, w)).transpose()
    }

    /// Δa of that family (Proposition 3.2, operator units), None when the family is not
    /// reached.
    #[getter]
    fn delta_a(&self) -> Option<f64> {
        reached(self.file()).and_then(|w| w.delta_a)
    }

    /// The compensation error bound at the output (Δa through ψ_out's slope; output units),
    /// None when the family is not reached.
    #[getter]
    fn output_bound(&self) -> Option<f64> {
        reached(self.file()).and_then(|w| w.output_bound)
    }

    /// Wall time of the fit (s).
    #[getter]
    fn seconds(&self) -> f64 {
        self.file().metrics.fit_seconds
    }

    /// With `compare=True`: both model kinds' summaries (list of dicts); else empty.
    #[getter]
    fn comparison<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.report.comparison)
    }

    /// The report as `hyst fit` prints it.
    fn report(&self) -> String {
        text_report(&self.report)
    }

    /// The report as JSON, with the keys of `hyst fit --json`.
    fn to_json(&self) -> PyResult<String> {
        serde_json::to_string_pretty(&self.report).map_err(value_error)
    }

    /// Which way the data's loops run: "counterclockwise" (the output lags the input) or
    /// "clockwise" (it leads: friction); the smooth model's form follows it unless given.
    #[getter]
    fn orientation(&self) -> &'static str {
        self.report.findings.orientation.name()
    }

    /// The mean gap between the data's rising and falling branches, as a fraction of the
    /// output span (positive for clockwise).
    #[getter]
    fn loop_gap(&self) -> f64 {
        self.report.findings.loop_gap
    }

    /// True when the fit found no hysteresis and was kept (`keep_degenerate=True`).
    #[getter]
    fn degenerate(&self) -> bool {
        self.report.findings.degenerate
    }

    /// Notes of the identification, one sentence each (degeneracy, the Dahl limit, …).
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.report.findings.notes.clone()
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, Pickled)> {
        let me = slf.borrow();
        let restore = slf
            .py()
            .import("hyst._hyst")?
            .getattr("_fit_result_from_json")?;
        let toml = me.file().to_toml().map_err(errors::model)?;
        let comparison = serde_json::to_string(&me.report.comparison).map_err(value_error)?;
        let findings = serde_json::to_string(&me.report.findings).map_err(value_error)?;
        Ok((restore, (toml, me.report.output_span, comparison, findings)))
    }

    fn __repr__(&self) -> String {
        format!(
            "FitResult(kind={:?}, rms={:?}, rms_percent={:.4}, delta_a={})",
            self.file().kind.name(),
            self.rms(),
            self.rms_percent(),
            self.delta_a().map_or("None".into(), |d| format!("{d:?}"))
        )
    }
}

/// What pickling stores of a `FitResult`: the model file's TOML, the output span, the
/// comparison and the findings (JSON).
type Pickled = (String, f64, String, String);

/// Rebuilds a `FitResult` from what pickling stores: the model file's TOML, the output span,
/// the comparison and the findings (JSON).
#[pyfunction(name = "_fit_result_from_json")]
pub fn fit_result_from_json(
    py: Python<'_>,
    toml: &str,
    output_span: f64,
    comparison: &str,
    findings: &str,
) -> PyResult<FitResult> {
    let model = ModelFile::from_toml(toml, Path::new("<pickle>")).map_err(errors::model)?;
    let comparison: Vec<Summary> = serde_json::from_str(comparison).map_err(value_error)?;
    let findings: Findings = serde_json::from_str(findings).map_err(value_error)?;
    FitResult::new(
        py,
        Report {
            model_file: String::new(),
            input_units: hyst_model::input_units(&model),
            model,
            output_span,
            findings,
            comparison,
            plots: Vec::new(),
        },
    )
}
