//! `hyst fmu`: the operator H(k1, k2), a fitted model, or the inverse of either, as an FMI 2.0
//! Co-Simulation FMU for linux64 (Simulink's FMU Import block, OpenModelica, FMPy, ...).
//!
//! Contract (docs/fmu.md; the layout is shared with crates/hyst-fmu, which reads it: its file
//! names, fmu.toml's format and version and the value references are `hyst_fmu::layout`'s):
//! - NAME.fmu is a zip archive holding `modelDescription.xml` (modelName NAME, a fresh GUID,
//!   modelIdentifier `hyst`), `binaries/linux64/hyst.so` (the cdylib of crates/hyst-fmu,
//!   `libhyst_fmu.so`, copied byte for byte), `resources/fmu.toml` (kind, inverse, the GUID and
//!   k1, k2), `resources/model.toml` (with `--model`: the model file, byte for byte) and
//!   `documentation/index.html`.
//! - Variables: 0 `x` (input), 1 `y` (output, direct feedthrough), for the operator 2 `k1`, 3 `k2`
//!   (fixed parameters), for a timed model's compensator 2.. `x_d1`.. (`hyst_fmu::timed`).
//! - The binary is the file named by `HYST_FMU_LIBRARY`, else the one a release build of
//!   `hyst` embeds (crates/hyst-cli/build.rs: an installed `hyst` needs nothing beside it), else
//!   `libhyst_fmu.so` beside the running `hyst` (cargo puts both in target/debug).
//! - The inputs are checked before anything is written (k1, k2 by the core, the model file by
//!   hyst-fit, the binary as an x86-64 ELF shared object exporting the FMI 2.0 functions), and the
//!   FMU is written atomically: on failure no output file exists.

use std::fmt::Write as _;
use std::io::{Cursor, Write as _};
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use crate::source::{Chosen, Source};
use anyhow::{bail, Context, Result};
use hyst_fmu::layout::{CONFIG_FILE, FORMAT, MODEL_FILE, VERSION, VR_K1, VR_K2, VR_X, VR_Y};
use hyst_fmu::layout::{DERIVATIVE_NAMES, VR_X_D1};
use hyst_fmu::timed::Timing;
use hyst_model::ModelFile;
use hyst_model::ModelKind;
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, ZipWriter};

mod library;
use library::read_library;

/// The FMI modelIdentifier: the binary's name inside the FMU (binaries/linux64/hyst.so).
const MODEL_IDENTIFIER: &str = "hyst";

/// Arguments of `hyst fmu`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The operator.
    #[command(flatten)]
    pub source: Source,
    /// With --model --inverse, for a model whose output is bounded by a saturating output or
    /// input shaping (tanh, Langevin): the FMU clamps every desired output beyond the model's
    /// limits (the outputs reachable from every state, within 99.9 % of each saturating
    /// shaping's range: docs/formats.md) to them, as `hyst run --saturate` does, instead of
    /// refusing a value out of reach; fmi2DoStep returns fmi2Warning (and logs it) when the
    /// desired output enters saturation.
    #[arg(long)]
    pub saturate: bool,
    /// The FMU to write (NAME.fmu; NAME becomes the modelName). Written atomically.
    #[arg(short = 'o', long = "out", alias = "output", value_name = "FILE")]
    pub output: PathBuf,
}

/// What the FMU computes.
enum Kind {
    /// H(k1, k2) or its inverse; k1, k2 are the parameters' start values.
    Operator { k1: f64, k2: f64 },
    /// A fitted model (or its inverse): the parsed file, its bytes, and for a model with
    /// dynamics or a rate term what the FMU needs.
    Model {
        file: Box<ModelFile>,
        bytes: Vec<u8>,
        timing: Option<Timing>,
    },
}

/// Everything that goes into the FMU besides the binary.
struct Fmu {
    model_name: String,
    guid: String,
    /// generationDateAndTime (xs:dateTime, UTC).
    generated: String,
    /// The same instant for the zip entries' timestamps.
    timestamp: zip::DateTime,
    kind: Kind,
    inverse: bool,
    /// Clamp desired outputs into the model's saturation limits (`--saturate`).
    saturate: bool,
    /// The command line that made the FMU (shell-quoted).
    command: String,
}

