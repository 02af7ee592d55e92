//! What an FMU of hyst holds besides its binary, written from what it computes
//! ([`Description`]): `modelDescription.xml` (its variables, their value references and
//! causality, the model structure), `resources/fmu.toml` (what this binary reads at
//! fmi2Instantiate, [`crate::config`]) and `documentation/index.html`. `hyst fmu` packs them
//! with the binary; the value references are [`crate::layout`]'s, so the variables the
//! description declares and the ones this binary serves are defined in one crate (docs/fmu.md).
//!
//! - Variables: 0 `x` (input), 1 `y` (output, direct feedthrough), for the operator 2 `k1`, 3 `k2`
//!   (fixed parameters), for a timed model's compensator 2.. `x_d1`.. ([`crate::timed`]).

use std::fmt::Write as _;

use hyst_model::{ModelFile, ModelKind};

use crate::layout::{DERIVATIVE_NAMES, VR_X_D1};
use crate::layout::{FORMAT, MODEL_FILE, VERSION, VR_K1, VR_K2, VR_X, VR_Y};
use crate::timed::Timing;

/// The FMI modelIdentifier: the binary's name inside the FMU (binaries/linux64/hyst.so).
const MODEL_IDENTIFIER: &str = "hyst";

/// hyst's version, in generationTool and the documentation: the workspace's, which this crate
/// and the `hyst` executable share.
const HYST_VERSION: &str = env!("CARGO_PKG_VERSION");

/// What the FMU computes.
#[derive(Clone, Debug)]
pub enum Kind {
    /// H(k1, k2) or its inverse.
    Operator {
        /// The start value of the parameter k1 (the half-width of the loop, > 0).
        k1: f64,
        /// The start value of the parameter k2 (the rate of the transition, > 0).
        k2: f64,
    },
    /// A fitted model (or its inverse).
    Model {
        /// The model file, as checked (its bytes go into `resources/model.toml`).
        file: Box<ModelFile>,
        /// For a model with dynamics or a rate term, what the FMU needs ([`Timing::of`]).
        timing: Option<Timing>,
    },
}

/// Everything an FMU's description, configuration and documentation are written from.
#[derive(Clone, Debug)]
pub struct Description {
    /// The modelName (the FMU's file name without `.fmu`).
    pub model_name: String,
    /// The FMU's GUID, `{8-4-4-4-12}` (modelDescription.xml and fmu.toml, which this binary
    /// compares at fmi2Instantiate).
    pub guid: String,
    /// generationDateAndTime (xs:dateTime, UTC).
    pub generated: String,
    /// What the FMU computes.
    pub kind: Kind,
    /// The inverse of the operator or model: the desired output in, the command out.
    pub inverse: bool,
    /// Clamp desired outputs into the model's saturation limits (`--saturate`).
    pub saturate: bool,
    /// The command line that made the FMU (shell-quoted), for the documentation.
    pub command: String,
}

/// Escapes text for XML and HTML (element content and quoted attributes).
fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            // Control characters and the non-characters U+FFFE and U+FFFF are not allowed in
            // XML 1.0 (TOML strings may hold them).
            c if c.is_control() || matches!(c, '\u{fffe}' | '\u{ffff}') => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// A number in full precision, as xs:double and TOML both read it (`8.0`, `0.2`, `1e-7`).
fn number(v: f64) -> String {
    format!("{v:?}")
}

/// One variable of the FMU.
#[derive(Clone)]
struct Variable {
    name: &'static str,
    value_reference: u32,
    causality: &'static str,
    variability: &'static str,
    /// `initial` attribute, if any.
    initial: Option<&'static str>,
    start: Option<f64>,
    unit: String,
    description: String,
}

impl Description {
    /// What the FMU needs for a model with dynamics or a rate term.
    fn timing(&self) -> Option<&Timing> {
        match &self.kind {
            Kind::Model { timing, .. } => timing.as_ref(),
            Kind::Operator { .. } => None,
        }
    }

