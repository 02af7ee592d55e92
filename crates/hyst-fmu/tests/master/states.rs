//! FMU states: copies and their serialised form resume bit for bit; corrupted serialised
//! states are refused.

use super::*;
use crate::harness::*;

/// Saves the state after `xs[..split]`, runs the rest, restores and runs it again, then
/// serialises the state, reads it into `other` (another instance of the same FMU, in step mode)
/// and runs the rest there: the three runs are the same bits.
fn check_state_round_trip(fmu: &Fmu, other: &Fmu, xs: &[f64], split: usize) {
    fmu.run(&xs[..split]);
    let saved = fmu.get_state();
    let first = fmu.run(&xs[split..]);
    assert_eq!(fmu.set_state(saved), OK);
    assert_eq!(fmu.get(VR_X), Ok(xs[split - 1]));
    assert_eq!(bits(&fmu.run(&xs[split..])), bits(&first));
    let bytes = fmu.serialize(saved);
    other.run(&xs[..17]); // whatever it did before is replaced
    let restored = other.deserialize(&bytes).unwrap();
    assert_eq!(other.set_state(restored), OK);
    assert_eq!(bits(&other.run(&xs[split..])), bits(&first));
    // The same state serialises to the same bytes in the other instance.
    assert_eq!(other.serialize(restored), bytes);
    // fmi2GetFMUstate into an existing state overwrites it.
    let mut handle = saved;
    assert_eq!(unsafe { fmi2GetFMUstate(fmu.c, &mut handle) }, OK);
    assert_eq!(handle, saved);
    assert_ne!(fmu.serialize(saved), bytes);
    // Freed: NULL, and no longer accepted.
    let mut handle = saved;
    assert_eq!(unsafe { fmi2FreeFMUstate(fmu.c, &mut handle) }, OK);
    assert!(handle.is_null());
    assert_eq!(unsafe { fmi2FreeFMUstate(fmu.c, &mut handle) }, OK); // NULL is ignored
    assert_eq!(fmu.set_state(saved), ERROR);
    fmu.expect_error(&["fmi2SetFMUstate", "not one of this instance"]);
    // A state of another instance is not accepted either (it is never dereferenced).
    assert_eq!(fmu.set_state(restored), ERROR);
    fmu.expect_error(&["not one of this instance"]);
    assert!(other.errors().is_empty());
}

#[test]
fn fmu_states_and_their_serialisation_resume_bit_for_bit() {
    let xs: Vec<f64> = (0..1200).map(signal).collect();
    for inverse in [false, true] {
        let dir = operator_resources(inverse, 0.2, 8.0);
        let (a, b) = (Fmu::started(dir.path()), Fmu::started(dir.path()));
        check_state_round_trip(&a, &b, &xs, 613);
    }
    for file in [fitted_model(), pi_model()] {
        for inverse in [false, true] {
            let dir = model_resources(&file, inverse);
            let (a, b) = (Fmu::started(dir.path()), Fmu::started(dir.path()));
            check_state_round_trip(&a, &b, &xs, 613);
        }
    }
}

