//! When the fit stops: a structure whose best point on the data lies at a parameter's infinity
//! (a saturating ψ_in whose best shape is its linear limit) ends once the gains of its steps
//! fade below what the data can tell, not after a crawl of dozens of iterations that changes
//! nothing the data resolves.

use hyst_fit::layout::Layout;
use hyst_fit::lm::{LevenbergMarquardt, Silent, Termination};
use hyst_fit::smooth::normalisation;
use hyst_fit::{fit_smooth, Dataset, FitError, FitOptions};
use hyst_model::{ShapingKind, Structure};
use hyst_test_support::rng::XorShift64Star;
use hyst_test_support::signals::{loops as input, normals};

#[test]
fn a_langevin_input_shaping_on_data_it_cannot_bend_to_stops_when_its_gains_fade(
) -> Result<(), FitError> {
    // The truth: ψ_in = x + 0.15 x³ (normalised input), which steepens toward both ends; a
    // Langevin ψ_in only flattens toward its ends, so its best is its linear limit (scale → ∞).
    let truth_structure = Structure {
        input_shaping: ShapingKind::Poly3,
        ..Structure::default()
    };
    let x = input(4000);
    let probe = Dataset::single(&x, &vec![0.0; x.len()]);
    let layout = Layout::new(truth_structure, normalisation(&probe));
    let mut theta = layout.start();
    for (name, v) in [
        ("k1", 0.12),
        ("k2", 7.0),
        ("in.p3", 0.15),
        ("out.gain", 20.0),
        ("out.offset", -95.0),
    ] {
        let i = layout
            .index(name)
            .ok_or_else(|| FitError::Invalid(format!("no parameter {name}")))?;
        theta[i] = layout.params[i].transform.theta(v);
    }
    let model = layout.model(&theta, probe.input_range())?;
    let clean = model.run(&x)?;
    let y: Vec<f64> = clean
        .iter()
        .zip(normals(&mut XorShift64Star(7), x.len()))
        .map(|(y, e)| y + 0.05 * e)
        .collect();
    let data = Dataset::single(&x, &y);

    let langevin = Structure {
        input_shaping: ShapingKind::Langevin,
        ..Structure::default()
    };
    let fit = fit_smooth(&data, langevin, &FitOptions::default(), &mut Silent)?;
    assert_eq!(fit.termination, Termination::FadingDecrease, "{fit:?}");

    // The same fit without the offset tests (a relative offset of 0 turns both off) crawls on,
    // to a cost lower by less than the negligible gain ‖r‖² p/(n − p) · 1e-6 (with room for
    // the geometric extrapolation, which bounds the fading series, not every crawl).
    let crawl = FitOptions {
        method: LevenbergMarquardt::new().with_relative_offset(0.0)?,
        ..FitOptions::default()
    };
    let crawled = fit_smooth(&data, langevin, &crawl, &mut Silent)?;
    assert_ne!(crawled.termination, Termination::FadingDecrease);
    assert!(
        crawled.iterations > fit.iterations + 5,
        "{} iterations against {} with the rule",
        crawled.iterations,
        fit.iterations
    );
    let n = fit.training.samples as f64;
    let cost = |rms: f64| n * rms * rms;
    let p = layout_len(langevin, &data);
    let negligible = cost(fit.training.rms) * p / (n - p) * 1e-6;
    let gained = cost(fit.training.rms) - cost(crawled.training.rms);
    assert!(
        gained <= 10.0 * negligible,
        "the crawl gained {gained}, negligible is {negligible}"
    );
    Ok(())
}

/// The number of parameters of `structure` on `data`.
fn layout_len(structure: Structure, data: &Dataset) -> f64 {
    Layout::new(structure, normalisation(data)).len() as f64
}
