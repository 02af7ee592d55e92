//! A bank of operators: N channels, each its own H(k1, k2) (or H⁻¹) with its own memory
//! (Definition 2.1), stepped together — a deformable mirror's actuators, the axes of a stage.
//!
//! The state is a structure of arrays over storage `S` (`[T; N]` arrays without allocation, or
//! with `std` one `Vec<T>` whose columns start five cache lines apart modulo 4 KiB, see
//! [`Storage`]). In blocks the channels run in chunks of four vector registers (AVX-512:
//! 32 × f64, 64 × f32) whose state stays in registers while the ticks go by (four independent
//! dependency chains per tick, which the processor overlaps); one tick ([`ParametricBank::step`])
//! runs chunks of one or two vectors (four with SSE2 and the portable code), the next chunk's
//! state loaded before this one's is stored. The code is branch-free over lanes, written once
//! against a small vector trait ([`lanes`] has the elementary functions). With `std` on x86-64 the
//! instruction set is chosen at run time: AVX-512, else AVX2 + FMA, else SSE2 (x86-64's
//! baseline); other targets and `no_std` builds run the portable code (plain floats, four
//! channels at a time). [`isa`] tells which runs, [`force_isa`] chooses one. docs/performance.md
//! has the measurements behind these choices.
//!
//! The results agree with the scalar operator ([`crate::Hysteresis`],
//! [`crate::InverseHysteresis`]) to a few ulp, not bit for bit: the bank has its own `exp`, `ln`
//! and ω where the scalar operator calls the platform's `exp` and the `lambert_w` crate, and the
//! AVX2 and AVX-512 kernels fuse multiply-adds (so they also differ from the SSE2 and portable
//! kernels in the last bits). For every kernel, |bank − scalar| ≤ 4 ulp (inverse) and 16 ulp
//! (direct) of max(|input|, |output|, k1, |memory points|), tested in `tests/bank.rs`.
//!
//! Guarantees shared with the scalar operator: every output satisfies |output − input| ≤ k1 as
//! computed in floating point (so a saved memory always passes [`Memory::validate`]); a lane
//! whose output would leave that band or not be finite is computed by the scalar operator from
//! the same memory. A non-finite input, or a finite one whose output is beyond the float range,
//! is an error naming the channel; the ticks before it are done and every channel's memory is
//! as after them (for [`ParametricBank::step`]: unchanged).
//!
//! Inverse operator (eq. 4): v = (x − α0 + β0) + (1 − e^(−k2 ũd)) s M*, s M* cached per channel.
//! Direct operator (eq. 2): ũ = ṽ − M* + ω(y)/k2 with y = ln(k2 M*) + k2 (M* − ṽ) (the scalar
//! operator's W0(k2 M* e^(k2 (M* − ṽ))) in the log domain, so nothing overflows), and
//! ũ = (ln(k2 M*) − ln ω)/k2 where e^y would overflow. M* and ln(k2 M*) change only at reversals
//! and are cached per channel.

mod kernel;
pub mod lanes;
#[doc(hidden)]
pub mod simd;
#[cfg(all(feature = "std", target_arch = "x86_64"))]
mod x86;

use core::marker::PhantomData;

pub use lanes::Lane;

use crate::{Direct, Direction, Error, Formula, Inverse, Memory};

/// A channel's error: which channel, and the core's error for it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BankError {
    /// The channel (from 0).
    pub channel: usize,
    /// What is wrong.
    pub error: Error,
}

impl core::fmt::Display for BankError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "channel {}: {}", self.channel, self.error)
    }
}

#[cfg(feature = "std")]
impl std::error::Error for BankError {}

/// The state columns, in this order in the storage (one value per channel each): k1, k2,
/// then the direct operator's 1 / k2 and ln k2 (fixed), then Definition 2.1's memory, then two
/// values per formula that change only at reversals (see [`ColumnsMut`]).
const K1: usize = 0;
const K2: usize = 1;
const INV_K2: usize = 2;
const LN_K2: usize = 3;
const REVERSAL_INPUT: usize = 4;
const REVERSAL_OUTPUT: usize = 5;
const SIGN: usize = 6;
const LAST_INPUT: usize = 7;
const LAST_OUTPUT: usize = 8;
const M_STAR: usize = 9;
const LN_A: usize = 10;
/// The number of state columns.
const COLUMNS: usize = 11;

