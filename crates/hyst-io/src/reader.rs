//! Reading a numeric CSV file row by row, in constant memory: [`CsvReader`]. [`Table`](crate::Table)
//! is built on it, so a file read whole and a file streamed are parsed, checked and located
//! (line numbers) by the same code.

use std::collections::HashMap;
use std::fs::File;
use std::io::{self, Read};
use std::path::Path;

use crate::error::IoError;

/// Bytes already located (their newlines counted) that may pile up before they are dropped
/// from the window: dropping moves the rest of the window, so doing it once per this many bytes
/// keeps the cost per byte constant.
const DROP_AFTER: usize = 64 * 1024;

/// A CSV file with a header row, read one data row at a time.
///
/// The header and every row are checked as [`Table::read`](crate::Table::read) documents (the
/// two share this code), except that every cell must parse as a finite `f64` here (a
/// [`Table`](crate::Table) keeps a column of text as text): every row must have one cell
/// per column, blank lines and `#` comment lines are skipped but counted, and errors name the
/// file, the line, the column and the value. Memory stays constant: only the current row, the
/// parser's buffer and the bytes of the current line are held.
///
/// # Examples
/// ```
/// # fn main() -> Result<(), hyst_io::IoError> {
/// use hyst_io::CsvReader;
///
/// let mut rows = CsvReader::new(&b"t,x\n# a comment\n0,0.5\n1,0.25\n"[..], "data.csv")?;
/// assert_eq!(rows.names(), ["t", "x"]);
/// assert_eq!(rows.pick_column(None)?, 1);
/// assert_eq!(rows.next_row()?, Some((3, &[0.0, 0.5][..])));
/// assert_eq!(rows.next_row()?, Some((4, &[1.0, 0.25][..])));
/// assert_eq!(rows.next_row()?, None);
/// # Ok(())
/// # }
/// ```
pub struct CsvReader<R: Read> {
    /// The parser, reading through the window of recent bytes.
    reader: csv::Reader<Window<R>>,
    /// The current record.
    record: csv::ByteRecord,
    /// The values of the current row.
    values: Vec<f64>,
    /// Line numbers of byte offsets.
    lines: LineCounter,
    /// Column names, in file order.
    names: Vec<String>,
    /// 1-based line of the header.
    header_line: usize,
    /// Data rows returned so far.
    rows: usize,
    /// File path or other name of the source, for messages.
    source: String,
}

impl CsvReader<File> {
    /// Opens a CSV file and reads its header; the path (as displayed) names the file in errors.
    ///
    /// # Errors
    /// [`IoError::IsDirectory`] or [`IoError::Read`] when the file cannot be read, and the
    /// header errors of [`CsvReader::new`].
    pub fn open(path: &Path) -> Result<Self, IoError> {
        let (handle, file) = open_file(path)?;
        Self::new(handle, &file)
    }
}

/// Opens `path` for reading, with its name as errors give it.
///
/// # Errors
/// [`IoError::IsDirectory`], [`IoError::Read`].
pub fn open_file(path: &Path) -> Result<(File, String), IoError> {
    let file = path.display().to_string();
    if path.is_dir() {
        return Err(IoError::IsDirectory {
            path: path.to_path_buf(),
        });
    }
    let handle = File::open(path).map_err(|source| IoError::Read {
        file: file.clone(),
        source,
    })?;
    Ok((handle, file))
}

