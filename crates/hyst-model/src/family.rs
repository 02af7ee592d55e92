//! The family widths a model file records (`[family]`): the smallest (Δk1, Δk2) for which the
//! family RH(k1, Δk1, k2, Δk2) around the fitted model reproduces the data (Definition 2.8) at a
//! coverage, and the compensation bound Δa that follows (Propositions 3.2, 3.3 and 4.3).
//! hyst-fit's `widths` module computes them.

use serde::{Deserialize, Serialize};

/// The family that reproduces the data, and its bound.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FamilyWidths {
    /// The coverage asked for (fraction of samples inside the envelope).
    pub coverage_target: f64,
    /// Whether some family inside the limits reached it.
    pub reachable: bool,
    /// Δk1 (operator units).
    pub delta_k1: f64,
    /// Δk2 (1 / operator units), around the fitted k2 (or k2 law).
    pub delta_k2: f64,
    /// The coverage reached with these widths.
    pub coverage: f64,
    /// Proposition 4.3's extra Δk2* = sup|φ'| k1 for an input-dependent k2 (0 for constant k2).
    pub delta_k2_law: f64,
    /// Range of the nominal k2 over the data (equal ends for constant k2).
    pub k2_range: (f64, f64),
    /// Δa of Proposition 3.2 for RH(k1, Δk1, k2, Δk2 + Δk2*), the worst over the k2 range
    /// (operator units); Δb ≤ Δa (Proposition 3.3). `None` when the coverage is not
    /// reachable: no family within the limits reproduces the data, so no bound holds for it.
    pub delta_a: Option<f64>,
    /// The bound in output units: Δa times the Lipschitz constant of ψ_out on the data
    /// (`None` when not reachable).
    pub output_bound: Option<f64>,
    /// `output_bound` as % of the output span (`None` when not reachable).
    pub output_bound_pct_span: Option<f64>,
}
