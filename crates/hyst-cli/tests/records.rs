//! Integration tests of `hyst run --record` (one operator start per record, FORC curves and B-H
//! loops) and `--saturate` (desired outputs beyond a saturating output shaping, or out of the
//! reach of a saturating input shaping), and of their messages.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use std::path::{Path, PathBuf};

use hyst_core::Operator;

use hyst_test_support::cli::{stderr, Binary};
use hyst_test_support::files::{piezo, piezo_fit, repo, s};

const HYST: Binary = Binary::new(env!("CARGO_BIN_EXE_hyst"));

/// Runs `hyst run ARGS INPUT -o OUTPUT` and returns OUTPUT's text; panics with stderr on failure.
fn run_ok(args: &[&str], input: &Path, output: &Path) -> String {
    let mut all = vec!["run"];
    all.extend_from_slice(args);
    all.extend_from_slice(&[s(input), "-o", s(output)]);
    let out = HYST.output(&all);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    std::fs::read_to_string(output).unwrap()
}

/// The header of a CSV text, split at commas.
fn header(text: &str) -> Vec<String> {
    text.lines()
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect()
}

/// The index of the column `name` in the header of a CSV text.
fn index(text: &str, name: &str) -> usize {
    let header = header(text);
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name:?} in {header:?}"))
}

