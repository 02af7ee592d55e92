//! Property tests of the operator pair (proptest): Proposition 4.1 (left and right inverse), the
//! band |u − v| ≤ k1, monotonicity, passivity, rate independence, Proposition 4.2 (convergence
//! from mismatched initial states) and the inequalities of Lemma 3.1.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use hyst_core::lambert::omega;
use hyst_core::Operator;
use hyst_core::{Direction, Hysteresis, InverseHysteresis};
use proptest::prelude::*;

/// A random input signal: a random walk with steps of random size and sign, sometimes repeating
/// a sample (zero step), scaled to `amplitude`.
fn signal(amplitude: f64) -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec((-1.0f64..1.0, 0u8..10), 2..300).prop_map(move |steps| {
        let mut x = 0.0;
        steps
            .into_iter()
            .map(|(s, kind)| {
                if kind != 0 {
                    x += s * amplitude * if kind < 3 { 0.01 } else { 0.3 };
                }
                x
            })
            .collect()
    })
}

fn params() -> impl Strategy<Value = (f64, f64)> {
    // k1 from 1e-3 to 10, k2 from 1e-2 to 1e4 (log-uniform)
    (-3.0f64..1.0, -2.0f64..4.0).prop_map(|(a, b)| (10f64.powf(a), 10f64.powf(b)))
}

fn scale(xs: &[f64], k1: f64) -> f64 {
    xs.iter().fold(k1, |m, x| m.max(x.abs()))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    /// Proposition 4.1, left inverse: H(H⁻¹(u_d)) = u_d.
    #[test]
    fn left_inverse((k1, k2) in params(), xs in signal(3.0)) {
        let mut h = Hysteresis::new(k1, k2).unwrap();
        let mut hinv = InverseHysteresis::new(k1, k2).unwrap();
        let tol = 1e-12 * scale(&xs, k1);
        for &ud in &xs {
            let v = hinv.try_step(ud).unwrap();
            let u = h.try_step(v).unwrap();
            prop_assert!((u - ud).abs() <= tol, "k1 {} k2 {} ud {} v {} u {}", k1, k2, ud, v, u);
        }
    }

    /// Proposition 4.1, right inverse: H⁻¹(H(v)) = v. The inverse amplifies rounding in u by its
    /// slope, up to 1 + 2 k1 k2; the tolerance is 1e-12 relative for k1 k2 ≤ 100.
    #[test]
    fn right_inverse(k1 in 1e-3f64..1.0, k1k2 in 1e-2f64..100.0, xs in signal(3.0)) {
        let k2 = k1k2 / k1;
        let mut h = Hysteresis::new(k1, k2).unwrap();
        let mut hinv = InverseHysteresis::new(k1, k2).unwrap();
        let tol = 1e-12 * scale(&xs, k1);
        for &v in &xs {
            let u = h.try_step(v).unwrap();
            let back = hinv.try_step(u).unwrap();
            prop_assert!((back - v).abs() <= tol, "k1 {} k2 {} v {} back {}", k1, k2, v, back);
        }
    }

    /// The output stays in the band |u − v| ≤ k1, for the direct and the inverse operator.
    #[test]
    fn band((k1, k2) in params(), xs in signal(5.0)) {
        let mut h = Hysteresis::new(k1, k2).unwrap();
        let mut hinv = InverseHysteresis::new(k1, k2).unwrap();
        let tol = k1 * 1e-12 + 1e-14 * scale(&xs, k1);
        for &x in &xs {
            prop_assert!((h.step(x) - x).abs() <= k1 + tol);
            prop_assert!((hinv.step(x) - x).abs() <= k1 + tol);
        }
    }

    /// Monotonicity (Section 4.2): each output step has the sign of the input step (or is 0).
    #[test]
    fn monotone((k1, k2) in params(), xs in signal(2.0)) {
        let mut h = Hysteresis::new(k1, k2).unwrap();
        let mut hinv = InverseHysteresis::new(k1, k2).unwrap();
        let tol = 1e-14 * scale(&xs, k1);
        let (mut u_prev, mut v_prev) = (h.step(xs[0]), hinv.step(xs[0]));
        for w in xs.windows(2) {
            let dx = w[1] - w[0];
            let (u, v) = (h.step(w[1]), hinv.step(w[1]));
            prop_assert!((u - u_prev) * dx.signum() >= -tol, "direct not monotone");
            prop_assert!((v - v_prev) * dx.signum() >= -tol, "inverse not monotone");
            if dx == 0.0 {
                prop_assert_eq!(u, u_prev);
                prop_assert_eq!(v, v_prev);
            }
            u_prev = u;
            v_prev = v;
        }
    }

    /// Rate independence: inserting samples between consecutive samples (which keeps every
    /// monotone stretch monotone) leaves the outputs at the original samples unchanged.
    #[test]
    fn rate_independent((k1, k2) in params(), xs in signal(2.0), splits in 1usize..5) {
        let mut coarse = Hysteresis::new(k1, k2).unwrap();
        let mut fine = Hysteresis::new(k1, k2).unwrap();
        let mut coarse_inv = InverseHysteresis::new(k1, k2).unwrap();
        let mut fine_inv = InverseHysteresis::new(k1, k2).unwrap();
        let mut prev: Option<f64> = None;
        for &x in &xs {
            if let Some(p) = prev {
                for j in 1..splits {
                    let xi = p + (x - p) * j as f64 / splits as f64;
                    fine.step(xi);
                    fine_inv.step(xi);
                }
            }
            prop_assert_eq!(coarse.step(x), fine.step(x));
            prop_assert_eq!(coarse_inv.step(x), fine_inv.step(x));
            prev = Some(x);
        }
    }

    /// Passivity (Section 4.2): closed loops are counter-clockwise; over one period of a
    /// periodic input the loop area −∮ u dv is ≥ 0 and the rising branch lies below the falling one.
    #[test]
    fn passive((k1, k2) in params(), lo in -3.0f64..0.0, width in 0.01f64..4.0, n in 8usize..60) {
        let mut h = Hysteresis::new(k1, k2).unwrap();
        let hi = lo + width;
        let period: Vec<f64> = (0..2 * n)
            .map(|i| if i < n { lo + width * i as f64 / n as f64 } else { hi - width * (i - n) as f64 / n as f64 })
            .collect();
        // Two periods to settle on the limit cycle, then measure the third.
        for _ in 0..2 {
            for &v in &period { h.step(v); }
        }
        let mut u: Vec<f64> = period.iter().map(|&v| h.step(v)).collect();
        u.push(h.step(lo));
        // −∮ u dv (trapezoids); the path is closed by the vertical segment at v = lo, which adds
        // nothing, so the area is meaningful even while the loop still drifts (accommodation).
        let mut area = 0.0;
        for i in 0..period.len() {
            let v_next = if i + 1 < period.len() { period[i + 1] } else { lo };
            area -= 0.5 * (u[i] + u[i + 1]) * (v_next - period[i]);
        }
        prop_assert!(area >= -1e-12 * width * width, "area {}", area);
        for i in 1..n {
            // rising sample i and falling sample 2n − i share the input value
            prop_assert!(u[i] <= u[2 * n - i] + 1e-12, "rising above falling at {}", period[i]);
        }
    }

    /// Proposition 4.2: an inverse started from a different state than the direct operator still
    /// converges under persistent excitation; the error decays like e^(−k2 ũd).
    #[test]
    fn converges_from_mismatched_state(k1 in 0.01f64..1.0, k2k1 in 2.0f64..50.0, offset in -1.0f64..1.0) {
        let k2 = k2k1 / k1;
        let mut h = Hysteresis::new(k1, k2).unwrap();
        let mut hinv = InverseHysteresis::new(k1, k2)
            .unwrap()
            .with_initial_state(0.0, offset * k1, Direction::Rising)
            .unwrap();
        let amplitude = 10.0 * k1 + 5.0 / k2;
        let mut first_cycle = 0.0f64;
        let mut last_cycle = 0.0f64;
        let n = 200;
        for cycle in 0..6 {
            for i in 0..n {
                let ud = amplitude * (std::f64::consts::TAU * i as f64 / n as f64).sin();
                let err = (h.step(hinv.step(ud)) - ud).abs();
                if cycle == 0 { first_cycle = first_cycle.max(err); }
                if cycle == 5 { last_cycle = last_cycle.max(err); }
            }
        }
        prop_assert!(last_cycle <= 1e-9 * amplitude, "still {} after 5 cycles (first {})", last_cycle, first_cycle);
    }

    /// Lemma 3.1: W(a e^a) = a; a ≤ W(a e^b) < b for a < b; b < W(a e^b) < a for a > b
    /// (evaluated in the log domain as ω(ln a + b)).
    #[test]
    fn lemma_3_1(a in 1e-6f64..50.0, b in -50.0f64..50.0) {
        let w = omega(a.ln() + b);
        let tol = 4.0 * f64::EPSILON * a.max(b.abs()).max(1.0);
        prop_assert!((omega(a.ln() + a) - a).abs() <= tol);
        if a < b {
            prop_assert!(a <= w + tol && w <= b + tol, "a {} b {} w {}", a, b, w);
        } else if a > b {
            prop_assert!(b <= w + tol && w <= a + tol, "a {} b {} w {}", a, b, w);
        }
    }
}

