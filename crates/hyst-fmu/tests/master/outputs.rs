//! Stepping an instance: its outputs against the core and the evaluator bit for bit,
//! independent instances, parameters and modes, refused samples.

use super::*;
use crate::harness::*;

#[test]
fn operator_outputs_equal_the_core_bit_for_bit() {
    let xs: Vec<f64> = (0..3000).map(signal).collect();
    for inverse in [false, true] {
        let dir = operator_resources(inverse, 0.2, 8.0);
        let fmu = Fmu::started(dir.path());
        let mut reference: Box<dyn FnMut(f64) -> f64> = if inverse {
            let mut op = InverseHysteresis::new(0.2, 8.0).unwrap();
            Box::new(move |x| op.try_step(x).unwrap())
        } else {
            let mut op = Hysteresis::new(0.2, 8.0).unwrap();
            Box::new(move |x| op.try_step(x).unwrap())
        };
        let peek = |committed: &[f64], x: f64| {
            let mut all = committed.to_vec();
            all.push(x);
            let ys = if inverse {
                core_run(InverseHysteresis::new(0.2, 8.0).unwrap(), &all)
            } else {
                core_run(Hysteresis::new(0.2, 8.0).unwrap(), &all)
            };
            *ys.last().unwrap()
        };
        for (k, x) in xs.iter().enumerate() {
            if k % 499 == 7 {
                // A value set and read but replaced before fmi2DoStep is never committed.
                assert_eq!(fmu.set(VR_X, x + 0.3), OK);
                assert_eq!(fmu.y().to_bits(), peek(&xs[..k], x + 0.3).to_bits());
            }
            let y = fmu.step(*x);
            assert_eq!(
                y.to_bits(),
                reference(*x).to_bits(),
                "inverse {inverse}, sample {k}"
            );
        }
        assert!(fmu.errors().is_empty());
        let mut t = 0.0;
        assert_eq!(
            unsafe { fmi2GetRealStatus(fmu.c, fmi2LastSuccessfulTime, &mut t) },
            OK
        );
        assert_eq!(t, fmu.time.get());
        assert_eq!(fmu.get(VR_K1), Ok(0.2));
        assert_eq!(fmu.get(VR_K2), Ok(8.0));
        assert_eq!(fmu.get(VR_X), Ok(xs[2999]));
    }
}

#[test]
fn model_outputs_equal_the_evaluator_bit_for_bit() {
    let xs: Vec<f64> = (0..1500).map(|k| signal(k + 11)).collect();
    for (name, file) in [("smooth", fitted_model()), ("pi", pi_model())] {
        for inverse in [false, true] {
            let input: Vec<f64> = if inverse {
                xs.iter().map(|x| 3.0 * x + 1.0).collect()
            } else {
                xs.clone()
            };
            let dir = model_resources(&file, inverse);
            let fmu = Fmu::started(dir.path());
            // Before the first fmi2DoStep, y comes from an evaluator started at the current x.
            assert_eq!(fmu.set(VR_X, input[5]), OK);
            assert_eq!(
                fmu.y().to_bits(),
                evaluator_run(&file, inverse, &input[5..6])[0].to_bits()
            );
            let ys = fmu.run(&input);
            assert_eq!(
                bits(&ys),
                bits(&evaluator_run(&file, inverse, &input)),
                "{name} {inverse}"
            );
            // A model has no parameters k1, k2.
            assert_eq!(fmu.get(VR_K1), Err(ERROR));
            fmu.expect_error(&["value reference 2"]);
            assert_eq!(fmu.set(VR_K2, 1.0), ERROR);
            fmu.expect_error(&["value reference 3"]);
        }
    }
}

#[test]
fn two_instances_are_independent() {
    let dir_a = operator_resources(false, 0.2, 8.0);
    let dir_b = operator_resources(true, 0.5, 3.0);
    let a = Fmu::started(dir_a.path());
    let b = Fmu::started(dir_b.path());
    let file = pi_model();
    let dir_c = model_resources(&file, false);
    let c = Fmu::started(dir_c.path());
    let xa: Vec<f64> = (0..1000).map(signal).collect();
    let xb: Vec<f64> = (0..1000).map(|k| -2.0 * signal(k + 300)).collect();
    let xc: Vec<f64> = (0..1000).map(|k| signal(2 * k)).collect();
    let (mut ya, mut yb, mut yc) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..1000 {
        ya.push(a.step(xa[k]));
        yb.push(b.step(xb[k]));
        yc.push(c.step(xc[k]));
    }
    assert_eq!(
        bits(&ya),
        bits(&core_run(Hysteresis::new(0.2, 8.0).unwrap(), &xa))
    );
    assert_eq!(
        bits(&yb),
        bits(&core_run(InverseHysteresis::new(0.5, 3.0).unwrap(), &xb))
    );
    assert_eq!(bits(&yc), bits(&evaluator_run(&file, false, &xc)));
}

