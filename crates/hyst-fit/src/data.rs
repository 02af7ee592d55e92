//! Measured data: one or more independent records of (input, output) samples with optional
//! weights, read from a CSV table, and the split into training and validation records.

use std::borrow::Cow;

use hyst_io::{Samples, Table};

use hyst_model::time::{split_of, time_column};
use hyst_model::Columns;

use crate::error::FitError;
pub use crate::grouping::MAX_RECORD_ID;
use crate::grouping::{group_rows, Column, RecordColumn};
pub use crate::record::{DataOptions, History, Record};
use crate::weights::Weights;

/// The largest magnitude of an input or output value the fit accepts: 1e100. Beyond it, squared
/// residuals, their sums and the Jacobian's products can overflow (data scaled by 1e300 gave an
/// infinite RMS; one 1e308 outlier a meaningless k1 with NaN standard errors).
pub const MAX_MAGNITUDE: f64 = 1e100;

/// The smallest span (max − min) of an input or output column the fit accepts: 1e-100,
/// symmetric to [`MAX_MAGNITUDE`]. Below it, squared residuals and their sums underflow (data
/// scaled by 1e-300 fitted with a zero RMS and NaN standard errors; at 1e-160 the output
/// offset was already unidentified).
pub const MIN_SPAN: f64 = 1e-100;

pub use hyst_model::time::TIME_COLUMNS;

/// A dataset: named columns, records, and the file it came from.
#[derive(Clone, Debug)]
pub struct Dataset {
    /// The source file (as given).
    pub source: String,
    /// The columns used.
    pub columns: Columns,
    /// The records, in file order.
    pub records: Vec<Record>,
    /// The labels of the records when the record column holds text: record `i` (its
    /// [`Record::id`]) is the rows labelled `labels[i]`, numbered in order of first
    /// appearance. Empty for numeric record ids, and after `--segment` (whose segments are
    /// numbered afresh).
    pub labels: Vec<String>,
    /// What reading the data did that the report should say (a record split at a gap in its
    /// time stamps).
    pub notes: Vec<String>,
}

/// Column names recognised as record columns when none is named. `segment` is one because a
/// file of several experiments often labels them so; a column of that name that is not a
/// record id gets the error naming its line, and `--no-record` reads the file as one record.
pub const RECORD_COLUMNS: [&str; 4] = ["loop", "curve_index", "record", "segment"];

impl Dataset {
    /// Builds a dataset from a table read by `hyst_io` (which refuses a column used as numbers
    /// that holds a cell that is not a finite number, naming file, line and column). A record
    /// column with a cell that is not a number is read as labels: records numbered 0, 1, …
    /// in order of first appearance ([`Dataset::labels`]).
    ///
    /// # Errors
    /// Missing columns ([`FitError::Io`]), non-integer record ids, negative weights, unknown
    /// validation records, a split that leaves no training record.
    pub fn from_table(table: &Table, options: &DataOptions) -> Result<Self, FitError> {
        let input = table.column(&options.input)?;
        let output = table.column(&options.output)?;
        let columns = (Column::Borrowed(input), Column::Borrowed(output));
        Self::build(table, options, columns, None)
    }

    /// [`Dataset::from_table`], taking the table: the input and output columns of a file
    /// read as one record move into it rather than being copied (a long record is held once).
    ///
    /// # Errors
    /// As [`Dataset::from_table`].
    pub fn from_table_owned(mut table: Table, options: &DataOptions) -> Result<Self, FitError> {
        // The columns the dataset reads, each once: a column read for two purposes (the same
        // input and output, a record column that is also the input) is not taken.
        let used = read_columns(|n| table.column_index(n).is_some(), options);
        let uses = |name: &str| used.iter().filter(|n| n.as_deref() == Some(name)).count();
        let [.., record] = &used;
        if uses(&options.input) > 1 || uses(&options.output) > 1 {
            return Self::from_table(&table, options);
        }
        let input = table.take_column(&options.input)?;
        let output = table.take_column(&options.output)?;
        // Numeric record ids are read once, into the records' grouping: taken, they are given
        // back before the samples are (8 bytes a row less at the peak).
        let ids = match record {
            Some(name) if uses(name) == 1 && !table.is_text(name) => table.take_column(name).ok(),
            _ => None,
        };
        Self::build(
            &table,
            options,
            (Column::Taken(input), Column::Taken(output)),
            ids,
        )
    }

