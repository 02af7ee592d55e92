//! Integration tests of text record columns in `hyst fit`: a CSV's text
//! columns are accepted where they are not used as numbers, and a text `record` column gives
//! record labels numbered in order of first appearance.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use hyst_test_support::cli::{stderr, Binary};
use hyst_test_support::files::s;

const HYST: Binary = Binary::new(env!("CARGO_BIN_EXE_hyst"));

/// Every 16th row of each record of the friction damper file (a debug-mode fit of all its
/// 154k rows takes half a minute), written twice: with its text `record` labels as they are,
/// and with the labels replaced by numbers 0, 1, … in order of first appearance.
fn damper_files(dir: &Path) -> (PathBuf, PathBuf) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/friction-damper/friction_damper_sines.csv");
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    assert!(header.starts_with("record,"), "{header}");
    let (mut labelled, mut numbered) = (format!("{header}\n"), format!("{header}\n"));
    let mut ids: HashMap<String, usize> = HashMap::new();
    let mut seen: HashMap<String, usize> = HashMap::new();
    for line in lines {
        let (label, rest) = line.split_once(',').unwrap();
        let count = seen.entry(label.to_string()).or_insert(0);
        *count += 1;
        if !(*count - 1).is_multiple_of(16) {
            continue;
        }
        let next = ids.len();
        let id = *ids.entry(label.to_string()).or_insert(next);
        labelled.push_str(&format!("{label},{rest}\n"));
        numbered.push_str(&format!("{id},{rest}\n"));
    }
    assert_eq!(ids.len(), 10, "the file holds 10 records");
    let a = dir.join("labelled.csv");
    let b = dir.join("numbered.csv");
    std::fs::write(&a, labelled).unwrap();
    std::fs::write(&b, numbered).unwrap();
    (a, b)
}

/// The `"parameters": [...]` array of a `--json` report.
fn parameters(json: &str) -> String {
    let start = json.find("\"parameters\": [").expect(json);
    let end = start + json[start..].find(']').unwrap();
    json[start..=end].to_string()
}

/// `hyst fit DATA --input x_mm --output force_kN EXTRA --json`: the report's parameters.
fn fit(data: &Path, model: &Path, extra: &[&str]) -> String {
    let mut args = vec![
        "fit",
        s(data),
        "--input",
        "x_mm",
        "--output",
        "force_kN",
        "-o",
        s(model),
        "--json",
    ];
    args.extend_from_slice(extra);
    let out = HYST.output(&args);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    parameters(&String::from_utf8_lossy(&out.stdout))
}

#[test]
fn a_text_record_column_fits_as_numbered_records() {
    let dir = tempfile::tempdir().unwrap();
    let (labelled, numbered) = damper_files(dir.path());
    let model = dir.path().join("m.toml");
    let by_label = fit(&labelled, &model, &[]);
    assert!(by_label.contains("\"k2\""), "{by_label}");
    assert_eq!(by_label, fit(&numbered, &model, &[]));

    // --validate takes the record numbers.
    let held = ["--validate", "3,4,5,9"];
    let by_label = fit(&labelled, &model, &held);
    assert_eq!(by_label, fit(&numbered, &model, &held));

    // A record that does not exist: the records are listed with their labels.
    let out = HYST.output(&[
        "fit",
        s(&labelled),
        "--input",
        "x_mm",
        "--output",
        "force_kN",
        "-o",
        s(&model),
        "--validate",
        "12",
    ]);
    assert!(!out.status.success());
    let err = stderr(&out);
    assert!(
        err.contains("no record 12 to hold out for validation (records: 0 (\"f0.25Hz_a0.5in_T30lb\"), 1 (\"f0.25Hz_a1.0in_T30lb\")"),
        "{err}"
    );
}

#[test]
fn a_text_column_used_as_numbers_is_refused_as_before() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("d.csv");
    std::fs::write(&data, "x,y,note\n0,0,a\n1,1,b\n2,3,c\n1,2,d\n0,0,e\n").unwrap();
    let out = HYST.output(&[
        "fit",
        s(&data),
        "--input",
        "x",
        "--output",
        "note",
        "-o",
        s(&dir.path().join("m.toml")),
    ]);
    assert!(!out.status.success());
    let err = stderr(&out);
    assert!(
        err.contains(&format!(
            "{}:2: column 3 (\"note\"): cannot parse \"a\" as a number",
            data.display()
        )),
        "{err}"
    );
}
