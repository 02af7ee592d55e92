//! Every input that broke an invariant while fuzzing (fuzz/regressions/<target>/, named after
//! what it found; docs/reliability.md lists them), replayed through the fuzz targets' checks.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

mod common;

use common::replay;

#[test]
fn csv_regressions() {
    replay("regressions", "csv", hyst_checks::check_csv, 1);
}

#[test]
fn model_file_regressions() {
    replay(
        "regressions",
        "model_file",
        hyst_checks::check_model_file,
        1,
    );
}

#[test]
fn operators_regressions() {
    replay("regressions", "operators", hyst_checks::check_operators, 9);
}