impl<R: Read> CsvReader<R> {
    /// Reads the header from `reader`; `source` names the input in errors.
    ///
    /// # Errors
    /// [`IoError::Empty`] (nothing but blank lines and comments), [`IoError::NoHeader`] (the
    /// first row holds only numbers), [`IoError::EmptyName`], [`IoError::DuplicateName`],
    /// [`IoError::InvalidUtf8`], [`IoError::Csv`] and [`IoError::Read`].
    pub fn new(reader: R, source: &str) -> Result<Self, IoError> {
        let reader = csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .comment(Some(b'#'))
            .from_reader(Window {
                inner: reader,
                bytes: Vec::new(),
                base: 0,
            });
        let mut this = CsvReader {
            reader,
            record: csv::ByteRecord::new(),
            values: Vec::new(),
            lines: LineCounter { pos: 0, line: 1 },
            names: Vec::new(),
            header_line: 0,
            rows: 0,
            source: source.to_string(),
        };
        let Some(header_line) = this.next_record()? else {
            return Err(IoError::Empty {
                file: this.source.clone(),
            });
        };
        let mut names = Vec::with_capacity(this.record.len());
        for i in 0..this.record.len() {
            let name = cell(&this.record, i, &this.source, header_line, "")?;
            // csv-core strips a BOM at the start of the input; be safe if it did not (and
            // strip BOMs and spaces in any order, so that a written name reads back as itself).
            let name = if i == 0 {
                name.trim_start_matches(|c: char| c == '\u{feff}' || c.is_whitespace())
                    .trim_end()
            } else {
                name
            };
            names.push(name.to_string());
        }
        if names.iter().all(|n| looks_numeric(n)) {
            return Err(IoError::NoHeader {
                file: this.source.clone(),
                line: header_line,
                cells: names,
            });
        }
        let mut seen: HashMap<&str, usize> = HashMap::new();
        for (i, name) in names.iter().enumerate() {
            if name.is_empty() {
                return Err(IoError::EmptyName {
                    file: this.source.clone(),
                    line: header_line,
                    column: i + 1,
                });
            }
            if let Some(first) = seen.insert(name, i + 1) {
                return Err(IoError::DuplicateName {
                    file: this.source.clone(),
                    line: header_line,
                    column: i + 1,
                    name: name.clone(),
                    first,
                });
            }
        }
        this.values = vec![0.0; names.len()];
        this.names = names;
        this.header_line = header_line;
        Ok(this)
    }

    /// The column names, in file order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The file path or other source name used in error messages.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The 0-based index of the column called `name` (exact, case-sensitive match).
    pub fn column_index(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }

    /// The 0-based index of the column called `name`.
    ///
    /// # Errors
    /// [`IoError::UnknownColumn`], listing the available columns.
    pub fn column(&self, name: &str) -> Result<usize, IoError> {
        self.column_index(name)
            .ok_or_else(|| unknown_column(&self.source, &self.names, name))
    }

    /// Chooses the input column as [`Table::pick_column`](crate::Table::pick_column) does:
    /// `name` if given, else `x`, else the only column; returns its 0-based index.
    ///
    /// # Errors
    /// As [`Table::pick_column`](crate::Table::pick_column).
    pub fn pick_column(&self, name: Option<&str>) -> Result<usize, IoError> {
        pick_column(&self.source, &self.names, name)
    }

    /// The next data row: its 1-based line and its values (one per column, all finite), or
    /// `None` after the last row.
    ///
    /// # Errors
    /// [`IoError::CellCount`], [`IoError::Parse`], [`IoError::NonFinite`],
    /// [`IoError::InvalidUtf8`], [`IoError::Csv`] or [`IoError::Read`] for this row, and
    /// [`IoError::NoData`] when the file ends before its first data row.
    pub fn next_row(&mut self) -> Result<Option<(usize, &[f64])>, IoError> {
        let Some(line) = self.next_cells()? else {
            return Ok(None);
        };
        let file = self.source.as_str();
        for (i, (name, slot)) in self.names.iter().zip(&mut self.values).enumerate() {
            let text = cell(&self.record, i, file, line, name)?;
            *slot = number(text, file, line, i, name)?;
        }
        Ok(Some((line, &self.values)))
    }

    /// Reads the next data row, checking only its number of cells, and returns its 1-based
    /// line (`None` after the last row); [`CsvReader::cell_text`] and [`CsvReader::value`] then
    /// give its cells, as text or as numbers (for a file whose other columns may hold text).
    ///
    /// # Errors
    /// As [`CsvReader::next_row`], except the errors of single cells.
    pub fn next_cells(&mut self) -> Result<Option<usize>, IoError> {
        let Some(line) = self.next_record()? else {
            if self.rows == 0 {
                return Err(IoError::NoData {
                    file: self.source.clone(),
                    header_line: self.header_line,
                });
            }
            return Ok(None);
        };
        let record = &self.record;
        if record.len() != self.names.len() {
            let cells = (0..record.len())
                .map(|i| {
                    String::from_utf8_lossy(record.get(i).unwrap_or_default())
                        .trim()
                        .to_string()
                })
                .collect();
            return Err(IoError::CellCount {
                file: self.source.clone(),
                line,
                expected: self.names.len(),
                found: record.len(),
                header_line: self.header_line,
                cells,
            });
        }
        self.rows += 1;
        Ok(Some(line))
    }

