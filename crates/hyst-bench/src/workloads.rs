//! The workloads measured by `hyst bench` and by this crate (the criterion benches, `cargo bench
//! -p hyst-bench`, and the plain-C peer's comparison, `hyst-bench`), and how they are measured
//! ([`calibrate`], [`measure`]): one definition, so all of them report the same thing. hyst-cli
//! compiles this file as its module `workloads` (it has no dependency on this crate, whose build
//! compiles the C peer).
//!
//! Each workload processes [`SAMPLES`] samples of a signal with many reversals (a sum of sines
//! with a slowly growing amplitude) and returns a checksum so the work cannot be optimised away.
//! Every workload reads its input through one `black_box` of the whole slice, as the C peer
//! reads its array: the compiler cannot see the values, and no sample pays for a trip through
//! memory of its own (a `black_box` per sample would store and reload each one, a cost the C
//! peer's loop does not pay).
//! The bank workloads run [`BANK_CHANNELS`] channels (each its own stretch of that signal) for
//! [`BANK_TICKS`] ticks from no history ([`Inputs::samples`] channel-samples per call), reported
//! per channel-sample: in one block (`process`, time-major), and tick by tick (`step` with one
//! sample per channel, a controller's loop) next to 1,024 scalar operators stepped the same way
//! (each once per tick), on the best kernel and with the AVX2 kernel forced (a processor without
//! AVX-512; not run where the processor has no AVX2 + FMA, see [`Inputs::available`]). The
//! plain-C peer of the inverse (this crate's `peer`) runs on the inverse workload's [`signal`]
//! with its [`K1`] and [`K2`].

use std::cell::RefCell;
use std::hint::black_box;
use std::time::{Duration, Instant};

use hyst_bank::{force_isa, isa, BankFormula, BankVec, Isa, Lane};
use hyst_core::{
    Affine, Direct, Hysteresis, Inverse, InverseHysteresis, Jet, Operator, Polynomial, ShapedModel,
};

/// Samples per workload call.
pub const SAMPLES: usize = 4096;

/// Channels of the bank workloads (a deformable mirror's actuators).
pub const BANK_CHANNELS: usize = 1024;

/// Ticks per call of the bank workloads (each call starts from no history, as the scalar
/// workloads do: one tick in 64 is a channel's first).
pub const BANK_TICKS: usize = 64;

/// The names of the workloads, in report order, with their JSON keys.
pub const NAMES: [(&str, &str); 20] = [
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
];

/// The workloads run on 1,024 channels (reported per channel-sample): the banks in blocks, then
/// tick by tick, the scalar operators tick by tick, and the banks with the AVX2 kernel forced.
const BANK_WORKLOADS: [core::ops::RangeInclusive<usize>; 2] = [6..=8, 12..=19];

/// The workloads that force the AVX2 kernel (the tick-by-tick ones of `12..=14`, 5 places on).
const AVX2_WORKLOADS: core::ops::RangeInclusive<usize> = 17..=19;

/// The inverse workload's k1 (the half-width of the loop), shared by the C peer.
pub const K1: f64 = 0.14;
/// The inverse workload's k2 (the rate of the transition), shared by the C peer.
pub const K2: f64 = 8.0;

/// The sample period of [`signal`], s.
const DT: f64 = 1e-3;

/// The input of the scalar workloads at time t (s): a sum of sines with a slowly growing
/// amplitude, many reversals.
fn signal_at(t: f64) -> f64 {
    (0.5 + 0.3 * t) * (t * 7.0).sin() + 0.2 * (t * 23.0).sin()
}

/// The [`SAMPLES`] samples of the scalar workloads' input, 1 ms apart.
#[must_use]
pub fn signal() -> Vec<f64> {
    (0..SAMPLES).map(|k| signal_at(k as f64 * DT)).collect()
}

/// A set of workloads measured together, each by its index in `0..count()`.
pub trait Suite {
    /// How many workloads.
    fn count(&self) -> usize;
    /// The (channel-)samples of one call of workload `index`.
    fn samples(&self, index: usize) -> usize;
    /// Whether workload `index` runs on this processor.
    fn available(&self, index: usize) -> bool;
    /// Runs workload `index` once; a checksum (NaN if it could not run).
    fn run(&self, index: usize) -> f64;
}

/// Target duration of one batch, in seconds.
const BATCH_SECONDS: f64 = 0.005;

/// ns per sample of one batch of `calls` calls of workload `index`.
fn batch_ns(suite: &impl Suite, index: usize, calls: usize) -> f64 {
    let start = Instant::now();
    let mut checksum = 0.0;
    for _ in 0..calls {
        checksum += suite.run(index);
    }
    let elapsed = start.elapsed();
    black_box(checksum);
    elapsed.as_secs_f64() * 1e9 / (calls * suite.samples(index)) as f64
}

