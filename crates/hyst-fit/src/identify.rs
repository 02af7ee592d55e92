//! Identification as one call: fit the requested model kind (and, for a comparison, the other),
//! measure how fast the result runs, and assemble the model file and the report. `hyst fit` and
//! the Python binding's `hyst.fit` both go through [`identify`], so they fit the same way and
//! print the same words.

use std::time::{Duration, Instant};

use hyst_io::number::sig;
use hyst_model::file::{FORMAT, MIN_VERSION};
use hyst_model::{
    Choice, Form, InitialState, Metrics, ModelFile, ModelKind, Provenance, Structure, Units,
};

use crate::data::Dataset;
use crate::degeneracy::{diagnose, Diagnosis, DRIFT_NOTE, RATE_NOTE};
use crate::error::FitError;
use crate::lm::Observer;
use crate::orientation::{against_trend, loops, FormChoice, Orientation, StartChoice};
use crate::outputs::ModelOutputs;
use crate::pi_fit::{fit_pi_with, PiFit, PiOutputKind};
use crate::report::{Findings, Report, Summary};
use crate::smooth::driver::fit_smooth;
use crate::smooth::fit::{FitOptions, SmoothFit};
use crate::smooth::limits::ParameterLimit;
use crate::timed::{static_view, OrderTried, MAX_AUTO_ORDER, MIN_IMPROVEMENT};

/// The branch gap (fraction of the output span) above which the data's loops are clockwise
/// beyond doubt, and a Prandtl–Ishlinskii fit (counterclockwise only) is refused.
const PI_CLOCKWISE_GAP: f64 = 0.005;

/// Above this share of the output span going back against its trend along the branches
/// ([`against_trend`]), counterclockwise or loop-free data is not monotone: refused. Measured:
/// 0 on every counterclockwise record tried (piezo, FORC, B-H loops, backlash, creep), 0.05 on
/// pure noise; butterflies 0.29–0.97 (the less, the more the field is biased to one side).
pub const FOLD_LIMIT: f64 = 0.2;

/// The same for clockwise loops (friction's branches are flat with stiction peaks).
pub const FOLD_LIMIT_CLOCKWISE: f64 = 0.8;

/// What to identify: the model kind with its structure, and the fit's options.
#[derive(Clone, Debug)]
pub struct Request {
    /// The model kind written to the model file.
    pub kind: ModelKind,
    /// Also fit the other kind and report both side by side.
    pub compare: bool,
    /// The smooth model's structure; its `form` is replaced by [`Request::form`]'s choice.
    pub structure: Structure,
    /// The smooth model's form: from the data's loop orientation (`Auto`), or given.
    pub form: FormChoice,
    /// How each record starts: from the data (`Auto`: `falling` for records that only rise),
    /// or given; it replaces the structure's `initial_state`.
    pub start: StartChoice,
    /// Keep a fit that found no hysteresis ([`crate::degeneracy`]) instead of failing with
    /// [`FitError::Degenerate`]; the report then says `degenerate`.
    pub keep_degenerate: bool,
    /// The smooth fit's options (starts, coverage of the family widths, …).
    pub options: FitOptions,
    /// Plays of the Prandtl–Ishlinskii model (1 ..= [`hyst_model::pi::MAX_PLAYS`]).
    pub plays: usize,
    /// The Prandtl–Ishlinskii model's output polynomial.
    pub pi_output: PiOutputKind,
    /// Units of the input and output columns (for the model file and the report).
    pub units: Units,
}

impl Default for Request {
    fn default() -> Self {
        Self {
            kind: ModelKind::Smooth,
            compare: false,
            structure: Structure::default(),
            form: FormChoice::Auto,
            start: StartChoice::Auto,
            keep_degenerate: false,
            options: FitOptions::default(),
            plays: 16,
            pi_output: PiOutputKind::None,
            units: Units::default(),
        }
    }
}

/// The result of [`identify`]: the fits made, the model file and the report.
#[derive(Debug)]
pub struct Identified {
    /// The smooth fit (when the kind is smooth, or with `compare`).
    pub smooth: Option<SmoothFit>,
    /// The Prandtl–Ishlinskii fit (when that is the kind, or with `compare`).
    pub pi: Option<PiFit>,
    /// The report, holding the model file of the requested kind (`report.model`).
    pub report: Report,
}

