//! The bank on rayon's threads (feature `rayon`): [`ParametricBank::step_par`] and
//! [`ParametricBank::process_block_par`] split the channels into parts of whole chunks, one
//! part per task, and give the same outputs as one thread, bit for bit.

use crate::block::Block;
use crate::checked::{check_block, run_checked};
use crate::columns::Storage;
use crate::error::BankError;
use crate::formula::BankFormula;
use crate::vector::Lane;
use crate::ParametricBank;

/// Threads: the channels split into parts of whole chunks, one part per task (rayon).
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
        check_block(self.channels(), input, output, samples)?;
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
            return run_checked::<T, F, S::Slab>(
                &mut self.columns,
                limit,
                input,
                output,
                samples,
                channel_major,
            );
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
