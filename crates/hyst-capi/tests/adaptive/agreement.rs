//! The C functions against the core: the `double` compensator equals
//! `hyst_core::adaptive::AdaptiveInverse` bit for bit, the `float` twin follows a truth whose
//! output gain is 20 % above the fitted model's, the linear variant is the core's of width four.

use super::*;
use crate::common::*;

#[test]
fn config_default_is_the_cores() {
    let mut cfg: hyst_adaptive_config = zeroed();
    unsafe { assert_eq!(hyst_adaptive_config_default(&mut cfg, 2e-3), HYST_OK) };
    let core = AdaptiveConfig::<f64>::new(2e-3);
    assert_eq!(
        cfg.parameters,
        HYST_ADAPT_K1 | HYST_ADAPT_K2 | HYST_ADAPT_GAIN | HYST_ADAPT_OFFSET
    );
    assert_eq!(
        (cfg.noise, cfg.drift, cfg.uncertainty, cfg.rest),
        (core.noise, core.drift, core.uncertainty, core.rest)
    );
    assert_eq!(
        (
            cfg.step,
            cfg.range,
            cfg.dead_zone,
            cfg.input_min,
            cfg.input_max
        ),
        (
            core.step,
            core.range,
            core.dead_zone,
            core.input_range.0,
            core.input_range.1
        )
    );
    // The bits are the indices of Parameter::ALL.
    let bits = [
        HYST_ADAPT_K1,
        HYST_ADAPT_K2,
        HYST_ADAPT_GAIN,
        HYST_ADAPT_OFFSET,
        HYST_ADAPT_INPUT_GAIN,
        HYST_ADAPT_INPUT_OFFSET,
    ];
    for (p, bit) in Parameter::ALL.iter().zip(bits) {
        assert_eq!(bit, 1 << p.index());
    }
    let mut cfg32: hyst_adaptive_config_f32 = zeroed();
    unsafe { assert_eq!(hyst_adaptive_config_default_f32(&mut cfg32, 2e-3), HYST_OK) };
    assert_eq!(cfg32.parameters, cfg.parameters);
    assert_eq!(cfg32.noise, 2e-3_f32);
}

/// The C function's prediction and status of sample `k` equal the core's.
fn assert_same_update(k: usize, c: (f64, i32), core: (f64, Status)) {
    assert_eq!(c.0.to_bits(), core.0.to_bits(), "prediction {k}");
    assert_eq!(c.1, status_of(core.1), "status {k}");
}

/// The C block's parameters and sample counts equal the core compensator's.
fn assert_same_estimates(a: &hyst_adaptive, core: &AdaptiveInverse<f64>) {
    for (i, p) in Parameter::ALL.iter().enumerate() {
        let v = parameter(a, i as i32);
        assert_eq!(v.to_bits(), core.estimator().value(*p).to_bits(), "{p:?}");
    }
    let mut counts: hyst_adaptive_sample_counts = zeroed();
    unsafe { assert_eq!(hyst_adaptive_counts(a, &mut counts), HYST_OK) };
    let c = core.estimator().counts();
    assert_eq!(
        counts,
        hyst_adaptive_sample_counts {
            updated: c.updated,
            rest: c.rest,
            starting: c.starting,
            dead_zone: c.dead_zone,
            bad_input: c.bad_input,
            out_of_range: c.out_of_range,
            bad_output: c.bad_output,
            refused: c.refused,
        }
    );
}

