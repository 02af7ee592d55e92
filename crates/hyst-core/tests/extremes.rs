//! Extreme parameters and inputs: finite inputs give finite outputs or an error that leaves the
//! memory untouched; the memory never holds a NaN; subnormal parameters are refused; the band
//! |output − input| ≤ k1 holds in floating point even when k1 is below the input's spacing.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use hyst_core::{Affine, Error, Hysteresis, InverseHysteresis, Memory, Operator, ShapedModel};
use hyst_test_support::rng::{Lcg64, Random};
use proptest::prelude::*;

fn memory_is_finite<T: hyst_core::Real>(m: Option<Memory<T>>) -> bool {
    m.is_none_or(|m| {
        [
            m.reversal_input,
            m.reversal_output,
            m.last_input,
            m.last_output,
        ]
        .iter()
        .all(|v| v.is_finite())
    })
}

#[test]
fn opposite_extremes_give_finite_outputs() {
    let mut h = Hysteresis::new(0.2_f64, 8.0).unwrap();
    assert_eq!(h.try_step(1e308).unwrap(), 1e308);
    let y = h.try_step(-1e308).unwrap();
    assert!(y.is_finite() && (y - -1e308).abs() <= 0.2, "{y}");
    let y = h.try_step(1e308).unwrap();
    assert!(y.is_finite() && (y - 1e308).abs() <= 0.2, "{y}");
    assert!(memory_is_finite(h.memory()));
    let mut inv = InverseHysteresis::new(0.2_f64, 8.0).unwrap();
    for x in [1e308, -1e308, 1e308, -f64::MAX, f64::MAX] {
        let v = inv.try_step(x).unwrap();
        assert!(v.is_finite() && (v - x).abs() <= 0.2, "{x} -> {v}");
    }
    assert!(memory_is_finite(inv.memory()));
}

#[test]
fn huge_k1_k2_products_are_computed_in_the_overflow_free_form() {
    // k2 M* = 1e600: a near-backlash of half-width 1e300, almost flat near a reversal point.
    let mut h = Hysteresis::new(1e300_f64, 1e300).unwrap();
    assert_eq!(h.try_step(0.0).unwrap(), 0.0);
    let up = h.try_step(1.0).unwrap();
    assert!((0.0..=1e-15).contains(&up), "{up}");
    let down = h.try_step(-1.0).unwrap();
    assert!((-1e-15..=0.0).contains(&down), "{down}");
    assert!(memory_is_finite(h.memory()));

    let mut h = Hysteresis::new(1e10_f32, 1e30).unwrap();
    for x in [0.0_f32, 1.0, -1.0, 5.0] {
        let y = h.try_step(x).unwrap();
        assert!(y.is_finite() && y.abs() <= 1e-6, "{x} -> {y}");
    }
    assert!(memory_is_finite(h.memory()));
}

#[test]
fn an_output_beyond_the_float_range_is_an_error_that_leaves_the_memory_alone() {
    // The direct output lies between the reversal output and the input, so it never overflows;
    // the inverse's v lies within k1 of its input: falling to −MAX it would be −MAX − k1.
    let mut inv = InverseHysteresis::new(1e300_f64, 1.0).unwrap();
    inv.try_step(0.0).unwrap();
    let before = inv.memory();
    let err = inv.try_step(-f64::MAX).unwrap_err();
    assert!(matches!(err, Error::NonFiniteOutput { .. }), "{err}");
    assert_eq!(inv.memory(), before);
    assert_eq!(inv.step(-f64::MAX), 0.0); // `step` holds the last output
                                          // A finite neighbour still works.
    let v = inv.try_step(-1e307).unwrap();
    assert!(v.is_finite() && v < -1e307);
    assert!(memory_is_finite(inv.memory()));
    // ψ_out overflowing in a model: an error, memory unchanged (the C API's HYST_ERR_OVERFLOW).
    let mut m = ShapedModel::new(
        Affine::new(1.0, 0.0).unwrap(),
        Hysteresis::new(0.2_f64, 8.0).unwrap(),
        Affine::new(1e300, 0.0).unwrap(),
    )
    .unwrap();
    m.try_step(0.0).unwrap();
    let before = m.memory();
    let err = m.try_step(1e10).unwrap_err();
    assert!(matches!(err, Error::NonFiniteOutput { .. }), "{err}");
    assert_eq!(m.memory(), before);
    assert_eq!(
        err.to_string(),
        "input sample 10000000000: the output or one of its time derivatives is beyond the float \
         range (inf)"
    );
}

