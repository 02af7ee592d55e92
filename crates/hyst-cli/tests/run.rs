//! Integration tests of `hyst run`: agreement with an independent implementation of eqs. (2) and
//! (4) with Definition 2.1's discrete memory, full-precision output, derivatives, and errors that
//! name the file, line and column without leaving any output behind.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use hyst_core::Operator;

use hyst_test_support::cli::Binary;
use hyst_test_support::files::{column, read_csv};
use hyst_test_support::rng::{Random, XorShift64};

const HYST: Binary = Binary::new(env!("CARGO_BIN_EXE_hyst"));

/// Independent reference: Definition 2.1 in discrete time and the printed eqs. (2) and (4),
/// straight from the paper (no log-domain tricks; fine for moderate k2).
struct Reference {
    k1: f64,
    k2: f64,
    inverse: bool,
    state: Option<(f64, f64, f64, f64, f64)>, // (alpha0, beta0, s, last_in, last_out)
}

impl Reference {
    fn step(&mut self, x: f64) -> f64 {
        let (mut a0, mut b0, mut s, last_in, last_out) = self.state.unwrap_or((x, x, 1.0, x, x));
        let dir = if x > last_in {
            1.0
        } else if x < last_in {
            -1.0
        } else {
            s
        };
        if dir != s {
            a0 = last_in;
            b0 = last_out;
            s = dir;
        }
        let m = if s > 0.0 { b0 - a0 } else { a0 - b0 };
        let xt = s * (x - a0);
        let yt = if self.inverse {
            let m_star = -m + self.k1;
            xt + m_star * (1.0 - (-self.k2 * xt).exp())
        } else {
            let m_star = m + self.k1;
            xt - m_star
                + lambert_w::lambert_w0(self.k2 * m_star * (self.k2 * (m_star - xt)).exp())
                    / self.k2
        };
        let y = b0 + s * yt;
        self.state = Some((a0, b0, s, x, y));
        y
    }
}

fn random_walk(n: usize, seed: u64) -> Vec<f64> {
    let mut rng = XorShift64(seed);
    let mut x = 0.0;
    (0..n)
        .map(|_| {
            x += (rng.unit() - 0.5) * 0.4;
            x
        })
        .collect()
}

#[test]
fn agrees_with_the_equations_and_writes_full_precision() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.csv");
    for (seed, (k1, k2)) in [(1u64, (0.14, 8.0)), (2, (0.2, 3.0)), (3, (0.05, 40.0))] {
        let xs = random_walk(2000, seed);
        let mut text = String::from("t,u\n");
        for (i, x) in xs.iter().enumerate() {
            text.push_str(&format!("{i},{x:e}\n"));
        }
        std::fs::write(&input, text).unwrap();
        for inverse in [false, true] {
            let output = dir.path().join(format!("out-{seed}-{inverse}.csv"));
            let mut cmd = HYST.command();
            cmd.args([
                "run",
                "--k1",
                &k1.to_string(),
                "--k2",
                &k2.to_string(),
                "--column",
                "u",
            ]);
            if inverse {
                cmd.arg("--inverse");
            }
            let status = cmd.arg(&input).arg("-o").arg(&output).status().unwrap();
            assert!(status.success());
            let (header, rows) = read_csv(&output);
            assert_eq!(header, ["t", "u", "y"]);
            assert_eq!(rows.len(), xs.len());
            assert_eq!(
                column(&header, &rows, "t"),
                (0..xs.len()).map(|i| i as f64).collect::<Vec<_>>()
            );
            let mut reference = Reference {
                k1,
                k2,
                inverse,
                state: None,
            };
            let mut core: Box<dyn FnMut(f64) -> f64> = if inverse {
                let mut op = hyst_core::InverseHysteresis::new(k1, k2).unwrap();
                Box::new(move |x| op.step(x))
            } else {
                let mut op = hyst_core::Hysteresis::new(k1, k2).unwrap();
                Box::new(move |x| op.step(x))
            };
            let (u, y) = (column(&header, &rows, "u"), column(&header, &rows, "y"));
            for ((&u, &y), &x) in u.iter().zip(&y).zip(&xs) {
                assert_eq!(u.to_bits(), x.to_bits(), "input passed through exactly");
                let want = reference.step(x);
                let scale = x.abs().max(want.abs()).max(k1);
                assert!(
                    (y - want).abs() <= 1e-11 * scale,
                    "k1 {k1} k2 {k2} inverse {inverse}: x {x}: hyst {y} vs equations {want}"
                );
                // Full precision: the file holds exactly what the library computed.
                assert_eq!(y.to_bits(), core(x).to_bits());
            }
        }
    }
}

