//! The multi-start driver of a smooth fit ([`fit_smooth`]): the starts (a grid, the optima of
//! the simpler structures the structure contains, or the optimum of a search on a long
//! record's reduction), the descent from them on the machine's threads, then the standard
//! errors, error statistics and family widths of the best.

use std::time::Instant;

use hyst_model::{FamilyWidths, Form, SmoothModel, Structure};

use crate::data::Dataset;
use crate::error::FitError;
use crate::layout::{Layout, Normalisation};
use crate::lm::{LevenbergMarquardt, Observer, Solution, Stage, Staged};
use crate::outputs::ModelOutputs;
use crate::race::{best_of, threads};
use crate::reduction::{draw, reduce, Reduction, TARGET};
use crate::smooth::fit::{FitOptions, SmoothFit};
use crate::smooth::limits::LIMIT_SCALE;
use crate::smooth::nesting::{contained, embed, NESTED_SCALE};
use crate::smooth::problem::SmoothProblem;
use crate::smooth::starts::{grid_starts, ranked_starts, Starts};
use crate::smooth::stats::{check_finite, error_stats_of};
use crate::smooth::std_errors::estimates_at;
use crate::timed::{is_timed, static_view, TimedFindings};
use crate::widths::{confirm, family_widths};

/// The time constants τ (in sample periods) tried when a fit adds one order of dynamics: the
/// plant P(s) of the simpler fit becomes P(s)(τs + 1), which is P(s) itself for τ → 0.
const TIME_CONSTANTS: [f64; 9] = [0.3, 1.0, 3.0, 10.0, 30.0, 100.0, 300.0, 1e3, 3e3];

/// The time constant (in sample periods) of the start at the limit where a richer timed fit
/// reproduces the simpler one to rounding: a pole this fast lags the command by a thousandth
/// of a sample period.
const LIMIT_TIME_CONSTANT: f64 = 1e-3;

/// The polish of a long record on its full data stops once a Gauss–Newton step would lower χ²
/// by less than this (see [`fit_smooth`]).
const POLISH_CHI2: f64 = 0.1;

/// The normalisation of a dataset (from all its records, so that validation data uses the
/// same polynomial domains).
#[must_use]
pub fn normalisation(data: &Dataset) -> Normalisation {
    let (lo, hi) = data.input_range();
    let (ylo, yhi) = data.output_range();
    Normalisation {
        centre: 0.5 * (lo + hi),
        half_span: (0.5 * (hi - lo)).max(f64::MIN_POSITIVE),
        output_centre: 0.5 * (ylo + yhi),
        output_half_span: (0.5 * (yhi - ylo)).max(f64::MIN_POSITIVE),
    }
}

/// Fits `structure` to the training records of `data`.
///
/// # Errors
/// Bad data ([`Dataset::check`]), [`FitError::Interrupted`] when the observer stops the fit,
/// [`FitError::NoConvergence`] when no start gives a finite cost.
pub fn fit_smooth(
    data: &Dataset,
    structure: Structure,
    options: &FitOptions,
    observer: &mut dyn Observer,
) -> Result<SmoothFit, FitError> {
    fit_smooth_with(data, structure, options, observer, &mut Vec::new()).map(|(fit, _)| fit)
}

/// The fits of the structures a richer one contains, on one dataset with one set of options
/// (each with its cost Σ r²), so that a structure reached along two paths of the lattice
/// (`--k2 affine` with two shapings) is fitted once.
type Contained = Vec<(Structure, SmoothFit, f64)>;

