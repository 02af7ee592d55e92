//! Models with dynamics or a rate term: each communication step size is the direct model's time
//! step to the next sample (the first its nominal step); the inverse is Lemma 5.1's
//! compensator, with the desired output's derivatives as the inputs x_d1 … x_dn.

use super::*;
use crate::harness::*;
use crate::interface::refused;

/// The dynamics and rate sections the timed tests append to a model file.
const DYNAMICS_2: &str = "[dynamics]\nb = 1.0\na = [0.05, 0.001]\n";
const RATE: &str = "[rate]\nc = 0.3\n";

/// A sample period that is exact in binary (2⁻¹⁰ s), so `hyst run`'s mean step equals it.
const H: f64 = 1.0 / 1024.0;

/// `fitted_model()` as a version-4 file with `sections` appended: its text and the model as
/// `ModelFile::read` reads it.
fn timed_model(sections: &str) -> (String, ModelFile) {
    let text = fitted_model().to_toml().unwrap();
    assert!(text.contains("\nversion = 1\n"), "{text}");
    // A hold other than the first-order one needs version 5.
    let version = if sections.contains("hold") { 5 } else { 4 };
    let text =
        text.replacen("\nversion = 1\n", &format!("\nversion = {version}\n"), 1) + "\n" + sections;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("timed.toml");
    std::fs::write(&path, &text).unwrap();
    let file = ModelFile::read(&path).unwrap();
    assert!(file.smooth.as_ref().unwrap().is_timed());
    (text, file)
}

fn timed_resources(text: &str, inverse: bool) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    write_config(dir.path(), &model_config(inverse));
    std::fs::write(dir.path().join("model.toml"), text).unwrap();
    dir
}

/// `TimedRun` over `xs` at the period `h`, as `hyst run --model` runs a timed record.
fn timed_run(file: &ModelFile, h: f64, xs: &[f64]) -> Vec<f64> {
    let smooth = file.smooth.as_ref().unwrap();
    let mut run = hyst_model::TimedRun::new(smooth, h, xs[0]).unwrap();
    xs.iter().map(|x| run.step(*x).unwrap().y).collect()
}

/// A smooth desired output and its first two time derivatives at sample k (period H).
fn desired(k: usize) -> [f64; 3] {
    let (t, w, a) = (k as f64 * H, 2.0 * std::f64::consts::PI * 3.0, 0.5);
    [
        1.0 + a * (w * t).sin(),
        a * w * (w * t).cos(),
        -a * w * w * (w * t).sin(),
    ]
}

/// One communication step of a timed model: set x, read y, step, read y again (`Fmu::step`:
/// the same bits, the output at the communication point held).
fn timed_step(fmu: &Fmu, x: f64) -> f64 {
    fmu.step(x)
}

fn timed_steps(fmu: &Fmu, xs: &[f64]) -> Vec<f64> {
    xs.iter().map(|x| timed_step(fmu, *x)).collect()
}

#[test]
fn a_timed_model_runs_as_timed_run_bit_for_bit() {
    let xs: Vec<f64> = (0..2500).map(signal).collect();
    let both = format!("{DYNAMICS_2}{RATE}");
    for sections in [DYNAMICS_2, RATE, both.as_str()] {
        let (text, file) = timed_model(sections);
        let dir = timed_resources(&text, false);
        let fmu = Fmu::started(dir.path());
        fmu.step_size.set(H);
        // y before the first fmi2DoStep (the period not fixed yet) is the first doStep's.
        assert_eq!(fmu.set(VR_X, xs[0]), OK);
        let before = fmu.y();
        let ys = timed_steps(&fmu, &xs);
        let reference = timed_run(&file, H, &xs);
        // y after the last doStep is the last sample's, held; x set again (the same value)
        // is the next sample's, for x held there (the plant moved on).
        assert_eq!(fmu.y().to_bits(), reference[xs.len() - 1].to_bits());
        let held: Vec<f64> = xs.iter().chain(xs.last()).copied().collect();
        assert_eq!(fmu.set(VR_X, xs[xs.len() - 1]), OK);
        let next = timed_run(&file, H, &held)[xs.len()];
        assert_eq!(fmu.y().to_bits(), next.to_bits());
        assert_ne!(
            next.to_bits(),
            reference[xs.len() - 1].to_bits(),
            "{sections}"
        );
        assert_eq!(before.to_bits(), reference[0].to_bits(), "{sections}");
        assert_eq!(bits(&ys), bits(&reference), "{sections}");
        // The plant or the rate term matters: the static model gives other outputs.
        assert_ne!(bits(&ys), bits(&evaluator_run(&fitted_model(), false, &xs)));
        assert!(fmu.errors().is_empty());
    }
}

