//! The bank's kernels, written once against [`Simd`]: a chunk of `V::LANES` channels keeps its
//! state in registers while the ticks go by (time inside, channels outside), so a tick costs
//! the arithmetic and one load and store of the samples.
//!
//! A tick is Definition 2.1's memory update with selects, then eq. (4) (inverse) or eq. (2)
//! (direct) on every lane. Where a lane's output is not within the band |output − input| ≤ k1
//! as computed in floating point (rounding at the band's edge, or a value that is not finite
//! because an intermediate overflowed), the scalar operator computes that lane from the same
//! memory, and the output is put inside the band (the rare path, [`repair`]).
//!
//! The large functions here are `#[inline(always)]` only when optimising: the kernels need them
//! inlined into their `#[target_feature]` entry points, but in debug builds the unoptimised
//! frames of all of them inlined together need more than a thread's 2 MiB of stack.

use super::block::Block;
use super::columns::ColumnsMut;
use super::error::BankError;
use super::formula::BankFormula;
use super::lanes::{decay, exp, fsc_step, ln, omega_series, omega_start, omega_v};
use super::vector::{Lane, Simd};
use crate::k2law::ConstantK2;
use crate::memory::{Direction, Memory};
use crate::operator::Operator;
use crate::parametric::ParametricHysteresis;
use crate::real::Real;

/// The most lanes of any vector (AVX-512 f32).
const MAX_LANES: usize = 64;

/// A chunk's state: the columns of its channels, and the direct formula's cached values.
#[derive(Clone, Copy)]
struct State<V> {
    k1: V,
    k2: V,
    rin: V,
    rout: V,
    sign: V,
    lin: V,
    lout: V,
    /// Direct: 1 / k2, ln k2, M* (eq. 2, clamped to [0, 2 k1]) and ln(k2 M*); these change only
    /// at reversals.
    inv_k2: V,
    ln_k2: V,
    m_star: V,
    ln_a: V,
    /// Inverse: −k2 s (its sign is −s; `sign` is not kept up to date) and s M* = s k1 − (β0 − α0)
    /// (eq. 4); both change only at reversals.
    neg_k2: V,
    sm: V,
    /// Inverse: s k1 (the band edge the output approaches, eq. 4 far from the reversal point).
    ks: V,
}

/// A column's values for `start .. start + width` into a vector, padding with `fill`.
#[inline(always)]
fn column<V: Simd>(s: &[V::T], start: usize, width: usize, fill: V::T) -> V {
    if width == V::LANES {
        // An exact range: the slice's length is then the constant V::LANES, so the vector
        // loads inside (a `Pair` splits it) need no length checks of their own.
        return V::load(s.get(start..start + V::LANES).unwrap_or(&[]));
    }
    let mut buf = [fill; MAX_LANES];
    for (b, v) in buf.iter_mut().zip(s.iter().skip(start).take(width)) {
        *b = *v;
    }
    V::load(&buf)
}

/// Writes the first `width` lanes of `v` to `s[start..]`.
#[inline(always)]
fn put<V: Simd>(s: &mut [V::T], start: usize, width: usize, v: V) {
    if width == V::LANES {
        if let Some(slot) = s.get_mut(start..start + V::LANES) {
            v.store(slot);
        }
        return;
    }
    let mut buf = [<V::T as Real>::ZERO; MAX_LANES];
    v.store(&mut buf);
    for (slot, b) in s.iter_mut().skip(start).take(width).zip(buf) {
        *slot = b;
    }
}

/// M* of eq. (2) (M + k1 clamped into [0, 2 k1]) and ln(k2 M*) = ln k2 + ln M* (−∞ at M* = 0).
#[cfg_attr(not(debug_assertions), inline(always))]
fn direct_cache<V: Simd>(st: &State<V>) -> (V, V) {
    let zero = V::c(0.0);
    let two_k1 = st.k1 + st.k1;
    let m = (st.rout - st.rin).fma(st.sign, st.k1);
    let m = V::select(m.less(zero), zero, V::select(two_k1.less(m), two_k1, m));
    (m, st.ln_k2 + ln(m))
}