#[test]
fn derivatives_columns() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.csv");
    std::fs::write(&input, "x,x_d1,x_d2\n0,1,0\n0.1,1,0\n0.05,-1,0.5\n").unwrap();
    let output = dir.path().join("out.csv");
    let status = HYST
        .command()
        .args([
            "run",
            "--k1",
            "0.2",
            "--k2",
            "8",
            "--inverse",
            "--derivatives",
            "2",
        ])
        .arg(&input)
        .arg("-o")
        .arg(&output)
        .status()
        .unwrap();
    assert!(status.success());
    let (header, rows) = read_csv(&output);
    assert_eq!(header, ["x", "x_d1", "x_d2", "y", "y_d1", "y_d2"]);
    // At the first sample (on the line, rising): v' = (1 + k2 k1) u', v'' = −k1 k2² u'^2.
    let (d1, d2) = (
        column(&header, &rows, "y_d1"),
        column(&header, &rows, "y_d2"),
    );
    assert!((d1[0] - (1.0 + 8.0 * 0.2)).abs() < 1e-12);
    assert!((d2[0] + 0.2 * 64.0).abs() < 1e-12);
}

fn assert_fails_cleanly(args: &[&str], input: &str, expected: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let in_path = dir.path().join("data.csv");
    std::fs::write(&in_path, input).unwrap();
    let out_path = dir.path().join("out.csv");
    std::fs::write(&out_path, "previous contents\n").unwrap();
    let out = HYST
        .command()
        .arg("run")
        .args(args)
        .arg(&in_path)
        .arg("-o")
        .arg(&out_path)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    for e in expected {
        assert!(stderr.contains(e), "stderr {stderr:?} lacks {e:?}");
    }
    assert_eq!(
        std::fs::read_to_string(&out_path).unwrap(),
        "previous contents\n"
    );
    let leftovers: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(leftovers.len(), 2, "no temporary files left behind");
}

#[test]
fn errors_name_file_line_and_column_and_write_nothing() {
    assert_fails_cleanly(
        &["--k1", "0.2", "--k2", "8"],
        "t,x\n0,1\n1,oops\n",
        &["data.csv:3", "column 2", "\"x\"", "oops"],
    );
    assert_fails_cleanly(
        &["--k1", "0.2", "--k2", "8"],
        "t,x\n0,1\n1,nan\n",
        &["data.csv:3", "nan"],
    );
    assert_fails_cleanly(
        &["--k1", "0.2", "--k2", "8", "--column", "u"],
        "t,x\n0,1\n",
        &["no column named \"u\"", "\"t\", \"x\""],
    );
    assert_fails_cleanly(&["--k1", "0", "--k2", "8"], "x\n1\n", &["k1 = 0", "> 0"]);
    assert_fails_cleanly(&["--k1", "0.1", "--k2", "-3"], "x\n1\n", &["k2 = -3"]);
    assert_fails_cleanly(
        &["--k1", "0.1", "--k2", "3", "--derivatives", "1"],
        "x\n1\n",
        &["x_d1"],
    );
    assert_fails_cleanly(&["--k1", "0.1", "--k2", "3"], "t,u\n1,2\n", &["--column"]);
    // The file is streamed: an error far into it still leaves nothing behind.
    let mut long = String::from("t,x\n");
    for i in 0..10_000 {
        long += &format!("{i},{}\n", (i as f64 * 0.01).sin());
    }
    long += "10000,oops\n";
    assert_fails_cleanly(
        &["--k1", "0.2", "--k2", "8"],
        &long,
        &["data.csv:10002: column 2 (\"x\"): cannot parse \"oops\""],
    );
    let k = ["--k1", "0.2", "--k2", "8"];
    assert_fails_cleanly(
        &[&k[..], &["--record", "loop"]].concat(),
        "x,curve\n0,0\n",
        &["--record: ", "no column named \"loop\""],
    );
    assert_fails_cleanly(
        &[&k[..], &["--inverse", "--saturate"]].concat(),
        "x\n1\n",
        &["--saturate applies to --model FILE --inverse"],
    );
}

/// The record column may be the column run (the output has no column `x` of its own to clash
/// with): every change of `x` starts a record, so each sample starts afresh on
/// the line y = x; the record column `curve` next to it is just passed through.
#[test]
fn the_column_run_may_be_the_record_column() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.csv");
    std::fs::write(&input, "x,curve\n0,0\n0.5,0\n1,1\n0.25,1\n").unwrap();
    let output = dir.path().join("out.csv");
    let status = HYST
        .command()
        .args(["run", "--k1", "0.2", "--k2", "8", "--record", "x"])
        .arg(&input)
        .arg("-o")
        .arg(&output)
        .status()
        .unwrap();
    assert!(status.success());
    assert_eq!(
        std::fs::read_to_string(&output).unwrap(),
        "x,curve,y\n0,0,0\n0.5,0,0.5\n1,1,1\n0.25,1,0.25\n"
    );
}

