//! The validation of docs/adaptation.md: a simulated truth whose k1 and output gain drift by
//! 30 % over a record, driven by a command with reversals and rests. Each test prints the
//! figures the page states; the assertions hold the goals.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)]

use hyst_core::adaptive::{
    Adaptive, AdaptiveConfig, AdaptiveInverse, AdaptiveModel, Parameter, Status,
};
use hyst_core::{AnyK2Law, Hysteresis, InitialState, Operator, ScaledShaping, ShapedModel};
use hyst_test_support::rng::{Lcg64, Random};

/// Samples in the record; the drift ramps over the first 60 %, then stops.
const SAMPLES: usize = 300_000;
const DRIFT_END: usize = SAMPLES * 6 / 10;
/// The settling time after which the RMS figures are taken.
const SETTLE: usize = 30_000;
/// σ of the measurement noise: 0.05 % of the output span (about 4).
const NOISE: f64 = 2e-3;

const K1: f64 = 0.15;
const K2: f64 = 10.0;
const GAIN: f64 = 2.0;
const OFFSET: f64 = 0.1;

fn model(k1: f64, gain: f64) -> AdaptiveModel<f64> {
    let mut out = ScaledShaping::identity();
    out.post_gain = gain;
    out.post_offset = OFFSET;
    let h = Hysteresis::with_k2_law(k1, AnyK2Law::Constant { value: K2 }).unwrap();
    ShapedModel::new(ScaledShaping::identity(), h, out).unwrap()
}

/// The drift's progress at sample k: 0 → 1 over the first 60 %, then 1.
fn ramp(k: usize) -> f64 {
    (k as f64 / DRIFT_END as f64).min(1.0)
}

/// The truth at sample k: k1 up 30 %, the output gain down 30 %.
fn truth_parameters(k: usize) -> (f64, f64) {
    (K1 * (1.0 + 0.3 * ramp(k)), GAIN * (1.0 - 0.3 * ramp(k)))
}

/// A truth whose parameters change each sample; its memory carries over (operator units).
struct Truth {
    model: AdaptiveModel<f64>,
}

impl Truth {
    fn new() -> Self {
        Self {
            model: model(K1, GAIN),
        }
    }
    fn at(&mut self, k: usize) -> &mut AdaptiveModel<f64> {
        let (k1, gain) = truth_parameters(k);
        let memory = self.model.memory();
        let mut next = model(k1, gain);
        next.set_memory(memory).unwrap();
        self.model = next;
        &mut self.model
    }
}

/// A command with reversals of changing amplitude, and rests (one block in five holds).
fn command(k: usize) -> f64 {
    let block = 2_000;
    if (k / block) % 5 == 4 {
        return command((k / block) * block - 1);
    }
    let t = k as f64 * 1e-3;
    (0.55 + 0.35 * (0.13 * t).sin()) * (1.7 * t).sin() + 0.25 * (4.3 * t + 1.0).sin()
}

fn config() -> AdaptiveConfig<f64> {
    AdaptiveConfig::new(NOISE)
}

fn rms(sum: f64, n: usize) -> f64 {
    (sum / n as f64).sqrt()
}

/// One-step prediction: the adaptive RMS after the settling time is ≤ 1/3 of the fixed
/// model's; when the drift stops, k1 and the gain converge to the truth's within 5 %.
#[test]
fn prediction_follows_the_drift_and_converges() {
    let fitted = model(K1, GAIN);
    let mut fixed = fitted;
    let mut a = Adaptive::new(&fitted, InitialState::Line, config()).unwrap();
    let mut truth = Truth::new();
    let mut noise = Lcg64::new(2026);
    let (mut sf, mut sa, mut n) = (0.0, 0.0, 0);
    for k in 0..SAMPLES {
        let x = command(k);
        let y = truth.at(k).step(x) + noise.gaussian(NOISE);
        let u = a.update(x, y);
        let f = fixed.step(x);
        if k >= SETTLE {
            sf += (y - f) * (y - f);
            sa += (y - u.prediction) * (y - u.prediction);
            n += 1;
        }
    }
    let (rf, ra) = (rms(sf, n), rms(sa, n));
    let (k1, gain) = truth_parameters(SAMPLES);
    let k1_err = a.value(Parameter::K1) / k1 - 1.0;
    let gain_err = a.value(Parameter::Gain) / gain - 1.0;
    println!(
        "drift: rms_fixed {rf:.5}, rms_adaptive {ra:.5} (ratio {:.3}, noise {NOISE}) after \
         {SETTLE} samples; final k1 {:+.2} %, gain {:+.2} %, k2 {:.3} (truth {K2}), offset {:.4} \
         (truth {OFFSET}); {:?}",
        ra / rf,
        100.0 * k1_err,
        100.0 * gain_err,
        a.value(Parameter::K2),
        a.value(Parameter::Offset),
        a.counts()
    );
    assert!(ra <= rf / 3.0, "{ra} vs {rf}");
    assert!(k1_err.abs() <= 0.05 && gain_err.abs() <= 0.05);
}

