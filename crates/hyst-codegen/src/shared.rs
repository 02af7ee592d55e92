//! What every generated file shares: the name check, where the model came from, exact number
//! literals, the shaping and k2 parameters as the C API numbers them, and the comment that
//! describes the model.

use core::fmt::Write as _;

use hyst_core::{AnyK2Law, AnyShaping, ScaledShaping, Shaping as _};

use hyst_model::dynamics::{PlantState, MAX_DYNAMICS};
use hyst_model::error::ModelError;
use hyst_model::file::{ModelFile, ModelKind};
use hyst_model::smooth::{Form, SmoothModel};

/// Where the exported model came from, for the generated file's comments.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Source {
    /// The model file as the user named it (a path, or `<fit>` for a model never saved).
    pub name: String,
    /// FNV-1a 64-bit hash of the file's bytes (of its TOML text when it was never saved).
    pub fnv1a64: u64,
}

impl Source {
    /// The source of a model file read from `name` whose bytes are `bytes`.
    #[must_use]
    pub fn of_file(name: &str, bytes: &[u8]) -> Self {
        Self {
            name: name.to_string(),
            fnv1a64: hyst_model::file::fnv1a64(bytes),
        }
    }
}

/// What an export takes beyond the model file: for a model with dynamics, the sample period
/// of its exported forward model (`hyst export --period SECONDS`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Options {
    /// The sample period (s) at which the exported forward model of a model with dynamics
    /// steps: its plant is discretised for it at export time (Φ, Γ0, Γ1 of
    /// [`hyst_model::dynamics`], written as constants). `None`: no forward model with the plant is
    /// written (the compensator needs no period). Unused for a model without dynamics.
    pub period: Option<f64>,
}

/// The dynamics part of an export: Lemma 5.1's plant a_n v⁽ⁿ⁾ + … + a_1 v̇ + v = b u of a
/// model with dynamics, and, for a sample period, its discretisation.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Timing {
    /// The plant gain b.
    pub b: f64,
    /// [a_1, …, a_n].
    pub a: Vec<f64>,
    /// Whether the model has a compensator (operator form).
    pub compensator: bool,
    /// The plant discretised for `Options::period`, when given.
    pub plant: Option<Plant>,
}

/// A plant discretised for one sample period, as [`hyst_model::dynamics::Discrete`] steps it:
/// x_{k+1} = Φ x_k + Γ0 u_k + Γ1 (u_{k+1} − u_k), v = x[0]; at the first sample the plant is
/// at rest, x = (b u_0, 0, …).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Plant {
    /// The sample period (s).
    pub period: f64,
    /// Φ, n × n.
    pub phi: Vec<Vec<f64>>,
    /// Γ0.
    pub g0: Vec<f64>,
    /// Γ1 (per unit step of the command over one period; 0 under the zero-order hold).
    pub g1: Vec<f64>,
    /// The hold it is discretised with (the model file's).
    pub hold: hyst_model::Hold,
}

impl Plant {
    /// What the update does with the command between samples, for the exported comments.
    pub fn hold_words(&self) -> &'static str {
        match self.hold {
            hyst_model::Hold::Zoh => "G1 = 0: the command held over each step (zero-order hold)",
            hyst_model::Hold::Foh => "the command linear between samples (first-order hold)",
        }
    }
}

impl Timing {
    /// The order n.
    pub fn order(&self) -> usize {
        self.a.len()
    }
}

