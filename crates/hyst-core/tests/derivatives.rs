//! Time derivatives of any order (Proposition 2.7 and beyond): jets through the operators agree
//! with the corrected closed forms (7)–(8) and with finite differences of the plain operators,
//! on rising and on falling segments, for orders 1..4.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]

use hyst_core::{
    AffineK2, Direction, Formula, Jet, K2Law, Memory, Operator, ParametricHysteresis, Polynomial,
    QuadraticExp, Sample, Shaping,
};

/// A smooth input through t = 0: x(t) = x0 + s (0.8 t + 0.3 t² − 0.05 t³ + 0.1 sin 3t).
fn input(x0: f64, s: f64, t: f64) -> f64 {
    x0 + s * (0.8 * t + 0.3 * t * t - 0.05 * t * t * t + 0.1 * (3.0 * t).sin())
}

/// Its value and derivatives 1..4 at t = 0.
fn input_jet(x0: f64, s: f64) -> Jet<f64, 4> {
    Jet::from_derivatives(x0, [s * 1.1, s * 0.6, s * (-0.3 - 2.7), 0.0])
}

/// Derivatives 1..4 at t = 0 of f by fourth-order central differences: step `h` for orders 1
/// and 2, `5 h` for orders 3 and 4 (where rounding, ~ε/h^k, would otherwise dominate).
fn finite_differences(f: impl Fn(f64) -> f64, h: f64) -> [f64; 4] {
    let stencil = |h: f64| {
        let g = |j: i32| f(j as f64 * h);
        (g(0), g(1), g(-1), g(2), g(-2), g(3), g(-3))
    };
    let (f0, f1, fm1, f2, fm2, _, _) = stencil(h);
    let d1 = (-f2 + 8.0 * f1 - 8.0 * fm1 + fm2) / (12.0 * h);
    let d2 = (-f2 + 16.0 * f1 - 30.0 * f0 + 16.0 * fm1 - fm2) / (12.0 * h * h);
    let h = 5.0 * h;
    let (f0, f1, fm1, f2, fm2, f3, fm3) = stencil(h);
    [
        d1,
        d2,
        (-f3 + 8.0 * f2 - 13.0 * f1 + 13.0 * fm1 - 8.0 * fm2 + fm3) / (8.0 * h * h * h),
        (-f3 + 12.0 * f2 - 39.0 * f1 + 56.0 * f0 - 39.0 * fm1 + 12.0 * fm2 - fm3)
            / (6.0 * h * h * h * h),
    ]
}

/// An operator whose memory sits at a reversal point `back` input units behind x0 on the
/// branch of `direction`, with the reversal output `offset` from the line: every input of the
/// finite-difference stencil then stays on that branch.
fn on_branch<K: K2Law<f64> + Clone, F: Formula>(
    op: ParametricHysteresis<f64, K, F>,
    x0: f64,
    direction: Direction,
    back: f64,
    offset: f64,
) -> ParametricHysteresis<f64, K, F> {
    let s = direction.sign::<f64>();
    let alpha0 = x0 - s * back;
    let mut op = op;
    op.set_memory(Some(Memory {
        reversal_input: alpha0,
        reversal_output: alpha0 + offset,
        direction,
        last_input: alpha0,
        last_output: alpha0 + offset,
    }))
    .unwrap();
    op
}

/// The operator's derivatives 1..4 at t = 0 for the input through x0 heading s: by jets, and by
/// finite differences of the plain operator.
fn jet_and_fd<K: K2Law<f64>, F: Formula>(
    op: &ParametricHysteresis<f64, K, F>,
    x0: f64,
    s: f64,
) -> ([f64; 4], [f64; 4]) {
    let jet = op.peek(input_jet(x0, s)).unwrap().derivatives();
    let fd = finite_differences(|t| op.peek(input(x0, s, t)).unwrap(), 2e-3);
    (jet, fd)
}

fn assert_close(what: &str, jet: [f64; 4], fd: [f64; 4], orders: usize) {
    for k in 0..orders {
        let tol = if k < 2 { 1e-7 } else { 1e-4 } * jet[k].abs().max(1.0);
        assert!(
            (jet[k] - fd[k]).abs() <= tol,
            "{what}: order {}: jet {} vs finite differences {}",
            k + 1,
            jet[k],
            fd[k]
        );
    }
}

const CASES: [(f64, f64, f64, f64); 4] = [
    // (k1, k2, back, offset as a fraction of k1)
    (0.14, 8.0, 0.05, 0.3),
    (0.2, 8.0, 0.3, -0.9),
    (0.06, 5.0, 0.05, 0.0),
    (0.5, 2.0, 1.5, 0.99),
];

#[test]
fn inverse_jets_match_finite_differences_and_corrected_eq_8() {
    for direction in [Direction::Rising, Direction::Falling] {
        let s = direction.sign::<f64>();
        for (k1, k2, back, offset) in CASES {
            let x0 = 0.37;
            let op = on_branch(
                hyst_core::InverseHysteresis::new(k1, k2).unwrap(),
                x0,
                direction,
                back,
                offset * k1,
            );
            let (jet, fd) = jet_and_fd(&op, x0, s);
            let what = format!("inverse {direction:?} k1 {k1} k2 {k2}");
            assert_close(&what, jet, fd, 4);

            // The corrected eq. (7)–(8) of NOTES.md, with M* = −M + k1 and the direction s.
            let m = op.memory().unwrap();
            let m_star = k1 - m.m();
            let ud_tilde = s * (x0 - m.reversal_input);
            let e = (-k2 * ud_tilde).exp();
            let [ud1, ud2, _, _] = input_jet(x0, s).derivatives();
            let v1 = (1.0 + k2 * m_star * e) * ud1;
            let v2 = (1.0 + k2 * m_star * e) * ud2 - s * m_star * k2 * k2 * e * ud1 * ud1;
            assert!(
                (jet[0] - v1).abs() <= 1e-13 * v1.abs().max(1.0),
                "{what}: eq. 7"
            );
            assert!(
                (jet[1] - v2).abs() <= 1e-12 * v2.abs().max(1.0),
                "{what}: eq. 8"
            );
        }
    }
}

