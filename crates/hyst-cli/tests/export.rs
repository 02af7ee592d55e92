//! `hyst export c|rust`: the generated files compile (C99 with -Wall -Wextra -Werror, C++), say
//! where they came from, and bad input (an unknown kind, a newer format version, a name that is
//! no C identifier or clashes with hyst.h's) gets a clear error and writes nothing.
//! scripts/test-firmware runs the generated code against `hyst run` on the host and under QEMU.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod common;
use common::{hyst, repo};

fn model(name: &str) -> PathBuf {
    repo()
        .join("examples/firmware/models")
        .join(format!("{name}.toml"))
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Compiles `source` (which includes the generated header) with `compiler` and `flags`, syntax
/// only; `None` when the compiler is not installed.
fn compiles(compiler: &str, flags: &[&str], dir: &Path, source: &str) -> Option<Output> {
    let file = dir.join(if compiler.ends_with("++") {
        "use.cpp"
    } else {
        "use.c"
    });
    std::fs::write(&file, source).unwrap();
    let include = repo().join("include");
    Command::new(compiler)
        .args(flags)
        .args(["-Wall", "-Wextra", "-Werror", "-fsyntax-only"])
        .arg(format!("-I{}", include.display()))
        .arg(format!("-I{}", dir.display()))
        .arg(&file)
        .output()
        .ok()
}

#[test]
fn every_smooth_model_exports_a_header_that_compiles() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["piezo", "steel", "friction"] {
        let header = dir.path().join(format!("{name}.h"));
        let out = hyst(&[
            "export",
            "c",
            model(name).to_str().unwrap(),
            "--name",
            name,
            "-o",
            header.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{name}: {}", stderr(&out));
        let text = std::fs::read_to_string(&header).unwrap();
        assert!(
            text.contains(&format!("source: {}", model(name).display())),
            "{text}"
        );
        assert!(text.contains("FNV-1a 64 of its bytes"));
        for f in ["_init(", "_init_inverse(", "_step(", "_reset(", "_params("] {
            for suffix in ["", "_f32"] {
                let f = f.replace('(', &format!("{suffix}("));
                assert!(text.contains(&format!("{name}{f}")), "{name}{f} missing");
            }
        }
        let source = format!(
            "#include \"{name}.h\"\nint main(void) {{\n    {name}_state s;\n    \
             {name}_state_f32 s32;\n    double y;\n    float y32;\n    \
             if ({name}_init(&s) != HYST_OK || {name}_init_f32(&s32) != HYST_OK) return 1;\n    \
             (void){name}_step(&s, 0.5, &y);\n    (void){name}_step_f32(&s32, 0.5f, &y32);\n    \
             (void){name}_init_inverse(&s);\n    return {name}_reset(&s) == HYST_OK ? 0 : 1;\n}}\n"
        );
        for (compiler, flags) in [("cc", &["-std=c99", "-pedantic"][..]), ("c++", &[][..])] {
            if let Some(out) = compiles(compiler, flags, dir.path(), &source) {
                assert!(
                    out.status.success(),
                    "{name} with {compiler}: {}",
                    stderr(&out)
                );
            }
        }
    }
}

#[test]
fn python_and_cli_share_one_generator_and_rust_exports_every_kind() {
    for name in ["piezo", "steel", "friction", "piezo_pi"] {
        let out = hyst(&["export", "rust", model(name).to_str().unwrap()]);
        assert!(out.status.success(), "{name}: {}", stderr(&out));
        let text = String::from_utf8(out.stdout).unwrap();
        assert!(
            text.contains(&format!("pub fn {name}<T: hyst_core::Real>()")),
            "{text}"
        );
        // Paths written in full: the file can be include!d next to another.
        assert!(!text.contains("\nuse "), "{text}");
    }
}

#[test]
fn a_prandtl_ishlinskii_model_is_refused_by_c_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let header = dir.path().join("pi.h");
    let out = hyst(&[
        "export",
        "c",
        model("piezo_pi").to_str().unwrap(),
        "-o",
        header.to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    let e = stderr(&out);
    assert!(
        e.contains("Prandtl-Ishlinskii") && e.contains("hyst.h"),
        "{e}"
    );
    assert!(!header.exists());
}

#[test]
fn bad_input_names_the_problem_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let good = std::fs::read_to_string(model("piezo")).unwrap();
    let cases = [
        (
            "kind",
            good.replacen("kind = \"smooth\"", "kind = \"preisach\"", 1),
            "piezo",
            "preisach",
        ),
        (
            "newer",
            good.replacen("version = 1", "version = 99", 1),
            "piezo",
            "version 99",
        ),
        ("digit", good.clone(), "2axis", "starts with a digit"),
        ("dash", good.clone(), "stage-x", "'-' is not allowed"),
        ("clash", good.clone(), "hyst_model", "clash with hyst.h"),
        ("keyword", good.clone(), "double", "keyword"),
    ];
    for (case, text, name, expected) in cases {
        let input = dir.path().join(format!("{case}.toml"));
        std::fs::write(&input, &text).unwrap();
        let output = dir.path().join(format!("{case}.h"));
        std::fs::write(&output, "kept").unwrap();
        for lang in ["c", "rust"] {
            let out = hyst(&[
                "export",
                lang,
                input.to_str().unwrap(),
                "--name",
                name,
                "-o",
                output.to_str().unwrap(),
            ]);
            assert!(!out.status.success(), "{case} {lang}");
            let e = stderr(&out);
            assert!(e.contains(expected), "{case} {lang}: {e}");
            assert_eq!(std::fs::read_to_string(&output).unwrap(), "kept", "{case}");
        }
    }
    // The model file itself is never the output.
    let input = dir.path().join("self.toml");
    std::fs::write(&input, &good).unwrap();
    let out = hyst(&[
        "export",
        "c",
        input.to_str().unwrap(),
        "--name",
        "piezo",
        "-o",
        input.to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    assert_eq!(std::fs::read_to_string(&input).unwrap(), good);
}

#[test]
fn without_a_name_the_file_name_is_used_when_it_can_be() {
    let out = hyst(&["export", "c", model("piezo").to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(String::from_utf8(out.stdout)
        .unwrap()
        .contains("piezo_init_inverse("));
    let dir = tempfile::tempdir().unwrap();
    let odd = dir.path().join("my model.toml");
    std::fs::copy(model("piezo"), &odd).unwrap();
    let out = hyst(&["export", "c", odd.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("give --name NAME"),
        "{}",
        stderr(&out)
    );
}

/// The sample period of the timed test records: 2^-10 s, so that `hyst run`'s mean step of
/// their time stamps, (t_last − t_first) / (rows − 1), is this number exactly.
const PERIOD: f64 = 1.0 / 1024.0;

/// A desired output of the piezo model with its first two time derivatives, from rest: a
/// cosine with a third harmonic (reversals and minor loops), `rows` samples of [`PERIOD`].
fn desired(rows: usize) -> Vec<[f64; 3]> {
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
fn csv_column(path: &Path, name: &str) -> Vec<f64> {
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
fn timed_reference(dir: &Path, rows: usize) -> (Vec<[f64; 3]>, Vec<f64>, Vec<f64>) {
    let model = model("piezo_dyn");
    let y = desired(rows);
    let mut text = String::from("t,y_capsensor_um,y_capsensor_um_d1,y_capsensor_um_d2\n");
    for (i, d) in y.iter().enumerate() {
        text += &format!("{:?},{:?},{:?},{:?}\n", i as f64 * PERIOD, d[0], d[1], d[2]);
    }
    let input = dir.join("desired.csv");
    std::fs::write(&input, text).unwrap();
    let commands = dir.join("commands.csv");
    let out = hyst(&[
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
    let out = hyst(&[
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
fn export_timed(language: &str, dir: &Path, file: &str) -> PathBuf {
    let path = dir.join(file);
    let out = hyst(&[
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
fn cargo(args: &[&str], dir: &Path) -> Output {
    Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()))
        .args(args)
        .arg("--offline")
        .env("CARGO_TARGET_DIR", repo().join("target/export-test"))
        .current_dir(dir)
        .output()
        .unwrap()
}

/// "u BITS" and "y BITS" lines (hex of the f64) against the commands and outputs of hyst run.
fn assert_bit_identical(what: &str, printed: &str, u: &[f64], y: &[f64]) {
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
fn a_timed_model_exports_its_compensator_and_its_plant() {
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
    let out = hyst(&["export", "c", model("piezo_dyn").to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("piezo_dyn_timed_compensator_step(") && !text.contains("_timed_step("));
    assert!(text.contains("export with `--period SECONDS`"), "{text}");
}

#[test]
fn timed_models_that_do_not_export_say_why_and_write_nothing() {
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
            let out = hyst(&args);
            assert!(!out.status.success(), "{case} {lang}");
            let e = stderr(&out);
            assert!(e.contains(expected), "{case} {lang}: {e}");
            assert!(!output.exists(), "{case} {lang}");
        }
    }
    // The stop form with dynamics and a period: its model with the plant.
    let input = dir.path().join("stop.toml");
    let out = hyst(&[
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
fn exported_c_of_a_timed_model_equals_hyst_run() {
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
    if Command::new("cc").arg("--version").output().is_err() {
        println!("no C compiler (cc): the exported C is not run");
        return;
    }
    // The host library, built here as a debug build of its own (the same numbers as release).
    let built = cargo(&["build", "-p", "hyst-capi", "--quiet"], &repo());
    assert!(built.status.success(), "{}", stderr(&built));
    let lib = repo().join("target/export-test/debug/libhyst.a");
    let exe = dir.path().join("harness");
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
        .arg(format!("-I{}", dir.path().display()))
        .arg(&harness)
        .arg(&lib)
        .args(["-lm", "-lpthread", "-ldl", "-o"])
        .arg(&exe)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    let run = Command::new(&exe).output().unwrap();
    assert!(run.status.success(), "{run:?}");
    let printed = String::from_utf8(run.stdout).unwrap();
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
fn exported_rust_of_a_timed_model_equals_hyst_run() {
    let dir = tempfile::tempdir().unwrap();
    let rows = 600;
    let (y, u, out_y) = timed_reference(dir.path(), rows);
    let krate = dir.path().join("check");
    std::fs::create_dir_all(krate.join("src")).unwrap();
    export_timed("rust", &krate.join("src"), "piezo_dyn.rs");
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
    // The workspace's versions of hyst-core's dependencies (bit-identical maths).
    std::fs::copy(repo().join("Cargo.lock"), krate.join("Cargo.lock")).unwrap();
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

/// The model file piezo_dyn.toml with column names and units that try to end the comment they
/// are written in (C), end its line (Rust), nest a comment, splice lines or reorder the text,
/// each defining an item if it escaped.
fn hostile_model(path: &Path) {
    let quote = |s: &str| {
        let mut q = String::from("\"");
        for c in s.chars() {
            match c {
                '"' | '\\' => q.extend(['\\', c]),
                c if c.is_control() => q.push_str(&format!("\\u{:04X}", u32::from(c))),
                c => q.push(c),
            }
        }
        q + "\""
    };
    let text = std::fs::read_to_string(model("piezo_dyn"))
        .unwrap()
        .replacen(
            "input = \"u_actuator_V\"",
            &format!("input = {}", quote("u*/ int injected_by_column = 1; /*")),
            1,
        )
        .replacen(
            "output = \"y_capsensor_um\"",
            &format!(
                "output = {}",
                quote("y\npub const INJECTED_BY_COLUMN: i32 = 1;\n/* ??/")
            ),
            1,
        )
        .replacen(
            "input = \"\"",
            &format!("input = {}", quote("V\r\n*/ int injected_by_unit; /*\u{0}")),
            1,
        )
        .replacen(
            "output = \"\"",
            &format!(
                "output = {}",
                quote("um\u{202e}\u{2028}\npub const INJECTED_BY_UNIT: i32 = 1;\n\\")
            ),
            1,
        );
    assert!(text.contains("INJECTED_BY_UNIT"), "{text}");
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, text).unwrap();
}

/// A model path, column names and units that try to end the comment they are written in and
/// define an item (`*/` in C, a line feed in Rust, and more): the header compiles with
/// `-std=c99 -pedantic -Wall -Wextra -Werror` and its preprocessed text holds none of the items;
/// the exported Rust builds beside items of the names it would define, and none of its lines
/// outside a comment names one.
#[test]
fn hostile_paths_columns_and_units_inject_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir
        .path()
        .join("a*")
        .join(" int injected_by_path = 42; ")
        .join("\npub const INJECTED_BY_PATH: i32 = 42;\n")
        .join("*b.toml");
    hostile_model(&path);
    let export = |language: &str, output: &Path| {
        let out = hyst(&[
            "export",
            language,
            path.to_str().unwrap(),
            "--name",
            "m",
            "--period",
            "0.001",
            "-o",
            output.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        std::fs::read_to_string(output).unwrap()
    };
    let header = export("c", &dir.path().join("m.h"));
    let source = "#include \"m.h\"\nint main(void) {\n    m_state s;\n    \
                  m_timed_compensator c;\n    \
                  return m_init(&s) == HYST_OK && m_timed_compensator_init(&c) == HYST_OK ? 0 : 1;\n}\n";
    match compiles("cc", &["-std=c99", "-pedantic"], dir.path(), source) {
        Some(out) => assert!(out.status.success(), "{}\n{header}", stderr(&out)),
        None => println!("no C compiler (cc): the exported C is not compiled"),
    }
    if let Ok(out) = Command::new("cc")
        .args(["-std=c99", "-E", "-P"])
        .arg(format!("-I{}", repo().join("include").display()))
        .arg(format!("-I{}", dir.path().display()))
        .arg(dir.path().join("use.c"))
        .output()
    {
        assert!(out.status.success(), "{}", stderr(&out));
        let code = String::from_utf8_lossy(&out.stdout);
        assert!(code.contains("m_timed_compensator_init"), "{code}");
        assert!(!code.contains("injected"), "{header}");
    }

    let krate = dir.path().join("check");
    std::fs::create_dir_all(krate.join("src")).unwrap();
    let rust = export("rust", &krate.join("src/m.rs"));
    for line in rust.lines().filter(|l| !l.trim_start().starts_with("//")) {
        assert!(!line.contains("INJECTED"), "{line}\n{rust}");
    }
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
    // A second item of one of these names would not build.
    std::fs::write(
        krate.join("src/main.rs"),
        "#![allow(dead_code)]\ninclude!(\"m.rs\");\n\
         const INJECTED_BY_PATH: i32 = 0;\nconst INJECTED_BY_COLUMN: i32 = 0;\n\
         const INJECTED_BY_UNIT: i32 = 0;\n\
         fn main() {\n    let _ = m_timed::<f64>().unwrap();\n}\n",
    )
    .unwrap();
    let built = cargo(&["build", "--quiet"], &krate);
    assert!(built.status.success(), "{}\n{rust}", stderr(&built));
}

/// The piezo record (0 to 3.6 V) fitted with a tanh or a Langevin input shaping and a tanh
/// output shaping (crates/hyst-model/testdata), exported as C and Rust: the exported inverses
/// clamp no desired output of the training range, and give the commands of `hyst run
/// --inverse` (1.33, 2.30, 3.34 V), bit for bit.
#[test]
fn exported_inverse_of_a_saturating_input_model_keeps_the_training_range() {
    let dir = tempfile::tempdir().unwrap();
    let names = ["piezo_tanh_in", "piezo_langevin_in"];
    let desired = [-120.0, -100.0, -80.0];
    let csv = dir.path().join("desired.csv");
    std::fs::write(&csv, "y_capsensor_um\n-120\n-100\n-80\n").unwrap();
    let krate = dir.path().join("check");
    std::fs::create_dir_all(krate.join("src")).unwrap();
    let mut reference = Vec::new();
    for name in names {
        let file = repo()
            .join("crates/hyst-model/testdata")
            .join(format!("{}.toml", name.replace('_', "-")));
        let out = dir.path().join(format!("{name}.csv"));
        let run = hyst(&[
            "run",
            "--model",
            file.to_str().unwrap(),
            "--inverse",
            csv.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(run.status.success(), "{name}: {}", stderr(&run));
        let u = csv_column(&out, "u_actuator_V");
        for (u, right) in u.iter().zip([1.33, 2.30, 3.34]) {
            assert!(
                (u - right).abs() < 0.01,
                "{name}: hyst run gives {u} V, not about {right}"
            );
        }
        reference.push(u);
        for (language, path) in [
            ("c", dir.path().join(format!("{name}.h"))),
            ("rust", krate.join("src").join(format!("{name}.rs"))),
        ] {
            let o = hyst(&[
                "export",
                language,
                file.to_str().unwrap(),
                "--name",
                name,
                "-o",
                path.to_str().unwrap(),
            ]);
            assert!(o.status.success(), "{name}: {}", stderr(&o));
        }
    }
    let rows: String = desired.iter().map(|y| format!("{y:?}, ")).collect();
    let expected: Vec<u64> = reference.iter().flatten().map(|u| u.to_bits()).collect();
    let printed = |text: &str| -> Vec<u64> {
        text.lines()
            .filter_map(|l| l.strip_prefix("u "))
            .map(|h| u64::from_str_radix(h.trim(), 16).unwrap())
            .collect()
    };
    // C, on the host against the host library.
    if Command::new("cc").arg("--version").output().is_ok() {
        let mut harness = String::from(
            "#include <stdio.h>\n#include <string.h>\n#include \"piezo_tanh_in.h\"\n\
             #include \"piezo_langevin_in.h\"\n\n\
             static unsigned long long bits(double x) {\n    unsigned long long b;\n    \
             memcpy(&b, &x, sizeof b);\n    return b;\n}\n\n",
        );
        harness += &format!("static const double desired[3] = {{{rows}}};\n\n");
        harness += "int main(void) {\n    int i;\n";
        for name in names {
            harness += &format!(
                "    {{\n        {name}_state s;\n        \
                 if ({name}_init_inverse(&s) != HYST_OK) return 1;\n        \
                 for (i = 0; i < 3; i++) {{\n            double u;\n            \
                 if ({name}_step(&s, desired[i], &u) != HYST_OK) return 2;\n            \
                 printf(\"u %016llx\\n\", bits(u));\n        }}\n        \
                 if (s.clamped != 0) return 3;\n    }}\n"
            );
        }
        harness += "    return 0;\n}\n";
        let source = dir.path().join("harness.c");
        std::fs::write(&source, harness).unwrap();
        let built = cargo(&["build", "-p", "hyst-capi", "--quiet"], &repo());
        assert!(built.status.success(), "{}", stderr(&built));
        let exe = dir.path().join("harness");
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
            .arg(format!("-I{}", dir.path().display()))
            .arg(&source)
            .arg(repo().join("target/export-test/debug/libhyst.a"))
            .args(["-lm", "-lpthread", "-ldl", "-o"])
            .arg(&exe)
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", stderr(&out));
        let run = Command::new(&exe).output().unwrap();
        assert!(run.status.success(), "{run:?}");
        let got = printed(&String::from_utf8(run.stdout).unwrap());
        assert_eq!(got, expected, "exported C");
        println!("exported C: commands {reference:?} V, none clamped");
    } else {
        println!("no C compiler (cc): the exported C is not run");
    }
    // Rust, in a crate of its own over hyst-core.
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
    let mut main = String::from(
        "#![allow(clippy::all, dead_code)]\ninclude!(\"piezo_tanh_in.rs\");\n\
         include!(\"piezo_langevin_in.rs\");\n\nfn main() {\n",
    );
    main += &format!("    let desired = [{rows}];\n");
    for name in names {
        main += &format!(
            "    let mut m = {name}_inverse::<f64>().unwrap();\n    \
             for y in desired {{\n        \
             assert_eq!({name}_clamp(y), y);\n        \
             let u = hyst_core::Operator::try_step(&mut m, {name}_clamp(y)).unwrap();\n        \
             println!(\"u {{:016x}}\", u.to_bits());\n    }}\n"
        );
    }
    main += "}\n";
    std::fs::write(krate.join("src/main.rs"), main).unwrap();
    let run = cargo(&["run", "--quiet"], &krate);
    assert!(run.status.success(), "{}", stderr(&run));
    assert_eq!(
        printed(&String::from_utf8(run.stdout).unwrap()),
        expected,
        "exported Rust"
    );
    println!("exported Rust: the same commands, none clamped");
}

/// A model float cannot represent (k1 = 3.5e38: `(float)3.5e38` is undefined behaviour in C)
/// exports in double only: the C header has no `_f32` twins and compiles, the Rust refuses
/// `T = f32` naming k1, and both say why on stderr.
#[test]
fn a_model_float_cannot_represent_exports_in_double_only() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(repo().join("crates/hyst-model/testdata/static-model.toml"))
        .unwrap()
        .replacen("k1 = 0.2", "k1 = 3.5e38", 1);
    let model = dir.path().join("huge.toml");
    std::fs::write(&model, text).unwrap();
    let header = dir.path().join("huge.h");
    let reason = "smooth.k1 = 3.5e38 is beyond float's range (±3.4028235e38)";
    let o = hyst(&[
        "export",
        "c",
        model.to_str().unwrap(),
        "-o",
        header.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let note = stderr(&o);
    println!("{note}");
    assert!(
        note.contains("no _f32 twins written") && note.contains(reason),
        "{note}"
    );
    let text = std::fs::read_to_string(&header).unwrap();
    assert!(
        !text.contains("huge_init_f32") && !text.contains("(float)"),
        "{text}"
    );
    let source = "#include \"huge.h\"\nint main(void) {\n    huge_state s;\n    double y;\n    \
                  if (huge_init(&s) != HYST_OK) return 1;\n    \
                  return huge_step(&s, 0.5, &y) == HYST_OK ? 0 : 1;\n}\n";
    for (compiler, flags) in [("cc", &["-std=c99", "-pedantic"][..]), ("c++", &[][..])] {
        if let Some(out) = compiles(compiler, flags, dir.path(), source) {
            assert!(out.status.success(), "{compiler}: {}", stderr(&out));
        }
    }
    let o = hyst(&["export", "rust", model.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("T = f32 returns Err(InvalidParameter)"),
        "{}",
        stderr(&o)
    );
    let code = String::from_utf8(o.stdout).unwrap();
    assert!(code.contains("name: \"smooth.k1\""), "{code}");
    // Built and run: f64 works, f32 is refused naming k1.
    let krate = dir.path().join("check");
    std::fs::create_dir_all(krate.join("src")).unwrap();
    std::fs::write(krate.join("src/huge.rs"), code).unwrap();
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
    std::fs::write(
        krate.join("src/main.rs"),
        r#"#![allow(clippy::all, dead_code)]
include!("huge.rs");

fn main() {
    let mut m = huge::<f64>().unwrap();
    println!("f64: {}", hyst_core::Operator::try_step(&mut m, 0.5).unwrap());
    match huge::<f32>() {
        Err(e) => println!("f32: {e}"),
        Ok(_) => panic!("f32 accepted"),
    }
}
"#,
    )
    .unwrap();
    let run = cargo(&["run", "--quiet"], &krate);
    assert!(run.status.success(), "{}", stderr(&run));
    let printed = String::from_utf8(run.stdout).unwrap();
    println!("{printed}");
    assert!(
        printed.contains("f32: invalid parameter smooth.k1 = 3.5e38"),
        "{printed}"
    );
}
