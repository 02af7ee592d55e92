//! CSV tables of numbers (and, where a column holds words, of text).

use std::borrow::Cow;
use std::io::{self, Write};
use std::path::Path;

use crate::atomic::write_atomic_with;
use crate::cell::push_cell;
use crate::digest::{CountingReader, Digest, Hashing};
use crate::error::{IoError, MEMORY_SOURCE};
use crate::reader::CsvReader;
use crate::reader::{number, pick_column, unknown_column};
use crate::samples::{Samples, SamplesWriter};
use crate::writer::{check_names, push_f64, push_row, write_header};

/// A table of named `f64` columns, all of the same length, as read from or
/// written to a CSV file with a header row.
///
/// Every value is finite and every name is non-empty and unique; the
/// constructors ([`Table::read`], [`Table::new`]) enforce this. A column of a
/// file that holds a cell that is not a finite number is kept as text: it gives
/// its cells with [`Table::labels`], and [`Table::column`] refuses it with the
/// error of its first such cell. Each row remembers the line of the source file it came from,
/// so later checks (for example by the fitting code) can point at the exact
/// line of bad data.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// Column names, in file order.
    names: Vec<String>,
    /// Column values; `columns[i]` belongs to `names[i]` (empty for a text column). A long
    /// column read from a file is spilled to a temporary file ([`Samples`]).
    columns: Vec<Samples>,
    /// The cells of the columns kept as text; `None` for a column of numbers.
    text: Vec<Option<TextColumn>>,
    /// Whether each column was read (all are, except those a reader given a selection left
    /// out: [`Table::read_digest_selected`]).
    read: Vec<bool>,
    /// The 1-based source line of each row.
    lines: Lines,
    /// File path or other name of the source, used in error messages.
    source: String,
}

impl Table {
    /// Reads a CSV file with a header row.
    ///
    /// Cells are trimmed of leading and trailing spaces. A column whose cells
    /// all parse as finite `f64` is a column of numbers; a column with any other
    /// cell (a word, an empty cell, or `nan`, `inf` and out-of-range values such
    /// as `1e999`) is kept as text, and [`Table::column`] refuses it with the
    /// error that cell gives ([`IoError::Parse`] or [`IoError::NonFinite`]),
    /// so that only the columns used as numbers need to be numbers. Blank lines and lines starting with `#` are skipped, but
    /// still count for line numbers. `\r\n` line endings and a UTF-8 byte order
    /// mark are accepted. The path (as displayed) becomes the table's
    /// [`source`](Table::source).
    ///
    /// # Errors
    ///
    /// - [`IoError::Read`] or [`IoError::IsDirectory`] if the file cannot be read;
    /// - [`IoError::Empty`] if there are no lines besides blank lines and comments;
    /// - [`IoError::NoHeader`] if the first row contains only numbers;
    /// - [`IoError::EmptyName`] / [`IoError::DuplicateName`] for bad header cells;
    /// - [`IoError::CellCount`] if a row does not have one cell per column;
    /// - [`IoError::InvalidUtf8`] for a cell that is not UTF-8;
    /// - [`IoError::Csv`] if the CSV parser itself fails;
    /// - [`IoError::NoData`] if there is a header but no data rows.
    pub fn read(path: &Path) -> Result<Table, IoError> {
        collect(CsvReader::open(path)?, Vec::new())
    }

    /// [`Table::read`], and the size and hash of the bytes read, taken in the same single pass
    /// (a pipe or a FIFO can be read only once).
    ///
    /// # Errors
    /// As [`Table::read`].
    pub fn read_digest(path: &Path) -> Result<(Table, Digest), IoError> {
        Self::read_digest_with(path, Box::new(|_| {}))
    }

    /// [`Table::read_digest`], telling `on_read` how many bytes it has read so far as it goes
    /// (a progress display).
    ///
    /// # Errors
    /// As [`Table::read`].
    pub fn read_digest_with(
        path: &Path,
        on_read: Box<dyn FnMut(u64)>,
    ) -> Result<(Table, Digest), IoError> {
        Self::read_digest_selected(path, on_read, &|_| Vec::new())
    }

    /// [`Table::read_digest_with`], keeping only the columns `select` picks from the header's
    /// names: the others are checked for their number of cells only, and hold nothing (a
    /// long file's unused columns cost no memory). Asked for, such a column gives
    /// [`IoError::NotRead`]; [`Table::names`] still lists every column, so that an unknown
    /// name's error lists them all.
    ///
    /// # Errors
    /// As [`Table::read`].
    pub fn read_digest_selected(
        path: &Path,
        on_read: Box<dyn FnMut(u64)>,
        select: &dyn Fn(&[String]) -> Vec<bool>,
    ) -> Result<(Table, Digest), IoError> {
        let (file, name) = crate::reader::open_file(path)?;
        let (hashing, digest) = Hashing::new(CountingReader::new(file, on_read));
        let rows = CsvReader::new(hashing, &name)?;
        let read = select(rows.names());
        let table = collect(rows, read)?;
        Ok((table, digest.get()))
    }

    /// Parses CSV `bytes` as [`Table::read`] parses a file's contents, with
    /// `source` as the file name in error messages.
    ///
    /// # Errors
    ///
    /// As [`Table::read`], except the read errors.
    pub fn parse(bytes: &[u8], source: &str) -> Result<Table, IoError> {
        parse(bytes, source)
    }

    /// The CSV text [`Table::write_atomic`] writes.
    pub fn to_csv(&self) -> Vec<u8> {
        let mut out = Vec::new();
        // Writing into a Vec cannot fail.
        let _ = self.write_csv(&mut out);
        out
    }

