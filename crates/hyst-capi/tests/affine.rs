//! `hyst_affine_model_*` and `hyst_affine_compensator_*` compute what `hyst_shaped_model_*` and
//! `hyst_shaped_compensator_*` compute for affine shapings, bit for bit, with each start rule
//! and form, in double and float; other shaping kinds are refused and leave the state as it was.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]
// The tests call the C API through raw pointers, as a C program does.
#![allow(unsafe_code)]

use hyst::api_f32::*;
use hyst::api_f64::*;
use hyst::status::*;
use hyst::{
    HYST_FORM_OPERATOR, HYST_FORM_STOP, HYST_INITIAL_STATE_FALLING, HYST_INITIAL_STATE_LINE,
    HYST_INITIAL_STATE_RISING, HYST_K2_AFFINE, HYST_SHAPING_AFFINE, HYST_SHAPING_IDENTITY,
    HYST_SHAPING_TANH,
};

fn zeroed<T>() -> T {
    // SAFETY: the C state and parameter types are plain data: all-zero bits are valid.
    unsafe { std::mem::zeroed() }
}

fn signal(k: usize) -> f64 {
    let t = k as f64 * 0.03;
    0.5 + (0.4 + 0.04 * t).min(1.3) * t.sin() + 0.25 * (2.9 * t).cos()
}

/// Affine shapings with scalings, an affine k2 law, the start rule `rule` and the form `form`.
fn params(rule: i32, form: i32) -> hyst_shaped_model_params {
    let mut p: hyst_shaped_model_params = zeroed();
    p.k1 = 0.21;
    p.k2.kind = HYST_K2_AFFINE;
    p.k2.value = 6.0;
    p.k2.slope = 1.5;
    p.k2.min = 2.0;
    p.k2.max = 9.0;
    p.input.kind = HYST_SHAPING_IDENTITY;
    p.input.pre_gain = 0.55;
    p.input.pre_offset = -0.3;
    p.input.post_gain = 1.0;
    p.output.kind = HYST_SHAPING_AFFINE;
    p.output.p[0] = 1.7;
    p.output.p[1] = 0.2;
    p.output.pre_gain = 1.1;
    p.output.post_gain = 35.0;
    p.output.post_offset = -96.0;
    p.initial_state = rule;
    p.form = form;
    p.linear = if form == HYST_FORM_STOP { 0.4 } else { 0.0 };
    p
}

fn f32_params(p: &hyst_shaped_model_params) -> hyst_shaped_model_params_f32 {
    let s = |s: &hyst_shaping| hyst_shaping_f32 {
        kind: s.kind,
        p: s.p.map(|x| x as f32),
        pre_gain: s.pre_gain as f32,
        pre_offset: s.pre_offset as f32,
        post_gain: s.post_gain as f32,
        post_offset: s.post_offset as f32,
    };
    hyst_shaped_model_params_f32 {
        k1: p.k1 as f32,
        k2: hyst_k2_law_f32 {
            kind: p.k2.kind,
            value: p.k2.value as f32,
            slope: p.k2.slope as f32,
            min: p.k2.min as f32,
            max: p.k2.max as f32,
        },
        input: s(&p.input),
        output: s(&p.output),
        initial_state: p.initial_state,
        form: p.form,
        linear: p.linear as f32,
    }
}

#[test]
fn the_linear_model_is_the_shaped_model_bit_for_bit() {
    for rule in [
        HYST_INITIAL_STATE_LINE,
        HYST_INITIAL_STATE_RISING,
        HYST_INITIAL_STATE_FALLING,
    ] {
        for (form, inverse) in [
            (HYST_FORM_OPERATOR, false),
            (HYST_FORM_OPERATOR, true),
            (HYST_FORM_STOP, false),
        ] {
            let p = params(rule, form);
            let p32 = f32_params(&p);
            let (mut lin, mut shp): (hyst_affine_model, hyst_shaped_model) = (zeroed(), zeroed());
            let (mut lin32, mut shp32): (hyst_affine_model_f32, hyst_shaped_model_f32) =
                (zeroed(), zeroed());
            unsafe {
                let (a, b, c, d) = if inverse {
                    (
                        hyst_affine_model_init_inverse(&mut lin, &p),
                        hyst_shaped_model_init_inverse(&mut shp, &p),
                        hyst_affine_model_init_inverse_f32(&mut lin32, &p32),
                        hyst_shaped_model_init_inverse_f32(&mut shp32, &p32),
                    )
                } else {
                    (
                        hyst_affine_model_init_direct(&mut lin, &p),
                        hyst_shaped_model_init_direct(&mut shp, &p),
                        hyst_affine_model_init_direct_f32(&mut lin32, &p32),
                        hyst_shaped_model_init_direct_f32(&mut shp32, &p32),
                    )
                };
                assert_eq!([a, b, c, d], [HYST_OK; 4]);
                for k in 0..800 {
                    if k == 500 {
                        assert_eq!(hyst_affine_model_reset(&mut lin), HYST_OK);
                        assert_eq!(hyst_shaped_model_reset(&mut shp), HYST_OK);
                    }
                    // The inverse takes desired outputs in the output's range.
                    let x = if inverse {
                        -96.0 + 30.0 * signal(k)
                    } else {
                        signal(k)
                    };
                    let (mut y1, mut y2, mut y3, mut y4) = (0.0, 0.0, 0.0_f32, 0.0_f32);
                    assert_eq!(hyst_affine_model_step(&mut lin, x, &mut y1), HYST_OK);
                    assert_eq!(hyst_shaped_model_step(&mut shp, x, &mut y2), HYST_OK);
                    assert_eq!(
                        hyst_affine_model_step_f32(&mut lin32, x as f32, &mut y3),
                        HYST_OK
                    );
                    assert_eq!(
                        hyst_shaped_model_step_f32(&mut shp32, x as f32, &mut y4),
                        HYST_OK
                    );
                    assert_eq!(y1.to_bits(), y2.to_bits(), "rule {rule} form {form} at {k}");
                    assert_eq!(
                        y3.to_bits(),
                        y4.to_bits(),
                        "f32 rule {rule} form {form} at {k}"
                    );
                }
            }
        }
    }
}

