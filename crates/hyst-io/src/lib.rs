//! Reading and writing numeric CSV tables for `hyst`, with exact error messages
//! and atomic output.
//!
//! - [`Table`] holds named `f64` columns read from a CSV file with a header row
//!   ([`Table::read`], [`Table::from_reader`]) or built in memory
//!   ([`Table::new`]), and remembers the source line of every row.
//! - [`Table::write_atomic`] writes a table so that every value parses back to
//!   the identical `f64`, and [`write_atomic`] writes arbitrary bytes (JSON,
//!   TOML, PNG, SVG, ...); both replace the destination atomically and never
//!   leave a half-written or temporary file behind.
//! - [`IoError`] messages name the file, line, column (index and name) and the
//!   offending value, e.g.
//!   `data.csv:17: column 2 ("y"): cannot parse "1.2.3" as a number`.
//!
//! ```
//! # fn main() -> Result<(), hyst_io::IoError> {
//! let csv = "# measured 2024-05-01\nt, x, y\n0, 0.0, 0.1\n1, 0.5, 0.4\n";
//! let table = hyst_io::Table::from_reader(csv.as_bytes(), "<stdin>")?;
//! assert_eq!(table.names(), ["t", "x", "y"]);
//! assert_eq!(table.column("y")?, [0.1, 0.4]);
//! assert_eq!(table.pick_column(None)?.0, 1);
//! assert_eq!(table.line_of_row(1), 4);
//!
//! let err = hyst_io::Table::from_reader("x,y\n1,2\n3,1.2.3\n".as_bytes(), "data.csv")
//!     .unwrap_err();
//! assert_eq!(
//!     err.to_string(),
//!     r#"data.csv:3: column 2 ("y"): cannot parse "1.2.3" as a number"#
//! );
//! # Ok(())
//! # }
//! ```

#![forbid(unsafe_code)]

mod atomic;
mod error;
mod table;

pub use atomic::write_atomic;
pub use error::IoError;
pub use table::Table;
