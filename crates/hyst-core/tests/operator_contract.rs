//! The contract of the one stepping interface, [`Operator`], checked on every implementor in the
//! core: a refused sample leaves the memory untouched and `step` holds the last output; a saved
//! memory resumes bit for bit; `reset` returns to the start; `process` is `step` over a block;
//! a jet's value is the plain evaluation's, bit for bit.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use hyst_core::{
    Affine, AffineK2, Error, Hysteresis, InverseHysteresis, Jet, Operator, Play, Polynomial,
    PrandtlIshlinskii, ShapedModel, ShapedPrandtlIshlinskii, Tanh,
};

/// A signal with growing amplitude and minor loops.
fn signal(k: usize) -> f64 {
    let t = k as f64 * 0.037;
    (0.3 + 0.05 * t).min(1.2) * t.sin() + 0.2 * (3.1 * t).cos()
}

fn check<O: Operator<f64> + Clone>(name: &str, fresh: O, scale: f64) {
    let x = |k: usize| scale * signal(k);
    let mut op = fresh.clone();
    assert_eq!(
        op.last_output(),
        None,
        "{name}: output before the first sample"
    );

    // Refused samples: memory untouched, step holds the last output.
    let first = op.step(x(0));
    assert_eq!(op.last_output(), Some(first), "{name}");
    for k in 1..100 {
        op.step(x(k));
    }
    let saved = op.memory();
    let last = op.last_output();
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert!(
            matches!(op.try_step(bad), Err(Error::NonFiniteInput { .. })),
            "{name}"
        );
        assert_eq!(op.memory(), saved, "{name}: memory changed by {bad}");
        assert_eq!(Some(op.step(bad)), last, "{name}: step({bad}) must hold");
    }
    let jet_nan = Jet::<f64, 2>::from_derivatives(x(100), [f64::NAN, 0.0]);
    assert!(op.try_step(jet_nan).is_err(), "{name}: NaN derivative");
    assert_eq!(op.memory(), saved, "{name}");

    // Save and restore: the continuation is the same, bit for bit.
    let ahead: Vec<f64> = (100..160).map(|k| op.step(x(k))).collect();
    let mut other = fresh.clone();
    other.step(x(7)); // some other history
    other.set_memory(saved.clone()).unwrap();
    let again: Vec<f64> = (100..160).map(|k| other.step(x(k))).collect();
    assert_eq!(
        ahead.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
        again.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
        "{name}: restored memory"
    );

    // Reset: the same as a fresh operator.
    op.reset();
    let mut new = fresh.clone();
    for k in 0..60 {
        assert_eq!(op.step(x(k)).to_bits(), new.step(x(k)).to_bits(), "{name}");
    }

    // Jets: the value is the plain evaluation's, and a constant jet has zero derivatives.
    let mut plain = fresh.clone();
    let mut jets = fresh.clone();
    for k in 0..200 {
        let v = x(k);
        let d = scale * (signal(k + 1) - signal(k)) / 0.037;
        let y = jets
            .try_step(Jet::<f64, 2>::from_derivatives(v, [d, 0.0]))
            .unwrap();
        assert_eq!(
            y.value().to_bits(),
            plain.step(v).to_bits(),
            "{name}: k {k}"
        );
    }

    // process == step over a block; a length mismatch is refused before anything happens.
    let input: Vec<f64> = (0..300).map(x).collect();
    let mut a = fresh.clone();
    let mut out = vec![0.0; input.len()];
    a.process(&input, &mut out).unwrap();
    let mut b = fresh.clone();
    let stepped: Vec<f64> = input.iter().map(|v| b.step(*v)).collect();
    assert_eq!(out, stepped, "{name}: process");
    let before = a.memory();
    let mut short = vec![0.0; 3];
    assert!(matches!(
        a.process(&input, &mut short),
        Err(Error::LengthMismatch {
            input: 300,
            output: 3
        })
    ));
    assert_eq!(a.memory(), before, "{name}");
    let mut in_place = input.clone();
    fresh.clone().process_in_place(&mut in_place);
    assert_eq!(in_place, stepped, "{name}: process_in_place");
}

#[test]
fn every_core_operator_keeps_the_contract() -> Result<(), Error> {
    check("Hysteresis", Hysteresis::new(0.2, 8.0)?, 1.0);
    check("InverseHysteresis", InverseHysteresis::new(0.2, 8.0)?, 1.0);
    check(
        "Hysteresis with affine k2",
        Hysteresis::with_k2_law(0.105, AffineK2::new(9.0, -2.0, 5.0, 12.0)?)?,
        1.0,
    );
    check("near-backlash Hysteresis", Hysteresis::new(0.2, 1e9)?, 1.0);
    let model = ShapedModel::new(
        Polynomial::new([0.0, 1.0, -0.098, 0.0], -5.0, 5.0)?,
        Hysteresis::new(0.105, 8.0)?,
        Affine::new(2.02, 0.1)?,
    )?;
    check("ShapedModel", model, 1.0);
    check("InverseShapedModel", model.inverse(), 1.0);
    let saturating = ShapedModel::new(
        Affine::new(1.0, 0.0)?,
        Hysteresis::new(0.1, 5.0)?,
        Tanh::new(3.0, 2.0)?,
    )?;
    check("InverseShapedModel through tanh", saturating.inverse(), 1.0);
    check("Play", Play::new(0.15)?, 1.0);
    let pi = PrandtlIshlinskii::<f64, 8>::new(0.4, &[0.1, 0.25, 0.5], &[0.5, 0.3, 0.2], 0.1)?;
    check("PrandtlIshlinskii", pi, 1.0);
    check("inverse PrandtlIshlinskii", pi.inverse()?, 1.0);
    let shaped =
        ShapedPrandtlIshlinskii::new(pi, Polynomial::new([0.2, 1.0, -0.1, 0.03], -3.0, 4.0)?)?;
    check("ShapedPrandtlIshlinskii", shaped, 1.0);
    check("InverseShapedPrandtlIshlinskii", shaped.inverse()?, 1.0);
    Ok(())
}

#[test]
fn a_memory_outside_the_band_is_refused_and_changes_nothing() -> Result<(), Error> {
    let mut h = Hysteresis::new(0.2_f64, 8.0)?;
    h.step(0.3);
    let saved = h.memory();
    let mut bad = saved.unwrap();
    bad.reversal_output = bad.reversal_input + 0.5;
    assert!(matches!(
        h.set_memory(Some(bad)),
        Err(Error::StateOutsideBand { .. })
    ));
    assert_eq!(h.memory(), saved);
    let mut play = Play::new(0.1_f64)?;
    assert!(play.set_memory(Some(f64::NAN)).is_err());
    assert_eq!(play.memory(), None);
    Ok(())
}