/// Runs `hyst fmu`.
pub fn main(args: Args) -> Result<()> {
    let model_name = model_name(&args.output)?;
    let kind = match args.source.chosen()? {
        Chosen::Model(path) => read_model(path, &args)?,
        Chosen::Parameters { k1, k2 } => Kind::Operator { k1, k2 },
    };
    if args.saturate {
        match &kind {
            Kind::Model { file, .. } if args.source.inverse => {
                if file.saturation().is_none() {
                    bail!(
                        "--saturate: the model's output is unbounded (neither its input nor its \
                         output shaping saturates), so no desired output needs clamping"
                    );
                }
            }
            _ => bail!(
                "--saturate applies to --model FILE --inverse: the inverse of a model whose \
                 output is bounded (a saturating input or output shaping)"
            ),
        }
    }
    let library = read_library()?;
    let (generated, timestamp) = now()?;
    let fmu = Fmu {
        model_name,
        guid: guid()?,
        generated,
        timestamp,
        kind,
        inverse: args.source.inverse,
        saturate: args.saturate,
        command: command_line(),
    };
    let bytes = fmu.archive(&library)?;
    hyst_io::write_atomic(&args.output, &bytes)?;
    outln!(
        "wrote {} (FMI 2.0 co-simulation, linux64: {}; guid {})",
        args.output.display(),
        fmu.what(),
        fmu.guid
    );
    Ok(())
}

/// The modelName: the output file's name without `.fmu`.
fn model_name(output: &Path) -> Result<String> {
    let is_fmu = output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("fmu"));
    let stem = output.file_stem().and_then(|s| s.to_str()).unwrap_or("");
    if !is_fmu || stem.is_empty() {
        bail!(
            "-o {}: the FMU's file name must be NAME.fmu (tools look for the .fmu extension; \
             NAME becomes the modelName)",
            output.display()
        );
    }
    Ok(stem.to_string())
}

/// Reads and checks the model file, keeping the bytes that were checked (they go into the FMU).
/// What the FMU cannot run (`Timing::of`) is refused here rather than at instantiation.
fn read_model(path: &Path, args: &Args) -> Result<Kind> {
    let model = ModelFile::read(path)?; // the same checks and messages as `hyst run --model`
    let timing = Timing::of(&model, args.source.inverse, args.saturate)
        .map_err(anyhow::Error::msg)
        .with_context(|| path.display().to_string())?;
    if is_same_file(path, &args.output) {
        bail!(
            "-o {}: that is the model file itself; write the FMU to another file",
            args.output.display()
        );
    }
    let bytes = std::fs::read(path).with_context(|| format!("{}: cannot read", path.display()))?;
    let text = std::str::from_utf8(&bytes)
        .with_context(|| format!("{}: not UTF-8 text", path.display()))?;
    let file = ModelFile::from_toml(text, path)?;
    Ok(Kind::Model {
        file: Box::new(file),
        bytes,
        timing,
    })
}

/// Whether `a` and `b` name the same existing file.
fn is_same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

/// A fresh GUID, `{8-4-4-4-12}` lowercase hex (a random UUID, version 4).
fn guid() -> Result<String> {
    let mut b = [0u8; 16];
    getrandom::fill(&mut b).map_err(|e| anyhow::anyhow!("cannot draw random bits: {e}"))?;
    b[6] = (b[6] & 0x0f) | 0x40;
    b[8] = (b[8] & 0x3f) | 0x80;
    let hex: String = b.iter().map(|v| format!("{v:02x}")).collect();
    Ok(format!(
        "{{{}-{}-{}-{}-{}}}",
        &hex[0..8],
        &hex[8..12],
        &hex[12..16],
        &hex[16..20],
        &hex[20..32]
    ))
}

/// The current UTC time as xs:dateTime and as a zip timestamp.
fn now() -> Result<(String, zip::DateTime)> {
    let secs = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .context("the system clock is before 1970")?
        .as_secs();
    let (year, month, day) = civil_from_days((secs / 86_400) as i64);
    let s = secs % 86_400;
    let (hour, minute, second) = (s / 3600, s / 60 % 60, s % 60);
    let text = format!("{year:04}-{month:02}-{day:02}T{hour:02}:{minute:02}:{second:02}Z");
    // Zip timestamps cover 1980..=2107; outside, the zip format's default (1980-01-01).
    let stamp = u16::try_from(year)
        .ok()
        .and_then(|y| {
            zip::DateTime::from_date_and_time(
                y,
                month as u8,
                day as u8,
                hour as u8,
                minute as u8,
                second as u8,
            )
            .ok()
        })
        .unwrap_or_default();
    Ok((text, stamp))
}