    /// The columns of a table that [`Dataset::from_table`] reads with `options`, given the
    /// table's column names (a reader keeps only these: [`Table::read_digest_selected`]).
    #[must_use]
    pub fn wanted_columns(names: &[String], options: &DataOptions) -> Vec<bool> {
        let used = read_columns(|name| names.iter().any(|n| n == name), options);
        names
            .iter()
            .map(|n| used.iter().any(|u| u.as_deref() == Some(n.as_str())))
            .collect()
    }

    /// The dataset of `table` read with `options`, from its input and output columns, and from
    /// the record ids `ids` when they were taken out of the table.
    fn build(
        table: &Table,
        options: &DataOptions,
        (input, output): (Column<'_>, Column<'_>),
        ids: Option<Samples>,
    ) -> Result<Self, FitError> {
        check_columns(table, options, &input, &output)?;
        let record_name = record_column(table, options);
        let labels = match &record_name {
            Some(name) if table.is_text(name) => Some(table.labels(name)?),
            _ => None,
        };
        let record = match (&record_name, &labels) {
            (Some(_), Some(labels)) => Some(RecordColumn::Labels(labels)),
            (Some(name), None) => Some(RecordColumn::Ids(
                name,
                match ids {
                    Some(ids) => Column::Taken(ids),
                    None => Column::Borrowed(table.column(name)?),
                },
            )),
            (None, _) => None,
        };
        let weight = match &options.weight {
            Some(name) => Some((name.as_str(), table.samples(name)?)),
            None => None,
        };
        let file = table.source().to_string();
        let (mut records, mut labels) = group_rows(table, input, output, record, weight)?;
        let mut notes = Vec::new();
        let time = if options.timed {
            let (name, split) = set_periods(table, options, records, &mut notes)?;
            records = split;
            Some(name)
        } else {
            None
        };
        if let Some(len) = options.segment {
            records = segment(records, len)?;
            labels.clear();
        }
        hold_out(&mut records, &labels, options, &file)?;
        normalise_weights(&mut records).map_err(|e| e.reading(&file))?;
        Ok(Self {
            source: file,
            columns: Columns {
                input: options.input.clone(),
                output: options.output.clone(),
                record: record_name,
                weight: options.weight.clone(),
                time,
            },
            records,
            labels,
            notes,
        })
    }

    /// The label of record `id` when the record column holds text ([`Dataset::labels`]).
    #[must_use]
    pub fn label(&self, id: i64) -> Option<&str> {
        usize::try_from(id)
            .ok()
            .and_then(|i| self.labels.get(i))
            .map(String::as_str)
    }

    /// Builds a dataset from records in memory (tests, synthetic data).
    #[must_use]
    pub fn from_records(source: &str, columns: Columns, records: Vec<Record>) -> Self {
        Self {
            source: source.to_string(),
            columns,
            records,
            labels: Vec::new(),
            notes: Vec::new(),
        }
    }

    /// A one-record dataset from input and output slices (unit weights).
    #[must_use]
    pub fn single(input: &[f64], output: &[f64]) -> Self {
        let n = input.len().min(output.len());
        Self::from_records(
            "<memory>",
            Columns {
                input: "x".into(),
                output: "y".into(),
                record: None,
                weight: None,
                time: None,
            },
            vec![Record {
                id: 0,
                input: input[..n].into(),
                output: output[..n].into(),
                weight: Weights::Unit(n),
                rows: (0..n).collect(),
                validation: false,
                continues: false,
                period: None,
            }],
        )
    }