/// Calls per batch of each workload, calibrated to about 5 ms: double the calls until a batch
/// takes ≥ 1 ms, then scale (a single cold call is no guide: it can be much slower or, rounded,
/// faster). 0 for a workload this processor does not run.
#[must_use]
pub fn calibrate(suite: &impl Suite) -> Vec<usize> {
    (0..suite.count())
        .map(|i| {
            if !suite.available(i) {
                return 0;
            }
            let mut calls = 1usize;
            loop {
                let t = Instant::now();
                for _ in 0..calls {
                    black_box(suite.run(i));
                }
                let took = t.elapsed();
                if took >= Duration::from_millis(1) || calls >= 1 << 20 {
                    let per_call = took.as_secs_f64() / calls as f64;
                    break ((BATCH_SECONDS / per_call.max(1e-9)) as usize).clamp(1, 1 << 20);
                }
                calls *= 2;
            }
        })
        .collect()
}

/// ns per sample of each workload: batches of `calls` calls in interleaved rounds (at least 5,
/// for at least `budget`), the fastest batch of each kept, the one least disturbed by other
/// processes (on a shared machine, slower batches measure the neighbours, not the code). NaN
/// for a workload of no calls (one this processor does not run).
#[must_use]
pub fn measure(suite: &impl Suite, calls: &[usize], budget: Duration) -> Vec<f64> {
    let started = Instant::now();
    let mut samples = vec![Vec::new(); suite.count()];
    let mut rounds = 0usize;
    while rounds < 5 || started.elapsed() < budget {
        for (i, s) in samples.iter_mut().enumerate() {
            let calls = calls.get(i).copied().unwrap_or(0);
            if calls > 0 {
                s.push(batch_ns(suite, i, calls));
            }
        }
        rounds += 1;
    }
    samples
        .iter()
        .map(|s| s.iter().copied().reduce(f64::min).unwrap_or(f64::NAN))
        .collect()
}

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
        let d1 = |t: f64| {
            0.3 * (t * 7.0).sin()
                + (0.5 + 0.3 * t) * 7.0 * (t * 7.0).cos()
                + 0.2 * 23.0 * (t * 23.0).cos()
        };
        let x = signal();
        let jets = (0..SAMPLES)
            .map(|k| {
                let t = k as f64 * DT;
                Jet::from_derivatives(signal_at(t), [d1(t), -49.0 * signal_at(t)])
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
            12..=16 => self.tick(index)?,
            17..=19 => {
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
            _ => return None,
        })
    }

    /// The tick-by-tick workloads `12..=16`: a bank's `step`, or each of 1,024 scalar operators'
    /// `step`, once a tick, over the [`BANK_TICKS`] rows of the bank workloads from no history.
    fn tick(&self, index: usize) -> Option<f64> {
        let mut banks = self.banks.try_borrow_mut().ok()?;
        let b = banks.as_mut()?;
        match index {
            12 => bank_ticks(&mut b.inverse, &self.bank_x, &mut b.y),
            13 => bank_ticks(&mut b.direct, &self.bank_x, &mut b.y),
            14 => bank_ticks(&mut b.inverse32, &self.bank_x32, &mut b.y32),
            15 => scalar_ticks(&mut b.inverses, &self.bank_x, &mut b.y),
            16 => scalar_ticks(&mut b.directs, &self.bank_x, &mut b.y),
            _ => None,
        }
    }
}

/// The workloads of [`NAMES`], in its order.
impl Suite for Inputs {
    fn count(&self) -> usize {
        NAMES.len()
    }

    /// [`SAMPLES`], or for a bank workload [`BANK_CHANNELS`] × [`BANK_TICKS`]
    /// channel-samples.
    fn samples(&self, index: usize) -> usize {
        if BANK_WORKLOADS.iter().any(|r| r.contains(&index)) {
            BANK_CHANNELS * BANK_TICKS
        } else {
            SAMPLES
        }
    }

    /// All but those that force the AVX2 kernel where the processor has no AVX2 + FMA (their
    /// figures are then null).
    fn available(&self, index: usize) -> bool {
        !AVX2_WORKLOADS.contains(&index) || Isa::Avx2.available()
    }

    /// Runs workload `index` once over all samples; a checksum (NaN if the workload could not
    /// be built).
    fn run(&self, index: usize) -> f64 {
        self.try_run(index).unwrap_or(f64::NAN)
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
/// (3 cycles each, about as long as the bank's own work a channel-sample), which would double
/// the bank's measured time, whereas the scalar workloads' sums overlap their operators' own dependency chains.
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