/// The data rows of a CSV text, split at commas.
fn rows(text: &str) -> Vec<Vec<String>> {
    text.lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

/// Records: the id and the samples (value, first derivative) of each.
type Records = Vec<(f64, Vec<(f64, f64)>)>;

/// A FORC-like file: records 0, 1 and 0 again (a repeat that is not contiguous), each a
/// reversal curve, with a time derivative column.
fn forc_file(dir: &Path) -> (PathBuf, Records) {
    let mut records = Vec::new();
    for (id, top) in [(0.0, 1.0), (1.0, 0.4), (0.0, -0.3)] {
        let n = 40;
        let samples: Vec<(f64, f64)> = (0..n)
            .map(|i| {
                let t = i as f64 / (n - 1) as f64;
                // Down from saturation to the reversal field `top`, then back up.
                let x = if t < 0.5 {
                    1.5 - (1.5 - top) * 2.0 * t
                } else {
                    top + (1.5 - top) * (2.0 * t - 1.0)
                };
                (x, if t < 0.5 { -1.0 } else { 1.0 })
            })
            .collect();
        records.push((id, samples));
    }
    let mut text = String::from("# FORC\nH,H_d1,curve\n");
    for (id, samples) in &records {
        for (x, d) in samples {
            text += &format!("{x},{d},{id}\n");
        }
    }
    let path = dir.join("forc.csv");
    std::fs::write(&path, text).unwrap();
    (path, records)
}

#[test]
fn k1_k2_records_restart_the_operator_and_repeats_are_new_records() {
    let dir = tempfile::tempdir().unwrap();
    let (input, records) = forc_file(dir.path());
    for inverse in [false, true] {
        let mut args = vec![
            "--k1", "0.2", "--k2", "8", "--column", "H", "--record", "curve",
        ];
        if inverse {
            args.push("--inverse");
        }
        let text = run_ok(&args, &input, &dir.path().join("out.csv"));
        // INPUT's columns (the record column in its place), then the output.
        assert!(text.starts_with("H,H_d1,curve,y\n"), "{text}");
        let got = rows(&text);
        let mut i = 0;
        for (id, samples) in &records {
            // Each record from no history, as a fresh operator.
            let mut direct = hyst_core::Hysteresis::new(0.2, 8.0).unwrap();
            let mut inv = hyst_core::InverseHysteresis::new(0.2, 8.0).unwrap();
            for (x, _) in samples {
                let want = if inverse {
                    inv.step(*x)
                } else {
                    direct.step(*x)
                };
                let row = &got[i];
                assert_eq!(row[0].parse::<f64>().unwrap(), *x);
                assert_eq!(
                    row[3].parse::<f64>().unwrap().to_bits(),
                    want.to_bits(),
                    "row {i}, inverse {inverse}"
                );
                assert_eq!(row[2].parse::<f64>().unwrap(), *id);
                i += 1;
            }
        }
        assert_eq!(i, got.len());
        // Without --record the file is one history: the third curve differs.
        let one = run_ok(&args[..6], &input, &dir.path().join("one.csv"));
        assert!(one.starts_with("H,H_d1,curve,y\n"));
        let one = rows(&one);
        let (a, b) = (&one[80], &got[80]);
        assert_ne!(a[3], b[3], "the third record must restart");
    }
}

/// Fits a model to the steel B-H loops (tanh output shaping) and returns its path.
fn steel_model(dir: &Path) -> PathBuf {
    let model = dir.join("steel.toml");
    let data = repo().join("data/bh-loops/m130_27s_steel_loops.csv");
    let out = HYST.output(&[
        "fit",
        "--input",
        "H_A_per_m",
        "--output",
        "B_T",
        "--output-shaping",
        "tanh",
        s(&data),
        "-o",
        s(&model),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    model
}

#[test]
fn model_records_start_by_the_model_rule_at_each_first_sample() {
    let dir = tempfile::tempdir().unwrap();
    let model = steel_model(dir.path());
    let data = repo().join("data/bh-loops/m130_27s_steel_loops.csv");
    let text = std::fs::read_to_string(&data).unwrap();
    // The loops, each in a file of its own: running it alone is the reference.
    let mut header_and_loops: Vec<(String, String)> = Vec::new();
    for line in text.lines().skip(1) {
        let id = line.split(',').next().unwrap().to_string();
        match header_and_loops.last_mut() {
            Some((last, body)) if *last == id => {
                body.push_str(line);
                body.push('\n');
            }
            _ => header_and_loops.push((id, format!("loop,H_A_per_m,B_T\n{line}\n"))),
        }
    }
    assert!(header_and_loops.len() >= 3);
    for (args, computed) in [
        (&["--model", s(&model)][..], "B_T_out"),
        (
            &["--model", s(&model), "--inverse", "--saturate"][..],
            "H_A_per_m_out,B_T_saturated",
        ),
    ] {
        let mut all: Vec<&str> = args.to_vec();
        all.extend_from_slice(&["--record", "loop"]);
        let text = run_ok(&all, &data, &dir.path().join("all.csv"));
        // The data's columns (the record column first, in its place), then what is computed,
        // named after the model's columns (which the data has: `_out`).
        assert!(
            text.starts_with(&format!("loop,H_A_per_m,B_T,{computed}\n")),
            "{args:?}"
        );
        let together = rows(&text);
        let mut i = 0;
        for (k, (id, body)) in header_and_loops.iter().enumerate() {
            let part = dir.path().join(format!("loop{k}.csv"));
            std::fs::write(&part, body).unwrap();
            let alone = rows(&run_ok(args, &part, &dir.path().join("alone.csv")));
            for row in alone {
                // Every cell, the loop's label and the computed ones, as the loop alone gives.
                assert_eq!(together[i], row, "{args:?} loop {id} row {i}");
                assert_eq!(together[i][0], *id);
                i += 1;
            }
        }
        assert_eq!(i, together.len());
    }
}

#[test]
fn records_carry_derivatives_through_a_model() {
    let dir = tempfile::tempdir().unwrap();
    let (input, records) = forc_file(dir.path());
    // A model in the units of the FORC file: fit to a synthetic loop of H.
    let mut data = String::from("H,M\n");
    let mut truth = hyst_core::Hysteresis::new(0.2, 6.0).unwrap();
    for i in 0..600 {
        let x = 1.5 * (i as f64 * 0.05).sin() * (1.0 - i as f64 / 900.0);
        data += &format!("{x},{}\n", 0.8 * truth.step(x));
    }
    let data_path = dir.path().join("loop.csv");
    std::fs::write(&data_path, data).unwrap();
    let model = dir.path().join("m.toml");
    let out = HYST.output(&[
        "fit",
        "--input",
        "H",
        "--output",
        "M",
        s(&data_path),
        "-o",
        s(&model),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let args = [
        "--model",
        s(&model),
        "--column",
        "H",
        "--derivatives",
        "1",
        "--record",
        "curve",
    ];
    let text = run_ok(&args, &input, &dir.path().join("out.csv"));
    assert!(text.starts_with("H,H_d1,curve,M,M_d1\n"), "{text}");
    let got = rows(&text);
    // Record by record, alone.
    let mut i = 0;
    for (k, (_, samples)) in records.iter().enumerate() {
        let mut body = String::from("H,H_d1\n");
        for (x, d) in samples {
            body += &format!("{x},{d}\n");
        }
        let part = dir.path().join(format!("c{k}.csv"));
        std::fs::write(&part, body).unwrap();
        let alone = run_ok(&args[..6], &part, &dir.path().join("alone.csv"));
        assert!(alone.starts_with("H,H_d1,M,M_d1\n"), "{alone}");
        for row in rows(&alone) {
            // The row without its record column.
            let mut together = got[i].clone();
            together.remove(2);
            assert_eq!(together, row, "record {k}, row {i}");
            i += 1;
        }
    }
    assert_eq!(i, got.len());
}

#[test]
fn forc_file_runs_record_by_record() {
    let dir = tempfile::tempdir().unwrap();
    let data = repo().join("data/feco-forc/feco_forc_sequence.csv");
    let out_path = dir.path().join("out.csv");
    let text = run_ok(
        &[
            "--k1",
            "300",
            "--k2",
            "0.01",
            "--column",
            "H_Oe",
            "--record",
            "curve_index",
        ],
        &data,
        &out_path,
    );
    assert!(text.starts_with("H_Oe,moment_emu,is_calibration_point,curve_index,y\n"));
    let (h, y, curve) = (
        index(&text, "H_Oe"),
        index(&text, "y"),
        index(&text, "curve_index"),
    );
    let got = rows(&text);
    assert_eq!(got.len(), 30628);
    // Every curve starts on the line y = x (no history: the first sample is a reversal point).
    let mut last = String::new();
    let mut starts = 0;
    for row in &got {
        if row[curve] != last {
            assert_eq!(
                row[h].parse::<f64>().unwrap(),
                row[y].parse::<f64>().unwrap(),
                "curve {} starts at its first sample",
                row[curve]
            );
            last.clone_from(&row[curve]);
            starts += 1;
        }
    }
    assert_eq!(starts, 152);
}

/// A desired-output file for the steel model: in range, then beyond tanh's range.
fn desired(dir: &Path, values: &[f64]) -> PathBuf {
    let mut text = String::from("B_T\n");
    for v in values {
        text += &format!("{v}\n");
    }
    let path = dir.join("desired.csv");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn beyond_a_saturating_shaping_is_one_clear_error_by_default() {
    let dir = tempfile::tempdir().unwrap();
    let model = steel_model(dir.path());
    let out = dir.path().join("cmd.csv");
    std::fs::write(&out, "previous\n").unwrap();
    for (values, line, value) in [
        (&[0.1, 0.5, 2.0, 0.3][..], 4, "2"),
        (&[-7.5, 0.5][..], 2, "-7.5"),
    ] {
        let input = desired(dir.path(), values);
        let o = HYST.output(&[
            "run",
            "--model",
            s(&model),
            "--inverse",
            s(&input),
            "-o",
            s(&out),
        ]);
        assert_eq!(o.status.code(), Some(1));
        let err = stderr(&o);
        assert!(
            err.contains(&format!(
                "desired.csv:{line}: column 1 (\"B_T\"): desired output {value} is outside the \
                 range ("
            )),
            "{err}"
        );
        assert!(err.contains("of the model's tanh output shaping"), "{err}");
        assert!(err.contains("--saturate clamps"), "{err}");
        // The range and the limits with 7 significant digits, not 17.
        let numbers = |open: &str, close: char| -> Vec<String> {
            let from = err.find(open).unwrap() + open.len();
            let to = from + err[from..].find(close).unwrap();
            err[from..to].split(", ").map(str::to_string).collect()
        };
        for n in numbers("outside the range (", ')')
            .into_iter()
            .chain(numbers("clamps such values into [", ']'))
        {
            let digits = n.split('e').next().unwrap().replace(['-', '.'], "");
            assert_eq!(digits.trim_start_matches('0').len(), 7, "{n} in {err}");
        }
        // Said once.
        assert_eq!(err.matches("outside the range").count(), 1, "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "previous\n");
    }
}

#[test]
fn saturate_clamps_into_the_stated_fraction_of_the_range_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let model = steel_model(dir.path());
    let file: toml::Table = std::fs::read_to_string(&model).unwrap().parse().unwrap();
    let psi = &file["smooth"]["output_shaping"];
    let (gain, offset) = (
        psi["post_gain"].as_float().unwrap(),
        psi["post_offset"].as_float().unwrap(),
    );
    let tanh_gain = psi["shape"]["tanh"]["gain"].as_float().unwrap();
    let (lo, hi) = (offset - gain * tanh_gain, offset + gain * tanh_gain);
    let half = 0.5 * (hi - lo);
    // The limits: 99.9 % of the range about its centre, widened to the outputs the model gives
    // over its fitted input range (never narrower, never the range's ends).
    let saturation = hyst_model::ModelFile::read(&model)
        .unwrap()
        .saturation()
        .unwrap();
    let (a, b) = saturation.limits;
    assert!(a <= lo + 0.001 * half && a > lo, "{a} against ({lo}, {hi})");
    assert!(b >= hi - 0.001 * half && b < hi, "{b} against ({lo}, {hi})");
    let values = [0.1, 0.5, 2.0, hi, 0.3, -9.0, 0.5 * (b + hi)];
    let input = desired(dir.path(), &values);
    let out = dir.path().join("cmd.csv");
    let o = HYST.output(&[
        "run",
        "--model",
        s(&model),
        "--inverse",
        "--saturate",
        s(&input),
        "-o",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.starts_with("hyst run: --saturate clamped 4 of 7 desired outputs into ["),
        "{err}"
    );
    assert!(err.contains("99.9 % of the range"), "{err}");
    assert!(err.contains("desired.csv:4 (value 2)"), "{err}");
    let text = std::fs::read_to_string(&out).unwrap();
    // The desired output as read, the command (named after the model's input column), and the
    // desired output actually inverted (after clamping).
    assert!(text.starts_with("B_T,H_A_per_m,B_T_saturated\n"), "{text}");
    let got = rows(&text);
    let column = |name: &str| -> Vec<f64> {
        let k = index(&text, name);
        got.iter().map(|r| r[k].parse().unwrap()).collect()
    };
    assert_eq!(
        column("B_T"),
        values,
        "the desired outputs are passed through"
    );
    let x = column("B_T_saturated");
    let command = column("H_A_per_m");
    assert!(command.iter().all(|c| c.is_finite()));
    // Values inside the limits are inverted as they are.
    for k in [0, 1, 4] {
        assert_eq!(x[k], values[k]);
    }
    assert_eq!(x[0], 0.1);
    assert!(
        (x[2] - b).abs() < 1e-12 && (x[3] - b).abs() < 1e-12,
        "{x:?}"
    );
    assert!((x[5] - a).abs() < 1e-12, "{x:?}");
    assert!((x[6] - b).abs() < 1e-12, "{x:?}");
    // The clamped commands are what the model needs to produce the limits: run them forward.
    let mut fwd = String::from("H_A_per_m\n");
    for c in &command {
        fwd += &format!("{c}\n");
    }
    let fwd_in = dir.path().join("commands.csv");
    std::fs::write(&fwd_in, fwd).unwrap();
    let back = run_ok(
        &["--model", s(&model)],
        &fwd_in,
        &dir.path().join("back.csv"),
    );
    assert!(back.starts_with("H_A_per_m,B_T\n"), "{back}");
    for (row, want) in rows(&back).iter().zip(&x) {
        let y: f64 = row[1].parse().unwrap();
        assert!(
            (y - want).abs() < 1e-6,
            "model(command) {y} vs desired {want}"
        );
    }
}

/// `hyst run` tells records apart by the column `hyst fit` takes for it (`loop`,
/// `curve_index`, `record`, `segment`) unless told `--no-record`, with a note: a model with
/// dynamics runs a file whose time restarts at each record, and a static run equals
/// `--record`'s.
#[test]
fn run_finds_the_record_column_fit_finds() {
    let dir = tempfile::tempdir().unwrap();
    let (forc, _) = forc_file(dir.path());
    let text = std::fs::read_to_string(&forc)
        .unwrap()
        .replace(",curve\n", ",segment\n");
    let input = dir.path().join("segments.csv");
    std::fs::write(&input, text).unwrap();
    let args = ["--k1", "0.2", "--k2", "8", "--column", "H"];
    let found = HYST.output(
        &[
            &["run"],
            &args[..],
            &[s(&input), "-o", s(&dir.path().join("a.csv"))],
        ]
        .concat(),
    );
    assert!(found.status.success(), "{}", stderr(&found));
    assert!(
        stderr(&found).contains("note: column \"segment\" tells the records apart"),
        "{}",
        stderr(&found)
    );
    let named = run_ok(
        &[&args[..], &["--record", "segment"]].concat(),
        &input,
        &dir.path().join("b.csv"),
    );
    assert_eq!(
        std::fs::read_to_string(dir.path().join("a.csv")).unwrap(),
        named
    );
    let one = run_ok(
        &[&args[..], &["--no-record"]].concat(),
        &input,
        &dir.path().join("c.csv"),
    );
    assert_ne!(one, named);

    // A model with dynamics on records whose time starts at 0 each: without the record
    // column, the second record's first stamp would go back.
    let model = repo().join("examples/firmware/models/piezo_dyn.toml");
    let mut text = String::from("t,u_actuator_V,record\n");
    for record in 0..2 {
        for k in 0..200 {
            let t = f64::from(k) * 1e-3;
            text += &format!("{t},{},{record}\n", 2.0 + (20.0 * t).sin());
        }
    }
    let input = dir.path().join("timed.csv");
    std::fs::write(&input, text).unwrap();
    let out = run_ok(&["--model", s(&model)], &input, &dir.path().join("t.csv"));
    assert_eq!(rows(&out).len(), 400);
    let refused = HYST.output(&[
        "run",
        "--model",
        s(&model),
        "--no-record",
        s(&input),
        "-o",
        s(&dir.path().join("u.csv")),
    ]);
    assert_eq!(refused.status.code(), Some(1));
    assert!(
        stderr(&refused).contains("goes back")
            && stderr(&refused).contains("with --record COLUMN)"),
        "{}",
        stderr(&refused)
    );
}

/// The piezo record (inputs 0 to 3.6 V) fitted with input shaping `input` and a tanh output
/// shaping (its data in the tail of the tanh).
fn piezo_saturating(dir: &Path, input: &str) -> PathBuf {
    let model = dir.join(format!("piezo-{input}.toml"));
    let data = piezo();
    let mut args = piezo_fit(&data, &model).to_vec();
    args.extend_from_slice(&["--input-shaping", input, "--output-shaping", "tanh"]);
    let o = HYST.output(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    model
}

#[test]
fn saturate_with_a_saturating_input_shaping_leaves_the_training_range_alone() {
    let dir = tempfile::tempdir().unwrap();
    for input in ["tanh", "langevin"] {
        let model = piezo_saturating(dir.path(), input);
        // Desired outputs inside the training range (about -130 to -75 um).
        let desired = dir.path().join("desired.csv");
        std::fs::write(&desired, "y_capsensor_um\n-120\n-100\n-80\n").unwrap();
        let out = dir.path().join("cmd.csv");
        let o = HYST.output(&[
            "run",
            "--model",
            s(&model),
            "--inverse",
            "--saturate",
            s(&desired),
            "-o",
            s(&out),
        ]);
        assert!(o.status.success(), "{input}: {}", stderr(&o));
        assert!(!stderr(&o).contains("clamped"), "{input}: {}", stderr(&o));
        let text = std::fs::read_to_string(&out).unwrap();
        let k = index(&text, "u_actuator_V");
        let command: Vec<f64> = rows(&text).iter().map(|r| r[k].parse().unwrap()).collect();
        let saturated = index(&text, "y_capsensor_um_saturated");
        let inverted: Vec<f64> = rows(&text)
            .iter()
            .map(|r| r[saturated].parse().unwrap())
            .collect();
        assert_eq!(inverted, [-120.0, -100.0, -80.0], "{input}");
        println!("{input}: commands {command:?} V");
        for (u, right) in command.iter().zip([1.33, 2.30, 3.34]) {
            assert!(
                (u - right).abs() < 0.01,
                "{input}: {u} V, expected about {right} V"
            );
        }
    }
}

/// A hand-built model with a bounded output through its input shaping alone:
/// y = 10 · H(0.1, 8)[tanh(x)] (affine ψ_out). The operator input lies in (−1, 1), so the
/// outputs lie in (−11, 11); from every state the model reaches 10 · [−0.899, 0.899] (k1 inside
/// 99.9 % of tanh's range), the limits of `--saturate`.
const TANH_INPUT_MODEL: &str = include_str!("../../hyst-model/testdata/tanh-input.toml");

/// A desired output that a model bounded by its tanh input shaping cannot reach is refused in
/// the user's units (the value as given, the line, the outputs the state reaches, the limits of
/// `--saturate`), and nothing is written; `--saturate` clamps into the limits instead.
#[test]
fn a_saturating_input_shaping_bounds_the_output_said_in_output_units() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("tanh-in.toml");
    std::fs::write(&model, TANH_INPUT_MODEL).unwrap();
    let out = dir.path().join("cmd.csv");
    std::fs::write(&out, "previous\n").unwrap();
    let cases = [
        // From the lower asymptote (rising through 8.5), up to 10 · (1 − 0.1).
        (
            &[0.0, 5.0, 8.5, 9.5, 12.0, 3.0][..],
            "desired.csv:5: column 1 (\"y_um\"): desired output 9.5 is outside the range \
             (-9.000002, 9.000000) of the outputs the model can reach from its state at this line \
             (its tanh input shaping bounds its operator input); --saturate clamps desired \
             outputs into [-8.990000, 8.990000] (",
        ),
        // A first sample: the start rule puts the operator input at u0 + k1.
        (
            &[10.5][..],
            "desired.csv:2: column 1 (\"y_um\"): desired output 10.5 is outside the range \
             (-11.00000, 9.000000) of the outputs the model can reach from its state",
        ),
        // Beyond the model's whole range.
        (
            &[-3.0, 12.0][..],
            "desired.csv:3: column 1 (\"y_um\"): desired output 12 is outside the range \
             (-11.00000, 11.00000) of the model's outputs (bounded by its tanh input shaping), \
             which no command reaches; --saturate clamps such values into [-8.990000, 8.990000]",
        ),
    ];
    for (values, expected) in cases {
        let input = dir.path().join("desired.csv");
        let text: String = values.iter().map(|v| format!("{v}\n")).collect();
        std::fs::write(&input, format!("y_um\n{text}")).unwrap();
        let o = HYST.output(&[
            "run",
            "--model",
            s(&model),
            "--inverse",
            s(&input),
            "-o",
            s(&out),
        ]);
        assert_eq!(o.status.code(), Some(1));
        let err = stderr(&o);
        assert!(err.contains(expected), "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "previous\n");
    }
    // --saturate: the first case runs, 9.5 and 12 inverted at 8.99 (v = 0.999, x = atanh 0.999).
    let input = dir.path().join("desired.csv");
    std::fs::write(&input, "y_um\n0\n5\n8.5\n9.5\n12\n3\n").unwrap();
    let o = HYST.output(&[
        "run",
        "--model",
        s(&model),
        "--inverse",
        "--saturate",
        s(&input),
        "-o",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.starts_with(
            "hyst run: --saturate clamped 2 of 6 desired outputs into [-8.990000, 8.990000]"
        ),
        "{err}"
    );
    assert!(
        err.contains(
            "the open range of the model's outputs (bounded by its tanh input shaping) is \
             (-11.00000, 11.00000)"
        ),
        "{err}"
    );
    let text = std::fs::read_to_string(&out).unwrap();
    let (x, inverted) = (index(&text, "x_V"), index(&text, "y_um_saturated"));
    let rows = rows(&text);
    let at = |k: usize| -> Vec<f64> { rows.iter().map(|r| r[k].parse().unwrap()).collect() };
    assert_eq!(at(inverted), [0.0, 5.0, 8.5, 8.99, 8.99, 3.0]);
    let command = at(x);
    assert!((command[3] - 0.999_f64.atanh()).abs() < 1e-9, "{command:?}");
    assert_eq!(command[4], command[3]);
    // The model gives the inverted outputs back.
    let direct = hyst_model::ModelFile::read(&model).unwrap();
    let mut m = direct.evaluator(command[0], false).unwrap();
    for (x, y) in command.iter().zip(at(inverted)) {
        assert!((m.try_step(*x).unwrap() - y).abs() < 1e-9, "{x} -> {y}");
    }
}