/// Definition 2.1's memory update: a step against the direction s ((x − x_last) s < 0) reverses
/// it and makes the last point the reversal point (α0, β0); a zero step keeps everything.
/// Returns the lanes that reversed. The inverse kernel keeps s only inside −k2 s (one vector
/// fewer a chunk in registers), whose sign is −s.
#[cfg_attr(not(debug_assertions), inline(always))]
fn observe<V: Simd, F: BankFormula>(st: &mut State<V>, x: V) -> V::M {
    let step = x - st.lin;
    let reversed = if F::DIRECT {
        (step * st.sign).less(V::c(0.0))
    } else {
        V::c(0.0).less(step * st.neg_k2)
    };
    st.rin = V::select(reversed, st.lin, st.rin);
    st.rout = V::select(reversed, st.lout, st.rout);
    if F::DIRECT {
        st.sign = st.sign.negate_where(reversed);
    } else {
        st.neg_k2 = st.neg_k2.negate_where(reversed);
        st.ks = st.ks.negate_where(reversed);
    }
    reversed
}

/// The inverse kernel's s from −k2 s (k2 > 0).
#[inline(always)]
fn sign_of<V: Simd>(neg_k2_s: V) -> V {
    V::select(neg_k2_s.less(V::c(0.0)), V::c(1.0), V::c(-1.0))
}

/// Eq. (4) with the transformation folded in: v = (x − α0 + β0) + (1 − e^(−k2 ũd)) · s M*,
/// ũd = s (x − α0), s M* = s k1 − (β0 − α0), which is v = x + s k1 − e^(−k2 ũd) s M*.
#[cfg_attr(not(debug_assertions), inline(always))]
fn inverse_output<V: Simd>(st: &State<V>, x: V) -> V
where
    V::T: Lane,
{
    // −k2 ũd as (x − α0) (−k2 s): the scalar operator's −(k2 ũd), bit for bit (s = ±1).
    let e = decay((x - st.rin) * st.neg_k2);
    x + (-e).fma(st.sm, st.ks)
}

/// s M* = s k1 − (β0 − α0) of eq. (4), from the memory.
#[inline(always)]
fn inverse_cache<V: Simd>(st: &State<V>) -> V {
    st.ks + (st.rin - st.rout)
}

/// Eq. (2): ũ = ṽ − M* + ω(y) / k2 with y = ln(k2 M*) + k2 (M* − ṽ) (W0(k2 M* e^(k2 (M* − ṽ)))
/// in the log domain, so nothing overflows), and ũ = (ln(k2 M*) − ln ω) / k2 where e^y would
/// overflow (the scalar operator's log form); ũ = 0 at the reversal point (ṽ = 0).
///
/// ω: below [`Lane::OMEGA_SERIES`] its series in t = eʸ; above, a start within 2.2e-5
/// ([`omega_start`]) and one Fritsch–Shafer–Crowley step, with [`omega_v`] for a lane whose
/// start was not close enough (none is known; the test keeps the step honest). Each part runs
/// only when some lane of the chunk needs it.
#[cfg_attr(not(debug_assertions), inline(always))]
fn direct_output<V: Simd>(st: &State<V>, x: V) -> V
where
    V::T: Lane,
{
    let zero = V::c(0.0);
    let vt = (x - st.rin) * st.sign;
    let y = (st.m_star - vt).fma(st.k2, st.ln_a);
    let t = exp(y);
    let series = omega_series(t);
    let exact = y.less(V::splat(<V::T as Lane>::OMEGA_SERIES));
    let w = if V::all(exact) {
        series
    } else {
        let (w1, r) = fsc_step(omega_start(y, series), y);
        let ok = V::or(
            exact,
            r.magnitude().less_eq(V::splat(<V::T as Lane>::RESIDUAL_OK)),
        );
        let w = V::select(exact, series, w1);
        if V::all(ok) {
            w
        } else {
            V::select(ok, w, omega_v(y))
        }
    };
    let plain = w.fma(st.inv_k2, vt - st.m_star);
    let huge = V::splat(<V::T as Real>::EXP_ARG_MAX).less(y);
    let u = if V::any(huge) {
        V::select(huge, (st.ln_a - ln(w)) * st.inv_k2, plain)
    } else {
        plain
    };
    let u = V::select(vt.equal(zero), zero, u);
    u.fma(st.sign, st.rout)
}

