//! `hyst export c`: a model file as one header-only C99 file over `hyst.h`, with no allocation
//! and no file system. The header defines `NAME_state` and, in `double` and as `_f32` twins on
//! `float`, `NAME_init` (the direct model), `NAME_init_inverse` (its exact inverse, clamping
//! desired outputs into a saturating model's limits), `NAME_step`, `NAME_reset`, `NAME_params`
//! (the model's `hyst_shaped_model_params`) and the model's Lemma 5.1 compensator
//! (`NAME_compensator`, `_init`, `_step`, `_reset`). A model whose shapings are affine runs on
//! the `hyst_linear_*` functions, which link no nonlinear shape.

use core::fmt::Write as _;

use crate::error::ModelError;
use crate::file::ModelFile;
use crate::smooth::{Form, SmoothModel};

use super::shared::{
    affine_shapings, check_name, description, has_infinity, k2_parameters, literal,
    shape_parameters, smooth, Source,
};

/// The header for the model `file` under the name `name` (see the module documentation).
///
/// # Errors
/// [`ModelError::Invalid`] for a name that is not a usable C identifier ([`check_name`]) and
/// for a model the firmware cannot run (Prandtl–Ishlinskii; dynamics or a rate term, which
/// need a sample period: [`ModelFile::untimed`]), naming what it lacks.
pub fn c(file: &ModelFile, name: &str, source: &Source) -> Result<String, ModelError> {
    check_name(name)?;
    file.untimed("a firmware export (`hyst export c`), whose step has no sample period")?;
    let m = smooth(file, "the C firmware API (hyst.h)")?;
    let mut out = String::new();
    header_comment(&mut out, file, m, name, source);
    let guard = format!("{}_H", name.to_ascii_uppercase());
    let fill = format!("{}_FILL_PARAMS_", name.to_ascii_uppercase());
    w(&mut out, &format!("#ifndef {guard}\n#define {guard}\n\n"));
    w(&mut out, "#include <stddef.h>\n#include <stdint.h>\n");
    if has_infinity(m) {
        w(
            &mut out,
            "#include <math.h> /* INFINITY: an open end of a polynomial shaping */\n",
        );
    }
    w(
        &mut out,
        "#include \"hyst.h\"\n\n\
         #if !defined(HYST_FORM_STOP) || !defined(HYST_INITIAL_STATE_RISING)\n\
         #error \"this header needs a hyst.h with start rules and forms (HYST_INITIAL_STATE_*, HYST_FORM_*)\"\n\
         #endif\n\n\
         #ifdef __cplusplus\nextern \"C\" {\n#endif\n\n",
    );
    params_macro(&mut out, m, &fill);
    let limits = file.saturation().map(|s| s.limits);
    let api = Api::of(m);
    for (real, suffix) in [("double", ""), ("float", "_f32")] {
        functions(&mut out, name, &fill, real, suffix, limits, api);
        compensator(&mut out, name, real, suffix, api);
    }
    w(
        &mut out,
        &format!("#undef {fill}\n\n#ifdef __cplusplus\n}}\n#endif\n\n#endif /* {guard} */\n"),
    );
    Ok(out)
}

/// Which C API family runs the model: the linear one when both shapings are affine (it links
/// none of the nonlinear shapes), else the shaped one. The results are the same, bit for bit.
#[derive(Clone, Copy)]
struct Api {
    /// `hyst_linear_model` or `hyst_shaped_model`.
    model: &'static str,
    /// `hyst_linear_compensator` or `hyst_shaped_compensator`.
    compensator: &'static str,
}

impl Api {
    fn of(m: &SmoothModel) -> Self {
        if affine_shapings(m) {
            Self {
                model: "hyst_linear_model",
                compensator: "hyst_linear_compensator",
            }
        } else {
            Self {
                model: "hyst_shaped_model",
                compensator: "hyst_shaped_compensator",
            }
        }
    }
}

