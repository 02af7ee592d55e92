//! `hyst`: the command-line face of the hyst library. One module per subcommand.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// `print!` to standard output, for the commands' reports: a reader that went away (a closed
/// pipe, `hyst bench | head`) ends the command quietly with status 0, instead of `print!`'s
/// panic.
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = write!(std::io::stdout().lock(), $($arg)*) {
            crate::stdout_failed(&e)
        }
    }};
}

/// [`out!`] with a line break.
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = writeln!(std::io::stdout().lock(), $($arg)*) {
            crate::stdout_failed(&e)
        }
    }};
}

/// Ends the command after a failed write to standard output: quietly with status 0 when the
/// reader went away (it has what it wanted), else with the error and status 1.
fn stdout_failed(e: &std::io::Error) -> ! {
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        std::process::exit(0);
    }
    eprintln!("hyst: cannot write to standard output: {e}");
    std::process::exit(1);
}

mod adapt;
mod bench;
mod bench_fit;
mod bound;
mod choice;
mod export;
mod fit;
mod fmu;
mod naming;
mod paper;
mod plot;
mod progress;
mod run;
mod signals;
mod source;
mod spelling;
// The benchmark workloads, one file with hyst-bench's (which adds the C peer `hyst` leaves out).
#[path = "../../hyst-bench/src/workloads.rs"]
mod workloads;

/// Smooth parametric hysteresis: model, bound, compensate and fit.
#[derive(Parser, Debug)]
#[command(name = "hyst", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run the operator or a model (or its exact inverse) over a CSV file.
    Run(run::Args),
    /// Error bound Δa of a family of operators (Propositions 3.2, 3.3).
    Bound(bound::Args),
    /// Reproduce the paper's examples, figures and numbers.
    Paper(paper::Args),
    /// Identify a model from measured data.
    Fit(fit::Args),
    /// Export the operator, a fitted model or its inverse as an FMU (FMI 2.0 co-simulation).
    ///
    /// With --k1/--k2, these are the start values of the FMU's parameters k1 and k2 (tunable
    /// before initialisation); with --model, the model file is packed into the FMU.
    Fmu(fmu::Args),
    /// Measure the speed of the operators (ns per sample).
    Bench(bench::Args),
    /// Write a model file as firmware source: header-only C over hyst.h, or no_std Rust over
    /// hyst-core, exact from the first sample.
    Export(export::Args),
    /// Follow a fitted model's parameters over a record as the actuator drifts (recursive
    /// estimator): one-step prediction y_pred and each parameter per row, rms_fixed and
    /// rms_adaptive.
    Adapt(adapt::Args),
}

/// The environment variable that sets how many values a column read from a file holds in
/// memory before it goes to a temporary file ([`hyst_io::set_spill_after`]).
const SPILL_VARIABLE: &str = "HYST_SPILL_AFTER";

/// Applies [`SPILL_VARIABLE`] when it is set.
///
/// # Errors
/// A value that is not a whole number of values.
fn spill_setting() -> anyhow::Result<()> {
    let Some(value) = std::env::var_os(SPILL_VARIABLE) else {
        return Ok(());
    };
    let text = value.to_string_lossy();
    let values = text.trim().parse::<usize>().map_err(|_| {
        anyhow::anyhow!(
            "{SPILL_VARIABLE}={text:?}: expected the number of values a column holds in memory \
             before it goes to a temporary file (a whole number ≥ 0; default {})",
            hyst_io::SPILL_AFTER
        )
    })?;
    hyst_io::set_spill_after(values);
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let argv: Vec<std::ffi::OsString> = std::env::args_os().skip(1).collect();
    for old in spelling::used(&argv) {
        eprintln!("{}", spelling::note(&old));
    }
    if let Err(e) = signals::install() {
        eprintln!("error: {}", message(&e));
        return ExitCode::FAILURE;
    }
    let result = spill_setting()
        .and_then(|()| distinct_files(&cli.command))
        .and_then(|()| match cli.command {
            Command::Run(args) => run::main(args),
            Command::Bound(args) => bound::main(args),
            Command::Paper(args) => paper::main(args),
            Command::Fit(args) => fit::main(args),
            Command::Fmu(args) => fmu::main(args),
            Command::Bench(args) => bench::main(args),
            Command::Export(args) => export::main(args),
            Command::Adapt(args) => adapt::main(args),
        });
    match result {
        Ok(()) => ExitCode::SUCCESS,
        // `-o -` into a pipe whose reader went away (`hyst run ... -o - | head`): it has what it
        // wanted; quietly, with success.
        Err(e) if is_broken_pipe(&e) => ExitCode::SUCCESS,
        Err(e) if is_interrupted(&e) => {
            eprintln!("error: {}", message(&e));
            ExitCode::from(signals::EXIT_INTERRUPTED)
        }
        Err(e) => {
            eprintln!("error: {}", message(&e));
            ExitCode::FAILURE
        }
    }
}

/// Whether `e` comes from a write into a pipe whose reader went away.
fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|cause| {
        cause
            .downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// Refuses, before anything is read or written, an output that is one of the command's inputs
/// (the same file by device and inode: the same path, a symbolic or a hard link).
fn distinct_files(command: &Command) -> anyhow::Result<()> {
    match command {
        Command::Run(args) => {
            hyst_io::check_distinct(&args.input, &args.output)?;
            if let Some(model) = &args.source.model {
                hyst_io::check_distinct(model, &args.output)?;
            }
        }
        Command::Fit(args) => {
            // The model file and every plot: none is the data, none is another.
            let plots = args
                .plot
                .as_deref()
                .map(fit::plots::plot_files)
                .unwrap_or_default();
            let mut outputs = vec![args.model_out.as_path()];
            outputs.extend(plots.iter().map(PathBuf::as_path));
            hyst_io::check_all_distinct(&[args.data.as_path()], &outputs)?;
            // And writable, before the data is read and fitted: a fit of a long record is not
            // thrown away for a missing directory.
            hyst_io::check_writable(&args.model_out)?;
            if let Some(dir) = &args.plot {
                hyst_io::check_writable_dir(dir)?;
            }
        }
        Command::Adapt(args) => {
            let mut outputs = vec![args.output_file.as_path()];
            outputs.extend(args.model_out.as_deref());
            hyst_io::check_all_distinct(&[args.data.as_path(), args.model.as_path()], &outputs)?;
            for path in &outputs {
                hyst_io::check_writable(path)?;
            }
        }
        Command::Export(args) => {
            let a = args.target.args();
            if let Some(output) = &a.output {
                hyst_io::check_distinct(&a.model, output)?;
            }
        }
        // `hyst fmu` checks its model file itself.
        Command::Fmu(_) | Command::Bound(_) | Command::Paper(_) | Command::Bench(_) => {}
    }
    Ok(())
}

/// Whether the command stopped because of Ctrl-C (exit status 130, not 1).
fn is_interrupted(e: &anyhow::Error) -> bool {
    e.chain().any(|cause| {
        matches!(
            cause.downcast_ref::<hyst_fit::FitError>(),
            Some(hyst_fit::FitError::Interrupted)
        )
    })
}

/// The error and its causes on one line, `outer: inner: …`, leaving out a cause whose text the
/// line already contains (an error that prints its source, as the I/O errors do, would otherwise
/// repeat the OS message: "…(os error 2): …(os error 2)").
fn message(e: &anyhow::Error) -> String {
    let mut line = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if line.contains(&text) {
            continue;
        }
        if !line.is_empty() {
            line.push_str(": ");
        }
        line.push_str(&text);
    }
    line
}
