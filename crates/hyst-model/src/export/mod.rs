//! A model file as firmware source: a header-only C99 file over `hyst.h` ([`c()`]), or a `no_std`
//! Rust constructor over hyst-core ([`rust()`]). Both run the model exactly as `hyst run --model`
//! does, from the first sample: the start rule is applied at the first sample, the parameters
//! are the file's, bit for bit, and an inverse clamps desired outputs into the limits of a
//! saturating output shaping as `hyst run --inverse --saturate` does.
//!
//! A model with dynamics (Lemma 5.1's plant before the hysteresis) exports, besides its
//! hysteresis, its compensator (operator form): the desired output and its first n time
//! derivatives in, the command out, as `hyst run --model M --inverse` computes it from the
//! derivative columns; and, for a sample period given in [`Options`] ([`c_with`],
//! [`rust_with`]), its forward model with the plant discretised for that period, as `hyst run
//! --model M` runs a record of that period. A rate term is refused with the reason.
//!
//! `hyst export c|rust` and Python's `Model.export_c`/`export_rust` call these functions, so
//! every surface writes the same text.

pub mod c;
pub mod rust;
mod shared;

pub use c::{c, c_with};
pub use rust::{rust, rust_with};
pub use shared::{check_name, Options, Source};

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use std::path::Path;

    use super::*;
    use crate::file::ModelFile;

    /// A static smooth model file as `hyst fit` writes it (format version 1): y = 3 H(0.2,
    /// 6)[v] + 1, v = x / 2 − 1 (shared with hyst-capi's tests of timed models).
    const STATIC: &str = include_str!("../../testdata/static-model.toml");

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
}
