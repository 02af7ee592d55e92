//! Every bad argument of the adaptive compensator's functions returns its status and changes
//! nothing: NULL pointers, uninitialised, misaligned and foreign blocks, bad settings and
//! models, desired outputs the model cannot produce, bad samples.

use super::*;
use crate::common::*;

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

/// The default settings for a noise of 1e-3.
fn config() -> hyst_adaptive_config {
    let mut cfg: hyst_adaptive_config = zeroed();
    assert_eq!(
        unsafe { hyst_adaptive_config_default(&mut cfg, 1e-3) },
        HYST_OK
    );
    cfg
}

/// The block initialised with [`saturating`] and [`config`], run over `samples` of 0.6 × the
/// desired output, its output measured exactly (every other measurement without the prediction
/// and status outputs). Returns the last command.
unsafe fn run(a: &mut hyst_adaptive, samples: std::ops::Range<usize>) -> f64 {
    let (mut x, mut prediction, mut status) = (7.0, 7.0, 7);
    for k in samples {
        assert_eq!(hyst_adaptive_step(a, 0.6 * desired(k), &mut x), HYST_OK);
        let y = 0.6 * desired(k);
        let code = if k % 2 == 0 {
            hyst_adaptive_measure(a, y, ptr::null_mut(), ptr::null_mut())
        } else {
            hyst_adaptive_measure(a, y, &mut prediction, &mut status)
        };
        assert_eq!(code, HYST_OK);
    }
    x
}

/// config_default: NULL, a noise that is not finite and > 0 (the settings untouched).
#[test]
fn config_default_refuses_null_and_bad_noise() {
    let mut cfg: hyst_adaptive_config = zeroed();
    unsafe {
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
    }
}

/// An uninitialised (zeroed) block: every function refuses it and writes no output.
#[test]
fn an_uninitialised_block_is_refused_by_every_function() {
    let mut a: hyst_adaptive = zeroed();
    let (mut x, mut v, mut prediction, mut status) = (7.0, 7.0, 7.0, 7);
    let mut counts: hyst_adaptive_sample_counts = zeroed();
    unsafe {
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
    }
}

/// NULL for the block, the model, the settings or an output: HYST_ERR_NULL_POINTER.
#[test]
fn null_pointers_are_refused_everywhere() {
    let p = saturating();
    let cfg = config();
    let mut a: hyst_adaptive = zeroed();
    let (mut x, mut v, mut prediction, mut status) = (7.0, 7.0, 7.0, 7);
    let mut counts: hyst_adaptive_sample_counts = zeroed();
    unsafe {
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

        assert_eq!(hyst_adaptive_init(&mut a, &p, &cfg), HYST_OK);
        // NULL outputs of an initialised block
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
    }
}

/// Bad settings and models: HYST_ERR_INVALID_PARAMETER (a decreasing input shaping:
/// HYST_ERR_NOT_MONOTONE), and the block stays uninitialised.
#[test]
fn bad_settings_and_models_are_refused_at_init() {
    let p = saturating();
    let cfg = config();
    let mut a: hyst_adaptive = zeroed();
    let mut x = 7.0;
    unsafe {
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
    }
}

/// A misaligned block (4 bytes off), and a float block is not a double one.
#[test]
fn misaligned_and_float_blocks_are_refused() {
    let p = saturating();
    let cfg = config();
    let mut x = 7.0;
    unsafe {
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
    }
}

/// A measurement needs a command, and a desired output the model cannot produce gives its
/// status, leaves *x at the last command and leaves no command waiting for a measurement.
#[test]
fn refused_desired_outputs_keep_the_last_command() {
    let p = saturating();
    let cfg = config();
    let mut a: hyst_adaptive = zeroed();
    let (mut x, mut prediction, mut status) = (7.0, 7.0, 7);
    unsafe {
        assert_eq!(hyst_adaptive_init(&mut a, &p, &cfg), HYST_OK);
        assert_eq!(hyst_adaptive_init(&mut a, &p, &cfg), HYST_OK);
        assert_eq!(
            hyst_adaptive_measure(&mut a, 0.1, &mut prediction, &mut status),
            HYST_ERR_NO_COMMAND
        );
        assert_eq!((prediction, status), (7.0, 7));
        // before any command, a refused desired output leaves *x alone
        assert_eq!(
            hyst_adaptive_step(&mut a, 1.5, &mut x),
            HYST_ERR_OUT_OF_RANGE
        );
        assert_eq!(x, 7.0);
        // a few samples; the prediction and status outputs may be NULL
        x = run(&mut a, 0..200);
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
    }
    let text = unsafe { CStr::from_ptr(hyst_status_message(HYST_ERR_NO_COMMAND)) };
    assert!(text.to_str().unwrap().contains("no command"));
}

/// A NaN measurement and non-finite recorded commands are counted as bad samples and move
/// nothing: the block continues exactly as a copy that never saw them; a parameter index
/// outside 0 … 5 is refused.
#[test]
fn bad_samples_are_counted_and_move_nothing() {
    let p = saturating();
    let cfg = config();
    let mut a: hyst_adaptive = zeroed();
    let (mut x, mut prediction, mut status) = (7.0, 7.0, 7);
    let mut counts: hyst_adaptive_sample_counts = zeroed();
    unsafe {
        assert_eq!(hyst_adaptive_init(&mut a, &p, &cfg), HYST_OK);
        run(&mut a, 0..200);
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
            let mut v = 7.0;
            assert_eq!(
                hyst_adaptive_parameter(&a, which, &mut v),
                HYST_ERR_INVALID_PARAMETER
            );
            assert_eq!(v, 7.0);
        }
    }
}