/// [`fit_smooth`], with the fits of contained structures done so far, and the cost Σ r² of
/// the fit's training residuals (in units of the output half-span).
fn fit_smooth_with(
    data: &Dataset,
    structure: Structure,
    options: &FitOptions,
    observer: &mut dyn Observer,
    contained: &mut Contained,
) -> Result<(SmoothFit, f64), FitError> {
    let started = Instant::now();
    check_options(options)?;
    let timed = is_timed(structure);
    check_timed(data, structure)?;
    let layout = Layout::new(structure, normalisation(data));
    data.check(layout.len(), structure.form == Form::Operator)?;
    let problem = SmoothProblem::new(&layout, data, options.estimate_starts);

    // A long record is searched on its reduction (turning points and every k-th sample, exact
    // where kept: `crate::reduction`), then polished here on the full data from that optimum.
    // Not with dynamics or a rate term, which need every sample.
    let reduced = if options.estimate_starts || timed {
        None
    } else {
        reduce(data)
    };
    let (candidates, limits) = search_starts(
        &problem,
        structure,
        options,
        reduced.as_ref().map(Reduction::data),
        &mut Staged {
            inner: &mut *observer,
            stage: Stage::Search,
        },
        contained,
    )?;
    let method = polish_method(options, reduced.is_some(), layout.len())?;
    let best = descend(
        &method,
        &problem,
        candidates,
        limits,
        &mut Staged {
            inner: &mut *observer,
            stage: Stage::Polish,
        },
    )?;
    let model = layout.model(&best.theta, problem.input_range)?;
    let (estimates, statistical, correlation, allowance) =
        estimates_at(&problem, &model, &best, options)?;

    let starts = problem.bands(&model);
    // The model's outputs are replayed, not held: 8 bytes a sample beside the data.
    let outputs = ModelOutputs {
        data,
        model: &model,
        starts: starts.as_deref(),
    };
    let (training, validation) = error_stats_of(data, &outputs)?;
    let widths = widths(
        data,
        &model,
        starts.as_deref(),
        options,
        reduced.as_ref(),
        observer,
    )?;
    check_finite(
        &data.source,
        &training,
        validation.as_ref(),
        estimates.iter().map(|e| (e.name.as_str(), e.value)),
    )?;
    let cost = best.cost;
    let fit = SmoothFit {
        model,
        layout,
        theta: best.theta.clone(),
        estimates,
        statistical,
        training,
        validation,
        widths,
        iterations: best.iterations,
        termination: best.termination,
        starts,
        seconds: started.elapsed().as_secs_f64(),
        timed: None,
        correlation,
        allowance,
    };
    if timed {
        let (mut fit, cost) = timed_findings(data, fit, cost, contained, started);
        // A rate term left out: its nested fit had no widths.
        if options.widths && fit.widths.is_none() {
            fit.widths = self::widths(data, &fit.model, None, options, None, observer)?;
        }
        return Ok((fit, cost));
    }
    Ok((fit, cost))
}

/// Refuses what a fit with dynamics or a rate term cannot do: records without a sample
/// period.
fn check_timed(data: &Dataset, structure: Structure) -> Result<(), FitError> {
    if !is_timed(structure) {
        return Ok(());
    }
    if let Some(r) = data.records.iter().find(|r| r.period.is_none()) {
        return Err(FitError::Invalid(format!(
            "{}: record {} has no sample period: a model with dynamics or a rate term needs the \
             time column (--time)",
            data.source, r.id
        )));
    }
    Ok(())
}

