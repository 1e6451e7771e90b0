//! Fuzz bodies for the bake's limits (issue 26): mesh bakes under work
//! budgets, and the baker's texel tables under a byte limit.

use micromap_index::bake::mesh::{
    bake_meshes, LevelRule, Material, Mesh, MeshOptions, MeshTriangles,
};
use micromap_index::bake::{
    AddressMode, AlphaTexture, Baker, Cutoff, Filter, Model, Sampler, TextureError, TriangleStatus,
    Unorm8Texture, UvTriangle, DEFAULT_BLOCK_BUDGET,
};
use micromap_index::micromap::{Format, UnknownPolicy};
use micromap_index::Level;

/// Reads bytes in order, zeros past the end.
struct Bytes<'a>(&'a [u8]);

impl Bytes<'_> {
    fn u8(&mut self) -> u8 {
        match self.0.split_first() {
            Some((&b, rest)) => {
                self.0 = rest;
                b
            }
            None => 0,
        }
    }

    fn u32(&mut self) -> u32 {
        u32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }
}

/// The most one micro-triangle spends past a budget (`bake::work`): under
/// the GPU model it may be classified under both models, each up to 7
/// lookups plus the block budget (the dilated one without its point
/// lookups, and one bounding block before both).
const OVERSHOOT: u64 = 8 + 2 * DEFAULT_BLOCK_BUDGET as u64;

/// A mesh bake under work budgets: never panics, spends within one
/// micro-triangle of each budget, counts every cut triangle, and every
/// baked triangle (cut or not) is sound by the verifier.
///
/// Input: width, height (1..=8 each), `w h` texel alphas, the address
/// mode per axis and the filter (one byte each), level (0..=5), 4-state or
/// 2-state, the model, the per-triangle and per-bake budgets (`u32` each,
/// little endian), then up to 4 triangles of 6 `f32` bits each.
///
/// ```
/// micromap_index_lab::fuzzing::bake_budgets(&[2, 2, 255, 0, 0, 255, 0, 0, 0, 3]);
/// ```
pub fn bake_budgets(data: &[u8]) {
    let mut b = Bytes(data);
    let (w, h) = (u32::from(b.u8() % 8) + 1, u32::from(b.u8() % 8) + 1);
    let texels: Vec<u8> = (0..w * h).map(|_| b.u8()).collect();
    let texture = Unorm8Texture::new(w, h, &texels).expect("w h texels");
    let address =
        |b: &mut Bytes<'_>| AddressMode::ALL[usize::from(b.u8()) % AddressMode::ALL.len()];
    let sampler = Sampler {
        address_u: address(&mut b),
        address_v: address(&mut b),
        filter: if b.u8() % 2 == 0 {
            Filter::Nearest
        } else {
            Filter::Linear
        },
        ..Sampler::default()
    };
    let level = Level::new(u32::from(b.u8() % 6)).expect("level <= 5");
    let format = if b.u8() % 2 == 0 {
        Format::FourState
    } else {
        Format::TwoState
    };
    let model = if b.u8() % 2 == 0 {
        Model::GpuBinary32
    } else {
        Model::Exact
    };
    let triangle_budget = u64::from(b.u32());
    let bake_budget = u64::from(b.u32());
    let mut triangles: Vec<UvTriangle> = Vec::new();
    while !b.0.is_empty() && triangles.len() < 4 {
        let mut c = || f32::from_bits(b.u32());
        triangles.push([[c(), c()], [c(), c()], [c(), c()]]);
    }
    let mesh = Mesh {
        triangles: MeshTriangles::Uv(&triangles),
        texture: &texture,
        material: Material {
            sampler,
            cutoff: Cutoff::default(),
            alpha_factor: 1.0,
            uv_transform: micromap_index::bake::UvTransform::IDENTITY,
        },
        vertex_alpha: None,
    };
    let options = MeshOptions {
        levels: LevelRule::Fixed(level),
        format,
        unknown: UnknownPolicy::Fallback,
        triangle_work_budget: triangle_budget,
        bake_work_budget: bake_budget,
        model,
        ..MeshOptions::default()
    };
    let baked = bake_meshes(&[mesh], &options, &mut |_, _| {})
        .unwrap_or_else(|e| panic!("bake failed: {e} ({data:02x?})"));
    let report = &baked.report;
    let n = triangles.len();
    assert_eq!(report.triangles, n);
    assert!(
        report.work <= bake_budget + OVERSHOOT,
        "work {} over the bake budget {bake_budget} ({data:02x?})",
        report.work
    );
    let s = report.status;
    assert_eq!(
        s.exact
            + s.not_finite
            + s.out_of_exact_range
            + s.block_budget_exceeded
            + s.work_budget_exceeded,
        n
    );
    let baker = Baker::new(&texture, sampler, Cutoff::default())
        .expect("the texture")
        .with_model(model);
    let mut cut = 0;
    for (i, uv) in triangles.iter().enumerate() {
        let t = baked.triangle(0, i).expect("every triangle baked");
        assert!(
            t.work <= triangle_budget + OVERSHOOT,
            "triangle work {} over its budget {triangle_budget} ({data:02x?})",
            t.work
        );
        assert_eq!(
            t.counts.iter().sum::<u64>(),
            level.micro_triangle_count() as u64
        );
        cut += usize::from(t.status == TriangleStatus::WorkBudgetExceeded);
        // 2-state maps carry no unknowns to trust: only 4-state is checked.
        if format == Format::FourState {
            let opacity = baked.opacity(0, i).expect("every triangle baked");
            let verdict = baker.verify(uv, &opacity.as_opacity());
            assert!(
                verdict.contradictions.is_empty(),
                "unsound under a work budget: {:?} at {uv:?} ({data:02x?})",
                verdict.contradictions[0]
            );
        }
    }
    assert_eq!(cut, s.work_budget_exceeded);
}

