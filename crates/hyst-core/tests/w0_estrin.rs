//! The direct operator's outputs (eq. 2) and W0 over a sweep, against the values of
//! `data/w0_estrin.txt`: the same computations with W0 evaluated by Estrin's scheme (Fukushima's
//! regions and coefficients as the `lambert_w` crate has them, with fused multiply-adds), which
//! the crate evaluates by Horner's scheme. The two differ by rounding only; this test bounds the
//! difference in ulps and prints the largest: 16 ulps of max(|input|, |output|, k1) for the
//! outputs, 10 ulps for W0.
//!
//! Run with `cargo test -p hyst-core --test w0_estrin -- --nocapture` to see the figures.

#![allow(clippy::panic, clippy::unwrap_used, clippy::expect_used)]

use hyst_core::lambert::w0;
use hyst_core::{Hysteresis, Operator};

/// The (k1, k2) of the sweep: the paper's examples, a large k2 (the log domain of eq. 2), a
/// small one, a near-backlash one.
const CASES: [(f64, f64); 7] = [
    (0.14, 8.0),
    (0.105, 5.0),
    (0.06, 5.0),
    (0.2, 8.0),
    (0.2, 2000.0),
    (0.5, 0.5),
    (1e-3, 1e6),
];

/// Samples per case.
const SAMPLES: usize = 1500;

/// The input of a case at sample t: a sine whose amplitude wanders from 1.2 k1 to 6 k1, with a
/// faster ripple of 0.3 k1 (reversals at every depth of the band).
fn input(k1: f64, t: usize) -> f64 {
    let t = t as f64;
    let amplitude = 6.0 * k1 * (0.2 + 0.8 * (t * 0.0071).sin().abs());
    amplitude * (t * 0.05).sin() + 0.3 * k1 * (t * 0.9).sin()
}

/// The arguments of W0 itself: 1e-6 to 1e6 in steps of 10^0.01, then to 1e300 in steps of
/// 10^0.5.
fn arguments() -> impl Iterator<Item = f64> {
    let fine = (0..1200).map(|i| 10f64.powf(-6.0 + 0.01 * f64::from(i)));
    let coarse = (0..589).map(|i| 10f64.powf(6.0 + 0.5 * f64::from(i)));
    fine.chain(coarse)
}

/// Every value of the sweep, in order, each with the scale its difference is measured in: each
/// case's outputs (scale max(|input|, |output|, k1), the scale of the operator's rounding: an
/// output near 0 is the difference of terms of that size), then W0's (scale |W0|).
fn values() -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for (k1, k2) in CASES {
        let mut h = Hysteresis::new(k1, k2).unwrap();
        out.extend((0..SAMPLES).map(|t| {
            let x = input(k1, t);
            let y = h.step(x);
            (y, x.abs().max(y.abs()).max(k1))
        }));
    }
    out.extend(arguments().map(|z| {
        let w = w0(z);
        (w, w.abs())
    }));
    out
}

/// The spacing of the floats at |s| (s finite, not zero).
fn ulp(s: f64) -> f64 {
    let s = s.abs();
    f64::from_bits(s.to_bits() + 1) - s
}

/// At most this many ulps of the scale between an output and its value with W0 by Estrin's
/// scheme (16 measured: a difference at a reversal stays in the memory and adds to later ones).
const MAX_OUTPUT_ULPS: f64 = 16.0;

/// At most this many ulps between W0 and its value by Estrin's scheme (10 measured, near
/// z = 0.07, in the crate's Taylor polynomial of degree 32).
const MAX_W0_ULPS: f64 = 10.0;

const RECORDED: &str = include_str!("data/w0_estrin.txt");

#[test]
fn outputs_and_w0_are_within_a_few_ulps_of_estrins() {
    let recorded: Vec<f64> = RECORDED
        .lines()
        .map(|l| f64::from_bits(u64::from_str_radix(l, 16).unwrap()))
        .collect();
    let now = values();
    assert_eq!(now.len(), recorded.len());
    let outputs = CASES.len() * SAMPLES;
    // (worst in ulps of the scale, values that differ) for the outputs, then for W0.
    let mut worst = [(0.0_f64, 0_usize); 2];
    for (i, ((a, scale), b)) in now.iter().zip(&recorded).enumerate() {
        let d = (a - b).abs() / ulp(*scale);
        let bound = if i < outputs {
            MAX_OUTPUT_ULPS
        } else {
            MAX_W0_ULPS
        };
        assert!(
            d <= bound,
            "value {i}: {a:e} against {b:e}, {d} ulps of {scale:e}"
        );
        let w = &mut worst[usize::from(i >= outputs)];
        w.0 = w.0.max(d);
        w.1 += usize::from(a != b);
    }
    let [(out_ulps, out_differ), (w0_ulps, w0_differ)] = worst;
    println!(
        "outputs: {out_differ} of {outputs} differ, by {out_ulps:.2} ulps of max(|x|, |y|, k1) at most"
    );
    println!(
        "W0: {w0_differ} of {} differ, by {w0_ulps:.2} ulps at most",
        now.len() - outputs
    );
}