/// The timed fit `fit` (cost `cost`) with its findings ([`TimedFindings`]) from the nested fits
/// in `contained`; a rate term the data does not support is left out: the fit without it
/// (with these findings) is returned instead.
fn timed_findings(
    data: &Dataset,
    mut fit: SmoothFit,
    cost: f64,
    contained: &Contained,
    started: Instant,
) -> (SmoothFit, f64) {
    let structure = fit.layout.structure;
    let nested = |dynamics: u8| {
        let s = Structure {
            dynamics,
            rate: None,
            ..structure
        };
        if s == structure {
            return Some((fit.clone(), cost));
        }
        contained
            .iter()
            .find(|(c, _, _)| *c == s)
            .map(|(_, f, c)| (f.clone(), *c))
    };
    let rms_by_order: Vec<f64> = (0..=structure.dynamics)
        .map(|k| nested(k).map_or(f64::NAN, |(f, _)| f.training.rms_pct_span))
        .collect();
    let with_rate = structure.rate.map(|_| fit.training);
    // Support and identification are decided on the noise's standard errors; the report
    // gives the full ones.
    let mut findings = TimedFindings::new(data, rms_by_order, &fit.statistical, with_rate);
    findings.report_errors(&fit.estimates);
    let mut nesting: Vec<(Structure, usize, f64)> = contained
        .iter()
        .filter(|(s, _, _)| {
            s.dynamics <= structure.dynamics
                && (structure.rate.is_some() || s.rate.is_none())
                && Structure {
                    dynamics: 0,
                    rate: None,
                    ..*s
                } == Structure {
                    dynamics: 0,
                    rate: None,
                    ..structure
                }
        })
        .map(|(s, f, _)| {
            // A rate term the data did not support came back left out: its own fit's error.
            match (
                &f.timed,
                f.layout.structure.rate.is_none() && s.rate.is_some(),
            ) {
                (Some(t), true) => (
                    *s,
                    f.layout.len() + 1,
                    t.rate.as_ref().map_or(f64::NAN, |r| r.rms_with),
                ),
                _ => (*s, f.layout.len(), f.training.rms_pct_span),
            }
        })
        .collect();
    nesting.push((structure, fit.layout.len(), fit.training.rms_pct_span));
    nesting.sort_by_key(|(s, _, _)| (s.dynamics, s.rate.is_some()));
    findings.nesting = nesting
        .into_iter()
        .map(|(s, parameters, rms_pct_span)| crate::timed::Nested {
            structure: crate::timed::Nested::name(s),
            parameters,
            rms_pct_span,
        })
        .collect();
    let unsupported = findings.rate.as_ref().is_some_and(|r| !r.supported);
    if unsupported {
        if let Some((mut without, c)) = nested(structure.dynamics) {
            without.timed = (structure.dynamics > 0 || findings.rate.is_some()).then_some(findings);
            without.seconds = started.elapsed().as_secs_f64();
            return (without, c);
        }
    }
    fit.timed = Some(findings);
    (fit, cost)
}

/// Refuses options a fit cannot run with: no start, a coverage outside (0, 1].
fn check_options(options: &FitOptions) -> Result<(), FitError> {
    if options.starts == 0 {
        return Err(FitError::InvalidSetting {
            name: "starts",
            value: 0.0,
            expected: "at least 1 start".into(),
        });
    }
    if !(options.coverage > 0.0 && options.coverage <= 1.0) {
        return Err(FitError::Invalid(format!(
            "coverage {} must be in (0, 1]",
            options.coverage
        )));
    }
    Ok(())
}

/// The starts of the descent on the full data, and the contained fits at their limits (see
/// [`start_candidates`]; none when the starts come from another fit): after a search on the
/// long record's reduction `reduced`, its optimum; when the fit estimates the records' starts,
/// the optimum of the fit from the start rule; otherwise [`start_candidates`].
fn search_starts(
    problem: &SmoothProblem<'_>,
    structure: Structure,
    options: &FitOptions,
    reduced: Option<&Dataset>,
    observer: &mut dyn Observer,
    contained: &mut Contained,
) -> Result<(Starts, Starts), FitError> {
    if let Some(small) = reduced {
        let search = FitOptions {
            widths: false,
            ..*options
        };
        let f = fit_smooth(small, structure, &search, observer)?;
        Ok((vec![(f64::NAN, f.theta)], Vec::new()))
    } else if options.estimate_starts {
        // The fit from the start rule first (grid, nested starts and all), then the estimated
        // starts refine its optimum: each trial of θ costs a search per history, so it runs
        // from one good start only.
        let rule = FitOptions {
            widths: false,
            estimate_starts: false,
            ..*options
        };
        let (f, _) = fit_smooth_with(problem.data, structure, &rule, observer, contained)?;
        // A timed fit may come back without a rate term the data did not support: placed
        // back at c = 0.
        let theta = if f.layout.structure == structure {
            f.theta
        } else {
            embed_timed(problem.layout, &f, 0.0)
        };
        Ok((vec![(f64::NAN, theta)], Vec::new()))
    } else {
        start_candidates(problem, structure, options, observer, contained)
    }
}