    /// Builds a table from column names and columns.
    ///
    /// The table's [`source`](Table::source) is `<memory>`, and row `i` gets
    /// line `i + 2`, the line it has when the table is written with
    /// [`Table::write_atomic`].
    ///
    /// # Errors
    ///
    /// - [`IoError::ShapeMismatch`] if there are not as many names as columns;
    /// - [`IoError::NoColumns`] if there are none;
    /// - [`IoError::InvalidName`] if a name is empty, duplicated, has leading or
    ///   trailing whitespace or a line break, or if every name parses as a
    ///   number (the file written from such a table could not be read back);
    /// - [`IoError::ColumnLength`] if the columns differ in length;
    /// - [`IoError::NonFiniteValue`] for NaN or infinite values.
    pub fn new(names: Vec<String>, columns: Vec<Vec<f64>>) -> Result<Table, IoError> {
        let file = MEMORY_SOURCE.to_string();
        if names.len() != columns.len() {
            return Err(IoError::ShapeMismatch {
                file,
                names: names.len(),
                columns: columns.len(),
            });
        }
        check_names(&names, &file)?;
        let len = columns[0].len();
        for (i, column) in columns.iter().enumerate() {
            if column.len() != len {
                return Err(IoError::ColumnLength {
                    file,
                    column: i + 1,
                    name: names[i].clone(),
                    found: column.len(),
                    first: names[0].clone(),
                    expected: len,
                });
            }
            if let Some(row) = column.iter().position(|v| !v.is_finite()) {
                return Err(IoError::NonFiniteValue {
                    file,
                    column: i + 1,
                    name: names[i].clone(),
                    row: row + 1,
                    value: column[row],
                });
            }
        }
        Ok(Table {
            text: vec![None; names.len()],
            read: vec![true; names.len()],
            names,
            columns: columns.into_iter().map(Samples::from).collect(),
            lines: Lines::from(2, len),
            source: file,
        })
    }

    /// The column names, in file order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The number of rows (not counting the header).
    pub fn len(&self) -> usize {
        self.lines.rows
    }

    /// Whether the table has no rows (only possible for tables from [`Table::new`]).
    pub fn is_empty(&self) -> bool {
        self.lines.rows == 0
    }

    /// The values of the column called `name`.
    ///
    /// # Errors
    ///
    /// [`IoError::UnknownColumn`], listing the available columns, if there is no
    /// such column; for a column kept as text, the [`IoError::Parse`] or
    /// [`IoError::NonFinite`] error of its first cell that is not a finite
    /// number (file, line, column and cell), as reading the file once gave.
    pub fn column(&self, name: &str) -> Result<&[f64], IoError> {
        self.numbers(self.index_of(name)?)
    }

    /// The values of the column called `name` as [`Samples`] that share the table's (no copy
    /// of a long column, held or spilled).
    ///
    /// # Errors
    /// As [`Table::column`].
    pub fn samples(&self, name: &str) -> Result<Samples, IoError> {
        let i = self.index_of(name)?;
        self.numbers(i)?;
        Ok(self.columns[i].clone())
    }

    /// Moves the values of the column called `name` out of the table (no copy of a long
    /// column, held or spilled); the column then counts as not read ([`IoError::NotRead`]).
    ///
    /// # Errors
    /// As [`Table::column`].
    pub fn take_column(&mut self, name: &str) -> Result<Samples, IoError> {
        let i = self.index_of(name)?;
        self.numbers(i)?;
        self.read[i] = false;
        Ok(std::mem::take(&mut self.columns[i]))
    }

    /// The cells of the column called `name` as text: the cells as written
    /// (trimmed) in a column kept as text, except that the numbers before its
    /// first other cell are given in their shortest form (`1.50` as `1.5`), as
    /// are all the values of a column of numbers.
    ///
    /// # Errors
    ///
    /// [`IoError::UnknownColumn`], listing the available columns, if there is no
    /// such column.
    pub fn labels(&self, name: &str) -> Result<Cow<'_, [String]>, IoError> {
        let i = self.index_of(name)?;
        self.check_read(i)?;
        Ok(match &self.text[i] {
            Some(text) => Cow::Borrowed(&text.cells),
            None => Cow::Owned(self.columns[i].iter().map(|&v| shortest(v)).collect()),
        })
    }

    /// Whether the column called `name` holds a cell that is not a number at all
    /// (a word or an empty cell; `nan`, `inf` and `1e999` are numbers here, if not
    /// finite ones); `false` if there is no such column.
    pub fn is_text(&self, name: &str) -> bool {
        self.column_index(name)
            .and_then(|i| self.text[i].as_ref())
            .is_some_and(|text| text.words)
    }

    /// The values of column `i`, or the error of its first cell that is not a
    /// finite number.
    fn numbers(&self, i: usize) -> Result<&[f64], IoError> {
        self.check_read(i)?;
        let Some(text) = &self.text[i] else {
            return Ok(&self.columns[i]);
        };
        let name = &self.names[i];
        let error = match number(&text.bad_value, &self.source, text.bad_line, i, name) {
            Err(e) => e,
            // Cannot happen: the cell was refused when the file was read.
            Ok(_) => IoError::Parse {
                file: self.source.clone(),
                line: text.bad_line,
                column: i + 1,
                name: name.clone(),
                value: text.bad_value.clone(),
            },
        };
        Err(error)
    }

    /// [`IoError::NotRead`] if column `i` was left out by the reader's selection.
    fn check_read(&self, i: usize) -> Result<(), IoError> {
        if self.read[i] {
            return Ok(());
        }
        Err(IoError::NotRead {
            file: self.source.clone(),
            column: i + 1,
            name: self.names[i].clone(),
        })
    }

    /// [`Table::column_index`], or [`IoError::UnknownColumn`] listing the available columns.
    fn index_of(&self, name: &str) -> Result<usize, IoError> {
        self.column_index(name)
            .ok_or_else(|| unknown_column(&self.source, &self.names, name))
    }

    /// The 0-based index of the column called `name` (exact, case-sensitive match).
    pub fn column_index(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }

    /// The 1-based line number in the source of row `row` (0-based); the header
    /// of a file without leading comments is line 1, so its first row is line 2.
    ///
    /// # Panics
    ///
    /// If `row >= self.len()`.
    pub fn line_of_row(&self, row: usize) -> usize {
        self.lines.line_of_row(row)
    }

    /// The file path or other source name used in error messages.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// Chooses the input column the way `hyst run` does: the column called
    /// `name` if given; otherwise a column called `x`; otherwise the only
    /// column. Returns its 0-based index and values.
    ///
    /// # Errors
    ///
    /// [`IoError::UnknownColumn`] if `name` is given but not a column, and
    /// [`IoError::AmbiguousColumn`] (listing the columns and suggesting
    /// `--column`) if no name is given, there is no `x` column and there is more
    /// than one column; as [`Table::column`] for a column kept as text.
    pub fn pick_column(&self, name: Option<&str>) -> Result<(usize, &[f64]), IoError> {
        let index = pick_column(&self.source, &self.names, name)?;
        Ok((index, self.numbers(index)?))
    }

    /// Writes the table as CSV with a header row, atomically (see
    /// [`write_atomic`](crate::write_atomic)).
    ///
    /// Every value is written in the shortest form that parses back to the
    /// identical `f64` (including `-0`), in plain notation for magnitudes in
    /// `[1e-5, 1e16)` and in exponent notation (`1e300`, `5e-324`) otherwise.
    /// Names containing `,` or `"`, or a first name starting with `#`, are
    /// quoted, as are the cells of a column kept as text that would not read
    /// back as themselves. Lines end with `\n`.
    ///
    /// # Errors
    ///
    /// As [`write_atomic`](crate::write_atomic): on any error the destination is
    /// untouched and no temporary file remains.
    pub fn write_atomic(&self, path: &Path) -> Result<(), IoError> {
        write_atomic_with(path, |w| self.write_csv(w))
    }

    /// Writes the table as CSV (the format of [`Table::write_atomic`]) to `w`.
    /// A table read with a selection writes the columns it read.
    fn write_csv(&self, w: &mut dyn Write) -> io::Result<()> {
        let read = |i: &usize| self.read[*i];
        let kept: Vec<usize> = (0..self.names.len()).filter(read).collect();
        let names: Vec<String> = kept.iter().map(|&i| self.names[i].clone()).collect();
        write_header(w, &names)?;
        let mut line = String::new();
        let all_numbers = kept.iter().all(|&i| self.text[i].is_none());
        for row in 0..self.len() {
            line.clear();
            if all_numbers {
                push_row(&mut line, kept.iter().map(|&i| self.columns[i][row]));
            } else {
                for (k, &i) in kept.iter().enumerate() {
                    let (column, text) = (&self.columns[i], &self.text[i]);
                    if k > 0 {
                        line.push(',');
                    }
                    match text {
                        Some(text) => push_cell(&mut line, &text.cells[row], k == 0),
                        None => push_f64(&mut line, column[row]),
                    }
                }
                line.push('\n');
            }
            w.write_all(line.as_bytes())?;
        }
        Ok(())
    }
}