/// Appends `text` (writing to a `String` cannot fail).
fn w(out: &mut String, text: &str) {
    out.push_str(text);
}

/// The comment that opens the header: what the model is, where it came from, how to use it.
fn header_comment(
    out: &mut String,
    file: &ModelFile,
    m: &SmoothModel,
    name: &str,
    source: &Source,
) {
    let _ = writeln!(
        out,
        "/* {name}.h: a hyst model as firmware code, over hyst.h."
    );
    let _ = writeln!(out, " *");
    for line in description(file, m, source, &format!("hyst export c --name {name}")) {
        // The source line stays whole: a path is not split.
        let lines = if line.starts_with("source:") {
            vec![line]
        } else {
            wrap(&line, 94)
        };
        for wrapped in lines {
            let _ = writeln!(out, " * {wrapped}");
        }
    }
    let inverse = match m.form {
        Form::Operator => {
            format!("  {name}_init_inverse(&s): the exact inverse, the command for a desired y;")
        }
        Form::Stop => format!(
            "  {name}_init_inverse(&s) returns HYST_ERR_INVALID_PARAMETER: no inverse (stop form);"
        ),
    };
    let usage = [
        String::new(),
        "Use (double; the _f32 twins take float):".to_string(),
        format!("  {name}_state s;   plain data: static, stack or retained RAM; memcpy copies it"),
        format!("  {name}_init(&s): the model, x in, y out;"),
        inverse,
        format!("  {name}_step(&s, x, &y) each sample: y, and HYST_OK or a HYST_ERR_* status of"),
        "    hyst.h (hyst_status_message names it; on an error y is the last output and the"
            .to_string(),
        "    memory is kept);".to_string(),
        format!(
            "  {name}_reset(&s): forget the history; the start rule applies again next sample."
        ),
        "Without history the model starts at its first sample by the start rule, exactly as"
            .to_string(),
        "`hyst run --model` starts a record. Link with libhyst.a (docs/c.md).".to_string(),
    ];
    for line in usage {
        let _ = writeln!(out, " *{}{line}", if line.is_empty() { "" } else { " " });
    }
    let _ = writeln!(out, " */\n");
}

/// `text` broken into lines of at most `width` characters at spaces.
fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines = vec![String::new()];
    for word in text.split(' ') {
        let last = lines.last_mut();
        match last {
            Some(line) if line.is_empty() => line.push_str(word),
            Some(line) if line.len() + 1 + word.len() <= width => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_string()),
        }
    }
    lines
}

/// The macro that fills a `hyst_shaped_model_params` (`double` or `float`) with the model's
/// numbers, each written once as its exact `double` literal and converted by a cast.
fn params_macro(out: &mut String, m: &SmoothModel, fill: &str) {
    let num = |x: f64| literal(x, "INFINITY");
    let mut lines = vec![format!("(p)->k1 = (T){};", num(m.k1))];
    let (k2_kind, [value, slope, min, max]) = k2_parameters(&m.k2);
    lines.push(format!("(p)->k2.kind = {k2_kind};"));
    for (field, x) in [
        ("value", value),
        ("slope", slope),
        ("min", min),
        ("max", max),
    ] {
        lines.push(format!("(p)->k2.{field} = (T){};", num(x)));
    }
    for (field, s) in [("input", &m.input_shaping), ("output", &m.output_shaping)] {
        let (kind, p) = shape_parameters(s);
        lines.push(format!("(p)->{field}.kind = {kind};"));
        for (i, x) in p.iter().enumerate() {
            lines.push(format!("(p)->{field}.p[{i}] = (T){};", num(*x)));
        }
        for (part, x) in [
            ("pre_gain", s.pre_gain),
            ("pre_offset", s.pre_offset),
            ("post_gain", s.post_gain),
            ("post_offset", s.post_offset),
        ] {
            lines.push(format!("(p)->{field}.{part} = (T){};", num(x)));
        }
    }
    let rule = match m.initial_state {
        hyst_core::InitialState::Rising => "HYST_INITIAL_STATE_RISING",
        hyst_core::InitialState::Falling => "HYST_INITIAL_STATE_FALLING",
        hyst_core::InitialState::Line => "HYST_INITIAL_STATE_LINE",
    };
    lines.push(format!("(p)->initial_state = {rule};"));
    let form = match m.form {
        Form::Operator => "HYST_FORM_OPERATOR",
        Form::Stop => "HYST_FORM_STOP",
    };
    lines.push(format!("(p)->form = {form};"));
    lines.push(format!("(p)->linear = (T){};", num(m.linear)));
    let _ = writeln!(
        out,
        "/* The model's parameters in a hyst_shaped_model_params (T: double) or _f32 (T: float):\n \
         * every number is the model file's, as a double literal converted by the cast. */"
    );
    let _ = writeln!(out, "#define {fill}(p, T) \\\n    do {{ \\");
    for line in lines {
        let _ = writeln!(out, "        {line} \\");
    }
    let _ = writeln!(out, "    }} while (0)\n");
}

