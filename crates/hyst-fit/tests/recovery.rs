//! Recovery of known parameters from synthetic data: exact (to 1e-6) without noise, within the
//! reported standard errors with noise. The truth is a member of the fitted structure.

use hyst_fit::layout::Layout;
use hyst_fit::lm::Silent;
use hyst_fit::smooth::normalisation;
use hyst_fit::{fit_smooth, Dataset, FitError, FitOptions};
use hyst_model::{InitialState, K2Kind, ShapingKind, SmoothModel, Structure};
use hyst_test_support::rng::XorShift64Star;
use hyst_test_support::signals::{loops as input, normals};

/// The truth: `values` by parameter name, laid out for the data's normalisation.
fn truth(
    structure: Structure,
    x: &[f64],
    values: &[(&str, f64)],
) -> Result<(SmoothModel, Layout), FitError> {
    let probe = Dataset::single(x, &vec![0.0; x.len()]);
    let layout = Layout::new(structure, normalisation(&probe));
    let mut theta = layout.start();
    for (name, v) in values {
        let i = layout
            .index(name)
            .ok_or_else(|| FitError::Invalid(format!("no parameter {name}")))?;
        theta[i] = layout.params[i].transform.theta(*v);
    }
    let model = layout.model(&theta, probe.input_range())?;
    Ok((model, layout))
}

fn check_exact(structure: Structure, values: &[(&str, f64)]) -> Result<(), FitError> {
    let x = input(3000);
    let (model, _) = truth(structure, &x, values)?;
    let y = model.run(&x)?;
    let data = Dataset::single(&x, &y);
    let fit = fit_smooth(&data, structure, &FitOptions::default(), &mut Silent)?;
    for (name, v) in values {
        let e = fit
            .estimates
            .iter()
            .find(|e| e.name == *name)
            .ok_or_else(|| FitError::Invalid(format!("no estimate {name}")))?;
        let tol = 1e-6 * v.abs().max(1e-3);
        assert!(
            (e.value - v).abs() <= tol,
            "{name}: fitted {} vs true {v} ({:?}, {} iterations)",
            e.value,
            fit.termination,
            fit.iterations
        );
    }
    assert!(fit.training.rms_pct_span < 1e-6, "{:?}", fit.training);
    Ok(())
}

#[test]
fn noise_free_default_structure_is_recovered_to_1e_6() -> Result<(), FitError> {
    check_exact(
        Structure::default(),
        &[
            ("k1", 0.12),
            ("k2", 7.0),
            ("out.gain", 20.0),
            ("out.offset", -95.0),
        ],
    )
}

#[test]
fn noise_free_affine_k2_and_polynomial_shaping_are_recovered() -> Result<(), FitError> {
    let structure = Structure {
        k2: K2Kind::Affine,
        input_shaping: ShapingKind::Poly2,
        output_shaping: ShapingKind::Poly3,
        ..Structure::default()
    };
    check_exact(
        structure,
        &[
            ("k1", 0.08),
            ("k2", 6.0),
            ("k2.slope", -1.5),
            ("in.p2", -0.15),
            ("out.q2", 0.05),
            ("out.q3", -0.04),
            ("out.gain", 3.0),
            ("out.offset", 1.0),
        ],
    )
}

#[test]
fn noise_free_tanh_output_and_rising_start_are_recovered() -> Result<(), FitError> {
    let structure = Structure {
        output_shaping: ShapingKind::Tanh,
        initial_state: InitialState::Rising,
        ..Structure::default()
    };
    check_exact(structure, TANH_OUTPUT)
}

/// A tanh ψ_out's truth: slope 1.5 and level 0.2 at the centre, bending with scale 0.8.
const TANH_OUTPUT: &[(&str, f64)] = &[
    ("k1", 0.1),
    ("k2", 12.0),
    ("out.scale", 0.8),
    ("out.arg_at_centre", 0.3),
    ("out.slope", 1.5),
    ("out.level_at_centre", 0.2),
];

/// A saturating ψ_out (and ψ_in) parameterised by its slope and level at the centre of the
/// data converges quickly: with (scale, centre, gain, offset) the fit crawled along a valley
/// and took hundreds of iterations.
/// A case: ψ_in, ψ_out and the true parameter values.
type Case = (ShapingKind, ShapingKind, &'static [(&'static str, f64)]);

