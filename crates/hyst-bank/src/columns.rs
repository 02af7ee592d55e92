//! The storage of a bank's state: eleven columns of one value per channel (structure of
//! arrays), in `[[T; N]; 11]` or, with `std`, one `Vec<T>` whose columns start five cache lines
//! apart modulo 4 KiB (`SPREAD`); [`Columns`] owns them and [`ColumnsMut`] borrows those of a
//! range of channels, the part a kernel (or one thread's kernel) runs on.

/// The state columns, in this order in the storage (one value per channel each): k1, k2,
/// then the direct operator's 1 / k2 and ln k2 (fixed), then Definition 2.1's memory, then two
/// values per formula that change only at reversals (see [`ColumnsMut`]).
pub(super) const K1: usize = 0;
pub(super) const K2: usize = 1;
pub(super) const INV_K2: usize = 2;
pub(super) const LN_K2: usize = 3;
pub(super) const REVERSAL_INPUT: usize = 4;
pub(super) const REVERSAL_OUTPUT: usize = 5;
pub(super) const SIGN: usize = 6;
pub(super) const LAST_INPUT: usize = 7;
pub(super) const LAST_OUTPUT: usize = 8;
pub(super) const M_STAR: usize = 9;
pub(super) const LN_A: usize = 10;
/// The number of state columns.
pub(super) const COLUMNS: usize = 11;

/// Where column j starts with `Vec` storage, in bytes modulo 4 KiB: j × this. The columns of a
/// bank are one allocation, each column's start 320 bytes (five cache lines) after the last
/// one's modulo 4 KiB, so that a load of one column never waits on an older store to another
/// column at an address equal modulo 4 KiB (4K aliasing: the processor compares only the low
/// 12 bits of addresses before it knows whether they differ). Eleven columns at 320 bytes keep
/// any two at least five lines apart modulo 4 KiB. `cargo bench -p hyst-bank --bench bank`
/// measures `step` a few per cent faster this way than with columns in separate allocations.
#[cfg(feature = "std")]
pub(super) const SPREAD: usize = 320;

/// The bytes of the 4 KiB that addresses are compared in for 4K aliasing.
#[cfg(feature = "std")]
pub(super) const ALIAS_SPAN: usize = 4096;

/// The storage behind a bank's columns: `[[T; N]; 11]` for arrays, one `Vec<T>` with `std`.
/// Public only as the sealed [`Storage::Slab`].
#[doc(hidden)]
pub trait Slab<T>: Clone + core::fmt::Debug + PartialEq {
    /// Every value, columns one after another (with padding between them for `Vec`).
    fn flat(&self) -> &[T];
    /// Every value, mutably.
    fn flat_mut(&mut self) -> &mut [T];
}

impl<T: Copy + core::fmt::Debug + PartialEq, const N: usize> Slab<T> for [[T; N]; COLUMNS] {
    fn flat(&self) -> &[T] {
        self.as_flattened()
    }
    fn flat_mut(&mut self) -> &mut [T] {
        self.as_flattened_mut()
    }
}

#[cfg(feature = "std")]
impl<T: Copy + core::fmt::Debug + PartialEq> Slab<T> for std::vec::Vec<T> {
    fn flat(&self) -> &[T] {
        self
    }
    fn flat_mut(&mut self) -> &mut [T] {
        self
    }
}

/// The per-channel state columns (structure of arrays): `n` channels, column j at
/// `j * stride` in the slab. Public only as a parameter of the sealed
/// [`RunBlock`](crate::RunBlock); nothing outside the bank can build or read one.
#[doc(hidden)]
#[derive(Clone, Debug, PartialEq)]
pub struct Columns<B> {
    pub(super) slab: B,
    pub(super) n: usize,
    pub(super) stride: usize,
}

impl<B> Columns<B> {
    /// Column `j` (see [`K1`] and the others).
    pub(super) fn col<T>(&self, j: usize) -> &[T]
    where
        B: Slab<T>,
    {
        let at = j * self.stride;
        self.slab.flat().get(at..at + self.n).unwrap_or(&[])
    }

    /// Column `j`, mutably.
    pub(super) fn col_mut<T>(&mut self, j: usize) -> &mut [T]
    where
        B: Slab<T>,
    {
        let at = j * self.stride;
        self.slab
            .flat_mut()
            .get_mut(at..at + self.n)
            .unwrap_or(&mut [])
    }