/// At most this many samples (the records' first ones) are timed by [`ns_per_sample`]: the cost
/// per sample does not depend on the record's length, and a long record would otherwise add a
/// whole run of the model to the fit.
const TIMED_SAMPLES: usize = 1 << 16;

/// How long [`ns_per_sample`] repeats the model: the report prints 3 digits, and 10 ms of runs
/// (over 10⁵ samples on a slow machine) hold them within the load's noise; 50 ms cost a tenth
/// of an 8k fit.
const TIMED_FOR: Duration = Duration::from_millis(10);

/// Mean evaluation time per sample of `run` over the records' first [`TIMED_SAMPLES`] samples
/// (repeated for ≥ [`TIMED_FOR`] and ≥ 3 rounds), in ns.
fn ns_per_sample(data: &Dataset, run: impl Fn(&[f64]) -> Option<Vec<f64>>) -> f64 {
    let mut budget = TIMED_SAMPLES;
    let mut inputs: Vec<&[f64]> = Vec::new();
    for r in &data.records {
        let take = r.input.len().min(budget);
        if take > 0 {
            inputs.push(&r.input[..take]);
            budget -= take;
        }
    }
    let samples: usize = inputs.iter().map(|x| x.len()).sum();
    let started = Instant::now();
    let mut rounds = 0usize;
    while rounds < 3 || started.elapsed() < TIMED_FOR {
        for x in &inputs {
            std::hint::black_box(run(std::hint::black_box(x)));
        }
        rounds += 1;
    }
    started.elapsed().as_secs_f64() * 1e9 / (samples * rounds).max(1) as f64
}

/// The model file's provenance of a fit made now by `command` of the data `file` with its
/// `rows`: this version of hyst and the time (Unix seconds); [`identify`] adds the records,
/// the caller the data's size and hash.
#[must_use]
pub fn provenance(file: String, rows: usize, command: String) -> Provenance {
    Provenance {
        file,
        rows,
        command,
        hyst_version: env!("CARGO_PKG_VERSION").to_string(),
        created_unix: std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs()),
        ..Provenance::default()
    }
}

/// Fits `data` as `request` asks and assembles the model file and report.
///
/// `observer` sees the smooth fit's progress and may stop it; `interrupted` is asked between
/// the steps (a stop gives [`FitError::Interrupted`]). `provenance` goes into the model file
/// as given, except `records` and `validation_records`, which come from `data`. The report's
/// `model_file` and `plots` are left empty for the caller to fill in.
///
/// # Errors
/// The fits' errors (bad data, invalid settings, [`FitError::Interrupted`]); for the
/// Prandtl–Ishlinskii fit, an invalid `plays` names the setting `plays`.
pub fn identify(
    data: &Dataset,
    request: &Request,
    observer: &mut dyn Observer,
    interrupted: &dyn Fn() -> bool,
    provenance: Provenance,
) -> Result<Identified, FitError> {
    if request.kind == ModelKind::PrandtlIshlinskii && crate::timed::is_timed(request.structure) {
        return Err(FitError::Invalid(
            "dynamics and rate terms belong to the smooth model: fit it (--model-kind smooth), \
             or leave out --dynamics and --rate-term for the Prandtl–Ishlinskii model"
                .into(),
        ));
    }
    let want_smooth = request.kind == ModelKind::Smooth || request.compare;
    let timed = crate::timed::is_timed(request.structure) || request.options.auto_dynamics;
    let mut notes = data.notes.clone();
    let Settled {
        smooth,
        data: settled,
        not_monotone,
        want_pi,
        found,
    } = if request.options.auto_dynamics && want_smooth {
        fit_auto_order(data, request, observer, &mut notes)?
    } else {
        fit_smooth_settled(data, request, want_smooth, observer, &mut notes)?
    };
    let data = settled.as_ref().unwrap_or(data);
    if interrupted() {
        return Err(FitError::Interrupted);
    }
    let not_monotone = not_monotone
        || match &smooth {
            Some(f) if timed => check_view_monotone(data, request, f, &mut notes)?,
            _ => false,
        };
    let pi = if want_pi {
        Some(fit_pi_with(data, request.plays, request.pi_output)?)
    } else {
        None
    };
    // Did the requested model find hysteresis at all?
    let diagnosis = diagnose_requested(data, request, &smooth, &pi, found.orientation, &mut notes)?;
    residual_notes(&diagnosis, &mut notes);
    let (out_lo, out_hi) = data.output_range();
    if diagnosis.degenerate {
        let message = diagnosis.message(&data.source, &request.units.output, out_hi - out_lo);
        if !request.keep_degenerate {
            return Err(FitError::Degenerate(format!(
                "{message}. No model file was written; pass --keep-degenerate to keep it"
            )));
        }
        notes.insert(0, message);
    }
    let smooth_summary = smooth.as_ref().map(|f| smooth_summary(data, f));
    let pi_summary = pi.as_ref().map(|f| pi_summary(data, f));
    let model = match (request.kind, &smooth, &smooth_summary, &pi, &pi_summary) {
        (ModelKind::Smooth, Some(f), Some(s), _, _) => {
            model_file(request, data, Fitted::Smooth(f), s, provenance)
        }
        (ModelKind::PrandtlIshlinskii, _, _, Some(f), Some(s)) => {
            model_file(request, data, Fitted::PrandtlIshlinskii(f), s, provenance)
        }
        _ => return Err(not_fitted()),
    };
    if interrupted() {
        return Err(FitError::Interrupted);
    }
    let (lo, hi) = data.output_range();
    let comparison = if request.compare {
        smooth_summary.into_iter().chain(pi_summary).collect()
    } else {
        Vec::new()
    };
    Ok(Identified {
        smooth,
        pi,
        report: Report {
            model_file: String::new(),
            input_units: hyst_model::input_units(&model),
            model,
            output_span: hi - lo,
            findings: Findings {
                orientation: found.orientation,
                loop_gap: found.gap,
                degenerate: diagnosis.degenerate || not_monotone,
                notes,
            },
            comparison,
            plots: Vec::new(),
        },
    })
}