/// The timed part of the export of `m` for `target` (`hyst export c` or `rust`): `None` for a
/// static model; the plant (and its discretisation for `options.period`) for a model with
/// dynamics. A rate term is refused, and so is a stop-form model with dynamics without a
/// period (it has no compensator, and its forward model needs the period), each with the
/// reason.
pub(crate) fn timing(
    m: &SmoothModel,
    options: &Options,
    target: &str,
) -> Result<Option<Timing>, ModelError> {
    if m.rate.is_some() {
        return Err(ModelError::Invalid(format!(
            "the model has {}: {target} writes no rate term (c times the backward \
             difference of v at the record's sample period, added to the output), and a model \
             with one has no compensator; run it on the host with its sample period \
             (hyst_model_load_timed, or `hyst run` on a record with a time column)",
            m.timed_parts()
        )));
    }
    let Some(d) = m.dynamics else {
        return Ok(None);
    };
    let compensator = m.form == Form::Operator;
    if !compensator && options.period.is_none() {
        return Err(ModelError::Invalid(format!(
            "the model is of the stop form with dynamics of order {}: it has no compensator \
             (no inverse), and its forward model needs the sample period its plant is \
             discretised at: give `{target} --period SECONDS` (the records' mean time step, \
             as `hyst run` takes it from their time stamps)",
            d.order()
        )));
    }
    let plant = match options.period {
        Some(period) => Some(plant(&d, period)?),
        None => None,
    };
    Ok(Some(Timing {
        b: d.b,
        a: d.a().to_vec(),
        compensator,
        plant,
    }))
}

/// Φ, Γ0 and Γ1 of `d` discretised for `period`, read from [`hyst_model::dynamics::Discrete::step`]
/// itself: a step from x = e_j with the command 0 gives column j of Φ, a step with the command
/// held at 1 gives Γ0, a unit step of the command from 0 gives Γ1 (each exactly: the other
/// terms of the step's sums are zeros).
fn plant(d: &hyst_model::Dynamics, period: f64) -> Result<Plant, ModelError> {
    let discrete = d.discretise(period).map_err(|e| {
        ModelError::Invalid(format!(
            "--period {period}: {e} (the sample period in seconds of the exported model's step)"
        ))
    })?;
    let n = d.order();
    let step = |x: [f64; MAX_DYNAMICS], from: f64, to: f64| {
        let mut state = PlantState { x, u: from };
        discrete.step(&mut state, to);
        state.x
    };
    let unit = |j: usize| core::array::from_fn(|i| if i == j { 1.0 } else { 0.0 });
    let columns: Vec<[f64; MAX_DYNAMICS]> = (0..n).map(|j| step(unit(j), 0.0, 0.0)).collect();
    let phi = (0..n)
        .map(|i| {
            columns
                .iter()
                .map(|c| c.get(i).copied().unwrap_or(0.0))
                .collect()
        })
        .collect();
    let g0 = step([0.0; MAX_DYNAMICS], 1.0, 1.0);
    let g1 = step([0.0; MAX_DYNAMICS], 0.0, 1.0);
    Ok(Plant {
        period,
        phi,
        g0: g0.iter().take(n).copied().collect(),
        g1: g1.iter().take(n).copied().collect(),
        hold: d.hold(),
    })
}

/// C and C++ keywords and the names of `<stdint.h>` and `<math.h>` that a generated identifier
/// could collide with, and Rust's keywords: refused as names.
const RESERVED: &[&str] = &[
    // C99 and C11 keywords.
    "auto",
    "break",
    "case",
    "char",
    "const",
    "continue",
    "default",
    "do",
    "double",
    "else",
    "enum",
    "extern",
    "float",
    "for",
    "goto",
    "if",
    "inline",
    "int",
    "long",
    "register",
    "restrict",
    "return",
    "short",
    "signed",
    "sizeof",
    "static",
    "struct",
    "switch",
    "typedef",
    "union",
    "unsigned",
    "void",
    "volatile",
    "while",
    "_Bool",
    "_Complex",
    "_Imaginary",
    "_Alignas",
    "_Alignof",
    "_Atomic",
    "_Generic",
    "_Noreturn",
    "_Static_assert",
    "_Thread_local",
    "bool",
    "true",
    "false", // C++ keywords.
    "alignas",
    "alignof",
    "and",
    "asm",
    "catch",
    "class",
    "constexpr",
    "decltype",
    "delete",
    "explicit",
    "export",
    "friend",
    "mutable",
    "namespace",
    "new",
    "noexcept",
    "not",
    "nullptr",
    "operator",
    "or",
    "private",
    "protected",
    "public",
    "template",
    "this",
    "throw",
    "try",
    "typeid",
    "typename",
    "using",
    "virtual",
    "xor", // Rust keywords.
    "as",
    "crate",
    "dyn",
    "fn",
    "impl",
    "in",
    "let",
    "loop",
    "match",
    "mod",
    "move",
    "mut",
    "pub",
    "ref",
    "self",
    "Self",
    "super",
    "trait",
    "type",
    "unsafe",
    "use",
    "where",
    "async",
    "await",
    "abstract",
    "become",
    "box",
    "final",
    "macro",
    "override",
    "priv",
    "typeof",
    "unsized",
    "yield",
    "gen", // Library names.
    "NULL",
    "INFINITY",
    "NAN",
    "math",
    "core",
];

