//! The C API called as C would call it: results equal the core's bit for bit, states resume
//! from a saved memory, and every bad argument (NULL, misaligned, uninitialised, non-finite, out
//! of range) returns its status without touching anything.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]
// The tests call the C API through raw pointers, as a C program does.
#![allow(unsafe_code)]

use std::ffi::{CStr, CString};
use std::ptr;

use hyst::api_f32::*;
use hyst::api_f64::*;
use hyst::host::*;
use hyst::status::*;
use hyst::{HYST_K2_CONSTANT, HYST_SHAPING_AFFINE, HYST_SHAPING_IDENTITY, HYST_SHAPING_POLYNOMIAL};
use hyst_core::{
    Affine, AnyShaping, Compensator, Hysteresis, InverseHysteresis, Jet, Operator, Polynomial,
    ScaledShaping, ShapedModel,
};

fn signal(k: usize) -> f64 {
    let t = k as f64 * 0.03;
    (0.4 + 0.04 * t).min(1.3) * t.sin() + 0.25 * (2.9 * t).cos()
}

fn zeroed<T>() -> T {
    // SAFETY: the C state and parameter types are plain data: all-zero bits are valid.
    unsafe { std::mem::zeroed() }
}

#[test]
fn operator_equals_the_core_bit_for_bit() {
    let mut op: hyst_operator = zeroed();
    let mut inv: hyst_operator = zeroed();
    unsafe {
        assert_eq!(hyst_operator_init_direct(&mut op, 0.2, 8.0), HYST_OK);
        assert_eq!(hyst_operator_init_inverse(&mut inv, 0.2, 8.0), HYST_OK);
    }
    let mut h = Hysteresis::new(0.2, 8.0).unwrap();
    let mut hinv = InverseHysteresis::new(0.2, 8.0).unwrap();
    for k in 0..2000 {
        let x = signal(k);
        let (mut y, mut v) = (0.0, 0.0);
        unsafe {
            assert_eq!(hyst_operator_step(&mut op, x, &mut y), HYST_OK);
            assert_eq!(hyst_operator_step(&mut inv, x, &mut v), HYST_OK);
        }
        assert_eq!(y.to_bits(), h.step(x).to_bits());
        assert_eq!(v.to_bits(), hinv.step(x).to_bits());
    }
}

#[test]
fn f32_twin_follows_the_f64_operator() {
    let mut op: hyst_operator_f32 = zeroed();
    let mut op64: hyst_operator = zeroed();
    unsafe {
        assert_eq!(hyst_operator_init_inverse_f32(&mut op, 0.2, 8.0), HYST_OK);
        assert_eq!(hyst_operator_init_inverse(&mut op64, 0.2, 8.0), HYST_OK);
    }
    let mut core = InverseHysteresis::new(0.2_f32, 8.0).unwrap();
    for k in 0..2000 {
        let x = signal(k);
        let (mut y, mut y64) = (0.0_f32, 0.0);
        unsafe {
            assert_eq!(hyst_operator_step_f32(&mut op, x as f32, &mut y), HYST_OK);
            assert_eq!(hyst_operator_step(&mut op64, x, &mut y64), HYST_OK);
        }
        assert_eq!(y.to_bits(), core.step(x as f32).to_bits());
        assert!(
            (f64::from(y) - y64).abs() <= 1e-5 * (1.0 + y64.abs()),
            "{k}: {y} vs {y64}"
        );
    }
}

