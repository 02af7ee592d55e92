//! One word per concept on every surface: the vocabulary table of docs/architecture.md
//! ("Vocabulary") checked against what the CLI, the Python stubs, the C header, the FMU and the
//! Rust crates expose, so that a name drifting on one surface fails here.
//!
//! - every name in a surface's column of the concept table is on that surface (a whole token:
//!   `--k1` is not found inside `--dk1`);
//! - no name of the "Old names" table is exposed by the CLI's help, the Python stubs, the C
//!   header or the Rust sources any more;
//! - the documentation of the inverses (H⁻¹, the shaped model's inverse, `--inverse`) does not
//!   call them a compensator: that word is Lemma 5.1's alone;
//! - every `cargo install` of this project that README.md and docs/ show is `--locked`: it
//!   builds with the dependency versions of Cargo.lock, those the tests ran with.
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

/// The code of every `.rs` file under `dir` (recursively), without its comments: names in
/// prose are not what a surface exposes.
fn sources(dir: &Path, out: &mut String) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let text = std::fs::read_to_string(&path).unwrap_or_default();
            for line in text.lines() {
                out.push_str(line.split("//").next().unwrap_or(""));
                out.push('\n');
            }
        }
    }
}

/// The Rust sources of every crate's `src/`.
fn rust_sources() -> String {
    let mut out = String::new();
    let crates = root().join("crates");
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(&crates)
        .expect("crates/")
        .filter_map(|e| e.ok().map(|e| e.path().join("src")))
        .collect();
    dirs.sort();
    for dir in dirs {
        sources(&dir, &mut out);
    }
    out
}

