//! The model file: versioned TOML holding a fitted model (smooth or Prandtl–Ishlinskii), its
//! structure, parameters with standard errors, family widths, units and column names, fit
//! metrics and the data's provenance. The format is documented in `docs/formats.md`.
//!
//! Numbers are written in the shortest form that parses back to the same `f64`, so a model
//! read back evaluates bit for bit like the one that was fitted.

use std::path::Path;

use hyst_core::{Hysteresis, K2Law, Operator, Shaping};
use serde::{Deserialize, Serialize};

use crate::choice::Choice;
use crate::dynamics::{DynamicsSection, Rate, RateSection};
use crate::error::ModelError;
use crate::evaluator::Evaluator;
use crate::family::FamilyWidths;
use crate::pi::PiModel;
use crate::provenance::{Columns, Estimate, Metrics, Provenance, Units};
use crate::saturation::Saturation;
use crate::smooth::{Form, SmoothModel};
use crate::structure::Structure;

/// The value of the `format` key.
pub const FORMAT: &str = "hyst-model";
/// The newest format version this crate reads and writes. Version 2 adds the optional
/// `[prandtl-ishlinskii.output]` polynomial, version 3 the stop form of the smooth model
/// (`form = "stop"` and `linear` in `[smooth]`), version 4 the optional `[dynamics]` and `[rate]`
/// (and `dynamics`, `rate` in `[structure]`), version 5 `hold` in `[dynamics]` (the
/// zero-order hold; a file without it has the first-order hold); a file is written with the lowest version that
/// holds its content ([`ModelFile::required_version`]), so files without it stay readable by
/// version-1 readers, and version-1 readers refuse the files they would misread.
pub const VERSION: u32 = 5;
/// The oldest format version this crate reads.
pub const MIN_VERSION: u32 = 1;

/// Which model the file holds: `smooth` (section `[smooth]`) or `prandtl-ishlinskii` (section
/// `[prandtl-ishlinskii]`; the command line also takes `pi` for it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ModelKind {
    /// The smooth parametric operator with shaping functions.
    Smooth,
    /// The Prandtl–Ishlinskii baseline (also read as `pi`).
    #[serde(alias = "pi")]
    PrandtlIshlinskii,
}

impl Choice for ModelKind {
    const WHAT: &'static str = "model kind";
    const CHOICES: &'static [(Self, &'static str, &'static str)] = &[
        (
            ModelKind::Smooth,
            "smooth",
            "The smooth parametric operator with shaping functions",
        ),
        (
            ModelKind::PrandtlIshlinskii,
            "prandtl-ishlinskii",
            "The Prandtl–Ishlinskii baseline",
        ),
    ];
    const ALIASES: &'static [(&'static str, Self)] = &[("pi", ModelKind::PrandtlIshlinskii)];
}

/// A model file (see `docs/formats.md`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModelFile {
    /// Always "hyst-model".
    pub format: String,
    /// Format version ([`VERSION`]).
    pub version: u32,
    /// Which model.
    pub kind: ModelKind,
    /// Column names of the data.
    pub columns: Columns,
    /// Units of input and output.
    pub units: Units,
    /// The fitted parameters with standard errors.
    pub parameters: Vec<Estimate>,
    /// Fit metrics.
    pub metrics: Metrics,
    /// The chosen structure (smooth models).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub structure: Option<Structure>,
    /// The smooth model (kind = "smooth").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub smooth: Option<SmoothModel>,
    /// The Prandtl–Ishlinskii model (kind = "prandtl-ishlinskii").
    #[serde(
        default,
        rename = "prandtl-ishlinskii",
        skip_serializing_if = "Option::is_none"
    )]
    pub prandtl_ishlinskii: Option<PiModel>,
    /// Lemma 5.1's plant before the hysteresis of a smooth model with dynamics, with standard
    /// errors (format version 4; installed into [`SmoothModel::dynamics`] on reading).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dynamics: Option<DynamicsSection>,
    /// The rate term of a smooth model, with its standard error (format version 4; installed
    /// into [`SmoothModel::rate`] on reading).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rate: Option<RateSection>,
    /// Family widths and the bound (smooth models).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub family: Option<FamilyWidths>,
    /// Provenance of the data.
    pub provenance: Provenance,
}

