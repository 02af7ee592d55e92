//! `hyst export rust`: a model file as `no_std` Rust over hyst-core, for embedded Rust (RTIC,
//! Embassy). The file defines, generic over the precision `T` (`f32` or `f64`):
//!
//! - `fn NAME<T: Real>() -> Result<NAME_TYPE<T>, Error>`: the model (x in, y out), run by its
//!   start rule from the first sample;
//! - `fn NAME_inverse<T: Real>()`: its exact inverse (operator form only);
//! - `fn NAME_clamp<T: Real>(y: T) -> T`: a desired output clamped into the saturation limits
//!   of a bounded output (the identity otherwise), as `hyst run --inverse --saturate`;
//! - the types of both, named from `NAME` in CamelCase, for statics and struct fields.
//!
//! A model with dynamics adds `NAME_ORDER` (upper case), `fn NAME_timed_compensator<T>(first)`:
//! Lemma 5.1's compensator of its fitted plant (a `hyst_core::compensator::Compensator`, run by
//! `track` on the desired output's jet, `NAME_reference` builds it), and with a sample period
//! (`Options::period`) `NAME_PERIOD` and `fn NAME_timed<T>()`: the model with its plant.
//!
//! Every path is written in full (`hyst_core::…`), so the file can be `include!`d anywhere and
//! several exported models can share one module.

use core::fmt::Write as _;

use hyst_core::{AnyK2Law, AnyShaping, InitialState, ScaledShaping};

use hyst_model::error::ModelError;
use hyst_model::file::{ModelFile, ModelKind};
use hyst_model::pi::PiModel;
use hyst_model::smooth::{Form, SmoothModel};

use crate::shared::{
    affine_shapings, check_name, description, literal, no_float, smooth, source_line, timing,
    NoFloat, Options, Plant, Source, Timing,
};

/// The generated Rust for the model `file` under the name `name` (see the module
/// documentation), with the default [`Options`] (no sample period).
///
/// # Errors
/// As [`rust_with`].
pub fn rust(file: &ModelFile, name: &str, source: &Source) -> Result<String, ModelError> {
    rust_with(file, name, source, &Options::default())
}

/// The generated Rust for the model `file` under the name `name` (see the module
/// documentation).
///
/// # Errors
/// [`ModelError::Invalid`] for a name that is not a usable identifier ([`check_name`]), for a
/// model with a rate term or of the stop form with dynamics and no period (with the reason),
/// and for a period its plant cannot be discretised at.
pub fn rust_with(
    file: &ModelFile,
    name: &str,
    source: &Source,
    options: &Options,
) -> Result<String, ModelError> {
    check_name(name)?;
    let tool = format!("hyst export rust --name {name}");
    let camel = camel_case(name);
    let mut out = String::new();
    if file.kind == ModelKind::PrandtlIshlinskii {
        if let Some(p) = &file.prandtl_ishlinskii {
            prandtl_ishlinskii(&mut out, file, p, name, &camel, source, &tool)?;
            return Ok(out);
        }
    }
    let m = smooth(file, "hyst-core")?;
    let timed = timing(m, options, "hyst export rust")?;
    let no_float = no_float(file, m, timed.as_ref());
    let _ = writeln!(
        out,
        "// {name}: a hyst model as no_std Rust over hyst-core."
    );
    for line in description(file, m, source, &tool, no_float.as_ref()) {
        let _ = writeln!(out, "// {line}");
    }
    if let Some(t) = &timed {
        let _ = writeln!(
            out,
            "// `{name}` and `{name}_inverse` are the hysteresis after the plant (v in, y out, and \
             its inverse); {}.",
            match (&t.plant, t.compensator) {
                (Some(_), true) => format!(
                    "`{name}_timed_compensator` is the plant's compensator, `{name}_timed` the \
                     model with its plant"
                ),
                (None, _) => format!(
                    "`{name}_timed_compensator` is the plant's compensator (export with --period \
                     SECONDS for the model with its plant)"
                ),
                (Some(_), false) => format!("`{name}_timed` is the model with its plant"),
            }
        );
    }
    let _ = writeln!(
        out,
        "// Without history the model starts at its first sample by the start rule, exactly as\n\
         // `hyst run --model` starts a record; `Operator::reset` makes it start again.\n"
    );
    // Affine shapings as `AffineShaping`: the same arithmetic, and no nonlinear shape's code.
    let psi = if affine_shapings(m) {
        "hyst_core::ScaledShaping<T, hyst_core::AffineShaping<T>>"
    } else {
        "hyst_core::ScaledShaping<T>"
    };
    let core = format!("hyst_core::ShapedModel<T, {psi}, hyst_core::AnyK2Law<T>, {psi}>");
    let (direct_ty, doc) = match m.form {
        Form::Operator => (core.clone(), "y = psi_out(H[psi_in(x)])"),
        Form::Stop => (
            format!("hyst_core::Stop<T, {psi}, hyst_core::AnyK2Law<T>, {psi}>"),
            "y = psi_out(v - H[v]) + c v, v = psi_in(x)",
        ),
    };
    let _ = writeln!(
        out,
        "/// The model `{name}`, {doc}, run by its start rule: what [`{name}`] returns.\n\
         pub type {camel}<T> = hyst_core::Started<{direct_ty}>;\n"
    );
    if m.form == Form::Operator {
        let inverse_ty = core.replacen("ShapedModel", "InverseShapedModel", 1);
        let _ = writeln!(
            out,
            "/// The exact inverse of [`{camel}`] (a desired y in, the command x out): what\n\
             /// [`{name}_inverse`] returns.\n\
             pub type {camel}Inverse<T> = hyst_core::Started<{inverse_ty}>;\n"
        );
    }
    constructor(&mut out, m, name, &camel, no_float.as_ref());
    clamp(&mut out, file, name);
    if let Some(t) = &timed {
        let upper = name.to_ascii_uppercase();
        let _ = writeln!(
            out,
            "\n/// The plant order n of `{name}`'s dynamics: the derivatives of the desired output\n\
             /// that its compensator takes.\n\
             pub const {upper}_ORDER: usize = {};",
            t.order()
        );
        if t.compensator {
            timed_compensator(&mut out, name, &camel, &upper, psi, t);
        }
        if let Some(plant) = &t.plant {
            timed_model(&mut out, name, &camel, &upper, t, plant);
        }
    }
    Ok(out)
}

