//! Test signals: noise, loops and strokes, deterministic from their seeds.

use crate::rng::Random;
use std::f64::consts::PI;

/// `n` standard normal numbers from `rng` ([`Random::normal`], two words each).
pub fn normals(rng: &mut impl Random, n: usize) -> Vec<f64> {
    (0..n).map(|_| rng.normal()).collect()
}

/// An input that sweeps loops of growing then shrinking amplitude around an offset of 2 (volts,
/// say), `n` samples: 2 + (0.3 + 1.5 sin(π t))·sin(40 t) + 0.2 sin(97 t) at t = k/n.
pub fn loops(n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| {
            let t = k as f64 / n as f64;
            let amp = 0.3 + 1.5 * (PI * t).sin();
            2.0 + amp * (40.0 * t).sin() + 0.2 * (97.0 * t).sin()
        })
        .collect()
}

/// A piston stroke (mm) at 1 kHz, `n` samples: three sines with amplitudes 4 + 2 |r| mm,
/// frequencies `f0` + `f_spread` |r| Hz and phases r (rad), the r nine standard normals of
/// `rng`.
pub fn stroke(n: usize, rng: &mut impl Random, f0: f64, f_spread: f64) -> Vec<f64> {
    let r = normals(rng, 9);
    (0..n)
        .map(|k| {
            let t = k as f64 * 1e-3;
            (0..3)
                .map(|i| {
                    let amp = 4.0 + 2.0 * r[3 * i].abs();
                    let f = f0 + f_spread * r[3 * i + 1].abs();
                    amp * (2.0 * PI * f * t + r[3 * i + 2]).sin()
                })
                .sum()
        })
        .collect()
}
