//! Family widths: the smallest (Δk1, Δk2) for which the family RH(k1, Δk1, k2, Δk2) around a
//! fitted model reproduces the data (Definition 2.8: at each sample some member gives the
//! measured output) at a chosen coverage, and the compensation bound Δa that follows
//! (Propositions 3.2, 3.3 and, for an input-dependent k2, 4.3).
//!
//! The envelope of the family at each sample is taken over the 3 × 3 lattice of members
//! (k1 + a Δk1, k2 + b Δk2), a, b ∈ {−1, 0, 1} (the core's [`Family`]; for a k2 law φ the
//! members use φ(v) + b Δk2), each run over the whole record with the fitted shaping and start
//! rule, and compared with the data by the core's [`Reproducibility`]. Widths are searched along rays of fixed proportion
//! (Δk1/Δk1_max, Δk2/Δk2_max) ∈ {(1, 0), (1, ½), (1, 1), (½, 1), (0, 1)} by bisection on the
//! coverage; of the widths that reach the coverage, the one with the smallest Δa is reported.

use std::ops::ControlFlow;

use hyst_core::family::{delta_a_over_k2_range, fold_envelope, shaped_bound};
use hyst_core::{AnyK2Law, Family, K2Law, Reproducibility, Shaping};

use hyst_model::{FamilyWidths, SmoothModel};

use crate::data::{Dataset, History};
use crate::error::FitError;
use crate::lm::{Observer, Progress};

/// Histories at least this long share the family's members among threads (below it, starting
/// the threads would cost more than they save).
const PARALLEL_FROM: usize = 4_000;

/// Samples of a history whose envelope is taken at a time: the members carry their memory from
/// one piece to the next ([`fold_envelope`]), so the scratch is a few pieces, whatever
/// the history's length (the envelopes of a 10 M-sample history held whole took 48 bytes a
/// sample with two threads, and 16 more per thread beyond).
const PIECE: usize = 1 << 16;

/// At most this many samples, over all histories, keep ψ_in(in) and the centre member's
/// envelope across [`coverage`]'s calls (24 bytes a sample: 48 MB); longer data recomputes them
/// in each call, piece by piece.
const CACHED_SAMPLES: usize = 1 << 21;

/// A member of the family, started for its history.
type Member = hyst_core::Hysteresis<f64, hyst_core::family::ShiftedK2<AnyK2Law<f64>, f64>>;

/// What [`coverage`] keeps across its calls for one model on one dataset (with the same
/// starts): scratch envelopes of one piece, one (lower, upper) pair per worker thread, and per
/// history (up to [`CACHED_SAMPLES`] in all) the operator input ψ_in(in) and the operator output
/// of the family's centre member (the model itself, whatever the widths).
struct Scratch {
    envelopes: Vec<(Vec<f64>, Vec<f64>)>,
    /// Per history: ψ_in(in) and the centre member's envelope, lower and upper (its operator
    /// output H[ψ_in(in)]; empty until computed, and for a history left out of the cache).
    histories: Vec<(Vec<f64>, Vec<f64>, Vec<f64>)>,
    /// Samples cached in `histories` so far.
    cached: usize,
    /// A piece of ψ_in(in) and of the centre's envelope, for a history not cached.
    piece: (Vec<f64>, Vec<f64>, Vec<f64>),
}

impl Scratch {
    /// One pair per thread the machine offers, at most one per member of the 3 × 3 lattice.
    fn new() -> Self {
        let workers = std::thread::available_parallelism().map_or(1, |n| n.get().min(9));
        Self {
            envelopes: vec![(Vec::new(), Vec::new()); workers],
            histories: Vec::new(),
            cached: 0,
            piece: (Vec::new(), Vec::new(), Vec::new()),
        }
    }
}