/// The method of the descent: the fit's own, or, for the polish after a search on the
/// reduction (`reduced`), one that stops once a full Gauss–Newton step would lower
/// χ² = cost / s² by less than [`POLISH_CHI2`] (of a structure with `parameters` parameters).
///
/// That is Bates and Watts' relative offset below √(0.1 / p): the step gains p · offset² in
/// units of s² = cost / (n − p). The test is a prediction, made from the Jacobian each
/// iteration computes anyway, so the polish stops without the confirming iterations a
/// cost-decrease rule needs (each a pass over the full record). Not for every fit: where the
/// optimum lies at the end of a long crawl of small steps (k2 → ∞, the stop form's Dahl limit)
/// a tolerance this loose stops far too early (MnZn with Langevin ψ_out: 2.45 % of span instead
/// of 1.22 %; a seal record: 8.5 % instead of 5.8 %, with the equivalent cost-decrease rule);
/// the polish starts at an optimum.
fn polish_method(
    options: &FitOptions,
    reduced: bool,
    parameters: usize,
) -> Result<LevenbergMarquardt, FitError> {
    if !reduced {
        return Ok(options.method);
    }
    let loose = (POLISH_CHI2 / parameters.max(1) as f64).sqrt();
    options
        .method
        .with_relative_offset(loose.max(options.method.relative_offset()))
}

/// The best solution of `method` from the starts `candidates`, run on the machine's threads
/// with the result of running them in order (each raced against the best before it:
/// `crate::race`), then from the contained fits at their `limits` where they cost less.
///
/// A contained structure that fitted better than every start of this one did: its optimum
/// is (up to a saturating shape's limit of infinite scale) a point of this structure, but
/// the starts from it ended higher (the limit's start at scale 30 costs more than the
/// contained fit, and the descent from there crawls toward the infinite scale and stops
/// on its statistical tests before it gets back to the contained cost). Then the fit
/// descends from the contained optimum placed at that limit, where it costs the same to
/// rounding, and keeps the result if it is lower: a richer structure never ends worse than
/// one it contains.
fn descend(
    method: &LevenbergMarquardt,
    problem: &SmoothProblem<'_>,
    candidates: Starts,
    limits: Starts,
    observer: &mut dyn Observer,
) -> Result<Solution, FitError> {
    let starts: Vec<Vec<f64>> = candidates.into_iter().map(|(_, theta)| theta).collect();
    let best = best_of(method, problem, &starts, threads(), observer)?;
    let mut best = best
        .filter(|b| b.cost.is_finite())
        .ok_or_else(|| FitError::NoConvergence("no starting point gave a finite cost".into()))?;
    for (cost, theta) in limits {
        if cost < best.cost {
            let f = best_of(method, problem, &[theta], 1, observer)?;
            if let Some(f) = f.filter(|f| f.cost < best.cost) {
                best = f;
            }
        }
    }
    Ok(best)
}

/// The family widths of the fitted `model` when the options ask for them: on the data from the
/// records' `starts`, or, after a search on the reduction `reduced`, searched there and then
/// checked (and widened if need be) on the full data.
fn widths(
    data: &Dataset,
    model: &SmoothModel,
    starts: Option<&[f64]>,
    options: &FitOptions,
    reduced: Option<&Reduction>,
    observer: &mut dyn Observer,
) -> Result<Option<FamilyWidths>, FitError> {
    if options.widths && model.is_timed() {
        // On the static view: the hysteresis part for the fitted plant and rate term, a static
        // dataset (searched on its reduction when it is long, as a static fit's).
        let (view, hysteresis) = static_view(data, model)?;
        let reduced = reduce(&view);
        return widths(
            &view,
            &hysteresis,
            None,
            options,
            reduced.as_ref(),
            observer,
        );
    }
    Ok(match (options.widths, reduced) {
        (false, _) => None,
        (true, None) => Some(family_widths(
            data,
            model,
            starts,
            options.coverage,
            observer,
        )?),
        // Searched on the reduction, then checked (and widened if need be) on the full data.
        (true, Some(small)) => {
            let found = match small {
                Reduction::Draw(drawn) => widths_on_draw(drawn, model, options.coverage, observer)?,
                // Turning points that are themselves many (up to `MAX_KEPT`): each of the
                // search's 50 or so coverages would run up to eight members of the family over
                // them, so the search runs on a draw of the full data instead.
                Reduction::Turning(small) if small.training_samples() > 2 * TARGET => {
                    widths_on_draw(&draw(data), model, options.coverage, observer)?
                }
                Reduction::Turning(small) => {
                    family_widths(small, model, None, options.coverage, observer)?
                }
            };
            Some(confirm(data, model, found, observer)?)
        }
    })
}