/// The channel's output as the scalar operator computes it from the same memory (`st` after the
/// memory update, before the last point moves), then kept inside the band: the rare path for
/// lanes whose output left the band or is not finite. Returns the outputs and the reversal
/// points and signs after the step (the state goes by value, so that the hot loop keeps it in
/// registers).
#[inline(never)]
#[cold]
fn repair<V: Simd, F: BankFormula>(
    st: State<V>,
    x: V,
    y: V,
    start: usize,
    width: usize,
) -> Result<[V; 4], BankError> {
    let zero = <V::T as Real>::ZERO;
    let spill = |v: V| {
        let mut a = [zero; MAX_LANES];
        v.store(&mut a);
        a
    };
    let (xs, mut ys, k1, k2) = (spill(x), spill(y), spill(st.k1), spill(st.k2));
    let (mut rin, mut rout, mut sign) = (spill(st.rin), spill(st.rout), spill(st.sign));
    let (lin, lout) = (spill(st.lin), spill(st.lout));
    for i in 0..width.min(MAX_LANES) {
        let at = |a: &[V::T; MAX_LANES]| a.get(i).copied().unwrap_or(zero);
        let (xi, k1i) = (at(&xs), at(&k1));
        if (at(&ys) - xi).magnitude() <= k1i {
            continue;
        }
        let wrap = |error| BankError {
            channel: start + i,
            error,
        };
        let memory = Memory {
            reversal_input: at(&rin),
            reversal_output: at(&rout),
            direction: if at(&sign) > zero {
                Direction::Rising
            } else {
                Direction::Falling
            },
            last_input: at(&lin),
            last_output: at(&lout),
        };
        let mut op =
            ParametricHysteresis::<V::T, ConstantK2<V::T>, F>::new(k1i, at(&k2)).map_err(wrap)?;
        op.set_memory(Some(memory)).map_err(wrap)?;
        let out = op.try_step(xi).map_err(wrap)?;
        if let Some(m) = op.memory() {
            for (col, v) in [
                (&mut rin, m.reversal_input),
                (&mut rout, m.reversal_output),
                (&mut sign, m.direction.sign()),
            ] {
                if let Some(slot) = col.get_mut(i) {
                    *slot = v;
                }
            }
        }
        if let Some(slot) = ys.get_mut(i) {
            *slot = within_band(out, xi, k1i);
        }
    }
    Ok([V::load(&ys), V::load(&rin), V::load(&rout), V::load(&sign)])
}

/// `y` clamped so that |y − x|, computed in floating point, is at most k1 (the test
/// [`crate::Memory::validate`] makes): the edges x ± k1 rounded, then moved one float towards
/// x where rounding put them outside.
fn within_band<T: Lane>(y: T, x: T, k1: T) -> T {
    let mut lo = x - k1;
    if x - lo > k1 {
        lo = lo.next_above();
    }
    let mut hi = x + k1;
    if hi - x > k1 {
        hi = hi.next_below();
    }
    if y < lo {
        lo
    } else if y > hi {
        hi
    } else {
        y
    }
}

/// `y` clamped into the band |y − x| ≤ k1 as computed in floating point, in vector code: the
/// edges x ± k1 as rounded, each moved one float towards x where rounding put it outside (by
/// [`Lane::ONE_STEP`]; exact for normal edges, a subnormal edge stays and fails the caller's
/// test), then `y` clamped to them (NaN stays NaN).
#[cfg_attr(not(debug_assertions), inline(always))]
fn into_band<V: Simd>(y: V, x: V, k1: V) -> V
where
    V::T: Lane,
{
    let step = V::splat(<V::T as Lane>::ONE_STEP);
    let hi = x + k1;
    let hi = V::select(k1.less(hi - x), (-hi.magnitude()).fma(step, hi), hi);
    let lo = x - k1;
    let lo = V::select(k1.less(x - lo), lo.magnitude().fma(step, lo), lo);
    V::select(hi.less(y), hi, V::select(y.less(lo), lo, y))
}

/// The lanes whose output is outside the band by no more than rounding explains: 192 units of
/// roundoff of the largest of |x|, k1 and |β0| (64 units of their sum, the bank's stated
/// agreement with the scalar operator being 16 ulp of these magnitudes; the largest, because
/// the sum overflows near the end of the float range and would then excuse any output); false
/// for NaN and ±∞. Lanes further out go to the scalar operator.
#[cfg_attr(not(debug_assertions), inline(always))]
fn near_band<V: Simd>(st: &State<V>, x: V, y: V) -> V::M
where
    V::T: Lane,
{
    let slack = V::splat(<V::T as Lane>::ONE_STEP) * V::c(192.0);
    let scale = x.magnitude().max_or(st.k1).max_or(st.rout.magnitude());
    (y - x).magnitude().less_eq(scale.fma(slack, st.k1))
}

