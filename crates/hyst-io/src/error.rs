//! The error type of this crate.

use std::fmt;
use std::path::PathBuf;

/// Everything that can go wrong while reading or writing tables and files.
///
/// Every message starts with the file it is about (`data.csv: ...`), followed by
/// the 1-based line number where there is one (`data.csv:17: ...`), the column as
/// both 1-based index and header name where there is one (`column 2 ("y")`), and
/// the offending value, for example
/// `data.csv:17: column 2 ("y"): cannot parse "1.2.3" as a number`.
///
/// Tables built in memory with [`Table::new`](crate::Table::new) use the source
/// name `<memory>`.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum IoError {
    /// A line longer than the reader's bound (`MAX_LINE_BYTES`): not a line of numbers; reading
    /// stopped there, in constant memory.
    #[error(
        "{file}:{line}: the line is longer than {limit} bytes: not a CSV line of numbers (is \
         this the right file?)"
    )]
    LineTooLong {
        /// File name as given.
        file: String,
        /// 1-based line where the long line starts.
        line: usize,
        /// The bound in bytes.
        limit: usize,
    },

    /// The file could not be opened or read (the OS error is attached).
    #[error("{file}: cannot read: {source}")]
    Read {
        /// The file (path or source name).
        file: String,
        /// The underlying OS error.
        #[source]
        source: std::io::Error,
    },

    /// The path to read from or write to is a directory.
    #[error("{}: is a directory, not a file", path.display())]
    IsDirectory {
        /// The offending path.
        path: PathBuf,
    },

    /// The input has no lines other than blank lines and `#` comments.
    #[error("{file}: no header row: the input is empty (only blank lines and # comments)")]
    Empty {
        /// The file (path or source name).
        file: String,
    },

    /// The first row contains only numbers, so it is data rather than column names.
    #[error(
        "{file}:{line}: no header row: the first row ({}) contains only numbers; \
         add a first line with the column names, e.g. \"x,y\"",
        quoted_list(cells)
    )]
    NoHeader {
        /// The file (path or source name).
        file: String,
        /// The 1-based line of the would-be header.
        line: usize,
        /// The cells of that row, trimmed.
        cells: Vec<String>,
    },

    /// A header cell is empty (or only whitespace).
    #[error("{file}:{line}: column {column}: empty column name in the header")]
    EmptyName {
        /// The file (path or source name).
        file: String,
        /// The 1-based line of the header.
        line: usize,
        /// The 1-based column index.
        column: usize,
    },

    /// Two header cells have the same name.
    #[error(
        "{file}:{line}: column {column} ({}): duplicate column name \
         (column {first} has the same name)",
        cut(name)
    )]
    DuplicateName {
        /// The file (path or source name).
        file: String,
        /// The 1-based line of the header.
        line: usize,
        /// The 1-based index of the second occurrence.
        column: usize,
        /// The duplicated name.
        name: String,
        /// The 1-based index of the first occurrence.
        first: usize,
    },

    /// A data row has a different number of cells than the header.
    #[error(
        "{file}:{line}: expected {expected} cells (one per column of the header on line \
         {header_line}), found {found}: {}",
        quoted_list(cells)
    )]
    CellCount {
        /// The file (path or source name).
        file: String,
        /// The 1-based line of the row.
        line: usize,
        /// The number of columns in the header.
        expected: usize,
        /// The number of cells in the row.
        found: usize,
        /// The 1-based line of the header.
        header_line: usize,
        /// The cells of the row, trimmed.
        cells: Vec<String>,
    },

    /// A cell is not valid UTF-8.
    #[error(
        "{file}:{line}: column {column} ({}): invalid UTF-8 in {}",
        cut(name),
        cut(value)
    )]
    InvalidUtf8 {
        /// The file (path or source name).
        file: String,
        /// The 1-based line of the row.
        line: usize,
        /// The 1-based column index.
        column: usize,
        /// The column name (`""` if the header itself is affected).
        name: String,
        /// The cell, with invalid bytes replaced by U+FFFD.
        value: String,
    },

    /// A data cell does not parse as a number. A cell with a ';' adds that the file seems to
    /// use ';' as its separator, where hyst reads comma-separated values.
    #[error(
        "{file}:{line}: column {column} ({}): cannot parse {} as a number{}",
        cut(name),
        cut(value),
        semicolon_hint(value)
    )]
    Parse {
        /// The file (path or source name).
        file: String,
        /// The 1-based line of the row.
        line: usize,
        /// The 1-based column index.
        column: usize,
        /// The column name.
        name: String,
        /// The cell, trimmed.
        value: String,
    },

    /// A data cell parses as a number, but not a finite one (`nan`, `inf`, `1e999`).
    #[error(
        "{file}:{line}: column {column} ({}): {} is not a finite number",
        cut(name),
        cut(value)
    )]
    NonFinite {
        /// The file (path or source name).
        file: String,
        /// The 1-based line of the row.
        line: usize,
        /// The 1-based column index.
        column: usize,
        /// The column name.
        name: String,
        /// The cell, trimmed.
        value: String,
    },

    /// The CSV parser reported an error.
    #[error("{file}:{line}: malformed CSV: {message}")]
    Csv {
        /// The file (path or source name).
        file: String,
        /// The 1-based line where the problem was found.
        line: usize,
        /// The parser's description.
        message: String,
    },

    /// The file has a header but no data rows.
    #[error("{file}: no data rows: the header is on line {header_line} and nothing follows it")]
    NoData {
        /// The file (path or source name).
        file: String,
        /// The 1-based line of the header.
        header_line: usize,
    },

    /// A column was asked for by a name the table does not have.
    #[error(
        "{file}: no column named {}; the available columns are {}",
        cut(name),
        quoted_list(available)
    )]
    UnknownColumn {
        /// The file (path or source name).
        file: String,
        /// The name asked for.
        name: String,
        /// The column names of the table.
        available: Vec<String>,
    },

    /// A long column could not be kept in its temporary file ([`Samples`](crate::Samples)):
    /// the directory is full or cannot be written.
    #[error(
        "{file}: cannot keep a long column in a temporary file in {dir}: {source} (set TMPDIR \
         to a directory on a disk with free space)"
    )]
    Spill {
        /// The file being read ([`IoError::reading`]; `<memory>` for values not read from a
        /// file).
        file: String,
        /// The temporary directory ([`std::env::temp_dir`]).
        dir: String,
        /// The underlying OS error.
        #[source]
        source: std::io::Error,
    },

    /// A column the reader was told to leave out (a selection) was asked for: a mistake of the
    /// program, not of the file.
    #[error(
        "{file}: column {column} ({name:?}) was not read: the reader was told to keep only the \
         columns it needed"
    )]
    NotRead {
        /// The file (path or source name).
        file: String,
        /// 1-based column index.
        column: usize,
        /// The column's name.
        name: String,
    },

    /// No input column was named, and none can be chosen automatically.
    #[error(
        "{file}: cannot tell which column is the input: there is no column named \"x\" \
         and there are {} columns ({}); pass --column NAME",
        available.len(),
        quoted_list(available)
    )]
    AmbiguousColumn {
        /// The file (path or source name).
        file: String,
        /// The column names of the table.
        available: Vec<String>,
    },

    /// [`Table::new`](crate::Table::new) got a different number of names and columns.
    #[error("{file}: {names} column names but {columns} columns")]
    ShapeMismatch {
        /// The table's source name.
        file: String,
        /// The number of names.
        names: usize,
        /// The number of columns.
        columns: usize,
    },

    /// [`Table::new`](crate::Table::new) got no columns at all.
    #[error("{file}: a table needs at least one column")]
    NoColumns {
        /// The table's source name.
        file: String,
    },

    /// [`Table::new`](crate::Table::new) got a column name that could not be
    /// written and read back (empty, duplicate, surrounding whitespace, line break,
    /// or all names numeric).
    #[error(
        "{file}: column {column} ({}): invalid column name: {reason}",
        cut(name)
    )]
    InvalidName {
        /// The table's source name.
        file: String,
        /// The 1-based column index.
        column: usize,
        /// The offending name.
        name: String,
        /// Why it is rejected.
        reason: String,
    },

    /// [`Table::new`](crate::Table::new) got columns of different lengths.
    #[error(
        "{file}: column {column} ({}) has {found} values, but column 1 ({}) has {expected}",
        cut(name),
        cut(first)
    )]
    ColumnLength {
        /// The table's source name.
        file: String,
        /// The 1-based column index.
        column: usize,
        /// The column name.
        name: String,
        /// The number of values in this column.
        found: usize,
        /// The name of the first column.
        first: String,
        /// The number of values in the first column.
        expected: usize,
    },

    /// [`Table::new`](crate::Table::new) got a NaN or infinite value.
    #[error(
        "{file}: column {column} ({}), row {row}: {value} is not a finite number",
        cut(name)
    )]
    NonFiniteValue {
        /// The table's source name.
        file: String,
        /// The 1-based column index.
        column: usize,
        /// The column name.
        name: String,
        /// The 1-based row index (not counting the header).
        row: usize,
        /// The offending value.
        value: f64,
    },

    /// The output path names the same file as an input (directly, through a
    /// symbolic link or as a hard link: same device and inode), so writing it
    /// would destroy the input. Nothing was written.
    #[error(
        "{}: is the same file as the input {} (the input would be overwritten); \
         choose another output",
        output.display(),
        input.display()
    )]
    SameFile {
        /// The input path as given.
        input: PathBuf,
        /// The output path as given.
        output: PathBuf,
    },

    /// Two outputs of one command are the same file: one would replace the other.
    #[error(
        "{}: is the same file as the output {} (one would replace the other); choose another \
         output",
        second.display(),
        first.display()
    )]
    SameOutput {
        /// The first output as given.
        first: PathBuf,
        /// The second output as given.
        second: PathBuf,
    },

    /// Writing a file failed; the destination was left untouched and the
    /// temporary file was removed.
    #[error("{}: cannot {action}: {source}", path.display())]
    Write {
        /// The destination path.
        path: PathBuf,
        /// What was being done, e.g. `create a file in its directory`.
        action: String,
        /// The underlying OS error.
        #[source]
        source: std::io::Error,
    },
}