#[test]
fn process_in_place_derivatives_and_memory() {
    let mut op: hyst_operator = zeroed();
    unsafe { assert_eq!(hyst_operator_init_direct(&mut op, 0.14, 5.0), HYST_OK) };
    // process in place == step by step
    let mut block: Vec<f64> = (0..500).map(signal).collect();
    let mut reference = Hysteresis::new(0.14, 5.0).unwrap();
    let expected: Vec<f64> = block.iter().map(|x| reference.step(*x)).collect();
    unsafe {
        let p = block.as_mut_ptr();
        assert_eq!(hyst_operator_process(&mut op, p, p, block.len()), HYST_OK);
    }
    assert_eq!(block, expected);
    // save, continue, restore, continue: the same outputs
    let mut saved: hyst_memory = zeroed();
    unsafe { assert_eq!(hyst_operator_get_memory(&mut op, &mut saved), HYST_OK) };
    assert_eq!(saved.has_history, 1);
    let run = |op: &mut hyst_operator| -> Vec<f64> {
        (500..700)
            .map(|k| {
                let mut y = 0.0;
                unsafe { assert_eq!(hyst_operator_step(op, signal(k), &mut y), HYST_OK) };
                y
            })
            .collect()
    };
    let first = run(&mut op);
    unsafe { assert_eq!(hyst_operator_set_memory(&mut op, &saved), HYST_OK) };
    assert_eq!(run(&mut op), first);
    // a memory outside the band is refused and changes nothing
    let mut bad = saved;
    bad.reversal_output = bad.reversal_input + 1.0;
    unsafe {
        assert_eq!(
            hyst_operator_set_memory(&mut op, &bad),
            HYST_ERR_STATE_OUTSIDE_BAND
        );
        bad = saved;
        bad.direction = 0;
        assert_eq!(
            hyst_operator_set_memory(&mut op, &bad),
            HYST_ERR_INVALID_PARAMETER
        );
    }
    // derivatives: the core's jets
    let x = [0.3, 1.0, -0.5, 0.2, 0.1];
    let mut y = [0.0; 5];
    let mut inv: hyst_operator = zeroed();
    unsafe {
        assert_eq!(hyst_operator_init_inverse(&mut inv, 0.2, 8.0), HYST_OK);
        assert_eq!(
            hyst_operator_step_derivatives(&mut inv, x.as_ptr(), y.as_mut_ptr(), 4),
            HYST_OK
        );
    }
    let jet = InverseHysteresis::new(0.2, 8.0)
        .unwrap()
        .try_step(Jet::from_derivatives(0.3, [1.0, -0.5, 0.2, 0.1]))
        .unwrap();
    assert_eq!(y[0], jet.value());
    assert_eq!(&y[1..], &jet.derivatives());
    // reset: back to no history
    unsafe { assert_eq!(hyst_operator_reset(&mut op), HYST_OK) };
    let mut m: hyst_memory = zeroed();
    unsafe { assert_eq!(hyst_operator_get_memory(&mut op, &mut m), HYST_OK) };
    assert_eq!(m.has_history, 0);
}