/// `piezo_stage` → `PiezoStage`.
fn camel_case(name: &str) -> String {
    name.split('_')
        .filter(|part| !part.is_empty())
        .map(|part| {
            let mut chars = part.chars();
            chars.next().map_or_else(String::new, |c| {
                c.to_ascii_uppercase().to_string() + chars.as_str()
            })
        })
        .collect()
}

/// A number as `c(literal)`, `c` being `T::from_f64`.
fn num(x: f64) -> String {
    format!("c({})", literal(x, "f64::INFINITY"))
}

/// The expression that builds a shaping function (its shape a `AffineShaping` when `linear`).
fn shaping(s: &ScaledShaping<f64>, linear: bool) -> String {
    let any = if linear {
        "AffineShaping"
    } else {
        "AnyShaping"
    };
    let shape = match s.shape {
        AnyShaping::Identity => format!("hyst_core::{any}::Identity"),
        AnyShaping::Affine(a) => format!(
            "hyst_core::{any}::Affine(hyst_core::Affine::new({}, {})?)",
            num(a.gain),
            num(a.offset)
        ),
        AnyShaping::Polynomial(p) => format!(
            "hyst_core::AnyShaping::Polynomial(hyst_core::Polynomial::new([{}], {}, {})?)",
            p.coefficients.map(num).join(", "),
            num(p.lo),
            num(p.hi)
        ),
        AnyShaping::Tanh(t) => format!(
            "hyst_core::AnyShaping::Tanh(hyst_core::Tanh::new({}, {})?)",
            num(t.gain),
            num(t.scale)
        ),
        AnyShaping::Langevin(l) => format!(
            "hyst_core::AnyShaping::Langevin(hyst_core::Langevin::new({}, {})?)",
            num(l.gain),
            num(l.scale)
        ),
        AnyShaping::QuadraticExp(q) => format!(
            "hyst_core::AnyShaping::QuadraticExp(hyst_core::QuadraticExp::new({}, {}, {}, {}, {})?)",
            num(q.a),
            num(q.b),
            num(q.c),
            num(q.lo),
            num(q.hi)
        ),
    };
    format!(
        "hyst_core::ScaledShaping::new(\n        {},\n        {},\n        {shape},\n        {},\n        {},\n    )?",
        num(s.pre_gain),
        num(s.pre_offset),
        num(s.post_gain),
        num(s.post_offset)
    )
}