/// Checks that `name` can prefix every identifier of a generated file: a C (and Rust)
/// identifier of ASCII letters, digits and underscores, not starting with a digit, not a
/// keyword, not reserved by C (a leading underscore), and not in `hyst.h`'s namespace (`hyst_…`,
/// `HYST_…`), whose identifiers the generated ones would clash with.
///
/// # Errors
/// [`ModelError::Invalid`] naming the name and the rule it breaks.
pub fn check_name(name: &str) -> Result<(), ModelError> {
    let bad = |why: &str| Err(ModelError::Invalid(format!("--name {name:?}: {why}")));
    let Some(first) = name.chars().next() else {
        return bad("empty: the name prefixes every identifier of the generated file");
    };
    if let Some(c) = name
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || *c == '_'))
    {
        return bad(&format!(
            "{c:?} is not allowed: a C identifier has ASCII letters, digits and underscores only"
        ));
    }
    if first.is_ascii_digit() {
        return bad("starts with a digit, which a C identifier cannot");
    }
    if first == '_' {
        return bad("starts with an underscore: such identifiers are reserved by C");
    }
    if name.len() > 48 {
        return bad("longer than 48 characters");
    }
    if name.to_ascii_lowercase().starts_with("hyst") {
        return bad(
            "starts with \"hyst\": the identifiers made from it (NAME_init, NAME_state, …) would \
             clash with hyst.h's own (hyst_…, HYST_…)",
        );
    }
    if RESERVED.contains(&name) {
        return bad("a C, C++ or Rust keyword or a standard name");
    }
    Ok(())
}

/// The smooth model of `file`, or a refusal naming what `target` lacks.
pub(crate) fn smooth<'a>(file: &'a ModelFile, target: &str) -> Result<&'a SmoothModel, ModelError> {
    match (file.kind, &file.smooth) {
        (ModelKind::Smooth, Some(m)) => Ok(m),
        (ModelKind::PrandtlIshlinskii, _) => Err(ModelError::Invalid(format!(
            "this is a Prandtl-Ishlinskii model: {target} has no Prandtl-Ishlinskii operator \
             (its firmware part runs the smooth operator, its shaped model and its stop form); \
             fit a smooth model (`hyst fit --model smooth`) to export it"
        ))),
        _ => Err(ModelError::Invalid(
            "kind = \"smooth\" but the file holds no [smooth] model".into(),
        )),
    }
}

/// A number as a literal that reads back to the same `f64` in C and in Rust: the shortest
/// decimal that round-trips (`{:?}`), or `inf` and `-inf` as the caller spells them.
pub(crate) fn literal(x: f64, infinity: &str) -> String {
    if x.is_infinite() {
        if x > 0.0 {
            infinity.to_string()
        } else {
            format!("-{infinity}")
        }
    } else {
        format!("{x:?}")
    }
}

/// Whether both shapings are affine (identity or affine shape): such a model exports on the
/// affine C functions and on `AffineShaping`, which link no nonlinear shape.
pub(crate) fn affine_shapings(m: &SmoothModel) -> bool {
    [&m.input_shaping, &m.output_shaping]
        .iter()
        .all(|s| matches!(s.shape, AnyShaping::Identity | AnyShaping::Affine(_)))
}

/// Whether any parameter of the model is infinite (a polynomial's open end).
pub(crate) fn has_infinity(m: &SmoothModel) -> bool {
    [&m.input_shaping, &m.output_shaping]
        .iter()
        .any(|s| shape_parameters(s).1.iter().any(|p| p.is_infinite()))
}

