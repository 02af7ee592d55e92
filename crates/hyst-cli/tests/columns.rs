//! Integration tests of `hyst run` with several `--column`s: one operator per column, each
//! column's output the same as a run of that column alone (bit for bit on the scalar path:
//! models, derivatives; within a stated tolerance on the bank path: `--k1/--k2` without
//! derivatives), records restarting every column, and errors that name the file, line,
//! column and value.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use std::path::{Path, PathBuf};

use hyst_test_support::cli::Binary;
use hyst_test_support::files::{column, read_csv, s};
use hyst_test_support::rng::{Random, XorShift64};

const HYST: Binary = Binary::new(env!("CARGO_BIN_EXE_hyst"));

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
    let out = HYST.output(&all);
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
    let mut rng = XorShift64(0x2545_f491_4f6c_dd1d);
    let mut walk = 0.0;
    for i in 0..9000 {
        walk += (rng.unit() - 0.5) * 0.3;
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
            // Every input column first (the record column in its place), then one output per
            // column run.
            let inputs = ["t", "a", "b", "c", "u_actuator_V", "curve"];
            assert_eq!(header, [&inputs[..], &["y_a", "y_b", "y_c"]].concat());
            assert_eq!(together.len(), 9000);
            for name in ["a", "b", "c"] {
                let mut alone_args = args.clone();
                alone_args.extend(["--column", name]);
                let (alone_header, alone) =
                    run_ok(&alone_args, &input, &dir.path().join("alone.csv"));
                assert_eq!(alone_header, [&inputs[..], &["y"]].concat());
                for input in inputs {
                    assert_eq!(
                        column(&header, &together, input),
                        column(&alone_header, &alone, input),
                        "{all:?}: the input column {input} is copied"
                    );
                }
                let x = column(&alone_header, &alone, name);
                let ys = column(&alone_header, &alone, "y");
                let yb = column(&header, &together, &format!("y_{name}"));
                for (i, (yb, ys)) in yb.iter().zip(&ys).enumerate() {
                    assert!(
                        close(*yb, *ys, 0.2),
                        "{all:?}, column {name}, row {i}: bank {yb} vs alone {ys}"
                    );
                }
                // The outputs do move off the line y = x (a test that could not fail otherwise).
                let moved = x.iter().zip(&ys).filter(|(x, y)| x != y).count();
                assert!(moved > 1000, "{name}: {moved} outputs off the line y = x");
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
        let (header, rows) = run_ok(&args, &input, &dir.path().join("out.csv"));
        assert_eq!(header, ["a", "b", "r", "y_a", "y_b"]);
        let (a, ya, yb) = (
            column(&header, &rows, "a"),
            column(&header, &rows, "y_a"),
            column(&header, &rows, "y_b"),
        );
        let n = samples.len();
        for i in 0..n {
            assert_eq!((ya[i], yb[i]), (ya[i + n], yb[i + n]), "{args:?} row {i}");
        }
        assert_ne!(ya[1], a[1], "the operator moves off the line");
    }
}

/// The columns of [`scalar_path_input`].
const SCALAR_PATH_INPUTS: [&str; 9] = [
    "a",
    "a_d1",
    "a_d2",
    "b",
    "b_d1",
    "b_d2",
    "u_actuator_V",
    "v",
    "curve",
];

/// Signals of the scalar path, 5,000 rows at 1 kHz in four records (`curve`): the columns
/// [`SCALAR_PATH_INPUTS`], two with their first two derivatives, in `dir/in.csv`.
fn scalar_path_input(dir: &Path) -> PathBuf {
    let input = dir.join("in.csv");
    let inputs = SCALAR_PATH_INPUTS;
    let mut text = inputs.join(",") + "\n";
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
    input
}

