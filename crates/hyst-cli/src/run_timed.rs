//! `hyst run --model M` for a model with dynamics or a rate term: the records' time stamps give
//! the sample period, and the model runs with the one discretisation of
//! `hyst_model::dynamics`.
//!
//! - Direct: the command column in, the model output out (`t,x,y`).
//! - `--inverse`: Lemma 5.1's compensator, the desired output in, the command out (`t,x,y`). The
//!   desired output's derivatives come from the columns `<name>_d1 … <name>_dn` when the file has
//!   them all (n the plant order), else from a reference prefilter of order n and bandwidth
//!   `--prefilter-hz F`: the command then makes the plant track the prefiltered reference
//!   (written as the column `x_filtered`), not the raw one.
//!
//! The file is read whole (a record's period comes from all its stamps), checked, then run; the
//! output is written atomically.

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
    hyst_io::check_all_distinct(&[args.input, path], &[args.output])?;
    let table = Table::read(args.input)?;
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
    let record = match args.record {
        Some(r) => Some(table.column(r)?),
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
    let mut names = vec![time_name.clone(), "x".into(), "y".into()];
    if filtered {
        names.push("x_filtered".into());
    }
    if let Some(r) = args.record {
        names.push(r.to_string());
    }
    let mut out = CsvWriter::create(args.output, names)?;
    let columns = Columns {
        table: &table,
        values,
        time,
        time_name: &time_name,
        record,
        derivatives: derivatives.as_deref(),
        order,
        filtered,
    };
    for rows in records(table.len(), record) {
        columns.run_record(smooth, args, rows, &mut out)?;
    }
    out.finish()?;
    Ok(())
}

/// The columns of a timed run, read and checked.
struct Columns<'a> {
    table: &'a Table,
    values: &'a [f64],
    time: &'a [f64],
    time_name: &'a str,
    record: Option<&'a [f64]>,
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
            values,
            time,
            time_name,
            record,
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
                let mut row = vec![time[i], values[i], u];
                if filtered {
                    row.push(desired[0]);
                }
                if let Some(r) = record {
                    row.push(r[i]);
                }
                out.write_row(&row)?;
            }
        } else {
            let mut run = TimedRun::new(smooth, period, first)
                .with_context(|| format!("{}: the model cannot start here", at(rows.start)))?;
            for i in rows.clone() {
                let s = run
                    .step(values[i])
                    .with_context(|| format!("{}: input {}", at(i), values[i]))?;
                let mut row = vec![time[i], values[i], s.y];
                if let Some(r) = record {
                    row.push(r[i]);
                }
                out.write_row(&row)?;
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

/// The rows of each record: runs of equal values of the record column (the whole file
/// without one).
fn records(len: usize, record: Option<&[f64]>) -> Vec<std::ops::Range<usize>> {
    let mut out = Vec::new();
    let Some(r) = record else {
        out.push(0..len);
        return out;
    };
    let mut start = 0;
    for i in 1..=len {
        if i == len || r[i].to_bits() != r[start].to_bits() {
            out.push(start..i);
            start = i;
        }
    }
    out.retain(|r| !r.is_empty());
    out
}
