//! The bank's kernels, written once against [`Simd`]: a chunk of `V::LANES` channels keeps its
//! state in registers while the ticks go by (time inside, channels outside), so a tick costs
//! the arithmetic and one load and store of the samples. The chunk and its tick are the `chunk`
//! module's; a block of one tick (`step`) runs the `step` module's visits instead.

use crate::block::Block;
use crate::chunk::{all_within, load, put_state, tick, MAX_LANES};
use crate::columns::ColumnsMut;
use crate::error::BankError;
use crate::formula::BankFormula;
use crate::step::one_tick;
use crate::vector::Simd;
use hyst_core::real::Real;

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
    tk: V::Token,
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
        // shorter one runs `Simd::Tick`, two chunks at a time (see the `step` module).
        return if F::DIRECT {
            one_tick::<V, F>(tk, cols, block)
        } else {
            one_tick::<V::Tick, F>(tk, cols, block)
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
            Some(limit) => first_beyond::<V>(tk, input, &layout, t0, t1, limit),
            None => None,
        };
        if let Some(bad) = stop {
            t1 = bad;
        }
        let mut start = 0;
        while start < n && t0 < t1 {
            let width = (n - start).min(V::LANES);
            let x0 = gather::<V>(tk, input, &layout, start, width, t0);
            let (mut st, mut changed) = load::<V, F>(cols, start, width, x0);
            let mut x = x0;
            for t in t0..t1 {
                let y = tick::<V, F>(&mut st, x, start, width, &mut changed)?;
                // The next samples are loaded before this tick's outputs are stored: with rows
                // of 4 KiB (1,024 f32 channels) a load after a store to the same address modulo
                // 4 KiB waits for it (4K aliasing).
                if t + 1 < t1 {
                    x = gather::<V>(tk, input, &layout, start, width, t + 1);
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

/// The first tick of `t0..t1` with a sample whose magnitude is not below `limit` (NaN, ±∞ or
/// near the end of the float range), a vector at a time over the tile.
#[cfg_attr(not(debug_assertions), inline(always))]
fn first_beyond<V: Simd>(
    tk: V::Token,
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
            if !all_within::<V>(tk, row, limit) {
                let t = row.iter().position(|x| !within(x)).map_or(t1, |i| t0 + i);
                first = Some(first.map_or(t, |f: usize| f.min(t)));
            }
        }
        first
    } else {
        let tile = input.get(t0 * at.n..t1 * at.n).unwrap_or(&[]);
        if all_within::<V>(tk, tile, limit) {
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
fn gather<V: Simd>(
    tk: V::Token,
    input: &[V::T],
    at: &Layout,
    start: usize,
    width: usize,
    t: usize,
) -> V {
    if !at.channel_major && width == V::LANES {
        let i = t * at.n + start;
        return V::load(tk, input.get(i..i + V::LANES).unwrap_or(&[]));
    }
    let zero = <V::T as Real>::ZERO;
    let mut buf = [zero; MAX_LANES];
    for (i, b) in buf.iter_mut().enumerate().take(width) {
        *b = input.get(at.index(start + i, t)).copied().unwrap_or(zero);
    }
    V::load(tk, &buf)
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
