//! `hyst run`'s output as a user sees it (the user's columns are kept): every
//! column of INPUT first, in file order, each cell as read (trimmed; text included), then the
//! computed columns, named after what they are (the model's output column, its input column
//! with `--inverse`, `y` for `--k1/--k2`), with `_out` appended to a name INPUT already has.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use std::path::{Path, PathBuf};

use hyst_core::Operator;

use hyst_test_support::cli::Binary;
use hyst_test_support::files::{numbers, parse_cells, read_cells, repo, s};

const HYST: Binary = Binary::new(env!("CARGO_BIN_EXE_hyst"));

/// A model of the firmware examples: `piezo` (fitted on data/piezo-sine: input
/// `u_actuator_V`, output `y_capsensor_um`), `piezo_dyn` (the same with a plant of order 2),
/// `steel` (fitted on data/bh-loops: `H_A_per_m` to `B_T`, Langevin output shaping).
fn model(name: &str) -> PathBuf {
    repo()
        .join("examples/firmware/models")
        .join(format!("{name}.toml"))
}

/// Runs `hyst run ARGS INPUT -o OUTPUT`; returns OUTPUT's text (panics with stderr on failure).
fn run_ok(args: &[&str], input: &Path, output: &Path) -> String {
    let mut all = vec!["run"];
    all.extend_from_slice(args);
    all.extend_from_slice(&[s(input), "-o", s(output)]);
    let out = HYST.output(&all);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    std::fs::read_to_string(output).unwrap()
}

/// The header line of a CSV text.
fn header(text: &str) -> &str {
    text.lines().next().unwrap()
}

/// The first `rows` data rows of the piezo data (t_s, u_actuator_V, y_capsensor_um).
fn piezo_rows(rows: usize) -> Vec<[f64; 3]> {
    let text = std::fs::read_to_string(repo().join("data/piezo-sine/piezo_sine_1hz.csv")).unwrap();
    text.lines()
        .skip(1)
        .take(rows)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|c| c.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect()
}

