//! The operators' common path tests nothing before the formula: a plain sample goes
//! through Definition 2.1's memory update and eq. (2) or (4), and one band test
//! |y − x| ≤ k1 decides whether the rare path runs. These tests show that the rare path still
//! catches every case the checks before the formula caught: a non-finite input (NaN, ±∞) is
//! `NonFiniteInput` with the memory unchanged (also when it would have reversed the direction),
//! an intermediate overflow (α0 = 1e308 then α = −1e308, k2 M* beyond the float range) is
//! repaired into the band, an output beyond the float range is `NonFiniteOutput` with the memory
//! unchanged, and every output is finite and inside the band. For the direct and the inverse
//! operator, f32 and f64, and each built-in k2 law.
//!
//! The reference is [`ParametricHysteresis::peek`], which still tests the input before the
//! formula and never touches the memory: `try_step` must give the same result bit for bit.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use hyst_core::{
    AffineK2, AnyK2Law, ConstantK2, Direct, Error, Formula, Inverse, Jet, K2Law, Memory, Operator,
    ParametricHysteresis, Real,
};
use proptest::prelude::*;

/// The band of docs/reliability.md: |y − x| ≤ k1 + ½ ulp(|x| + k1).
fn in_band<T: Real>(x: T, y: T, k1: T) -> bool {
    let half_ulp = (x.abs() + k1) * T::epsilon() * T::from_f64(0.5);
    y.is_finite() && (y - x).abs() <= k1 + half_ulp
}