impl ModelFile {
    /// Serialises to TOML.
    ///
    /// # Errors
    /// [`ModelError::Invalid`] if a value cannot be written (never for fitted models).
    pub fn to_toml(&self) -> Result<String, ModelError> {
        let body = toml::to_string(self)
            .map_err(|e| ModelError::Invalid(format!("cannot write the model file: {e}")))?;
        // The version this file says it is (`hyst fit` writes the lowest that holds it), not
        // the newest this crate knows.
        Ok(format!(
            "# hyst model file, format version {} (see docs/formats.md)\n{body}",
            self.version
        ))
    }

    /// Parses and checks a model file's text (`path` names it in errors).
    ///
    /// # Errors
    /// [`ModelError::File`] for TOML errors, a wrong format or version, a missing model
    /// section, or parameters the core refuses.
    pub fn from_toml(text: &str, path: &Path) -> Result<Self, ModelError> {
        let bad = |message: String| ModelError::File {
            path: path.to_path_buf(),
            message,
        };
        let value: toml::Table = text.parse().map_err(|e: toml::de::Error| {
            bad(format!("not valid TOML: {}", toml_message(text, &e)))
        })?;
        match value.get("format").and_then(|v| v.as_str()) {
            Some(FORMAT) => {}
            _ => {
                return Err(bad(format!(
                    "not a hyst model file (no `format = \"{FORMAT}\"`)"
                )))
            }
        }
        match value.get("version") {
            Some(toml::Value::Integer(v))
                if (i64::from(MIN_VERSION)..=i64::from(VERSION)).contains(v) => {}
            Some(toml::Value::Integer(v)) => {
                return Err(bad(format!(
                    "format version {v}; this hyst reads versions {MIN_VERSION} to {VERSION}"
                )))
            }
            Some(other) => {
                let at = top_level_line(text, "version")
                    .map_or_else(String::new, |line| format!("line {line}: "));
                // The hint fits what was written: "1" needs its quotes removed, 1.0 its
                // decimal point.
                let hint = match other {
                    toml::Value::String(_) => ", no quotes",
                    toml::Value::Float(_) => ", no decimal point",
                    _ => "",
                };
                // TOML writes a string with a line break in triple quotes over several lines:
                // the message stays on one line, and short.
                let mut shown = other.to_string().replace('\n', "\\n");
                if shown.chars().count() > 60 {
                    shown = shown.chars().take(40).collect::<String>() + "...";
                }
                return Err(bad(format!(
                    "{at}`version = {shown}` is a {}: the format version is an integer \
                     (`version = {MIN_VERSION}`{hint})",
                    other.type_str()
                )));
            }
            None => return Err(bad("no `version`".into())),
        }
        let mut file: ModelFile = toml::from_str(text).map_err(|e: toml::de::Error| {
            bad(format!("invalid model file: {}", toml_message(text, &e)))
        })?;
        file.install_timed().map_err(bad)?;
        file.provenance.check().map_err(bad)?;
        if file.version < file.required_version() {
            return Err(bad(format!(
                "version = {} but {} needs format version {}",
                file.version,
                file.required_by(),
                file.required_version()
            )));
        }
        match file.kind {
            ModelKind::Smooth => {
                let m = file
                    .smooth
                    .as_ref()
                    .ok_or_else(|| bad("kind = \"smooth\" but no [smooth] section".into()))?;
                // Each shaping first, so that the error names its section.
                for (section, psi) in [
                    ("[smooth.input_shaping]", &m.input_shaping),
                    ("[smooth.output_shaping]", &m.output_shaping),
                ] {
                    psi.validate().map_err(|e| bad(format!("{section}: {e}")))?;
                }
                m.validate().map_err(|e| bad(format!("[smooth]: {e}")))?;
            }
            ModelKind::PrandtlIshlinskii => {
                let m = file.prandtl_ishlinskii.as_ref().ok_or_else(|| {
                    bad("kind = \"prandtl-ishlinskii\" but no [prandtl-ishlinskii] section".into())
                })?;
                m.operator()
                    .map_err(|e| bad(format!("[prandtl-ishlinskii]: {e}")))?;
            }
        }
        Ok(file)
    }