    /// The records grouped into uninterrupted histories ([`Record::continues`]): a model runs
    /// over each history from its start rule, so that a segment starts where the one before
    /// it ended.
    #[must_use]
    pub fn histories(&self) -> Vec<History<'_>> {
        let mut out: Vec<History<'_>> = Vec::new();
        for (i, r) in self.records.iter().enumerate() {
            match out.last_mut() {
                Some(h) if r.continues => {
                    h.parts.push((i, h.input.len(), r.len()));
                    h.input = h.input.join(&r.input);
                    h.output = h.output.join(&r.output);
                    h.weight.to_mut().extend(&r.weight);
                }
                _ => out.push(History {
                    input: r.input.clone(),
                    output: r.output.clone(),
                    weight: Cow::Borrowed(&r.weight),
                    parts: vec![(i, 0, r.len())],
                    period: r.period.as_ref(),
                }),
            }
        }
        out
    }

    /// Runs `run` (a record's input → the model output, `None` when the model cannot run it)
    /// over each history and returns the output of every record, in record order.
    #[must_use]
    pub fn run_histories(&self, run: impl Fn(&[f64]) -> Option<Vec<f64>>) -> Option<Vec<Vec<f64>>> {
        self.run_histories_with(|_, input| run(input))
    }

    /// As [`Dataset::run_histories`], with the index of each history in
    /// [`Dataset::histories`] (for a start estimated per history).
    #[must_use]
    pub fn run_histories_with(
        &self,
        run: impl Fn(usize, &[f64]) -> Option<Vec<f64>>,
    ) -> Option<Vec<Vec<f64>>> {
        let mut out = vec![Vec::new(); self.records.len()];
        for (index, h) in self.histories().into_iter().enumerate() {
            let y = run(index, &h.input)?;
            match h.parts[..] {
                // A history of one record: its output as it is (a long record's is not copied).
                [(i, 0, len)] if y.len() == len => out[i] = y,
                _ => {
                    for (i, start, len) in h.parts {
                        out[i] = y.get(start..start + len)?.to_vec();
                    }
                }
            }
        }
        Some(out)
    }

    /// The training records.
    pub fn training(&self) -> impl Iterator<Item = &Record> {
        self.records.iter().filter(|r| !r.validation)
    }

    /// The smallest and largest nominal sample period (s) of the records of a timed dataset
    /// (the model file's `[provenance] sample_periods`); `None` for a static one.
    #[must_use]
    pub fn sample_periods(&self) -> Option<[f64; 2]> {
        self.records
            .iter()
            .filter_map(|r| r.period.as_ref().map(hyst_model::TimeSteps::nominal))
            .fold(None, |range, h| {
                Some(range.map_or([h, h], |[lo, hi]: [f64; 2]| [lo.min(h), hi.max(h)]))
            })
    }

    /// The validation records.
    pub fn validation(&self) -> impl Iterator<Item = &Record> {
        self.records.iter().filter(|r| r.validation)
    }

    /// Training samples with a non-zero weight.
    #[must_use]
    pub fn training_samples(&self) -> usize {
        self.training()
            .map(|r| r.weight.iter().filter(|w| *w > 0.0).count())
            .sum()
    }

    /// (min, max) of the input over all records.
    #[must_use]
    pub fn input_range(&self) -> (f64, f64) {
        range(self.records.iter().flat_map(|r| r.input.iter()))
    }

    /// (min, max) of the output over all records.
    #[must_use]
    pub fn output_range(&self) -> (f64, f64) {
        range(self.records.iter().flat_map(|r| r.output.iter()))
    }

    /// Checks that the data can identify a model with `parameters` free parameters: a moving
    /// input, more training samples than parameters, and, when the model is `increasing` (the
    /// operator form and the Prandtl–Ishlinskii model; not the stop form, whose linear term
    /// takes either sign), an output that rises with the input.
    ///
    /// # Errors
    /// [`FitError::ConstantInput`], [`FitError::ConstantOutput`], [`FitError::TooFewSamples`],
    /// [`FitError::DecreasingOutput`].
    pub fn check(&self, parameters: usize, increasing: bool) -> Result<(), FitError> {
        let samples = self.training_samples();
        let (lo, hi) = range(self.training().flat_map(|r| r.input.iter()));
        if hi.is_nan() || hi <= lo {
            return Err(FitError::ConstantInput {
                file: self.source.clone(),
                column: self.columns.input.clone(),
                value: lo,
                samples,
            });
        }
        let (ylo, yhi) = range(self.training().flat_map(|r| r.output.iter()));
        if yhi.is_nan() || yhi <= ylo {
            return Err(FitError::ConstantOutput {
                file: self.source.clone(),
                column: self.columns.output.clone(),
                value: ylo,
                samples,
            });
        }
        if samples <= parameters {
            return Err(FitError::TooFewSamples {
                file: self.source.clone(),
                samples,
                parameters,
            });
        }
        // Sign of the input-output correlation over the training data.
        let (mut n, mut sx, mut sy, mut sxy, mut sxx) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for r in self.training() {
            for (x, y) in r.input.iter().zip(&r.output) {
                n += 1.0;
                sx += x;
                sy += y;
                sxy += x * y;
                sxx += x * x;
            }
        }
        let cov = sxy / n - (sx / n) * (sy / n);
        if increasing && cov < 0.0 && sxx / n - (sx / n) * (sx / n) > 0.0 {
            return Err(FitError::DecreasingOutput {
                file: self.source.clone(),
                column: self.columns.output.clone(),
            });
        }
        Ok(())
    }
}