#[test]
fn printed_eq_8_is_wrong_on_falling_segments() {
    // The printed eq. (8) lacks the direction sign s; on a falling segment it disagrees with
    // finite differences, which is why the code does not use it.
    let (k1, k2) = (0.2, 8.0);
    let x0 = 0.37;
    let op = on_branch(
        hyst_core::InverseHysteresis::new(k1, k2).unwrap(),
        x0,
        Direction::Falling,
        0.05,
        0.0,
    );
    let m_star = k1 - op.memory().unwrap().m();
    let e = (-k2 * 0.05_f64).exp();
    let [ud1, ud2, _, _] = input_jet(x0, -1.0).derivatives();
    let printed = (1.0 + k2 * m_star * e) * ud2 - m_star * k2 * k2 * e * ud1 * ud1;
    let fd = finite_differences(|t| op.peek(input(x0, -1.0, t)).unwrap(), 2e-3);
    assert!(
        (printed - fd[1]).abs() > 1.0,
        "printed {printed} fd {}",
        fd[1]
    );
}

#[test]
fn direct_jets_match_finite_differences() {
    for direction in [Direction::Rising, Direction::Falling] {
        let s = direction.sign::<f64>();
        for (k1, k2, back, offset) in CASES {
            let x0 = -0.8;
            let op = on_branch(
                hyst_core::Hysteresis::new(k1, k2).unwrap(),
                x0,
                direction,
                back,
                offset * k1,
            );
            let (jet, fd) = jet_and_fd(&op, x0, s);
            assert_close(&format!("direct {direction:?} k1 {k1} k2 {k2}"), jet, fd, 4);
        }
    }
}

#[test]
fn jets_with_input_dependent_k2_match_finite_differences() {
    let law = AffineK2::new(9.0, -2.0, 5.0, 12.0).unwrap();
    for direction in [Direction::Rising, Direction::Falling] {
        let s = direction.sign::<f64>();
        let x0 = 0.4;
        let direct = on_branch(
            hyst_core::Hysteresis::with_k2_law(0.105, law).unwrap(),
            x0,
            direction,
            0.1,
            0.02,
        );
        let inverse = on_branch(
            hyst_core::InverseHysteresis::with_k2_law(0.105, law).unwrap(),
            x0,
            direction,
            0.1,
            0.02,
        );
        for (name, (jet, fd)) in [
            ("direct", jet_and_fd(&direct, x0, s)),
            ("inverse", jet_and_fd(&inverse, x0, s)),
        ] {
            assert_close(&format!("{name} φ {direction:?}"), jet, fd, 4);
        }
    }
}

#[test]
fn shaped_model_and_inverse_jets_match_finite_differences() {
    let psi_in = Polynomial::new([0.0, 1.0, -0.098, 0.0], -3.0, 5.0).unwrap();
    let psi_out = QuadraticExp::example2().unwrap();
    let x0 = 0.5;
    for direction in [Direction::Rising, Direction::Falling] {
        let s = direction.sign::<f64>();
        let op = on_branch(
            hyst_core::Hysteresis::new(0.06, 5.0).unwrap(),
            psi_in.apply(x0),
            direction,
            0.1,
            0.01,
        );
        let model = hyst_core::ShapedModel::new(psi_in, op, psi_out).unwrap();
        let peek = |x: f64| {
            let mut m = model;
            m.step(x)
        };
        let jet = {
            let mut m = model;
            m.try_step(input_jet(x0, s)).unwrap()
        };
        let fd = finite_differences(|t| peek(input(x0, s, t)), 2e-3);
        assert_close(&format!("model {direction:?}"), jet.derivatives(), fd, 4);

        // The inverse on the jet of the model's output gives back the input's jet.
        let mut inverse = model.inverse();
        let back = inverse.try_step(jet).unwrap();
        let want = input_jet(x0, s).derivatives();
        for (k, (a, b)) in back.derivatives().iter().zip(want.iter()).enumerate() {
            assert!(
                (a - b).abs() <= 1e-9 * b.abs().max(1.0),
                "order {}: {a} vs {b}",
                k + 1
            );
        }
        assert!((back.value() - x0).abs() < 1e-12);
    }
}

#[test]
fn jets_of_order_eight_are_consistent_with_lower_orders() {
    // Truncation is consistent: the first four derivatives of an order-8 jet equal those of an
    // order-4 jet.
    let op = on_branch(
        hyst_core::InverseHysteresis::new(0.2, 8.0).unwrap(),
        0.0,
        Direction::Falling,
        0.1,
        0.05,
    );
    let x4 = input_jet(0.0, -1.0);
    let d = x4.derivatives();
    let x8 = Jet::<f64, 8>::from_derivatives(0.0, [d[0], d[1], d[2], d[3], 0.0, 0.0, 0.0, 0.0]);
    let y4 = op.peek(x4).unwrap().derivatives();
    let y8 = op.peek(x8).unwrap().derivatives();
    for k in 0..4 {
        assert!((y4[k] - y8[k]).abs() <= 1e-12 * y4[k].abs().max(1.0));
    }
    assert!(Sample::<f64>::all_finite(&op.peek(x8).unwrap()));
}