/// A number of an exported model that float cannot represent: the first found by
/// [`no_float`]. The model then has no float form (C: no `_f32` twins; Rust: `T = f32` is
/// refused with this number).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct NoFloat {
    /// Where the number is: its key in the model file (`smooth.k1`,
    /// `smooth.output_shaping.post_gain`, …), or what it is (`saturation limit`, `dynamics b`).
    pub key: String,
    /// The number (the model file's double).
    pub value: f64,
    /// Whether it is beyond float's range (else: a parameter that must be a positive normal
    /// float, which in float is subnormal or 0).
    pub overflows: bool,
}

impl NoFloat {
    /// Why, in words: "smooth.k1 = 3.5e38 is beyond float's range (±3.4028235e38)".
    pub fn reason(&self) -> String {
        if self.overflows {
            format!(
                "{} = {:e} is beyond float's range (±{:e})",
                self.key,
                self.value,
                f32::MAX
            )
        } else {
            format!(
                "{} = {:e} is below float's smallest normal number ({:e}), and it must be a \
                 positive normal number",
                self.key,
                self.value,
                f32::MIN_POSITIVE
            )
        }
    }
}

/// The first number of the exported model that float cannot represent, if any: a finite
/// double beyond float's range (C's `(float)x` is then undefined behaviour), or a parameter
/// the core needs as a positive normal float (k1, a constant k2, a shaping's gains and
/// scales) that is subnormal or 0 in float. The numbers are every parameter, the saturation
/// limits and, for a model with dynamics, its plant's coefficients.
pub(crate) fn no_float(
    file: &ModelFile,
    m: &SmoothModel,
    timed: Option<&Timing>,
) -> Option<NoFloat> {
    // (key, value, must be a positive normal float)
    let mut numbers: Vec<(String, f64, bool)> = vec![("smooth.k1".into(), m.k1, true)];
    match m.k2 {
        AnyK2Law::Constant { value } => numbers.push(("smooth.k2.value".into(), value, true)),
        AnyK2Law::Affine(a) => numbers.extend([
            ("smooth.k2.at_zero".into(), a.at_zero, false),
            ("smooth.k2.slope".into(), a.slope, false),
            ("smooth.k2.min".into(), a.min, false),
            ("smooth.k2.max".into(), a.max, false),
        ]),
    }
    for (section, psi) in [
        ("smooth.input_shaping", &m.input_shaping),
        ("smooth.output_shaping", &m.output_shaping),
    ] {
        numbers.extend([
            (format!("{section}.pre_gain"), psi.pre_gain, true),
            (format!("{section}.pre_offset"), psi.pre_offset, false),
            (format!("{section}.post_gain"), psi.post_gain, true),
            (format!("{section}.post_offset"), psi.post_offset, false),
        ]);
        let (_, p) = shape_parameters(psi);
        let names: &[(&str, bool)] = match psi.shape {
            AnyShaping::Identity => &[],
            AnyShaping::Affine(_) => &[("affine.gain", true), ("affine.offset", false)],
            AnyShaping::Polynomial(_) => &[
                ("polynomial.coefficients[0]", false),
                ("polynomial.coefficients[1]", false),
                ("polynomial.coefficients[2]", false),
                ("polynomial.coefficients[3]", false),
                ("polynomial.lo", false),
                ("polynomial.hi", false),
            ],
            AnyShaping::Tanh(_) => &[("tanh.gain", true), ("tanh.scale", true)],
            AnyShaping::Langevin(_) => &[("langevin.gain", true), ("langevin.scale", true)],
            AnyShaping::QuadraticExp(_) => &[
                ("quadratic-exp.a", false),
                ("quadratic-exp.b", false),
                ("quadratic-exp.c", false),
                ("quadratic-exp.lo", false),
                ("quadratic-exp.hi", false),
            ],
        };
        for ((name, normal), x) in names.iter().zip(p) {
            numbers.push((format!("{section}.shape.{name}"), x, *normal));
        }
    }
    numbers.push(("smooth.linear".into(), m.linear, false));
    if let Some(s) = file.saturation() {
        numbers.push(("saturation limit".into(), s.limits.0, false));
        numbers.push(("saturation limit".into(), s.limits.1, false));
    }
    if let Some(t) = timed {
        numbers.push(("dynamics b".into(), t.b, false));
        numbers.extend(t.a.iter().map(|a| ("dynamics a".to_string(), *a, false)));
        if let Some(p) = &t.plant {
            let all = p.phi.iter().flatten().chain(&p.g0).chain(&p.g1);
            numbers.extend(all.map(|x| ("discretised plant".to_string(), *x, false)));
        }
    }
    numbers.into_iter().find_map(|(key, value, normal)| {
        #[allow(clippy::cast_possible_truncation)] // the point: what float makes of it
        let single = value as f32;
        let overflows = value.is_finite() && value.abs() > f64::from(f32::MAX);
        (overflows || (normal && !single.is_normal())).then_some(NoFloat {
            key,
            value,
            overflows,
        })
    })
}