/// Where column j starts with `Vec` storage, in bytes modulo 4 KiB: j × this. The columns of a
/// bank are one allocation, each column's start 320 bytes (five cache lines) after the last
/// one's modulo 4 KiB, so that a load of one column never waits on an older store to another
/// column at an address equal modulo 4 KiB (4K aliasing: the processor compares only the low
/// 12 bits of addresses before it knows whether they differ). Eleven columns at 320 bytes keep
/// any two at least five lines apart modulo 4 KiB. Measured (docs/performance.md), against
/// columns in separate allocations: `step` direct f64 6–7 % faster, direct f32 8 %, inverse
/// f64 4–6 %.
const SPREAD: usize = 320;

/// The bytes of the 4 KiB that addresses are compared in for 4K aliasing.
const ALIAS_SPAN: usize = 4096;

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
/// `j * stride` in the slab. Public only as a parameter of the sealed [`RunBlock`]; nothing
/// outside the bank can build or read one.
#[doc(hidden)]
#[derive(Clone, Debug, PartialEq)]
pub struct Columns<B> {
    slab: B,
    n: usize,
    stride: usize,
}

impl<B> Columns<B> {
    /// Column `j` (see [`K1`] and the others).
    fn col<T>(&self, j: usize) -> &[T]
    where
        B: Slab<T>,
    {
        let at = j * self.stride;
        self.slab.flat().get(at..at + self.n).unwrap_or(&[])
    }

    /// Column `j`, mutably.
    fn col_mut<T>(&mut self, j: usize) -> &mut [T]
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
    fn view<T>(&mut self) -> ColumnsMut<'_, T>
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
/// thread's part of it). Public only as a parameter of the sealed [`RunBlock`].
#[doc(hidden)]
pub struct ColumnsMut<'a, T> {
    k1: &'a [T],
    k2: &'a [T],
    /// Direct operator: 1 / k2 and ln k2 (fixed).
    inv_k2: &'a [T],
    ln_k2: &'a [T],
    reversal_input: &'a mut [T],
    reversal_output: &'a mut [T],
    /// s = ±1 of Definition 2.1.
    sign: &'a mut [T],
    /// NaN before the channel's first sample (no history).
    last_input: &'a mut [T],
    last_output: &'a mut [T],
    /// Direct operator: M* (eq. 2) and ln(k2 M*), which change only at reversals (NaN: to be
    /// computed from the memory when the channel next runs).
    m_star: &'a mut [T],
    ln_a: &'a mut [T],
}