/// A texture that costs no memory: alpha from its coordinates.
struct Procedural {
    width: u32,
    height: u32,
}

impl AlphaTexture for Procedural {
    fn width(&self) -> u32 {
        self.width
    }
    fn height(&self) -> u32 {
        self.height
    }
    fn alpha(&self, x: u32, y: u32) -> f64 {
        f64::from((x ^ y) & 1)
    }
}

/// The baker's texel tables under a byte limit: `Baker::new_within` either
/// builds them (only when `w h + 2 (w + 1) (h + 1)` fits the limit) or
/// answers `AllocationFailed` naming the bytes and the limit; never an
/// abort, whatever the size.
///
/// Input: width and height (`u32` each, little endian; 0 allowed) and the
/// limit (`u32`, at most 4 GiB). The tables are built only under 2^22
/// bytes, so a run stays small.
///
/// ```
/// micromap_index_lab::fuzzing::texel_tables_within(&[0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 1]);
/// ```
pub fn texel_tables_within(data: &[u8]) {
    let mut b = Bytes(data);
    let (width, height) = (b.u32(), b.u32());
    let limit = u64::from(b.u32()).min(1 << 22);
    let texture = Procedural { width, height };
    let (w, h) = (u64::from(width), u64::from(height));
    // Saturating: `2 (w + 1) (h + 1)` passes `u64` near `u32::MAX` squared.
    let need = (w * h).saturating_add((w + 1).saturating_mul(h + 1).saturating_mul(2));
    match Baker::new_within(&texture, Sampler::default(), Cutoff::default(), limit) {
        Ok(baker) => {
            assert!(
                need <= limit,
                "{width}x{height}: {need} bytes built under {limit}"
            );
            assert_eq!(baker.size(), (width, height));
        }
        Err(TextureError::Empty) => assert!(width == 0 || height == 0),
        Err(TextureError::TooLarge { .. }) => assert!(w * h >= 1 << 32),
        Err(TextureError::AllocationFailed {
            bytes,
            limit: named,
        }) => {
            assert_eq!(named, limit);
            assert!(
                bytes > limit,
                "{width}x{height}: refused {bytes} bytes under {limit}"
            );
        }
        Err(other) => panic!("{width}x{height} under {limit}: {other}"),
    }
}
