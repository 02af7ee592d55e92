//! Integration tests of `hyst run` with several `--column`s: one operator per column, each
//! column's output the same as a run of that column alone (bit for bit on the scalar path:
//! models, derivatives; within a stated tolerance on the bank path: `--k1/--k2` without
//! derivatives), records restarting every column, and errors that name the file, line,
//! column and value.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod common;
use common::read_csv;

fn hyst(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hyst"))
        .args(args)
        .output()
        .unwrap()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn corpus(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fuzz/corpus/model_file")
        .join(name)
}

/// Runs `hyst run ARGS INPUT -o OUTPUT`; returns the header and the rows.
fn run_ok(args: &[&str], input: &Path, output: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let mut all = vec!["run"];
    all.extend_from_slice(args);
    all.extend_from_slice(&[s(input), "-o", s(output)]);
    let out = hyst(&all);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    read_csv(output)
}

/// Three signals with many reversals, at different scales (one of them far beyond the band),
/// a fourth that the model files read (column u_actuator_V, in volts), and a record column.
fn signals(dir: &Path) -> PathBuf {
    let path = dir.join("signals.csv");
    let mut text = String::from("t,a,b,c,u_actuator_V,curve\n");
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut walk = 0.0;
    for i in 0..9000 {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        walk += ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.3;
        let t = i as f64 * 1e-3;
        let a = (t * 7.0).sin() * (0.5 + 0.3 * t) + 0.2 * (t * 23.0).sin();
        let b = 40.0 * (t * 3.0).cos();
        let u = 1.8 + 1.5 * (t * 5.0).sin();
        // Records of uneven lengths that cross the 4,096-row blocks.
        let curve = (i / 1700) % 3;
        text += &format!("{t},{a},{b},{walk},{u},{curve}\n");
    }
    std::fs::write(&path, text).unwrap();
    path
}

/// The bank's stated agreement with the scalar operator: |Δy| ≤ 1e-13 · max(|y|, k1), a few
/// hundred ulp at most (measured: ≤ 16 ulp).
fn close(bank: f64, scalar: f64, k1: f64) -> bool {
    (bank - scalar).abs() <= 1e-13 * scalar.abs().max(k1)
}

#[test]
fn several_plain_columns_equal_their_single_runs_within_the_tolerance() {
    let dir = tempfile::tempdir().unwrap();
    let input = signals(dir.path());
    let out = dir.path().join("out.csv");
    for inverse in [false, true] {
        for record in [false, true] {
            let mut args = vec!["--k1", "0.2", "--k2", "8"];
            if inverse {
                args.push("--inverse");
            }
            if record {
                args.extend(["--record", "curve"]);
            }
            let mut all = args.clone();
            all.extend(["--column", "a", "--column", "b", "--column", "c"]);
            let (header, together) = run_ok(&all, &input, &out);
            let mut expected: Vec<String> = ["a", "b", "c", "y_a", "y_b", "y_c"]
                .map(String::from)
                .to_vec();
            if record {
                expected.push("curve".into());
            }
            assert_eq!(header, expected);
            assert_eq!(together.len(), 9000);
            for (k, column) in ["a", "b", "c"].iter().enumerate() {
                let mut alone_args = args.clone();
                alone_args.extend(["--column", column]);
                let (_, alone) = run_ok(&alone_args, &input, &dir.path().join("alone.csv"));
                for (i, (t, a)) in together.iter().zip(&alone).enumerate() {
                    assert_eq!(t[k], a[0], "{all:?} row {i}: the input is copied");
                    let (yb, ys) = (t[3 + k], a[1]);
                    assert!(
                        close(yb, ys, 0.2),
                        "{all:?}, column {column}, row {i}: bank {yb} vs alone {ys}"
                    );
                    if record {
                        assert_eq!(t[6], a[2]);
                    }
                }
                // The outputs do move off the line y = x (a test that could not fail otherwise).
                let moved = alone.iter().filter(|r| r[0] != r[1]).count();
                assert!(moved > 1000, "{column}: {moved} outputs off the line y = x");
            }
        }
    }
}

#[test]
fn records_restart_every_column() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.csv");
    // Record 1 repeats record 0's samples: restarted, its outputs are record 0's.
    let samples = [0.0, 0.5, 1.0, 0.2, -0.4, 0.3];
    let mut text = String::from("a,b,r\n");
    for r in 0..2 {
        for x in samples {
            text += &format!("{x},{},{r}\n", -2.0 * x);
        }
    }
    std::fs::write(&input, text).unwrap();
    for extra in [&[][..], &["--inverse"][..], &["--derivatives", "0"][..]] {
        let mut args = vec!["--k1", "0.3", "--k2", "5", "--record", "r"];
        args.extend_from_slice(extra);
        args.extend(["--column", "a", "--column", "b"]);
        let (_, rows) = run_ok(&args, &input, &dir.path().join("out.csv"));
        let n = samples.len();
        for i in 0..n {
            assert_eq!(rows[i][2..4], rows[i + n][2..4], "{args:?} row {i}");
        }
        assert_ne!(rows[1][2], rows[1][0], "the operator moves off the line");
    }
}