    /// A short description of what the FMU computes (modelDescription.xml's `description`, the
    /// documentation's first line, what `hyst fmu` prints).
    #[must_use]
    pub fn what(&self) -> String {
        match (&self.kind, self.inverse) {
            (Kind::Operator { k1, k2 }, false) => {
                format!("the hysteresis operator H(k1 = {k1}, k2 = {k2})")
            }
            (Kind::Operator { k1, k2 }, true) => format!(
                "the inverse operator H^-1(k1 = {k1}, k2 = {k2}): desired output in, command out"
            ),
            (Kind::Model { file, timing, .. }, inverse) => {
                let kind = match file.kind {
                    ModelKind::Smooth => "smooth",
                    ModelKind::PrandtlIshlinskii => "Prandtl-Ishlinskii",
                };
                let with = timing.as_ref().map(|t| format!(" with {}", t.what));
                let kind = format!("{kind} hysteresis model{}", with.unwrap_or_default());
                let (input, output) = (&file.columns.input, &file.columns.output);
                if inverse {
                    let clamped = match file.saturation().filter(|_| self.saturate) {
                        Some(s) => format!(
                            ", desired outputs clamped into [{}, {}]",
                            s.limits.0, s.limits.1
                        ),
                        None => String::new(),
                    };
                    let inverse = match timing {
                        Some(_) => "Lemma 5.1's compensator",
                        None => "the exact inverse",
                    };
                    format!("{inverse} of a fitted {kind} ({output} -> {input}){clamped}")
                } else {
                    format!("a fitted {kind} ({input} -> {output})")
                }
            }
        }
    }

    /// The variables in value-reference order (their 1-based index in ModelVariables is vr + 1).
    fn variables(&self) -> Vec<Variable> {
        let [(x, xu), (y, yu)] = self.signals();
        let input = Variable {
            name: "x",
            value_reference: VR_X,
            causality: "input",
            variability: "continuous",
            initial: None,
            start: Some(0.0),
            unit: xu,
            description: x,
        };
        let mut vars = vec![
            input.clone(),
            Variable {
                name: "y",
                value_reference: VR_Y,
                causality: "output",
                variability: "continuous",
                initial: Some("calculated"),
                start: None,
                unit: yu,
                description: y,
            },
        ];
        if let Kind::Operator { k1, k2 } = self.kind {
            vars.extend(self.parameters(k1, k2));
        }
        if let (Some(t), Kind::Model { file, .. }) = (self.timing(), &self.kind) {
            for (k, name) in DERIVATIVE_NAMES.iter().enumerate().take(t.derivatives) {
                let description = Timing::derivative_description(k + 1, file);
                let (value_reference, unit) = (VR_X_D1 + k as u32, String::new());
                vars.push(Variable {
                    name,
                    value_reference,
                    description,
                    unit,
                    ..input.clone()
                });
            }
        }
        vars
    }

    /// The descriptions and units of x and y: the operator's or the model's input and output,
    /// or for an inverse the desired output and the command.
    fn signals(&self) -> [(String, String); 2] {
        let with_unit = |name: &str, unit: &str| {
            if unit.is_empty() {
                name.to_string()
            } else {
                format!("{name} [{unit}]")
            }
        };
        match (&self.kind, self.inverse) {
            (Kind::Operator { .. }, false) => [
                (
                    "input v of the hysteresis operator H(k1, k2)".to_string(),
                    String::new(),
                ),
                (
                    "output H[v] for the input history including the current x".to_string(),
                    String::new(),
                ),
            ],
            (Kind::Operator { .. }, true) => [
                (
                    "desired output of H(k1, k2), the input of its inverse H^-1".to_string(),
                    String::new(),
                ),
                (
                    "command H^-1[x] for the history including the current x: the input that \
                     makes H produce x"
                        .to_string(),
                    String::new(),
                ),
            ],
            (Kind::Model { file, .. }, false) => [
                (
                    format!(
                        "model input: {}",
                        with_unit(&file.columns.input, &file.units.input)
                    ),
                    file.units.input.clone(),
                ),
                (
                    format!(
                        "model output: {}, for the input history including the current x",
                        with_unit(&file.columns.output, &file.units.output)
                    ),
                    file.units.output.clone(),
                ),
            ],
            (Kind::Model { file, .. }, true) => [
                (
                    format!(
                        "desired model output: {}",
                        with_unit(&file.columns.output, &file.units.output)
                    ),
                    file.units.output.clone(),
                ),
                (
                    format!(
                        "command: {}, that makes the model produce x (the exact inverse), for \
                         the history including the current x",
                        with_unit(&file.columns.input, &file.units.input)
                    ),
                    file.units.input.clone(),
                ),
            ],
        }
    }