impl<T> ColumnsMut<'_, T> {
    /// Every column's first `n` values (all of a shorter column): with `n` at most every
    /// column's length, the compiler knows that all have length `n`.
    fn cut(&mut self, n: usize) -> ColumnsMut<'_, T> {
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
    fn split_at(self, mid: usize) -> (Self, Self) {
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

/// N operators of formula `F` ([`Direct`]: eq. 2, [`Inverse`]: eq. 4) stepped together, state
/// in storage `S`. Use [`Bank`] (arrays, no allocation) or, with `std`, [`BankVec`].
#[derive(Clone, Debug, PartialEq)]
pub struct ParametricBank<T, F, S: Storage<T>> {
    columns: Columns<S::Slab>,
    /// Inputs with |x| above this (or not finite) take the checked path (see `input_limit`).
    limit: T,
    formula: PhantomData<(T, F)>,
}

/// A bank of `N` channels in arrays: no allocation, `no_std`.
pub type Bank<T, F, const N: usize> = ParametricBank<T, F, [T; N]>;
/// N direct operators H(k1, k2) (eq. 2).
pub type DirectBank<T, const N: usize> = Bank<T, Direct, N>;
/// N inverse operators H⁻¹(k1, k2) (eq. 4): the compensators of N actuators.
pub type InverseBank<T, const N: usize> = Bank<T, Inverse, N>;
/// A bank whose channel count is chosen at run time (`std`).
#[cfg(feature = "std")]
pub type BankVec<T, F> = ParametricBank<T, F, std::vec::Vec<T>>;

/// The storage of a bank: `[T; N]` (arrays, no allocation) or `Vec<T>` (`std`), the type of
/// the k1 and k2 given to [`ParametricBank::new`].
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

/// Checks each channel's parameters as [`crate::ParametricHysteresis::new`] does for one
/// operator (the bank accepts exactly the channels the scalar operator accepts).
fn check<T: Lane, F: BankFormula>(k1: &[T], k2: &[T]) -> Result<(), BankError> {
    if k1.len() != k2.len() {
        return Err(BankError {
            channel: k1.len().min(k2.len()),
            error: Error::LengthMismatch {
                input: k1.len(),
                output: k2.len(),
            },
        });
    }
    for (channel, (a, b)) in k1.iter().zip(k2).enumerate() {
        crate::ParametricHysteresis::<T, crate::ConstantK2<T>, F>::new(*a, *b)
            .map_err(|error| BankError { channel, error })?;
    }
    Ok(())
}

/// The largest |input| for which no channel's output can leave the float range: every output
/// lies within 3 k1 of its input (eqs. 2 and 4 on a memory in the band, or their overflow-free
/// forms), so below T::MAX − 4 max k1 the scalar operator never refuses a finite sample.
fn input_limit<T: Lane>(k1: &[T]) -> T {
    let max = k1
        .iter()
        .fold(T::zero(), |m, v| if *v > m { *v } else { m });
    T::max_value() - T::from_f64(4.0) * max
}

impl<T: Lane, F: BankFormula, S: Storage<T>> ParametricBank<T, F, S> {
    /// A bank with the channels' k1 (> 0, output units of H) and k2 (> 0, 1 / input units),
    /// every channel without history (its first sample lies on the line output = input).
    ///
    /// # Errors
    /// The first channel whose k1, k2 [`crate::ParametricHysteresis::new`] refuses (each
    /// finite, positive and normal, k1 at most a quarter of the largest float, k1 k2 not below
    /// the subnormal range), with its channel; k1 and k2 of different lengths
    /// ([`Error::LengthMismatch`]).
    ///
    /// # Examples
    /// ```
    /// use hyst_core::{InverseBank, InverseHysteresis, Operator};
    /// let mut bank = InverseBank::<f64, 3>::new([0.1, 0.2, 0.3], [8.0, 8.0, 2.0])?;
    /// let mut out = [0.0; 3];
    /// bank.step(&[0.0, 0.0, 0.0], &mut out)?;
    /// bank.step(&[0.5, -0.5, 1.0], &mut out)?;
    /// // Channel 1 is H⁻¹(0.2, 8) on its own input.
    /// let mut one = InverseHysteresis::new(0.2, 8.0)?;
    /// one.step(0.0);
    /// assert!((out[1] - one.step(-0.5)).abs() < 1e-14);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(k1: S, k2: S) -> Result<Self, BankError> {
        check::<T, F>(k1.as_ref(), k2.as_ref())?;
        let n = k1.as_ref().len();
        let (slab, stride) = S::slab(n, T::zero());
        let mut columns = Columns { slab, n, stride };
        let fill = |c: &mut Columns<S::Slab>, j: usize, from: &[T], f: &dyn Fn(T) -> T| {
            for (v, x) in c.col_mut(j).iter_mut().zip(from) {
                *v = f(*x);
            }
        };
        let (k1, k2) = (k1.as_ref(), k2.as_ref());
        fill(&mut columns, K1, k1, &|v| v);
        fill(&mut columns, K2, k2, &|v| v);
        fill(&mut columns, INV_K2, k2, &|v| T::one() / v);
        fill(&mut columns, LN_K2, k2, &|v| v.ln_l());
        fill(&mut columns, SIGN, k1, &|_| T::one());
        for j in [LAST_INPUT, M_STAR, LN_A] {
            fill(&mut columns, j, k1, &|_| T::nan());
        }
        Ok(Self {
            limit: input_limit(k1),
            columns,
            formula: PhantomData,
        })
    }

    /// The number of channels.
    #[must_use]
    pub fn channels(&self) -> usize {
        self.columns.n
    }

    /// The channels' k1.
    #[must_use]
    pub fn k1(&self) -> &[T] {
        self.columns.col(K1)
    }

    /// The channels' k2.
    #[must_use]
    pub fn k2(&self) -> &[T] {
        self.columns.col(K2)
    }

    /// Forgets every channel's history.
    pub fn reset(&mut self) {
        for v in self.columns.col_mut(LAST_INPUT) {
            *v = T::nan();
        }
    }

    /// The memory of Definition 2.1 of `channel` (`None` before its first sample or for a
    /// channel beyond the bank), as [`crate::Operator::memory`] gives it for one operator.
    #[must_use]
    pub fn memory(&self, channel: usize) -> Option<Memory<T>> {
        let get = |j: usize| self.columns.col(j).get(channel).copied();
        if get(LAST_INPUT)?.is_nan() {
            return None;
        }
        Some(Memory {
            reversal_input: get(REVERSAL_INPUT)?,
            reversal_output: get(REVERSAL_OUTPUT)?,
            direction: if get(SIGN)? > T::zero() {
                Direction::Rising
            } else {
                Direction::Falling
            },
            last_input: get(LAST_INPUT)?,
            last_output: get(LAST_OUTPUT)?,
        })
    }

    /// Restores the memory of `channel` (`None`: no history).
    ///
    /// # Errors
    /// A memory the channel cannot be in ([`Memory::validate`] against its k1), or a channel
    /// beyond the bank ([`Error::LengthMismatch`]); nothing changes then.
    pub fn set_memory(
        &mut self,
        channel: usize,
        memory: Option<Memory<T>>,
    ) -> Result<(), BankError> {
        let n = self.channels();
        let wrap = |error| BankError { channel, error };
        let k1 = *self
            .columns
            .col(K1)
            .get(channel)
            .ok_or(wrap(Error::LengthMismatch {
                input: channel + 1,
                output: n,
            }))?;
        if let Some(m) = &memory {
            m.validate(k1).map_err(wrap)?;
        }
        let mut put = |j: usize, v: T| {
            if let Some(slot) = self.columns.col_mut(j).get_mut(channel) {
                *slot = v;
            }
        };
        match memory {
            None => put(LAST_INPUT, T::nan()),
            Some(m) => {
                put(REVERSAL_INPUT, m.reversal_input);
                put(REVERSAL_OUTPUT, m.reversal_output);
                put(SIGN, m.direction.sign());
                put(LAST_INPUT, m.last_input);
                put(LAST_OUTPUT, m.last_output);
                put(M_STAR, T::nan());
            }
        }
        Ok(())
    }

    /// One tick: `input[c]` is channel c's new sample, `output[c]` receives its output.
    ///
    /// # Errors
    /// Slices of another length than the bank ([`Error::LengthMismatch`]), a non-finite sample
    /// ([`Error::NonFiniteInput`], with its channel), or a finite sample whose output is beyond
    /// the float range ([`Error::NonFiniteOutput`], with its channel: only possible within
    /// 4 k1 of the largest float). No channel's memory changes then; the contents of `output`
    /// are unspecified.
    pub fn step(&mut self, input: &[T], output: &mut [T]) -> Result<(), BankError> {
        self.process(input, output)
    }

    /// A block of `samples` ticks, channel-major ("channels × time", a C-ordered 2-D array of
    /// shape (channels, samples)): `input[c * samples + t]` is channel c at tick t.
    ///
    /// # Errors
    /// As [`ParametricBank::step`], for the first tick that fails (with its first failing
    /// channel): the ticks before it are processed (their outputs written, every channel's
    /// memory as after them), that tick and the later ones are not (their outputs are
    /// unspecified). Lengths are checked before anything runs.
    pub fn process_block(
        &mut self,
        input: &[T],
        output: &mut [T],
        samples: usize,
    ) -> Result<(), BankError> {
        self.check_block(input, output, samples)?;
        self.run_checked(input, output, samples, true)
    }

    /// Checks the lengths of a channel-major block of `samples` ticks.
    fn check_block(&self, input: &[T], output: &[T], samples: usize) -> Result<(), BankError> {
        let expected = self.channels().saturating_mul(samples);
        if input.len() != expected || output.len() != expected {
            return Err(BankError {
                channel: 0,
                error: Error::LengthMismatch {
                    input: input.len(),
                    output: expected,
                },
            });
        }
        Ok(())
    }

    /// A block of ticks, time-major: `input[t * channels + c]` is channel c at tick t (each
    /// tick's samples contiguous, as a controller produces them). The fastest layout: no
    /// transposition. `input.len()` must be a multiple of the channel count.
    ///
    /// # Errors
    /// As [`ParametricBank::process_block`].
    pub fn process(&mut self, input: &[T], output: &mut [T]) -> Result<(), BankError> {
        let n = self.channels();
        if n == 0 || !input.len().is_multiple_of(n) || output.len() != input.len() {
            return Err(BankError {
                channel: 0,
                error: Error::LengthMismatch {
                    input: input.len(),
                    output: output.len(),
                },
            });
        }
        self.run_checked(input, output, input.len() / n, false)
    }

    /// Runs a block whose lengths are checked. The kernel checks each tile of ticks against
    /// the input limit before running it and stops before the first tick with a sample at or
    /// beyond the limit; that tick is an error if a sample is not finite, and otherwise runs
    /// alone on the memory with a copy to put back should the scalar operator refuse a sample
    /// (an output beyond the float range). Either way the ticks before the failing one are
    /// done and the memory is as after them.
    fn run_checked(
        &mut self,
        input: &[T],
        output: &mut [T],
        samples: usize,
        channel_major: bool,
    ) -> Result<(), BankError> {
        let n = self.channels().max(1);
        let mut begin = 0;
        while begin < samples {
            let mut block = Block {
                input,
                output: &mut *output,
                samples,
                channel_major,
                begin,
                end: samples,
                limit: Some(self.limit),
            };
            let Some(bad) = T::run::<F>(&mut self.columns.view(), &mut block)? else {
                return Ok(());
            };
            let sample = |c: usize| {
                let i = if channel_major {
                    c * samples + bad
                } else {
                    bad * n + c
                };
                input.get(i).copied().unwrap_or_else(T::zero)
            };
            if let Some(channel) = (0..n).find(|c| !sample(*c).is_finite()) {
                return Err(BankError {
                    channel,
                    error: Error::NonFiniteInput {
                        value: sample(channel).as_f64(),
                    },
                });
            }
            let before = self.columns.clone();
            let mut block = Block {
                input,
                output: &mut *output,
                samples,
                channel_major,
                begin: bad,
                end: bad + 1,
                limit: None,
            };
            if let Err(e) = T::run::<F>(&mut self.columns.view(), &mut block) {
                self.columns = before;
                return Err(e);
            }
            begin = bad + 1;
        }
        Ok(())
    }
}

