//! Parameter sensitivities by forward-mode duals ([`hyst_core::Dual`]) against central finite
//! differences of the plain `f64` run, on random parameters and random histories with many
//! reversals: k1, a constant or affine (input-dependent) k2, polynomial / tanh / Langevin input
//! shaping, tanh / Langevin / polynomial output shaping, the initial state, the direct model and
//! its exact inverse, and the Wright-omega form of eq. (2) (large k2). The dual's value must be
//! the plain run's, bit for bit.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use hyst_core::{
    AffineK2, AnyK2Law, AnyShaping, Direction, Dual, Error, Hysteresis, Langevin, Operator,
    Polynomial, Real, ScaledShaping, ShapedModel, Shaping, Tanh,
};
use proptest::prelude::*;

/// Number of parameters: k1, k2 (at 0), k2 slope, ψ_in parameter, ψ_out scale, ψ_out centre,
/// initial state (fraction of k1 below the line), ψ_out gain.
const P: usize = 8;

type Shaped<T> = ShapedModel<T, ScaledShaping<T>, AnyK2Law<T>, ScaledShaping<T>>;

#[derive(Clone, Copy, Debug)]
struct Case {
    input_kind: u8,
    output_kind: u8,
    affine_k2: bool,
}

/// The model for parameters `p`, generic over the number type, so the plain run and the dual run
/// are the same code.
fn build<T: Real>(case: Case, p: &[T; P], first_input: T) -> Result<Shaped<T>, Error> {
    let c = T::from_f64;
    let [k1, k2, slope, pin, scale, centre, start, gain] = *p;
    let in_shape = match case.input_kind {
        0 => AnyShaping::Identity,
        1 => AnyShaping::Polynomial(Polynomial::new(
            [c(0.0), c(1.0), pin, c(0.1)],
            c(-2.0),
            c(2.0),
        )?),
        2 => AnyShaping::Tanh(Tanh::new(c(1.0), pin)?),
        _ => AnyShaping::Langevin(Langevin::new(c(1.0), pin)?),
    };
    let input = ScaledShaping::new(c(1.0), c(0.0), in_shape, c(1.0), c(0.0))?;
    let out_shape = match case.output_kind {
        0 => AnyShaping::Tanh(Tanh::new(c(1.0), c(1.0))?),
        1 => AnyShaping::Langevin(Langevin::new(c(1.0), c(1.0))?),
        _ => AnyShaping::Polynomial(Polynomial::new(
            [c(0.0), c(1.0), c(0.05), c(0.02)],
            c(-10.0),
            c(10.0),
        )?),
    };
    let output = ScaledShaping::new(T::one() / scale, centre, out_shape, gain, c(0.0))?;
    let law = if case.affine_k2 {
        AnyK2Law::Affine(AffineK2::new(k2, slope, c(1e-3), c(1e4))?)
    } else {
        AnyK2Law::Constant { value: k2 }
    };
    let v0 = input.apply(first_input);
    let h = Hysteresis::with_k2_law(k1, law)?.with_initial_state(
        v0,
        v0 - k1 * start,
        Direction::Rising,
    )?;
    ShapedModel::new(input, h, output)
}

/// Outputs of the model (and of its exact inverse fed with `desired`) for parameters `p`.
fn run<T: Real>(
    case: Case,
    p: &[T; P],
    xs: &[f64],
    desired: &[f64],
) -> Result<(Vec<T>, Vec<T>), Error> {
    let mut model = build(case, p, T::from_f64(xs[0]))?;
    let mut inverse = model.inverse();
    let y = xs
        .iter()
        .map(|&x| model.try_step(T::from_f64(x)))
        .collect::<Result<Vec<_>, _>>()?;
    let back = desired
        .iter()
        .map(|&d| inverse.try_step(T::from_f64(d)))
        .collect::<Result<Vec<_>, _>>()?;
    Ok((y, back))
}