/// What the CLI exposes: every command's help, the JSON of `hyst bound`, and the header of a
/// `hyst run` output.
fn cli_surface() -> String {
    let mut text = HYST.stdout(&["--help"]);
    for command in [
        "run", "bound", "paper", "fit", "fmu", "bench", "export", "adapt",
    ] {
        text += &HYST.stdout(&[command, "--help"]);
    }
    for language in ["c", "rust"] {
        text += &HYST.stdout(&["export", language, "--help"]);
    }
    text += &HYST.stdout(&[
        "bound", "--k1", "0.14", "--dk1", "0.1", "--k2", "8", "--dk2", "5", "--json",
    ]);
    let dir = std::env::temp_dir().join(format!("hyst-vocabulary-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temporary folder");
    let input = dir.join("x.csv");
    std::fs::write(&input, "x\n0\n0.5\n").expect("writes the input");
    let output = dir.join("y.csv");
    HYST.stdout(&[
        "run",
        "--k1",
        "0.2",
        "--k2",
        "8",
        input.to_str().expect("utf-8 path"),
        "-o",
        output.to_str().expect("utf-8 path"),
    ]);
    text += &std::fs::read_to_string(&output).expect("reads the output");
    let _ = std::fs::remove_dir_all(&dir);
    text
}

/// Whether `name` occurs in `text` as a whole token (not inside a longer name).
fn has_token(text: &str, name: &str) -> bool {
    let word = |c: char| c.is_alphanumeric() || c == '_' || c == '-';
    text.match_indices(name).any(|(i, _)| {
        let before = text[..i].chars().next_back();
        let after = text[i + name.len()..].chars().next();
        // A name ending in a word character must not run on; a leading `-` belongs to a flag.
        before.is_none_or(|c| !word(c) || name.starts_with('-') && c == ' ')
            && after.is_none_or(|c| !word(c))
    })
}

/// The rows of the first markdown table at or after `marker` (cells trimmed), header excluded.
fn table_after(text: &str, marker: &str) -> Vec<Vec<String>> {
    let start = text.find(marker).unwrap_or_else(|| panic!("no {marker:?}"));
    text[start..]
        .lines()
        .skip_while(|l| !l.starts_with('|'))
        .take_while(|l| l.starts_with('|'))
        .skip(2)
        .map(|l| {
            l.trim_matches('|')
                .split('|')
                .map(|c| c.trim().to_string())
                .collect()
        })
        .collect()
}

/// The names in backticks of one table cell.
fn names(cell: &str) -> Vec<String> {
    cell.split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

const COLUMNS: [&str; 5] = ["Rust", "CLI", "Python", "C", "FMU"];

#[test]
fn every_surface_uses_the_names_of_the_vocabulary_table() {
    let doc = read("docs/architecture.md");
    let vocabulary = &doc[doc.find("## Vocabulary").expect("a Vocabulary section")..];
    let header: Vec<String> = vocabulary
        .lines()
        .find(|l| l.starts_with('|'))
        .expect("the concept table")
        .trim_matches('|')
        .split('|')
        .map(|c| c.trim().to_string())
        .collect();
    let rows = table_after(vocabulary, "| concept |");
    assert!(
        rows.len() >= 20,
        "the concept table has {} rows",
        rows.len()
    );

    let surfaces = [
        rust_sources(),
        cli_surface(),
        read("crates/hyst-py/python/hyst/_hyst.pyi")
            + &read("crates/hyst-py/python/hyst/__init__.py"),
        read("include/hyst.h"),
        {
            let mut fmu = String::new();
            sources(&root().join("crates/hyst-fmu/src"), &mut fmu);
            sources(&root().join("crates/hyst-cli/src/fmu"), &mut fmu);
            fmu
        },
    ];
    let mut missing = Vec::new();
    for row in &rows {
        for (surface, column) in surfaces.iter().zip(COLUMNS) {
            let index = header
                .iter()
                .position(|h| h == column)
                .unwrap_or_else(|| panic!("no column {column}"));
            for name in names(&row[index]) {
                if !has_token(surface, &name) {
                    missing.push(format!("{column}: `{name}` ({})", row[0]));
                }
            }
        }
    }
    assert!(
        missing.is_empty(),
        "names of the vocabulary table that their surface does not expose:\n{}",
        missing.join("\n")
    );
}

/// Whether the Python stub defines `name`: a class, a function or method, a parameter or
/// attribute (`name: …`, `name = …`), or a literal value (`"name"`). Prose in docstrings may
/// use the word.
fn python_defines(stub: &str, name: &str) -> bool {
    stub.lines().any(|line| {
        let code = line.trim_start();
        code.strip_prefix("def ")
            .or_else(|| code.strip_prefix("class "))
            .is_some_and(|rest| has_token(rest.split('(').next().unwrap_or(""), name))
            || code
                .strip_prefix(name)
                .is_some_and(|rest| rest.trim_start().starts_with([':', '=']))
            || line.contains(&format!("\"{name}\""))
            || line.contains(&format!(", {name}:")) && line.contains("def ")
            || line.contains(&format!("({name}:")) && line.contains("def ")
    })
}

/// The C header without its comments: the names it declares.
fn c_declarations(header: &str) -> String {
    let mut out = String::new();
    let mut rest = header;
    while let Some(start) = rest.find("/*") {
        out.push_str(&rest[..start]);
        rest = rest[start..]
            .find("*/")
            .map_or("", |end| &rest[start + end + 2..]);
    }
    out.push_str(rest);
    out.lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn no_surface_exposes_an_old_name() {
    let doc = read("docs/architecture.md");
    let vocabulary = &doc[doc.find("## Vocabulary").expect("a Vocabulary section")..];
    let old = table_after(vocabulary, "| old | new |");
    assert!(old.len() >= 8, "the old-names table has {} rows", old.len());
    let help = {
        let mut text = HYST.stdout(&["--help"]);
        for command in [
            "run", "bound", "paper", "fit", "fmu", "bench", "export", "adapt",
        ] {
            text += &HYST.stdout(&[command, "--help"]);
        }
        for language in ["c", "rust"] {
            text += &HYST.stdout(&["export", language, "--help"]);
        }
        text
    };
    let stub = read("crates/hyst-py/python/hyst/_hyst.pyi");
    let header = c_declarations(&read("include/hyst.h"));
    let rust = rust_sources();
    let mut found = Vec::new();
    for row in &old {
        for name in names(&row[0]) {
            for surface in row[2].split(',').map(str::trim) {
                let exposed = match surface {
                    "CLI" => has_token(&help, &name),
                    "Python" => python_defines(&stub, &name),
                    "C" => has_token(&header, &name),
                    // The Rust code names an old spelling only where it still accepts it (a
                    // serde or clap alias).
                    "Rust" => rust
                        .lines()
                        .any(|l| has_token(l, &name) && !l.contains("alias")),
                    other => panic!("unknown surface {other:?} in the old-names table"),
                };
                if exposed {
                    found.push(format!("`{name}` on the {surface} surface"));
                }
            }
        }
    }
    assert!(
        found.is_empty(),
        "old names still exposed:\n{}",
        found.join("\n")
    );
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
