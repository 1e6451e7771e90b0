//! Lookup time per query, levels 1..=12: the flat micromap (packed as the
//! APIs store it), the paper's Algorithm 3 on its depth-first tree, and the
//! level-order layout. The map is the 2-state micromap of the Crytek Sponza
//! thorn texture (first triangle, nearest texel at centroids; see
//! `micromap_index_lab::succinct_maps`). Two query streams of 256 indices:
//! random (uniform over the map) and coherent (256 consecutive indices from
//! a random start: neighbours on the curve are neighbours in space).
//!
//! `level_order_table7` is the level-order tree with its deepest top table
//! (`with_top_depth(7)`); `level_order` has the default one.
//!
//! A third stream, `hit`, is what a ray tracer asks: 256 binary32 hits
//! `(u, v)` uniform over the triangle, each turned into the reference index
//! (`spec::index_f32`) and then read: `Micromap::state_at` for the flat map,
//! `get_f32` for the trees.
//!
//! `cargo bench -p micromap-index-lab --bench succinct`; per-query time = reported time / 256.

// `criterion_group!` generates undocumented public functions.
#![allow(missing_docs)]

use micromap_index_lab::succinct_maps;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use micromap_index::micromap::{Format, Micromap, State};
use micromap_index::succinct::{LevelOrderTree, PaperTree};
use micromap_index::Level;
use micromap_index_test_support::SplitMix64;
use std::hint::black_box;
use std::time::Duration;

const QUERIES: usize = 256;

/// The flat 2-state map, one bit per micro-triangle, least-significant
/// first: the baseline a GPU reads.
struct Flat(Vec<u64>);

impl Flat {
    fn new(states: &[State]) -> Self {
        let mut words = vec![0u64; states.len().div_ceil(64)];
        for (i, s) in states.iter().enumerate() {
            words[i / 64] |= u64::from(s.bits() & 1) << (i % 64);
        }
        Flat(words)
    }

    #[inline]
    fn get(&self, index: u64) -> Option<State> {
        let word = *self.0.get((index / 64) as usize)?;
        State::from_bits(((word >> (index % 64)) & 1) as u8)
    }
}

fn lookups(c: &mut Criterion) {
    let texture = succinct_maps::sponza_texture("sponza_thorn.png");
    let mut group = c.benchmark_group("succinct_lookup");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1))
        .throughput(Throughput::Elements(QUERIES as u64));
    for level in 1..=12u32 {
        let states = texture.micromap(level, Format::TwoState, 0);
        let level_n = Level::new(level).unwrap();
        let flat = Flat::new(&states);
        let paper = PaperTree::encode(level_n, Format::TwoState, &states).unwrap();
        let fast = LevelOrderTree::from_paper(&paper);
        // The deepest top table (up to seven levels in one read).
        let deepest_table = fast.clone().with_top_depth(7);
        let n = states.len() as u64;
        let mut rng = SplitMix64::new(u64::from(level));
        let random: Vec<u64> = (0..QUERIES).map(|_| rng.below(n)).collect();
        let start = rng.below(n);
        let coherent: Vec<u64> = (0..QUERIES as u64).map(|k| (start + k) % n).collect();
        let hits: Vec<(f32, f32)> = (0..QUERIES)
            .map(|_| {
                let u = (rng.next_u64() >> 40) as f32 / (1u64 << 24) as f32;
                let v = (rng.next_u64() >> 40) as f32 / (1u64 << 24) as f32;
                // Reflected into the triangle (u + v <= 1).
                if u + v > 1.0 {
                    (1.0 - u, 1.0 - v)
                } else {
                    (u, v)
                }
            })
            .collect();
        let map = Micromap::from_states(level_n, Format::TwoState, states.iter().copied()).unwrap();
        for &(u, v) in &hits {
            let state = Some(map.state_at(u, v));
            assert_eq!(fast.get_f32(u, v), state);
            assert_eq!(deepest_table.get_f32(u, v), state);
            assert_eq!(paper.get_f32(u, v), state);
        }
        let run_hits = |get: &dyn Fn(f32, f32) -> Option<State>| {
            hits.iter()
                .map(|&(u, v)| {
                    let (u, v) = black_box((u, v));
                    get(u, v).map_or(0u32, |s| u32::from(s.bits()))
                })
                .sum::<u32>()
        };
        group.bench_with_input(BenchmarkId::new("flat/hit", level), &level, |b, _| {
            b.iter(|| run_hits(&|u, v| Some(map.state_at(u, v))));
        });
        group.bench_with_input(BenchmarkId::new("paper_alg3/hit", level), &level, |b, _| {
            b.iter(|| run_hits(&|u, v| paper.get_f32(u, v)));
        });
        group.bench_with_input(
            BenchmarkId::new("level_order/hit", level),
            &level,
            |b, _| b.iter(|| run_hits(&|u, v| fast.get_f32(u, v))),
        );
        group.bench_with_input(
            BenchmarkId::new("level_order_table7/hit", level),
            &level,
            |b, _| b.iter(|| run_hits(&|u, v| deepest_table.get_f32(u, v))),
        );
        for (pattern, queries) in [("random", &random), ("coherent", &coherent)] {
            // Every layout answers like the flat map before it is timed.
            for &q in queries {
                assert_eq!(paper.get(q), flat.get(q));
                assert_eq!(fast.get(q), flat.get(q));
                assert_eq!(deepest_table.get(q), flat.get(q));
            }
            let run = |get: &dyn Fn(u64) -> Option<State>| {
                queries
                    .iter()
                    .map(|&q| get(black_box(q)).map_or(0u32, |s| u32::from(s.bits())))
                    .sum::<u32>()
            };
            group.bench_with_input(
                BenchmarkId::new(format!("flat/{pattern}"), level),
                &level,
                |b, _| b.iter(|| run(&|q| flat.get(q))),
            );
            group.bench_with_input(
                BenchmarkId::new(format!("paper_alg3/{pattern}"), level),
                &level,
                |b, _| b.iter(|| run(&|q| paper.get(q))),
            );
            group.bench_with_input(
                BenchmarkId::new(format!("level_order/{pattern}"), level),
                &level,
                |b, _| b.iter(|| run(&|q| fast.get(q))),
            );
            group.bench_with_input(
                BenchmarkId::new(format!("level_order_table7/{pattern}"), level),
                &level,
                |b, _| b.iter(|| run(&|q| deepest_table.get(q))),
            );
        }
    }
    group.finish();
}

criterion_group!(benches, lookups);
criterion_main!(benches);