/// The smooth fit of `structure`. With a rate term and the form left to the data, both forms
/// are fitted and the better kept: a viscous force turns the loops of the data clockwise
/// whatever the hysteresis underneath, so the loop orientation no longer tells the form (a
/// note says when the fit overrules it).
fn fit_smooth_form(
    data: &Dataset,
    request: &Request,
    structure: Structure,
    observer: &mut dyn Observer,
    notes: &mut Vec<String>,
) -> Result<SmoothFit, FitError> {
    let fit = fit_smooth(data, structure, &request.options, observer)?;
    if structure.rate.is_none() || request.form != FormChoice::Auto {
        return Ok(fit);
    }
    let other = Structure {
        form: match structure.form {
            Form::Operator => Form::Stop,
            Form::Stop => Form::Operator,
        },
        ..structure
    };
    let Ok(alternative) = fit_smooth(data, other, &request.options, observer) else {
        return Ok(fit);
    };
    if alternative.training.rms < fit.training.rms {
        notes.push(format!(
            "with the rate term, the {} form fits better than the {} form the loops' orientation \
             suggests (training RMS {} % against {} % of span): kept (give --form to choose)",
            other.form.name(),
            structure.form.name(),
            sig(alternative.training.rms_pct_span, 3),
            sig(fit.training.rms_pct_span, 3)
        ));
        return Ok(alternative);
    }
    Ok(fit)
}

