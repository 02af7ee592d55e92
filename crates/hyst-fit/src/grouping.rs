//! The rows of a table grouped into records ([`group_rows`]): each record's samples, weights
//! and rows, a part of the columns without a copy where a record's rows are one run.

use std::collections::{BTreeMap, HashMap};
use std::ops::Deref;

use hyst_io::{Samples, Table};

use crate::error::FitError;
use crate::record::Record;
use crate::rows::Rows;
use crate::weights::Weights;

/// The largest magnitude of a record id: beyond, a float no longer holds every integer
/// (2⁵³ ≈ 9.007e15), so neighbouring ids would merge.
pub const MAX_RECORD_ID: f64 = 9.0e15;

/// A column a dataset reads: borrowed from its table, or taken out of it (no copy).
pub(crate) enum Column<'a> {
    /// Borrowed from the table.
    Borrowed(&'a [f64]),
    /// Taken out of the table ([`Table::take_column`]).
    Taken(Samples),
}

impl Deref for Column<'_> {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        match self {
            Column::Borrowed(values) => values,
            Column::Taken(values) => values,
        }
    }
}

/// The record column of a table.
pub(crate) enum RecordColumn<'a> {
    /// Numeric record ids: the column's name and values.
    Ids(&'a str, Column<'a>),
    /// Text labels, one per row.
    Labels(&'a [String]),
}

/// The rows of `table` grouped into records by the value of the `record` column (one record
/// without it), each sample with its weight from the `weight` column (1 without it). A record
/// is a run of equal ids (or labels); an id that comes back later continues its record.
/// Labels are numbered 0, 1, … in order of first appearance; the labels are returned in that
/// order (none for numeric ids). Without a record column every row is record 0's, and owned
/// input and output columns become its samples without a copy ([`fill_samples`]).
///
/// # Errors
/// A record id that is not an integer of at most [`MAX_RECORD_ID`], a negative weight, a
/// temporary file that cannot be written ([`FitError::Io`]).
pub(crate) fn group_rows(
    table: &Table,
    input: Column<'_>,
    output: Column<'_>,
    record: Option<RecordColumn<'_>>,
    weight: Option<(&str, Samples)>,
) -> Result<(Vec<Record>, Vec<String>), FitError> {
    // Whether each record's weights are all 1 (kept as a count).
    let mut unit: Vec<bool> = Vec::new();
    let mut records: Vec<Record> = Vec::new();
    let mut index_of: BTreeMap<i64, usize> = BTreeMap::new();
    let mut label_ids: HashMap<&str, i64> = HashMap::new();
    let mut labels: Vec<String> = Vec::new();
    for row in 0..table.len() {
        let id = match &record {
            Some(RecordColumn::Labels(cells)) => {
                let label = cells[row].as_str();
                let next = label_ids.len() as i64;
                *label_ids.entry(label).or_insert_with(|| {
                    labels.push(label.to_string());
                    next
                })
            }
            Some(RecordColumn::Ids(name, col)) => {
                let v = col[row];
                if v.fract() != 0.0 || v.abs() > MAX_RECORD_ID {
                    return Err(FitError::BadRecordId {
                        file: table.source().to_string(),
                        line: table.line_of_row(row),
                        column: name.to_string(),
                        value: v,
                        limit: MAX_RECORD_ID,
                    });
                }
                v as i64
            }
            None => 0,
        };
        let w = match &weight {
            Some((name, col)) => {
                let w = col[row];
                if w < 0.0 {
                    return Err(FitError::NegativeWeight {
                        file: table.source().to_string(),
                        line: table.line_of_row(row),
                        column: name.to_string(),
                        value: w,
                    });
                }
                w
            }
            None => 1.0,
        };
        let at = *index_of.entry(id).or_insert_with(|| {
            records.push(Record {
                id,
                input: Samples::default(),
                output: Samples::default(),
                weight: Weights::default(),
                rows: Rows::default(),
                validation: false,
                continues: false,
                period: None,
            });
            unit.push(true);
            records.len() - 1
        });
        unit[at] &= w == 1.0;
        records[at].rows.push(row);
    }
    // The record ids are done with: given back before the samples are moved.
    drop(label_ids);
    drop(record);
    fill_samples(&mut records, input, output).map_err(|e| e.reading(table.source()))?;
    fill_weights(&mut records, weight.map(|(_, col)| col), &unit)
        .map_err(|e| e.reading(table.source()))?;
    Ok((records, labels))
}

/// Gives each record the weights of its rows from the weight column `weight`: a count where
/// they are all 1 (`unit`, or without a column), the record's part of the column where its
/// rows are one run (no copy), else its rows' weights gathered (a long record's to a
/// temporary file).
///
/// # Errors
/// A temporary file that cannot be written.
fn fill_weights(
    records: &mut [Record],
    weight: Option<Samples>,
    unit: &[bool],
) -> Result<(), hyst_io::IoError> {
    let weight = weight.map(Column::Taken);
    for (r, &unit) in records.iter_mut().zip(unit) {
        r.weight = match &weight {
            Some(col) if !unit => Weights::Each(rows_of(col, &r.rows)?),
            _ => Weights::Unit(r.rows.len()),
        };
    }
    Ok(())
}

/// Gives each record the input and output of its rows ([`rows_of`]): a record whose rows are
/// one run shares a taken column (a long file is held once, a spilled one stays in its file);
/// others copy their rows' samples (a long record's to a temporary file).
///
/// # Errors
/// A temporary file that cannot be written.
fn fill_samples(
    records: &mut [Record],
    input: Column<'_>,
    output: Column<'_>,
) -> Result<(), hyst_io::IoError> {
    for r in records.iter_mut() {
        r.input = rows_of(&input, &r.rows)?;
        r.output = rows_of(&output, &r.rows)?;
    }
    Ok(())
}

/// The values of `column` at `rows`: a part of a taken column when the rows are one run (no
/// copy), else the values gathered.
///
/// # Errors
/// A temporary file for a long gathered record that cannot be written.
fn rows_of(column: &Column<'_>, rows: &Rows) -> Result<Samples, hyst_io::IoError> {
    match (column, rows.as_run()) {
        (Column::Taken(values), Some(run)) => Ok(values.slice(run)),
        _ => Samples::collect_spilling(rows.iter().map(|row| column[row])),
    }
}
