//! Lemma 5.1: the compensator turns b / (a_n sⁿ + … + a_1 s + 1) followed by hysteresis into n
//! pure integrators. Checked (1) algebraically, sample by sample, to round-off; (2) by
//! simulating the plant with RK4 between samples, with the exact model as the plant's
//! hysteresis (error at the integration error) and with family members (error within Δa).

use hyst_core::family::{delta_a, Family};
use hyst_core::Operator;
use hyst_core::{
    Affine, Compensator, Error, Hysteresis, Identity, Jet, K2Law, QuadraticExp, ShapedModel,
    Shaping,
};
use hyst_test_support::plant::LinearPlant;

/// Denominators (τ s + 1)ⁿ written as [a_1, …, a_n], for n = 1..4.
const A1: [f64; 1] = [0.1];
const A2: [f64; 2] = [0.9, 1.0]; // Example 3: s² + 0.9 s + 1
const A3: [f64; 3] = [1.5, 0.75, 0.125];
const A4: [f64; 4] = [2.0, 1.5, 0.5, 0.0625];

/// A smooth new input with reversals of v at several amplitudes.
fn u_new(t: f64) -> f64 {
    (1.3 * t).sin() + 0.6 * (3.1 * t).cos() - 0.2
}

/// Simulates the compensated plant for `samples` steps of `dt`; the plant's hysteresis is
/// `truth` (a closure on x1). Returns the worst |truth(x1) − v| and the worst |x1 − x_target|.
#[allow(clippy::too_many_arguments)]
fn simulate_from<const N: usize, I, O>(
    comp: &mut Compensator<f64, N, I, hyst_core::ConstantK2<f64>, O>,
    a: &[f64; N],
    b: f64,
    mut truth: impl FnMut(f64) -> f64,
    dt: f64,
    samples: usize,
    t_start: f64,
    x0: [f64; N],
    input: impl Fn(f64) -> f64,
) -> Result<(f64, f64), Error>
where
    I: Shaping<f64> + Clone,
    O: Shaping<f64> + Clone,
{
    let mut x = x0;
    let mut worst_out = 0.0_f64;
    let mut worst_state = 0.0_f64;
    for k in 0..samples {
        let t = t_start + k as f64 * dt;
        let un = input(t + 0.5 * dt);
        // Integrate over [t, t + dt], split at a turning point of v (the command jumps there).
        let split = comp.turning_point(un, dt);
        let mut x_next = x;
        let mut t0 = 0.0;
        for t1 in [split.unwrap_or(dt), dt] {
            if t1 > t0 {
                // The end of the first piece is the left limit at the turning point.
                let sub = 1;
                for j in 0..sub {
                    let ta = t0 + (t1 - t0) * j as f64 / sub as f64;
                    let tb = t0 + (t1 - t0) * (j + 1) as f64 / sub as f64;
                    let end = if Some(t1) == split && j + 1 == sub {
                        tb - 1e-9 * dt
                    } else {
                        tb
                    };
                    x_next = LinearPlant { a: *a, b }.rk4(
                        &x_next,
                        tb - ta,
                        [
                            comp.peek(un, ta)?,
                            comp.peek(un, 0.5 * (ta + tb))?,
                            comp.peek(un, end)?,
                        ],
                    );
                }
                t0 = t1;
            }
        }
        // Sample k: the command and the reference at time t.
        let _ = comp.try_step(un, dt)?;
        let v = comp.last_reference();
        let target = comp.last_target().value();
        worst_out = worst_out.max((truth(x[0]) - v).abs());
        worst_state = worst_state.max((x[0] - target).abs());
        x = x_next;
    }
    Ok((worst_out, worst_state))
}

/// [`simulate_from`] from rest at v = 0 with the input [`u_new`].
fn simulate<const N: usize, I, O>(
    comp: &mut Compensator<f64, N, I, hyst_core::ConstantK2<f64>, O>,
    a: &[f64; N],
    b: f64,
    truth: impl FnMut(f64) -> f64,
    dt: f64,
    samples: usize,
) -> Result<(f64, f64), Error>
where
    I: Shaping<f64> + Clone,
    O: Shaping<f64> + Clone,
{
    simulate_from(comp, a, b, truth, dt, samples, 0.0, [0.0; N], u_new)
}

