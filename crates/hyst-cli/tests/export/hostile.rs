//! Hostile paths, column names and units: nothing they hold escapes the comment or string it is
//! written in.

use super::*;
use crate::headers::*;
use crate::timed::*;

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
        let out = HYST.output(&[
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