#[test]
fn the_scalar_path_gives_the_single_runs_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let input = scalar_path_input(dir.path());
    let inputs = SCALAR_PATH_INPUTS;
    let smooth = corpus("smooth.toml");
    let pi = corpus("pi.toml");
    // The arguments, the columns run, and the name of what is computed.
    let cases: Vec<(Vec<&str>, [&str; 2], &str)> = vec![
        (
            vec!["--k1", "0.2", "--k2", "8", "--derivatives", "2"],
            ["a", "b"],
            "y",
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
            "y",
        ),
        (
            vec!["--model", s(&smooth)],
            ["u_actuator_V", "v"],
            "y_capsensor_um",
        ),
        (
            vec!["--model", s(&smooth), "--record", "curve"],
            ["u_actuator_V", "v"],
            "y_capsensor_um",
        ),
        (
            vec!["--model", s(&pi)],
            ["u_actuator_V", "v"],
            "y_capsensor_um",
        ),
    ];
    for (args, columns, base) in cases {
        let mut all = args.clone();
        all.extend(["--column", columns[0], "--column", columns[1]]);
        let (header, together) = run_ok(&all, &input, &dir.path().join("out.csv"));
        let n: usize = args
            .iter()
            .position(|a| *a == "--derivatives")
            .map_or(0, |i| args[i + 1].parse().unwrap());
        // Every input column, then BASE_a, BASE_b, then their derivatives column by column.
        let mut expected: Vec<String> = inputs.map(String::from).to_vec();
        expected.extend(columns.map(|c| format!("{base}_{c}")));
        for c in columns {
            expected.extend((1..=n).map(|d| format!("{base}_{c}_d{d}")));
        }
        assert_eq!(header, expected);
        for name in columns {
            let mut alone_args = args.clone();
            alone_args.extend(["--column", name]);
            let (alone_header, alone) = run_ok(&alone_args, &input, &dir.path().join("alone.csv"));
            let mut alone_expected: Vec<String> = inputs.map(String::from).to_vec();
            alone_expected.push(base.to_string());
            alone_expected.extend((1..=n).map(|d| format!("{base}_d{d}")));
            assert_eq!(alone_header, alone_expected);
            for input in inputs {
                assert_eq!(
                    column(&header, &together, input),
                    column(&alone_header, &alone, input),
                    "{all:?}: {input}"
                );
            }
            let bits = |h: &[String], rows: &[Vec<f64>], c: &str| -> Vec<u64> {
                column(h, rows, c).iter().map(|v| v.to_bits()).collect()
            };
            assert_eq!(
                bits(&header, &together, &format!("{base}_{name}")),
                bits(&alone_header, &alone, base),
                "{all:?}: {base}_{name}"
            );
            for d in 1..=n {
                assert_eq!(
                    bits(&header, &together, &format!("{base}_{name}_d{d}")),
                    bits(&alone_header, &alone, &format!("{base}_d{d}")),
                    "{all:?}: {base}_{name}_d{d}"
                );
            }
        }
    }
}

/// A computed name that INPUT already has is not refused: it gets `_out` appended
/// (`--column a --column y_a` computes `y_a`, written `y_a_out`, and `y_y_a`), and a record
/// column named like an output is passed through in its place.
#[test]
fn a_computed_name_the_input_has_gets_the_suffix_out() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.csv");
    let samples = [(0.0, 1.0), (0.6, 0.2), (1.0, -0.5), (0.3, 0.4), (-0.2, 0.9)];
    let mut text = String::from("a,y_a\n");
    for (a, b) in samples {
        text += &format!("{a},{b}\n");
    }
    std::fs::write(&input, text).unwrap();
    let k = ["--k1", "0.2", "--k2", "8"];
    let out = dir.path().join("out.csv");
    for extra in [&[][..], &["--inverse"][..]] {
        let args = [&k[..], extra, &["--column", "a", "--column", "y_a"]].concat();
        let (header, rows) = run_ok(&args, &input, &out);
        assert_eq!(header, ["a", "y_a", "y_a_out", "y_y_a"], "{args:?}");
        // INPUT's y_a is passed through; the outputs are those of each column alone.
        let y_a_in: Vec<f64> = samples.iter().map(|s| s.1).collect();
        assert_eq!(column(&header, &rows, "y_a"), y_a_in);
        for (name, computed) in [("a", "y_a_out"), ("y_a", "y_y_a")] {
            let (alone_header, alone) = run_ok(
                &[&k[..], extra, &["--column", name]].concat(),
                &input,
                &dir.path().join("alone.csv"),
            );
            assert_eq!(alone_header, ["a", "y_a", "y"]);
            let (together, alone) = (
                column(&header, &rows, computed),
                column(&alone_header, &alone, "y"),
            );
            for (t, a) in together.iter().zip(&alone) {
                assert!(close(*t, *a, 0.2), "{args:?} {computed}: {t} vs {a}");
            }
        }
    }
    // The record column y_b: passed through, and the output for b is y_b_out.
    let input = dir.path().join("rec.csv");
    std::fs::write(&input, "a,b,y_b\n1,2,0\n0.5,2.5,0\n0,1,1\n").unwrap();
    let (header, rows) = run_ok(
        &[
            &k[..],
            &["--column", "a", "--column", "b", "--record", "y_b"],
        ]
        .concat(),
        &input,
        &out,
    );
    assert_eq!(header, ["a", "b", "y_b", "y_a", "y_b_out"]);
    assert_eq!(column(&header, &rows, "y_b"), [0.0, 0.0, 1.0]);
    // The third row starts a record: no history, on the line y = x.
    assert_eq!(column(&header, &rows, "y_b_out")[2], 1.0);
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
    let out = HYST.output(&all);
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
