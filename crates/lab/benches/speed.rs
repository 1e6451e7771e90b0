//! Every implementation of each operation side by side with the C reference,
//! per element, after asserting that they agree on the inputs being timed.
//!
//! `cargo bench -p micromap-index-lab --bench speed` (all groups), or a
//! filter such as `cargo bench -p micromap-index-lab --bench speed --
//! index_f32/`. Input sets (4096 points each):
//!
//! * `uniform`: uniform in the closed triangle;
//! * `near-lines`: lattice lines `k / 2^16` moved by up to 3 ulps;
//! * `subnormal`: half of the coordinates subnormal;
//! * `outside`: NaN, ±inf, negatives, values above 1, `u + v > 1`.
//!
//! Ratios between rows of one run are the result (`docs/performance.md`);
//! absolute times depend on the CPU and its load.

// Loops index `u`, `v` and `out` together, as a caller's loop over
// parallel arrays does.
#![allow(clippy::needless_range_loop)]
// `criterion_group!` generates undocumented public functions.
#![allow(missing_docs)]

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use micromap_index::batch::{self, Backend};
use micromap_index::internals::{exact_index_f32_ref, exact_index_f64_ref, micro_triangle_ref};
use micromap_index::{inverse, spec, uv2index, Level, SpecLevel};
use micromap_index_c_reference::spec_index;
use micromap_index_test_support::{step_ulps, SplitMix64 as Rng};
use std::hint::black_box;
use std::time::Duration;

const POINTS: usize = 4096;

/// Uniform in `[0, 1)` with 24 random bits.
fn unit(rng: &mut Rng) -> f32 {
    (rng.next_u64() >> 40) as f32 * 2f32.powi(-24)
}

/// A point of the closed triangle, uniform: reflect `(u, v)` with
/// `u + v > 1`; both sums are then exact tests on representable values.
fn uniform_point(rng: &mut Rng) -> (f32, f32) {
    let (u, v) = (unit(rng), unit(rng));
    if f64::from(u) + f64::from(v) > 1.0 {
        let (u, v) = (1.0 - u, 1.0 - v); // exact: u, v are multiples of 2^-24 in [0, 1)
        (u, v)
    } else {
        (u, v)
    }
}

struct Set {
    name: &'static str,
    u: Vec<f32>,
    v: Vec<f32>,
}

fn input_sets() -> Vec<Set> {
    let mut rng = Rng::new(2026);
    let mut sets = Vec::new();
    let mut make = |name, f: &mut dyn FnMut(&mut Rng) -> (f32, f32)| {
        let (u, v): (Vec<f32>, Vec<f32>) = (0..POINTS).map(|_| f(&mut rng)).unzip();
        sets.push(Set { name, u, v });
    };
    make("uniform", &mut |rng| uniform_point(rng));
    make("near-lines", &mut |rng| {
        let line = |rng: &mut Rng| {
            let k = rng.below(1 << 16) as f32 * 2f32.powi(-16);
            step_ulps(k, rng.below(7) as i32 - 3)
        };
        let (u, v) = (line(rng), line(rng));
        if f64::from(u) + f64::from(v) > 1.0 {
            (v.min(1.0) * 0.5, u.min(1.0) * 0.5)
        } else {
            (u, v)
        }
    });
    make("subnormal", &mut |rng| {
        let sub = |rng: &mut Rng| f32::from_bits(rng.below(0x0080_0000) as u32);
        match rng.below(3) {
            0 => (sub(rng), sub(rng)),
            1 => (sub(rng), unit(rng)),
            _ => (unit(rng), sub(rng)),
        }
    });
    make("outside", &mut |rng| {
        let odd = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -0.25, 1.5, 1e30];
        match rng.below(3) {
            0 => (odd[rng.below(6) as usize], unit(rng)),
            1 => (unit(rng), odd[rng.below(6) as usize]),
            _ => (0.5 + 0.5 * unit(rng), 0.5 + 0.5 * unit(rng)),
        }
    });
    sets
}