/// `--dynamics auto`: [`fit_smooth_settled`] for the plant orders 0, 1, … up to
/// [`MAX_AUTO_ORDER`] (with the request's rate term), stopping once an order lowers neither
/// the training error by [`MIN_IMPROVEMENT`] nor the validation error; the order the
/// validation records prefer, or else the lowest information criterion
/// ([`OrderTried::choose`]), is kept, and its notes and the table of the orders tried are the
/// report's.
fn fit_auto_order(
    data: &Dataset,
    request: &Request,
    observer: &mut dyn Observer,
    notes: &mut Vec<String>,
) -> Result<Settled, FitError> {
    let mut tried: Vec<OrderTried> = Vec::new();
    let mut fits: Vec<(Settled, Vec<String>)> = Vec::new();
    // Each order's training samples and its residuals' correlation time.
    let mut times: Vec<(f64, f64)> = Vec::new();
    for order in 0..=MAX_AUTO_ORDER {
        let request = Request {
            structure: Structure {
                dynamics: order,
                ..request.structure
            },
            options: FitOptions {
                auto_dynamics: false,
                ..request.options
            },
            ..request.clone()
        };
        let mut own = Vec::new();
        let settled = fit_smooth_settled(data, &request, true, observer, &mut own)?;
        let Some(f) = settled.smooth.as_ref() else {
            break;
        };
        times.push((
            f.training.samples.max(1) as f64,
            f.correlation.time.max(1.0),
        ));
        let this = OrderTried {
            order,
            parameters: f.layout.len(),
            training: f.training.rms_pct_span,
            validation: f.validation.map(|v| v.rms_pct_span),
            criterion: f64::NAN,
        };
        let better = tried.last().is_none_or(|last| {
            this.training <= (1.0 - MIN_IMPROVEMENT) * last.training
                || matches!((this.validation, last.validation), (Some(v), Some(w)) if v < w)
        });
        tried.push(this);
        fits.push((settled, own));
        if !better {
            break;
        }
    }
    // One count of independent samples for every order, that of the whitest residuals (the
    // richest fit's, as a rule): criteria over different counts do not compare.
    let (n, time) = times
        .iter()
        .copied()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((1.0, 1.0));
    let effective = (n / time).max(1.0);
    for t in &mut tried {
        t.criterion = effective * t.training.powi(2).ln() + t.parameters as f64 * effective.ln();
    }
    let kept = OrderTried::choose(&tried).unwrap_or(0);
    let by_validation = tried.iter().any(|t| t.validation.is_some());
    let at = tried.iter().position(|t| t.order == kept).unwrap_or(0);
    let note = OrderTried::note(&tried, kept, by_validation);
    let Some((settled, own)) = fits.into_iter().nth(at) else {
        return Err(not_fitted());
    };
    notes.extend(own);
    notes.push(note);
    Ok(settled)
}

/// The fold pre-check of a timed fit `f`, on its static view (the plant's output v against the
/// output less the rate term): [`check_monotone`] of what the hysteresis sees.
fn check_view_monotone(
    data: &Dataset,
    request: &Request,
    f: &SmoothFit,
    notes: &mut Vec<String>,
) -> Result<bool, FitError> {
    if !f.model.is_timed() {
        return Ok(false);
    }
    let (view, _) = static_view(data, &f.model)?;
    let orientation = loops(&view).orientation;
    check_monotone(&view, request, orientation, notes)
}

/// What [`fit_smooth_settled`] gives: the smooth fit (when wanted), the data it was fitted on
/// when its records' starts were discounted, whether the pre-check found the output not
/// monotone, whether to fit the Prandtl–Ishlinskii model, and the data's loops.
struct Settled {
    smooth: Option<SmoothFit>,
    data: Option<Dataset>,
    not_monotone: bool,
    want_pi: bool,
    found: crate::orientation::Loops,
}

/// The pre-checks and the smooth fit of [`identify`]. A timed record's start (the memory, the
/// plant's state) is not known: it is discounted until the input has swept its range, unless
/// estimated or trusted; then, once a first fit gives the plant and the operator, until they
/// have forgotten it (`crate::settling`), and the fit is made again where that takes longer.
fn fit_smooth_settled(
    data: &Dataset,
    request: &Request,
    want_smooth: bool,
    observer: &mut dyn Observer,
    notes: &mut Vec<String>,
) -> Result<Settled, FitError> {
    let timed = crate::timed::is_timed(request.structure);
    let settle = timed && !request.options.estimate_starts && !request.options.fit_from_start;
    let mut settled = None;
    let mut settling_note = None;
    if settle {
        let (d, note) = crate::settling::settle(data);
        settling_note = note;
        settled = Some(d);
    }
    let found = loops(settled.as_ref().unwrap_or(data));
    // A timed fit's pre-check looks at what the hysteresis sees, the plant's output v, once
    // the plant is fitted ([`identify`]): a slow plant's lag folds the command's loops.
    let not_monotone = if timed {
        false
    } else {
        check_monotone(data, request, found.orientation, notes)?
    };
    let want_pi = pi_wanted(data, request, found.gap, notes)?;
    let structure = structure(data, request, found.orientation, notes);
    // The smooth fit's own notes (its form), replaced when the fit is made again.
    let mut form_notes = Vec::new();
    let mut smooth = if want_smooth {
        Some(fit_smooth_form(
            settled.as_ref().unwrap_or(data),
            request,
            structure,
            observer,
            &mut form_notes,
        )?)
    } else {
        None
    };
    // A static fit keeps the start rule unless the records' starts fit worse than the rest:
    // then it is settled as a timed one.
    let mut mismatch = None;
    if let (false, Some(fitted)) = (timed, &smooth) {
        let rule = !request.options.estimate_starts
            && !request.options.fit_from_start
            && request.start == StartChoice::Auto;
        mismatch = rule
            .then(|| crate::settling::start_mismatch(data, &fitted.model))
            .flatten();
        if mismatch.is_some() {
            settled = Some(data.clone());
        }
    }
    if let (Some(fitted), Some(d)) = (smooth.as_mut(), settled.as_mut()) {
        settling_note = crate::settling::settle_fit(data, d, fitted, |d| {
            form_notes.clear();
            fit_smooth_form(d, request, structure, observer, &mut form_notes)
        })?;
    }
    if let (Some(words), Some(note)) = (mismatch, settling_note.as_mut()) {
        note.insert_str(0, &words);
    }
    notes.extend(form_notes);
    notes.splice(0..0, settling_note);
    Ok(Settled {
        smooth,
        data: settled,
        not_monotone,
        want_pi,
        found,
    })
}

