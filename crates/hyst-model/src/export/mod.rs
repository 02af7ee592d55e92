//! A model file as firmware source: a header-only C99 file over `hyst.h` ([`c()`]), or a `no_std`
//! Rust constructor over hyst-core ([`rust()`]). Both run the model exactly as `hyst run --model`
//! does, from the first sample: the start rule is applied at the first sample, the parameters
//! are the file's, bit for bit, and an inverse clamps desired outputs into the limits of a
//! saturating output shaping as `hyst run --inverse --saturate` does.
//!
//! `hyst export c|rust` and Python's `Model.export_c`/`export_rust` call these functions, so
//! every surface writes the same text.

pub mod c;
pub mod rust;
mod shared;

pub use c::c;
pub use rust::rust;
pub use shared::{check_name, Source};

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use std::path::Path;

    use super::*;
    use crate::file::ModelFile;

    /// A static smooth model file as `hyst fit` writes it (format version 1).
    const STATIC: &str = r#"
format = "hyst-model"
version = 1
kind = "smooth"
parameters = []
[columns]
input = "x"
output = "y"
[units]
input = ""
output = ""
[metrics]
parameters = 0
fit_seconds = 0.0
ns_per_sample = 0.0
[metrics.training]
samples = 0
rms = 0.0
max_abs = 0.0
rms_pct_span = 0.0
max_pct_span = 0.0
[smooth]
k1 = 0.2
initial_state = "rising"
[smooth.k2]
law = "constant"
value = 6.0
[smooth.input_shaping]
pre_gain = 0.5
pre_offset = -1.0
shape = "identity"
post_gain = 1.0
post_offset = 0.0
[smooth.output_shaping]
pre_gain = 1.0
pre_offset = 0.0
shape = "identity"
post_gain = 3.0
post_offset = 1.0
[provenance]
file = "none"
bytes = 0
fnv1a64 = "0"
rows = 0
records = 0
command = "hand-written"
hyst_version = "0.1.0"
created_unix = 0
"#;

    /// The static model with `sections` appended, as format version 4.
    fn timed(sections: &str) -> ModelFile {
        let text = STATIC.replace("version = 1", "version = 4") + sections;
        ModelFile::from_toml(&text, Path::new("timed.toml")).unwrap()
    }

    /// A model with dynamics or a rate term is refused by both exports, with the reason (its
    /// plant or rate term needs a sample period), never exported without them.
    #[test]
    fn timed_models_are_refused() {
        let source = Source::of_file("m.toml", b"");
        let plain = ModelFile::from_toml(STATIC, Path::new("static.toml")).unwrap();
        assert!(c(&plain, "piezo", &source).is_ok());
        assert!(rust(&plain, "piezo", &source).is_ok());
        for (sections, what) in [
            ("[dynamics]\nb = 1.0\na = [0.05]\n", "dynamics of order 1"),
            ("[rate]\nc = 0.3\n", "a rate term"),
            (
                "[dynamics]\nb = 1.0\na = [0.05]\n[rate]\nc = 0.3\n",
                "dynamics of order 1 and a rate term",
            ),
        ] {
            let file = timed(sections);
            assert!(file.smooth.as_ref().unwrap().is_timed());
            for (target, result) in [
                ("hyst export c", c(&file, "piezo", &source)),
                ("hyst export rust", rust(&file, "piezo", &source)),
            ] {
                let message = result.unwrap_err().to_string();
                assert!(message.contains(what), "{message}");
                assert!(message.contains(target), "{message}");
                assert!(message.contains("sample period"), "{message}");
            }
        }
    }
}