#[cfg(feature = "std")]
impl<T: Lane, F: BankFormula> ParametricBank<T, F, std::vec::Vec<T>> {
    /// A bank of `k1.len()` channels (run-time count).
    ///
    /// # Errors
    /// As [`ParametricBank::new`].
    pub fn from_vecs(k1: std::vec::Vec<T>, k2: std::vec::Vec<T>) -> Result<Self, BankError> {
        Self::new(k1, k2)
    }
}

/// Threads: the channels split into parts of whole chunks, one part per task (rayon).
#[cfg(feature = "rayon")]
impl<T: Lane + Send + Sync, F: BankFormula, S: Storage<T>> ParametricBank<T, F, S> {
    /// [`ParametricBank::step`] with the channels split over rayon's threads: the same outputs,
    /// bit for bit. Worth it for banks of many thousands of channels (a tick of 1,024 channels
    /// takes about a microsecond on one core, the order of a task's overhead).
    ///
    /// # Errors
    /// As [`ParametricBank::step`] (a tick with a sample the threads' kernels would have to
    /// refuse runs on this thread instead).
    pub fn step_par(&mut self, input: &[T], output: &mut [T]) -> Result<(), BankError> {
        let n = self.channels();
        if n == 0 || input.len() != n || output.len() != n {
            return self.step(input, output);
        }
        self.run_par(input, output, 1, true)
    }

