//! `hyst run`: the operator or a fitted model, or its exact inverse, over a CSV file.
//!
//! Contract (relied on by tests and other tools):
//! - INPUT has a header row. The input column is `--column NAME`; else with `--model` the model's
//!   input column (its output column with `--inverse`); else `x`, else the only column.
//! - With `--derivatives N` INPUT also holds `<name>_d1 … <name>_dN`, the input's time
//!   derivatives, and OUTPUT gets `BASE_d1 … BASE_dN` (Proposition 2.7 and beyond, by jets). This
//!   holds for `--model` too: smooth models carry the jets through ψ_in, H (or H⁻¹) and ψ_out;
//!   Prandtl–Ishlinskii models give the piecewise derivatives of their plays (a play at the edge
//!   of its band that the input pushes moves with the input, every other play is stuck).
//! - With `--record COLUMN` the operator starts afresh (by its start rule, at the record's first
//!   sample) wherever the value of COLUMN changes from one row to the next: a value that comes
//!   back later starts a new record. COLUMN may hold numbers or text labels.
//! - OUTPUT holds every column of INPUT first, unchanged (each cell as read, trimmed; text
//!   columns included), then the computed columns, named after what they are
//!   ([`crate::naming`]): `BASE[,BASE_d1…]`, BASE the model's output column, its input column
//!   with `--inverse` (the command), or `y` for `--k1/--k2`; with `--saturate` also
//!   `COLUMN_saturated`, the desired output after clamping. One row per input row, every
//!   computed value in full `f64` precision (parses back to the identical number).
//! - `--column` may be repeated: one operator per column (the same parameters or model, each
//!   its own memory), computed columns `BASE_a,BASE_b,…[,BASE_a_d1…,BASE_b_d1…]`, and a record
//!   restarts every column. Plain `--k1/--k2` columns without derivatives run as one bank
//!   (outputs within a few ulp of the single-column run, not bit for bit); everything else runs
//!   each column exactly as alone. A single column takes the exact path always.
//! - Only the columns run (and their derivatives, and the record column) must hold numbers.
//! - The file is streamed: memory does not grow with its length.
//! - Errors name the file, line and column; nothing is written on failure (temporary file, then
//!   rename), and an OUTPUT that is INPUT (or the model file) is refused before anything is read.
//!   `-o -` streams to standard output (rows before an error stay written there).

use std::io::Read;
use std::path::PathBuf;

use hyst_model::Choice;

use crate::choice::choice;
use anyhow::{bail, Context, Result};

use crate::source::{Chosen, Source};
use hyst_bank::{BankFormula, BankVec};
use hyst_core::{Direct, Hysteresis, Inverse, InverseHysteresis, Jet, Operator, Sample};
use hyst_io::number::sig;
use hyst_io::{CsvReader, CsvWriter};
use hyst_model::saturation::Saturation;

mod columns;
mod reach;
pub(crate) mod rows;
mod timed;
use columns::{Columns, Input, Num};
use rows::{label_of, read_row, Block, Records, BLOCK};

use hyst_core::compensator::MAX_ORDER;