/// The error of a requested model kind that was not fitted (which [`identify`] never lets
/// happen).
fn not_fitted() -> FitError {
    FitError::Invalid("internal: the requested model was not fitted".into())
}

/// Whether the output goes back against its trend along each branch (a butterfly loop) by
/// more than the fold limit of the data's `orientation`: an error unless the request keeps a
/// degenerate fit, then a note.
///
/// Such a loop is none the model makes, whichever form: refused unless kept, rather than fitted
/// with a confident report. Friction's branches are flat with a stiction peak and rate effects
/// (up to 0.36 of the span measured on LuGre seals), hence the higher limit for clockwise
/// loops.
fn check_monotone(
    data: &Dataset,
    request: &Request,
    orientation: Orientation,
    notes: &mut Vec<String>,
) -> Result<bool, FitError> {
    let folded = against_trend(data);
    let fold_limit = if orientation == Orientation::Clockwise {
        FOLD_LIMIT_CLOCKWISE
    } else {
        FOLD_LIMIT
    };
    let not_monotone = folded > fold_limit;
    if not_monotone {
        let message = format!(
            "the output of {} is not monotone along the input: along each branch it goes back \
             by {} % of the output span against its trend (a butterfly loop, as \
             magnetostriction's strain, even in the field; or a sensor that folds), which no \
             hysteresis model here makes (each branch of theirs is monotone): fit against a \
             quantity the output is monotone in (|input| or input² for an even response, or \
             one side of the range)",
            data.source,
            sig(100.0 * folded, 3)
        );
        if !request.keep_degenerate {
            return Err(FitError::Degenerate(format!(
                "{message}. No model file was written; pass --keep-degenerate to fit it anyway"
            )));
        }
        notes.push(message);
    }
    Ok(not_monotone)
}

/// Whether to fit the Prandtl–Ishlinskii model, given the data's branch gap `gap` (positive
/// for clockwise loops, which it cannot make): an error when it is the requested kind and
/// cannot describe the data. A comparison does not lose the smooth fit over a
/// Prandtl–Ishlinskii model that cannot describe the data: it is left out, with a note.
fn pi_wanted(
    data: &Dataset,
    request: &Request,
    gap: f64,
    notes: &mut Vec<String>,
) -> Result<bool, FitError> {
    let pi_cannot = gap > PI_CLOCKWISE_GAP;
    let want_pi = request.kind == ModelKind::PrandtlIshlinskii
        || (request.compare && !(pi_cannot && request.kind == ModelKind::Smooth));
    if request.compare && !want_pi {
        notes.push(format!(
            "no Prandtl–Ishlinskii comparison: the loops run clockwise (rising minus falling \
             branch {} % of the output span), which a Prandtl–Ishlinskii model cannot make",
            sig(100.0 * gap, 3)
        ));
    }
    if want_pi && pi_cannot {
        return Err(FitError::Invalid(format!(
            "the loops in {} run clockwise (the output leads the input: rising minus falling \
             branch +{} % of the output span, as friction against position); a \
             Prandtl–Ishlinskii model only makes counterclockwise loops: fit the smooth model, \
             whose stop form fits clockwise loops (--model-kind smooth)",
            data.source,
            sig(100.0 * gap, 3)
        )));
    }
    Ok(want_pi)
}

