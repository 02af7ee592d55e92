//! A bank of operators: N channels, each its own H(k1, k2) (or H⁻¹) with its own memory
//! (Definition 2.1), stepped together — a deformable mirror's actuators, the axes of a stage.
//!
//! The state is a structure of arrays over storage `S` (`[T; N]` arrays without allocation, or
//! `Vec<T>` with `std`). The channels run in chunks of four vector registers (AVX-512: 32 × f64,
//! 64 × f32) whose state stays in registers while the ticks go by (four independent dependency
//! chains per tick, which the processor overlaps), in branch-free code written once against a
//! small vector trait ([`lanes`] has the elementary functions). With `std` on x86-64 the
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

/// The per-channel state columns (structure of arrays). Public only as a parameter of the
/// sealed [`RunBlock`]; nothing outside the bank can build or read one.
#[doc(hidden)]
#[derive(Clone, Debug, PartialEq)]
pub struct Columns<S> {
    k1: S,
    k2: S,
    reversal_input: S,
    reversal_output: S,
    /// s = ±1 of Definition 2.1.
    sign: S,
    /// NaN before the channel's first sample (no history).
    last_input: S,
    last_output: S,
    /// Direct operator: 1 / k2 and ln k2 (fixed), and M* (eq. 2) and ln(k2 M*), which change
    /// only at reversals (NaN: to be computed from the memory when the channel next runs).
    inv_k2: S,
    ln_k2: S,
    m_star: S,
    ln_a: S,
}

/// The columns of a range of channels, borrowed: what a kernel runs on (a whole bank, or one
/// thread's part of it). Public only as a parameter of the sealed [`RunBlock`].
#[doc(hidden)]
pub struct ColumnsMut<'a, T> {
    k1: &'a [T],
    k2: &'a [T],
    inv_k2: &'a [T],
    ln_k2: &'a [T],
    reversal_input: &'a mut [T],
    reversal_output: &'a mut [T],
    sign: &'a mut [T],
    last_input: &'a mut [T],
    last_output: &'a mut [T],
    m_star: &'a mut [T],
    ln_a: &'a mut [T],
}

impl<S> Columns<S> {
    /// All channels' columns, borrowed.
    fn view<T>(&mut self) -> ColumnsMut<'_, T>
    where
        S: AsRef<[T]> + AsMut<[T]>,
    {
        ColumnsMut {
            k1: self.k1.as_ref(),
            k2: self.k2.as_ref(),
            inv_k2: self.inv_k2.as_ref(),
            ln_k2: self.ln_k2.as_ref(),
            reversal_input: self.reversal_input.as_mut(),
            reversal_output: self.reversal_output.as_mut(),
            sign: self.sign.as_mut(),
            last_input: self.last_input.as_mut(),
            last_output: self.last_output.as_mut(),
            m_star: self.m_star.as_mut(),
            ln_a: self.ln_a.as_mut(),
        }
    }
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
pub struct ParametricBank<T, F, S> {
    columns: Columns<S>,
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

/// Storage of one state column: a slice of the channels' values.
pub trait Storage<T>: AsRef<[T]> + AsMut<[T]> + Clone {
    /// A column of `n` copies of `value` shaped like `like` (the same length).
    fn filled(like: &Self, value: T) -> Self;
}

impl<T: Copy, const N: usize> Storage<T> for [T; N] {
    fn filled(_like: &Self, value: T) -> Self {
        [value; N]
    }
}

#[cfg(feature = "std")]
impl<T: Copy> Storage<T> for std::vec::Vec<T> {
    fn filled(like: &Self, value: T) -> Self {
        std::vec![value; like.len()]
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
        let zero = |v| S::filled(&k1, v);
        let map = |s: &S, f: fn(T) -> T| {
            let mut out = s.clone();
            for v in out.as_mut() {
                *v = f(*v);
            }
            out
        };
        Ok(Self {
            limit: input_limit(k1.as_ref()),
            columns: Columns {
                reversal_input: zero(T::zero()),
                reversal_output: zero(T::zero()),
                sign: zero(T::one()),
                last_input: zero(T::nan()),
                last_output: zero(T::zero()),
                inv_k2: map(&k2, |v| T::one() / v),
                ln_k2: map(&k2, |v| v.ln_l()),
                m_star: zero(T::nan()),
                ln_a: zero(T::nan()),
                k1,
                k2,
            },
            formula: PhantomData,
        })
    }

    /// The number of channels.
    #[must_use]
    pub fn channels(&self) -> usize {
        self.columns.k1.as_ref().len()
    }

    /// The channels' k1.
    #[must_use]
    pub fn k1(&self) -> &[T] {
        self.columns.k1.as_ref()
    }

    /// The channels' k2.
    #[must_use]
    pub fn k2(&self) -> &[T] {
        self.columns.k2.as_ref()
    }

    /// Forgets every channel's history.
    pub fn reset(&mut self) {
        for v in self.columns.last_input.as_mut() {
            *v = T::nan();
        }
    }

    /// The memory of Definition 2.1 of `channel` (`None` before its first sample or for a
    /// channel beyond the bank), as [`crate::Operator::memory`] gives it for one operator.
    #[must_use]
    pub fn memory(&self, channel: usize) -> Option<Memory<T>> {
        let c = &self.columns;
        let get = |s: &S| s.as_ref().get(channel).copied();
        if get(&c.last_input)?.is_nan() {
            return None;
        }
        Some(Memory {
            reversal_input: get(&c.reversal_input)?,
            reversal_output: get(&c.reversal_output)?,
            direction: if get(&c.sign)? > T::zero() {
                Direction::Rising
            } else {
                Direction::Falling
            },
            last_input: get(&c.last_input)?,
            last_output: get(&c.last_output)?,
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
            .k1
            .as_ref()
            .get(channel)
            .ok_or(wrap(Error::LengthMismatch {
                input: channel + 1,
                output: n,
            }))?;
        if let Some(m) = &memory {
            m.validate(k1).map_err(wrap)?;
        }
        let c = &mut self.columns;
        let put = |s: &mut S, v: T| {
            if let Some(slot) = s.as_mut().get_mut(channel) {
                *slot = v;
            }
        };
        match memory {
            None => put(&mut c.last_input, T::nan()),
            Some(m) => {
                put(&mut c.reversal_input, m.reversal_input);
                put(&mut c.reversal_output, m.reversal_output);
                put(&mut c.sign, m.direction.sign());
                put(&mut c.last_input, m.last_input);
                put(&mut c.last_output, m.last_output);
                put(&mut c.m_star, T::nan());
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
        self.process_ticks(input, output)
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
    pub fn process_ticks(&mut self, input: &[T], output: &mut [T]) -> Result<(), BankError> {
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
