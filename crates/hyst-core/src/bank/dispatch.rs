//! How `f32` and `f64` run a block ([`RunBlock`]): the kernel of the chosen instruction set
//! (AVX-512, AVX2 + FMA or SSE2 with `std` on x86-64), else the portable kernel on plain
//! floats, four channels at a time.

use super::block::{Block, RunBlock};
use super::columns::ColumnsMut;
use super::error::BankError;
use super::formula::BankFormula;
#[cfg(all(feature = "std", target_arch = "x86_64"))]
use super::instruction_set::{isa, Isa};
use super::kernel;
use super::simd::Pair;
#[cfg(all(feature = "std", target_arch = "x86_64"))]
use super::x86;

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
                kernel::run::<Pair<Pair<$t>>, F>(cols, block)
            }
        }
    };
}

run_block!(f64, run_f64);
run_block!(f32, run_f32);
