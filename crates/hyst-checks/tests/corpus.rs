//! Replays the fuzz corpus (fuzz/corpus/<target>/, minimised with `cargo fuzz cmin`) through the
//! same check functions the fuzz targets call, under stable `cargo test`.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use std::path::PathBuf;

fn replay(target: &str, check: fn(&[u8]) -> Result<(), String>) {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../fuzz/corpus")
        .join(target);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert!(
        files.len() >= 10,
        "{}: only {} corpus files",
        dir.display(),
        files.len()
    );
    let mut broken = Vec::new();
    for file in &files {
        let data = std::fs::read(file).unwrap();
        if let Err(e) = check(&data) {
            broken.push(format!("{}: {e}", file.display()));
        }
    }
    assert!(broken.is_empty(), "{}", broken.join("\n"));
}

#[test]
fn csv_corpus() {
    replay("csv", hyst_checks::check_csv);
}

#[test]
fn model_file_corpus() {
    replay("model_file", hyst_checks::check_model_file);
}

#[test]
fn operators_corpus() {
    replay("operators", hyst_checks::check_operators);
}