#[test]
fn bad_arguments_give_statuses_and_change_nothing() {
    let mut op: hyst_operator = zeroed();
    let mut y = 7.0;
    unsafe {
        // uninitialised (zeroed) state
        assert_eq!(
            hyst_operator_step(&mut op, 0.1, &mut y),
            HYST_ERR_NOT_INITIALISED
        );
        assert_eq!(y, 7.0);
        // invalid parameters leave the block untouched
        assert_eq!(
            hyst_operator_init_direct(&mut op, -1.0, 8.0),
            HYST_ERR_INVALID_PARAMETER
        );
        assert_eq!(
            hyst_operator_init_direct(&mut op, 0.2, f64::NAN),
            HYST_ERR_INVALID_PARAMETER
        );
        assert_eq!(
            hyst_operator_step(&mut op, 0.1, &mut y),
            HYST_ERR_NOT_INITIALISED
        );
        // NULL everywhere
        assert_eq!(
            hyst_operator_init_direct(ptr::null_mut(), 0.2, 8.0),
            HYST_ERR_NULL_POINTER
        );
        assert_eq!(
            hyst_operator_step(ptr::null_mut(), 0.1, &mut y),
            HYST_ERR_NULL_POINTER
        );
        assert_eq!(hyst_operator_init_direct(&mut op, 0.2, 8.0), HYST_OK);
        assert_eq!(
            hyst_operator_step(&mut op, 0.1, ptr::null_mut()),
            HYST_ERR_NULL_POINTER
        );
        assert_eq!(
            hyst_operator_process(&mut op, ptr::null(), &mut y, 1),
            HYST_ERR_NULL_POINTER
        );
        assert_eq!(
            hyst_operator_process(&mut op, ptr::null(), ptr::null_mut(), 0),
            HYST_OK
        );
        assert_eq!(
            hyst_operator_get_memory(&mut op, ptr::null_mut()),
            HYST_ERR_NULL_POINTER
        );
        assert_eq!(
            hyst_operator_set_memory(&mut op, ptr::null()),
            HYST_ERR_NULL_POINTER
        );
        // a non-finite sample holds the last output and leaves the memory alone
        assert_eq!(hyst_operator_step(&mut op, 0.5, &mut y), HYST_OK);
        let held = y;
        let mut before: hyst_memory = zeroed();
        assert_eq!(hyst_operator_get_memory(&mut op, &mut before), HYST_OK);
        assert_eq!(
            hyst_operator_step(&mut op, f64::NAN, &mut y),
            HYST_ERR_NON_FINITE
        );
        assert_eq!(y, held);
        let mut after: hyst_memory = zeroed();
        assert_eq!(hyst_operator_get_memory(&mut op, &mut after), HYST_OK);
        assert_eq!(before, after);
        // process: the first refused sample's status, the rest processed
        let x = [0.6, f64::INFINITY, 0.7];
        let mut out = [0.0; 3];
        assert_eq!(
            hyst_operator_process(&mut op, x.as_ptr(), out.as_mut_ptr(), 3),
            HYST_ERR_NON_FINITE
        );
        assert_eq!(out[1], out[0]);
        assert!(out[2] > out[0]);
        // derivative order out of range, NaN derivative
        let xs = [0.1; 6];
        let mut ys = [9.0; 6];
        assert_eq!(
            hyst_operator_step_derivatives(&mut op, xs.as_ptr(), ys.as_mut_ptr(), 5),
            HYST_ERR_LENGTH
        );
        let xs = [0.1, f64::NAN];
        assert_eq!(
            hyst_operator_step_derivatives(&mut op, xs.as_ptr(), ys.as_mut_ptr(), 1),
            HYST_ERR_NON_FINITE
        );
        assert_eq!(ys, [9.0; 6]);
        // misaligned state
        let mut words = [0_u64; 17];
        let misaligned = words
            .as_mut_ptr()
            .cast::<u8>()
            .add(4)
            .cast::<hyst_operator>();
        assert_eq!(
            hyst_operator_init_direct(misaligned, 0.2, 8.0),
            HYST_ERR_MISALIGNED
        );
        // a float state must be 8-byte aligned too (as documented), not only 4
        let mut words32 = [0_u64; 9];
        let at4 = words32
            .as_mut_ptr()
            .cast::<u8>()
            .add(4)
            .cast::<hyst_operator_f32>();
        assert_eq!(
            hyst_operator_init_direct_f32(at4, 0.2, 8.0),
            HYST_ERR_MISALIGNED
        );
        // an f32 state is not an f64 state (different tags)
        let mut op32: hyst_operator_f32 = zeroed();
        assert_eq!(hyst_operator_init_direct_f32(&mut op32, 0.2, 8.0), HYST_OK);
        let as64 = (&mut op32 as *mut hyst_operator_f32).cast::<hyst_operator>();
        let mut fake = [0_u64; 16];
        ptr::copy_nonoverlapping(as64.cast::<u64>(), fake.as_mut_ptr(), 8);
        assert_eq!(
            hyst_operator_step(fake.as_mut_ptr().cast::<hyst_operator>(), 0.1, &mut y),
            HYST_ERR_NOT_INITIALISED
        );
    }
    for status in 0..=13 {
        let text = unsafe { CStr::from_ptr(hyst_status_message(status)) };
        assert!(!text.to_bytes().is_empty());
    }
    let unknown = unsafe { CStr::from_ptr(hyst_status_message(-3)) };
    assert_eq!(unknown.to_str().unwrap(), "unknown status");
}

fn params() -> hyst_shaped_model_params {
    let mut p: hyst_shaped_model_params = zeroed();
    p.k1 = 0.105;
    p.k2.kind = HYST_K2_CONSTANT;
    p.k2.value = 8.0;
    p.input = hyst_shaping {
        kind: HYST_SHAPING_POLYNOMIAL,
        p: [0.0, 1.0, -0.098, 0.0, -5.0, 5.0],
        pre_gain: 0.5,
        pre_offset: 0.1,
        post_gain: 1.0,
        post_offset: 0.0,
    };
    p.output = hyst_shaping {
        kind: HYST_SHAPING_AFFINE,
        p: [2.02, 0.3, 0.0, 0.0, 0.0, 0.0],
        pre_gain: 1.0,
        pre_offset: 0.0,
        post_gain: 1.5,
        post_offset: -0.2,
    };
    p
}

fn core_model() -> ShapedModel<f64, ScaledShaping<f64>, hyst_core::AnyK2Law<f64>, ScaledShaping<f64>>
{
    let input = ScaledShaping::new(
        0.5,
        0.1,
        AnyShaping::Polynomial(Polynomial::new([0.0, 1.0, -0.098, 0.0], -5.0, 5.0).unwrap()),
        1.0,
        0.0,
    )
    .unwrap();
    let output = ScaledShaping::new(
        1.0,
        0.0,
        AnyShaping::Affine(Affine::new(2.02, 0.3).unwrap()),
        1.5,
        -0.2,
    )
    .unwrap();
    let law = hyst_core::AnyK2Law::Constant { value: 8.0 };
    ShapedModel::new(input, Hysteresis::with_k2_law(0.105, law).unwrap(), output).unwrap()
}

