//! The report of an identification (`hyst fit`, Python's `FitResult.report()`): the summaries,
//! the JSON report and its text form.

use hyst_io::number::{percent_floor, percent_given, sig};
use hyst_model::{
    Choice, ErrorStats, FamilyWidths, Form, InitialState, InputUnits, ModelFile, ModelKind,
};
use serde::{Deserialize, Serialize};

use crate::orientation::Orientation;

/// One model kind's summary, for the side-by-side comparison.
#[derive(Serialize, Deserialize, Debug, Clone)]
pub struct Summary {
    /// "smooth" or "prandtl-ishlinskii".
    pub kind: String,
    /// Free parameters.
    pub parameters: usize,
    /// Training errors.
    pub training: ErrorStats,
    /// Validation errors.
    pub validation: Option<ErrorStats>,
    /// Fit time (s).
    pub fit_seconds: f64,
    /// Evaluation time (ns per sample).
    pub ns_per_sample: f64,
}

/// What the identification found about the data and the fit, beside the model.
#[derive(Serialize, Deserialize, Debug, Clone, PartialEq)]
pub struct Findings {
    /// Which way the data's loops run ([`crate::orientation::loops`]); the smooth model's form
    /// follows it unless the form was given.
    pub orientation: Orientation,
    /// The mean gap between the rising and falling branches of the data, as a fraction of the
    /// output span (positive for clockwise).
    pub loop_gap: f64,
    /// The fit found no hysteresis ([`crate::degeneracy`]) and was kept on request.
    pub degenerate: bool,
    /// Notes for the reader, one sentence each (the degeneracy found, the Dahl limit, …).
    pub notes: Vec<String>,
}

/// The report (`--json` prints it).
#[derive(Serialize, Debug, Clone)]
pub struct Report {
    /// The model file written.
    pub model_file: String,
    /// The model file's content.
    pub model: ModelFile,
    /// Output span of the data (output units).
    pub output_span: f64,
    /// k1 in input units and k2 in 1/input units beside the normalised values of the model
    /// (smooth models; JSON: top-level keys `k1_input`, `k1_input_std_error`, `k2_input`,
    /// `k2_input_std_error`, `input_slope`), from [`hyst_model::input_units`].
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    pub input_units: Option<InputUnits>,
    /// What the identification found beside the fit (JSON: top-level keys `orientation`,
    /// `loop_gap`, `degenerate`, `notes`).
    #[serde(flatten)]
    pub findings: Findings,
    /// Side-by-side comparison (with `--compare`).
    pub comparison: Vec<Summary>,
    /// Plot files written.
    pub plots: Vec<String>,
}

fn unit(u: &str) -> String {
    if u.is_empty() {
        String::new()
    } else {
        format!(" {u}")
    }
}

fn stats_line(label: &str, s: &ErrorStats, u: &str) -> String {
    format!(
        "  {label:<26} {:>12}{u} ({:>6} %)   {:>12}{u} ({:>6} %)\n",
        sig(s.rms, 4),
        sig(s.rms_pct_span, 3),
        sig(s.max_abs, 4),
        sig(s.max_pct_span, 3)
    )
}

/// The report as text, the way `hyst fit` prints it.
#[must_use]
pub fn text_report(r: &Report) -> String {
    let m = &r.model;
    let u = unit(&m.units.output);
    let mut s = String::new();
    s += &data_lines(m, &u);
    s += &model_line(m);
    s += &findings_lines(r);
    s += &errors_table(r, &u);
    s += &parameter_table(m);
    if let Some(k) = &r.input_units {
        s += &input_units_lines(m, k);
    }
    if let Some(w) = &m.family {
        s += &family_lines(m, w, &u);
    }
    if !r.comparison.is_empty() {
        s += &comparison_table(&r.comparison);
    }
    if !r.model_file.is_empty() {
        s += &format!("\nwrote {}\n", r.model_file);
    }
    for p in &r.plots {
        s += &format!("wrote {p}\n");
    }
    s
}