#[test]
fn noise_free_saturating_shapings_converge_in_few_iterations() -> Result<(), FitError> {
    let cases: [Case; 3] = [
        (ShapingKind::Affine, ShapingKind::Tanh, TANH_OUTPUT),
        (
            ShapingKind::Affine,
            ShapingKind::Langevin,
            &[
                ("k1", 0.1),
                ("k2", 12.0),
                ("out.scale", 0.4),
                ("out.arg_at_centre", -0.5),
                ("out.slope", 1.5),
                ("out.level_at_centre", 0.2),
            ],
        ),
        (
            ShapingKind::Tanh,
            ShapingKind::Affine,
            &[
                ("k1", 0.1),
                ("k2", 12.0),
                ("in.scale", 1.2),
                ("in.arg_at_centre", 0.4),
                ("out.gain", 1.5),
                ("out.offset", 0.2),
            ],
        ),
    ];
    for (input_shaping, output_shaping, values) in cases {
        let structure = Structure {
            input_shaping,
            output_shaping,
            ..Structure::default()
        };
        let x = input(3000);
        let (model, _) = truth(structure, &x, values)?;
        let y = model.run(&x)?;
        let fit = fit_smooth(
            &Dataset::single(&x, &y),
            structure,
            &FitOptions::default(),
            &mut Silent,
        )?;
        assert!(
            fit.training.rms_pct_span < 1e-6 && fit.iterations < 50,
            "{structure:?}: RMS {} % of span after {} iterations ({:?})",
            fit.training.rms_pct_span,
            fit.iterations,
            fit.termination
        );
    }
    Ok(())
}

#[test]
fn noisy_data_recovers_within_the_reported_standard_errors() -> Result<(), FitError> {
    let structure = Structure::default();
    let values = [
        ("k1", 0.12),
        ("k2", 7.0),
        ("out.gain", 20.0),
        ("out.offset", -95.0),
    ];
    let x = input(4000);
    let (model, _) = truth(structure, &x, &values)?;
    let mut within = 0;
    let mut total = 0;
    for seed in [1_u64, 2, 3, 4, 5] {
        let noise = normals(&mut XorShift64Star(0x9e37_79b9_7f4a_7c15 ^ seed), x.len());
        let y: Vec<f64> = model
            .run(&x)?
            .iter()
            .zip(&noise)
            .map(|(y, n)| y + 0.2 * n)
            .collect();
        let fit = fit_smooth(
            &Dataset::single(&x, &y),
            structure,
            &FitOptions::default(),
            &mut Silent,
        )?;
        for (name, v) in values {
            let e = fit
                .estimates
                .iter()
                .find(|e| e.name == name)
                .ok_or_else(|| FitError::Invalid(format!("no estimate {name}")))?;
            assert!(e.std_error.is_finite() && e.std_error > 0.0, "{e:?}");
            // Every estimate within 4 standard errors; about 68 % within one.
            assert!(
                (e.value - v).abs() < 4.0 * e.std_error,
                "{name}: {} ± {} vs {v}",
                e.value,
                e.std_error
            );
            total += 1;
            if (e.value - v).abs() < e.std_error {
                within += 1;
            }
        }
        // The residual RMS estimates the noise level.
        assert!((fit.training.rms - 0.2).abs() < 0.02, "{:?}", fit.training);
    }
    // 20 estimates: expect ~13.7 within 1 SE; binomial 2.5 % lower tail is about 9.
    assert!(
        within >= 9,
        "only {within} of {total} estimates within one standard error"
    );
    Ok(())
}

/// A model file of a smooth model with an affine k2, a cubic input and a Langevin output
/// shaping (a truth of 500 samples of [`input`]), and those samples.
fn langevin_model_file() -> Result<(hyst_model::ModelFile, Vec<f64>), FitError> {
    use hyst_model::{file::FORMAT, file::VERSION, Metrics, ModelKind, Provenance, Units};
    let structure = Structure {
        k2: K2Kind::Affine,
        input_shaping: ShapingKind::Poly3,
        output_shaping: ShapingKind::Langevin,
        ..Structure::default()
    };
    let x = input(500);
    let (model, _) = truth(
        structure,
        &x,
        &[
            ("k1", 0.1 + 1e-17),
            ("k2", 0.3 + 6.0),
            ("k2.slope", 0.7),
            ("in.p2", 0.1),
            ("in.p3", 0.05),
        ],
    )?;
    let file = hyst_model::ModelFile {
        format: FORMAT.into(),
        version: VERSION,
        kind: ModelKind::Smooth,
        columns: hyst_model::Columns::default(),
        units: Units::default(),
        parameters: Vec::new(),
        metrics: Metrics::default(),
        structure: Some(structure),
        smooth: Some(model),
        prandtl_ishlinskii: None,
        family: None,
        dynamics: None,
        rate: None,
        provenance: Provenance::default(),
    };
    Ok((file, x))
}