#[test]
fn the_scalar_path_gives_the_single_runs_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.csv");
    let mut text = String::from("a,a_d1,a_d2,b,b_d1,b_d2,u_actuator_V,v,curve\n");
    for i in 0..5000 {
        let t = i as f64 * 1e-3;
        let (a, da, dda) = (
            (t * 7.0).sin(),
            7.0 * (t * 7.0).cos(),
            -49.0 * (t * 7.0).sin(),
        );
        let b = 0.3 * (t * 2.0).cos();
        let u = 1.8 + 1.5 * (t * 5.0).sin();
        let v = 1.5 + (t * 11.0).cos();
        text += &format!(
            "{a},{da},{dda},{b},{},{},{u},{v},{}\n",
            -0.6 * (t * 2.0).sin(),
            -1.2 * (t * 2.0).cos(),
            i / 1300
        );
    }
    std::fs::write(&input, text).unwrap();
    let smooth = corpus("smooth.toml");
    let pi = corpus("pi.toml");
    let cases: Vec<(Vec<&str>, [&str; 2])> = vec![
        (
            vec!["--k1", "0.2", "--k2", "8", "--derivatives", "2"],
            ["a", "b"],
        ),
        (
            vec![
                "--k1",
                "0.2",
                "--k2",
                "8",
                "--inverse",
                "--derivatives",
                "1",
                "--record",
                "curve",
            ],
            ["a", "b"],
        ),
        (vec!["--model", s(&smooth)], ["u_actuator_V", "v"]),
        (
            vec!["--model", s(&smooth), "--record", "curve"],
            ["u_actuator_V", "v"],
        ),
        (vec!["--model", s(&pi)], ["u_actuator_V", "v"]),
    ];
    for (args, columns) in cases {
        let mut all = args.clone();
        all.extend(["--column", columns[0], "--column", columns[1]]);
        let (header, together) = run_ok(&all, &input, &dir.path().join("out.csv"));
        let n: usize = args
            .iter()
            .position(|a| *a == "--derivatives")
            .map_or(0, |i| args[i + 1].parse().unwrap());
        let record = args.contains(&"--record");
        assert_eq!(
            header.len(),
            2 * (2 + n) + usize::from(record),
            "{header:?}"
        );
        for (k, column) in columns.iter().enumerate() {
            assert_eq!(header[2 + k], format!("y_{column}"));
            let mut alone_args = args.clone();
            alone_args.extend(["--column", column]);
            let (_, alone) = run_ok(&alone_args, &input, &dir.path().join("alone.csv"));
            for (i, (t, a)) in together.iter().zip(&alone).enumerate() {
                assert_eq!(t[k], a[0], "{all:?} row {i}");
                assert_eq!(t[2 + k], a[1], "{all:?} row {i}: y_{column}");
                for d in 0..n {
                    assert_eq!(
                        t[4 + k * n + d],
                        a[2 + d],
                        "{all:?} row {i}: y_{column}_d{d}"
                    );
                }
            }
        }
    }
}

