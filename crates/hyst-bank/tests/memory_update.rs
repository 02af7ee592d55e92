//! Definition 2.1's memory update in the bank's lanes against its scalar home, hyst-core's
//! operator, bit for bit: before each tick every channel is given the scalar operator's memory,
//! and after it the bank's reversal point (α0, β0), direction and last input must be the scalar
//! operator's exactly, for every kernel this processor runs and both formulas. (The last output
//! is eq. (2) or (4) itself, which the bank evaluates with its own `exp`, `ln` and ω: within a
//! few ulps, `tests/bank.rs`.)
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use hyst_bank::{force_isa, BankFormula, BankVec, Isa};
use hyst_core::{ConstantK2, Direct, Inverse, Memory, Operator, ParametricHysteresis};

/// Channels: more than a chunk of every kernel, and a remainder.
const CHANNELS: usize = 75;
/// Ticks.
const TICKS: usize = 400;

/// Channel c's input at tick t: sines of different periods and depths around the band (many
/// reversals, some of them at repeated values: a zero step keeps the direction).
fn input(c: usize, t: usize, k1: f64) -> f64 {
    // Every 17th tick holds the previous sample: the step is zero.
    let t = if t % 17 == 3 { t - 1 } else { t };
    let (c, t) = (c as f64, t as f64);
    k1 * (3.0 + c % 5.0) * (t * (0.05 + 0.01 * c)).sin() + 0.4 * k1 * (t * 0.7).cos()
}

/// The bits of the parts of a memory that Definition 2.1's update sets from the input.
fn update_bits(m: Option<Memory<f64>>) -> Option<(u64, u64, i8, u64)> {
    m.map(|m| {
        (
            m.reversal_input.to_bits(),
            m.reversal_output.to_bits(),
            m.direction.sign::<f64>() as i8,
            m.last_input.to_bits(),
        )
    })
}

fn memory_update_is_the_scalar_one<F: BankFormula>() -> usize {
    let k1: Vec<f64> = (0..CHANNELS).map(|c| 0.05 + 0.01 * c as f64).collect();
    let k2: Vec<f64> = (0..CHANNELS).map(|c| 0.5 + 0.37 * c as f64).collect();
    let mut bank = BankVec::<f64, F>::from_vecs(k1.clone(), k2.clone()).unwrap();
    let mut scalar: Vec<ParametricHysteresis<f64, ConstantK2<f64>, F>> = (0..CHANNELS)
        .map(|c| ParametricHysteresis::new(k1[c], k2[c]).unwrap())
        .collect();
    let mut out = vec![0.0; CHANNELS];
    let mut reversals = 0;
    for t in 0..TICKS {
        let x: Vec<f64> = (0..CHANNELS).map(|c| input(c, t, k1[c])).collect();
        for (c, h) in scalar.iter().enumerate() {
            bank.set_memory(c, h.memory()).unwrap();
        }
        bank.step(&x, &mut out).unwrap();
        for (c, h) in scalar.iter_mut().enumerate() {
            let before = h.memory().map(|m| m.reversal_input.to_bits());
            h.step(x[c]);
            let (want, got) = (update_bits(h.memory()), update_bits(bank.memory(c)));
            assert_eq!(got, want, "tick {t}, channel {c}");
            reversals += usize::from(before.is_some() && before != want.map(|w| w.0));
        }
    }
    reversals
}

#[test]
fn every_kernel_updates_the_memory_as_the_scalar_operator_does() {
    let mut kernels = 0;
    for isa in Isa::ALL {
        if force_isa(Some(isa)).is_err() {
            continue;
        }
        let reversals = memory_update_is_the_scalar_one::<Inverse>()
            + memory_update_is_the_scalar_one::<Direct>();
        assert!(reversals > 1000, "{}: {reversals} reversals", isa.name());
        kernels += 1;
    }
    force_isa(None).unwrap();
    assert!(kernels >= 1);
}