/// Whether every lane's output is within the band |y − x| ≤ k1 (false for NaN and ±∞).
///
/// A function, not a closure: a closure's body is compiled without the kernel's target
/// features, so the vector operations in it stay calls (measured on the AVX2 kernel: the band
/// test as a closure was a call per chunk and tick, 42 instructions per channel-sample).
#[inline(always)]
fn in_band<V: Simd>(y: V, x: V, k1: V) -> bool {
    V::all((y - x).magnitude().less_eq(k1))
}

/// One tick of a chunk: memory update, formula, band check (rare path [`repair`]), last point.
#[cfg_attr(not(debug_assertions), inline(always))]
fn tick<V: Simd, F: BankFormula>(
    st: &mut State<V>,
    x: V,
    start: usize,
    width: usize,
    changed: &mut bool,
) -> Result<V, BankError> {
    let reversed = observe::<V, F>(st, x);
    let any_reversed = V::any(reversed);
    *changed |= any_reversed;
    if F::DIRECT && any_reversed {
        let (m, ln_a) = direct_cache(st);
        st.m_star = V::select(reversed, m, st.m_star);
        st.ln_a = V::select(reversed, ln_a, st.ln_a);
    } else if !F::DIRECT {
        // Every tick, not only when a lane reversed: two operations a vector, against a branch
        // that a bank's reversals make hard to predict (taken on 45 % of the visits of the
        // benchmark's signal); the value is the same when nothing reversed.
        st.sm = inverse_cache(st);
    }
    let mut y = if F::DIRECT {
        direct_output(st, x)
    } else {
        inverse_output(st, x)
    };
    // One test on the hot path, also false for NaN and ±∞.
    let k1 = st.k1;
    if !in_band(y, x, k1) {
        // Usually an output that rounding put an ulp outside the band: far from the reversal
        // point the output is x ± k1 as rounded (e^(−k2 ũd) vanishes: large k2 or large
        // excursions, most ticks then). Clamped here in vector code; the rare path only for
        // what that does not mend (not finite, or further out than rounding explains).
        let clamped = into_band(y, x, k1);
        if in_band(clamped, x, k1) && V::all(near_band(st, x, y)) {
            y = clamped;
        } else {
            if !F::DIRECT {
                st.sign = sign_of(st.neg_k2);
            }
            [y, st.rin, st.rout, st.sign] = repair::<V, F>(*st, x, y, start, width)?;
            *changed = true;
            if F::DIRECT {
                (st.m_star, st.ln_a) = direct_cache(st);
            } else {
                st.neg_k2 = -(st.k2 * st.sign);
                st.ks = st.k1 * st.sign;
                st.sm = inverse_cache(st);
            }
        }
    }
    st.lin = x;
    st.lout = y;
    Ok(y)
}

/// Ticks per tile: the block runs tile by tile, and in a tile chunk by chunk, so that a chunk's
/// samples of a tile are a few cache lines that the next chunk's neighbours share (a chunk
/// through all ticks of a time-major block would read one line per 8 KiB row: measured 2.3 ×
/// slower for 1,024 channels).
const TILE: usize = 16;

