//! `hyst run`: the direct operator, or its inverse (the compensator), over a CSV file.
//!
//! Contract (relied on by tests and other tools):
//! - INPUT has a header row. The input column is `--column NAME`, else `x`, else the only column
//!   (with `--model`: else the model's input column, its output column with `--inverse`).
//! - With `--derivatives N` INPUT also holds `<name>_d1 … <name>_dN`, the input's time
//!   derivatives, and OUTPUT gets `y_d1 … y_dN` (Proposition 2.7 and beyond, by jets). This
//!   holds for `--model` too: smooth models carry the jets through ψ_in, H (or H⁻¹) and ψ_out;
//!   Prandtl–Ishlinskii models give the piecewise derivatives of their plays (a play at the edge
//!   of its band that the input pushes moves with the input, every other play is stuck).
//! - With `--record COLUMN` the operator starts afresh (by its start rule, at the record's first
//!   sample) wherever the value of COLUMN changes from one row to the next: a value that comes
//!   back later starts a new record. OUTPUT then ends with COLUMN.
//! - OUTPUT has the header `x,y[,y_d1…][,RECORD]`, one row per input row, every value in full
//!   `f64` precision (parses back to the identical number).
//! - The file is streamed: memory does not grow with its length.
//! - Errors name the file, line and column; nothing is written on failure (temporary file, then
//!   rename), and an OUTPUT that is INPUT (or the model file) is refused before anything is read.
//!   `-o -` streams to standard output (rows before an error stay written there).

use std::io::Read;
use std::path::PathBuf;

use anyhow::{bail, Context, Result};

use crate::source::{Chosen, Source};
use hyst_core::{Hysteresis, InverseHysteresis, Jet, Operator, Sample};
use hyst_fit::modelfile::{Saturation, SATURATION_FRACTION};
use hyst_io::{CsvReader, CsvWriter};

/// The most time derivatives `--derivatives` accepts.
pub const MAX_DERIVATIVES: usize = 8;

/// Arguments of `hyst run`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The operator.
    #[command(flatten)]
    pub source: Source,
    /// The input column (default: `x`, or the only column; with --model the model's input
    /// column, or its output column with --inverse).
    #[arg(long)]
    pub column: Option<String>,
    /// Also propagate N time derivatives (columns <column>_d1 … <column>_dN in, y_d1 … out).
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u8).range(0..=MAX_DERIVATIVES as i64))]
    pub derivatives: u8,
    /// Restart the operator wherever the value of COLUMN changes (FORC curves, B-H loops): each
    /// record starts by the start rule (--model: the model's initial_state at the record's first
    /// sample; --k1/--k2: no history). A value that comes back after another is a new record,
    /// not a continuation. COLUMN is copied to the end of OUTPUT.
    #[arg(long, value_name = "COLUMN")]
    pub record: Option<String>,
    /// With --model --inverse, for a model whose output shaping saturates (tanh, Langevin; open
    /// range (lo, hi), unreachable): clamp every desired output beyond 99.9 % of the range about
    /// its centre to that limit, instead of stopping at the first one outside (lo, hi). A
    /// clamped row gets the clamped value in x and zero derivatives; stderr says how many rows
    /// were clamped and which was first.
    #[arg(long)]
    pub saturate: bool,
    /// Input CSV file.
    pub input: PathBuf,
    /// Output CSV file: written atomically (temporary file, then rename); `-` is standard
    /// output; a symbolic link or a device (/dev/null) is written through. Must not be INPUT.
    #[arg(short, long)]
    pub output: PathBuf,
}

/// Runs `hyst run`.
pub fn main(args: Args) -> Result<()> {
    if args.saturate && !(args.source.model.is_some() && args.source.inverse) {
        bail!(
            "--saturate applies to --model FILE --inverse: the compensator of a model whose \
             output shaping saturates"
        );
    }
    let mut rows = CsvReader::open(&args.input)?;
    match args.source.chosen()? {
        Chosen::Model(path) => {
            let model = hyst_fit::ModelFile::read(path)?;
            let inverse = args.source.inverse;
            let column = match &args.column {
                Some(c) => c.clone(),
                None if inverse => model.columns.output.clone(),
                None => model.columns.input.clone(),
            };
            let saturation = if inverse { model.saturation() } else { None };
            if args.saturate && saturation.is_none() {
                eprintln!(
                    "hyst run: --saturate: the model's output is unbounded (no saturating output \
                     shaping); nothing will be clamped"
                );
            }
            let limits = saturation.map(|s| Limits {
                saturation: s,
                clamp: args.saturate,
            });
            let start = |first: f64| {
                model
                    .evaluator(first, inverse)
                    .with_context(|| format!("the model {} cannot start here", path.display()))
            };
            run(&mut rows, &args, Some(&column), limits, start)
        }
        Chosen::Parameters { k1, k2 } if args.source.inverse => {
            let start = |_: f64| InverseHysteresis::new(k1, k2).context("--k1/--k2");
            run(&mut rows, &args, args.column.as_deref(), None, start)
        }
        Chosen::Parameters { k1, k2 } => {
            let start = |_: f64| Hysteresis::new(k1, k2).context("--k1/--k2");
            run(&mut rows, &args, args.column.as_deref(), None, start)
        }
    }
}

