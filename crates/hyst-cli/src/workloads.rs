//! The workloads measured by `hyst bench` and by the criterion benches (`cargo bench -p
//! hyst-cli`): one definition, so both report the same thing.
//!
//! Each workload processes [`SAMPLES`] samples of a signal with many reversals (a sum of sines
//! with a slowly growing amplitude) and returns a checksum so the work cannot be optimised away.
//! Every workload reads its input through one `black_box` of the whole slice, as the C peer
//! reads its array: the compiler cannot see the values, and no sample pays for a trip through
//! memory of its own (a `black_box` per sample stored and reloaded each one, about 0.3 ns, in
//! hyst's workloads but not in the C peer's loop).
//! The bank workloads run [`BANK_CHANNELS`] channels (each its own stretch of that signal) for
//! [`BANK_TICKS`] ticks from no history ([`Inputs::samples`] channel-samples per call), reported
//! per channel-sample: in one block (`process`, time-major), and tick by tick (`step` with one
//! sample per channel, a controller's loop) next to 1,024 scalar operators stepped the same way
//! (each once per tick), on the best kernel and with the AVX2 kernel forced (a processor without
//! AVX-512; not run where the processor has no AVX2 + FMA, see [`Inputs::available`]). The C
//! peer (`c_peer_ns`) is a plain-C inverse of eq. (4) with no checks (src/peer/peer.c, compiled
//! by build.rs), on the inverse workload's signal.

use std::cell::RefCell;
use std::hint::black_box;

use hyst_bank::{force_isa, isa, BankFormula, BankVec, Isa, Lane};
use hyst_core::{
    Affine, Direct, Hysteresis, Inverse, InverseHysteresis, Jet, Operator, Polynomial, Real as _,
    ShapedModel,
};

/// Samples per workload call.
pub const SAMPLES: usize = 4096;

/// Channels of the bank workloads (a deformable mirror's actuators).
pub const BANK_CHANNELS: usize = 1024;

/// Ticks per call of the bank workloads (each call starts from no history, as the scalar
/// workloads do: one tick in 64 is a channel's first).
pub const BANK_TICKS: usize = 64;

/// The names of the workloads, in report order, with their JSON keys.
pub const NAMES: [(&str, &str); 22] = [
    ("direct operator H (eq. 2)", "direct_ns"),
    ("inverse operator H^-1 (eq. 4)", "inverse_ns"),
    ("inverse with 2 derivatives (jet)", "inverse_d2_ns"),
    ("model, polynomial shaping", "model_ns"),
    ("f64 exp (yardstick)", "exp_ns"),
    ("lambert_w0 (yardstick)", "lambert_w0_ns"),
    ("bank of 1024 H^-1, f64 (per channel)", "bank_inverse_ns"),
    ("bank of 1024 H, f64 (per channel)", "bank_direct_ns"),
    (
        "bank of 1024 H^-1, f32 (per channel)",
        "bank_inverse_f32_ns",
    ),
    ("fitted model, static (run_timed)", "fitted_static_ns"),
    ("fitted model, dynamics of order 2", "fitted_dynamics_ns"),
    ("adaptive estimator, 4 parameters", "adaptive_ns"),
    ("plain-C inverse (peer, no checks)", "c_peer_ns"),
    (
        "bank of 1024 H^-1, f64, tick by tick",
        "bank_tick_inverse_ns",
    ),
    ("bank of 1024 H, f64, tick by tick", "bank_tick_direct_ns"),
    (
        "bank of 1024 H^-1, f32, tick by tick",
        "bank_tick_inverse_f32_ns",
    ),
    (
        "1024 scalar H^-1, f64, tick by tick",
        "scalar_tick_inverse_ns",
    ),
    ("1024 scalar H, f64, tick by tick", "scalar_tick_direct_ns"),
    (
        "bank H^-1 f64 tick, AVX2 kernel forced",
        "bank_avx2_tick_inverse_ns",
    ),
    (
        "bank H f64 tick, AVX2 kernel forced",
        "bank_avx2_tick_direct_ns",
    ),
    (
        "bank H^-1 f32 tick, AVX2 kernel forced",
        "bank_avx2_tick_inverse_f32_ns",
    ),
    ("f64 exp inline, the inverse's", "exp_inline_ns"),
];

