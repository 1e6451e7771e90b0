//! The texture unit as the APIs allow it (`docs/bake.md`, "The texture
//! unit"): the two counterexamples to the earlier GPU model, now regression
//! tests, and the value rule's reach on a hand-made gradient.

use micromap_index::bake::{
    Baker, Comparison, Cutoff, Filter, LinearRule, Model, Sampler, TextureUnit, Unorm8Texture,
};
use micromap_index::micromap::{BakedOpacity, Format, State, TriangleOpacity, UnknownPolicy};
use micromap_index::Level;

fn bake(
    texture: &Unorm8Texture<'_>,
    sampler: Sampler,
    cutoff: Cutoff,
    uv: &[[f32; 2]; 3],
    level: u32,
    unit: TextureUnit,
) -> BakedOpacity {
    Baker::new_for(texture, sampler, cutoff, unit, u64::MAX)
        .unwrap()
        .bake(
            uv,
            Level::new(level).unwrap(),
            Format::FourState,
            UnknownPolicy::default(),
        )
        .unwrap()
        .opacity
}

/// Counterexample 1: every texel 51, cutoff `0.2 = f32(51 / 255)`. A GPU
/// converting 51 to `0x3e4ccccd` passes `>= 0x3e4ccccd`; one rounding the
/// other way fails: neither state is sound, so the triangle is unknown
/// (the earlier model compared the exact `51 / 255 < 0.2` and said
/// transparent). Both models, both filters.
#[test]
fn a_cutoff_equal_to_a_texel_in_binary32_leaves_it_unknown() {
    let texels = [51u8; 4];
    let texture = Unorm8Texture::new(2, 2, &texels).unwrap();
    let uv = [[0.1, 0.1], [0.9, 0.1], [0.1, 0.9]];
    assert_eq!(0.2f32.to_bits(), 0x3e4c_cccd);
    for filter in [Filter::Nearest, Filter::Linear] {
        for model in Model::ALL {
            let sampler = Sampler {
                filter,
                ..Sampler::default()
            };
            let cutoff = Cutoff::new(0.2, Comparison::AtLeast).unwrap();
            let baker = Baker::new(&texture, sampler, cutoff)
                .unwrap()
                .with_model(model);
            let baked = baker
                .bake(
                    &uv,
                    Level::new(0).unwrap(),
                    Format::FourState,
                    UnknownPolicy::default(),
                )
                .unwrap();
            let state = baked.opacity.state(0).unwrap();
            assert!(!state.is_known(), "{filter:?} {model:?}: {state:?}");
        }
    }
    // Just off the texel's values, the state is known again.
    for (cutoff, state) in [(0.19f32, State::Opaque), (0.21, State::Transparent)] {
        let cutoff = Cutoff::new(cutoff, Comparison::AtLeast).unwrap();
        let baked = bake(
            &texture,
            Sampler::default(),
            cutoff,
            &uv,
            0,
            TextureUnit::default(),
        );
        assert_eq!(baked.state(0), Some(state));
    }
}

/// Counterexample 2: alphas `[0, 0, 255, 255]`, nearest, the triangle's
/// right edge `2^-12` texels left of texel 2. A hit at `b1 = 1` reads
/// `x = 1.999755859375`; snapped to 1/256 it is 2.0: texel 2, opaque. The
/// micro-triangle is not transparent (the earlier model said it was).
/// With the snapping radius below the gap (16 sub-texel bits) it is.
#[test]
fn sub_texel_snapping_dilates_the_micro_triangle() {
    let texels = [0u8, 0, 255, 255];
    let texture = Unorm8Texture::new(4, 1, &texels).unwrap();
    let right = f32::from_bits(0x3eff_f800);
    assert_eq!(f64::from(right) * 4.0, 1.999_755_859_375);
    let uv = [[0.375, 0.0], [right, 0.0], [0.375, 1.0]];
    let sampler = Sampler::default();
    let cutoff = Cutoff::default();
    let baked = bake(&texture, sampler, cutoff, &uv, 0, TextureUnit::default());
    assert!(!baked.state(0).unwrap().is_known(), "{:?}", baked.state(0));
    let four = TextureUnit::default().with_subtexel_bits(4);
    assert!(!bake(&texture, sampler, cutoff, &uv, 0, four)
        .state(0)
        .unwrap()
        .is_known());
    let fine = TextureUnit::default().with_subtexel_bits(16);
    assert_eq!(
        bake(&texture, sampler, cutoff, &uv, 0, fine).state(0),
        Some(State::Transparent)
    );
}