/// What the compensator of a model with a saturating output shaping may be asked for, and
/// whether to clamp (`--saturate`) or refuse the rest.
#[derive(Clone, Copy)]
struct Limits {
    /// The model's output range and the clamp limits.
    saturation: Saturation,
    /// Clamp (`--saturate`) instead of refusing.
    clamp: bool,
}

/// The columns of one run.
struct Columns {
    /// The input column.
    input: usize,
    /// Its name.
    name: String,
    /// The derivative columns `<name>_d1 …`.
    derivatives: Vec<usize>,
    /// The record column.
    record: Option<usize>,
}

/// Streams INPUT through the operator that `start` builds for each record (from the record's
/// first sample) into OUTPUT.
fn run<R: Read, E: Operator<f64>>(
    rows: &mut CsvReader<R>,
    args: &Args,
    column: Option<&str>,
    limits: Option<Limits>,
    start: impl FnMut(f64) -> Result<E>,
) -> Result<()> {
    let n = usize::from(args.derivatives);
    let input = rows.pick_column(column)?;
    let name = rows.names().get(input).cloned().unwrap_or_default();
    let mut derivatives = Vec::with_capacity(n);
    for k in 1..=n {
        let wanted = format!("{name}_d{k}");
        derivatives.push(rows.column(&wanted).with_context(|| {
            format!(
                "--derivatives {n} needs the column {wanted:?} (time derivative {k} of {name:?})"
            )
        })?);
    }
    let record = match &args.record {
        Some(r) => Some(rows.column(r).context("--record")?),
        None => None,
    };
    let mut names = vec!["x".to_string(), "y".to_string()];
    names.extend((1..=n).map(|k| format!("y_d{k}")));
    if let Some(r) = &args.record {
        if names.contains(r) {
            bail!("--record {r}: the output already has a column {r:?}; rename the record column");
        }
        names.push(r.clone());
    }
    let columns = Columns {
        input,
        name,
        derivatives,
        record,
    };
    let mut out = CsvWriter::create(&args.output, names)?;
    macro_rules! with_order {
        ($($n:literal)*) => {
            match n {
                0 => stream::<R, E, 0>(rows, &columns, limits, start, &mut out),
                $($n => stream::<R, E, $n>(rows, &columns, limits, start, &mut out),)*
                n => bail!("--derivatives {n}: at most {MAX_DERIVATIVES} are supported"),
            }
        };
    }
    let clamped = with_order!(1 2 3 4 5 6 7 8)?;
    out.finish()?;
    if let (Some(limits), Some(first)) = (limits, clamped.first) {
        let s = limits.saturation;
        eprintln!(
            "hyst run: --saturate clamped {} of {} desired outputs into [{}, {}] ({} % of the \
             range ({}, {}) of the model's {} output shaping); the first on {}:{} (value {})",
            clamped.rows,
            clamped.of,
            Num(s.limits.0),
            Num(s.limits.1),
            100.0 * SATURATION_FRACTION,
            Num(s.range.0),
            Num(s.range.1),
            s.shaping,
            rows.source(),
            first.0,
            Num(first.1)
        );
    }
    Ok(())
}

/// How many rows `--saturate` clamped, of how many, and the first (line and value).
#[derive(Default)]
struct Clamped {
    /// Rows clamped.
    rows: usize,
    /// Rows read.
    of: usize,
    /// Line and value of the first clamped row.
    first: Option<(usize, f64)>,
}

/// Rows read, run and written at a time: each phase runs over a block in a tight loop (as
/// when the whole file was held), and memory stays bounded by the block.
const BLOCK: usize = 4096;

/// One block of rows: where they are and what the operator gets.
struct Block<const N: usize> {
    /// Source lines.
    lines: Vec<usize>,
    /// Operator inputs (after `--saturate`) with their time derivatives.
    x: Vec<Jet<f64, N>>,
    /// Record ids (empty without `--record`).
    id: Vec<f64>,
    /// Outputs.
    y: Vec<Jet<f64, N>>,
}

