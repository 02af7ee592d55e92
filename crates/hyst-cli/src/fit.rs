//! `hyst fit`: identify a smooth hysteresis model (or the Prandtl–Ishlinskii baseline) from
//! measured data, write the model file, print the report, draw the plots.
//!
//! Contract:
//! - DATA is a CSV file with a header; `--input` and `--output` name the columns. A column
//!   `loop`, `curve_index` or `record` (or `--record NAME`) splits it into independent records.
//! - The model file (`-o`, TOML, docs/formats.md) is written atomically after the fit: an error
//!   or Ctrl-C leaves no file behind (and an existing file untouched).
//! - The report goes to stdout (text, or JSON with `--json`); progress to stderr.

use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use hyst_fit::lm::{Observer, Progress};
use hyst_fit::modelfile::{fnv1a64, Metrics, ModelKind, Provenance, Units};
use hyst_fit::pi::PiOutputKind;
use hyst_fit::pi_fit::{fit_pi_with, PiFit};
use hyst_fit::smooth::ErrorStats;
use hyst_fit::{
    fit_smooth, DataOptions, Dataset, FitOptions, InitialState, K2Kind, ModelFile, ShapingKind,
    SmoothFit, Structure,
};
use hyst_io::Table;
use serde::Serialize;

use crate::plot::{Figure, Panel, Series};

/// Arguments of `hyst fit`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Measured data (CSV with a header row).
    pub data: PathBuf,
    /// The input column.
    #[arg(long)]
    pub input: String,
    /// The output column.
    #[arg(long)]
    pub output: String,
    /// The model file to write (TOML, docs/formats.md).
    #[arg(short = 'o', long = "model-out", value_name = "MODEL")]
    pub model_out: PathBuf,
    /// Which model to fit.
    #[arg(long, value_enum, default_value_t = ModelKind::Smooth)]
    pub model_kind: ModelKind,
    /// Number of play operators of the Prandtl–Ishlinskii model.
    #[arg(long, default_value_t = 16)]
    pub operators: usize,
    /// Monotone output polynomial after the Prandtl–Ishlinskii sum (its inverse stays exact).
    #[arg(long, value_enum, default_value_t = PiOutputKind::None)]
    pub pi_output: PiOutputKind,
    /// Also fit the other model kind and report both side by side.
    #[arg(long)]
    pub compare: bool,
    /// k2 law.
    #[arg(long, value_enum, default_value_t = K2Kind::Constant)]
    pub k2: K2Kind,
    /// Input shaping ψ_in.
    #[arg(long, value_enum, default_value_t = ShapingKind::Affine)]
    pub input_shaping: ShapingKind,
    /// Output shaping ψ_out.
    #[arg(long, value_enum, default_value_t = ShapingKind::Affine)]
    pub output_shaping: ShapingKind,
    /// Fit an input offset (default: only for tanh and Langevin input shaping).
    #[arg(long)]
    pub input_offset: bool,
    /// Do not fit an output offset.
    #[arg(long)]
    pub no_output_offset: bool,
    /// How each record starts.
    #[arg(long, value_enum, default_value_t = InitialState::Rising)]
    pub initial_state: InitialState,
    /// Record column (default: `loop`, `curve_index` or `record` if present).
    #[arg(long)]
    pub record: Option<String>,
    /// Treat the file as one record even if it has a record column.
    #[arg(long, conflicts_with = "record")]
    pub no_record: bool,
    /// Sample weight column (weights ≥ 0).
    #[arg(long)]
    pub weight: Option<String>,
    /// Cut every record into segments of N samples (each its own record).
    #[arg(long, value_name = "N")]
    pub segment: Option<usize>,
    /// Hold out these record ids for validation (comma-separated).
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    pub validate: Vec<i64>,
    /// Hold out every K-th record for validation.
    #[arg(long, value_name = "K", conflicts_with = "validate")]
    pub validate_every: Option<usize>,
    /// Coverage of the family widths (fraction of samples the family envelope must hold).
    #[arg(long, default_value_t = 0.99)]
    pub coverage: f64,
    /// Number of starts refined by Levenberg–Marquardt.
    #[arg(long, default_value_t = 3)]
    pub starts: usize,
    /// Units of the input column (for the model file and the report).
    #[arg(long, default_value = "")]
    pub input_unit: String,
    /// Units of the output column.
    #[arg(long, default_value = "")]
    pub output_unit: String,
    /// Draw plots into this directory (fit-io.png/svg, fit-residuals.png/svg).
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
    /// The time column for the residual plot (default: a column named t, t_s, time or time_s if
    /// there is one; otherwise residuals are drawn against the data row).
    #[arg(long, value_name = "COL")]
    pub time: Option<String>,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
}