/// The smooth model's structure: the requested one with the form resolved from the data's loop
/// `orientation` and the start rule from the data (noted when every record moves one way).
fn structure(
    data: &Dataset,
    request: &Request,
    orientation: Orientation,
    notes: &mut Vec<String>,
) -> Structure {
    let (initial_state, one_way) = request.start.resolve(data);
    if one_way {
        let (moves, after, rule) = match initial_state {
            InitialState::Falling => ("rises", "a long fall", "falling"),
            _ => ("falls", "a long rise", "rising"),
        };
        notes.push(format!(
            "every record only {moves} (first-order reversal curves, say): each starts at a \
             reversal, as after {after} (--initial-state {rule}; give --initial-state to choose)"
        ));
    }
    Structure {
        form: request.form.resolve(orientation),
        initial_state,
        ..request.structure
    }
}

/// The diagnosis of the requested model's fit ([`diagnose`]), with the notes on a smooth fit
/// (its parameter limit, its estimated starts).
fn diagnose_requested(
    data: &Dataset,
    request: &Request,
    smooth: &Option<SmoothFit>,
    pi: &Option<PiFit>,
    orientation: Orientation,
    notes: &mut Vec<String>,
) -> Result<Diagnosis, FitError> {
    Ok(match (request.kind, smooth, pi) {
        (ModelKind::Smooth, Some(f), _) => {
            let limit = ParameterLimit::of(&f.model);
            smooth_notes(f, limit, notes);
            // A model with dynamics or a rate term: its hysteresis part on the static view.
            let view = if f.model.is_timed() {
                Some(static_view(data, &f.model)?)
            } else {
                None
            };
            // The outputs as the fit ran them (from its estimated starts), replayed.
            let (data, model, starts) = match &view {
                Some((v, m)) => (v, m, None),
                None => (data, &f.model, f.starts.as_deref()),
            };
            diagnose(
                data,
                &ModelOutputs {
                    data,
                    model,
                    starts,
                },
                &|x| model.run(x).ok(),
                Some(&f.statistical),
                limit.map_or(&[][..], ParameterLimit::unidentified),
                orientation,
                match f.model.form {
                    Form::Operator => Orientation::Counterclockwise,
                    Form::Stop => Orientation::Clockwise,
                },
            )
        }
        (_, _, Some(f)) => diagnose(
            data,
            &data
                .run_histories(|x| f.model.run(x).ok())
                .unwrap_or_default(),
            &|x| f.model.run(x).ok(),
            None,
            &[],
            orientation,
            Orientation::Counterclockwise,
        ),
        _ => return Err(not_fitted()),
    })
}

/// The notes on a smooth fit `f`: the parameter limit it is in (`limit`), the range of the
/// initial states it estimated.
fn smooth_notes(f: &SmoothFit, limit: Option<ParameterLimit>, notes: &mut Vec<String>) {
    if let Some(limit) = limit {
        notes.push(limit.note(f.model.k1));
    }
    if let Some(t) = &f.timed {
        notes.extend(t.notes());
    }
    if let Some(d) = f.model.dynamics {
        notes.push(format!(
            "hold: {} (--hold {})",
            d.hold().describe(),
            d.hold().name()
        ));
    }
    let c = f.correlation;
    if c.time >= 2.0 || c.capped {
        notes.push(format!(
            "the residuals are correlated over {} samples (a model mismatch, or coloured \
             noise): each standard error is the larger of the white-noise one and the block \
             sandwich over {} blocks of {} samples{}",
            sig(c.time, 3),
            c.blocks,
            c.block,
            if c.capped {
                "; the correlation outlasts a twentieth of the records, so even these are \
                 lower bounds: record longer, or more records"
            } else {
                ""
            }
        ));
    }
    notes.extend(f.allowance.as_ref().and_then(|a| a.note(&f.estimates)));
    if let Some(starts) = f.starts.as_ref().filter(|s| !s.is_empty()) {
        let (lo, hi) = starts
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), s| {
                (a.min(*s), b.max(*s))
            });
        notes.push(format!(
            "initial states estimated for {} histor{}: the operator output starts at \
             v0 + b·k1 with b from {} to {} (−1: as after a rise, 1: as after a fall)",
            starts.len(),
            if starts.len() == 1 { "y" } else { "ies" },
            sig(lo, 3),
            sig(hi, 3)
        ));
    }
}

