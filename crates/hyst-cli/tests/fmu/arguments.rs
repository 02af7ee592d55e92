//! Bad arguments and binaries name the problem and leave no file behind; a failed run overwrites
//! nothing.

use crate::archive::*;
use crate::model::*;

#[test]
fn bad_arguments_name_the_problem_and_leave_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let lib = fake_library(d);
    let fmu = d.join("out.fmu");
    let fmu = fmu.to_str().unwrap();
    let only_lib = ["libhyst_fmu.so"];

    fails(
        d,
        &lib,
        &["--k1", "-1", "--k2", "8", "-o", fmu],
        &["k1 = -1", "must be finite and > 0"],
        &only_lib,
    );
    fails(
        d,
        &lib,
        &["--k1", "0.2", "--k2", "inf", "-o", fmu],
        &["k2 = inf"],
        &only_lib,
    );
    fails(
        d,
        &lib,
        &["--k1", "0.2", "--k2", "NaN", "-o", fmu],
        &["k2 = NaN"],
        &only_lib,
    );
    fails(d, &lib, &["--k1", "0.2", "-o", fmu], &["--k2"], &only_lib);
    let missing = d.join("missing.toml");
    fails(
        d,
        &lib,
        &["--model", missing.to_str().unwrap(), "-o", fmu],
        &[missing.to_str().unwrap(), "cannot read"],
        &only_lib,
    );
    let not_a_model = d.join("notes.toml");
    std::fs::write(&not_a_model, "title = \"not a model\"\n").unwrap();
    fails(
        d,
        &lib,
        &["--model", not_a_model.to_str().unwrap(), "-o", fmu],
        &["notes.toml", "not a hyst model file"],
        &["libhyst_fmu.so", "notes.toml"],
    );
    std::fs::remove_file(&not_a_model).unwrap();
    fails(
        d,
        &lib,
        &[
            "--model",
            missing.to_str().unwrap(),
            "--k1",
            "0.2",
            "-o",
            fmu,
        ],
        &["--model", "cannot be used with", "--k1"],
        &only_lib,
    );
    let csv = d.join("out.csv");
    fails(
        d,
        &lib,
        &["--k1", "0.2", "--k2", "8", "-o", csv.to_str().unwrap()],
        &["out.csv", "NAME.fmu"],
        &only_lib,
    );
    fails(
        d,
        &lib,
        &[
            "--k1",
            "0.2",
            "--k2",
            "8",
            "-o",
            d.join("no-dir/out.fmu").to_str().unwrap(),
        ],
        &["no-dir/out.fmu", "No such file or directory"],
        &only_lib,
    );
}

/// The FMU binary missing (the message says how to build it), or not a shared library.
#[test]
fn a_missing_or_foreign_binary_is_named_with_how_to_build_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The library the other runs take, which the listings show.
    fake_library(d);
    let fmu = d.join("out.fmu");
    let fmu = fmu.to_str().unwrap();
    let only_lib = ["libhyst_fmu.so"];
    let nowhere = d.join("nowhere/libhyst_fmu.so");
    fails(
        d,
        &nowhere,
        &["--k1", "0.2", "--k2", "8", "-o", fmu],
        &[
            nowhere.to_str().unwrap(),
            "HYST_FMU_LIBRARY",
            "cargo build -p hyst-fmu",
        ],
        &only_lib,
    );
    let script = d.join("script.so");
    std::fs::write(&script, "#!/bin/sh\n").unwrap();
    fails(
        d,
        &script,
        &["--k1", "0.2", "--k2", "8", "-o", fmu],
        &["script.so", "not an ELF file", "cargo build -p hyst-fmu"],
        &["libhyst_fmu.so", "script.so"],
    );
    std::fs::remove_file(&script).unwrap();
}

/// A model file called *.fmu is never overwritten by its own FMU, and a failed run keeps an
/// existing FMU as it was.
#[test]
fn a_failed_run_overwrites_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let lib = fake_library(d);
    let fmu = d.join("out.fmu");
    let fmu = fmu.to_str().unwrap();
    // A model file that happens to be called *.fmu is never overwritten by its own FMU.
    let fitted = fit_piezo(d);
    let odd = d.join("model.fmu");
    std::fs::rename(&fitted, &odd).unwrap();
    let before = std::fs::read(&odd).unwrap();
    fails(
        d,
        &lib,
        &[
            "--model",
            odd.to_str().unwrap(),
            "-o",
            odd.to_str().unwrap(),
        ],
        &["model.fmu", "the model file itself"],
        &["libhyst_fmu.so", "model.fmu"],
    );
    assert_eq!(std::fs::read(&odd).unwrap(), before);

    // A failed run keeps an existing FMU as it was.
    ok(&hyst_fmu(&lib, &["--k1", "0.2", "--k2", "8", "-o", fmu]));
    let good = std::fs::read(fmu).unwrap();
    fails(
        d,
        &lib,
        &["--k1", "0", "--k2", "8", "-o", fmu],
        &["k1 = 0"],
        &["libhyst_fmu.so", "model.fmu", "out.fmu"],
    );
    assert_eq!(std::fs::read(fmu).unwrap(), good);
}