/// The same properties hold at f32 precision (with f32 tolerances).
#[test]
fn left_inverse_f32() {
    let mut h = Hysteresis::new(0.14_f32, 8.0).unwrap();
    let mut hinv = InverseHysteresis::new(0.14_f32, 8.0).unwrap();
    for k in 0..2000 {
        let t = k as f32 * 0.01;
        let ud = 2.0 * (t).sin() * (0.3 * t).cos();
        let u = h.step(hinv.step(ud));
        assert!((u - ud).abs() <= 2e-6, "{ud} {u}");
        assert!((hinv.step(ud) - ud).abs() <= 0.14 + 1e-6);
    }
}

/// Non-finite input: try_step errors, step holds the last output, the memory is untouched.
#[test]
fn non_finite_input_never_corrupts_the_state() {
    let mut h = Hysteresis::new(0.2_f64, 5.0).unwrap();
    assert!(h.step(f64::NAN).is_nan()); // no history yet: the input comes back as is
    assert!(h.memory().is_none());
    h.step(0.0);
    let y = h.step(1.0);
    let before = h.memory();
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert!(h.try_step(bad).is_err());
        assert_eq!(h.step(bad), y);
        assert_eq!(h.memory(), before);
    }
    assert!(h.memory().is_some_and(|m| m.last_output.is_finite()));
}