#[test]
fn states_before_the_first_step_and_across_modes() {
    let dir = operator_resources(false, 0.2, 8.0);
    let fmu = Fmu::instantiate(dir.path());
    // A state of the Instantiated mode, with a parameter set, restores k1 and x.
    assert_eq!(fmu.set(VR_K1, 0.35), OK);
    assert_eq!(fmu.set(VR_X, 0.5), OK);
    let early = fmu.get_state();
    let early_bytes = fmu.serialize(early);
    assert_eq!(fmu.set(VR_K1, 0.9), OK);
    assert_eq!(fmu.set_state(early), OK);
    fmu.initialise();
    assert_eq!(fmu.get(VR_K1), Ok(0.35));
    let xs: Vec<f64> = (0..300).map(signal).collect();
    let ys = fmu.run(&xs);
    assert_eq!(
        bits(&ys),
        bits(&core_run(Hysteresis::new(0.35, 8.0).unwrap(), &xs))
    );
    let late = fmu.get_state();
    let late_bytes = fmu.serialize(late);
    // In step mode, the early state (no history) starts over.
    assert_eq!(fmu.set_state(early), OK);
    assert_eq!(bits(&fmu.run(&xs)), bits(&ys));
    // A fresh instance in Instantiated reads the late state but cannot restore a history yet.
    let other = Fmu::instantiate(dir.path());
    let late_other = other.deserialize(&late_bytes).unwrap();
    assert_eq!(other.set_state(late_other), ERROR);
    other.expect_error(&["fmi2SetFMUstate", "history", "Instantiated"]);
    let early_other = other.deserialize(&early_bytes).unwrap();
    assert_eq!(other.set_state(early_other), OK);
    other.initialise();
    assert_eq!(other.set_state(late_other), OK);
    let more: Vec<f64> = (300..600).map(signal).collect();
    let all: Vec<f64> = xs.iter().chain(&more).copied().collect();
    let reference = core_run(Hysteresis::new(0.35, 8.0).unwrap(), &all);
    assert_eq!(bits(&other.run(&more)), bits(&reference[300..]));
    // A state with a NaN input lives in memory but is not serialised.
    assert_eq!(fmu.set(VR_X, f64::NAN), OK);
    let nan = fmu.get_state();
    let mut size = 0;
    assert_eq!(
        unsafe { fmi2SerializedFMUstateSize(fmu.c, nan, &mut size) },
        ERROR
    );
    fmu.expect_error(&["cannot be serialised", "x = NaN"]);
    assert_eq!(fmu.set_state(late), OK);
    assert_eq!(bits(&fmu.run(&more)), bits(&reference[300..]));
}

/// Re-seals edited bytes with a correct checksum (so the deeper checks are reached).
fn reseal(bytes: &mut [u8]) {
    let n = bytes.len() - 8;
    let sum = fnv1a64(&bytes[..n]);
    bytes[n..].copy_from_slice(&sum.to_le_bytes());
}

/// `bytes` changed by `change`, then resealed (its checksum made right again).
fn resealed(bytes: &[u8], change: impl FnOnce(&mut Vec<u8>)) -> Vec<u8> {
    let mut b = bytes.to_vec();
    change(&mut b);
    reseal(&mut b);
    b
}

fn with_f64(bytes: &[u8], offset: usize, value: f64) -> Vec<u8> {
    resealed(bytes, |b| {
        b[offset..offset + 8].copy_from_slice(&value.to_le_bytes());
    })
}

/// An operator FMU (k1 = 0.2, k2 = 8) started and run over the first 400 samples of 800 of
/// [`signal`]: its resources, the instance, the samples, its state and that state serialised.
fn serialised_midway() -> (tempfile::TempDir, Fmu, Vec<f64>, fmi2FMUstate, Vec<u8>) {
    let dir = operator_resources(false, 0.2, 8.0);
    let fmu = Fmu::started(dir.path());
    let xs: Vec<f64> = (0..800).map(signal).collect();
    fmu.run(&xs[..400]);
    let state = fmu.get_state();
    let bytes = fmu.serialize(state);
    (dir, fmu, xs, state, bytes)
}