    /// Cell `index` (0-based) of the row [`CsvReader::next_cells`] read from `line`, trimmed.
    ///
    /// # Errors
    /// [`IoError::InvalidUtf8`].
    pub fn cell_text(&self, index: usize, line: usize) -> Result<&str, IoError> {
        let name = self.names.get(index).map_or("", String::as_str);
        cell(&self.record, index, &self.source, line, name)
    }

    /// Cell `index` (0-based) of the row [`CsvReader::next_cells`] read from `line`, as a
    /// finite number.
    ///
    /// # Errors
    /// [`IoError::Parse`], [`IoError::NonFinite`] or [`IoError::InvalidUtf8`], naming the file,
    /// line, column and cell.
    pub fn value(&self, index: usize, line: usize) -> Result<f64, IoError> {
        let name = self.names.get(index).map_or("", String::as_str);
        let text = cell(&self.record, index, &self.source, line, name)?;
        number(text, &self.source, line, index, name)
    }

    /// Appends every cell of the row [`CsvReader::next_cells`] read from `line` to `out`, as
    /// read (trimmed) and quoted where it would not read back as itself, each followed by `,`: the cells a command passes through before its own columns
    /// ([`CsvWriter::write_row_after`](crate::CsvWriter::write_row_after)). On an error `out`
    /// may hold part of the row.
    ///
    /// # Errors
    /// [`IoError::InvalidUtf8`].
    pub fn push_cells(&self, line: usize, out: &mut String) -> Result<(), IoError> {
        for i in 0..self.names.len() {
            crate::cell::push_cell(out, self.cell_text(i, line)?, i == 0);
            out.push(',');
        }
        Ok(())
    }

    /// Reads the next non-blank record into `self.record` and returns its 1-based start line.
    fn next_record(&mut self) -> Result<Option<usize>, IoError> {
        loop {
            let start = usize::try_from(self.reader.position().byte()).unwrap_or(usize::MAX);
            let more = self.reader.read_byte_record(&mut self.record);
            let window = self.reader.get_mut();
            let line = self.lines.line_at(window, window.skip_to_record(start));
            let more = more.map_err(|e| {
                let message = e.to_string();
                match e.into_kind() {
                    csv::ErrorKind::Io(source) if source.to_string() == LINE_TOO_LONG => {
                        IoError::LineTooLong {
                            file: self.source.clone(),
                            line,
                            limit: MAX_LINE_BYTES,
                        }
                    }
                    csv::ErrorKind::Io(source) => IoError::Read {
                        file: self.source.clone(),
                        source,
                    },
                    _ => IoError::Csv {
                        file: self.source.clone(),
                        line,
                        message,
                    },
                }
            })?;
            if more {
                // A quote that is never closed runs to the end of the input, which the parser
                // takes as the end of the cell (and of the record).
                let end = usize::try_from(self.reader.position().byte()).unwrap_or(usize::MAX);
                let window = self.reader.get_mut();
                let first = window.skip_to_record(start);
                let raw = window.from(first);
                let raw = raw.get(..end.saturating_sub(first)).unwrap_or(raw);
                if let Some(at) = raw.contains(&b'"').then(|| unclosed_quote(raw)).flatten() {
                    let opened = line
                        + raw
                            .get(..at)
                            .unwrap_or_default()
                            .iter()
                            .filter(|&&b| b == b'\n')
                            .count();
                    let tail = raw.get(at..).unwrap_or_default();
                    let tail = tail.strip_suffix(b"\n").unwrap_or(tail);
                    let rest = tail.iter().filter(|&&b| b == b'\n').count() + 1;
                    return Err(IoError::Csv {
                        file: self.source.clone(),
                        line: opened,
                        message: format!(
                            "a quote (\") on this line opens a cell that is never closed: the \
                             {rest} line(s) from it to the end of the file would be read as that \
                             one cell. Close the quote, or remove it"
                        ),
                    });
                }
            }
            let window = self.reader.get_mut();
            window.drop_before(self.lines.pos);
            if !more {
                return Ok(None);
            }
            if !is_blank(&self.record) {
                return Ok(Some(line));
            }
        }
    }
}