/// `H(0.3, 5)` (or its inverse) over `xs`, from no history.
fn plain(xs: &[f64], inverse: bool) -> Vec<f64> {
    if inverse {
        let mut op = hyst_core::InverseHysteresis::new(0.3, 5.0).unwrap();
        xs.iter().map(|x| op.step(*x)).collect()
    } else {
        let mut op = hyst_core::Hysteresis::new(0.3, 5.0).unwrap();
        xs.iter().map(|x| op.step(*x)).collect()
    }
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// INPUT's cells come first, byte for byte as read (trimmed of surrounding spaces): text
/// labels, a quoted cell with a comma and with doubled quotes, numbers in any form (`1.50`,
/// `2e-3`, `.5`, `-0`, `+3`), then `y`, in full precision.
#[test]
fn input_cells_come_first_as_read_then_y() {
    let dir = tempfile::tempdir().unwrap();
    // Each row's cells as written in INPUT, and as OUTPUT holds them.
    let rows: [[(&str, &str); 4]; 6] = [
        [
            ("0", "0"),
            ("up", "up"),
            ("1.50", "1.50"),
            ("\"a,b\"", "\"a,b\""),
        ],
        [
            ("0.5", "0.5"),
            (" down ", "down"),
            ("2e-3", "2e-3"),
            ("plain text", "plain text"),
        ],
        [
            ("1", "1"),
            ("\"a \"\"quoted\"\" word\"", "\"a \"\"quoted\"\" word\""),
            (" -0.25 ", "-0.25"),
            ("+3", "+3"),
        ],
        [("1.5", "1.5"), ("up", "up"), (".5", ".5"), ("1E2", "1E2")],
        [("2", "2"), ("été", "été"), ("-0", "-0"), ("x", "x")],
        [
            ("2.50", "2.50"),
            ("down", "down"),
            ("4.000", "4.000"),
            ("0x1", "0x1"),
        ],
    ];
    let x = [1.5, 2e-3, -0.25, 0.5, -0.0, 4.0];
    let mut text = String::from("t,label,x,other\n");
    for row in &rows {
        text += &row.map(|c| c.0).join(",");
        text.push('\n');
    }
    let input = dir.path().join("in.csv");
    std::fs::write(&input, text).unwrap();
    for inverse in [false, true] {
        let mut args = vec!["--k1", ".3", "--k2", "5"];
        if inverse {
            args.push("--inverse");
        }
        let out = run_ok(&args, &input, &dir.path().join("out.csv"));
        let mut lines = out.lines();
        assert_eq!(lines.next(), Some("t,label,x,other,y"));
        let want = plain(&x, inverse);
        for (i, (row, line)) in rows.iter().zip(lines.by_ref()).enumerate() {
            let cells = row.map(|c| c.1).join(",") + ",";
            let y = line
                .strip_prefix(&cells)
                .unwrap_or_else(|| panic!("row {i}: {line:?} does not start with {cells:?}"));
            assert!(!y.contains(','), "{line}");
            assert_eq!(
                y.parse::<f64>().unwrap().to_bits(),
                want[i].to_bits(),
                "row {i}, inverse {inverse}"
            );
        }
        assert_eq!(lines.next(), None);
        // The output reads back as the input's cells.
        let (names, cells) = read_cells(&dir.path().join("out.csv"));
        assert_eq!(names, ["t", "label", "x", "other", "y"]);
        let labels: Vec<&str> = cells.iter().map(|r| r[1].as_str()).collect();
        assert_eq!(
            labels,
            ["up", "down", "a \"quoted\" word", "up", "été", "down"]
        );
        assert_eq!(cells[0][3], "a,b");
    }
}

/// A model's output is named after the model's output column, its inverse's (the command)
/// after its input column; where INPUT already has that name, `_out` is appended. A file with
/// a column `x` run by a model of `x` still has `x`: INPUT's own.
#[test]
fn computed_columns_are_named_after_the_model_columns() {
    let dir = tempfile::tempdir().unwrap();
    let piezo = model("piezo");
    let data = piezo_rows(400);
    let write = |name: &str, header: &str, pick: &dyn Fn(&[f64; 3]) -> Vec<f64>| -> PathBuf {
        let mut text = format!("{header}\n");
        for r in &data {
            let cells: Vec<String> = pick(r).iter().map(|v| format!("{v:?}")).collect();
            text += &cells.join(",");
            text.push('\n');
        }
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        path
    };
    let commands = write("u.csv", "t_s,u_actuator_V", &|r| vec![r[0], r[1]]);
    let measured = write("all.csv", "t_s,u_actuator_V,y_capsensor_um", &|r| {
        r.to_vec()
    });
    let out = dir.path().join("out.csv");

    // Direct: the model's output column.
    let direct = run_ok(&["--model", s(&piezo)], &commands, &out);
    assert_eq!(header(&direct), "t_s,u_actuator_V,y_capsensor_um");
    let (names, cells) = parse_cells(&direct);
    let predicted = numbers(&names, &cells, "y_capsensor_um");
    // On the training data, which has y_capsensor_um: the prediction is y_capsensor_um_out,
    // the same numbers, next to the measured column.
    let beside = run_ok(&["--model", s(&piezo)], &measured, &out);
    assert_eq!(
        header(&beside),
        "t_s,u_actuator_V,y_capsensor_um,y_capsensor_um_out"
    );
    let (names, cells) = parse_cells(&beside);
    assert_eq!(
        bits(&numbers(&names, &cells, "y_capsensor_um_out")),
        bits(&predicted)
    );
    let y: Vec<f64> = data.iter().map(|r| r[2]).collect();
    assert_eq!(numbers(&names, &cells, "y_capsensor_um"), y);

    // --inverse: the model's input column (the command), here from the predicted outputs.
    let desired = dir.path().join("desired.csv");
    let mut text = String::from("t_s,y_capsensor_um\n");
    for (r, y) in data.iter().zip(&predicted) {
        text += &format!("{:?},{y:?}\n", r[0]);
    }
    std::fs::write(&desired, text).unwrap();
    let inverse = run_ok(&["--model", s(&piezo), "--inverse"], &desired, &out);
    assert_eq!(header(&inverse), "t_s,y_capsensor_um,u_actuator_V");
    let (names, cells) = parse_cells(&inverse);
    let u = numbers(&names, &cells, "u_actuator_V");
    for (i, (u, r)) in u.iter().zip(&data).enumerate() {
        assert!((u - r[1]).abs() < 1e-9, "row {i}: {u} vs {}", r[1]);
    }
    // … and on the data, which has u_actuator_V: u_actuator_V_out.
    let inverse = run_ok(&["--model", s(&piezo), "--inverse"], &measured, &out);
    assert_eq!(
        header(&inverse),
        "t_s,u_actuator_V,y_capsensor_um,u_actuator_V_out"
    );

    // A model of x and y (crates/hyst-model/testdata), and the same with other names.
    let xy = repo().join("crates/hyst-model/testdata/static-model.toml");
    let renamed = dir.path().join("renamed.toml");
    let toml = std::fs::read_to_string(&xy).unwrap();
    assert!(toml.contains("[columns]\ninput = \"x\"\noutput = \"y\"\n"));
    std::fs::write(
        &renamed,
        toml.replace(
            "[columns]\ninput = \"x\"\noutput = \"y\"\n",
            "[columns]\ninput = \"coil_A\"\noutput = \"flux_Wb\"\n",
        ),
    )
    .unwrap();
    let file = dir.path().join("x.csv");
    std::fs::write(&file, "x\n0.5\n1\n0.25\n").unwrap();
    let with_x = run_ok(&["--model", s(&xy)], &file, &out);
    assert_eq!(header(&with_x), "x,y");
    let with_names = run_ok(&["--model", s(&renamed), "--column", "x"], &file, &out);
    assert_eq!(header(&with_names), "x,flux_Wb");
    // The same numbers whatever the names.
    let strip = |t: &str| t.lines().skip(1).collect::<Vec<_>>().join("\n");
    assert_eq!(strip(&with_x), strip(&with_names));
    let back = run_ok(
        &["--model", s(&renamed), "--inverse", "--column", "x"],
        &file,
        &out,
    );
    assert_eq!(header(&back), "x,coil_A");
    std::fs::write(&file, "y,x\n2,0\n3,1\n").unwrap();
    let back = run_ok(&["--model", s(&xy), "--inverse"], &file, &out);
    assert_eq!(header(&back), "y,x,x_out");
}

/// `--record` with a text label column: the operator restarts wherever the label changes (a
/// label that comes back is a new record), exactly as if each record's rows were a file of
/// their own; the labels are passed through in their place.
#[test]
fn text_records_restart_at_each_label_and_are_passed_through() {
    let dir = tempfile::tempdir().unwrap();
    // Records of different labels (one of them quoted, with a comma), `up` twice.
    let labels = ["up", "down", "\"a,b\"", "up"];
    let mut records: Vec<(&str, Vec<(f64, f64)>)> = Vec::new();
    for (r, label) in labels.iter().enumerate() {
        let rows: Vec<(f64, f64)> = (0..30)
            .map(|i| {
                let t = (r * 30 + i) as f64 * 0.01;
                (t, 20.0 + 15.0 * (t * 9.0 + r as f64).sin())
            })
            .collect();
        records.push((label, rows));
    }
    let file = |records: &[(&str, Vec<(f64, f64)>)]| {
        let mut text = String::from("t,label,u_actuator_V\n");
        for (label, rows) in records {
            for (t, u) in rows {
                text += &format!("{t:?},{label},{u:?}\n");
            }
        }
        text
    };
    let input = dir.path().join("in.csv");
    std::fs::write(&input, file(&records)).unwrap();
    let piezo = model("piezo");
    let piezo_dyn = model("piezo_dyn");
    for (args, computed) in [
        (
            vec!["--k1", ".3", "--k2", "5", "--column", "u_actuator_V"],
            "y",
        ),
        (
            vec![
                "--k1",
                ".3",
                "--k2",
                "5",
                "--inverse",
                "--column",
                "u_actuator_V",
            ],
            "y",
        ),
        (vec!["--model", s(&piezo)], "y_capsensor_um"),
        (vec!["--model", s(&piezo_dyn)], "y_capsensor_um"),
    ] {
        let together = run_ok(
            &[&args[..], &["--record", "label"]].concat(),
            &input,
            &dir.path().join("out.csv"),
        );
        assert_eq!(
            header(&together),
            format!("t,label,u_actuator_V,{computed}"),
            "{args:?}"
        );
        let (names, cells) = parse_cells(&together);
        let got: Vec<&str> = cells.iter().map(|r| r[1].as_str()).collect();
        let want: Vec<&str> = records
            .iter()
            .flat_map(|(l, rows)| std::iter::repeat_n(l.trim_matches('"'), rows.len()))
            .collect();
        assert_eq!(got, want, "the labels are passed through");
        let y = numbers(&names, &cells, computed);
        let mut alone_y = Vec::new();
        for (k, record) in records.iter().enumerate() {
            let part = dir.path().join(format!("part{k}.csv"));
            std::fs::write(&part, file(std::slice::from_ref(record))).unwrap();
            let alone = run_ok(&args, &part, &dir.path().join("alone.csv"));
            let (names, cells) = parse_cells(&alone);
            alone_y.extend(numbers(&names, &cells, computed));
        }
        assert_eq!(bits(&y), bits(&alone_y), "{args:?}");
        // Without --record the file is one history: the second `up` does not restart.
        let one = run_ok(&args, &input, &dir.path().join("one.csv"));
        let (names, cells) = parse_cells(&one);
        let one_y = numbers(&names, &cells, computed);
        assert_ne!(
            one_y[90], y[90],
            "{args:?}: the repeated label starts a new record"
        );
    }
}

/// Numeric record cells are compared as numbers: 1, 1.0 and 1e0 are one record.
#[test]
fn numeric_record_cells_are_compared_as_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let numeric = dir.path().join("numeric.csv");
    std::fs::write(&numeric, "r,x\n1,0\n1.0,1\n1e0,0.5\n2,0.5\n").unwrap();
    let out = run_ok(
        &["--k1", ".3", "--k2", "5", "--record", "r"],
        &numeric,
        &dir.path().join("out.csv"),
    );
    let want = plain(&[0.0, 1.0, 0.5], false);
    let mut lines = out.lines().skip(1);
    for (cells, y) in [
        ("1,0,", want[0]),
        ("1.0,1,", want[1]),
        ("1e0,0.5,", want[2]),
    ] {
        let line = lines.next().unwrap();
        let got = line.strip_prefix(cells).unwrap_or_else(|| panic!("{line}"));
        assert_eq!(got.parse::<f64>().unwrap().to_bits(), y.to_bits(), "{line}");
    }
    assert_eq!(lines.next(), Some("2,0.5,0.5"));
}