    /// The lowest format version that holds this file's content: 5 for a plant driven through
    /// a zero-order hold (`hold` in `[dynamics]`), 4 for a smooth model with dynamics or a rate
    /// term, 3 for a stop-form smooth model, 2 with a PI output polynomial,
    /// else 1. `hyst fit` writes this version.
    #[must_use]
    pub fn required_version(&self) -> u32 {
        let timed_structure = self
            .structure
            .is_some_and(|s| s.dynamics != 0 || s.rate.is_some());
        let hold = self.dynamics.as_ref().is_some_and(|d| d.hold.is_some())
            || self
                .smooth
                .as_ref()
                .is_some_and(|m| m.dynamics.is_some_and(|d| d.hold().recorded().is_some()));
        match (&self.smooth, &self.prandtl_ishlinskii) {
            _ if hold => 5,
            (Some(m), _) if m.is_timed() || timed_structure => 4,
            (Some(m), _) if m.form == Form::Stop => 3,
            (_, Some(p)) if p.output.is_some() => 2,
            _ => MIN_VERSION,
        }
    }

    /// What makes [`ModelFile::required_version`] what it is, in the file's words.
    fn required_by(&self) -> &'static str {
        match self.required_version() {
            5 => "hold in [dynamics]",
            4 => "[dynamics] or [rate]",
            3 => "form = \"stop\" in [smooth]",
            2 => "[prandtl-ishlinskii.output]",
            _ => "the content",
        }
    }

    /// The model ready to run one record sample by sample, on plain numbers or jets. Direct:
    /// `first` is the record's first input (the smooth model's start rule uses it). Inverse
    /// (the exact compensator): `first` is the first desired output, and the compensator starts
    /// from the state the model's start rule implies for it. PI models start with the plays at
    /// rest at the first sample.
    ///
    /// # Errors
    /// [`ModelError::Core`] for parameters the core refuses or a first desired output the model
    /// cannot produce.
    pub fn evaluator(&self, first: f64, inverse: bool) -> Result<Evaluator, ModelError> {
        self.untimed("running it sample by sample without time")?;
        match (&self.smooth, &self.prandtl_ishlinskii) {
            (Some(m), _) if self.kind == ModelKind::Smooth => {
                if inverse {
                    return Ok(Evaluator::SmoothInverse(Box::new(
                        m.inverse_from_desired(first)?,
                    )));
                }
                let operator = Hysteresis::with_k2_law(m.k1, m.k2)?;
                Ok(Evaluator::Smooth(Box::new(m.shaped(operator, first)?)))
            }
            (_, Some(p)) if inverse => Ok(Evaluator::Pi(Box::new(p.inverse_operator()?))),
            (_, Some(p)) => Ok(Evaluator::Pi(Box::new(p.operator()?))),
            _ => Err(ModelError::Invalid("the model file holds no model".into())),
        }
    }

    /// The smooth model's evaluator resumed at `memory`, a memory its run held
    /// ([`Operator::memory`] of an evaluator of this file, direct or `inverse` as here): the
    /// start rule does not apply, and the next sample continues that run exactly.
    ///
    /// # Errors
    /// [`ModelError::Invalid`] for a Prandtl–Ishlinskii model (its memory is its plays);
    /// [`ModelError::Core`] for a memory the model's operator cannot be in.
    pub fn evaluator_at(
        &self,
        memory: hyst_core::Memory<f64>,
        inverse: bool,
    ) -> Result<Evaluator, ModelError> {
        let Some(m) = self
            .smooth
            .as_ref()
            .filter(|_| self.kind == ModelKind::Smooth)
        else {
            return Err(ModelError::Invalid(
                "only a smooth model's run resumes from a memory of Definition 2.1".into(),
            ));
        };
        // A first sample whose start the memory then replaces: the input or the desired output
        // that memory's last sample stands for (reachable, so the start rule accepts it).
        let probe = if inverse {
            m.output_shaping.apply(memory.last_output)
        } else {
            m.input_shaping.invert(memory.last_input).unwrap_or(0.0)
        };
        let mut evaluator = self.evaluator(probe, inverse)?;
        evaluator.set_memory(crate::evaluator::EvaluatorMemory::Smooth(Some(memory)))?;
        Ok(evaluator)
    }

    /// Puts the `[dynamics]` and `[rate]` sections into the smooth model they belong to.
    fn install_timed(&mut self) -> Result<(), String> {
        if self.dynamics.is_none() && self.rate.is_none() {
            return Ok(());
        }
        let Some(m) = self
            .smooth
            .as_mut()
            .filter(|_| self.kind == ModelKind::Smooth)
        else {
            return Err(
                "[dynamics] and [rate] belong to a smooth model (kind = \"smooth\")".into(),
            );
        };
        if let Some(d) = &self.dynamics {
            let plant = d.dynamics().map_err(|e| format!("[dynamics]: {e}"))?;
            m.dynamics = Some(plant);
            if let Some(s) = self.structure.as_mut() {
                s.hold = plant.hold();
            }
        }
        if let Some(r) = &self.rate {
            if !r.c.is_finite() {
                return Err(format!("[rate]: c = {} must be finite", r.c));
            }
            m.rate = Some(Rate { c: r.c });
        }
        Ok(())
    }

    /// The hysteresis part of a model with dynamics or a rate term: this file without its plant
    /// (`[dynamics]`, Lemma 5.1's b / (a_n sⁿ + … + a_1 s + 1), eq. 18) and its rate term
    /// (`[rate]`), their parameters (`dynamics.a1` …, `rate.c`) and their entries in
    /// `[structure]`, written at the lowest format version that holds the rest. It maps the
    /// plant output x1 (input units) to the output y = ψ_out(H(k1, k2)[ψ_in(x1)]) (output
    /// units), and runs, inverts and exports as a static model. Its metrics and family are the
    /// fit's, of the model with its plant. A static model's file comes back as it is.
    #[must_use]
    pub fn hysteresis(&self) -> ModelFile {
        let mut out = self.clone();
        if self.dynamics.is_none()
            && self.rate.is_none()
            && !self.smooth.as_ref().is_some_and(SmoothModel::is_timed)
        {
            return out;
        }
        if let Some(m) = out.smooth.as_mut() {
            m.dynamics = None;
            m.rate = None;
        }
        out.dynamics = None;
        out.rate = None;
        if let Some(s) = out.structure.as_mut() {
            s.dynamics = 0;
            s.rate = None;
            s.hold = crate::dynamics::Hold::UNRECORDED;
        }
        out.parameters
            .retain(|e| !(e.name.starts_with("dynamics.") || e.name.starts_with("rate.")));
        out.version = out.required_version();
        out
    }

    /// Refuses a model with dynamics or a rate term ([`SmoothModel::is_timed`]) for a use
    /// that cannot run one (`what`, in words: "the FMU", "the C host API", …): such a model
    /// needs the sample period of a timed record, and running it without would silently drop
    /// its plant.
    ///
    /// # Errors
    /// [`ModelError::Invalid`] naming what the model has and what can run it.
    pub fn untimed(&self, what: &str) -> Result<(), ModelError> {
        let Some(m) = self.smooth.as_ref().filter(|m| m.is_timed()) else {
            return Ok(());
        };
        let mut parts = Vec::new();
        if let Some(d) = m.dynamics {
            parts.push(format!("dynamics of order {}", d.order()));
        }
        if m.rate.is_some() {
            parts.push("a rate term".to_string());
        }
        Err(ModelError::Invalid(format!(
            "the model has {}: it runs on timed records only (`hyst run` with a time column), \
             not for {what}",
            parts.join(" and ")
        )))
    }

    /// The saturation of a smooth model whose output is bounded, by a saturating output or
    /// input shaping (tanh, Langevin): the open range of its output and the limits that
    /// `hyst run --inverse --saturate` (and every other surface's saturation) clamps desired
    /// outputs to ([`Saturation::of`]). `None` for a model whose output is unbounded (affine or
    /// polynomial shapings, Prandtl–Ishlinskii).
    #[must_use]
    pub fn saturation(&self) -> Option<Saturation> {
        self.smooth
            .as_ref()
            .filter(|_| self.kind == ModelKind::Smooth)
            .and_then(Saturation::of)
    }

    /// Reads and checks a model file.
    ///
    /// # Errors
    /// [`ModelError::File`] when it cannot be read or is invalid.
    pub fn read(path: &Path) -> Result<Self, ModelError> {
        let text = std::fs::read_to_string(path).map_err(|e| ModelError::File {
            path: path.to_path_buf(),
            message: format!("cannot read: {e}"),
        })?;
        Self::from_toml(&text, path)
    }

    /// Runs the model (direct) over one record of input samples.
    ///
    /// # Errors
    /// [`ModelError::Core`] when the model cannot run the input (a non-finite sample).
    pub fn run(&self, input: &[f64]) -> Result<Vec<f64>, ModelError> {
        match (&self.smooth, &self.prandtl_ishlinskii) {
            (Some(m), _) if self.kind == ModelKind::Smooth => Ok(m.run(input)?),
            (_, Some(p)) => Ok(p.run(input)?),
            _ => Err(ModelError::Invalid("the model file holds no model".into())),
        }
    }

    /// Runs the exact compensator over one record of desired outputs: the command that makes
    /// the model produce them. The compensator starts from the state the model's start rule
    /// implies for the first desired output.
    ///
    /// # Errors
    /// [`ModelError::Core`] for a desired output the model cannot produce (beyond a saturating
    /// output shaping, say) or a non-finite sample; the message names the sample.
    pub fn run_inverse(&self, desired: &[f64]) -> Result<Vec<f64>, ModelError> {
        let Some(&y0) = desired.first() else {
            return Ok(Vec::new());
        };
        let mut comp = self.evaluator(y0, true)?;
        desired
            .iter()
            .enumerate()
            .map(|(i, y)| {
                comp.try_step(*y).map_err(|e| {
                    ModelError::Invalid(format!("sample {} (desired output {y}): {e}", i + 1))
                })
            })
            .collect()
    }

    /// k2 at the operator input 0 and its range over the operator input interval [lo, hi]
    /// (a convenience for reports).
    #[must_use]
    pub fn k2_range(&self, lo: f64, hi: f64) -> Option<(f64, f64)> {
        self.smooth.as_ref().map(|m| m.k2.range(lo, hi))
    }
}