/// Time stamps with steps of H, 2H, 3H, 2H over and over (exact in binary): their mean step is
/// 2H, and the first H.
fn uneven_stamps(n: usize) -> Vec<f64> {
    let mut t = vec![0.0];
    for k in 1..n {
        t.push(t[k - 1] + H * [1.0, 2.0, 3.0, 2.0][(k - 1) % 4]);
    }
    t
}

/// What `hyst run --model` (and Python's `Model.process(x, t=...)`) computes on a record with
/// the time stamps `t`: the record cut at its gaps, each part run at its measured steps.
fn timed_run_at(file: &ModelFile, t: &[f64], xs: &[f64]) -> Vec<f64> {
    let smooth = file.smooth.as_ref().unwrap();
    let (parts, _) = hyst_model::time::split(t).unwrap();
    let mut y = Vec::new();
    for (range, steps) in parts {
        smooth
            .run_timed(&xs[range], Some(&steps), None, |_, s| y.push(s.y))
            .unwrap();
    }
    y
}

#[test]
fn varying_steps_run_as_hyst_run_at_the_same_stamps() {
    let n = 2001;
    let xs: Vec<f64> = (0..n).map(signal).collect();
    let t = uneven_stamps(n);
    let both = format!("{DYNAMICS_2}{RATE}");
    let zoh = format!("{DYNAMICS_2}hold = \"zoh\"\n");
    for sections in [DYNAMICS_2, RATE, both.as_str(), zoh.as_str()] {
        let (text, file) = timed_model(sections);
        let dir = timed_resources(&text, false);
        let fmu = Fmu::started(dir.path());
        // Each fmi2DoStep's size is the step from its sample to the next.
        let mut ys = Vec::new();
        for k in 0..n {
            let next = t.get(k + 1).map_or(H, |after| after - t[k]);
            fmu.step_size.set(next);
            ys.push(timed_step(&fmu, xs[k]));
        }
        let reference = timed_run_at(&file, &t, &xs);
        assert_eq!(bits(&ys), bits(&reference), "{sections}");
        // The steps matter: the record at its mean step gives other outputs.
        assert_ne!(
            bits(&ys),
            bits(&timed_run(&file, 2.0 * H, &xs)),
            "{sections}"
        );
        assert!(fmu.errors().is_empty(), "{sections}");
    }
}

#[test]
fn a_zero_step_is_refused_for_a_timed_model() {
    let xs: Vec<f64> = (0..400).map(signal).collect();
    let (text, file) = timed_model(DYNAMICS_2);
    let reference = timed_run(&file, H, &xs);
    let dir = timed_resources(&text, false);
    let fmu = Fmu::started(dir.path());
    // A first step of 0 cannot be the sample period.
    fmu.step_size.set(0.0);
    assert_eq!(fmu.set(VR_X, xs[0]), OK);
    assert_eq!(fmu.do_step(), ERROR);
    fmu.expect_error(&["fmi2DoStep", "communicationStepSize = 0", "must be > 0"]);
    fmu.step_size.set(H);
    let mut ys = timed_steps(&fmu, &xs[..200]);
    // A step of 0 or below: refused, naming it; nothing changes.
    for factor in [0.0, -1.0] {
        fmu.step_size.set(H * factor);
        assert_eq!(fmu.set(VR_X, xs[200]), OK);
        assert_eq!(fmu.do_step(), ERROR, "{factor}");
        let step = format!("communicationStepSize = {}", H * factor);
        fmu.expect_error(&["fmi2DoStep", &step]);
    }
    fmu.step_size.set(H);
    ys.extend(timed_steps(&fmu, &xs[200..]));
    assert_eq!(bits(&ys), bits(&reference));
    // fmi2Reset forgets the period: the next first step fixes another one.
    assert_eq!(unsafe { fmi2Reset(fmu.c) }, OK);
    fmu.initialise();
    fmu.step_size.set(2.0 * H);
    let ys = timed_steps(&fmu, &xs);
    assert_eq!(bits(&ys), bits(&timed_run(&file, 2.0 * H, &xs)));
    assert!(fmu.errors().is_empty());
    // The inverse (the compensator) takes the derivatives as inputs: any steps are fine.
    let inverse = Fmu::started(timed_resources(&text, true).path());
    for (k, h) in [H, 3.0 * H, 0.0, 0.5 * H].into_iter().enumerate() {
        inverse.step_size.set(h);
        let d = desired(k);
        assert_eq!(inverse.set(VR_X, d[0]), OK);
        assert_eq!(inverse.do_step(), OK);
    }
}