/// `--saturate` writes `<column>_saturated`: the desired output actually inverted (clamped
/// into the limits where it was beyond them), after the command; the desired output itself is
/// passed through as read.
#[test]
fn saturate_writes_the_desired_output_inverted_as_column_saturated() {
    let dir = tempfile::tempdir().unwrap();
    let steel = model("steel");
    let (lo, hi) = hyst_model::ModelFile::read(&steel)
        .unwrap()
        .saturation()
        .unwrap()
        .limits;
    let input = dir.path().join("desired.csv");
    let values = ["0.1", "1.5", "-9", "0.50", "30"];
    let mut text = String::from("t,B_ref\n");
    for (i, v) in values.iter().enumerate() {
        text += &format!("{i},{v}\n");
    }
    std::fs::write(&input, text).unwrap();
    let out = dir.path().join("out.csv");
    let args = [
        "--model",
        s(&steel),
        "--inverse",
        "--saturate",
        "--column",
        "B_ref",
    ];
    let got = run_ok(&args, &input, &out);
    assert_eq!(header(&got), "t,B_ref,H_A_per_m,B_ref_saturated");
    let (names, cells) = parse_cells(&got);
    let passed: Vec<&str> = cells.iter().map(|r| r[1].as_str()).collect();
    assert_eq!(passed, values);
    let saturated = numbers(&names, &cells, "B_ref_saturated");
    assert!(lo < 0.1 && hi > 0.5 && hi < 30.0, "limits [{lo}, {hi}]");
    let want = [0.1, 1.5_f64.clamp(lo, hi), lo, 0.5, hi];
    assert_eq!(saturated, want);
    // The command is the inverse of what was inverted: the desired outputs of
    // `_saturated` as a file give the same commands without --saturate.
    let clamped = dir.path().join("clamped.csv");
    let mut text = String::from("B_T\n");
    for v in &saturated {
        text += &format!("{v:?}\n");
    }
    std::fs::write(&clamped, text).unwrap();
    let plain = run_ok(
        &["--model", s(&steel), "--inverse"],
        &clamped,
        &dir.path().join("plain.csv"),
    );
    assert_eq!(header(&plain), "B_T,H_A_per_m");
    let (plain_names, plain_cells) = parse_cells(&plain);
    assert_eq!(
        bits(&numbers(&names, &cells, "H_A_per_m")),
        bits(&numbers(&plain_names, &plain_cells, "H_A_per_m"))
    );
    // The model's own output column as input: B_T_saturated (and B_T passed through).
    let got = run_ok(
        &["--model", s(&steel), "--inverse", "--saturate"],
        &clamped,
        &out,
    );
    assert_eq!(header(&got), "B_T,H_A_per_m,B_T_saturated");
}

