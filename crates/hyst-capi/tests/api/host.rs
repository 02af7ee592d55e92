//! The host part's model files: run like the evaluator in one block or many, saturation of the
//! compensator's desired outputs, memories refused when impossible.

use super::*;
use crate::operator::*;

fn fitted_model_file(dir: &std::path::Path) -> std::path::PathBuf {
    // A small smooth model file, as `hyst fit` writes it (docs/formats.md).
    // The operator the data would come from, as a fitted smooth model: y = 3 H(0.2, 6)[x] + 1,
    // starting as after a rise (a fit of that data recovers it).
    let model = ::hyst_model::SmoothModel {
        k1: 0.2,
        k2: hyst_core::AnyK2Law::Constant { value: 6.0 },
        input_shaping: hyst_core::ScaledShaping::identity(),
        output_shaping: hyst_core::ScaledShaping::new(
            1.0,
            0.0,
            hyst_core::AnyShaping::Identity,
            3.0,
            1.0,
        )
        .unwrap(),
        initial_state: ::hyst_model::InitialState::Rising,
        form: ::hyst_model::Form::Operator,
        linear: 0.0,
        dynamics: None,
        rate: None,
    };
    let file = ::hyst_model::ModelFile {
        format: ::hyst_model::file::FORMAT.into(),
        version: 1,
        kind: ::hyst_model::ModelKind::Smooth,
        columns: ::hyst_model::Columns {
            input: "x".into(),
            output: "y".into(),
            ..Default::default()
        },
        units: Default::default(),
        parameters: Vec::new(),
        metrics: Default::default(),
        structure: Some(::hyst_model::Structure::default()),
        smooth: Some(model),
        prandtl_ishlinskii: None,
        dynamics: None,
        rate: None,
        family: None,
        provenance: Default::default(),
    };
    let path = dir.join("model.toml");
    std::fs::write(&path, file.to_toml().unwrap()).unwrap();
    path
}

#[test]
fn host_model_runs_like_the_evaluator_in_one_block_or_many() {
    let dir = tempfile_dir("blocks");
    let path = fitted_model_file(&dir);
    let file = ::hyst_model::ModelFile::read(&path).unwrap();
    let cpath = CString::new(path.to_str().unwrap()).unwrap();
    let mut error = [0 as std::ffi::c_char; 256];
    let m = unsafe { hyst_model_load(cpath.as_ptr(), error.as_mut_ptr(), error.len()) };
    assert!(!m.is_null());
    let desired: Vec<f64> = (0..800).map(|k| 3.0 * signal(k + 5) + 1.0).collect();
    // The whole record at once, then the same in blocks of 77.
    let mut whole = vec![0.0; desired.len()];
    let mut blocks = vec![0.0; desired.len()];
    unsafe {
        assert_eq!(
            hyst_model_process(m, 1, desired.as_ptr(), whole.as_mut_ptr(), desired.len()),
            HYST_OK
        );
        assert_eq!(hyst_model_reset(m), HYST_OK);
        for (x, y) in desired.chunks(77).zip(blocks.chunks_mut(77)) {
            assert_eq!(
                hyst_model_process(m, 1, x.as_ptr(), y.as_mut_ptr(), x.len()),
                HYST_OK
            );
        }
    }
    assert_eq!(whole, blocks);
    let mut evaluator = file.evaluator(desired[0], true).unwrap();
    for (x, y) in desired.iter().zip(&whole) {
        assert_eq!(evaluator.try_step(*x).unwrap().to_bits(), y.to_bits());
    }
    // A refused sample stops the run with its status.
    let bad = [1.0, f64::NAN, 1.0];
    let mut out = [0.0; 3];
    unsafe {
        assert_eq!(
            hyst_model_process(m, 0, bad.as_ptr(), out.as_mut_ptr(), 3),
            HYST_ERR_NON_FINITE
        );
        assert_eq!(
            hyst_model_process(ptr::null_mut(), 0, bad.as_ptr(), out.as_mut_ptr(), 3),
            HYST_ERR_NULL_POINTER
        );
        // A finite input whose output overflows the output shaping (gain about 3): refused,
        // no longer HYST_OK with y = inf.
        let huge = [0.5, 1e308];
        let mut out = [0.0; 2];
        assert_eq!(
            hyst_model_process(m, 0, huge.as_ptr(), out.as_mut_ptr(), 2),
            HYST_ERR_OVERFLOW
        );
        assert!(out[0].is_finite());
        assert!(!CStr::from_ptr(hyst_status_message(HYST_ERR_OVERFLOW))
            .to_str()
            .unwrap()
            .is_empty());
        hyst_model_free(m);
        hyst_model_free(ptr::null_mut());
    }
    // A missing file: NULL and a message naming it, truncated safely into a small buffer.
    let missing = CString::new(dir.join("nope.toml").to_str().unwrap()).unwrap();
    let m = unsafe { hyst_model_load(missing.as_ptr(), error.as_mut_ptr(), error.len()) };
    assert!(m.is_null());
    let text = unsafe { CStr::from_ptr(error.as_ptr()) }.to_str().unwrap();
    assert!(text.contains("nope.toml"), "{text}");
    let mut tiny = [1 as std::ffi::c_char; 5];
    let m = unsafe { hyst_model_load(missing.as_ptr(), tiny.as_mut_ptr(), tiny.len()) };
    assert!(m.is_null());
    assert_eq!(tiny[4], 0);
    assert!(unsafe { hyst_model_load(ptr::null(), ptr::null_mut(), 0) }.is_null());
    let _ = std::fs::remove_dir_all(&dir);
}