/// The `# Errors` text of the model's constructor and the guard that opens its body: for a
/// model float cannot represent, `T = f32` is refused, naming the number ([`NoFloat`]).
fn f32_guard(no_float: Option<&NoFloat>) -> (String, String) {
    match no_float {
        Some(n) => {
            let (test, expected) = if n.overflows {
                (
                    "is_finite",
                    "within f32's range (a model f32 cannot represent)",
                )
            } else {
                ("is_normal", "a normal f32 (a model f32 cannot represent)")
            };
            let value = literal(n.value, "f64::INFINITY");
            (
                format!(
                    "[`hyst_core::Error::InvalidParameter`] for `T = f32`: {}. For `f64`, never \
                     for this file's parameters.",
                    n.reason()
                ),
                format!(
                    "if !c({value}).{test}() {{\n        \
                         return Err(hyst_core::Error::InvalidParameter {{\n            \
                             name: {key:?},\n            \
                             value: {value},\n            \
                             expected: {expected:?},\n        \
                         }});\n    \
                     }}\n    ",
                    key = n.key,
                ),
            )
        }
        None => (
            "Never for this file's parameters; the core's check of each part is kept.".to_string(),
            String::new(),
        ),
    }
}

/// The constructors of the model and its inverse.
fn constructor(
    out: &mut String,
    m: &SmoothModel,
    name: &str,
    camel: &str,
    no_float: Option<&NoFloat>,
) {
    let k2 = match m.k2 {
        AnyK2Law::Constant { value } => {
            format!("hyst_core::AnyK2Law::Constant {{ value: {} }}", num(value))
        }
        AnyK2Law::Affine(a) => format!(
            "hyst_core::AnyK2Law::Affine(hyst_core::AffineK2::new({}, {}, {}, {})?)",
            num(a.at_zero),
            num(a.slope),
            num(a.min),
            num(a.max)
        ),
    };
    let rule = match m.initial_state {
        InitialState::Rising => "Rising",
        InitialState::Falling => "Falling",
        InitialState::Line => "Line",
    };
    let body = match m.form {
        Form::Operator => "hyst_core::ShapedModel::new(input, operator, output)?".to_string(),
        Form::Stop => format!(
            "hyst_core::Stop::new(input, operator, output, {})?",
            num(m.linear)
        ),
    };
    let (errors, guard) = f32_guard(no_float);
    let _ = writeln!(
        out,
        "/// The model `{name}` (x in, y out) with no history, in the precision `T` (`f32` or\n\
         /// `f64`: each number is the model file's `f64`, rounded once to `T`).\n\
         ///\n\
         /// # Errors\n\
         /// {errors}\n\
         #[allow(non_snake_case, clippy::excessive_precision, clippy::unreadable_literal)]\n\
         pub fn {name}<T: hyst_core::Real>() -> Result<{camel}<T>, hyst_core::Error> {{\n    \
             let c = T::from_f64;\n    \
             {guard}let input = {input};\n    \
             let output = {output};\n    \
             let operator = hyst_core::Hysteresis::with_k2_law({k1}, {k2})?;\n    \
             let model = {body};\n    \
             Ok(hyst_core::Started::new(model, hyst_core::InitialState::{rule}))\n\
         }}\n",
        input = shaping(&m.input_shaping, affine_shapings(m)),
        output = shaping(&m.output_shaping, affine_shapings(m)),
        k1 = num(m.k1),
    );
    if m.form == Form::Operator {
        let _ = writeln!(
            out,
            "/// The exact inverse of [`{name}`] (a desired y in, the command x out) with no history:\n\
             /// at its first sample it starts where the start rule puts the model that produces\n\
             /// that output. Clamp desired outputs with [`{name}_clamp`] first.\n\
             ///\n\
             /// # Errors\n\
             /// As [`{name}`].\n\
             #[allow(non_snake_case)]\n\
             pub fn {name}_inverse<T: hyst_core::Real>() -> Result<{camel}Inverse<T>, hyst_core::Error> {{\n    \
                 let model = {name}::<T>()?;\n    \
                 Ok(hyst_core::Started::new(model.model().inverse(), model.rule()))\n\
             }}\n"
        );
    }
}

