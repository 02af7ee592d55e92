//! Exported inverses of saturating input shapings keep the training range; a model float
//! cannot represent exports in double only.

use super::*;
use crate::headers::*;
use crate::timed::*;

/// A C program that runs the exported inverses `names` (from their initial state) over the
/// desired outputs `rows` (a C initialiser list), printing each command's bits as "u HEX", and
/// fails if one clamps.
fn c_harness(names: &[&str], rows: &str) -> String {
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
    harness
}

/// The main.rs of a crate that runs the exported Rust inverses `names` over the desired outputs
/// `rows`, none of them clamped, printing each command's bits as "u HEX".
fn rust_main(names: &[&str], rows: &str) -> String {
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
    main
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
    let krate = rust_check_crate(dir.path());
    let mut reference = Vec::new();
    for name in names {
        let file = repo()
            .join("crates/hyst-model/testdata")
            .join(format!("{}.toml", name.replace('_', "-")));
        let out = dir.path().join(format!("{name}.csv"));
        let run = HYST.output(&[
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
            let o = HYST.output(&[
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
        let harness = c_harness(&names, &rows);
        let source = dir.path().join("harness.c");
        std::fs::write(&source, harness).unwrap();
        let stdout = run_c_against_the_library(dir.path(), &source).unwrap();
        let got = printed(&stdout);
        assert_eq!(got, expected, "exported C");
        println!("exported C: commands {reference:?} V, none clamped");
    } else {
        println!("no C compiler (cc): the exported C is not run");
    }
    // Rust, in a crate of its own over hyst-core.
    let main = rust_main(&names, &rows);
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
    let o = HYST.output(&[
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
    let o = HYST.output(&["export", "rust", model.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("T = f32 returns Err(InvalidParameter)"),
        "{}",
        stderr(&o)
    );
    let code = String::from_utf8(o.stdout).unwrap();
    assert!(code.contains("name: \"smooth.k1\""), "{code}");
    // Built and run: f64 works, f32 is refused naming k1.
    let krate = rust_check_crate(dir.path());
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