/// (year, month, day) of the proleptic Gregorian calendar for a count of days since 1970-01-01
/// (H. Hinnant's algorithm).
fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let month = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let year = yoe + era * 400 + i64::from(month <= 2);
    (year, month, day)
}

/// The command line, each argument quoted for a POSIX shell where it needs it.
fn command_line() -> String {
    std::env::args_os()
        .enumerate()
        .map(|(i, a)| {
            if i == 0 {
                return "hyst".to_string();
            }
            let a = a.to_string_lossy();
            let plain = !a.is_empty()
                && a.chars()
                    .all(|c| c.is_ascii_alphanumeric() || "-_./=:,+@%".contains(c));
            if plain {
                a.into_owned()
            } else {
                format!("'{}'", a.replace('\'', r"'\''"))
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
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

impl Fmu {
    /// What the FMU needs for a model with dynamics or a rate term.
    fn timing(&self) -> Option<&Timing> {
        match &self.kind {
            Kind::Model { timing, .. } => timing.as_ref(),
            Kind::Operator { .. } => None,
        }
    }

    /// A short description of what the FMU computes.
    fn what(&self) -> String {
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
        let mut vars = vec![
            Variable {
                name: "x",
                value_reference: VR_X,
                causality: "input",
                variability: "continuous",
                initial: None,
                start: Some(0.0),
                unit: xu,
                description: x,
            },
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
                    ..vars[0].clone()
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
    fn model_description(&self) -> String {
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
            env!("CARGO_PKG_VERSION"),
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

    /// resources/fmu.toml: what the binary reads at fmi2Instantiate.
    fn config(&self) -> String {
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
    fn documentation(&self) -> String {
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
            version = env!("CARGO_PKG_VERSION"),
            what = escape(&self.what()),
            time = escape(&hyst_fmu::timed::summary(self.timing())),
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

    /// The FMU's bytes (a deflated zip archive).
    fn archive(&self, library: &[u8]) -> Result<Vec<u8>> {
        let options = SimpleFileOptions::default()
            .compression_method(CompressionMethod::Deflated)
            .last_modified_time(self.timestamp);
        let file = options.unix_permissions(0o644);
        let dir = options.unix_permissions(0o755);
        let (config_name, model_name) = (
            format!("resources/{CONFIG_FILE}"),
            format!("resources/{MODEL_FILE}"),
        );
        let mut files: Vec<(&str, Vec<u8>, SimpleFileOptions)> = vec![
            (
                "modelDescription.xml",
                self.model_description().into_bytes(),
                file,
            ),
            ("binaries/", Vec::new(), dir),
            ("binaries/linux64/", Vec::new(), dir),
            ("binaries/linux64/hyst.so", library.to_vec(), dir),
            ("resources/", Vec::new(), dir),
            (&config_name, self.config().into_bytes(), file),
        ];
        if let Kind::Model { bytes, .. } = &self.kind {
            files.push((&model_name, bytes.clone(), file));
        }
        files.push(("documentation/", Vec::new(), dir));
        files.push((
            "documentation/index.html",
            self.documentation().into_bytes(),
            file,
        ));
        let mut zip = ZipWriter::new(Cursor::new(Vec::new()));
        for (name, bytes, options) in files {
            if name.ends_with('/') {
                zip.add_directory(name, options)
            } else {
                zip.start_file(name, options)
            }
            .with_context(|| format!("cannot add {name} to the FMU"))?;
            zip.write_all(&bytes)
                .with_context(|| format!("cannot add {name} to the FMU"))?;
        }
        let cursor = zip
            .finish()
            .context("cannot finish the FMU's zip archive")?;
        Ok(cursor.into_inner())
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

    use super::*;

    #[test]
    fn civil_dates() {
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(11_016), (2000, 2, 29));
        assert_eq!(civil_from_days(11_017), (2000, 3, 1));
        assert_eq!(civil_from_days(19_723), (2024, 1, 1));
        assert_eq!(civil_from_days(-1), (1969, 12, 31));
    }

    #[test]
    fn guids_are_fresh_and_well_formed() {
        let a = guid().unwrap();
        let b = guid().unwrap();
        assert_ne!(a, b);
        assert_eq!(a.len(), 38);
        let inner = a.strip_prefix('{').unwrap().strip_suffix('}').unwrap();
        let groups: Vec<usize> = inner.split('-').map(str::len).collect();
        assert_eq!(groups, [8, 4, 4, 4, 12]);
        assert!(inner
            .chars()
            .all(|c| c == '-' || c.is_ascii_digit() || ('a'..='f').contains(&c)));
    }

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
