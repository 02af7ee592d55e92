//! The estimator against simulated truths: the validation in the small (the record of
//! docs/adaptation.md is `hyst adapt`'s test), bad samples, rests, the compensator.

use super::*;
use crate::{AnyK2Law, Hysteresis, InitialState, Operator, ScaledShaping, ShapedModel};
use hyst_test_support::rng::{Lcg64, Random};

fn model(k1: f64, k2: f64, gain: f64, offset: f64) -> AdaptiveModel<f64> {
    let mut out = ScaledShaping::identity();
    out.post_gain = gain;
    out.post_offset = offset;
    let h = Hysteresis::with_k2_law(k1, AnyK2Law::Constant { value: k2 }).unwrap();
    ShapedModel::new(ScaledShaping::identity(), h, out).unwrap()
}

/// A command with reversals of changing amplitude and rests.
fn command(k: usize) -> f64 {
    let t = k as f64 * 1e-3;
    let rest = (k / 3000) % 5 == 4;
    if rest {
        return command(k - k % 3000 - 1);
    }
    (0.6 + 0.4 * (0.37 * t).sin()) * (2.1 * t).sin() + 0.3 * (5.3 * t).sin()
}

#[test]
fn with_no_update_the_prediction_is_the_fitted_model_bit_for_bit() {
    let m = model(0.2, 8.0, 1.3, 0.1);
    let mut config = AdaptiveConfig::new(1e-3);
    config.rest = 1e300;
    let mut a = Adaptive::new(&m, InitialState::Rising, config).unwrap();
    let mut fixed = m;
    let mut started = false;
    for k in 0..5000 {
        let x = command(k);
        if !started {
            crate::Start::start_at(&mut fixed, x, InitialState::Rising).unwrap();
            started = true;
        }
        let y = fixed.step(x);
        let u = a.update(x, y);
        assert_eq!(u.prediction, y, "sample {k}");
        assert!(matches!(u.status, Status::Rest | Status::Starting));
    }
}

#[test]
fn a_truth_with_other_parameters_is_found() {
    let m = model(0.2, 8.0, 1.0, 0.0);
    let mut truth = model(0.24, 6.5, 1.15, -0.05);
    let mut a = Adaptive::new(&m, InitialState::Line, AdaptiveConfig::new(1e-3)).unwrap();
    let mut noise = Lcg64::new(7);
    for k in 0..60_000 {
        let x = command(k);
        let y = truth.step(x) + 1e-3 * noise.normal();
        a.update(x, y);
    }
    for (p, want) in [
        (Parameter::K1, 0.24),
        (Parameter::K2, 6.5),
        (Parameter::Gain, 1.15),
        (Parameter::Offset, -0.05),
    ] {
        let got = a.value(p);
        let tol = if p == Parameter::Offset {
            0.01
        } else {
            0.05 * want
        };
        assert!((got - want).abs() < tol, "{}: {got} for {want}", p.name());
    }
    assert_eq!(a.counts().refused, 0);
}

#[test]
fn a_rest_of_a_million_samples_moves_nothing() {
    let m = model(0.2, 8.0, 1.0, 0.0);
    let mut truth = model(0.22, 8.0, 1.05, 0.0);
    let mut a = Adaptive::new(&m, InitialState::Line, AdaptiveConfig::new(1e-3)).unwrap();
    let mut noise = Lcg64::new(11);
    for k in 0..20_000 {
        let x = command(k);
        a.update(x, truth.step(x) + 1e-3 * noise.normal());
    }
    let before = Parameter::ALL.map(|p| a.value(p));
    let x = command(19_999);
    for _ in 0..1_000_000 {
        let u = a.update(x, truth.step(x) + 1e-3 * noise.normal());
        assert_eq!(u.status, Status::Rest);
    }
    assert_eq!(Parameter::ALL.map(|p| a.value(p)), before);
}

#[test]
fn bad_samples_are_counted_and_change_nothing() {
    let m = model(0.2, 8.0, 1.0, 0.0);
    let mut config = AdaptiveConfig::new(1e-3);
    config.input_range = (-2.0, 2.0);
    let mut a = Adaptive::new(&m, InitialState::Line, config).unwrap();
    for k in 0..100 {
        let x = command(k);
        a.update(x, x);
    }
    let memory = a.memory();
    let values = Parameter::ALL.map(|p| a.value(p));
    for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let u = a.update(x, 0.0);
        assert_eq!(u.status, Status::BadInput);
        assert!(u.prediction.is_nan());
    }
    assert_eq!(a.memory(), memory);
    assert_eq!(a.update(0.5, f64::NAN).status, Status::BadOutput);
    assert_eq!(a.update(3.0, 3.0).status, Status::OutOfRange);
    assert_eq!(Parameter::ALL.map(|p| a.value(p)), values);
    let c = a.counts();
    assert_eq!((c.bad_input, c.bad_output, c.out_of_range), (3, 1, 1));
    assert_eq!(c.skipped(), 5);
}

#[test]
fn settings_are_checked_by_name() {
    let m = model(0.2, 8.0, 1.0, 0.0);
    let bad = [
        (
            "noise",
            AdaptiveConfig {
                noise: 0.0,
                ..AdaptiveConfig::new(1e-3)
            },
        ),
        (
            "drift",
            AdaptiveConfig {
                drift: -1.0,
                ..AdaptiveConfig::new(1e-3)
            },
        ),
        (
            "range",
            AdaptiveConfig {
                range: 1.0,
                ..AdaptiveConfig::new(1e-3)
            },
        ),
        (
            "step",
            AdaptiveConfig {
                step: f64::NAN,
                ..AdaptiveConfig::new(1e-3)
            },
        ),
        (
            "parameters",
            AdaptiveConfig {
                parameters: Parameters::NONE,
                ..AdaptiveConfig::new(1e-3)
            },
        ),
    ];
    for (name, config) in bad {
        match Adaptive::new(&m, InitialState::Line, config) {
            Err(crate::Error::InvalidParameter { name: n, .. }) => assert_eq!(n, name),
            other => panic!("{name}: {other:?}"),
        }
    }
}