#[test]
fn shaped_model_and_its_inverse_equal_the_core() {
    let p = params();
    let mut m: hyst_shaped_model = zeroed();
    let mut inv: hyst_shaped_model = zeroed();
    unsafe {
        assert_eq!(hyst_shaped_model_init_direct(&mut m, &p), HYST_OK);
        assert_eq!(hyst_shaped_model_init_inverse(&mut inv, &p), HYST_OK);
    }
    let mut core = core_model();
    let mut core_inv = core.inverse();
    for k in 0..1500 {
        let x = 2.0 * signal(k);
        let (mut y, mut c) = (0.0, 0.0);
        unsafe {
            assert_eq!(hyst_shaped_model_step(&mut m, x, &mut y), HYST_OK);
            assert_eq!(hyst_shaped_model_step(&mut inv, y, &mut c), HYST_OK);
        }
        assert_eq!(y.to_bits(), core.step(x).to_bits());
        assert_eq!(c.to_bits(), core_inv.step(y).to_bits());
    }
    // Bad parameters are named by their status.
    let mut bad = p;
    bad.input.p = [0.0, 1.0, -0.098, 0.0, 0.0, 6.0]; // turns at 5.1: not monotone
    bad.input.pre_gain = 1.0;
    bad.input.pre_offset = 0.0;
    let mut other = params();
    other.output.kind = 42;
    unsafe {
        assert_eq!(
            hyst_shaped_model_init_direct(&mut m, &bad),
            HYST_ERR_NOT_MONOTONE
        );
        assert_eq!(
            hyst_shaped_model_init_direct(&mut m, &other),
            HYST_ERR_INVALID_PARAMETER
        );
        assert_eq!(
            hyst_shaped_model_init_direct(&mut m, ptr::null()),
            HYST_ERR_NULL_POINTER
        );
    }
    // Identity shaping from a zeroed struct needs its gains: refused, not silently 0.
    let mut zero_gain = params();
    zero_gain.input.kind = HYST_SHAPING_IDENTITY;
    zero_gain.input.pre_gain = 0.0;
    unsafe {
        assert_eq!(
            hyst_shaped_model_init_direct(&mut m, &zero_gain),
            HYST_ERR_INVALID_PARAMETER
        )
    };
}

#[test]
fn compensator_equals_the_core_lemma_5_1() {
    let p = params();
    let a = [0.9, 1.0];
    let v0 = [0.2, 0.0];
    let mut c: hyst_shaped_compensator = zeroed();
    unsafe {
        assert_eq!(
            hyst_shaped_compensator_init(&mut c, &p, 1.0, a.as_ptr(), v0.as_ptr(), 2),
            HYST_OK
        )
    };
    // The C API runs the core's Compensator<_, 4> with n = 2 chosen at run time: bit for bit.
    let mut core = Compensator::<f64, 4, _, _, _>::with_order(core_model().inverse(), 1.0, &a)
        .unwrap()
        .with_state([0.2, 0.0, 0.0, 0.0])
        .unwrap();
    // The const-order Compensator<_, 2> agrees to rounding: the shaping's Newton inverse on a
    // jet takes one step per order, so order 4 may move the last bit.
    let mut core2 = Compensator::from_shaped_model(&core_model(), 1.0, a)
        .unwrap()
        .with_state(v0)
        .unwrap();
    for k in 0..3000 {
        let u_new = (k as f64 * 0.004).sin() * 2.0;
        let mut u = 0.0;
        unsafe {
            assert_eq!(
                hyst_shaped_compensator_step(&mut c, u_new, 1e-3, &mut u),
                HYST_OK
            )
        };
        assert_eq!(u.to_bits(), core.step(u_new, 1e-3).to_bits(), "{k}");
        let u2 = core2.step(u_new, 1e-3);
        assert!(
            (u - u2).abs() <= 1e-12 * (1.0 + u2.abs()),
            "{k}: {u} vs {u2}"
        );
    }
    let mut v = [0.0; 2];
    unsafe {
        assert_eq!(
            hyst_shaped_compensator_get_state(&mut c, v.as_mut_ptr(), ptr::null_mut()),
            HYST_OK
        )
    };
    assert_eq!(&v[..], &core.state()[..2]);
    // Reference mode, reset, bad input.
    let reference = [0.3, 0.5, -0.1];
    let mut u = 0.0;
    unsafe {
        assert_eq!(
            hyst_shaped_compensator_track(&mut c, reference.as_ptr(), &mut u),
            HYST_OK
        );
        assert_eq!(
            u.to_bits(),
            core.track(Jet::from_derivatives(0.3, [0.5, -0.1, 0.0, 0.0]))
                .unwrap()
                .to_bits()
        );
        assert_eq!(hyst_shaped_compensator_reset(&mut c), HYST_OK);
        assert_eq!(
            hyst_shaped_compensator_get_state(&mut c, v.as_mut_ptr(), ptr::null_mut()),
            HYST_OK
        );
        assert_eq!(v, v0);
        assert_eq!(
            hyst_shaped_compensator_step(&mut c, f64::NAN, 1e-3, &mut u),
            HYST_ERR_NON_FINITE
        );
        assert_eq!(u, 0.0); // the held command: 0 after a reset
        assert_eq!(
            hyst_shaped_compensator_init(&mut c, &p, 0.0, a.as_ptr(), ptr::null(), 2),
            HYST_ERR_INVALID_PARAMETER
        );
        assert_eq!(
            hyst_shaped_compensator_init(&mut c, &p, 1.0, a.as_ptr(), ptr::null(), 5),
            HYST_ERR_LENGTH
        );
        assert_eq!(
            hyst_shaped_compensator_init(&mut c, &p, 1.0, ptr::null(), ptr::null(), 2),
            HYST_ERR_NULL_POINTER
        );
        assert_eq!(
            hyst_shaped_compensator_init(&mut c, &p, 1.0, ptr::null(), ptr::null(), 0),
            HYST_OK
        );
    }
}