/// Linear filtering by value: on a horizontal ramp of alphas 0, 64, 128,
/// 192, 255 the filtered value crosses 0.5 between the centres of texels 1
/// and 2, at `x = 1.5 + (0.5 - 64/255) / (64/255)`. A thin triangle left of
/// that line is transparent by value, though its footprint reads texel 2
/// (opaque): the footprint rule calls it unknown.
#[test]
fn linear_filtering_by_value_knows_what_the_footprint_rule_does_not() {
    let row = [0u8, 64, 128, 192, 255];
    let texels: Vec<u8> = row.iter().cycle().take(25).copied().collect();
    let texture = Unorm8Texture::new(5, 5, &texels).unwrap();
    let sampler = Sampler {
        filter: Filter::Linear,
        address_u: micromap_index::bake::AddressMode::ClampToEdge,
        address_v: micromap_index::bake::AddressMode::ClampToEdge,
        border_alpha: 0.0,
    };
    let crossing = 1.5 + (0.5 - 64.0 / 255.0) / (64.0 / 255.0);
    let x = ((crossing - 0.1) / 5.0) as f32;
    let uv = [[0.3, 0.4], [x, 0.4], [0.3, 0.6]];
    let by_value = bake(
        &texture,
        sampler,
        Cutoff::default(),
        &uv,
        0,
        TextureUnit::default(),
    );
    assert_eq!(by_value.state(0), Some(State::Transparent));
    let footprint = TextureUnit::default().with_linear_rule(LinearRule::Footprint);
    let by_footprint = bake(&texture, sampler, Cutoff::default(), &uv, 0, footprint);
    assert!(!by_footprint.state(0).unwrap().is_known());
    // Past the line: unknown by value too.
    let past = ((crossing + 0.1) / 5.0) as f32;
    let uv = [[0.3, 0.4], [past, 0.4], [0.3, 0.6]];
    let by_value = bake(
        &texture,
        sampler,
        Cutoff::default(),
        &uv,
        0,
        TextureUnit::default(),
    );
    assert!(!by_value.state(0).unwrap().is_known());
}

/// The verifier judges linear filtering by value on micro-triangles of
/// any size: a whole triangle (a special index) spanning 40 texels of a
/// ramp, left of where the filtered value reaches the cutoff, is
/// transparent by value (its footprint reads opaque texels: the footprint
/// rule contradicts it); one reaching past that line is contradicted, at a
/// witness where the filtered value passes.
#[test]
fn the_verifier_splits_large_micro_triangles_by_value() {
    // Alpha rises by 4 per texel: 128 (>= 0.5) from texel 32 on.
    let (w, h) = (64u32, 48u32);
    let texels: Vec<u8> = (0..w * h).map(|i| ((i % w) * 4) as u8).collect();
    let texture = Unorm8Texture::new(w, h, &texels).unwrap();
    let sampler = Sampler {
        filter: Filter::Linear,
        address_u: micromap_index::bake::AddressMode::ClampToEdge,
        address_v: micromap_index::bake::AddressMode::ClampToEdge,
        border_alpha: 0.0,
    };
    let unit = TextureUnit::default();
    let baker = Baker::new_for(&texture, sampler, Cutoff::default(), unit, u64::MAX).unwrap();
    let footprint = Baker::new_for(
        &texture,
        sampler,
        Cutoff::default(),
        unit.with_linear_rule(LinearRule::Footprint),
        u64::MAX,
    )
    .unwrap();
    // The filtered value at texel-space x is 4 (x - 0.5) / 255: 0.5 at
    // x = 32.375.
    let tx = |x: f32| x / w as f32;
    let ty = |y: f32| y / h as f32;
    // Up to x = 31.6: at most 0.4878, below 0.5 by more than the default
    // filter error (2^-7) and the margin.
    let left = [[tx(1.0), ty(2.0)], [tx(31.6), ty(2.0)], [tx(1.0), ty(44.0)]];
    let whole = TriangleOpacity::Special(State::Transparent);
    let v = baker.verify(&left, &whole);
    assert!(v.checked);
    assert_eq!((v.contradictions.len(), v.undecided), (0, 0), "{v:?}");
    // Its footprint at x = 31.6 reads texels 31 (124/255) and 32
    // (128/255): the footprint rule sees an opaque texel.
    assert_eq!(footprint.verify(&left, &whole).contradictions.len(), 1);
    // The bake agrees: transparent by value at a level where pieces are small.
    let baked = bake(&texture, sampler, Cutoff::default(), &left, 4, unit);
    assert!((0..256).all(|i| baked.state(i) == Some(State::Transparent)));

    let past = [[tx(1.0), ty(2.0)], [tx(40.0), ty(2.0)], [tx(1.0), ty(44.0)]];
    let v = baker.verify(&past, &whole);
    assert_eq!(v.contradictions.len(), 1, "{v:?}");
    let c = v.contradictions[0];
    let witness = c.witness.expect("a value witness");
    let x = witness.x as f64 / 2f64.powi(witness.shift_x as i32);
    // The witness's filtered value passes (within the filter's error).
    let value = 4.0 * (x - 0.5) / 255.0;
    assert!(value >= 0.5 - 1e-6, "witness x {x}: value {value}");
}

