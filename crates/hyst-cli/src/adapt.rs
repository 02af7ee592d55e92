//! `hyst adapt`: a fitted model's parameters followed over a record by the recursive estimator
//! of `hyst_core::adaptive`, with the one-step prediction and each parameter per row.
//!
//! Contract (relied on by tests and other tools):
//! - OUTPUT holds every column of DATA first, unchanged (each cell as read), then `y_pred` (the
//!   one-step prediction of the output column, with the parameters before that row's update),
//!   then one column per adapted parameter (`k1`, `k2`, `gain`, `offset`, `input_gain`,
//!   `input_offset`: their values after that row's update). A computed name DATA already has
//!   gets the suffix `_out`. A row whose command is not finite has an empty `y_pred`.
//! - A measurement that is empty, `nan` or infinite, a command that is not finite or is outside
//!   the input range: the row is written, its update skipped and counted (`counts` of the
//!   summary). Any other cell that is not a number in those two columns is an error naming the
//!   file, line and column.
//! - The summary (`--json`: one JSON object on standard output, or on standard error with
//!   `-o -`) has `rms_fixed` (the fitted model, not adapted, run over the same rows from the
//!   same start) and `rms_adaptive` (the one-step prediction), over the rows after `--settle`
//!   whose measurement and both predictions are finite, summed without overflow (any finite
//!   errors give a finite RMS unless the RMS itself exceeds the largest double); `rms_note`
//!   says why when either is `null` (no such row, or that) and is `null` otherwise.
//! - The file is streamed; OUTPUT is written atomically (nothing on failure), and must not be
//!   DATA or the model file.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use hyst_core::adaptive::{Adaptive, AdaptiveConfig, Parameter, Parameters, Status};
use hyst_core::Operator;
use hyst_io::number::{shortest, sig};
use hyst_io::{CsvReader, CsvWriter, IoError};
use hyst_model::{ModelFile, SmoothModel};

/// Arguments of `hyst adapt`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The fitted model file (a smooth model of the operator form, static: no [dynamics] or
    /// [rate]).
    #[arg(long)]
    pub model: PathBuf,
    /// The command column (default: the model's input column).
    #[arg(long, value_name = "NAME")]
    pub input: Option<String>,
    /// The measured output column (default: the model's output column).
    #[arg(long, value_name = "NAME")]
    pub output: Option<String>,
    /// The parameters that adapt, comma-separated, from k1, k2, gain, offset, input_gain,
    /// input_offset.
    #[arg(long, value_delimiter = ',', default_value = "k1,k2,gain,offset")]
    pub parameters: Vec<String>,
    /// σ of the measurement noise (output units; default: the model's training RMS).
    #[arg(long, allow_negative_numbers = true)]
    pub noise: Option<f64>,
    /// σ of the parameters' relative drift per k1 of input travel.
    #[arg(long, default_value_t = 1e-3, allow_negative_numbers = true)]
    pub drift: f64,
    /// σ of the fitted parameters' relative error at the start (later σ grow with the drift,
    /// up to the larger of this and 0.1).
    #[arg(long, default_value_t = 0.01, allow_negative_numbers = true)]
    pub uncertainty: f64,
    /// Input travel (in units of k1) between updates: at a constant input nothing moves.
    #[arg(long, default_value_t = 1e-3, allow_negative_numbers = true)]
    pub rest: f64,
    /// Largest relative change of any parameter in one update.
    #[arg(long, default_value_t = 0.01, allow_negative_numbers = true)]
    pub step: f64,
    /// Each gain, k1 and k2 stays within [fitted / R, fitted · R]; each offset within R
    /// half-widths of the loop.
    #[arg(long, default_value_t = 4.0, allow_negative_numbers = true)]
    pub range: f64,
    /// Prediction errors of at most this size (output units) do not update.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub dead_zone: f64,
    /// Commands outside MIN,MAX (input units) do not update (default: for a fitted model, the
    /// input range it was fitted on widened by 10 % of its span on each side; else none).
    #[arg(long, value_name = "MIN,MAX", allow_hyphen_values = true)]
    pub input_range: Option<String>,
    /// Records that are separate experiments (B-H loops of other amplitudes): wherever the
    /// value of COLUMN changes, the model and the estimator start afresh from the fitted
    /// parameters (by the start rule). COLUMN may hold numbers or text labels. A record that is
    /// one history (FORC curves in measurement order) needs no --record.
    #[arg(long, value_name = "COLUMN")]
    pub record: Option<String>,
    /// The first SAMPLES rows are left out of rms_fixed and rms_adaptive (a settling time).
    #[arg(long, default_value_t = 0, value_name = "SAMPLES")]
    pub settle: usize,
    /// Also write the model file of the parameters at the end of the record (for hyst run,
    /// hyst export, the bindings): the fit's file with k1, k2 and the shaping functions
    /// replaced. Written atomically.
    #[arg(long, value_name = "FILE")]
    pub model_out: Option<PathBuf>,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
    /// The record (CSV with a header row).
    pub data: PathBuf,
    /// Output CSV file: written atomically; `-` is standard output. Must not be DATA.
    #[arg(short = 'o', long = "out", alias = "output-file", value_name = "FILE")]
    pub output_file: PathBuf,
}

