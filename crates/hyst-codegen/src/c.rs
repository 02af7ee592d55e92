//! `hyst export c`: a model file as one header-only C99 file over `hyst.h`, with no allocation
//! and no file system. The header defines `NAME_state` and, in `double` and as `_f32` twins on
//! `float`, `NAME_init` (the direct model), `NAME_init_inverse` (its exact inverse, clamping
//! desired outputs into a saturating model's limits), `NAME_step`, `NAME_reset`, `NAME_params`
//! (the model's `hyst_shaped_model_params`) and the model's Lemma 5.1 compensator
//! (`NAME_compensator`, `_init`, `_step`, `_reset`). A model whose shapings are affine runs on
//! the `hyst_affine_*` functions, which link no nonlinear shape. A model float cannot represent
//! (a number beyond float's range, whose `(float)` cast is undefined behaviour, or a gain that
//! turns subnormal) gets no `_f32` twins, and its header says which number stands in the way.
//!
//! A model with dynamics adds `NAME_ORDER` and the compensator of its own plant in track mode
//! (`NAME_timed_compensator`, `_init`, `_step`, `_reset`: the desired output and its first n
//! derivatives in, the command out), over `hyst_shaped_model_step_derivatives` of its inverse
//! run by the start rule; with a sample period (`Options::period`), also `NAME_PERIOD` and its
//! forward model with the plant (`NAME_timed_state`, `NAME_timed_init`, `_step`, `_reset`).
//! `NAME_init`/`NAME_step` then run its hysteresis alone, from the plant's output.

use core::fmt::Write as _;

use hyst_model::error::ModelError;
use hyst_model::file::ModelFile;
use hyst_model::smooth::{Form, SmoothModel};

use crate::shared::{
    affine_shapings, check_name, comment_text, description, has_infinity, k2_parameters, literal,
    no_float, shape_parameters, smooth, timing, NoFloat, Options, Plant, Source, Timing,
};

/// The header for the model `file` under the name `name` (see the module documentation), with
/// the default [`Options`] (no sample period).
///
/// # Errors
/// As [`c_with`].
pub fn c(file: &ModelFile, name: &str, source: &Source) -> Result<String, ModelError> {
    c_with(file, name, source, &Options::default())
}

/// The header for the model `file` under the name `name` (see the module documentation).
///
/// # Errors
/// [`ModelError::Invalid`] for a name that is not a usable C identifier ([`check_name`]) and
/// for a model the firmware cannot run (Prandtl–Ishlinskii; a rate term; the stop form with
/// dynamics and no period), naming what it lacks, and for a period its plant cannot be
/// discretised at.
pub fn c_with(
    file: &ModelFile,
    name: &str,
    source: &Source,
    options: &Options,
) -> Result<String, ModelError> {
    check_name(name)?;
    let m = smooth(file, "the C firmware API (hyst.h)")?;
    let timed = timing(m, options, "hyst export c")?;
    let no_float = no_float(file, m, timed.as_ref());
    let mut out = String::new();
    header_comment(
        &mut out,
        file,
        m,
        name,
        source,
        timed.as_ref(),
        no_float.as_ref(),
    );
    let upper = name.to_ascii_uppercase();
    let guard = format!("{upper}_H");
    let fill = format!("{upper}_FILL_PARAMS_");
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
    params_macro(&mut out, m, &fill, no_float.is_none());
    if let Some(t) = &timed {
        timed_macros(&mut out, name, &upper, t);
    }
    let limits = file.saturation().map(|s| s.limits);
    let api = Api::of(m);
    // A model float cannot represent has no float twins: `(float)x` of a double beyond float's
    // range is undefined behaviour in C, and a parameter that turns subnormal would be refused.
    let precisions: &[(&str, &str)] = match no_float {
        Some(_) => &[("double", "")],
        None => &[("double", ""), ("float", "_f32")],
    };
    for &(real, suffix) in precisions {
        functions(&mut out, name, &fill, real, suffix, limits, api);
        compensator(&mut out, name, real, suffix, api);
        if let Some(t) = &timed {
            let p = Precision { real, suffix };
            if t.compensator {
                timed_compensator(&mut out, name, &upper, p, t);
            }
            if let Some(plant) = &t.plant {
                timed_model(&mut out, name, &upper, p, t, plant);
            }
        }
    }
    w(
        &mut out,
        &format!("#undef {fill}\n\n#ifdef __cplusplus\n}}\n#endif\n\n#endif /* {guard} */\n"),
    );
    Ok(out)
}