/// Algebraic check: along the compensator's own trajectory, the target x = H⁻¹[v] satisfies
/// the plant equation with the command (b u = x + Σ a_i x⁽ⁱ⁾) and H[x] = v, to round-off.
fn algebraic<const N: usize>(a: [f64; N]) -> Result<f64, Error> {
    let model = ShapedModel::new(
        Affine::new(0.8, 0.1)?,
        Hysteresis::new(0.2_f64, 8.0)?,
        Affine::new(1.5, -0.05)?,
    )?;
    let b = 2.5;
    let mut comp = Compensator::from_shaped_model(&model, b, a)?;
    let mut worst = 0.0_f64;
    for k in 0..20_000 {
        let t = k as f64 * 1e-3;
        // The direct model with the compensator's memory mirrored (Proposition 4.1).
        let mirror = comp.inverse().operator().direct();
        let u = comp.try_step(u_new(t), 1e-3)?;
        let x = comp.last_target();
        let d = x.derivatives();
        let mut rhs = x.value();
        for i in 0..N {
            rhs += a[i] * d[i];
        }
        worst = worst.max((b * u - rhs).abs() / (1.0 + rhs.abs()));
        if k > 0 {
            let h = mirror.peek(model.input_shaping().apply(x.value()))?;
            let out = model.output_shaping().apply(h);
            worst = worst.max((out - comp.last_reference()).abs());
        }
    }
    Ok(worst)
}

#[test]
fn compensated_plant_is_n_integrators_to_round_off() -> Result<(), Error> {
    for worst in [
        algebraic(A1)?,
        algebraic(A2)?,
        algebraic(A3)?,
        algebraic(A4)?,
    ] {
        assert!(worst < 1e-11, "worst residual {worst}");
    }
    Ok(())
}

/// With the exact model as the plant's hysteresis, the simulated error is the integration error
/// of the plant (RK4 between samples, split at turning points of v; the truth sees x1 only at
/// the samples): small, and shrinking with the step.
///
/// For n ≥ 3 the plant's state includes ẍ1, which is continuous, while ẍ = d²/dt² H⁻¹[v] jumps
/// at a reversal unless v̈ = 0 there (Proposition 2.7: second and higher derivatives are
/// discontinuous): every reversal then starts a decaying transient, and Lemma 5.1's "after the
/// transients" applies between reversals. With reversals that are flat up to order n − 1
/// (v̇ = cos³), the compensation is exact again, which is what is checked for n = 3, 4; the
/// size of the transient with ordinary reversals is asserted to be large, as a record.
#[test]
fn simulated_plant_with_exact_model_tracks_v() -> Result<(), Error> {
    fn run<const N: usize>(a: [f64; N], dt: f64, flat: bool) -> Result<f64, Error> {
        let model = ShapedModel::new(Identity, Hysteresis::new(0.2_f64, 8.0)?, Identity)?;
        let mut truth = model;
        let samples = (20.0 / dt) as usize;
        let (out, state) = if flat {
            // v = 0.75 sin t + sin(3t)/12, so v̇ = cos³ t: reversals with v̈ = v⃛ = 0. Start at
            // the maximum t = π/2 at rest.
            let t0 = core::f64::consts::FRAC_PI_2;
            let v0: f64 = 0.75 * t0.sin() + (3.0 * t0).sin() / 12.0;
            let mut comp = Compensator::from_shaped_model(&model, 1.0, a)?
                .with_state(core::array::from_fn(|i| if i == 0 { v0 } else { 0.0 }))?;
            let _ = truth.try_step(v0)?;
            let x0 = core::array::from_fn(|i| if i == 0 { v0 } else { 0.0 });
            let input = |t: f64| {
                let p = N as f64 * core::f64::consts::FRAC_PI_2;
                0.75 * (t + p).sin() + 3f64.powi(N as i32) / 12.0 * (3.0 * t + p).sin()
            };
            simulate_from(
                &mut comp,
                &a,
                1.0,
                |x| truth.step(x),
                dt,
                samples,
                t0,
                x0,
                input,
            )?
        } else {
            let mut comp = Compensator::from_shaped_model(&model, 1.0, a)?;
            simulate(&mut comp, &a, 1.0, |x| truth.step(x), dt, samples)?
        };
        eprintln!("n = {N}, dt = {dt}, flat reversals {flat}: worst |x2 − v| {out:.3e}, |x1 − H⁻¹[v]| {state:.3e}");
        Ok(out.max(state))
    }
    let coarse = [
        run(A1, 1e-3, false)?,
        run(A2, 1e-3, false)?,
        run(A3, 1e-3, true)?,
        run(A4, 1e-3, true)?,
    ];
    let fine = [
        run(A1, 2.5e-4, false)?,
        run(A2, 2.5e-4, false)?,
        run(A3, 2.5e-4, true)?,
        run(A4, 2.5e-4, true)?,
    ];
    // Measured when written: n = 1: 4.3e-6 -> 3.2e-7; n = 2: 2.6e-4 -> 4.0e-5; n = 3 (flat):
    // 1.8e-4 -> 2.8e-5; n = 4 (flat): 9.4e-3 -> 3.6e-3 (dt = 1 ms -> 0.25 ms).
    let limits = [1e-5, 5e-4, 5e-4, 2e-2];
    for (n, ((c, f), limit)) in coarse.iter().zip(fine.iter()).zip(limits).enumerate() {
        assert!(*c < limit, "n = {}: {c}", n + 1);
        let factor = if n < 3 { 3.0 } else { 2.0 };
        assert!(*f < c / factor, "n = {}: no convergence {c} -> {f}", n + 1);
    }
    let transient = run(A3, 1e-3, false)?;
    assert!(
        transient > 1e-2,
        "n = 3 with ordinary reversals: {transient}"
    );
    Ok(())
}