/// The workloads run on 1,024 channels (reported per channel-sample): the banks in blocks, then
/// tick by tick, the scalar operators tick by tick, and the banks with the AVX2 kernel forced.
const BANK_WORKLOADS: [core::ops::RangeInclusive<usize>; 2] = [6..=8, 13..=20];

/// The workloads that force the AVX2 kernel (the tick-by-tick ones of `13..=15`, 5 places on).
const AVX2_WORKLOADS: core::ops::RangeInclusive<usize> = 18..=20;

/// The inverse workload's k1 and k2, shared by the C peer.
const K1: f64 = 0.14;
const K2: f64 = 8.0;

/// Precomputed inputs for all workloads.
pub struct Inputs {
    x: Vec<f64>,
    jets: Vec<Jet<f64, 2>>,
    w_args: Vec<f64>,
    exp_args: Vec<f64>,
    /// The bank workloads' inputs, time-major (`BANK_TICKS` ticks of `BANK_CHANNELS`).
    bank_x: Vec<f64>,
    /// The same in f32.
    bank_x32: Vec<f32>,
    /// Measured outputs for the adaptive estimator: a truth with k1 and the output gain 10 %
    /// off the model's, on `x`.
    adapt_y: Vec<f64>,
    /// The banks and their output buffers, made once (`None`: they could not be built).
    banks: RefCell<Option<Banks>>,
}

/// The banks of the bank workloads, kept between calls (building one computes ln k2 for each
/// channel and allocates its state: not what a control loop does per tick), and the scalar
/// operators of the tick-by-tick workloads, one per channel.
struct Banks {
    inverse: BankVec<f64, Inverse>,
    direct: BankVec<f64, Direct>,
    inverse32: BankVec<f32, Inverse>,
    inverses: Vec<InverseHysteresis<f64>>,
    directs: Vec<Hysteresis<f64>>,
    y: Vec<f64>,
    y32: Vec<f32>,
}