/// Compares the dual gradient of every output with central differences.
fn check(case: Case, p: [f64; P], xs: &[f64]) -> Result<(), TestCaseError> {
    let (plain, _) = run(case, &p, xs, &[]).unwrap();
    // The inverse is fed with the model's own outputs (inside ψ_out's range). Its start point
    // moves with the parameters while these samples do not, so a first sample equal to it would
    // be a zero step on one side of a central difference and a reversal on the other (the
    // direction rule's discontinuity, where no derivative exists): such leading samples go.
    let first = plain[0];
    let mut desired: Vec<f64> = plain.iter().copied().skip_while(|y| *y == first).collect();
    // With an affine k2 the inverse uses φ(u_d), not φ(v) (Proposition 4.3): it is not the
    // model's exact inverse, and its output may leave ψ_in's range. Then only the model.
    let (plain, plain_back) = match run(case, &p, xs, &desired) {
        Ok(r) => r,
        Err(_) => {
            desired.clear();
            run(case, &p, xs, &desired).unwrap()
        }
    };
    let seeded: [Dual<f64, P>; P] = core::array::from_fn(|j| Dual::variable(p[j], j));
    let (dual, dual_back) = run(case, &seeded, xs, &desired).unwrap();
    for (d, f) in dual
        .iter()
        .chain(&dual_back)
        .zip(plain.iter().chain(&plain_back))
    {
        prop_assert_eq!(
            d.value().to_bits(),
            f.to_bits(),
            "value {} vs {}",
            d.value(),
            f
        );
    }
    for j in 0..P {
        let gradient: Vec<f64> = dual
            .iter()
            .chain(&dual_back)
            .map(|d| d.gradient()[j])
            .collect();
        // Central differences with a relative step of 1e-6, then down to 1e-10 where a sharp
        // transition (k2 M* in the thousands) makes the larger step nonlinear, or where the
        // inverse's first step is shorter than the move of its start point under the larger
        // step (k2 = 18400: a step of 8.6e-10 from a start that 1e-8 · k1 moves by 1.5e-9, a
        // reversal on one side): the dual must match one of them at every output.
        let mut pending: Vec<usize> = (0..gradient.len()).collect();
        let mut worst = String::new();
        for step in [1e-6, 1e-7, 1e-8, 1e-9, 1e-10] {
            let h = step * p[j].abs().max(1e-3);
            let (mut up, mut down) = (p, p);
            up[j] += h;
            down[j] -= h;
            let runs =
                run(case, &up, xs, &desired).and_then(|u| Ok((u, run(case, &down, xs, &desired)?)));
            // A step that takes a desired output out of the perturbed inverse's range.
            prop_assume!(runs.is_ok());
            let ((yu, bu), (yd, bd)) = runs.unwrap();
            let ups: Vec<f64> = yu.into_iter().chain(bu).collect();
            let downs: Vec<f64> = yd.into_iter().chain(bd).collect();
            pending.retain(|&k| {
                let fd = (ups[k] - downs[k]) / (2.0 * h);
                let ok = (gradient[k] - fd).abs() <= 2e-5 * (1.0 + fd.abs());
                if !ok {
                    worst = format!(
                        "output {k}: dual {} vs central difference {fd}",
                        gradient[k]
                    );
                }
                !ok
            });
        }
        prop_assert!(
            pending.is_empty(),
            "{:?} parameter {} {} (p = {:?})",
            case,
            j,
            worst,
            p
        );
    }
    Ok(())
}

/// A random history in [−1.5, 1.5] with many reversals (random walk with random step sizes).
fn history() -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(-0.4f64..0.4, 10..40).prop_map(|steps| {
        let mut x = 0.0_f64;
        steps
            .iter()
            .map(|s| {
                x = (x + s).clamp(-1.5, 1.5);
                x
            })
            .collect()
    })
}

fn parameters() -> impl Strategy<Value = [f64; P]> {
    (
        (0.05f64..0.4, 1.0f64..20.0, -0.3f64..0.3, 0.0f64..1.0),
        (0.5f64..3.0, -0.5f64..0.5, 0.0f64..1.0, 0.5f64..5.0),
    )
        .prop_map(|((k1, k2, slope, pin), (scale, centre, start, gain))| {
            // slope as a fraction of k2 (the affine law stays far from its clamps);
            // pin mapped into the valid range of the chosen ψ_in by `for_input`.
            [k1, k2, slope * k2, pin, scale, centre, start, gain]
        })
}

/// The ψ_in parameter in the valid range of its kind (polynomial p2 ∈ [−0.2, 0.2], tanh scale
/// ∈ [0.5, 2], Langevin scale ∈ [0.2, 1]).
fn for_input(mut p: [f64; P], kind: u8) -> [f64; P] {
    let t = p[3];
    p[3] = match kind {
        1 => -0.2 + 0.4 * t,
        2 => 0.5 + 1.5 * t,
        3 => 0.2 + 0.8 * t,
        _ => t,
    };
    p
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn duals_equal_central_differences(
        p in parameters(),
        xs in history(),
        input_kind in 0u8..4,
        output_kind in 0u8..3,
        affine_k2 in any::<bool>(),
    ) {
        let case = Case { input_kind, output_kind, affine_k2 };
        check(case, for_input(p, input_kind), &xs)?;
    }

    /// k2 M* beyond 700: eq. (2) goes through the Wright omega function in the log domain,
    /// whose gradient comes from the implicit-function theorem.
    #[test]
    fn duals_through_the_log_domain_form(k2 in 4000.0f64..20000.0, xs in history()) {
        let case = Case { input_kind: 0, output_kind: 2, affine_k2: false };
        let p = [0.3, k2, 0.0, 0.0, 1.0, 0.0, 0.5, 1.0];
        check(case, p, &xs)?;
    }
}

/// The doc example's claim on a fixed case, with the direct operator alone: ∂u/∂k1 and ∂u/∂k2
/// after three reversals.
#[test]
fn direct_operator_gradient_after_reversals() -> Result<(), Error> {
    let xs = [0.0, 0.8, 1.0, -0.5, 0.2, -0.1, 0.6];
    let plain = |k1: f64, k2: f64| -> Result<f64, Error> {
        let mut h = Hysteresis::new(k1, k2)?;
        let mut y = 0.0;
        for &x in &xs {
            y = h.try_step(x)?;
        }
        Ok(y)
    };
    let mut h = Hysteresis::new(Dual::<f64, 2>::variable(0.2, 0), Dual::variable(6.0, 1))?;
    let mut y = Dual::constant(0.0);
    for &x in &xs {
        y = h.try_step(Dual::constant(x))?;
    }
    let e = 1e-6;
    let d1 = (plain(0.2 + e, 6.0)? - plain(0.2 - e, 6.0)?) / (2.0 * e);
    let d2 = (plain(0.2, 6.0 + e)? - plain(0.2, 6.0 - e)?) / (2.0 * e);
    let [g1, g2] = y.gradient();
    assert!((g1 - d1).abs() < 1e-8, "{g1} {d1}");
    assert!((g2 - d2).abs() < 1e-8, "{g2} {d2}");
    assert_eq!(y.value(), plain(0.2, 6.0)?);
    Ok(())
}
