//! The invariants checked by the fuzz targets of `fuzz/` (cargo-fuzz, nightly) and by the corpus
//! replay test `tests/corpus.rs` (stable `cargo test`): both call the same functions, so the
//! corpus in `fuzz/corpus/<target>/` guards the same properties in CI without nightly.
//!
//! Each `check_*` function takes arbitrary bytes, never panics, and returns `Err` with a
//! description when a documented invariant is broken:
//!
//! - [`check_csv`]: the CSV reader (hyst-io) accepts or refuses any bytes with a one-line error;
//!   an accepted table holds only finite values and reads back identically after writing.
//! - [`check_model_file`]: the model-file reader (hyst-fit) accepts or refuses any text with a
//!   one-line error; an accepted model runs, direct and inverse, with finite outputs or an error.
//! - [`check_operators`]: the operator pair, shaped models, the compensator and jets, f64 and
//!   f32, with arbitrary parameters and inputs: see [`operators`].
//! - [`check_timed`]: a smooth model with Lemma 5.1's plant (order 1…4) and a rate term, any
//!   coefficients, sample period and commands, and its compensator: see [`timed`].

mod message;
pub mod operators;
pub mod timed;

pub use operators::check_operators;
pub use timed::check_timed;

use hyst_io::Table;
use hyst_model::ModelFile;
use message::one_line;

/// The CSV reader on arbitrary bytes.
///
/// # Errors
/// A description of the broken invariant.
pub fn check_csv(data: &[u8]) -> Result<(), String> {
    let table = match Table::parse(data, "fuzz.csv") {
        Ok(t) => t,
        Err(e) => return one_line("csv", &e.to_string()),
    };
    let names = table.names().to_vec();
    // Each column as numbers, or (a column with a cell that is not a finite number) as text:
    // then asking for its numbers is a one-line refusal, and its labels are one per row.
    let mut columns: Vec<Result<Vec<f64>, Vec<String>>> = Vec::with_capacity(names.len());
    for name in &names {
        let labels = table
            .labels(name)
            .map_err(|e| format!("labels of {name:?}: {e}"))?;
        if labels.len() != table.len() {
            return Err(format!(
                "column {name:?} has {} labels for {} rows",
                labels.len(),
                table.len()
            ));
        }
        let column = match table.column(name) {
            Ok(column) => column,
            Err(e) => {
                one_line(&format!("column {name:?}"), &e.to_string())?;
                columns.push(Err(labels.into_owned()));
                continue;
            }
        };
        if let Some(v) = column.iter().find(|v| !v.is_finite()) {
            return Err(format!("column {name:?} holds the non-finite value {v}"));
        }
        if column.len() != table.len() {
            return Err(format!(
                "column {name:?} has {} rows of {}",
                column.len(),
                table.len()
            ));
        }
        columns.push(Ok(column.to_vec()));
    }
    let mut last_line = 0;
    for row in 0..table.len() {
        let line = table.line_of_row(row);
        // Non-decreasing: a lone \r ends a CSV record but not a line, so two rows can share one.
        if line < last_line {
            return Err(format!("row {row} on line {line} after line {last_line}"));
        }
        last_line = line;
    }
    // Written and read back: the identical names and bits.
    let text = table.to_csv();
    let again = Table::parse(&text, "again.csv")
        .map_err(|e| format!("the written table does not read back: {e}"))?;
    if again.names() != names.as_slice() {
        return Err(format!(
            "names {:?} read back as {:?}",
            names,
            again.names()
        ));
    }
    for (name, column) in names.iter().zip(&columns) {
        let same = match column {
            Ok(column) => {
                let back = again.column(name).map_err(|e| e.to_string())?;
                back.len() == column.len()
                    && back
                        .iter()
                        .zip(column)
                        .all(|(a, b)| a.to_bits() == b.to_bits())
            }
            Err(labels) => {
                let back = again.labels(name).map_err(|e| e.to_string())?;
                back.as_ref() == labels.as_slice()
            }
        };
        if !same {
            return Err(format!("column {name:?} does not read back bit for bit"));
        }
    }
    Ok(())
}

