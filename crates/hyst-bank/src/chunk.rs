//! A chunk of `V::LANES` channels of the bank, written once against [`Simd`]: its state in
//! registers, and its tick: Definition 2.1's memory update with selects, then eq. (4) (inverse)
//! or eq. (2) (direct) on every lane. Where a lane's output is not within the band
//! |output − input| ≤ k1 as computed in floating point (rounding at the band's edge, or a value
//! that is not finite because an intermediate overflowed), the scalar operator computes that
//! lane from the same memory, and the output is put inside the band (the rare path,
//! [`repair`]). Blocks run ticks of a chunk in the `kernel` module, `step` one tick in the
//! `step` module.
//!
//! The large functions here are `#[inline(always)]` only when optimising: the kernels need them
//! inlined into their `#[target_feature]` entry points, but in debug builds the unoptimised
//! frames of all of them inlined together need more than a thread's 2 MiB of stack.

use crate::columns::ColumnsMut;
use crate::error::BankError;
use crate::formula::BankFormula;
use crate::lanes::{decay, exp, fsc_step, ln, omega_series, omega_start, omega_v};
use crate::vector::{Lane, Simd};
use hyst_core::k2law::ConstantK2;
use hyst_core::memory::{Direction, Memory};
use hyst_core::operator::Operator;
use hyst_core::parametric::ParametricHysteresis;
use hyst_core::real::Real;

/// The most lanes of any vector (AVX-512 f32).
pub(super) const MAX_LANES: usize = 64;

