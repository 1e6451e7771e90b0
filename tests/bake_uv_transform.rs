//! `KHR_texture_transform` baked as the shader applies it (issue 34): an
//! oracle written apart from the baker evaluates, for binary32 hits on and
//! around every micro-triangle's vertices and edge midpoints (±1 ulp per
//! barycentric) and inside it, the texel a GPU reads after interpolating
//! the *untransformed* coordinates and transforming them in binary32, in
//! several renderers' orders (a CPU-built matrix applied left to right or
//! with fused multiply-adds; scale, rotate and offset in steps with
//! `f32` or `f64` sine and cosine), scales by the texture size (±1 ulp),
//! snaps to 1/256 texel (rounding or truncating) and floors. A known
//! micro-triangle must never read a texel of the other class.
//!
//! The negative control bakes what the baker did before: the transformed
//! vertices as plain coordinates. With UVs near 100 and an offset of −100
//! (an exact transform, accepted before) the shader's interpolation error
//! of the large coordinates exceeds that bake's margin, and the oracle
//! finds contradictions there.

use micromap_index::bake::{
    AddressMode, Baker, Cutoff, Filter, Sampler, Unorm8Texture, UvTransform,
};
use micromap_index::inverse::micro_triangle;
use micromap_index::micromap::{Format, State, UnknownPolicy};
use micromap_index::{spec, Level, SpecLevel};
use micromap_index_test_support::{step_ulps, SplitMix64};

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

/// Every texture coordinate along one axis (before scaling by the size)
/// that some renderer computes for the hit `(b1, b2)`.
fn shader_coordinates(
    uv: &[[f32; 2]; 3],
    p: &([f32; 2], f32, [f32; 2]),
    b1: f32,
    b2: f32,
) -> Vec<[f32; 2]> {
    let (offset, rotation, scale) = *p;
    let interpolate = |k: usize| -> [f32; 5] {
        let [c0, c1, c2] = uv.map(|c| c[k]);
        let w = (1.0 - b1) - b2;
        let w2 = 1.0 - (b1 + b2);
        [
            w * c0 + b1 * c1 + b2 * c2,
            w2 * c0 + b1 * c1 + b2 * c2,
            c0 + b1 * (c1 - c0) + b2 * (c2 - c0),
            b2.mul_add(c2, b1.mul_add(c1, w * c0)),
            b2.mul_add(c2 - c0, b1.mul_add(c1 - c0, c0)),
        ]
    };
    let (xs, ys) = (interpolate(0), interpolate(1));
    let (s64, c64) = f64::from(rotation).sin_cos();
    let [sx, sy] = scale;
    // A matrix built on the CPU in f64 (three.js, the sample viewer),
    // stored as binary32.
    let m = [
        [(c64 * f64::from(sx)) as f32, (-s64 * f64::from(sy)) as f32],
        [(s64 * f64::from(sx)) as f32, (c64 * f64::from(sy)) as f32],
    ];
    let trig = [(s64 as f32, c64 as f32), rotation.sin_cos()];
    let mut out = Vec::new();
    for (&x, &y) in xs.iter().zip(&ys) {
        // Matrix, left to right and fused.
        out.push([
            m[0][0] * x + m[0][1] * y + offset[0],
            m[1][0] * x + m[1][1] * y + offset[1],
        ]);
        out.push([
            m[0][1].mul_add(y, m[0][0].mul_add(x, offset[0])),
            m[1][1].mul_add(y, m[1][0].mul_add(x, offset[1])),
        ]);
        // Scale, rotate, offset in steps.
        for &(s, c) in &trig {
            let (u, v) = (sx * x, sy * y);
            out.push([(c * u - s * v) + offset[0], (s * u + c * v) + offset[1]]);
            out.push([
                offset[0] + c.mul_add(u, -(s * v)),
                offset[1] + s.mul_add(u, c * v),
            ]);
        }
    }
    out
}