/// The hint of [`IoError::Parse`] for a cell that holds a ';'.
fn semicolon_hint(value: &str) -> &'static str {
    if value.contains(';') {
        " (the file seems to use ';' as the separator; hyst reads comma-separated values with a \
         '.' decimal point)"
    } else {
        ""
    }
}

/// Formats names or cells as `"a", "b", "c"` (each in Rust debug quoting).
fn quoted_list(items: &[String]) -> QuotedList<'_> {
    QuotedList(items)
}

impl IoError {
    /// The error, naming `file` as the one being read when it is a temporary file's
    /// ([`IoError::Spill`]) that does not name one yet.
    #[must_use]
    pub fn reading(self, file: &str) -> IoError {
        match self {
            IoError::Spill {
                file: name,
                dir,
                source,
            } if name == MEMORY_SOURCE => IoError::Spill {
                file: file.to_string(),
                dir,
                source,
            },
            other => other,
        }
    }
}

/// Source name of tables built with [`Table::new`](crate::Table::new), and the file of an
/// [`IoError::Spill`] of values not read from a file.
pub(crate) const MEMORY_SOURCE: &str = "<memory>";

/// Display helper for [`quoted_list`]: at most [`LIST_ITEMS`] items, each [`cut`].
struct QuotedList<'a>(&'a [String]);