    /// k1 and k2, the operator's parameters (fixed, set before initialisation).
    fn parameters(&self, k1: f64, k2: f64) -> [Variable; 2] {
        // H's output is y (x for the inverse), its input x (y for the inverse).
        let (k1_units, k2_units) = if self.inverse {
            ("units of x", "1/units of y")
        } else {
            ("units of y", "1/units of x")
        };
        let parameter = |name, value_reference, start, description| Variable {
            name,
            value_reference,
            causality: "parameter",
            variability: "fixed",
            initial: Some("exact"),
            start: Some(start),
            unit: String::new(),
            description,
        };
        [
            parameter(
                "k1",
                VR_K1,
                k1,
                format!(
                    "k1: half-width of the hysteresis loop of H ({k1_units}), > 0; set before \
                     initialisation"
                ),
            ),
            parameter(
                "k2",
                VR_K2,
                k2,
                format!(
                    "k2: rate of the transition of H to its asymptotes ({k2_units}), > 0; set \
                     before initialisation"
                ),
            ),
        ]
    }

    /// modelDescription.xml (FMI 2.0, Co-Simulation).
    #[must_use]
    pub fn model_description(&self) -> String {
        let vars = self.variables();
        let mut units: Vec<&str> = Vec::new();
        for v in &vars {
            if !v.unit.is_empty() && !units.contains(&v.unit.as_str()) {
                units.push(&v.unit);
            }
        }
        let mut x = String::new();
        x.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
        let _ = writeln!(
            x,
            "<fmiModelDescription\n  fmiVersion=\"2.0\"\n  modelName=\"{}\"\n  guid=\"{}\"\n  \
             description=\"{}\"\n  generationTool=\"hyst {}\"\n  \
             generationDateAndTime=\"{}\"\n  variableNamingConvention=\"flat\"\n  \
             numberOfEventIndicators=\"0\">",
            escape(&self.model_name),
            self.guid,
            escape(&self.what()),
            HYST_VERSION,
            self.generated
        );
        let timing = self.timing();
        // Every model takes steps of any size: a timed one is discretised for each.
        let variable_step = true;
        let _ = writeln!(
            x,
            "  <CoSimulation\n    modelIdentifier=\"{MODEL_IDENTIFIER}\"\n    \
             needsExecutionTool=\"false\"\n    \
             canHandleVariableCommunicationStepSize=\"{variable_step}\"\n    \
             canInterpolateInputs=\"false\"\n    maxOutputDerivativeOrder=\"0\"\n    \
             canRunAsynchronuously=\"false\"\n    \
             canBeInstantiatedOnlyOncePerProcess=\"false\"\n    \
             canNotUseMemoryManagementFunctions=\"true\"\n    \
             canGetAndSetFMUstate=\"true\"\n    canSerializeFMUstate=\"{}\"\n    \
             providesDirectionalDerivative=\"false\"/>",
            timing.is_none()
        );
        if !units.is_empty() {
            x.push_str("  <UnitDefinitions>\n");
            for u in &units {
                let _ = writeln!(x, "    <Unit name=\"{}\"/>", escape(u));
            }
            x.push_str("  </UnitDefinitions>\n");
        }
        x.push_str("  <ModelVariables>\n");
        for v in &vars {
            let _ = write!(
                x,
                "    <!-- index {} -->\n    <ScalarVariable name=\"{}\" valueReference=\"{}\" \
                 description=\"{}\" causality=\"{}\" variability=\"{}\"",
                v.value_reference + 1,
                v.name,
                v.value_reference,
                escape(&v.description),
                v.causality,
                v.variability
            );
            if let Some(initial) = v.initial {
                let _ = write!(x, " initial=\"{initial}\"");
            }
            x.push_str(">\n      <Real");
            if let Some(start) = v.start {
                let _ = write!(x, " start=\"{}\"", number(start));
            }
            if !v.unit.is_empty() {
                let _ = write!(x, " unit=\"{}\"", escape(&v.unit));
            }
            x.push_str("/>\n    </ScalarVariable>\n");
        }
        x.push_str("  </ModelVariables>\n");
        // y depends directly on the inputs (x, and x_d1 ... of a compensator); initially also on
        // the parameters k1, k2 (a variable's index is its value reference + 1).
        let index = |vr: u32| (vr + 1).to_string();
        let y_index = index(VR_Y);
        let on = |causalities: &[&str]| {
            let on = vars.iter().filter(|v| causalities.contains(&v.causality));
            let indices: Vec<String> = on.map(|v| index(v.value_reference)).collect();
            (
                indices.join(" "),
                vec!["dependent"; indices.len()].join(" "),
            )
        };
        let ((inputs, input_kinds), (initial, kinds)) =
            (on(&["input"]), on(&["input", "parameter"]));
        let _ = write!(
            x,
            "  <ModelStructure>\n    <Outputs>\n      \
             <Unknown index=\"{y_index}\" dependencies=\"{inputs}\" \
             dependenciesKind=\"{input_kinds}\"/>\n    \
             </Outputs>\n    <InitialUnknowns>\n      \
             <Unknown index=\"{y_index}\" dependencies=\"{initial}\" \
             dependenciesKind=\"{kinds}\"/>\n    \
             </InitialUnknowns>\n  </ModelStructure>\n</fmiModelDescription>\n"
        );
        x
    }

