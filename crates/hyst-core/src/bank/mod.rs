//! A bank of operators: N channels, each its own H(k1, k2) (or H⁻¹) with its own memory
//! (Definition 2.1), stepped together — a deformable mirror's actuators, the axes of a stage.
//!
//! The state is a structure of arrays over storage `S` (`[T; N]` arrays without allocation, or
//! `Vec<T>` with `std`), and the channels are computed in chunks of [`Lane::LANES`] (8 × f64,
//! 16 × f32) by branch-free code ([`lanes`]) that the compiler vectorises. With `std`, the
//! chunk loop is compiled for AVX-512, AVX2 + FMA and the x86-64 baseline (SSE2) and the best
//! one the processor has is chosen at run time (the `multiversion` crate; docs/performance.md
//! says why); without `std` it is compiled for the target's own features.
//!
//! Every clone does the same arithmetic (no fused multiply-add is introduced), so a bank's
//! results do not depend on the processor. They agree with the scalar operator
//! ([`crate::Hysteresis`], [`crate::InverseHysteresis`]) to a few ulp, not bit for bit: the
//! bank has its own `exp`, `ln` and ω where the scalar operator calls the platform's `exp` and
//! the `lambert_w` crate (the bound is stated and tested in `tests/bank.rs`).
//!
//! Direct operator (eq. 2): ũ = ṽ − M* + ω(y)/k2 with y = ln(k2 M*) + k2 (M* − ṽ) (the scalar
//! operator's W0(k2 M* e^(k2 (M* − ṽ))) in the log domain, so nothing overflows), and
//! ũ = (ln(k2 M*) − ln ω)/k2 where e^y would overflow. ω starts from the previous sample's ω
//! extrapolated along dω/dy = ω/(1 + ω), one fourth-order step; when any channel of a chunk is
//! too far for that (after a reversal, a jump of the input), the chunk takes the full
//! evaluation of [`lanes::omega`].

pub mod lanes;

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
    last_input: S,
    last_output: S,
    /// 1 once the channel has a history, 0 before its first sample.
    started: S,
    /// Direct operator: the last ω and its y (the next sample's start).
    omega: S,
    omega_y: S,
    /// ln k2 and 1 / k2, fixed.
    ln_k2: S,
    inv_k2: S,
}

/// N operators of formula `F` ([`Direct`]: eq. 2, [`Inverse`]: eq. 4) stepped together, state
/// in storage `S`. Use [`Bank`] (arrays, no allocation) or, with `std`, [`BankVec`].
#[derive(Clone, Debug, PartialEq)]
pub struct ParametricBank<T, F, S> {
    columns: Columns<S>,
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

fn check<T: Lane>(k1: &[T], k2: &[T]) -> Result<(), BankError> {
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
        let wrap = |error| BankError { channel, error };
        crate::error::positive("k1", *a).map_err(wrap)?;
        crate::error::positive("k2", *b).map_err(wrap)?;
    }
    Ok(())
}

