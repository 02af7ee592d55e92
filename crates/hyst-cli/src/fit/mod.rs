//! `hyst fit`: identify a smooth hysteresis model (or the Prandtl–Ishlinskii baseline) from
//! measured data, write the model file, print the report, draw the plots.
//!
//! Contract:
//! - DATA is a CSV file with a header; `--input` and `--output` name the columns. A column
//!   `loop`, `curve_index`, `record` or `segment` (or `--record NAME`) splits it into independent
//!   records.
//! - The model file (`-o`, TOML, docs/formats.md) is written atomically after the fit: an error
//!   or Ctrl-C leaves no file behind (and an existing file untouched).
//! - The report goes to stdout (text, or JSON with `--json`); progress to stderr.

pub(crate) mod plots;
mod progress;

use std::path::PathBuf;

use hyst_model::Choice;

use crate::choice::choice;
use anyhow::Result;
use hyst_fit::identify::{provenance, Request};
use hyst_fit::pi_fit::PiOutputKind;
use hyst_fit::report::text_report;
use hyst_fit::{identify, DataOptions, Dataset, FitOptions, FormChoice, StartChoice};
use hyst_io::Table;
use hyst_model::{K2Kind, ShapingKind, Structure};
use hyst_model::{ModelKind, Units};

use hyst_model::time::is_time_column;
use plots::{draw, time_column, Axes};
use progress::ProgressObserver;

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
    #[arg(short = 'o', long = "out", alias = "model-out", value_name = "MODEL")]
    pub model_out: PathBuf,
    /// Which model to fit.
    #[arg(long, value_parser = choice::<ModelKind>(), default_value = ModelKind::Smooth.name())]
    pub model_kind: ModelKind,
    /// Number of plays (play operators) of the Prandtl–Ishlinskii model.
    #[arg(long, default_value_t = 16, alias = "operators")]
    pub plays: usize,
    /// Monotone output polynomial after the Prandtl–Ishlinskii sum (its inverse stays exact).
    #[arg(long, value_parser = choice::<PiOutputKind>(), default_value = PiOutputKind::None.name())]
    pub pi_output: PiOutputKind,
    /// Also fit the other model kind and report both side by side.
    #[arg(long)]
    pub compare: bool,
    /// k2 law.
    #[arg(long, value_parser = choice::<K2Kind>(), default_value = K2Kind::Constant.name())]
    pub k2: K2Kind,
    /// Input shaping ψ_in.
    #[arg(long, value_parser = choice::<ShapingKind>(), default_value = ShapingKind::Affine.name())]
    pub input_shaping: ShapingKind,
    /// Output shaping ψ_out.
    #[arg(long, value_parser = choice::<ShapingKind>(), default_value = ShapingKind::Affine.name())]
    pub output_shaping: ShapingKind,
    /// Fit an input offset (default: only for tanh and Langevin input shaping).
    #[arg(long)]
    pub input_offset: bool,
    /// Do not fit an output offset.
    #[arg(long)]
    pub no_output_offset: bool,
    /// The smooth model's form: `auto` takes the stop form ψ_out(v − H[v]) + c·v when the data's
    /// loops run clockwise (the output leads the input, as friction against position) and the
    /// operator form ψ_out(H[v]) otherwise; the report states the orientation found.
    #[arg(long, value_parser = choice::<FormChoice>(), default_value = FormChoice::Auto.name())]
    pub form: FormChoice,
    /// Keep a fit that found no hysteresis (a model without loops, or parameters the data does
    /// not identify): write the model file and mark the report `degenerate`, instead of
    /// failing.
    #[arg(long)]
    pub keep_degenerate: bool,
    /// Estimate each record's initial state from its data (a reversal at its first sample with
    /// the operator output anywhere in the band, by least squares) instead of assuming
    /// `--initial-state`, which stays the model's rule for new data. For records that start
    /// mid-history.
    #[arg(long)]
    pub estimate_initial_states: bool,
    /// With --dynamics or --rate-term: count every sample from each record's first, trusting
    /// --initial-state and the plant at rest there. By default each record's start is
    /// discounted until its input has swept its range (the state it starts in is not known).
    #[arg(long, conflicts_with = "estimate_initial_states")]
    pub fit_from_start: bool,
    /// How each record starts (the model's rule for new data too). `auto`: `falling` when every
    /// record only rises (first-order reversal curves, each starting at a reversal after a fall
    /// from saturation), `rising` when every record only falls, `rising` otherwise.
    #[arg(long, value_parser = choice::<StartChoice>(), default_value = StartChoice::Auto.name())]
    pub initial_state: StartChoice,
    /// Record column (default: `loop`, `curve_index`, `record` or `segment` if present).
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
    #[arg(
        long,
        value_delimiter = ',',
        allow_negative_numbers = true,
        value_parser = record_id
    )]
    pub validate: Vec<i64>,
    /// Hold out every K-th record for validation.
    #[arg(long, value_name = "K", conflicts_with = "validate")]
    pub validate_every: Option<usize>,
    /// Coverage of the family widths (fraction of samples the family envelope must hold).
    #[arg(long, default_value_t = 0.99)]
    pub coverage: f64,
    /// Number of starts refined by Levenberg–Marquardt (at least 1): the best of a grid over
    /// (k1, k2), and for a richer structure first the optimum of the simpler one it contains.
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
    /// The time column, in seconds (default: a column named t, t_s, time or time_s if there is
    /// one). `--dynamics` and `--rate-term` need it; the residual plot uses it (otherwise
    /// residuals are drawn against the data row).
    #[arg(long, value_name = "COLUMN")]
    pub time: Option<String>,
    /// Identify Lemma 5.1's plant of order N (1 to 4) between the input (the command) and the
    /// hysteresis: a_N v⁽ᴺ⁾ + … + a_1 v̇ + v = u, jointly with the hysteresis and shapings, from
    /// the records' time stamps. `auto` fits orders 0 to 4 in turn and keeps the one the
    /// validation records (--validate) prefer, or else an information criterion; the report
    /// prints the table.
    #[arg(long, value_name = "N|auto", value_parser = dynamics_order)]
    pub dynamics: Option<DynamicsOrder>,
    /// Add a rate term to the output: `viscous` is c·v̇, a force proportional to the rate of
    /// the hysteresis input (friction, dampers). The report says whether the data supports it.
    #[arg(long, value_parser = choice::<hyst_model::RateTerm>(), value_name = "TERM")]
    pub rate_term: Option<hyst_model::RateTerm>,
    /// The command between samples, for the plant of --dynamics: zoh, held over each step (an
    /// actuator driven by a DAC; the default), or foh, linear between samples. The model file
    /// records it (`[dynamics] hold`). Given, the standard errors make no allowance for the
    /// other hold, which the records cannot tell apart.
    #[arg(long, value_parser = choice::<hyst_model::Hold>(), value_name = "HOLD", requires = "dynamics")]
    pub hold: Option<hyst_model::Hold>,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
}