/// A rest of 10⁶ samples at a constant input moves no parameter by more than 0.1 % (here: not
/// at all).
#[test]
fn a_rest_of_a_million_samples_moves_no_parameter() {
    let fitted = model(K1, GAIN);
    let mut a = Adaptive::new(&fitted, InitialState::Line, config()).unwrap();
    let mut truth = Truth::new();
    let mut noise = Lcg64::new(7);
    for k in 0..50_000 {
        let x = command(k);
        a.update(x, truth.at(k).step(x) + noise.gaussian(NOISE));
    }
    let before = Parameter::ALL.map(|p| a.value(p));
    let x = command(49_999);
    let truth = truth.at(49_999);
    for _ in 0..1_000_000 {
        let y = truth.step(x) + noise.gaussian(NOISE);
        assert_eq!(a.update(x, y).status, Status::Rest);
    }
    let after = Parameter::ALL.map(|p| a.value(p));
    let moved = before
        .iter()
        .zip(after.iter())
        .map(|(b, a)| ((a - b) / b).abs())
        .fold(0.0, f64::max);
    println!("rest: largest relative move over 10^6 samples {moved:e}");
    assert!(moved <= 1e-3);
}

/// Closed loop: the adaptive compensator's tracking error of the drifting truth (measured
/// output − desired, after the settling time) is within 1.5 × that of a compensator that knows
/// the truth (the truth's own inverse at each sample: its error is the noise alone).
#[test]
fn the_adaptive_compensator_tracks_the_drifting_truth() {
    let fitted = model(K1, GAIN);
    let mut c = AdaptiveInverse::new(Adaptive::new(&fitted, InitialState::Line, config()).unwrap());
    let mut fixed = fitted.inverse();
    let (mut truth, mut fixed_truth, mut oracle_truth) = (Truth::new(), Truth::new(), Truth::new());
    let mut noise = Lcg64::new(99);
    let (mut sa, mut sf, mut so, mut n) = (0.0, 0.0, 0.0, 0);
    for k in 0..SAMPLES {
        let desired = OFFSET + GAIN * 0.8 * command(k);
        let x = c.step(desired).unwrap();
        let y = truth.at(k).step(x) + noise.gaussian(NOISE);
        c.measure(y);
        let yf = fixed_truth.at(k).step(fixed.step(desired)) + noise.gaussian(NOISE);
        let o = oracle_truth.at(k);
        let xo = o.inverse().step(desired);
        let yo = o.step(xo) + noise.gaussian(NOISE);
        if k >= SETTLE {
            sa += (y - desired) * (y - desired);
            sf += (yf - desired) * (yf - desired);
            so += (yo - desired) * (yo - desired);
            n += 1;
        }
    }
    let (ra, rf, ro) = (rms(sa, n), rms(sf, n), rms(so, n));
    println!(
        "closed loop: tracking RMS adaptive {ra:.5}, fixed {rf:.5}, knowing the truth {ro:.5} \
         (ratio {:.3}); {:?}",
        ra / ro,
        c.estimator().counts()
    );
    assert!(ra <= 1.5 * ro, "{ra} vs {ro}");
}

mod hostile {
    use super::*;
    use hyst_core::adaptive::Parameters;
    use proptest::prelude::*;

    /// A sample from a mix of ordinary values, extremes and non-finite ones.
    fn sample() -> impl Strategy<Value = f64> {
        prop_oneof![
            8 => -3.0f64..3.0,
            1 => prop::sample::select(vec![
                f64::NAN,
                f64::INFINITY,
                f64::NEG_INFINITY,
                1e300,
                -1e300,
                0.0,
                5e-324,
            ]),
            1 => any::<f64>(),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

        /// Any model, any settings, any samples: no panic; every parameter in its range and
        /// finite; a prediction that is finite or NaN; every sample counted once; the f32 twin
        /// the same.
        #[test]
        fn anything_in_nothing_broken(
            k1 in 1e-3f64..10.0,
            k2 in 1e-2f64..1e3,
            gain in 1e-2f64..1e2,
            offset in -10.0f64..10.0,
            mask in 1u8..64,
            noise in 1e-6f64..1.0,
            drift in 0.0f64..0.1,
            step in 1e-4f64..0.5,
            samples in prop::collection::vec((sample(), sample()), 1..400),
        ) {
            let mut out = ScaledShaping::identity();
            out.post_gain = gain;
            out.post_offset = offset;
            let h = Hysteresis::with_k2_law(k1, AnyK2Law::Constant { value: k2 }).unwrap();
            let m: AdaptiveModel<f64> = ShapedModel::new(ScaledShaping::identity(), h, out).unwrap();
            let parameters: Parameters = Parameter::ALL
                .into_iter()
                .filter(|p| mask & (1 << p.index()) != 0)
                .collect();
            let config = AdaptiveConfig { parameters, drift, step, ..AdaptiveConfig::new(noise) };
            let mut a = Adaptive::new(&m, InitialState::Rising, config).unwrap();
            let mut c = AdaptiveInverse::new(Adaptive::new(&m, InitialState::Line, config).unwrap());
            for (k, &(x, y)) in samples.iter().enumerate() {
                let u = a.update(x, y);
                prop_assert!(u.prediction.is_finite() || u.prediction.is_nan());
                if k % 3 == 0 {
                    if c.step(y).is_ok() {
                        c.measure(x);
                    }
                } else {
                    c.update(x, y);
                }
            }
            for e in [&a, c.estimator()] {
                for p in Parameter::ALL {
                    let v = e.value(p);
                    prop_assert!(v.is_finite(), "{} = {v}", p.name());
                    if matches!(p, Parameter::K1 | Parameter::K2 | Parameter::Gain | Parameter::InputGain) {
                        prop_assert!(v > 0.0, "{} = {v}", p.name());
                    }
                }
            }
            let n = a.counts();
            let total = n.updated + n.rest + n.starting + n.dead_zone + n.skipped() + n.refused;
            prop_assert_eq!(total, samples.len() as u64);
        }
    }
}
