//! `hyst paper` end to end: every figure is written, the summary has the required keys, the
//! bounds match NOTES.md, Example 2's compensation error stays within its bound and Example 3's is
//! the measured one.

use hyst_test_support::cli::Binary;

const HYST: Binary = Binary::new(env!("CARGO_BIN_EXE_hyst"));

#[test]
fn paper_writes_figures_and_summary() {
    let dir = std::env::temp_dir().join(format!("hyst-paper-test-{}", std::process::id()));
    let out = match HYST.command().args(["paper", "--out"]).arg(&dir).output() {
        Ok(o) => o,
        Err(e) => unreachable!("cannot run hyst: {e}"),
    };
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("quantity") && stdout.contains("0.1301"),
        "{stdout}"
    );
    let text = std::fs::read_to_string(dir.join("summary.json")).unwrap_or_default();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap_or(serde_json::Value::Null);
    let num = |p: &str| v.pointer(p).and_then(|x| x.as_f64()).unwrap_or(f64::NAN);
    assert!((num("/bounds/example1_linear") - 0.1301).abs() < 5e-5);
    assert!((num("/bounds/example1_linear_shaped") - 0.1822).abs() < 5e-5);
    assert!((num("/bounds/example1_nonlinear/k2_5") - 0.0229).abs() < 5e-5);
    assert!((num("/bounds/example1_nonlinear/k2_12") - 0.0102).abs() < 5e-5);
    assert!((num("/bounds/example2") - 0.0302).abs() < 5e-5);
    let e2 = num("/example2/max_compensation_error");
    assert!(e2 > 0.0 && e2 <= num("/example2/bound"), "{e2}");
    assert!(num("/example2/max_force_n") > 0.0 && num("/example2/max_force_error_n") >= 0.0);
    // Example 3 after 10 s: measured 0.1354 m, the backlash corners H(0.2, 8) rounds off (the
    // uncompensated output lags by the play's half-width, 0.2 m).
    let e3 = num("/example3/max_compensation_error");
    assert!((0.13..0.14).contains(&e3), "{e3}");
    let figures = v["figures"].as_array().cloned().unwrap_or_default();
    assert_eq!(figures.len(), 10);
    for f in figures {
        let path = f.as_str().unwrap_or("");
        let len = std::fs::metadata(path).map(|m| m.len()).unwrap_or(0);
        assert!(len > 10_000, "{path}: {len} bytes");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