/// The offset in `raw` (one record's bytes as read) of a quote that opens a cell and is never
/// closed, by the parser's rules: a `"` at the start of a cell opens it, `""` inside is a quote,
/// and the next lone `"` closes it; a `"` inside an unquoted cell is plain text.
fn unclosed_quote(raw: &[u8]) -> Option<usize> {
    let mut opened = None;
    let mut cell_start = true;
    let mut i = 0;
    while let Some(&b) = raw.get(i) {
        if opened.is_some() {
            if b == b'"' {
                if raw.get(i + 1) == Some(&b'"') {
                    i += 1;
                } else {
                    opened = None;
                }
            }
        } else if b == b'"' && cell_start {
            opened = Some(i);
        } else {
            cell_start = matches!(b, b',' | b'\n' | b'\r');
            i += 1;
            continue;
        }
        cell_start = false;
        i += 1;
    }
    opened
}

/// The reader under the CSV parser, keeping the bytes read since the last located offset (the
/// parser reads ahead in blocks), so that lines can be counted without holding the file.
struct Window<R> {
    /// The underlying reader.
    inner: R,
    /// The bytes from offset `base` on, up to what the parser has read.
    bytes: Vec<u8>,
    /// The offset in the input of `bytes[0]`.
    base: usize,
}

/// The longest line a CSV input may have, in bytes: a line of hyst's data holds numbers, and a
/// bound keeps reading in constant memory whatever the input (a file of NUL bytes, /dev/zero).
pub const MAX_LINE_BYTES: usize = 8 << 20;

/// The error [`Window`] returns when a line exceeds [`MAX_LINE_BYTES`].
const LINE_TOO_LONG: &str = "hyst: line too long";

impl<R: Read> Read for Window<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        // `bytes` holds the record being parsed (and what was read ahead of it).
        if self.bytes.len() > MAX_LINE_BYTES {
            return Err(io::Error::new(io::ErrorKind::InvalidData, LINE_TOO_LONG));
        }
        let n = self.inner.read(buf)?;
        self.bytes
            .extend_from_slice(buf.get(..n).unwrap_or_default());
        Ok(n)
    }
}

impl<R> Window<R> {
    /// The bytes from input offset `offset` on (empty if they are not held).
    fn from(&self, offset: usize) -> &[u8] {
        offset
            .checked_sub(self.base)
            .and_then(|i| self.bytes.get(i..))
            .unwrap_or_default()
    }

    /// Skips what the CSV parser skips before a record (blank lines, `#` comment lines, and at
    /// the very start a UTF-8 BOM) and returns the input offset of the record's first byte.
    fn skip_to_record(&self, start: usize) -> usize {
        let mut pos = start;
        if pos == 0 && self.from(0).starts_with(b"\xEF\xBB\xBF") {
            pos = 3;
        }
        loop {
            match self.from(pos).first() {
                Some(b'\r' | b'\n') => pos += 1,
                Some(b'#') => {
                    let rest = self.from(pos);
                    pos += rest
                        .iter()
                        .position(|&b| b == b'\n')
                        .map_or(rest.len(), |nl| nl + 1);
                }
                _ => return pos,
            }
        }
    }

    /// Forgets the bytes before input offset `offset` (once enough of them have piled up).
    fn drop_before(&mut self, offset: usize) {
        let done = offset.saturating_sub(self.base).min(self.bytes.len());
        if done >= DROP_AFTER {
            self.bytes.drain(..done);
            self.base += done;
        }
    }
}

/// Converts input offsets into 1-based line numbers, for increasing offsets.
struct LineCounter {
    /// Offset up to which newlines have been counted.
    pos: usize,
    /// The line number at `pos`.
    line: usize,
}