/// The data fitted: the file with its rows, records and samples, then the columns (`u`: the
/// output unit as [`unit`] prints it).
fn data_lines(m: &ModelFile, u: &str) -> String {
    let mut s = String::new();
    let train_samples = m.metrics.training.samples;
    s += &format!(
        "hyst fit: {} ({} rows, {} record{}; {} training samples{})\n",
        m.provenance.file,
        m.provenance.rows,
        m.provenance.records,
        if m.provenance.records == 1 { "" } else { "s" },
        train_samples,
        m.metrics.validation.map_or(String::new(), |v| format!(
            ", {} validation samples",
            v.samples
        )),
    );
    s += &format!(
        "columns: input {:?}{}, output {:?}{}{}\n",
        m.columns.input,
        unit(&m.units.input),
        m.columns.output,
        u,
        m.columns
            .record
            .as_ref()
            .map_or(String::new(), |c| format!(", records by {c:?}"))
    );
    s
}

/// The model line: the smooth model's structure, or the Prandtl–Ishlinskii model's plays and
/// output polynomial.
fn model_line(m: &ModelFile) -> String {
    match (m.kind, &m.structure) {
        (ModelKind::Smooth, Some(st)) => format!(
            "model: smooth {}, k2 {}, input shaping {}, output shaping {}{}{}, start {}\n",
            match st.form {
                Form::Operator => "operator ψ_out(H[ψ_in(in)])",
                Form::Stop => "stop form ψ_out(v − H[v]) + c·v, v = ψ_in(in)",
            },
            st.k2.name(),
            st.input_shaping.name(),
            st.output_shaping.name(),
            if st.output_offset {
                ", output offset"
            } else {
                ""
            },
            if st.input_offset == Some(true) {
                ", input offset"
            } else {
                ""
            },
            match st.initial_state {
                InitialState::Rising => "rising",
                InitialState::Falling => "falling",
                InitialState::Line => "line",
            }
        ),
        _ => {
            let pi = m.prandtl_ishlinskii.as_ref();
            format!(
                "model: Prandtl–Ishlinskii, {} play operators{}\n",
                pi.map_or(0, |p| p.thresholds.len()),
                match pi.and_then(|p| p.output) {
                    Some(o) => format!(
                        ", output polynomial of degree {} (increasing on the PI output range \
                         [{}, {}]; exact inverse PI⁻¹ ∘ P⁻¹)",
                        o.degree,
                        sig(o.lo, 4),
                        sig(o.hi, 4)
                    ),
                    None => String::new(),
                }
            )
        }
    }
}

/// The loops found, the fit's cost, the notes, and the warning on a degenerate fit kept.
fn findings_lines(r: &Report) -> String {
    let m = &r.model;
    let mut s = String::new();
    s += &format!(
        "loops: {} (rising minus falling branch {} % of the output span)\n",
        r.findings.orientation.name(),
        sig(100.0 * r.findings.loop_gap, 3)
    );
    s += &format!(
        "fit: {} s, {} parameters, {} ns per sample to evaluate\n",
        sig(m.metrics.fit_seconds, 3),
        m.metrics.parameters,
        sig(m.metrics.ns_per_sample, 3)
    );
    for note in &r.findings.notes {
        s += &format!("note: {note}\n");
    }
    if r.findings.degenerate {
        s += "WARNING: degenerate fit kept on request (--keep-degenerate): no hysteresis found\n";
    }
    s
}

/// The table of training and validation errors (`u`: the output unit).
fn errors_table(r: &Report, u: &str) -> String {
    let m = &r.model;
    let mut s = String::new();
    s += &format!(
        "\nerrors (output span {}{u})          RMS (% of span)             max (% of span)\n",
        sig(r.output_span, 4)
    );
    s += &stats_line(
        &format!("training ({} samples)", m.metrics.training.samples),
        &m.metrics.training,
        u,
    );
    if let Some(v) = &m.metrics.validation {
        s += &stats_line(&format!("validation ({} samples)", v.samples), v, u);
    }
    s
}

/// The table of parameters with their standard errors (the first 40).
fn parameter_table(m: &ModelFile) -> String {
    let mut s = String::new();
    s += "\nparameter              value           std. error     unit\n";
    // A plant coefficient the records do not identify has no value to print (the notes say
    // why): the model file keeps the fitted number, which has no measurable effect on the data.
    let unidentified = |name: &str| {
        let i: usize = name.strip_prefix("dynamics.a")?.parse().ok()?;
        let d = m.dynamics.as_ref()?;
        (d.identified.get(i.checked_sub(1)?) == Some(&false)).then_some(())
    };
    for e in m.parameters.iter().take(40) {
        let (value, error) = if unidentified(&e.name).is_some() {
            ("not identified".to_string(), "-".to_string())
        } else {
            (sig(e.value, 7), sig(e.std_error, 3))
        };
        s += &format!(
            "  {:<20} {:>14}  {:>14}     {}\n",
            e.name, value, error, e.unit
        );
    }
    if m.parameters.len() > 40 {
        s += &format!("  … {} more in the model file\n", m.parameters.len() - 40);
    }
    if m.kind == ModelKind::Smooth {
        s += "  (k1, k2 in normalised input units: the input range maps to [-1, 1]; standard errors\n   allow for correlated residuals: docs/fitting.md)\n";
    }
    s
}

