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
//! That footprint oracle judges linear bakes made with
//! `LinearRule::Footprint`, the rule it states.
//!
//! The value oracle (second half) judges linear bakes by the library's
//! default, `LinearRule::Value`: for the same hits it models the texture
//! unit too (sub-texel snapping by rounding and by truncation, the 2x2
//! texels and their exact weights, both binary32 conversions of each
//! UNORM8 texel, the filter's error, the alpha test in binary32), for
//! bakes at 8 and 4 sub-texel bits; its negative controls are the exact
//! model, and a bake for 16 sub-texel bits judged with 4.
//!
//! `MICROMAP_GPU_ORACLE=full` runs the whole grid (128 triangles) at levels
//! 6 and 8, nearest and linear, under both models, the value oracle over
//! every grid triangle at level 6 and more generated bakes (release build:
//! a few minutes), and prints the counts `docs/bake.md` quotes.

use micromap_index::bake::{
    AddressMode, AlphaTexture, Baker, Comparison, Cutoff, Filter, LinearRule, Model, Sampler,
    TextureUnit, Unorm8Texture, UvTriangle,
};
use micromap_index::micromap::{BakedOpacity, Format, State, UnknownPolicy};
use micromap_index::{spec, Level, SpecLevel};
use micromap_index_assets::{decode_alpha_image, read_triangles_json, AlphaTexels, Limits};
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

