//! The FMU's configuration: `resources/fmu.toml` (and `resources/model.toml` for a model), found
//! through fmi2Instantiate's `fmuResourceLocation` URI.
//!
//! ```toml
//! format = "hyst-fmu"
//! version = 1
//! guid = "{...}"      # the same string as modelDescription.xml's guid
//! kind = "operator"   # or "model" (then resources/model.toml is the model file)
//! inverse = false     # true: H^-1 (operator) or the model's exact inverse (model)
//! saturate = false    # kind = "model", inverse = true, a bounded output only:
//!                     # clamp desired outputs into the model's saturation limits
//! k1 = 0.2            # kind = "operator" only: the start values of the parameters
//! k2 = 8.0
//! ```
//!
//! A model with dynamics or a rate term is checked by [`Timing::of`] (which `hyst fmu` calls
//! too): the inverse of one without a compensator, or `saturate` with one, is refused.

use std::path::{Path, PathBuf};

use hyst_core::{Hysteresis, InverseHysteresis};
use hyst_model::ModelFile;
use hyst_model::Saturation;
use serde::Deserialize;

use crate::layout::{CONFIG_FILE, FORMAT, MODEL_FILE, VERSION};
use crate::timed::Timing;

/// What the FMU runs.
#[derive(Clone, Debug)]
pub enum Kind {
    /// The parametric operator H(k1, k2) (or H⁻¹) with these start values of k1, k2.
    Operator {
        /// The start value of k1.
        k1: f64,
        /// The start value of k2.
        k2: f64,
    },
    /// A fitted model file, run as `hyst run --model` runs it.
    Model(Box<ModelFile>),
}

/// The checked contents of the resources folder.
#[derive(Clone, Debug)]
pub struct Config {
    /// The GUID fmi2Instantiate must be given.
    pub guid: String,
    /// H⁻¹ / the model's exact inverse instead of the direct operator or model.
    pub inverse: bool,
    /// The operator or the model.
    pub kind: Kind,
    /// `saturate = true`: the output range of a model bounded by a saturating output or input
    /// shaping and the limits (`ModelFile::saturation`) that desired outputs are clamped into
    /// before the inverse sees them, as `hyst run --saturate` clamps them.
    /// `None`: a desired output beyond the range is refused.
    pub saturation: Option<Saturation>,
    /// A model with dynamics or a rate term ([`Timing`]); `None` for a static model or the
    /// operator.
    pub timing: Option<Timing>,
}

/// fmu.toml as written, after its `format` and `version` (checked first, so that a file of
/// another version is named as such whatever its other keys), checked further by
/// [`Config::read`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawConfig {
    guid: String,
    kind: String,
    #[serde(default)]
    inverse: bool,
    #[serde(default)]
    saturate: bool,
    k1: Option<f64>,
    k2: Option<f64>,
}

