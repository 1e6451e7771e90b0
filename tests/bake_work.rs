//! Bounded work (issue 26): the per-triangle and per-bake work budgets turn
//! what is left unknown (sound, counted), and the auto level drops to 0
//! where micro-triangles would each hold a whole texture period.

use micromap_index::bake::mesh::{
    bake_meshes, LevelRule, Material, Mesh, MeshOptions, MeshTriangles,
};
use micromap_index::bake::{
    spans_whole_periods, AddressMode, Baker, Cutoff, Model, Sampler, TriangleStatus, Unorm8Texture,
    UvTriangle, DEFAULT_BAKE_WORK_BUDGET, DEFAULT_TRIANGLE_WORK_BUDGET,
};
use micromap_index::micromap::{Format, State, UnknownPolicy};
use micromap_index::Level;

/// The case: one triangle over 10^6 texture periods.
const HUGE: UvTriangle = [[0.0, 0.0], [1e6, 0.0], [0.0, 1e6]];

/// The most one micro-triangle can spend past a budget (`bake::work`):
/// under the GPU model (the larger bound) 8 lookups plus twice the larger
/// of the block budget and the 36 texels of a small block, as it may be
/// classified under both models.
const OVERSHOOT: u64 = 8 + 2 * micromap_index::bake::DEFAULT_BLOCK_BUDGET as u64;

/// 8 x 8, opaque where `(x + y) % 3 == 0`: mixed everywhere at any scale.
fn texels() -> Vec<u8> {
    (0..64u32)
        .map(|i| if (i % 8 + i / 8) % 3 == 0 { 255 } else { 0 })
        .collect()
}

fn known(counts: [u64; 4]) -> u64 {
    counts[State::Opaque.bits() as usize] + counts[State::Transparent.bits() as usize]
}

fn level(n: u32) -> Level {
    Level::new(n).unwrap()
}

#[test]
fn the_defaults_are_the_documented_ones() {
    let options = MeshOptions::default();
    assert_eq!(options.triangle_work_budget, DEFAULT_TRIANGLE_WORK_BUDGET);
    assert_eq!(options.bake_work_budget, DEFAULT_BAKE_WORK_BUDGET);
    assert_eq!(DEFAULT_TRIANGLE_WORK_BUDGET, 1 << 26);
    assert_eq!(DEFAULT_BAKE_WORK_BUDGET, 1 << 34);
}

/// Every budget cuts the same walk at a later point: the known
/// micro-triangles only grow with the budget, the work stays within one
/// micro-triangle of it, and every cut bake is sound by the verifier.
#[test]
fn a_triangle_budget_cuts_the_walk_soundly_and_monotonically() {
    let texels = texels();
    let texture = Unorm8Texture::new(8, 8, &texels).unwrap();
    for model in [Model::GpuBinary32, Model::Exact] {
        let baker = Baker::new(&texture, Sampler::default(), Cutoff::default())
            .unwrap()
            .with_model(model);
        let uv = [[0.1, 0.05], [2.3, 0.4], [0.7, 1.9]];
        let full = baker
            .bake(&uv, level(7), Format::FourState, UnknownPolicy::Fallback)
            .unwrap();
        assert_eq!(full.status, TriangleStatus::Exact, "{model:?}");
        assert!(full.work > 1000, "{model:?}: {}", full.work);
        let mut last_known = 0;
        for budget in [
            0,
            1,
            2,
            10,
            100,
            full.work / 4,
            full.work / 2,
            // The last micro-triangle starts at or above this.
            full.work - OVERSHOOT,
        ] {
            let cut = baker
                .bake_within(
                    &uv,
                    level(7),
                    Format::FourState,
                    UnknownPolicy::Fallback,
                    budget,
                )
                .unwrap();
            assert_eq!(
                cut.status,
                TriangleStatus::WorkBudgetExceeded,
                "{model:?} {budget}"
            );
            assert!(
                cut.work <= budget + OVERSHOOT,
                "{model:?} {budget}: {}",
                cut.work
            );
            assert_eq!(cut.counts.iter().sum::<u64>(), 1 << 14);
            let k = known(cut.counts);
            assert!(k >= last_known, "{model:?} {budget}: {k} < {last_known}");
            last_known = k;
            let verdict = baker.verify(&uv, &cut.opacity.as_opacity());
            assert!(verdict.contradictions.is_empty(), "{model:?} {budget}");
            // Every known state of the cut bake is the full bake's.
            for i in 0..1u64 << 14 {
                let s = cut.opacity.state(i).unwrap();
                if s.is_known() {
                    assert_eq!(Some(s), full.opacity.state(i), "{model:?} {budget} {i}");
                }
            }
        }
        assert!(last_known < known(full.counts));
        let enough = baker
            .bake_within(
                &uv,
                level(7),
                Format::FourState,
                UnknownPolicy::Fallback,
                full.work,
            )
            .unwrap();
        assert_eq!(enough, full);
    }
}