/// `hyst export c|rust` of an accepted model file: the C export of a smooth model and the Rust
/// export of any model succeed, refusals are one line, and no number is written as a literal
/// that C or Rust would not read back (`NaN`, `inf`).
///
/// # Errors
/// A description of the broken invariant.
fn check_export(file: &ModelFile) -> Result<(), String> {
    let source = hyst_codegen::Source {
        name: "fuzz.toml".into(),
        fnv1a64: 0,
    };
    for (language, text) in [
        ("c", hyst_codegen::c(file, "m", &source)),
        ("rust", hyst_codegen::rust(file, "m", &source)),
    ] {
        match text {
            Ok(text) => {
                if let Some(bad) = ["NaN", "(T)inf", "(T)-inf", "c(inf)", "c(-inf)"]
                    .iter()
                    .find(|bad| text.contains(**bad))
                {
                    return Err(format!("export {language} wrote the literal {bad}"));
                }
                comments_hold(language, &text)?;
            }
            Err(e) if language == "c" && file.kind == hyst_model::ModelKind::PrandtlIshlinskii => {
                one_line("export c", &e.to_string())?;
            }
            // A rate term, or a stop form with dynamics without a period, is refused with the
            // reason (docs/c.md); the refusal must be one line.
            Err(e)
                if file
                    .smooth
                    .as_ref()
                    .is_some_and(|m| m.rate.is_some() || m.dynamics.is_some()) =>
            {
                one_line(&format!("export {language}"), &e.to_string())?;
            }
            Err(e) => return Err(format!("export {language} refused an accepted model: {e}")),
        }
    }
    Ok(())
}

/// The user text of a model file (column names, units) stays inside the comments of an
/// exported file: no character but the generator's line feeds breaks a line or is a control
/// character, and in C every comment ends, with no `/*` inside one (GCC's -Wcomment).
///
/// # Errors
/// A description of the broken invariant.
fn comments_hold(language: &str, text: &str) -> Result<(), String> {
    if let Some(c) = text
        .chars()
        .find(|c| *c != '\n' && (c.is_control() || matches!(c, '\u{2028}' | '\u{2029}')))
    {
        return Err(format!("export {language} wrote the character {c:?}"));
    }
    if language == "c" {
        let mut rest = text;
        while let Some(start) = rest.find("/*") {
            let inside = rest.get(start + 2..).unwrap_or_default();
            let Some(end) = inside.find("*/") else {
                return Err("export c wrote a comment that never ends".into());
            };
            if inside.get(..end).is_some_and(|c| c.contains("/*")) {
                return Err("export c wrote /* inside a comment".into());
            }
            rest = inside.get(end + 2..).unwrap_or_default();
        }
    }
    Ok(())
}

/// The model-file reader on arbitrary bytes (as UTF-8 text).
///
/// # Errors
/// A description of the broken invariant.
pub fn check_model_file(data: &[u8]) -> Result<(), String> {
    let Ok(text) = std::str::from_utf8(data) else {
        return Ok(());
    };
    let file = match ModelFile::from_toml(text, std::path::Path::new("fuzz.toml")) {
        Ok(f) => f,
        Err(e) => return one_line("model file", &e.to_string()),
    };
    let inputs = [0.0, 0.5, 1.0, -1.0, 0.25, 1e3, -1e3, 0.0];
    for inverse in [false, true] {
        let mut op = match file.evaluator(0.0, inverse) {
            Ok(op) => op,
            Err(e) => {
                one_line("model file evaluator", &e.to_string())?;
                continue;
            }
        };
        for &x in &inputs {
            use hyst_core::Operator;
            match op.try_step(x) {
                Ok(y) if !y.is_finite() => {
                    return Err(format!(
                        "accepted model (inverse: {inverse}) gives {y} for the finite input {x}"
                    ));
                }
                Ok(_) => {}
                Err(e) => one_line("model step", &e.to_string())?,
            }
        }
    }
    check_export(&file)?;
    // What the reader accepted, written and read again, is accepted again.
    if let Ok(again) = file.to_toml() {
        ModelFile::from_toml(&again, std::path::Path::new("again.toml"))
            .map_err(|e| format!("the written model file does not read back: {e}"))?;
    }
    Ok(())
}