impl Banks {
    fn new() -> Option<Self> {
        let k = |v: f64| vec![v; BANK_CHANNELS];
        let k32 = |v: f32| vec![v; BANK_CHANNELS];
        Some(Self {
            inverse: BankVec::from_vecs(k(0.14), k(8.0)).ok()?,
            direct: BankVec::from_vecs(k(0.14), k(8.0)).ok()?,
            inverse32: BankVec::from_vecs(k32(0.14), k32(8.0)).ok()?,
            inverses: (0..BANK_CHANNELS)
                .map(|_| InverseHysteresis::new(0.14, 8.0).ok())
                .collect::<Option<_>>()?,
            directs: (0..BANK_CHANNELS)
                .map(|_| Hysteresis::new(0.14, 8.0).ok())
                .collect::<Option<_>>()?,
            y: vec![0.0; BANK_CHANNELS * BANK_TICKS],
            y32: vec![0.0; BANK_CHANNELS * BANK_TICKS],
        })
    }
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
        // Channel c at tick t: sample c·61 + t of the signal (every channel its own stretch,
        // consecutive ticks consecutive samples, as the scalar workloads see them).
        let bank_x: Vec<f64> = (0..BANK_TICKS)
            .flat_map(|t| (0..BANK_CHANNELS).map(move |c| (c * 61 + t) % SAMPLES))
            .map(|i| x.get(i).copied().unwrap_or_default())
            .collect();
        let bank_x32 = bank_x.iter().map(|&v| v as f32).collect();
        let adapt_y = adaptive_model(0.154, 1.1).map_or_else(Vec::new, |mut truth| {
            x.iter().map(|&v| truth.step(v)).collect()
        });
        Self {
            adapt_y,
            x,
            jets,
            w_args,
            exp_args,
            bank_x,
            bank_x32,
            banks: RefCell::new(Banks::new()),
        }
    }

    /// The (channel-)samples of one call of workload `index`.
    #[must_use]
    pub fn samples(&self, index: usize) -> usize {
        if BANK_WORKLOADS.iter().any(|r| r.contains(&index)) {
            BANK_CHANNELS * BANK_TICKS
        } else {
            SAMPLES
        }
    }

    /// Whether workload `index` runs on this processor: all but those that force the AVX2
    /// kernel where the processor has no AVX2 + FMA (their figures are then null).
    #[must_use]
    pub fn available(&self, index: usize) -> bool {
        !AVX2_WORKLOADS.contains(&index) || Isa::Avx2.available()
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
                black_box(&self.x).iter().map(|&v| h.step(v)).sum()
            }
            1 => {
                let mut h = InverseHysteresis::new(K1, K2).ok()?;
                black_box(&self.x).iter().map(|&v| h.step(v)).sum()
            }
            2 => {
                let mut h = InverseHysteresis::new(0.14, 8.0).ok()?;
                black_box(&self.jets)
                    .iter()
                    .map(|&v| h.try_step(v).map_or(0.0, |y| y.derivatives()[1]))
                    .sum()
            }
            3 => {
                let mut m = example_model()?;
                black_box(&self.x).iter().map(|&v| m.step(v)).sum()
            }
            4 => black_box(&self.exp_args).iter().map(|&a| a.exp()).sum(),
            // The yardstick: the lambert_w crate's W0, the one the direct operator evaluates.
            5 => black_box(&self.w_args)
                .iter()
                .map(|&a| lambert_w::lambert_w0(a))
                .sum(),
            6..=8 => {
                let mut banks = self.banks.try_borrow_mut().ok()?;
                let b = banks.as_mut()?;
                match index {
                    6 => bank(&mut b.inverse, &self.bank_x, &mut b.y)?,
                    7 => bank(&mut b.direct, &self.bank_x, &mut b.y)?,
                    _ => bank(&mut b.inverse32, &self.bank_x32, &mut b.y32)?,
                }
            }
            9 | 10 => {
                let model = fitted_model(index == 10)?;
                let mut sum = 0.0;
                model
                    .run_timed(
                        black_box(&self.x),
                        Some(&hyst_model::TimeSteps::even(1e-3)),
                        None,
                        |_, s| sum += s.y,
                    )
                    .ok()?;
                sum
            }
            11 => {
                use hyst_core::adaptive::{Adaptive, AdaptiveConfig};
                use hyst_core::InitialState;
                let model = adaptive_model(0.14, 1.0)?;
                let config = AdaptiveConfig::new(1e-3);
                // Width 4: the duals of the four parameters that adapt.
                let mut a =
                    Adaptive::<f64, 4>::of_width(&model, InitialState::Line, config).ok()?;
                black_box(&self.x)
                    .iter()
                    .zip(black_box(&self.adapt_y))
                    .map(|(&x, &y)| a.update(x, y).prediction)
                    .sum()
            }
            12 => peer::inverse_sum(K1, K2, black_box(&self.x)),
            13..=17 => self.tick(index)?,
            18..=20 => {
                // The AVX2 kernel for this call only, then the kernel that ran before (the
                // best, or the one --kernel forced).
                if !Isa::Avx2.available() {
                    return None;
                }
                let kernel = isa();
                force_isa(Some(Isa::Avx2)).ok()?;
                let sum = self.tick(index - 5);
                force_isa(Some(kernel)).ok()?;
                sum?
            }
            21 => black_box(&self.exp_args)
                .iter()
                .map(|&a| a.exp_inline())
                .sum(),
            _ => return None,
        })
    }

    /// The tick-by-tick workloads `13..=17`: a bank's `step`, or each of 1,024 scalar operators'
    /// `step`, once a tick, over the [`BANK_TICKS`] rows of the bank workloads from no history.
    fn tick(&self, index: usize) -> Option<f64> {
        let mut banks = self.banks.try_borrow_mut().ok()?;
        let b = banks.as_mut()?;
        match index {
            13 => bank_ticks(&mut b.inverse, &self.bank_x, &mut b.y),
            14 => bank_ticks(&mut b.direct, &self.bank_x, &mut b.y),
            15 => bank_ticks(&mut b.inverse32, &self.bank_x32, &mut b.y32),
            16 => scalar_ticks(&mut b.inverses, &self.bank_x, &mut b.y),
            17 => scalar_ticks(&mut b.directs, &self.bank_x, &mut b.y),
            _ => None,
        }
    }
}