/// The state type and the functions of one precision (`real`: `double` or `float`, `suffix`:
/// the C API's `""` or `"_f32"`).
fn functions(
    out: &mut String,
    name: &str,
    fill: &str,
    real: &str,
    suffix: &str,
    limits: Option<(f64, f64)>,
    api: Api,
) {
    let s = suffix;
    let model = api.model;
    let _ = write!(
        out,
        "/* Everything the model needs ({real}): the shaped model with its memory and start rule, and\n \
         * the inverse's clamp count. Plain data, 8-byte aligned; memcpy makes an independent copy. */\n\
         typedef struct {name}_state{s} {{\n    \
             {model}{s} model;\n    \
             int32_t inverse;  /* 1 after {name}_init_inverse{s} */\n    \
             uint32_t clamped; /* desired outputs clamped into the limits since the init (inverse) */\n\
         }} {name}_state{s};\n\n\
         /* Fills *p with the model's parameters (for hyst_shaped_model_init_*{s} and the other\n \
          * functions that take a hyst_shaped_model_params{s}). */\n\
         static inline void {name}_params{s}(hyst_shaped_model_params{s} *p) {{\n    \
             {fill}(p, {real});\n\
         }}\n\n\
         /* Initialises *s as the model, x in, y out, with no history (the start rule applies at the\n \
          * first sample). HYST_OK, or the status of {model}_init_direct{s} (s untouched). */\n\
         static inline int32_t {name}_init{s}({name}_state{s} *s) {{\n    \
             hyst_shaped_model_params{s} p;\n    \
             int32_t status;\n    \
             if (s == NULL) {{\n        return HYST_ERR_NULL_POINTER;\n    }}\n    \
             {name}_params{s}(&p);\n    \
             status = {model}_init_direct{s}(&s->model, &p);\n    \
             if (status == HYST_OK) {{\n        s->inverse = 0;\n        s->clamped = 0;\n    }}\n    \
             return status;\n\
         }}\n\n\
         /* Initialises *s as the model's exact inverse: a desired y in, the command x out, started\n \
          * where the start rule puts the model that produces the first desired y. */\n\
         static inline int32_t {name}_init_inverse{s}({name}_state{s} *s) {{\n    \
             hyst_shaped_model_params{s} p;\n    \
             int32_t status;\n    \
             if (s == NULL) {{\n        return HYST_ERR_NULL_POINTER;\n    }}\n    \
             {name}_params{s}(&p);\n    \
             status = {model}_init_inverse{s}(&s->model, &p);\n    \
             if (status == HYST_OK) {{\n        s->inverse = 1;\n        s->clamped = 0;\n    }}\n    \
             return status;\n\
         }}\n\n"
    );
    let clamp = match limits {
        Some((lo, hi)) => {
            let (lo, hi) = (literal(lo, "INFINITY"), literal(hi, "INFINITY"));
            format!(
                "    /* The inverse clamps a finite desired y into the limits of the saturating psi_out. */\n    \
                 if (s->inverse && x - x == 0) {{\n        \
                     const {real} lo = ({real}){lo}, hi = ({real}){hi};\n        \
                     if (x < lo) {{\n            x = lo;\n            s->clamped++;\n        }} \
                     else if (x > hi) {{\n            x = hi;\n            s->clamped++;\n        }}\n    \
                 }}\n"
            )
        }
        None => String::new(),
    };
    let _ = write!(
        out,
        "/* One sample: *y = the model's output for x (the command for a desired x, inverse). */\n\
         static inline int32_t {name}_step{s}({name}_state{s} *s, {real} x, {real} *y) {{\n    \
             if (s == NULL) {{\n        return HYST_ERR_NULL_POINTER;\n    }}\n\
         {clamp}    \
             return {model}_step{s}(&s->model, x, y);\n\
         }}\n\n\
         /* Forgets the history: the start rule applies again at the next sample. */\n\
         static inline int32_t {name}_reset{s}({name}_state{s} *s) {{\n    \
             if (s == NULL) {{\n        return HYST_ERR_NULL_POINTER;\n    }}\n    \
             return {model}_reset{s}(&s->model);\n\
         }}\n\n"
    );
}