/// `--derivatives 2` names the derivatives after the computed column: `BASE_d1, BASE_d2`
/// (after its `_out`, if it got one).
#[test]
fn derivatives_are_named_after_the_computed_column() {
    let dir = tempfile::tempdir().unwrap();
    let jets = |name: &str, extra: &str| -> PathBuf {
        let mut text = format!("{name},{name}_d1,{name}_d2{extra}\n");
        for i in 0..200 {
            let t = f64::from(i) * 1e-3;
            let (v, d1, d2) = (
                30.0 + 20.0 * (5.0 * t).sin(),
                100.0 * (5.0 * t).cos(),
                -500.0 * (5.0 * t).sin(),
            );
            let other = if extra.is_empty() { "" } else { ",0" };
            text += &format!("{v:?},{d1:?},{d2:?}{other}\n");
        }
        let path = dir.path().join(format!("{name}{}.csv", extra.len()));
        std::fs::write(&path, text).unwrap();
        path
    };
    let out = dir.path().join("out.csv");
    let d2 = ["--derivatives", "2"];
    let u = jets("u_actuator_V", "");
    let y = jets("y_capsensor_um", "");
    let piezo = model("piezo");
    for (args, input, expected) in [
        (
            vec!["--k1", ".3", "--k2", "5", "--column", "u_actuator_V"],
            &u,
            "u_actuator_V,u_actuator_V_d1,u_actuator_V_d2,y,y_d1,y_d2",
        ),
        (
            vec!["--model", s(&piezo)],
            &u,
            "u_actuator_V,u_actuator_V_d1,u_actuator_V_d2,y_capsensor_um,y_capsensor_um_d1,\
             y_capsensor_um_d2",
        ),
        (
            vec!["--model", s(&piezo), "--inverse"],
            &y,
            "y_capsensor_um,y_capsensor_um_d1,y_capsensor_um_d2,u_actuator_V,u_actuator_V_d1,\
             u_actuator_V_d2",
        ),
    ] {
        let got = run_ok(&[&args[..], &d2[..]].concat(), input, &out);
        assert_eq!(header(&got), expected, "{args:?}");
    }
    // INPUT has the command's name already: u_actuator_V_out, u_actuator_V_out_d1, …
    let clash = jets("y_capsensor_um", ",u_actuator_V");
    let got = run_ok(
        &[&["--model", s(&piezo), "--inverse"][..], &d2[..]].concat(),
        &clash,
        &out,
    );
    assert_eq!(
        header(&got),
        "y_capsensor_um,y_capsensor_um_d1,y_capsensor_um_d2,u_actuator_V,u_actuator_V_out,\
         u_actuator_V_out_d1,u_actuator_V_out_d2"
    );
}

