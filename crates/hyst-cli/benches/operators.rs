//! Criterion benchmarks: ns per sample of the operators and of the yardsticks `exp` and
//! `lambert_w0`, and banks of 1,024 operators, measured in one process (`cargo bench -p
//! hyst-cli`). Divide the reported time by the workload's samples per call (`SAMPLES` = 4096;
//! 1024 × 64 channel-samples for the banks) for ns per sample; `hyst bench` prints that directly.
#![allow(missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion, Throughput};

#[path = "../src/workloads.rs"]
mod workloads;

fn operators(c: &mut Criterion) {
    let inputs = workloads::Inputs::new();
    let mut group = c.benchmark_group("per_sample");
    for (index, (_, key)) in workloads::NAMES.iter().enumerate() {
        // A workload that forces a kernel this processor lacks is not measured (`hyst bench`
        // reports it as null).
        if !inputs.available(index) {
            continue;
        }
        group.throughput(Throughput::Elements(inputs.samples(index) as u64));
        group.bench_function(key.trim_end_matches("_ns"), |b| {
            b.iter(|| inputs.run(index))
        });
    }
    group.finish();
}

criterion_group!(benches, operators);
criterion_main!(benches);
