//! The operator H / H⁻¹ of the C API: its results equal the core's bit for bit (the `float` twin
//! follows the `double` one), derivatives and memories, and every bad argument returns its
//! status without touching anything.

use super::*;

pub(crate) fn signal(k: usize) -> f64 {
    let t = k as f64 * 0.03;
    (0.4 + 0.04 * t).min(1.3) * t.sin() + 0.25 * (2.9 * t).cos()
}

pub(crate) fn zeroed<T>() -> T {
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

/// An uninitialised block, invalid parameters and NULL pointers: their statuses, and the block
/// and the output untouched.
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
    }
}

/// A non-finite sample holds the last output and leaves the memory alone; `process` returns the
/// first refused sample's status and processes the rest; a derivative order out of range or a
/// NaN derivative writes nothing.
#[test]
fn refused_samples_hold_the_output_and_the_memory() {
    let mut op: hyst_operator = zeroed();
    let mut y = 7.0;
    unsafe {
        assert_eq!(hyst_operator_init_direct(&mut op, 0.2, 8.0), HYST_OK);
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
    }
}

/// A misaligned block is refused (a `float` one needs 8-byte alignment too), and a `float`
/// block is not a `double` one.
#[test]
fn misaligned_and_foreign_blocks_are_refused() {
    let mut y = 7.0;
    unsafe {
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
}

/// Every status has a message; an unknown one says so.
#[test]
fn every_status_has_a_message() {
    for status in 0..=13 {
        let text = unsafe { CStr::from_ptr(hyst_status_message(status)) };
        assert!(!text.to_bytes().is_empty());
    }
    let unknown = unsafe { CStr::from_ptr(hyst_status_message(-3)) };
    assert_eq!(unknown.to_str().unwrap(), "unknown status");
}
