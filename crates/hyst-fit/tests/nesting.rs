//! A richer structure never ends worse than a structure it contains (docs/fitting.md, "Nested
//! starts"), in the stop form too: on a clockwise LuGre friction record, for every k2 law and
//! every pair of input and output shapings the command line offers (quadratic-exp aside, which
//! contains nothing), the training cost is at most that of each structure one step simpler
//! (`hyst_fit::smooth::contained`). Before, a tanh or Langevin shape started from an affine
//! optimum at scale 30 (which costs more than the affine fit) and crawled toward its linear
//! limit without getting back, and only one contained structure was a start: friction records
//! ended 0.1 % (tanh ψ_out) to 4 % (Langevin ψ_out with tanh ψ_in) above simpler fits.

use hyst_fit::lm::Silent;
use hyst_fit::smooth::contained;
use hyst_fit::{fit_smooth, Dataset, FitError, FitOptions, SmoothFit};
use hyst_model::{Form, K2Kind, ShapingKind, Structure};
use hyst_sim::LuGre;
use hyst_test_support::rng::XorShift64Star;
use hyst_test_support::signals::{normals, stroke};

/// Samples of the record, and whether every structure is checked: in release builds 3,000 and
/// all 50 (25–35 s); in debug builds (the workspace's `cargo test`, ten times slower: 11 min for
/// all) 1,500 and the constant k2 with affine, tanh and Langevin shapings, the pairs that ended
/// worse before.
const FULL: bool = !cfg!(debug_assertions);
const SAMPLES: usize = if FULL { 3000 } else { 1500 };

/// A seal's friction (N) along a stroke of three sines (mm), 1 kHz, 0.5 N of noise.
fn friction() -> Result<Dataset, FitError> {
    let x = stroke(SAMPLES, &mut XorShift64Star(5), 0.6, 0.8);
    let seal = LuGre {
        sigma0: 200.0,
        sigma1: 0.5,
        sigma2: 0.05,
        coulomb: 20.0,
        stiction: 26.0,
        stribeck_velocity: 2.0,
    };
    let mut f = seal
        .force(&x, 1e-3)
        .map_err(|e| FitError::Invalid(e.to_string()))?;
    for (v, e) in f.iter_mut().zip(normals(&mut XorShift64Star(105), x.len())) {
        *v += 0.5 * e;
    }
    Ok(Dataset::single(&x, &f))
}

/// Σ r² of the training errors, in output units (all weights 1).
fn cost(fit: &SmoothFit) -> f64 {
    fit.training.rms.powi(2) * fit.training.samples as f64
}

#[test]
fn every_structure_fits_stop_form_friction_at_least_as_well_as_those_it_contains(
) -> Result<(), FitError> {
    let data = friction()?;
    let options = FitOptions {
        widths: false,
        ..FitOptions::default()
    };
    let shapings: &[ShapingKind] = if FULL {
        &[
            ShapingKind::Affine,
            ShapingKind::Poly2,
            ShapingKind::Poly3,
            ShapingKind::Tanh,
            ShapingKind::Langevin,
        ]
    } else {
        &[
            ShapingKind::Affine,
            ShapingKind::Tanh,
            ShapingKind::Langevin,
        ]
    };
    let k2_laws: &[K2Kind] = if FULL {
        &[K2Kind::Constant, K2Kind::Affine]
    } else {
        &[K2Kind::Constant]
    };
    let mut fits: Vec<(Structure, f64)> = Vec::new();
    let mut failures = Vec::new();
    // Simpler structures first, so that each one's contained fits are known when it is done.
    for &k2 in k2_laws {
        for &input_shaping in shapings {
            for &output_shaping in shapings {
                let structure = Structure {
                    k2,
                    input_shaping,
                    output_shaping,
                    form: Form::Stop,
                    ..Structure::default()
                };
                let fit = fit_smooth(&data, structure, &options, &mut Silent)?;
                let c = cost(&fit);
                for simple in contained(structure) {
                    let Some(&(_, inner)) = fits.iter().find(|(s, _)| *s == simple) else {
                        return Err(FitError::Invalid(format!("{simple:?} not fitted yet")));
                    };
                    if c > inner * (1.0 + 1e-9) {
                        failures.push(format!(
                            "{k2:?} k2, in {input_shaping:?}, out {output_shaping:?}: {c} > {inner} \
                             of {:?} k2, in {:?}, out {:?}",
                            simple.k2, simple.input_shaping, simple.output_shaping
                        ));
                    }
                }
                fits.push((structure, c));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    Ok(())
}