/// Runs `hyst adapt`.
pub fn main(args: Args) -> Result<()> {
    let file = ModelFile::read(&args.model)?;
    let smooth = hyst_model::adaptive::adaptable(&file)
        .with_context(|| format!("hyst adapt --model {}", args.model.display()))?;
    let config = config(&args, &file, smooth)?;
    let mut reader = CsvReader::open(&args.data)?;
    let x_name = args.input.as_deref().unwrap_or(&file.columns.input);
    let y_name = args.output.as_deref().unwrap_or(&file.columns.output);
    let xi = reader.column(x_name)?;
    let yi = reader.column(y_name)?;
    let ri = args
        .record
        .as_deref()
        .map(|r| reader.column(r))
        .transpose()?;
    let mut label: Option<String> = None;
    let adapted: Vec<Parameter> = config.parameters.iter().collect();
    let names = output_names(reader.names(), &adapted);
    let mut out = CsvWriter::create(&args.output_file, names)?;
    let mut run = Run::new(smooth, config, args.settle);
    let width = reader.names().len() + 1 + adapted.len();
    let mut row = String::new();
    while let Some(line) = reader.next_cells()? {
        let x = measured(&reader, xi, line)?;
        let y = measured(&reader, yi, line)?;
        if let Some(ri) = ri {
            let this = reader.cell_text(ri, line)?;
            if label.as_deref().is_some_and(|l| l != this) {
                run.restart();
            }
            if label.as_deref() != Some(this) {
                label = Some(this.to_string());
            }
        }
        let prediction = run.sample(x, y)?;
        row.clear();
        reader.push_cells(line, &mut row)?;
        push_value(&mut row, prediction);
        if let Some(a) = &run.adaptive {
            for p in &adapted {
                push_value(&mut row, a.value(*p));
            }
        } else {
            for _ in &adapted {
                push_value(&mut row, f64::NAN);
            }
        }
        out.write_row_after(&row, width, &[])?;
    }
    out.finish()?;
    if let Some(path) = &args.model_out {
        let Some(a) = &run.adaptive else {
            bail!(
                "--model-out: {} has no row with a finite command to adapt on",
                args.data.display()
            );
        };
        let adapted = hyst_model::adaptive::adapted_file(&file, &a.model()?, &command_line());
        hyst_fit::file::write(&adapted, path)?;
    }
    let summary = run.summary(&args, &adapted, &config);
    let to_stderr = args.output_file.as_os_str() == "-";
    let text = if args.json {
        format!("{}\n", serde_json::to_string_pretty(&summary)?)
    } else {
        text(&summary)
    };
    if to_stderr {
        eprint!("{text}");
    } else {
        out!("{text}");
    }
    Ok(())
}

