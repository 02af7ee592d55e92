//! Progress on a terminal: `hyst fit` shows one bar with its stage, the
//! fraction done and the time left when stderr is a terminal, and nothing on a pipe or with
//! `--json`. The terminal is a pseudo-terminal from util-linux `script` (the test is skipped,
//! saying so, where it is missing).
#![cfg(unix)]
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use std::path::Path;
use std::process::Command;

fn hyst() -> &'static str {
    env!("CARGO_BIN_EXE_hyst")
}

fn piezo() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/piezo-sine/piezo_sine_1hz.csv")
        .display()
        .to_string()
}

/// What `hyst ARGS` writes to a terminal (stdout and stderr together), or `None` without
/// `script`.
fn on_terminal(args: &str) -> Option<String> {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("typescript");
    let o = Command::new("script")
        // At once: a fit of the piezo record may end within the usual second.
        .env("HYST_PROGRESS_DELAY_MS", "0")
        .arg("-qec")
        .arg(format!("{} {args}", hyst()))
        .arg(&log)
        .current_dir(dir.path())
        .output();
    match o {
        Ok(o) if o.status.success() => {
            Some(String::from_utf8_lossy(&std::fs::read(&log).unwrap()).into_owned())
        }
        Ok(o) => panic!("script failed: {}", String::from_utf8_lossy(&o.stderr)),
        Err(_) => {
            eprintln!("skipped: util-linux `script` is not installed (no pseudo-terminal)");
            None
        }
    }
}

/// The piezo record repeated 50 times (400 k rows, 11 MB): a fit long enough to draw each stage.
fn long_record(dir: &Path) -> String {
    let text = std::fs::read_to_string(piezo()).unwrap();
    let (header, rows) = text.split_once('\n').unwrap();
    let path = dir.join("long.csv");
    std::fs::write(&path, format!("{header}\n{}", rows.repeat(50))).unwrap();
    path.display().to_string()
}

#[test]
fn fit_shows_its_stages_on_a_terminal_and_nothing_with_json() {
    let data = tempfile::tempdir().unwrap();
    let fit = format!(
        "fit {} --input u_actuator_V --output y_capsensor_um -o m.toml",
        long_record(data.path())
    );
    let Some(shown) = on_terminal(&fit) else {
        return;
    };
    assert!(shown.contains("reading "), "{shown}");
    assert!(shown.contains("fit: search"), "{shown}");
    assert!(shown.contains("fit: polish"), "{shown}");
    assert!(shown.contains("fit: family widths"), "{shown}");
    assert!(shown.contains('%'), "{shown}");
    assert!(shown.contains("RMS"), "the report follows: {shown}");
    let quiet = on_terminal(&format!("{fit} --json")).unwrap();
    assert!(
        !quiet.contains("fit: ") && !quiet.contains("reading "),
        "{quiet}"
    );
}

#[test]
fn nothing_on_a_pipe() {
    let dir = tempfile::tempdir().unwrap();
    let o = Command::new(hyst())
        .args([
            "fit",
            &piezo(),
            "--input",
            "u_actuator_V",
            "--output",
            "y_capsensor_um",
            "-o",
        ])
        .arg(dir.path().join("m.toml"))
        .output()
        .unwrap();
    assert!(o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!err.contains("fit: ") && !err.contains('\r'), "{err}");
}