/// The cells of a column kept as text, because one of them is not a finite number.
#[derive(Debug, Clone, PartialEq)]
struct TextColumn {
    /// Every cell, trimmed (numbers before the first other cell in shortest form).
    cells: Vec<String>,
    /// The 1-based line of the first cell that is not a finite number.
    bad_line: usize,
    /// That cell.
    bad_value: String,
    /// Whether some cell is not a number at all (rather than a non-finite one).
    words: bool,
}

impl TextColumn {
    /// A column whose cells were the numbers `values`, then `cell` (not a finite number) on
    /// line `line`.
    fn after(values: &[f64], line: usize, cell: &str) -> TextColumn {
        let mut cells: Vec<String> = values.iter().map(|&v| shortest(v)).collect();
        cells.push(cell.to_string());
        TextColumn {
            cells,
            bad_line: line,
            bad_value: cell.to_string(),
            words: cell.parse::<f64>().is_err(),
        }
    }

    /// Adds the next cell.
    fn push(&mut self, cell: &str) {
        if !self.words && cell.parse::<f64>().is_err() {
            self.words = true;
        }
        self.cells.push(cell.to_string());
    }
}

/// `v` in its shortest round-trip form.
fn shortest(v: f64) -> String {
    let mut s = String::new();
    push_f64(&mut s, v);
    s
}

/// Reads a whole CSV input into a table.
///
/// A column stays a column of numbers while its cells are finite numbers; at its first other
/// cell it becomes a [`TextColumn`] (its numbers so far in shortest form), so that only the
/// columns that need it hold text.
/// Only the columns `read` marks are kept (`read` shorter than the header reads the rest).
fn collect<R: std::io::Read>(rows: CsvReader<R>, read: Vec<bool>) -> Result<Table, IoError> {
    let source = rows.source().to_string();
    collect_columns(rows, read).map_err(|e| e.reading(&source))
}

/// [`collect`], its temporary files' errors not yet naming the file read.
fn collect_columns<R: std::io::Read>(
    mut rows: CsvReader<R>,
    mut read: Vec<bool>,
) -> Result<Table, IoError> {
    let n = rows.names().len();
    read.resize(n, true);
    let mut columns: Vec<SamplesWriter> = (0..n).map(|_| SamplesWriter::default()).collect();
    let mut text: Vec<Option<TextColumn>> = vec![None; n];
    let mut lines = Lines::default();
    while let Some(line) = rows.next_cells()? {
        for (i, (column, text)) in columns.iter_mut().zip(&mut text).enumerate() {
            if !read[i] {
                continue;
            }
            let cell = rows.cell_text(i, line)?;
            match text {
                Some(text) => text.push(cell),
                None => match number(cell, "", line, i, "") {
                    Ok(value) => column.push(value)?,
                    Err(_) => {
                        let numbers = std::mem::take(column).finish()?;
                        *text = Some(TextColumn::after(&numbers, line, cell));
                    }
                },
            }
        }
        lines.push(line);
    }
    // A held column's slack goes back (a large block shrinks in place); a long one is mapped.
    let columns = columns
        .into_iter()
        .map(SamplesWriter::finish)
        .collect::<Result<_, _>>()?;
    Ok(Table {
        names: rows.names().to_vec(),
        columns,
        text,
        read,
        lines,
        source: rows.source().to_string(),
    })
}

/// Parses a whole CSV input held in memory.
fn parse(bytes: &[u8], file: &str) -> Result<Table, IoError> {
    collect(CsvReader::new(bytes, file)?, Vec::new())
}

/// The source line of every row, held as runs of rows on consecutive lines: one run for a file
/// without comments, blank lines or cells across lines, whatever its length.
#[derive(Debug, Clone, PartialEq, Default)]
struct Lines {
    /// (first row, its line) of each run, in order.
    runs: Vec<(usize, usize)>,
    /// The number of rows.
    rows: usize,
}

impl Lines {
    /// `rows` rows on consecutive lines from `first`.
    fn from(first: usize, rows: usize) -> Lines {
        let runs = if rows > 0 {
            vec![(0, first)]
        } else {
            Vec::new()
        };
        Lines { runs, rows }
    }