/// `NAME_clamp`: the saturation clamp of the inverse's desired outputs.
fn clamp(out: &mut String, file: &ModelFile, name: &str) {
    let body = match file.saturation() {
        Some(s) => format!(
            "    let (lo, hi) = (T::from_f64({}), T::from_f64({}));\n    \
             if y.is_finite() && (y < lo || y > hi) {{\n        y.max(lo).min(hi)\n    }} else {{\n        y\n    }}",
            literal(s.limits.0, "f64::INFINITY"),
            literal(s.limits.1, "f64::INFINITY")
        ),
        None => "    y".to_string(),
    };
    let what = if file.saturation().is_some() {
        "a finite desired output clamped into the saturation limits of the bounded output"
    } else {
        "the desired output itself (this model's output is unbounded)"
    };
    let _ = writeln!(
        out,
        "/// `y` for the inverse of [`{name}`]: {what}, as `hyst run --inverse --saturate`.\n\
         #[allow(non_snake_case, clippy::excessive_precision, clippy::unreadable_literal)]\n\
         pub fn {name}_clamp<T: hyst_core::Real>(y: T) -> T {{\n{body}\n}}"
    );
}

/// A Prandtl–Ishlinskii model: the core's sum of N plays (N the model's play count), with its
/// output polynomial when it has one, and its exact inverse.
fn prandtl_ishlinskii(
    out: &mut String,
    file: &ModelFile,
    p: &PiModel,
    name: &str,
    camel: &str,
    source: &Source,
    tool: &str,
) -> Result<(), ModelError> {
    p.operator()?;
    let n = p.thresholds.len();
    let _ = writeln!(
        out,
        "// {name}: a hyst model as no_std Rust over hyst-core.\n\
         // Generated by `{tool}`; do not edit (export the model file again instead).\n\
         // {}\n\
         // model: Prandtl-Ishlinskii, {n} plays{}; the plays start at rest at the first sample.\n\
         // {}\n",
        source_line(source),
        if p.output.is_some() {
            " and an output polynomial"
        } else {
            ""
        },
        crate::shared::columns(file)
    );
    let list = |v: &[f64]| v.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", ");
    let sum = format!(
        "hyst_core::PrandtlIshlinskii::<T, {n}>::new({}, &[{}], &[{}], {})?",
        num(p.identity_weight),
        list(&p.thresholds),
        list(&p.weights),
        num(p.offset)
    );
    let (ty, inv_ty, build, inverse) = match &p.output {
        None => (
            format!("hyst_core::PrandtlIshlinskii<T, {n}>"),
            format!("hyst_core::PrandtlIshlinskii<T, {n}>"),
            sum,
            format!("{name}::<T>()?.inverse()"),
        ),
        Some(o) => {
            let poly = o.polynomial()?;
            (
                format!("hyst_core::ShapedPrandtlIshlinskii<T, {n}>"),
                format!("hyst_core::InverseShapedPrandtlIshlinskii<T, {n}>"),
                format!(
                    "hyst_core::ShapedPrandtlIshlinskii::new(\n        {sum},\n        \
                     hyst_core::Polynomial::new([{}], {}, {})?,\n    )?",
                    poly.coefficients.map(num).join(", "),
                    num(poly.lo),
                    num(poly.hi)
                ),
                format!("{name}::<T>()?.inverse()"),
            )
        }
    };
    let _ = writeln!(
        out,
        "/// The model `{name}`: what [`{name}`] returns.\n\
         pub type {camel}<T> = {ty};\n\n\
         /// Its exact inverse: what [`{name}_inverse`] returns.\n\
         pub type {camel}Inverse<T> = {inv_ty};\n\n\
         /// The model `{name}` (x in, y out), in the precision `T`.\n\
         ///\n\
         /// # Errors\n\
         /// Never for this file's parameters; the core's checks are kept.\n\
         #[allow(non_snake_case, clippy::excessive_precision, clippy::unreadable_literal)]\n\
         pub fn {name}<T: hyst_core::Real>() -> Result<{camel}<T>, hyst_core::Error> {{\n    \
             let c = T::from_f64;\n    \
             let model = {build};\n    \
             Ok(model)\n\
         }}\n\n\
         /// The exact inverse of [`{name}`] (a desired y in, the command x out).\n\
         ///\n\
         /// # Errors\n\
         /// As [`{name}`].\n\
         #[allow(non_snake_case)]\n\
         pub fn {name}_inverse<T: hyst_core::Real>() -> Result<{camel}Inverse<T>, hyst_core::Error> {{\n    \
             {inverse}\n\
         }}"
    );
    Ok(())
}