/// A generated bake's triangle: corners on texel or half-texel lines of a
/// `w x h` texture, a period `offsets` picks away (far away or near 0), as
/// binary32; by `case`, an axis-aligned right triangle, a needle, or as
/// drawn.
fn adversarial_uv(
    rng: &mut SplitMix64,
    (w, h): (u32, u32),
    offsets: &[f64],
    case: u64,
) -> UvTriangle {
    let offset = rng.pick(offsets);
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
    uv
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

/// Bakes for the footprint oracle above: linear filtering judged by
/// footprint ([`LinearRule::Footprint`]), the rule that oracle states (a
/// known state holds for every texel a hit can read). The default, by
/// value, makes known micro-triangles whose footprint holds both classes;
/// the value oracle below judges those.
fn bake(scene: &Scene<'_>, model: Model, uv: &UvTriangle, level: u32) -> BakedOpacity {
    let unit = TextureUnit::default().with_linear_rule(LinearRule::Footprint);
    Baker::new_for(scene.texture, scene.sampler, scene.cutoff, unit, u64::MAX)
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
        let uv = adversarial_uv(
            &mut rng,
            (w, h),
            &[0.0, 0.0, 1.0, -3.0, 1000.0, -1000.0, 65536.0],
            case,
        );
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

// The binary32 oracle for linear filtering judged by value.
//
// `Scene` above asks which texels a hit can read (the footprint); under the
// library's default `LinearRule::Value` a linear bake is judged by the
// filtered value instead. What follows models the texture unit as well,
// written apart from the baker (`src/bake/texture_unit.rs`,
// `src/bake/alpha_test.rs`, `src/bake/classify/bilinear.rs`): sub-texel
// snapping by rounding and by truncation, the 2x2 texels and their exact
// weights, each texel's two faithful binary32 conversions, the filter's
// error, and the alpha test in binary32.

/// The texture unit's `2^k` for `k` sub-texel bits.
fn scale_of(subtexel_bits: u32) -> f64 {
    f64::from(1u32 << subtexel_bits)
}

/// Both binary32 values a texture unit may convert the UNORM8 code `c` to
/// (Vulkan's "Fixed-Point Data Conversions" does not require the nearest):
/// the binary32 values on either side of `c / 255`, one value when the
/// quotient is exact (0 and 255). The side is decided exactly: `f * 255`
/// is a 24-bit mantissa times an 8-bit integer, exact in `f64`.
fn faithful(c: u8) -> (f32, f32) {
    let f = (f64::from(c) / 255.0) as f32;
    let side = f64::from(f) * 255.0 - f64::from(c);
    if side > 0.0 {
        (next(f, false), f)
    } else if side < 0.0 {
        (f, next(f, true))
    } else {
        (f, f)
    }
}

/// The least binary32 value at least `x` (the lowest value a filter whose
/// result lies in `[x, ..]` can return).
fn f32_at_least(x: f64) -> f32 {
    let v = x as f32;
    if f64::from(v) < x {
        next(v, true)
    } else {
        v
    }
}

/// The greatest binary32 value at most `x`.
fn f32_at_most(x: f64) -> f32 {
    let v = x as f32;
    if f64::from(v) > x {
        next(v, false)
    } else {
        v
    }
}

/// A UNORM8 texture, sampler, cutoff and texture unit as the value oracle
/// reads them: the codes themselves, not the baker's texture tables.
struct ValueScene<'a> {
    width: u32,
    height: u32,
    /// `width * height` codes, row-major.
    codes: &'a [u8],
    sampler: Sampler,
    cutoff: Cutoff,
    /// `k`: the snapped coordinate is a multiple of `2^-k` texels.
    subtexel_bits: u32,
    /// The filter's error `E` in alpha units (`TextureUnit::filter_error`).
    filter_error: f64,
}

impl ValueScene<'_> {
    /// The binary32 value of the test `value >= cutoff` (or `>`), both
    /// operands binary32 as a GPU compares them.
    fn passes(&self, value: f32) -> bool {
        let c = self.cutoff.alpha();
        match self.cutoff.comparison() {
            Comparison::AtLeast => value >= c,
            Comparison::Above => value > c,
        }
    }

    /// The lowest and highest binary32 value texel `(i, j)` (before
    /// wrapping) can have: a code's faithful pair, or the border alpha
    /// (binary32 already, so its own pair) outside a clamp-to-border axis.
    fn texel(&self, i: i64, j: i64) -> (f32, f32) {
        match (
            Scene::wrap(self.sampler.address_u, i, self.width),
            Scene::wrap(self.sampler.address_v, j, self.height),
        ) {
            (Some(x), Some(y)) => faithful(self.codes[(y * self.width + x) as usize]),
            _ => (self.sampler.border_alpha, self.sampler.border_alpha),
        }
    }

    /// The snapped coordinates `x - 1/2` one axis can filter with, for the
    /// shader's coordinates `cs` over `size` texels, as the lowest and the
    /// highest multiple of `2^-k`: `fl(c size)` moved by -2..=2 ulps (the
    /// model's `2^-22` relative error of the sampler), `- 0.5` in binary32,
    /// then snapped by truncation toward -inf (the lowest) and by rounding
    /// to nearest, ties away from zero (the highest; with truncation both
    /// tie directions are tried). Every step is monotone, so the
    /// candidates' snapped values lie between the snapped extremes; the
    /// caller tries every multiple of `2^-k` between them, a superset
    /// still within the model (each is within `2^-k` of a point between
    /// two computed coordinates, which the margin's box covers, the
    /// micro-triangle being convex). Scaling by `2^k` and flooring are
    /// exact in `f64`. `None` when a product overflows.
    fn snapped(&self, cs: &[f32; 8], size: u32) -> Option<(f64, f64)> {
        let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
        for &c in cs {
            let x = c * size as f32;
            if !x.is_finite() {
                return None;
            }
            lo = lo.min(x);
            hi = hi.max(x);
        }
        let scale = scale_of(self.subtexel_bits);
        let lo = f64::from(next(next(lo, false), false) - 0.5) * scale;
        let hi = f64::from(next(next(hi, true), true) - 0.5) * scale;
        assert!(hi.abs() < 2f64.powi(52) && lo.abs() < 2f64.powi(52));
        Some((lo.floor() / scale, hi.round() / scale))
    }

    /// The lowest and highest exact bilinear mix at the snapped point
    /// `(sx, sy)` (coordinates already less 1/2): the texels of
    /// `floor(s)` and the next, weights `a = s - floor(s)` (exact), every
    /// texel at its low conversion for the lowest and its high for the
    /// highest.
    ///
    /// Exact in `f64` for `k <= 10`: a texel value is a binary32 value in
    /// `[2^-8, 1]` (1/255 is above `2^-8`) or 0, so a multiple of
    /// `2^-31`; a weight product is a multiple of `2^-2k`; each term and
    /// every partial sum is then a multiple of `2^-(31 + 2k)` below 2 in
    /// magnitude, at most `32 + 2k <= 52` significant bits.
    fn mix(&self, sx: f64, sy: f64) -> (f64, f64) {
        let (fx, fy) = (sx.floor(), sy.floor());
        let (a, b) = (sx - fx, sy - fy);
        let (i, j) = (fx as i64, fy as i64);
        let weights = [(1.0 - a) * (1.0 - b), a * (1.0 - b), (1.0 - a) * b, a * b];
        let (mut lo, mut hi) = (0.0, 0.0);
        for (k, w) in weights.into_iter().enumerate() {
            let (l, h) = self.texel(i + (k % 2) as i64, j + (k / 2) as i64);
            lo += w * f64::from(l);
            hi += w * f64::from(h);
        }
        (lo, hi)
    }
}

