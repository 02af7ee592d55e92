//! The banks of the C API (`hyst_bank_*`, `hyst_bank_*_f32`) called as C would call them: each
//! channel agrees with the scalar operator within the stated tolerance, errors name the
//! channel and leave every memory as it was, memories move between a bank and an operator, and
//! bad arguments give a status.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)]
// The tests call the C API through raw pointers, as a C program does.
#![allow(unsafe_code)]

use std::ptr;

use hyst::api_f64::*;
use hyst::bank_f32::*;
use hyst::bank_f64::*;
use hyst::status::*;
use hyst_core::{InverseHysteresis, Operator};

const CHANNELS: usize = 37;

fn k1(c: usize) -> f64 {
    0.05 + 0.01 * c as f64
}

fn k2(c: usize) -> f64 {
    2.0 + 0.5 * c as f64
}

fn x(t: usize, c: usize) -> f64 {
    let s = t as f64 * 0.02;
    (0.3 + 0.02 * c as f64) * (s * (1.0 + 0.1 * c as f64)).sin() + 0.1 * (3.1 * s).cos()
}

/// The bank's stated agreement with the scalar operator: |Δy| ≤ tol · max(|y|, k1).
fn close(bank: f64, scalar: f64, k1: f64, tol: f64) -> bool {
    (bank - scalar).abs() <= tol * scalar.abs().max(k1)
}

fn create(inverse: bool) -> *mut hyst_bank {
    let a: Vec<f64> = (0..CHANNELS).map(k1).collect();
    let b: Vec<f64> = (0..CHANNELS).map(k2).collect();
    let mut bank = ptr::null_mut();
    let mut channel = usize::MAX;
    let status = unsafe {
        hyst_bank_create(
            a.as_ptr(),
            b.as_ptr(),
            CHANNELS,
            i32::from(inverse),
            &mut bank,
            &mut channel,
        )
    };
    assert_eq!(status, HYST_OK);
    assert_eq!(channel, usize::MAX, "untouched on success");
    assert_eq!(unsafe { hyst_bank_channels(bank) }, CHANNELS);
    bank
}

#[test]
fn every_channel_agrees_with_the_scalar_operator_by_step_and_by_block() {
    for inverse in [false, true] {
        let stepped = create(inverse);
        let blocked = create(inverse);
        // The scalar operators of the C API (bit for bit the core's, tests/api.rs).
        let mut ops: Vec<hyst_operator> = (0..CHANNELS)
            .map(|c| {
                let mut op: hyst_operator = unsafe { std::mem::zeroed() };
                let s = unsafe {
                    if inverse {
                        hyst_operator_init_inverse(&mut op, k1(c), k2(c))
                    } else {
                        hyst_operator_init_direct(&mut op, k1(c), k2(c))
                    }
                };
                assert_eq!(s, HYST_OK);
                op
            })
            .collect();
        let ticks = 3000;
        let input: Vec<f64> = (0..ticks)
            .flat_map(|t| (0..CHANNELS).map(move |c| x(t, c)))
            .collect();
        let mut block = input.clone();
        // In place (y = x), in blocks of 500 ticks.
        for chunk in block.chunks_mut(500 * CHANNELS) {
            let n = chunk.len() / CHANNELS;
            let p = chunk.as_mut_ptr();
            let s = unsafe { hyst_bank_process(blocked, p, p, n, ptr::null_mut()) };
            assert_eq!(s, HYST_OK);
        }
        let mut moved = 0;
        let mut y = vec![0.0; CHANNELS];
        for t in 0..ticks {
            let row = &input[t * CHANNELS..(t + 1) * CHANNELS];
            let s =
                unsafe { hyst_bank_step(stepped, row.as_ptr(), y.as_mut_ptr(), ptr::null_mut()) };
            assert_eq!(s, HYST_OK);
            for c in 0..CHANNELS {
                let mut scalar = 0.0;
                let s = unsafe { hyst_operator_step(&mut ops[c], row[c], &mut scalar) };
                assert_eq!(s, HYST_OK);
                assert!(
                    close(y[c], scalar, k1(c), 1e-13),
                    "inverse {inverse} t {t} c {c}: {} vs {scalar}",
                    y[c]
                );
                assert_eq!(y[c], block[t * CHANNELS + c], "step and block agree");
                moved += usize::from(y[c] != row[c]);
            }
        }
        assert!(moved > ticks * CHANNELS / 2);
        unsafe {
            hyst_bank_free(stepped);
            hyst_bank_free(blocked);
        }
    }
}