/// Runs ticks `block.begin..block.end` through every channel of `cols`. Tile by tile of
/// [`TILE`] ticks; in a tile, chunk by chunk, whose state stays in registers while its ticks go
/// by. With a limit, each tile's samples are checked first (while they are in cache for the
/// run that follows), and the run stops before the first tick with a sample whose magnitude is
/// not below the limit (or is NaN): `Ok(Some(t))`, every tick before t done.
///
/// # Errors
/// What the scalar operator refuses on the rare path (an output beyond the float range); some
/// channels have then run further than others (the caller restores the memory).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn run<V: Simd, F: BankFormula>(
    cols: &mut ColumnsMut<'_, V::T>,
    block: &mut Block<'_, V::T>,
) -> Result<Option<usize>, BankError> {
    // Every column cut to the same length `n` here, once a call: a chunk's loads and stores
    // then share one range check (`start + LANES <= n`) instead of one per column.
    let cols = &mut cols.cut(cols.k1.len());
    let n = cols.k1.len();
    if block.samples == 1 && block.begin == 0 && block.end >= 1 {
        // The direct operator's tick is a long chain (`exp`, ω, selects): it runs the block's
        // chunk of four vectors, whose four chains the processor overlaps; the inverse's
        // shorter one runs `Simd::Tick`, two chunks' state in registers (see `one_tick`).
        return if F::DIRECT {
            one_tick::<V, F>(cols, block)
        } else {
            one_tick::<V::Tick, F>(cols, block)
        };
    }
    let layout = Layout {
        n,
        samples: block.samples,
        channel_major: block.channel_major,
    };
    let (input, end) = (block.input, block.end.min(block.samples));
    let mut t0 = block.begin;
    while t0 < end {
        let mut t1 = (t0 + TILE).min(end);
        let stop = match block.limit {
            Some(limit) => first_beyond::<V>(input, &layout, t0, t1, limit),
            None => None,
        };
        if let Some(bad) = stop {
            t1 = bad;
        }
        let mut start = 0;
        while start < n && t0 < t1 {
            let width = (n - start).min(V::LANES);
            let x0 = gather::<V>(input, &layout, start, width, t0);
            let (mut st, mut changed) = load::<V, F>(cols, start, width, x0);
            let mut x = x0;
            for t in t0..t1 {
                let y = tick::<V, F>(&mut st, x, start, width, &mut changed)?;
                // The next samples are loaded before this tick's outputs are stored: with rows
                // of 4 KiB (1,024 f32 channels) a load after a store to the same address modulo
                // 4 KiB waits for it (4K aliasing).
                if t + 1 < t1 {
                    x = gather::<V>(input, &layout, start, width, t + 1);
                }
                scatter(block.output, &layout, start, width, t, y);
            }
            put_state::<V, F>(cols, start, width, &st, changed);
            start += width;
        }
        if stop.is_some() {
            return Ok(stop);
        }
        t0 = t1;
    }
    Ok(None)
}

/// A block of one tick (`step`; both layouts are then `input[c]`): chunk by chunk, the state
/// loaded, one tick, the state stored, in a loop with none of the tiles' bookkeeping (a `step`
/// is a visit of every chunk per tick, so what a visit costs beyond the tick is what `step`
/// costs beyond a block).
#[cfg_attr(not(debug_assertions), inline(always))]
fn one_tick<V: Simd, F: BankFormula>(
    cols: &mut ColumnsMut<'_, V::T>,
    block: &mut Block<'_, V::T>,
) -> Result<Option<usize>, BankError> {
    let n = cols.k1.len();
    let input = block.input.get(..n).unwrap_or(&[]);
    let output = block.output.get_mut(..n).unwrap_or(&mut []);
    if let Some(limit) = block.limit {
        if !all_within::<V>(input, limit) {
            return Ok(Some(0));
        }
    }
    // Whole chunks through iterators of exact chunks, so that no load or store has a range
    // check of its own (12 columns: the checks were a fifth of a visit's instructions).
    let l = V::LANES;
    let full = n - n % l;
    let (input, input_rest) = input.split_at(full.min(input.len()));
    let (output, output_rest) = output.split_at_mut(full.min(output.len()));
    let (head, mut rest) = cols.cut(n).split_at(full);
    let chunks = input
        .chunks_exact(l)
        .zip(output.chunks_exact_mut(l))
        .zip(head.k1.chunks_exact(l).zip(head.k2.chunks_exact(l)))
        .zip(head.inv_k2.chunks_exact(l).zip(head.ln_k2.chunks_exact(l)))
        .zip(
            head.reversal_input
                .chunks_exact_mut(l)
                .zip(head.reversal_output.chunks_exact_mut(l)),
        )
        .zip(
            head.sign
                .chunks_exact_mut(l)
                .zip(head.last_input.chunks_exact_mut(l)),
        )
        .zip(
            head.last_output
                .chunks_exact_mut(l)
                .zip(head.m_star.chunks_exact_mut(l)),
        )
        .zip(head.ln_a.chunks_exact_mut(l));
    // The columns of each whole chunk (no vector operation in this closure: a closure is
    // compiled without the kernel's target features).
    let mut chunks = (0..).step_by(l).zip(chunks).map(|(start, chunk)| {
        let ((((((io, k), c), r), sl), lm), ln_a) = chunk;
        let (input, output) = io;
        let one = ColumnsMut {
            k1: k.0,
            k2: k.1,
            inv_k2: c.0,
            ln_k2: c.1,
            reversal_input: r.0,
            reversal_output: r.1,
            sign: sl.0,
            last_input: sl.1,
            last_output: lm.0,
            m_star: lm.1,
            ln_a,
        };
        (start, one, input, output)
    });
    // Software-pipelined: the next chunk's state is loaded before this chunk's is stored, so
    // that no load waits on the store just before it to an address equal modulo 4 KiB (a
    // `Vec` bank spreads its columns modulo 4 KiB, which keeps older stores apart; an array
    // bank's columns may agree there). Measured with the columns in separate allocations
    // (docs/performance.md): `step` inverse 6–12 % faster, f32 8–18 %, and the f64 direct
    // operator 1–3 %; the f32 direct operator, whose chunks of two vectors of 16 or 8 lanes
    // with its larger state spill registers when two chunks are live, 6 % slower (and in
    // one run with the spread columns the f32 inverse took 0.968 ns pipelined, 1.023 not).
    // The direct operator now runs chunks of four vectors, one at a time (`run`): on an Intel
    // Xeon (AVX-512), `cargo bench -p hyst-core --bench bank`, rows cold, `step` direct f64
    // 0.40 → 0.33 × scalar, and 0.56 → 0.43 with the AVX2 kernel forced (two vectors
    // pipelined before).
    if F::DIRECT {
        for (start, mut one, input, output) in chunks {
            visit::<V, F>(&mut one, input, output, start, l)?;
        }
    } else if let Some((mut start, mut one, input, mut output)) = chunks.next() {
        let zero = <V::T as Real>::ZERO;
        let mut x = column::<V>(input, 0, l, zero);
        let (mut st, mut changed) = load::<V, F>(&one, 0, l, x);
        loop {
            let y = tick::<V, F>(&mut st, x, start, l, &mut changed)?;
            let Some((next_start, next, next_input, next_output)) = chunks.next() else {
                store::<V, F>(&mut one, output, 0, l, &st, y, changed);
                break;
            };
            let next_x = column::<V>(next_input, 0, l, zero);
            let (next_st, next_changed) = load::<V, F>(&next, 0, l, next_x);
            store::<V, F>(&mut one, output, 0, l, &st, y, changed);
            (start, one, output) = (next_start, next, next_output);
            (x, st, changed) = (next_x, next_st, next_changed);
        }
    }
    if full < n {
        visit::<V, F>(&mut rest, input_rest, output_rest, full, n - full)?;
    }
    Ok(None)
}

