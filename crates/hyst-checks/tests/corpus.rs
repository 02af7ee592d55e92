//! Replays the fuzz corpus (fuzz/corpus/<target>/, minimised with `cargo fuzz cmin`) through the
//! same check functions the fuzz targets call, under stable `cargo test`.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

mod common;

use common::replay;

#[test]
fn csv_corpus() {
    replay("corpus", "csv", hyst_checks::check_csv, 10);
}

#[test]
fn model_file_corpus() {
    replay("corpus", "model_file", hyst_checks::check_model_file, 10);
}

#[test]
fn operators_corpus() {
    replay("corpus", "operators", hyst_checks::check_operators, 10);
}

#[test]
fn timed_corpus() {
    replay("corpus", "timed", hyst_checks::check_timed, 10);
}