/// The C API's shaping kind (`HYST_SHAPING_*`) and the six parameters `p` of a shape.
pub(crate) fn shape_parameters(s: &ScaledShaping<f64>) -> (&'static str, [f64; 6]) {
    match s.shape {
        AnyShaping::Identity => ("HYST_SHAPING_IDENTITY", [0.0; 6]),
        AnyShaping::Affine(a) => (
            "HYST_SHAPING_AFFINE",
            [a.gain, a.offset, 0.0, 0.0, 0.0, 0.0],
        ),
        AnyShaping::Polynomial(p) => {
            let [c0, c1, c2, c3] = p.coefficients;
            ("HYST_SHAPING_POLYNOMIAL", [c0, c1, c2, c3, p.lo, p.hi])
        }
        AnyShaping::Tanh(t) => ("HYST_SHAPING_TANH", [t.gain, t.scale, 0.0, 0.0, 0.0, 0.0]),
        AnyShaping::Langevin(l) => (
            "HYST_SHAPING_LANGEVIN",
            [l.gain, l.scale, 0.0, 0.0, 0.0, 0.0],
        ),
        AnyShaping::QuadraticExp(q) => (
            "HYST_SHAPING_QUADRATIC_EXP",
            [q.a, q.b, q.c, q.lo, q.hi, 0.0],
        ),
    }
}

/// The k2 law as the C API's (kind, value, slope, min, max).
pub(crate) fn k2_parameters(k2: &AnyK2Law<f64>) -> (&'static str, [f64; 4]) {
    match k2 {
        AnyK2Law::Constant { value } => ("HYST_K2_CONSTANT", [*value, 0.0, 0.0, 0.0]),
        AnyK2Law::Affine(a) => ("HYST_K2_AFFINE", [a.at_zero, a.slope, a.min, a.max]),
    }
}

/// User text (a model path, a column name, a unit) as it stands in a comment of a generated
/// file, C or Rust: whatever it holds, the comment neither ends nor nests another one, and no
/// line of it breaks. The rendering is one line, and unambiguous: a backslash reads `\\`; a
/// control character (line feed, carriage return, NUL, tab, DEL, C1 controls), a line or
/// paragraph separator, a byte-order mark and the characters that reorder text on screen
/// (bidirectional controls, which rustc refuses in comments and GCC warns about) read `\u{…}`
/// with their code point in hexadecimal; of `*/` and `/*` (a C comment's end, a nested Rust
/// block comment's start) the second character reads `\/` or `\*`; and of `??` the second
/// `?` reads `\?`, so that no C trigraph forms (`??/` is a backslash, which at the end of a
/// line would join the next). Everything else (letters of any script, `µ`, spaces) is kept.
///
/// The text around it must not end in `*` or `/` where the user text starts, nor start with
/// one where it ends: every caller puts it after a space or a backquote and before a space,
/// a backquote or punctuation.
pub(crate) fn comment_text(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut last = None;
    for c in text.chars() {
        match (last, c) {
            (_, '\\') => out.push_str("\\\\"),
            (Some('*'), '/') => out.push_str("\\/"),
            (Some('/'), '*') => out.push_str("\\*"),
            (Some('?'), '?') => out.push_str("\\?"),
            (_, c) if breaks_comment(c) => {
                let _ = write!(out, "\\u{{{:04x}}}", u32::from(c));
            }
            (_, c) => out.push(c),
        }
        last = Some(c);
    }
    out
}