/// The estimator's settings from the arguments and the model file.
fn config(args: &Args, file: &ModelFile, smooth: &SmoothModel) -> Result<AdaptiveConfig<f64>> {
    let mut parameters = Parameters::NONE;
    for name in &args.parameters {
        let Some(p) = Parameter::from_name(name.trim()) else {
            bail!(
                "--parameters: {name:?} is not a parameter: give some of k1, k2, gain, offset, \
                 input_gain, input_offset"
            );
        };
        parameters = parameters.with(p);
    }
    let noise = match args
        .noise
        .or_else(|| hyst_model::adaptive::training_noise(file))
    {
        Some(n) => n,
        None => bail!(
            "--noise is needed: {} has no training RMS to take the measurement noise from",
            args.model.display()
        ),
    };
    let input_range = match args.input_range.as_deref() {
        Some(text) => parse_range(text)?,
        None => hyst_model::adaptive::fitted_input_range(file, smooth),
    };
    let config = AdaptiveConfig {
        parameters,
        noise,
        drift: args.drift,
        uncertainty: args.uncertainty,
        rest: args.rest,
        step: args.step,
        range: args.range,
        dead_zone: args.dead_zone,
        input_range,
    };
    config
        .validate()
        .map_err(|e| anyhow::anyhow!("--{}", flag_of(&e)))?;
    Ok(config)
}

/// `--input-range MIN,MAX`.
fn parse_range(text: &str) -> Result<(f64, f64)> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let numbers: Vec<Option<f64>> = parts.iter().map(|p| p.parse::<f64>().ok()).collect();
    match numbers.as_slice() {
        [Some(lo), Some(hi)] if lo <= hi => Ok((*lo, *hi)),
        _ => bail!("--input-range {text:?}: give two numbers MIN,MAX with MIN <= MAX"),
    }
}

/// The setting's flag and the core's message.
fn flag_of(e: &hyst_core::Error) -> String {
    match e {
        hyst_core::Error::InvalidParameter {
            name,
            value,
            expected,
        } => format!(
            "{} {}: must be {expected}",
            name.replace('_', "-"),
            shortest(*value)
        ),
        other => other.to_string(),
    }
}

/// A command or measurement cell: NaN for a cell that is empty or not finite (the estimator
/// skips and counts it); an error naming the file, line and column for any other text.
fn measured<R: std::io::Read>(reader: &CsvReader<R>, index: usize, line: usize) -> Result<f64> {
    if reader.cell_text(index, line)?.is_empty() {
        return Ok(f64::NAN);
    }
    match reader.value(index, line) {
        Ok(v) => Ok(v),
        Err(IoError::NonFinite { .. }) => Ok(f64::NAN),
        Err(e) => Err(e.into()),
    }
}

/// OUTPUT's names: DATA's, then `y_pred` and the parameters, each made distinct with `_out`.
fn output_names(input: &[String], adapted: &[Parameter]) -> Vec<String> {
    let mut names = input.to_vec();
    let mut taken = input.iter().cloned().collect();
    let computed = std::iter::once("y_pred").chain(adapted.iter().map(|p| p.name()));
    for name in computed {
        crate::naming::push_distinct(&mut names, &mut taken, name.to_string());
    }
    names
}

/// Appends one computed cell (shortest round-trip form; empty for NaN) and a separator.
fn push_value(row: &mut String, v: f64) {
    if v.is_finite() {
        row.push_str(&shortest(v));
    }
    row.push(',');
}