/// A chunk's state: the columns of its channels, and the direct formula's cached values.
#[derive(Clone, Copy)]
pub(super) struct State<V> {
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
pub(super) fn column<V: Simd>(
    tk: V::Token,
    s: &[V::T],
    start: usize,
    width: usize,
    fill: V::T,
) -> V {
    if width == V::LANES {
        // An exact range: the slice's length is then the constant V::LANES, so the vector
        // loads inside (a `Pair` splits it) need no length checks of their own.
        return V::load(tk, s.get(start..start + V::LANES).unwrap_or(&[]));
    }
    let mut buf = [fill; MAX_LANES];
    for (b, v) in buf.iter_mut().zip(s.iter().skip(start).take(width)) {
        *b = *v;
    }
    V::load(tk, &buf)
}

/// Writes the first `width` lanes of `v` to `s[start..]`.
#[inline(always)]
pub(super) fn put<V: Simd>(s: &mut [V::T], start: usize, width: usize, v: V) {
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
    let tk = st.k1.token();
    let zero = V::c(tk, 0.0);
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
    let tk = x.token();
    let step = x - st.lin;
    let reversed = if F::DIRECT {
        (step * st.sign).less(V::c(tk, 0.0))
    } else {
        V::c(tk, 0.0).less(step * st.neg_k2)
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
    let tk = neg_k2_s.token();
    V::select(neg_k2_s.less(V::c(tk, 0.0)), V::c(tk, 1.0), V::c(tk, -1.0))
}

/// Eq. (4) with the transformation folded in: v = (x − α0 + β0) + (1 − e^(−k2 ũd)) · s M*,
/// ũd = s (x − α0), s M* = s k1 − (β0 − α0), which is v = x + s k1 − e^(−k2 ũd) s M*.
#[cfg_attr(not(debug_assertions), inline(always))]
fn inverse_output<V: Simd>(st: &State<V>, x: V) -> V
where
    V::T: Lane,
{
    // −k2 ũd as (x − α0) (−k2 s): the scalar operator's −(k2 ũd), bit for bit (s = ±1).
    inverse_from(x, decay((x - st.rin) * st.neg_k2), st.sm, st.ks)
}

/// Eq. (4)'s output v = x + s k1 − e^z s M* from the decay e^z = e^(−k2 ũd) ([`decay`]), s M*
/// and s k1: the one evaluation of it, for the block's tick and `step`'s alike (bit for bit the
/// same).
#[inline(always)]
pub(super) fn inverse_from<V: Simd>(x: V, e: V, sm: V, ks: V) -> V {
    x + (-e).fma(sm, ks)
}

/// s M* = s k1 − (β0 − α0) of eq. (4), from s k1 and the reversal point.
#[inline(always)]
pub(super) fn inverse_cache<V: Simd>(ks: V, rin: V, rout: V) -> V {
    ks + (rin - rout)
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
    let tk = x.token();
    let zero = V::c(tk, 0.0);
    let vt = (x - st.rin) * st.sign;
    let y = (st.m_star - vt).fma(st.k2, st.ln_a);
    let t = exp(y);
    let series = omega_series(t);
    let exact = y.less(V::splat(tk, <V::T as Lane>::OMEGA_SERIES));
    let w = if V::all(exact) {
        series
    } else {
        let (w1, r) = fsc_step(omega_start(y, series), y);
        let ok = V::or(
            exact,
            r.magnitude()
                .less_eq(V::splat(tk, <V::T as Lane>::RESIDUAL_OK)),
        );
        let w = V::select(exact, series, w1);
        if V::all(ok) {
            w
        } else {
            V::select(ok, w, omega_v(y))
        }
    };
    let plain = w.fma(st.inv_k2, vt - st.m_star);
    let huge = V::splat(tk, <V::T as Real>::EXP_ARG_MAX).less(y);
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
    let tk = x.token();
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
    Ok([
        V::load(tk, &ys),
        V::load(tk, &rin),
        V::load(tk, &rout),
        V::load(tk, &sign),
    ])
}

/// `y` clamped so that |y − x|, computed in floating point, is at most k1 (the test
/// [`hyst_core::Memory::validate`] makes): the edges x ± k1 rounded, then moved one float towards
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
    let tk = y.token();
    let step = V::splat(tk, <V::T as Lane>::ONE_STEP);
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
fn near_band<V: Simd>(k1: V, rout: V, x: V, y: V) -> V::M
where
    V::T: Lane,
{
    let tk = k1.token();
    let slack = V::splat(tk, <V::T as Lane>::ONE_STEP) * V::c(tk, 192.0);
    let scale = x.magnitude().max_or(k1).max_or(rout.magnitude());
    (y - x).magnitude().less_eq(scale.fma(slack, k1))
}

/// `y` put inside the band by [`into_band`] when every lane is outside it by no more than
/// rounding explains ([`near_band`]; `rout` the reversal output β0 after the memory update);
/// `None` when a lane needs the rare path.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(super) fn clamp_near<V: Simd>(k1: V, rout: V, x: V, y: V) -> Option<V>
where
    V::T: Lane,
{
    let clamped = into_band(y, x, k1);
    (in_band(clamped, x, k1) && V::all(near_band(k1, rout, x, y))).then_some(clamped)
}

/// Whether every lane's output is within the band |y − x| ≤ k1 (false for NaN and ±∞).
///
/// A function, not a closure: a closure's body is compiled without the kernel's target
/// features, so the vector operations in it stay calls (measured on the AVX2 kernel: the band
/// test as a closure was a call per chunk and tick, 42 instructions per channel-sample).
#[inline(always)]
pub(super) fn in_band<V: Simd>(y: V, x: V, k1: V) -> bool {
    V::all((y - x).magnitude().less_eq(k1))
}

/// One tick of a chunk: memory update, formula, band check (rare path [`repair`]), last point.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(super) fn tick<V: Simd, F: BankFormula>(
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
        st.sm = inverse_cache(st.ks, st.rin, st.rout);
    }
    let mut y = if F::DIRECT {
        direct_output(st, x)
    } else {
        inverse_output(st, x)
    };
    // One test on the hot path, also false for NaN and ±∞.
    if !in_band(y, x, st.k1) {
        y = mend::<V, F>(st, x, y, start, width, changed)?;
    }
    st.lin = x;
    st.lout = y;
    Ok(y)
}