/// The distinct members among the lattice positions `members` of `family` (positions giving the
/// same k1 and k2 shift run the same operator: all nine when both widths are 0, three when one
/// is), without the centre's (the model itself, run once by [`coverage`]).
fn distinct_members(
    family: &Family<f64, AnyK2Law<f64>>,
    members: impl IntoIterator<Item = (f64, f64)>,
) -> Vec<(f64, f64)> {
    // Bit patterns, with −0 as +0 (k2 + (−0) = k2 + 0).
    let key = |(a, b): (f64, f64)| {
        let (k1, shift) = family.member_params(a, b);
        ((k1 + 0.0).to_bits(), (shift + 0.0).to_bits())
    };
    let mut seen = vec![key((0.0, 0.0))];
    let mut kept = Vec::new();
    for m in members {
        let k = key(m);
        if !seen.contains(&k) {
            seen.push(k);
            kept.push(m);
        }
    }
    kept
}

/// Fraction of samples (weight > 0, all records) inside the envelope of the family
/// RH(k1, `d1`, k2 law, `d2`) around `model`: at each sample the smallest and largest output of
/// the [`Family::lattice`] of 3 × 3 members, each run over each whole history (a record, or a
/// record cut into segments) inside the fitted shaping, from the history's estimated start
/// `starts` or the start rule (as [`SmoothModel::shaped_from`] starts them). On a long history
/// the members are shared among the threads of `scratch`; the result does not depend on how
/// many there are, nor on the pieces ([`PIECE`]) the history is folded in.
///
/// Each distinct member runs once (see [`distinct_members`]), and the centre member (the model)
/// once for all calls with the same `scratch` (on up to [`CACHED_SAMPLES`]). ψ_in(in) is
/// computed once per history (or piece), and the members run as bare operators on it: the
/// envelope is taken over the operator outputs H[v] and mapped to the output once per sample
/// ([`SmoothModel::output_envelope`]; ψ_out is strictly increasing), instead of every member's
/// output going through ψ_out.
///
/// # Errors
/// The core's error when the family is invalid (`d1` ≥ k1, a negative or non-finite width), a
/// member cannot run a record, or the output of the envelope is not finite
/// ([`hyst_core::Error::NonFiniteOutput`], as a member's output would have been).
fn coverage(
    data: &Dataset,
    model: &SmoothModel,
    starts: Option<&[f64]>,
    d1: f64,
    d2: f64,
    scratch: &mut Scratch,
) -> Result<f64, hyst_core::Error> {
    let family = Family::with_k2_law(model.k1, d1, model.k2, d2)?;
    let members = distinct_members(&family, Family::<f64, AnyK2Law<f64>>::lattice(3));
    let mut inside = 0usize;
    let mut samples = 0usize;
    // Each history whole: a segment starts where the one before it ended.
    for (index, h) in data.histories().into_iter().enumerate() {
        if h.input.is_empty() {
            continue;
        }
        let band = starts.and_then(|s| s.get(index).copied());
        let (i, n) = history_coverage(&family, &members, model, &h, (index, band), scratch)?;
        inside += i;
        samples += n;
    }
    Ok(if samples == 0 {
        0.0
    } else {
        inside as f64 / samples as f64
    })
}

