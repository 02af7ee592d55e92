//! What the tests of the adaptive compensator share: a zeroed C block, the desired output, the
//! model's parameters in C and in the core, reading statuses and parameters.

use super::*;

pub(crate) fn zeroed<T>() -> T {
    // SAFETY: the C state and parameter types are plain data: all-zero bits are valid.
    unsafe { std::mem::zeroed() }
}

/// A desired output with reversals of changing amplitude and a few rests.
pub(crate) fn desired(k: usize) -> f64 {
    let block = 400;
    if (k / block) % 6 == 5 {
        return desired((k / block) * block - 1);
    }
    let t = k as f64 * 4e-3;
    (0.5 + 0.3 * (0.11 * t).sin()) * (1.7 * t).sin() + 0.2 * (4.3 * t + 1.0).sin()
}

/// The fitted model of the bit-for-bit test: polynomial ψ_in, an affine k2 law, affine ψ_out
/// with a gain and an offset, the rising start rule.
pub(crate) fn params() -> hyst_shaped_model_params {
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
pub(crate) fn core_model(gain: f64) -> AdaptiveModel<f64> {
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

pub(crate) fn status_of(s: Status) -> i32 {
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

pub(crate) fn parameter(a: *const hyst_adaptive, which: i32) -> f64 {
    let mut v = f64::NAN;
    unsafe { assert_eq!(hyst_adaptive_parameter(a, which, &mut v), HYST_OK) };
    v
}

pub(crate) fn parameter_f32(a: *const hyst_adaptive_f32, which: i32) -> f32 {
    let mut v = f32::NAN;
    unsafe { assert_eq!(hyst_adaptive_parameter_f32(a, which, &mut v), HYST_OK) };
    v
}
