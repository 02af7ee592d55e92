//! The checks around the kernels: the channels' parameters (as the scalar operator checks
//! them), the lengths of a block, the input limit below which no channel can fail, and the
//! checked path that runs a block up to the first tick with a sample at or beyond that limit,
//! then that tick alone.

use crate::block::Block;
use crate::columns::{Columns, Slab};
use crate::error::BankError;
use crate::formula::BankFormula;
use crate::vector::Lane;
use hyst_core::error::Error;
use hyst_core::k2law::ConstantK2;
use hyst_core::parametric::ParametricHysteresis;

/// Checks each channel's parameters as [`ParametricHysteresis::new`] does for one operator
/// (the bank accepts exactly the channels the scalar operator accepts).
pub(super) fn check<T: Lane, F: BankFormula>(k1: &[T], k2: &[T]) -> Result<(), BankError> {
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
        ParametricHysteresis::<T, ConstantK2<T>, F>::new(*a, *b)
            .map_err(|error| BankError { channel, error })?;
    }
    Ok(())
}

/// The largest |input| for which no channel's output can leave the float range: every output
/// lies within 3 k1 of its input (eqs. 2 and 4 on a memory in the band, or their overflow-free
/// forms), so below T::MAX − 4 max k1 the scalar operator never refuses a finite sample.
pub(super) fn input_limit<T: Lane>(k1: &[T]) -> T {
    let max = k1
        .iter()
        .fold(T::zero(), |m, v| if *v > m { *v } else { m });
    T::max_value() - T::from_f64(4.0) * max
}

/// Checks the lengths of a channel-major block of `samples` ticks of `channels` channels.
pub(super) fn check_block<T>(
    channels: usize,
    input: &[T],
    output: &[T],
    samples: usize,
) -> Result<(), BankError> {
    let expected = channels.saturating_mul(samples);
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

/// Runs a block whose lengths are checked through `columns`, with the bank's input `limit`.
/// The kernel checks each tile of ticks against the input limit before running it and stops
/// before the first tick with a sample at or beyond the limit; that tick is an error if a
/// sample is not finite, and otherwise runs alone on the memory with a copy to put back should
/// the scalar operator refuse a sample (an output beyond the float range). Either way the
/// ticks before the failing one are done and the memory is as after them.
pub(super) fn run_checked<T: Lane, F: BankFormula, B: Slab<T>>(
    columns: &mut Columns<B>,
    limit: T,
    input: &[T],
    output: &mut [T],
    samples: usize,
    channel_major: bool,
) -> Result<(), BankError> {
    let n = columns.n.max(1);
    let mut begin = 0;
    while begin < samples {
        let mut block = Block {
            input,
            output: &mut *output,
            samples,
            channel_major,
            begin,
            end: samples,
            limit: Some(limit),
        };
        let Some(bad) = T::run::<F>(&mut columns.view(), &mut block)? else {
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
        let before = columns.clone();
        let mut block = Block {
            input,
            output: &mut *output,
            samples,
            channel_major,
            begin: bad,
            end: bad + 1,
            limit: None,
        };
        if let Err(e) = T::run::<F>(&mut columns.view(), &mut block) {
            *columns = before;
            return Err(e);
        }
        begin = bad + 1;
    }
    Ok(())
}