#[test]
fn model_file_reads_back_exactly() -> Result<(), FitError> {
    use hyst_model::file::VERSION;
    let (file, x) = langevin_model_file()?;
    let text = file.to_toml()?;
    let back = hyst_model::ModelFile::from_toml(&text, std::path::Path::new("m.toml"))?;
    assert_eq!(back, file);
    let a = file.run(&x)?;
    let b = back.run(&x)?;
    assert!(a.iter().zip(&b).all(|(p, q)| p.to_bits() == q.to_bits()));
    // A newer version is refused with a clear message; version 1 (no PI output polynomial)
    // still reads.
    assert!(text.contains(&format!("version = {VERSION}")));
    let newer = text.replace(
        &format!("version = {VERSION}"),
        &format!("version = {}", VERSION + 1),
    );
    let err = hyst_model::ModelFile::from_toml(&newer, std::path::Path::new("m.toml"));
    assert!(
        matches!(&err, Err(hyst_model::ModelError::File { message, .. }) if message.contains(&format!("versions 1 to {VERSION}"))),
        "{err:?}"
    );
    assert_eq!(file.required_version(), 1);
    let older = text.replace(&format!("version = {VERSION}"), "version = 1");
    let back = hyst_model::ModelFile::from_toml(&older, std::path::Path::new("m.toml"))?;
    assert_eq!(back.version, 1);
    // The comment above `version` names the version written, not the newest one known.
    assert!(text.starts_with(&format!("# hyst model file, format version {VERSION} ")));
    let written_as_1 = hyst_model::ModelFile {
        version: 1,
        ..file.clone()
    }
    .to_toml()?;
    assert!(written_as_1.starts_with("# hyst model file, format version 1 "));
    assert!(written_as_1.contains("\nversion = 1\n"));
    Ok(())
}

/// A format version of the wrong type is named with its value and line, not reported missing;
/// a float is not told to drop quotes it does not have.
#[test]
fn a_version_of_the_wrong_type_is_named_with_its_line() -> Result<(), FitError> {
    use hyst_model::file::VERSION;
    let (file, _) = langevin_model_file()?;
    let older = file
        .to_toml()?
        .replace(&format!("version = {VERSION}"), "version = 1");
    let quoted = older.replace("version = 1", "version = \"1\"");
    let err = hyst_model::ModelFile::from_toml(&quoted, std::path::Path::new("m.toml"))
        .err()
        .map(|e| e.to_string());
    assert_eq!(
        err.as_deref(),
        Some(
            "m.toml: line 3: `version = \"1\"` is a string: the format version is an integer \
             (`version = 1`, no quotes)"
        )
    );
    let float = older.replace("version = 1", "version = 1.0");
    let err = hyst_model::ModelFile::from_toml(&float, std::path::Path::new("m.toml"))
        .err()
        .map(|e| e.to_string());
    assert_eq!(
        err.as_deref(),
        Some(
            "m.toml: line 3: `version = 1.0` is a float: the format version is an integer \
             (`version = 1`, no decimal point)"
        )
    );
    Ok(())
}

/// A Langevin output shaping saturates: the model file gives the range and the limits of
/// `--saturate`; the limits are reachable with finite commands, the range's end is not, and the
/// refusal names the desired output and the range in output units.
#[test]
fn a_langevin_output_shaping_gives_the_saturation_range_and_limits() -> Result<(), FitError> {
    let (file, _) = langevin_model_file()?;
    let missing = |what: &str| FitError::Invalid(format!("the test model has no {what}"));
    let model = file.smooth.ok_or_else(|| missing("smooth model"))?;
    let sat = file
        .saturation()
        .ok_or_else(|| missing("saturating output shaping"))?;
    let psi = model.output_shaping;
    let hyst_core::AnyShaping::Langevin(l) = psi.shape else {
        return Err(missing("Langevin output shaping"));
    };
    let (lo, hi) = (
        psi.post_offset - psi.post_gain * l.gain,
        psi.post_offset + psi.post_gain * l.gain,
    );
    assert_eq!(sat.shaping, "langevin");
    assert_eq!(sat.range, (lo, hi));
    let half = 0.5 * (hi - lo);
    assert!((sat.limits.0 - (lo + 0.001 * half)).abs() < 1e-12 * half);
    assert!((sat.limits.1 - (hi - 0.001 * half)).abs() < 1e-12 * half);
    let commands = file.run_inverse(&[0.5 * (lo + hi), sat.limits.1, sat.limits.0])?;
    assert!(commands.iter().all(|c| c.is_finite()), "{commands:?}");
    let refused = file.run_inverse(&[hi]);
    assert!(
        matches!(
            refused,
            Err(hyst_model::ModelError::Core(hyst_core::Error::OutOfRange { value, min, max, .. }))
                if (value, min, max) == (hi, lo, hi)
        ),
        "{refused:?}"
    );
    Ok(())
}

