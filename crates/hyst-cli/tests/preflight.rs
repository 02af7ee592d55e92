//! `hyst fit` checks where it will write before it reads or fits anything: a model file in a
//! missing directory, or a plot directory under a file, is refused first, so a long fit is never
//! thrown away at the end.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use hyst_test_support::cli::Binary;
use std::fs;
use std::path::Path;

const HYST: Binary = Binary::new(env!("CARGO_BIN_EXE_hyst"));

/// `hyst fit` of a data file in `dir` that does not exist, with `-o OUT` (and `--plot PLOT`):
/// it must fail with status 1; returns its stderr.
fn fit_missing_data(dir: &Path, out: &Path, plot: Option<&Path>) -> String {
    let mut command = HYST.command();
    command
        .arg("fit")
        .arg(dir.join("no-such-data.csv"))
        .args(["--input", "u", "--output", "y", "-o"])
        .arg(out);
    if let Some(plot) = plot {
        command.arg("--plot").arg(plot);
    }
    let o = command.output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(1), "{err}");
    err
}

/// The data does not exist: an error about the output proves the output was checked first.
#[test]
fn a_model_file_in_a_missing_directory_is_refused_before_the_data_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("missing/model.toml");
    let err = fit_missing_data(dir.path(), &out, None);
    assert!(err.contains("missing/model.toml"), "{err}");
    assert!(
        err.contains("cannot create a file in its directory"),
        "{err}"
    );
    assert!(!err.contains("no-such-data"), "{err}");
    assert!(!dir.path().join("missing").exists());
}

#[test]
fn a_model_file_that_is_a_directory_is_refused_before_the_data_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let err = fit_missing_data(dir.path(), dir.path(), None);
    assert!(err.contains("directory"), "{err}");
    assert!(!err.contains("no-such-data"), "{err}");
}

#[test]
fn a_plot_directory_under_a_file_is_refused_before_the_data_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("a-file");
    fs::write(&file, "not a directory").unwrap();
    let err = fit_missing_data(
        dir.path(),
        &dir.path().join("m.toml"),
        Some(&file.join("plots")),
    );
    assert!(err.contains("a-file/plots"), "{err}");
    assert!(err.contains("is not a directory"), "{err}");
    assert!(!err.contains("no-such-data"), "{err}");
    assert_eq!(fs::read_to_string(&file).unwrap(), "not a directory");
    // Nothing was left behind: no model file, no temporary file.
    let names: Vec<_> = fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, vec![std::ffi::OsString::from("a-file")]);
}

/// A plot directory that does not exist yet is fine (it is created once the fit is done), and
/// the check creates nothing.
#[test]
fn a_new_plot_directory_passes_the_check_and_is_not_created_by_it() {
    let dir = tempfile::tempdir().unwrap();
    let err = fit_missing_data(
        dir.path(),
        &dir.path().join("m.toml"),
        Some(&dir.path().join("new/plots")),
    );
    assert!(err.contains("no-such-data"), "the data is read next: {err}");
    assert!(!dir.path().join("new").exists());
}
