//! A bank of operators: N channels, each its own H(k1, k2) (or H⁻¹) with its own memory
//! (Definition 2.1), stepped together — a deformable mirror's actuators, the axes of a stage.
//!
//! The state is a structure of arrays over storage `S` (`[T; N]` arrays without allocation, or
//! with `std` one `Vec<T>` whose columns start five cache lines apart modulo 4 KiB, see
//! [`Storage`]). In blocks the channels run in chunks of four vector registers (AVX-512:
//! 32 × f64, 64 × f32) whose state stays in registers while the ticks go by (four independent
//! dependency chains per tick, which the processor overlaps); one tick ([`ParametricBank::step`])
//! of the inverse runs chunks of one or two vectors (four with SSE2 and the portable code), the
//! next chunk's state loaded before this one's is stored, and of the direct operator, whose
//! tick is a longer chain, chunks of four vectors as blocks do. The code is branch-free over
//! lanes, written once against a small vector trait ([`lanes`] has the elementary functions).
//! With `std` on x86-64 the instruction set is chosen at run time: AVX-512, else AVX2 + FMA,
//! else SSE2 (x86-64's baseline); other targets and `no_std` builds run the portable code
//! (plain floats, four channels at a time). [`isa`] tells which runs, [`force_isa`] chooses one. docs/performance.md
//! has the measurements behind these choices.
//!
//! The results agree with the scalar operator ([`hyst_core::Hysteresis`],
//! [`hyst_core::InverseHysteresis`]) to a few ulp, not bit for bit: the bank has its own `exp`, `ln`
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
//!
//! This file holds the bank's public API. Its modules: `columns` (the storage of the state
//! columns, [`Storage`]), `checked` (the checks of the parameters and of a block, and the checked
//! path around the kernels), `block` (what a kernel runs on, [`RunBlock`]), `vector` (the
//! vector trait and [`Lane`]), `simd` and [`lanes`] (the one-lane and paired vectors, the
//! elementary functions), `kernel` (the kernels), `instruction_set` and `dispatch` (the choice
//! of kernel, [`Isa`]), `x86` (the SSE2, AVX2 and AVX-512 vectors, each holding the token of its
//! instruction set, which only run-time detection makes) and `par` (rayon's threads).

#![no_std]
// `unsafe` only in `x86` (std::arch intrinsics; its vectors exist only with a proof that the
// processor has their instruction set, see that module).
#![deny(unsafe_code)]
#![deny(clippy::unwrap_used, clippy::expect_used, clippy::panic)]
// No indexing that could panic in library code (unit tests may index).
#![cfg_attr(not(test), deny(clippy::indexing_slicing))]
#![warn(missing_docs)]

#[cfg(feature = "std")]
extern crate std;

mod block;
mod checked;
mod chunk;
mod columns;
mod dispatch;
mod error;
mod formula;
mod instruction_set;
mod kernel;
pub mod lanes;
#[cfg(feature = "rayon")]
mod par;
#[doc(hidden)]
pub mod simd;
mod step;
#[cfg(all(feature = "std", target_arch = "x86_64"))]
mod token;
mod vector;
#[cfg(all(feature = "std", target_arch = "x86_64"))]
mod x86;

use core::marker::PhantomData;

#[doc(hidden)]
pub use block::Block;
pub use block::RunBlock;
use checked::{check, check_block, input_limit, run_checked};
pub use columns::Storage;
#[doc(hidden)]
pub use columns::{Columns, ColumnsMut, Slab};
use columns::{
    INV_K2, K1, K2, LAST_INPUT, LAST_OUTPUT, LN_A, LN_K2, M_STAR, REVERSAL_INPUT, REVERSAL_OUTPUT,
    SIGN,
};
pub use error::BankError;
pub use formula::BankFormula;
pub use instruction_set::{force_isa, isa, Isa};
pub use lanes::Lane;

use hyst_core::error::Error;
use hyst_core::memory::{Direction, Memory};
use hyst_core::parametric::{Direct, Inverse};

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
/// N inverse operators H⁻¹(k1, k2) (eq. 4): the exact inverses of N actuators' hysteresis.
pub type InverseBank<T, const N: usize> = Bank<T, Inverse, N>;
/// A bank whose channel count is chosen at run time (`std`).
#[cfg(feature = "std")]
pub type BankVec<T, F> = ParametricBank<T, F, std::vec::Vec<T>>;

impl<T: Lane, F: BankFormula, S: Storage<T>> ParametricBank<T, F, S> {
    /// A bank with the channels' k1 (> 0, output units of H) and k2 (> 0, 1 / input units),
    /// every channel without history (its first sample lies on the line output = input).
    ///
    /// # Errors
    /// The first channel whose k1, k2 [`hyst_core::ParametricHysteresis::new`] refuses (each
    /// finite, positive and normal, k1 at most a quarter of the largest float, k1 k2 not below
    /// the subnormal range), with its channel; k1 and k2 of different lengths
    /// ([`Error::LengthMismatch`]).
    ///
    /// # Examples
    /// ```
    /// use hyst_bank::InverseBank;
    /// use hyst_core::{InverseHysteresis, Operator};
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
    /// channel beyond the bank), as [`hyst_core::Operator::memory`] gives it for one operator.
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
        check_block(self.channels(), input, output, samples)?;
        run_checked::<T, F, S::Slab>(&mut self.columns, self.limit, input, output, samples, true)
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
        let samples = input.len() / n;
        run_checked::<T, F, S::Slab>(&mut self.columns, self.limit, input, output, samples, false)
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

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

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