/// One precision of the generated functions: the C type and the C API's suffix.
#[derive(Clone, Copy)]
struct Precision {
    /// `double` or `float`.
    real: &'static str,
    /// `""` or `"_f32"`.
    suffix: &'static str,
}

/// Which C API family runs the model: the linear one when both shapings are affine (it links
/// none of the nonlinear shapes), else the shaped one. The results are the same, bit for bit.
#[derive(Clone, Copy)]
struct Api {
    /// `hyst_affine_model` or `hyst_shaped_model`.
    model: &'static str,
    /// `hyst_affine_compensator` or `hyst_shaped_compensator`.
    compensator: &'static str,
}

impl Api {
    fn of(m: &SmoothModel) -> Self {
        if affine_shapings(m) {
            Self {
                model: "hyst_affine_model",
                compensator: "hyst_affine_compensator",
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
    timed: Option<&Timing>,
    no_float: Option<&NoFloat>,
) {
    let _ = writeln!(
        out,
        "/* {name}.h: a hyst model as firmware code, over hyst.h."
    );
    let _ = writeln!(out, " *");
    let tool = format!("hyst export c --name {name}");
    for line in description(file, m, source, &tool, no_float) {
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
    let (x, what) = match timed {
        Some(_) => (
            "v",
            "the hysteresis after the plant, v (the plant's output) in, y out",
        ),
        None => ("x", "the model, x in, y out"),
    };
    let inverse = match (m.form, timed) {
        (Form::Operator, None) => {
            format!("  {name}_init_inverse(&s): the exact inverse, the command for a desired y;")
        }
        (Form::Operator, Some(_)) => format!(
            "  {name}_init_inverse(&s): its exact inverse, the v the plant must deliver for a \
             desired y;"
        ),
        (Form::Stop, _) => format!(
            "  {name}_init_inverse(&s) returns HYST_ERR_INVALID_PARAMETER: no inverse (stop form);"
        ),
    };
    let mut usage = vec![
        String::new(),
        match no_float {
            Some(_) => "Use (double only: no _f32 twins, see above):".to_string(),
            None => "Use (double; the _f32 twins take float):".to_string(),
        },
        format!("  {name}_state s;   plain data: static, stack or retained RAM; memcpy copies it"),
        format!("  {name}_init(&s): {what};"),
        inverse,
        format!("  {name}_step(&s, {x}, &y) each sample: y, and HYST_OK or a HYST_ERR_* status of"),
        "    hyst.h (hyst_status_message names it; on an error y is the last output and the"
            .to_string(),
        "    memory is kept);".to_string(),
        format!(
            "  {name}_reset(&s): forget the history; the start rule applies again next sample."
        ),
    ];
    if let Some(t) = timed {
        usage.extend(timed_usage(name, &comment_text(&file.columns.output), t));
    }
    usage.extend([
        "Without history the model starts at its first sample by the start rule, exactly as"
            .to_string(),
        "`hyst run --model` starts a record. Link with libhyst.a (docs/c.md).".to_string(),
    ]);
    for line in usage {
        let _ = writeln!(out, " *{}{line}", if line.is_empty() { "" } else { " " });
    }
    let _ = writeln!(out, " */\n");
}

/// The header comment's lines on the parts of a model with dynamics (`output`: the model's
/// output column, as [`comment_text`] renders it).
fn timed_usage(name: &str, output: &str, t: &Timing) -> Vec<String> {
    let upper = name.to_ascii_uppercase();
    let n = t.order();
    let mut paragraphs = Vec::new();
    if t.compensator {
        paragraphs.push(format!(
            "{name}_timed_compensator c; {name}_timed_compensator_init(&c): its Lemma 5.1 \
             compensator, started by the start rule at its first sample; \
             {name}_timed_compensator_step(&c, desired, &u) each sample: desired = [y_d, y_d', \
             ..., y_d^({n})] ({upper}_ORDER + 1 values, the k-th derivative in y units per s^k) \
             in, the command u = (x + a_1 x' + ... + a_n x^(n)) / b of x = \
             psi_in^-1(H^-1[psi_out^-1(y_d)]) out, as `hyst run --model --inverse` computes it \
             from the columns {output}_d1 ... {output}_d{n}; {name}_timed_compensator_reset(&c): \
             start again."
        ));
    }
    paragraphs.push(match &t.plant {
        Some(p) => format!(
            "{name}_timed_state s; {name}_timed_init(&s), {name}_timed_step(&s, x, &y), \
             {name}_timed_reset(&s): the model with its plant, x (the command) in, y out, one \
             sample every {upper}_PERIOD = {:?} s (its plant discretised for that period by \
             `hyst export c --period`), as `hyst run --model` runs a record of that period; \
             the plant starts at rest at the first sample.",
            p.period
        ),
        None => "The model with its plant (x in, y out) needs a sample period: export with \
                 `--period SECONDS` for it."
            .to_string(),
    });
    let mut lines = Vec::new();
    for paragraph in paragraphs {
        lines.extend(wrap(&paragraph, 92).into_iter().enumerate().map(|(i, l)| {
            if i == 0 {
                format!("  {l}")
            } else {
                format!("    {l}")
            }
        }));
    }
    lines
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
fn params_macro(out: &mut String, m: &SmoothModel, fill: &str, float: bool) {
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
    let twin = if float { " or _f32 (T: float)" } else { "" };
    let _ = writeln!(
        out,
        "/* The model's parameters in a hyst_shaped_model_params (T: double){twin}:\n \
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
                "    /* The inverse clamps a finite desired y into the saturation limits of the bounded output. */\n    \
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

/// `NAME_ORDER` (and `NAME_PERIOD` with a sample period): the macros of a model with dynamics.
fn timed_macros(out: &mut String, name: &str, upper: &str, t: &Timing) {
    let what = if t.compensator {
        format!(
            ": {name}_timed_compensator_step takes the desired\n * output and its first n time \
             derivatives"
        )
    } else {
        String::new()
    };
    let _ = writeln!(
        out,
        "/* The plant order n of the model's dynamics{what}. */\n#define {upper}_ORDER {}\n",
        t.order()
    );
    if let Some(p) = &t.plant {
        let _ = writeln!(
            out,
            "/* The sample period (s) {name}_timed_step runs at: its plant is discretised for it. */\n\
             #define {upper}_PERIOD {}\n",
            literal(p.period, "INFINITY")
        );
    }
}

/// `(T)literal` of a coefficient in the precision `real`.
fn cast(real: &str, x: f64) -> String {
    format!("({real}){}", literal(x, "INFINITY"))
}

/// The compensator of the model's own plant in track mode, over the shaped inverse run by the
/// start rule and its jets: `NAME_timed_compensator`, `_init`, `_step`, `_reset` of one
/// precision. The jets are of order `HYST_MAX_ORDER` with the derivatives beyond n zero, and
/// eq. (19) is summed in the core compensator's order, so the commands are those of
/// `hyst_model::TimedCompensator` (what `hyst run --model --inverse` runs), bit for bit.
fn timed_compensator(out: &mut String, name: &str, upper: &str, p: Precision, t: &Timing) {
    let Precision { real, suffix: s } = p;
    let n = t.order();
    let mut jet = String::new();
    for k in 0..=4 {
        if k <= n {
            let _ = writeln!(jet, "    jet[{k}] = desired[{k}];");
        } else {
            let _ = writeln!(jet, "    jet[{k}] = ({real})0;");
        }
    }
    let mut law = String::from("    command = x[0];\n");
    for (i, a) in t.a.iter().enumerate() {
        let _ = writeln!(
            law,
            "    command = command + {} * x[{}];",
            cast(real, *a),
            i + 1
        );
    }
    let _ = writeln!(law, "    command = command / {};", cast(real, t.b));
    let _ = write!(
        out,
        "/* Lemma 5.1's compensator of the model's own plant ({real}), in track mode: the exact inverse of\n \
         * the hysteresis, run by the model's start rule, and the command of eq. (19). Plain data. */\n\
         typedef struct {name}_timed_compensator{s} {{\n    \
             hyst_shaped_model{s} inverse; /* psi_in^-1(H^-1[psi_out^-1(.)]) with its memory */\n    \
             {real} command; /* the last command (0 before the first) */\n\
         }} {name}_timed_compensator{s};\n\n\
         /* Initialises *c with no history: the start rule applies at its first sample, as\n \
          * `hyst run --model --inverse` starts a record. HYST_OK, or the init's status. */\n\
         static inline int32_t {name}_timed_compensator_init{s}({name}_timed_compensator{s} *c) {{\n    \
             hyst_shaped_model_params{s} p;\n    \
             int32_t status;\n    \
             if (c == NULL) {{\n        return HYST_ERR_NULL_POINTER;\n    }}\n    \
             {name}_params{s}(&p);\n    \
             status = hyst_shaped_model_init_inverse{s}(&c->inverse, &p);\n    \
             if (status == HYST_OK) {{\n        c->command = 0;\n    }}\n    \
             return status;\n\
         }}\n\n\
         /* One sample: desired[k] = the k-th time derivative of the desired output, k = 0 ... {upper}_ORDER;\n \
          * *u = the command. On an error (a desired output beyond a saturating psi_out, a non-finite\n \
          * value, a command beyond the float range: HYST_ERR_OVERFLOW) *u is the last command and\n \
          * the memory is kept. */\n\
         static inline int32_t {name}_timed_compensator_step{s}({name}_timed_compensator{s} *c,\n    \
             const {real} *desired, {real} *u) {{\n    \
             {real} jet[HYST_MAX_ORDER + 1];\n    \
             {real} x[HYST_MAX_ORDER + 1];\n    \
             {real} command;\n    \
             hyst_memory{s} before;\n    \
             int32_t status;\n    \
             if (c == NULL || desired == NULL || u == NULL) {{\n        return HYST_ERR_NULL_POINTER;\n    }}\n    \
             /* Jets of order HYST_MAX_ORDER, as hyst run's compensator: the same numbers, bit for bit. */\n\
         {jet}    \
             status = hyst_shaped_model_get_memory{s}(&c->inverse, &before);\n    \
             if (status == HYST_OK) {{\n        \
                 status = hyst_shaped_model_step_derivatives{s}(&c->inverse, jet, x, HYST_MAX_ORDER);\n    \
             }}\n    \
             if (status != HYST_OK) {{\n        *u = c->command;\n        return status;\n    }}\n    \
             /* eq. (19): u = (x + a_1 x' + ... + a_n x^(n)) / b, summed in this order. */\n\
         {law}    \
             if (command - command != 0) {{\n        \
                 (void)hyst_shaped_model_set_memory{s}(&c->inverse, &before);\n        \
                 *u = c->command;\n        \
                 return HYST_ERR_OVERFLOW;\n    \
             }}\n    \
             c->command = command;\n    \
             *u = command;\n    \
             return HYST_OK;\n\
         }}\n\n\
         /* Forgets the history: the start rule applies again at the next sample. */\n\
         static inline int32_t {name}_timed_compensator_reset{s}({name}_timed_compensator{s} *c) {{\n    \
             if (c == NULL) {{\n        return HYST_ERR_NULL_POINTER;\n    }}\n    \
             c->command = 0;\n    \
             return hyst_shaped_model_reset{s}(&c->inverse);\n\
         }}\n\n"
    );
}

/// The model with its plant, discretised at export time for one sample period:
/// `NAME_timed_state`, `_init`, `_step`, `_reset` of one precision. The plant's update is
/// `hyst_model::dynamics::Discrete::step`'s sums in its order, and the hysteresis after it is
/// `NAME_step`, so the outputs are those of `hyst run --model` on a record of that period.
fn timed_model(out: &mut String, name: &str, upper: &str, p: Precision, t: &Timing, plant: &Plant) {
    let Precision { real, suffix: s } = p;
    let n = t.order();
    let mut update = String::new();
    for i in 0..n {
        let _ = writeln!(
            update,
            "        next[{i}] = {} * s->last + {} * du;",
            cast(real, plant.g0.get(i).copied().unwrap_or(0.0)),
            cast(real, plant.g1.get(i).copied().unwrap_or(0.0))
        );
        for j in 0..n {
            let phi = plant
                .phi
                .get(i)
                .and_then(|row| row.get(j))
                .copied()
                .unwrap_or(0.0);
            let _ = writeln!(
                update,
                "        next[{i}] = next[{i}] + {} * s->plant[{j}];",
                cast(real, phi)
            );
        }
    }
    let mut rest = String::new();
    let mut commit = String::new();
    let mut clear = String::new();
    for i in 0..n {
        if i > 0 {
            let _ = writeln!(rest, "        next[{i}] = ({real})0;");
        }
        let _ = writeln!(commit, "        s->plant[{i}] = next[{i}];");
        let _ = writeln!(clear, "        s->plant[{i}] = ({real})0;");
    }
    let _ = write!(
        out,
        "/* The model with its plant ({real}): the command x in, y out, one sample every {upper}_PERIOD\n \
         * seconds. Plain data. */\n\
         typedef struct {name}_timed_state{s} {{\n    \
             {name}_state{s} model; /* the hysteresis after the plant ({name}_init{s}) */\n    \
             {real} plant[{upper}_ORDER]; /* v, v', ... at the last sample */\n    \
             {real} last; /* the last command */\n    \
             int32_t started; /* 0: no sample yet; the plant starts at rest at the next */\n\
         }} {name}_timed_state{s};\n\n\
         /* Initialises *s with no history: at its first sample the plant is at rest (v = b x) and\n \
          * the hysteresis starts by the start rule, as `hyst run --model` starts a record. */\n\
         static inline int32_t {name}_timed_init{s}({name}_timed_state{s} *s) {{\n    \
             int32_t status;\n    \
             if (s == NULL) {{\n        return HYST_ERR_NULL_POINTER;\n    }}\n    \
             status = {name}_init{s}(&s->model);\n    \
             if (status == HYST_OK) {{\n\
         {clear}        \
                 s->last = 0;\n        \
                 s->started = 0;\n    \
             }}\n    \
             return status;\n\
         }}\n\n\
         /* One sample: *y = the model's output for the command x. On an error y is the last output\n \
          * and the state is kept. */\n\
         static inline int32_t {name}_timed_step{s}({name}_timed_state{s} *s, {real} x, {real} *y) {{\n    \
             {real} next[{upper}_ORDER];\n    \
             int32_t status;\n    \
             if (s == NULL || y == NULL) {{\n        return HYST_ERR_NULL_POINTER;\n    }}\n    \
             if (s->started) {{\n        \
                 /* x_k+1 = Phi x_k + G0 u_k + G1 (u_k+1 - u_k), {hold}. */\n        \
                 const {real} du = x - s->last;\n\
         {update}    \
             }} else {{\n        \
                 next[0] = {} * x;\n\
         {rest}    \
             }}\n    \
             status = {name}_step{s}(&s->model, next[0], y);\n    \
             if (status == HYST_OK) {{\n\
         {commit}        \
                 s->last = x;\n        \
                 s->started = 1;\n    \
             }}\n    \
             return status;\n\
         }}\n\n\
         /* Forgets the history: the plant starts at rest at the next sample. */\n\
         static inline int32_t {name}_timed_reset{s}({name}_timed_state{s} *s) {{\n    \
             if (s == NULL) {{\n        return HYST_ERR_NULL_POINTER;\n    }}\n    \
             s->started = 0;\n    \
             return {name}_reset{s}(&s->model);\n\
         }}\n\n",
        cast(real, t.b),
        hold = plant.hold_words(),
    );
}
