//! `spec::reference_bits_f32_by_integers` (integers only) against `spec::index_f32`
//! (binary32): bit for bit on random pairs, on every structurally
//! sensitive class of inputs, and (in the ignored exhaustive tier, `-- --ignored`) on every
//! f32 in [0, 1] for u against a fixed set of v partners.

use micromap_index::spec;
use micromap_index_test_support::{edge_values, window_fractions, SplitMix64};

fn assert_same(u: f32, v: f32, level: u32) {
    let (mirror, reference) = (
        spec::reference_bits_f32_by_integers(u, v, level),
        spec::reference_bits_f32(u, v, level),
    );
    assert_eq!(
        mirror,
        reference,
        "u = {:#010x}, v = {:#010x}, level {level}: mirror {mirror}, spec {reference}",
        u.to_bits(),
        v.to_bits()
    );
}

#[test]
fn mirror_matches_spec_on_every_structured_pair() {
    let values = edge_values();
    for level in 0..=33 {
        for &u in &values {
            for &v in &values {
                assert_same(u, v, level);
            }
        }
    }
}

/// Pairs whose scaled fractions sum to within a few ulps of 1: the only
/// place binary32 rounding decides (`uf + vf` in `[1 - 2^-25, 1)`).
#[test]
fn mirror_matches_spec_in_the_rounding_window() {
    let mut rng = SplitMix64::new(25);
    let mut in_window = 0u32;
    for _ in 0..400_000 {
        let level = (rng.next_u64() % 17) as u32;
        let cells = (1u64 << level) as f32;
        let (uf, vf) = window_fractions(rng.next_u64() as u32, rng.next_u64() as u32);
        let cell = |r: u64| (r % (1u64 << level)) as f32 * (r & 1) as f32;
        let u = (cell(rng.next_u64()) + uf) / cells;
        let v = (cell(rng.next_u64()) + vf) / cells;
        let exact_sum = f64::from((u * cells).fract()) + f64::from((v * cells).fract());
        if (1.0 - 2f64.powi(-25)..1.0).contains(&exact_sum) {
            in_window += 1;
        }
        assert_same(u, v, level);
        assert_same(v, u, level);
    }
    assert!(in_window > 10_000, "only {in_window} pairs in the window");
}

#[test]
fn mirror_matches_spec_on_random_pairs() {
    let mut rng = SplitMix64::new(0x6d69_7272_6f72);
    for i in 0..3_000_000u32 {
        let r = rng.next_u64();
        let (u, v) = if i % 2 == 0 {
            (f32::from_bits(r as u32), f32::from_bits((r >> 32) as u32))
        } else {
            // Both in [0, 1].
            (
                f32::from_bits((r as u32) % 0x3f80_0001),
                f32::from_bits(((r >> 32) as u32) % 0x3f80_0001),
            )
        };
        assert_same(u, v, i % 34);
    }
}

/// Every f32 in [0, 1] (0x00000000..=0x3f800000) as u, each level 0..=16,
/// against v partners that hit each class: fixed values (0, 1, 1/2, NaN,
/// a subnormal, just below 1) and partners derived from u (the hypotenuse
/// `1 - u` and its neighbours, and the rounding-window partner whose scaled
/// fraction is `1 - uf` lowered by 1 ulp). About 1.8 * 10^11 pairs (an hour
/// on two cores): run it with
/// `cargo test --release -p micromap-index-lab --test mirror -- --ignored --nocapture`.
/// Blocks of 2^20 consecutive u values are visited in a scattered order and
/// progress is printed, so an interrupted run still reports an evenly spread
/// share of [0, 1].
#[test]
#[ignore = "exhaustive tier (about an hour): run with --ignored"]
fn exhaustive_u_sweep_against_v_partners() {
    const BLOCK_BITS: u32 = 20;
    let last = 0x3f80_0000u32;
    let blocks = (last >> BLOCK_BITS) + 1; // 1017 blocks, the last one short
                                           // An odd stride coprime to the block count scatters the visiting order.
    let stride = (0..blocks)
        .map(|k| 389 + 2 * k)
        .find(|s| gcd(*s, blocks) == 1)
        .unwrap();
    let threads = std::thread::available_parallelism().map_or(2, std::num::NonZero::get) as u32;
    let next_block = std::sync::atomic::AtomicU32::new(0);
    let done = std::sync::atomic::AtomicU64::new(0);
    let started = std::time::Instant::now();
    let checked: u64 = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                scope.spawn(|| {
                    let mut count = 0u64;
                    loop {
                        let i = next_block.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        if i >= blocks {
                            return count;
                        }
                        let block = (i * stride) % blocks;
                        let first = block << BLOCK_BITS;
                        let end = (first + (1 << BLOCK_BITS) - 1).min(last);
                        for bits in first..=end {
                            count += sweep_one_u(f32::from_bits(bits));
                        }
                        let finished = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
                        if finished % 32 == 0 {
                            eprintln!(
                                "mirror sweep: {finished}/{blocks} blocks of 2^{BLOCK_BITS} u values equal, {:.0} s",
                                started.elapsed().as_secs_f64()
                            );
                        }
                    }
                })
            })
            .collect();
        workers.into_iter().map(|w| w.join().unwrap()).sum()
    });
    eprintln!(
        "exhaustive mirror sweep: {checked} (u, v, level) triples equal in {:.0} s",
        started.elapsed().as_secs_f64()
    );
}

fn gcd(a: u32, b: u32) -> u32 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

fn sweep_one_u(u: f32) -> u64 {
    let fixed_partners = [
        0.0,
        1.0,
        0.5,
        f32::NAN,
        f32::from_bits(1),
        f32::from_bits(0x3f7f_ffff),
    ];
    let hypotenuse = 1.0 - u;
    let mut count = 0;
    for level in 0..=16 {
        let cells = (1u32 << level) as f32;
        let scaled = u * cells;
        let uf = scaled - (scaled as u32) as f32; // exact, as in the reference
        let window_partner = f32::from_bits((1.0 - uf).to_bits().saturating_sub(1)) / cells;
        let partners = fixed_partners.into_iter().chain([
            hypotenuse,
            f32::from_bits(hypotenuse.to_bits() + 1),
            f32::from_bits(hypotenuse.to_bits().saturating_sub(1)),
            window_partner,
        ]);
        for v in partners {
            assert_same(u, v, level);
            count += 1;
        }
    }
    count
}