/// The family widths searched on a `draw`, at a coverage above `target` by three binomial
/// standard errors of the drawn samples' count (at most halfway to 1), so that the check on
/// the full data ([`confirm`]) seldom needs to widen them (each widening a bisection of passes
/// over every sample); when that coverage is out of reach, at `target`. The widths say
/// `target`.
fn widths_on_draw(
    draw: &Dataset,
    model: &SmoothModel,
    target: f64,
    observer: &mut dyn Observer,
) -> Result<FamilyWidths, FitError> {
    let n = draw.training_samples().max(1) as f64;
    let above = (target + 3.0 * (target * (1.0 - target) / n).sqrt()).min(0.5 * (1.0 + target));
    let found = family_widths(draw, model, None, above, observer)?;
    let found = if found.reachable {
        found
    } else {
        family_widths(draw, model, None, target, observer)?
    };
    Ok(FamilyWidths {
        coverage_target: target,
        ..found
    })
}

/// The starts of a timed structure's fit, and the contained fits at their limits (the fallback
/// of [`descend`]).
///
/// Two kinds, so that the fit finds the in-class optimum whatever the simpler fits did:
/// - **fresh starts** ([`fresh_points`]): the static fit's shapings with a grid over (k1, k2)
///   and over the plant's time constant τ (n equal poles, (τs + 1)ⁿ), c = 0, each with the
///   least-squares output gain and offset; the best `options.starts` (at least 3) by their cost.
///   They do not inherit the static optimum's k1 and k2, which a plant's lag can push to a
///   degenerate limit (a wide backlash, k2 → ∞) that the richer structure would never leave.
/// - **nested starts** from the optimum of each structure this one contains one step down
///   ([`contained_timed`], fitted first): a rate term added at c = 0; an order of dynamics added
///   as P(s)(τs + 1) for the τ of [`TIME_CONSTANTS`] (in sample periods) that cost least (at
///   most 2).
///
/// The fresh starts come first: the race (`crate::race`) then measures the nested ones against
/// the best fresh optimum, not the other way round. The limits: each contained fit at a τ of
/// [`LIMIT_TIME_CONSTANT`] and c = 0, where this structure reproduces it to rounding.
fn timed_candidates(
    problem: &SmoothProblem<'_>,
    structure: Structure,
    options: &FitOptions,
    observer: &mut dyn Observer,
    contained_fits: &mut Contained,
) -> Result<(Starts, Starts), FitError> {
    let inner = FitOptions {
        widths: false,
        ..*options
    };
    let period = problem
        .data
        .records
        .iter()
        .filter_map(|r| r.period.as_ref().map(hyst_model::TimeSteps::nominal))
        .fold(f64::INFINITY, f64::min);
    let mut nested: Starts = Vec::new();
    let mut limits: Starts = Vec::new();
    for simple in contained_timed(structure) {
        let at = fitted(problem.data, simple, &inner, observer, contained_fits)?;
        let Some((_, f, cost)) = contained_fits.get(at) else {
            continue;
        };
        limits.push((
            *cost,
            embed_timed(problem.layout, f, LIMIT_TIME_CONSTANT * period),
        ));
        if simple.dynamics == structure.dynamics {
            nested.push((f64::NAN, embed_timed(problem.layout, f, 0.0)));
            continue;
        }
        // Each start's Σ r² summed as the run goes (`Problem::cost`): no vector of every
        // residual.
        let mut ranked: Starts = TIME_CONSTANTS
            .iter()
            .filter_map(|k| {
                let theta = embed_timed(problem.layout, f, k * period);
                let c = crate::lm::Problem::cost(problem, &theta).ok()?;
                c.is_finite().then_some((c, theta))
            })
            .collect();
        ranked.sort_by(|a, b| a.0.total_cmp(&b.0));
        // At most 2: each descent is a pass of dual runs over every sample (no reduction with
        // a plant).
        ranked.truncate(options.starts.clamp(1, 2));
        nested.extend(ranked);
    }
    let static_structure = Structure {
        dynamics: 0,
        rate: None,
        ..structure
    };
    let at = fitted(
        problem.data,
        static_structure,
        &inner,
        observer,
        contained_fits,
    )?;
    let mut candidates = match contained_fits.get(at) {
        Some((_, f, _)) => ranked_starts(problem, fresh_points(problem.layout, f, period)),
        None => Vec::new(),
    };
    candidates.truncate(options.starts.max(MIN_FRESH_STARTS));
    candidates.extend(nested);
    Ok((candidates, limits))
}