#[test]
fn family_members_stay_within_delta_a() -> Result<(), Error> {
    let (k1, dk1, k2, dk2) = (0.06, 0.005, 5.0, 2.5); // Example 2's family
    let bound = delta_a(k1, dk1, k2, dk2)?.delta_a;
    let family = Family::new(k1, dk1, k2, dk2)?;
    let psi = QuadraticExp::<f64>::example2()?;
    let model = ShapedModel::new(Identity, Hysteresis::new(k1, k2)?, psi)?;
    let mut seen = 0.0_f64;
    for &(pa, pb) in &[
        (-1.0, -1.0),
        (-1.0, 1.0),
        (1.0, -1.0),
        (1.0, 1.0),
        (0.4, -0.6),
    ] {
        // n = 1 (Example 2's RL circuit: b = 1/R, a_1 = L/R).
        let mut comp = Compensator::from_shaped_model(&model, 1.0, [0.1])?;
        let mut member = family.member(pa, pb)?;
        // The error at the operator level: H̄[x1] − ψ⁻¹(v) (Δb of eq. 15).
        let truth = |x: f64| -> f64 {
            let h = member.step(x);
            psi.invert(psi.apply(h)).unwrap_or(f64::NAN)
        };
        let mut comp_inner = comp;
        let (worst_psi_inv, _) = {
            // Compare against ψ⁻¹(v) rather than v.
            let mut worst = 0.0_f64;
            let mut x = [0.0_f64; 1];
            let mut truth = truth;
            let dt = 1e-3;
            for k in 0..15_000 {
                let t = k as f64 * dt;
                let un = 0.8 * u_new(t);
                let (u0, uh, u1) = (
                    comp_inner.peek(un, 0.0)?,
                    comp_inner.peek(un, 0.5 * dt)?,
                    comp_inner.peek(un, dt)?,
                );
                let _ = comp_inner.try_step(un, dt)?;
                let v = comp_inner.last_reference();
                worst = worst.max((truth(x[0]) - psi.invert(v)?).abs());
                x = LinearPlant { a: [0.1], b: 1.0 }.rk4(&x, dt, [u0, uh, u1]);
            }
            (worst, ())
        };
        comp = comp_inner;
        let _ = comp.state();
        assert!(
            worst_psi_inv <= bound + 1e-6,
            "member ({pa}, {pb}): {worst_psi_inv} > {bound}"
        );
        seen = seen.max(worst_psi_inv);
    }
    eprintln!("Example 2 family: worst compensation error {seen:.5} (bound {bound:.5})");
    assert!(
        seen > 0.5 * bound,
        "the test never approaches the bound: {seen}"
    );

    // n = 2 (Example 3's mass-spring-damper), unshaped family around H(0.2, 8).
    let fam3 = Family::new(0.2, 0.02, 8.0, 3.0)?;
    let bound3 = fam3.bound().delta_a;
    let model3 = ShapedModel::new(Identity, Hysteresis::new(0.2_f64, 8.0)?, Identity)?;
    for &(pa, pb) in &[(-1.0, -1.0), (1.0, 1.0), (1.0, -1.0), (-1.0, 1.0)] {
        let mut comp = Compensator::from_shaped_model(&model3, 1.0, A2)?;
        let mut member = fam3.member(pa, pb)?;
        let (worst, _) = simulate(&mut comp, &A2, 1.0, |x| member.step(x), 1e-3, 20_000)?;
        assert!(
            worst <= bound3 + 1e-6,
            "n = 2 member ({pa}, {pb}): {worst} > {bound3}"
        );
    }
    Ok(())
}