/// k1 and k2 in the input's units (`k`), beside the normalised values of the table above.
fn input_units_lines(m: &ModelFile, k: &InputUnits) -> String {
    let u = if m.units.input.is_empty() {
        "input units".to_string()
    } else {
        m.units.input.clone()
    };
    format!(
        "  in input units: k1 = {} {u} (std. error {}), k2 = {} 1/{u} (std. error {})\n   \
         (k1 / s and k2 · s, s = {} operator units per {u}: ψ_in's mean slope over the fitted \
         input range)\n",
        sig(k.k1_input, 7),
        sig(k.k1_input_std_error, 3),
        sig(k.k2_input, 7),
        sig(k.k2_input_std_error, 3),
        sig(k.input_slope, 7),
    )
}

/// The family widths `w` that reproduce the data (Definition 2.8) and the bound Δa they give
/// (`u`: the output unit).
fn family_lines(m: &ModelFile, w: &FamilyWidths, u: &str) -> String {
    let mut s = String::new();
    s += &format!(
        "\nfamily RH(k1, Δk1, k2, Δk2) reproducing {} % of the samples (Definition 2.8):\n",
        percent_given(w.coverage_target)
    );
    if w.reachable {
        s += &format!(
            "  Δk1 = {}, Δk2 = {} (coverage {} %)\n",
            sig(w.delta_k1, 4),
            sig(w.delta_k2, 4),
            percent_floor(w.coverage, 2)
        );
        if w.delta_k2_law > 0.0 {
            s += &format!(
                "  k2 over the data in [{}, {}]; Proposition 4.3 adds Δk2* = {}\n",
                sig(w.k2_range.0, 4),
                sig(w.k2_range.1, 4),
                sig(w.delta_k2_law, 4)
            );
        }
    } else {
        s += &format!(
            "  NOT reachable with Δk1 < k1, Δk2 < k2: the widest family covers {} % \
             (Δk1 = {}, Δk2 = {}), so there is no bound Δa for this coverage; the data \
             holds behaviour the model structure lacks (look at the residuals, try a richer \
             structure or a lower --coverage)\n",
            percent_floor(w.coverage, 2),
            sig(w.delta_k1, 4),
            sig(w.delta_k2, 4)
        );
    }
    if let (Some(delta_a), Some(bound), Some(pct)) =
        (w.delta_a, w.output_bound, w.output_bound_pct_span)
    {
        let (what, meaning) = match m.structure.map(|st| st.form) {
            Some(Form::Stop) => (
                "prediction error bound at the output (the feed-forward force)",
                "|ΔH| ≤ Δa moves v − H[v] by as much",
            ),
            _ => (
                "compensation error bound at the output",
                "Proposition 3.2, and Δb ≤ Δa by Proposition 3.3",
            ),
        };
        s += &format!("  Δa = {} (operator units; {meaning})\n", sig(delta_a, 4));
        s += &format!(
            "  {what}: {}{u} ({} % of span)\n",
            sig(bound, 4),
            sig(pct, 3)
        );
    }
    s
}

/// The side-by-side comparison of the model kinds fitted.
fn comparison_table(comparison: &[Summary]) -> String {
    let mut s = String::new();
    s += "\ncomparison on the same data   parameters   train RMS %   valid RMS %   ns/sample   fit s\n";
    for c in comparison {
        s += &format!(
            "  {:<28} {:>10}   {:>11}   {:>11}   {:>9}   {:>5}\n",
            c.kind,
            c.parameters,
            sig(c.training.rms_pct_span, 3),
            c.validation
                .map_or("-".to_string(), |v| sig(v.rms_pct_span, 3)),
            sig(c.ns_per_sample, 3),
            sig(c.fit_seconds, 3)
        );
    }
    s
}