/// One model kind's summary, for the side-by-side comparison.
#[derive(Serialize, Debug, Clone)]
pub struct Summary {
    /// "smooth" or "prandtl-ishlinskii".
    pub kind: String,
    /// Free parameters.
    pub parameters: usize,
    /// Training errors.
    pub training: ErrorStats,
    /// Validation errors.
    pub validation: Option<ErrorStats>,
    /// Fit time (s).
    pub fit_seconds: f64,
    /// Evaluation time (ns per sample).
    pub ns_per_sample: f64,
}

/// The report (`--json` prints it).
#[derive(Serialize, Debug)]
pub struct Report {
    /// The model file written.
    pub model_file: String,
    /// The model file's content.
    pub model: ModelFile,
    /// Output span of the data (output units).
    pub output_span: f64,
    /// Side-by-side comparison (with `--compare`).
    pub comparison: Vec<Summary>,
    /// Plot files written.
    pub plots: Vec<String>,
}

/// Ctrl-C sets this; the fit's observer stops at the next iteration.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Progress on stderr (indicatif), shown once a fit has run for a second; stops on Ctrl-C.
struct ProgressObserver {
    started: Instant,
    bar: Option<indicatif::ProgressBar>,
    starts: usize,
}

impl Observer for ProgressObserver {
    fn observe(&mut self, p: &Progress) -> ControlFlow<()> {
        if INTERRUPTED.load(Ordering::SeqCst) {
            return ControlFlow::Break(());
        }
        if self.bar.is_none() && self.started.elapsed() > Duration::from_secs(1) {
            let bar = indicatif::ProgressBar::new_spinner();
            bar.enable_steady_tick(Duration::from_millis(120));
            self.bar = Some(bar);
        }
        if let Some(bar) = &self.bar {
            if p.start == usize::MAX {
                bar.set_message(format!("family widths: step {}", p.iteration));
            } else {
                bar.set_message(format!(
                    "least squares: start {}/{}, iteration {}, cost {:.4e}",
                    p.start + 1,
                    self.starts,
                    p.iteration,
                    p.cost
                ));
            }
        }
        ControlFlow::Continue(())
    }
}