#[test]
fn the_inverse_of_a_timed_model_is_its_compensator_with_derivative_inputs() {
    let (text, file) = timed_model(DYNAMICS_2);
    let dir = timed_resources(&text, true);
    let fmu = Fmu::started(dir.path());
    fmu.step_size.set(H);
    let smooth = file.smooth.as_ref().unwrap();
    let mut compensator = hyst_model::TimedCompensator::new(smooth, desired(0)[0]).unwrap();
    let mut commands = Vec::new();
    for k in 0..3000 {
        let d = desired(k);
        let vrs = [VR_X, 2, 3];
        assert_eq!(
            unsafe { fmi2SetReal(fmu.c, vrs.as_ptr(), 3, d.as_ptr()) },
            OK
        );
        let y = fmu.y();
        assert_eq!(fmu.do_step(), OK);
        let (u, _) = compensator.step(&d).unwrap();
        assert_eq!(y.to_bits(), u.to_bits(), "sample {k}");
        commands.push(u);
    }
    // The command drives the plant and the hysteresis along the desired output (once the
    // start, at rest, has settled).
    let ys = timed_run(&file, H, &commands);
    let worst = (1000..3000)
        .map(|k| (ys[k] - desired(k)[0]).abs())
        .fold(0.0, f64::max);
    assert!(worst < 5e-3, "{worst}"); // 1.4e-3 here: a sanity check, the bits are checked above
                                      // The derivatives read back; there are exactly n = 2 of them.
    assert_eq!(fmu.get(2), Ok(desired(2999)[1]));
    assert_eq!(fmu.get(3), Ok(desired(2999)[2]));
    assert_eq!(fmu.get(4), Err(ERROR));
    fmu.expect_error(&["value reference 4"]);
    assert_eq!(fmu.set(4, 1.0), ERROR);
    fmu.expect_error(&["value reference 4"]);
    // A non-finite derivative is refused and changes nothing.
    assert_eq!(fmu.set(3, f64::NAN), OK);
    assert_eq!(fmu.do_step(), ERROR);
    fmu.expect_error(&["fmi2DoStep", "x_d2 = NaN"]);
    // The direct FMU of the same model has no derivative inputs.
    let direct = Fmu::started(timed_resources(&text, false).path());
    assert_eq!(direct.set(2, 1.0), ERROR);
    direct.expect_error(&["value reference 2"]);
}

#[test]
fn timed_states_are_restored_in_memory_and_not_serialised() {
    let xs: Vec<f64> = (0..800).map(signal).collect();
    for inverse in [false, true] {
        let (text, _) = timed_model(DYNAMICS_2);
        let dir = timed_resources(&text, inverse);
        let fmu = Fmu::started(dir.path());
        fmu.step_size.set(H);
        let drive = |range: std::ops::Range<usize>| -> Vec<f64> {
            range
                .map(|k| {
                    let d = if inverse {
                        desired(k)
                    } else {
                        [xs[k], 0.0, 0.0]
                    };
                    if inverse {
                        assert_eq!(fmu.set(2, d[1]), OK);
                        assert_eq!(fmu.set(3, d[2]), OK);
                    }
                    timed_step(&fmu, d[0])
                })
                .collect()
        };
        drive(0..400);
        let saved = fmu.get_state();
        let first = drive(400..800);
        assert_eq!(fmu.set_state(saved), OK);
        assert_eq!(bits(&drive(400..800)), bits(&first), "inverse = {inverse}");
        let mut size = 0;
        assert_eq!(
            unsafe { fmi2SerializedFMUstateSize(fmu.c, saved, &mut size) },
            ERROR
        );
        fmu.expect_error(&["dynamics of order 2", "not serialised"]);
        let bytes = vec![0u8; 64];
        assert_eq!(fmu.deserialize(&bytes), Err(ERROR));
        fmu.expect_error(&["fmi2DeSerializeFMUstate", "not serialised"]);
    }
}

