//! `hyst run --model M` for a model with dynamics or a rate term: the records' time stamps give
//! the sample period, and the model runs with the one discretisation of
//! `hyst_model::dynamics`.
//!
//! - Direct: the command column in, the model output out (named after the model's output
//!   column).
//! - `--inverse`: Lemma 5.1's compensator, the desired output in, the command out (named after
//!   the model's input column). The desired output's derivatives come from the columns
//!   `<name>_d1 … <name>_dn` when the file has them all (n the plant order), else from a
//!   reference prefilter of order n and bandwidth `--prefilter-hz F`: the command then makes the
//!   plant track the prefiltered reference (written as the column `<name>_filtered`), not the
//!   raw one.
//!
//! OUTPUT holds every column of INPUT first, as `hyst run` does for a static model
//! ([`crate::naming`]).
//!
//! The file is read whole (a record's period comes from all its stamps), checked, then run; the
//! output is written atomically.

use std::io::Read as _;
use std::path::Path;

use anyhow::{bail, Context, Result};
use hyst_io::{CsvWriter, Table};
use hyst_model::dynamics::sample_period;
use hyst_model::{ModelFile, Prefilter, SmoothModel, TimedCompensator, TimedRun};

/// What `hyst run` asks of a timed model (its arguments, as `crate::run` parsed them).
pub struct Options<'a> {
    /// `--inverse`.
    pub inverse: bool,
    /// `--column` (at most one is accepted).
    pub columns: &'a [String],
    /// `--time`.
    pub time: Option<&'a str>,
    /// `--record`.
    pub record: Option<&'a str>,
    /// `--prefilter-hz`.
    pub prefilter_hz: Option<f64>,
    /// `--derivatives` (refused when non-zero).
    pub derivatives: u8,
    /// `--saturate` (refused).
    pub saturate: bool,
    /// INPUT.
    pub input: &'a Path,
    /// OUTPUT.
    pub output: &'a Path,
}

