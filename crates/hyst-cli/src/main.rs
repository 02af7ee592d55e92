//! `hyst`: the command-line face of the hyst library. One module per subcommand.

use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod bench;
mod bound;
mod fit;
mod fmu;
mod paper;
mod plot;
mod run;
mod source;
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
    /// Run the direct operator (or its inverse, the compensator) over a CSV file.
    Run(run::Args),
    /// Error bound Δa of a family of operators (Propositions 3.2, 3.3).
    Bound(bound::Args),
    /// Reproduce the paper's examples, figures and numbers.
    Paper(paper::Args),
    /// Identify a model from measured data.
    Fit(fit::Args),
    /// Export the operator, a fitted model or its compensator as an FMU (FMI 2.0 co-simulation).
    ///
    /// With --k1/--k2, these are the start values of the FMU's parameters k1 and k2 (tunable
    /// before initialisation); with --model, the model file is packed into the FMU.
    Fmu(fmu::Args),
    /// Measure the speed of the operators (ns per sample).
    Bench(bench::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run(args) => run::main(args),
        Command::Bound(args) => bound::main(args),
        Command::Paper(args) => paper::main(args),
        Command::Fit(args) => fit::main(args),
        Command::Fmu(args) => fmu::main(args),
        Command::Bench(args) => bench::main(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