/// What the FMU cannot run is refused at instantiation (NULL, and the reason logged): the
/// inverse of a model without a compensator (a rate term), and saturate with a timed model.
#[test]
fn a_timed_model_without_a_compensator_is_refused_as_an_inverse() {
    let both = format!("{DYNAMICS_2}{RATE}");
    for (sections, what) in [
        (RATE, "a rate term"),
        (both.as_str(), "dynamics of order 2 and a rate term"),
    ] {
        let (text, _) = timed_model(sections);
        let dir = timed_resources(&text, true);
        refused(
            &uri(dir.path()),
            GUID,
            fmi2CoSimulation,
            &["fmi2Instantiate", "model.toml", what, "inverse"],
        );
        // Its direct model runs.
        Fmu::started(timed_resources(&text, false).path());
    }
    let (text, _) = timed_model(DYNAMICS_2);
    let dir = timed_resources(&text, true);
    let config = model_config(true) + "saturate = true\n";
    write_config(dir.path(), &config);
    refused(
        &uri(dir.path()),
        GUID,
        fmi2CoSimulation,
        &[
            "fmi2Instantiate",
            "model.toml",
            "saturate",
            "dynamics of order 2",
        ],
    );
}

/// One communication point as fmuCheck steps it: set the inputs (x, then x_d1 … of a
/// compensator), read y, fmi2DoStep, read y again. Returns y read before the step, and the
/// samples where the read after it differed.
fn read_twice(fmu: &Fmu, inputs: &[Vec<f64>]) -> (Vec<f64>, Vec<usize>) {
    let mut ys = Vec::new();
    let mut changed = Vec::new();
    for (k, sample) in inputs.iter().enumerate() {
        let vrs: Vec<u32> = (0..sample.len())
            .map(|i| if i == 0 { VR_X } else { VR_Y + i as u32 })
            .collect();
        let status = unsafe { fmi2SetReal(fmu.c, vrs.as_ptr(), vrs.len(), sample.as_ptr()) };
        assert_eq!(status, OK);
        let y = fmu.y();
        assert_eq!(fmu.do_step(), OK);
        if fmu.y().to_bits() != y.to_bits() {
            changed.push(k);
        }
        ys.push(y);
    }
    (ys, changed)
}

/// An FMU to step: its name, its resources, the inputs of each sample (x, then x_d1 …) and
/// the outputs `hyst run` gives for them.
type Kind = (String, tempfile::TempDir, Vec<Vec<f64>>, Vec<f64>);