/// The samples of the history `h` inside the envelope of `family` around `model`, and the
/// samples compared (as [`coverage`] counts them): `at` is the history's index (its place in
/// `scratch`) and its estimated start (`None`: the start rule), `members` the distinct members
/// besides the centre. The history is folded piece by piece ([`PIECE`]).
fn history_coverage(
    family: &Family<f64, AnyK2Law<f64>>,
    members: &[(f64, f64)],
    model: &SmoothModel,
    h: &History<'_>,
    (index, band): (usize, Option<f64>),
    scratch: &mut Scratch,
) -> Result<(usize, usize), hyst_core::Error> {
    let n = h.input.len();
    // Each member started as the model starts a history (its start looks at the record's own
    // input), then stepped on ψ_in(in).
    let start = |(a, b): (f64, f64)| model.start_in(family.member(a, b)?, &h.input, band);
    let workers = if n >= PARALLEL_FROM {
        scratch.envelopes.len().min(members.len()).max(1)
    } else {
        1
    };
    let mut shares = (0..workers)
        .map(|w| {
            members
                .iter()
                .skip(w)
                .step_by(workers)
                .map(|m| start(*m))
                .collect::<Result<Vec<_>, _>>()
        })
        .collect::<Result<Vec<_>, _>>()?;
    if scratch.histories.len() <= index {
        scratch
            .histories
            .resize(index + 1, (Vec::new(), Vec::new(), Vec::new()));
    }
    let Scratch {
        envelopes,
        histories,
        cached,
        piece,
    } = scratch;
    let cache = histories
        .get_mut(index)
        .ok_or(hyst_core::Error::LengthMismatch {
            input: n,
            output: 0,
        })?;
    // ψ_in(in) and the centre's envelope, once for the whole history while the cache has room.
    if cache.0.len() != n && *cached + n <= CACHED_SAMPLES {
        centre_envelope(model, &mut start((0.0, 0.0))?, &h.input, cache)?;
        *cached += n;
    }
    let mut centre = if cache.0.len() == n {
        None
    } else {
        Some(start((0.0, 0.0))?)
    };
    let (mut inside, mut samples) = (0, 0);
    for from in (0..n).step_by(PIECE) {
        let to = n.min(from + PIECE);
        let (input, centre_lower, centre_upper): (&[f64], &[f64], &[f64]) = match &mut centre {
            None => (&cache.0[from..to], &cache.1[from..to], &cache.2[from..to]),
            Some(member) => {
                centre_envelope(model, member, &h.input[from..to], piece)?;
                (&piece.0, &piece.1, &piece.2)
            }
        };
        let (lower, upper) =
            members_envelope(envelopes, &mut shares, input, (centre_lower, centre_upper))?;
        model.output_envelope(input, lower, upper)?;
        let r = Reproducibility::compare(
            &h.output[from..to],
            h.weight.as_slice().map(|w| &w[from..to]),
            lower,
            upper,
            0.0,
        );
        inside += r.inside;
        samples += r.samples;
    }
    Ok((inside, samples))
}

/// ψ_in of the model inputs `input` and the envelope of the centre member `member` over them
/// (its operator output, from the state it is in), into `out` (resized to `input`).
fn centre_envelope(
    model: &SmoothModel,
    member: &mut Member,
    input: &[f64],
    out: &mut (Vec<f64>, Vec<f64>, Vec<f64>),
) -> Result<(), hyst_core::Error> {
    let (v, lower, upper) = out;
    v.clear();
    v.extend(input.iter().map(|x| model.input_shaping.apply(*x)));
    lower.clear();
    lower.resize(input.len(), f64::INFINITY);
    upper.clear();
    upper.resize(input.len(), f64::NEG_INFINITY);
    fold_envelope(std::slice::from_mut(member), v, lower, upper)
}