/// The fresh starts a timed fit descends from at least (see [`timed_candidates`]).
const MIN_FRESH_STARTS: usize = 3;

/// The (k1, k2) of the fresh starts of a timed fit (normalised units): k1 from a narrow loop to
/// half the input range, k2 from a round loop to a near backlash.
const FRESH_K1: [f64; 5] = [0.02, 0.05, 0.1, 0.2, 0.4];
/// See [`FRESH_K1`].
const FRESH_K2: [f64; 5] = [1.0, 3.0, 10.0, 30.0, 100.0];

/// The index in `contained_fits` of the fit of `structure` on `data`, fitted now if it is not
/// there yet.
fn fitted(
    data: &Dataset,
    structure: Structure,
    options: &FitOptions,
    observer: &mut dyn Observer,
    contained_fits: &mut Contained,
) -> Result<usize, FitError> {
    if let Some(at) = contained_fits.iter().position(|(s, _, _)| *s == structure) {
        return Ok(at);
    }
    let (f, cost) = fit_smooth_with(data, structure, options, observer, contained_fits)?;
    contained_fits.push((structure, f, cost));
    Ok(contained_fits.len() - 1)
}

/// The timed structures `structure` contains one step down: without the rate term, and with
/// one order of dynamics less (keeping the rate term); each is a point of `structure` (c = 0,
/// or a time constant τ → 0).
#[must_use]
fn contained_timed(structure: Structure) -> Vec<Structure> {
    let mut out = Vec::new();
    if structure.rate.is_some() {
        out.push(Structure {
            rate: None,
            ..structure
        });
    }
    if structure.dynamics > 0 {
        out.push(Structure {
            dynamics: structure.dynamics - 1,
            ..structure
        });
    }
    out
}

/// The fit `f` of a structure contained in `layout`'s as a point θ of it: its parameters by
/// name; the rate term's c = 0 when `f` has none; its plant P(s) times (τs + 1) when it has
/// one order less (a'_i = a_i + τ a_{i−1}, a_0 = 1; P(s) itself for τ = 0).
fn embed_timed(layout: &Layout, f: &SmoothFit, tau: f64) -> Vec<f64> {
    let simple = f.layout.structure;
    // The simpler plant's a_0 = 1, a_1, …, a_{n−1}.
    let old: Vec<f64> = std::iter::once(1.0)
        .chain(
            (1..=simple.dynamics)
                .map(|i| layout_value(f, &crate::layout::dynamics_name(usize::from(i)))),
        )
        .collect();
    layout
        .params
        .iter()
        .map(|spec| {
            let value = match spec.name.strip_prefix("dynamics.a") {
                Some(i) if layout.structure.dynamics > simple.dynamics => {
                    let i: usize = i.parse().unwrap_or(1);
                    old.get(i).copied().unwrap_or(0.0)
                        + tau * old.get(i - 1).copied().unwrap_or(0.0)
                }
                _ => layout_value(f, &spec.name),
            };
            spec.transform.theta(value)
        })
        .collect()
}