/// What the value oracle found over one bake.
#[derive(Default)]
struct Tally {
    /// Known micro-triangles some hit was checked on.
    checked: u64,
    /// Hits checked (on known micro-triangles).
    hits: u64,
    /// Known micro-triangles a GPU value contradicts.
    contradicted: BTreeSet<u32>,
}

impl Tally {
    fn add(&mut self, other: &Tally) {
        self.checked += other.checked;
        self.hits += other.hits;
        self.contradicted.extend(&other.contradicted);
    }
}

/// Runs the value oracle over a bake: for every hit of [`hits`] on a
/// known micro-triangle, the lowest and highest binary32 value a GPU may
/// compare (over the formulas, the sampler's ulps, both snappings, both
/// conversions, the filter error), and whether it contradicts the state.
/// The axes are chosen independently: the model's margin is a box.
fn value_judge(scene: &ValueScene<'_>, uv: &UvTriangle, level: u32, baked: &BakedOpacity) -> Tally {
    assert!(
        scene.subtexel_bits <= 10,
        "the mix is exact in f64 for k <= 10"
    );
    let spec_level = SpecLevel::new(level).unwrap();
    let mut tally = Tally::default();
    let mut seen = BTreeSet::new();
    hits(level, |b1, b2| {
        let index = spec::index_f32(b1, b2, spec_level);
        let opaque = match baked.state(u64::from(index)).unwrap() {
            State::Opaque => true,
            State::Transparent => false,
            _ => return,
        };
        if seen.insert(index) {
            tally.checked += 1;
        }
        tally.hits += 1;
        if tally.contradicted.contains(&index) {
            return;
        }
        let us = formulas(uv.map(|c| c[0]), b1, b2);
        let vs = formulas(uv.map(|c| c[1]), b1, b2);
        let (Some((x0, x1)), Some((y0, y1))) = (
            scene.snapped(&us, scene.width),
            scene.snapped(&vs, scene.height),
        ) else {
            return;
        };
        // Every multiple of 2^-k from the lowest to the highest snapped
        // value (the steps are exact: below 2^52 units).
        let step = 1.0 / scale_of(scene.subtexel_bits);
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let mut sy = y0;
        while sy <= y1 {
            let mut sx = x0;
            while sx <= x1 {
                let (l, h) = scene.mix(sx, sy);
                lo = lo.min(l);
                hi = hi.max(h);
                sx += step;
            }
            sy += step;
        }
        // Exact: lo and hi are multiples of 2^-(31 + 2k) below 2, E = 2^-16.
        let wrong = if opaque {
            !scene.passes(f32_at_least(lo - scene.filter_error))
        } else {
            scene.passes(f32_at_most(hi + scene.filter_error))
        };
        if wrong {
            tally.contradicted.insert(index);
        }
    });
    tally
}