/// The envelope (lower, upper) over a piece `input` of the operator outputs of the members in
/// `shares` (started, in the state the previous piece left) and of the centre member (its
/// envelope `centre` on the piece, computed before): each share is folded into a pair of
/// `envelopes`, one share per worker thread when there are several, and the shares are merged
/// into the first pair, which is returned.
fn members_envelope<'e>(
    envelopes: &'e mut [(Vec<f64>, Vec<f64>)],
    shares: &mut [Vec<Member>],
    input: &[f64],
    centre: (&[f64], &[f64]),
) -> Result<(&'e mut [f64], &'e mut [f64]), hyst_core::Error> {
    let n = input.len();
    let workers = shares.len();
    let (first, others) = envelopes
        .split_first_mut()
        .ok_or(hyst_core::Error::LengthMismatch {
            input: n,
            output: 0,
        })?;
    for (lower, upper) in std::iter::once(&mut *first)
        .chain(others.iter_mut())
        .take(workers)
    {
        lower.clear();
        lower.resize(n, f64::INFINITY);
        upper.clear();
        upper.resize(n, f64::NEG_INFINITY);
    }
    let (own_share, other_shares) =
        shares
            .split_first_mut()
            .ok_or(hyst_core::Error::LengthMismatch {
                input: n,
                output: 0,
            })?;
    std::thread::scope(|scope| -> Result<(), hyst_core::Error> {
        let running: Vec<_> = others
            .iter_mut()
            .zip(other_shares.iter_mut())
            .map(|((lower, upper), share)| {
                scope.spawn(move || fold_envelope(share, input, &mut lower[..n], &mut upper[..n]))
            })
            .collect();
        let own = fold_envelope(own_share, input, &mut first.0[..n], &mut first.1[..n]);
        for handle in running {
            // A worker's panic is resumed here, as it would have unwound without threads.
            handle
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic))?;
        }
        own
    })?;
    let (lower, upper) = (&mut first.0[..n], &mut first.1[..n]);
    for (l, u) in others
        .iter()
        .take(workers - 1)
        .map(|(l, u)| (&l[..n], &u[..n]))
        .chain(std::iter::once(centre))
    {
        for ((lo, hi), (l, u)) in lower.iter_mut().zip(upper.iter_mut()).zip(l.iter().zip(u)) {
            *lo = lo.min(*l);
            *hi = hi.max(*u);
        }
    }
    Ok((lower, upper))
}

/// The bound Δa for the family (k1, Δk1, k2 law, Δk2): Proposition 3.2 over the k2 range, with
/// Proposition 4.3's Δk2* added for an affine law. Returns (Δa, Δk2*, k2 range).
///
/// # Errors
/// When the family leaves k1, k2 > 0 (the core refuses it).
pub fn bound(
    model: &SmoothModel,
    delta_k1: f64,
    delta_k2: f64,
    v_range: (f64, f64),
) -> Result<(f64, f64, (f64, f64)), hyst_core::Error> {
    let (k2_lo, k2_hi) = model.k2.range(v_range.0, v_range.1);
    let law = match model.k2 {
        AnyK2Law::Constant { .. } => 0.0,
        AnyK2Law::Affine(_) => {
            hyst_core::family::delta_k2_prop43(&model.k2, model.k1, v_range.0, v_range.1)
        }
    };
    let b = delta_a_over_k2_range(model.k1, delta_k1, k2_lo, k2_hi, delta_k2 + law, 9)?;
    Ok((b.delta_a, law, (k2_lo, k2_hi)))
}

/// Reports step `step` of a width search to `observer` (progress of no start, without cost);
/// [`FitError::Interrupted`] when it stops the search.
fn tick(observer: &mut dyn Observer, step: usize) -> Result<(), FitError> {
    match observer.observe(&Progress {
        iteration: step,
        max_iterations: usize::MAX,
        cost: f64::NAN,
        lambda: f64::NAN,
        start: usize::MAX,
        starts: 1,
        finished: 0,
        stage: crate::lm::Stage::Widths,
    }) {
        ControlFlow::Continue(()) => Ok(()),
        ControlFlow::Break(()) => Err(FitError::Interrupted),
    }
}

/// What bounds the family widths of `model` on `data`, and what turns Δa into an output bound.
#[derive(Clone, Copy)]
struct Limits {
    /// ψ_in over the data's input range.
    v_range: (f64, f64),
    /// The largest Δk1 (members keep k1 > 0).
    d1_max: f64,
    /// The largest Δk2 (members keep k2 > 0, with room for Proposition 4.3's Δk2*).
    d2_max: f64,
    /// The output span of the data.
    span: f64,
    /// The Lipschitz constant of ψ_out over its argument's range on the data.
    lipschitz: f64,
}