/// Writes `text` to `data.csv` and a previous `out.csv`, runs `hyst run ARGS data.csv -o
/// out.csv`, and checks that it fails with every `expected` piece in stderr and leaves `out.csv`
/// as it was and nothing else behind.
fn refused(args: &[&str], text: &str, expected: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("data.csv");
    std::fs::write(&input, text).unwrap();
    let out_path = dir.path().join("out.csv");
    std::fs::write(&out_path, "previous\n").unwrap();
    let mut all = vec!["run"];
    all.extend_from_slice(args);
    all.extend_from_slice(&[s(&input), "-o", s(&out_path)]);
    let out = HYST.output(&all);
    assert_eq!(out.status.code(), Some(1), "{args:?} on {text:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    for e in expected {
        assert!(err.contains(e), "{args:?}: {err:?} lacks {e:?}");
    }
    assert_eq!(std::fs::read_to_string(&out_path).unwrap(), "previous\n");
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        2,
        "leftovers"
    );
}

/// Only the columns run (and their derivatives) must hold numbers: a text cell there is refused
/// with the file, line, column and value, and nothing is written; a text cell in any other
/// column is passed through.
#[test]
fn text_in_a_column_run_is_refused_and_elsewhere_passed_through() {
    let k = ["--k1", ".3", "--k2", "5"];
    refused(
        &k,
        "t,label,x\n0,a,1\n# a comment\n1,b,up\n",
        &["data.csv:4: column 3 (\"x\"): cannot parse \"up\""],
    );
    refused(
        &[&k[..], &["--derivatives", "1"]].concat(),
        "x,x_d1,note\n0,1,a\n0.5,fast,b\n",
        &["data.csv:3: column 2 (\"x_d1\"): cannot parse \"fast\""],
    );
    refused(
        &[&k[..], &["--column", "a", "--column", "b"]].concat(),
        "a,b,c\n1,2,x\n1,2,y\n3,n/a,z\n",
        &["data.csv:4: column 2 (\"b\"): cannot parse \"n/a\""],
    );
    refused(
        &["--model", s(&model("piezo"))],
        "u_actuator_V,note\n1,a\n,b\n",
        &["data.csv:3: column 1 (\"u_actuator_V\")"],
    );
    refused(
        &["--model", s(&model("piezo_dyn"))],
        "t,u_actuator_V\n0,1\n0.001,2\n0.002,high\n",
        &["data.csv:4: column 2 (\"u_actuator_V\"): cannot parse \"high\""],
    );
    // The same text in columns not run.
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("data.csv");
    std::fs::write(&input, "t,label,x\n0,a,1\nlater,up,0.5\n").unwrap();
    let out = run_ok(&k, &input, &dir.path().join("out.csv"));
    let y = plain(&[1.0, 0.5], false)[1];
    let (head, last) = out.rsplit_once(',').unwrap();
    assert_eq!(head, "t,label,x,y\n0,a,1,1\nlater,up,0.5");
    assert_eq!(
        last.trim_end().parse::<f64>().unwrap().to_bits(),
        y.to_bits()
    );
    std::fs::write(&input, "x,x_d1,note\n0,1,slow\n0.5,-1,fast\n").unwrap();
    let out = run_ok(
        &[&k[..], &["--derivatives", "1"]].concat(),
        &input,
        &dir.path().join("out.csv"),
    );
    assert!(out.starts_with("x,x_d1,note,y,y_d1\n0,1,slow,"), "{out}");
}