/// The most items of a list an error message shows.
const LIST_ITEMS: usize = 12;

impl fmt::Display for QuotedList<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, item) in self.0.iter().take(LIST_ITEMS).enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            write!(f, "{}", cut(item))?;
        }
        if self.0.len() > LIST_ITEMS {
            write!(f, " and {} more", self.0.len() - LIST_ITEMS)?;
        }
        Ok(())
    }
}

/// The longest text an error message quotes in full, in characters.
const QUOTED_CHARS: usize = 60;

/// `text` quoted as `{:?}` does, cut after its first 40 characters when it is longer than
/// [`QUOTED_CHARS`], with its length in bytes: a message never echoes a 50 MB cell.
pub fn cut(text: &str) -> Cut<'_> {
    Cut(text)
}

/// Display helper for [`cut`].
pub struct Cut<'a>(&'a str);

impl fmt::Display for Cut<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.chars().count() <= QUOTED_CHARS {
            return write!(f, "{:?}", self.0);
        }
        let head: String = self.0.chars().take(40).collect();
        write!(f, "{head:?}... ({} bytes in all)", self.0.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_texts_are_cut_and_long_lists_shortened() {
        let long = "a".repeat(5_000_000);
        let shown = cut(&long).to_string();
        assert!(
            shown.len() < 100 && shown.ends_with("(5000000 bytes in all)"),
            "{shown}"
        );
        assert_eq!(cut("x,y").to_string(), "\"x,y\"");
        let many: Vec<String> = (0..100).map(|i| i.to_string()).collect();
        assert!(quoted_list(&many)
            .to_string()
            .ends_with("\"11\" and 88 more"));
    }

    #[test]
    fn quoted_list_formats_and_escapes() {
        let items = vec!["x".to_string(), "a \"b\"".to_string()];
        assert_eq!(quoted_list(&items).to_string(), r#""x", "a \"b\"""#);
        assert_eq!(quoted_list(&[]).to_string(), "");
    }

    #[test]
    fn io_errors_keep_their_source() {
        let err = IoError::Read {
            file: "a.csv".into(),
            source: std::io::Error::new(std::io::ErrorKind::NotFound, "gone"),
        };
        assert_eq!(err.to_string(), "a.csv: cannot read: gone");
        assert!(std::error::Error::source(&err).is_some());
    }
}
