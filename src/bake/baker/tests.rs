//! The walk and the split walk, through [`Baker`]: each leaf is what the
//! plain search gives it alone, the `i64` and `i128` walks agree, and a
//! split walk is the serial walk for every budget.

use super::*;
use crate::bake::classify::{Classes, NARROW_SHIFT, NARROW_WALK_COORDINATE};
use crate::bake::exact::ExactTriangle;
use crate::bake::{AddressMode, Filter, Unorm8Texture};
use micromap_index_test_support::SplitMix64;

/// Every micro-triangle of a bake (whose leaves are read four at a
/// time, sharing their vertices: `Walk::visit_leaves`, and whose
/// searches look only for the classes its points did not read) has
/// the state the plain search gives it alone: every class its closed
/// (for the GPU model, dilated) area reads, with no points, no
/// shortcut and no budget, or under linear filtering by value (a small
/// footprint reading both) what the value over the region allows, decided
/// whole (no node above it, no points). Known where that is one class, else
/// unknown by its centroid texel. Random blobby textures, both filters, wrapping and
/// bordered samplers, both models, levels 1..=6, triangles reaching
/// past the texture.
#[test]
fn each_leaf_is_what_it_alone_classifies_as() {
    let mut rng = SplitMix64::new(0x1eaf);
    let (w, h) = (12u32, 10u32);
    let mut checked = [0u64; 2];
    for case in 0..24u32 {
        let texels: Vec<u8> = (0..w * h)
            .map(|i| {
                let blob = ((i % w) / 3 + (i / w) / 4 + case) % 3 == 0;
                if blob ^ (rng.next_u64() % 7 == 0) {
                    255
                } else {
                    0
                }
            })
            .collect();
        let texture = Unorm8Texture::new(w, h, &texels).unwrap();
        let address = [
            AddressMode::Repeat,
            AddressMode::ClampToEdge,
            AddressMode::ClampToBorder,
        ][(case % 3) as usize];
        let sampler = Sampler {
            filter: [Filter::Linear, Filter::Nearest][(case / 3 % 2) as usize],
            address_u: address,
            address_v: AddressMode::MirroredRepeat,
            border_alpha: 1.0,
        };
        let model = Model::ALL[(case % 2) as usize];
        let baker = Baker::new(&texture, sampler, Cutoff::default())
            .unwrap()
            .with_model(model);
        let mut c = || (rng.next_u64() % 1000) as f32 / 700.0 - 0.2;
        let uv = [[c(), c()], [c(), c()], [c(), c()]];
        let level = Level::new(1 + case % 6).unwrap();
        let policy = UnknownPolicy::default();
        let baked = baker
            .bake_as(
                model,
                &uv,
                level,
                Format::FourState,
                policy,
                u64::MAX,
                false,
            )
            .unwrap();
        let (fx, fy, grid) = baker.frames(model, &uv, level).unwrap();
        let mut stack = Vec::new();
        for i in 0..1u64 << (2 * level.get()) {
            let vertices = crate::inverse::micro_triangle(level, i)
                .unwrap()
                .vertices_scaled();
            let p = Baker::place(&fx, &fy, level.get(), vertices);
            let t = ExactTriangle::new(p.x, p.y);
            let search =
                baker
                    .classifier
                    .classes
                    .search(&t, grid, Classes::BOTH, u32::MAX, &mut stack);
            assert!(!search.exhausted);
            // Linear filtering by value: a small footprint reading both
            // classes is decided by the value over the region.
            let classes = &baker.classifier.classes;
            let small = crate::bake::classify::is_small(baker.classifier.bounding_block(&p, grid));
            let known = if search.classes.is_mixed() && classes.test.by_value && small {
                Classes::of_bits(classes.region_value(&p, grid, None).bits)
            } else {
                search.classes
            };
            let expected = match known.known_state() {
                Some(state) => state,
                None if baker.classifier.centroid_is_opaque(&p, grid.shifts) => {
                    State::UnknownOpaque
                }
                None => State::UnknownTransparent,
            };
            assert_eq!(
                baked.opacity.state(i),
                Some(expected),
                "case {case}: {uv:?} at {level:?}, micro-triangle {i}"
            );
            checked[usize::from(expected.is_known())] += 1;
        }
    }
    // Both kinds of state were met, many times.
    assert!(checked[0] > 300 && checked[1] > 300, "{checked:?}");
}