impl LineCounter {
    /// The 1-based line containing input offset `offset` (must not decrease), counting the
    /// newlines the window holds.
    fn line_at<R>(&mut self, window: &Window<R>, offset: usize) -> usize {
        if offset > self.pos {
            let held = window.from(self.pos);
            let upto = held.get(..offset - self.pos).unwrap_or(held);
            self.line += upto.iter().filter(|&&b| b == b'\n').count();
            self.pos += upto.len();
        }
        self.line
    }
}

/// Decodes one cell of `record`, trimmed of surrounding whitespace.
fn cell<'r>(
    record: &'r csv::ByteRecord,
    index: usize,
    file: &str,
    line: usize,
    name: &str,
) -> Result<&'r str, IoError> {
    let raw = record.get(index).unwrap_or_default();
    match std::str::from_utf8(raw) {
        Ok(s) => Ok(s.trim()),
        Err(_) => Err(IoError::InvalidUtf8 {
            file: file.to_string(),
            line,
            column: index + 1,
            name: name.to_string(),
            value: String::from_utf8_lossy(raw).trim().to_string(),
        }),
    }
}

/// The value of a (trimmed) cell: a finite number, else the error naming the file, line,
/// column (0-based `index`, and `name`) and the cell.
pub(crate) fn number(
    text: &str,
    file: &str,
    line: usize,
    index: usize,
    name: &str,
) -> Result<f64, IoError> {
    match text.parse::<f64>() {
        Ok(value) if value.is_finite() => Ok(value),
        Ok(_) => Err(IoError::NonFinite {
            file: file.to_string(),
            line,
            column: index + 1,
            name: name.to_string(),
            value: text.to_string(),
        }),
        Err(_) => Err(IoError::Parse {
            file: file.to_string(),
            line,
            column: index + 1,
            name: name.to_string(),
            value: text.to_string(),
        }),
    }
}

/// Whether the record is an all-whitespace line (the parser skips truly empty lines itself, but
/// not lines of spaces). Whitespace is what a cell is trimmed of ([`str::trim`], Unicode's), so
/// a line that would be one empty cell is blank: a table never holds a row the writer could
/// only write as a line the reader skips.
fn is_blank(record: &csv::ByteRecord) -> bool {
    record.len() == 1
        && record
            .get(0)
            .is_some_and(|c| std::str::from_utf8(c).is_ok_and(|s| s.trim().is_empty()))
}

/// Whether a (trimmed) cell parses as a number, finite or not.
pub(crate) fn looks_numeric(cell: &str) -> bool {
    cell.trim().parse::<f64>().is_ok()
}

/// The error for a column name that does not exist in `names`.
pub(crate) fn unknown_column(source: &str, names: &[String], name: &str) -> IoError {
    IoError::UnknownColumn {
        file: source.to_string(),
        name: name.to_string(),
        available: names.to_vec(),
    }
}