/// The classes (bit 0 transparent, bit 1 opaque) a GPU can read at the
/// hit `(b1, b2)`, nearest filter, under every coordinate of
/// [`shader_coordinates`]. The texture varies along `u` only, so only `u`
/// is followed to its texel.
fn classes_read(case: &Case, b1: f32, b2: f32) -> u8 {
    let mut read = 0;
    let n = i64::from(case.w);
    for c in shader_coordinates(&case.uv, &case.transform, b1, b2) {
        let x = c[0] * case.w as f32;
        for d in -1..=1 {
            let x = step_ulps(x, d);
            for snapped in [(x * 256.0).round() / 256.0, (x * 256.0).floor() / 256.0] {
                let i = snapped.floor() as i64;
                let texel = match case.sampler.address_u {
                    AddressMode::Repeat => i.rem_euclid(n),
                    _ => i.clamp(0, n - 1),
                };
                read |= if case.texels[texel as usize] >= 128 {
                    2
                } else {
                    1
                };
            }
        }
    }
    read
}

struct Case {
    w: u32,
    h: u32,
    texels: Vec<u8>,
    sampler: Sampler,
    uv: [[f32; 2]; 3],
    transform: ([f32; 2], f32, [f32; 2]),
    level: u32,
}

/// Known micro-triangles of `states` (micro-triangle order) and those the
/// oracle contradicts.
fn contradictions(case: &Case, states: &[State], rng: &mut SplitMix64) -> (u64, u64) {
    let level = Level::new(case.level).unwrap();
    let spec_level = SpecLevel::new(case.level).unwrap();
    let side = (1u64 << case.level) as f32;
    let (mut known, mut wrong) = (0, 0);
    for (index, &state) in states.iter().enumerate() {
        if !state.is_known() {
            continue;
        }
        known += 1;
        let t = micro_triangle(level, index as u64).unwrap();
        let v = t
            .vertices_scaled()
            .map(|(a, b)| [a as f32 / side, b as f32 / side]);
        let mut points = Vec::new();
        for k in 0..3 {
            points.push(v[k]);
            let n = v[(k + 1) % 3];
            points.push([(v[k][0] + n[0]) / 2.0, (v[k][1] + n[1]) / 2.0]);
        }
        for _ in 0..4 {
            let (r1, r2) = (
                rng.below(1000) as f32 / 1000.0,
                rng.below(1000) as f32 / 1000.0,
            );
            let (r1, r2) = if r1 + r2 > 1.0 {
                (1.0 - r1, 1.0 - r2)
            } else {
                (r1, r2)
            };
            points.push([
                v[0][0] + r1 * (v[1][0] - v[0][0]) + r2 * (v[2][0] - v[0][0]),
                v[0][1] + r1 * (v[1][1] - v[0][1]) + r2 * (v[2][1] - v[0][1]),
            ]);
        }
        let other = if state == State::Opaque { 1 } else { 2 };
        let mut contradicted = false;
        'points: for p in points {
            for d1 in -1..=1 {
                for d2 in -1..=1 {
                    let (b1, b2) = (step_ulps(p[0], d1), step_ulps(p[1], d2));
                    let in_triangle =
                        b1 >= 0.0 && b2 >= 0.0 && f64::from(b1) + f64::from(b2) <= 1.0;
                    if !in_triangle || spec::index_f32(b1, b2, spec_level) as usize != index {
                        continue;
                    }
                    if classes_read(case, b1, b2) & other != 0 {
                        contradicted = true;
                        break 'points;
                    }
                }
            }
        }
        wrong += u64::from(contradicted);
    }
    (known, wrong)
}

fn states(baker: &Baker, uv: &[[f32; 2]; 3], level: u32) -> Vec<State> {
    let level = Level::new(level).unwrap();
    let baked = baker
        .bake(uv, level, Format::FourState, UnknownPolicy::default())
        .unwrap();
    match &baked.opacity {
        micromap_index::micromap::BakedOpacity::Map(map) => (0..level.micro_triangle_count()
            as u64)
            .map(|i| map.get(i).unwrap())
            .collect(),
        micromap_index::micromap::BakedOpacity::Special(s) => {
            vec![*s; level.micro_triangle_count() as usize]
        }
    }
}