#[test]
fn subnormal_and_tiny_parameters_are_refused_with_the_reason() {
    let err = Hysteresis::new(0.2_f64, 1e-320).unwrap_err();
    assert!(
        err.to_string().starts_with("invalid parameter k2 = 1e-320")
            && err.to_string().contains("subnormal"),
        "{err}"
    );
    let err = InverseHysteresis::new(1e-310_f64, 1.0).unwrap_err();
    assert!(err.to_string().contains("k1 = 1e-310"), "{err}");
    let err = Hysteresis::new(1e-150_f64, 1e-150).unwrap_err();
    assert!(
        err.to_string().starts_with(
            "invalid parameters k1 = 1e-150 and k2 = 1e-150: their product k1·k2 = 1e-300 is \
             below 2.0e-292 for f64"
        ),
        "{err}"
    );
    // A product below the float range is named with its factors and its value, not as 0.
    let err = Hysteresis::new(1e-300_f64, 1e-300).unwrap_err();
    assert!(
        err.to_string().starts_with(
            "invalid parameters k1 = 1e-300 and k2 = 1e-300: their product k1·k2 = 1e-600 is"
        ),
        "{err}"
    );
    let err = Hysteresis::new(3e-160_f64, 7e-170).unwrap_err();
    assert!(err.to_string().contains("k1·k2 = 2.1e-329 is"), "{err}");
    let err = Hysteresis::new(1e-30_f32, 1e-30).unwrap_err();
    assert!(err.to_string().contains("k1·k2 = 1e-60 is"), "{err}");
    let err = Hysteresis::new(1e308_f64, 1.0).unwrap_err();
    assert!(
        err.to_string().contains("quarter of the largest float"),
        "{err}"
    );
    assert!(Hysteresis::new(f32::MIN_POSITIVE, 1e10).is_ok());
    assert!(Hysteresis::new(1e-30_f32, 1e-30).is_err());
    // Normal values that were accepted before still are.
    assert!(Hysteresis::new(1e-300_f64, 1e10).is_ok());
}

#[test]
fn f32_band_stays_bounded_when_k1_is_below_the_input_spacing() {
    let k1 = 5e-6_f32;
    let mut h = Hysteresis::new(k1, 8.0).unwrap();
    let mut inv = InverseHysteresis::new(k1, 8.0).unwrap();
    let mut rng = Lcg64::new(12345);
    let mut worst = 0.0_f64;
    for _ in 0..1_000_000 {
        let x = (((rng.next_u64() >> 40) as f32) / (1u64 << 24) as f32 - 0.5) * 2000.0;
        for y in [h.step(x), inv.step(x)] {
            let err = (f64::from(y) - f64::from(x)).abs();
            // k1 plus half the spacing of f32 at |x| + k1 (the band computed in f32).
            let half_ulp = f64::from(x.abs() + k1) * f64::from(f32::EPSILON) / 2.0;
            assert!(err <= f64::from(k1) + half_ulp, "x = {x}: |y - x| = {err}");
            worst = worst.max(err);
        }
    }
    assert!(worst < 1e-4, "{worst}");
}

fn extreme() -> impl Strategy<Value = f64> {
    prop_oneof![
        (-308.0f64..308.0).prop_map(|e| 10f64.powf(e)),
        (-308.0f64..308.0).prop_map(|e| -(10f64.powf(e))),
        -1e3f64..1e3,
        Just(f64::MAX),
        Just(-f64::MAX),
        Just(0.0),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    /// Any valid parameters, any finite inputs: finite outputs inside the band, or
    /// `NonFiniteOutput` with the memory unchanged; never a NaN in the memory.
    #[test]
    fn finite_in_finite_out_or_refused(
        k1e in -300.0f64..307.0,
        k2e in -300.0f64..308.0,
        xs in prop::collection::vec(extreme(), 1..60),
    ) {
        let (k1, k2) = (10f64.powf(k1e), 10f64.powf(k2e));
        let Ok(mut h) = Hysteresis::new(k1, k2) else { return Ok(()); };
        let mut inv = InverseHysteresis::new(k1, k2).unwrap();
        for &x in &xs {
            let before = (h.memory(), inv.memory());
            for (name, result, memory) in [
                ("direct", h.try_step(x), h.memory()),
                ("inverse", inv.try_step(x), inv.memory()),
            ] {
                match result {
                    Ok(y) => {
                        prop_assert!(y.is_finite(), "{name} {x} -> {y}");
                        let half_ulp = (x.abs() + k1) * f64::EPSILON / 2.0;
                        prop_assert!((y - x).abs() <= k1 + half_ulp, "{name} {x} -> {y}");
                    }
                    Err(Error::NonFiniteOutput { .. }) => {
                        let old = if name == "direct" { before.0 } else { before.1 };
                        prop_assert_eq!(memory, old);
                    }
                    Err(e) => prop_assert!(false, "{name} {x}: {e}"),
                }
                prop_assert!(memory_is_finite(memory));
            }
        }
    }
}