/// The output `y` of a tick that is not within the band |y − x| ≤ k1 (`st` after the memory
/// update), put inside it: usually an output that rounding put an ulp outside (far from the
/// reversal point the output is x ± k1 as rounded: e^(−k2 ũd) vanishes for large k2 or large
/// excursions, most ticks then), clamped in vector code; the rare path ([`repair`]) only for
/// what that does not mend (not finite, or further out than rounding explains), which also
/// sets `changed` and updates the memory in `st`.
#[cfg_attr(not(debug_assertions), inline(always))]
pub(super) fn mend<V: Simd, F: BankFormula>(
    st: &mut State<V>,
    x: V,
    y: V,
    start: usize,
    width: usize,
    changed: &mut bool,
) -> Result<V, BankError> {
    if let Some(clamped) = clamp_near(st.k1, st.rout, x, y) {
        return Ok(clamped);
    }
    if !F::DIRECT {
        st.sign = sign_of(st.neg_k2);
    }
    let out;
    [out, st.rin, st.rout, st.sign] = repair::<V, F>(*st, x, y, start, width)?;
    *changed = true;
    if F::DIRECT {
        (st.m_star, st.ln_a) = direct_cache(st);
    } else {
        st.neg_k2 = -(st.k2 * st.sign);
        st.ks = st.k1 * st.sign;
        st.sm = inverse_cache(st.ks, st.rin, st.rout);
    }
    Ok(out)
}

/// A chunk's state into its columns (channels `start .. start + width`): the last point, and
/// the reversal point, the sign and the direct formula's cache only when some lane `changed`
/// them (they change only at reversals and at a channel's first sample: most calls of a few
/// ticks skip them).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(super) fn put_state<V: Simd, F: BankFormula>(
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

/// Whether every sample's magnitude is at most `limit` (false for NaN and ±∞ above a finite
/// limit), a vector at a time.
///
/// At the float range's end as the limit (the bank's for every k1 below about 1e291 in f64,
/// 1e30 in f32), the samples are first added up, one addition a vector in two sums: ∞ and NaN
/// stay in a sum (and make its product with 0 NaN), so finite sums mean finite samples, within
/// the limit. A sum that overflows from finite samples leaves the answer to the test of each
/// sample that follows. (`step` pays for this pass before any channel's memory may change: the
/// test of each sample took 6 % of an AVX2 `step` of the inverse.)
#[inline(always)]
pub(super) fn all_within<V: Simd>(tk: V::Token, input: &[V::T], limit: V::T) -> bool {
    if limit == <V::T as num_traits::Float>::max_value() {
        let mut pairs = input.chunks_exact(2 * V::LANES);
        let (mut a, mut b) = (V::c(tk, 0.0), V::c(tk, 0.0));
        for pair in &mut pairs {
            let (low, high) = pair.split_at(V::LANES);
            a = a + V::load(tk, low);
            b = b + V::load(tk, high);
        }
        let sum = a + b;
        if V::all((sum * V::c(tk, 0.0)).equal(V::c(tk, 0.0)))
            && pairs.remainder().iter().all(|x| x.magnitude() <= limit)
        {
            return true;
        }
    }
    let lim = V::splat(tk, limit);
    let mut chunks = input.chunks_exact(V::LANES);
    let mut ok = V::splat(tk, <V::T as Real>::ZERO).equal(V::c(tk, 0.0));
    for c in &mut chunks {
        ok = V::and(ok, V::load(tk, c).magnitude().less_eq(lim));
    }
    V::all(ok) && chunks.remainder().iter().all(|x| x.magnitude() <= limit)
}

