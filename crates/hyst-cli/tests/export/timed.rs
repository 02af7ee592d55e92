//! Timed models (dynamics, a rate term): their compensator and plant exported, run in C and in
//! Rust against `hyst run`, bit for bit; the ones that do not export say why.

use super::*;
use crate::headers::*;

/// The sample period of the timed test records: 2^-10 s, so that `hyst run`'s mean step of
/// their time stamps, (t_last − t_first) / (rows − 1), is this number exactly.
pub(crate) const PERIOD: f64 = 1.0 / 1024.0;

/// A desired output of the piezo model with its first two time derivatives, from rest: a
/// cosine with a third harmonic (reversals and minor loops), `rows` samples of [`PERIOD`].
pub(crate) fn desired(rows: usize) -> Vec<[f64; 3]> {
    let w = 2.0 * std::f64::consts::PI * 3.0;
    (0..rows)
        .map(|i| {
            let t = i as f64 * PERIOD;
            [
                -120.0 + 20.0 * (1.0 - (w * t).cos()) + 4.0 * (1.0 - (3.0 * w * t).cos()),
                20.0 * w * (w * t).sin() + 12.0 * w * (3.0 * w * t).sin(),
                20.0 * w * w * (w * t).cos() + 36.0 * w * w * (3.0 * w * t).cos(),
            ]
        })
        .collect()
}

/// Column `name` of the CSV file `path`.
pub(crate) fn csv_column(path: &Path, name: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = header.iter().position(|h| *h == name).unwrap();
    lines
        .map(|l| l.split(',').nth(k).unwrap().parse().unwrap())
        .collect()
}