#[test]
fn the_float_bank_agrees_with_the_float_operator() {
    let a: Vec<f32> = (0..CHANNELS).map(|c| k1(c) as f32).collect();
    let b: Vec<f32> = (0..CHANNELS).map(|c| k2(c) as f32).collect();
    let mut bank = ptr::null_mut();
    let s = unsafe {
        hyst_bank_create_f32(
            a.as_ptr(),
            b.as_ptr(),
            CHANNELS,
            1,
            &mut bank,
            ptr::null_mut(),
        )
    };
    assert_eq!(s, HYST_OK);
    let mut ops: Vec<InverseHysteresis<f32>> = (0..CHANNELS)
        .map(|c| InverseHysteresis::new(a[c], b[c]).unwrap())
        .collect();
    let mut y = vec![0.0f32; CHANNELS];
    for t in 0..2000 {
        let row: Vec<f32> = (0..CHANNELS).map(|c| x(t, c) as f32).collect();
        assert_eq!(
            unsafe { hyst_bank_step_f32(bank, row.as_ptr(), y.as_mut_ptr(), ptr::null_mut()) },
            HYST_OK
        );
        for c in 0..CHANNELS {
            let scalar = ops[c].try_step(row[c]).unwrap();
            // float: |Δy| ≤ 1e-5 · max(|y|, k1) (about 100 ulp of float).
            assert!(
                close(f64::from(y[c]), f64::from(scalar), f64::from(a[c]), 1e-5),
                "t {t} c {c}: {} vs {scalar}",
                y[c]
            );
        }
    }
    unsafe { hyst_bank_free_f32(bank) };
}

/// `create` with a bad parameter, no channels or NULLs: its status (naming the channel of the
/// bad parameter), and no bank.
#[test]
fn create_names_the_channel_of_a_bad_parameter() {
    let mut a: Vec<f64> = (0..CHANNELS).map(k1).collect();
    let b: Vec<f64> = (0..CHANNELS).map(k2).collect();
    a[11] = -1.0;
    let mut bank = ptr::dangling_mut::<hyst_bank>();
    let mut channel = 0;
    let s =
        unsafe { hyst_bank_create(a.as_ptr(), b.as_ptr(), CHANNELS, 0, &mut bank, &mut channel) };
    assert_eq!((s, channel), (HYST_ERR_INVALID_PARAMETER, 11));
    assert!(bank.is_null(), "*bank is NULL on failure");
    let s = unsafe { hyst_bank_create(a.as_ptr(), b.as_ptr(), 0, 0, &mut bank, &mut channel) };
    assert_eq!(s, HYST_ERR_LENGTH);
    let s = unsafe {
        hyst_bank_create(
            ptr::null(),
            b.as_ptr(),
            CHANNELS,
            0,
            &mut bank,
            &mut channel,
        )
    };
    assert_eq!(s, HYST_ERR_NULL_POINTER);
    let s = unsafe {
        hyst_bank_create(
            a.as_ptr(),
            b.as_ptr(),
            CHANNELS,
            0,
            ptr::null_mut(),
            &mut channel,
        )
    };
    assert_eq!(s, HYST_ERR_NULL_POINTER);
}

/// The memories of every channel of `bank`.
fn memories(bank: *mut hyst_bank) -> Vec<hyst_memory> {
    (0..CHANNELS)
        .map(|c| {
            let mut m = hyst_memory::default();
            assert_eq!(unsafe { hyst_bank_get_memory(bank, c, &mut m) }, HYST_OK);
            m
        })
        .collect()
}

/// A bank (no channel saturating) stepped once: the bank, the tick's inputs, its memories.
fn stepped_bank() -> (*mut hyst_bank, Vec<f64>, Vec<hyst_memory>) {
    let bank = create(false);
    let row: Vec<f64> = (0..CHANNELS).map(|c| x(5, c)).collect();
    let mut y = vec![0.0; CHANNELS];
    assert_eq!(
        unsafe { hyst_bank_step(bank, row.as_ptr(), y.as_mut_ptr(), ptr::null_mut()) },
        HYST_OK
    );
    let before = memories(bank);
    assert!(before.iter().all(|m| m.has_history == 1));
    (bank, row, before)
}

