//! The GPU model's oracle (`docs/bake.md`, "The GPU model"): what a GPU
//! computes for binary32 hits, written out independently of the baker, must
//! never contradict a known state baked under `Model::GpuBinary32`; it must
//! contradict bakes under `Model::Exact` on the committed texel-aligned grid
//! (the negative control).
//!
//! For every bake it enumerates binary32 barycentric pairs densely around
//! every micro-triangle vertex and edge (every lattice vertex `(a, b) / 2^n`
//! moved by -2..=2 ulps per coordinate; 7 points along every lattice edge,
//! moved by -2..=2 ulps across it), keeps those in the closed triangle,
//! assigns each to a micro-triangle with `spec::index_f32`, computes the
//! texture coordinate with each of the renderers' binary32 formulas (with
//! and without `mul_add`), scales it by the texture size in binary32 (and
//! moves the result by up to 2 ulps, the model's `2^-22` relative error of
//! the sampler), subtracts 1/2 for linear filtering, floors, wraps with
//! Vulkan's address formulas written again here, and reads the texel(s).
//!
//! `MICROMAP_GPU_ORACLE=full` runs the whole grid (128 triangles) at levels
//! 6 and 8, nearest and linear, under both models (release build: a few
//! minutes), and prints the counts `docs/bake.md` quotes.

use micromap_index::bake::{
    AddressMode, AlphaTexture, Baker, Comparison, Cutoff, Filter, Model, Sampler, Unorm8Texture,
    UvTriangle,
};
use micromap_index::micromap::{BakedOpacity, Format, State, UnknownPolicy};
use micromap_index::{spec, Level, SpecLevel};
use micromap_index_assets::{decode_alpha_image, read_triangles_json, Limits};
use micromap_index_test_support::SplitMix64;
use std::collections::BTreeSet;

/// The binary32 value next to a finite `x`, up or down (`f32::next_up` is
/// newer than the minimum Rust).
fn next(x: f32, up: bool) -> f32 {
    if x == 0.0 {
        let tiny = f32::from_bits(1);
        return if up { tiny } else { -tiny };
    }
    let bits = x.to_bits();
    f32::from_bits(if (x > 0.0) == up { bits + 1 } else { bits - 1 })
}

/// The texels and sampler as the oracle reads them.
struct Scene<'a> {
    texture: &'a dyn AlphaTexture,
    sampler: Sampler,
    cutoff: Cutoff,
}