/// One tick of the chunk of `width` channels whose columns are `cols` (channel `start` first):
/// the state loaded, the tick, the state stored.
#[cfg_attr(not(debug_assertions), inline(always))]
fn visit<V: Simd, F: BankFormula>(
    cols: &mut ColumnsMut<'_, V::T>,
    input: &[V::T],
    output: &mut [V::T],
    start: usize,
    width: usize,
) -> Result<(), BankError> {
    let zero = <V::T as Real>::ZERO;
    let x = column::<V>(input, 0, width, zero);
    let (mut st, mut changed) = load::<V, F>(cols, 0, width, x);
    let y = tick::<V, F>(&mut st, x, start, width, &mut changed)?;
    store::<V, F>(cols, output, 0, width, &st, y, changed);
    Ok(())
}

/// A chunk's outputs `y` of one tick and its state after it into its columns.
#[cfg_attr(not(debug_assertions), inline(always))]
fn store<V: Simd, F: BankFormula>(
    cols: &mut ColumnsMut<'_, V::T>,
    output: &mut [V::T],
    start: usize,
    width: usize,
    st: &State<V>,
    y: V,
    changed: bool,
) {
    put(output, start, width, y);
    put_state::<V, F>(cols, start, width, st, changed);
}

/// A chunk's state into its columns (channels `start .. start + width`): the last point, and
/// the reversal point, the sign and the direct formula's cache only when some lane `changed`
/// them (they change only at reversals and at a channel's first sample: most calls of a few
/// ticks skip them).
#[cfg_attr(not(debug_assertions), inline(always))]
fn put_state<V: Simd, F: BankFormula>(
    cols: &mut ColumnsMut<'_, V::T>,
    start: usize,
    width: usize,
    st: &State<V>,
    changed: bool,
) {
    put(cols.last_input, start, width, st.lin);
    put(cols.last_output, start, width, st.lout);
    if changed {
        put(cols.reversal_input, start, width, st.rin);
        put(cols.reversal_output, start, width, st.rout);
        let sign = if F::DIRECT {
            st.sign
        } else {
            sign_of(st.neg_k2)
        };
        put(cols.sign, start, width, sign);
        if F::DIRECT {
            put(cols.m_star, start, width, st.m_star);
            put(cols.ln_a, start, width, st.ln_a);
        }
    }
}

