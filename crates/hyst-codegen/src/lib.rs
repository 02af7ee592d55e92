//! A model file as firmware source: a header-only C99 file over `hyst.h` ([`c()`]), or a `no_std`
//! Rust constructor over hyst-core ([`rust()`]). Both run the model exactly as `hyst run --model`
//! does, from the first sample: the start rule is applied at the first sample, the parameters
//! are the file's, bit for bit, and an inverse clamps desired outputs into the saturation limits
//! of a bounded output as `hyst run --inverse --saturate` does.
//!
//! A model with dynamics (Lemma 5.1's plant before the hysteresis) exports, besides its
//! hysteresis, its compensator (operator form): the desired output and its first n time
//! derivatives in, the command out, as `hyst run --model M --inverse` computes it from the
//! derivative columns; and, for a sample period given in [`Options`] ([`c_with`],
//! [`rust_with`]), its forward model with the plant discretised for that period, as `hyst run
//! --model M` runs a record of that period. A rate term is refused with the reason.
//!
//! `hyst export c|rust` and Python's `Model.export_c`/`export_rust` call these functions, so
//! every surface writes the same text. The generators are a crate of their own, over the model
//! runtime (hyst-model): the C library and the FMU run models through the runtime and do not
//! compile them.

pub mod c;
pub mod rust;
mod shared;

pub use c::{c, c_with};
pub use rust::{rust, rust_with};
pub use shared::{check_name, Options, Source};

use hyst_model::file::ModelFile;

