//! Criterion benchmarks: ns per sample of the operators and of the yardsticks `exp` and
//! `lambert_w0`, banks of 1,024 operators, and the plain-C peer of the inverse, measured in one
//! process (`cargo bench -p hyst-bench --bench operators`). Divide the reported time by the
//! workload's samples per call (`SAMPLES` = 4096; 1024 × 64 channel-samples for the banks) for
//! ns per sample; `hyst bench` and `hyst-bench` print that directly.
#![allow(missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use hyst_bench::peer::{PeerComparison, PEER_NAME};
use hyst_bench::workloads::{Inputs, Suite, NAMES};

fn operators(c: &mut Criterion) {
    let inputs = Inputs::new();
    let peer = PeerComparison::new();
    let mut group = c.benchmark_group("per_sample");
    for (index, (_, key)) in NAMES.iter().enumerate() {
        group.throughput(Throughput::Elements(inputs.samples(index) as u64));
        group.bench_function(key.trim_end_matches("_ns"), |b| {
            b.iter(|| inputs.run(index))
        });
    }
    // The peer, workload 1 of the comparison.
    group.throughput(Throughput::Elements(peer.samples(1) as u64));
    group.bench_function(PEER_NAME.1.trim_end_matches("_ns"), |b| {
        b.iter(|| peer.run(1))
    });
    group.finish();
}

criterion_group!(benches, operators);
criterion_main!(benches);