/// `NAME_timed_compensator` and `NAME_reference`: Lemma 5.1's compensator of the model's
/// fitted plant, built exactly as `hyst_model::TimedCompensator::new` builds it (the inverse
/// started by the rule for the first desired output, jets of `MAX_ORDER`), so that `track`
/// gives `hyst run --model --inverse`'s commands bit for bit.
fn timed_compensator(
    out: &mut String,
    name: &str,
    camel: &str,
    upper: &str,
    psi: &str,
    t: &Timing,
) {
    let n = t.order();
    let a = t.a.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", ");
    let pad = (0..4)
        .map(|k| {
            if k < n {
                format!("desired[{}]", k + 1)
            } else {
                "T::zero()".to_string()
            }
        })
        .collect::<Vec<_>>()
        .join(", ");
    let _ = writeln!(
        out,
        "\n/// Lemma 5.1's compensator of `{name}`'s fitted plant: what [`{name}_timed_compensator`]\n\
         /// returns. Its jets carry `hyst_core::compensator::MAX_ORDER` derivatives (those beyond\n\
         /// [`{upper}_ORDER`] zero: [`{name}_reference`]), as `hyst run`'s compensator.\n\
         pub type {camel}TimedCompensator<T> = hyst_core::compensator::Compensator<\n    \
             T,\n    \
             {{ hyst_core::compensator::MAX_ORDER }},\n    \
             {psi},\n    \
             hyst_core::AnyK2Law<T>,\n    \
             {psi},\n\
         >;\n\n\
         /// The compensator of `{name}`'s plant for a record whose first desired output is `first`:\n\
         /// its inverse starts where the start rule puts the model that produces `first`, as\n\
         /// `hyst run --model --inverse` starts a record (and `reset` returns there). Each sample,\n\
         /// `track({name}_reference(&desired))` with the desired output and its first\n\
         /// [`{upper}_ORDER`] time derivatives gives the command u = (x + a_1 x' + ... + a_n x^(n)) / b.\n\
         ///\n\
         /// # Errors\n\
         /// A `first` the model cannot produce (beyond a saturating output shaping).\n\
         #[allow(non_snake_case, clippy::excessive_precision, clippy::unreadable_literal)]\n\
         pub fn {name}_timed_compensator<T: hyst_core::Real>(\n    \
             first: T,\n\
         ) -> Result<{camel}TimedCompensator<T>, hyst_core::Error> {{\n    \
             let c = T::from_f64;\n    \
             let model = {name}::<T>()?;\n    \
             let shaped = model.model();\n    \
             let u0 = hyst_core::Shaping::invert(shaped.output_shaping(), first)?;\n    \
             let operator = model.rule().start_from_output(*shaped.operator(), u0)?;\n    \
             if let Some(m) = hyst_core::Operator::memory(&operator) {{\n        \
                 hyst_core::Shaping::invert(shaped.input_shaping(), m.last_input)?;\n    \
             }}\n    \
             let inverse =\n        \
                 hyst_core::ShapedModel::new(*shaped.input_shaping(), operator, *shaped.output_shaping())?\n            \
                     .inverse();\n    \
             hyst_core::compensator::Compensator::with_order(inverse, {b}, &[{a}])\n\
         }}\n\n\
         /// The jet that [`{name}_timed_compensator`]'s `track` takes: `desired` = the desired output\n\
         /// and its first [`{upper}_ORDER`] time derivatives (the k-th in output units per s^k).\n\
         #[allow(non_snake_case)]\n\
         pub fn {name}_reference<T: hyst_core::Real>(\n    \
             desired: &[T; {upper}_ORDER + 1],\n\
         ) -> hyst_core::Jet<T, {{ hyst_core::compensator::MAX_ORDER }}> {{\n    \
             hyst_core::Jet::from_derivatives(desired[0], [{pad}])\n\
         }}",
        b = num(t.b),
    );
}

