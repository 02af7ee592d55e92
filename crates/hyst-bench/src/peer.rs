//! The plain-C peer of the inverse operator (src/peer.c): eq. (4) with Definition 2.1's memory,
//! the same arithmetic as `InverseHysteresis` with no checks, compiled at -O2 by build.rs; and
//! [`PeerComparison`], hyst's inverse next to it on the same signal.

// The only unsafe code of this crate: two calls into C that read `x[..n]` and write `y[..n]`.
#![allow(unsafe_code)]

use std::hint::black_box;

use crate::workloads::{signal, Inputs, Suite, K1, K2, NAMES, SAMPLES};

extern "C" {
    fn hyst_peer_inverse(k1: f64, k2: f64, x: *const f64, y: *mut f64, n: usize);
    fn hyst_peer_inverse_sum(k1: f64, k2: f64, x: *const f64, n: usize) -> f64;
}

/// H⁻¹(k1, k2) from no history over `x`, the sum of its outputs.
#[must_use]
pub fn inverse_sum(k1: f64, k2: f64, x: &[f64]) -> f64 {
    // SAFETY: the C function reads x[0..n) only, n = x.len(), and keeps no pointer.
    unsafe { hyst_peer_inverse_sum(k1, k2, x.as_ptr(), x.len()) }
}

/// H⁻¹(k1, k2) from no history over `x` into `y` (as many outputs as both have room for).
pub fn inverse(k1: f64, k2: f64, x: &[f64], y: &mut [f64]) {
    let n = x.len().min(y.len());
    // SAFETY: the C function reads x[0..n), writes y[0..n) (n within both slices, which
    // cannot overlap: `y` is borrowed mutably) and keeps no pointer.
    unsafe { hyst_peer_inverse(k1, k2, x.as_ptr(), y.as_mut_ptr(), n) }
}

/// The JSON key of hyst's inverse workload (in [`NAMES`]), which the peer is compared with.
pub const INVERSE_KEY: &str = "inverse_ns";

/// The peer's workload: its name and JSON key.
pub const PEER_NAME: (&str, &str) = ("plain-C inverse (peer, no checks)", "c_peer_ns");

/// The goal: hyst's inverse over the peer, per sample, at most this.
pub const C_PEER_GOAL: f64 = 1.0;

/// hyst's inverse operator (the workload `inverse_ns` of `hyst bench`, workload 0 here) and the
/// C peer (1) on the same [`signal`] with the same [`K1`], [`K2`], measured as one [`Suite`].
pub struct PeerComparison {
    inputs: Inputs,
    /// The index of hyst's inverse in [`NAMES`].
    inverse: usize,
    /// The peer's input: the inverse workload's signal.
    x: Vec<f64>,
}

impl PeerComparison {
    /// Builds both workloads' inputs.
    #[must_use]
    pub fn new() -> Self {
        Self {
            inputs: Inputs::new(),
            inverse: NAMES
                .iter()
                .position(|&(_, key)| key == INVERSE_KEY)
                .unwrap_or(usize::MAX),
            x: signal(),
        }
    }

    /// The names and JSON keys of the two workloads, in their order.
    #[must_use]
    pub fn names(&self) -> [(&'static str, &'static str); 2] {
        let inverse = NAMES
            .get(self.inverse)
            .copied()
            .unwrap_or(("", INVERSE_KEY));
        [inverse, PEER_NAME]
    }
}

impl Default for PeerComparison {
    fn default() -> Self {
        Self::new()
    }
}

impl Suite for PeerComparison {
    fn count(&self) -> usize {
        2
    }

    fn samples(&self, _: usize) -> usize {
        SAMPLES
    }

    fn available(&self, _: usize) -> bool {
        true
    }

    /// 0: hyst's inverse, 1: the peer, each through one `black_box` of its whole input.
    fn run(&self, index: usize) -> f64 {
        match index {
            0 => self.inputs.run(self.inverse),
            1 => inverse_sum(K1, K2, black_box(&self.x)),
            _ => f64::NAN,
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use hyst_core::{InverseHysteresis, Operator as _};

    use super::*;

    /// The C peer is a real inverse: on the benchmark's signal (and a signal of k1-sized
    /// reversals) its outputs equal hyst's inverse bit for bit (the same arithmetic in the same
    /// order and the same `exp`, the platform's; hyst's band clamp, which may move an output by
    /// an ulp, does not fire on these signals).
    #[test]
    fn the_c_peer_is_the_inverse_operator() {
        let x = signal();
        let small: Vec<f64> = (0..2000)
            .map(|k| 0.3 * (f64::from(k) * 0.05).sin() * (f64::from(k) * 0.013).cos())
            .collect();
        for (k1, k2, x) in [(K1, K2, &x), (0.2, 40.0, &small), (0.05, 1.0, &small)] {
            let mut y = vec![0.0; x.len()];
            inverse(k1, k2, x, &mut y);
            let mut h = InverseHysteresis::new(k1, k2).unwrap();
            for (i, (&u, &c)) in x.iter().zip(&y).enumerate() {
                let v = h.try_step(u).unwrap();
                assert_eq!(v.to_bits(), c.to_bits(), "sample {i}: hyst {v}, C peer {c}");
            }
            let sum = y.iter().fold(0.0, |a, b| a + b);
            assert_eq!(inverse_sum(k1, k2, x).to_bits(), sum.to_bits());
        }
    }

    /// The comparison's first workload is `hyst bench`'s inverse, its second the peer, both
    /// over the same samples: the peer's sum is the one its own call gives.
    #[test]
    fn the_comparison_runs_hysts_inverse_and_the_peer() {
        let c = PeerComparison::new();
        assert_eq!(c.names()[0].1, INVERSE_KEY);
        assert_eq!(c.names()[1], PEER_NAME);
        let inputs = Inputs::new();
        assert_eq!(c.run(0).to_bits(), inputs.run(c.inverse).to_bits());
        assert_eq!(c.run(1).to_bits(), inverse_sum(K1, K2, &signal()).to_bits());
        assert!(c.run(2).is_nan());
    }
}