    /// All channels' columns, borrowed.
    pub(super) fn view<T>(&mut self) -> ColumnsMut<'_, T>
    where
        B: Slab<T>,
    {
        let (n, stride) = (self.n, self.stride);
        let mut rest = self.slab.flat_mut();
        // The columns in their order in the slab (struct fields are evaluated in the order
        // written).
        let mut next = || {
            let all = core::mem::take(&mut rest);
            let (column, after) = all.split_at_mut(stride.min(all.len()));
            rest = after;
            column.split_at_mut(n.min(column.len())).0
        };
        ColumnsMut {
            k1: next(),
            k2: next(),
            inv_k2: next(),
            ln_k2: next(),
            reversal_input: next(),
            reversal_output: next(),
            sign: next(),
            last_input: next(),
            last_output: next(),
            m_star: next(),
            ln_a: next(),
        }
    }
}

/// The columns of a range of channels, borrowed: what a kernel runs on (a whole bank, or one
/// thread's part of it). Public only as a parameter of the sealed [`RunBlock`](crate::RunBlock).
#[doc(hidden)]
pub struct ColumnsMut<'a, T> {
    pub(super) k1: &'a [T],
    pub(super) k2: &'a [T],
    /// Direct operator: 1 / k2 and ln k2 (fixed).
    pub(super) inv_k2: &'a [T],
    pub(super) ln_k2: &'a [T],
    pub(super) reversal_input: &'a mut [T],
    pub(super) reversal_output: &'a mut [T],
    /// s = ±1 of Definition 2.1.
    pub(super) sign: &'a mut [T],
    /// NaN before the channel's first sample (no history).
    pub(super) last_input: &'a mut [T],
    pub(super) last_output: &'a mut [T],
    /// Direct operator: M* (eq. 2) and ln(k2 M*), which change only at reversals (NaN: to be
    /// computed from the memory when the channel next runs).
    pub(super) m_star: &'a mut [T],
    pub(super) ln_a: &'a mut [T],
}

impl<T> ColumnsMut<'_, T> {
    /// Every column's first `n` values (all of a shorter column): with `n` at most every
    /// column's length, the compiler knows that all have length `n`.
    pub(super) fn cut(&mut self, n: usize) -> ColumnsMut<'_, T> {
        let n = [
            self.k2.len(),
            self.inv_k2.len(),
            self.ln_k2.len(),
            self.reversal_input.len(),
            self.reversal_output.len(),
            self.sign.len(),
            self.last_input.len(),
            self.last_output.len(),
            self.m_star.len(),
            self.ln_a.len(),
        ]
        .into_iter()
        .fold(n.min(self.k1.len()), usize::min);
        fn c<T>(s: &[T], n: usize) -> &[T] {
            s.split_at(n.min(s.len())).0
        }
        fn m<T>(s: &mut [T], n: usize) -> &mut [T] {
            let n = n.min(s.len());
            s.split_at_mut(n).0
        }
        ColumnsMut {
            k1: c(self.k1, n),
            k2: c(self.k2, n),
            inv_k2: c(self.inv_k2, n),
            ln_k2: c(self.ln_k2, n),
            reversal_input: m(self.reversal_input, n),
            reversal_output: m(self.reversal_output, n),
            sign: m(self.sign, n),
            last_input: m(self.last_input, n),
            last_output: m(self.last_output, n),
            m_star: m(self.m_star, n),
            ln_a: m(self.ln_a, n),
        }
    }
}