/// Reference mode equals integrator mode when no turning point falls inside a sample (n = 1),
/// and stays close otherwise (n = 2: the integrator mode places the reversal at the extremum).
#[test]
fn reference_mode_matches_integrator_mode() -> Result<(), Error> {
    let model = ShapedModel::new(Identity, Hysteresis::new(0.2_f64, 8.0)?, Identity)?;
    let mut chain = Compensator::from_shaped_model(&model, 1.0, A1)?;
    let mut direct = Compensator::from_shaped_model(&model, 1.0, A1)?;
    for k in 0..5_000 {
        let un = u_new(k as f64 * 1e-3);
        let [v] = chain.state();
        let u_chain = chain.try_step(un, 1e-3)?;
        let u_ref = direct.track(Jet::from_derivatives(v, [un]))?;
        assert!((u_chain - u_ref).abs() <= 1e-12 * (1.0 + u_ref.abs()));
    }
    let mut chain = Compensator::from_shaped_model(&model, 1.0, A2)?;
    let mut direct = Compensator::from_shaped_model(&model, 1.0, A2)?;
    let mut worst = 0.0_f64;
    for k in 0..5_000 {
        let un = u_new(k as f64 * 1e-3);
        let [v, v1] = chain.state();
        let u_chain = chain.try_step(un, 1e-3)?;
        let u_ref = direct.track(Jet::from_derivatives(v, [v1, un]))?;
        worst = worst.max((u_chain - u_ref).abs());
    }
    assert!(worst < 1e-2, "{worst}");
    Ok(())
}

/// k2 = φ(input): the direct operator uses φ(v), the inverse φ(ud), so the pair is inverse only
/// up to Δk2* = sup|φ'| k1 (Proposition 4.3); the error stays within the resulting Δa. In f32.
#[test]
fn input_dependent_k2_and_f32_work() -> Result<(), Error> {
    let law = hyst_core::AffineK2::new(9.0_f32, -2.0, 5.0, 12.0)?;
    assert!(law.k2(0.0_f32) == 9.0);
    let model = ShapedModel::new(Identity, Hysteresis::with_k2_law(0.105_f32, law)?, Identity)?;
    let bound = Family::with_k2_law(0.105_f32, 0.0, law, 0.0)?
        .bound_on(-0.2, 1.0, true, 33)?
        .delta_a;
    let mut comp = Compensator::from_shaped_model(&model, 1.0, [0.1_f32, 0.01])?;
    let mut direct = model;
    let mut worst = 0.0_f32;
    for k in 0..4_000 {
        let t = k as f32 * 1e-3;
        let _ = comp.try_step(3.0 * (3.0 * t).sin(), 1e-3)?;
        let out = direct.try_step(comp.last_target().value())?;
        worst = worst.max((out - comp.last_reference()).abs());
    }
    eprintln!("k2 = φ(v), f32: worst |H[H⁻¹[v]] − v| = {worst:.5}, bound {bound:.5}");
    assert!(worst <= bound + 1e-5, "{worst} > {bound}");
    assert!(
        worst > 1e-4,
        "the mismatch of Proposition 4.3 should show: {worst}"
    );
    Ok(())
}