impl Config {
    /// Reads `fmu.toml` (and `model.toml` for kind = "model") from the resources folder `dir`.
    ///
    /// # Errors
    /// A message naming the file, and the key and value where the file is wrong.
    pub fn read(dir: &Path) -> Result<Self, String> {
        let path = dir.join(CONFIG_FILE);
        let name = path.display();
        let text =
            std::fs::read_to_string(&path).map_err(|e| format!("{name}: cannot read: {e}"))?;
        let mut table: toml::Table = text.parse().map_err(|e: toml::de::Error| {
            format!(
                "{name}: not valid TOML: {}",
                hyst_model::file::toml_message(&text, &e)
            )
        })?;
        match table.remove("format") {
            Some(toml::Value::String(f)) if f == FORMAT => {}
            Some(v) => return Err(format!("{name}: format = {v}: must be \"{FORMAT}\"")),
            None => return Err(format!("{name}: no `format = \"{FORMAT}\"`")),
        }
        match table.remove("version") {
            Some(toml::Value::Integer(VERSION)) => {}
            Some(v) => {
                return Err(format!(
                    "{name}: version = {v}: this FMU binary reads version {VERSION}"
                ))
            }
            None => return Err(format!("{name}: no `version`")),
        }
        let raw: RawConfig =
            toml::Value::Table(table)
                .try_into()
                .map_err(|e: toml::de::Error| {
                    format!(
                        "{name}: invalid configuration: {}",
                        e.message().trim().replace('\n', "; ")
                    )
                })?;
        if raw.guid.is_empty() {
            return Err(format!("{name}: guid = \"\": must not be empty"));
        }
        let kind = match raw.kind.as_str() {
            "operator" => {
                let k1 = raw
                    .k1
                    .ok_or_else(|| format!("{name}: kind = \"operator\" needs k1"))?;
                let k2 = raw
                    .k2
                    .ok_or_else(|| format!("{name}: kind = \"operator\" needs k2"))?;
                // The core's constructor checks the values (its error names the parameter).
                let check = if raw.inverse {
                    InverseHysteresis::new(k1, k2).map(|_| ())
                } else {
                    Hysteresis::new(k1, k2).map(|_| ())
                };
                check.map_err(|e| format!("{name}: k1 = {k1}, k2 = {k2}: {e}"))?;
                Kind::Operator { k1, k2 }
            }
            "model" => model_kind(dir, &name.to_string(), &raw)?,
            other => {
                return Err(format!(
                    "{name}: kind = \"{other}\": must be \"operator\" or \"model\""
                ))
            }
        };
        // A model with dynamics or a rate term: what the FMU needs, or why it cannot run it.
        let timing = match &kind {
            Kind::Model(model) => Timing::of(model, raw.inverse, raw.saturate)
                .map_err(|e| format!("{}: {e}", dir.join(MODEL_FILE).display()))?,
            Kind::Operator { .. } => None,
        };
        let saturation = match (&kind, raw.saturate) {
            (_, false) => None,
            (Kind::Model(model), true) if raw.inverse => {
                Some(model.saturation().ok_or_else(|| {
                    format!(
                        "{name}: saturate = true: the model's output is unbounded (neither its \
                         input nor its output shaping saturates), so no desired output needs \
                         clamping"
                    )
                })?)
            }
            (_, true) => {
                return Err(format!(
                    "{name}: saturate = true: applies to kind = \"model\" with inverse = true \
                     (the inverse of a model whose output is bounded)"
                ))
            }
        };
        Ok(Self {
            guid: raw.guid,
            inverse: raw.inverse,
            kind,
            saturation,
            timing,
        })
    }
}

/// The model of kind = "model": `model.toml` in `dir`, read and checked (`name`: fmu.toml's
/// path, for messages).
fn model_kind(dir: &Path, name: &str, raw: &RawConfig) -> Result<Kind, String> {
    for (key, value) in [("k1", raw.k1), ("k2", raw.k2)] {
        if let Some(v) = value {
            return Err(format!(
                "{name}: {key} = {v}: only kind = \"operator\" has parameters \
                 (a model's are in {MODEL_FILE})"
            ));
        }
    }
    let path = dir.join(MODEL_FILE);
    let model = ModelFile::read(&path).map_err(|e| format!("{name}: kind = \"model\": {e}"))?;
    Ok(Kind::Model(Box::new(model)))
}

