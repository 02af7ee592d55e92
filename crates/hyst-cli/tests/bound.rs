//! `hyst bound` end to end: the numbers of the paper's examples (NOTES.md), JSON keys, errors.

use hyst_test_support::cli::Binary;

const HYST: Binary = Binary::new(env!("CARGO_BIN_EXE_hyst"));

fn json(args: &[&str]) -> serde_json::Value {
    let out = HYST.success(args);
    match serde_json::from_slice(&out.stdout) {
        Ok(v) => v,
        Err(e) => unreachable!("bad JSON ({e}): {}", String::from_utf8_lossy(&out.stdout)),
    }
}

fn num(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or(f64::NAN)
}

#[test]
fn example1_linear_with_output_gain() {
    let v = json(&[
        "bound",
        "--k1",
        "0.14",
        "--dk1",
        "0.1",
        "--k2",
        "8",
        "--dk2",
        "5",
        "--output-gain",
        "1.4",
        "--json",
    ]);
    assert!((num(&v["delta_a"]) - 0.1301).abs() < 5e-5, "{v}");
    assert!((num(&v["delta_b_max"]) - 0.1822).abs() < 5e-5, "{v}");
    let corners: Vec<f64> = v["corners"]
        .as_array()
        .map_or(vec![], |a| a.iter().map(num).collect());
    assert_eq!(corners.len(), 4);
    for (c, e) in corners.iter().zip([-0.1131, 0.1000, -0.1301, 0.1209]) {
        assert!((c - e).abs() < 5e-5, "{c} vs {e}");
    }
}

#[test]
fn example2_text() {
    let out = HYST.output(&[
        "bound", "--k1", "0.06", "--dk1", "0.005", "--k2", "5", "--dk2", "2.5",
    ]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("delta_a = 0.0302"), "{text}");
    let v = json(&[
        "bound", "--k1", "0.06", "--dk1", "0.005", "--k2", "5", "--dk2", "2.5", "--json",
    ]);
    assert!((num(&v["delta_b_max"]) - num(&v["delta_a"])).abs() < 1e-15);
}

#[test]
fn invalid_family_is_an_error() {
    let out = HYST.output(&[
        "bound", "--k1", "0.1", "--dk1", "0.2", "--k2", "5", "--dk2", "1",
    ]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("dk1"), "{err}");
}

/// Example 1's family with linear shaping.
const EXAMPLE1: [&str; 9] = [
    "bound", "--k1", "0.14", "--dk1", "0.1", "--k2", "8", "--dk2", "5",
];

#[test]
fn a_gain_that_is_not_positive_is_refused_naming_flag_and_value() {
    for (gain, shown) in [
        ("-1", "-1"),
        ("0", "0"),
        ("-0", "-0"),
        ("inf", "inf"),
        ("nan", "NaN"),
    ] {
        let out = HYST.output(&[&EXAMPLE1[..], &["--output-gain", gain]].concat());
        assert_eq!(out.status.code(), Some(1), "--output-gain {gain}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains(&format!(
                "--output-gain {shown}: the gain must be finite and > 0"
            )),
            "{err}"
        );
        assert!(out.stdout.is_empty(), "nothing printed for {gain}");
    }
}

#[test]
fn a_given_gain_is_always_reported() {
    // Gain 1 changes nothing, but the line says it was applied.
    let out = HYST.output(&[&EXAMPLE1[..], &["--output-gain", "1"]].concat());
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("after the output shaping (gain 1): delta_b <= 0.1301"),
        "{text}"
    );
    let out = HYST.output(&EXAMPLE1);
    assert!(!String::from_utf8_lossy(&out.stdout).contains("after the output shaping"));
}

/// Text output: significant digits at every scale, never fixed decimals (docs/fitting.md, "The
/// report"): tiny and huge parameters print their digits, not "0.0000" or 300-digit numbers.
#[test]
fn text_prints_significant_digits_at_any_scale() {
    let out = HYST.output(&[
        "bound", "--k1", "2e-6", "--dk1", "2e-7", "--k2", "5e5", "--dk2", "5e4",
    ]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.starts_with("family RH(k1 = 2e-6, dk1 = 2e-7, k2 = 500000, dk2 = 50000)\n"),
        "{text}"
    );
    let v = json(&[
        "bound", "--k1", "2e-6", "--dk1", "2e-7", "--k2", "5e5", "--dk2", "5e4", "--json",
    ]);
    let delta_a = num(&v["delta_a"]);
    assert!(delta_a > 0.0 && delta_a < 1e-6, "{v}");
    let shown = format!("delta_a = {:.3e}  (Proposition 3.2", delta_a);
    assert!(text.contains(&shown), "{shown} in {text}");
    assert!(!text.contains("0.0000"), "{text}");
    assert!(text.contains("k1bar = 1.800e-6, k2bar = 450000,"), "{text}");
    let out = HYST.output(&[
        "bound", "--k1", "1e-300", "--dk1", "1e-301", "--k2", "1e300", "--dk2", "1e299",
    ]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.starts_with("family RH(k1 = 1e-300, dk1 = 1e-301, k2 = 1e300, dk2 = 1e299)\n"),
        "{text}"
    );
    assert!(text.lines().all(|l| l.len() < 120), "{text}");
    assert!(text.contains("k2bar = 9.000e299"), "{text}");
}

/// k1 above MAX / 4 and a gain that overflows the bound are
/// refused with status 1, naming the value, instead of printing inf and NaN.
#[test]
fn a_bound_beyond_the_float_range_is_refused() {
    let out = HYST.output(&[
        "bound", "--k1", "1e308", "--dk1", "9e307", "--k2", "1", "--dk2", ".5",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("k1") && err.contains("MAX / 4"), "{err}");
    assert!(out.stdout.is_empty());
    // Δa ≥ Δk1 = 2 here: times 1e308 it is beyond the float range.
    let wide = [
        "bound", "--k1", "3", "--dk1", "2", "--k2", "8", "--dk2", "5",
    ];
    let out = HYST.output(&[&wide[..], &["--output-gain", "1e308"]].concat());
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--output-gain 1e308") && err.contains("beyond"),
        "{err}"
    );
    for args in [
        &[
            "bound", "--k1", "1e308", "--dk1", "9e307", "--k2", "1", "--dk2", ".5", "--json",
        ][..],
        &[&wide[..], &["--output-gain", "1e308", "--json"]].concat(),
    ] {
        let out = HYST.output(args);
        assert_eq!(out.status.code(), Some(1));
        assert!(!String::from_utf8_lossy(&out.stdout).contains("null"));
    }
}