/// The notes on what the residuals hold that a rate-independent model cannot represent: drift
/// and rate dependence, each above its share of the residuals' variance.
fn residual_notes(diagnosis: &Diagnosis, notes: &mut Vec<String>) {
    notes.extend(diagnosis.notes.iter().cloned());
    if diagnosis.drift_share > DRIFT_NOTE {
        notes.push(format!(
            "{} % of the residuals' variance is a straight line in time within the records: \
             drift, creep or a temperature change, which a rate-independent model cannot \
             represent; the model fits the rest (remove the trend, or fit shorter records)",
            sig(100.0 * diagnosis.drift_share, 2)
        ));
    }
    if diagnosis.rate_share > RATE_NOTE {
        notes.push(format!(
            "{} % of the residuals' variance follows the input's rate of change: the data holds \
             rate-dependent behaviour (viscous friction, creep, eddy currents) that a \
             rate-independent model cannot represent; the model fits the rate-independent part",
            sig(100.0 * diagnosis.rate_share, 2)
        ));
    }
}

/// The smooth fit's summary for the comparison (its evaluation timed on `data`).
fn smooth_summary(data: &Dataset, f: &SmoothFit) -> Summary {
    Summary {
        kind: "smooth".into(),
        parameters: f.layout.len(),
        training: f.training,
        validation: f.validation,
        fit_seconds: f.seconds,
        ns_per_sample: ns_per_sample(data, |x| {
            let period = data.records.first().and_then(|r| r.period.as_ref());
            let mut y = Vec::with_capacity(x.len());
            f.model
                .run_timed(x, period, None, |_, s| y.push(s.y))
                .ok()?;
            Some(y)
        }),
    }
}

/// The Prandtl–Ishlinskii fit's summary for the comparison (its evaluation timed on `data`).
fn pi_summary(data: &Dataset, f: &PiFit) -> Summary {
    Summary {
        kind: match f.model.output {
            Some(o) => format!("prandtl-ishlinskii + poly{}", o.degree),
            None => "prandtl-ishlinskii".into(),
        },
        parameters: f.model.parameter_count(),
        training: f.training,
        validation: f.validation,
        fit_seconds: f.seconds,
        ns_per_sample: ns_per_sample(data, |x| f.model.run(x).ok()),
    }
}

/// The fit a model file is written from, of either model kind.
enum Fitted<'a> {
    Smooth(&'a SmoothFit),
    PrandtlIshlinskii(&'a PiFit),
}

/// The model file of `fit` with `summary`'s metrics, and the records of `data` added to
/// `provenance`. It is written at the lowest version that holds the content: readers of older
/// versions refuse a stop form, version-1 readers keep reading plain PI files and refuse the
/// ones with an output polynomial.
fn model_file(
    request: &Request,
    data: &Dataset,
    fit: Fitted<'_>,
    summary: &Summary,
    mut provenance: Provenance,
) -> ModelFile {
    provenance.records = data.records.len();
    provenance.validation_records = data.validation().map(|r| r.id).collect();
    provenance.sample_periods = data.sample_periods();
    let mut file = ModelFile {
        format: FORMAT.into(),
        version: MIN_VERSION,
        kind: request.kind,
        columns: data.columns.clone(),
        units: request.units.clone(),
        parameters: Vec::new(),
        metrics: Metrics {
            parameters: summary.parameters,
            training: summary.training,
            validation: summary.validation,
            fit_seconds: summary.fit_seconds,
            ns_per_sample: summary.ns_per_sample,
        },
        structure: None,
        smooth: None,
        dynamics: None,
        rate: None,
        prandtl_ishlinskii: None,
        family: None,
        provenance,
    };
    match fit {
        Fitted::Smooth(f) => {
            file.parameters = f.estimates.clone();
            file.structure = Some(f.layout.structure);
            file.smooth = Some(f.model);
            file.dynamics = f.timed.as_ref().and_then(|t| t.dynamics_section(&f.model));
            file.rate = f.timed.as_ref().and_then(|t| t.rate_section(&f.model));
            file.family = f.widths;
        }
        Fitted::PrandtlIshlinskii(f) => {
            file.parameters = f.estimates.clone();
            file.prandtl_ishlinskii = Some(f.model.clone());
        }
    }
    file.version = file.required_version();
    file
}