/// A refused sample of a block (a NaN, an output beyond the float range, a tick count beyond
/// any array) names its channel and leaves every memory as it was.
#[test]
fn refused_blocks_name_the_channel_and_leave_the_memories() {
    let (bank, _, before) = stepped_bank();
    let mut y = vec![0.0; CHANNELS];
    // A NaN on channel 29 of tick 2 of 3: nothing is processed.
    let mut block: Vec<f64> = (0..3 * CHANNELS)
        .map(|i| x(6 + i / CHANNELS, i % CHANNELS))
        .collect();
    block[2 * CHANNELS + 29] = f64::NAN;
    let mut out = vec![0.0; block.len()];
    let mut channel = 0;
    let s = unsafe { hyst_bank_process(bank, block.as_ptr(), out.as_mut_ptr(), 3, &mut channel) };
    assert_eq!((s, channel), (HYST_ERR_NON_FINITE, 29));
    assert_eq!(memories(bank), before);
    assert!(memories(bank) == before, "memories changed");
    // An output beyond the float range on channel 1 (k1 = 4e307, the largest the core takes is
    // max/4): refused, every memory as
    // before the call.
    let (big_k1, big_k2) = ([0.2, 4e307], [8.0, 8.0]);
    let mut big = ptr::null_mut();
    unsafe {
        assert_eq!(
            hyst_bank_create(
                big_k1.as_ptr(),
                big_k2.as_ptr(),
                2,
                1,
                &mut big,
                ptr::null_mut()
            ),
            HYST_OK
        );
        assert_eq!(
            hyst_bank_step(big, [0.0, 0.0].as_ptr(), y.as_mut_ptr(), ptr::null_mut()),
            HYST_OK
        );
    }
    let mut first = hyst_memory::default();
    assert_eq!(unsafe { hyst_bank_get_memory(big, 1, &mut first) }, HYST_OK);
    let ticks = [0.1, 0.1, 0.2, 1.5e308];
    let s = unsafe { hyst_bank_process(big, ticks.as_ptr(), out.as_mut_ptr(), 2, &mut channel) };
    assert_eq!((s, channel), (HYST_ERR_OVERFLOW, 1));
    let mut after = hyst_memory::default();
    assert_eq!(unsafe { hyst_bank_get_memory(big, 1, &mut after) }, HYST_OK);
    assert_eq!(after, first);
    unsafe { hyst_bank_free(big) };
    // A tick count whose values would take more bytes than any array holds (channels × ticks
    // itself does not overflow): a length error, checked before a slice is made of it (it
    // panicked in an allocation and was reported as an internal error).
    let s = unsafe {
        hyst_bank_process(
            bank,
            block.as_ptr(),
            out.as_mut_ptr(),
            usize::MAX / 8 / CHANNELS,
            &mut channel,
        )
    };
    assert_eq!(s, HYST_ERR_LENGTH);
    unsafe { hyst_bank_free(bank) };
}