/// The plain-C peer of the inverse operator (src/peer/peer.c): eq. (4) with Definition 2.1's
/// memory, the same arithmetic as `InverseHysteresis` with no checks, compiled at -O2 by build.rs.
pub mod peer {
    // The unsafe code of hyst-cli: a call into C that reads `x[..n]` (and, in this file's
    // test, one that also writes `y[..n]`).
    #![allow(unsafe_code)]

    extern "C" {
        fn hyst_peer_inverse_sum(k1: f64, k2: f64, x: *const f64, n: usize) -> f64;
    }

    /// H⁻¹(k1, k2) from no history over `x`, the sum of its outputs.
    #[must_use]
    pub fn inverse_sum(k1: f64, k2: f64, x: &[f64]) -> f64 {
        // SAFETY: the C function reads x[0..n) only, n = x.len(), and keeps no pointer.
        unsafe { hyst_peer_inverse_sum(k1, k2, x.as_ptr(), x.len()) }
    }
}

/// gain · H(k1, 8)\[x\], the model of the adaptive workload (k1, k2, the output gain and offset
/// adapt).
fn adaptive_model(k1: f64, gain: f64) -> Option<hyst_core::adaptive::AdaptiveModel<f64>> {
    use hyst_core::{AnyK2Law, ScaledShaping, ShapedModel};
    let mut out = ScaledShaping::identity();
    out.post_gain = gain;
    let h = Hysteresis::with_k2_law(k1, AnyK2Law::Constant { value: 8.0 }).ok()?;
    ShapedModel::new(ScaledShaping::identity(), h, out).ok()
}

/// A fitted smooth model as the model runtime runs it (a model file's `[smooth]`):
/// 2.02 H(0.105, 8)[in], with the plant 1e-4 s² v̈ + 0.02 s v̇ + v = u before it when `dynamics`
/// (the model of `hyst run --model` for a model with dynamics, at a 1 ms period).
fn fitted_model(dynamics: bool) -> Option<hyst_model::SmoothModel> {
    use hyst_core::{AnyK2Law, AnyShaping, ScaledShaping};
    Some(hyst_model::SmoothModel {
        k1: 0.105,
        k2: AnyK2Law::Constant { value: 8.0 },
        input_shaping: ScaledShaping::identity(),
        output_shaping: ScaledShaping::new(1.0, 0.0, AnyShaping::Identity, 2.02, 0.0).ok()?,
        initial_state: hyst_core::InitialState::Rising,
        form: hyst_model::Form::Operator,
        linear: 0.0,
        dynamics: if dynamics {
            Some(hyst_model::Dynamics::new(1.0, &[0.02, 1e-4]).ok()?)
        } else {
            None
        },
        rate: None,
    })
}

/// `bank` from no history over the ticks `x` (time-major) into `y`; a checksum of the outputs
/// (the first and the last, with every output made observable by `black_box`).
///
/// Not the sum of all outputs: that is a second pass of one dependent add per channel-sample
/// (3 cycles each, about 1.1 ns on the development machine), which doubled the bank's measured
/// time, whereas the scalar workloads' sums overlap their operators' own dependency chains.
fn bank<T: Lane, F: BankFormula>(bank: &mut BankVec<T, F>, x: &[T], y: &mut [T]) -> Option<f64> {
    bank.reset();
    bank.process(black_box(x), y).ok()?;
    let y = black_box(&*y);
    Some(y.first()?.as_f64() + y.last()?.as_f64())
}

/// `bank` from no history, one `step` per tick (row) of the time-major `x`, into `y`; the
/// checksum of [`bank`].
fn bank_ticks<T: Lane, F: BankFormula>(
    bank: &mut BankVec<T, F>,
    x: &[T],
    y: &mut [T],
) -> Option<f64> {
    bank.reset();
    for (row, out) in x
        .chunks_exact(BANK_CHANNELS)
        .zip(y.chunks_exact_mut(BANK_CHANNELS))
    {
        bank.step(black_box(row), out).ok()?;
    }
    let y = black_box(&*y);
    Some(y.first()?.as_f64() + y.last()?.as_f64())
}