#[test]
fn pi_model_file_with_output_polynomial_reads_back_exactly() -> Result<(), FitError> {
    use hyst_fit::pi_fit::fit_pi_with;
    use hyst_fit::pi_fit::PiOutputKind;
    use hyst_model::{file::FORMAT, Metrics, ModelKind, Provenance, Units};
    let x = input(3000);
    let y: Vec<f64> = x.iter().map(|v| (1.5 * v).tanh() + 0.05 * v).collect();
    let fit = fit_pi_with(&Dataset::single(&x, &y), 8, PiOutputKind::Poly3)?;
    let mut file = hyst_model::ModelFile {
        format: FORMAT.into(),
        version: 1,
        kind: ModelKind::PrandtlIshlinskii,
        columns: hyst_model::Columns::default(),
        units: Units::default(),
        parameters: fit.estimates.clone(),
        metrics: Metrics::default(),
        structure: None,
        smooth: None,
        prandtl_ishlinskii: Some(fit.model.clone()),
        family: None,
        dynamics: None,
        rate: None,
        provenance: Provenance::default(),
    };
    assert_eq!(file.required_version(), 2);
    // Written as version 1 it would be misread by a version-1 reader: refused, naming why.
    let wrong = file.to_toml()?;
    let err = hyst_model::ModelFile::from_toml(&wrong, std::path::Path::new("m.toml"));
    assert!(
        matches!(&err, Err(hyst_model::ModelError::File { message, .. }) if message.contains("[prandtl-ishlinskii.output]")),
        "{err:?}"
    );
    file.version = file.required_version();
    let text = file.to_toml()?;
    assert!(text.contains("[prandtl-ishlinskii.output]"), "{text}");
    let back = hyst_model::ModelFile::from_toml(&text, std::path::Path::new("m.toml"))?;
    assert_eq!(back, file);
    let a = file.run(&x)?;
    let b = back.run(&x)?;
    assert!(a.iter().zip(&b).all(|(p, q)| p.to_bits() == q.to_bits()));
    // The compensator read back is exact.
    let command = back.run_inverse(&y)?;
    let again = back.run(&command)?;
    for (k, (p, q)) in again.iter().zip(&y).enumerate() {
        assert!((p - q).abs() < 1e-12, "{k}: {p} vs {q}");
    }
    Ok(())
}

/// Pieces of one long noise-free record, given as independent records (as when a measurement
/// was logged in files): each starts mid-history, which no start rule describes. With
/// `estimate_starts` the truth is recovered; from the rule it is not.
#[test]
fn records_that_start_mid_history_are_recovered_with_estimated_starts() -> Result<(), FitError> {
    let structure = Structure::default();
    let x = input(3000);
    let (model, _) = truth(
        structure,
        &x,
        &[("k1", 0.2), ("k2", 6.0), ("out.gain", 20.0)],
    )?;
    let y = model.run(&x)?;
    let cuts = [0, 700, 1450, 2200, 3000];
    let records = cuts
        .windows(2)
        .enumerate()
        .map(|(id, w)| hyst_fit::Record {
            id: id as i64,
            input: x[w[0]..w[1]].into(),
            output: y[w[0]..w[1]].into(),
            weight: hyst_fit::Weights::Unit(w[1] - w[0]),
            rows: (w[0]..w[1]).collect(),
            validation: false,
            continues: false,
            period: None,
        })
        .collect();
    let data = Dataset::from_records("<memory>", Dataset::single(&x, &y).columns, records);
    let rule = fit_smooth(&data, structure, &FitOptions::default(), &mut Silent)?;
    let estimated = fit_smooth(
        &data,
        structure,
        &FitOptions {
            estimate_starts: true,
            ..FitOptions::default()
        },
        &mut Silent,
    )?;
    let k1 = |f: &hyst_fit::SmoothFit| f.model.k1;
    assert!(
        estimated.training.rms_pct_span < 0.1 * rule.training.rms_pct_span,
        "estimated {:?} rule {:?}",
        estimated.training,
        rule.training
    );
    assert!((k1(&estimated) - 0.2).abs() < 1e-3, "k1 {}", k1(&estimated));
    let starts = estimated
        .starts
        .as_ref()
        .ok_or(FitError::Invalid("no starts".into()))?;
    assert_eq!(starts.len(), 4);
    assert!(starts.iter().all(|b| (-1.0..=1.0).contains(b)));
    Ok(())
}