fn memory_is_finite<T: Real>(m: Option<Memory<T>>) -> bool {
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

/// One sample through `op`, checked against the reference (`peek`, which tests the input
/// first): the same output bit for bit or the same error; on an error the memory as it was; on
/// success the output in the band and the sample in the memory. Returns the result.
fn step_checked<T: Real, K: K2Law<T> + Clone, F: Formula>(
    op: &mut ParametricHysteresis<T, K, F>,
    x: T,
) -> Result<Result<T, Error>, TestCaseError> {
    let before = op.memory();
    let expected = op.peek(x);
    prop_assert_eq!(op.memory(), before, "peek changed the memory");
    let got = op.try_step(x);
    match (expected, got) {
        (Ok(e), Ok(g)) => {
            prop_assert_eq!(
                e.as_f64().to_bits(),
                g.as_f64().to_bits(),
                "{} {:?}",
                F::NAME,
                x
            );
            prop_assert!(in_band(x, g, op.k1()), "{} {:?} -> {:?}", F::NAME, x, g);
            let m = op.memory().unwrap();
            prop_assert!(m.last_input == x && m.last_output == g);
        }
        (Err(e), Err(g)) => {
            // Debug, not ==: the errors carry the sample, which may be NaN.
            prop_assert_eq!(format!("{e:?}"), format!("{g:?}"));
            prop_assert_eq!(op.memory(), before, "{} {:?}: {}", F::NAME, x, g);
        }
        (e, g) => prop_assert!(false, "{} {:?}: peek {:?}, try_step {:?}", F::NAME, x, e, g),
    }
    if !x.is_finite() {
        prop_assert!(
            matches!(got, Err(Error::NonFiniteInput { .. })),
            "{} {:?}: {:?}",
            F::NAME,
            x,
            got
        );
    }
    prop_assert!(memory_is_finite(op.memory()));
    Ok(got)
}

/// Runs `xs` through `op`, each sample checked by [`step_checked`]; after a refused sample, the
/// operator continues exactly as a copy that never saw it.
fn run_checked<T: Real, K: K2Law<T> + Clone, F: Formula>(
    mut op: ParametricHysteresis<T, K, F>,
    xs: &[T],
) -> Result<(), TestCaseError> {
    for &x in xs {
        let copy = op.clone();
        if step_checked(&mut op, x)?.is_err() {
            prop_assert_eq!(op.memory(), copy.memory());
        }
    }
    Ok(())
}

/// The histories a bad sample can arrive after: none, rising, falling, just reversed (each way).
fn histories<T: Real>() -> [Vec<T>; 5] {
    let v = |xs: &[f64]| xs.iter().map(|&x| T::from_f64(x)).collect::<Vec<T>>();
    [
        v(&[]),
        v(&[0.0, 0.1, 0.3]),
        v(&[0.0, -0.1, -0.3]),
        v(&[0.0, 0.5, 0.2]),
        v(&[0.0, -0.5, -0.2, -0.1]),
    ]
}

/// NaN and ±∞ after every history, for one operator: refused, memory unchanged, and the
/// operator goes on as if the sample had not come (a following finite sample gives the same
/// output as on a copy that never saw the bad one).
fn non_finite_refused<T: Real, K: K2Law<T> + Clone, F: Formula>(
    op: &ParametricHysteresis<T, K, F>,
) {
    for history in histories::<T>() {
        for bad in [T::nan(), T::infinity(), T::neg_infinity()] {
            let mut op = op.clone();
            for &x in &history {
                op.try_step(x).unwrap();
            }
            let clean = op.clone();
            let before = op.memory();
            let err = op.try_step(bad).unwrap_err();
            assert!(
                matches!(err, Error::NonFiniteInput { .. }),
                "{} {history:?} {bad:?}: {err}",
                F::NAME
            );
            assert_eq!(op.memory(), before, "{} {history:?} {bad:?}", F::NAME);
            // `step` holds the last output (or passes the input through with no history).
            let held = op.step(bad);
            let hold = before.map_or(bad, |m| m.last_output);
            assert_eq!(held.as_f64().to_bits(), hold.as_f64().to_bits());
            assert_eq!(op.memory(), before);
            let next = T::from_f64(0.05);
            let (a, b) = (
                op.try_step(next).unwrap(),
                clean.clone().try_step(next).unwrap(),
            );
            assert_eq!(a.as_f64().to_bits(), b.as_f64().to_bits());
        }
    }
}

fn laws<T: Real>() -> (ConstantK2<T>, AffineK2<T>, AnyK2Law<T>) {
    let c = |x: f64| T::from_f64(x);
    let affine = AffineK2::new(c(9.0), c(-2.0), c(5.0), c(12.0)).unwrap();
    (ConstantK2(c(8.0)), affine, AnyK2Law::Affine(affine))
}

fn non_finite_refused_for_every_law<T: Real>() {
    let k1 = T::from_f64(0.14);
    let (constant, affine, any) = laws::<T>();
    non_finite_refused(&ParametricHysteresis::<T, _, Direct>::with_k2_law(k1, constant).unwrap());
    non_finite_refused(&ParametricHysteresis::<T, _, Inverse>::with_k2_law(k1, constant).unwrap());
    non_finite_refused(&ParametricHysteresis::<T, _, Direct>::with_k2_law(k1, affine).unwrap());
    non_finite_refused(&ParametricHysteresis::<T, _, Inverse>::with_k2_law(k1, affine).unwrap());
    non_finite_refused(&ParametricHysteresis::<T, _, Direct>::with_k2_law(k1, any).unwrap());
    non_finite_refused(&ParametricHysteresis::<T, _, Inverse>::with_k2_law(k1, any).unwrap());
}

#[test]
fn non_finite_inputs_are_refused_with_the_memory_unchanged_f64() {
    non_finite_refused_for_every_law::<f64>();
}

#[test]
fn non_finite_inputs_are_refused_with_the_memory_unchanged_f32() {
    non_finite_refused_for_every_law::<f32>();
}

/// A non-finite jet (value or derivative) is still refused before the formula.
#[test]
fn non_finite_jets_are_refused() {
    let mut h = ParametricHysteresis::<f64, ConstantK2<f64>, Inverse>::new(0.14, 8.0).unwrap();
    h.try_step(Jet::<f64, 2>::from_derivatives(0.1, [1.0, 0.0]))
        .unwrap();
    let before = h.memory();
    for bad in [
        Jet::from_derivatives(f64::NAN, [1.0, 0.0]),
        Jet::from_derivatives(0.2, [f64::INFINITY, 0.0]),
    ] {
        let err = h.try_step(bad).unwrap_err();
        assert!(matches!(err, Error::NonFiniteInput { .. }), "{err}");
        assert_eq!(h.memory(), before);
    }
}

/// The intermediate overflows of docs/reliability.md, each repaired into the band (or, when the
/// output itself is beyond the float range, refused with the memory unchanged), the same as the
/// reference.
#[test]
fn overflows_are_repaired_or_refused() {
    let cases_f64: [(f64, f64, &[f64]); 5] = [
        (0.2, 8.0, &[1e308, -1e308, 1e308, -f64::MAX, f64::MAX, 0.0]),
        (1e300, 1e300, &[0.0, 1.0, -1.0, 5.0, -1e308, 1e308]),
        (0.2, 1e300, &[0.0, 1e-300, -1e-300, 1e308, -1e308]),
        (1e300, 1.0, &[0.0, -f64::MAX, -1e307, f64::MAX, 1e307]),
        (4e307, 1e-300, &[-f64::MAX, f64::MAX, 0.0, f64::MAX]),
    ];
    for (k1, k2, xs) in cases_f64 {
        let xs = xs.to_vec();
        run_checked(
            ParametricHysteresis::<f64, _, Direct>::new(k1, k2).unwrap(),
            &xs,
        )
        .unwrap();
        run_checked(
            ParametricHysteresis::<f64, _, Inverse>::new(k1, k2).unwrap(),
            &xs,
        )
        .unwrap();
    }
    let cases_f32: [(f32, f32, &[f32]); 4] = [
        (0.2, 8.0, &[3e38, -3e38, 3e38, -f32::MAX, f32::MAX]),
        (1e10, 1e30, &[0.0, 1.0, -1.0, 5.0, -3e38]),
        (5e37, 2.4e-38, &[0.0, -f32::MAX, f32::MAX, 1e38]),
        (5e-6, 8.0, &[1000.0, -1000.0, 999.99994, 1000.0]),
    ];
    for (k1, k2, xs) in cases_f32 {
        let xs = xs.to_vec();
        run_checked(
            ParametricHysteresis::<f32, _, Direct>::new(k1, k2).unwrap(),
            &xs,
        )
        .unwrap();
        run_checked(
            ParametricHysteresis::<f32, _, Inverse>::new(k1, k2).unwrap(),
            &xs,
        )
        .unwrap();
    }
    // The inverse's output beyond −MAX: refused, memory unchanged (checked in run_checked too).
    let mut inv = ParametricHysteresis::<f64, _, Inverse>::new(1e300, 1.0).unwrap();
    inv.try_step(0.0).unwrap();
    let before = inv.memory();
    let err = inv.try_step(-f64::MAX).unwrap_err();
    assert!(matches!(err, Error::NonFiniteOutput { .. }), "{err}");
    assert_eq!(inv.memory(), before);
}

/// Finite samples of every magnitude, and NaN and ±∞ among them.
fn sample() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => -2.0f64..2.0,
        2 => (-308.0f64..308.3).prop_map(|e| 10f64.powf(e)),
        2 => (-308.0f64..308.3).prop_map(|e| -(10f64.powf(e))),
        1 => Just(f64::MAX),
        1 => Just(-f64::MAX),
        1 => Just(0.0),
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
    ]
}

