//! How `f32` and `f64` run a block ([`RunBlock`]): the kernel of the chosen instruction set
//! (AVX-512, AVX2 + FMA or SSE2 with `std` on x86-64), else the portable kernel on plain
//! floats, four channels at a time.

use crate::block::{Block, RunBlock};
use crate::columns::ColumnsMut;
use crate::error::BankError;
use crate::formula::BankFormula;
#[cfg(all(feature = "std", target_arch = "x86_64"))]
use crate::instruction_set::{isa, Isa};
use crate::kernel;
use crate::simd::Pair;
#[cfg(all(feature = "std", target_arch = "x86_64"))]
use crate::x86;

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
                kernel::run::<Pair<Pair<$t>>, F>((), cols, block)
            }
        }
    };
}

run_block!(f64, run_f64);
run_block!(f32, run_f32);
