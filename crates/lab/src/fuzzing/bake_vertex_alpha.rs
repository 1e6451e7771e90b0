//! Fuzz body for vertex alpha read per part of the walk (issue 34): a mesh
//! whose triangles share UVs with other alphas (walked together) bakes
//! each triangle as it bakes alone, holds at every sampled point, and is
//! sound to the verifier.

use micromap_index::bake::mesh::{
    bake_mesh, bake_meshes, verify_mesh, LevelRule, Material, Mesh, MeshOptions, MeshTriangles,
};
use micromap_index::bake::{AddressMode, Filter, Sampler, Unorm8Texture};
use micromap_index::inverse::micro_triangle;
use micromap_index::micromap::{BakedOpacity, State};
use micromap_index::Level;

/// A vertex-alpha mesh under linear filtering by value, clamp to edge: the
/// bake never panics; every known micro-triangle holds at 45 points of it
/// (corners, edges, inside) under the exact bilinear value times the exact
/// interpolated alpha (points within `1e-9` of the cutoff skipped); each
/// triangle baked alone, beside a triangle elsewhere whose alphas span the
/// bake's (so the texel classes are the same), gets the states it gets in
/// the mesh (where its UVs are walked with other alphas); and
/// [`verify_mesh`] calls the bake sound. (That last triangle is in the
/// mesh too.)
///
/// Input: width, height (1..=8 each), `w h` texel codes, level (0..=4),
/// the number of distinct UV triangles (1..=3), each as 6 bytes (a
/// coordinate `b / 64 - 1`), then up to 12 triangles as a UV triangle's
/// number and its 3 alphas (a byte each, `b / 255`).
///
/// ```
/// micromap_index_lab::fuzzing::bake_vertex_alpha(&[2, 1, 255, 0, 2, 1, 64, 64, 128, 64, 64, 128]);
/// ```
pub fn bake_vertex_alpha(data: &[u8]) {
    let at = core::cell::Cell::new(0usize);
    let byte = || {
        let b = data.get(at.get()).copied().unwrap_or(0);
        at.set(at.get() + 1);
        b
    };
    let (w, h) = (usize::from(byte() % 8) + 1, usize::from(byte() % 8) + 1);
    let texels: Vec<u8> = (0..w * h).map(|_| byte()).collect();
    let level = Level::new(u32::from(byte() % 5)).expect("level <= 4");
    let coordinate = |b: u8| f32::from(b) / 64.0 - 1.0;
    let shapes: Vec<[[f32; 2]; 3]> = (0..=usize::from(byte() % 3))
        .map(|_| [0, 1, 2].map(|_| [coordinate(byte()), coordinate(byte())]))
        .collect();
    let count = (data.len().saturating_sub(at.get()) / 4).clamp(1, 12);
    let (mut triangles, mut alphas) = (Vec::new(), Vec::new());
    for _ in 0..count {
        triangles.push(shapes[usize::from(byte()) % shapes.len()]);
        alphas.push([0, 1, 2].map(|_| f32::from(byte()) / 255.0));
    }
    // The texel classes hold over every alpha of the bake: a last triangle
    // (elsewhere) spanning them all makes that range the same for the mesh
    // and for each triangle baked beside it alone.
    let (low, high) = alphas
        .iter()
        .flatten()
        .fold((1.0f32, 0.0f32), |(l, h), &a| (l.min(a), h.max(a)));
    triangles.push([[5.0, 5.0], [5.25, 5.0], [5.0, 5.25]]);
    alphas.push([low, high, high]);
    let all = count + 1;
    let texture = Unorm8Texture::new(w as u32, h as u32, &texels).expect("w h texels");
    let material = Material {
        sampler: Sampler {
            filter: Filter::Linear,
            address_u: AddressMode::ClampToEdge,
            address_v: AddressMode::ClampToEdge,
            border_alpha: 0.0,
        },
        ..Material::default()
    };
    let options = MeshOptions {
        levels: LevelRule::Fixed(level),
        ..MeshOptions::default()
    };
    let mesh = |t: core::ops::Range<usize>| Mesh {
        triangles: MeshTriangles::Uv(&triangles[t.clone()]),
        texture: &texture,
        material,
        vertex_alpha: Some(&alphas[t]),
    };
    let baked = bake_mesh(&mesh(0..all), &options)
        .unwrap_or_else(|e| panic!("bake failed: {e} ({data:02x?})"));
    let texel = |x: f64, y: f64| {
        let x = (x as isize).clamp(0, w as isize - 1) as usize;
        let y = (y as isize).clamp(0, h as isize - 1) as usize;
        f64::from(texels[y * w + x]) / 255.0
    };
    let bilinear = |x: f64, y: f64| {
        let (fx, fy) = ((x - 0.5).floor(), (y - 0.5).floor());
        let (a, b) = (x - 0.5 - fx, y - 0.5 - fy);
        (1.0 - a) * (1.0 - b) * texel(fx, fy)
            + a * (1.0 - b) * texel(fx + 1.0, fy)
            + (1.0 - a) * b * texel(fx, fy + 1.0)
            + a * b * texel(fx + 1.0, fy + 1.0)
    };
    for t in 0..all {
        let opacity = baked.opacity(0, t).expect("a bake per triangle");
        let beside = Mesh {
            triangles: MeshTriangles::Uv(&triangles[count..]),
            vertex_alpha: Some(&alphas[count..]),
            ..mesh(0..1)
        };
        let alone = bake_meshes(&[mesh(t..t + 1), beside], &options, &mut |_, _| {})
            .expect("baked in the mesh");
        assert_eq!(
            alone.opacity(0, 0),
            Some(opacity.clone()),
            "triangle {t} bakes otherwise alone ({data:02x?})"
        );
        let (uv, va) = (triangles[t], alphas[t]);
        let level_of = match &opacity {
            BakedOpacity::Map(map) => map.level(),
            BakedOpacity::Special(_) => Level::new(0).expect("level 0"),
        };
        for i in 0..level_of.micro_triangle_count() as u64 {
            let state = opacity.state(i).expect("index in range");
            if !state.is_known() {
                continue;
            }
            let [p, q, r] = micro_triangle(level_of, i)
                .expect("index in range")
                .vertices_f64();
            for j in 0..=8 {
                for k in 0..=(8 - j) {
                    let (s, z) = (f64::from(j) / 8.0, f64::from(k) / 8.0);
                    let b1 = (1.0 - s - z) * p.0 + s * q.0 + z * r.0;
                    let b2 = (1.0 - s - z) * p.1 + s * q.1 + z * r.1;
                    let interpolate = |c: [f32; 3]| {
                        (1.0 - b1 - b2) * f64::from(c[0])
                            + b1 * f64::from(c[1])
                            + b2 * f64::from(c[2])
                    };
                    let (u, v) = (interpolate(uv.map(|c| c[0])), interpolate(uv.map(|c| c[1])));
                    let alpha = bilinear(u * w as f64, v * h as f64) * interpolate(va);
                    if (alpha - 0.5).abs() < 1e-9 {
                        continue;
                    }
                    assert_eq!(
                        alpha >= 0.5,
                        state == State::Opaque,
                        "triangle {t} micro {i} {state:?}: alpha {alpha} at ({b1}, {b2}) ({data:02x?})"
                    );
                }
            }
        }
    }
    let opacities: Vec<BakedOpacity> = (0..all)
        .map(|t| baked.opacity(0, t).expect("a bake per triangle"))
        .collect();
    let opacities: Vec<_> = opacities.iter().map(BakedOpacity::as_opacity).collect();
    let verdict = verify_mesh(
        &mesh(0..all),
        &opacities,
        &options,
        u64::MAX,
        &mut |_, _| {},
    )
    .unwrap_or_else(|e| panic!("verify failed: {e:?} ({data:02x?})"));
    assert!(
        verdict.is_sound(all),
        "the verifier finds {verdict:?} ({data:02x?})"
    );
}