/// Runs a model with dynamics or a rate term (`model`, read from `path`) as `args` ask.
pub fn main(args: &Options<'_>, model: &ModelFile, path: &Path) -> Result<()> {
    let smooth = check(args, model, path)?;
    hyst_io::check_all_distinct(&[args.input, path], &[args.output])?;
    let (table, passed) = read(args.input, args.output)?;
    let inverse = args.inverse;
    let name = args.columns.first().map_or_else(
        || {
            if inverse {
                model.columns.output.clone()
            } else {
                model.columns.input.clone()
            }
        },
        Clone::clone,
    );
    let values = table.column(&name)?;
    let time_name = match args.time {
        Some(t) => t.to_string(),
        None => hyst_fit::data::default_time_column(&table)
            .map(str::to_string)
            .with_context(|| {
                format!(
                    "{}: the model {} has {}: it needs the records' time stamps, and the file has \
                     no column named {} (name it with --time COLUMN)",
                    table.source(),
                    path.display(),
                    what(smooth),
                    hyst_fit::data::TIME_COLUMNS.join(", ")
                )
            })?,
    };
    let time = table.column(&time_name)?;
    let labels = match args.record {
        Some(r) => Some(table.labels(r)?),
        None => None,
    };
    let order = smooth.dynamics.map_or(0, |d| d.order());
    let derivatives: Option<Vec<&[f64]>> = (1..=order)
        .map(|k| table.column(&format!("{name}_d{k}")).ok())
        .collect();
    if inverse && derivatives.is_none() && args.prefilter_hz.is_none() {
        bail!(
            "{}: the compensator of a plant of order {order} needs the desired output's first \
             {order} time derivatives: give the columns {} or a reference prefilter \
             (--prefilter-hz F, the bandwidth in Hz the command then tracks)",
            table.source(),
            (1..=order)
                .map(|k| format!("{name}_d{k}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    let filtered = inverse && derivatives.is_none();
    let base = if inverse {
        &model.columns.input
    } else {
        &model.columns.output
    };
    let names = crate::naming::output_names(
        table.names(),
        &crate::naming::Computed {
            base,
            columns: &[name.as_str()],
            derivatives: 0,
            extra: filtered.then_some("filtered"),
        },
    )?;
    let mut out = CsvWriter::create(args.output, names)?;
    let columns = Columns {
        table: &table,
        passed: &passed,
        values,
        time,
        time_name: &time_name,
        derivatives: derivatives.as_deref(),
        order,
        filtered,
    };
    for rows in records(table.len(), labels.as_deref()) {
        columns.run_record(smooth, args, rows, &mut out)?;
    }
    out.finish()?;
    Ok(())
}

/// Refuses, before the data is read, what a timed model cannot do as `args` ask; returns its
/// smooth model.
fn check<'m>(args: &Options<'_>, model: &'m ModelFile, path: &Path) -> Result<&'m SmoothModel> {
    let Some(smooth) = model.smooth.as_ref() else {
        bail!("{}: the model file holds no smooth model", path.display());
    };
    if args.derivatives > 0 || args.saturate || args.columns.len() > 1 {
        bail!(
            "{}: a model with dynamics or a rate term runs one column, without --derivatives or \
             --saturate (its compensator takes the desired output's derivatives from columns \
             <name>_d1 ... or from --prefilter-hz)",
            path.display()
        );
    }
    let inverse = args.inverse;
    if args.prefilter_hz.is_some() && !inverse {
        bail!("--prefilter-hz applies to --inverse (the compensator's reference)");
    }
    if inverse {
        TimedCompensator::check(smooth)
            .with_context(|| format!("{}: --inverse", path.display()))?;
    }
    Ok(smooth)
}

/// Reads INPUT once (a pipe cannot be read twice) and parses it twice: as numbers, and as the
/// cells OUTPUT passes through as they were written.
fn read(input: &Path, output: &Path) -> Result<(Table, Passed)> {
    let quiet = crate::progress::writes_to_terminal(output);
    let reading = crate::progress::reading(input, crate::progress::LARGE_FILE, quiet);
    let (file, source) = hyst_io::open_file(input)?;
    let mut bytes = Vec::new();
    hyst_io::CountingReader::new(file, reading)
        .read_to_end(&mut bytes)
        .map_err(|e| hyst_io::IoError::Read {
            file: source.clone(),
            source: e,
        })?;
    let table = Table::parse(&bytes, &source)?;
    let passed = Passed::read(&bytes, &source)?;
    Ok((table, passed))
}

/// Every row's cells as read, formatted for OUTPUT, each followed by `,`.
struct Passed {
    /// The cells of all rows.
    text: String,
    /// Where each row's cells end in `text`.
    ends: Vec<usize>,
    /// Cells per row.
    width: usize,
}

impl Passed {
    /// The cells of every row of the CSV `bytes` (`source` names it in errors).
    fn read(bytes: &[u8], source: &str) -> Result<Passed> {
        let mut rows = hyst_io::CsvReader::new(bytes, source)?;
        let width = rows.names().len();
        let mut text = String::new();
        let mut ends = Vec::new();
        while let Some(line) = rows.next_cells()? {
            rows.push_cells(line, &mut text)?;
            ends.push(text.len());
        }
        Ok(Passed { text, ends, width })
    }

    /// Row `i`'s cells.
    fn row(&self, i: usize) -> &str {
        let from = i
            .checked_sub(1)
            .and_then(|j| self.ends.get(j))
            .copied()
            .unwrap_or(0);
        let to = self.ends.get(i).copied().unwrap_or(from);
        self.text.get(from..to).unwrap_or_default()
    }
}

/// The columns of a timed run, read and checked.
struct Columns<'a> {
    table: &'a Table,
    passed: &'a Passed,
    values: &'a [f64],
    time: &'a [f64],
    time_name: &'a str,
    derivatives: Option<&'a [&'a [f64]]>,
    order: usize,
    filtered: bool,
}

impl Columns<'_> {
    /// Runs one record (`rows`) and writes its rows.
    fn run_record(
        &self,
        smooth: &SmoothModel,
        args: &Options<'_>,
        rows: std::ops::Range<usize>,
        out: &mut CsvWriter,
    ) -> Result<()> {
        let Columns {
            table,
            passed,
            values,
            time,
            time_name,
            derivatives,
            order,
            filtered,
        } = *self;
        let inverse = args.inverse;
        let t: Vec<f64> = rows.clone().map(|i| time[i]).collect();
        let period = sample_period(&t).map_err(|(i, message)| {
            anyhow::anyhow!(
                "{}:{}: column {time_name:?}: {message}",
                table.source(),
                table.line_of_row(rows.start + i)
            )
        })?;
        let at = |i: usize| format!("{}:{}", table.source(), table.line_of_row(i));
        let first = values[rows.start];
        if inverse {
            let mut c = TimedCompensator::new(smooth, first).with_context(|| {
                format!("{}: the compensator cannot start here", at(rows.start))
            })?;
            let mut prefilter = match (filtered, args.prefilter_hz) {
                (true, Some(hz)) => Some(Prefilter::new(order, hz, period, first)?),
                _ => None,
            };
            for i in rows.clone() {
                let desired: Vec<f64> = match (&mut prefilter, &derivatives) {
                    (Some(p), _) => p.step(values[i])[..=order].to_vec(),
                    (None, Some(d)) => std::iter::once(values[i])
                        .chain(d.iter().map(|col| col[i]))
                        .collect(),
                    (None, None) => vec![values[i]],
                };
                let (u, _) = c.step(&desired).with_context(|| {
                    format!(
                        "{}: desired output {}",
                        at(i),
                        hyst_io::number::sig(desired[0], 6)
                    )
                })?;
                let computed = [u, desired[0]];
                let n = if filtered { 2 } else { 1 };
                write_row(passed, i, computed.get(..n).unwrap_or_default(), out)?;
            }
        } else {
            let mut run = TimedRun::new(smooth, period, first)
                .with_context(|| format!("{}: the model cannot start here", at(rows.start)))?;
            for i in rows.clone() {
                let s = run
                    .step(values[i])
                    .with_context(|| format!("{}: input {}", at(i), values[i]))?;
                write_row(passed, i, &[s.y], out)?;
            }
        }
        Ok(())
    }
}

/// What makes a model timed, in words.
fn what(m: &SmoothModel) -> String {
    match (m.dynamics, m.rate) {
        (Some(d), Some(_)) => format!("dynamics of order {} and a rate term", d.order()),
        (Some(d), None) => format!("dynamics of order {}", d.order()),
        _ => "a rate term".into(),
    }
}

/// Writes row `i` of INPUT (every cell, as read) followed by the `computed` values.
fn write_row(passed: &Passed, i: usize, computed: &[f64], out: &mut CsvWriter) -> Result<()> {
    out.write_row_after(passed.row(i), passed.width, computed)?;
    Ok(())
}

/// The rows of each record: runs of equal labels of the record column (the whole file
/// without one).
fn records(len: usize, record: Option<&[String]>) -> Vec<std::ops::Range<usize>> {
    let mut out = Vec::new();
    let Some(r) = record else {
        out.push(0..len);
        return out;
    };
    let mut start = 0;
    for i in 1..=len {
        if i == len || r.get(i) != r.get(start) {
            out.push(start..i);
            start = i;
        }
    }
    out.retain(|r| !r.is_empty());
    out
}
