//! The repository's paths and the CSV files `hyst` reads and writes: a header row, then rows
//! of cells.

use std::path::{Path, PathBuf};

/// The repository's root (the bundled data is under `data/`).
pub fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The bundled piezo record.
pub fn piezo() -> PathBuf {
    repo().join("data/piezo-sine/piezo_sine_1hz.csv")
}

/// The arguments of `hyst fit` of the piezo record `data` (its input and output columns) into
/// `model`.
pub fn piezo_fit<'a>(data: &'a Path, model: &'a Path) -> [&'a str; 8] {
    [
        "fit",
        data.to_str().unwrap(),
        "--input",
        "u_actuator_V",
        "--output",
        "y_capsensor_um",
        "-o",
        model.to_str().unwrap(),
    ]
}

/// A path as the `&str` an argument list takes.
pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A CSV file written by `hyst run`: its header and its rows as numbers.
pub fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(|c| c.parse::<f64>().unwrap()).collect())
        .collect();
    (header, rows)
}

/// The index of the column `name` in `header` (panics naming the header if there is none).
pub fn index(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name:?} in {header:?}"))
}

/// The column `name` of a file read by [`read_csv`].
pub fn column(header: &[String], rows: &[Vec<f64>], name: &str) -> Vec<f64> {
    let k = index(header, name);
    rows.iter().map(|r| r[k]).collect()
}

/// The cells of a CSV text (RFC 4180: a quoted cell may hold commas, doubled quotes and line
/// ends; the quotes are removed): its header and its rows of text.
pub fn parse_cells(text: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let mut records: Vec<Vec<String>> = Vec::new();
    let mut record: Vec<String> = Vec::new();
    let mut cell = String::new();
    let mut quoted = false;
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                chars.next();
                cell.push('"');
            }
            (true, '"') => quoted = false,
            (true, c) => cell.push(c),
            (false, '"') => quoted = true,
            (false, ',') => record.push(std::mem::take(&mut cell)),
            (false, '\r') => {}
            (false, '\n') => {
                record.push(std::mem::take(&mut cell));
                records.push(std::mem::take(&mut record));
            }
            (false, c) => cell.push(c),
        }
    }
    if !cell.is_empty() || !record.is_empty() {
        record.push(cell);
        records.push(record);
    }
    let mut records = records.into_iter();
    let header = records.next().unwrap_or_default();
    (header, records.collect())
}

/// [`parse_cells`] of the file `path`.
pub fn read_cells(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    parse_cells(&std::fs::read_to_string(path).unwrap())
}

/// The column `name` of rows of text (as [`parse_cells`] gives them), as numbers.
pub fn numbers(header: &[String], rows: &[Vec<String>], name: &str) -> Vec<f64> {
    let k = index(header, name);
    rows.iter()
        .map(|r| {
            r[k].parse::<f64>()
                .unwrap_or_else(|e| panic!("{name}: {:?}: {e}", r[k]))
        })
        .collect()
}