/// The first tick of `t0..t1` with a sample whose magnitude is not below `limit` (NaN, ±∞ or
/// near the end of the float range), a vector at a time over the tile.
#[cfg_attr(not(debug_assertions), inline(always))]
fn first_beyond<V: Simd>(
    input: &[V::T],
    at: &Layout,
    t0: usize,
    t1: usize,
    limit: V::T,
) -> Option<usize> {
    // Not `>`: NaN is beyond too.
    let within = |x: &V::T| x.magnitude() <= limit;
    if at.channel_major {
        let mut first = None;
        for c in 0..at.n {
            let row = input
                .get(c * at.samples + t0..c * at.samples + t1)
                .unwrap_or(&[]);
            if !all_within::<V>(row, limit) {
                let t = row.iter().position(|x| !within(x)).map_or(t1, |i| t0 + i);
                first = Some(first.map_or(t, |f: usize| f.min(t)));
            }
        }
        first
    } else {
        let tile = input.get(t0 * at.n..t1 * at.n).unwrap_or(&[]);
        if all_within::<V>(tile, limit) {
            None
        } else {
            Some(
                tile.iter()
                    .position(|x| !within(x))
                    .map_or(t1, |i| t0 + i / at.n.max(1)),
            )
        }
    }
}

/// Whether every sample's magnitude is at most `limit` (false for NaN and ±∞ above a finite
/// limit), a vector at a time.
#[inline(always)]
fn all_within<V: Simd>(input: &[V::T], limit: V::T) -> bool {
    let lim = V::splat(limit);
    let mut chunks = input.chunks_exact(V::LANES);
    let mut ok = V::splat(<V::T as Real>::ZERO).equal(V::c(0.0));
    for c in &mut chunks {
        ok = V::and(ok, V::load(c).magnitude().less_eq(lim));
    }
    V::all(ok) && chunks.remainder().iter().all(|x| x.magnitude() <= limit)
}

/// Where the samples are: `n` channels, `samples` ticks, channel-major or time-major.
struct Layout {
    n: usize,
    samples: usize,
    channel_major: bool,
}

impl Layout {
    #[inline(always)]
    fn index(&self, c: usize, t: usize) -> usize {
        if self.channel_major {
            c * self.samples + t
        } else {
            t * self.n + c
        }
    }
}

/// The samples of tick `t` of the chunk at `start` (`width` channels; padding lanes 0).
#[inline(always)]
fn gather<V: Simd>(input: &[V::T], at: &Layout, start: usize, width: usize, t: usize) -> V {
    if !at.channel_major && width == V::LANES {
        let i = t * at.n + start;
        return V::load(input.get(i..i + V::LANES).unwrap_or(&[]));
    }
    let zero = <V::T as Real>::ZERO;
    let mut buf = [zero; MAX_LANES];
    for (i, b) in buf.iter_mut().enumerate().take(width) {
        *b = input.get(at.index(start + i, t)).copied().unwrap_or(zero);
    }
    V::load(&buf)
}

/// Writes the outputs `y` of tick `t` of the chunk at `start`.
#[inline(always)]
fn scatter<V: Simd>(output: &mut [V::T], at: &Layout, start: usize, width: usize, t: usize, y: V) {
    if !at.channel_major && width == V::LANES {
        let i = t * at.n + start;
        if let Some(slot) = output.get_mut(i..i + V::LANES) {
            y.store(slot);
        }
        return;
    }
    let mut buf = [<V::T as Real>::ZERO; MAX_LANES];
    y.store(&mut buf);
    for (i, b) in buf.iter().enumerate().take(width) {
        if let Some(slot) = output.get_mut(at.index(start + i, t)) {
            *slot = *b;
        }
    }
}

