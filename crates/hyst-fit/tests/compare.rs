//! `--compare` (the smooth model and the Prandtl–Ishlinskii baseline side by side) on clockwise
//! loops, which a Prandtl–Ishlinskii model cannot make: the smooth fit is kept, with a note,
//! instead of the whole command failing on the baseline.

mod common;
use common::identify;
use hyst_fit::identify::Request;
use hyst_fit::{Dataset, FitError};
use hyst_model::ModelKind;

/// Dahl friction (N) along a stroke of two sines (mm): dF = σ dx (1 − F/Fc · sign dx).
fn dahl() -> Dataset {
    let x: Vec<f64> = (0..4000)
        .map(|k| {
            let t = k as f64 * 1e-3;
            5.0 * (2.0 * std::f64::consts::PI * 0.7 * t).sin()
                + 2.0 * (2.0 * std::f64::consts::PI * 1.9 * t).sin()
        })
        .collect();
    let (sigma, fc) = (40.0, 20.0);
    let mut f = 0.0_f64;
    let mut last = x[0];
    let y: Vec<f64> = x
        .iter()
        .map(|&v| {
            let dx = v - last;
            last = v;
            f += sigma * dx * (1.0 - f / fc * dx.signum());
            f
        })
        .collect();
    Dataset::single(&x, &y)
}

#[test]
fn compare_on_clockwise_loops_keeps_the_smooth_fit() -> Result<(), FitError> {
    let data = dahl();
    let request = Request {
        compare: true,
        ..Request::default()
    };
    let done = identify(&data, &request)?;
    assert_eq!(done.report.model.kind, ModelKind::Smooth);
    assert!(done.pi.is_none());
    assert_eq!(done.report.comparison.len(), 1);
    assert!(
        done.report
            .findings
            .notes
            .iter()
            .any(|n| n.starts_with("no Prandtl–Ishlinskii comparison")),
        "{:?}",
        done.report.findings.notes
    );
    // The baseline alone is still refused, with the reason.
    let pi = Request {
        kind: ModelKind::PrandtlIshlinskii,
        ..Request::default()
    };
    let Err(err) = identify(&data, &pi) else {
        return Err(FitError::Invalid("PI fitted a clockwise loop".into()));
    };
    assert!(err.to_string().contains("run clockwise"), "{err}");
    Ok(())
}

/// A butterfly (magnetostriction's strain, even in the field, shifted between the branches),
/// with the field biased so that the output rises overall: refused as not monotone, not fitted
/// with a confident report; kept on request, marked degenerate.
#[test]
fn a_butterfly_is_refused_unless_kept() -> Result<(), FitError> {
    let h: Vec<f64> = (0..4000)
        .map(|k| 0.2 + (k as f64 * 2.0 * std::f64::consts::PI / 1000.0).sin())
        .collect();
    let strain: Vec<f64> = (0..h.len())
        .map(|i| {
            let rising = i + 1 < h.len() && h[i + 1] > h[i];
            // Rising below falling on the larger (positive) side: counterclockwise overall.
            let s = if rising { -0.1 } else { 0.1 };
            1000.0 * (h[i] + s) * (h[i] + s)
        })
        .collect();
    let data = Dataset::single(&h, &strain);
    let Err(err) = identify(&data, &Request::default()) else {
        return Err(FitError::Invalid("a butterfly was fitted".into()));
    };
    assert!(matches!(err, FitError::Degenerate(_)), "{err}");
    assert!(err.to_string().contains("not monotone"), "{err}");
    let kept = identify(
        &data,
        &Request {
            keep_degenerate: true,
            ..Request::default()
        },
    )?;
    assert!(kept.report.findings.degenerate);
    Ok(())
}