/// The Lemma 5.1 compensator of the model for a plant b / (a_n sⁿ + … + a_1 s + 1), n ≤ 4,
/// before the hysteresis: `NAME_compensator`, `_init`, `_step`, `_reset` of one precision.
fn compensator(out: &mut String, name: &str, real: &str, suffix: &str, api: Api) {
    let (s, comp) = (suffix, api.compensator);
    let _ = write!(
        out,
        "/* The Lemma 5.1 compensator of this model ({real}) for a plant b / (a_n s^n + ... + a_1 s + 1),\n \
         * n <= HYST_MAX_ORDER, before the hysteresis (docs/c.md). Plain data. */\n\
         typedef struct {name}_compensator{s} {{\n    \
             {comp}{s} compensator;\n\
         }} {name}_compensator{s};\n\n\
         /* Initialises *c for the plant b, a = [a_1 ... a_n] (n values) with its n integrators at v0\n \
          * (NULL: at rest); the model's history is set by them, not by its start rule. */\n\
         static inline int32_t {name}_compensator_init{s}({name}_compensator{s} *c, {real} b,\n    \
             const {real} *a, const {real} *v0, size_t n) {{\n    \
             hyst_shaped_model_params{s} p;\n    \
             if (c == NULL) {{\n        return HYST_ERR_NULL_POINTER;\n    }}\n    \
             {name}_params{s}(&p);\n    \
             p.initial_state = HYST_INITIAL_STATE_LINE;\n    \
             return {comp}_init{s}(&c->compensator, &p, b, a, v0, n);\n\
         }}\n\n\
         /* One control period of dt seconds: the new input u_new of the n integrators in, the\n \
          * plant command *u out. */\n\
         static inline int32_t {name}_compensator_step{s}({name}_compensator{s} *c, {real} u_new,\n    \
             {real} dt, {real} *u) {{\n    \
             if (c == NULL) {{\n        return HYST_ERR_NULL_POINTER;\n    }}\n    \
             return {comp}_step{s}(&c->compensator, u_new, dt, u);\n\
         }}\n\n\
         /* Back to the integrators' initial state, the model's memory forgotten. */\n\
         static inline int32_t {name}_compensator_reset{s}({name}_compensator{s} *c) {{\n    \
             if (c == NULL) {{\n        return HYST_ERR_NULL_POINTER;\n    }}\n    \
             return {comp}_reset{s}(&c->compensator);\n\
         }}\n\n"
    );
}