    /// [`ParametricBank::process_block`] (channel-major) with the channels split over rayon's
    /// threads: the same outputs, bit for bit.
    ///
    /// # Errors
    /// As [`ParametricBank::process_block`] (a block with a sample the threads' kernels would
    /// have to refuse runs on this thread instead).
    pub fn process_block_par(
        &mut self,
        input: &[T],
        output: &mut [T],
        samples: usize,
    ) -> Result<(), BankError> {
        self.check_block(input, output, samples)?;
        self.run_par(input, output, samples, true)
    }

    /// Runs `samples` ticks, channel-major (one tick is both layouts), in parts of whole chunks
    /// on rayon's threads, when every sample is below the input limit (then no channel can
    /// fail); otherwise on this thread through the checked path.
    fn run_par(
        &mut self,
        input: &[T],
        output: &mut [T],
        samples: usize,
        channel_major: bool,
    ) -> Result<(), BankError> {
        use rayon::prelude::*;
        let limit = self.limit;
        if !input
            .par_iter()
            .all(|x| num_traits::Float::abs(*x) <= limit)
        {
            return self.run_checked(input, output, samples, channel_major);
        }
        let n = self.channels();
        // Parts of whole 64-channel chunks, about four per thread.
        let parts = 4 * rayon::current_num_threads().max(1);
        let size = n.div_ceil(parts).div_ceil(64).max(1) * 64;
        let mut jobs = std::vec::Vec::new();
        let (mut cols, mut inp, mut out) = (self.columns.view(), input, output);
        while cols.k1.len() > size {
            let (head, tail) = cols.split_at(size);
            let at = (size * samples).min(inp.len()).min(out.len());
            let (i_head, i_tail) = inp.split_at(at);
            let (o_head, o_tail) = out.split_at_mut(at);
            jobs.push((head, i_head, o_head));
            (cols, inp, out) = (tail, i_tail, o_tail);
        }
        jobs.push((cols, inp, out));
        jobs.into_par_iter()
            .map(|(mut cols, input, output)| {
                let mut block = Block {
                    input,
                    output,
                    samples,
                    channel_major,
                    begin: 0,
                    end: samples,
                    limit: None,
                };
                T::run::<F>(&mut cols, &mut block).map(|_| ())
            })
            .collect::<Result<(), BankError>>()
    }
}