/// The input column among `names`: `name` if given, else `x`, else the only column.
pub(crate) fn pick_column(
    source: &str,
    names: &[String],
    name: Option<&str>,
) -> Result<usize, IoError> {
    let index_of = |wanted: &str| names.iter().position(|n| n == wanted);
    match name {
        Some(name) => index_of(name).ok_or_else(|| unknown_column(source, names, name)),
        None => match index_of("x") {
            Some(i) => Ok(i),
            None if names.len() == 1 => Ok(0),
            None => Err(IoError::AmbiguousColumn {
                file: source.to_string(),
                available: names.to_vec(),
            }),
        },
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::*;

    /// A reader that hands out at most `chunk` bytes per call, so records and line ends fall
    /// across the parser's reads.
    struct Trickle<'a> {
        bytes: &'a [u8],
        chunk: usize,
    }

    impl Read for Trickle<'_> {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            let n = self.chunk.min(buf.len()).min(self.bytes.len());
            buf[..n].copy_from_slice(&self.bytes[..n]);
            self.bytes = &self.bytes[n..];
            Ok(n)
        }
    }

    fn lines_of(text: &[u8], chunk: usize) -> Vec<(usize, Vec<f64>)> {
        let mut rows = CsvReader::new(Trickle { bytes: text, chunk }, "t.csv").unwrap();
        let mut out = Vec::new();
        while let Some((line, values)) = rows.next_row().unwrap() {
            out.push((line, values.to_vec()));
        }
        out
    }

    #[test]
    fn line_numbers_do_not_depend_on_how_the_input_arrives() {
        // Comments, blank lines, CRLF and a quoted header cell with a line break, long enough
        // that the window is dropped from several times. (A byte order mark is recognised
        // only when the parser's first read holds all three of its bytes, as a file's does.)
        let mut text = b"# head\r\n\"a\nb\",c\r\n\r\n".to_vec();
        for i in 0..40_000 {
            if i % 7 == 0 {
                text.extend_from_slice(b"# comment, with \"quote\n\n");
            }
            text.extend_from_slice(format!("{i},{}\r\n", i * 2).as_bytes());
        }
        let whole = lines_of(&text, usize::MAX);
        assert_eq!(whole.len(), 40_000);
        // Lines 1-4: comment, header (two lines), blank; then a comment and a blank line
        // before every 7th row.
        assert_eq!(whole[0], (7, vec![0.0, 0.0]));
        let mut line = 5;
        for (i, (l, v)) in whole.iter().enumerate() {
            if i % 7 == 0 {
                line += 2;
            }
            assert_eq!((*l, v[0]), (line, i as f64));
            line += 1;
        }
        for chunk in [1, 2, 3, 7, 64, 4096, 100_000] {
            assert_eq!(lines_of(&text, chunk), whole, "chunk {chunk}");
        }
    }

    #[test]
    fn errors_deep_in_a_stream_name_their_line() {
        let mut text = String::from("x,y\n");
        for i in 0..100_000 {
            text.push_str(&format!("{i},1\n"));
        }
        text.push_str("5,oops\n");
        let mut rows = CsvReader::new(
            Trickle {
                bytes: text.as_bytes(),
                chunk: 777,
            },
            "big.csv",
        )
        .unwrap();
        let err = loop {
            match rows.next_row() {
                Ok(Some(_)) => {}
                Ok(None) => panic!("no error"),
                Err(e) => break e,
            }
        };
        assert_eq!(
            err.to_string(),
            r#"big.csv:100002: column 2 ("y"): cannot parse "oops" as a number"#
        );
    }

    #[test]
    fn a_read_error_is_reported_as_one() {
        struct Failing;
        impl Read for Failing {
            fn read(&mut self, _: &mut [u8]) -> io::Result<usize> {
                Err(io::Error::other("disk on fire"))
            }
        }
        let err = CsvReader::new(Failing, "f.csv").err().unwrap();
        assert_eq!(err.to_string(), "f.csv: cannot read: disk on fire");
    }

    /// A quote that is never closed is refused on the line it opens, wherever the parser's
    /// reads end, instead of swallowing the rest of the file into one cell (a lost row when the
    /// cell is a column nobody reads); closed quotes, `""` inside them and a `"` inside an
    /// unquoted cell read as before.
    #[test]
    fn a_quote_never_closed_is_refused_where_it_opens() {
        for chunk in [1, 3, 4096] {
            for text in [&b"x,y\n0,1\n0.5,\"2\n1,3\n"[..], b"x,y\n0,1\n\"0.5,2\n1,3"] {
                let mut rows = CsvReader::new(Trickle { bytes: text, chunk }, "q.csv").unwrap();
                assert!(rows.next_cells().unwrap().is_some());
                let e = rows.next_cells().unwrap_err().to_string();
                assert!(
                    e.starts_with(
                        "q.csv:3: malformed CSV: a quote (\") on this line opens a cell \
                                   that is never closed: the 2 line(s)"
                    ),
                    "{chunk}: {e}"
                );
            }
            let text = b"x,label\n0,\"a \"\"b\"\" c\"\n1,12\"\n2,\"two\nlines\"\n";
            let mut rows = CsvReader::new(Trickle { bytes: text, chunk }, "q.csv").unwrap();
            let mut labels = Vec::new();
            while let Some(line) = rows.next_cells().unwrap() {
                labels.push(rows.cell_text(1, line).unwrap().to_string());
            }
            assert_eq!(labels, ["a \"b\" c", "12\"", "two\nlines"]);
        }
        assert_eq!(unclosed_quote(b"1,\"a\"\"\n"), Some(2));
        assert_eq!(unclosed_quote(b"1,\"a\"\"\"\n"), None);
    }
}