/// A chunk's state from the columns, and whether it differs from them in more than the last
/// point; a channel without history (last input NaN) starts at rest at its first sample `x0`
/// on the line output = input, rising (its first output is then exactly x0).
#[cfg_attr(not(debug_assertions), inline(always))]
fn load<V: Simd, F: BankFormula>(
    cols: &ColumnsMut<'_, V::T>,
    start: usize,
    width: usize,
    x0: V,
) -> (State<V>, bool) {
    let zero = <V::T as Real>::ZERO;
    let one = V::c(1.0);
    let lin = column::<V>(cols.last_input, start, width, zero);
    let started = lin.equal(lin);
    let mut st = State {
        k1: column::<V>(cols.k1, start, width, <V::T as Real>::from_f64(1.0)),
        k2: column::<V>(cols.k2, start, width, <V::T as Real>::from_f64(1.0)),
        rin: column::<V>(cols.reversal_input, start, width, zero),
        rout: column::<V>(cols.reversal_output, start, width, zero),
        sign: column::<V>(cols.sign, start, width, zero),
        lin,
        lout: column::<V>(cols.last_output, start, width, zero),
        inv_k2: one,
        ln_k2: one,
        m_star: one,
        ln_a: one,
        neg_k2: one,
        sm: one,
        ks: one,
    };
    let mut fresh = !V::all(started);
    if fresh {
        st.rin = V::select(started, st.rin, x0);
        st.rout = V::select(started, st.rout, x0);
        st.lin = V::select(started, st.lin, x0);
        st.lout = V::select(started, st.lout, x0);
        st.sign = V::select(started, st.sign, one);
    }
    if F::DIRECT {
        st.inv_k2 = column::<V>(cols.inv_k2, start, width, <V::T as Real>::from_f64(1.0));
        st.ln_k2 = column::<V>(cols.ln_k2, start, width, zero);
        st.m_star = column::<V>(cols.m_star, start, width, zero);
        st.ln_a = column::<V>(cols.ln_a, start, width, zero);
        // Cached values are NaN after `new` and `set_memory`.
        let valid = V::and(started, st.m_star.equal(st.m_star));
        if !V::all(valid) {
            fresh = true;
            let (m, ln_a) = direct_cache(&st);
            st.m_star = V::select(valid, st.m_star, m);
            st.ln_a = V::select(valid, st.ln_a, ln_a);
        }
    } else {
        st.neg_k2 = -(st.k2 * st.sign);
        st.ks = st.k1 * st.sign;
        st.sm = inverse_cache(&st);
    }
    (st, fresh)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `into_band` on one lane (`f64`, `f32` as their own one-lane vectors) against
    /// `within_band`, the scalar clamp of the rare path: both put the edges x ± k1 as rounded one
    /// float towards x where rounding left them outside.
    fn check<T: Lane>(x: T, k1: T) {
        for y in [x + k1, x - k1, x + k1 + k1, x - k1 - k1, x] {
            let clamped = into_band(y, x, k1);
            assert!(
                (clamped - x).magnitude() <= k1,
                "x {x:?} k1 {k1:?} y {y:?} -> {clamped:?}"
            );
            assert_eq!(clamped, within_band(y, x, k1), "x {x:?} k1 {k1:?} y {y:?}");
        }
    }

    /// Near the end of the float range |x| + k1 + |β0| overflows; the slack must stay finite,
    /// so that an output gone to ±∞ (or anywhere far out) still goes to the scalar operator.
    #[test]
    fn the_band_slack_stays_finite_at_the_end_of_the_range() {
        let mut st = State {
            k1: 1e300,
            k2: 1e-290,
            rin: 1e308,
            rout: 1e308,
            sign: -1.0,
            lin: 1e308,
            lout: 1e308,
            inv_k2: 1e290,
            ln_k2: 0.0,
            m_star: 0.0,
            ln_a: 0.0,
            neg_k2: 0.0,
            sm: 0.0,
            ks: 0.0,
        };
        let x = -1e308;
        for y in [f64::NEG_INFINITY, -1.7e308, x - 2e300] {
            assert!(!near_band(&st, x, y), "{y:e}");
        }
        assert!(near_band(&st, x, x - 1e300));
        st.rout = -f64::MAX;
        assert!(!near_band(&st, -f64::MAX, f64::NEG_INFINITY));
    }

    #[test]
    fn the_vector_band_clamp_is_the_scalar_one() {
        // Magnitudes of x from far below k1 to far above (where x ± k1 rounds outside the band
        // about half the time), both signs, powers of two and their neighbours.
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..200_000 {
            let k1 = 10f64.powf(-3.0 + 4.0 * next());
            let x = (next() - 0.5) * 10f64.powf(-4.0 + 24.0 * next());
            check::<f64>(x, k1);
            check::<f32>(x as f32, k1 as f32);
        }
        for e in -20..60 {
            let x = 2f64.powi(e);
            for x in [x, x.next_below(), x.next_above(), -x, (-x).next_below()] {
                check::<f64>(x, 1.0);
                check::<f64>(x, 0.75);
            }
        }
    }
}