// ------------------------------------------------------------------------------------------
// Parameters and modes.

#[test]
fn parameters_are_set_before_initialisation_only() {
    let dir = operator_resources(false, 0.2, 8.0);
    let fmu = Fmu::instantiate(dir.path());
    let xs: Vec<f64> = (0..800).map(signal).collect();
    unsafe {
        assert_eq!(fmu.set(VR_K1, 0.3), OK); // Instantiated
        assert_eq!(fmi2EnterInitializationMode(fmu.c), OK);
        assert_eq!(fmu.set(VR_K2, 5.0), OK); // InitializationMode
        assert_eq!(fmu.set(VR_X, xs[0]), OK);
        // y is an initial unknown: computed with the current k1, k2 and x.
        assert_eq!(
            fmu.y().to_bits(),
            Hysteresis::new(0.3, 5.0)
                .unwrap()
                .try_step(xs[0])
                .unwrap()
                .to_bits()
        );
        assert_eq!(fmi2ExitInitializationMode(fmu.c), OK);
    }
    let ys = fmu.run(&xs[..400]);
    let reference = core_run(Hysteresis::new(0.3, 5.0).unwrap(), &xs);
    assert_eq!(bits(&ys), bits(&reference[..400]));
    // After initialisation k1 and k2 are fixed: refused, named, nothing changes.
    assert_eq!(fmu.set(VR_K1, 0.25), ERROR);
    fmu.expect_error(&["fmi2SetReal", "k1 = 0.25", "fixed parameter"]);
    assert_eq!(fmu.get(VR_K1), Ok(0.3));
    // All values or none: x is not set when k2 is refused in the same call.
    let (vrs, values) = ([VR_X, VR_K2], [9.0, 1.0]);
    assert_eq!(
        unsafe { fmi2SetReal(fmu.c, vrs.as_ptr(), 2, values.as_ptr()) },
        ERROR
    );
    fmu.expect_error(&["k2 = 1"]);
    assert_eq!(fmu.get(VR_X), Ok(xs[399]));
    assert_eq!(fmu.get(VR_K2), Ok(5.0));
    // y is an output.
    assert_eq!(fmu.set(VR_Y, 1.0), ERROR);
    fmu.expect_error(&["output"]);
    assert_eq!(bits(&fmu.run(&xs[400..])), bits(&reference[400..]));
    // Several values in one call, y once.
    let vrs = [VR_Y, VR_X, VR_K1, VR_K2, VR_Y];
    let mut out = [0.0; 5];
    assert_eq!(
        unsafe { fmi2GetReal(fmu.c, vrs.as_ptr(), 5, out.as_mut_ptr()) },
        OK
    );
    assert_eq!(out, [reference[799], xs[799], 0.3, 5.0, reference[799]]);
    unsafe {
        assert_eq!(fmi2Terminate(fmu.c), OK);
        assert_eq!(fmu.set(VR_K1, 0.3), ERROR); // Terminated: nothing may be set
        fmu.expect_error(&["fmi2SetReal", "Terminated"]);
        assert_eq!(fmu.y(), reference[799]); // but values may be read
    }
}

#[test]
fn invalid_parameters_fail_initialisation_naming_them() {
    let dir = operator_resources(true, 0.2, 8.0);
    let fmu = Fmu::instantiate(dir.path());
    unsafe {
        assert_eq!(fmi2EnterInitializationMode(fmu.c), OK);
        assert_eq!(fmu.set(VR_K1, -1.0), OK);
        assert_eq!(fmu.get(VR_Y), Err(ERROR));
        fmu.expect_error(&["fmi2GetReal", "k1", "-1"]);
        assert_eq!(fmi2ExitInitializationMode(fmu.c), ERROR);
        fmu.expect_error(&["fmi2ExitInitializationMode", "k1 = -1"]);
        assert_eq!(fmu.do_step(), ERROR); // still in InitializationMode
        fmu.expect_error(&["fmi2DoStep", "InitializationMode"]);
        assert_eq!(fmu.set(VR_K2, f64::NAN), OK);
        assert_eq!(fmu.set(VR_K1, 0.4), OK);
        assert_eq!(fmi2ExitInitializationMode(fmu.c), ERROR);
        fmu.expect_error(&["k2 = NaN"]);
        assert_eq!(fmu.set(VR_K2, 2.0), OK);
        assert_eq!(fmi2ExitInitializationMode(fmu.c), OK);
    }
    let xs: Vec<f64> = (0..500).map(signal).collect();
    assert_eq!(
        bits(&fmu.run(&xs)),
        bits(&core_run(InverseHysteresis::new(0.4, 2.0).unwrap(), &xs))
    );
}

