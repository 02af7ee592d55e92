//! Criterion benchmark of issue 25's speed goal for the fit: a fit with `--dynamics 2` on
//! 100,000 samples costs at most 3 × the static fit of the same data (`cargo bench -p hyst-cli
//! --bench fit`; compare the two times of one run). The data: a multisine command through the
//! plant 4e-4 s² v̈ + 0.05 s v̇ + v = u (run by the model runtime's discretisation at 1 kHz),
//! then 2 H(0.1, 5)[v] with 0.1 % noise.
#![allow(missing_docs, clippy::expect_used)]

use criterion::{criterion_group, criterion_main, Criterion};
use hyst_core::{Hysteresis, InitialState, Operator};
use hyst_fit::identify::{identify, Request};
use hyst_fit::lm::Silent;
use hyst_fit::{Dataset, Record};
use hyst_model::{Columns, Dynamics, Provenance, Structure};

const SAMPLES: usize = 100_000;

fn data() -> Dataset {
    let h = 1e-3;
    let u: Vec<f64> = (0..SAMPLES)
        .map(|k| {
            let t = k as f64 * h;
            let tau = 2.0 * std::f64::consts::PI;
            1.0 + (0.8 * (tau * 0.7 * t).sin()
                + 0.5 * (tau * 3.1 * t + 1.0).sin()
                + 0.3 * (tau * 9.3 * t + 2.0).sin())
                * (t / 0.5).min(1.0)
        })
        .collect();
    let plant = Dynamics::new(1.0, &[0.05, 4e-4])
        .and_then(|d| d.discretise(h))
        .expect("a stable plant");
    let mut state = plant.at_rest(u[0]);
    let v: Vec<f64> = (0..SAMPLES)
        .map(|k| {
            if k == 0 {
                u[0]
            } else {
                plant.step(&mut state, u[k])
            }
        })
        .collect();
    let mut op = InitialState::Rising
        .start(Hysteresis::new(0.1, 5.0).expect("valid"), v[0])
        .expect("a start");
    let mut seed = 1_u64;
    let y: Vec<f64> = v
        .iter()
        .map(|x| {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            let noise = ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.014;
            2.0 * op.step(*x) + noise
        })
        .collect();
    let record = Record {
        id: 0,
        weight: hyst_fit::Weights::Unit(SAMPLES),
        rows: (0..SAMPLES).collect(),
        input: u.into(),
        output: y.into(),
        validation: false,
        continues: false,
        period: Some(hyst_model::TimeSteps::even(h)),
    };
    Dataset::from_records("bench", Columns::default(), vec![record])
}

fn fit(c: &mut Criterion) {
    let data = data();
    let mut group = c.benchmark_group("fit_100k");
    group.sample_size(10);
    for (name, dynamics) in [("static", 0_u8), ("dynamics_2", 2)] {
        let request = Request {
            structure: Structure {
                dynamics,
                ..Structure::default()
            },
            ..Request::default()
        };
        group.bench_function(name, |b| {
            b.iter(|| {
                identify(
                    &data,
                    &request,
                    &mut Silent,
                    &|| false,
                    Provenance::default(),
                )
                .expect("the fit")
            })
        });
    }
    group.finish();
}

criterion_group!(benches, fit);
criterion_main!(benches);