/// Channels beyond the bank, NULLs and memories outside a channel's band: their statuses, and
/// the memories as they were.
#[test]
fn bad_channels_nulls_and_memories_are_refused() {
    let (bank, row, before) = stepped_bank();
    let mut y = vec![0.0; CHANNELS];
    // Channels beyond the bank, NULLs.
    let mut m = hyst_memory::default();
    assert_eq!(
        unsafe { hyst_bank_get_memory(bank, CHANNELS, &mut m) },
        HYST_ERR_LENGTH
    );
    assert_eq!(
        unsafe { hyst_bank_set_memory(bank, CHANNELS, &before[0]) },
        HYST_ERR_LENGTH
    );
    assert_eq!(
        unsafe { hyst_bank_get_memory(bank, 0, ptr::null_mut()) },
        HYST_ERR_NULL_POINTER
    );
    assert_eq!(
        unsafe { hyst_bank_get_memory(ptr::null_mut(), 0, &mut m) },
        HYST_ERR_NULL_POINTER
    );
    assert_eq!(
        unsafe { hyst_bank_step(bank, ptr::null(), y.as_mut_ptr(), ptr::null_mut()) },
        HYST_ERR_NULL_POINTER
    );
    assert_eq!(
        unsafe {
            hyst_bank_step(
                ptr::null_mut(),
                row.as_ptr(),
                y.as_mut_ptr(),
                ptr::null_mut(),
            )
        },
        HYST_ERR_NULL_POINTER
    );
    assert_eq!(
        unsafe { hyst_bank_process(bank, ptr::null(), ptr::null_mut(), 0, ptr::null_mut()) },
        HYST_OK
    );
    assert_eq!(
        unsafe {
            hyst_bank_process(
                bank,
                row.as_ptr(),
                y.as_mut_ptr(),
                usize::MAX,
                ptr::null_mut(),
            )
        },
        HYST_ERR_LENGTH
    );
    assert_eq!(
        unsafe { hyst_bank_reset(ptr::null_mut()) },
        HYST_ERR_NULL_POINTER
    );
    assert_eq!(unsafe { hyst_bank_channels(ptr::null()) }, 0);
    // A memory outside channel 0's band, a non-finite one.
    let mut bad = before[0];
    bad.last_output = bad.last_input + 10.0 * k1(0);
    assert_eq!(
        unsafe { hyst_bank_set_memory(bank, 0, &bad) },
        HYST_ERR_STATE_OUTSIDE_BAND
    );
    bad.last_output = f64::NAN;
    assert_ne!(unsafe { hyst_bank_set_memory(bank, 0, &bad) }, HYST_OK);
    assert!(memories(bank) == before, "memories changed");
    unsafe { hyst_bank_free(bank) };
    unsafe { hyst_bank_free(ptr::null_mut()) };
}

#[test]
fn memories_move_between_a_bank_and_an_operator() {
    let bank = create(true);
    let mut y = vec![0.0; CHANNELS];
    for t in 0..400 {
        let row: Vec<f64> = (0..CHANNELS).map(|c| x(t, c)).collect();
        assert_eq!(
            unsafe { hyst_bank_step(bank, row.as_ptr(), y.as_mut_ptr(), ptr::null_mut()) },
            HYST_OK
        );
    }
    // Channel 7 continues in a scalar operator from the bank's memory, and channel 8 of the
    // bank continues from channel 7's memory: the same outputs (within the tolerance).
    let mut m = hyst_memory::default();
    assert_eq!(unsafe { hyst_bank_get_memory(bank, 7, &mut m) }, HYST_OK);
    let mut op: hyst_operator = unsafe { std::mem::zeroed() };
    unsafe {
        assert_eq!(hyst_operator_init_inverse(&mut op, k1(7), k2(7)), HYST_OK);
        assert_eq!(hyst_operator_set_memory(&mut op, &m), HYST_OK);
    }
    let k = [k1(7); CHANNELS];
    let kk = [k2(7); CHANNELS];
    let mut twin = ptr::null_mut();
    unsafe {
        assert_eq!(
            hyst_bank_create(
                k.as_ptr(),
                kk.as_ptr(),
                CHANNELS,
                1,
                &mut twin,
                ptr::null_mut()
            ),
            HYST_OK
        );
        assert_eq!(hyst_bank_set_memory(twin, 8, &m), HYST_OK);
    }
    let mut y2 = vec![0.0; CHANNELS];
    for t in 400..800 {
        let row: Vec<f64> = (0..CHANNELS).map(|c| x(t, c)).collect();
        let mut shifted = row.clone();
        shifted[8] = row[7];
        unsafe {
            assert_eq!(
                hyst_bank_step(bank, row.as_ptr(), y.as_mut_ptr(), ptr::null_mut()),
                HYST_OK
            );
            assert_eq!(
                hyst_bank_step(twin, shifted.as_ptr(), y2.as_mut_ptr(), ptr::null_mut()),
                HYST_OK
            );
        }
        let mut scalar = 0.0;
        assert_eq!(
            unsafe { hyst_operator_step(&mut op, row[7], &mut scalar) },
            HYST_OK
        );
        assert!(
            close(y[7], scalar, k1(7), 1e-13),
            "t {t}: {} vs {scalar}",
            y[7]
        );
        assert_eq!(y2[8], y[7], "t {t}");
    }
    // Reset: back on the line output = input.
    unsafe { hyst_bank_reset(bank) };
    let mut m = hyst_memory::default();
    assert_eq!(unsafe { hyst_bank_get_memory(bank, 0, &mut m) }, HYST_OK);
    assert_eq!(m.has_history, 0);
    unsafe {
        hyst_bank_free(bank);
        hyst_bank_free(twin);
    }
}