/// Runs `xs` through the direct and the inverse operator with parameters (k1, k2) and with an
/// affine k2 law, in `T`.
fn all_operators<T: Real>(k1: f64, k2: f64, xs: &[f64]) -> Result<(), TestCaseError> {
    let (k1, k2) = (T::from_f64(k1), T::from_f64(k2));
    let xs: Vec<T> = xs.iter().map(|&x| T::from_f64(x)).collect();
    let Ok(direct) = ParametricHysteresis::<T, ConstantK2<T>, Direct>::new(k1, k2) else {
        return Ok(());
    };
    run_checked(direct, &xs)?;
    run_checked(
        ParametricHysteresis::<T, ConstantK2<T>, Inverse>::new(k1, k2).unwrap(),
        &xs,
    )?;
    let half = T::from_f64(0.5);
    if let Ok(law) = AffineK2::new(k2, k2 * T::from_f64(0.01), k2 * half, k2 + k2) {
        if let Ok(op) = ParametricHysteresis::<T, _, Direct>::with_k2_law(k1, AnyK2Law::Affine(law))
        {
            run_checked(op, &xs)?;
            let op = ParametricHysteresis::<T, _, Inverse>::with_k2_law(k1, AnyK2Law::Affine(law));
            run_checked(op.unwrap(), &xs)?;
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    /// Any valid parameters, any samples (NaN and ±∞ among them), f64 and f32: `try_step`
    /// agrees with the reference bit for bit, refuses exactly the non-finite inputs and the
    /// outputs beyond the float range with the memory unchanged, and keeps every output in
    /// the band.
    #[test]
    fn the_rare_path_catches_what_the_checks_caught(
        k1e in -300.0f64..307.0,
        k2e in -300.0f64..308.0,
        xs in prop::collection::vec(sample(), 1..60),
    ) {
        let (k1, k2) = (10f64.powf(k1e), 10f64.powf(k2e));
        all_operators::<f64>(k1, k2, &xs)?;
        all_operators::<f32>(k1, k2, &xs)?;
    }

    /// Ordinary parameters and signals with reversals, NaN and ±∞ injected.
    #[test]
    fn ordinary_signals_with_bad_samples(
        k1 in 1e-3f64..10.0,
        k2 in 1e-2f64..1e6,
        xs in prop::collection::vec(prop_oneof![
            20 => -5.0f64..5.0,
            1 => Just(f64::NAN),
            1 => Just(f64::INFINITY),
            1 => Just(f64::NEG_INFINITY),
        ], 1..200),
    ) {
        all_operators::<f64>(k1, k2, &xs)?;
        all_operators::<f32>(k1, k2, &xs)?;
    }
}