/// Refuses input and output columns the fit cannot use: a value beyond [`MAX_MAGNITUDE`], the
/// same column for both, a span below [`MIN_SPAN`].
fn check_columns(
    table: &Table,
    options: &DataOptions,
    input: &[f64],
    output: &[f64],
) -> Result<(), FitError> {
    for (name, column) in [(&options.input, input), (&options.output, output)] {
        if let Some(row) = column.iter().position(|v| v.abs() > MAX_MAGNITUDE) {
            return Err(FitError::ValueTooLarge {
                file: table.source().to_string(),
                line: table.line_of_row(row),
                column: name.clone(),
                value: column[row],
                limit: MAX_MAGNITUDE,
            });
        }
    }
    if options.input == options.output {
        return Err(FitError::Invalid(format!(
            "{}: the input and the output are the same column {:?}: a hysteresis model \
             needs an output measured apart from its input",
            table.source(),
            options.input
        )));
    }
    for (name, column) in [(&options.input, input), (&options.output, output)] {
        let (min, max) = range(column.iter());
        let span = max - min;
        if span > 0.0 && span < MIN_SPAN {
            return Err(FitError::SpanTooSmall {
                file: table.source().to_string(),
                column: name.clone(),
                span,
                min,
                max,
                limit: MIN_SPAN,
            });
        }
    }
    Ok(())
}

/// The columns a dataset reads with `options` from a table whose column names are those `has`:
/// input, output, weight, time (read only for a timed fit) and record column, in that order.
fn read_columns(has: impl Fn(&str) -> bool, options: &DataOptions) -> [Option<String>; 5] {
    let time = options
        .timed
        .then(|| time_column(options.time.as_deref(), &has).map(str::to_string))
        .flatten();
    [
        Some(options.input.clone()),
        Some(options.output.clone()),
        options.weight.clone(),
        time,
        record_column_in(has, options),
    ]
}

/// The record column: the one named, else the first of [`RECORD_COLUMNS`] in the table; none
/// with `no_record`.
fn record_column(table: &Table, options: &DataOptions) -> Option<String> {
    record_column_in(|n| table.column_index(n).is_some(), options)
}

/// [`record_column`] of a table whose column names are those `has`.
fn record_column_in(has: impl Fn(&str) -> bool, options: &DataOptions) -> Option<String> {
    if options.no_record {
        None
    } else {
        match &options.record {
            Some(name) => Some(name.clone()),
            None => RECORD_COLUMNS
                .iter()
                .find(|n| has(n))
                .map(|n| (*n).to_string()),
        }
    }
}

/// Gives every record its time steps from the time column (`--time`, else the first of
/// [`TIME_COLUMNS`]), splitting a record at a gap in its stamps (a note for each in `notes`),
/// and returns the column's name and the records.
///
/// # Errors
/// [`FitError::Invalid`] without a time column; [`FitError::BadTime`] naming the line of a
/// stamp that is not finite, repeated or decreasing, or of the first stamp of a record whose
/// stamps cannot resolve its steps.
fn set_periods(
    table: &Table,
    options: &DataOptions,
    records: Vec<Record>,
    notes: &mut Vec<String>,
) -> Result<(String, Vec<Record>), FitError> {
    let name = match &options.time {
        Some(name) => name.clone(),
        None => time_column(None, |n| table.column_index(n).is_some())
            .map(str::to_string)
            .ok_or_else(|| {
                FitError::Invalid(format!(
                    "{}: a model with dynamics or a rate term needs time stamps, and the file has \
                     no column named {} (name the time column with --time COLUMN)",
                    table.source(),
                    TIME_COLUMNS.join(", ")
                ))
            })?,
    };
    let column = table.column(&name)?;
    let mut out = Vec::with_capacity(records.len());
    for mut r in records {
        // The stamps from the column (no copy of a long record's).
        let (parts, gaps) = match split_of(|| r.rows.iter().map(|row| (row, column[row]))) {
            Ok(split) => split,
            Err((row, message)) => {
                return Err(FitError::BadTime {
                    file: table.source().to_string(),
                    line: table.line_of_row(row),
                    column: name,
                    record: r.id,
                    message,
                })
            }
        };
        for gap in &gaps {
            notes.push(format!(
                "{}:{}: record {}: {}",
                table.source(),
                table.line_of_row(gap.at),
                r.id,
                gap.describe()
            ));
        }
        if let [(_, steps)] = parts.as_slice() {
            r.period = Some(steps.clone());
            out.push(r);
            continue;
        }
        for (range, steps) in parts {
            out.push(Record {
                input: r.input.slice(range.clone()),
                output: r.output.slice(range.clone()),
                weight: r.weight.slice(range.clone()),
                rows: r.rows.slice(range),
                period: Some(steps),
                ..r.clone()
            });
        }
    }
    Ok((name, out))
}