    /// resources/fmu.toml: what the binary reads at fmi2Instantiate ([`crate::config`]).
    #[must_use]
    pub fn config(&self) -> String {
        let mut t = String::from(
            "# The configuration of this FMU, read by binaries/linux64/hyst.so at fmi2Instantiate\n\
             # (see docs/fmu.md of hyst).\n",
        );
        let _ = writeln!(t, "format = \"{FORMAT}\"\nversion = {VERSION}");
        let _ = writeln!(t, "guid = \"{}\"", self.guid);
        match self.kind {
            Kind::Operator { k1, k2 } => {
                let _ = writeln!(
                    t,
                    "kind = \"operator\"\ninverse = {}\nk1 = {}\nk2 = {}",
                    self.inverse,
                    number(k1),
                    number(k2)
                );
            }
            Kind::Model { .. } => {
                let _ = writeln!(t, "kind = \"model\"\ninverse = {}", self.inverse);
                if self.saturate {
                    let _ = writeln!(t, "saturate = true");
                }
            }
        }
        t
    }

    /// documentation/index.html: what the FMU is, its variables, the command that made it.
    #[must_use]
    pub fn documentation(&self) -> String {
        let mut h = String::new();
        let _ = write!(
            h,
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
             <title>{name}: hyst FMU</title>\n</head>\n<body>\n<h1>{name}</h1>\n\
             <p>An FMI 2.0 Co-Simulation FMU (linux64) made by hyst {version}: {what}.</p>\n\
             <p>Direct feedthrough: after <code>x</code> is set, <code>y</code> is the output \
             for the input history including that value; <code>fmi2DoStep</code> commits it to \
             the memory, once, and <code>y</code> keeps that output until an input is set for \
             the next communication point. So <code>y</code> at each communication point equals \
             <code>hyst run</code> on the sequence of inputs set at those points, read before \
             or after the step. {time}</p>\n\
             <h2>Variables</h2>\n<table>\n\
             <tr><th>name</th><th>causality</th><th>start</th><th>unit</th>\
             <th>description</th></tr>\n",
            name = escape(&self.model_name),
            version = HYST_VERSION,
            what = escape(&self.what()),
            time = escape(&crate::timed::summary(self.timing())),
        );
        for v in self.variables() {
            let _ = writeln!(
                h,
                "<tr><td><code>{}</code></td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                v.name,
                v.causality,
                v.start.map(number).unwrap_or_default(),
                escape(&v.unit),
                escape(&v.description)
            );
        }
        h.push_str("</table>\n");
        if let Kind::Model { file, .. } = &self.kind {
            let _ = writeln!(
                h,
                "<p>The model file is in <code>resources/{MODEL_FILE}</code> (fitted by \
                 <code>{}</code>).</p>",
                escape(&file.provenance.command)
            );
        }
        let _ = write!(
            h,
            "<h2>Made by</h2>\n<pre>{}</pre>\n<p>GUID {}, {}.</p>\n</body>\n</html>\n",
            escape(&self.command),
            self.guid,
            self.generated
        );
        h
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    #[test]
    fn escaping_and_numbers() {
        assert_eq!(escape("a<b>&\"c'\u{1}"), "a&lt;b&gt;&amp;&quot;c&apos; ");
        // Every character that XML 1.0 does not allow becomes a space: the controls (but tab,
        // line feed and carriage return, which an attribute's value reads as spaces anyway)
        // and the non-characters U+FFFE and U+FFFF.
        assert_eq!(
            escape("\u{0}\t\n\r\u{7f}\u{85}\u{fffe}\u{ffff}µm\u{fffd}"),
            "        µm\u{fffd}"
        );
        assert_eq!(number(8.0), "8.0");
        assert_eq!(number(0.2), "0.2");
        assert_eq!(number(1e-7), "1e-7");
        assert_eq!(number(1e300).parse::<f64>().unwrap(), 1e300);
    }
}