#[test]
fn calls_in_the_wrong_mode_are_refused_and_reset_starts_over() {
    let dir = operator_resources(false, 0.2, 8.0);
    let fmu = Fmu::instantiate(dir.path());
    let xs: Vec<f64> = (0..600).map(signal).collect();
    unsafe {
        assert_eq!(fmu.get(VR_Y), Err(ERROR)); // Instantiated: y is not yet calculated
        fmu.expect_error(&["fmi2GetReal", "Instantiated"]);
        assert_eq!(fmu.do_step(), ERROR);
        fmu.expect_error(&["fmi2DoStep", "Instantiated"]);
        assert_eq!(fmi2ExitInitializationMode(fmu.c), ERROR);
        assert_eq!(fmi2Terminate(fmu.c), ERROR);
        fmu.errors();
        assert_eq!(fmu.set(VR_K1, 0.7), OK);
        assert_eq!(fmi2EnterInitializationMode(fmu.c), OK);
        assert_eq!(fmi2EnterInitializationMode(fmu.c), ERROR);
        assert_eq!(fmi2SetupExperiment(fmu.c, 0, 0.0, 0.0, 0, 0.0), ERROR);
        assert_eq!(fmi2Terminate(fmu.c), ERROR);
        assert_eq!(fmu.errors().len(), 3);
        assert_eq!(fmi2ExitInitializationMode(fmu.c), OK);
        fmu.run(&xs[..100]);
        let mut status = fmi2Status::fmi2OK;
        assert_eq!(fmi2GetStatus(fmu.c, fmi2DoStepStatus, &mut status), DISCARD);
        let mut terminated = fmi2True;
        assert_eq!(
            fmi2GetBooleanStatus(fmu.c, fmi2Terminated, &mut terminated),
            OK
        );
        assert_eq!(terminated, fmi2False);
        assert_eq!(fmi2GetRealStatus(fmu.c, 17, &mut 0.0), ERROR);
        assert_eq!(fmi2Terminate(fmu.c), OK);
        assert_eq!(fmu.do_step(), ERROR);
        assert_eq!(fmu.set(VR_X, 1.0), ERROR);
        assert_eq!(fmi2Terminate(fmu.c), ERROR);
        fmu.errors();
        // Reset: Instantiated again, k1 back to its start value, no history.
        assert_eq!(fmi2Reset(fmu.c), OK);
        assert_eq!(fmu.get(VR_Y), Err(ERROR));
        fmu.errors();
        assert_eq!(fmi2EnterInitializationMode(fmu.c), OK);
        assert_eq!(fmu.get(VR_K1), Ok(0.2));
        assert_eq!(fmu.get(VR_X), Ok(0.0));
        assert_eq!(fmi2ExitInitializationMode(fmu.c), OK);
    }
    assert_eq!(
        bits(&fmu.run(&xs)),
        bits(&core_run(Hysteresis::new(0.2, 8.0).unwrap(), &xs))
    );
}

// ------------------------------------------------------------------------------------------
// Refused samples.

#[test]
fn a_non_finite_input_is_refused_and_changes_nothing() {
    let dir = operator_resources(false, 0.2, 8.0);
    let fmu = Fmu::started(dir.path());
    let xs: Vec<f64> = (0..900).map(signal).collect();
    let reference = core_run(Hysteresis::new(0.2, 8.0).unwrap(), &xs);
    let mut ys = fmu.run(&xs[..450]);
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert_eq!(fmu.set(VR_X, bad), OK);
        assert_eq!(fmu.get(VR_Y), Err(ERROR));
        fmu.expect_error(&["fmi2GetReal", "y", "not finite"]);
        assert_eq!(fmu.do_step(), ERROR);
        fmu.expect_error(&["fmi2DoStep", "not finite"]);
    }
    ys.extend(fmu.run(&xs[450..]));
    assert_eq!(bits(&ys), bits(&reference));
    // A model, before and after its first step.
    let file = pi_model();
    let dir = model_resources(&file, false);
    let fmu = Fmu::started(dir.path());
    assert_eq!(fmu.set(VR_X, f64::NAN), OK);
    assert_eq!(fmu.get(VR_Y), Err(ERROR));
    assert_eq!(fmu.do_step(), ERROR);
    assert_eq!(fmu.errors().len(), 2);
    assert_eq!(bits(&fmu.run(&xs)), bits(&evaluator_run(&file, false, &xs)));
}