/// Scales the weights so that the positive weights of the training records average 1: the
/// fit depends on their ratios only, never on their scale (weights of 1e-100 on every row
/// fitted nothing, the tolerances of the least squares being absolute). Unit weights stay
/// exactly 1. No positive training weight: nothing to scale.
///
/// # Errors
/// A temporary file for a long record's weights that cannot be written.
fn normalise_weights(records: &mut [Record]) -> Result<(), hyst_io::IoError> {
    let training = || records.iter().filter(|r| !r.validation);
    let largest = training()
        .flat_map(|r| r.weight.iter())
        .fold(0.0_f64, f64::max);
    if !(largest > 0.0 && largest.is_finite()) {
        return Ok(());
    }
    // Scaled by the largest first, so that the sum cannot overflow.
    let (sum, count) = training()
        .flat_map(|r| r.weight.iter())
        .filter(|w| *w > 0.0)
        .fold((0.0, 0_usize), |(s, n), w| (s + w / largest, n + 1));
    let mean = sum / count as f64;
    // Records whose weights are neighbouring parts of one column (the segments of a record)
    // are scaled as one column and cut again, so that they stay parts of one column (their
    // histories then join them without a copy).
    let mut rest = records;
    while let Some(first) = rest.first() {
        let mut joined = first.weight.clone();
        let mut n = 1;
        while let Some(next) = rest.get(n).filter(|r| joined.adjoins(&r.weight)) {
            joined.extend(&next.weight);
            n += 1;
        }
        joined.map(|w| w / largest / mean)?;
        let (run, after) = rest.split_at_mut(n);
        let mut at = 0;
        for r in run {
            let len = r.weight.len();
            r.weight = joined.slice(at..at + len);
            at += len;
        }
        rest = after;
    }
    Ok(())
}

/// Every record cut into consecutive segments of `len` samples (`--segment`), each its own
/// record numbered from 0, continuing the one before it when cut from the same record.
///
/// # Errors
/// A `len` below 2.
fn segment(records: Vec<Record>, len: usize) -> Result<Vec<Record>, FitError> {
    if len < 2 {
        return Err(FitError::Invalid(format!(
            "--segment {len}: a segment needs at least 2 samples"
        )));
    }
    let mut cut = Vec::new();
    let mut next = 0_i64;
    for r in records {
        for start in (0..r.len()).step_by(len) {
            let end = (start + len).min(r.len());
            cut.push(Record {
                id: next,
                input: r.input.slice(start..end),
                output: r.output.slice(start..end),
                weight: r.weight.slice(start..end),
                rows: r.rows.slice(start..end),
                validation: false,
                continues: start > 0,
                period: r.period.as_ref().map(|p| p.after(start)),
            });
            next += 1;
        }
    }
    Ok(cut)
}

