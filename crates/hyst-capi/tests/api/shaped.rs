//! The shaped model, its inverse and the Lemma 5.1 compensators of the C API against the core.

use super::*;
use crate::operator::*;

pub(crate) fn params() -> hyst_shaped_model_params {
    let mut p: hyst_shaped_model_params = zeroed();
    p.k1 = 0.105;
    p.k2.kind = HYST_K2_CONSTANT;
    p.k2.value = 8.0;
    p.input = hyst_shaping {
        kind: HYST_SHAPING_POLYNOMIAL,
        p: [0.0, 1.0, -0.098, 0.0, -5.0, 5.0],
        pre_gain: 0.5,
        pre_offset: 0.1,
        post_gain: 1.0,
        post_offset: 0.0,
    };
    p.output = hyst_shaping {
        kind: HYST_SHAPING_AFFINE,
        p: [2.02, 0.3, 0.0, 0.0, 0.0, 0.0],
        pre_gain: 1.0,
        pre_offset: 0.0,
        post_gain: 1.5,
        post_offset: -0.2,
    };
    p
}

pub(crate) fn core_model(
) -> ShapedModel<f64, ScaledShaping<f64>, hyst_core::AnyK2Law<f64>, ScaledShaping<f64>> {
    let input = ScaledShaping::new(
        0.5,
        0.1,
        AnyShaping::Polynomial(Polynomial::new([0.0, 1.0, -0.098, 0.0], -5.0, 5.0).unwrap()),
        1.0,
        0.0,
    )
    .unwrap();
    let output = ScaledShaping::new(
        1.0,
        0.0,
        AnyShaping::Affine(Affine::new(2.02, 0.3).unwrap()),
        1.5,
        -0.2,
    )
    .unwrap();
    let law = hyst_core::AnyK2Law::Constant { value: 8.0 };
    ShapedModel::new(input, Hysteresis::with_k2_law(0.105, law).unwrap(), output).unwrap()
}

#[test]
fn shaped_model_and_its_inverse_equal_the_core() {
    let p = params();
    let mut m: hyst_shaped_model = zeroed();
    let mut inv: hyst_shaped_model = zeroed();
    unsafe {
        assert_eq!(hyst_shaped_model_init_direct(&mut m, &p), HYST_OK);
        assert_eq!(hyst_shaped_model_init_inverse(&mut inv, &p), HYST_OK);
    }
    let mut core = core_model();
    let mut core_inv = core.inverse();
    for k in 0..1500 {
        let x = 2.0 * signal(k);
        let (mut y, mut c) = (0.0, 0.0);
        unsafe {
            assert_eq!(hyst_shaped_model_step(&mut m, x, &mut y), HYST_OK);
            assert_eq!(hyst_shaped_model_step(&mut inv, y, &mut c), HYST_OK);
        }
        assert_eq!(y.to_bits(), core.step(x).to_bits());
        assert_eq!(c.to_bits(), core_inv.step(y).to_bits());
    }
    // Bad parameters are named by their status.
    let mut bad = p;
    bad.input.p = [0.0, 1.0, -0.098, 0.0, 0.0, 6.0]; // turns at 5.1: not monotone
    bad.input.pre_gain = 1.0;
    bad.input.pre_offset = 0.0;
    let mut other = params();
    other.output.kind = 42;
    unsafe {
        assert_eq!(
            hyst_shaped_model_init_direct(&mut m, &bad),
            HYST_ERR_NOT_MONOTONE
        );
        assert_eq!(
            hyst_shaped_model_init_direct(&mut m, &other),
            HYST_ERR_INVALID_PARAMETER
        );
        assert_eq!(
            hyst_shaped_model_init_direct(&mut m, ptr::null()),
            HYST_ERR_NULL_POINTER
        );
    }
    // Identity shaping from a zeroed struct needs its gains: refused, not silently 0.
    let mut zero_gain = params();
    zero_gain.input.kind = HYST_SHAPING_IDENTITY;
    zero_gain.input.pre_gain = 0.0;
    unsafe {
        assert_eq!(
            hyst_shaped_model_init_direct(&mut m, &zero_gain),
            HYST_ERR_INVALID_PARAMETER
        )
    };
}