/// Why the export of `file` has no float form, when it has none: the first number float cannot
/// represent, in words ("smooth.k1 = 3.5e38 is beyond float's range (±3.4028235e38)"). The
/// exported C then has no `_f32` twins and the exported Rust refuses `T = f32`, naming it;
/// `hyst export` prints it as a note. `None` for a model float represents, and for one that
/// does not export (the export's own error says why).
#[must_use]
pub fn no_float_reason(file: &ModelFile, options: &Options) -> Option<String> {
    let m = shared::smooth(file, "").ok()?;
    let timed = shared::timing(m, options, "").ok()?;
    shared::no_float(file, m, timed.as_ref()).map(|n| n.reason())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::panic)]
    use std::path::Path;

    use super::*;
    use hyst_model::file::ModelFile;

    /// A static smooth model file as `hyst fit` writes it (format version 1): y = 3 H(0.2,
    /// 6)[v] + 1, v = x / 2 − 1 (shared with hyst-capi's tests of timed models).
    const STATIC: &str = include_str!("../../hyst-model/testdata/static-model.toml");

    /// The static model with `sections` appended, as format version 4.
    fn timed(sections: &str) -> ModelFile {
        let text = STATIC.replace("version = 1", "version = 4") + sections;
        ModelFile::from_toml(&text, Path::new("timed.toml")).unwrap()
    }

    /// A rate term is refused by both exports with the reason, and so is a stop-form model with
    /// dynamics without a sample period; a model with dynamics exports its compensator (operator
    /// form) and, with a period, its forward model with the plant.
    #[test]
    fn timed_models_export_their_dynamics_or_say_why_not() {
        let source = Source::of_file("m.toml", b"");
        let plain = ModelFile::from_toml(STATIC, Path::new("static.toml")).unwrap();
        assert!(c(&plain, "piezo", &source).is_ok());
        assert!(rust(&plain, "piezo", &source).is_ok());
        let period = Options { period: Some(1e-3) };
        // A period is unused without dynamics.
        assert_eq!(
            c_with(&plain, "piezo", &source, &period).unwrap(),
            c(&plain, "piezo", &source).unwrap()
        );
        for (sections, what) in [
            ("[rate]\nc = 0.3\n", "a rate term"),
            (
                "[dynamics]\nb = 1.0\na = [0.05]\n[rate]\nc = 0.3\n",
                "dynamics of order 1 and a rate term",
            ),
        ] {
            let file = timed(sections);
            assert!(file.smooth.as_ref().unwrap().is_timed());
            for options in [Options::default(), period] {
                for (target, result) in [
                    ("hyst export c", c_with(&file, "piezo", &source, &options)),
                    (
                        "hyst export rust",
                        rust_with(&file, "piezo", &source, &options),
                    ),
                ] {
                    let message = result.unwrap_err().to_string();
                    assert!(message.contains(what), "{message}");
                    assert!(message.contains(target), "{message}");
                    assert!(message.contains("no compensator"), "{message}");
                }
            }
        }
        let dynamic = timed("[dynamics]\nb = 1.0\na = [0.05, 0.001]\n");
        let header = c(&dynamic, "piezo", &source).unwrap();
        for name in [
            "#define PIEZO_ORDER 2",
            "piezo_timed_compensator_init(",
            "piezo_timed_compensator_step_f32(",
            "(double)0.05 * x[1]",
            "(float)0.001 * x[2]",
        ] {
            assert!(header.contains(name), "{name}");
        }
        assert!(!header.contains("piezo_timed_step("));
        let header = c_with(&dynamic, "piezo", &source, &period).unwrap();
        assert!(
            header.contains("piezo_timed_step(") && header.contains("#define PIEZO_PERIOD 0.001")
        );
        let code = rust_with(&dynamic, "piezo", &source, &period).unwrap();
        for name in [
            "pub const PIEZO_ORDER: usize = 2;",
            "pub fn piezo_timed_compensator<T: hyst_core::Real>(",
            "pub fn piezo_timed<T: hyst_core::Real>()",
            "pub const PIEZO_PERIOD: f64 = 0.001;",
        ] {
            assert!(code.contains(name), "{name}");
        }
        // The stop form with dynamics: its forward model with a period, nothing without.
        let stop = STATIC
            .replace("version = 1", "version = 4")
            .replace("[smooth]\n", "[smooth]\nform = \"stop\"\nlinear = 0.5\n")
            + "[dynamics]\nb = 1.0\na = [0.05]\n";
        let stop = ModelFile::from_toml(&stop, Path::new("stop.toml")).unwrap();
        for (target, result) in [
            ("hyst export c", c(&stop, "piezo", &source)),
            ("hyst export rust", rust(&stop, "piezo", &source)),
        ] {
            let message = result.unwrap_err().to_string();
            assert!(message.contains("stop form"), "{message}");
            assert!(message.contains(&format!("{target} --period")), "{message}");
        }
        let header = c_with(&stop, "piezo", &source, &period).unwrap();
        assert!(header.contains("piezo_timed_step(") && !header.contains("timed_compensator"));
        let code = rust_with(&stop, "piezo", &source, &period).unwrap();
        assert!(code.contains("pub fn piezo_timed<") && !code.contains("timed_compensator"));
        // A period the plant cannot be discretised at.
        for bad in [0.0, -1e-3, f64::NAN, f64::INFINITY] {
            let options = Options { period: Some(bad) };
            let message = c_with(&dynamic, "piezo", &source, &options)
                .unwrap_err()
                .to_string();
            assert!(message.contains("--period"), "{message}");
        }
    }

    /// Text a user controls that tries to end a comment, nest one, break a line, splice lines
    /// (a trigraph) or reorder what a comment shows, each with an item it would define.
    const HOSTILE: [&str; 4] = [
        "a*/ int injected_c; /*b",
        "a\npub const INJECTED_RUST: i32 = 42;\n#define injected_macro 1\n",
        "a\r\0\t\u{7f}\u{85}\u{2028}\u{2029}\u{202e}\u{2066}\u{feff}??/",
        "*/ /* /*/ */ \\",
    ];

    /// `file` with every column name and unit replaced by hostile text.
    fn hostile_columns(text: &str) -> ModelFile {
        // A TOML basic string.
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
        let mut text = text.to_string();
        for (from, to) in [
            ("input = \"x\"", HOSTILE[0]),
            ("output = \"y\"", HOSTILE[1]),
            ("input = \"\"", HOSTILE[2]),
            ("output = \"\"", HOSTILE[3]),
            ("input = \"u_actuator_V\"", HOSTILE[0]),
            ("output = \"y_capsensor_um\"", HOSTILE[1]),
        ] {
            let key = from.split(' ').next().unwrap_or_default();
            text = text.replacen(from, &format!("{key} = {}", quote(to)), 1);
        }
        let file = ModelFile::from_toml(&text, Path::new("hostile.toml")).unwrap();
        assert_eq!(file.columns.output, HOSTILE[1]);
        file
    }

    /// C `text` without its comments, or what is wrong with them: a `/*` inside a comment
    /// (GCC's -Wcomment), a comment that never ends.
    fn c_outside_comments(text: &str) -> Result<String, String> {
        let mut code = String::new();
        let mut rest = text;
        while let Some(start) = rest.find("/*") {
            code.push_str(&rest[..start]);
            let inside = &rest[start + 2..];
            let end = inside.find("*/").ok_or("a comment that never ends")?;
            if inside[..end].contains("/*") {
                return Err(format!("/* inside a comment: {}", &inside[..end]));
            }
            rest = &inside[end + 2..];
        }
        code.push_str(rest);
        Ok(code)
    }

    /// Rust `text` without its line comments.
    fn rust_outside_comments(text: &str) -> String {
        text.lines()
            .map(|l| l.find("//").map_or(l, |i| &l[..i]))
            .collect::<Vec<_>>()
            .join("\n")
    }

    /// A model path, column names and units that try to end the comment they are written in,
    /// break its line or reorder its text stay inside it: the C and the Rust outside their
    /// comments hold none of it, no line breaks but at a line feed of the generator, and no
    /// character that a compiler refuses or warns about in a comment is written.
    #[test]
    fn user_text_stays_inside_the_comments() {
        let source = Source::of_file(&HOSTILE.concat(), b"");
        let pi = include_str!("../../../examples/firmware/models/piezo_pi.toml");
        let dynamics = STATIC.replace("version = 1", "version = 4")
            + "[dynamics]\nb = 1.0\na = [0.05, 0.001]\n";
        let period = Options { period: Some(1e-3) };
        let mut outputs = Vec::new();
        for text in [STATIC, &dynamics] {
            let file = hostile_columns(text);
            outputs.push(("c", c_with(&file, "m", &source, &period).unwrap()));
            outputs.push(("rust", rust_with(&file, "m", &source, &period).unwrap()));
        }
        outputs.push(("rust", rust(&hostile_columns(pi), "m", &source).unwrap()));
        for (language, text) in outputs {
            let code = if language == "c" {
                c_outside_comments(&text).unwrap_or_else(|e| panic!("{e}\n{text}"))
            } else {
                rust_outside_comments(&text)
            };
            for injected in ["injected", "INJECTED"] {
                assert!(!code.contains(injected), "{language}: {injected}\n{text}");
            }
            assert!(text.contains("a*\\/ int injected_c; /\\*b"), "{text}");
            // No trigraph (`??/` at the end of a line joins the next), no control character but
            // the generator's line feeds, no line separator, byte-order mark or bidirectional
            // control (rustc refuses those in comments, GCC warns).
            assert!(!text.contains("??"), "{language}: {text}");
            let bad = text.chars().find(|c| {
                *c != '\n'
                    && (c.is_control()
                        || matches!(c, '\u{2028}' | '\u{2029}' | '\u{feff}')
                        || ('\u{202a}'..='\u{202e}').contains(c)
                        || ('\u{2066}'..='\u{2069}').contains(c))
            });
            assert_eq!(bad, None, "{language}: {text}");
        }
    }

    /// A model float cannot represent gets no `_f32` twins in C and a refusal of `T = f32` in
    /// Rust, each naming the number; a model float represents gets both as before.
    #[test]
    fn a_model_float_cannot_represent_has_no_float_twins_and_says_why() {
        let source = Source::of_file("m.toml", b"");
        let options = Options::default();
        let plain = ModelFile::from_toml(STATIC, Path::new("static.toml")).unwrap();
        assert_eq!(no_float_reason(&plain, &options), None);
        let header = c(&plain, "m", &source).unwrap();
        assert!(header.contains("m_init_f32(") && !header.contains("No float form"));
        assert!(!rust(&plain, "m", &source)
            .unwrap()
            .contains("InvalidParameter"));
        for (from, to, reason) in [
            (
                "k1 = 0.2",
                "k1 = 3.5e38",
                "smooth.k1 = 3.5e38 is beyond float's range (±3.4028235e38)",
            ),
            (
                "post_gain = 3.0",
                "post_gain = 1e-40",
                "smooth.output_shaping.post_gain = 1e-40 is below float's smallest normal number \
                 (1.1754944e-38)",
            ),
        ] {
            assert!(STATIC.contains(from), "{from}");
            let text = STATIC.replacen(from, to, 1);
            let file = ModelFile::from_toml(&text, Path::new("big.toml")).unwrap();
            let why = no_float_reason(&file, &options).unwrap();
            println!("{to}: {why}");
            assert!(why.starts_with(reason), "{why}");
            let header = c(&file, "m", &source).unwrap();
            for f32_code in [
                "_state_f32",
                "_init_f32(",
                "_step_f32(",
                "(float)",
                "float *",
            ] {
                assert!(!header.contains(f32_code), "{f32_code} in {header}");
            }
            assert!(
                // The comment's lines joined.
                header
                    .replace("\n * ", " ")
                    .contains(&format!("No float form: {reason}")),
                "{header}"
            );
            assert!(header.contains("m_init_inverse(") && header.contains("(double)"));
            let code = rust(&file, "m", &source).unwrap();
            assert!(
                code.contains("return Err(hyst_core::Error::InvalidParameter"),
                "{code}"
            );
            assert!(code.contains(reason), "{code}");
        }
    }
}