fn fails(args: &[&str], input: &str, expected: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let in_path = dir.path().join("data.csv");
    std::fs::write(&in_path, input).unwrap();
    let out_path = dir.path().join("out.csv");
    std::fs::write(&out_path, "previous contents\n").unwrap();
    let mut all = vec!["run"];
    all.extend_from_slice(args);
    all.extend_from_slice(&[s(&in_path), "-o", s(&out_path)]);
    let out = hyst(&all);
    assert!(!out.status.success(), "{args:?} succeeded");
    let stderr = String::from_utf8_lossy(&out.stderr);
    for e in expected {
        assert!(
            stderr.contains(e),
            "{args:?}: stderr {stderr:?} lacks {e:?}"
        );
    }
    assert_eq!(
        std::fs::read_to_string(&out_path).unwrap(),
        "previous contents\n"
    );
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        2,
        "leftovers"
    );
}

#[test]
fn errors_name_the_file_line_column_and_value() {
    let k = ["--k1", "0.2", "--k2", "8", "--column", "a", "--column", "b"];
    let mut long = String::from("a,b\n");
    for i in 0..6000 {
        long += &format!("{},{}\n", (i as f64 * 0.01).sin(), (i as f64 * 0.02).cos());
    }
    let mut bad = long.clone();
    bad += "1,oops\n";
    fails(
        &k,
        &bad,
        &["data.csv:6002: column 2 (\"b\"): cannot parse \"oops\""],
    );
    let mut bad = long.clone();
    bad += "inf,1\n";
    fails(&k, &bad, &["data.csv:6002", "column 1 (\"a\")", "inf"]);
    fails(
        &["--k1", "0.2", "--k2", "8", "--column", "a", "--column", "a"],
        "a,b\n1,2\n",
        &["--column a: given twice"],
    );
    fails(
        &[
            "--k1", "0.2", "--k2", "8", "--column", "a", "--column", "y_a",
        ],
        "a,y_a\n1,2\n",
        &["the column \"y_a\" twice"],
    );
    fails(
        &[&k[..], &["--record", "y_b"]].concat(),
        "a,b,y_b\n1,2,0\n",
        &["--record y_b: the output already has a column \"y_b\""],
    );
    fails(
        &["--k1", "0.2", "--k2", "8", "--column", "a", "--column", "c"],
        "a,b\n1,2\n",
        &["data.csv: no column named \"c\""],
    );
    fails(
        &["--k1", "0.2", "--k2", "0", "--column", "a", "--column", "b"],
        "a,b\n1,2\n",
        &["k2 = 0"],
    );
    fails(
        &[&k[..], &["--derivatives", "1"]].concat(),
        "a,a_d1,b\n1,2,3\n",
        &["--derivatives 1 needs the column \"b_d1\""],
    );
    // The bank (plain operators) gives an output beyond the float range on the second column
    // of row 5 (line 6); the message names that row, not the block's first.
    fails(
        &[
            "--k1",
            "4e307",
            "--k2",
            "8",
            "--inverse",
            "--column",
            "a",
            "--column",
            "b",
        ],
        "a,b\n1,2\n3,1\n0,0\n1,2\n2,1.7e308\n4,5\n",
        &["data.csv:6: column 2 (\"b\")", "1.7e308"],
    );
    // The model gives an output beyond the float range on the second column.
    let smooth = corpus("smooth.toml");
    fails(
        &["--model", s(&smooth), "--column", "a", "--column", "b"],
        "a,b\n1,2\n3,1e308\n",
        &["data.csv:3: column 2 (\"b\"): value 1e308"],
    );
}