/// The closed loop (command → truth → measure) and recorded samples (update), every value
/// equal to the core's bit for bit: commands, predictions, statuses, parameters, counts.
#[test]
fn f64_equals_the_core_bit_for_bit() {
    let p = params();
    let mut cfg: hyst_adaptive_config = zeroed();
    unsafe { assert_eq!(hyst_adaptive_config_default(&mut cfg, 1e-3), HYST_OK) };
    cfg.parameters |= HYST_ADAPT_INPUT_GAIN;
    cfg.dead_zone = 2e-4;
    cfg.input_max = 0.9;
    let mut a: hyst_adaptive = zeroed();
    unsafe { assert_eq!(hyst_adaptive_init(&mut a, &p, &cfg), HYST_OK) };

    let mut config = AdaptiveConfig::new(1e-3);
    config.parameters = config.parameters.with(Parameter::InputGain);
    config.dead_zone = 2e-4;
    config.input_range.1 = 0.9;
    let fitted = core_model(1.0);
    let mut core =
        AdaptiveInverse::new(Adaptive::new(&fitted, InitialState::Rising, config).unwrap());
    let mut truth = core_model(1.15);
    let mut noise = Lcg64::new(30);
    let mut statuses = std::collections::BTreeSet::new();
    for k in 0..6000 {
        let d = desired(k);
        let mut x = f64::NAN;
        unsafe { assert_eq!(hyst_adaptive_step(&mut a, d, &mut x), HYST_OK) };
        assert_eq!(x.to_bits(), core.step(d).unwrap().to_bits(), "command {k}");
        // Every 997th measurement is lost; every 1009th a command is never measured.
        let y = if k % 997 == 3 {
            f64::NAN
        } else {
            truth.step(x) + noise.symmetric(1e-3)
        };
        if k % 1009 == 7 {
            continue;
        }
        let (mut prediction, mut status) = (0.0, -1);
        unsafe {
            assert_eq!(
                hyst_adaptive_measure(&mut a, y, &mut prediction, &mut status),
                HYST_OK
            )
        };
        let u = core.measure(y).unwrap();
        assert_same_update(k, (prediction, status), (u.prediction, u.status));
        statuses.insert(status);
    }
    // Recorded samples, NaN and out-of-range commands among them.
    for k in 6000..9000 {
        let x = if k % 501 == 0 {
            f64::NAN
        } else {
            1.3 * desired(k)
        };
        let y = if x.is_finite() {
            truth.step(x) + noise.symmetric(1e-3)
        } else {
            0.0
        };
        let (mut prediction, mut status) = (0.0, -1);
        unsafe {
            assert_eq!(
                hyst_adaptive_update(&mut a, x, y, &mut prediction, &mut status),
                HYST_OK
            );
        }
        let u = core.update(x, y);
        assert_same_update(k, (prediction, status), (u.prediction, u.status));
        statuses.insert(status);
    }
    for s in [
        HYST_ADAPT_UPDATED,
        HYST_ADAPT_STARTING,
        HYST_ADAPT_REST,
        HYST_ADAPT_DEAD_ZONE,
        HYST_ADAPT_BAD_INPUT,
        HYST_ADAPT_OUT_OF_RANGE,
        HYST_ADAPT_BAD_OUTPUT,
    ] {
        assert!(statuses.contains(&s), "status {s} never seen: {statuses:?}");
    }
    assert_same_estimates(&a, &core);
    // The block is plain data: a copy is an independent compensator in the same state.
    let mut copy: hyst_adaptive = zeroed();
    unsafe { ptr::copy_nonoverlapping(&a, &mut copy, 1) };
    for k in 9000..9100 {
        let (mut x1, mut x2) = (0.0, 0.0);
        unsafe {
            assert_eq!(hyst_adaptive_step(&mut a, desired(k), &mut x1), HYST_OK);
            assert_eq!(hyst_adaptive_step(&mut copy, desired(k), &mut x2), HYST_OK);
        }
        assert_eq!(x1.to_bits(), x2.to_bits());
    }
}