/// The formula of a bank: eq. (2) or eq. (4). Implemented by [`Direct`] and [`Inverse`].
pub trait BankFormula: Formula {
    /// Whether this is the direct formula (eq. 2).
    #[doc(hidden)]
    const DIRECT: bool;
}

impl BankFormula for Direct {
    const DIRECT: bool = true;
}

impl BankFormula for Inverse {
    const DIRECT: bool = false;
}

/// An instruction set the bank's kernels are compiled for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Isa {
    /// AVX-512F, 512-bit vectors (8 × f64, 16 × f32) with fused multiply-add (x86-64, `std`).
    Avx512,
    /// AVX2 + FMA, 256-bit vectors (4 × f64, 8 × f32) (x86-64, `std`).
    Avx2,
    /// SSE2, 128-bit vectors (2 × f64, 4 × f32), no fused multiply-add: x86-64's baseline
    /// (`std`).
    Sse2,
    /// Portable code, plain floats (every target).
    Portable,
}

impl Isa {
    /// Every instruction set, best first.
    pub const ALL: [Isa; 4] = [Isa::Avx512, Isa::Avx2, Isa::Sse2, Isa::Portable];

    /// "avx512", "avx2", "sse2" or "portable".
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Isa::Avx512 => "avx512",
            Isa::Avx2 => "avx2",
            Isa::Sse2 => "sse2",
            Isa::Portable => "portable",
        }
    }

    /// Whether this processor (and build) can run it.
    #[must_use]
    pub fn available(self) -> bool {
        match self {
            Isa::Portable => true,
            #[cfg(all(feature = "std", target_arch = "x86_64"))]
            Isa::Avx512 => std::arch::is_x86_feature_detected!("avx512f"),
            #[cfg(all(feature = "std", target_arch = "x86_64"))]
            Isa::Sse2 => true,
            #[cfg(all(feature = "std", target_arch = "x86_64"))]
            Isa::Avx2 => {
                std::arch::is_x86_feature_detected!("avx2")
                    && std::arch::is_x86_feature_detected!("fma")
            }
            #[cfg(not(all(feature = "std", target_arch = "x86_64")))]
            _ => false,
        }
    }
}

/// The forced instruction set: 0 none, else 1 + its index in `ISAS`.
static FORCED: core::sync::atomic::AtomicU8 = core::sync::atomic::AtomicU8::new(0);
const ISAS: [Isa; 4] = Isa::ALL;

