//! The report of an identification (`hyst fit`, Python's `FitResult.report()`): the summaries,
//! the JSON report and its text form.

use crate::modelfile::ModelKind;
use crate::smooth::ErrorStats;
use crate::{InitialState, K2Kind, ModelFile};
use serde::{Deserialize, Serialize};

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

/// The report (`--json` prints it).
#[derive(Serialize, Debug, Clone)]
pub struct Report {
    /// The model file written.
    pub model_file: String,
    /// The model file's content.
    pub model: ModelFile,
    /// Output span of the data (output units).
    pub output_span: f64,
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
        "  {label:<26} {:>12.5}{u} ({:>6.3} %)   {:>12.5}{u} ({:>6.3} %)\n",
        s.rms, s.rms_pct_span, s.max_abs, s.max_pct_span
    )
}

/// The report as text, the way `hyst fit` prints it.
#[must_use]
pub fn text_report(r: &Report) -> String {
    let m = &r.model;
    let u = unit(&m.units.output);
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
    match (m.kind, &m.structure) {
        (ModelKind::Smooth, Some(st)) => {
            s += &format!(
                "model: smooth operator, k2 {}, input shaping {}, output shaping {}{}{}, start {}\n",
                match st.k2 {
                    K2Kind::Constant => "constant",
                    K2Kind::Affine => "affine",
                },
                st.input_shaping.name(),
                st.output_shaping.name(),
                if st.output_offset { ", output offset" } else { "" },
                if st.input_offset == Some(true) { ", input offset" } else { "" },
                match st.initial_state {
                    InitialState::Rising => "rising",
                    InitialState::Falling => "falling",
                    InitialState::Line => "line",
                }
            );
        }
        _ => {
            let pi = m.prandtl_ishlinskii.as_ref();
            s += &format!(
                "model: Prandtl–Ishlinskii, {} play operators{}\n",
                pi.map_or(0, |p| p.thresholds.len()),
                match pi.and_then(|p| p.output) {
                    Some(o) => format!(
                        ", output polynomial of degree {} (increasing on the PI output range \
                         [{:.4}, {:.4}]; exact inverse PI⁻¹ ∘ P⁻¹)",
                        o.degree, o.lo, o.hi
                    ),
                    None => String::new(),
                }
            );
        }
    }
    s += &format!(
        "fit: {:.3} s, {} parameters, {:.0} ns per sample to evaluate\n\n",
        m.metrics.fit_seconds, m.metrics.parameters, m.metrics.ns_per_sample
    );
    s += &format!(
        "errors (output span {:.5}{u})          RMS (% of span)             max (% of span)\n",
        r.output_span
    );
    s += &stats_line(
        &format!("training ({} samples)", m.metrics.training.samples),
        &m.metrics.training,
        &u,
    );
    if let Some(v) = &m.metrics.validation {
        s += &stats_line(&format!("validation ({} samples)", v.samples), v, &u);
    }
    s += "\nparameter              value           std. error     unit\n";
    for e in m.parameters.iter().take(40) {
        s += &format!(
            "  {:<20} {:>14.7}  {:>14.3e}     {}\n",
            e.name, e.value, e.std_error, e.unit
        );
    }
    if m.parameters.len() > 40 {
        s += &format!("  … {} more in the model file\n", m.parameters.len() - 40);
    }
    if m.kind == ModelKind::Smooth {
        s += "  (k1, k2 in normalised input units: the input range maps to [-1, 1]; standard errors\n   assume independent residuals)\n";
    }
    if let Some(w) = &m.family {
        s += &format!(
            "\nfamily RH(k1, Δk1, k2, Δk2) reproducing {:.1} % of the samples (Definition 2.8):\n",
            100.0 * w.coverage_target
        );
        if !w.reachable {
            s += &format!(
                "  NOT reachable with Δk1 < k1, Δk2 < k2: at most {:.2} % covered\n",
                100.0 * w.coverage
            );
        }
        s += &format!(
            "  Δk1 = {:.5}, Δk2 = {:.5} (coverage {:.2} %)\n",
            w.delta_k1,
            w.delta_k2,
            100.0 * w.coverage
        );
        if w.delta_k2_law > 0.0 {
            s += &format!(
                "  k2 over the data in [{:.4}, {:.4}]; Proposition 4.3 adds Δk2* = {:.5}\n",
                w.k2_range.0, w.k2_range.1, w.delta_k2_law
            );
        }
        s += &format!(
            "  Δa = {:.5} (operator units; Proposition 3.2, and Δb ≤ Δa by Proposition 3.3)\n",
            w.delta_a
        );
        s += &format!(
            "  compensation error bound at the output: {:.5}{u} ({:.3} % of span)\n",
            w.output_bound, w.output_bound_pct_span
        );
    }
    if !r.comparison.is_empty() {
        s += "\ncomparison on the same data   parameters   train RMS %   valid RMS %   ns/sample   fit s\n";
        for c in &r.comparison {
            s += &format!(
                "  {:<28} {:>10}   {:>11.3}   {:>11}   {:>9.1}   {:>5.2}\n",
                c.kind,
                c.parameters,
                c.training.rms_pct_span,
                c.validation
                    .map_or("-".to_string(), |v| format!("{:.3}", v.rms_pct_span)),
                c.ns_per_sample,
                c.fit_seconds
            );
        }
    }
    if !r.model_file.is_empty() {
        s += &format!("\nwrote {}\n", r.model_file);
    }
    for p in &r.plots {
        s += &format!("wrote {p}\n");
    }
    s
}