/// The `float` twin against a truth whose output gain is 20 % above the fitted model's: the
/// gain converges to the truth's, and the tracking error at the end is a small part of the
/// error at the start (the fitted model's).
#[test]
fn f32_twin_follows_a_truth_with_20_percent_more_gain() {
    let mut p: hyst_shaped_model_params_f32 = zeroed();
    p.k1 = 0.15;
    p.k2.kind = HYST_K2_CONSTANT;
    p.k2.value = 10.0;
    p.input.pre_gain = 1.0;
    p.input.post_gain = 1.0;
    p.output = hyst_shaping_f32 {
        kind: HYST_SHAPING_IDENTITY,
        p: [0.0; 6],
        pre_gain: 1.0,
        pre_offset: 0.0,
        post_gain: 2.0,
        post_offset: 0.1,
    };
    let noise_sigma = 2e-3;
    let mut cfg: hyst_adaptive_config_f32 = zeroed();
    let mut a: hyst_adaptive_f32 = zeroed();
    unsafe {
        assert_eq!(
            hyst_adaptive_config_default_f32(&mut cfg, noise_sigma),
            HYST_OK
        );
        assert_eq!(hyst_adaptive_init_f32(&mut a, &p, &cfg), HYST_OK);
    }
    let mut out = ScaledShaping::<f32>::identity();
    out.post_gain = 2.0 * 1.2;
    out.post_offset = 0.1;
    let law = AnyK2Law::Constant { value: 10.0_f32 };
    let h = Hysteresis::with_k2_law(0.15_f32, law).unwrap();
    let mut truth: AdaptiveModel<f32> =
        ShapedModel::new(ScaledShaping::identity(), h, out).unwrap();
    let mut noise = Lcg64::new(12);
    let n = 60_000;
    let tenth = n / 10;
    let (mut first, mut last) = (0.0_f64, 0.0_f64);
    for k in 0..n {
        let d = 0.1 + 1.6 * desired(k) as f32;
        let mut x = 0.0_f32;
        unsafe { assert_eq!(hyst_adaptive_step_f32(&mut a, d, &mut x), HYST_OK) };
        let y = truth.step(x) + noise.symmetric(f64::from(noise_sigma) * 3.0_f64.sqrt()) as f32;
        let mut status = -1;
        unsafe {
            assert_eq!(
                hyst_adaptive_measure_f32(&mut a, y, ptr::null_mut(), &mut status),
                HYST_OK
            );
        }
        assert!((0..=HYST_ADAPT_REFUSED).contains(&status));
        let e = f64::from(y - d).powi(2);
        if k < tenth {
            first += e;
        } else if k >= n - tenth {
            last += e;
        }
    }
    let (first, last) = ((first / tenth as f64).sqrt(), (last / tenth as f64).sqrt());
    let gain = parameter_f32(&a, 2);
    let mut counts: hyst_adaptive_sample_counts = zeroed();
    unsafe { assert_eq!(hyst_adaptive_counts_f32(&a, &mut counts), HYST_OK) };
    println!(
        "f32, truth gain +20 %: tracking rms first tenth {first:.5}, last tenth {last:.5}; gain \
         {gain} (truth 2.4), k1 {} (0.15), offset {} (0.1); {counts:?}",
        parameter_f32(&a, 0),
        parameter_f32(&a, 3)
    );
    assert!((gain / 2.4 - 1.0).abs() < 0.01, "gain {gain}");
    assert!(last <= first / 3.0, "{last} vs {first}");
    assert!(last < 3.0 * f64::from(noise_sigma), "{last}");
    assert_eq!(counts.refused + counts.bad_input + counts.bad_output, 0);
}

/// A recorded sample is `hyst_adaptive_update` in `float` too, and the f32 parameters start at
/// the fitted ones.
#[test]
fn f32_update_and_parameters() {
    let mut p: hyst_shaped_model_params_f32 = zeroed();
    p.k1 = 0.2;
    p.k2.value = 8.0;
    p.input.pre_gain = 1.0;
    p.input.post_gain = 1.5;
    p.input.post_offset = 0.25;
    p.output.pre_gain = 1.0;
    p.output.post_gain = 3.0;
    p.output.post_offset = -1.0;
    let mut cfg: hyst_adaptive_config_f32 = zeroed();
    let mut a: hyst_adaptive_f32 = zeroed();
    unsafe {
        assert_eq!(hyst_adaptive_config_default_f32(&mut cfg, 1e-3), HYST_OK);
        assert_eq!(hyst_adaptive_init_f32(&mut a, &p, &cfg), HYST_OK);
    }
    assert_eq!(
        [0, 1, 2, 3, 4, 5].map(|i| parameter_f32(&a, i)),
        [0.2, 8.0, 3.0, -1.0, 1.5, 0.25]
    );
    let (mut prediction, mut status) = (0.0_f32, -1);
    unsafe {
        assert_eq!(
            hyst_adaptive_update_f32(&mut a, 0.1, 0.0, &mut prediction, &mut status),
            HYST_OK
        );
        assert_eq!(status, HYST_ADAPT_STARTING);
        assert_eq!(
            hyst_adaptive_update_f32(&mut a, f32::NAN, 0.0, &mut prediction, &mut status),
            HYST_OK
        );
    }
    assert_eq!(status, HYST_ADAPT_BAD_INPUT);
    assert!(prediction.is_nan());
}

