//! Criterion benchmark of the exhaustive check: one whole level, so the time
//! per face (`time / face_count`) is what `micromap-lab prove` pays.
//!
//! `cargo bench --bench prove`; the machine's load skews it, note `uptime`.

// `criterion_group!` generates undocumented public functions.
#![allow(missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use micromap_index::Level;
use micromap_index_lab::lattice::face_count;
use micromap_index_lab::prove::{prove_level, Progress, Reference, Settings};

/// Level 11: 12,589,057 faces, long enough to time, short enough to repeat.
const LEVEL: u32 = 11;

fn bench_prove(c: &mut Criterion) {
    let level = Level::new(LEVEL).expect("level 11 exists");
    let mut group = c.benchmark_group("prove");
    group.throughput(Throughput::Elements(face_count(level) as u64));
    group.sample_size(20);
    for (name, reference, threads) in [
        ("spec/1-thread", Reference::Spec, 1),
        ("spec-wide/1-thread", Reference::SpecWide, 1),
        ("spec/all-threads", Reference::Spec, 0),
    ] {
        let settings = Settings {
            reference,
            threads,
            ..Settings::default()
        };
        group.bench_function(format!("level-{LEVEL}/{name}"), |b| {
            b.iter(|| {
                let report =
                    prove_level(level, &settings, &Progress::new()).expect("level in range");
                assert!(report.is_proof());
                report
            });
        });
    }
    group.finish();
}

criterion_group!(benches, bench_prove);
criterion_main!(benches);