/// The folder named by fmi2Instantiate's `fmuResourceLocation`: a `file` URI (`file:///abs/path`,
/// `file://localhost/abs/path` or `file:/abs/path`, percent-encoded, with or without a trailing
/// slash). A plain absolute path (no scheme) is taken as it is, as some masters pass one.
///
/// # Errors
/// A message saying what is wrong with the URI.
pub fn resource_dir(uri: &str) -> Result<PathBuf, String> {
    let bad = |why: &str| format!("fmuResourceLocation \"{uri}\": {why}");
    if uri.starts_with('/') {
        return Ok(PathBuf::from(uri));
    }
    let scheme_end = uri
        .find(':')
        .ok_or_else(|| bad("not a file URI (file:///path) nor an absolute path"))?;
    let (scheme, rest) = uri.split_at(scheme_end);
    if !scheme.eq_ignore_ascii_case("file") {
        return Err(bad("only file URIs are supported"));
    }
    let rest = rest.strip_prefix(':').unwrap_or(rest);
    let path = match rest.strip_prefix("//") {
        Some(authority_and_path) => {
            let slash = authority_and_path
                .find('/')
                .unwrap_or(authority_and_path.len());
            let (authority, path) = authority_and_path.split_at(slash);
            if !(authority.is_empty() || authority.eq_ignore_ascii_case("localhost")) {
                return Err(bad(&format!(
                    "host \"{authority}\": only local files (no host, or localhost) are supported"
                )));
            }
            path
        }
        None => rest,
    };
    if !path.starts_with('/') {
        return Err(bad("the path is not absolute"));
    }
    let bytes = percent_decode(path).map_err(|e| bad(&e))?;
    path_from_bytes(bytes).map_err(|e| bad(&e))
}

/// Decodes `%XX` escapes.
fn percent_decode(text: &str) -> Result<Vec<u8>, String> {
    let mut out = Vec::with_capacity(text.len());
    let mut bytes = text.bytes();
    while let Some(b) = bytes.next() {
        if b != b'%' {
            out.push(b);
            continue;
        }
        let hex = |d: Option<u8>| d.and_then(|d| char::from(d).to_digit(16));
        match (hex(bytes.next()), hex(bytes.next())) {
            // Two hex digits make one byte (< 256).
            (Some(hi), Some(lo)) => out.push(u8::try_from(hi * 16 + lo).unwrap_or(0)),
            _ => return Err("a '%' is not followed by two hexadecimal digits".into()),
        }
    }
    Ok(out)
}

#[cfg(unix)]
fn path_from_bytes(bytes: Vec<u8>) -> Result<PathBuf, String> {
    use std::os::unix::ffi::OsStringExt;
    Ok(PathBuf::from(std::ffi::OsString::from_vec(bytes)))
}

#[cfg(not(unix))]
fn path_from_bytes(bytes: Vec<u8>) -> Result<PathBuf, String> {
    String::from_utf8(bytes)
        .map(PathBuf::from)
        .map_err(|_| "the decoded path is not UTF-8".into())
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    /// A corrupt fmu.toml is named in one line, as model files are.
    #[test]
    fn a_corrupt_configuration_is_one_line() {
        let dir = std::env::temp_dir().join(format!("hyst-fmu-config-{}", std::process::id()));
        std::fs::create_dir_all(&dir).ok();
        for text in [
            "format = \"hyst-fmu\"\nversion = [1,\n\nkind = 3\n",
            "format = \"hyst-fmu\"\nversion = 1\nkind = [\"operator\"]\nguid = 1\n",
        ] {
            std::fs::write(dir.join(CONFIG_FILE), text).ok();
            let message = Config::read(&dir).err().unwrap_or_default();
            assert!(!message.is_empty(), "accepted {text:?}");
            assert!(!message.contains('\n'), "{message}");
            assert!(message.contains("fmu.toml"), "{message}");
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn file_uris_in_every_form() {
        for uri in [
            "file:///tmp/a b/resources",
            "file:///tmp/a%20b/resources/",
            "file:/tmp/a%20b/resources",
            "file://localhost/tmp/a%20b/resources/",
            "FILE:///tmp/a%20b/resources",
            "/tmp/a b/resources/",
        ] {
            let dir = resource_dir(uri).unwrap();
            assert_eq!(
                dir.join("fmu.toml"),
                Path::new("/tmp/a b/resources/fmu.toml"),
                "{uri}"
            );
        }
        assert_eq!(
            resource_dir("file:///x/%C3%A9t%c3%a9").unwrap(),
            Path::new("/x/été")
        );
        for uri in [
            "http://host/x",
            "file://server/share/x",
            "file:relative/x",
            "relative/x",
            "file:///x/%2",
            "file:///x/%zz",
            "",
        ] {
            assert!(resource_dir(uri).is_err(), "{uri}");
        }
    }
}