impl Limits {
    /// The report of the widths (Δk1, Δk2) that reach `coverage` (of `target`): Δa and the
    /// output bound when `reachable`, none otherwise.
    fn widths(
        &self,
        model: &SmoothModel,
        target: f64,
        reachable: bool,
        (d1, d2): (f64, f64),
        coverage: f64,
    ) -> Result<FamilyWidths, FitError> {
        let (delta_a, law, k2_range) = bound(model, d1, d2, self.v_range)?;
        let delta_a = reachable.then_some(delta_a);
        Ok(FamilyWidths {
            coverage_target: target,
            reachable,
            delta_k1: d1,
            delta_k2: d2,
            coverage,
            delta_k2_law: law,
            k2_range,
            delta_a,
            output_bound: delta_a.map(|d| d * self.lipschitz),
            output_bound_pct_span: delta_a.map(|d| 100.0 * d * self.lipschitz / self.span),
        })
    }
}

fn limits(data: &Dataset, model: &SmoothModel) -> Result<Limits, FitError> {
    let (in_lo, in_hi) = data.input_range();
    let v_range = (
        model.input_shaping.apply(in_lo),
        model.input_shaping.apply(in_hi),
    );
    let (k2_lo, _) = model.k2.range(v_range.0 - model.k1, v_range.1 + model.k1);
    let d1_max = 0.98 * model.k1;
    // Members must keep k2 > 0, and an affine law keeps its lower clamp > 0.
    let d2_max = match model.k2 {
        AnyK2Law::Constant { value } => 0.98 * value,
        AnyK2Law::Affine(law) => (0.98 * law.min).min(0.98 * k2_lo),
    };
    // The Δk2 of Proposition 4.3 must also leave room in the bound.
    let (_, law, _) = bound(model, 0.0, 0.0, v_range)?;
    let d2_max = (d2_max - law).max(0.0);
    let (ylo, yhi) = data.output_range();
    let span = (yhi - ylo).max(f64::MIN_POSITIVE);
    // The Lipschitz constant of ψ_out over its argument's range on the data: the operator
    // output, or the stop value v − H[v] (which moves with H: |Δ(v − H)| = |ΔH| ≤ Δa).
    let (arg_lo, arg_hi) =
        SmoothModel::output_argument_range(model.form, model.k1, v_range.0, v_range.1);
    let lipschitz = shaped_bound(1.0, &model.output_shaping, arg_lo, arg_hi);

    Ok(Limits {
        v_range,
        d1_max,
        d2_max,
        span,
        lipschitz,
    })
}

/// Family widths found on a reduction of `data` (`crate::reduction`), checked on all of
/// `data`: the coverage is recomputed there, and when it falls short of the target the widths
/// are widened along their own ray (Δk1 : Δk2 kept) by bisection, up to the limits; if even the
/// widest family on that ray falls short, the coverage is not reachable (no Δa).
///
/// # Errors
/// As [`family_widths`].
pub fn confirm(
    data: &Dataset,
    model: &SmoothModel,
    found: FamilyWidths,
    observer: &mut dyn Observer,
) -> Result<FamilyWidths, FitError> {
    let lim = limits(data, model)?;
    let Limits { d1_max, d2_max, .. } = lim;
    let mut scratch = Scratch::new();
    // Counted after the search's steps (a progress display's fraction only moves on).
    let mut step = crate::lm::WIDTH_SEARCH_STEPS;
    let mut cover = |d1: f64, d2: f64| -> Result<f64, FitError> {
        step += 1;
        tick(observer, step)?;
        Ok(coverage(data, model, None, d1, d2, &mut scratch)?)
    };
    let target = found.coverage_target;
    let (d1, d2) = (found.delta_k1, found.delta_k2);
    let at_found = cover(d1, d2)?;
    let (reachable, d1, d2, cov) = if at_found >= target || !found.reachable {
        (found.reachable && at_found >= target, d1, d2, at_found)
    } else {
        // The widest family on the same ray.
        let t_max = [(d1, d1_max), (d2, d2_max)]
            .iter()
            .filter(|(d, _)| *d > 0.0)
            .map(|(d, max)| max / d)
            .fold(f64::INFINITY, f64::min);
        let t_max = if t_max.is_finite() {
            t_max.max(1.0)
        } else {
            1.0
        };
        let widest = cover(t_max * d1, t_max * d2)?;
        if widest < target {
            (false, t_max * d1, t_max * d2, widest)
        } else {
            let (mut lo, mut hi, mut hi_cov) = (1.0, t_max, widest);
            for _ in 0..8 {
                let mid = 0.5 * (lo + hi);
                let c = cover(mid * d1, mid * d2)?;
                if c >= target {
                    (hi, hi_cov) = (mid, c);
                } else {
                    lo = mid;
                }
            }
            (true, hi * d1, hi * d2, hi_cov)
        }
    };
    lim.widths(model, target, reachable, (d1, d2), cov)
}