/// A chunk's state from the columns, and whether it differs from them in more than the last
/// point; a channel without history (last input NaN) starts at rest at its first sample `x0`
/// on the line output = input, rising (its first output is then exactly x0).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(super) fn load<V: Simd, F: BankFormula>(
    cols: &ColumnsMut<'_, V::T>,
    start: usize,
    width: usize,
    x0: V,
) -> (State<V>, bool) {
    let tk = x0.token();
    let zero = <V::T as Real>::ZERO;
    let one = V::c(tk, 1.0);
    let lin = column::<V>(tk, cols.last_input, start, width, zero);
    let started = lin.equal(lin);
    let mut st = State {
        k1: column::<V>(tk, cols.k1, start, width, <V::T as Real>::from_f64(1.0)),
        k2: column::<V>(tk, cols.k2, start, width, <V::T as Real>::from_f64(1.0)),
        rin: column::<V>(tk, cols.reversal_input, start, width, zero),
        rout: column::<V>(tk, cols.reversal_output, start, width, zero),
        sign: column::<V>(tk, cols.sign, start, width, zero),
        lin,
        lout: column::<V>(tk, cols.last_output, start, width, zero),
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
        st.inv_k2 = column::<V>(tk, cols.inv_k2, start, width, <V::T as Real>::from_f64(1.0));
        st.ln_k2 = column::<V>(tk, cols.ln_k2, start, width, zero);
        st.m_star = column::<V>(tk, cols.m_star, start, width, zero);
        st.ln_a = column::<V>(tk, cols.ln_a, start, width, zero);
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
        st.sm = inverse_cache(st.ks, st.rin, st.rout);
    }
    (st, fresh)
}

#[cfg(test)]
mod tests {
    use super::*;
    use hyst_test_support::rng::{Random, XorShift64};

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
            assert!(!near_band(st.k1, st.rout, x, y), "{y:e}");
        }
        assert!(near_band(st.k1, st.rout, x, x - 1e300));
        st.rout = -f64::MAX;
        assert!(!near_band(st.k1, st.rout, -f64::MAX, f64::NEG_INFINITY));
    }

    #[test]
    fn the_vector_band_clamp_is_the_scalar_one() {
        // Magnitudes of x from far below k1 to far above (where x ± k1 rounds outside the band
        // about half the time), both signs, powers of two and their neighbours.
        let mut rng = XorShift64(0x2545_f491_4f6c_dd1d);
        let mut next = || rng.unit();
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

    /// The input check answers as the test of each sample does, its sums included: samples
    /// that overflow a sum while finite, an ∞ of each sign (whose sum is NaN), NaN, in any
    /// place of a row of any length, at the float range's end as the limit and below it.
    #[test]
    fn the_input_check_is_the_test_of_each_sample() {
        use crate::simd::Pair;
        use std::{vec, vec::Vec};
        fn each(row: &[f64], limit: f64) -> bool {
            row.iter().all(|x| x.abs() <= limit)
        }
        let specials = [
            f64::MAX,
            -f64::MAX,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            1e300,
        ];
        for limit in [f64::MAX, f64::MAX - 4.0 * 1e300, 2.0] {
            for n in [0_usize, 1, 7, 8, 9, 17, 40] {
                let base: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
                let mut rows = vec![base.clone(), vec![f64::MAX; n]];
                for (i, a) in specials.iter().enumerate() {
                    for at in [0, n / 2, n.saturating_sub(1)] {
                        let mut row = base.clone();
                        if let Some(v) = row.get_mut(at) {
                            *v = *a;
                        }
                        if let Some(v) = row.get_mut((at + 3) % n.max(1)) {
                            *v = specials[(i + 1) % specials.len()];
                        }
                        rows.push(row);
                    }
                }
                for row in &rows {
                    let want = each(row, limit);
                    assert_eq!(all_within::<f64>((), row, limit), want, "{row:?} {limit}");
                    assert_eq!(
                        all_within::<Pair<Pair<f64>>>((), row, limit),
                        want,
                        "{row:?} {limit}"
                    );
                }
            }
        }
    }
}
