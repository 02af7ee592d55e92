//! Near-backlash use (Example 3 wants k2 → ∞): with k2 = 1e9 and beyond the operator stays
//! finite and within (ln(2 k1 k2) + 1) / k2 (≈ 2.6e-8 for k1 = 0.2, k2 = 1e9) of a hard backlash
//! (play operator) of half-width k1.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use hyst_core::Operator;
use hyst_core::{Hysteresis, InverseHysteresis};

/// The play operator: the output stays put until the input drags it along at distance k1.
fn play(k1: f64, u_prev: f64, v: f64) -> f64 {
    u_prev.clamp(v - k1, v + k1)
}

fn input(k: usize) -> f64 {
    let t = k as f64 * 1e-3;
    1.3 * (t).sin() + 0.4 * (3.7 * t).sin() + 0.05 * (31.0 * t).cos()
}

#[test]
fn large_k2_approaches_the_hard_backlash() {
    for &(k1, k2) in &[(0.2_f64, 1e9_f64), (0.2, 1e12), (0.05, 1e10), (1.0, 1e9)] {
        let mut h = Hysteresis::new(k1, k2).unwrap();
        let mut hinv = InverseHysteresis::new(k1, k2).unwrap();
        let bound = ((2.0 * k1 * k2).ln() + 1.0) / k2;
        let mut u_play = input(0);
        let mut worst = 0.0f64;
        for k in 0..20_000 {
            let v = input(k);
            let u = h.step(v);
            assert!(u.is_finite(), "k1 {k1} k2 {k2}: non-finite output at {v}");
            u_play = play(k1, u_play, v);
            worst = worst.max((u - u_play).abs());
            // The inverse is finite too and undoes the direct operator.
            let back = hinv.step(u);
            assert!(back.is_finite());
        }
        assert!(
            worst <= bound,
            "k1 {k1} k2 {k2}: worst deviation from backlash {worst} > {bound}"
        );
        if k2 == 1e9 && k1 == 0.2 {
            assert!(worst < 3e-8, "{worst}");
        }
    }
}

#[test]
fn f32_survives_huge_k2() {
    let mut h = Hysteresis::new(0.2_f32, 1e9).unwrap();
    for k in 0..5000 {
        let v = input(k) as f32;
        let u = h.step(v);
        assert!(u.is_finite());
        assert!((u - v).abs() <= 0.2 + 1e-6);
    }
}
