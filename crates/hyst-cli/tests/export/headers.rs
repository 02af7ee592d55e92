//! Headers and sources of every kind of model: they compile (C99 with -Wall -Wextra -Werror,
//! C++), say where they came from, and bad input gets a clear error and writes nothing.

use super::*;

pub(crate) fn model(name: &str) -> PathBuf {
    repo()
        .join("examples/firmware/models")
        .join(format!("{name}.toml"))
}

/// Compiles `source` (which includes the generated header) with `compiler` and `flags`, syntax
/// only; `None` when the compiler is not installed.
pub(crate) fn compiles(compiler: &str, flags: &[&str], dir: &Path, source: &str) -> Option<Output> {
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
pub(crate) fn every_smooth_model_exports_a_header_that_compiles() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["piezo", "steel", "friction"] {
        let header = dir.path().join(format!("{name}.h"));
        let out = HYST.output(&[
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
pub(crate) fn python_and_cli_share_one_generator_and_rust_exports_every_kind() {
    for name in ["piezo", "steel", "friction", "piezo_pi"] {
        let out = HYST.output(&["export", "rust", model(name).to_str().unwrap()]);
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
pub(crate) fn a_prandtl_ishlinskii_model_is_refused_by_c_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let header = dir.path().join("pi.h");
    let out = HYST.output(&[
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
pub(crate) fn bad_input_names_the_problem_and_writes_nothing() {
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
            let out = HYST.output(&[
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
    let out = HYST.output(&[
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
pub(crate) fn without_a_name_the_file_name_is_used_when_it_can_be() {
    let out = HYST.output(&["export", "c", model("piezo").to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(String::from_utf8(out.stdout)
        .unwrap()
        .contains("piezo_init_inverse("));
    let dir = tempfile::tempdir().unwrap();
    let odd = dir.path().join("my model.toml");
    std::fs::copy(model("piezo"), &odd).unwrap();
    let out = HYST.output(&["export", "c", odd.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("give --name NAME"),
        "{}",
        stderr(&out)
    );
}
