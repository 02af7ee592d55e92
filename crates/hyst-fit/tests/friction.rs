//! Identification of friction against position (clockwise loops) by the stop form, on LuGre
//! friction — a structure the fit does not contain (Stribeck and viscous terms depend on the
//! rate) — with measurement noise: the form is chosen from the data, the fit lands within 6 % of
//! the span and well below the plain Coulomb model, and the operator form forced onto the same
//! data is reported as degenerate instead of returned as a line.

mod common;
use common::identify;
use hyst_fit::identify::Request;
use hyst_fit::orientation::{loops, FormChoice, Orientation};
use hyst_fit::{Dataset, FitError};
use hyst_model::{Form, ModelFile};
use hyst_sim::LuGre;
use hyst_test_support::rng::XorShift64Star;
use hyst_test_support::signals::normals;

/// A piston stroke: three sines of incommensurate frequencies (mm), 1 kHz, 8 s.
fn stroke(seed: u64) -> Vec<f64> {
    hyst_test_support::signals::stroke(8000, &mut XorShift64Star(seed), 0.3, 0.4)
}

/// Friction of a seal (N) along the stroke, with 0.5 N of sensor noise.
fn record(seal: LuGre, seed: u64) -> Result<Dataset, FitError> {
    let x = stroke(seed);
    let mut f = seal
        .force(&x, 1e-3)
        .map_err(|e| FitError::Invalid(e.to_string()))?;
    for (v, e) in f
        .iter_mut()
        .zip(normals(&mut XorShift64Star(seed + 100), x.len()))
    {
        *v += 0.5 * e;
    }
    Ok(Dataset::single(&x, &f))
}

/// RMS of the best Coulomb model a · sign(ẋ) + b · x + c, as % of the output span.
fn coulomb_pct(data: &Dataset) -> f64 {
    let r = &data.records[0];
    let n = r.input.len();
    let rows: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            let d = r.input[(i + 1).min(n - 1)] - r.input[i.saturating_sub(1)];
            [d.signum(), r.input[i], 1.0]
        })
        .collect();
    // Normal equations, 3 × 3, by Cramer's rule.
    let mut a = [[0.0; 3]; 3];
    let mut b = [0.0; 3];
    for (row, y) in rows.iter().zip(&r.output) {
        for i in 0..3 {
            b[i] += row[i] * y;
            for j in 0..3 {
                a[i][j] += row[i] * row[j];
            }
        }
    }
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    let coef: Vec<f64> = (0..3)
        .map(|k| {
            let mut m = a;
            for i in 0..3 {
                m[i][k] = b[i];
            }
            det(m) / d
        })
        .collect();
    let ss: f64 = rows
        .iter()
        .zip(&r.output)
        .map(|(row, y)| (y - (0..3).map(|k| coef[k] * row[k]).sum::<f64>()).powi(2))
        .sum();
    let (lo, hi) = data.output_range();
    100.0 * (ss / n as f64).sqrt() / (hi - lo)
}

fn seals() -> [LuGre; 3] {
    [
        LuGre {
            sigma0: 200.0,
            sigma1: 0.5,
            sigma2: 0.05,
            coulomb: 20.0,
            stiction: 26.0,
            stribeck_velocity: 2.0,
        },
        LuGre {
            sigma0: 120.0,
            sigma1: 0.3,
            sigma2: 0.02,
            coulomb: 12.0,
            stiction: 15.0,
            stribeck_velocity: 4.0,
        },
        LuGre {
            sigma0: 500.0,
            sigma1: 1.0,
            sigma2: 0.08,
            coulomb: 35.0,
            stiction: 42.0,
            stribeck_velocity: 1.0,
        },
    ]
}

#[test]
fn default_fit_of_seal_friction_takes_the_stop_form_within_six_percent() -> Result<(), FitError> {
    for (k, seal) in seals().into_iter().enumerate() {
        let data = record(seal, 11 + k as u64)?;
        assert_eq!(loops(&data).orientation, Orientation::Clockwise);
        let done = identify(&data, &Request::default())?;
        let fit = done
            .smooth
            .ok_or(FitError::Invalid("no smooth fit".into()))?;
        let report = &done.report;
        assert_eq!(report.findings.orientation, Orientation::Clockwise);
        assert!(!report.findings.degenerate);
        assert_eq!(fit.model.form, Form::Stop);
        let pct = fit.training.rms_pct_span;
        let coulomb = coulomb_pct(&data);
        assert!(pct <= 6.0, "seal {k}: {pct} % of span");
        assert!(
            pct < 0.8 * coulomb,
            "seal {k}: {pct} % against Coulomb {coulomb} %"
        );
        // Its level is the sliding force, between the Coulomb and the static level (± noise).
        let level = fit
            .estimates
            .iter()
            .find(|e| e.name == "out.level")
            .map_or(f64::NAN, |e| e.value);
        assert!(
            level > 0.8 * seal.coulomb && level < 1.2 * seal.stiction,
            "seal {k}: level {level}"
        );
        // The model file holds the form (format version 3) and runs the same after reading.
        let text = report.model.to_toml()?;
        assert!(text.contains("form = \"stop\"") && text.contains("version = 3"));
        let back = ModelFile::from_toml(&text, std::path::Path::new("m.toml"))?;
        let x = &data.records[0].input;
        assert_eq!(back.run(x)?, fit.model.run(x)?);
        // It has no inverse: friction is compensated by feeding the force forward.
        match back.run_inverse(&[1.0, 2.0]) {
            Err(e) => assert!(e.to_string().contains("no inverse"), "{e}"),
            Ok(_) => return Err(FitError::Invalid("a stop form ran inverted".into())),
        }
    }
    Ok(())
}

#[test]
fn the_operator_form_forced_onto_friction_is_reported_degenerate() -> Result<(), FitError> {
    let data = record(seals()[0], 3)?;
    let request = Request {
        form: FormChoice::Operator,
        ..Request::default()
    };
    let Err(err) = identify(&data, &request) else {
        return Err(FitError::Invalid(
            "the operator form fitted friction".into(),
        ));
    };
    let message = err.to_string();
    assert!(
        matches!(err, FitError::Degenerate(_)) && message.starts_with("no hysteresis found in"),
        "{message}"
    );
    assert!(message.contains("straight line fits with RMS"), "{message}");
    assert!(message.contains("stop form"), "{message}");
    // Kept on request, and marked.
    let kept = identify(
        &data,
        &Request {
            keep_degenerate: true,
            ..request
        },
    )?;
    assert!(kept.report.findings.degenerate);
    assert!(kept.report.findings.notes[0].starts_with("no hysteresis found"));
    Ok(())
}
