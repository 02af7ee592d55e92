//! Writing a numeric CSV file row by row, in constant memory and atomically: [`CsvWriter`].
//! [`Table::write_atomic`](crate::Table::write_atomic) writes through the same functions, so a
//! table written whole and one written row by row are the same bytes.

use std::collections::HashMap;
use std::io::{self, Write};
use std::path::Path;

use crate::atomic::Output;
use crate::error::IoError;
use crate::reader::looks_numeric;

/// A CSV output written one row at a time, with the guarantees of
/// [`write_atomic`](crate::write_atomic): the rows go to a temporary file that
/// [`CsvWriter::finish`] renames over the destination, so a writer dropped unfinished (an error
/// on the way, a panic) leaves the destination as it was and no temporary file. Standard output
/// (`-`) and devices are written straight through (what was written there stays written).
///
/// The format is [`Table::write_atomic`](crate::Table::write_atomic)'s: a header row, then every
/// value in the shortest form that parses back to the identical `f64`.
///
/// # Examples
/// ```
/// # fn main() -> Result<(), hyst_io::IoError> {
/// use hyst_io::CsvWriter;
///
/// let dir = tempfile::tempdir().expect("a temporary directory");
/// let path = dir.path().join("out.csv");
/// let mut out = CsvWriter::create(&path, vec!["x".into(), "y".into()])?;
/// out.write_row(&[0.1, -0.0])?;
/// out.write_row(&[1e300, 2.5])?;
/// out.finish()?;
/// assert_eq!(std::fs::read_to_string(&path).expect("written"), "x,y\n0.1,-0\n1e300,2.5\n");
/// # Ok(())
/// # }
/// ```
pub struct CsvWriter {
    /// The output.
    out: Output,
    /// The column names (for messages).
    names: Vec<String>,
    /// The header row until it is written, with the first row or by `finish` (so that standard
    /// output gets nothing from a command that fails before its first row).
    header: Option<Vec<u8>>,
    /// The line being formatted.
    line: String,
    /// Rows written so far.
    rows: usize,
    /// The output's name in messages.
    file: String,
}

impl CsvWriter {
    /// Opens the output for `path` (see [`write_atomic`](crate::write_atomic)); the header row
    /// goes out with the first row (or on [`CsvWriter::finish`]).
    ///
    /// # Errors
    /// [`IoError::NoColumns`] or [`IoError::InvalidName`] for names that could not be read back
    /// (as [`Table::new`](crate::Table::new)), [`IoError::IsDirectory`] or [`IoError::Write`].
    pub fn create(path: &Path, names: Vec<String>) -> Result<Self, IoError> {
        let file = path.display().to_string();
        check_names(&names, &file)?;
        let out = Output::create(path)?;
        let mut header = Vec::new();
        write_header(&mut header, &names).map_err(|e| out.error(e))?;
        Ok(CsvWriter {
            out,
            names,
            header: Some(header),
            line: String::new(),
            rows: 0,
            file,
        })
    }

    /// Writes one row: one finite value per column.
    ///
    /// # Errors
    /// [`IoError::ShapeMismatch`] for a row of the wrong length, [`IoError::NonFiniteValue`]
    /// for NaN or an infinity (nothing of the row is written), [`IoError::Write`].
    pub fn write_row(&mut self, values: &[f64]) -> Result<(), IoError> {
        self.write_row_after("", 0, values)
    }

