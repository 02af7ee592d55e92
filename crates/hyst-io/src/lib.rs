//! Reading and writing numeric CSV tables for `hyst`, with exact error messages
//! and atomic output.
//!
//! - [`Table`] holds named `f64` columns read from a CSV file with a header row
//!   ([`Table::read`]) or built in memory ([`Table::new`]), and remembers the
//!   source line of every row. A column of a file with a cell that is not a
//!   finite number is kept as text ([`Table::labels`]); asked for as numbers
//!   ([`Table::column`]), it gives the error of that cell.
//! - [`Table::write_atomic`] writes a table so that every value parses back to
//!   the identical `f64`, and [`write_atomic`] writes arbitrary bytes (JSON,
//!   TOML, PNG, SVG, ...); both replace the destination atomically (a
//!   [`tempfile`] in the same directory, then a rename) and never leave a
//!   half-written or temporary file behind.
//! - [`number`]: numbers as every report and message prints them ([`number::sig`],
//!   [`number::shortest`], percentages).
//! - [`Samples`]: a column read from a file that is longer than [`SPILL_AFTER`] values is
//!   held in an unnamed temporary file mapped into memory, and its pages leave resident
//!   memory once read: a long file is read in bounded memory.
//! - [`IoError`] messages name the file, line, column (index and name) and the
//!   offending value, e.g.
//!   `data.csv:17: column 2 ("y"): cannot parse "1.2.3" as a number`.
//!
//! ```
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! use hyst_io::{write_atomic, Table};
//!
//! let dir = tempfile::tempdir()?;
//! let path = dir.path().join("data.csv");
//! write_atomic(&path, b"# measured 2024-05-01\nt, x, y\n0, 0.0, 0.1\n1, 0.5, 0.4\n")?;
//! let table = Table::read(&path)?;
//! assert_eq!(table.names(), ["t", "x", "y"]);
//! assert_eq!(table.column("y")?, [0.1, 0.4]);
//! assert_eq!(table.pick_column(None)?.0, 1);
//! assert_eq!(table.line_of_row(1), 4);
//!
//! write_atomic(&path, b"x,y\n1,2\n3,1.2.3\n")?;
//! let table = Table::read(&path)?;
//! assert_eq!(table.labels("y")?[..], ["2", "1.2.3"]);
//! let err = table.column("y").unwrap_err();
//! assert_eq!(
//!     err.to_string(),
//!     format!(r#"{}:3: column 2 ("y"): cannot parse "1.2.3" as a number"#, path.display())
//! );
//! # Ok(())
//! # }
//! ```

#![deny(unsafe_code)]

mod atomic;
mod cell;
mod digest;
mod error;
pub mod number;
mod reader;
mod samples;
mod table;
mod writer;

pub use atomic::{
    check_all_distinct, check_distinct, check_writable, check_writable_dir, remove_temporary_files,
    write_atomic, STDOUT,
};
pub use digest::{CountingReader, Digest};
pub use error::IoError;
pub use reader::{open_file, CsvReader};
pub use samples::{set_spill_after, Samples, SamplesWriter, SPILL_AFTER};
pub use table::Table;
pub use writer::CsvWriter;