impl Drop for ProgressObserver {
    fn drop(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}

/// Mean evaluation time per sample of `run` over the records (repeated to ≥ 50 ms).
fn ns_per_sample(data: &Dataset, run: impl Fn(&[f64]) -> Option<Vec<f64>>) -> f64 {
    let samples: usize = data.records.iter().map(|r| r.len()).sum();
    let started = Instant::now();
    let mut rounds = 0usize;
    while rounds == 0 || started.elapsed() < Duration::from_millis(50) {
        for r in &data.records {
            std::hint::black_box(run(std::hint::black_box(&r.input)));
        }
        rounds += 1;
    }
    started.elapsed().as_secs_f64() * 1e9 / (samples * rounds).max(1) as f64
}

/// Runs `hyst fit`.
pub fn main(args: Args) -> Result<()> {
    let interrupted = Arc::new(());
    let _ = ctrlc::set_handler(move || {
        let _keep = &interrupted;
        INTERRUPTED.store(true, Ordering::SeqCst);
    });
    let table = Table::read(&args.data)?;
    let options = DataOptions {
        input: args.input.clone(),
        output: args.output.clone(),
        record: args.record.clone(),
        no_record: args.no_record,
        weight: args.weight.clone(),
        segment: args.segment,
        validate: args.validate.clone(),
        validate_every: args.validate_every,
    };
    let data = Dataset::from_table(&table, &options)?;
    // Checked before the fit, so a bad --time costs nothing and writes nothing.
    let time = match &args.plot {
        Some(_) => time_column(&table, args.time.as_deref())?,
        None => None,
    };
    let structure = Structure {
        k2: args.k2,
        input_shaping: args.input_shaping,
        output_shaping: args.output_shaping,
        input_offset: if args.input_offset { Some(true) } else { None },
        output_offset: !args.no_output_offset,
        initial_state: args.initial_state,
    };
    let fit_options = FitOptions {
        starts: args.starts,
        coverage: args.coverage,
        ..FitOptions::default()
    };
    let want_smooth = args.model_kind == ModelKind::Smooth || args.compare;
    let want_pi = args.model_kind == ModelKind::PrandtlIshlinskii || args.compare;
    let smooth = if want_smooth {
        let mut observer = ProgressObserver {
            started: Instant::now(),
            bar: None,
            starts: args.starts.max(1),
        };
        Some(fit_smooth(&data, structure, &fit_options, &mut observer)?)
    } else {
        None
    };
    if INTERRUPTED.load(Ordering::SeqCst) {
        bail!(hyst_fit::FitError::Interrupted);
    }
    let pi = if want_pi {
        let fit = fit_pi_with(&data, args.operators, args.pi_output);
        // The library names its parameter; the user knows it as the flag.
        Some(fit.map_err(|e| match e {
            e @ hyst_fit::FitError::InvalidSetting {
                name: "operators", ..
            } => anyhow::Error::new(e).context("--operators"),
            e => e.into(),
        })?)
    } else {
        None
    };

    let bytes = std::fs::read(&args.data).unwrap_or_default();
    let provenance = Provenance {
        file: args.data.display().to_string(),
        bytes: bytes.len() as u64,
        fnv1a64: format!("{:016x}", fnv1a64(&bytes)),
        rows: table.len(),
        records: data.records.len(),
        validation_records: data.validation().map(|r| r.id).collect(),
        command: std::env::args().collect::<Vec<_>>().join(" "),
        hyst_version: env!("CARGO_PKG_VERSION").to_string(),
        created_unix: std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs()),
    };
    let smooth_summary = smooth.as_ref().map(|f| Summary {
        kind: "smooth".into(),
        parameters: f.layout.len(),
        training: f.training,
        validation: f.validation,
        fit_seconds: f.seconds,
        ns_per_sample: ns_per_sample(&data, |x| f.model.run(x).ok()),
    });
    let pi_summary = pi.as_ref().map(|f| Summary {
        kind: match f.model.output {
            Some(o) => format!("prandtl-ishlinskii + poly{}", o.degree),
            None => "prandtl-ishlinskii".into(),
        },
        parameters: f.model.parameter_count(),
        training: f.training,
        validation: f.validation,
        fit_seconds: f.seconds,
        ns_per_sample: ns_per_sample(&data, |x| f.model.run(x).ok()),
    });
    let columns = data.columns.clone();
    let units = Units {
        input: args.input_unit.clone(),
        output: args.output_unit.clone(),
    };
    let file = match (args.model_kind, &smooth, &pi) {
        (ModelKind::Smooth, Some(f), _) => {
            smooth_file(f, smooth_summary.as_ref(), columns, units, provenance)
        }
        (ModelKind::PrandtlIshlinskii, _, Some(f)) => {
            pi_file(f, pi_summary.as_ref(), columns, units, provenance)
        }
        _ => bail!("internal: the requested model was not fitted"),
    };
    if INTERRUPTED.load(Ordering::SeqCst) {
        bail!(hyst_fit::FitError::Interrupted);
    }
    // Plots first: if they cannot be written, the command fails before the model file exists.
    let mut plots = Vec::new();
    if let Some(dir) = &args.plot {
        plots = draw(dir, &data, &args, time, smooth.as_ref(), pi.as_ref())?;
    }
    file.write(&args.model_out)?;