    /// Writes one row whose first `cells` cells are `prefix`, already formatted as CSV and each
    /// followed by `,` (cells a command passes through unchanged:
    /// [`CsvReader::push_cells`](crate::CsvReader::push_cells)), then `values`, one finite value
    /// per remaining column.
    ///
    /// # Errors
    /// As [`CsvWriter::write_row`], for `cells + values.len()` columns.
    pub fn write_row_after(
        &mut self,
        prefix: &str,
        cells: usize,
        values: &[f64],
    ) -> Result<(), IoError> {
        if cells + values.len() != self.names.len() {
            return Err(IoError::ShapeMismatch {
                file: self.file.clone(),
                names: self.names.len(),
                columns: cells + values.len(),
            });
        }
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(IoError::NonFiniteValue {
                file: self.file.clone(),
                column: cells + i + 1,
                name: self.names.get(cells + i).cloned().unwrap_or_default(),
                row: self.rows + 1,
                value: values.get(i).copied().unwrap_or(f64::NAN),
            });
        }
        self.write_header()?;
        self.line.clear();
        self.line.push_str(prefix);
        if values.is_empty() {
            // The prefix's last separator ends the line instead.
            if self.line.ends_with(',') {
                self.line.pop();
            }
            self.line.push('\n');
        } else {
            push_row(&mut self.line, values.iter().copied());
        }
        self.out.write_bytes(self.line.as_bytes())?;
        self.rows += 1;
        Ok(())
    }

    /// Completes the output: flushes it and, for a regular file, renames the temporary file
    /// over the destination.
    ///
    /// # Errors
    /// [`IoError::Write`] naming the step that failed; the destination is then untouched.
    pub fn finish(mut self) -> Result<(), IoError> {
        self.write_header()?;
        self.out.finish()
    }

    /// Writes the header row if it is not written yet.
    fn write_header(&mut self) -> Result<(), IoError> {
        match self.header.take() {
            Some(header) => self.out.write_bytes(&header),
            None => Ok(()),
        }
    }
}

/// Checks that `names` can head a CSV file that reads back to the same names (`file` names the
/// output in errors).
pub(crate) fn check_names(names: &[String], file: &str) -> Result<(), IoError> {
    if names.is_empty() {
        return Err(IoError::NoColumns {
            file: file.to_string(),
        });
    }
    let invalid = |i: usize, name: &str, reason: String| IoError::InvalidName {
        file: file.to_string(),
        column: i + 1,
        name: name.to_string(),
        reason,
    };
    let mut seen: HashMap<&str, usize> = HashMap::new();
    for (i, name) in names.iter().enumerate() {
        if name.trim().is_empty() {
            return Err(invalid(i, name, "the name is empty".into()));
        }
        if name.trim() != name {
            return Err(invalid(
                i,
                name,
                "leading or trailing whitespace would be lost when the file is read back".into(),
            ));
        }
        if name.contains(['\n', '\r']) {
            return Err(invalid(i, name, "names cannot contain line breaks".into()));
        }
        if let Some(first) = seen.insert(name, i + 1) {
            return Err(invalid(
                i,
                name,
                format!("column {first} has the same name"),
            ));
        }
    }
    if names.iter().all(|n| looks_numeric(n)) {
        return Err(invalid(
            0,
            names.first().map_or("", String::as_str),
            "all column names are numbers, so the header could not be told apart from data".into(),
        ));
    }
    Ok(())
}

/// Writes the header row: names containing `,`, `"` or a line break, or a first name starting
/// with `#`, are quoted.
pub(crate) fn write_header(w: &mut dyn Write, names: &[String]) -> io::Result<()> {
    for (i, name) in names.iter().enumerate() {
        if i > 0 {
            w.write_all(b",")?;
        }
        let needs_quotes =
            name.contains([',', '"', '\n', '\r']) || (i == 0 && name.starts_with('#'));
        if needs_quotes {
            write!(w, "\"{}\"", name.replace('"', "\"\""))?;
        } else {
            w.write_all(name.as_bytes())?;
        }
    }
    w.write_all(b"\n")
}

/// Appends one data row, values separated by `,` and ended by `\n`.
pub(crate) fn push_row(line: &mut String, values: impl Iterator<Item = f64>) {
    for (i, v) in values.enumerate() {
        if i > 0 {
            line.push(',');
        }
        push_f64(line, v);
    }
    line.push('\n');
}

/// Appends `v` in its shortest round-trip form.
pub(crate) fn push_f64(out: &mut String, v: f64) {
    use std::fmt::Write as _;
    let a = v.abs();
    // Both `{}` and `{:e}` print the shortest digits that parse back to `v`;
    // `{}` never uses an exponent, which gets unwieldy for 1e300 or 5e-324.
    // Writing into a String cannot fail.
    let _ = if a == 0.0 || (1e-5..1e16).contains(&a) {
        write!(out, "{v}")
    } else {
        write!(out, "{v:e}")
    };
}