/// Marks the records held out for validation: those `--validate` names, else every k-th
/// (`--validate-every`).
///
/// # Errors
/// A record to hold out that does not exist, `--validate-every` below 2, a split that holds
/// out every record (`file` names the data in the messages).
fn hold_out(
    records: &mut [Record],
    labels: &[String],
    options: &DataOptions,
    file: &str,
) -> Result<(), FitError> {
    if !options.validate.is_empty() {
        for id in &options.validate {
            match records.iter_mut().find(|r| r.id == *id) {
                Some(r) => r.validation = true,
                None => {
                    let ids: Vec<String> = records
                        .iter()
                        .map(
                            |r| match usize::try_from(r.id).ok().and_then(|i| labels.get(i)) {
                                Some(label) => format!("{} ({label:?})", r.id),
                                None => r.id.to_string(),
                            },
                        )
                        .collect();
                    return Err(FitError::Invalid(format!(
                        "{file}: no record {id} to hold out for validation (records: {})",
                        abbreviate(&ids)
                    )));
                }
            }
        }
    } else if let Some(k) = options.validate_every {
        if k < 2 {
            return Err(FitError::Invalid(
                "--validate-every K needs K >= 2 (K = 1 would hold out every record)".into(),
            ));
        }
        for (i, r) in records.iter_mut().enumerate() {
            r.validation = i % k == k - 1;
        }
    }
    if records.iter().all(|r| r.is_empty()) {
        return Err(FitError::Invalid(format!(
            "{file}: no samples: a fit needs data"
        )));
    }
    if records.iter().all(|r| r.validation) {
        return Err(FitError::Invalid(format!(
            "{file}: every record is held out for validation; nothing is left to fit"
        )));
    }
    Ok(())
}
/// (min, max) of finite values; (+∞, −∞) when there are none.
pub(crate) fn range<'a>(values: impl Iterator<Item = &'a f64>) -> (f64, f64) {
    values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(*v), hi.max(*v))
    })
}

