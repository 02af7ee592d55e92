//! `hyst fit`: identify a smooth hysteresis model (or the Prandtl–Ishlinskii baseline) from
//! measured data, write the model file, print the report, draw the plots.
//!
//! Contract:
//! - DATA is a CSV file with a header; `--input` and `--output` name the columns. A column
//!   `loop`, `curve_index` or `record` (or `--record NAME`) splits it into independent records.
//! - The model file (`-o`, TOML, docs/formats.md) is written atomically after the fit: an error
//!   or Ctrl-C leaves no file behind (and an existing file untouched).
//! - The report goes to stdout (text, or JSON with `--json`); progress to stderr.

mod plots;
mod progress;
mod report;

use std::path::PathBuf;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use anyhow::{bail, Result};
use hyst_fit::modelfile::{fnv1a64, Metrics, ModelKind, Provenance, Units};
use hyst_fit::pi::PiOutputKind;
use hyst_fit::pi_fit::{fit_pi_with, PiFit};
use hyst_fit::{
    fit_smooth, DataOptions, Dataset, FitOptions, InitialState, K2Kind, ModelFile, ShapingKind,
    SmoothFit, Structure,
};
use hyst_io::Table;

use plots::{draw, time_column};
use progress::{ProgressObserver, INTERRUPTED};
use report::{text_report, Report, Summary};

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
        print!("{}", text_report(&report));
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