    let (lo, hi) = data.output_range();
    let comparison = if args.compare {
        smooth_summary.into_iter().chain(pi_summary).collect()
    } else {
        Vec::new()
    };
    let report = Report {
        model_file: args.model_out.display().to_string(),
        model: file,
        output_span: hi - lo,
        comparison,
        plots: plots.iter().map(|p| p.display().to_string()).collect(),
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", text_report(&report, &data));
    }
    Ok(())
}

fn smooth_file(
    f: &SmoothFit,
    summary: Option<&Summary>,
    columns: hyst_fit::Columns,
    units: Units,
    provenance: Provenance,
) -> ModelFile {
    ModelFile {
        format: hyst_fit::modelfile::FORMAT.into(),
        version: hyst_fit::modelfile::MIN_VERSION,
        kind: ModelKind::Smooth,
        columns,
        units,
        parameters: f.estimates.clone(),
        metrics: Metrics {
            parameters: f.layout.len(),
            training: f.training,
            validation: f.validation,
            fit_seconds: f.seconds,
            ns_per_sample: summary.map_or(f64::NAN, |s| s.ns_per_sample),
        },
        structure: Some(f.layout.structure),
        smooth: Some(f.model),
        prandtl_ishlinskii: None,
        family: f.widths,
        provenance,
    }
}

fn pi_file(
    f: &PiFit,
    summary: Option<&Summary>,
    columns: hyst_fit::Columns,
    units: Units,
    provenance: Provenance,
) -> ModelFile {
    let mut file = ModelFile {
        format: hyst_fit::modelfile::FORMAT.into(),
        version: hyst_fit::modelfile::MIN_VERSION,
        kind: ModelKind::PrandtlIshlinskii,
        columns,
        units,
        parameters: f.estimates.clone(),
        metrics: Metrics {
            parameters: f.model.parameter_count(),
            training: f.training,
            validation: f.validation,
            fit_seconds: f.seconds,
            ns_per_sample: summary.map_or(f64::NAN, |s| s.ns_per_sample),
        },
        structure: None,
        smooth: None,
        prandtl_ishlinskii: Some(f.model.clone()),
        family: None,
        provenance,
    };
    // The lowest version that holds the content: version-1 readers keep reading plain PI files
    // and refuse the ones with an output polynomial.
    file.version = file.required_version();
    file
}

fn unit(u: &str) -> String {
    if u.is_empty() {
        String::new()
    } else {
        format!(" {u}")
    }
}

fn stats_line(label: &str, s: &ErrorStats, u: &str) -> String {
    format!(
        "  {label:<26} {:>12.5}{u} ({:>6.3} %)   {:>12.5}{u} ({:>6.3} %)\n",
        s.rms, s.rms_pct_span, s.max_abs, s.max_pct_span
    )
}

