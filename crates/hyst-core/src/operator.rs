//! The one stepping interface of the project: a causal operator with memory that maps an input
//! signal to an output signal, sample by sample.
//!
//! Every hysteresis operator of the paper is of this kind (Section 2: the output at time t
//! depends on the input up to t through the memory of Definition 2.1), and so is everything
//! built from them. [`Operator`] is implemented by
//!
//! - the direct and inverse parametric operators [`Hysteresis`](crate::Hysteresis) (eq. 2) and
//!   [`InverseHysteresis`](crate::InverseHysteresis) (eq. 4), and every
//!   [`ParametricHysteresis`](crate::ParametricHysteresis) with an input-dependent k2;
//! - the shaped model [`ShapedModel`](crate::ShapedModel) (Section 4.3) and its exact inverse
//!   [`InverseShapedModel`](crate::InverseShapedModel);
//! - the [`Play`](crate::Play) operator (backlash), the
//!   [`PrandtlIshlinskii`](crate::PrandtlIshlinskii) sum of plays, its shaped form and inverse;
//!
//! and, outside the core, by the simulated "true" hysteresis of `hyst-sim` and the fitted-model
//! evaluator of `hyst-fit`. The simulator, the fitting code and the `hyst` tool step operators
//! only through this trait; rustdoc's "Implementors" list below is the complete list.
//!
//! A sample is a plain number or a [`Jet`](crate::Jet) (a value and its first N time derivatives): the same
//! [`Operator::try_step`] gives the output's derivatives when it is given the input's.

use crate::error::Error;
use crate::real::Real;
use crate::sample::Sample;

/// A causal operator with memory: one output sample per input sample, plain or [`Jet`](crate::Jet).
///
/// Implementors provide [`Operator::try_step`] (every evaluation goes through it),
/// [`Operator::last_output`], [`Operator::reset`] and the memory accessors; the block and
/// holding methods are provided.
///
/// The contract every implementation keeps:
/// - [`Operator::try_step`] either returns the output and commits the memory, or returns an
///   error (a non-finite sample, an input outside a shaping function's range, …) and leaves the
///   memory exactly as it was. It never panics.
/// - [`Operator::memory`] followed later by [`Operator::set_memory`] resumes exactly where the
///   operator stood (a controller that restarts).
///
/// # Examples
/// Any operator runs through the same generic code:
/// ```
/// use hyst_core::{Hysteresis, Operator, Play};
/// fn run<O: Operator<f64>>(op: &mut O, input: &[f64]) -> Vec<f64> {
///     input.iter().map(|x| op.step(*x)).collect()
/// }
/// let input = [0.0, 1.0, 0.5, -1.0];
/// let smooth = run(&mut Hysteresis::new(0.2, 1e9)?, &input);
/// let hard = run(&mut Play::new(0.2)?, &input);
/// for (s, h) in smooth.iter().zip(&hard) {
///     assert!((s - h).abs() < 1e-7); // k2 → ∞ is a backlash of half-width k1
/// }
/// # Ok::<(), hyst_core::Error>(())
/// ```
pub trait Operator<T: Real> {
    /// What [`Operator::memory`] saves and [`Operator::set_memory`] restores: the operator's
    /// whole history-dependent state (for the parametric operator, the memory of
    /// Definition 2.1, `None` before the first sample).
    type Memory: Clone + core::fmt::Debug + PartialEq;

    /// One sample, plain or a [`Jet`](crate::Jet): the output, with its time derivatives when the input
    /// carries them (Proposition 2.7 and beyond).
    ///
    /// # Errors
    /// [`Error::NonFiniteInput`] for a non-finite value or derivative, and the operator's own
    /// refusals (an invalid k2 from a custom law, a value outside a shaping function's range).
    /// The memory is then unchanged.
    fn try_step<S: Sample<T>>(&mut self, x: S) -> Result<S, Error>;

    /// The output of the last accepted sample; `None` before the first.
    fn last_output(&self) -> Option<T>;

    /// Forgets the history: back to the initial state the operator was built with.
    fn reset(&mut self);

    /// The current memory (save it to resume later).
    #[doc(alias = "state")]
    fn memory(&self) -> Self::Memory;

    /// Restores a memory saved by [`Operator::memory`] (from this operator or one with the same
    /// parameters).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] or [`Error::StateOutsideBand`] for a memory the operator
    /// cannot be in (non-finite values, a point outside the band |output − input| ≤ k1); the
    /// operator is then unchanged.
    #[doc(alias = "restore")]
    fn set_memory(&mut self, memory: Self::Memory) -> Result<(), Error>;

    /// One plain sample that never fails: a sample [`Operator::try_step`] refuses holds the last
    /// output (or returns the input as is before any output) and leaves the memory untouched.
    #[inline]
    fn step(&mut self, x: T) -> T {
        match self.try_step(x) {
            Ok(y) => y,
            Err(_) => self.last_output().unwrap_or(x),
        }
    }

    /// Processes a block of samples into `output` (same length) without allocating; each
    /// sample behaves as [`Operator::step`].
    ///
    /// # Errors
    /// [`Error::LengthMismatch`] when the slices differ in length (nothing is processed).
    fn process(&mut self, input: &[T], output: &mut [T]) -> Result<(), Error> {
        if input.len() != output.len() {
            return Err(Error::LengthMismatch {
                input: input.len(),
                output: output.len(),
            });
        }
        for (x, y) in input.iter().zip(output.iter_mut()) {
            *y = self.step(*x);
        }
        Ok(())
    }

    /// Processes a block of samples in place: each input sample is replaced by its output (as
    /// [`Operator::step`]).
    fn process_in_place(&mut self, samples: &mut [T]) {
        for x in samples.iter_mut() {
            *x = self.step(*x);
        }
    }
}