/// A 2-state bake cut by the budget stores the unknowns as the policy says.
#[test]
fn a_cut_two_state_bake_resolves_its_unknowns_by_the_policy() {
    let texels = texels();
    let texture = Unorm8Texture::new(8, 8, &texels).unwrap();
    let baker = Baker::new(&texture, Sampler::default(), Cutoff::default()).unwrap();
    let uv = [[0.1, 0.05], [2.3, 0.4], [0.7, 1.9]];
    for (policy, state) in [
        (UnknownPolicy::Opaque, State::Opaque),
        (UnknownPolicy::Transparent, State::Transparent),
    ] {
        let cut = baker
            .bake_within(&uv, level(5), Format::TwoState, policy, 0)
            .unwrap();
        assert_eq!(cut.status, TriangleStatus::WorkBudgetExceeded);
        assert_eq!(cut.work, 0);
        assert_eq!(known(cut.counts), 0);
        assert!((0..1u64 << 10).all(|i| cut.opacity.state(i) == Some(state)));
    }
}

/// The triangle at a fixed level 12 (16.7 M micro-triangles each
/// over about 244 periods) stops at its budget with a reported status.
#[test]
fn the_many_periods_triangle_at_level_12_stops_at_its_budget() {
    let texels = texels();
    let texture = Unorm8Texture::new(8, 8, &texels).unwrap();
    let budget = 1 << 16;
    let baker = Baker::new(&texture, Sampler::default(), Cutoff::default())
        .unwrap()
        .with_work_budget(budget);
    let baked = baker
        .bake(&HUGE, level(12), Format::FourState, UnknownPolicy::Fallback)
        .unwrap();
    assert_eq!(baked.status, TriangleStatus::WorkBudgetExceeded);
    assert!(
        baked.work >= budget && baked.work <= budget + OVERSHOOT,
        "{}",
        baked.work
    );
    assert_eq!(known(baked.counts), 0);
}

/// The per-bake budget is spent in triangle order: the first triangles
/// bake exactly, the later ones are cut or get nothing, every one is
/// counted, and the total stays within one micro-triangle of the budget.
#[test]
fn a_bake_budget_is_spent_in_triangle_order_and_counted() {
    let texels = texels();
    let texture = Unorm8Texture::new(8, 8, &texels).unwrap();
    let triangles: Vec<UvTriangle> = (0..12)
        .map(|k| {
            let d = k as f32 * 0.01;
            [[0.1 + d, 0.05], [2.3, 0.4 + d], [0.7, 1.9 - d]]
        })
        .collect();
    let mesh = Mesh {
        triangles: MeshTriangles::Uv(&triangles),
        texture: &texture,
        material: Material::default(),
        vertex_alpha: None,
    };
    let fixed = MeshOptions {
        levels: LevelRule::Fixed(level(6)),
        ..MeshOptions::default()
    };
    let full = bake_meshes(&[mesh], &fixed, &mut |_, _| {}).unwrap();
    assert_eq!(full.report.status.exact, 12);
    let of = |baked: &micromap_index::bake::mesh::MeshBake| -> Vec<_> {
        (0..triangles.len())
            .map(|t| baked.triangle(0, t).unwrap())
            .collect()
    };
    let per: Vec<u64> = of(&full).iter().map(|t| t.work).collect();
    assert_eq!(full.report.work, per.iter().sum::<u64>());
    // Enough for the first four and half of the fifth.
    let budget = per[..4].iter().sum::<u64>() + per[4] / 2;
    let cut = bake_meshes(
        &[mesh],
        &MeshOptions {
            bake_work_budget: budget,
            ..fixed
        },
        &mut |_, _| {},
    )
    .unwrap();
    let statuses: Vec<TriangleStatus> = of(&cut).iter().map(|t| t.status).collect();
    assert!(
        statuses[..4].iter().all(|&s| s == TriangleStatus::Exact),
        "{statuses:?}"
    );
    assert!(statuses[4..]
        .iter()
        .all(|&s| s == TriangleStatus::WorkBudgetExceeded));
    assert_eq!(cut.report.status.exact, 4);
    assert_eq!(cut.report.status.work_budget_exceeded, 8);
    assert!(cut.report.work <= budget + OVERSHOOT, "{}", cut.report.work);
    assert_eq!(of(&cut)[4..].iter().skip(1).map(|t| t.work).sum::<u64>(), 0);
    assert!(known(cut.report.counts) < known(full.report.counts));
    // Sound: what is still known agrees with the verifier.
    let baker = Baker::new(&texture, Sampler::default(), Cutoff::default()).unwrap();
    for (t, uv) in triangles.iter().enumerate() {
        assert!(baker
            .verify(uv, &cut.opacity(0, t).unwrap().as_opacity())
            .contradictions
            .is_empty());
    }
    // A per-triangle budget cuts every triangle the same way.
    let each = bake_meshes(
        &[mesh],
        &MeshOptions {
            triangle_work_budget: per.iter().min().unwrap() / 2,
            ..fixed
        },
        &mut |_, _| {},
    )
    .unwrap();
    assert_eq!(each.report.status.work_budget_exceeded, 12);
}