/// The `i64` walk gives the `i128` walk's micromap wherever
/// [`Placed::narrowed`] accepts a root: roots with coordinates just
/// below `2^59` (and some crossing zero), shifts up to 58, every
/// filter, on a wrapping and a bordered sampler. Roots at `2^59` or
/// with a shift of 59 are refused.
#[test]
fn narrow_and_wide_walks_agree_near_their_threshold() {
    let mut rng = SplitMix64::new(0x0b5e_55ed);
    let mut next = move || rng.next_u64();
    // 4 x 4 checks of random alpha, so that known states are common.
    let checks: Vec<u8> = (0..16).map(|_| (next() % 256) as u8).collect();
    let texels: Vec<u8> = (0..16 * 16)
        .map(|i| checks[i % 16 / 4 + i / 64 * 4])
        .collect();
    let texture = Unorm8Texture::new(16, 16, &texels).unwrap();
    let limit = NARROW_WALK_COORDINATE;
    let mut seen = [0u64; 4];
    for case in 0..400u32 {
        let filter = if case % 2 == 0 {
            Filter::Nearest
        } else {
            Filter::Linear
        };
        let address = if case % 4 < 2 {
            AddressMode::Repeat
        } else {
            AddressMode::ClampToBorder
        };
        let sampler = Sampler {
            filter,
            address_u: address,
            address_v: address,
            border_alpha: 1.0,
        };
        let baker = Baker::new(&texture, sampler, Cutoff::default())
            .unwrap()
            .with_block_budget(16);
        let level = case % 4;
        // A shift near the threshold most of the time, any otherwise.
        let shift = |r: u64| {
            if r % 4 == 0 {
                1 + (r / 4 % 58) as u32
            } else {
                NARROW_SHIFT - (r / 4 % 3) as u32
            }
        };
        let shifts = (shift(next()), shift(next()));
        let grid = Grid::exact(shifts);
        // Coordinates within 2^spread of +-2^59 (below it), or near 0;
        // multiples of 2^level, as a root's are.
        let spread = 1 + next() % 58;
        let mut coordinate = || {
            let offset = 1 + (i128::from(next()) & ((1 << spread) - 1));
            let magnitude = if next() % 5 == 0 {
                offset
            } else {
                limit - offset
            };
            let sign = if next() % 2 == 0 { 1 } else { -1 };
            sign * (magnitude >> level << level)
        };
        let root = Placed {
            x: [coordinate(), coordinate(), coordinate()],
            y: [coordinate(), coordinate(), coordinate()],
        };
        let narrow = root.narrowed(grid).unwrap();
        let bake = |walk: &dyn Fn(&mut Micromap, &mut [u64; 4]) -> Spent| {
            let mut map = Micromap::new(Level(level as u8), Format::FourState).unwrap();
            let mut counts = [0; 4];
            let spent = walk(&mut map, &mut counts);
            (map, counts, spent.status, spent.work, spent.widened)
        };
        let policy = UnknownPolicy::Fallback;
        let c = &baker.classifier;
        let wide = bake(&|map, counts| {
            walk_whole(c, (root, level, grid), policy, u64::MAX, (map, counts)).unwrap()
        });
        let narrowed = bake(&|map, counts| {
            walk_whole(c, (narrow, level, grid), policy, u64::MAX, (map, counts)).unwrap()
        });
        assert_eq!(narrowed, wide, "{root:?} {shifts:?} level {level}");
        for (total, count) in seen.iter_mut().zip(wide.1) {
            *total += count;
        }
        // One step past either bound takes the wide walk.
        let mut over = root;
        over.x[case as usize % 3] = if case % 2 == 0 { limit } else { -limit };
        assert!(over.narrowed(grid).is_none());
        assert!(root
            .narrowed(Grid::exact((NARROW_SHIFT + 1, shifts.1)))
            .is_none());
    }
    // Every state came out, many times.
    assert!(seen.iter().all(|&n| n > 100), "{seen:?}");
}