impl Scene<'_> {
    fn opaque(&self, alpha: f64) -> bool {
        let c = f64::from(self.cutoff.alpha());
        match self.cutoff.comparison() {
            Comparison::AtLeast => alpha >= c,
            Comparison::Above => alpha > c,
        }
    }

    /// Vulkan's wrapping operation ("Wrapping Operation"), per axis.
    fn wrap(mode: AddressMode, i: i64, size: u32) -> Option<u32> {
        let n = i64::from(size);
        let mirror = |k: i64| if k < 0 { -(1 + k) } else { k };
        let t = match mode {
            AddressMode::Repeat => i.rem_euclid(n),
            AddressMode::MirroredRepeat => (n - 1) - mirror(i.rem_euclid(2 * n) - n),
            AddressMode::ClampToEdge => i.clamp(0, n - 1),
            AddressMode::ClampToBorder => {
                if i < 0 || i >= n {
                    return None;
                }
                i
            }
            AddressMode::MirrorClampToEdge => mirror(i).clamp(0, n - 1),
        };
        Some(t as u32)
    }

    fn texel_opaque(&self, x: i64, y: i64) -> bool {
        let (w, h) = (self.texture.width(), self.texture.height());
        match (
            Self::wrap(self.sampler.address_u, x, w),
            Self::wrap(self.sampler.address_v, y, h),
        ) {
            (Some(x), Some(y)) => self.opaque(self.texture.alpha(x, y)),
            _ => self.opaque(f64::from(self.sampler.border_alpha)),
        }
    }

    /// The texel coordinates one axis can read for the shader's coordinate
    /// `c` over `size` texels: `floor(fl(c size))`, moved by up to 2 ulps
    /// (and `- 1/2` in binary32 then the next texel for linear).
    fn axis_range(&self, c: f32, size: u32) -> Option<(i64, i64)> {
        let x = c * size as f32;
        if !x.is_finite() {
            return None;
        }
        let (lo, hi) = (next(next(x, false), false), next(next(x, true), true));
        Some(match self.sampler.filter {
            Filter::Nearest => (lo.floor() as i64, hi.floor() as i64),
            Filter::Linear => ((lo - 0.5).floor() as i64, (hi - 0.5).floor() as i64 + 1),
        })
    }

    /// The texel coordinates one axis can read over all the formulas'
    /// values `cs` (the union of their ranges: consecutive integers).
    fn axis_union(&self, cs: &[f32], size: u32) -> Option<(i64, i64)> {
        let mut range: Option<(i64, i64)> = None;
        for &c in cs {
            let (lo, hi) = self.axis_range(c, size)?;
            range = Some(range.map_or((lo, hi), |(a, b)| (a.min(lo), b.max(hi))));
        }
        range
    }

    /// Does some texel the point reads, by any of the formulas (per axis),
    /// have the class `opaque`?
    fn reads(&self, us: &[f32], vs: &[f32], opaque: bool) -> bool {
        let (Some((x0, x1)), Some((y0, y1))) = (
            self.axis_union(us, self.texture.width()),
            self.axis_union(vs, self.texture.height()),
        ) else {
            return false;
        };
        (y0..=y1).any(|y| (x0..=x1).any(|x| self.texel_opaque(x, y) == opaque))
    }
}

/// The renderers' binary32 texture coordinates for the hit `(b1, b2)`, on
/// one axis with corner values `c`.
fn formulas(c: [f32; 3], b1: f32, b2: f32) -> [f32; 8] {
    let [c0, c1, c2] = c;
    let w = (1.0 - b1) - b2;
    let w_sum = 1.0 - (b1 + b2);
    let (d1, d2) = (c1 - c0, c2 - c0);
    [
        w * c0 + b1 * c1 + b2 * c2,
        w * c0 + (b1 * c1 + b2 * c2),
        w_sum * c0 + b1 * c1 + b2 * c2,
        b2.mul_add(c2, b1.mul_add(c1, w * c0)),
        w.mul_add(c0, b1.mul_add(c1, b2 * c2)),
        c0 + b1 * d1 + b2 * d2,
        b2.mul_add(d2, b1.mul_add(d1, c0)),
        c0 + (b1 * d1 + b2 * d2),
    ]
}

/// Every binary32 pair the oracle tries at `level`, in the closed triangle.
fn hits(level: u32, mut visit: impl FnMut(f32, f32)) {
    let n = 1u32 << level;
    let at = |q: u64, den: u64| (q as f64 / den as f64) as f32; // exact: dyadic, few bits
    let mut try_pair = |b1: f32, b2: f32| {
        if b1 >= 0.0 && b2 >= 0.0 && f64::from(b1) + f64::from(b2) <= 1.0 {
            visit(b1, b2);
        }
    };
    let step = |x: f32, k: i32| -> f32 {
        let mut y = x;
        for _ in 0..k.unsigned_abs() {
            y = next(y, k > 0);
        }
        y
    };
    let (den, fine) = (u64::from(n), 8 * u64::from(n));
    for b in 0..=n {
        for a in 0..=n - b {
            let (b1, b2) = (at(a.into(), den), at(b.into(), den));
            for i in -2..=2 {
                for j in -2..=2 {
                    try_pair(step(b1, i), step(b2, j));
                }
            }
            for t in 1..8u64 {
                // Along the edges from (a, b): +b1, +b2, and the diagonal
                // a + b + 1 = c (from (a + 1, b) towards (a, b + 1)).
                let (fa, fb) = (8 * u64::from(a), 8 * u64::from(b));
                if a + b < n {
                    let (e1, e2) = (at(fa + t, fine), b2);
                    let (f1, f2) = (b1, at(fb + t, fine));
                    let (g1, g2) = (at(fa + 8 - t, fine), at(fb + t, fine));
                    for k in -2..=2 {
                        try_pair(e1, step(e2, k));
                        try_pair(step(f1, k), f2);
                        try_pair(g1, step(g2, k));
                        try_pair(step(g1, k), g2);
                    }
                }
            }
        }
    }
}