/// Parameters stay in range whatever the measurements say.
#[test]
fn parameters_stay_in_their_ranges() {
    let m = model(0.2, 8.0, 1.0, 0.0);
    let mut a = Adaptive::new(&m, InitialState::Line, AdaptiveConfig::new(1e-3)).unwrap();
    for k in 0..50_000 {
        let x = command(k);
        let y = if k % 2 == 0 { 1e6 } else { -1e6 * x };
        a.update(x, y);
    }
    for p in [Parameter::K1, Parameter::K2, Parameter::Gain] {
        let v = a.value(p);
        let f = a.fitted_value(p);
        assert!(
            v >= f / 4.0 * (1.0 - 1e-12) && v <= 4.0 * f * (1.0 + 1e-12),
            "{}: {v}",
            p.name()
        );
    }
}

/// After every update, the inverse of the current model gives back the last command for the
/// last desired output: switching parameters adds no jump (k1 and k2 adapt; the output gain
/// and offset, when they adapt, change the command by what they require).
#[test]
fn the_compensator_switches_without_a_jump() {
    let m = model(0.2, 8.0, 1.0, 0.0);
    let mut truth = model(0.25, 6.0, 1.0, 0.0);
    let config = AdaptiveConfig {
        parameters: [Parameter::K1, Parameter::K2].into_iter().collect(),
        ..AdaptiveConfig::new(1e-3)
    };
    let mut c = AdaptiveInverse::new(Adaptive::new(&m, InitialState::Line, config).unwrap());
    let (mut updates, mut kept, mut largest, mut largest_dk1) = (0, 0, 0.0_f64, 0.0_f64);
    for k in 0..20_000 {
        let desired = 0.9 * command(k);
        let x = c.step(desired).unwrap();
        let k1 = c.estimator().value(Parameter::K1);
        let u = c.measure(truth.step(x)).unwrap();
        if u.status == Status::Updated {
            updates += 1;
            // What the next command does: anchor, then invert the current model.
            let mut e = *c.estimator();
            e.anchor();
            let mut inverse = e.model().unwrap().inverse();
            let again = inverse.step(desired);
            // On the asymptote the output is v ∓ k1 whatever the memory: the command moves by
            // the change of k1 there, and by nothing elsewhere.
            let dk1 = (c.estimator().value(Parameter::K1) - k1).abs();
            let jump = (again - x).abs();
            if jump <= 1e-9 {
                kept += 1;
            } else {
                // Near the asymptote the output is v ∓ k1 whatever the memory: the command
                // moves by what the new k1 and k2 require there, a small fraction of the
                // command's span (about 2) per update; a compensator started afresh would move
                // it by up to k1 = 0.2.
                assert!(
                    jump <= 1e-3,
                    "sample {k}: {jump:e} for a change of k1 {dk1:e}"
                );
                largest = largest.max(jump);
                largest_dk1 = largest_dk1.max(dk1);
            }
        }
    }
    std::println!(
        "no jump: {kept} of {updates} updates keep the command to 1e-9; the others (near the \
         asymptote) move it by at most {largest:e}, k1 by at most {largest_dk1:e}"
    );
    assert!(kept > updates * 9 / 10);
    assert!(updates > 10_000);
    let k1 = c.estimator().value(Parameter::K1);
    assert!((k1 - 0.25).abs() < 0.0125, "{k1}");
}

/// The same estimator on f32 (firmware) follows the same truth.
#[test]
fn f32_follows_too() {
    let h = Hysteresis::with_k2_law(0.2_f32, AnyK2Law::Constant { value: 8.0 }).unwrap();
    let mut out = ScaledShaping::<f32>::identity();
    let m: AdaptiveModel<f32> = ShapedModel::new(ScaledShaping::identity(), h, out).unwrap();
    out.post_gain = 1.2;
    let mut truth: AdaptiveModel<f32> =
        ShapedModel::new(ScaledShaping::identity(), *m.operator(), out).unwrap();
    let mut a = Adaptive::new(&m, InitialState::Line, AdaptiveConfig::new(1e-3_f32)).unwrap();
    for k in 0..40_000 {
        let x = command(k) as f32;
        a.update(x, truth.step(x));
    }
    assert!((a.value(Parameter::Gain) - 1.2).abs() < 0.02);
    assert_eq!(a.counts().refused, 0);
}

/// A narrower estimator gives the same numbers bit for bit, and refuses more parameters than
/// its width.
#[test]
fn width_four_is_width_six_for_four_parameters() {
    let m = model(0.2, 8.0, 1.0, 0.0);
    let mut truth = model(0.24, 6.5, 1.15, -0.05);
    let config = AdaptiveConfig::new(1e-3);
    let mut six = Adaptive::new(&m, InitialState::Line, config).unwrap();
    let mut four = Adaptive::<f64, 4>::of_width(&m, InitialState::Line, config).unwrap();
    for k in 0..20_000 {
        let x = command(k);
        let y = truth.step(x);
        assert_eq!(six.update(x, y), four.update(x, y), "sample {k}");
    }
    let five = AdaptiveConfig {
        parameters: Parameters::DEFAULT.with(Parameter::InputOffset),
        ..config
    };
    assert!(matches!(
        Adaptive::<f64, 4>::of_width(&m, InitialState::Line, five),
        Err(crate::Error::InvalidParameter {
            name: "parameters",
            ..
        })
    ));
}
