//! `hyst-bench`: hyst's inverse and the plain-C peer measured in one run, the ratio the quotient
//! of the two figures it reports, and the goal's verdict that ratio's.
#![allow(missing_docs, clippy::unwrap_used, clippy::expect_used)]

use std::process::Command;

fn hyst_bench(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_hyst-bench"))
        .args(args)
        .output()
        .expect("runs hyst-bench")
}

#[test]
fn the_peer_comparison_reports_both_figures_and_their_ratio() {
    let o = hyst_bench(&["--json", "--seconds", "0.05"]);
    assert!(o.status.success(), "{o:?}");
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let ns = |key: &str| json[key].as_f64().unwrap_or(f64::NAN);
    let (inverse, peer) = (ns("inverse_ns"), ns("c_peer_ns"));
    assert!(inverse > 0.0 && inverse.is_finite(), "{json}");
    assert!(peer > 0.0 && peer.is_finite(), "{json}");
    let ratio = ns("inverse_over_c_peer");
    assert!((ratio - inverse / peer).abs() <= 1e-12 * ratio, "{json}");
    assert_eq!(json["c_peer_goal_met"].as_bool(), Some(ratio <= 1.0));

    let text = hyst_bench(&["--seconds", "0.05"]);
    assert!(text.status.success(), "{text:?}");
    let text = String::from_utf8(text.stdout).unwrap();
    for row in [
        "inverse operator H^-1 (eq. 4)",
        "plain-C inverse (peer, no checks)",
        "goal inverse <= 1.0 x plain-C peer:",
    ] {
        assert!(text.contains(row), "{text}");
    }
    for bad in [["--seconds", "0"], ["--seconds", "61"]] {
        let o = hyst_bench(&bad);
        assert!(!o.status.success());
        assert!(String::from_utf8_lossy(&o.stderr).contains("--seconds"));
    }
}