/// Arguments of `hyst run`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The operator.
    #[command(flatten)]
    pub source: Source,
    /// The input column (default: with --model the model's input column, or its output column
    /// with --inverse; else `x`, or the only column). Repeat it for several columns, one
    /// operator each (the same parameters or model, each with its own memory): OUTPUT then
    /// has every input column, then `<output>_<column>` for each (see docs/formats.md).
    #[arg(long, value_name = "NAME")]
    pub column: Vec<String>,
    /// Also propagate N time derivatives (columns <column>_d1 … <column>_dN in, <output>_d1 …
    /// out).
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u8).range(0..=MAX_ORDER as i64))]
    pub derivatives: u8,
    /// Restart the operator wherever the value of COLUMN changes (FORC curves, B-H loops): each
    /// record starts by the start rule (--model: the model's initial_state at the record's first
    /// sample; --k1/--k2: no history). A value that comes back after another is a new record,
    /// not a continuation. COLUMN may hold numbers or text labels. With several --column,
    /// every column restarts at a new record.
    #[arg(long, value_name = "COLUMN")]
    pub record: Option<String>,
    /// Run the file as one history even if it has a record column (by default, as `hyst fit`
    /// takes it, the first of `loop`, `curve_index`, `record` and `segment` that INPUT has and
    /// that is not an input column tells the records apart, with a note).
    #[arg(long, conflicts_with = "record")]
    pub no_record: bool,
    /// With --model --inverse, for a model whose output is bounded by a saturating output or
    /// input shaping (tanh, Langevin): clamp every desired output beyond the limits (the outputs
    /// reachable from every state, within 99.9 % of each saturating shaping's range:
    /// docs/formats.md) to them, instead of stopping at the first one out of reach. A
    /// clamped row is inverted at the clamped value (with zero derivatives), which OUTPUT's
    /// column `<column>_saturated` holds; stderr says how many rows were clamped and which was
    /// first.
    #[arg(long)]
    pub saturate: bool,
    /// The time column (s) of a model with dynamics or a rate term (default: a column named t,
    /// t_s, time or time_s): each step is taken as measured, and a gap of more than 10 times
    /// the median step starts the record afresh.
    #[arg(long, value_name = "COLUMN")]
    pub time: Option<String>,
    /// With --model --inverse for a model with dynamics of order n, when the file does not
    /// hold the desired output's n derivatives: a reference prefilter 1/(s/ω + 1)ⁿ, ω = 2πF,
    /// gives them, and the command makes the plant track the prefiltered reference exactly
    /// (written as the column `<column>_filtered`). F is a finite, positive frequency of at
    /// most 1/20 of the Nyquist frequency of each record's sample period (25 Hz at 1 kHz): the
    /// sampled commands carry no more.
    #[arg(long, value_name = "F", value_parser = bandwidth, allow_negative_numbers = true)]
    pub prefilter_hz: Option<f64>,
    /// The hold of the plant of a model with dynamics, instead of the model file's
    /// (`[dynamics] hold`): zoh, the command held over each step (an actuator driven by a DAC),
    /// or foh, the command linear between samples.
    #[arg(long, value_parser = choice::<hyst_model::Hold>(), value_name = "HOLD")]
    pub hold: Option<hyst_model::Hold>,
    /// Input CSV file.
    pub input: PathBuf,
    /// Output CSV file: written atomically (temporary file, then rename); `-` is standard
    /// output; a symbolic link or a device (/dev/null) is written through. Must not be INPUT.
    #[arg(short = 'o', long = "out", alias = "output", value_name = "OUTPUT")]
    pub output: PathBuf,
}

/// `--prefilter-hz F`, parsed and checked on its own (finite, positive); its bound for the
/// records' sample period is checked once they are read.
fn bandwidth(text: &str) -> std::result::Result<f64, String> {
    let hz: f64 = text.trim().parse().map_err(|e| format!("{e}"))?;
    hyst_model::Prefilter::check_bandwidth(hz, None).map_err(|e| e.to_string())?;
    Ok(hz)
}

