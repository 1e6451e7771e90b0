//! `KHR_texture_transform` baked as the shader applies it (issue 34),
//! judged by `micromap_index_lab::uv_transform_oracle` (written apart from
//! the baker): binary32 hits on and around every known micro-triangle's
//! vertices and edge midpoints and inside it, every renderer form of the
//! interpolation and the transform, the scaling ±1 ulp, snapping to 1/256
//! texel by rounding and truncation. A known micro-triangle must never read
//! a texel of the other class.
//!
//! The negative control bakes what the baker did before: the transformed
//! vertices as plain coordinates. With UVs near 100 and an offset of −100
//! (an exact transform, accepted before) the shader's interpolation error
//! of the large coordinates exceeds that bake's margin, and the oracle
//! finds contradictions there.

use micromap_index::bake::{
    AddressMode, Baker, Cutoff, Filter, Sampler, Unorm8Texture, UvTransform,
};
use micromap_index::micromap::{BakedOpacity, Format, State, UnknownPolicy};
use micromap_index::Level;
use micromap_index_lab::uv_transform_oracle::{judge, Case, TransformParams};
use micromap_index_test_support::SplitMix64;

/// A texture of `w x h` texels that varies along `u` only: runs of opaque
/// and transparent columns, 1 to 3 wide.
fn columns(rng: &mut SplitMix64, w: u32, h: u32) -> Vec<u8> {
    let mut column = Vec::new();
    while column.len() < w as usize {
        let value = if rng.below(2) == 0 { 0 } else { 255 };
        for _ in 0..=rng.below(3) {
            column.push(value);
        }
    }
    column.truncate(w as usize);
    (0..h).flat_map(|_| column.iter().copied()).collect()
}

fn states(baker: &Baker, uv: &[[f32; 2]; 3], level: u32) -> Vec<State> {
    let level = Level::new(level).unwrap();
    let baked = baker
        .bake(uv, level, Format::FourState, UnknownPolicy::default())
        .unwrap();
    let count = level.micro_triangle_count() as u64;
    match &baked.opacity {
        BakedOpacity::Map(map) => (0..count).map(|i| map.get(i).unwrap()).collect(),
        BakedOpacity::Special(s) => vec![*s; count as usize],
    }
}

/// A generated case: `far` puts the stored UVs near 100 and the offset at
/// −100 (the control's case); otherwise rotations at several angles,
/// scales and offsets that are not exact in binary32. The triangle spans a
/// few texels once transformed.
fn case(rng: &mut SplitMix64, far: bool) -> (Vec<u8>, Sampler, [[f32; 2]; 3], TransformParams) {
    let w = 4096;
    let texels = columns(rng, w, 4);
    let address = if rng.below(2) == 0 {
        AddressMode::Repeat
    } else {
        AddressMode::ClampToEdge
    };
    let sampler = Sampler {
        filter: Filter::Nearest,
        address_u: address,
        address_v: address,
        ..Sampler::default()
    };
    let unit = |rng: &mut SplitMix64| rng.below(1 << 20) as f32 / (1 << 20) as f32;
    let span = 6.0 / w as f32;
    let (base, transform) = if far {
        (
            [100.0 + unit(rng), 100.0 + unit(rng)],
            ([-100.0, -100.0], 0.0, [1.0, 1.0]),
        )
    } else {
        let angles = [
            0.3f32,
            core::f32::consts::FRAC_PI_2,
            -2.5,
            core::f32::consts::FRAC_PI_4,
            3.0,
        ];
        let rotation = angles[rng.below(angles.len() as u64) as usize];
        let s = [0.35f32, 1.0, 3.0][rng.below(3) as usize];
        (
            [unit(rng) * 10.0, unit(rng) * 10.0],
            ([0.705, 0.285], rotation, [s, s * 0.5]),
        )
    };
    let scale = transform.2[0].abs().max(transform.2[1].abs());
    let mut corner = || {
        [
            base[0] + unit(rng) * span / scale,
            base[1] + unit(rng) * span / scale,
        ]
    };
    let uv = [corner(), corner(), corner()];
    (texels, sampler, uv, transform)
}

#[test]
fn a_transformed_bake_holds_for_the_shaders_binary32_transform() {
    let mut rng = SplitMix64::new(34);
    let level = 5;
    let (mut known, mut wrong) = (0, 0);
    let (mut control_known, mut control_wrong) = (0, 0);
    for i in 0..16 {
        let far = i % 2 == 0;
        let (texels, sampler, uv, transform) = case(&mut rng, far);
        let texture = Unorm8Texture::new(4096, 4, &texels).unwrap();
        let baker = Baker::new(&texture, sampler, Cutoff::default()).unwrap();
        let (offset, rotation, scale) = transform;
        let t = UvTransform::new(offset, rotation, scale).unwrap();
        let judged = Case {
            texels: &texels,
            width: 4096,
            height: 4,
            sampler,
            uv,
            transform,
        };
        let modelled = baker.clone().with_uv_transform(t);
        let (k, w, first) = judge(&judged, &states(&modelled, &uv, level), level);
        assert_eq!(w, 0, "case {i}: {w} of {k} contradicted, first {first:?}");
        known += k;
        wrong += w;
        if far {
            // The control: the placed triangle baked as plain coordinates.
            let placed = uv.map(|c| t.place(c));
            let (k, w, _) = judge(&judged, &states(&baker, &placed, level), level);
            control_known += k;
            control_wrong += w;
        }
    }
    println!(
        "transformed: {wrong} of {known} known contradicted; control: {control_wrong} of {control_known}"
    );
    assert!(
        known > 2000,
        "too few known micro-triangles to judge: {known}"
    );
    assert!(
        control_wrong > 0,
        "the control (transformed vertices as plain coordinates) should be contradicted: \
         {control_wrong} of {control_known}"
    );
}