/// FNV-1a 64-bit hash (provenance of the data file).
#[must_use]
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The 1-based line of the top-level key `key` (before the first table header), if it is
/// written plainly as `key = …`.
fn top_level_line(text: &str, key: &str) -> Option<usize> {
    text.lines()
        .take_while(|line| !line.trim_start().starts_with('['))
        .position(|line| {
            line.trim_start()
                .strip_prefix(key)
                .is_some_and(|rest| rest.trim_start().starts_with('='))
        })
        .map(|i| i + 1)
}

/// A TOML error on one line: "line L, column C: message" (the parser's own display spans several
/// lines with a snippet of the file).
/// A TOML parser's error in one line, "line L, column C: message" (the parser's own message
/// spans several lines and quotes the source), cut at 300 characters.
#[must_use]
pub fn toml_message(text: &str, e: &toml::de::Error) -> String {
    let mut message = e.message().trim().replace('\n', "; ");
    // The parser's message may quote the offending value: a 5 MB name is not echoed whole.
    if message.chars().count() > 300 {
        let bytes = message.len();
        message =
            message.chars().take(200).collect::<String>() + &format!("... ({bytes} bytes in all)");
    }
    match e.span() {
        Some(span) => {
            let before = text.get(..span.start).unwrap_or("");
            let line = before.matches('\n').count() + 1;
            let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
            format!("line {line}, column {column}: {message}")
        }
        None => message,
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::saturation::Saturated;
    use hyst_core::AnyShaping;

    /// A model whose tanh output shaping holds its data in the last 0.1 % of its range (the
    /// tail used as an exponential, as a fit can place it): ψ_out(u) = 1e8 tanh(u + 5) − 1e8.
    fn tail_model() -> ModelFile {
        ModelFile::from_toml(TAIL, Path::new("tail.toml")).unwrap()
    }

    /// The text of [`tail_model`].
    const TAIL: &str = r#"
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
pre_offset = 5.0
post_gain = 1e8
post_offset = -1e8
[smooth.output_shaping.shape.tanh]
gain = 1.0
scale = 1.0
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

    #[test]
    fn saturation_never_clamps_an_output_of_the_fitted_input_range() {
        let file = tail_model();
        let m = file.smooth.unwrap();
        let s = file.saturation().unwrap();
        // 99.9 % of the range about its centre would stop 1e5 below the top: every output
        // of the data (x in [0, 4], the interval ψ_in's scaling maps to [-1, 1]) is higher.
        let top = m.output_shaping.apply(1.0 + m.k1);
        let bottom = m.output_shaping.apply(-1.0 - m.k1);
        assert!(top > -1e5 && top < s.range.1);
        assert!(s.widened);
        assert_eq!(s.limits.1, top);
        assert!(s.limits.0 <= bottom && s.limits.0 > s.range.0);
        // Every output the model gives for inputs in [0, 4] is inside the limits.
        for k in 0..=400 {
            let x = 4.0 * f64::from(k) / 400.0;
            for y in file.run(&[0.0, x]).unwrap() {
                assert!(s.limits.0 <= y && y <= s.limits.1, "{y} at {x}");
            }
        }
        assert!(s.rule().contains("widened"));
    }

    /// The piezo record (inputs 0 to 3.6 V) fitted with a tanh or a Langevin ψ_in and a tanh
    /// ψ_out whose data sit in its tail (`hyst fit --input-shaping tanh|langevin
    /// --output-shaping tanh`, see each file's provenance).
    fn saturating_input_models() -> [(&'static str, ModelFile); 2] {
        let read = |name: &str, text: &str| ModelFile::from_toml(text, Path::new(name)).unwrap();
        [
            (
                "tanh",
                read(
                    "piezo-tanh-in.toml",
                    include_str!("../testdata/piezo-tanh-in.toml"),
                ),
            ),
            (
                "langevin",
                read(
                    "piezo-langevin-in.toml",
                    include_str!("../testdata/piezo-langevin-in.toml"),
                ),
            ),
        ]
    }

    #[test]
    fn a_saturating_input_shaping_keeps_the_fitted_range_and_its_limits() {
        for (name, file) in saturating_input_models() {
            let m = file.smooth.as_ref().unwrap();
            let (lo, hi) = m.fitted_input_interval();
            println!("{name}: fitted input interval [{lo}, {hi}] V");
            assert!(
                lo.abs() < 1e-6 && (hi - 3.6).abs() < 1e-6,
                "{name}: [{lo}, {hi}]"
            );
            // Adaptation learns over the fitted range widened by 10 % of its span.
            let (a, b) = crate::adaptive::fitted_input_range(&file, m);
            assert!(
                (a + 0.36).abs() < 1e-6 && (b - 3.96).abs() < 1e-6,
                "{name}: [{a}, {b}]"
            );
            // Desired outputs inside the training range (-130 to -75 um) are not clamped:
            // the saturated inverse gives the plain inverse's commands, bit for bit.
            let s = file.saturation().unwrap();
            println!("{name}: limits {:?} ({})", s.limits, s.rule());
            let desired = [-120.0, -100.0, -80.0];
            let plain = file.run_inverse(&desired).unwrap();
            let mut clamped =
                Saturated::new(file.evaluator(desired[0], true).unwrap(), Some(s.limits));
            let saturated: Vec<f64> = desired
                .iter()
                .map(|y| clamped.try_step(*y).unwrap())
                .collect();
            println!("{name}: commands {saturated:?} V");
            assert_eq!(saturated, plain, "{name}");
            assert_eq!(clamped.saturated, 0, "{name}");
            for (u, right) in saturated.iter().zip([1.33, 2.30, 3.34]) {
                assert!(
                    (u - right).abs() < 0.01,
                    "{name}: {u} V, expected about {right} V"
                );
            }
            // Every output of the fitted input range is inside the limits.
            for k in 0..=360 {
                let x = 3.6 * f64::from(k) / 360.0;
                for y in file.run(&[0.0, x, 0.0]).unwrap() {
                    assert!(s.limits.0 <= y && y <= s.limits.1, "{name}: {y} at {x}");
                }
            }
        }
    }

    /// `tail_model` with a curved ψ_in of the form `hyst fit` writes for a saturating input
    /// shaping, on data from 0 to 4: ψ_in(x) = (σ / f'(a)) (f(x̂ / σ + a) − f(a)), x̂ = (x − 2) / 2,
    /// σ = 0.7, a = 0.4 (value 0 and slope 1 per unit of x̂ at the centre).
    fn curved_input_model(shape: AnyShaping<f64>) -> ModelFile {
        let mut file = tail_model();
        let (sigma, a, centre, half) = (0.7, 0.4, 2.0, 2.0);
        let (value, slope) = shape.value_and_slope(a);
        let gain = sigma / slope;
        let m = file.smooth.as_mut().unwrap();
        m.input_shaping = hyst_core::ScaledShaping::new(
            1.0 / (half * sigma),
            -centre / (half * sigma) + a,
            shape,
            gain,
            -gain * value,
        )
        .unwrap();
        file.provenance.rows = 1000;
        file
    }

    #[test]
    fn a_curved_saturating_input_shaping_keeps_the_fitted_range_and_its_limits() {
        use hyst_core::{Langevin, Tanh};
        for shape in [
            AnyShaping::Tanh(Tanh::new(1.0, 1.0).unwrap()),
            AnyShaping::Langevin(Langevin::new(1.0, 1.0).unwrap()),
        ] {
            let file = curved_input_model(shape);
            let name = shape.name();
            let m = file.smooth.as_ref().unwrap();
            let (lo, hi) = m.fitted_input_interval();
            assert!(
                lo.abs() < 1e-12 && (hi - 4.0).abs() < 1e-12,
                "{name}: [{lo}, {hi}]"
            );
            let (a, b) = crate::adaptive::fitted_input_range(&file, m);
            assert!(
                (a + 0.4).abs() < 1e-12 && (b - 4.4).abs() < 1e-12,
                "{name}: [{a}, {b}]"
            );
            let s = file.saturation().unwrap();
            // Outputs of commands inside the fitted range invert, saturated, to those commands.
            let commands = [0.0, 0.5, 2.0, 3.5, 4.0, 1.0];
            let desired = file.run(&commands).unwrap();
            let mut clamped =
                Saturated::new(file.evaluator(desired[0], true).unwrap(), Some(s.limits));
            for (x, y) in commands.iter().zip(&desired) {
                let u = clamped.try_step(*y).unwrap();
                assert!((u - x).abs() < 1e-6, "{name}: {y} gave {u}, expected {x}");
            }
            assert_eq!(clamped.saturated, 0, "{name}");
        }
    }

    #[test]
    fn a_gain_whose_inverse_overflows_is_refused_on_load_naming_file_key_and_value() {
        let text = TAIL;
        let cases = [
            (
                "[smooth.output_shaping]",
                "post_gain = 1e8",
                "post_gain = 1e-310",
                "post_gain = 1e-310",
            ),
            (
                "[smooth.input_shaping]",
                "pre_gain = 0.5",
                "pre_gain = 5e-324",
                "pre_gain = 5e-324",
            ),
            (
                "[smooth.output_shaping]",
                "gain = 1.0\nscale = 1.0",
                "gain = 1.0\nscale = 2e-310",
                "tanh scale = 2e-310",
            ),
        ];
        for (section, from, to, named) in cases {
            assert!(text.contains(from), "{from} in {text}");
            let bad = text.replacen(from, to, 1);
            let e = ModelFile::from_toml(&bad, Path::new("subnormal.toml"))
                .unwrap_err()
                .to_string();
            println!("{e}");
            assert!(e.starts_with("subnormal.toml: "), "{e}");
            assert!(e.contains(section) && e.contains(named), "{e}");
            assert!(e.contains("normal float"), "{e}");
        }
    }

    #[test]
    fn the_hysteresis_part_of_a_timed_model_is_its_static_model() {
        let file = tail_model();
        let mut timed = file.clone();
        let estimate = |name: &str, value: f64| Estimate {
            name: name.into(),
            value,
            std_error: 0.001,
            unit: "s".into(),
        };
        timed.parameters = vec![estimate("k1", 0.2), estimate("dynamics.a1", 0.01)];
        timed.parameters.push(estimate("rate.c", 0.5));
        timed.dynamics = Some(DynamicsSection {
            b: 2.0,
            a: vec![0.01],
            a_std_error: vec![0.001],
            identified: vec![true],
            hold: Some(crate::dynamics::Hold::Zoh),
        });
        timed.rate = Some(RateSection {
            c: 0.5,
            c_std_error: 0.01,
        });
        timed.version = VERSION;
        // Through its text, as a file is read: the sections are installed in the model.
        let timed = ModelFile::from_toml(&timed.to_toml().unwrap(), Path::new("t.toml")).unwrap();
        assert!(timed.untimed("a test").is_err());
        let part = timed.hysteresis();
        part.untimed("a test").unwrap();
        assert_eq!(part.version, 1);
        let names: Vec<&str> = part.parameters.iter().map(|e| e.name.as_str()).collect();
        assert_eq!(names, ["k1"]);
        assert_eq!(part.smooth, file.smooth);
        // It reads back as what it is, and runs as the static model does.
        let text = part.to_toml().unwrap();
        assert!(!text.contains("dynamics") && !text.contains("[rate]"));
        let back = ModelFile::from_toml(&text, Path::new("p.toml")).unwrap();
        let x = [0.0, 1.0, 3.0, 2.0, 4.0];
        assert_eq!(back.run(&x).unwrap(), file.run(&x).unwrap());
        // A static model's file comes back as it is.
        assert_eq!(file.hysteresis(), file);
    }
}
