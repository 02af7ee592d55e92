//! `step`: one tick of every channel. Each chunk's state is loaded, run one tick and stored
//! (a visit); what a visit costs beyond the tick is what `step` costs beyond a block
//! (docs/performance.md, "How the bank is built").

use crate::block::Block;
use crate::chunk::{
    all_within, clamp_near, column, in_band, inverse_cache, inverse_from, load, mend, put,
    put_state, tick, State,
};
use crate::columns::ColumnsMut;
use crate::error::BankError;
use crate::formula::BankFormula;
use crate::lanes::decay;
use crate::vector::{Lane, Simd};
use hyst_core::parametric::Inverse;
use hyst_core::real::Real;

/// A block of one tick (`step`; both layouts are then `input[c]`): chunk by chunk, the state
/// loaded, one tick, the state stored, in a loop with none of the tiles' bookkeeping (a `step`
/// is a visit of every chunk per tick, so what a visit costs beyond the tick is what `step`
/// costs beyond a block).
#[cfg_attr(not(debug_assertions), inline(always))]
pub(super) fn one_tick<V: Simd, F: BankFormula>(
    tk: V::Token,
    cols: &mut ColumnsMut<'_, V::T>,
    block: &mut Block<'_, V::T>,
) -> Result<Option<usize>, BankError> {
    let n = cols.k1.len();
    let input = block.input.get(..n).unwrap_or(&[]);
    let output = block.output.get_mut(..n).unwrap_or(&mut []);
    if let Some(limit) = block.limit {
        if !all_within::<V>(tk, input, limit) {
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
    let chunks = (0..).step_by(l).zip(chunks).map(|(start, chunk)| {
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
    // The direct operator runs chunks of four vectors, one at a time (`run`): its chain is
    // long and its state large, and four vectors give the most to overlap (`cargo bench -p
    // hyst-bank --bench bank`, rows cold, measures it faster than two vectors pipelined). The
    // inverse runs chunks of `Simd::Tick` by `inverse_visit`, which measures faster than the
    // block's tick, software-pipelined, on every kernel.
    if F::DIRECT {
        for (start, mut one, input, output) in chunks {
            visit::<V, F>(tk, &mut one, input, output, start, l)?;
        }
    } else {
        for (start, mut one, input, output) in chunks {
            inverse_visit::<V>(tk, &mut one, input, output, start)?;
        }
    }
    if full < n {
        visit::<V, F>(tk, &mut rest, input_rest, output_rest, full, n - full)?;
    }
    Ok(None)
}

/// One tick of the chunk of `width` channels whose columns are `cols` (channel `start` first):
/// the state loaded, the tick, the state stored.
#[cfg_attr(not(debug_assertions), inline(always))]
fn visit<V: Simd, F: BankFormula>(
    tk: V::Token,
    cols: &mut ColumnsMut<'_, V::T>,
    input: &[V::T],
    output: &mut [V::T],
    start: usize,
    width: usize,
) -> Result<(), BankError> {
    let zero = <V::T as Real>::ZERO;
    let x = column::<V>(tk, input, 0, width, zero);
    let (mut st, mut changed) = load::<V, F>(cols, 0, width, x);
    let y = tick::<V, F>(&mut st, x, start, width, &mut changed)?;
    store::<V, F>(cols, output, 0, width, &st, y, changed);
    Ok(())
}

/// One tick of eq. (4) on a whole chunk of channels that have all started (`step`): the memory
/// update of the chunk module's `observe` and eq. (4) by [`inverse_from`], bit for bit [`tick`],
/// arranged for a tick that is a chunk's only one:
/// - the exponent −k2 ũd = (x − α0)(−k2 s) is computed for both outcomes of the memory update
///   before it: the memory unchanged, or a reversal at the last point, where it is
///   (x − x_last)(k2 s) = −p exactly, p the product the reversal test looks at. The test then
///   only selects, off the chain to `decay`;
/// - the reversal point and the sign go to their columns when a lane reversed. With 32
///   registers ([`Simd::REGISTERS`], AVX-512) the memory after the update stays in registers
///   across `decay`. With 16, LLVM spilled it; so only the exponent and the reversal test's
///   outcome stay in registers past the test: after a compiler barrier the reversal loads its
///   inputs again (fewer instructions under callgrind, `bank_count step inverse f64`, than
///   keeping them for it), and eq. (4) loads x, k1 and the memory after the update again after
///   `decay` ([`reloaded`]: s k1 and s M* formed anew, bit for bit what the update gives).
///   AVX-512 has no barrier: with one, f32 `step` (`cargo bench -p hyst-bank --bench bank`,
///   rows in cache) runs slower even than the block's tick;
/// - the output goes to `output` before the band test, and the test's rare path ([`edge`],
///   behind a call of a `#[cold]` function) reads everything from memory: nothing is kept in
///   registers or on the stack for it.
///
/// With AVX2, a visit of two vectors spills nothing and one of four (faster: more to overlap)
/// a few values of `decay`; the block's tick, software-pipelined, spills three registers for
/// every value it loads or stores. Blocks keep [`tick`]: there the state stays in registers
/// from tick to tick, and the exponent for both outcomes measures slower there.
#[cfg_attr(not(debug_assertions), inline(always))]
fn inverse_visit<V: Simd>(
    tk: V::Token,
    cols: &mut ColumnsMut<'_, V::T>,
    input: &[V::T],
    output: &mut [V::T],
    start: usize,
) -> Result<(), BankError>
where
    V::T: Lane,
{
    let (l, zero) = (V::LANES, <V::T as Real>::ZERO);
    let x = column::<V>(tk, input, 0, l, zero);
    let lin = column::<V>(tk, cols.last_input, 0, l, zero);
    if !V::all(lin.equal(lin)) {
        // A channel's first sample: the general tick.
        return visit::<V, Inverse>(tk, cols, input, output, start, l);
    }
    let sign = column::<V>(tk, cols.sign, 0, l, zero);
    let neg_k2 = -(column::<V>(tk, cols.k2, 0, l, zero) * sign);
    let p = (x - lin) * neg_k2;
    let rin = column::<V>(tk, cols.reversal_input, 0, l, zero);
    let reversed = V::c(tk, 0.0).less(p);
    let z = V::select(reversed, -p, (x - rin) * neg_k2);
    let (e, x, k1, ks, sm) = if V::REGISTERS >= 32 {
        // The memory after the update stays in registers across `decay`.
        let rout = column::<V>(tk, cols.reversal_output, 0, l, zero);
        let (rin, rout, sign) = if V::any(reversed) {
            let lout = column::<V>(tk, cols.last_output, 0, l, zero);
            reverse::<V>(cols, reversed, (lin, lout), (rin, rout), sign)
        } else {
            (rin, rout, sign)
        };
        let e = decay(z);
        let k1 = column::<V>(tk, cols.k1, 0, l, zero);
        let ks = k1 * sign;
        (e, x, k1, ks, inverse_cache(ks, rin, rout))
    } else {
        // Only the exponent stays in registers across `decay`, and only it and the reversal
        // test's outcome across the reversal, which loads its inputs again after a barrier.
        let any = V::any(reversed);
        core::hint::black_box(());
        if any {
            let last = (
                column::<V>(tk, cols.last_input, 0, l, zero),
                column::<V>(tk, cols.last_output, 0, l, zero),
            );
            let reversal = (
                column::<V>(tk, cols.reversal_input, 0, l, zero),
                column::<V>(tk, cols.reversal_output, 0, l, zero),
            );
            let sign = column::<V>(tk, cols.sign, 0, l, zero);
            reverse::<V>(cols, reversed, last, reversal, sign);
        }
        reloaded::<V>(cols, input, z)
    };
    let y = inverse_from(x, e, sm, ks);
    put(output, 0, l, y);
    // The rare path reads x, y, k1 and the state from memory: nothing is kept for it.
    core::hint::black_box(());
    if !in_band(y, x, k1) {
        cold();
        return edge::<V>(tk, cols, input, output, start);
    }
    put(cols.last_input, 0, l, x);
    put(cols.last_output, 0, l, y);
    Ok(())
}

/// The memory update of a visit in which some lane reversed (the chunk module's `observe`, bit
/// for bit): where `reversed`, the last point (x, y) becomes the reversal point (α0, β0) and the
/// sign s flips. The memory after it goes to its columns and is returned as (α0, β0, s).
#[inline(always)]
fn reverse<V: Simd>(
    cols: &mut ColumnsMut<'_, V::T>,
    reversed: V::M,
    (lin, lout): (V, V),
    (rin, rout): (V, V),
    sign: V,
) -> (V, V, V) {
    let l = V::LANES;
    let rin = V::select(reversed, lin, rin);
    let rout = V::select(reversed, lout, rout);
    let sign = sign.negate_where(reversed);
    put(cols.reversal_input, 0, l, rin);
    put(cols.reversal_output, 0, l, rout);
    put(cols.sign, 0, l, sign);
    (rin, rout, sign)
}

/// e^z by `decay`, then x, k1, s k1 and s M* loaded again from the input and the columns after
/// a compiler barrier (`black_box` is an empty `asm!` that may read and write any memory), so
/// that none of them is kept in a register across `decay`.
#[inline(always)]
fn reloaded<V: Simd>(cols: &ColumnsMut<'_, V::T>, input: &[V::T], z: V) -> (V, V, V, V, V)
where
    V::T: Lane,
{
    let tk = z.token();
    let (l, zero) = (V::LANES, <V::T as Real>::ZERO);
    core::hint::black_box(());
    let e = decay(z);
    let x = column::<V>(tk, input, 0, l, zero);
    let k1 = column::<V>(tk, cols.k1, 0, l, zero);
    let ks = k1 * column::<V>(tk, cols.sign, 0, l, zero);
    let sm = inverse_cache(
        ks,
        column::<V>(tk, cols.reversal_input, 0, l, zero),
        column::<V>(tk, cols.reversal_output, 0, l, zero),
    );
    (e, x, k1, ks, sm)
}

/// The rare path of a visit whose output (in `output`) is outside the band: usually rounding at
/// the band's edge ([`clamp_near`], β0 after the memory update in its column), else [`mend`] on
/// the state after the memory update, from the columns (the last point not yet moved).
#[cfg_attr(not(debug_assertions), inline(always))]
fn edge<V: Simd>(
    tk: V::Token,
    cols: &mut ColumnsMut<'_, V::T>,
    input: &[V::T],
    output: &mut [V::T],
    start: usize,
) -> Result<(), BankError>
where
    V::T: Lane,
{
    let (l, zero) = (V::LANES, <V::T as Real>::ZERO);
    let x = column::<V>(tk, input, 0, l, zero);
    let y = column::<V>(tk, output, 0, l, zero);
    let k1 = column::<V>(tk, cols.k1, 0, l, zero);
    let rout = column::<V>(tk, cols.reversal_output, 0, l, zero);
    if let Some(clamped) = clamp_near(k1, rout, x, y) {
        finish(cols, output, x, clamped);
        return Ok(());
    }
    let (mut st, _) = load::<V, Inverse>(cols, 0, l, x);
    let mut changed = false;
    let y = mend::<V, Inverse>(&mut st, x, y, start, l, &mut changed)?;
    if changed {
        put_state::<V, Inverse>(cols, 0, l, &st, true);
    }
    finish(cols, output, x, y);
    Ok(())
}

/// A visit's output `y` to `output` and the last point (x, y) to its columns.
#[inline(always)]
fn finish<V: Simd>(cols: &mut ColumnsMut<'_, V::T>, output: &mut [V::T], x: V, y: V) {
    let l = V::LANES;
    put(output, 0, l, y);
    put(cols.last_input, 0, l, x);
    put(cols.last_output, 0, l, y);
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

/// Marks the path that calls it as rarely taken (a call of a `#[cold]` function: the compiler
/// then keeps the common path's values in registers and spills only on the rare one).
#[cold]
#[inline(never)]
fn cold() {}
