//! What a kernel runs on: the [`Block`] of samples (its layout and the ticks to run) and
//! [`RunBlock`], the trait by which a float type runs a block through the columns of a range
//! of channels. Both are public only as parts of the sealed bank API.

use crate::columns::ColumnsMut;
use crate::error::BankError;
use crate::formula::BankFormula;

/// The samples a kernel runs: `samples` ticks of all channels, channel c at tick t at
/// `c * samples + t` (`channel_major`) or `t * channels + c`, of which ticks `begin..end` run;
/// with a `limit`, only while every sample's magnitude is below it. Public only as a parameter
/// of the sealed [`RunBlock`].
#[doc(hidden)]
pub struct Block<'a, T> {
    pub(super) input: &'a [T],
    pub(super) output: &'a mut [T],
    pub(super) samples: usize,
    pub(super) channel_major: bool,
    pub(super) begin: usize,
    pub(super) end: usize,
    pub(super) limit: Option<T>,
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