mod value_oracle {
    //! An independent check of linear filtering by value: every known
    //! micro-triangle of random bakes, sampled on a grid 4 times finer (and
    //! under the GPU model at the corners of the margin's box around each
    //! sample), in exact rational arithmetic: the bilinear mix of the
    //! texels' binary32 values, less (plus) the filter's error, passes
    //! (fails) the cutoff at every sample.

    use micromap_index::bake::{
        faithful_f32, AddressMode, Baker, Comparison, Cutoff, Filter, Model, Sampler, TextureUnit,
        Unorm8Texture, UvTriangle,
    };
    use micromap_index::inverse::micro_triangles;
    use micromap_index::micromap::{BakedOpacity, Format, State, UnknownPolicy};
    use micromap_index::Level;
    use micromap_index_test_support::SplitMix64;
    use num_bigint::BigInt;
    use num_rational::BigRational;
    use num_traits::{One, Zero};

    fn rational(x: f64) -> BigRational {
        BigRational::from_float(x).expect("finite")
    }

    struct Case {
        width: u32,
        height: u32,
        codes: Vec<u8>,
        sampler: Sampler,
        cutoff: Cutoff,
        uv: UvTriangle,
        level: Level,
    }

    impl Case {
        /// Texel `(i, j)` after wrapping (or the border): its lowest and
        /// highest binary32 values.
        fn texel(&self, i: &BigInt, j: &BigInt) -> (BigRational, BigRational) {
            let wrap = |mode: AddressMode, c: &BigInt, size: u32| -> Option<u32> {
                let c = i64::try_from(c).ok()?;
                mode.wrap(c, size)
            };
            if let (Some(x), Some(y)) = (
                wrap(self.sampler.address_u, i, self.width),
                wrap(self.sampler.address_v, j, self.height),
            ) {
                let c = self.codes[(y * self.width + x) as usize];
                let (lo, hi) = faithful_f32(f64::from(c) / 255.0);
                (rational(f64::from(lo)), rational(f64::from(hi)))
            } else {
                let (lo, hi) = faithful_f32(f64::from(self.sampler.border_alpha));
                (rational(f64::from(lo)), rational(f64::from(hi)))
            }
        }

        /// The bilinear mix at texel coordinate `(x, y)`: lowest, highest.
        fn value(&self, x: &BigRational, y: &BigRational) -> (BigRational, BigRational) {
            let half = BigRational::new(1.into(), 2.into());
            let (fx, fy) = (x - &half, y - &half);
            let (i, j) = (fx.floor().to_integer(), fy.floor().to_integer());
            let a = &fx - BigRational::from_integer(i.clone());
            let b = &fy - BigRational::from_integer(j.clone());
            let one = BigRational::one();
            let weights = [
                (&one - &a) * (&one - &b),
                &a * (&one - &b),
                (&one - &a) * &b,
                &a * &b,
            ];
            let mut lo = BigRational::zero();
            let mut hi = BigRational::zero();
            for (k, w) in weights.iter().enumerate() {
                let (di, dj) = ((k % 2) as i32, (k / 2) as i32);
                let (l, h) = self.texel(&(&i + di), &(&j + dj));
                lo += w * l;
                hi += w * h;
            }
            (lo, hi)
        }

        fn passes(&self, v: &BigRational) -> bool {
            let c = rational(f64::from(self.cutoff.alpha()));
            match self.cutoff.comparison() {
                Comparison::AtLeast => *v >= c,
                Comparison::Above => *v > c,
            }
        }

        /// The texel-space point of barycentrics `(a, b) / 2^bits`.
        fn point(&self, a: u64, b: u64, bits: u32) -> (BigRational, BigRational) {
            let den = BigRational::from_integer(BigInt::one() << bits);
            let a = BigRational::from_integer(a.into()) / &den;
            let b = BigRational::from_integer(b.into()) / &den;
            let w = BigRational::one() - &a - &b;
            let axis = |k: usize, size: u32| {
                (&w * rational(f64::from(self.uv[0][k]))
                    + &a * rational(f64::from(self.uv[1][k]))
                    + &b * rational(f64::from(self.uv[2][k])))
                    * BigRational::from_integer(size.into())
            };
            (axis(0, self.width), axis(1, self.height))
        }