#[test]
fn compensator_equals_the_core_lemma_5_1() {
    let p = params();
    let a = [0.9, 1.0];
    let v0 = [0.2, 0.0];
    let mut c: hyst_shaped_compensator = zeroed();
    unsafe {
        assert_eq!(
            hyst_shaped_compensator_init(&mut c, &p, 1.0, a.as_ptr(), v0.as_ptr(), 2),
            HYST_OK
        )
    };
    // The C API runs the core's Compensator<_, 4> with n = 2 chosen at run time: bit for bit.
    let mut core = Compensator::<f64, 4, _, _, _>::with_order(core_model().inverse(), 1.0, &a)
        .unwrap()
        .with_state([0.2, 0.0, 0.0, 0.0])
        .unwrap();
    // The const-order Compensator<_, 2> agrees to rounding: the shaping's Newton inverse on a
    // jet takes one step per order, so order 4 may move the last bit.
    let mut core2 = Compensator::from_shaped_model(&core_model(), 1.0, a)
        .unwrap()
        .with_state(v0)
        .unwrap();
    for k in 0..3000 {
        let u_new = (k as f64 * 0.004).sin() * 2.0;
        let mut u = 0.0;
        unsafe {
            assert_eq!(
                hyst_shaped_compensator_step(&mut c, u_new, 1e-3, &mut u),
                HYST_OK
            )
        };
        assert_eq!(u.to_bits(), core.step(u_new, 1e-3).to_bits(), "{k}");
        let u2 = core2.step(u_new, 1e-3);
        assert!(
            (u - u2).abs() <= 1e-12 * (1.0 + u2.abs()),
            "{k}: {u} vs {u2}"
        );
    }
    let mut v = [0.0; 2];
    unsafe {
        assert_eq!(
            hyst_shaped_compensator_get_state(&mut c, v.as_mut_ptr(), ptr::null_mut()),
            HYST_OK
        )
    };
    assert_eq!(&v[..], &core.state()[..2]);
    // Reference mode, reset, bad input.
    let reference = [0.3, 0.5, -0.1];
    let mut u = 0.0;
    unsafe {
        assert_eq!(
            hyst_shaped_compensator_track(&mut c, reference.as_ptr(), &mut u),
            HYST_OK
        );
        assert_eq!(
            u.to_bits(),
            core.track(Jet::from_derivatives(0.3, [0.5, -0.1, 0.0, 0.0]))
                .unwrap()
                .to_bits()
        );
        assert_eq!(hyst_shaped_compensator_reset(&mut c), HYST_OK);
        assert_eq!(
            hyst_shaped_compensator_get_state(&mut c, v.as_mut_ptr(), ptr::null_mut()),
            HYST_OK
        );
        assert_eq!(v, v0);
        assert_eq!(
            hyst_shaped_compensator_step(&mut c, f64::NAN, 1e-3, &mut u),
            HYST_ERR_NON_FINITE
        );
        assert_eq!(u, 0.0); // the held command: 0 after a reset
        assert_eq!(
            hyst_shaped_compensator_init(&mut c, &p, 0.0, a.as_ptr(), ptr::null(), 2),
            HYST_ERR_INVALID_PARAMETER
        );
        assert_eq!(
            hyst_shaped_compensator_init(&mut c, &p, 1.0, a.as_ptr(), ptr::null(), 5),
            HYST_ERR_LENGTH
        );
        assert_eq!(
            hyst_shaped_compensator_init(&mut c, &p, 1.0, ptr::null(), ptr::null(), 2),
            HYST_ERR_NULL_POINTER
        );
        assert_eq!(
            hyst_shaped_compensator_init(&mut c, &p, 1.0, ptr::null(), ptr::null(), 0),
            HYST_OK
        );
    }
}

#[test]
fn plain_compensator_equals_the_core_and_the_shaped_one_with_identity_shaping() {
    let a = [0.9, 1.0];
    let mut plain: hyst_compensator = zeroed();
    let mut shaped: hyst_shaped_compensator = zeroed();
    let mut p: hyst_shaped_model_params = zeroed();
    p.k1 = 0.2;
    p.k2.value = 8.0;
    for s in [&mut p.input, &mut p.output] {
        s.kind = HYST_SHAPING_IDENTITY;
        s.pre_gain = 1.0;
        s.post_gain = 1.0;
    }
    unsafe {
        assert_eq!(
            hyst_compensator_init(&mut plain, 0.2, 8.0, 1.0, a.as_ptr(), ptr::null(), 2),
            HYST_OK
        );
        assert_eq!(
            hyst_shaped_compensator_init(&mut shaped, &p, 1.0, a.as_ptr(), ptr::null(), 2),
            HYST_OK
        );
        assert_eq!(
            hyst_compensator_init(&mut plain, 0.0, 8.0, 1.0, a.as_ptr(), ptr::null(), 2),
            HYST_ERR_INVALID_PARAMETER
        );
        assert_eq!(
            hyst_compensator_init(&mut plain, 0.2, 8.0, 1.0, a.as_ptr(), ptr::null(), 5),
            HYST_ERR_LENGTH
        );
        let mut other: hyst_compensator = zeroed();
        assert_eq!(
            hyst_compensator_step(&mut other, 0.0, 1e-3, &mut 0.0),
            HYST_ERR_NOT_INITIALISED
        );
    }
    let model = ShapedModel::new(
        hyst_core::Identity,
        Hysteresis::new(0.2, 8.0).unwrap(),
        hyst_core::Identity,
    )
    .unwrap();
    let mut core = Compensator::from_shaped_model(&model, 1.0, a).unwrap();
    for k in 0..3000 {
        let u_new = 2.0 * (k as f64 * 0.004).sin();
        let (mut u, mut w) = (0.0, 0.0);
        unsafe {
            assert_eq!(
                hyst_compensator_step(&mut plain, u_new, 1e-3, &mut u),
                HYST_OK
            );
            assert_eq!(
                hyst_shaped_compensator_step(&mut shaped, u_new, 1e-3, &mut w),
                HYST_OK
            );
        }
        assert_eq!(u.to_bits(), core.step(u_new, 1e-3).to_bits(), "{k}");
        assert_eq!(u.to_bits(), w.to_bits(), "{k}");
    }
}