/// The fresh points of a timed fit (see [`timed_candidates`]): the static fit `f`'s parameters
/// (its shapings) with (k1, k2) over [`FRESH_K1`] × [`FRESH_K2`], the plant (τs + 1)ⁿ for the τ
/// of [`TIME_CONSTANTS`] (in sample periods `period`), and c = 0.
fn fresh_points(layout: &Layout, f: &SmoothFit, period: f64) -> Vec<Vec<f64>> {
    let n = usize::from(layout.structure.dynamics);
    let taus: Vec<f64> = if n == 0 {
        vec![0.0]
    } else {
        TIME_CONSTANTS.iter().map(|k| k * period).collect()
    };
    let mut points = Vec::new();
    for &tau in &taus {
        for k1 in FRESH_K1 {
            for k2 in FRESH_K2 {
                let theta = layout
                    .params
                    .iter()
                    .map(|spec| {
                        let value = match spec.name.as_str() {
                            "k1" => k1,
                            "k2" => k2,
                            name => match name.strip_prefix("dynamics.a") {
                                Some(i) => {
                                    crate::layout::equal_poles(n, i.parse().unwrap_or(1), tau)
                                }
                                None => layout_value(f, name),
                            },
                        };
                        spec.transform.theta(value)
                    })
                    .collect();
                points.push(theta);
            }
        }
    }
    points
}

/// The value of the parameter `name` in the fit `f` (0 when it has none).
fn layout_value(f: &SmoothFit, name: &str) -> f64 {
    f.estimates
        .iter()
        .find(|e| e.name == name)
        .map_or(0.0, |e| e.value)
}

/// The starts of the least-squares method: first the optimum of the simpler structure
/// `structure` contains ([`simpler`](crate::smooth::simpler)), then the best points of a grid
/// over (k1, k2), each with the least-squares output gain and offset (`options.starts` in all;
/// [`grid_starts`]), then the optima of the other structures it contains ([`contained`]). Also,
/// for each contained structure, its cost and its optimum at the limit where this structure
/// reproduces it to rounding (for the fallback of [`descend`]).
fn start_candidates(
    problem: &SmoothProblem<'_>,
    structure: Structure,
    options: &FitOptions,
    observer: &mut dyn Observer,
    contained_fits: &mut Contained,
) -> Result<(Starts, Starts), FitError> {
    if is_timed(structure) {
        return timed_candidates(problem, structure, options, observer, contained_fits);
    }
    let mut candidates = grid_starts(problem);
    // The optima of the simpler structures this one contains: the first (along the chain of
    // [`simpler`]) is the first start, the others follow the grid's. The fit then never ends
    // worse than those simpler fits (local minima of the richer one aside; the limits below
    // take care of a saturating shape's). The first counts as one of the `starts`, the best of
    // the grid fill the rest.
    let inner = FitOptions {
        widths: false,
        ..*options
    };
    let mut nested = Vec::new();
    let mut limits = Vec::new();
    for simple in contained(structure) {
        let known = contained_fits.iter().position(|(s, _, _)| *s == simple);
        let at = if let Some(at) = known {
            at
        } else {
            let (f, cost) =
                fit_smooth_with(problem.data, simple, &inner, observer, contained_fits)?;
            contained_fits.push((simple, f, cost));
            contained_fits.len() - 1
        };
        let Some((_, f, cost)) = contained_fits.get(at) else {
            continue;
        };
        if let Some(theta) = embed(problem.layout, f, problem.input_range, NESTED_SCALE) {
            nested.push(theta);
        }
        if let Some(theta) = embed(problem.layout, f, problem.input_range, LIMIT_SCALE) {
            limits.push((*cost, theta));
        }
    }
    let first = !nested.is_empty();
    candidates.truncate(options.starts - usize::from(first && options.starts > 1));
    let mut nested = nested.into_iter();
    if let Some(theta) = nested.next() {
        candidates.insert(0, (f64::NAN, theta));
    }
    candidates.extend(nested.map(|theta| (f64::NAN, theta)));
    Ok((candidates, limits))
}