/// The plant order `--dynamics` asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DynamicsOrder {
    /// Orders 0 to 4, the best kept.
    Auto,
    /// This order (1 to 4).
    Order(u8),
}

/// `--dynamics N|auto`, with a message that says what it takes.
fn dynamics_order(s: &str) -> Result<DynamicsOrder, String> {
    match s.trim() {
        "auto" => Ok(DynamicsOrder::Auto),
        n => match n.parse::<u8>() {
            Ok(n @ 1..=4) => Ok(DynamicsOrder::Order(n)),
            _ => Err(format!(
                "--dynamics takes the plant order 1 to 4, or auto (orders 0 to 4, the best \
                 kept); got {s:?}"
            )),
        },
    }
}

/// One id of `--validate`: an integer, with a message that says what the option takes (clap's
/// own said only "invalid digit found in string" for `--validate 0.5`).
fn record_id(s: &str) -> Result<i64, String> {
    s.trim().parse::<i64>().map_err(|_| {
        "--validate takes the integer ids of the records to hold out for validation (values of \
         the record column), comma-separated, e.g. --validate 2,5; for every K-th record use \
         --validate-every K"
            .to_string()
    })
}

/// Runs `hyst fit`.
pub fn main(args: Args) -> Result<()> {
    // Read once, hashed on the way: a pipe or a FIFO cannot be read a second time.
    let reading = crate::progress::reading(&args.data, 0, args.json);
    // Only the columns the fit uses are kept (a long file's others would cost 8 bytes a row
    // each), and the dataset takes the input and output columns over without copying them.
    let options = data_options(&args);
    let plot = args.plot.is_some();
    let select = |names: &[String]| {
        let mut keep = Dataset::wanted_columns(names, &options);
        for (k, name) in keep.iter_mut().zip(names) {
            *k |= plot && is_time_column(name, args.time.as_deref());
        }
        keep
    };
    let (table, digest) = Table::read_digest_selected(&args.data, reading, &select)?;
    // Checked before the fit, so a bad --time costs nothing and writes nothing (a bad dataset
    // is reported first).
    let time = match &args.plot {
        Some(_) => time_column(&table, args.time.as_deref()),
        None => Ok(None),
    };
    let command = std::env::args().collect::<Vec<_>>().join(" ");
    let provenance = provenance(args.data.display().to_string(), table.len(), command);
    let data = Dataset::from_table_owned(table, &options)?;
    let time = time?;
    let request = request(&args);
    let mut observer = ProgressObserver::new(args.json);
    let identified = identify(&data, &request, &mut observer, &|| false, provenance);
    let identified = identified.map_err(|e| match e {
        // The library names its parameter; the user knows it as the flag (named once).
        hyst_fit::FitError::InvalidSetting {
            name: "plays",
            expected,
            ..
        } => anyhow::anyhow!("--plays {}: expected {expected}", args.plays),
        e => e.into(),
    })?;
    drop(observer);
    let mut report = identified.report;
    report.model.provenance.bytes = digest.bytes;
    report.model.provenance.fnv1a64 = format!("{:016x}", digest.fnv1a64);
    // Plots first: if they cannot be written, the command fails before the model file exists.
    if let Some(dir) = &args.plot {
        let axes = Axes {
            input: &args.input,
            input_unit: &args.input_unit,
            output: &args.output,
            output_unit: &args.output_unit,
        };
        let plots = draw(
            dir,
            &data,
            &axes,
            time.as_ref().map(|(name, t)| (name.as_str(), t.as_slice())),
            identified.smooth.as_ref(),
            identified.pi.as_ref(),
        )?;
        report.plots = plots.iter().map(|p| p.display().to_string()).collect();
    }
    hyst_fit::file::write(&report.model, &args.model_out)?;
    report.model_file = args.model_out.display().to_string();
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        out!("{}", text_report(&report));
    }
    Ok(())
}

