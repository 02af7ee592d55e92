//! `hyst run`: the direct operator, or its inverse (the compensator), over a CSV file.
//!
//! Contract (relied on by tests and other tools):
//! - INPUT has a header row. The input column is `--column NAME`, else `x`, else the only column.
//! - With `--derivatives N` INPUT also holds `<name>_d1 … <name>_dN`, the input's time
//!   derivatives, and OUTPUT gets `y_d1 … y_dN` (Proposition 2.7 and beyond, by jets). This
//!   holds for `--model` too: smooth models carry the jets through ψ_in, H (or H⁻¹) and ψ_out;
//!   Prandtl–Ishlinskii models give the piecewise derivatives of their plays (a play at the edge
//!   of its band that the input pushes moves with the input, every other play is stuck).
//! - OUTPUT has the header `x,y[,y_d1…]`, one row per input row, every value in full `f64`
//!   precision (parses back to the identical number).
//! - Errors name the file, line and column; nothing is written on failure (temporary file, then
//!   rename), and an OUTPUT that is INPUT (or the model file) is refused before anything is read.
//!   `-o -` streams to standard output.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};

use crate::source::{Chosen, Source};
use hyst_core::{Hysteresis, InverseHysteresis, Jet, Operator, Sample};
use hyst_io::Table;

/// The most time derivatives `--derivatives` accepts.
pub const MAX_DERIVATIVES: usize = 8;

/// Arguments of `hyst run`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The operator.
    #[command(flatten)]
    pub source: Source,
    /// The input column (default: `x`, or the only column).
    #[arg(long)]
    pub column: Option<String>,
    /// Also propagate N time derivatives (columns <column>_d1 … <column>_dN in, y_d1 … out).
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u8).range(0..=MAX_DERIVATIVES as i64))]
    pub derivatives: u8,
    /// Input CSV file.
    pub input: PathBuf,
    /// Output CSV file: written atomically (temporary file, then rename); `-` is standard
    /// output; a symbolic link or a device (/dev/null) is written through. Must not be INPUT.
    #[arg(short, long)]
    pub output: PathBuf,
}

/// Runs `hyst run`.
pub fn main(args: Args) -> Result<()> {
    let table = Table::read(&args.input)?;
    let output = match args.source.chosen()? {
        Chosen::Model(path) => run_model(path, &table, &args)?,
        Chosen::Parameters { k1, k2 } if args.source.inverse => {
            let mut op = InverseHysteresis::new(k1, k2).context("--k1/--k2")?;
            run_table(&mut op, &table, args.column.as_deref(), args.derivatives)?
        }
        Chosen::Parameters { k1, k2 } => {
            let mut op = Hysteresis::new(k1, k2).context("--k1/--k2")?;
            run_table(&mut op, &table, args.column.as_deref(), args.derivatives)?
        }
    };
    output.write_atomic(&args.output)?;
    Ok(())
}

/// Runs `op` over the chosen column of `table` (with `derivatives` time derivatives) and returns
/// the output table `x,y[,y_d1…]`.
///
/// # Errors
/// A missing column, or a sample the operator refuses, named by file, line and column.
pub fn run_table<E: Operator<f64>>(
    op: &mut E,
    table: &Table,
    column: Option<&str>,
    derivatives: u8,
) -> Result<Table> {
    macro_rules! with_order {
        ($($n:literal)*) => {
            match derivatives {
                0 => run_order::<E, 0>(op, table, column),
                $($n => run_order::<E, $n>(op, table, column),)*
                n => bail!("--derivatives {n}: at most {MAX_DERIVATIVES} are supported"),
            }
        };
    }
    with_order!(1 2 3 4 5 6 7 8)
}

fn run_order<E: Operator<f64>, const N: usize>(
    op: &mut E,
    table: &Table,
    column: Option<&str>,
) -> Result<Table> {
    let (index, xs) = table.pick_column(column)?;
    let name = table.names().get(index).cloned().unwrap_or_default();
    let mut derivative_columns: Vec<&[f64]> = Vec::with_capacity(N);
    for k in 1..=N {
        let wanted = format!("{name}_d{k}");
        derivative_columns.push(table.column(&wanted).with_context(|| {
            format!(
                "--derivatives {N} needs the column {wanted:?} (time derivative {k} of {name:?})"
            )
        })?);
    }
    let mut columns = vec![Vec::with_capacity(xs.len()); N + 2];
    for (row, &x) in xs.iter().enumerate() {
        let mut d = [0.0; N];
        for (k, c) in derivative_columns.iter().enumerate() {
            d[k] = c.get(row).copied().unwrap_or(0.0);
        }
        let y = op
            .try_step(Jet::<f64, N>::from_derivatives(x, d))
            .with_context(|| {
                format!(
                    "{}:{}: column {} ({name:?}): value {}",
                    table.source(),
                    table.line_of_row(row),
                    index + 1,
                    Num(x)
                )
            })?;
        if !y.all_finite() {
            // The core refuses overflowing outputs; a model's own parts (a Prandtl–Ishlinskii
            // output polynomial) are checked here, so the error names the input line.
            bail!(
                "{}:{}: column {} ({name:?}): value {} gives the output {}: not a finite number",
                table.source(),
                table.line_of_row(row),
                index + 1,
                Num(x),
                y.value()
            );
        }
        columns[0].push(x);
        columns[1].push(y.value());
        for (k, dk) in y.derivatives().iter().enumerate() {
            columns[k + 2].push(*dk);
        }
    }
    let mut names = vec!["x".to_string(), "y".to_string()];
    names.extend((1..=N).map(|k| format!("y_d{k}")));
    Ok(Table::new(names, columns)?)
}

/// A number in a message: shortest round trip, in exponent form outside [1e-5, 1e16).
struct Num(f64);

impl std::fmt::Display for Num {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let a = self.0.abs();
        if a == 0.0 || (1e-5..1e16).contains(&a) || !a.is_finite() {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

/// `hyst run --model FILE`: a fitted model (see docs/formats.md) over one column, as one record.
/// The column is `--column`, else the model's input column (its output column with `--inverse`:
/// the desired output). Output header `x,y[,y_d1…]`, derivatives as for `--k1/--k2`.
fn run_model(path: &std::path::Path, table: &Table, args: &Args) -> Result<Table> {
    let model = hyst_fit::ModelFile::read(path)?;
    let name = match &args.column {
        Some(c) => c.clone(),
        None if args.source.inverse => model.columns.output.clone(),
        None => model.columns.input.clone(),
    };
    let (index, x) = table.pick_column(Some(&name))?;
    let first = x.first().copied().unwrap_or(0.0);
    let mut op = model
        .evaluator(first, args.source.inverse)
        .with_context(|| {
            format!(
                "{}:{}: column {} ({name:?}): value {first}: the model {} cannot start here",
                table.source(),
                table.line_of_row(0),
                index + 1,
                path.display()
            )
        })?;
    run_table(&mut op, table, Some(&name), args.derivatives)
}
