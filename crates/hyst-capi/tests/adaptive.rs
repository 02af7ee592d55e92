//! The adaptive compensator of the C API (`hyst_adaptive_*`) called as C would call it: the
//! `double` one equals `hyst_core::adaptive::AdaptiveCompensator` bit for bit, the `float` twin
//! follows a truth whose output gain is 20 % above the fitted model's, and every bad argument
//! returns its status without touching anything.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]
// The tests call the C API through raw pointers, as a C program does.
#![allow(unsafe_code)]

use std::ffi::CStr;
use std::ptr;

use hyst::api_f32::*;
use hyst::api_f64::*;
use hyst::status::*;
use hyst::*;
use hyst_core::adaptive::{
    Adaptive, AdaptiveCompensator, AdaptiveConfig, AdaptiveModel, Parameter, Status,
};
use hyst_core::{
    Affine, AffineK2, AnyK2Law, AnyShaping, Hysteresis, InitialState, Operator, Polynomial,
    ScaledShaping, ShapedModel,
};

fn zeroed<T>() -> T {
    // SAFETY: the C state and parameter types are plain data: all-zero bits are valid.
    unsafe { std::mem::zeroed() }
}

/// A desired output with reversals of changing amplitude and a few rests.
fn desired(k: usize) -> f64 {
    let block = 400;
    if (k / block) % 6 == 5 {
        return desired((k / block) * block - 1);
    }
    let t = k as f64 * 4e-3;
    (0.5 + 0.3 * (0.11 * t).sin()) * (1.7 * t).sin() + 0.2 * (4.3 * t + 1.0).sin()
}

/// Deterministic measurement noise, uniform in ±`amplitude`.
struct Noise(u64);
impl Noise {
    fn next(&mut self, amplitude: f64) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        amplitude * (2.0 * ((self.0 >> 11) as f64 / (1u64 << 53) as f64) - 1.0)
    }
}

/// The fitted model of the bit-for-bit test: polynomial ψ_in, an affine k2 law, affine ψ_out
/// with a gain and an offset, the rising start rule.
fn params() -> hyst_shaped_model_params {
    let mut p: hyst_shaped_model_params = zeroed();
    p.k1 = 0.12;
    p.k2 = hyst_k2_law {
        kind: HYST_K2_AFFINE,
        value: 9.0,
        slope: 1.5,
        min: 6.0,
        max: 12.0,
    };
    p.input = hyst_shaping {
        kind: HYST_SHAPING_POLYNOMIAL,
        p: [0.0, 1.0, -0.05, 0.0, -5.0, 5.0],
        pre_gain: 0.8,
        pre_offset: 0.05,
        post_gain: 1.1,
        post_offset: 0.0,
    };
    p.output = hyst_shaping {
        kind: HYST_SHAPING_AFFINE,
        p: [1.5, 0.1, 0.0, 0.0, 0.0, 0.0],
        pre_gain: 1.0,
        pre_offset: 0.0,
        post_gain: 1.3,
        post_offset: -0.2,
    };
    p.initial_state = HYST_INITIAL_STATE_RISING;
    p
}

/// The core's model of [`params`], with the output gain times `gain`.
fn core_model(gain: f64) -> AdaptiveModel<f64> {
    let input = ScaledShaping::new(
        0.8,
        0.05,
        AnyShaping::Polynomial(Polynomial::new([0.0, 1.0, -0.05, 0.0], -5.0, 5.0).unwrap()),
        1.1,
        0.0,
    )
    .unwrap();
    let output = ScaledShaping::new(
        1.0,
        0.0,
        AnyShaping::Affine(Affine::new(1.5, 0.1).unwrap()),
        1.3 * gain,
        -0.2,
    )
    .unwrap();
    let law = AnyK2Law::Affine(AffineK2::new(9.0, 1.5, 6.0, 12.0).unwrap());
    ShapedModel::new(input, Hysteresis::with_k2_law(0.12, law).unwrap(), output).unwrap()
}

fn status_of(s: Status) -> i32 {
    match s {
        Status::Updated => HYST_ADAPT_UPDATED,
        Status::Rest => HYST_ADAPT_REST,
        Status::Starting => HYST_ADAPT_STARTING,
        Status::DeadZone => HYST_ADAPT_DEAD_ZONE,
        Status::BadInput => HYST_ADAPT_BAD_INPUT,
        Status::OutOfRange => HYST_ADAPT_OUT_OF_RANGE,
        Status::BadOutput => HYST_ADAPT_BAD_OUTPUT,
        Status::Refused => HYST_ADAPT_REFUSED,
    }
}