#[test]
fn the_linear_compensator_is_the_shaped_one_bit_for_bit() {
    let p = params(HYST_INITIAL_STATE_LINE, HYST_FORM_OPERATOR);
    let a = [0.05, 0.001];
    let (mut lin, mut shp): (hyst_affine_compensator, hyst_shaped_compensator) =
        (zeroed(), zeroed());
    unsafe {
        assert_eq!(
            hyst_affine_compensator_init(&mut lin, &p, 1.3, a.as_ptr(), std::ptr::null(), 2),
            HYST_OK
        );
        assert_eq!(
            hyst_shaped_compensator_init(&mut shp, &p, 1.3, a.as_ptr(), std::ptr::null(), 2),
            HYST_OK
        );
        for k in 0..600 {
            let u_new = if (k / 50) % 2 == 0 { 2000.0 } else { -2000.0 };
            let (mut u1, mut u2) = (0.0, 0.0);
            assert_eq!(
                hyst_affine_compensator_step(&mut lin, u_new, 1e-3, &mut u1),
                HYST_OK
            );
            assert_eq!(
                hyst_shaped_compensator_step(&mut shp, u_new, 1e-3, &mut u2),
                HYST_OK
            );
            assert_eq!(u1.to_bits(), u2.to_bits(), "at {k}");
        }
    }
}

#[test]
fn other_kinds_and_the_stop_forms_compensator_are_refused() {
    let mut p = params(HYST_INITIAL_STATE_RISING, HYST_FORM_OPERATOR);
    p.output.kind = HYST_SHAPING_TANH;
    p.output.p = [1.0, 1.0, 0.0, 0.0, 0.0, 0.0];
    let mut m: hyst_affine_model = zeroed();
    let mut c: hyst_affine_compensator = zeroed();
    unsafe {
        assert_eq!(
            hyst_affine_model_init_direct(&mut m, &p),
            HYST_ERR_INVALID_PARAMETER
        );
        // Untouched: still not initialised.
        let mut y = 0.0;
        assert_eq!(
            hyst_affine_model_step(&mut m, 0.1, &mut y),
            HYST_ERR_NOT_INITIALISED
        );
        let stop = params(HYST_INITIAL_STATE_LINE, HYST_FORM_STOP);
        let a = [0.05];
        assert_eq!(
            hyst_affine_compensator_init(&mut c, &stop, 1.0, a.as_ptr(), std::ptr::null(), 1),
            HYST_ERR_INVALID_PARAMETER
        );
        let rising = params(HYST_INITIAL_STATE_RISING, HYST_FORM_OPERATOR);
        assert_eq!(
            hyst_affine_compensator_init(&mut c, &rising, 1.0, a.as_ptr(), std::ptr::null(), 1),
            HYST_ERR_INVALID_PARAMETER
        );
        assert_eq!(
            hyst_affine_model_init_inverse(
                &mut m,
                &params(HYST_INITIAL_STATE_LINE, HYST_FORM_STOP)
            ),
            HYST_ERR_INVALID_PARAMETER
        );
    }
}

/// The old `hyst_linear_*` names (deprecated) are the affine model's: the same results, bit for
/// bit, on the same state types.
#[test]
#[allow(deprecated)]
fn the_old_linear_names_run_the_affine_model() {
    use hyst::api_f64::deprecated::*;
    let p = params(HYST_INITIAL_STATE_RISING, HYST_FORM_OPERATOR);
    let mut new: hyst_affine_model = zeroed();
    let mut old: hyst_linear_model = zeroed();
    unsafe {
        assert_eq!(hyst_affine_model_init_inverse(&mut new, &p), HYST_OK);
        assert_eq!(hyst_linear_model_init_inverse(&mut old, &p), HYST_OK);
    }
    for k in 0..500 {
        let desired = -96.0 + 20.0 * signal(k);
        let (mut a, mut b) = (f64::NAN, f64::NAN);
        unsafe {
            let sa = hyst_affine_model_step(&mut new, desired, &mut a);
            let sb = hyst_linear_model_step(&mut old, desired, &mut b);
            assert_eq!(sa, sb, "sample {k}");
        }
        assert_eq!(a.to_bits(), b.to_bits(), "sample {k}");
    }
}