/// Bakes under `model` with `k` sub-texel bits (the default unit
/// otherwise: binary32 interpolation, filter error `2^-16`, by value).
fn bake_unit(
    texture: &dyn AlphaTexture,
    scene: &ValueScene<'_>,
    model: Model,
    subtexel_bits: u32,
    uv: &UvTriangle,
    level: u32,
) -> BakedOpacity {
    let unit = TextureUnit::default().with_subtexel_bits(subtexel_bits);
    Baker::new_for(texture, scene.sampler, scene.cutoff, unit, u64::MAX)
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

/// The tallies of one tier: the GPU model's bakes at `k = 8` and `k = 4`
/// (each judged with its own `k`), and the two negative controls.
#[derive(Default)]
struct Tiers {
    /// `Model::GpuBinary32` baked and judged with `k = 8`, then `k = 4`.
    gpu: [Tally; 2],
    /// `Model::Exact` (no dilation) judged with `k = 8` snapping.
    exact: Tally,
    /// `Model::GpuBinary32` baked for `k = 16`, judged with `k = 4`.
    coarse: Tally,
}

impl Tiers {
    /// Bakes one case four ways and judges each; panics on a contradiction
    /// of the GPU model at its own `k`, with `what` naming the case.
    fn run(
        &mut self,
        texture: &dyn AlphaTexture,
        scene: &ValueScene<'_>,
        uv: &UvTriangle,
        level: u32,
        what: &dyn Fn() -> String,
    ) {
        let with_k = |k: u32| ValueScene {
            subtexel_bits: k,
            ..*scene
        };
        for (slot, k) in [8, 4].into_iter().enumerate() {
            let judge = with_k(k);
            let baked = bake_unit(texture, &judge, Model::GpuBinary32, k, uv, level);
            let tally = value_judge(&judge, uv, level, &baked);
            assert!(
                tally.contradicted.is_empty(),
                "{} k {k}: contradicted {:?}",
                what(),
                tally.contradicted
            );
            self.gpu[slot].add(&tally);
        }
        let judge = with_k(8);
        let baked = bake_unit(texture, &judge, Model::Exact, 8, uv, level);
        self.exact.add(&value_judge(&judge, uv, level, &baked));
        let baked = bake_unit(texture, &judge, Model::GpuBinary32, 16, uv, level);
        self.coarse.add(&value_judge(&with_k(4), uv, level, &baked));
    }

    fn print(&self, name: &str) {
        for (tally, label) in [
            (&self.gpu[0], "gpu-binary32 k 8, oracle k 8"),
            (&self.gpu[1], "gpu-binary32 k 4, oracle k 4"),
            (&self.exact, "exact, oracle k 8 (control)"),
            (&self.coarse, "gpu-binary32 k 16, oracle k 4 (control)"),
        ] {
            println!(
                "{name}: {label}: known checked {}, hits {}, contradicted {}",
                tally.checked,
                tally.hits,
                tally.contradicted.len()
            );
        }
    }
}

fn unorm8_codes(texels: &AlphaTexels) -> &[u8] {
    match texels {
        AlphaTexels::Unorm8(codes) => codes,
        _ => panic!("the committed textures are 8-bit"),
    }
}

/// The value oracle on the committed texel-aligned grid over the thorn
/// (183 alpha values) and chain (0 and 255) textures, linear, repeat,
/// cutoff 0.5: no known state of a GPU-model bake is contradicted at
/// `k = 8` or `k = 4`; the exact model's are (micro-triangle edges on
/// texel lines, the snapped point across them), and so are those of a
/// bake for `k = 16` judged at `k = 4`. The full tier runs more triangles.
#[test]
fn grid_linear_values_hold_under_the_texture_unit() {
    let triangles = read_triangles_json(&asset("assets/crytek-sponza/grid.tris.json")).unwrap();
    let full = full_tier();
    let every: Vec<usize> = (0..triangles.len()).collect();
    let runs: &[(&str, u32, &[usize], &[usize])] = &[
        ("sponza_thorn.png", 6, &[37, 101], &every),
        ("sponza_thorn.png", 8, &[64], &[9, 37, 64, 101]),
        ("chain.png", 6, &[9, 64], &every),
        ("chain.png", 8, &[37], &[9, 37, 64, 101]),
    ];
    let filter_error = f64::from(TextureUnit::default().filter_error);
    let mut all = Tiers::default();
    for &(file, level, subset, full_subset) in runs {
        let image = decode_alpha_image(
            &asset(&format!("assets/crytek-sponza/{file}")),
            &Limits::default(),
        )
        .unwrap();
        let texture = image.texture().unwrap();
        let scene = ValueScene {
            width: image.width,
            height: image.height,
            codes: unorm8_codes(&image.texels),
            sampler: Sampler {
                filter: Filter::Linear,
                ..Sampler::default()
            },
            cutoff: Cutoff::default(),
            subtexel_bits: 8,
            filter_error,
        };
        let chosen = if full { full_subset } else { subset };
        let mut tiers = Tiers::default();
        for &t in chosen {
            let uv = &triangles[t];
            tiers.run(&texture, &scene, uv, level, &|| {
                format!("{file} triangle {t} level {level}")
            });
        }
        let names = if chosen.len() == triangles.len() {
            format!("all {}", chosen.len())
        } else {
            format!("{chosen:?}")
        };
        tiers.print(&format!("grid {file} level {level} triangles {names}"));
        for (a, b) in all.gpu.iter_mut().zip(&tiers.gpu) {
            a.add(b);
        }
        all.exact.add(&tiers.exact);
        all.coarse.add(&tiers.coarse);
    }
    all.print("grid, all");
    assert!(all.gpu.iter().all(|t| t.checked > 1000));
    assert!(
        !all.exact.contradicted.is_empty(),
        "the exact model control found nothing"
    );
    assert!(
        !all.coarse.contradicted.is_empty(),
        "the k 16 / k 4 control found nothing"
    );
}

/// Generated adversarial bakes for the value oracle: textures 1..6 x 1..6
/// whose codes sit on and around a code `c` (`c - 1`, `c`, `c + 1`, 0,
/// 255, random), the cutoff `f32(c / 255)` (which texel `c` passes when
/// converted to the nearest binary32 and fails when converted down), both
/// comparisons, every address mode per axis, border 0 or 1, corners on
/// texel and half-texel lines near 0 and far away, axis-aligned and needle
/// triangles, levels 0..=5, linear filtering by value.
#[test]
fn generated_linear_values_hold_under_the_texture_unit() {
    let mut rng = SplitMix64::new(0x0a1e_5a7e);
    let cases = if full_tier() { 2000 } else { 200 };
    let filter_error = f64::from(TextureUnit::default().filter_error);
    let mut tiers = Tiers::default();
    for case in 0..cases {
        let (w, h) = (1 + rng.below(6) as u32, 1 + rng.below(6) as u32);
        // 51, 102, 153, 204: the cutoffs 0.2, 0.4, 0.6, 0.8 in binary32.
        let c = if rng.below(3) == 0 {
            rng.below(256) as u8
        } else {
            rng.pick(&[0u8, 1, 51, 102, 127, 128, 153, 204, 254, 255])
        };
        let codes: Vec<u8> = (0..w * h)
            .map(|_| match rng.below(6) {
                0 | 1 => c,
                2 => c.saturating_sub(1),
                3 => c.saturating_add(1),
                4 => rng.pick(&[0, 255]),
                _ => rng.below(256) as u8,
            })
            .collect();
        let comparison = rng.pick(&[Comparison::AtLeast, Comparison::Above]);
        let Ok(cutoff) = Cutoff::new((f64::from(c) / 255.0) as f32, comparison) else {
            continue;
        };
        let sampler = Sampler {
            filter: Filter::Linear,
            address_u: rng.pick(&AddressMode::ALL),
            address_v: rng.pick(&AddressMode::ALL),
            border_alpha: rng.pick(&[0.0, 1.0]),
        };
        let texture = Unorm8Texture::new(w, h, &codes).unwrap();
        let scene = ValueScene {
            width: w,
            height: h,
            codes: &codes,
            sampler,
            cutoff,
            subtexel_bits: 8,
            filter_error,
        };
        let uv = adversarial_uv(
            &mut rng,
            (w, h),
            &[0.0, 0.0, 0.0, 1.0, -3.0, 1000.0, 65536.0],
            case,
        );
        let level = (case % 6) as u32;
        tiers.run(&texture, &scene, &uv, level, &|| {
            format!("case {case}: {uv:?} level {level} {sampler:?} {cutoff:?} {w}x{h} {codes:?}")
        });
    }
    tiers.print(&format!("generated, {cases} bakes"));
    assert!(tiers.gpu.iter().all(|t| t.checked > 1000));
}

/// The value oracle's conversions: for every code, two adjacent binary32
/// values around `c / 255` (decided exactly: `v * 255` is exact in `f64`),
/// one value for 0 and 255; 51 converts to `0.2f32` (above 51/255) or the
/// value below it.
#[test]
fn faithful_pairs_bracket_every_code() {
    for c in 0..=255u8 {
        let (lo, hi) = faithful(c);
        let exact = f64::from(c);
        assert!(f64::from(lo) * 255.0 <= exact && exact <= f64::from(hi) * 255.0);
        if c == 0 || c == 255 {
            assert_eq!(lo, hi);
        } else {
            assert_eq!(next(lo, true), hi, "{c}");
        }
    }
    assert_eq!(faithful(51), (next(0.2, false), 0.2));
}