fn parameter(a: *const hyst_adaptive, which: i32) -> f64 {
    let mut v = f64::NAN;
    unsafe { assert_eq!(hyst_adaptive_parameter(a, which, &mut v), HYST_OK) };
    v
}

fn parameter_f32(a: *const hyst_adaptive_f32, which: i32) -> f32 {
    let mut v = f32::NAN;
    unsafe { assert_eq!(hyst_adaptive_parameter_f32(a, which, &mut v), HYST_OK) };
    v
}

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
        AdaptiveCompensator::new(Adaptive::new(&fitted, InitialState::Rising, config).unwrap());
    let mut truth = core_model(1.15);
    let mut noise = Noise(30);
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
            truth.step(x) + noise.next(1e-3)
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
        assert_eq!(
            prediction.to_bits(),
            u.prediction.to_bits(),
            "prediction {k}"
        );
        assert_eq!(status, status_of(u.status), "status {k}");
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
            truth.step(x) + noise.next(1e-3)
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
        assert_eq!(
            prediction.to_bits(),
            u.prediction.to_bits(),
            "prediction {k}"
        );
        assert_eq!(status, status_of(u.status), "status {k}");
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
    for (i, p) in Parameter::ALL.iter().enumerate() {
        let v = parameter(&a, i as i32);
        assert_eq!(v.to_bits(), core.estimator().value(*p).to_bits(), "{p:?}");
    }
    let mut counts: hyst_adaptive_sample_counts = zeroed();
    unsafe { assert_eq!(hyst_adaptive_counts(&a, &mut counts), HYST_OK) };
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
    let mut noise = Noise(12);
    let n = 60_000;
    let tenth = n / 10;
    let (mut first, mut last) = (0.0_f64, 0.0_f64);
    for k in 0..n {
        let d = 0.1 + 1.6 * desired(k) as f32;
        let mut x = 0.0_f32;
        unsafe { assert_eq!(hyst_adaptive_step_f32(&mut a, d, &mut x), HYST_OK) };
        let y = truth.step(x) + noise.next(f64::from(noise_sigma) * 3.0_f64.sqrt()) as f32;
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

/// A model whose ψ_out saturates (tanh), for the desired outputs it cannot produce.
fn saturating() -> hyst_shaped_model_params {
    let mut p: hyst_shaped_model_params = zeroed();
    p.k1 = 0.2;
    p.k2.value = 8.0;
    p.input.pre_gain = 1.0;
    p.input.post_gain = 1.0;
    p.output = hyst_shaping {
        kind: HYST_SHAPING_TANH,
        p: [1.0, 1.0, 0.0, 0.0, 0.0, 0.0],
        pre_gain: 1.0,
        pre_offset: 0.0,
        post_gain: 1.0,
        post_offset: 0.0,
    };
    p
}

#[test]
fn bad_arguments_give_statuses_and_change_nothing() {
    let p = saturating();
    let mut cfg: hyst_adaptive_config = zeroed();
    let mut a: hyst_adaptive = zeroed();
    let (mut x, mut v, mut prediction, mut status) = (7.0, 7.0, 7.0, 7);
    let mut counts: hyst_adaptive_sample_counts = zeroed();
    unsafe {
        // config_default: NULL, a noise that is not finite and > 0 (cfg untouched)
        assert_eq!(
            hyst_adaptive_config_default(ptr::null_mut(), 1e-3),
            HYST_ERR_NULL_POINTER
        );
        for noise in [0.0, -1e-3, f64::NAN, f64::INFINITY] {
            assert_eq!(
                hyst_adaptive_config_default(&mut cfg, noise),
                HYST_ERR_INVALID_PARAMETER
            );
            assert_eq!(cfg, zeroed());
        }
        assert_eq!(hyst_adaptive_config_default(&mut cfg, 1e-3), HYST_OK);

        // uninitialised (zeroed) block: every function
        assert_eq!(
            hyst_adaptive_step(&mut a, 0.1, &mut x),
            HYST_ERR_NOT_INITIALISED
        );
        assert_eq!(
            hyst_adaptive_measure(&mut a, 0.1, &mut prediction, &mut status),
            HYST_ERR_NOT_INITIALISED
        );
        assert_eq!(
            hyst_adaptive_update(&mut a, 0.1, 0.1, &mut prediction, &mut status),
            HYST_ERR_NOT_INITIALISED
        );
        assert_eq!(
            hyst_adaptive_parameter(&a, 0, &mut v),
            HYST_ERR_NOT_INITIALISED
        );
        assert_eq!(
            hyst_adaptive_counts(&a, &mut counts),
            HYST_ERR_NOT_INITIALISED
        );
        assert_eq!((x, v, prediction, status), (7.0, 7.0, 7.0, 7));

        // NULL everywhere
        assert_eq!(
            hyst_adaptive_init(ptr::null_mut(), &p, &cfg),
            HYST_ERR_NULL_POINTER
        );
        assert_eq!(
            hyst_adaptive_init(&mut a, ptr::null(), &cfg),
            HYST_ERR_NULL_POINTER
        );
        assert_eq!(
            hyst_adaptive_init(&mut a, &p, ptr::null()),
            HYST_ERR_NULL_POINTER
        );
        assert_eq!(
            hyst_adaptive_step(ptr::null_mut(), 0.1, &mut x),
            HYST_ERR_NULL_POINTER
        );
        assert_eq!(
            hyst_adaptive_measure(ptr::null_mut(), 0.1, &mut prediction, &mut status),
            HYST_ERR_NULL_POINTER
        );
        assert_eq!(
            hyst_adaptive_update(ptr::null_mut(), 0.1, 0.1, &mut prediction, &mut status),
            HYST_ERR_NULL_POINTER
        );
        assert_eq!(
            hyst_adaptive_parameter(ptr::null(), 0, &mut v),
            HYST_ERR_NULL_POINTER
        );
        assert_eq!(
            hyst_adaptive_counts(ptr::null(), &mut counts),
            HYST_ERR_NULL_POINTER
        );

        // bad settings and models: INVALID_PARAMETER, the block untouched
        let mut bad_configs = Vec::new();
        for mask in [0, 1 << 6, 0x8000_0000] {
            bad_configs.push(hyst_adaptive_config {
                parameters: mask,
                ..cfg
            });
        }
        for (field, value) in [
            ("noise", 0.0),
            ("noise", f64::NAN),
            ("drift", -1.0),
            ("uncertainty", 0.0),
            ("rest", f64::INFINITY),
            ("step", -0.1),
            ("range", 1.0),
            ("dead_zone", -1e-3),
            ("input_min", f64::NAN),
            ("input_min", 2.0),
        ] {
            let mut c = cfg;
            match field {
                "noise" => c.noise = value,
                "drift" => c.drift = value,
                "uncertainty" => c.uncertainty = value,
                "rest" => c.rest = value,
                "step" => c.step = value,
                "range" => c.range = value,
                "dead_zone" => c.dead_zone = value,
                "input_min" => {
                    c.input_min = value;
                    c.input_max = 1.0;
                }
                _ => unreachable!(),
            }
            bad_configs.push(c);
        }
        for c in &bad_configs {
            assert_eq!(
                hyst_adaptive_init(&mut a, &p, c),
                HYST_ERR_INVALID_PARAMETER,
                "{c:?}"
            );
        }
        let mut stop = p;
        stop.form = HYST_FORM_STOP;
        let mut linear = p;
        linear.linear = 0.5;
        let mut rule = p;
        rule.initial_state = 3;
        let mut k1 = p;
        k1.k1 = -0.2;
        let mut kind = p;
        kind.output.kind = 9;
        for bad in [stop, linear, rule, k1, kind] {
            assert_eq!(
                hyst_adaptive_init(&mut a, &bad, &cfg),
                HYST_ERR_INVALID_PARAMETER
            );
        }
        let mut decreasing = p;
        decreasing.input = hyst_shaping {
            kind: HYST_SHAPING_POLYNOMIAL,
            p: [0.0, -1.0, 0.0, 0.0, -1.0, 1.0],
            pre_gain: 1.0,
            pre_offset: 0.0,
            post_gain: 1.0,
            post_offset: 0.0,
        };
        assert_eq!(
            hyst_adaptive_init(&mut a, &decreasing, &cfg),
            HYST_ERR_NOT_MONOTONE
        );
        assert_eq!(
            hyst_adaptive_step(&mut a, 0.1, &mut x),
            HYST_ERR_NOT_INITIALISED
        );

        // misaligned block (4 bytes off), and a float block is not a double one
        let mut words = vec![0_u64; 260];
        let misaligned = words
            .as_mut_ptr()
            .cast::<u8>()
            .add(4)
            .cast::<hyst_adaptive>();
        assert_eq!(
            hyst_adaptive_init(misaligned, &p, &cfg),
            HYST_ERR_MISALIGNED
        );
        assert_eq!(
            hyst_adaptive_step(misaligned, 0.1, &mut x),
            HYST_ERR_MISALIGNED
        );
        let mut a32: hyst_adaptive_f32 = zeroed();
        let mut cfg32: hyst_adaptive_config_f32 = zeroed();
        let mut p32: hyst_shaped_model_params_f32 = zeroed();
        p32.k1 = 0.2;
        p32.k2.value = 8.0;
        p32.input.pre_gain = 1.0;
        p32.input.post_gain = 1.0;
        p32.output.pre_gain = 1.0;
        p32.output.post_gain = 1.0;
        assert_eq!(hyst_adaptive_config_default_f32(&mut cfg32, 1e-3), HYST_OK);
        assert_eq!(hyst_adaptive_init_f32(&mut a32, &p32, &cfg32), HYST_OK);
        let mut fake = vec![0_u64; 256];
        ptr::copy_nonoverlapping(
            (&a32 as *const hyst_adaptive_f32).cast::<u64>(),
            fake.as_mut_ptr(),
            128,
        );
        assert_eq!(
            hyst_adaptive_step(fake.as_mut_ptr().cast::<hyst_adaptive>(), 0.1, &mut x),
            HYST_ERR_NOT_INITIALISED
        );

        // initialised: measure without a command
        assert_eq!(hyst_adaptive_init(&mut a, &p, &cfg), HYST_OK);
        assert_eq!(
            hyst_adaptive_measure(&mut a, 0.1, &mut prediction, &mut status),
            HYST_ERR_NO_COMMAND
        );
        assert_eq!((prediction, status), (7.0, 7));
        // NULL outputs
        assert_eq!(
            hyst_adaptive_step(&mut a, 0.1, ptr::null_mut()),
            HYST_ERR_NULL_POINTER
        );
        assert_eq!(
            hyst_adaptive_parameter(&a, 0, ptr::null_mut()),
            HYST_ERR_NULL_POINTER
        );
        assert_eq!(
            hyst_adaptive_counts(&a, ptr::null_mut()),
            HYST_ERR_NULL_POINTER
        );
        // before any command, a refused desired output leaves *x alone
        assert_eq!(
            hyst_adaptive_step(&mut a, 1.5, &mut x),
            HYST_ERR_OUT_OF_RANGE
        );
        assert_eq!(x, 7.0);
        // a few samples; the prediction and status outputs may be NULL
        for k in 0..200 {
            assert_eq!(
                hyst_adaptive_step(&mut a, 0.6 * desired(k), &mut x),
                HYST_OK
            );
            let y = 0.6 * desired(k);
            let code = if k % 2 == 0 {
                hyst_adaptive_measure(&mut a, y, ptr::null_mut(), ptr::null_mut())
            } else {
                hyst_adaptive_measure(&mut a, y, &mut prediction, &mut status)
            };
            assert_eq!(code, HYST_OK);
        }
        assert_eq!(
            hyst_adaptive_measure(&mut a, 0.1, &mut prediction, &mut status),
            HYST_ERR_NO_COMMAND
        );
        // a desired output the model cannot produce: its status, *x = the last command, and no
        // command waits for a measurement
        let last = x;
        for d in [1.0, -2.0, f64::NAN, f64::INFINITY] {
            let expected = if d.is_finite() {
                HYST_ERR_OUT_OF_RANGE
            } else {
                HYST_ERR_NON_FINITE
            };
            x = 7.0;
            assert_eq!(hyst_adaptive_step(&mut a, d, &mut x), expected, "{d}");
            assert_eq!(x, last);
            assert_eq!(
                hyst_adaptive_measure(&mut a, 0.1, &mut prediction, &mut status),
                HYST_ERR_NO_COMMAND
            );
        }
        // a NaN measurement: HYST_OK, HYST_ADAPT_BAD_OUTPUT
        assert_eq!(hyst_adaptive_step(&mut a, 0.3, &mut x), HYST_OK);
        assert_eq!(
            hyst_adaptive_measure(&mut a, f64::NAN, &mut prediction, &mut status),
            HYST_OK
        );
        assert_eq!(status, HYST_ADAPT_BAD_OUTPUT);
        assert!(prediction.is_finite());
        // a non-finite recorded command: HYST_OK, HYST_ADAPT_BAD_INPUT, and nothing moves: the
        // block continues exactly as a copy that never saw it
        let mut copy: hyst_adaptive = zeroed();
        ptr::copy_nonoverlapping(&a, &mut copy, 1);
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!(
                hyst_adaptive_update(&mut a, bad, 0.2, &mut prediction, &mut status),
                HYST_OK
            );
            assert_eq!(status, HYST_ADAPT_BAD_INPUT);
            assert!(prediction.is_nan());
        }
        for k in 200..400 {
            let (mut x1, mut x2) = (0.0, 0.0);
            assert_eq!(
                hyst_adaptive_step(&mut a, 0.6 * desired(k), &mut x1),
                HYST_OK
            );
            assert_eq!(
                hyst_adaptive_step(&mut copy, 0.6 * desired(k), &mut x2),
                HYST_OK
            );
            assert_eq!(x1.to_bits(), x2.to_bits());
            let y = 0.62 * desired(k);
            assert_eq!(
                hyst_adaptive_measure(&mut a, y, &mut prediction, &mut status),
                HYST_OK
            );
            assert_eq!(
                hyst_adaptive_measure(&mut copy, y, ptr::null_mut(), ptr::null_mut()),
                HYST_OK
            );
        }
        for i in 0..6 {
            assert_eq!(parameter(&a, i).to_bits(), parameter(&copy, i).to_bits());
        }
        assert_eq!(hyst_adaptive_counts(&a, &mut counts), HYST_OK);
        assert_eq!(counts.bad_input, 3);
        assert_eq!(counts.bad_output, 1);
        // parameter: an index outside 0 … 5
        for which in [-1, 6, i32::MAX] {
            v = 7.0;
            assert_eq!(
                hyst_adaptive_parameter(&a, which, &mut v),
                HYST_ERR_INVALID_PARAMETER
            );
            assert_eq!(v, 7.0);
        }
    }
    let text = unsafe { CStr::from_ptr(hyst_status_message(HYST_ERR_NO_COMMAND)) };
    assert!(text.to_str().unwrap().contains("no command"));
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
    let mut a: hyst_linear_adaptive = zeroed();
    unsafe { assert_eq!(hyst_linear_adaptive_init(&mut a, &p, &cfg), HYST_OK) };
    let linear = |s: &hyst_shaping| {
        ScaledShaping::new(
            s.pre_gain,
            s.pre_offset,
            hyst_core::LinearShaping::Affine(Affine::new(s.p[0], s.p[1]).unwrap()),
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
    let estimator = Adaptive::<f64, 4, hyst_core::LinearShaping<f64>>::of_width(
        &model,
        InitialState::Rising,
        AdaptiveConfig::new(2e-3),
    )
    .unwrap();
    let mut core = AdaptiveCompensator::new(estimator);
    let mut truth = model;
    for k in 0..4000 {
        let d = desired(k);
        let mut x = 0.0;
        unsafe { assert_eq!(hyst_linear_adaptive_step(&mut a, d, &mut x), HYST_OK) };
        assert_eq!(x.to_bits(), core.step(d).unwrap().to_bits(), "sample {k}");
        let y = 1.1 * truth.step(x);
        let (mut pred, mut status) = (0.0, -1);
        unsafe {
            assert_eq!(
                hyst_linear_adaptive_measure(&mut a, y, &mut pred, &mut status),
                HYST_OK
            )
        };
        assert_eq!(
            pred.to_bits(),
            core.measure(y).unwrap().prediction.to_bits()
        );
    }
    let mut gain = 0.0;
    unsafe { assert_eq!(hyst_linear_adaptive_parameter(&a, 2, &mut gain), HYST_OK) };
    assert_eq!(gain, core.estimator().value(Parameter::Gain));

    // A polynomial ψ_in, or five parameters: refused, the block untouched.
    let mut b: hyst_linear_adaptive = zeroed();
    unsafe {
        assert_eq!(
            hyst_linear_adaptive_init(&mut b, &params(), &cfg),
            HYST_ERR_INVALID_PARAMETER
        )
    };
    cfg.parameters |= HYST_ADAPT_INPUT_OFFSET;
    unsafe {
        assert_eq!(
            hyst_linear_adaptive_init(&mut b, &p, &cfg),
            HYST_ERR_INVALID_PARAMETER
        );
        let mut x = 0.0;
        assert_eq!(
            hyst_linear_adaptive_step(&mut b, 0.1, &mut x),
            HYST_ERR_NOT_INITIALISED
        );
    }
}
