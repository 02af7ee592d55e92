//! What the vocabulary script (scripts/check-vocabulary, docs/vocabulary.toml) does not read:
//!
//! - the documentation of the inverses (H⁻¹, the shaped model's inverse, `--inverse`) does not
//!   call them a compensator: that word is Lemma 5.1's alone;
//! - every `cargo install` of this project that README.md and docs/ show is `--locked`: it
//!   builds with the dependency versions of Cargo.lock, those the tests ran with;
//! - old spellings of flags still parse, with a note.
// A test reports a broken surface by panicking with what it found.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use hyst_test_support::cli::Binary;
use std::path::{Path, PathBuf};

const HYST: Binary = Binary::new(env!("CARGO_BIN_EXE_hyst"));

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn read(path: &str) -> String {
    std::fs::read_to_string(root().join(path)).unwrap_or_else(|e| panic!("{path}: {e}"))
}

#[test]
fn an_inverse_is_never_called_a_compensator() {
    // The comment lines cbindgen writes directly above a C declaration.
    let header = read("include/hyst.h");
    let doc_above = |declaration: &str| -> String {
        let lines: Vec<&str> = header.lines().collect();
        let at = lines
            .iter()
            .position(|l| l.contains(declaration))
            .unwrap_or_else(|| panic!("no {declaration} in include/hyst.h"));
        let start = lines[..at]
            .iter()
            .rposition(|l| !l.trim_start().starts_with("//"))
            .map_or(0, |i| i + 1);
        assert!(start < at, "{declaration} has no comment above it");
        lines[start..at].join("\n")
    };
    let mut said = Vec::new();
    for declaration in [
        "hyst_operator_init_inverse(",
        "hyst_shaped_model_init_inverse(",
    ] {
        if doc_above(declaration)
            .to_lowercase()
            .contains("compensator")
        {
            said.push(format!("include/hyst.h, {declaration}"));
        }
    }
    let stub = read("crates/hyst-py/python/hyst/_hyst.pyi");
    let class = stub
        .split("class InverseHysteresis")
        .nth(1)
        .and_then(|rest| rest.split("\nclass ").next())
        .unwrap_or("");
    if class.to_lowercase().contains("compensator") {
        said.push("the stub's InverseHysteresis".into());
    }
    let run = HYST.stdout(&["run", "--help"]);
    let inverse = run
        .split("--inverse")
        .nth(1)
        .and_then(|rest| rest.split("\n  -").next())
        .unwrap_or("");
    if inverse.to_lowercase().contains("compensator") {
        said.push("hyst run --help, --inverse".into());
    }
    assert!(said.is_empty(), "an inverse called a compensator: {said:?}");
}

/// `cargo install --path crates/…` (this project) in README.md and docs/ always with `--locked`:
/// without it cargo resolves the dependencies afresh and may build versions no test ran with.
#[test]
fn every_cargo_install_of_this_project_is_locked() {
    let mut pages = vec!["README.md".to_string()];
    for entry in std::fs::read_dir(root().join("docs")).unwrap() {
        let name = entry.unwrap().file_name().into_string().unwrap();
        if name.ends_with(".md") {
            pages.push(format!("docs/{name}"));
        }
    }
    let mut shown = 0;
    for page in pages {
        let text = read(&page);
        for (i, line) in text.lines().enumerate() {
            let Some(at) = line.find("cargo install") else {
                continue;
            };
            let command = line[at..].split('`').next().unwrap_or_default();
            if command.contains("--path") {
                shown += 1;
                assert!(
                    command.contains("--locked"),
                    "{page}:{}: `{command}` without --locked",
                    i + 1
                );
            }
        }
    }
    assert!(shown > 0, "no page shows how to install hyst");
}

/// Each flag has one meaning on every subcommand (`-o`/`--out`: what the command writes); the
/// old spellings still parse, with a note that names the new flag, and the new ones give none.
#[test]
fn old_spellings_of_flags_still_work_with_a_note() {
    let dir = std::env::temp_dir().join(format!("hyst-spelling-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temporary folder");
    let input = dir.join("x.csv");
    std::fs::write(&input, "x\n0\n0.5\n").expect("writes the input");
    let path = |name: &str| dir.join(name).to_str().expect("utf-8 path").to_string();
    let run = |args: &[&str]| HYST.output(args);
    let x = path("x.csv");
    for (flag, name) in [
        ("--output", "old.csv"),
        ("--out", "new.csv"),
        ("-o", "short.csv"),
    ] {
        let out = run(&["run", "--k1", "0.2", "--k2", "8", &x, flag, &path(name)]);
        assert!(out.status.success(), "{flag}: {out:?}");
        assert!(dir.join(name).exists(), "{flag} wrote no {name}");
        let err = String::from_utf8_lossy(&out.stderr);
        let noted = err.contains("`hyst run --output` is the old spelling of -o/--out");
        assert_eq!(noted, flag == "--output", "{flag}: {err}");
    }
    // fit's and adapt's old spellings parse (the data is missing: the note comes before that
    // error), and fit's `--output` stays its output column.
    let missing = path("missing.csv");
    for (args, old) in [
        (
            vec![
                "fit",
                &missing,
                "--input",
                "x",
                "--output",
                "y",
                "--model-out",
                "m.toml",
            ],
            "--model-out",
        ),
        (
            vec![
                "adapt",
                "--model",
                "m.toml",
                &missing,
                "--output-file",
                "a.csv",
            ],
            "--output-file",
        ),
    ] {
        let out = run(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert!(
            err.contains(&format!("{old}` is the old spelling of -o/--out")),
            "{err}"
        );
        assert!(!err.contains("unexpected argument"), "{err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