/// Runs `hyst run`.
pub fn main(args: Args) -> Result<()> {
    if args.saturate && !(args.source.model.is_some() && args.source.inverse) {
        bail!(
            "--saturate applies to --model FILE --inverse: the inverse of a model whose output \
             is bounded (a saturating input or output shaping)"
        );
    }
    refuse_hold(&args, None)?;
    refuse_prefilter(&args)?;
    // The data is opened only once the model is known to do what is asked.
    let open = || open_input(&args.input, &args.output);
    let mut columns: Vec<Option<&str>> = args.column.iter().map(|c| Some(c.as_str())).collect();
    match args.source.chosen()? {
        Chosen::Model(path) => {
            let model = hyst_model::ModelFile::read(path)?;
            let inverse = args.source.inverse;
            if inverse {
                refuse_stop_form(&model, path)?;
            }
            if model.smooth.as_ref().is_some_and(|m| m.is_timed()) {
                return timed::main(&timed_options(&args), &model, path);
            }
            refuse_hold(&args, Some(path))?;
            if args.prefilter_hz.is_some() {
                bail!(
                    "--prefilter-hz applies to a model with dynamics: {} has none (its inverse \
                     needs no derivatives)",
                    path.display()
                );
            }
            let mut rows = open()?;
            if columns.is_empty() {
                columns.push(Some(if inverse {
                    model.columns.output.as_str()
                } else {
                    model.columns.input.as_str()
                }));
            }
            let saturation = if inverse { model.saturation() } else { None };
            if args.saturate && saturation.is_none() {
                eprintln!(
                    "hyst run: --saturate: the model's output is unbounded (no saturating input \
                     or output shaping); nothing will be clamped"
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
            let scalar = Scalar::new(start, limits);
            let base = if inverse {
                &model.columns.input
            } else {
                &model.columns.output
            };
            run(&mut rows, &args, &columns, base, |rows, c, out| {
                scalar.stream(rows, c, out, args.derivatives)
            })
        }
        Chosen::Parameters { k1, k2 } if columns.len() > 1 && args.derivatives == 0 => {
            let mut rows = open()?;
            // Several plain operators: one bank, stepped together.
            let n = columns.len();
            if args.source.inverse {
                let bank = Banked::<Inverse>::new(k1, k2, n)?;
                run(&mut rows, &args, &columns, PLAIN_OUTPUT, |rows, c, out| {
                    stream::<_, _, 0>(bank, rows, c, out)
                })
            } else {
                let bank = Banked::<Direct>::new(k1, k2, n)?;
                run(&mut rows, &args, &columns, PLAIN_OUTPUT, |rows, c, out| {
                    stream::<_, _, 0>(bank, rows, c, out)
                })
            }
        }
        Chosen::Parameters { k1, k2 } => {
            let mut rows = open()?;
            if columns.is_empty() {
                columns.push(None);
            }
            if args.source.inverse {
                let start = |_: f64| InverseHysteresis::new(k1, k2).context("--k1/--k2");
                run(&mut rows, &args, &columns, PLAIN_OUTPUT, |rows, c, out| {
                    Scalar::new(start, None).stream(rows, c, out, args.derivatives)
                })
            } else {
                let start = |_: f64| Hysteresis::new(k1, k2).context("--k1/--k2");
                run(&mut rows, &args, &columns, PLAIN_OUTPUT, |rows, c, out| {
                    Scalar::new(start, None).stream(rows, c, out, args.derivatives)
                })
            }
        }
    }
}

/// INPUT as streamed.
type Streamed = CsvReader<hyst_io::CountingReader<std::fs::File>>;

/// Opens INPUT for streaming; a large file shows the bytes read on a terminal
/// ([`crate::progress::LARGE_FILE`]), unless OUTPUT is that terminal (`-o -`).
fn open_input(path: &std::path::Path, output: &std::path::Path) -> Result<Streamed> {
    let (file, source) = hyst_io::open_file(path)?;
    let quiet = crate::progress::writes_to_terminal(output);
    let on_read = crate::progress::reading(path, crate::progress::LARGE_FILE, quiet);
    Ok(CsvReader::new(
        hyst_io::CountingReader::new(file, on_read),
        &source,
    )?)
}

/// `--hold` where it does not apply: without `--model` (`model` = `None`), or with a model
/// without dynamics (`model`, which the timed run does not take).
fn refuse_hold(args: &Args, model: Option<&std::path::Path>) -> Result<()> {
    match (args.hold, model) {
        (Some(_), None) if args.source.model.is_none() => bail!(
            "--hold applies to --model FILE, a model with dynamics (the hold is how its plant \
             sees the command)"
        ),
        (Some(hold), Some(path)) => bail!(
            "--hold {}: {} has no dynamics (the hold is how a plant sees its command)",
            hold.name(),
            path.display()
        ),
        _ => Ok(()),
    }
}

/// `--prefilter-hz` without `--model` (`--k1/--k2`): no plant, so nothing to prefilter for.
fn refuse_prefilter(args: &Args) -> Result<()> {
    if args.prefilter_hz.is_some() && args.source.model.is_none() {
        bail!(
            "--prefilter-hz applies to --model FILE --inverse, a model with dynamics (the \
             prefilter gives its compensator the desired output's derivatives)"
        );
    }
    Ok(())
}

/// What a run of a model with dynamics or a rate term takes of the arguments.
fn timed_options(args: &Args) -> timed::Options<'_> {
    timed::Options {
        inverse: args.source.inverse,
        columns: &args.column,
        time: args.time.as_deref(),
        record: args.record.as_deref(),
        no_record: args.no_record,
        prefilter_hz: args.prefilter_hz,
        hold: args.hold,
        derivatives: args.derivatives,
        saturate: args.saturate,
        input: &args.input,
        output: &args.output,
    }
}

/// `--inverse` of a stop-form (friction) model: refused before any data is read, since that
/// model maps position to force and has no inverse; friction is compensated by feeding the
/// predicted force forward instead (docs/fitting.md, "Compensating friction").
fn refuse_stop_form(model: &hyst_model::ModelFile, path: &std::path::Path) -> Result<()> {
    let stop = model.kind == hyst_model::ModelKind::Smooth
        && model
            .smooth
            .as_ref()
            .is_some_and(|m| m.invertible().is_err());
    if stop {
        bail!(
            "--inverse: the model {} is a stop-form (friction) model: it predicts the output \
             (force) from the input (position) and has no inverse. Friction is compensated by \
             feed-forward of the predicted force: run the model without --inverse on the \
             position (measured or desired) and add its output to the actuator command \
             (docs/fitting.md, \"Compensating friction\")",
            path.display()
        );
    }
    Ok(())
}

/// What the inverse of a model with a saturating output shaping may be asked for, and
/// whether to clamp (`--saturate`) or refuse the rest.
#[derive(Clone, Copy)]
struct Limits {
    /// The model's output range and the clamp limits.
    saturation: Saturation,
    /// Clamp (`--saturate`) instead of refusing.
    clamp: bool,
}

/// The computed column of a run with `--k1/--k2` (either direction).
const PLAIN_OUTPUT: &str = "y";

/// Streams INPUT through one operator per input column into OUTPUT: `go` runs the rows
/// (it holds the operators); `columns` names the input columns (`None`: the default one);
/// `base` names what the operators compute ([`crate::naming`]).
fn run<R: Read>(
    rows: &mut CsvReader<R>,
    args: &Args,
    columns: &[Option<&str>],
    base: &str,
    go: impl FnOnce(&mut CsvReader<R>, &Columns, &mut CsvWriter) -> Result<Clamped>,
) -> Result<()> {
    let n = usize::from(args.derivatives);
    let mut inputs: Vec<Input> = Vec::with_capacity(columns.len());
    for column in columns {
        let index = rows.pick_column(*column)?;
        let name = rows.names().get(index).cloned().unwrap_or_default();
        if inputs.iter().any(|i| i.index == index) {
            bail!("--column {name}: given twice (one operator per column)");
        }
        let mut derivatives = Vec::with_capacity(n);
        for k in 1..=n {
            let wanted = format!("{name}_d{k}");
            derivatives.push(rows.column(&wanted).with_context(|| {
                format!(
                    "--derivatives {n} needs the column {wanted:?} (time derivative {k} of \
                     {name:?})"
                )
            })?);
        }
        inputs.push(Input {
            index,
            name,
            derivatives,
        });
    }
    let record = rows::record_column(rows, args.record.as_deref(), args.no_record, &args.column)?;
    let run_names: Vec<&str> = inputs.iter().map(|i| i.name.as_str()).collect();
    let saturated = args.saturate;
    let names = crate::naming::output_names(
        rows.names(),
        &crate::naming::Computed {
            base,
            columns: &run_names,
            derivatives: n,
            extra: saturated.then_some("saturated"),
        },
    )?;
    let columns = Columns {
        inputs,
        record,
        width: rows.names().len(),
        saturated,
    };
    let mut out = CsvWriter::create(&args.output, names)?;
    let clamped = go(rows, &columns, &mut out)?;
    out.finish()?;
    if let (Some(limits), Some(first)) = (clamped.limits, clamped.first) {
        let s = limits.saturation;
        eprintln!(
            "hyst run: --saturate clamped {} of {} desired outputs into [{}, {}] ({}; the open \
             range of {} is ({}, {})); the first on {}:{} (value {})",
            clamped.rows,
            clamped.of,
            sig(s.limits.0, 7),
            sig(s.limits.1, 7),
            s.rule(),
            s.range_of(),
            sig(s.range.0, 7),
            sig(s.range.1, 7),
            rows.source(),
            first.0,
            Num(first.1)
        );
    }
    Ok(())
}

/// How many desired outputs `--saturate` clamped, of how many, and the first (line and
/// value).
#[derive(Clone, Copy, Default)]
struct Clamped {
    /// The limits that clamped them (`None`: nothing to clamp).
    limits: Option<Limits>,
    /// Values clamped.
    rows: usize,
    /// Values read.
    of: usize,
    /// Line and value of the first clamped one.
    first: Option<(usize, f64)>,
}

/// Where a value is, for messages.
struct Place<'a> {
    /// The file (or `<stdin>`).
    source: &'a str,
    /// The run's columns.
    columns: &'a Columns,
}