/// The largest t in [0, 1] at which the widths `widths(t)` along a ray still give a Δa
/// ([`bound`]) no larger than `best` (1 when the whole ray does, 0 when none of it does), to a
/// relative 1e-6 by bisection; Δa grows with both widths.
fn ray_end(
    model: &SmoothModel,
    v_range: (f64, f64),
    widths: impl Fn(f64) -> (f64, f64),
    best: f64,
) -> f64 {
    let within = |t: f64| {
        let (w1, w2) = widths(t);
        bound(model, w1, w2, v_range).is_ok_and(|(a, _, _)| a <= best)
    };
    if within(1.0) {
        return 1.0;
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    while hi - lo > 1e-6 {
        let mid = 0.5 * (lo + hi);
        if within(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// Searches the smallest family widths that reproduce `coverage` of the samples, the members
/// started as the fit started the model (`starts`: [`crate::SmoothFit::starts`]).
///
/// # Errors
/// [`FitError::Interrupted`] when the observer stops; [`FitError::Core`] when the model or a
/// member of the family cannot run the data.
pub fn family_widths(
    data: &Dataset,
    model: &SmoothModel,
    starts: Option<&[f64]>,
    coverage_target: f64,
    observer: &mut dyn Observer,
) -> Result<FamilyWidths, FitError> {
    let lim = limits(data, model)?;
    let Limits {
        v_range,
        d1_max,
        d2_max,
        ..
    } = lim;
    let rays = [(1.0, 0.0), (1.0, 0.5), (1.0, 1.0), (0.5, 1.0), (0.0, 1.0)];
    let mut best: Option<(f64, f64, f64, f64)> = None; // (Δa, Δk1, Δk2, coverage)
    let mut best_coverage = (0.0, 0.0, 0.0);
    let mut step = 0;
    let mut tick = |observer: &mut dyn Observer| -> Result<(), FitError> {
        step += 1;
        tick(observer, step)
    };
    let mut scratch = Scratch::new();
    let mut cover = |d1: f64, d2: f64| coverage(data, model, starts, d1, d2, &mut scratch);
    let base = cover(0.0, 0.0)?;
    if base >= coverage_target {
        return lim.widths(model, coverage_target, true, (0.0, 0.0), base);
    }
    for (c1, c2) in rays {
        if c2 > 0.0 && d2_max <= 0.0 {
            continue;
        }
        let widths = |t: f64| (t * c1 * d1_max, t * c2 * d2_max);
        // Δa grows along the ray: past the point where it equals the best Δa found so far the
        // ray cannot win, so the search ends there (one evaluation when even that point falls
        // short of the coverage, instead of a bisection over the whole ray).
        let t_end = match best {
            None => 1.0,
            Some((best_a, ..)) => ray_end(model, v_range, widths, best_a),
        };
        if t_end <= 0.0 {
            continue;
        }
        tick(observer)?;
        let (w1, w2) = widths(t_end);
        let full = cover(w1, w2)?;
        if full > best_coverage.0 {
            best_coverage = (full, w1, w2);
        }
        if full < coverage_target {
            continue;
        }
        let (mut lo, mut hi, mut hi_cov) = (0.0, t_end, full);
        for _ in 0..10 {
            tick(observer)?;
            let mid = 0.5 * (lo + hi);
            let (w1, w2) = widths(mid);
            let c = cover(w1, w2)?;
            if c >= coverage_target {
                hi = mid;
                hi_cov = c;
            } else {
                lo = mid;
            }
        }
        let (w1, w2) = widths(hi);
        if let Ok((delta_a, _, _)) = bound(model, w1, w2, v_range) {
            if best.is_none_or(|b| delta_a < b.0) {
                best = Some((delta_a, w1, w2, hi_cov));
            }
        }
    }
    let (reachable, d1, d2, cov) = match best {
        Some((_, d1, d2, c)) => (true, d1, d2, c),
        None => (false, best_coverage.1, best_coverage.2, best_coverage.0),
    };
    lim.widths(model, coverage_target, reachable, (d1, d2), cov)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::lm::Silent;
    use hyst_core::AnyShaping;
    use hyst_core::ScaledShaping;
    use hyst_model::InitialState;

    fn model() -> SmoothModel {
        let identity = AnyShaping::Identity;
        SmoothModel {
            k1: 0.1,
            k2: AnyK2Law::Constant { value: 5.0 },
            input_shaping: ScaledShaping::new(0.5, 0.1, identity, 1.0, 0.0).unwrap(),
            output_shaping: ScaledShaping::new(1.0, 0.0, identity, 2.0, 0.3).unwrap(),
            initial_state: InitialState::Falling,
            form: hyst_model::Form::Operator,
            linear: 0.0,
            dynamics: None,
            rate: None,
        }
    }

    fn input() -> Vec<f64> {
        (0..2000)
            .map(|k| {
                let t = k as f64 * 0.01;
                (0.4 + 0.1 * t) * (1.3 * t).sin() + 0.2 * (3.1 * t).cos()
            })
            .collect()
    }

    #[test]
    fn data_of_a_corner_member_is_covered_and_the_nominal_alone_is_not() {
        let m = model();
        // The member (k1 + Δk1, k2 − Δk2), started by the same rule on its own asymptote.
        let (d1, d2) = (0.03, 1.5);
        let truth = SmoothModel {
            k1: m.k1 + d1,
            k2: AnyK2Law::Constant { value: 5.0 - d2 },
            ..m
        };
        let x = input();
        let data = Dataset::single(&x, &truth.run(&x).unwrap());
        let mut scratch = Scratch::new();
        assert_eq!(
            coverage(&data, &m, None, d1, d2, &mut scratch).unwrap(),
            1.0
        );
        let nominal = coverage(&data, &m, None, 0.0, 0.0, &mut scratch).unwrap();
        assert!(nominal < 0.05, "{nominal}");
        // Half the widths leave part of the data outside.
        let half = coverage(&data, &m, None, d1 / 2.0, d2 / 2.0, &mut scratch).unwrap();
        assert!(half > nominal && half < 0.9, "{half}");
        // An invalid family is an error, not a coverage.
        assert!(coverage(&data, &m, None, m.k1, 0.0, &mut scratch).is_err());
    }

    /// A history of several pieces: the coverage is the one of the envelope taken over the
    /// whole history at once, with the centre cached or folded piece by piece, on one thread or
    /// several.
    #[test]
    fn pieces_and_threads_give_the_envelope_of_the_whole_history() {
        let m = model();
        let n = 3 * PIECE + 123;
        let x: Vec<f64> = (0..n)
            .map(|k| {
                let t = k as f64 * 0.003;
                (0.4 + 0.1 * (0.01 * t).sin()) * (1.3 * t).sin() + 0.2 * (3.1 * t).cos()
            })
            .collect();
        let truth = SmoothModel {
            k1: m.k1 + 0.01,
            k2: AnyK2Law::Constant { value: 4.5 },
            ..m
        };
        let mut y = truth.run(&x).unwrap();
        // Noise, so that some samples fall outside any family of these widths.
        for (k, v) in y.iter_mut().enumerate() {
            *v += 0.02 * ((k as f64 * 0.7).sin() * (k as f64 * 1.9).cos());
        }
        let data = Dataset::single(&x, &y);
        let (d1, d2) = (0.006, 0.4);
        // The whole history at once, as the core's family runs it.
        let family = Family::with_k2_law(m.k1, d1, m.k2, d2).unwrap();
        let v: Vec<f64> = x.iter().map(|u| m.input_shaping.apply(*u)).collect();
        let (mut lower, mut upper) = (vec![0.0; n], vec![0.0; n]);
        family
            .envelope_with(&v, &mut lower, &mut upper, 3, |member| {
                m.start_in(member, &x, None)
            })
            .unwrap();
        m.output_envelope(&v, &mut lower, &mut upper).unwrap();
        let whole = Reproducibility::compare(&y, None, &lower, &upper, 0.0);
        let expected = whole.inside as f64 / whole.samples as f64;
        assert!(expected > 0.2 && expected < 0.99, "{expected}");
        for (workers, cache) in [(1, true), (1, false), (3, true), (3, false)] {
            let mut scratch = Scratch::new();
            scratch.envelopes = vec![(Vec::new(), Vec::new()); workers];
            if !cache {
                scratch.cached = CACHED_SAMPLES;
            }
            for _ in 0..2 {
                let got = coverage(&data, &m, None, d1, d2, &mut scratch).unwrap();
                assert_eq!(got, expected, "{workers} workers, cache {cache}");
            }
            assert_eq!(scratch.histories[0].0.len(), if cache { n } else { 0 });
        }
    }

    #[test]
    fn samples_of_weight_zero_are_not_counted() {
        let m = model();
        let x = input();
        let mut y = m.run(&x).unwrap();
        // Spoil the second half, then give it weight 0: the nominal covers everything counted.
        y[1000..].iter_mut().for_each(|v| *v += 1.0);
        let mut data = Dataset::single(&x, &y);
        data.records[0].weight.fill(1000..usize::MAX, 0.0);
        let mut scratch = Scratch::new();
        assert_eq!(
            coverage(&data, &m, None, 0.0, 0.0, &mut scratch).unwrap(),
            1.0
        );
        data.records[0].weight.fill(1000..usize::MAX, 1.0);
        assert_eq!(
            coverage(&data, &m, None, 0.0, 0.0, &mut scratch).unwrap(),
            0.5
        );
    }

    #[test]
    fn widths_reach_the_data_of_a_member_and_bound_it() {
        let m = model();
        let truth = SmoothModel {
            k1: m.k1 + 0.02,
            k2: AnyK2Law::Constant { value: 4.0 },
            ..m
        };
        let x = input();
        let data = Dataset::single(&x, &truth.run(&x).unwrap());
        let w = family_widths(&data, &m, None, 0.99, &mut Silent).unwrap();
        assert!(w.reachable && w.coverage >= 0.99, "{w:?}");
        assert!(w.delta_k1 > 0.0 && w.delta_k1 < 0.98 * m.k1, "{w:?}");
        assert_eq!((w.delta_k2_law, w.k2_range), (0.0, (5.0, 5.0)));
        let b = hyst_core::family::delta_a(m.k1, w.delta_k1, 5.0, w.delta_k2).unwrap();
        assert_eq!(w.delta_a, Some(b.delta_a));
        // ψ_out has gain 2: the bound in output units doubles.
        assert!(
            (w.output_bound.unwrap() - 2.0 * b.delta_a).abs() < 1e-12,
            "{w:?}"
        );
    }
}