/// The reference in binary32 at level 16: C, the port with a `u32` level
/// and with a validated [`SpecLevel`], the integer mirror, the one-point
/// kernel and every batch backend.
fn bench_index_f32(c: &mut Criterion) {
    let level_number = 16;
    let level = SpecLevel::new(level_number).unwrap();
    for set in input_sets() {
        let (u, v) = (&set.u, &set.v);
        let expected: Vec<u32> = (0..POINTS)
            .map(|i| spec_index(u[i], v[i], level_number))
            .collect();
        let mut out = vec![0u32; POINTS];
        // Agreement before timing.
        for i in 0..POINTS {
            assert_eq!(spec::index_f32(u[i], v[i], level), expected[i]);
            assert_eq!(
                spec::reference_bits_f32(u[i], v[i], level_number),
                expected[i]
            );
            assert_eq!(spec::index_f32_by_integers(u[i], v[i], level), expected[i]);
            assert_eq!(batch::index_f32_one(u[i], v[i], level), expected[i]);
        }
        for backend in Backend::available() {
            batch::index_f32_with(backend, u, v, level, &mut out).unwrap();
            assert_eq!(out, expected, "{backend} on {}", set.name);
        }

        let mut group = c.benchmark_group(format!("index_f32/{}", set.name));
        group.throughput(Throughput::Elements(POINTS as u64));
        group.bench_function("c-reference", |b| {
            b.iter(|| {
                let l = black_box(level_number);
                for i in 0..POINTS {
                    out[i] = spec_index(u[i], v[i], l);
                }
                black_box(&out);
            });
        });
        group.bench_function("spec::reference_bits_f32", |b| {
            b.iter(|| {
                let l = black_box(level_number);
                for i in 0..POINTS {
                    out[i] = spec::reference_bits_f32(u[i], v[i], l);
                }
                black_box(&out);
            });
        });
        group.bench_function("spec::index_f32", |b| {
            b.iter(|| {
                let l = black_box(level);
                for i in 0..POINTS {
                    out[i] = spec::index_f32(u[i], v[i], l);
                }
                black_box(&out);
            });
        });
        // The same calls in an iterator loop over the slices, the way a
        // caller's loop over parallel arrays usually reads: no bounds
        // checks, so the compiler may vectorise what it inlines.
        group.bench_function("c-reference (iterator loop)", |b| {
            b.iter(|| {
                let l = black_box(level_number);
                for ((o, &u), &v) in out.iter_mut().zip(u).zip(v) {
                    *o = spec_index(u, v, l);
                }
                black_box(&out);
            });
        });
        group.bench_function("spec::index_f32 (iterator loop)", |b| {
            b.iter(|| {
                let l = black_box(level);
                for ((o, &u), &v) in out.iter_mut().zip(u).zip(v) {
                    *o = spec::index_f32(u, v, l);
                }
                black_box(&out);
            });
        });
        group.bench_function("spec::index_f32_by_integers", |b| {
            b.iter(|| {
                let l = black_box(level);
                for i in 0..POINTS {
                    out[i] = spec::index_f32_by_integers(u[i], v[i], l);
                }
                black_box(&out);
            });
        });
        group.bench_function("batch::index_f32_one", |b| {
            b.iter(|| {
                let l = black_box(level);
                for i in 0..POINTS {
                    out[i] = batch::index_f32_one(u[i], v[i], l);
                }
                black_box(&out);
            });
        });
        for backend in Backend::available() {
            group.bench_function(format!("batch/{backend}"), |b| {
                b.iter(|| {
                    batch::index_f32_with(backend, black_box(u), v, level, &mut out).unwrap();
                    black_box(&out);
                });
            });
        }
        group.finish();
    }
}

/// The reference widened to 64 bits at level 24.
fn bench_wide_index_f32(c: &mut Criterion) {
    let level = Level::new(24).unwrap();
    for set in input_sets() {
        let (u, v) = (&set.u, &set.v);
        let expected: Vec<u64> = (0..POINTS)
            .map(|i| spec::wide_index_f32(u[i], v[i], level))
            .collect();
        let mut out = vec![0u64; POINTS];
        for backend in Backend::available() {
            batch::wide_index_f32_with(backend, u, v, level, &mut out).unwrap();
            assert_eq!(out, expected, "{backend} on {}", set.name);
        }
        let mut group = c.benchmark_group(format!("wide_index_f32/{}", set.name));
        group.throughput(Throughput::Elements(POINTS as u64));
        group.bench_function("spec::wide_index_f32", |b| {
            b.iter(|| {
                let l = black_box(level);
                for i in 0..POINTS {
                    out[i] = spec::wide_index_f32(u[i], v[i], l);
                }
                black_box(&out);
            });
        });
        for backend in Backend::available() {
            group.bench_function(format!("batch/{backend}"), |b| {
                b.iter(|| {
                    batch::wide_index_f32_with(backend, black_box(u), v, level, &mut out).unwrap();
                    black_box(&out);
                });
            });
        }
        group.finish();
    }
}