/// A fresh folder for the test `name` (tests run in parallel threads of one process).
fn tempfile_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("hyst-capi-test-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn host_model_saturate_clamps_the_compensators_desired_outputs() {
    let dir = tempfile_dir("saturate");
    let affine = fitted_model_file(&dir);
    let mut file = ::hyst_model::ModelFile::read(&affine).unwrap();
    // The same model with an output saturating at ±2 (tanh).
    if let Some(m) = file.smooth.as_mut() {
        m.output_shaping = hyst_core::ScaledShaping {
            pre_gain: 1.0,
            pre_offset: 0.0,
            shape: hyst_core::AnyShaping::Tanh(hyst_core::Tanh::new(1.0, 1.0).unwrap()),
            post_gain: 2.0,
            post_offset: 0.0,
        };
    }
    let path = dir.join("tanh.toml");
    std::fs::write(&path, file.to_toml().unwrap()).unwrap();
    let limits = file.saturation().unwrap().limits;
    let load = |p: &std::path::Path| {
        let c = CString::new(p.to_str().unwrap()).unwrap();
        let m = unsafe { hyst_model_load(c.as_ptr(), ptr::null_mut(), 0) };
        assert!(!m.is_null());
        m
    };
    // Desired outputs beyond the range now and then, the first one too.
    let desired: Vec<f64> = std::iter::once(2.5)
        .chain((0..600).map(|k| 2.6 * signal(k + 40)))
        .collect();
    let beyond = desired
        .iter()
        .filter(|y| **y < limits.0 || **y > limits.1)
        .count();
    assert!(
        beyond > 10 && desired[0].abs() > 2.0,
        "{beyond} {}",
        desired[0]
    );
    let mut y = vec![0.0; desired.len()];
    let mut count = u64::MAX;
    unsafe {
        // An unbounded model has nothing to clamp.
        let open = load(&affine);
        assert_eq!(hyst_model_saturate(open, 1), HYST_ERR_INVALID_PARAMETER);
        assert_eq!(
            hyst_model_saturate(ptr::null_mut(), 1),
            HYST_ERR_NULL_POINTER
        );
        hyst_model_free(open);

        let m = load(&path);
        let (x, n) = (desired.as_ptr(), desired.len());
        assert_eq!(
            hyst_model_process(m, 1, x, y.as_mut_ptr(), n),
            HYST_ERR_OUT_OF_RANGE
        );
        assert_eq!(hyst_model_saturate(m, 1), HYST_OK);
        assert_eq!(hyst_model_process(m, 1, x, y.as_mut_ptr(), n), HYST_OK);
        assert_eq!(hyst_model_saturated(m, &mut count), HYST_OK);
        assert_eq!(count, beyond as u64);
        assert_eq!(
            hyst_model_saturated(m, ptr::null_mut()),
            HYST_ERR_NULL_POINTER
        );
        // Off again: the next value beyond the range is refused, in the run already started.
        assert_eq!(hyst_model_saturate(m, 0), HYST_OK);
        let mut out = [0.0];
        assert_eq!(
            hyst_model_process(m, 1, [9.0].as_ptr(), out.as_mut_ptr(), 1),
            HYST_ERR_OUT_OF_RANGE
        );
        assert_eq!(hyst_model_reset(m), HYST_OK);
        assert_eq!(hyst_model_saturated(m, &mut count), HYST_OK);
        assert_eq!(count, 0);
        hyst_model_free(m);
    }
    // The outputs are the compensator's for the clamped desired outputs.
    let clamped: Vec<f64> = desired
        .iter()
        .map(|v| v.clamp(limits.0, limits.1))
        .collect();
    let mut evaluator = file.evaluator(clamped[0], true).unwrap();
    for (x, y) in clamped.iter().zip(&y) {
        assert_eq!(evaluator.try_step(*x).unwrap().to_bits(), y.to_bits());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 28, item 6: `has_history` is 0 or 1, and a memory whose last input lies on the wrong
/// side of its reversal for its direction is refused; the operator keeps its memory.
#[test]
fn set_memory_refuses_impossible_states() {
    let mut op: hyst_operator = zeroed();
    unsafe {
        assert_eq!(hyst_operator_init_direct(&mut op, 0.2, 8.0), HYST_OK);
        let mut y = 0.0;
        assert_eq!(hyst_operator_step(&mut op, 0.4, &mut y), HYST_OK);
        let mut kept: hyst_memory = zeroed();
        assert_eq!(hyst_operator_get_memory(&mut op, &mut kept), HYST_OK);
        for has_history in [2, -1] {
            let mut m = kept;
            m.has_history = has_history;
            assert_eq!(
                hyst_operator_set_memory(&mut op, &m),
                HYST_ERR_INVALID_PARAMETER
            );
        }
        let mut m = kept;
        m.direction = 1;
        m.reversal_input = 1e300;
        m.reversal_output = 1e300;
        assert_eq!(
            hyst_operator_set_memory(&mut op, &m),
            HYST_ERR_INVALID_PARAMETER
        );
        let mut now: hyst_memory = zeroed();
        assert_eq!(hyst_operator_get_memory(&mut op, &mut now), HYST_OK);
        assert_eq!(now, kept);
    }
}

/// The piezo record (0 to 3.6 V) fitted with a tanh or a Langevin input shaping and a tanh
/// output shaping (crates/hyst-model/testdata): `hyst_model_saturate` leaves desired outputs of
/// the training range alone, so the commands are the plain inverse's (1.33, 2.30, 3.34 V).
#[test]
fn host_model_saturate_with_a_saturating_input_shaping_keeps_the_training_range() {
    let testdata = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../hyst-model/testdata");
    for name in ["piezo-tanh-in", "piezo-langevin-in"] {
        let c = CString::new(testdata.join(format!("{name}.toml")).to_str().unwrap()).unwrap();
        let desired = [-120.0, -100.0, -80.0];
        let run = |saturate: i32| {
            let mut u = [0.0; 3];
            let mut count = u64::MAX;
            unsafe {
                let m = hyst_model_load(c.as_ptr(), ptr::null_mut(), 0);
                assert!(!m.is_null(), "{name}");
                assert_eq!(hyst_model_saturate(m, saturate), HYST_OK, "{name}");
                assert_eq!(
                    hyst_model_process(m, 1, desired.as_ptr(), u.as_mut_ptr(), 3),
                    HYST_OK,
                    "{name}"
                );
                assert_eq!(hyst_model_saturated(m, &mut count), HYST_OK);
                hyst_model_free(m);
            }
            (u, count)
        };
        let (plain, _) = run(0);
        let (saturated, clamped) = run(1);
        println!("{name}: hyst_model_saturate commands {saturated:?} V, {clamped} clamped");
        assert_eq!(saturated, plain, "{name}");
        assert_eq!(clamped, 0, "{name}");
        for (u, right) in saturated.iter().zip([1.33, 2.30, 3.34]) {
            assert!(
                (u - right).abs() < 0.01,
                "{name}: {u} V, expected about {right} V"
            );
        }
    }
}
