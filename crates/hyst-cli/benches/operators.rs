//! Criterion benchmarks: ns per sample of the operators and of the yardsticks `exp` and
//! `lambert_w0`, measured in one process (`cargo bench -p hyst-cli`). Divide the reported time
//! by `SAMPLES` (4096) for ns per sample; `hyst bench` prints that directly.
#![allow(missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion, Throughput};

#[path = "../src/workloads.rs"]
#[allow(dead_code)]
mod workloads;

fn operators(c: &mut Criterion) {
    let inputs = workloads::Inputs::new();
    let mut group = c.benchmark_group("per_sample");
    group.throughput(Throughput::Elements(workloads::SAMPLES as u64));
    for (index, (_, key)) in workloads::NAMES.iter().enumerate() {
        group.bench_function(key.trim_end_matches("_ns"), |b| {
            b.iter(|| inputs.run(index))
        });
    }
    group.finish();
}

criterion_group!(benches, operators);
criterion_main!(benches);