    /// Adds the next row, read from `line`.
    fn push(&mut self, line: usize) {
        let follows = self
            .runs
            .last()
            .is_some_and(|&(row, start)| start + (self.rows - row) == line);
        if !follows {
            self.runs.push((self.rows, line));
        }
        self.rows += 1;
    }

    /// The line of row `row`.
    ///
    /// # Panics
    /// If `row` is not below the number of rows.
    fn line_of_row(&self, row: usize) -> usize {
        assert!(
            row < self.rows,
            "row {row} of a table of {} rows",
            self.rows
        );
        let run = self.runs.partition_point(|&(first, _)| first <= row) - 1;
        let (first, line) = self.runs[run];
        line + (row - first)
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::*;
    use hyst_test_support::rng::{Random, XorShift64Star};
    use std::fs;

    /// Parses `text` as a file called `data.csv`, and asks for every column as numbers (the
    /// error of the first cell, in file order, that is not a finite number).
    fn read_str(text: &str) -> Result<Table, IoError> {
        numbers(parse(text.as_bytes(), "data.csv")?)
    }

    /// `table` if every column is one of numbers, else the error of the first cell (in file
    /// order) that is not a finite number.
    fn numbers(table: Table) -> Result<Table, IoError> {
        let place = |e: &IoError| match e {
            IoError::Parse { line, column, .. } | IoError::NonFinite { line, column, .. } => {
                (*line, *column)
            }
            _ => (0, 0),
        };
        let first = table
            .names()
            .iter()
            .filter_map(|name| table.column(name).err())
            .min_by_key(place);
        match first {
            Some(e) => Err(e),
            None => Ok(table),
        }
    }

    /// The message of the error from parsing `text`.
    fn err_str(text: &str) -> String {
        match read_str(text) {
            Ok(t) => panic!("expected an error, got {t:?}"),
            Err(e) => e.to_string(),
        }
    }

    fn strings(names: &[&str]) -> Vec<String> {
        names.iter().map(|s| s.to_string()).collect()
    }

    fn files_in(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    // ---------------------------------------------------------------- reading

    #[test]
    fn reads_a_simple_table() {
        let t = read_str("x,y\n1,2\n3,4.5\n").unwrap();
        assert_eq!(t.names(), ["x", "y"]);
        assert_eq!(t.len(), 2);
        assert!(!t.is_empty());
        assert_eq!(t.column("x").unwrap(), [1.0, 3.0]);
        assert_eq!(t.column("y").unwrap(), [2.0, 4.5]);
        assert_eq!(t.columns, [vec![1.0, 3.0], vec![2.0, 4.5]]);
        assert_eq!(t.column_index("y"), Some(1));
        assert_eq!(t.column_index("Y"), None);
        assert_eq!((t.line_of_row(0), t.line_of_row(1)), (2, 3));
        assert_eq!(t.source(), "data.csv");
    }

    #[test]
    fn no_trailing_newline_is_fine() {
        let t = read_str("x\n1\n2").unwrap();
        assert_eq!(t.column("x").unwrap(), [1.0, 2.0]);
        assert_eq!(t.line_of_row(1), 3);
    }

    #[test]
    fn trims_spaces_and_tabs_around_cells_and_names() {
        let t = read_str("  x ,\ty\t\n  1 ,  -2.5e3\t\n+3,.5\n").unwrap();
        assert_eq!(t.names(), ["x", "y"]);
        assert_eq!(t.column("x").unwrap(), [1.0, 3.0]);
        assert_eq!(t.column("y").unwrap(), [-2500.0, 0.5]);
    }

    #[test]
    fn accepts_quoted_cells() {
        let t = read_str("\"x, in V\",\"y \"\"raw\"\"\"\n\"1\", 2\n").unwrap();
        assert_eq!(t.names(), ["x, in V", "y \"raw\""]);
        assert_eq!(t.columns, [vec![1.0], vec![2.0]]);
    }

    #[test]
    fn crlf_line_endings_with_exact_line_numbers() {
        let t = read_str("x,y\r\n1,2\r\n\r\n# note\r\n3,4\r\n").unwrap();
        assert_eq!(t.names(), ["x", "y"]);
        assert_eq!(t.columns, [vec![1.0, 3.0], vec![2.0, 4.0]]);
        assert_eq!((t.line_of_row(0), t.line_of_row(1)), (2, 5));
        assert_eq!(
            err_str("x,y\r\n1,2\r\n\r\n# note\r\n3,oops\r\n"),
            r#"data.csv:5: column 2 ("y"): cannot parse "oops" as a number"#
        );
    }

    #[test]
    fn utf8_bom_is_ignored() {
        let t = read_str("\u{feff}x,y\n1,2\n").unwrap();
        assert_eq!(t.names(), ["x", "y"]);
        assert_eq!(t.column_index("x"), Some(0));
        let t = read_str("\u{feff}# comment first\nx\n1\n").unwrap();
        assert_eq!(t.names(), ["x"]);
        assert_eq!(t.line_of_row(0), 3);
    }

    #[test]
    fn comments_and_blank_lines_are_skipped_but_counted() {
        let text = "# hysteresis test rig\n\n# units: V\nx,y\n\n1,2\n# pause\n   \n\t\n3,4\n\n";
        let t = read_str(text).unwrap();
        assert_eq!(t.names(), ["x", "y"]);
        assert_eq!(t.columns, [vec![1.0, 3.0], vec![2.0, 4.0]]);
        assert_eq!((t.line_of_row(0), t.line_of_row(1)), (6, 10));
        assert_eq!(
            err_str("# c\n\nx,y\n# c\n\n1,2\n\n# c\n5,1.2.3\n"),
            r#"data.csv:9: column 2 ("y"): cannot parse "1.2.3" as a number"#
        );
    }

    #[test]
    fn line_numbers_follow_multiline_quoted_cells() {
        let t = read_str("\"x\nlong\",y\n1,2\n3,4\n").unwrap();
        assert_eq!(t.names(), ["x\nlong", "y"]);
        assert_eq!((t.line_of_row(0), t.line_of_row(1)), (3, 4));
    }

    #[test]
    fn unparsable_cell_names_file_line_column_and_value() {
        let mut text = String::from("x,y\n");
        for i in 0..15 {
            text.push_str(&format!("{i},{i}\n"));
        }
        text.push_str("16, 1.2.3 \n");
        assert_eq!(
            err_str(&text),
            r#"data.csv:17: column 2 ("y"): cannot parse "1.2.3" as a number"#
        );
        assert_eq!(
            err_str("x,y\n,2\n"),
            r#"data.csv:2: column 1 ("x"): cannot parse "" as a number"#
        );
        assert_eq!(
            err_str("x,y\n1,2 3\n"),
            r#"data.csv:2: column 2 ("y"): cannot parse "2 3" as a number"#
        );
        // A ';'-separated file: the cell holds the whole row; said why.
        assert_eq!(
            err_str("t;x;y\n0;50;11.5\n"),
            r#"data.csv:2: column 1 ("t;x;y"): cannot parse "0;50;11.5" as a number (the file seems to use ';' as the separator; hyst reads comma-separated values with a '.' decimal point)"#
        );
        assert_eq!(
            err_str("x,y\n1,1,5\n"),
            r#"data.csv:2: expected 2 cells (one per column of the header on line 1), found 3: "1", "1", "5""#
        );
        let err = read_str("a,b\n1,x\n").unwrap_err();
        match err {
            IoError::Parse {
                file,
                line,
                column,
                name,
                value,
            } => {
                assert_eq!(
                    (file.as_str(), line, column, name.as_str(), value.as_str()),
                    ("data.csv", 2, 2, "b", "x")
                );
            }
            other => panic!("wrong variant: {other:?}"),
        }
    }

    #[test]
    fn non_finite_values_are_rejected() {
        for (cell, shown) in [
            ("nan", "nan"),
            ("NaN", "NaN"),
            (" inf ", "inf"),
            ("-inf", "-inf"),
            ("+infinity", "+infinity"),
            ("1e999", "1e999"),
            ("-1e400", "-1e400"),
        ] {
            assert_eq!(
                err_str(&format!("x,y\n1,2\n3,{cell}\n")),
                format!(r#"data.csv:3: column 2 ("y"): "{shown}" is not a finite number"#),
                "cell {cell:?}"
            );
        }
        assert!(matches!(
            read_str("x\nnan\n").unwrap_err(),
            IoError::NonFinite {
                line: 2,
                column: 1,
                ..
            }
        ));
    }

    /// A column of words is kept as text; used as numbers it gives the
    /// error reading it as numbers gave; its cells are there as text.
    #[test]
    fn a_text_column_is_kept_as_text() {
        let t = parse(
            b"record,x,y\n 3 ,1,2\nrun b,1.50,4\n# c\nrun \"a\",2,nan\n",
            "data.csv",
        )
        .unwrap();
        assert_eq!(t.len(), 3);
        assert_eq!(t.column("x").unwrap(), [1.0, 1.5, 2.0]);
        assert_eq!(
            t.column("record").unwrap_err().to_string(),
            r#"data.csv:3: column 1 ("record"): cannot parse "run b" as a number"#
        );
        assert!(matches!(
            t.column("record").unwrap_err(),
            IoError::Parse {
                line: 3,
                column: 1,
                ..
            }
        ));
        assert_eq!(
            t.pick_column(Some("record")).unwrap_err().to_string(),
            t.column("record").unwrap_err().to_string()
        );
        // Non-finite text keeps its error.
        assert_eq!(
            t.column("y").unwrap_err().to_string(),
            r#"data.csv:5: column 3 ("y"): "nan" is not a finite number"#
        );
        assert_eq!(t.labels("record").unwrap()[..], ["3", "run b", "run \"a\""]);
        assert_eq!(t.labels("x").unwrap()[..], ["1", "1.5", "2"]);
        assert_eq!(t.labels("y").unwrap()[..], ["2", "4", "nan"]);
        assert!(t.is_text("record"));
        assert!(!t.is_text("y") && !t.is_text("x") && !t.is_text("z"));
        assert!(matches!(
            t.labels("z").unwrap_err(),
            IoError::UnknownColumn { .. }
        ));
        // Only the text column holds text.
        assert_eq!(t.columns[1], [1.0, 1.5, 2.0]);
        assert!(t.text[1].is_none() && t.text[0].is_some());
        // Written and read back: the same cells.
        let again = parse(&t.to_csv(), "again.csv").unwrap();
        assert_eq!(again.labels("record").unwrap(), t.labels("record").unwrap());
        assert_eq!(again.column("x").unwrap(), t.column("x").unwrap());
        let odd = parse(b"a,b\n\"#1\",1\n\"\",\"p, q\"\n", "odd.csv").unwrap();
        let back = parse(&odd.to_csv(), "back.csv").unwrap();
        assert_eq!(back.labels("a").unwrap()[..], ["#1", ""]);
        assert_eq!(back.labels("b").unwrap()[..], ["1", "p, q"]);
        assert_eq!(back.len(), 2);
    }

    #[test]
    fn tiny_values_underflow_to_subnormal_or_zero_and_are_accepted() {
        let t = read_str("x\n5e-324\n1e-400\n-1e-400\n").unwrap();
        let x = t.column("x").unwrap();
        assert_eq!(x[0].to_bits(), 1);
        assert_eq!(x[1].to_bits(), 0);
        assert_eq!(x[2].to_bits(), (-0.0f64).to_bits());
    }

    #[test]
    fn header_of_numbers_is_no_header() {
        assert_eq!(
            err_str("1,2\n3,4\n"),
            r#"data.csv:1: no header row: the first row ("1", "2") contains only numbers; add a first line with the column names, e.g. "x,y""#
        );
        assert_eq!(
            err_str("# data\n\n 0.5 \n"),
            r#"data.csv:3: no header row: the first row ("0.5") contains only numbers; add a first line with the column names, e.g. "x,y""#
        );
        assert!(matches!(
            read_str("nan,1\n").unwrap_err(),
            IoError::NoHeader { line: 1, .. }
        ));
        // One name among numbers is a header (with odd names, but a header).
        let t = read_str("x,1\n1,2\n").unwrap();
        assert_eq!(t.names(), ["x", "1"]);
    }

    #[test]
    fn empty_input_is_an_error() {
        let expected =
            "data.csv: no header row: the input is empty (only blank lines and # comments)";
        assert_eq!(err_str(""), expected);
        assert_eq!(err_str("\n\r\n  \n"), expected);
        assert_eq!(err_str("# only\n# comments\n"), expected);
        assert_eq!(err_str("\u{feff}"), expected);
    }

    #[test]
    fn empty_header_name_is_an_error() {
        assert_eq!(
            err_str("x,,y\n1,2,3\n"),
            "data.csv:1: column 2: empty column name in the header"
        );
        assert_eq!(
            err_str("# c\nx,y,\n1,2,3\n"),
            "data.csv:2: column 3: empty column name in the header"
        );
    }

    #[test]
    fn duplicate_header_name_is_an_error() {
        assert_eq!(
            err_str("x,y, x\n1,2,3\n"),
            r#"data.csv:1: column 3 ("x"): duplicate column name (column 1 has the same name)"#
        );
    }

    #[test]
    fn wrong_number_of_cells_is_an_error() {
        assert_eq!(
            err_str("x,y,z\n1,2,3\n\n4,5\n"),
            r#"data.csv:4: expected 3 cells (one per column of the header on line 1), found 2: "4", "5""#
        );
        assert_eq!(
            err_str("# c\nx\n1\n2,\n"),
            r#"data.csv:4: expected 1 cells (one per column of the header on line 2), found 2: "2", """#
        );
        assert!(matches!(
            read_str("a,b\n1,2,3\n").unwrap_err(),
            IoError::CellCount {
                line: 2,
                expected: 2,
                found: 3,
                header_line: 1,
                ..
            }
        ));
    }

    #[test]
    fn header_without_data_is_an_error() {
        assert_eq!(
            err_str("x,y\n"),
            "data.csv: no data rows: the header is on line 1 and nothing follows it"
        );
        assert_eq!(
            err_str("# c\nx,y\n\n# nothing\n"),
            "data.csv: no data rows: the header is on line 2 and nothing follows it"
        );
    }

    #[test]
    fn invalid_utf8_is_an_error() {
        let err = parse(b"x,y\n1,\xff2\n", "data.csv").unwrap_err();
        assert_eq!(
            err.to_string(),
            "data.csv:2: column 2 (\"y\"): invalid UTF-8 in \"\u{fffd}2\""
        );
        let err = parse(b"x,\xffy\n1,2\n", "data.csv").unwrap_err();
        assert_eq!(
            err.to_string(),
            "data.csv:1: column 2 (\"\"): invalid UTF-8 in \"\u{fffd}y\""
        );
    }

    #[test]
    fn read_uses_the_path_in_messages() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("meas.csv");
        fs::write(&path, "x,y\r\n1,2\r\n3,abc\r\n").unwrap();
        let err = Table::read(&path).and_then(numbers).unwrap_err();
        assert_eq!(
            err.to_string(),
            format!(
                r#"{}:3: column 2 ("y"): cannot parse "abc" as a number"#,
                path.display()
            )
        );
        fs::write(&path, "x,y\n1,2\n").unwrap();
        let t = Table::read(&path).unwrap();
        assert_eq!(t.source(), path.display().to_string());
        assert_eq!(
            t.column("z").unwrap_err().to_string(),
            format!(
                r#"{}: no column named "z"; the available columns are "x", "y""#,
                path.display()
            )
        );
    }

    #[test]
    fn unreadable_file_names_path_and_os_error() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("missing.csv");
        let err = Table::read(&path).unwrap_err();
        assert!(matches!(err, IoError::Read { .. }), "{err:?}");
        assert_eq!(
            err.to_string(),
            format!(
                "{}: cannot read: {}",
                path.display(),
                io::Error::from_raw_os_error(2)
            )
        );
        assert!(err.to_string().contains("No such file or directory"));

        let err = Table::read(dir.path()).unwrap_err();
        assert_eq!(
            err.to_string(),
            format!("{}: is a directory, not a file", dir.path().display())
        );
    }

    // ---------------------------------------------------------------- columns

    #[test]
    fn unknown_column_lists_the_available_ones() {
        let t = read_str("t,x,y\n0,1,2\n").unwrap();
        let err = t.column("u").unwrap_err();
        assert_eq!(
            err.to_string(),
            r#"data.csv: no column named "u"; the available columns are "t", "x", "y""#
        );
        match err {
            IoError::UnknownColumn {
                name, available, ..
            } => {
                assert_eq!(name, "u");
                assert_eq!(available, ["t", "x", "y"]);
            }
            other => panic!("wrong variant: {other:?}"),
        }
    }

    #[test]
    fn pick_column_prefers_the_given_name() {
        let t = read_str("t,x,y\n0,1,2\n").unwrap();
        assert_eq!(t.pick_column(Some("y")).unwrap(), (2, &[2.0][..]));
        assert_eq!(t.pick_column(Some("x")).unwrap(), (1, &[1.0][..]));
        assert_eq!(
            t.pick_column(Some("X")).unwrap_err().to_string(),
            r#"data.csv: no column named "X"; the available columns are "t", "x", "y""#
        );
    }

    #[test]
    fn pick_column_falls_back_to_x() {
        let t = read_str("t,x,y\n0,1,2\n").unwrap();
        assert_eq!(t.pick_column(None).unwrap(), (1, &[1.0][..]));
    }

    #[test]
    fn pick_column_falls_back_to_the_only_column() {
        let t = read_str("u\n7\n8\n").unwrap();
        assert_eq!(t.pick_column(None).unwrap(), (0, &[7.0, 8.0][..]));
        // A single column still honours an explicit, wrong name.
        assert!(matches!(
            t.pick_column(Some("x")).unwrap_err(),
            IoError::UnknownColumn { .. }
        ));
    }

    #[test]
    fn pick_column_is_ambiguous_without_x() {
        let t = read_str("t,u,y\n0,1,2\n").unwrap();
        let err = t.pick_column(None).unwrap_err();
        assert_eq!(
            err.to_string(),
            r#"data.csv: cannot tell which column is the input: there is no column named "x" and there are 3 columns ("t", "u", "y"); pass --column NAME"#
        );
        assert!(matches!(err, IoError::AmbiguousColumn { .. }));
    }

    // ---------------------------------------------------------------- new

    #[test]
    fn new_builds_a_table() {
        let t = Table::new(strings(&["x", "y"]), vec![vec![1.0, 2.0], vec![3.0, 4.0]]).unwrap();
        assert_eq!(t.source(), "<memory>");
        assert_eq!(t.len(), 2);
        assert_eq!((t.line_of_row(0), t.line_of_row(1)), (2, 3));
        assert_eq!(
            t.column("z").unwrap_err().to_string(),
            r#"<memory>: no column named "z"; the available columns are "x", "y""#
        );
        let empty = Table::new(strings(&["x"]), vec![vec![]]).unwrap();
        assert!(empty.is_empty());
        assert_eq!(empty.len(), 0);
    }

    #[test]
    fn new_rejects_bad_shapes() {
        let err = Table::new(strings(&["x", "y"]), vec![vec![1.0]]).unwrap_err();
        assert_eq!(err.to_string(), "<memory>: 2 column names but 1 columns");
        let err = Table::new(vec![], vec![]).unwrap_err();
        assert_eq!(
            err.to_string(),
            "<memory>: a table needs at least one column"
        );
        let err = Table::new(strings(&["x", "y"]), vec![vec![1.0, 2.0], vec![3.0]]).unwrap_err();
        assert_eq!(
            err.to_string(),
            r#"<memory>: column 2 ("y") has 1 values, but column 1 ("x") has 2"#
        );
    }

    #[test]
    fn new_rejects_bad_names() {
        let cases: [(&[&str], &str); 6] = [
            (
                &["x", ""],
                r#"<memory>: column 2 (""): invalid column name: the name is empty"#,
            ),
            (
                &[" "],
                r#"<memory>: column 1 (" "): invalid column name: the name is empty"#,
            ),
            (
                &["x", "y", "x"],
                r#"<memory>: column 3 ("x"): invalid column name: column 1 has the same name"#,
            ),
            (
                &["x "],
                r#"<memory>: column 1 ("x "): invalid column name: leading or trailing whitespace would be lost when the file is read back"#,
            ),
            (
                &["a\nb"],
                r#"<memory>: column 1 ("a\nb"): invalid column name: names cannot contain line breaks"#,
            ),
            (
                &["1", "2.5"],
                r#"<memory>: column 1 ("1"): invalid column name: all column names are numbers, so the header could not be told apart from data"#,
            ),
        ];
        for (names, expected) in cases {
            let columns = vec![vec![0.0]; names.len()];
            let err = Table::new(strings(names), columns).unwrap_err();
            assert_eq!(err.to_string(), expected);
        }
    }

    #[test]
    fn new_rejects_non_finite_values() {
        let err = Table::new(
            strings(&["x", "y"]),
            vec![vec![1.0, 2.0], vec![3.0, f64::NAN]],
        )
        .unwrap_err();
        assert_eq!(
            err.to_string(),
            r#"<memory>: column 2 ("y"), row 2: NaN is not a finite number"#
        );
        let err = Table::new(strings(&["x"]), vec![vec![f64::NEG_INFINITY]]).unwrap_err();
        assert_eq!(
            err.to_string(),
            r#"<memory>: column 1 ("x"), row 1: -inf is not a finite number"#
        );
    }

    // ---------------------------------------------------------------- writing

    /// Awkward values that must survive a round trip bit for bit.
    fn awkward() -> Vec<f64> {
        vec![
            0.0,
            -0.0,
            5e-324,
            -5e-324,
            2.2250738585072014e-308,
            2.225073858507201e-308,
            f64::MIN_POSITIVE,
            f64::MAX,
            f64::MIN,
            1.7976931348623157e308,
            1e300,
            -1e-300,
            0.1 + 0.2,
            0.1,
            1.0 / 3.0,
            9007199254740993.0,
            1e15,
            1e16,
            123456789012345680.0,
            1e-5,
            9.999999999999999e-6,
            std::f64::consts::PI,
            -1.0,
            42.0,
        ]
    }

    #[test]
    fn formats_values_in_shortest_round_trip_form() {
        let shown: Vec<String> = [
            -0.0,
            0.0,
            1e300,
            5e-324,
            1.7976931348623157e308,
            0.1 + 0.2,
            1.5,
            1e16,
            1e-5,
            1e-6,
        ]
        .iter()
        .map(|&v| {
            let mut s = String::new();
            push_f64(&mut s, v);
            s
        })
        .collect();
        assert_eq!(
            shown,
            [
                "-0",
                "0",
                "1e300",
                "5e-324",
                "1.7976931348623157e308",
                "0.30000000000000004",
                "1.5",
                "1e16",
                "0.00001",
                "1e-6"
            ]
        );
    }

    #[test]
    fn formatting_round_trips_random_bit_patterns() {
        let mut rng = XorShift64Star(0x9E37_79B9_7F4A_7C15);
        let mut checked = 0;
        let mut s = String::new();
        while checked < 200_000 {
            let v = f64::from_bits(rng.next_u64());
            if !v.is_finite() {
                continue;
            }
            s.clear();
            push_f64(&mut s, v);
            let back: f64 = s.parse().unwrap();
            assert_eq!(back.to_bits(), v.to_bits(), "{v:e} written as {s}");
            checked += 1;
        }
    }

    #[test]
    fn write_and_read_back_bit_exactly() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("awkward.csv");
        let values = awkward();
        let negated: Vec<f64> = values.iter().map(|v| -v).collect();
        let t = Table::new(
            strings(&["x", "minus x"]),
            vec![values.clone(), negated.clone()],
        )
        .unwrap();
        t.write_atomic(&path).unwrap();
        let text = fs::read_to_string(&path).unwrap();
        assert!(
            text.starts_with("x,minus x\n0,-0\n-0,0\n5e-324,-5e-324\n"),
            "{text}"
        );
        assert!(
            text.contains("\n0.30000000000000004,-0.30000000000000004\n"),
            "{text}"
        );
        assert!(
            text.contains("\n1.7976931348623157e308,-1.7976931348623157e308\n"),
            "{text}"
        );
        assert!(text.contains("\n1e300,-1e300\n"), "{text}");

        let back = Table::read(&path).unwrap();
        assert_eq!(back.names(), t.names());
        assert_eq!(back.len(), values.len());
        for (col, expected) in [(0, &values), (1, &negated)] {
            let got = &back.columns[col];
            let got_bits: Vec<u64> = got.iter().map(|v| v.to_bits()).collect();
            let want_bits: Vec<u64> = expected.iter().map(|v| v.to_bits()).collect();
            assert_eq!(got_bits, want_bits);
        }
        for row in 0..t.len() {
            assert_eq!(back.line_of_row(row), t.line_of_row(row));
        }
        assert_eq!(files_in(dir.path()), ["awkward.csv"]);
    }