/// The micro-triangles of a bake whose known state a GPU hit contradicts.
fn contradicted(
    scene: &Scene<'_>,
    uv: &UvTriangle,
    level: u32,
    baked: &BakedOpacity,
) -> BTreeSet<u32> {
    let spec_level = SpecLevel::new(level).unwrap();
    let mut found = BTreeSet::new();
    hits(level, |b1, b2| {
        let index = spec::index_f32(b1, b2, spec_level);
        let state = baked.state(u64::from(index)).unwrap();
        let other = match state {
            State::Opaque => false,
            State::Transparent => true,
            _ => return,
        };
        if found.contains(&index) {
            return;
        }
        let us = formulas(uv.map(|c| c[0]), b1, b2);
        let vs = formulas(uv.map(|c| c[1]), b1, b2);
        if scene.reads(&us, &vs, other) {
            found.insert(index);
        }
    });
    found
}

fn bake(scene: &Scene<'_>, model: Model, uv: &UvTriangle, level: u32) -> BakedOpacity {
    Baker::new(scene.texture, scene.sampler, scene.cutoff)
        .unwrap()
        .with_model(model)
        .bake(
            uv,
            Level::new(level).unwrap(),
            Format::FourState,
            UnknownPolicy::default(),
        )
        .unwrap()
        .opacity
}

fn asset(path: &str) -> Vec<u8> {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../");
    std::fs::read(format!("{root}{path}")).unwrap()
}

fn full_tier() -> bool {
    std::env::var("MICROMAP_GPU_ORACLE").is_ok_and(|v| v == "full")
}

/// The committed grid over the thorn texture: under the exact model GPU
/// hits contradict known states on texel-aligned edges; under the GPU model
/// none. CI runs the triangles listed (those where the exact model fails,
/// and others); the full tier runs all 128.
#[test]
fn grid_gpu_hits_contradict_the_exact_model_and_never_the_gpu_model() {
    let image = decode_alpha_image(
        &asset("assets/crytek-sponza/sponza_thorn.png"),
        &Limits::default(),
    )
    .unwrap();
    let texture = image.texture().unwrap();
    let triangles = read_triangles_json(&asset("assets/crytek-sponza/grid.tris.json")).unwrap();
    let full = full_tier();
    let runs: &[(u32, Filter, &[usize])] = &[
        (6, Filter::Nearest, &[0, 9, 37, 64, 101, 127]),
        (8, Filter::Nearest, &[9, 64]),
        (6, Filter::Linear, &[37, 101]),
    ];
    let mut exact_total = 0;
    for &(level, filter, subset) in runs {
        let scene = Scene {
            texture: &texture,
            sampler: Sampler {
                filter,
                ..Sampler::default()
            },
            cutoff: Cutoff::default(),
        };
        let chosen: Vec<usize> = if full {
            (0..triangles.len()).collect()
        } else {
            subset.to_vec()
        };
        let mut counts = [0usize; 2];
        for &t in &chosen {
            let uv = &triangles[t];
            for (k, model) in Model::ALL.into_iter().enumerate() {
                let baked = bake(&scene, model, uv, level);
                let bad = contradicted(&scene, uv, level, &baked);
                if model == Model::GpuBinary32 {
                    assert!(
                        bad.is_empty(),
                        "triangle {t} level {level} {filter:?}: {bad:?}"
                    );
                }
                if full && !bad.is_empty() {
                    println!("{model:?} level {level} {filter:?} triangle {t}: {bad:?}");
                }
                counts[k] += bad.len();
            }
        }
        println!(
            "grid level {level} {filter:?}, {} triangles: contradicted micro-triangles gpu-binary32 {}, exact {}",
            chosen.len(),
            counts[0],
            counts[1]
        );
        exact_total += counts[1];
    }
    assert!(exact_total > 0, "the negative control found nothing");
}

