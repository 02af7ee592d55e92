//! k1 and k2 of a fitted smooth model in the units of its input, beside the normalised values
//! the model computes with.
//!
//! `hyst fit` normalises the input, x̂ = (x − centre) / half-span, and every ψ_in it fits has
//! slope 1 in x̂ at the centre, so k1 (operator units) and k2 (1/operator units) are in
//! normalised input units. The operator's input is v = ψ_in(x); with s the slope dv/dx, a band
//! of half-width k1 in v is k1 / s in x, and k2·v = (k2·s)·x. This module takes s as ψ_in's
//! mean slope over the input interval its scaling maps to [−1, 1] (the range of the data
//! `hyst fit` fitted):
//!
//! s = (ψ_in(x_hi) − ψ_in(x_lo)) / (x_hi − x_lo), k1_input = k1 / s, k2_input = k2 · s,
//!
//! exact for an affine ψ_in (s = 1 / half-span: H(k1, k2) on v is H(k1 / s, k2 · s) on x, by
//! the scaling H(k1, k2)\[s x\] = s H(k1 / s, k2 s)\[x\]), and the mean conversion over that
//! interval for a curved one.

use serde::{Deserialize, Serialize};

use crate::file::{ModelFile, ModelKind};

/// k1 in input units and k2 in 1/input units (with the standard errors of the normalised
/// values, scaled the same way: s is the normalisation's, not a fitted number, for an affine
/// ψ_in). JSON keys as the field names.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct InputUnits {
    /// k1 / s (input units): the half-width of the band of H in the input's units.
    pub k1_input: f64,
    /// The standard error of k1, / s (input units); NaN when the fit recorded none.
    pub k1_input_std_error: f64,
    /// k2 · s (1/input units; an affine k2 law's φ(0)).
    pub k2_input: f64,
    /// The standard error of k2, · s (1/input units); NaN when the fit recorded none.
    pub k2_input_std_error: f64,
    /// s = dv/dx, ψ_in's mean slope over the input interval its scaling maps to [−1, 1]
    /// (operator units per input unit).
    pub input_slope: f64,
}

/// k1 and k2 of `file`'s smooth model in its input's units; `None` for a Prandtl–Ishlinskii
/// model, or when ψ_in's slope over its interval is not finite and positive.
#[must_use]
pub fn input_units(file: &ModelFile) -> Option<InputUnits> {
    let m = file
        .smooth
        .as_ref()
        .filter(|_| file.kind == ModelKind::Smooth)?;
    let (lo, hi) = m.fitted_input_interval();
    let psi = &m.input_shaping;
    let s = (hyst_core::Shaping::apply(psi, hi) - hyst_core::Shaping::apply(psi, lo)) / (hi - lo);
    if !(s.is_finite() && s > 0.0) {
        return None;
    }
    let std_error = |name: &str| {
        file.parameters
            .iter()
            .find(|e| e.name == name)
            .map_or(f64::NAN, |e| e.std_error)
    };
    Some(InputUnits {
        k1_input: m.k1 / s,
        k1_input_std_error: std_error("k1") / s,
        k2_input: m.k2.at_zero() * s,
        k2_input_std_error: std_error("k2") * s,
        input_slope: s,
    })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use hyst_core::{Hysteresis, Operator};
    use std::path::Path;

    /// A model of an input from 0 to 4 V (ψ_in = x / 2 − 1, s = 0.5 per V), H(0.2, 6) in
    /// normalised units, output ψ_out = identity; started on the line.
    fn model() -> ModelFile {
        let text = r#"
format = "hyst-model"
version = 1
kind = "smooth"
[[parameters]]
name = "k1"
value = 0.2
std_error = 0.01
unit = "operator units"
[[parameters]]
name = "k2"
value = 6.0
std_error = 0.3
unit = "1/operator units"
[columns]
input = "x"
output = "y"
[units]
input = "V"
output = ""
[metrics]
parameters = 2
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
initial_state = "line"
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
pre_offset = 0.0
shape = "identity"
post_gain = 1.0
post_offset = 0.0
[provenance]
file = "none"
bytes = 0
fnv1a64 = "0"
rows = 0
records = 0
command = "hand-written"
hyst_version = "0"
created_unix = 0
"#;
        ModelFile::from_toml(text, Path::new("m.toml")).unwrap()
    }

    #[test]
    fn the_operator_in_input_units_runs_as_the_model() {
        let file = model();
        let k = input_units(&file).unwrap();
        assert_eq!(k.input_slope, 0.5);
        assert_eq!((k.k1_input, k.k2_input), (0.4, 3.0));
        assert_eq!((k.k1_input_std_error, k.k2_input_std_error), (0.02, 0.15));
        // y = H(0.2, 6)[x/2 − 1] = (1/2) H(0.4 V, 3 /V)[x] − 1: the model is the operator with
        // k1_input, k2_input on the input itself, scaled and shifted.
        let x: Vec<f64> = (0..2000)
            .map(|i| 2.0 + 1.9 * (f64::from(i) * 0.01).sin() * (f64::from(i) * 0.0013).cos())
            .collect();
        let y = file.run(&x).unwrap();
        let mut h = Hysteresis::new(k.k1_input, k.k2_input).unwrap();
        for (xi, yi) in x.iter().zip(&y) {
            let expected = 0.5 * h.step(*xi) - 1.0;
            assert!((expected - yi).abs() < 1e-12, "{xi}: {expected} vs {yi}");
        }
        // A Prandtl–Ishlinskii model has none.
        let mut pi = file;
        pi.kind = ModelKind::PrandtlIshlinskii;
        assert!(input_units(&pi).is_none());
    }
}