/// Whether `c` can end a line or a comment, or show a comment's text other than it is: a
/// control character, a line or paragraph separator, a byte-order mark, or a bidirectional
/// formatting character (the marks, embeddings, overrides and isolates of Unicode's
/// bidirectional algorithm).
fn breaks_comment(c: char) -> bool {
    c.is_control()
        || matches!(
            c,
            '\u{061c}'
                | '\u{200e}'
                | '\u{200f}'
                | '\u{2028}'
                | '\u{2029}'
                | '\u{202a}'..='\u{202e}'
                | '\u{2066}'..='\u{2069}'
                | '\u{feff}'
        )
}

/// What the comments of a generated file say about the model: its source, kind, units and
/// which parameters are normalised.
pub(crate) fn description(
    file: &ModelFile,
    m: &SmoothModel,
    source: &Source,
    tool: &str,
    no_float: Option<&NoFloat>,
) -> Vec<String> {
    let form = match m.form {
        Form::Operator => "y = psi_out(H[psi_in(x)]) (operator form)",
        Form::Stop => "y = psi_out(v - H[v]) + c v, v = psi_in(x) (stop form: no inverse)",
    };
    let mut lines = vec![
        format!("Generated by `{tool}`; do not edit (export the model file again instead)."),
        source_line(source),
        format!("model: {form}"),
        format!(
            "shaping: psi_in {}, psi_out {} (each after its affine scaling); k2 law {}; start \
             rule {}",
            m.input_shaping.name(),
            m.output_shaping.name(),
            match m.k2 {
                AnyK2Law::Constant { .. } => "constant",
                AnyK2Law::Affine(_) => "affine",
            },
            initial_state_name(m)
        ),
        columns(file),
    ];
    if let Some(d) = m.dynamics {
        lines.push(format!(
            "dynamics: the command x drives Lemma 5.1's plant {} = b x (b = {:?}, a = [{}], a_i \
             in s^i), whose output v is the input of the formula above; `hyst run --model` runs \
             it on timed records.",
            plant_equation(d.order()),
            d.b,
            d.a()
                .iter()
                .map(|a| format!("{a:?}"))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    lines.push(
        "k1 and k2 are in the operator's units (those of psi_in's value): `hyst fit` scales x \
         and y affinely so that the data span [-1, 1], and psi_in and psi_out hold that \
         scaling. They are not the k1, k2 of the plain operator between x and y."
            .to_string(),
    );
    match no_float {
        Some(n) => lines.push(format!(
            "No float form: {}. Float cannot represent this model, so it runs in double only \
             (C: no _f32 twins are written; Rust: `T = f32` returns Err(InvalidParameter) \
             naming it).",
            n.reason()
        )),
        // f32 resolves the normalised operator input (|v| up to about 1) to its epsilon.
        None => lines.push(format!(
            "In float (the _f32 twins) the operator input is resolved to about 6e-8 of its \
             normalised range [-1, 1]: {} of k1, the share of the loop's width that rounding \
             can move. Use double where that matters.",
            percent(0.5 * f64::from(f32::EPSILON) / m.k1)
        )),
    }
    if let Some(s) = file.saturation() {
        lines.push(format!(
            "The inverse clamps a desired y into [{:?}, {:?}] ({}; the open range of {} is \
             ({:?}, {:?})), as `hyst run --inverse --saturate`.",
            s.limits.0,
            s.limits.1,
            s.rule(),
            s.range_of(),
            s.range.0,
            s.range.1
        ));
    }
    lines
}

/// The comment line that names the model file the export was made from.
pub(crate) fn source_line(source: &Source) -> String {
    format!(
        "source: {} (FNV-1a 64 of its bytes: {:016x})",
        comment_text(&source.name),
        source.fnv1a64
    )
}

/// a_n v^(n) + ... + a_1 v' + v, in ASCII.
fn plant_equation(n: usize) -> String {
    let mut terms: Vec<String> = (1..=n)
        .rev()
        .map(|i| match i {
            1 => "a_1 v'".to_string(),
            2 => "a_2 v''".to_string(),
            _ => format!("a_{i} v^({i})"),
        })
        .collect();
    terms.push("v".to_string());
    terms.join(" + ")
}

/// A fraction as a percentage with two significant figures or so: "0.0073 %", "3.7e-5 %".
fn percent(fraction: f64) -> String {
    let p = 100.0 * fraction;
    if p >= 0.01 {
        format!("{p:.2} %")
    } else {
        format!("{p:.1e} %")
    }
}

/// What x and y are: the model file's columns and units.
pub(crate) fn columns(file: &ModelFile) -> String {
    let unit = |u: &str| {
        if u.is_empty() {
            "(no unit recorded)".to_string()
        } else {
            format!("in {}", comment_text(u))
        }
    };
    format!(
        "x: the input `{}` {}; y: the output `{}` {}.",
        comment_text(&file.columns.input),
        unit(&file.units.input),
        comment_text(&file.columns.output),
        unit(&file.units.output)
    )
}

/// The model file's name of the start rule.
fn initial_state_name(m: &SmoothModel) -> &'static str {
    match m.initial_state {
        hyst_core::InitialState::Rising => "rising",
        hyst_core::InitialState::Falling => "falling",
        hyst_core::InitialState::Line => "line",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_that_are_not_c_identifiers_or_clash_are_refused() {
        for good in ["piezo", "stage_x", "Mirror2", "bh"] {
            assert!(check_name(good).is_ok(), "{good}");
        }
        for bad in [
            "",
            "2axis",
            "_piezo",
            "pie-zo",
            "piëzo",
            "hyst",
            "hyst_model",
            "HYST_X",
            "int",
            "static",
            "fn",
            "class",
            "piezo.h",
        ] {
            assert!(check_name(bad).is_err(), "{bad}");
        }
    }

    /// Φ, Γ0 and Γ1 read from `Discrete::step` give its steps back bit for bit, summed as the
    /// exported code sums them, for every order.
    #[test]
    #[allow(
        clippy::unwrap_used,
        clippy::indexing_slicing,
        clippy::needless_range_loop,
        clippy::assign_op_pattern
    )]
    fn the_exported_plant_steps_as_the_discretisation() {
        for a in [
            &[0.05][..],
            &[0.05, 0.001],
            &[0.02, 1e-4, 1e-7],
            &[0.3, 0.03, 1e-3, 1e-5],
        ] {
            let d = hyst_model::Dynamics::new(1.5, a).unwrap();
            let p = plant(&d, 1.0 / 1024.0).unwrap();
            let discrete = d.discretise(1.0 / 1024.0).unwrap();
            let n = a.len();
            let command = |k: usize| (0.01 * k as f64).sin() + 0.3 * (0.37 * k as f64).cos();
            let mut state = discrete.at_rest(command(0));
            let mut x: Vec<f64> = (0..n).map(|i| state.x[i]).collect();
            let mut last = command(0);
            for k in 1..500 {
                let u = command(k);
                let v = discrete.step(&mut state, u);
                let du = u - last;
                let next: Vec<f64> = (0..n)
                    .map(|i| {
                        let mut acc = p.g0[i] * last + p.g1[i] * du;
                        for j in 0..n {
                            acc = acc + p.phi[i][j] * x[j];
                        }
                        acc
                    })
                    .collect();
                assert_eq!(next[0].to_bits(), v.to_bits(), "order {n}, sample {k}");
                for i in 0..n {
                    assert_eq!(next[i].to_bits(), state.x[i].to_bits(), "order {n}");
                }
                x = next;
                last = u;
            }
        }
    }

    #[test]
    fn literals_read_back_exactly() {
        for x in [
            0.1,
            -1.0 / 3.0,
            1e-300,
            6.02e23,
            5.0,
            -0.0,
            f64::MIN_POSITIVE,
        ] {
            let text = literal(x, "INFINITY");
            assert_eq!(
                text.parse::<f64>().ok().map(f64::to_bits),
                Some(x.to_bits())
            );
        }
        assert_eq!(literal(f64::NEG_INFINITY, "INFINITY"), "-INFINITY");
    }
}