/// The firmware variant: affine shapings, up to four parameters, bit for bit the core's
/// width-4 compensator with affine shapes; a nonlinear shape or a fifth parameter refused.
#[test]
fn the_linear_variant_is_the_core_of_width_four() {
    let mut p = params();
    p.input = hyst_shaping {
        kind: HYST_SHAPING_AFFINE,
        p: [1.2, 0.05, 0.0, 0.0, 0.0, 0.0],
        pre_gain: 0.8,
        pre_offset: 0.05,
        post_gain: 1.1,
        post_offset: 0.0,
    };
    let mut cfg: hyst_adaptive_config = zeroed();
    unsafe { assert_eq!(hyst_adaptive_config_default(&mut cfg, 2e-3), HYST_OK) };
    let mut a: hyst_affine_adaptive = zeroed();
    unsafe { assert_eq!(hyst_affine_adaptive_init(&mut a, &p, &cfg), HYST_OK) };
    let linear = |s: &hyst_shaping| {
        ScaledShaping::new(
            s.pre_gain,
            s.pre_offset,
            hyst_core::AffineShaping::Affine(Affine::new(s.p[0], s.p[1]).unwrap()),
            s.post_gain,
            s.post_offset,
        )
        .unwrap()
    };
    let law = AnyK2Law::Affine(AffineK2::new(9.0, 1.5, 6.0, 12.0).unwrap());
    let model = ShapedModel::new(
        linear(&p.input),
        Hysteresis::with_k2_law(0.12, law).unwrap(),
        linear(&p.output),
    )
    .unwrap();
    let estimator = Adaptive::<f64, 4, hyst_core::AffineShaping<f64>>::of_width(
        &model,
        InitialState::Rising,
        AdaptiveConfig::new(2e-3),
    )
    .unwrap();
    let mut core = AdaptiveInverse::new(estimator);
    let mut truth = model;
    for k in 0..4000 {
        let d = desired(k);
        let mut x = 0.0;
        unsafe { assert_eq!(hyst_affine_adaptive_step(&mut a, d, &mut x), HYST_OK) };
        assert_eq!(x.to_bits(), core.step(d).unwrap().to_bits(), "sample {k}");
        let y = 1.1 * truth.step(x);
        let (mut pred, mut status) = (0.0, -1);
        unsafe {
            assert_eq!(
                hyst_affine_adaptive_measure(&mut a, y, &mut pred, &mut status),
                HYST_OK
            )
        };
        assert_eq!(
            pred.to_bits(),
            core.measure(y).unwrap().prediction.to_bits()
        );
    }
    let mut gain = 0.0;
    unsafe { assert_eq!(hyst_affine_adaptive_parameter(&a, 2, &mut gain), HYST_OK) };
    assert_eq!(gain, core.estimator().value(Parameter::Gain));

    // A polynomial ψ_in, or five parameters: refused, the block untouched.
    let mut b: hyst_affine_adaptive = zeroed();
    unsafe {
        assert_eq!(
            hyst_affine_adaptive_init(&mut b, &params(), &cfg),
            HYST_ERR_INVALID_PARAMETER
        )
    };
    cfg.parameters |= HYST_ADAPT_INPUT_OFFSET;
    unsafe {
        assert_eq!(
            hyst_affine_adaptive_init(&mut b, &p, &cfg),
            HYST_ERR_INVALID_PARAMETER
        );
        let mut x = 0.0;
        assert_eq!(
            hyst_affine_adaptive_step(&mut b, 0.1, &mut x),
            HYST_ERR_NOT_INITIALISED
        );
    }
}