impl Place<'_> {
    /// `FILE:LINE: column C ("NAME")` for input column `k` of the run.
    fn column(&self, line: usize, k: usize) -> String {
        let (index, name) = self
            .columns
            .inputs
            .get(k)
            .map_or((0, ""), |i| (i.index, i.name.as_str()));
        format!("{}:{line}: column {} ({name:?})", self.source, index + 1)
    }

    /// `FILE:LINE: column C ("NAME"): value V`.
    fn at(&self, line: usize, k: usize, x: f64) -> String {
        format!("{}: value {}", self.column(line, k), Num(x))
    }
}

/// The operators of a run, one per input column, stepping jets of N time derivatives.
trait Channels<const N: usize> {
    /// Runs the block's rows in order, appending K outputs per row to `block.y`. An error
    /// names the first row, in file order (and in it the first column), where anything fails.
    fn run_block(
        &mut self,
        block: &mut Block<N>,
        place: &Place<'_>,
        clamped: &mut Clamped,
    ) -> Result<()>;
}

/// One scalar operator per column (the exact path of a single-column run): every option,
/// model files, derivatives, `--saturate`. `start` builds an operator for a record (or the
/// whole file) from its first sample.
struct Scalar<E, S> {
    /// The operators (empty before the first row and at a new record).
    ops: Vec<E>,
    /// The record of the running operators.
    record: f64,
    /// Builds an operator from a record's first sample.
    start: S,
    /// `--model --inverse` of a saturating output shaping: what may be asked.
    limits: Option<Limits>,
}