        /// The GPU model's margin per axis, restated from `docs/bake.md`
        /// (interpolation, index window, sampler scaling, snapping `2^-8`).
        fn margin(&self, model: Model) -> [BigRational; 2] {
            let axis = |k: usize, size: u32| {
                if model == Model::Exact {
                    return BigRational::zero();
                }
                let c = self.uv.map(|c| f64::from(c[k]));
                let a = c.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                let d = (c[1] - c[0]).abs().max((c[2] - c[0]).abs());
                let s = f64::from(size);
                let m = s * d * 2f64.powi(-25 - self.level.get() as i32)
                    + s * a * (2f64.powi(-20) + 2f64.powi(-21))
                    + 2f64.powi(-21)
                    + 2f64.powi(-8);
                rational(m)
            };
            [axis(0, self.width), axis(1, self.height)]
        }
    }

    fn random_case(rng: &mut SplitMix64) -> Case {
        let width = 1 + (rng.next_u64() % 6) as u32;
        let height = 1 + (rng.next_u64() % 6) as u32;
        // Codes around the cutoffs, and cutoffs on texel values in binary32.
        let cut_code = (rng.next_u64() % 254 + 1) as u8;
        let cutoff_alpha = match rng.next_u64() % 3 {
            0 => (f64::from(cut_code) / 255.0) as f32,
            1 => 0.5,
            _ => 0.3,
        };
        let codes = (0..width * height)
            .map(|_| match rng.next_u64() % 5 {
                0 => cut_code,
                1 => 0,
                2 => 255,
                _ => (rng.next_u64() % 256) as u8,
            })
            .collect();
        let pick = |rng: &mut SplitMix64| AddressMode::ALL[(rng.next_u64() % 5) as usize];
        let sampler = Sampler {
            filter: Filter::Linear,
            address_u: pick(rng),
            address_v: pick(rng),
            border_alpha: [0.0f32, 1.0, 0.5][(rng.next_u64() % 3) as usize],
        };
        let comparison = [Comparison::AtLeast, Comparison::Above][(rng.next_u64() % 2) as usize];
        let mut c = || (rng.next_u64() % 1400) as f32 / 1000.0 - 0.2;
        let uv = [[c(), c()], [c(), c()], [c(), c()]];
        let level = Level::new((rng.next_u64() % 4) as u32).unwrap();
        Case {
            width,
            height,
            codes,
            sampler,
            cutoff: Cutoff::new(cutoff_alpha, comparison).unwrap(),
            uv,
            level,
        }
    }

    #[test]
    fn known_states_hold_at_every_sample_under_the_value_rule() {
        let mut rng = SplitMix64::new(0x7a1_0e5);
        let error = rational(f64::from(TextureUnit::default().filter_error));
        let mut known = [0u64; 2];
        for case_number in 0..120 {
            let case = random_case(&mut rng);
            let texture = Unorm8Texture::new(case.width, case.height, &case.codes).unwrap();
            for (m, model) in Model::ALL.into_iter().enumerate() {
                let baker = Baker::new(&texture, case.sampler, case.cutoff)
                    .unwrap()
                    .with_model(model);
                let baked = baker
                    .bake(
                        &case.uv,
                        case.level,
                        Format::FourState,
                        UnknownPolicy::default(),
                    )
                    .unwrap();
                let BakedOpacity::Map(map) = baked.opacity else {
                    continue;
                };
                let [mx, my] = case.margin(model);
                let extra = 2;
                for t in micro_triangles(case.level) {
                    let state = map.get(t.index()).unwrap();
                    if !state.is_known() {
                        continue;
                    }
                    known[m] += 1;
                    let (p0, p1, p2) = {
                        let v = t.vertices_scaled();
                        (v[0], v[1], v[2])
                    };
                    let s = 1u64 << extra;
                    for i in 0..=s {
                        for j in 0..=s - i {
                            let k = s - i - j;
                            let a = k * p0.0 + i * p1.0 + j * p2.0;
                            let b = k * p0.1 + i * p1.1 + j * p2.1;
                            let (x, y) = case.point(a, b, case.level.get() + extra);
                            for (dx, dy) in [(0, 0), (-1, -1), (1, -1), (1, 1), (-1, 1)] {
                                let px = &x + &mx * BigRational::from_integer(dx.into());
                                let py = &y + &my * BigRational::from_integer(dy.into());
                                let (lo, hi) = case.value(&px, &py);
                                let wrong = match state {
                                    State::Opaque => !case.passes(&(lo - &error)),
                                    _ => case.passes(&(hi + &error)),
                                };
                                assert!(
                                    !wrong,
                                    "case {case_number} {model:?}: micro-triangle {} {state:?} fails at ({px}, {py}); uv {:?} level {} codes {:?} {}x{} sampler {:?} cutoff {:?}",
                                    t.index(),
                                    case.uv,
                                    case.level,
                                    case.codes,
                                    case.width,
                                    case.height,
                                    case.sampler,
                                    case.cutoff,
                                );
                            }
                        }
                    }
                }
            }
        }
        println!("known micro-triangles checked (gpu-binary32, exact): {known:?}");
        assert!(known.iter().all(|&n| n > 500), "{known:?}");
    }
}