    #[test]
    fn awkward_names_round_trip() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("names.csv");
        let names = strings(&["#x", "a,b", "say \"hi\"", "µ0 (H/m)", "1"]);
        let t = Table::new(names.clone(), vec![vec![1.0]; 5]).unwrap();
        t.write_atomic(&path).unwrap();
        assert_eq!(
            fs::read_to_string(&path).unwrap(),
            "\"#x\",\"a,b\",\"say \"\"hi\"\"\",µ0 (H/m),1\n1,1,1,1,1\n"
        );
        let back = Table::read(&path).unwrap();
        assert_eq!(back.names(), names);
        assert_eq!(back.line_of_row(0), 2);
    }

    #[test]
    fn empty_table_writes_only_the_header() {
        let mut out = Vec::new();
        Table::new(strings(&["x", "y"]), vec![vec![], vec![]])
            .unwrap()
            .write_csv(&mut out)
            .unwrap();
        assert_eq!(out, b"x,y\n");
    }

    #[test]
    fn failed_table_write_leaves_old_file_and_no_temp() {
        let dir = tempfile::tempdir().unwrap();
        let t = Table::new(strings(&["x"]), vec![vec![1.0, 2.0]]).unwrap();

        // Into a directory that does not exist.
        let missing = dir.path().join("nope").join("out.csv");
        let err = t.write_atomic(&missing).unwrap_err();
        assert!(matches!(err, IoError::Write { .. }), "{err:?}");
        assert!(err.to_string().starts_with(&format!(
            "{}: cannot create a file in its directory: ",
            missing.display()
        )));
        assert_eq!(files_in(dir.path()), Vec::<String>::new());

        // Onto a path that is a directory.
        let sub = dir.path().join("out.csv");
        fs::create_dir(&sub).unwrap();
        let err = t.write_atomic(&sub).unwrap_err();
        assert!(matches!(err, IoError::IsDirectory { .. }), "{err:?}");
        assert_eq!(files_in(dir.path()), ["out.csv"]);
        assert!(sub.is_dir());
        assert_eq!(files_in(&sub), Vec::<String>::new());

        // Replacing an existing file works and leaves nothing else behind.
        let path = dir.path().join("real.csv");
        fs::write(&path, "old\n").unwrap();
        t.write_atomic(&path).unwrap();
        assert_eq!(fs::read_to_string(&path).unwrap(), "x\n1\n2\n");
        assert_eq!(files_in(dir.path()), ["out.csv", "real.csv"]);
    }

    /// A column longer than `SPILL_AFTER` values is read into a temporary file, and reads
    /// back every value; a shorter one is held.
    #[test]
    fn a_long_column_is_spilled_and_a_short_one_held() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("long.csv");
        let n = crate::SPILL_AFTER + 3;
        let mut text = String::from("x,y\n");
        for i in 0..n {
            text += &format!("{i},{}\n", i % 7);
        }
        fs::write(&path, text).unwrap();
        let mut t = Table::read(&path).unwrap();
        assert!(t.columns.iter().all(Samples::is_spilled));
        let y = t.take_column("y").unwrap();
        assert_eq!(y.len(), n);
        assert!(y.iter().enumerate().all(|(i, &v)| v == (i % 7) as f64));
        assert_eq!(t.column("x").unwrap()[n - 1], (n - 1) as f64);
        let short = Table::parse(b"x\n1\n", "s").unwrap();
        assert!(!short.columns[0].is_spilled());
    }

    /// A reader given a selection keeps only those columns: the others cost nothing, are
    /// refused by name, and still appear in the names (and in an unknown name's error); rows
    /// and lines are those of the whole file.
    #[test]
    fn a_selection_reads_only_its_columns() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("d.csv");
        fs::write(&path, "t,u,note,y\n0,1,a,2\n# gap\n\n1,3,b,4\n2,5,c,6\n").unwrap();
        let select = |names: &[String]| names.iter().map(|n| n == "u" || n == "y").collect();
        let (t, digest) = Table::read_digest_selected(&path, Box::new(|_| {}), &select).unwrap();
        assert_eq!(digest, Table::read_digest(&path).unwrap().1);
        assert_eq!(t.names(), ["t", "u", "note", "y"]);
        assert_eq!(t.column("u").unwrap(), [1.0, 3.0, 5.0]);
        assert_eq!(t.column("y").unwrap(), [2.0, 4.0, 6.0]);
        assert_eq!(t.len(), 3);
        assert_eq!(
            (t.line_of_row(0), t.line_of_row(1), t.line_of_row(2)),
            (2, 5, 6)
        );
        assert!(t.columns[0].is_empty());
        let err = t.column("t").unwrap_err();
        assert!(matches!(err, IoError::NotRead { column: 1, .. }), "{err:?}");
        assert!(t.labels("note").is_err() && !t.is_text("note"));
        let err = t.column("v").unwrap_err().to_string();
        assert!(err.contains("\"note\""), "{err}");
        assert_eq!(t.to_csv(), b"u,y\n1,2\n3,4\n5,6\n");
        let mut t = t;
        assert_eq!(t.take_column("u").unwrap(), [1.0, 3.0, 5.0]);
        assert!(matches!(
            t.column("u"),
            Err(IoError::NotRead { column: 2, .. })
        ));
        assert!(matches!(t.take_column("t"), Err(IoError::NotRead { .. })));
        assert!(matches!(
            t.take_column("v"),
            Err(IoError::UnknownColumn { .. })
        ));
        assert_eq!(t.column("y").unwrap(), [2.0, 4.0, 6.0]);
    }

    /// Line numbers are runs: a row after a gap starts a new one, and every row maps back.
    #[test]
    fn lines_are_kept_as_runs() {
        let mut lines = Lines::default();
        let read = [2, 3, 4, 7, 8, 10, 11, 12, 13];
        for line in read {
            lines.push(line);
        }
        assert_eq!(lines.runs, [(0, 2), (3, 7), (5, 10)]);
        let back: Vec<usize> = (0..read.len()).map(|r| lines.line_of_row(r)).collect();
        assert_eq!(back, read);
        assert_eq!(Lines::from(2, 3).line_of_row(2), 4);
    }
}