/// Generated cases: `far` puts the source UVs near 100 and the offset at
/// −100 (the control's case); otherwise rotations at several angles,
/// scales and offsets that are not exact in binary32.
fn case(rng: &mut SplitMix64, far: bool) -> Case {
    let (w, h) = (4096, 4);
    let texels = columns(rng, w, h);
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
    // A triangle spanning a few texels once transformed.
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
    let corner = |rng: &mut SplitMix64| {
        [
            base[0] + unit(rng) * span / scale,
            base[1] + unit(rng) * span / scale,
        ]
    };
    Case {
        w,
        h,
        texels,
        sampler,
        uv: [corner(rng), corner(rng), corner(rng)],
        transform,
        level: 5,
    }
}

#[test]
fn a_transformed_bake_holds_for_the_shaders_binary32_transform() {
    let mut rng = SplitMix64::new(34);
    let (mut known, mut wrong, mut control_wrong) = (0, 0, 0);
    let (mut far_known, mut far_wrong) = (0, 0);
    for i in 0..16 {
        let far = i % 2 == 0;
        let case = case(&mut rng, far);
        let texture = Unorm8Texture::new(case.w, case.h, &case.texels).unwrap();
        let baker = Baker::new(&texture, case.sampler, Cutoff::default()).unwrap();
        let (offset, rotation, scale) = case.transform;
        let transform = UvTransform::new(offset, rotation, scale).unwrap();
        let modelled = baker.clone().with_uv_transform(transform);
        let (k, w) = contradictions(&case, &states(&modelled, &case.uv, case.level), &mut rng);
        known += k;
        wrong += w;
        if far {
            // The control: the placed triangle baked as plain coordinates.
            let placed = case.uv.map(|c| transform.place(c));
            let (k, w) = contradictions(&case, &states(&baker, &placed, case.level), &mut rng);
            far_known += k;
            far_wrong += w;
            control_wrong += w;
        }
    }
    println!(
        "transformed: {wrong} of {known} known contradicted; control: {far_wrong} of {far_known}"
    );
    assert_eq!(
        wrong, 0,
        "{wrong} of {known} known micro-triangles contradicted"
    );
    assert!(
        known > 2000,
        "too few known micro-triangles to judge: {known}"
    );
    assert!(
        control_wrong > 0,
        "the control (transformed vertices as plain coordinates) should be contradicted: \
         {far_wrong} of {far_known}"
    );
}

/// Two meshes over one texture and the same stored triangle, with
/// different transforms, are two distinct bakes (the transform is part of
/// what makes triangles bake alike), and each equals its own bake alone.
#[test]
fn different_transforms_are_never_deduplicated() {
    use micromap_index::bake::mesh::{
        bake_mesh, bake_meshes, LevelRule, Material, Mesh, MeshOptions, MeshTriangles,
    };
    // 4 x 1: opaque in the left texel only.
    let texture = Unorm8Texture::new(4, 1, &[255, 0, 0, 0]).unwrap();
    let triangle = [[[0.0f32, 0.0], [1.0, 0.0], [0.0, 1.0]]];
    let mesh = |uv_transform| Mesh {
        triangles: MeshTriangles::Uv(&triangle),
        texture: &texture,
        material: Material {
            sampler: Sampler {
                filter: Filter::Nearest,
                ..Sampler::default()
            },
            uv_transform,
            ..Material::default()
        },
        vertex_alpha: None,
    };
    let moved = UvTransform::new([0.25, 0.0], 0.0, [0.5, 0.5]).unwrap();
    let turned = UvTransform::new([0.6, 0.0], 0.4, [0.3, 0.3]).unwrap();
    let meshes = [mesh(UvTransform::IDENTITY), mesh(moved), mesh(turned)];
    let options = MeshOptions {
        levels: LevelRule::Fixed(Level::new(3).unwrap()),
        ..MeshOptions::default()
    };
    let together = bake_meshes(&meshes, &options, &mut |_, _| {}).unwrap();
    assert_eq!(together.report.distinct_triangles, 3);
    let alone: Vec<[u64; 4]> = meshes
        .iter()
        .map(|m| bake_mesh(m, &options).unwrap().report.counts)
        .collect();
    assert_ne!(alone[0], alone[1]);
    assert_ne!(alone[1], alone[2]);
    let summed = alone.iter().fold([0u64; 4], |mut s, c| {
        for (s, c) in s.iter_mut().zip(c) {
            *s += c;
        }
        s
    });
    assert_eq!(together.report.counts, summed);
}