/// The auto level of the triangle is 0 under repeat and mirrored
/// repeat (its micro-triangles would each hold whole periods), counted in
/// the report; clamped, it keeps its level (far outside the texture only
/// the edge is read, so parts can be known).
#[test]
fn auto_levels_drop_to_zero_over_whole_periods_only_when_the_texture_repeats() {
    let texels = texels();
    let texture = Unorm8Texture::new(8, 8, &texels).unwrap();
    let big = [HUGE, [[0.0, 0.0], [0.5, 0.0], [0.0, 0.5]]];
    for (address, lowered) in [
        (AddressMode::Repeat, true),
        (AddressMode::MirroredRepeat, true),
        (AddressMode::ClampToEdge, false),
    ] {
        let sampler = Sampler {
            address_u: address,
            address_v: address,
            ..Sampler::default()
        };
        let mesh = Mesh {
            triangles: MeshTriangles::Uv(&big),
            texture: &texture,
            material: Material {
                sampler,
                ..Material::default()
            },
            vertex_alpha: None,
        };
        let options = MeshOptions {
            levels: LevelRule::Useful { max: level(6) },
            ..MeshOptions::default()
        };
        let baked = bake_meshes(&[mesh], &options, &mut |_, _| {}).unwrap();
        let levels: Vec<u32> = (0..big.len())
            .map(|t| baked.triangle(0, t).unwrap().level.get())
            .collect();
        let expected_first = if lowered { 0 } else { 6 };
        assert_eq!(levels[0], expected_first, "{address:?}");
        // The small one is never lowered (a level-0 special index only
        // when uniform).
        assert_eq!(baked.report.levels.iter().sum::<u64>(), 2);
        assert_eq!(
            baked.report.period_level_zero,
            usize::from(lowered),
            "{address:?}"
        );
    }
}

/// The rule's claim: where every micro-triangle holds a whole period, a
/// non-uniform texture gives no known micro-triangle at that level (so
/// level 0 loses nothing), and a uniform one is known at any level.
#[test]
fn over_whole_periods_no_level_knows_more_than_level_0() {
    let mixed = texels();
    let opaque = [255u8; 64];
    let uv = [[0.3, 0.1], [300.0, 2.0], [5.0, 280.0]];
    for n in 0..=4 {
        assert!(
            spans_whole_periods(&uv, Sampler::default(), level(n)),
            "level {n}"
        );
    }
    assert!(!spans_whole_periods(&uv, Sampler::default(), level(8)));
    for model in [Model::GpuBinary32, Model::Exact] {
        let texture = Unorm8Texture::new(8, 8, &mixed).unwrap();
        let baker = Baker::new(&texture, Sampler::default(), Cutoff::default())
            .unwrap()
            .with_model(model);
        for n in 0..=4 {
            let b = baker
                .bake(&uv, level(n), Format::FourState, UnknownPolicy::Fallback)
                .unwrap();
            assert_eq!(known(b.counts), 0, "{model:?} level {n}");
        }
        let texture = Unorm8Texture::new(8, 8, &opaque).unwrap();
        let baker = Baker::new(&texture, Sampler::default(), Cutoff::default())
            .unwrap()
            .with_model(model);
        let b = baker
            .bake(&uv, level(4), Format::FourState, UnknownPolicy::Fallback)
            .unwrap();
        assert_eq!(b.counts[State::Opaque.bits() as usize], 256, "{model:?}");
    }
}