/// `NAME_timed`: the model with its plant discretised at export time for one sample period,
/// stepped with `hyst_model::dynamics::Discrete::step`'s sums in its order, then the
/// hysteresis: `hyst run --model`'s outputs on a record of that period, bit for bit.
fn timed_model(out: &mut String, name: &str, camel: &str, upper: &str, t: &Timing, plant: &Plant) {
    let n = t.order();
    let list = |v: &[f64]| v.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", ");
    let phi = plant
        .phi
        .iter()
        .map(|row| format!("[{}]", list(row)))
        .collect::<Vec<_>>()
        .join(", ");
    let _ = writeln!(
        out,
        "\n/// The sample period (s) of [`{name}_timed`]'s step: its plant is discretised for it.\n\
         pub const {upper}_PERIOD: f64 = {period};\n\n\
         /// The model `{name}` with its plant (the command x in, y out), one sample every\n\
         /// [`{upper}_PERIOD`] seconds: what [`{name}_timed`] returns.\n\
         #[derive(Clone, Copy, Debug)]\n\
         pub struct {camel}Timed<T> {{\n    \
             model: {camel}<T>,\n    \
             phi: [[T; {n}]; {n}],\n    \
             g0: [T; {n}],\n    \
             g1: [T; {n}],\n    \
             b: T,\n    \
             plant: [T; {n}],\n    \
             last: T,\n    \
             started: bool,\n\
         }}\n\n\
         /// The model `{name}` with its plant, with no history: at its first sample the plant is at\n\
         /// rest (v = b x) and the hysteresis starts by the start rule, as `hyst run --model` starts\n\
         /// a record of period [`{upper}_PERIOD`].\n\
         ///\n\
         /// # Errors\n\
         /// As [`{name}`].\n\
         #[allow(non_snake_case, clippy::excessive_precision, clippy::unreadable_literal)]\n\
         pub fn {name}_timed<T: hyst_core::Real>() -> Result<{camel}Timed<T>, hyst_core::Error> {{\n    \
             let c = T::from_f64;\n    \
             Ok({camel}Timed {{\n        \
                 model: {name}::<T>()?,\n        \
                 phi: [{phi}],\n        \
                 g0: [{g0}],\n        \
                 g1: [{g1}],\n        \
                 b: {b},\n        \
                 plant: [T::zero(); {n}],\n        \
                 last: T::zero(),\n        \
                 started: false,\n    \
             }})\n\
         }}",
        period = literal(plant.period, "f64::INFINITY"),
        g0 = list(&plant.g0),
        g1 = list(&plant.g1),
        b = num(t.b),
    );
    timed_step(out, camel, n, plant.hold_words());
}

/// The `impl` of `NAME_timed`'s type: `try_step` (the plant's sums in
/// `hyst_model::dynamics::Discrete::step`'s order, then the hysteresis) and `reset`.
fn timed_step(out: &mut String, camel: &str, n: usize, hold: &str) {
    let v = (0..n)
        .map(|j| format!("v{j}"))
        .collect::<Vec<_>>()
        .join(", ");
    let rows = (0..n)
        .map(|i| {
            let mut sum = format!("g0[{i}] * u + g1[{i}] * du");
            for j in 0..n {
                let _ = write!(sum, " + phi[{i}][{j}] * v{j}");
            }
            sum
        })
        .collect::<Vec<_>>()
        .join(",\n                ");
    let rest = (1..n).map(|_| ", T::zero()").collect::<String>();
    let _ = writeln!(
        out,
        "\n\
         impl<T: hyst_core::Real> {camel}Timed<T> {{\n    \
             /// One sample: the output for the command `x`; x_k+1 = Phi x_k + G0 u_k +\n    \
             /// G1 (u_k+1 - u_k), {hold}.\n    \
             ///\n    \
             /// # Errors\n    \
             /// The hysteresis's error for this sample, or a non-finite output; the model is\n    \
             /// then unchanged.\n    \
             pub fn try_step(&mut self, x: T) -> Result<T, hyst_core::Error> {{\n        \
                 let next = if self.started {{\n            \
                     let (u, du) = (self.last, x - self.last);\n            \
                     let [{v}] = self.plant;\n            \
                     let (phi, g0, g1) = (&self.phi, &self.g0, &self.g1);\n            \
                     [\n                \
                         {rows},\n            \
                     ]\n        \
                 }} else {{\n            \
                     [self.b * x{rest}]\n        \
                 }};\n        \
                 let mut model = self.model;\n        \
                 let y = hyst_core::Operator::try_step(&mut model, next[0])?;\n        \
                 if !y.is_finite() {{\n            \
                     return Err(hyst_core::Error::NonFiniteOutput {{\n                \
                         input: x.as_f64(),\n                \
                         output: y.as_f64(),\n            \
                     }});\n        \
                 }}\n        \
                 self.model = model;\n        \
                 self.plant = next;\n        \
                 self.last = x;\n        \
                 self.started = true;\n        \
                 Ok(y)\n    \
             }}\n\n    \
             /// Forgets the history: the plant starts at rest at the next sample.\n    \
             pub fn reset(&mut self) {{\n        \
                 hyst_core::Operator::reset(&mut self.model);\n        \
                 self.started = false;\n    \
             }}\n\
         }}"
    );
}