impl<'a, T> ColumnsMut<'a, T> {
    /// Channels `..mid` and `mid..` (all of them and none when `mid` is beyond the channels):
    /// the parts of rayon's tasks, and `step`'s whole chunks and the rest.
    pub(super) fn split_at(self, mid: usize) -> (Self, Self) {
        fn cut<T>(x: &[T], mid: usize) -> (&[T], &[T]) {
            x.split_at(mid.min(x.len()))
        }
        fn cut_mut<T>(x: &mut [T], mid: usize) -> (&mut [T], &mut [T]) {
            let mid = mid.min(x.len());
            x.split_at_mut(mid)
        }
        let (k1a, k1b) = cut(self.k1, mid);
        let (k2a, k2b) = cut(self.k2, mid);
        let (ia, ib) = cut(self.inv_k2, mid);
        let (la, lb) = cut(self.ln_k2, mid);
        let (ria, rib) = cut_mut(self.reversal_input, mid);
        let (roa, rob) = cut_mut(self.reversal_output, mid);
        let (sa, sb) = cut_mut(self.sign, mid);
        let (lia, lib) = cut_mut(self.last_input, mid);
        let (loa, lob) = cut_mut(self.last_output, mid);
        let (ma, mb) = cut_mut(self.m_star, mid);
        let (aa, ab) = cut_mut(self.ln_a, mid);
        (
            Self {
                k1: k1a,
                k2: k2a,
                inv_k2: ia,
                ln_k2: la,
                reversal_input: ria,
                reversal_output: roa,
                sign: sa,
                last_input: lia,
                last_output: loa,
                m_star: ma,
                ln_a: aa,
            },
            Self {
                k1: k1b,
                k2: k2b,
                inv_k2: ib,
                ln_k2: lb,
                reversal_input: rib,
                reversal_output: rob,
                sign: sb,
                last_input: lib,
                last_output: lob,
                m_star: mb,
                ln_a: ab,
            },
        )
    }
}

/// The storage of a bank: `[T; N]` (arrays, no allocation) or `Vec<T>` (`std`), the type of
/// the k1 and k2 given to [`ParametricBank::new`](crate::ParametricBank::new).
pub trait Storage<T>: AsRef<[T]> + AsMut<[T]> + Clone {
    /// Where the bank's state columns live.
    #[doc(hidden)]
    type Slab: Slab<T>;
    /// Room for the state columns of `n` channels, every value `fill`, and the distance from
    /// one column's start to the next (in values).
    #[doc(hidden)]
    fn slab(n: usize, fill: T) -> (Self::Slab, usize);
}

impl<T: Copy + core::fmt::Debug + PartialEq, const N: usize> Storage<T> for [T; N] {
    type Slab = [[T; N]; COLUMNS];
    fn slab(_n: usize, fill: T) -> (Self::Slab, usize) {
        ([[fill; N]; COLUMNS], N)
    }
}

#[cfg(feature = "std")]
impl<T: Copy + core::fmt::Debug + PartialEq> Storage<T> for std::vec::Vec<T> {
    type Slab = std::vec::Vec<T>;
    /// One allocation, the columns [`SPREAD`] bytes apart modulo 4 KiB.
    fn slab(n: usize, fill: T) -> (Self::Slab, usize) {
        let size = core::mem::size_of::<T>().max(1);
        let (span, spread) = (ALIAS_SPAN / size, SPREAD / size);
        // The least stride ≥ n that is `spread` modulo `span`.
        let stride = n + (spread + span - n % span) % span;
        (std::vec![fill; (COLUMNS - 1) * stride + n], stride)
    }
}

#[cfg(test)]
#[cfg(feature = "std")]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use crate::vector::Lane;

    /// Where each column of `Vec` storage for `n` channels starts, in bytes modulo 4 KiB, and
    /// its length.
    fn starts<T: Lane>(n: usize) -> std::vec::Vec<(usize, usize)> {
        let (slab, stride) = <std::vec::Vec<T> as Storage<T>>::slab(n, T::one());
        let mut columns = Columns { slab, n, stride };
        let c = columns.view();
        let columns: [&[T]; COLUMNS] = [
            c.k1,
            c.k2,
            c.inv_k2,
            c.ln_k2,
            c.reversal_input,
            c.reversal_output,
            c.sign,
            c.last_input,
            c.last_output,
            c.m_star,
            c.ln_a,
        ];
        columns
            .iter()
            .map(|s| (s.as_ptr() as usize % ALIAS_SPAN, s.len()))
            .collect()
    }

    #[test]
    fn vec_columns_are_spread_over_the_4k_that_aliasing_compares() {
        fn check<T: Lane>(n: usize) {
            let at = starts::<T>(n);
            assert!(at.iter().all(|&(_, len)| len == n), "{n}: {at:?}");
            for (i, &(a, _)) in at.iter().enumerate() {
                for &(b, _) in &at[i + 1..] {
                    let d = a.abs_diff(b);
                    // At least five cache lines apart modulo 4 KiB, both ways round.
                    assert!(d.min(ALIAS_SPAN - d) >= SPREAD, "{n}: {at:?}");
                }
            }
        }
        for n in [1, 7, 64, 500, 512, 1000, 1024, 4096, 5000] {
            check::<f64>(n);
            check::<f32>(n);
        }
    }
}