/// Exact answers for floats: the walk (oracle), the closed form
/// (`uv2index::exact_index_*`), the walk in f32 arithmetic, with the spec
/// port and C as the yardstick.
fn bench_exact(c: &mut Criterion) {
    let sets = input_sets();
    let uniform = &sets[0];
    let (u, v) = (&uniform.u, &uniform.v);
    let (u64s, v64s): (Vec<f64>, Vec<f64>) = u
        .iter()
        .zip(v)
        .map(|(&a, &b)| (f64::from(a), f64::from(b)))
        .unzip();
    let mut out = vec![0u64; POINTS];
    for level_number in [4u32, 8, 12, 16, 19, 24] {
        let level = Level::new(level_number).unwrap();
        for i in 0..POINTS {
            let walk = exact_index_f32_ref(u[i], v[i], level);
            assert!(walk.is_ok());
            assert_eq!(uv2index::exact_index_f32(u[i], v[i], level), walk);
            assert_eq!(uv2index::exact_index_f64(u64s[i], v64s[i], level), walk);
            assert_eq!(exact_index_f64_ref(u64s[i], v64s[i], level), walk);
        }
        let mut group = c.benchmark_group(format!("exact/level-{level_number}"));
        group.throughput(Throughput::Elements(POINTS as u64));
        if level_number <= 16 {
            group.bench_function("c-reference", |b| {
                b.iter(|| {
                    let l = black_box(level_number);
                    for i in 0..POINTS {
                        out[i] = u64::from(spec_index(u[i], v[i], l));
                    }
                    black_box(&out);
                });
            });
            let spec_level = SpecLevel::new(level_number).unwrap();
            group.bench_function("spec::index_f32", |b| {
                b.iter(|| {
                    let l = black_box(spec_level);
                    for i in 0..POINTS {
                        out[i] = u64::from(spec::index_f32(u[i], v[i], l));
                    }
                    black_box(&out);
                });
            });
        }
        // A macro, not a closure over `&dyn Fn`: each body is inlined into
        // its own loop, as in a caller's code (a dynamic call per element
        // would time the call and keep the level's setup in the loop).
        macro_rules! timed {
            ($name:expr, |$i:ident, $l:ident| $body:expr) => {
                group.bench_function($name, |b| {
                    b.iter(|| {
                        let $l = black_box(level);
                        for $i in 0..POINTS {
                            out[$i] = $body;
                        }
                        black_box(&out);
                    });
                });
            };
        }
        timed!("uv2index::exact_index_f32", |i, l| {
            uv2index::exact_index_f32(u[i], v[i], l).unwrap_or(u64::MAX)
        });
        timed!("uv2index::exact_index_f64", |i, l| {
            uv2index::exact_index_f64(u64s[i], v64s[i], l).unwrap_or(u64::MAX)
        });
        timed!("exact_index_f32_ref (walk)", |i, l| {
            exact_index_f32_ref(u[i], v[i], l).unwrap_or(u64::MAX)
        });
        timed!("exact_index_f64_ref (walk)", |i, l| {
            exact_index_f64_ref(u64s[i], v64s[i], l).unwrap_or(u64::MAX)
        });
        timed!("uv2index::index_in_f32_arithmetic", |i, l| {
            uv2index::index_in_f32_arithmetic(u[i], v[i], l).unwrap_or(u64::MAX)
        });
        group.finish();
    }
}

/// Index -> vertices: the walk replay against the closed-form inverse, on
/// random indices; and iterating over every micro-triangle of a level.
fn bench_inverse(c: &mut Criterion) {
    let mut rng = Rng::new(7);
    for level_number in [4u32, 10, 16, 32] {
        let level = Level::new(level_number).unwrap();
        let count = level.micro_triangle_count();
        let indices: Vec<u64> = (0..POINTS)
            .map(|_| (u128::from(rng.next_u64()) % count) as u64)
            .collect();
        for &i in &indices {
            let fast = inverse::micro_triangle(level, i).unwrap();
            let replay = micro_triangle_ref(level, i).unwrap();
            assert_eq!(fast, replay);
        }
        let mut group = c.benchmark_group(format!("inverse/level-{level_number}"));
        group.throughput(Throughput::Elements(POINTS as u64));
        group.bench_function("micro_triangle_ref (replay)", |b| {
            b.iter(|| {
                let mut sum = 0u64;
                for &i in &indices {
                    let t = micro_triangle_ref(black_box(level), i).unwrap();
                    sum = sum.wrapping_add(t.vertices_scaled()[2].0);
                }
                black_box(sum)
            });
        });
        group.bench_function("inverse::micro_triangle", |b| {
            b.iter(|| {
                let mut sum = 0u64;
                for &i in &indices {
                    let t = inverse::micro_triangle(black_box(level), i).unwrap();
                    sum = sum.wrapping_add(t.vertices_scaled()[2].0);
                }
                black_box(sum)
            });
        });
        group.finish();
    }
    for level_number in [8u32, 12] {
        let level = Level::new(level_number).unwrap();
        let count = 1u64 << (2 * level_number);
        for (i, t) in inverse::micro_triangles(level).enumerate() {
            assert_eq!(t, inverse::micro_triangle(level, i as u64).unwrap());
        }
        let mut group = c.benchmark_group("iterate");
        group.throughput(Throughput::Elements(count));
        group.bench_function(
            BenchmarkId::new("inverse::micro_triangles", level_number),
            |b| {
                b.iter(|| {
                    let mut sum = 0u64;
                    for t in inverse::micro_triangles(black_box(level)) {
                        let [p, q, r] = t.vertices_scaled();
                        sum = sum.wrapping_add(p.0 ^ q.1 ^ r.0);
                    }
                    black_box(sum)
                });
            },
        );
        group.bench_function(
            BenchmarkId::new("inverse::micro_triangle per index", level_number),
            |b| {
                b.iter(|| {
                    let mut sum = 0u64;
                    for i in 0..count {
                        let [p, q, r] = inverse::micro_triangle(black_box(level), i)
                            .unwrap()
                            .vertices_scaled();
                        sum = sum.wrapping_add(p.0 ^ q.1 ^ r.0);
                    }
                    black_box(sum)
                });
            },
        );
        group.finish();
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(20)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_millis(1200));
    targets = bench_index_f32, bench_wide_index_f32, bench_exact, bench_inverse
}
criterion_main!(benches);
