//! A small harness for instruction counts of the plain operator step (run it under
//! `valgrind --tool=callgrind`): `cargo run --release -p hyst-core --example step_cost -- WORKLOAD`
//! with WORKLOAD one of `direct64`, `inverse64`, `direct32`, `inverse32`, `none` (the input
//! generation alone, to subtract). 100,000 samples of a sine with decaying amplitude (minor loops).

use std::hint::black_box;

use hyst_core::{Hysteresis, InverseHysteresis, Operator};

const SAMPLES: usize = 100_000;

fn input(k: usize) -> f64 {
    let t = k as f64 * 1e-3;
    (1.0 + 0.5 * (0.37 * t).sin()) * (6.0 * t).sin()
}

fn main() -> Result<(), hyst_core::Error> {
    let which = std::env::args().nth(1).unwrap_or_default();
    let mut acc = 0.0_f64;
    match which.as_str() {
        "direct64" => {
            let mut h = Hysteresis::new(0.14_f64, 8.0)?;
            for k in 0..SAMPLES {
                acc += h.step(black_box(input(k)));
            }
        }
        "inverse64" => {
            let mut h = InverseHysteresis::new(0.14_f64, 8.0)?;
            for k in 0..SAMPLES {
                acc += h.step(black_box(input(k)));
            }
        }
        "direct32" => {
            let mut h = Hysteresis::new(0.14_f32, 8.0)?;
            for k in 0..SAMPLES {
                acc += f64::from(h.step(black_box(input(k) as f32)));
            }
        }
        "inverse32" => {
            let mut h = InverseHysteresis::new(0.14_f32, 8.0)?;
            for k in 0..SAMPLES {
                acc += f64::from(h.step(black_box(input(k) as f32)));
            }
        }
        _ => {
            for k in 0..SAMPLES {
                acc += black_box(input(k));
            }
        }
    }
    println!("{acc}");
    Ok(())
}