impl<E: Operator<f64>, S: FnMut(f64) -> Result<E>> Scalar<E, S> {
    /// Operators that `start` builds, `limits` on their inputs.
    fn new(start: S, limits: Option<Limits>) -> Self {
        Self {
            ops: Vec::new(),
            record: f64::NAN,
            start,
            limits,
        }
    }

    /// Streams INPUT into OUTPUT with N = `--derivatives` time derivatives.
    fn stream<R: Read>(
        self,
        rows: &mut CsvReader<R>,
        columns: &Columns,
        out: &mut CsvWriter,
        order: u8,
    ) -> Result<Clamped> {
        let limits = self.limits;
        macro_rules! with_order {
            ($($n:literal)*) => {
                match order {
                    $($n => stream::<R, Self, $n>(self, rows, columns, out),)*
                    n => bail!("--derivatives {n}: at most {MAX_ORDER} are supported"),
                }
            };
        }
        let clamped = with_order!(0 1 2 3 4)?;
        Ok(Clamped { limits, ..clamped })
    }

    /// The saturation of the model, if its output is bounded (for messages).
    fn saturation(&self) -> Option<&Saturation> {
        self.limits.as_ref().map(|l| &l.saturation)
    }

    /// `--saturate`: checks (or clamps) the desired output `x` of input column `k`.
    fn saturate<const N: usize>(
        &self,
        x: &mut Jet<f64, N>,
        line: usize,
        k: usize,
        place: &Place<'_>,
        clamped: &mut Clamped,
    ) -> Result<()> {
        let Some(limits) = self.limits else {
            return Ok(());
        };
        clamped.of += 1;
        let s = limits.saturation;
        let (lo, hi) = s.limits;
        let v = x.value();
        if limits.clamp && !(lo..=hi).contains(&v) {
            clamped.rows += 1;
            clamped.first.get_or_insert((line, v));
            *x = Jet::constant(v.clamp(lo, hi));
        } else if v <= s.range.0 || v >= s.range.1 {
            bail!(
                "{}: desired output {} is outside the range ({}, {}) of {}, which no command \
                 reaches; --saturate clamps such values into [{}, {}] ({})",
                place.column(line, k),
                Num(v),
                sig(s.range.0, 7),
                sig(s.range.1, 7),
                s.range_of(),
                sig(lo, 7),
                sig(hi, 7),
                s.rule()
            );
        }
        Ok(())
    }
}