/// How to read the dataset, as the arguments say.
fn data_options(args: &Args) -> DataOptions {
    DataOptions {
        input: args.input.clone(),
        output: args.output.clone(),
        record: args.record.clone(),
        no_record: args.no_record,
        weight: args.weight.clone(),
        segment: args.segment,
        validate: args.validate.clone(),
        validate_every: args.validate_every,
        time: args.time.clone(),
        timed: args.dynamics.is_some() || args.rate_term.is_some(),
    }
}

/// What to identify, as the arguments say (the form and start rule are resolved from the data
/// by the identification).
fn request(args: &Args) -> Request {
    let structure = Structure {
        k2: args.k2,
        input_shaping: args.input_shaping,
        output_shaping: args.output_shaping,
        input_offset: if args.input_offset { Some(true) } else { None },
        output_offset: !args.no_output_offset,
        dynamics: match args.dynamics {
            Some(DynamicsOrder::Order(n)) => n,
            None | Some(DynamicsOrder::Auto) => 0,
        },
        rate: args.rate_term,
        hold: args.hold.unwrap_or(hyst_model::Hold::FIT_DEFAULT),
        ..Structure::default()
    };
    let fit_options = FitOptions {
        starts: args.starts,
        coverage: args.coverage,
        estimate_starts: args.estimate_initial_states,
        fit_from_start: args.fit_from_start,
        auto_dynamics: args.dynamics == Some(DynamicsOrder::Auto),
        hold_stated: args.hold.is_some(),
        ..FitOptions::default()
    };
    Request {
        kind: args.model_kind,
        compare: args.compare,
        structure,
        form: args.form,
        start: args.initial_state,
        keep_degenerate: args.keep_degenerate,
        options: fit_options,
        plays: args.plays,
        pi_output: args.pi_output,
        units: Units {
            input: args.input_unit.clone(),
            output: args.output_unit.clone(),
        },
    }
}