/// Chooses the instruction set of every bank in the process (`None`: the best available, the
/// default) — for measurements and for testing each kernel against the scalar operator.
///
/// # Errors
/// `Err(isa)` when this processor or build cannot run `isa`; nothing changes then.
pub fn force_isa(isa: Option<Isa>) -> Result<(), Isa> {
    let code = match isa {
        None => 0,
        Some(i) if i.available() => match i {
            Isa::Avx512 => 1,
            Isa::Avx2 => 2,
            Isa::Sse2 => 3,
            Isa::Portable => 4,
        },
        Some(i) => return Err(i),
    };
    FORCED.store(code, core::sync::atomic::Ordering::Relaxed);
    Ok(())
}

/// The instruction set the banks run on now: the forced one ([`force_isa`]), else the best
/// available (AVX-512, AVX2 + FMA, SSE2, portable, in that order).
#[must_use]
pub fn isa() -> Isa {
    let forced = FORCED.load(core::sync::atomic::Ordering::Relaxed);
    if let Some(i) = ISAS.get(usize::from(forced).wrapping_sub(1)) {
        return *i;
    }
    ISAS.into_iter()
        .find(|i| i.available())
        .unwrap_or(Isa::Portable)
}

/// The samples a kernel runs: `samples` ticks of all channels, channel c at tick t at
/// `c * samples + t` (`channel_major`) or `t * channels + c`, of which ticks `begin..end` run;
/// with a `limit`, only while every sample's magnitude is below it. Public only as a parameter
/// of the sealed [`RunBlock`].
#[doc(hidden)]
pub struct Block<'a, T> {
    input: &'a [T],
    output: &'a mut [T],
    samples: usize,
    channel_major: bool,
    begin: usize,
    end: usize,
    limit: Option<T>,
}

/// How a float type runs a block: the dispatch to the kernel of the chosen instruction set.
/// Implemented for `f32` and `f64` only.
pub trait RunBlock: Sized {
    /// Runs the ticks of `block` through every channel of `cols`; `Ok(Some(t))` when tick `t`
    /// has a sample beyond the block's limit (the ticks before it have run, tick `t` has not).
    #[doc(hidden)]
    fn run<F: BankFormula>(
        cols: &mut ColumnsMut<'_, Self>,
        block: &mut Block<'_, Self>,
    ) -> Result<Option<usize>, BankError>;
}

macro_rules! run_block {
    ($t:ty, $entry:ident) => {
        impl RunBlock for $t {
            fn run<F: BankFormula>(
                cols: &mut ColumnsMut<'_, Self>,
                block: &mut Block<'_, Self>,
            ) -> Result<Option<usize>, BankError> {
                #[cfg(all(feature = "std", target_arch = "x86_64"))]
                {
                    let isa = isa();
                    if isa != Isa::Portable {
                        if let Some(r) = x86::$entry::<F>(isa, cols, block) {
                            return r;
                        }
                    }
                }
                kernel::run::<simd::Pair<simd::Pair<$t>>, F>(cols, block)
            }
        }
    };
}

run_block!(f64, run_f64);
run_block!(f32, run_f32);

#[cfg(all(test, feature = "std"))]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    /// Where each column of a `Vec` bank starts, in bytes modulo 4 KiB, and its length.
    fn starts<T: Lane>(n: usize) -> std::vec::Vec<(usize, usize)> {
        let k1 = std::vec![T::one(); n];
        let mut bank = BankVec::<T, Inverse>::from_vecs(k1.clone(), k1).unwrap();
        let c = bank.columns.view();
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

    #[test]
    fn array_columns_are_the_channels_in_order() {
        let mut bank = InverseBank::<f64, 3>::new([0.1, 0.2, 0.3], [4.0, 5.0, 6.0]).unwrap();
        assert_eq!(bank.k1(), [0.1, 0.2, 0.3]);
        assert_eq!(bank.k2(), [4.0, 5.0, 6.0]);
        let c = bank.columns.view();
        assert_eq!(c.inv_k2, [0.25, 0.2, 1.0 / 6.0]);
        assert!(c.last_input.iter().all(|v| v.is_nan()));
        assert_eq!(c.ln_a.len(), 3);
    }
}