impl<E: Operator<f64>, S: FnMut(f64) -> Result<E>, const N: usize> Channels<N> for Scalar<E, S> {
    fn run_block(
        &mut self,
        block: &mut Block<N>,
        place: &Place<'_>,
        clamped: &mut Clamped,
    ) -> Result<()> {
        let k = place.columns.inputs.len().max(1);
        for (i, (&line, row)) in block.lines.iter().zip(block.x.chunks_mut(k)).enumerate() {
            let id = block.id.get(i).copied();
            // A new record (or the first row): the operators start afresh from this row.
            let fresh = match id {
                Some(id) => id != self.record,
                None => self.ops.is_empty(),
            };
            if fresh {
                self.record = id.unwrap_or(f64::NAN);
                self.ops.clear();
            }
            for (c, x) in row.iter_mut().enumerate() {
                self.saturate(x, line, c, place, clamped)?;
                let at = || place.at(line, c, x.value());
                if fresh {
                    let started = (self.start)(x.value());
                    // A first desired output out of reach: said as at any other sample.
                    if let Some(e) = started.as_ref().err().and_then(reach::core_error) {
                        reach::refuse(&e, &place.column(line, c), self.saturation())?;
                    }
                    let started = started.with_context(|| match id {
                        Some(id) => format!(
                            "{} (first sample of record {})",
                            at(),
                            label_of(&block.labels, id)
                        ),
                        None => at(),
                    })?;
                    self.ops.push(started);
                }
                let Some(op) = self.ops.get_mut(c) else {
                    bail!("{}: the operator was not started", at());
                };
                let y = match op.try_step(*x) {
                    Ok(y) => y,
                    Err(e) => {
                        reach::refuse(&e, &place.column(line, c), self.saturation())?;
                        return Err(anyhow::Error::from(e).context(at()));
                    }
                };
                if !y.all_finite() {
                    // The core refuses overflowing outputs; a model's own parts (a
                    // Prandtl–Ishlinskii output polynomial) are checked here, so the error
                    // names the input line.
                    bail!(
                        "{} gives the output {}: not a finite number",
                        at(),
                        y.value()
                    );
                }
                block.y.push(y);
            }
        }
        Ok(())
    }
}

/// The plain operators H(k1, k2) or H⁻¹(k1, k2) of several columns (`--k1/--k2`, no
/// derivatives) as one bank ([`BankVec`]): the columns are stepped together, in SIMD lanes.
/// Its outputs agree with the scalar operator's to a few ulp, not bit for bit (the bank has
/// its own `exp`, `ln` and ω). A new record restarts every channel (no history).
struct Banked<F> {
    /// One channel per input column.
    bank: BankVec<f64, F>,
    /// The record running (`None` before the first row, and without `--record`).
    record: Option<f64>,
    /// The inputs of a run of rows, time-major.
    xs: Vec<f64>,
    /// Their outputs.
    ys: Vec<f64>,
}

impl<F: BankFormula> Banked<F> {
    /// `channels` channels of H(k1, k2) (or H⁻¹), checked.
    fn new(k1: f64, k2: f64, channels: usize) -> Result<Self> {
        let bank = BankVec::from_vecs(vec![k1; channels], vec![k2; channels])
            .map_err(|e| anyhow::anyhow!("--k1/--k2: {}", e.error))?;
        Ok(Self {
            bank,
            record: None,
            xs: Vec::with_capacity(BLOCK * channels),
            ys: Vec::with_capacity(BLOCK * channels),
        })
    }