/// Generated adversarial bakes: small textures with texels on the cutoff,
/// both cutoff rules, every address mode per axis, both filters, corners on
/// texel and half-texel lines, near 0 and far outside `[0, 1]` (up to
/// 65536.5), axis-aligned and needle triangles, levels 0..=5. None of the
/// GPU model's known states is contradicted; the exact model's are, many
/// times (a second negative control).
#[test]
fn generated_bakes_hold_for_every_gpu_hit() {
    let mut rng = SplitMix64::new(0x6a0d_e122);
    let cases = if full_tier() { 2000 } else { 160 };
    let mut known = 0u64;
    let mut exact_bad = 0usize;
    for case in 0..cases {
        let (w, h) = (1 + rng.below(6) as u32, 1 + rng.below(6) as u32);
        let cutoff_alpha = rng.pick(&[0.0f32, 0.25, 0.5, 1.0, 128.0 / 255.0]);
        let at_cutoff = (f64::from(cutoff_alpha) * 255.0).round() as u8;
        let texels: Vec<u8> = (0..w * h)
            .map(|_| match rng.below(4) {
                0 => at_cutoff,
                1 => 0,
                2 => 255,
                _ => rng.below(256) as u8,
            })
            .collect();
        let texture = Unorm8Texture::new(w, h, &texels).unwrap();
        let comparison = rng.pick(&[Comparison::AtLeast, Comparison::Above]);
        let Ok(cutoff) = Cutoff::new(cutoff_alpha, comparison) else {
            continue;
        };
        let sampler = Sampler {
            filter: rng.pick(&[Filter::Nearest, Filter::Linear]),
            address_u: rng.pick(&AddressMode::ALL),
            address_v: rng.pick(&AddressMode::ALL),
            border_alpha: rng.pick(&[0.0, 1.0, 0.5]),
        };
        let scene = Scene {
            texture: &texture,
            sampler,
            cutoff,
        };
        // Corners on texel or half-texel lines of a period far away or
        // near 0, as binary32.
        let offset = rng.pick(&[0.0f64, 0.0, 1.0, -3.0, 1000.0, -1000.0, 65536.0]);
        let mut corner = |size: u32| -> f32 {
            let k = rng.below(4 * u64::from(size) + 1) as f64;
            let step = if rng.below(2) == 0 { 1.0 } else { 0.5 };
            (offset + (k * step) / f64::from(size) - 0.5) as f32
        };
        let mut uv: UvTriangle = [[0.0; 2]; 3];
        for c in &mut uv {
            *c = [corner(w), corner(h)];
        }
        match case % 4 {
            // Axis-aligned right triangle.
            0 => {
                uv[1][1] = uv[0][1];
                uv[2][0] = uv[0][0];
            }
            // A needle.
            1 => uv[2] = [uv[1][0], uv[1][1] + 1.0 / (8.0 * h as f32)],
            _ => {}
        }
        let level = (case % 6) as u32;
        for model in Model::ALL {
            let baked = bake(&scene, model, &uv, level);
            let bad = contradicted(&scene, &uv, level, &baked);
            if model == Model::GpuBinary32 {
                assert!(
                    bad.is_empty(),
                    "case {case}: {uv:?} level {level} {sampler:?} {cutoff:?} {w}x{h}: {bad:?}"
                );
                known += (0..1u64 << (2 * level))
                    .filter(|&i| baked.state(i).unwrap().is_known())
                    .count() as u64;
            } else {
                exact_bad += bad.len();
            }
        }
    }
    println!("generated: {known} known micro-triangles (gpu-binary32), exact-model contradictions {exact_bad}");
    assert!(known > 1000, "{known}");
    assert!(exact_bad > 0);
}