#[test]
fn plain_compensator_equals_the_core_and_the_shaped_one_with_identity_shaping() {
    let a = [0.9, 1.0];
    let mut plain: hyst_compensator = zeroed();
    let mut shaped: hyst_shaped_compensator = zeroed();
    let mut p: hyst_shaped_model_params = zeroed();
    p.k1 = 0.2;
    p.k2.value = 8.0;
    for s in [&mut p.input, &mut p.output] {
        s.kind = HYST_SHAPING_IDENTITY;
        s.pre_gain = 1.0;
        s.post_gain = 1.0;
    }
    unsafe {
        assert_eq!(
            hyst_compensator_init(&mut plain, 0.2, 8.0, 1.0, a.as_ptr(), ptr::null(), 2),
            HYST_OK
        );
        assert_eq!(
            hyst_shaped_compensator_init(&mut shaped, &p, 1.0, a.as_ptr(), ptr::null(), 2),
            HYST_OK
        );
        assert_eq!(
            hyst_compensator_init(&mut plain, 0.0, 8.0, 1.0, a.as_ptr(), ptr::null(), 2),
            HYST_ERR_INVALID_PARAMETER
        );
        assert_eq!(
            hyst_compensator_init(&mut plain, 0.2, 8.0, 1.0, a.as_ptr(), ptr::null(), 5),
            HYST_ERR_LENGTH
        );
        let mut other: hyst_compensator = zeroed();
        assert_eq!(
            hyst_compensator_step(&mut other, 0.0, 1e-3, &mut 0.0),
            HYST_ERR_NOT_INITIALISED
        );
    }
    let model = ShapedModel::new(
        hyst_core::Identity,
        Hysteresis::new(0.2, 8.0).unwrap(),
        hyst_core::Identity,
    )
    .unwrap();
    let mut core = Compensator::from_shaped_model(&model, 1.0, a).unwrap();
    for k in 0..3000 {
        let u_new = 2.0 * (k as f64 * 0.004).sin();
        let (mut u, mut w) = (0.0, 0.0);
        unsafe {
            assert_eq!(
                hyst_compensator_step(&mut plain, u_new, 1e-3, &mut u),
                HYST_OK
            );
            assert_eq!(
                hyst_shaped_compensator_step(&mut shaped, u_new, 1e-3, &mut w),
                HYST_OK
            );
        }
        assert_eq!(u.to_bits(), core.step(u_new, 1e-3).to_bits(), "{k}");
        assert_eq!(u.to_bits(), w.to_bits(), "{k}");
    }
}

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
        assert_eq!(hyst_model_clamped(m, &mut count), HYST_OK);
        assert_eq!(count, beyond as u64);
        assert_eq!(
            hyst_model_clamped(m, ptr::null_mut()),
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
        assert_eq!(hyst_model_clamped(m, &mut count), HYST_OK);
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
                assert_eq!(hyst_model_clamped(m, &mut count), HYST_OK);
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