fn text_report(r: &Report, data: &Dataset) -> String {
    let m = &r.model;
    let u = unit(&m.units.output);
    let mut s = String::new();
    let train_samples = m.metrics.training.samples;
    s += &format!(
        "hyst fit: {} ({} rows, {} record{}; {} training samples{})\n",
        m.provenance.file,
        m.provenance.rows,
        m.provenance.records,
        if m.provenance.records == 1 { "" } else { "s" },
        train_samples,
        m.metrics.validation.map_or(String::new(), |v| format!(
            ", {} validation samples",
            v.samples
        )),
    );
    s += &format!(
        "columns: input {:?}{}, output {:?}{}{}\n",
        m.columns.input,
        unit(&m.units.input),
        m.columns.output,
        u,
        m.columns
            .record
            .as_ref()
            .map_or(String::new(), |c| format!(", records by {c:?}"))
    );
    match (m.kind, &m.structure) {
        (ModelKind::Smooth, Some(st)) => {
            s += &format!(
                "model: smooth operator, k2 {}, input shaping {}, output shaping {}{}{}, start {}\n",
                match st.k2 {
                    K2Kind::Constant => "constant",
                    K2Kind::Affine => "affine",
                },
                st.input_shaping.name(),
                st.output_shaping.name(),
                if st.output_offset { ", output offset" } else { "" },
                if st.input_offset == Some(true) { ", input offset" } else { "" },
                match st.initial_state {
                    InitialState::Rising => "rising",
                    InitialState::Falling => "falling",
                    InitialState::Line => "line",
                }
            );
        }
        _ => {
            let pi = m.prandtl_ishlinskii.as_ref();
            s += &format!(
                "model: Prandtl–Ishlinskii, {} play operators{}\n",
                pi.map_or(0, |p| p.thresholds.len()),
                match pi.and_then(|p| p.output) {
                    Some(o) => format!(
                        ", output polynomial of degree {} (increasing on the PI output range \
                         [{:.4}, {:.4}]; exact inverse PI⁻¹ ∘ P⁻¹)",
                        o.degree, o.lo, o.hi
                    ),
                    None => String::new(),
                }
            );
        }
    }
    s += &format!(
        "fit: {:.3} s, {} parameters, {:.0} ns per sample to evaluate\n\n",
        m.metrics.fit_seconds, m.metrics.parameters, m.metrics.ns_per_sample
    );
    s += &format!(
        "errors (output span {:.5}{u})          RMS (% of span)             max (% of span)\n",
        r.output_span
    );
    s += &stats_line(
        &format!("training ({} samples)", m.metrics.training.samples),
        &m.metrics.training,
        &u,
    );
    if let Some(v) = &m.metrics.validation {
        s += &stats_line(&format!("validation ({} samples)", v.samples), v, &u);
    }
    s += "\nparameter              value           std. error     unit\n";
    for e in m.parameters.iter().take(40) {
        s += &format!(
            "  {:<20} {:>14.7}  {:>14.3e}     {}\n",
            e.name, e.value, e.std_error, e.unit
        );
    }
    if m.parameters.len() > 40 {
        s += &format!("  … {} more in the model file\n", m.parameters.len() - 40);
    }
    if m.kind == ModelKind::Smooth {
        s += "  (k1, k2 in normalised input units: the input range maps to [-1, 1]; standard errors\n   assume independent residuals)\n";
    }
    if let Some(w) = &m.family {
        s += &format!(
            "\nfamily RH(k1, Δk1, k2, Δk2) reproducing {:.1} % of the samples (Definition 2.8):\n",
            100.0 * w.coverage_target
        );
        if !w.reachable {
            s += &format!(
                "  NOT reachable with Δk1 < k1, Δk2 < k2: at most {:.2} % covered\n",
                100.0 * w.coverage
            );
        }
        s += &format!(
            "  Δk1 = {:.5}, Δk2 = {:.5} (coverage {:.2} %)\n",
            w.delta_k1,
            w.delta_k2,
            100.0 * w.coverage
        );
        if w.delta_k2_law > 0.0 {
            s += &format!(
                "  k2 over the data in [{:.4}, {:.4}]; Proposition 4.3 adds Δk2* = {:.5}\n",
                w.k2_range.0, w.k2_range.1, w.delta_k2_law
            );
        }
        s += &format!(
            "  Δa = {:.5} (operator units; Proposition 3.2, and Δb ≤ Δa by Proposition 3.3)\n",
            w.delta_a
        );
        s += &format!(
            "  compensation error bound at the output: {:.5}{u} ({:.3} % of span)\n",
            w.output_bound, w.output_bound_pct_span
        );
    }
    if !r.comparison.is_empty() {
        s += "\ncomparison on the same data   parameters   train RMS %   valid RMS %   ns/sample   fit s\n";
        for c in &r.comparison {
            s += &format!(
                "  {:<28} {:>10}   {:>11.3}   {:>11}   {:>9.1}   {:>5.2}\n",
                c.kind,
                c.parameters,
                c.training.rms_pct_span,
                c.validation
                    .map_or("-".to_string(), |v| format!("{:.3}", v.rms_pct_span)),
                c.ns_per_sample,
                c.fit_seconds
            );
        }
    }
    s += &format!("\nwrote {}\n", r.model_file);
    for p in &r.plots {
        s += &format!("wrote {p}\n");
    }
    let _ = data;
    s
}