#[test]
fn a_missing_input_file_is_named() {
    let out = HYST
        .command()
        .args([
            "run",
            "--k1",
            "0.2",
            "--k2",
            "8",
            "/nonexistent/in.csv",
            "-o",
            "/tmp/never.csv",
        ])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("/nonexistent/in.csv"));
}

#[test]
fn standard_output_gets_nothing_from_a_run_that_fails_early() {
    let dir = tempfile::tempdir().unwrap();
    for (text, expected) in [("x\n", "no data rows"), ("x\n1\n2\nthree\n", "data.csv:4")] {
        let input = dir.path().join("data.csv");
        std::fs::write(&input, text).unwrap();
        let out = HYST
            .command()
            .args(["run", "--k1", "0.2", "--k2", "8"])
            .arg(&input)
            .args(["-o", "-"])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1));
        assert!(
            out.stdout.is_empty(),
            "{:?}",
            String::from_utf8_lossy(&out.stdout)
        );
        assert!(String::from_utf8_lossy(&out.stderr).contains(expected));
    }
}

/// A stop-form (friction) model, as `hyst fit` writes it for clockwise data.
const STOP_MODEL: &str = r#"format = "hyst-model"
version = 3
kind = "smooth"

[columns]
input = "x_mm"
output = "F_N"

[units]
input = ""
output = ""

[[parameters]]
name = "k1"
value = 0.2
std_error = 0.01
unit = "operator units"

[metrics]
parameters = 5
fit_seconds = 0.1
ns_per_sample = 37.0

[metrics.training]
samples = 8000
rms = 15.6
max_abs = 40.0
rms_pct_span = 7.68
max_pct_span = 19.6

[structure]
k2 = "constant"
input_shaping = "affine"
output_shaping = "affine"
output_offset = true
initial_state = "rising"
form = "stop"

[smooth]
k1 = 0.2
initial_state = "rising"
form = "stop"
linear = -7.4

[smooth.k2]
law = "constant"
value = 40.0

[smooth.input_shaping]
pre_gain = 0.046
pre_offset = 0.045
shape = "identity"
post_gain = 1.0
post_offset = 0.0

[smooth.output_shaping]
pre_gain = 1.0
pre_offset = 0.0
shape = "identity"
post_gain = 65.4
post_offset = 6.0

[provenance]
file = "friction.csv"
bytes = 213469
fnv1a64 = "1f2bc370a98ac8a0"
rows = 8000
records = 1
validation_records = []
command = "hyst fit friction.csv --input x_mm --output F_N -o fric.toml"
hyst_version = "0.1.0"
created_unix = 1795614884
"#;

/// `--inverse` of a stop-form model is refused before any data is read (the data file here does
/// not even exist), naming the model and saying what to do instead.
#[test]
fn the_inverse_of_a_stop_form_model_is_refused_before_the_data() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("fric.toml"), STOP_MODEL).unwrap();
    // Without --inverse the model runs (feed-forward of the predicted force).
    std::fs::write(d.join("x.csv"), "x_mm\n0\n0.5\n1\n0.2\n").unwrap();
    let o = HYST
        .command()
        .args(["run", "--model", "fric.toml", "x.csv", "-o", "f.csv"])
        .current_dir(d)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = HYST
        .command()
        .args([
            "run",
            "--model",
            "fric.toml",
            "--inverse",
            "none.csv",
            "-o",
            "o.csv",
        ])
        .current_dir(d)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        String::from_utf8_lossy(&o.stderr),
        "error: --inverse: the model fric.toml is a stop-form (friction) model: it predicts the \
         output (force) from the input (position) and has no inverse. Friction is compensated by \
         feed-forward of the predicted force: run the model without --inverse on the position \
         (measured or desired) and add its output to the actuator command (docs/fitting.md, \
         \"Compensating friction\")\n"
    );
    assert!(!d.join("o.csv").exists());
}

/// A quote never closed in a column the run passes through is refused on its line: the parser
/// would read the rest of the file into that cell, and the run would lose those rows with exit
/// status 0.
#[test]
fn a_quote_never_closed_loses_no_rows() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("q.csv");
    std::fs::write(&input, "x,note\n0,a\n0.5,\"b\n1,c\n").unwrap();
    let output = dir.path().join("o.csv");
    let out = HYST
        .command()
        .args(["run", "--k1", "0.2", "--k2", "8", "--column", "x"])
        .arg(&input)
        .arg("-o")
        .arg(&output)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("q.csv:3: malformed CSV: a quote (\") on this line"),
        "{err}"
    );
    assert!(!output.exists());
}