/// Several `--column`s: `BASE_a, BASE_b` (and `BASE_a_d1, BASE_b_d1` with derivatives) after
/// every input column, each the output of that column alone.
#[test]
fn several_columns_are_named_base_column() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.csv");
    let mut text = String::from("t,a,a_d1,b,b_d1,note\n");
    for i in 0..300 {
        let t = f64::from(i) * 1e-2;
        let (a, da) = (20.0 + 10.0 * (3.0 * t).sin(), 30.0 * (3.0 * t).cos());
        let (b, db) = (40.0 - 15.0 * (2.0 * t).cos(), 30.0 * (2.0 * t).sin());
        text += &format!("{t:?},{a:?},{da:?},{b:?},{db:?},n{i}\n");
    }
    std::fs::write(&input, text).unwrap();
    let piezo = model("piezo");
    let out = dir.path().join("out.csv");
    let alone = dir.path().join("alone.csv");
    for (args, base, n) in [
        (vec!["--k1", ".3", "--k2", "5"], "y", 0),
        (
            vec!["--k1", ".3", "--k2", "5", "--derivatives", "1"],
            "y",
            1,
        ),
        (vec!["--model", s(&piezo)], "y_capsensor_um", 0),
        (
            vec!["--model", s(&piezo), "--derivatives", "1"],
            "y_capsensor_um",
            1,
        ),
        (vec!["--model", s(&piezo), "--inverse"], "u_actuator_V", 0),
    ] {
        let both = [&args[..], &["--column", "a", "--column", "b"]].concat();
        let got = run_ok(&both, &input, &out);
        let mut expected = format!("t,a,a_d1,b,b_d1,note,{base}_a,{base}_b");
        if n == 1 {
            expected += &format!(",{base}_a_d1,{base}_b_d1");
        }
        assert_eq!(header(&got), expected, "{both:?}");
        let (names, cells) = parse_cells(&got);
        for column in ["a", "b"] {
            let single = run_ok(&[&args[..], &["--column", column]].concat(), &input, &alone);
            let (single_names, single_cells) = parse_cells(&single);
            let mut pairs = vec![(format!("{base}_{column}"), base.to_string())];
            if n == 1 {
                pairs.push((format!("{base}_{column}_d1"), format!("{base}_d1")));
            }
            for (together, by_itself) in pairs {
                let (t, a) = (
                    numbers(&names, &cells, &together),
                    numbers(&single_names, &single_cells, &by_itself),
                );
                if args[0] == "--k1" && n == 0 {
                    // Plain operators run as one bank: within its stated tolerance.
                    for (t, a) in t.iter().zip(&a) {
                        assert!((t - a).abs() <= 1e-13 * a.abs().max(0.3), "{t} vs {a}");
                    }
                } else {
                    assert_eq!(bits(&t), bits(&a), "{both:?}: {together}");
                }
            }
        }
    }
}