/// The estimator and the fixed model over one record, with the error sums.
struct Run<'a> {
    smooth: &'a SmoothModel,
    config: AdaptiveConfig<f64>,
    adaptive: Option<Adaptive<f64>>,
    fixed: Option<hyst_model::smooth::CoreShapedModel>,
    settle: usize,
    rows: usize,
    used: usize,
    sum_fixed: SquareSum,
    sum_adaptive: SquareSum,
    /// Rows with a command that is not finite before the first model started.
    bad_before_start: u64,
}

impl<'a> Run<'a> {
    fn new(smooth: &'a SmoothModel, config: AdaptiveConfig<f64>, settle: usize) -> Self {
        Self {
            smooth,
            config,
            adaptive: None,
            fixed: None,
            settle,
            rows: 0,
            used: 0,
            sum_fixed: SquareSum::default(),
            sum_adaptive: SquareSum::default(),
            bad_before_start: 0,
        }
    }

    /// A new record (a separate experiment): both models start afresh from the fitted
    /// parameters at its first command.
    fn restart(&mut self) {
        if let Some(a) = self.adaptive.as_mut() {
            a.reset();
        }
        self.fixed = None;
    }

    /// One row: the one-step prediction (NaN for a command that is not finite).
    fn sample(&mut self, x: f64, y: f64) -> Result<f64> {
        self.rows += 1;
        if self.fixed.is_none() {
            if !x.is_finite() {
                self.bad_before_start += 1;
                return Ok(f64::NAN);
            }
            // Both start by the model's start rule at the record's first command, as `hyst
            // run` does.
            self.fixed = Some(
                self.smooth
                    .core(x)
                    .context("the model cannot start at the first command")?,
            );
            if self.adaptive.is_none() {
                self.adaptive = Some(hyst_model::adaptive::estimator(self.smooth, self.config)?);
            }
        }
        let (Some(a), Some(fixed)) = (self.adaptive.as_mut(), self.fixed.as_mut()) else {
            return Ok(f64::NAN);
        };
        let update = a.update(x, y);
        let fixed_y = if update.status == Status::BadInput {
            f64::NAN
        } else {
            fixed.try_step(x).unwrap_or(f64::NAN)
        };
        let p = update.prediction;
        if self.rows > self.settle && y.is_finite() && p.is_finite() && fixed_y.is_finite() {
            self.used += 1;
            self.sum_fixed.add(y, fixed_y);
            self.sum_adaptive.add(y, p);
        }
        Ok(p)
    }

    fn summary(
        &self,
        args: &Args,
        adapted: &[Parameter],
        config: &AdaptiveConfig<f64>,
    ) -> serde_json::Value {
        let rms = |s: &SquareSum| s.rms(self.used).unwrap_or(f64::NAN);
        let (fixed, adaptive) = (rms(&self.sum_fixed), rms(&self.sum_adaptive));
        let note = if self.used == 0 {
            Some(format!(
                "no row after --settle {} has a finite measurement and finite predictions",
                self.settle
            ))
        } else if !(fixed.is_finite() && adaptive.is_finite()) {
            Some(format!(
                "an RMS is null: it exceeds the largest double ({}), which errors of that size \
                 make (a measurement or prediction near it)",
                sig(f64::MAX, 4)
            ))
        } else {
            None
        };
        let mut counts = self
            .adaptive
            .as_ref()
            .map(Adaptive::counts)
            .unwrap_or_default();
        counts.bad_input += self.bad_before_start;
        let values = |f: &dyn Fn(&Adaptive<f64>, Parameter) -> f64| {
            let map: serde_json::Map<String, serde_json::Value> = adapted
                .iter()
                .map(|p| {
                    let v = self.adaptive.as_ref().map_or(f64::NAN, |a| f(a, *p));
                    (p.name().to_string(), json_number(v))
                })
                .collect();
            serde_json::Value::Object(map)
        };
        serde_json::json!({
            "model": args.model.display().to_string(),
            "data": args.data.display().to_string(),
            "rows": self.rows,
            "samples": self.used,
            "settle": self.settle,
            "rms_fixed": json_number(fixed),
            "rms_adaptive": json_number(adaptive),
            "rms_note": note,
            "parameters": adapted.iter().map(|p| p.name()).collect::<Vec<_>>(),
            "fitted": values(&|a, p| a.fitted_value(p)),
            "final": values(&|a, p| a.value(p)),
            "std_error": values(&|a, p| a.std_error(p)),
            // The old key of `std_error` (docs/formats.md, "Deprecated names").
            "sigma": values(&|a, p| a.std_error(p)),
            "counts": Status::ALL
                .into_iter()
                .map(|s| (s.name().to_string(), serde_json::json!(counts.of(s))))
                .collect::<serde_json::Map<_, _>>(),
            "settings": {
                "noise": config.noise,
                "drift": config.drift,
                "uncertainty": config.uncertainty,
                "rest": config.rest,
                "step": config.step,
                "range": config.range,
                "dead_zone": config.dead_zone,
                "input_range": [json_number(config.input_range.0), json_number(config.input_range.1)],
            },
        })
    }
}