    /// Steps rows `from..to` of the block (one record) through the bank.
    fn run_rows(
        &mut self,
        block: &mut Block<0>,
        place: &Place<'_>,
        rows: std::ops::Range<usize>,
    ) -> Result<()> {
        let k = self.bank.channels();
        let first = rows.start;
        let line = |i: usize| block.lines.get(first + i / k).copied().unwrap_or(0);
        let xs = block
            .x
            .get(rows.start * k..rows.end * k)
            .unwrap_or_default();
        self.xs.clear();
        self.xs.extend(xs.iter().map(Jet::value));
        self.ys.clear();
        self.ys.resize(self.xs.len(), 0.0);
        // The reader gives finite numbers only, so the bank can only refuse an output beyond
        // the float range, from an input or k1 near it. The core stops a block at such a tick
        // without naming it: those blocks run tick by tick, so the message names the row.
        let near = |v: &f64| v.abs() > f64::MAX / 8.0;
        let result = if self.xs.iter().any(near) || self.bank.k1().iter().any(near) {
            self.xs
                .chunks(k.max(1))
                .zip(self.ys.chunks_mut(k.max(1)))
                .enumerate()
                .try_for_each(|(t, (row, out))| {
                    self.bank.step(row, out).map_err(|mut e| {
                        e.channel += t * k;
                        e
                    })
                })
        } else {
            self.bank.process(&self.xs, &mut self.ys)
        };
        if let Err(e) = result {
            // `e.channel` is the failing sample's index in the block here.
            let x = self.xs.get(e.channel).copied().unwrap_or(f64::NAN);
            bail!(
                "{}: {}",
                place.at(line(e.channel), e.channel % k.max(1), x),
                e.error
            );
        }
        if let Some(i) = self.ys.iter().position(|y| !y.is_finite()) {
            bail!(
                "{} gives the output {}: not a finite number",
                place.at(line(i), i % k, self.xs.get(i).copied().unwrap_or(f64::NAN)),
                self.ys.get(i).copied().unwrap_or(f64::NAN)
            );
        }
        block.y.extend(self.ys.iter().map(|&y| Jet::constant(y)));
        Ok(())
    }
}

impl<F: BankFormula> Channels<0> for Banked<F> {
    fn run_block(
        &mut self,
        block: &mut Block<0>,
        place: &Place<'_>,
        _clamped: &mut Clamped,
    ) -> Result<()> {
        let rows = block.lines.len();
        let mut from = 0;
        while from < rows {
            // The rows of one record: the channels restart (no history) at a new one.
            let id = block.id.get(from).copied();
            let to = match id {
                Some(id) => (from..rows)
                    .find(|&i| block.id.get(i).copied() != Some(id))
                    .unwrap_or(rows),
                None => rows,
            };
            if let Some(id) = id {
                if self.record != Some(id) {
                    self.bank.reset();
                }
                self.record = Some(id);
            }
            self.run_rows(block, place, from..to)?;
            from = to;
        }
        Ok(())
    }
}

/// The loop of [`run`] for N time derivatives: blocks of rows are read, run and written in
/// turn. An error is reported for the first row, in file order, where anything fails (a row
/// that cannot be read stops the reading; the rows before it are still run first), and the
/// block holding it is not written.
fn stream<R: Read, C: Channels<N>, const N: usize>(
    mut channels: C,
    rows: &mut CsvReader<R>,
    columns: &Columns,
    out: &mut CsvWriter,
) -> Result<Clamped> {
    let source = rows.source().to_string();
    let place = Place {
        source: &source,
        columns,
    };
    let k = columns.inputs.len();
    let mut clamped = Clamped::default();
    let mut block = Block::<N> {
        lines: Vec::with_capacity(BLOCK),
        x: Vec::with_capacity(BLOCK * k),
        id: Vec::with_capacity(BLOCK),
        labels: Vec::new(),
        cells: String::new(),
        ends: Vec::with_capacity(BLOCK),
        y: Vec::with_capacity(BLOCK * k),
    };
    let mut values = Vec::with_capacity(k * (N + 2) + 1);
    let mut record = Records::default();
    loop {
        // Read.
        block.lines.clear();
        block.x.clear();
        block.id.clear();
        block.labels.clear();
        block.cells.clear();
        block.ends.clear();
        block.y.clear();
        let mut unread = None;
        while block.lines.len() < BLOCK {
            match read_row(rows, columns, &mut block, &mut record) {
                Ok(true) => {}
                Ok(false) => break,
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
        channels.run_block(&mut block, &place, &mut clamped)?;
        // A row that cannot be read fails the run once the rows before it are known to run;
        // the block is not written (standard output gets no part of it).
        if let Some(e) = unread {
            return Err(e.into());
        }
        // Write: INPUT's cells, then the outputs, their derivatives and (--saturate) the
        // desired outputs inverted.
        let mut from = 0;
        for ((x, y), &end) in block.x.chunks(k).zip(block.y.chunks(k)).zip(&block.ends) {
            values.clear();
            values.extend(y.iter().map(Jet::value));
            for y in y {
                values.extend_from_slice(&y.derivatives());
            }
            if columns.saturated {
                values.extend(x.iter().map(Jet::value));
            }
            let cells = block.cells.get(from..end).unwrap_or_default();
            out.write_row_after(cells, columns.width, &values)?;
            from = end;
        }
    }
}