/// Keeps at most `max` points, evenly spaced.
fn thin(points: Vec<(f64, f64)>, max: usize) -> Vec<(f64, f64)> {
    if points.len() <= max {
        return points;
    }
    let step = points.len().div_ceil(max);
    points.into_iter().step_by(step).collect()
}

/// Points of a plot series.
type Points = Vec<(f64, f64)>;
/// A model run over one record.
type RunFn<'a> = Box<dyn Fn(&[f64]) -> Option<Vec<f64>> + 'a>;

/// The time axis of the residual plot: `--time COL`, else a column with a conventional time name.
fn time_column<'t>(
    table: &'t Table,
    name: Option<&'t str>,
) -> Result<Option<(&'t str, &'t [f64])>> {
    if let Some(name) = name {
        let column = table.column(name).context("--time")?;
        return Ok(Some((name, column)));
    }
    for candidate in ["t", "t_s", "time", "time_s"] {
        if let Ok(column) = table.column(candidate) {
            return Ok(Some((candidate, column)));
        }
    }
    Ok(None)
}

fn draw(
    dir: &Path,
    data: &Dataset,
    args: &Args,
    time: Option<(&str, &[f64])>,
    smooth: Option<&SmoothFit>,
    pi: Option<&PiFit>,
) -> Result<Vec<PathBuf>> {
    let xl = format!("{}{}", args.input, unit_paren(&args.input_unit));
    let yl = format!("{}{}", args.output, unit_paren(&args.output_unit));
    let mut measured = Vec::new();
    let mut models: Vec<(String, Points, Points)> = Vec::new();
    for r in &data.records {
        for (x, y) in r.input.iter().zip(&r.output) {
            measured.push((*x, *y));
        }
    }
    let runs: Vec<(&str, RunFn<'_>)> = [
        smooth.map(|f| {
            (
                "smooth model",
                Box::new(move |x: &[f64]| f.model.run(x).ok()) as RunFn<'_>,
            )
        }),
        pi.map(|f| {
            (
                "Prandtl–Ishlinskii",
                Box::new(move |x: &[f64]| f.model.run(x).ok()) as RunFn<'_>,
            )
        }),
    ]
    .into_iter()
    .flatten()
    .collect();
    for (name, run) in &runs {
        let mut io = Vec::new();
        let mut res = Vec::new();
        for r in &data.records {
            let y = run(&r.input).context("the fitted model cannot run the data")?;
            for (((x, m), o), row) in r.input.iter().zip(&y).zip(&r.output).zip(&r.rows) {
                io.push((*x, *m));
                let at = match time {
                    Some((_, t)) => t.get(*row).copied().unwrap_or(f64::NAN),
                    None => (*row + 1) as f64,
                };
                res.push((at, m - o));
            }
        }
        models.push(((*name).to_string(), io, res));
    }
    let mut io_panel = Panel::new("Data and model in the input-output plane", &xl, &yl)
        .series(Series::scatter("measured", thin(measured, 20_000)).color(0));
    let (res_title, res_x) = match time {
        Some((name, _)) => ("Residuals (model − measured) over time", name.to_string()),
        None => (
            "Residuals (model − measured) over the samples",
            "sample (data row)".to_string(),
        ),
    };
    let output_unit = if args.output_unit.is_empty() {
        format!(" (units of {})", args.output)
    } else {
        unit_paren(&args.output_unit)
    };
    let mut res_panel = Panel::new(res_title, &res_x, &format!("residual{output_unit}"));
    for (i, (name, io, res)) in models.into_iter().enumerate() {
        let color = i + 1;
        io_panel = io_panel.series(
            Series::scatter(&name, thin(io, 20_000))
                .color(color)
                .width(1),
        );
        res_panel = res_panel.series(
            Series::scatter(&name, thin(res, 20_000))
                .color(color)
                .width(1),
        );
    }
    let mut written = Figure::row(vec![io_panel]).save(dir, "fit-io")?;
    written.extend(Figure::row(vec![res_panel.hline("0", 0.0)]).save(dir, "fit-residuals")?);
    Ok(written)
}

fn unit_paren(u: &str) -> String {
    if u.is_empty() {
        String::new()
    } else {
        format!(" ({u})")
    }
}