/// A sum of squared errors that cannot overflow: Σ e² = (2 · scale)² · ssq, with scale the
/// largest |e| / 2 so far (each error is taken halved, (y − p) / 2 = y / 2 − p / 2, so the
/// difference of two finite numbers is finite too) and ssq ≥ 1 once an error was added
/// (the rescaling of LAPACK's dnrm2).
#[derive(Clone, Copy, Debug, Default)]
struct SquareSum {
    scale: f64,
    ssq: f64,
}

impl SquareSum {
    /// Adds the error y − p of two finite numbers.
    fn add(&mut self, y: f64, p: f64) {
        let e = (0.5 * y - 0.5 * p).abs();
        if e > self.scale {
            let r = self.scale / e;
            self.ssq = 1.0 + self.ssq * r * r;
            self.scale = e;
        } else if e > 0.0 {
            let r = e / self.scale;
            self.ssq += r * r;
        }
    }

    /// The RMS over `n` errors (`None` for n = 0); infinite only when it exceeds the largest
    /// double.
    fn rms(&self, n: usize) -> Option<f64> {
        (n > 0).then(|| self.scale * (2.0 * (self.ssq / n as f64).sqrt()))
    }
}

/// A number for JSON: `null` when it is not finite.
fn json_number(v: f64) -> serde_json::Value {
    if v.is_finite() {
        serde_json::json!(v)
    } else {
        serde_json::Value::Null
    }
}

/// The summary as text.
fn text(s: &serde_json::Value) -> String {
    let num = |v: &serde_json::Value| v.as_f64().map_or("-".to_string(), |x| sig(x, 4));
    let mut t = format!(
        "{} rows, {} in the RMS (after {} settling)\nrms_fixed = {}   rms_adaptive = {}\n",
        s["rows"],
        s["samples"],
        s["settle"],
        num(&s["rms_fixed"]),
        num(&s["rms_adaptive"])
    );
    if let Some(note) = s["rms_note"].as_str() {
        t += &format!("  ({note})\n");
    }
    if let Some(names) = s["parameters"].as_array() {
        for n in names.iter().filter_map(|n| n.as_str()) {
            t += &format!(
                "  {n:<12} fitted {:>10}   final {:>10} ± {}\n",
                num(&s["fitted"][n]),
                num(&s["final"][n]),
                num(&s["sigma"][n])
            );
        }
    }
    let c = &s["counts"];
    t += &format!(
        "updates {}, at rest {}, starting {}, dead zone {}; skipped: bad input {}, out of \
         range {}, bad output {}; refused {}\n",
        c["updated"],
        c["rest"],
        c["starting"],
        c["dead_zone"],
        c["bad_input"],
        c["out_of_range"],
        c["bad_output"],
        c["refused"]
    );
    t
}

/// The command line, for the adapted model's provenance.
fn command_line() -> String {
    std::env::args().collect::<Vec<_>>().join(" ")
}