/// `hyst run`'s commands for the desired output of [`desired`] (`--inverse`, with its derivative
/// columns) and its outputs for those commands, for the timed model piezo_dyn.toml.
pub(crate) fn timed_reference(dir: &Path, rows: usize) -> (Vec<[f64; 3]>, Vec<f64>, Vec<f64>) {
    let model = model("piezo_dyn");
    let y = desired(rows);
    let mut text = String::from("t,y_capsensor_um,y_capsensor_um_d1,y_capsensor_um_d2\n");
    for (i, d) in y.iter().enumerate() {
        text += &format!("{:?},{:?},{:?},{:?}\n", i as f64 * PERIOD, d[0], d[1], d[2]);
    }
    let input = dir.join("desired.csv");
    std::fs::write(&input, text).unwrap();
    let commands = dir.join("commands.csv");
    let out = HYST.output(&[
        "run",
        "--model",
        model.to_str().unwrap(),
        "--inverse",
        input.to_str().unwrap(),
        "-o",
        commands.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    // The commands are named after the model's input column, its outputs after its output
    // column.
    let u = csv_column(&commands, "u_actuator_V");
    let mut text = String::from("t,u_actuator_V\n");
    for (i, x) in u.iter().enumerate() {
        text += &format!("{:?},{x:?}\n", i as f64 * PERIOD);
    }
    let input = dir.join("commands_in.csv");
    std::fs::write(&input, text).unwrap();
    let outputs = dir.join("outputs.csv");
    let out = HYST.output(&[
        "run",
        "--model",
        model.to_str().unwrap(),
        input.to_str().unwrap(),
        "-o",
        outputs.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    (y, u, csv_column(&outputs, "y_capsensor_um"))
}

/// `hyst export LANGUAGE` of piezo_dyn.toml (dynamics of order 2) with `--period` into `dir`.
pub(crate) fn export_timed(language: &str, dir: &Path, file: &str) -> PathBuf {
    let path = dir.join(file);
    let out = HYST.output(&[
        "export",
        language,
        model("piezo_dyn").to_str().unwrap(),
        "--period",
        &format!("{PERIOD:?}"),
        "-o",
        path.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    path
}

/// Runs cargo (the one running this test) with `args` on a target folder of its own under the
/// workspace's `target/`, offline: the nested build cannot wait on the lock of this test's.
pub(crate) fn cargo(args: &[&str], dir: &Path) -> Output {
    Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()))
        .args(args)
        .arg("--offline")
        .env("CARGO_TARGET_DIR", repo().join("target/export-test"))
        .current_dir(dir)
        .output()
        .unwrap()
}

/// `source`, a C program, compiled with the host's `cc` (C99, -pedantic -Wall -Wextra -Werror,
/// -O2, floating-point expressions not contracted) against a debug build of the C library of
/// its own (the same numbers as release), and run: its stdout. `None` when there is no C
/// compiler.
pub(crate) fn run_c_against_the_library(dir: &Path, source: &Path) -> Option<String> {
    if Command::new("cc").arg("--version").output().is_err() {
        return None;
    }
    let built = cargo(&["build", "-p", "hyst-capi", "--quiet"], &repo());
    assert!(built.status.success(), "{}", stderr(&built));
    let exe = dir.join("harness");
    let out = Command::new("cc")
        .args([
            "-std=c99",
            "-pedantic",
            "-Wall",
            "-Wextra",
            "-Werror",
            "-O2",
        ])
        .arg("-ffp-contract=off")
        .arg(format!("-I{}", repo().join("include").display()))
        .arg(format!("-I{}", dir.display()))
        .arg(source)
        .arg(repo().join("target/export-test/debug/libhyst.a"))
        .args(["-lm", "-lpthread", "-ldl", "-o"])
        .arg(&exe)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    let run = Command::new(&exe).output().unwrap();
    assert!(run.status.success(), "{run:?}");
    Some(String::from_utf8(run.stdout).unwrap())
}

/// A crate `check` in `dir` over the workspace's hyst-core (with `std`), with the workspace's
/// Cargo.lock (the same versions of hyst-core's dependencies: bit-identical maths) and an empty
/// `src/`: its folder.
pub(crate) fn rust_check_crate(dir: &Path) -> PathBuf {
    let krate = dir.join("check");
    std::fs::create_dir_all(krate.join("src")).unwrap();
    std::fs::write(
        krate.join("Cargo.toml"),
        format!(
            "[package]\nname = \"export-check\"\nversion = \"0.1.0\"\nedition = \"2021\"\n\
             publish = false\n\n[workspace]\n\n[dependencies]\n\
             hyst-core = {{ path = {:?}, features = [\"std\"] }}\n",
            repo().join("crates/hyst-core").display().to_string()
        ),
    )
    .unwrap();
    std::fs::copy(repo().join("Cargo.lock"), krate.join("Cargo.lock")).unwrap();
    krate
}

/// "u BITS" and "y BITS" lines (hex of the f64) against the commands and outputs of hyst run.
pub(crate) fn assert_bit_identical(what: &str, printed: &str, u: &[f64], y: &[f64]) {
    let series = |tag: &str| -> Vec<u64> {
        printed
            .lines()
            .filter_map(|l| l.strip_prefix(tag))
            .map(|h| u64::from_str_radix(h.trim(), 16).unwrap())
            .collect()
    };
    for (tag, reference, name) in [("u ", u, "command"), ("y ", y, "output")] {
        let got = series(tag);
        assert_eq!(got.len(), reference.len(), "{what}: {name}s");
        for (i, (g, r)) in got.iter().zip(reference).enumerate() {
            assert_eq!(
                *g,
                r.to_bits(),
                "{what}: {name} {i}: {} against hyst run's {r}",
                f64::from_bits(*g)
            );
        }
        println!(
            "{what}: {} {name}s bit-identical to hyst run",
            reference.len()
        );
    }
}

#[test]
pub(crate) fn a_timed_model_exports_its_compensator_and_its_plant() {
    let dir = tempfile::tempdir().unwrap();
    let header = export_timed("c", dir.path(), "piezo_dyn.h");
    let text = std::fs::read_to_string(&header).unwrap();
    for f in [
        "piezo_dyn_timed_compensator_init(",
        "piezo_dyn_timed_compensator_step(",
        "piezo_dyn_timed_compensator_reset(",
        "piezo_dyn_timed_init(",
        "piezo_dyn_timed_step(",
        "piezo_dyn_timed_reset(",
        "piezo_dyn_init_inverse(",
    ] {
        for suffix in ["", "_f32"] {
            let f = f.replace('(', &format!("{suffix}("));
            assert!(text.contains(&f), "{f} missing");
        }
    }
    assert!(text.contains("#define PIEZO_DYN_ORDER 2"));
    assert!(text.contains("#define PIEZO_DYN_PERIOD 0.0009765625"));
    let source = r#"#include "piezo_dyn.h"
int main(void) {
    piezo_dyn_timed_compensator c;
    piezo_dyn_timed_state_f32 s;
    const double desired[PIEZO_DYN_ORDER + 1] = {-100.0, 0.0, 0.0};
    double u;
    float y;
    if (piezo_dyn_timed_compensator_init(&c) != HYST_OK || piezo_dyn_timed_init_f32(&s) != HYST_OK)
        return 1;
    (void)piezo_dyn_timed_compensator_step(&c, desired, &u);
    (void)piezo_dyn_timed_step_f32(&s, 0.5f, &y);
    return piezo_dyn_timed_reset_f32(&s) == HYST_OK ? 0 : 1;
}
"#;
    for (compiler, flags) in [("cc", &["-std=c99", "-pedantic"][..]), ("c++", &[][..])] {
        if let Some(out) = compiles(compiler, flags, dir.path(), source) {
            assert!(out.status.success(), "{compiler}: {}", stderr(&out));
        }
    }
    let rust = std::fs::read_to_string(export_timed("rust", dir.path(), "piezo_dyn.rs")).unwrap();
    for f in [
        "pub fn piezo_dyn_timed_compensator<T: hyst_core::Real>(",
        "pub fn piezo_dyn_reference<T: hyst_core::Real>(",
        "pub fn piezo_dyn_timed<T: hyst_core::Real>()",
        "pub const PIEZO_DYN_ORDER: usize = 2;",
        "pub const PIEZO_DYN_PERIOD: f64 = 0.0009765625;",
    ] {
        assert!(rust.contains(f), "{f} missing");
    }
    assert!(!rust.contains("\nuse "), "{rust}");
    // Without --period: the compensator, and no model with its plant (which needs the period).
    let out = HYST.output(&["export", "c", model("piezo_dyn").to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("piezo_dyn_timed_compensator_step(") && !text.contains("_timed_step("));
    assert!(text.contains("export with `--period SECONDS`"), "{text}");
}

#[test]
pub(crate) fn timed_models_that_do_not_export_say_why_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let good = std::fs::read_to_string(model("piezo_dyn")).unwrap();
    let friction = std::fs::read_to_string(model("friction")).unwrap();
    let stop =
        friction.replacen("version = 3", "version = 4", 1) + "\n[dynamics]\nb = 1.0\na = [0.02]\n";
    let cases = [
        (
            "rate",
            good.clone() + "\n[rate]\nc = 0.01\n",
            &[][..],
            "a rate term",
        ),
        ("stop", stop.clone(), &[][..], "--period SECONDS"),
        ("zero", good.clone(), &["--period", "0"][..], "--period 0"),
        (
            "nan",
            good.clone(),
            &["--period", "NaN"][..],
            "--period NaN",
        ),
    ];
    for (case, text, extra, expected) in cases {
        let input = dir.path().join(format!("{case}.toml"));
        std::fs::write(&input, &text).unwrap();
        for lang in ["c", "rust"] {
            let output = dir.path().join(format!("{case}.{lang}"));
            let mut args = vec!["export", lang, input.to_str().unwrap()];
            args.extend(extra);
            args.extend(["--name", "m", "-o", output.to_str().unwrap()]);
            let out = HYST.output(&args);
            assert!(!out.status.success(), "{case} {lang}");
            let e = stderr(&out);
            assert!(e.contains(expected), "{case} {lang}: {e}");
            assert!(!output.exists(), "{case} {lang}");
        }
    }
    // The stop form with dynamics and a period: its model with the plant.
    let input = dir.path().join("stop.toml");
    let out = HYST.output(&[
        "export",
        "c",
        input.to_str().unwrap(),
        "--name",
        "m",
        "--period",
        "0.001",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("m_timed_step(") && !text.contains("m_timed_compensator"));
}

/// The exported C of a timed model, on the host against the host library, gives `hyst run`'s
/// commands (`--inverse` with the derivative columns) and outputs (direct, on a timed record of
/// the exported period), bit for bit.
#[test]
pub(crate) fn exported_c_of_a_timed_model_equals_hyst_run() {
    let dir = tempfile::tempdir().unwrap();
    let rows = 600;
    let (y, u, out_y) = timed_reference(dir.path(), rows);
    export_timed("c", dir.path(), "piezo_dyn.h");
    let mut data = format!("#define ROWS {rows}\nstatic const double desired[ROWS][3] = {{\n");
    for d in &y {
        data += &format!("    {{{:?}, {:?}, {:?}}},\n", d[0], d[1], d[2]);
    }
    data += "};\nstatic const double command[ROWS] = {\n";
    for x in &u {
        data += &format!("    {x:?},\n");
    }
    data += "};\n";
    std::fs::write(dir.path().join("data.h"), data).unwrap();
    let harness = dir.path().join("harness.c");
    std::fs::write(
        &harness,
        r#"#include <stdio.h>
#include <string.h>
#include "piezo_dyn.h"
#include "data.h"

static unsigned long long bits(double x) {
    unsigned long long b;
    memcpy(&b, &x, sizeof b);
    return b;
}

int main(void) {
    piezo_dyn_timed_compensator c;
    piezo_dyn_timed_compensator_f32 c32;
    piezo_dyn_timed_state s;
    int i;
    if (piezo_dyn_timed_compensator_init(&c) != HYST_OK ||
        piezo_dyn_timed_compensator_init_f32(&c32) != HYST_OK || piezo_dyn_timed_init(&s) != HYST_OK) {
        return 1;
    }
    for (i = 0; i < ROWS; i++) {
        const float d32[3] = {(float)desired[i][0], (float)desired[i][1], (float)desired[i][2]};
        double u;
        float u32;
        if (piezo_dyn_timed_compensator_step(&c, desired[i], &u) != HYST_OK ||
            piezo_dyn_timed_compensator_step_f32(&c32, d32, &u32) != HYST_OK) {
            return 2;
        }
        printf("u %016llx\n", bits(u));
        printf("f %.9g\n", (double)u32);
    }
    for (i = 0; i < ROWS; i++) {
        double y;
        if (piezo_dyn_timed_step(&s, command[i], &y) != HYST_OK) {
            return 3;
        }
        printf("y %016llx\n", bits(y));
    }
    return 0;
}
"#,
    )
    .unwrap();
    let Some(printed) = run_c_against_the_library(dir.path(), &harness) else {
        println!("no C compiler (cc): the exported C is not run");
        return;
    };
    assert_bit_identical("exported C", &printed, &u, &out_y);
    // float: the same commands to single precision's resolution of the loop.
    let span =
        u.iter().copied().fold(f64::MIN, f64::max) - u.iter().copied().fold(f64::MAX, f64::min);
    let worst = printed
        .lines()
        .filter_map(|l| l.strip_prefix("f "))
        .zip(&u)
        .map(|(f, r)| (f.parse::<f64>().unwrap() - r).abs())
        .fold(0.0, f64::max);
    println!(
        "exported C in float: largest difference {:.2e} of the commands' span",
        worst / span
    );
    assert!(worst < 1e-3 * span, "{worst}");
}

/// The exported Rust of a timed model, built in a crate of its own over hyst-core (with the
/// platform's maths, as hyst run), gives `hyst run`'s commands and outputs bit for bit.
#[test]
pub(crate) fn exported_rust_of_a_timed_model_equals_hyst_run() {
    let dir = tempfile::tempdir().unwrap();
    let rows = 600;
    let (y, u, out_y) = timed_reference(dir.path(), rows);
    let krate = rust_check_crate(dir.path());
    export_timed("rust", &krate.join("src"), "piezo_dyn.rs");
    let mut data = String::from("const DESIRED: &[[f64; 3]] = &[\n");
    for d in &y {
        data += &format!("    [{:?}, {:?}, {:?}],\n", d[0], d[1], d[2]);
    }
    data += "];\nconst COMMAND: &[f64] = &[\n";
    for x in &u {
        data += &format!("    {x:?},\n");
    }
    data += "];\n";
    std::fs::write(krate.join("src/data.rs"), data).unwrap();
    std::fs::write(
        krate.join("src/main.rs"),
        r#"#![allow(clippy::all, dead_code)]
include!("piezo_dyn.rs");
include!("data.rs");

fn main() {
    let mut c = piezo_dyn_timed_compensator::<f64>(DESIRED[0][0]).unwrap();
    for d in DESIRED {
        println!("u {:016x}", c.track(piezo_dyn_reference(d)).unwrap().to_bits());
    }
    // f32 runs too (built and stepped; single precision is not compared).
    let mut c32 = piezo_dyn_timed_compensator::<f32>(DESIRED[0][0] as f32).unwrap();
    let mut m32 = piezo_dyn_timed::<f32>().unwrap();
    for (d, x) in DESIRED.iter().zip(COMMAND) {
        let d = [d[0] as f32, d[1] as f32, d[2] as f32];
        let _ = c32.track(piezo_dyn_reference(&d)).unwrap();
        let _ = m32.try_step(*x as f32).unwrap();
    }
    let mut m = piezo_dyn_timed::<f64>().unwrap();
    for x in COMMAND {
        println!("y {:016x}", m.try_step(*x).unwrap().to_bits());
    }
}
"#,
    )
    .unwrap();
    let run = cargo(&["run", "--quiet"], &krate);
    assert!(run.status.success(), "{}", stderr(&run));
    let printed = String::from_utf8(run.stdout).unwrap();
    assert_bit_identical("exported Rust", &printed, &u, &out_y);
}