/// `items` joined by commas, the middle of a long list left out (the first and last 6).
pub(crate) fn abbreviate(items: &[String]) -> String {
    if items.len() <= 12 {
        items.join(", ")
    } else {
        format!(
            "{}, …, {}",
            items[..6].join(", "),
            items[items.len() - 3..].join(", ")
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The weights' scale is removed (their ratios kept), unit weights stay
    /// exactly 1.
    #[test]
    fn weights_are_scaled_to_average_one() -> Result<(), FitError> {
        let options = DataOptions {
            input: "u".into(),
            output: "y".into(),
            weight: Some("w".into()),
            ..DataOptions::default()
        };
        let weights = |text: &[u8]| -> Result<Vec<f64>, FitError> {
            let table = Table::parse(text, "w.csv")?;
            let data = Dataset::from_table(&table, &options)?;
            Ok(data
                .records
                .iter()
                .flat_map(|r| r.weight.to_vec())
                .collect())
        };
        assert_eq!(weights(b"u,y,w\n0,0,1\n1,1,1\n2,1,1\n")?, [1.0, 1.0, 1.0]);
        assert_eq!(
            weights(b"u,y,w\n0,0,1e-100\n1,1,1e-100\n2,1,1e-100\n")?,
            [1.0, 1.0, 1.0]
        );
        let w = weights(b"u,y,w\n0,0,1e300\n1,1,3e300\n2,1,0\n")?;
        assert!(
            (w[0] - 0.5).abs() < 1e-15 && (w[1] - 1.5).abs() < 1e-15 && w[2] == 0.0,
            "{w:?}"
        );
        Ok(())
    }

    /// Weighted records cut by `--segment`: their scaled weights are still neighbouring parts
    /// of one column (each history joins its segments without a copy), with the values each
    /// segment scaled on its own would have.
    #[test]
    fn the_segments_of_a_weighted_record_stay_parts_of_one_column() -> Result<(), FitError> {
        let mut text = String::from("u,y,w,r\n");
        for i in 0..40 {
            let w = 0.5 + f64::from(i % 7) * 0.25;
            text.push_str(&format!("{i},{},{w},{}\n", i % 3, i / 30));
        }
        let table = Table::parse(text.as_bytes(), "w.csv")?;
        let options = DataOptions {
            input: "u".into(),
            output: "y".into(),
            weight: Some("w".into()),
            record: Some("r".into()),
            segment: Some(8),
            ..DataOptions::default()
        };
        let data = Dataset::from_table(&table, &options)?;
        let lens: Vec<usize> = data.records.iter().map(Record::len).collect();
        assert_eq!(lens, [8, 8, 8, 6, 8, 2]);
        let raw: Vec<f64> = table.column("w")?.to_vec();
        let positive: Vec<f64> = raw.iter().copied().filter(|w| *w > 0.0).collect();
        let largest = positive.iter().copied().fold(0.0, f64::max);
        let mean = positive.iter().map(|w| w / largest).sum::<f64>() / positive.len() as f64;
        let scaled: Vec<f64> = data
            .records
            .iter()
            .flat_map(|r| r.weight.to_vec())
            .collect();
        let want: Vec<f64> = raw.iter().map(|w| w / largest / mean).collect();
        assert_eq!(scaled, want);
        for pair in data.records.windows(2) {
            let joins = pair[0].weight.adjoins(&pair[1].weight);
            assert!(
                joins || !pair[1].continues,
                "{:?}",
                (pair[0].id, pair[1].id)
            );
        }
        let histories = data.histories();
        assert_eq!(histories.len(), 2);
        for h in &histories {
            let w = h.weight.as_slice().map(<[f64]>::as_ptr);
            let first = data.records[h.parts[0].0]
                .weight
                .as_slice()
                .map(<[f64]>::as_ptr);
            assert_eq!(
                w, first,
                "the history's weights are its first segment's column"
            );
        }
        Ok(())
    }

    /// Two experiments labelled by a `segment` column: two records, found without `--record`;
    /// `no_record` reads them as one.
    #[test]
    fn a_segment_column_splits_the_file_unless_told_not_to() -> Result<(), FitError> {
        let table = Table::parse(b"u,y,segment\n0,0,1\n1,1,1\n0,0.5,2\n1,1.5,2\n", "s.csv")?;
        let options = DataOptions {
            input: "u".into(),
            output: "y".into(),
            ..DataOptions::default()
        };
        let data = Dataset::from_table(&table, &options)?;
        assert_eq!(data.records.len(), 2);
        assert_eq!(data.columns.record.as_deref(), Some("segment"));
        let one = Dataset::from_table(
            &table,
            &DataOptions {
                no_record: true,
                ..options
            },
        )?;
        assert_eq!(one.records.len(), 1);
        Ok(())
    }

    /// The dataset built from a taken table is the one built from a borrowed table, and the
    /// reader's selection keeps every column the dataset asks for.
    #[test]
    fn a_taken_table_and_a_selection_give_the_same_dataset() -> Result<(), FitError> {
        let files: [&[u8]; 7] = [
            b"t,u,y,note\n0,0,0,a\n1,1,1,b\n2,2,1.5,c\n",
            b"u,loop,y\n0,3,0\n1,3,1\n2,5,1.5\n# gap\n3,5,1\n4,7,2\n",
            b"t,u,y,w\n0,0,0,1\n# gap\n1,1,1,2\n2,2,1.5,0\n",
            b"u,loop,y\n0,1,0\n1,1,1\n2,2,1.5\n3,2,1\n0,1,0.5\n",
            b"u,y,record,t\n0,0,a,0\n1,1,a,1\n2,1.5,b,2\n3,2,b,3\n",
            b"u,y,w\n0,0,1\n1,1,-1\n",
            b"u,y\n1,0\n1,1\n2,1.5\n2,1\n",
        ];
        for (k, text) in files.iter().enumerate() {
            let options = DataOptions {
                input: "u".into(),
                output: "y".into(),
                weight: (k == 2 || k == 5).then(|| "w".into()),
                timed: k == 4,
                // The input as the record column too: read twice, taken never.
                record: (k == 6).then(|| "u".into()),
                ..DataOptions::default()
            };
            let dir = tempfile::tempdir().map_err(|e| FitError::Invalid(e.to_string()))?;
            let path = dir.path().join("d.csv");
            std::fs::write(&path, text).map_err(|e| FitError::Invalid(e.to_string()))?;
            let whole = Table::read(&path)?;
            let select = |names: &[String]| Dataset::wanted_columns(names, &options);
            let (part, _) = Table::read_digest_selected(&path, Box::new(|_| {}), &select)?;
            let borrowed = Dataset::from_table(&whole, &options);
            let taken = Dataset::from_table_owned(part, &options);
            match (borrowed, taken) {
                (Ok(a), Ok(b)) => {
                    assert_eq!(a.records, b.records, "file {k}");
                    assert_eq!((a.labels, a.columns), (b.labels, b.columns), "file {k}");
                }
                (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string(), "file {k}"),
                (a, b) => assert_eq!(
                    a.err().map(|e| e.to_string()),
                    b.err().map(|e| e.to_string()),
                    "file {k}"
                ),
            }
        }
        Ok(())
    }
}