impl<T: Lane, F: BankFormula, S: Storage<T>> ParametricBank<T, F, S> {
    /// A bank with the channels' k1 (> 0, output units of H) and k2 (> 0, 1 / input units),
    /// every channel without history (its first sample lies on the line output = input).
    ///
    /// # Errors
    /// The first invalid parameter, with its channel; k1 and k2 of different lengths.
    pub fn new(k1: S, k2: S) -> Result<Self, BankError> {
        check(k1.as_ref(), k2.as_ref())?;
        let zero = |v| S::filled(&k1, v);
        let map = |s: &S, f: fn(T) -> T| {
            let mut out = s.clone();
            for v in out.as_mut() {
                *v = f(*v);
            }
            out
        };
        Ok(Self {
            columns: Columns {
                reversal_input: zero(T::zero()),
                reversal_output: zero(T::zero()),
                sign: zero(T::one()),
                last_input: zero(T::zero()),
                last_output: zero(T::zero()),
                started: zero(T::zero()),
                omega: zero(T::zero()),
                omega_y: zero(T::neg_infinity()),
                ln_k2: map(&k2, |v| v.ln_l()),
                inv_k2: map(&k2, |v| T::one() / v),
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
        for v in self.columns.started.as_mut() {
            *v = T::zero();
        }
    }

    /// The memory of Definition 2.1 of `channel` (`None` before its first sample or for a
    /// channel beyond the bank), as [`crate::Operator::memory`] gives it for one operator.
    #[must_use]
    pub fn memory(&self, channel: usize) -> Option<Memory<T>> {
        let c = &self.columns;
        let get = |s: &S| s.as_ref().get(channel).copied();
        if get(&c.started)? == T::zero() {
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
            None => put(&mut c.started, T::zero()),
            Some(m) => {
                put(&mut c.reversal_input, m.reversal_input);
                put(&mut c.reversal_output, m.reversal_output);
                put(&mut c.sign, m.direction.sign());
                put(&mut c.last_input, m.last_input);
                put(&mut c.last_output, m.last_output);
                put(&mut c.started, T::one());
                put(&mut c.omega_y, T::neg_infinity());
            }
        }
        Ok(())
    }

    /// One tick: `input[c]` is channel c's new sample, `output[c]` receives its output.
    ///
    /// # Errors
    /// Slices of another length than the bank ([`Error::LengthMismatch`]), or a non-finite
    /// sample ([`Error::NonFiniteInput`], with its channel); the memory is then untouched.
    pub fn step(&mut self, input: &[T], output: &mut [T]) -> Result<(), BankError> {
        self.process_ticks(input, output)
    }

    /// A block of `samples` ticks, channel-major ("channels × time", a C-ordered 2-D array of
    /// shape (channels, samples)): `input[c * samples + t]` is channel c at tick t.
    ///
    /// # Errors
    /// As [`ParametricBank::step`]; the non-finite sample is reported by channel (and nothing
    /// is processed).
    pub fn process_block(
        &mut self,
        input: &[T],
        output: &mut [T],
        samples: usize,
    ) -> Result<(), BankError> {
        let n = self.channels();
        let expected = n.checked_mul(samples).unwrap_or(usize::MAX);
        if input.len() != expected || output.len() != expected {
            return Err(BankError {
                channel: 0,
                error: Error::LengthMismatch {
                    input: input.len(),
                    output: expected,
                },
            });
        }
        if let Some((i, x)) = input.iter().enumerate().find(|(_, x)| !x.is_finite()) {
            return Err(BankError {
                channel: i / samples.max(1),
                error: Error::NonFiniteInput { value: x.as_f64() },
            });
        }
        T::run::<F, S>(&mut self.columns, input, output, samples, true);
        Ok(())
    }

    /// A block of ticks, time-major: `input[t * channels + c]` is channel c at tick t (each
    /// tick's samples contiguous, as a controller produces them). The fastest layout: no
    /// transposition. `input.len()` must be a multiple of the channel count.
    ///
    /// # Errors
    /// As [`ParametricBank::step`]; nothing is processed on error.
    pub fn process_ticks(&mut self, input: &[T], output: &mut [T]) -> Result<(), BankError> {
        let n = self.channels();
        if n == 0 || input.len() % n != 0 || output.len() != input.len() {
            return Err(BankError {
                channel: 0,
                error: Error::LengthMismatch {
                    input: input.len(),
                    output: output.len(),
                },
            });
        }
        if let Some((i, x)) = input.iter().enumerate().find(|(_, x)| !x.is_finite()) {
            return Err(BankError {
                channel: i % n,
                error: Error::NonFiniteInput { value: x.as_f64() },
            });
        }
        T::run::<F, S>(&mut self.columns, input, output, input.len() / n, false);
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

/// One chunk of `L` channels' state, in registers while it runs through the ticks.
#[derive(Clone, Copy)]
struct Chunk<T, const L: usize> {
    k1: [T; L],
    k2: [T; L],
    rin: [T; L],
    rout: [T; L],
    sign: [T; L],
    lin: [T; L],
    lout: [T; L],
    started: [T; L],
    omega: [T; L],
    omega_y: [T; L],
    ln_k2: [T; L],
    inv_k2: [T; L],
}

/// The formula of a bank: eq. (2) or eq. (4) on a chunk of channels.
pub trait BankFormula: Formula {
    /// Whether the chunk output is ũ of Definition 2.1 (to be untransformed: the direct
    /// formula) or the output itself (the inverse formula, which folds the transformation in).
    #[doc(hidden)]
    const TRANSFORMED: bool;
    /// One tick of a chunk: the memory update of Definition 2.1 done, computes the outputs.
    #[doc(hidden)]
    fn chunk_output<T: Lane, const L: usize>(
        c: &mut ChunkRef<'_, T, L>,
        x: &[T; L],
        reversal: &[bool; L],
    ) -> [T; L];
}

/// A chunk's state as the formulas see it (public only for the sealed [`BankFormula`]).
#[doc(hidden)]
pub struct ChunkRef<'a, T, const L: usize>(&'a mut Chunk<T, L>);

// Lane loops index `[T; L]` arrays with `i < L`: in bounds by construction, and the compiler
// drops the checks; iterator chains over eleven arrays would hide the arithmetic.
#[allow(clippy::indexing_slicing)]
mod kernels {
    use super::{BankFormula, Chunk, ChunkRef, Columns, Lane, Storage};
    use crate::{Direct, Inverse};

    /// M* of the direct formula: M + k1 clamped into the band [0, 2 k1].
    #[inline(always)]
    fn direct_m_star<T: Lane>(rin: T, rout: T, sign: T, k1: T) -> T {
        let m = (rout - rin) * sign + k1;
        let two_k1 = k1 + k1;
        T::select(m < T::zero(), T::zero(), T::select(m > two_k1, two_k1, m))
    }

    impl BankFormula for Inverse {
        const TRANSFORMED: bool = false;
        #[inline(always)]
        fn chunk_output<T: Lane, const L: usize>(
            c: &mut ChunkRef<'_, T, L>,
            x: &[T; L],
            _reversal: &[bool; L],
        ) -> [T; L] {
            let c = &mut *c.0;
            let one = T::one();
            let mut y = [T::zero(); L];
            for i in 0..L {
                let s = c.sign[i];
                let m_star = c.k1[i] - (c.rout[i] - c.rin[i]) * s;
                let ud = (x[i] - c.rin[i]) * s;
                let along = ud * s + c.rout[i];
                y[i] = along + (one - (-(c.k2[i] * ud)).exp_l()) * (m_star * s);
            }
            y
        }
    }

    impl BankFormula for Direct {
        const TRANSFORMED: bool = true;
        #[inline(always)]
        fn chunk_output<T: Lane, const L: usize>(
            c: &mut ChunkRef<'_, T, L>,
            x: &[T; L],
            _reversal: &[bool; L],
        ) -> [T; L] {
            let c = &mut *c.0;
            let zero = T::zero();
            let mut m_star = [zero; L];
            let mut vt = [zero; L];
            let mut ln_a = [zero; L];
            let mut y = [zero; L];
            for i in 0..L {
                m_star[i] = direct_m_star(c.rin[i], c.rout[i], c.sign[i], c.k1[i]);
                vt[i] = (x[i] - c.rin[i]) * c.sign[i];
                ln_a[i] = c.ln_k2[i] + m_star[i].ln_l();
                y[i] = ln_a[i] + c.k2[i] * (m_star[i] - vt[i]);
            }
            // ω(y): a start within 2.2e-5, then one FSC step. eʸ and ln y only where some
            // channel of the chunk needs them.
            let mut t = [zero; L];
            if y.iter().any(|v| *v < T::from_f64(-3.0)) {
                for i in 0..L {
                    t[i] = y[i].exp_l();
                }
            }
            let mut ln_y = [zero; L];
            if y.iter().any(|v| *v > T::from_f64(12.0)) {
                for i in 0..L {
                    ln_y[i] = y[i].ln_l();
                }
            }
            let mut w = [zero; L];
            let mut accepted = [false; L];
            for i in 0..L {
                let start = super::lanes::omega_start(y[i], t[i], ln_y[i]);
                let (w1, r) = super::lanes::fsc_step(start, y[i]);
                let small = y[i] < T::OMEGA_SMALL;
                w[i] = T::select(small, t[i] - t[i] * t[i], w1);
                accepted[i] = small || r.abs() <= T::RESIDUAL_OK;
            }
            // The start is good everywhere; should a channel still miss (a rounding corner),
            // the full evaluation, for that channel alone.
            for i in 0..L {
                if !accepted[i] {
                    w[i] = super::lanes::omega(y[i]);
                }
            }
            let mut out = [zero; L];
            for i in 0..L {
                let plain = vt[i] - m_star[i] + w[i] * c.inv_k2[i];
                out[i] = T::select(vt[i] == zero, zero, plain);
            }
            // Where e^y overflows, the scalar operator's log form (no cancellation of huge terms).
            if y.iter().any(|v| *v > T::EXP_ARG_MAX) {
                for i in 0..L {
                    let log_form = (ln_a[i] - w[i].ln_l()) * c.inv_k2[i];
                    out[i] = T::select(y[i] > T::EXP_ARG_MAX && vt[i] != zero, log_form, out[i]);
                }
            }
            out
        }
    }

    /// Definition 2.1's memory update on a chunk (selects, no branches), then the formula, then
    /// the output kept in the band [x − k1, x + k1] as the scalar operator keeps it.
    #[inline(always)]
    pub(super) fn tick<T: Lane, F: BankFormula, const L: usize>(
        c: &mut Chunk<T, L>,
        x: &[T; L],
    ) -> [T; L] {
        let (zero, one) = (T::zero(), T::one());
        let mut reversal = [false; L];
        for i in 0..L {
            // A channel's first sample: at rest on the line output = input, rising.
            let xi = x[i];
            let fresh = c.started[i] == zero;
            let lin = T::select(fresh, xi, c.lin[i]);
            let lout = T::select(fresh, xi, c.lout[i]);
            let sign = T::select(fresh, one, c.sign[i]);
            let rin = T::select(fresh, xi, c.rin[i]);
            let rout = T::select(fresh, xi, c.rout[i]);
            let new_sign = T::select(xi > lin, one, T::select(xi < lin, -one, sign));
            reversal[i] = (new_sign != sign) | fresh;
            c.rin[i] = T::select(reversal[i], lin, rin);
            c.rout[i] = T::select(reversal[i], lout, rout);
            c.sign[i] = new_sign;
            c.started[i] = one;
        }
        let u_tilde = F::chunk_output(&mut ChunkRef(c), x, &reversal);
        let mut y = [zero; L];
        for i in 0..L {
            // The direct formula returns ũ (untransformed here); the inverse returns v itself.
            let raw = if F::TRANSFORMED {
                u_tilde[i] * c.sign[i] + c.rout[i]
            } else {
                u_tilde[i]
            };
            let (lo, hi) = (x[i] - c.k1[i], x[i] + c.k1[i]);
            y[i] = T::select(raw < lo, lo, T::select(raw > hi, hi, raw));
            c.lin[i] = x[i];
            c.lout[i] = y[i];
        }
        y
    }

    /// Ticks per tile: the samples of a chunk's channels copied into a time-major buffer.
    const TILE: usize = 16;

    /// Runs the channels of `cols` in chunks of `L` through `samples` ticks of `input` into
    /// `output`, channel c at tick t at `c * samples + t` (`channel_major`) or at
    /// `t * channels + c`. Each chunk's state stays local while the ticks go by; channel-major
    /// data is transposed through a time-major tile of [`TILE`] ticks (contiguous stores, one
    /// strided load per value).
    #[inline(always)]
    pub(super) fn run_block<T: Lane, F: BankFormula, S: Storage<T>, const L: usize>(
        cols: &mut Columns<S>,
        input: &[T],
        output: &mut [T],
        samples: usize,
        channel_major: bool,
    ) {
        let n = cols.k1.as_ref().len();
        let mut start = 0;
        while start < n {
            let width = (n - start).min(L);
            let mut chunk = load::<T, S, L>(cols, start, width);
            if !channel_major {
                for t in 0..samples {
                    let row = &input[t * n + start..t * n + start + width];
                    let mut x = [T::zero(); L];
                    x[..width].copy_from_slice(row);
                    let y = tick::<T, F, L>(&mut chunk, &x);
                    output[t * n + start..t * n + start + width].copy_from_slice(&y[..width]);
                }
            } else {
                let mut t0 = 0;
                while t0 < samples {
                    let len = (samples - t0).min(TILE);
                    let mut xs = [[T::zero(); L]; TILE];
                    for (k, x) in xs.iter_mut().enumerate().take(len) {
                        for (i, xi) in x.iter_mut().enumerate().take(width) {
                            *xi = input[(start + i) * samples + t0 + k];
                        }
                    }
                    for (k, x) in xs.iter().enumerate().take(len) {
                        let y = tick::<T, F, L>(&mut chunk, x);
                        for (i, yi) in y.iter().enumerate().take(width) {
                            output[(start + i) * samples + t0 + k] = *yi;
                        }
                    }
                    t0 += len;
                }
            }
            store::<T, S, L>(cols, &chunk, start, width);
            start += width;
        }
    }

    fn load<T: Lane, S: Storage<T>, const L: usize>(
        cols: &Columns<S>,
        start: usize,
        width: usize,
    ) -> Chunk<T, L> {
        let col = |s: &S, fill: T| -> [T; L] {
            let mut a = [fill; L];
            a[..width].copy_from_slice(&s.as_ref()[start..start + width]);
            a
        };
        let (zero, one) = (T::zero(), T::one());
        Chunk {
            // Padding lanes get harmless parameters; their outputs are dropped.
            k1: col(&cols.k1, one),
            k2: col(&cols.k2, one),
            rin: col(&cols.reversal_input, zero),
            rout: col(&cols.reversal_output, zero),
            sign: col(&cols.sign, one),
            lin: col(&cols.last_input, zero),
            lout: col(&cols.last_output, zero),
            started: col(&cols.started, zero),
            omega: col(&cols.omega, zero),
            omega_y: col(&cols.omega_y, T::neg_infinity()),
            ln_k2: col(&cols.ln_k2, zero),
            inv_k2: col(&cols.inv_k2, one),
        }
    }

    fn store<T: Lane, S: Storage<T>, const L: usize>(
        cols: &mut Columns<S>,
        c: &Chunk<T, L>,
        start: usize,
        width: usize,
    ) {
        let put = |s: &mut S, a: &[T; L]| {
            s.as_mut()[start..start + width].copy_from_slice(&a[..width]);
        };
        put(&mut cols.reversal_input, &c.rin);
        put(&mut cols.reversal_output, &c.rout);
        put(&mut cols.sign, &c.sign);
        put(&mut cols.last_input, &c.lin);
        put(&mut cols.last_output, &c.lout);
        put(&mut cols.started, &c.started);
        put(&mut cols.omega, &c.omega);
        put(&mut cols.omega_y, &c.omega_y);
    }
}

/// How a float type runs a block: its chunk width, and the dispatch to the best instruction set.
/// Implemented for `f32` and `f64` only.
pub trait RunBlock: Sized {
    /// Runs `samples` ticks of the channel-major `input` through every channel of `cols`.
    #[doc(hidden)]
    fn run<F: BankFormula, S: Storage<Self>>(
        cols: &mut Columns<S>,
        input: &[Self],
        output: &mut [Self],
        samples: usize,
        channel_major: bool,
    );
}

/// Runs a block, compiled once per instruction set (AVX-512, AVX2 + FMA, baseline) with the
/// best one chosen at run time when `std` is on.
#[cfg_attr(
    feature = "std",
    multiversion::multiversion(targets(
        "x86_64+avx512f+avx512dq+avx512vl+avx512bw",
        "x86_64+avx2+fma",
    ))
)]
fn dispatch_f64<F: BankFormula, S: Storage<f64>>(
    cols: &mut Columns<S>,
    input: &[f64],
    output: &mut [f64],
    samples: usize,
    channel_major: bool,
) {
    kernels::run_block::<f64, F, S, 64>(cols, input, output, samples, channel_major);
}

#[cfg_attr(
    feature = "std",
    multiversion::multiversion(targets(
        "x86_64+avx512f+avx512dq+avx512vl+avx512bw",
        "x86_64+avx2+fma",
    ))
)]
fn dispatch_f32<F: BankFormula, S: Storage<f32>>(
    cols: &mut Columns<S>,
    input: &[f32],
    output: &mut [f32],
    samples: usize,
    channel_major: bool,
) {
    kernels::run_block::<f32, F, S, 64>(cols, input, output, samples, channel_major);
}

impl RunBlock for f64 {
    fn run<F: BankFormula, S: Storage<Self>>(
        cols: &mut Columns<S>,
        input: &[Self],
        output: &mut [Self],
        samples: usize,
        channel_major: bool,
    ) {
        dispatch_f64::<F, S>(cols, input, output, samples, channel_major);
    }
}

impl RunBlock for f32 {
    fn run<F: BankFormula, S: Storage<Self>>(
        cols: &mut Columns<S>,
        input: &[Self],
        output: &mut [Self],
        samples: usize,
        channel_major: bool,
    ) {
        dispatch_f32::<F, S>(cols, input, output, samples, channel_major);
    }
}