/// Every kind of FMU: y is the output at the communication point, for the inputs set there.
/// fmi2DoStep commits that sample once, and y read after it (before the next inputs are set)
/// is the same output, bit for bit; both equal the run of the same samples (`hyst run`).
#[test]
fn y_read_before_and_after_do_step_is_the_same_output_for_every_kind() {
    let xs: Vec<f64> = (0..3000).map(signal).collect();
    let plain: Vec<Vec<f64>> = xs.iter().map(|x| vec![*x]).collect();
    let mut kinds: Vec<Kind> = Vec::new();
    for inverse in [false, true] {
        let reference = if inverse {
            core_run(InverseHysteresis::new(0.2, 8.0).unwrap(), &xs)
        } else {
            core_run(Hysteresis::new(0.2, 8.0).unwrap(), &xs)
        };
        let dir = operator_resources(inverse, 0.2, 8.0);
        kinds.push((
            format!("operator, inverse {inverse}"),
            dir,
            plain.clone(),
            reference,
        ));
        let file = fitted_model();
        let input: Vec<f64> = if inverse {
            xs.iter().map(|x| 3.0 * x + 1.0).collect()
        } else {
            xs.clone()
        };
        let reference = evaluator_run(&file, inverse, &input);
        let inputs = input.iter().map(|x| vec![*x]).collect();
        let dir = model_resources(&file, inverse);
        kinds.push((format!("model, inverse {inverse}"), dir, inputs, reference));
    }
    let both = format!("{DYNAMICS_2}{RATE}");
    let (text, file) = timed_model(&both);
    let reference = timed_run(&file, H, &xs);
    kinds.push((
        "timed model".into(),
        timed_resources(&text, false),
        plain,
        reference,
    ));
    let (text, file) = timed_model(DYNAMICS_2);
    let smooth = file.smooth.as_ref().unwrap();
    let mut compensator = hyst_model::TimedCompensator::new(smooth, desired(0)[0]).unwrap();
    let inputs: Vec<Vec<f64>> = (0..3000).map(|k| desired(k).to_vec()).collect();
    let reference = inputs
        .iter()
        .map(|d| compensator.step(d).unwrap().0)
        .collect();
    kinds.push((
        "compensator".into(),
        timed_resources(&text, true),
        inputs,
        reference,
    ));
    let mut changed_by_a_step = Vec::new();
    for (name, dir, inputs, reference) in kinds {
        let fmu = Fmu::started(dir.path());
        fmu.step_size.set(H);
        let (ys, changed) = read_twice(&fmu, &inputs);
        // A saved state keeps the held output: another x set and read, the state restored, y
        // is the last sample's again.
        let saved = fmu.get_state();
        assert_eq!(fmu.set(VR_X, inputs[0][0] + 0.25), OK);
        assert_ne!(fmu.y().to_bits(), ys[ys.len() - 1].to_bits(), "{name}");
        assert_eq!(fmu.set_state(saved), OK);
        assert_eq!(fmu.y().to_bits(), ys[ys.len() - 1].to_bits(), "{name}");
        println!(
            "{name}: y changed by fmi2DoStep at {} of {} samples",
            changed.len(),
            ys.len()
        );
        changed_by_a_step.push((name.clone(), changed.len()));
        assert_eq!(bits(&ys), bits(&reference), "{name}");
        assert!(fmu.errors().is_empty(), "{name}");
    }
    assert!(
        changed_by_a_step.iter().all(|(_, n)| *n == 0),
        "{changed_by_a_step:?}"
    );
}

/// The compensator of a model whose loop's corners the communication step does not resolve
/// (k2 = 1000: the desired output crosses a corner in 3.2e-4 s, steps of 2⁻¹⁰ s) warns once,
/// with the step it needs, and computes the commands all the same; at k2 = 6 it does not warn.
#[test]
fn a_compensator_warns_once_when_the_step_cannot_resolve_the_loops_corners() {
    let (text, _) = timed_model(DYNAMICS_2);
    let constant = "law = \"constant\"\nvalue = 6.0\n";
    assert!(text.contains(constant), "{text}");
    let sharp = text.replace(constant, "law = \"constant\"\nvalue = 1000.0\n");
    for (text, warns) in [(text.as_str(), false), (sharp.as_str(), true)] {
        let dir = timed_resources(text, true);
        let fmu = Fmu::started(dir.path());
        fmu.step_size.set(H);
        let file = ModelFile::read(&dir.path().join("model.toml")).unwrap();
        let smooth = file.smooth.as_ref().unwrap();
        let mut compensator = hyst_model::TimedCompensator::new(smooth, desired(0)[0]).unwrap();
        let mut statuses = Vec::new();
        for k in 0..600 {
            let d = desired(k);
            let vrs = [VR_X, 2, 3];
            assert_eq!(
                unsafe { fmi2SetReal(fmu.c, vrs.as_ptr(), 3, d.as_ptr()) },
                OK
            );
            let y = fmu.y();
            statuses.push(fmu.do_step());
            assert_eq!(
                y.to_bits(),
                compensator.step(&d).unwrap().0.to_bits(),
                "{k}"
            );
        }
        let warnings: Vec<Logged> = fmu
            .log
            .take()
            .into_iter()
            .filter(|l| l.status == WARNING as c_int)
            .collect();
        let warned = statuses.iter().filter(|s| **s == WARNING).count();
        assert_eq!(
            (warned, warnings.len()),
            if warns { (1, 1) } else { (0, 0) }
        );
        assert!(statuses.iter().all(|s| *s == OK || *s == WARNING));
        if warns {
            let message = &warnings[0].message;
            let corner = compensator.fastest_corner().unwrap();
            println!("{message}");
            assert!((corner.time - 3.2e-4).abs() < 0.05e-4, "{corner:?}");
            for part in [
                "fmi2DoStep: ".to_string(),
                "corner of the model's loop".to_string(),
                format!("step at most every {:.4e} s", corner.time / 3.0),
            ] {
                assert!(message.contains(&part), "{part:?} not in {message}");
            }
        }
    }
}