/// A model with dynamics passes INPUT's columns through as well, text included, and names the
/// command and the prefiltered reference after the model's input column and the column run.
#[test]
fn a_timed_model_passes_the_columns_through_and_names_its_own() {
    let dir = tempfile::tempdir().unwrap();
    let piezo_dyn = model("piezo_dyn");
    let input = dir.path().join("in.csv");
    let mut text = String::from("t,label,u_actuator_V\n");
    for i in 0..200 {
        let t = f64::from(i) / 1024.0;
        let label = if i < 100 { "\"first, rising\"" } else { "next" };
        text += &format!("{t:?},{label},{:?}\n", 20.0 + 0.1 * f64::from(i));
    }
    std::fs::write(&input, text).unwrap();
    let out = dir.path().join("out.csv");
    let direct = run_ok(&["--model", s(&piezo_dyn)], &input, &out);
    assert_eq!(header(&direct), "t,label,u_actuator_V,y_capsensor_um");
    let (names, cells) = parse_cells(&direct);
    assert_eq!(cells[0][1], "first, rising");
    assert_eq!(cells[150][1], "next");
    let y = numbers(&names, &cells, "y_capsensor_um");
    // Its prediction as the desired output, prefiltered: the command is u_actuator_V_out
    // (INPUT has u_actuator_V), the reference tracked y_capsensor_um_filtered.
    let mut text = String::from("t,label,u_actuator_V,y_capsensor_um\n");
    for (row, y) in cells.iter().zip(&y) {
        text += &format!("{},{},{},{y:?}\n", row[0], row[1], row[2]);
    }
    text = text.replace("first, rising", "\"first, rising\"");
    let desired = dir.path().join("desired.csv");
    std::fs::write(&desired, text).unwrap();
    let inverse = run_ok(
        &[
            "--model",
            s(&piezo_dyn),
            "--inverse",
            "--prefilter-hz",
            "20",
        ],
        &desired,
        &out,
    );
    assert_eq!(
        header(&inverse),
        "t,label,u_actuator_V,y_capsensor_um,u_actuator_V_out,y_capsensor_um_filtered"
    );
    let (names, cells) = parse_cells(&inverse);
    assert_eq!(cells[0][1], "first, rising");
    assert_eq!(numbers(&names, &cells, "y_capsensor_um"), y);
}

/// A model with dynamics writes INPUT's numeric cells as read, as a static model does
/// (`0.000`, `10.50`, `12e0` stay so).
#[test]
fn a_timed_model_writes_numeric_cells_as_read() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.csv");
    std::fs::write(
        &input,
        "t,u_actuator_V,note\n0.000,10.50,a\n0.001,11,b\n0.002,12e0,c\n",
    )
    .unwrap();
    for m in ["piezo", "piezo_dyn"] {
        let out = run_ok(
            &["--model", s(&model(m))],
            &input,
            &dir.path().join("out.csv"),
        );
        let firsts: Vec<String> = out
            .lines()
            .map(|l| l.rsplit_once(',').unwrap().0.to_string())
            .collect();
        assert_eq!(
            firsts,
            [
                "t,u_actuator_V,note",
                "0.000,10.50,a",
                "0.001,11,b",
                "0.002,12e0,c"
            ],
            "{m}"
        );
    }
}