/// The scalar operators `ops` (one a channel) from no history, each stepped once per tick (row)
/// of the time-major `x`, into `y`; the checksum of [`bank`].
fn scalar_ticks<O: Operator<f64>>(ops: &mut [O], x: &[f64], y: &mut [f64]) -> Option<f64> {
    for op in ops.iter_mut() {
        op.reset();
    }
    for (row, out) in x
        .chunks_exact(BANK_CHANNELS)
        .zip(y.chunks_exact_mut(BANK_CHANNELS))
    {
        for ((op, v), u) in ops.iter_mut().zip(out.iter_mut()).zip(black_box(row)) {
            *v = op.step(*u);
        }
    }
    let y = black_box(&*y);
    Some(y.first()? + y.last()?)
}

impl Default for Inputs {
    fn default() -> Self {
        Self::new()
    }
}

/// The shaped model of the `model` workload.
type ExampleModel = ShapedModel<f64, Polynomial<f64>, hyst_core::ConstantK2<f64>, Affine<f64>>;

/// Example 1's shaped model: ψ_out(H(0.105, 8)[ψ_in(in)]) with ψ_in(in) = in − 0.098 in² and
/// ψ_out(out) = 2.02 out.
fn example_model() -> Option<ExampleModel> {
    let psi_in = Polynomial::new([0.0, 1.0, -0.098, 0.0], -5.0, 5.0).ok()?;
    let psi_out = Affine::new(2.02, 0.0).ok()?;
    ShapedModel::new(psi_in, Hysteresis::new(0.105, 8.0).ok()?, psi_out).ok()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    /// The C peer is a real inverse: on the benchmark's signal (and a signal of k1-sized
    /// reversals) its outputs equal hyst's inverse within 4 ulp of max(|input|, k1) (the same
    /// arithmetic but for the `exp`, the platform's in the peer and hyst's inline one, which
    /// agree to an ulp; and hyst's band clamp may move an output by an ulp).
    #[test]
    fn the_c_peer_is_the_inverse_operator() {
        // Here, not at the module's top: the criterion bench includes this file and drops the
        // test, which would leave the imports and this function unused.
        use super::{peer, Inputs, InverseHysteresis, Operator as _, K1, K2};
        /// The C peer's H⁻¹(k1, k2) from no history over `x` into `y` (as many outputs as both
        /// have room for).
        #[allow(unsafe_code)] // a call into C, as the peer module's
        fn peer_inverse(k1: f64, k2: f64, x: &[f64], y: &mut [f64]) {
            extern "C" {
                fn hyst_peer_inverse(k1: f64, k2: f64, x: *const f64, y: *mut f64, n: usize);
            }
            let n = x.len().min(y.len());
            // SAFETY: the C function reads x[0..n), writes y[0..n) (n within both slices, which
            // cannot overlap: `y` is borrowed mutably) and keeps no pointer.
            unsafe { hyst_peer_inverse(k1, k2, x.as_ptr(), y.as_mut_ptr(), n) }
        }
        let inputs = Inputs::new();
        let small: Vec<f64> = (0..2000)
            .map(|k| 0.3 * (f64::from(k) * 0.05).sin() * (f64::from(k) * 0.013).cos())
            .collect();
        for (k1, k2, x) in [
            (K1, K2, &inputs.x),
            (0.2, 40.0, &small),
            (0.05, 1.0, &small),
        ] {
            let mut y = vec![0.0; x.len()];
            peer_inverse(k1, k2, x, &mut y);
            let mut h = InverseHysteresis::new(k1, k2).unwrap();
            for (i, (&u, &c)) in x.iter().zip(&y).enumerate() {
                let v = h.try_step(u).unwrap();
                let tol = 4.0 * f64::EPSILON * u.abs().max(k1);
                assert!((v - c).abs() <= tol, "sample {i}: hyst {v}, C peer {c}");
            }
            let sum = y.iter().fold(0.0, |a, b| a + b);
            assert_eq!(peer::inverse_sum(k1, k2, x).to_bits(), sum.to_bits());
        }
    }
}