#[test]
fn a_desired_output_beyond_saturation_is_refused_and_changes_nothing() {
    let file = saturating_model();
    let dir = model_resources(&file, true);
    let fmu = Fmu::started(dir.path());
    let desired: Vec<f64> = (0..700).map(|k| 1.5 * signal(k) / 1.3).collect();
    assert!(desired.iter().all(|y| y.abs() < 2.0));
    // Refused at the first step: the evaluator cannot start at 3 (tanh's range is (-2, 2)).
    assert_eq!(fmu.set(VR_X, 3.0), OK);
    assert_eq!(fmu.get(VR_Y), Err(ERROR));
    fmu.expect_error(&["fmi2GetReal", "x = 3"]);
    assert_eq!(fmu.do_step(), ERROR);
    fmu.expect_error(&["fmi2DoStep", "x = 3"]);
    let mut ys = fmu.run(&desired[..300]);
    assert_eq!(fmu.set(VR_X, -2.5), OK);
    assert_eq!(fmu.do_step(), ERROR);
    fmu.expect_error(&["fmi2DoStep", "-2.5", "tanh"]);
    ys.extend(fmu.run(&desired[300..]));
    assert_eq!(bits(&ys), bits(&evaluator_run(&file, true, &desired)));
}

#[test]
fn saturate_clamps_desired_outputs_and_warns_when_saturation_starts() {
    let file = saturating_model();
    let limits = file.saturation().unwrap().limits;
    let dir = tempfile::tempdir().unwrap();
    write_config(
        dir.path(),
        &format!("{}saturate = true\n", model_config(true)),
    );
    std::fs::write(dir.path().join("model.toml"), file.to_toml().unwrap()).unwrap();
    let fmu = Fmu::started(dir.path());
    // Starts beyond the range (tanh's is (-2, 2)): clamped, with a warning, and run.
    let desired: Vec<f64> = [3.0, 2.5, 1.0, 0.2]
        .into_iter()
        .chain((0..300).map(|k| 1.5 * signal(k) / 1.3))
        .chain([-2.0, -7.0, -1.5, 1.9, 2.0])
        .collect();
    let mut ys = Vec::new();
    let mut warnings = Vec::new();
    for (k, x) in desired.iter().enumerate() {
        assert_eq!(fmu.set(VR_X, *x), OK);
        let y = fmu.y();
        let status = fmu.do_step();
        let clamped = x.clamp(limits.0, limits.1) != *x;
        let entering =
            clamped && (k == 0 || desired[k - 1].clamp(limits.0, limits.1) == desired[k - 1]);
        assert_eq!(status, if entering { WARNING } else { OK }, "x = {x}");
        if status == WARNING {
            fmu.time.set(fmu.time.get() + 0.01);
        }
        assert_eq!(fmu.y().to_bits(), y.to_bits());
        ys.push(y);
        let log = fmu.log.take();
        assert!(log.iter().all(|l| l.status != ERROR as c_int), "{log:?}");
        warnings.extend(log.into_iter().filter(|l| l.status == WARNING as c_int));
    }
    // A warning where saturation starts (3.0, -2.0), none while it lasts (2.5, -7.0).
    assert_eq!(warnings.len(), 3, "{warnings:?}");
    assert!(warnings.iter().all(|w| w.category == "logStatusWarning"));
    for part in ["fmi2DoStep", "x = 3", "tanh", "clamped to"] {
        assert!(
            warnings[0].message.contains(part),
            "{:?} lacks {part}",
            warnings[0]
        );
    }
    // The outputs are the evaluator's for the clamped desired outputs.
    let clamped: Vec<f64> = desired
        .iter()
        .map(|x| x.clamp(limits.0, limits.1))
        .collect();
    assert_eq!(bits(&ys), bits(&evaluator_run(&file, true, &clamped)));
}
