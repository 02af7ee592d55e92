//! The workloads measured by `hyst bench` and by the criterion benches (`cargo bench -p
//! hyst-cli`): one definition, so both report the same thing.
//!
//! Each workload processes [`SAMPLES`] samples of a signal with many reversals (a sum of sines
//! with a slowly growing amplitude) and returns a checksum so the work cannot be optimised away.

use std::hint::black_box;

use hyst_core::{
    Affine, Hysteresis, InverseHysteresis, Jet, Model, Operator, Polynomial, Real as _,
};

/// Samples per workload call.
pub const SAMPLES: usize = 4096;

/// The names of the workloads, in report order, with their JSON keys.
pub const NAMES: [(&str, &str); 6] = [
    ("direct operator H (eq. 2)", "direct_ns"),
    ("inverse operator H^-1 (eq. 4)", "inverse_ns"),
    ("inverse with 2 derivatives (jet)", "inverse_d2_ns"),
    ("model, polynomial shaping", "model_ns"),
    ("f64 exp (yardstick)", "exp_ns"),
    ("lambert_w0 (yardstick)", "lambert_w0_ns"),
];

/// Precomputed inputs for all workloads.
pub struct Inputs {
    x: Vec<f64>,
    jets: Vec<Jet<f64, 2>>,
    w_args: Vec<f64>,
    exp_args: Vec<f64>,
}

impl Inputs {
    /// Builds the input signals.
    #[must_use]
    pub fn new() -> Self {
        let dt = 1e-3;
        let signal = |t: f64| (0.5 + 0.3 * t) * (t * 7.0).sin() + 0.2 * (t * 23.0).sin();
        let d1 = |t: f64| {
            0.3 * (t * 7.0).sin()
                + (0.5 + 0.3 * t) * 7.0 * (t * 7.0).cos()
                + 0.2 * 23.0 * (t * 23.0).cos()
        };
        let x: Vec<f64> = (0..SAMPLES).map(|k| signal(k as f64 * dt)).collect();
        let jets = (0..SAMPLES)
            .map(|k| {
                let t = k as f64 * dt;
                Jet::from_derivatives(signal(t), [d1(t), -49.0 * signal(t)])
            })
            .collect();
        // Arguments like those the direct operator gives W: k2 M* e^(k2 (M* − ṽ)) ∈ (0, ~1e2).
        let w_args = x
            .iter()
            .map(|v| 2.24 * (2.24 - 8.0 * v.abs()).exp())
            .collect();
        let exp_args = x.iter().map(|v| -8.0 * v.abs()).collect();
        Self {
            x,
            jets,
            w_args,
            exp_args,
        }
    }

    /// Runs workload `index` (of [`NAMES`]) once over all samples; returns a checksum (NaN if
    /// the workload could not be built).
    #[must_use]
    pub fn run(&self, index: usize) -> f64 {
        self.try_run(index).unwrap_or(f64::NAN)
    }

    fn try_run(&self, index: usize) -> Option<f64> {
        Some(match index {
            0 => {
                let mut h = Hysteresis::new(0.14, 8.0).ok()?;
                self.x.iter().map(|&v| h.step(black_box(v))).sum()
            }
            1 => {
                let mut h = InverseHysteresis::new(0.14, 8.0).ok()?;
                self.x.iter().map(|&v| h.step(black_box(v))).sum()
            }
            2 => {
                let mut h = InverseHysteresis::new(0.14, 8.0).ok()?;
                self.jets
                    .iter()
                    .map(|&v| h.try_step(black_box(v)).map_or(0.0, |y| y.derivatives()[1]))
                    .sum()
            }
            3 => {
                let mut m = example_model()?;
                self.x.iter().map(|&v| m.step(black_box(v))).sum()
            }
            4 => self.exp_args.iter().map(|&a| black_box(a).exp()).sum(),
            5 => self
                .w_args
                .iter()
                .map(|&a| black_box(a).lambert_w0_fukushima())
                .sum(),
            _ => return None,
        })
    }
}

impl Default for Inputs {
    fn default() -> Self {
        Self::new()
    }
}

/// The shaped model of the `model` workload.
type ExampleModel = Model<f64, Polynomial<f64>, hyst_core::ConstantK2<f64>, Affine<f64>>;

/// Example 1's shaped model: ψ_out(H(0.105, 8)[ψ_in(in)]) with ψ_in(in) = in − 0.098 in² and
/// ψ_out(out) = 2.02 out.
fn example_model() -> Option<ExampleModel> {
    let psi_in = Polynomial::new([0.0, 1.0, -0.098, 0.0], -5.0, 5.0).ok()?;
    let psi_out = Affine::new(2.02, 0.0).ok()?;
    Model::new(psi_in, Hysteresis::new(0.105, 8.0).ok()?, psi_out).ok()
}
