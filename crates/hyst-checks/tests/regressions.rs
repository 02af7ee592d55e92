//! Every input that broke an invariant while fuzzing (fuzz/regressions/<target>/, named after
//! what it found; docs/reliability.md lists them), replayed through the fuzz targets' checks.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use std::path::PathBuf;

fn replay(target: &str, check: fn(&[u8]) -> Result<(), String>, at_least: usize) {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../fuzz/regressions")
        .join(target);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert!(files.len() >= at_least, "{}: {files:?}", dir.display());
    for file in &files {
        let data = std::fs::read(file).unwrap();
        if let Err(e) = check(&data) {
            panic!("{}: {e}", file.display());
        }
    }
}

#[test]
fn csv_regressions() {
    replay("csv", hyst_checks::check_csv, 1);
}

#[test]
fn model_file_regressions() {
    replay("model_file", hyst_checks::check_model_file, 1);
}

#[test]
fn operators_regressions() {
    replay("operators", hyst_checks::check_operators, 9);
}