/// The loop of [`run`] for N time derivatives: blocks of rows are read, run and written in
/// turn. An error is reported for the first row, in file order, where anything fails (a row
/// that cannot be read stops the reading; the rows before it are still run first), and the
/// block holding it is not written.
fn stream<R: Read, E: Operator<f64>, const N: usize>(
    rows: &mut CsvReader<R>,
    columns: &Columns,
    limits: Option<Limits>,
    mut start: impl FnMut(f64) -> Result<E>,
    out: &mut CsvWriter,
) -> Result<Clamped> {
    let source = rows.source().to_string();
    let (input, name) = (columns.input, columns.name.as_str());
    let at = |line: usize, x: f64| {
        format!(
            "{source}:{line}: column {} ({name:?}): value {}",
            input + 1,
            Num(x)
        )
    };
    let mut clamped = Clamped::default();
    let mut op: Option<E> = None;
    let mut record = f64::NAN;
    let mut block = Block::<N> {
        lines: Vec::with_capacity(BLOCK),
        x: Vec::with_capacity(BLOCK),
        id: Vec::with_capacity(BLOCK),
        y: Vec::with_capacity(BLOCK),
    };
    let mut values = Vec::with_capacity(N + 3);
    loop {
        // Read.
        block.lines.clear();
        block.x.clear();
        block.id.clear();
        block.y.clear();
        let mut unread = None;
        while block.lines.len() < BLOCK {
            match rows.next_row() {
                Ok(Some((line, row))) => {
                    let x = row.get(input).copied().unwrap_or_default();
                    let mut d = [0.0; N];
                    for (slot, &c) in d.iter_mut().zip(&columns.derivatives) {
                        *slot = row.get(c).copied().unwrap_or_default();
                    }
                    block.lines.push(line);
                    block.x.push(Jet::from_derivatives(x, d));
                    block
                        .id
                        .extend(columns.record.and_then(|r| row.get(r).copied()));
                }
                Ok(None) => break,
                Err(e) => {
                    unread = Some(e);
                    break;
                }
            }
        }
        if block.lines.is_empty() {
            return match unread {
                Some(e) => Err(e.into()),
                None => Ok(clamped),
            };
        }
        // Run.
        for (i, (&line, x)) in block.lines.iter().zip(block.x.iter_mut()).enumerate() {
            clamped.of += 1;
            if let Some(limits) = limits {
                let s = limits.saturation;
                let (lo, hi) = s.limits;
                let v = x.value();
                if limits.clamp && !(lo..=hi).contains(&v) {
                    clamped.rows += 1;
                    clamped.first.get_or_insert((line, v));
                    *x = Jet::constant(v.clamp(lo, hi));
                } else if v <= s.range.0 || v >= s.range.1 {
                    bail!(
                        "{source}:{line}: column {} ({name:?}): desired output {} is outside \
                         the range ({}, {}) of the model's {} output shaping, which no command \
                         reaches; --saturate clamps such values into [{}, {}] ({} % of the \
                         range)",
                        input + 1,
                        Num(v),
                        Num(s.range.0),
                        Num(s.range.1),
                        s.shaping,
                        Num(lo),
                        Num(hi),
                        100.0 * SATURATION_FRACTION
                    );
                }
            }
            let id = block.id.get(i).copied();
            // A new record (or the first row): the operator starts afresh from this sample.
            let fresh = match id {
                Some(id) => id != record,
                None => op.is_none(),
            };
            if fresh {
                let started = start(x.value()).with_context(|| match id {
                    Some(id) => format!(
                        "{} (first sample of record {})",
                        at(line, x.value()),
                        Num(id)
                    ),
                    None => at(line, x.value()),
                })?;
                record = id.unwrap_or(f64::NAN);
                op = Some(started);
            }
            let Some(op) = op.as_mut() else {
                bail!("{}: the operator was not started", at(line, x.value()));
            };
            let y = op.try_step(*x).with_context(|| at(line, x.value()))?;
            if !y.all_finite() {
                // The core refuses overflowing outputs; a model's own parts (a
                // Prandtl–Ishlinskii output polynomial) are checked here, so the error names
                // the input line.
                bail!(
                    "{} gives the output {}: not a finite number",
                    at(line, x.value()),
                    y.value()
                );
            }
            block.y.push(y);
        }
        // A row that cannot be read fails the run once the rows before it are known to run;
        // the block is not written (standard output gets no part of it).
        if let Some(e) = unread {
            return Err(e.into());
        }
        // Write.
        for (i, (x, y)) in block.x.iter().zip(&block.y).enumerate() {
            values.clear();
            values.push(x.value());
            values.push(y.value());
            values.extend_from_slice(&y.derivatives());
            values.extend(block.id.get(i).copied());
            out.write_row(&values)?;
        }
    }
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