/// A split walk (levels 10 and 11, subtrees on the pool's threads)
/// gives the serial walk's map, counts, widening, status and work,
/// under both models and formats, on textures with structure at
/// every scale, for every budget: those that cut the serial walk
/// (a fifth, half, four fifths of its work, a unit short of it, a few
/// units, none) as much as those that do not. Its speculative work is
/// 0 when nothing cuts, and bounded otherwise.
#[test]
fn split_walks_give_the_serial_walk() {
    let mut rng = SplitMix64::new(0x5b17);
    let (w, h) = (24u32, 20u32);
    let mut split_kept = 0;
    for case in 0..6u32 {
        // Blobs of each class with noisy edges.
        let texels: Vec<u8> = (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                let blob = (x / 6 + y / 5 + case) % 3 == 0;
                if blob ^ (rng.next_u64() % 9 == 0) {
                    255
                } else {
                    0
                }
            })
            .collect();
        let texture = Unorm8Texture::new(w, h, &texels).unwrap();
        let sampler = Sampler {
            filter: if case % 2 == 0 {
                Filter::Linear
            } else {
                Filter::Nearest
            },
            address_u: AddressMode::Repeat,
            address_v: AddressMode::ClampToEdge,
            border_alpha: 0.0,
        };
        let model = Model::ALL[(case % 2) as usize];
        let baker = Baker::new(&texture, sampler, Cutoff::default())
            .unwrap()
            .with_model(model);
        let mut c = || (rng.next_u64() % 1000) as f32 / 800.0 - 0.1;
        let uv = [[c(), c()], [c(), c()], [c(), c()]];
        let level = Level::new(10 + case % 2).unwrap();
        let format = [Format::FourState, Format::TwoState][(case / 2 % 2) as usize];
        let policy = UnknownPolicy::default();
        let serial = baker
            .bake_as(model, &uv, level, format, policy, u64::MAX, false)
            .unwrap();
        let split = baker
            .bake_as(model, &uv, level, format, policy, u64::MAX, true)
            .unwrap();
        assert_eq!(split, serial, "case {case}: {uv:?} at {level:?}");
        assert_eq!(split.speculative_work, 0);
        assert!(
            serial.work > 1000,
            "case {case}: too easy ({} units)",
            serial.work
        );
        let full = serial.work;
        let budgets = [
            full / 2,
            full / 5,
            full * 4 / 5,
            full - 1,
            full,
            full + 1,
            3,
            0,
        ];
        for budget in budgets {
            let serial = baker
                .bake_as(model, &uv, level, format, policy, budget, false)
                .unwrap();
            let mut split = baker
                .bake_as(model, &uv, level, format, policy, budget, true)
                .unwrap();
            // The speculative work is bounded: at most half of what
            // each batch had left, plus the top walked twice.
            assert!(
                split.speculative_work <= budget + serial.work / 4 + (1 << 14),
                "case {case}: budget {budget}: {} speculative",
                split.speculative_work
            );
            split.speculative_work = 0;
            assert_eq!(split, serial, "case {case}: budget {budget} of {full}");
            split_kept += u32::from(serial.status != TriangleStatus::WorkBudgetExceeded);
        }
    }
    // Budgets at or above the work kept every split bake (no cut).
    assert!(split_kept >= 12, "{split_kept}");
}
