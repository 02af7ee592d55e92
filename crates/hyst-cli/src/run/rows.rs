//! Reading `hyst run`'s INPUT block by block: each row's cells for OUTPUT (passed through
//! unchanged), the operators' inputs with their derivatives, and its record.

use std::io::Read;

use hyst_core::Jet;
use hyst_io::CsvReader;

use super::columns::{Columns, Num};

/// Rows read, run and written at a time: each phase runs over a block in a tight loop (as
/// when the whole file was held), and memory stays bounded by the block.
pub(super) const BLOCK: usize = 4096;

/// One block of rows: where they are and what the operators get, time-major (row after row,
/// each row's K input columns together).
pub(super) struct Block<const N: usize> {
    /// Source lines.
    pub(super) lines: Vec<usize>,
    /// Operator inputs (after `--saturate`) with their time derivatives, K per row.
    pub(super) x: Vec<Jet<f64, N>>,
    /// Record numbers, counted from 1 in file order (empty without `--record`).
    pub(super) id: Vec<f64>,
    /// The label (the record column's cell) of each record that starts in the block.
    pub(super) labels: Vec<(f64, String)>,
    /// Every cell of the rows, formatted for OUTPUT, each followed by `,`.
    pub(super) cells: String,
    /// Where each row's cells end in `cells`.
    pub(super) ends: Vec<usize>,
    /// Outputs, K per row.
    pub(super) y: Vec<Jet<f64, N>>,
}

/// Record `id` in a message: its label (quoted) if it starts in the block, else its number.
pub(super) fn label_of(labels: &[(f64, String)], id: f64) -> String {
    labels
        .iter()
        .find(|(n, _)| *n == id)
        .map_or_else(|| Num(id).to_string(), |(_, label)| format!("{label:?}"))
}

/// The record a row belongs to: the record column's cell, compared as a number when it is one
/// (`1` and `1.0` are one record), else as text (a label such as `sine_1Hz`).
#[derive(Clone, Debug, PartialEq)]
enum RecordKey {
    /// A numeric cell.
    Number(f64),
    /// A text cell.
    Text(String),
}

impl RecordKey {
    /// Whether `cell` is this record's.
    fn is(&self, cell: &str) -> bool {
        match self {
            RecordKey::Number(a) => cell.parse::<f64>().is_ok_and(|b| *a == b),
            // A text key comes from a cell that is not a finite number: the same text is the
            // same record.
            RecordKey::Text(a) => a == cell,
        }
    }

    /// The key of `cell`.
    fn of(cell: &str) -> RecordKey {
        match cell.parse::<f64>() {
            Ok(v) if v.is_finite() => RecordKey::Number(v),
            _ => RecordKey::Text(cell.to_string()),
        }
    }
}

/// The record running while a file is read: its key and number.
#[derive(Default)]
pub(crate) struct Records {
    /// The key of the current record (`None` before the first row).
    key: Option<RecordKey>,
    /// Its number, from 1.
    number: f64,
}

impl Records {
    /// Whether the record column's `cell` of the next row starts a record (a new value, or a
    /// value that comes back after another); the record is then counted.
    pub(crate) fn starts(&mut self, cell: &str) -> bool {
        if self.key.as_ref().is_some_and(|key| key.is(cell)) {
            return false;
        }
        self.key = Some(RecordKey::of(cell));
        self.number += 1.0;
        true
    }
}

/// Reads the next row of INPUT into `block`: its cells for OUTPUT, the operators' inputs and
/// derivatives, its record. `Ok(false)` after the last row; an error (a row that cannot be
/// read, a cell of a column run that is not a finite number) leaves `block` as it was.
pub(super) fn read_row<R: Read, const N: usize>(
    rows: &mut CsvReader<R>,
    columns: &Columns,
    block: &mut Block<N>,
    record: &mut Records,
) -> Result<bool, hyst_io::IoError> {
    let Some(line) = rows.next_cells()? else {
        return Ok(false);
    };
    let (xs, cells) = (block.x.len(), block.cells.len());
    let mut read = || -> Result<Option<&str>, hyst_io::IoError> {
        for input in &columns.inputs {
            let x = rows.value(input.index, line)?;
            let mut d = [0.0; N];
            for (slot, &c) in d.iter_mut().zip(&input.derivatives) {
                *slot = rows.value(c, line)?;
            }
            block.x.push(Jet::from_derivatives(x, d));
        }
        rows.push_cells(line, &mut block.cells)?;
        columns.record.map(|r| rows.cell_text(r, line)).transpose()
    };
    let cell = match read() {
        Ok(cell) => cell,
        Err(e) => {
            block.x.truncate(xs);
            block.cells.truncate(cells);
            return Err(e);
        }
    };
    if let Some(cell) = cell {
        if record.starts(cell) {
            block.labels.push((record.number, cell.to_string()));
        }
        block.id.push(record.number);
    }
    block.ends.push(block.cells.len());
    block.lines.push(line);
    Ok(true)
}

/// The index of the column that tells INPUT's records apart: `--record`'s, else (unless
/// `--no-record`) the first of [`hyst_fit::data::RECORD_COLUMNS`] that INPUT has and that is not
/// one of `inputs` (`--column`), as `hyst fit` takes it, with a note on standard error.
///
/// # Errors
/// A `--record` column INPUT does not have.
pub(crate) fn record_column<R: Read>(
    rows: &CsvReader<R>,
    named: Option<&str>,
    no_record: bool,
    inputs: &[String],
) -> anyhow::Result<Option<usize>> {
    if let Some(name) = named {
        return Ok(Some(anyhow::Context::context(
            rows.column(name),
            "--record",
        )?));
    }
    if no_record {
        return Ok(None);
    }
    let found = hyst_fit::data::RECORD_COLUMNS
        .iter()
        .filter(|name| !inputs.iter().any(|c| c == *name))
        .find_map(|name| rows.column_index(name).map(|index| (*name, index)));
    Ok(found.map(|(name, index)| {
        eprintln!(
            "note: column {name:?} tells the records apart, as hyst fit takes it: each starts \
             afresh by the start rule (--no-record runs the file as one history)"
        );
        index
    }))
}
