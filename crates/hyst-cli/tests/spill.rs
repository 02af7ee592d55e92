//! Integration tests of long columns held in temporary files (`hyst_io::Samples`): a fit with
//! every column spilled (`HYST_SPILL_AFTER=0`) writes the model a fit with every column held
//! writes, and a bad setting is refused by name.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use std::ffi::OsStr;
use std::path::Path;
use std::process::Output;

use hyst_test_support::cli::Binary;
use hyst_test_support::files::{piezo, piezo_fit, repo};

const HYST: Binary = Binary::new(env!("CARGO_BIN_EXE_hyst"));

/// `hyst ARGS` with the environment variables `env` set (`HYST_SPILL_AFTER` unset unless
/// `env` sets it).
fn hyst(args: &[&str], env: &[(&str, &OsStr)]) -> Output {
    HYST.command()
        .args(args)
        .env_remove("HYST_SPILL_AFTER")
        .envs(env.iter().copied())
        .output()
        .unwrap()
}

/// A model file without the lines that differ from run to run (timings, the command, the
/// time it was written).
fn stable(model: &Path) -> String {
    std::fs::read_to_string(model)
        .unwrap()
        .lines()
        .filter(|l| {
            !["fit_seconds", "ns_per_sample", "created_unix", "command"]
                .iter()
                .any(|key| l.starts_with(key))
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn a_fit_from_spilled_columns_writes_the_model_a_fit_from_held_ones_writes() {
    let dir = tempfile::tempdir().unwrap();
    let data = repo().join("data");
    let steel = data.join("bh-loops/m130_27s_steel_loops.csv");
    let piezo = piezo();
    // The steel loops with their rows dealt round-robin: each record gathered from every
    // other row, not taken as one run.
    let dealt = dir.path().join("dealt.csv");
    std::fs::write(
        &dealt,
        dealt_rows(&std::fs::read_to_string(&steel).unwrap()),
    )
    .unwrap();
    let cases: [(&str, &Path, &[&str]); 3] = [
        (
            "dealt",
            &dealt,
            &["--input", "H_A_per_m", "--output", "B_T"],
        ),
        (
            "steel",
            &steel,
            &[
                "--input",
                "H_A_per_m",
                "--output",
                "B_T",
                "--validate-every",
                "3",
            ],
        ),
        (
            "piezo",
            &piezo,
            &[
                "--input",
                "u_actuator_V",
                "--output",
                "y_capsensor_um",
                "--segment",
                "3000",
            ],
        ),
    ];
    for (name, file, options) in cases {
        let mut models = Vec::new();
        for spill in [None, Some("0")] {
            let model = dir.path().join(format!("{name}-{}.toml", spill.is_some()));
            let mut args = vec!["fit", file.to_str().unwrap()];
            args.extend_from_slice(options);
            args.extend_from_slice(&["-o", model.to_str().unwrap()]);
            let env = spill.map(|v| ("HYST_SPILL_AFTER", OsStr::new(v)));
            let out = hyst(&args, env.as_slice());
            assert!(
                out.status.success(),
                "{name} {spill:?}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            models.push(stable(&model));
        }
        assert_eq!(models[0], models[1], "{name}");
    }
}

/// The CSV `text` (header `loop,…`) with the rows of its loops dealt in turn: the first row
/// of each loop, then the second of each, …
fn dealt_rows(text: &str) -> String {
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header = lines.next().unwrap();
    assert!(header.starts_with("loop,"), "{header}");
    let mut loops: Vec<(String, Vec<&str>)> = Vec::new();
    for line in lines {
        let id = line.split(',').next().unwrap().to_string();
        match loops.iter_mut().find(|(l, _)| *l == id) {
            Some((_, rows)) => rows.push(line),
            None => loops.push((id, vec![line])),
        }
    }
    assert!(loops.len() > 1);
    let longest = loops.iter().map(|(_, r)| r.len()).max().unwrap();
    let mut out = format!("{header}\n");
    for i in 0..longest {
        for (_, rows) in &loops {
            if let Some(row) = rows.get(i) {
                out += row;
                out.push('\n');
            }
        }
    }
    out
}

#[test]
fn a_bad_spill_setting_is_refused_by_name_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("m.toml");
    let piezo = piezo();
    let args = piezo_fit(&piezo, &model);
    for bad in ["lots", "-1", "1.5"] {
        let out = hyst(&args, &[("HYST_SPILL_AFTER", OsStr::new(bad))]);
        assert!(!out.status.success());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains(&format!("HYST_SPILL_AFTER=\"{bad}\"")) && err.contains("whole number"),
            "{err}"
        );
        assert!(!model.exists());
    }
}

#[test]
fn a_temporary_directory_that_cannot_hold_the_column_is_named_with_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("m.toml");
    let missing = dir.path().join("no-such-dir");
    let piezo = piezo();
    let out = hyst(
        &piezo_fit(&piezo, &model),
        &[
            ("HYST_SPILL_AFTER", OsStr::new("0")),
            ("TMPDIR", missing.as_os_str()),
        ],
    );
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(&format!(
            "{}: cannot keep a long column in a temporary file in {}",
            piezo.display(),
            missing.display()
        )) && err.contains("TMPDIR"),
        "{err}"
    );
    assert!(!model.exists());
}