#[test]
fn corrupted_serialised_states_are_refused() {
    let (_dir, fmu, xs, _, bytes) = serialised_midway();
    // Layout (see hyst_fmu::state): header 24, x 24, time 32, k1 40, k2 48, memory 56:
    // reversal input 56, reversal output 64, last input 72, last output 80, direction 88;
    // checksum 89..97.
    assert_eq!(bytes.len(), 97);
    assert_eq!(&bytes[..8], b"hystFMUs");
    assert_eq!(
        f64::from_le_bytes(bytes[24..32].try_into().unwrap()),
        xs[399]
    );
    assert_eq!(f64::from_le_bytes(bytes[40..48].try_into().unwrap()), 0.2);
    let last_input = f64::from_le_bytes(bytes[72..80].try_into().unwrap());
    assert_eq!(last_input, xs[399]);
    let refuse = |b: &[u8], parts: &[&str]| {
        assert_eq!(fmu.deserialize(b), Err(ERROR));
        fmu.expect_error(&[&["fmi2DeSerializeFMUstate"][..], parts].concat());
    };
    // Every truncation, and one byte more.
    for n in 0..bytes.len() {
        assert_eq!(fmu.deserialize(&bytes[..n]), Err(ERROR), "{n} bytes");
    }
    fmu.errors();
    refuse(&resealed(&bytes, |b| b.insert(90, 0)), &["length"]);
    // The magic and the checksum, not resealed.
    let mut b = bytes.clone();
    b[0] = b'X';
    refuse(&b, &["magic"]);
    let mut b = bytes.clone();
    b[60] ^= 0x10;
    refuse(&b, &["checksum"]);
    let version_2 = |b: &mut Vec<u8>| b[8..12].copy_from_slice(&2u32.to_le_bytes());
    refuse(&resealed(&bytes, version_2), &["version 2"]);
    refuse(&resealed(&bytes, |b| b[12] ^= 1), &["another FMU"]);
    refuse(&resealed(&bytes, |b| b[20] = 1), &["kind"]);
    refuse(&resealed(&bytes, |b| b[21] = 1), &["inverse"]);
    refuse(&resealed(&bytes, |b| b[88] = 2), &["direction = 2"]);
    refuse(&with_f64(&bytes, 24, f64::NAN), &["x = NaN"]);
    refuse(&with_f64(&bytes, 56, f64::NAN), &["reversal input = NaN"]);
    refuse(&with_f64(&bytes, 32, f64::INFINITY), &["time = inf"]);
    refuse(&with_f64(&bytes, 40, -0.2), &["k1 = -0.2"]);
    // A memory outside the band |output - input| <= k1, refused by the core's set_memory.
    refuse(
        &with_f64(&bytes, 80, last_input + 0.5),
        &["outside the band"],
    );
    // Nothing of this changed the instance.
    let ys = fmu.run(&xs[400..]);
    let reference = core_run(Hysteresis::new(0.2, 8.0).unwrap(), &xs);
    assert_eq!(bits(&ys), bits(&reference[400..]));
    assert!(fmu.deserialize(&bytes).is_ok());
}

/// A PI model's state in the operator FMU is of another kind; a NaN play is refused by the PI
/// FMU, which takes its own state back.
#[test]
fn a_serialised_state_of_another_kind_or_with_a_nan_play_is_refused() {
    let (_dir, fmu, xs, _, bytes) = serialised_midway();
    let file = pi_model();
    let pi_dir = model_resources(&file, false);
    let pi = Fmu::started(pi_dir.path());
    pi.run(&xs[..50]);
    let pi_state = pi.get_state();
    let pi_bytes = pi.serialize(pi_state);
    assert_eq!(fmu.deserialize(&pi_bytes), Err(ERROR));
    fmu.expect_error(&["fmi2DeSerializeFMUstate", "kind"]);
    // The plays start after x, time, first (24 + 24) and n (4).
    assert_eq!(
        pi.deserialize(&with_f64(&pi_bytes, 52, f64::NAN)),
        Err(ERROR)
    );
    pi.expect_error(&["play output = NaN"]);
    assert!(pi.deserialize(&pi_bytes).is_ok());
    assert!(fmu.deserialize(&bytes).is_ok());
}

#[test]
fn null_pointers_and_short_buffers_of_the_state_functions_are_errors() {
    let (_dir, fmu, _, state, bytes) = serialised_midway();
    unsafe {
        assert_eq!(
            fmi2DeSerializeFMUstate(fmu.c, bytes.as_ptr().cast(), bytes.len(), ptr::null_mut()),
            ERROR
        );
        let mut s: fmi2FMUstate = ptr::null_mut();
        assert_eq!(
            fmi2DeSerializeFMUstate(fmu.c, ptr::null(), 97, &mut s),
            ERROR
        );
        assert_eq!(
            fmi2SerializeFMUstate(fmu.c, state, ptr::null_mut(), 97),
            ERROR
        );
        let mut small = [0 as fmi2Byte; 96];
        assert_eq!(
            fmi2SerializeFMUstate(fmu.c, state, small.as_mut_ptr(), 96),
            ERROR
        );
        assert_eq!(
            fmi2SerializedFMUstateSize(fmu.c, state, ptr::null_mut()),
            ERROR
        );
        assert_eq!(fmi2GetFMUstate(fmu.c, ptr::null_mut()), ERROR);
        let mut foreign = 0x1000 as fmi2FMUstate;
        assert_eq!(fmi2GetFMUstate(fmu.c, &mut foreign), ERROR);
    }
    let errors = fmu.errors();
    assert_eq!(errors.len(), 7, "{errors:?}");
}
