//! [`Baker`]: one texture, sampler and cutoff; bakes triangles (and, in
//! [`super::verify`], verifies them). Construction, the triangle's frames
//! on the exact grid, and the choice of walk.

use super::alpha_test::{judges_by_value, AlphaTest, VertexScale};
use super::classify::{Classifier, Grid, Margin, Placed, TexelClasses};
use super::exact::{AxisFrame, FrameError};
use super::gpu::{margin, margin_transformed, Model};
use super::parallel::Runner;
use super::split::{walk_split, SPLIT_FROM_LEVEL};
use super::texture::{AlphaTexture, Cutoff, Sampler, TextureError};
use super::texture_unit::TextureUnit;
use super::triangle::{BakeError, BakedTriangle, TriangleStatus, UvTriangle};
use super::uv_transform::UvTransform;
use super::walk::{walk_whole, Spent};
use super::walk_variants::VariantWalk;
use super::work::DEFAULT_TRIANGLE_WORK_BUDGET;
use crate::micromap::BakedOpacity;
use crate::micromap::{Format, Micromap, State, UnknownPolicy};
use crate::num::wide::GridInt;
use crate::Level;
use alloc::vec::Vec;

/// Block tests a micro-triangle may use before the baker calls it unknown
/// (see [`Baker::with_block_budget`]).
pub const DEFAULT_BLOCK_BUDGET: u32 = 4096;

/// The largest margin (`2^k` grid units) on the exact grid: coordinates
/// below `2^98` plus it stay below [`COORDINATE_LIMIT`](super::exact).
const MARGIN_LIMIT: u32 = 97;

/// A texture under a sampler and a cutoff, ready to bake and verify
/// micromaps exactly (see the [module docs](super) for the model).
///
/// ```
/// use micromap_index::bake::{Baker, Cutoff, Model, Sampler, Unorm8Texture};
/// use micromap_index::micromap::{Format, State};
/// use micromap_index::Level;
///
/// // Left column opaque, right column transparent.
/// let texels = [255u8, 0, 255, 0];
/// let texture = Unorm8Texture::new(2, 2, &texels).unwrap();
/// let baker = Baker::new(&texture, Sampler::default(), Cutoff::default()).unwrap();
/// // A triangle inside the left column (x < 1/2: x = 1/2 would read the
/// // right column; and under the default GPU model an edge on x = 0 could
/// // read x = -1, the right column again under repeat) and one across both.
/// let left = [[0.05, 0.0], [0.45, 0.0], [0.05, 1.0]];
/// let across = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
/// let level = Level::new(2).unwrap();
/// let baked = baker.bake(&left, level, Format::FourState, Default::default()).unwrap();
/// assert_eq!(baked.counts[State::Opaque.bits() as usize], 16);
/// // The exact model (real points only) knows the edge on x = 0 too.
/// let exact = baker.clone().with_model(Model::Exact);
/// let on_edge = [[0.0, 0.0], [0.45, 0.0], [0.0, 1.0]];
/// let baked = exact.bake(&on_edge, level, Format::FourState, Default::default()).unwrap();
/// assert_eq!(baked.counts[State::Opaque.bits() as usize], 16);
/// let baked = baker.bake(&on_edge, level, Format::FourState, Default::default()).unwrap();
/// assert!(baked.counts[State::Opaque.bits() as usize] < 16);
/// // Across both columns the exact model knows transparent micro-triangles;
/// // the GPU model none (each has an edge on a column boundary).
/// let baked = exact.bake(&across, level, Format::FourState, Default::default()).unwrap();
/// assert!(baked.counts[State::Transparent.bits() as usize] > 0);
/// // Whatever it bakes, its verifier finds sound; the GPU model's does not.
/// assert!(exact.verify(&across, &baked.opacity.as_opacity()).contradictions.is_empty());
/// assert!(!baker.verify(&across, &baked.opacity.as_opacity()).contradictions.is_empty());
/// let baked = baker.bake(&across, level, Format::FourState, Default::default()).unwrap();
/// assert!(baker.verify(&across, &baked.opacity.as_opacity()).contradictions.is_empty());
/// ```
#[derive(Clone, Debug)]
pub struct Baker {
    pub(super) classifier: Classifier,
    work_budget: u64,
    pub(super) model: Model,
    pub(super) texture_unit: TextureUnit,
    pub(super) uv_transform: UvTransform,
}

impl Baker {
    /// Classifies every texel of `texture` once under the default
    /// [`TextureUnit`] (one pass, `2 (w + 1) (h + 1)` bytes of prefix sums,
    /// and 8 bytes of values per texel for linear filtering by value).
    pub fn new(
        texture: &(impl AlphaTexture + ?Sized),
        sampler: Sampler,
        cutoff: Cutoff,
    ) -> Result<Baker, TextureError> {
        Self::new_within(texture, sampler, cutoff, u64::MAX)
    }

    /// [`new`](Self::new) with the tables held to `max_bytes`
    /// ([`table_bytes`](Self::table_bytes)): over it, or refused by the
    /// allocator, the answer is [`TextureError::AllocationFailed`], never
    /// an abort (`new` gives the same error when the allocator refuses).
    pub fn new_within(
        texture: &(impl AlphaTexture + ?Sized),
        sampler: Sampler,
        cutoff: Cutoff,
        max_bytes: u64,
    ) -> Result<Baker, TextureError> {
        Self::new_for(texture, sampler, cutoff, TextureUnit::default(), max_bytes)
    }

    /// [`new_within`](Self::new_within) for the texture unit `unit` (its
    /// sub-texel snapping, interpolation and filter; the tables depend on
    /// the filter's error, so a unit is chosen when the baker is made). A
    /// unit outside its ranges ([`TextureUnit::check`]) is refused.
    pub fn new_for(
        texture: &(impl AlphaTexture + ?Sized),
        sampler: Sampler,
        cutoff: Cutoff,
        unit: TextureUnit,
        max_bytes: u64,
    ) -> Result<Baker, TextureError> {
        Self::new_on(
            texture,
            (sampler, cutoff, unit, 1.0),
            max_bytes,
            &Runner::serial(),
        )
    }

    /// The bytes the tables of a `width x height` texture take under
    /// `sampler` and `unit`: `w h` class bytes, `2 (w + 1) (h + 1)` bytes
    /// of prefix sums, and under linear filtering by value 8 bytes of
    /// values per texel (saturated). A texture with texels whose binary32
    /// values straddle the cutoff takes a second `2 (w + 1) (h + 1)`.
    #[must_use]
    pub fn table_bytes(width: u32, height: u32, sampler: Sampler, unit: TextureUnit) -> u64 {
        TexelClasses::table_bytes(width, height, judges_by_value(sampler.filter, &unit))
    }

    /// [`new_for`](Self::new_for), its tables built on `runner`'s threads
    /// (the same tables on any), for a texture whose values carry a factor
    /// of `scale` (the filter's error scales with it).
    pub(crate) fn new_on(
        texture: &(impl AlphaTexture + ?Sized),
        test: (Sampler, Cutoff, TextureUnit, f64),
        max_bytes: u64,
        runner: &Runner,
    ) -> Result<Baker, TextureError> {
        Self::new_on_vertex(texture, test, None, max_bytes, runner)
    }

    /// [`new_on`](Self::new_on) for triangles whose vertex alphas all lie
    /// in `vertex` (when given): their bakes ([`bake_split`](Self::bake_split))
    /// multiply the texture's alpha by them.
    pub(crate) fn new_on_vertex(
        texture: &(impl AlphaTexture + ?Sized),
        (sampler, cutoff, unit, scale): (Sampler, Cutoff, TextureUnit, f64),
        vertex: Option<VertexScale>,
        max_bytes: u64,
        runner: &Runner,
    ) -> Result<Baker, TextureError> {
        let unit = unit.check().map_err(TextureError::TextureUnit)?;
        let test = AlphaTest::new(cutoff, sampler.filter, &unit, scale).with_vertex(vertex);
        Ok(Baker {
            classifier: Classifier {
                classes: TexelClasses::new_within(texture, sampler, test, max_bytes, runner)?,
                block_budget: DEFAULT_BLOCK_BUDGET,
            },
            work_budget: DEFAULT_TRIANGLE_WORK_BUDGET,
            model: Model::default(),
            texture_unit: unit,
            uv_transform: UvTransform::IDENTITY,
        })
    }

    /// The same baker for another [`Model`] (the default is
    /// [`Model::GpuBinary32`]); [`bake`](Self::bake) and
    /// [`verify`](Self::verify) both follow it.
    #[must_use]
    pub fn with_model(mut self, model: Model) -> Baker {
        self.model = model;
        self
    }

    /// The same baker for triangles whose texture coordinates the shader
    /// transforms (glTF's `KHR_texture_transform`) before sampling:
    /// [`bake`](Self::bake) and [`verify`](Self::verify) then take the
    /// *untransformed* vertex coordinates, place the triangle at their
    /// transformed images ([`UvTransform::place`]) and, under
    /// [`Model::GpuBinary32`], widen the margin by the transform's binary32
    /// error (`docs/bake.md`, "Texture transforms"). Under
    /// [`Model::Exact`] a triangle is placed only where every vertex's
    /// image is exactly binary32 ([`UvTransform::exact_image`]); otherwise
    /// it is unknown ([`TriangleStatus::OutOfExactRange`]).
    #[must_use]
    pub fn with_uv_transform(mut self, transform: UvTransform) -> Baker {
        self.uv_transform = transform;
        self
    }

    /// The texture transform it bakes and verifies for.
    #[must_use]
    pub fn uv_transform(&self) -> UvTransform {
        self.uv_transform
    }

    /// The texture unit it bakes and verifies for.
    #[must_use]
    pub fn texture_unit(&self) -> TextureUnit {
        self.texture_unit
    }

    /// The model it bakes and verifies for.
    #[must_use]
    pub fn model(&self) -> Model {
        self.model
    }

    /// The same baker with another cap on block tests per micro-triangle
    /// (at least 1).
    #[must_use]
    pub fn with_block_budget(mut self, budget: u32) -> Baker {
        self.classifier.block_budget = budget.max(1);
        self
    }

    /// The same baker with another cap on the work units one
    /// [`bake`](Self::bake) may spend (default
    /// [`DEFAULT_TRIANGLE_WORK_BUDGET`]; see [bounded work](crate::bake#bounded-work)).
    #[must_use]
    pub fn with_work_budget(mut self, units: u64) -> Baker {
        self.work_budget = units;
        self
    }

    /// The texture's width and height.
    #[must_use]
    pub fn size(&self) -> (u32, u32) {
        (
            self.classifier.classes.width,
            self.classifier.classes.height,
        )
    }

    /// The sampler.
    #[must_use]
    pub fn sampler(&self) -> Sampler {
        self.classifier.classes.sampler
    }

    /// The triangle's frames on both axes and their grid: for the GPU
    /// model, fine enough to hold the margin `units * 2^e` texels of
    /// [`margin`] (a grid unit of at most `2^e`), which is then
    /// `units * 2^(shift + e)` grid units.
    pub(super) fn frames(
        &self,
        model: Model,
        uv: &UvTriangle,
        level: Level,
    ) -> Result<(AxisFrame, AxisFrame, Grid), FrameError> {
        let n = level.get();
        let transform = &self.uv_transform;
        if !transform.is_identity() && uv.iter().flatten().any(|x| !x.is_finite()) {
            return Err(FrameError::NotFinite);
        }
        // Where the triangle is placed, and the transform's error terms
        // (`None`: no transform, the margin of `docs/bake.md` as it was).
        let (placed, errors) = if transform.is_identity() {
            (*uv, None)
        } else {
            match model {
                Model::Exact => {
                    let mut placed = *uv;
                    for (p, c) in placed.iter_mut().zip(uv) {
                        *p = transform.exact_image(*c).ok_or(FrameError::OutOfRange)?;
                    }
                    (placed, None)
                }
                Model::GpuBinary32 => {
                    let placed = uv.map(|c| transform.place(c));
                    if placed.iter().flatten().any(|x| !x.is_finite()) {
                        return Err(FrameError::OutOfRange);
                    }
                    (placed, Some(transform.axis_errors(uv, &placed)))
                }
            }
        };
        let axis = |k: usize, size: u32| -> Result<(AxisFrame, Option<Margin>), FrameError> {
            let c = placed.map(|c| c[k]);
            match model {
                Model::Exact => Ok((AxisFrame::new(c, size, n, 0)?, None)),
                Model::GpuBinary32 => {
                    if c.iter().any(|x| !x.is_finite()) {
                        return Err(FrameError::NotFinite);
                    }
                    let m = match &errors {
                        None => margin(c, size, n, &self.texture_unit),
                        Some(e) => margin_transformed(c, &e[k], size, n, &self.texture_unit),
                    }
                    .ok_or(FrameError::OutOfRange)?;
                    // A grid unit of at most 2^exponent texels, on which the
                    // margin is `units` times a power of two.
                    let frame = AxisFrame::new(c, size, n, (-m.exponent).max(0) as u32)?;
                    let shift = frame.shift as i32 + m.exponent;
                    if shift < 0 || shift + 3 > MARGIN_LIMIT as i32 {
                        return Err(FrameError::OutOfRange);
                    }
                    let margin = Margin {
                        units: m.units,
                        shift: shift as u32,
                    };
                    Ok((frame, Some(margin)))
                }
            }
        };
        let (fx, mx) = axis(0, self.classifier.classes.width)?;
        let (fy, my) = axis(1, self.classifier.classes.height)?;
        let grid = Grid {
            shifts: (fx.shift, fy.shift),
            margin: (mx, my),
        };
        Ok((fx, fy, grid))
    }

    pub(super) fn place(
        fx: &AxisFrame,
        fy: &AxisFrame,
        level: u32,
        vertices: [(u64, u64); 3],
    ) -> Placed<i128> {
        Placed {
            x: vertices.map(|(a, b)| fx.at(level, a, b)),
            y: vertices.map(|(a, b)| fy.at(level, a, b)),
        }
    }

    /// Bakes one triangle at `level` into `format`.
    ///
    /// Each micro-triangle is opaque (transparent) exactly when every point
    /// of it, closed, reads only opaque (transparent) texels under the
    /// sampler model; otherwise it is unknown, split into unknown-opaque /
    /// unknown-transparent by the texel under its centroid. A 2-state map
    /// resolves unknowns with `two_state` ([`UnknownPolicy::Fallback`]:
    /// by that split). Non-finite or off-grid coordinates give the special
    /// index unknown-opaque ([`TriangleStatus`]). The counts are taken
    /// before the 2-state resolution. The work is capped by the baker's
    /// work budget ([`with_work_budget`](Self::with_work_budget)), as
    /// [`bake_within`](Self::bake_within) says.
    pub fn bake(
        &self,
        uv: &UvTriangle,
        level: Level,
        format: Format,
        two_state: UnknownPolicy,
    ) -> Result<BakedTriangle, BakeError> {
        self.bake_within(uv, level, format, two_state, self.work_budget)
    }

    /// [`bake`](Self::bake) spending at most about `max_work` work units
    /// ([bounded work](crate::bake#bounded-work)): once they are spent, every micro-triangle
    /// not yet decided is unknown (sound) and the status is
    /// [`TriangleStatus::WorkBudgetExceeded`]. [`BakedTriangle::work`] says
    /// what it spent.
    ///
    /// ```
    /// use micromap_index::bake::{Baker, Cutoff, Sampler, TriangleStatus, Unorm8Texture};
    /// use micromap_index::micromap::{Format, State};
    /// use micromap_index::Level;
    /// // A checkerboard: most micro-triangles need a search.
    /// let texels: Vec<u8> = (0..64).map(|i| if (i + i / 8) % 2 == 0 { 255 } else { 0 }).collect();
    /// let texture = Unorm8Texture::new(8, 8, &texels).unwrap();
    /// let baker = Baker::new(&texture, Sampler::default(), Cutoff::default()).unwrap();
    /// let uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    /// let (level, four) = (Level::new(6).unwrap(), Format::FourState);
    /// let full = baker.bake(&uv, level, four, Default::default()).unwrap();
    /// assert_eq!(full.status, TriangleStatus::Exact);
    /// let cut = baker.bake_within(&uv, level, four, Default::default(), full.work / 2).unwrap();
    /// assert_eq!(cut.status, TriangleStatus::WorkBudgetExceeded);
    /// assert!(cut.work < full.work);
    /// let known = |c: [u64; 4]| c[State::Opaque.bits() as usize] + c[State::Transparent.bits() as usize];
    /// assert!(known(cut.counts) < known(full.counts));
    /// ```
    pub fn bake_within(
        &self,
        uv: &UvTriangle,
        level: Level,
        format: Format,
        two_state: UnknownPolicy,
        max_work: u64,
    ) -> Result<BakedTriangle, BakeError> {
        self.bake_as(self.model, uv, level, format, two_state, max_work, false)
    }

    /// [`bake_within`](Self::bake_within), with a triangle of
    /// [`SPLIT_FROM_LEVEL`] or above walked on the current thread pool's
    /// threads when `split` (the same result: see [`walk`](Self::walk)),
    /// its texture's alpha times the vertex `alphas` when given
    /// ([`bake_variants`](Self::bake_variants) with one variant).
    pub(crate) fn bake_split(
        &self,
        (uv, alphas): (&UvTriangle, Option<[f32; 3]>),
        level: Level,
        format: Format,
        two_state: UnknownPolicy,
        max_work: u64,
        split: bool,
    ) -> Result<BakedTriangle, BakeError> {
        let model = self.model;
        match alphas {
            None => self.bake_as(model, uv, level, format, two_state, max_work, split),
            Some(alphas) => {
                let mut one = self.bake_variants(
                    model,
                    (uv, &[alphas]),
                    level,
                    (format, two_state),
                    max_work,
                )?;
                Ok(one.remove(0))
            }
        }
    }

    /// A triangle `level` deep, every micro-triangle unknown-opaque with
    /// `status` (what a triangle whose coordinates cannot be placed gets).
    fn whole_unknown(level: Level, status: TriangleStatus) -> BakedTriangle {
        let mut counts = [0u64; 4];
        counts[State::UnknownOpaque.bits() as usize] = level.micro_triangle_count() as u64;
        BakedTriangle {
            opacity: BakedOpacity::Special(State::UnknownOpaque),
            status,
            counts,
            widened: 0,
            work: 0,
            speculative_work: 0,
        }
    }

    /// [`bake_within`](Self::bake_within) under `model`, split as
    /// [`bake_split`](Self::bake_split) says.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn bake_as(
        &self,
        model: Model,
        uv: &UvTriangle,
        level: Level,
        format: Format,
        two_state: UnknownPolicy,
        max_work: u64,
        split: bool,
    ) -> Result<BakedTriangle, BakeError> {
        let mut map = Micromap::new(level, format)?;
        let (fx, fy, grid) = match self.frames(model, uv, level) {
            Ok(frames) => frames,
            Err(FrameError::NotFinite) => {
                return Ok(Self::whole_unknown(level, TriangleStatus::NotFinite))
            }
            Err(FrameError::OutOfRange) => {
                let mut unknown = Self::whole_unknown(level, TriangleStatus::OutOfExactRange);
                // The GPU model's margin can push a triangle the exact
                // grid holds off it: then the whole exact bake's known
                // micro-triangles are the widening's cost.
                if model == Model::GpuBinary32 {
                    let four = Format::FourState;
                    let exact =
                        self.bake_as(Model::Exact, uv, level, four, two_state, max_work, split)?;
                    unknown.widened = exact.counts[0] + exact.counts[1];
                    unknown.work = exact.work;
                }
                return Ok(unknown);
            }
        };
        let n = level.get();
        let side = 1u64 << n;
        let root = Self::place(&fx, &fy, n, [(0, 0), (side, 0), (0, side)]);
        let mut counts = [0u64; 4];
        let out = (&mut map, &mut counts);
        let split = split && n >= SPLIT_FROM_LEVEL;
        let walk = |c: &Classifier, out| match root.narrowed(grid) {
            Some(narrow) => Self::walk(c, narrow, (n, grid), two_state, max_work, split, out),
            None => Self::walk(c, root, (n, grid), two_state, max_work, split, out),
        };
        let (spent, speculative_work) = walk(&self.classifier, out)?;
        Ok(BakedTriangle {
            opacity: BakedOpacity::Map(map),
            status: spent.status,
            counts,
            widened: spent.widened,
            work: spent.work,
            speculative_work,
        })
    }

    /// One triangle with several vertex-alpha variants (at most
    /// [`MAX_VARIANTS`](super::walk_variants::MAX_VARIANTS)), each its texture's alpha times its `alphas`, in
    /// one walk ([`super::walk_variants`]): one bake per variant, in order.
    /// The work is the walk's, given to the first (the others' is 0), and
    /// `max_work` caps the walk. Only on a baker made for their alphas
    /// ([`covers`](Self::covers)); a variant it does not cover is unknown
    /// ([`TriangleStatus::OutOfExactRange`]).
    pub(crate) fn bake_variants(
        &self,
        model: Model,
        (uv, alphas): (&UvTriangle, &[[f32; 3]]),
        level: Level,
        (format, two_state): (Format, UnknownPolicy),
        max_work: u64,
    ) -> Result<Vec<BakedTriangle>, BakeError> {
        let mut baked: Vec<BakedTriangle> = Vec::with_capacity(alphas.len());
        let (fx, fy, grid) = match self.frames(model, uv, level) {
            Ok(frames) => frames,
            Err(FrameError::NotFinite) => {
                baked.resize(
                    alphas.len(),
                    Self::whole_unknown(level, TriangleStatus::NotFinite),
                );
                return Ok(baked);
            }
            Err(FrameError::OutOfRange) => {
                let unknown = Self::whole_unknown(level, TriangleStatus::OutOfExactRange);
                baked.resize(alphas.len(), unknown);
                // As in `bake_as`: the exact bake's known micro-triangles
                // are the widening's cost.
                if model == Model::GpuBinary32 {
                    let four = (Format::FourState, two_state);
                    let exact =
                        self.bake_variants(Model::Exact, (uv, alphas), level, four, max_work)?;
                    for (b, e) in baked.iter_mut().zip(exact) {
                        b.widened = e.counts[0] + e.counts[1];
                        b.work = e.work;
                    }
                }
                return Ok(baked);
            }
        };
        // Only the variants the baker covers are walked.
        let covers: Vec<bool> = alphas.iter().map(|&a| self.covers(a)).collect();
        debug_assert!(
            covers.iter().all(|&c| c),
            "a baker made for other vertex alphas"
        );
        let covered: Vec<[f32; 3]> = alphas
            .iter()
            .zip(&covers)
            .filter_map(|(&a, &c)| c.then_some(a))
            .collect();
        let n = level.get();
        let side = 1u64 << n;
        let root = Self::place(&fx, &fy, n, [(0, 0), (side, 0), (0, side)]);
        let mut walk = VariantWalk::new(
            &self.classifier,
            (n, grid),
            (two_state, format),
            max_work,
            &covered,
        )?;
        let bary = [(0, 0), (side, 0), (0, side)];
        let open = walk.all();
        if let Some(narrow) = root.narrowed(grid) {
            let vertices = [0, 1, 2].map(|k| (narrow.x[k], narrow.y[k]));
            walk.visit((0, 0), (vertices, bary), false, open)?;
        } else {
            let vertices = [0, 1, 2].map(|k| (root.x[k], root.y[k]));
            walk.visit((0, 0), (vertices, bary), false, open)?;
        }
        let (work, out_of_work) = (walk.work, walk.out_of_work);
        let mut walked = walk.out.into_iter();
        for covered in covers {
            if !covered {
                baked.push(Self::whole_unknown(level, TriangleStatus::OutOfExactRange));
                continue;
            }
            let v = walked
                .next()
                .expect("a walked variant for every covered one");
            let status = if out_of_work {
                TriangleStatus::WorkBudgetExceeded
            } else if v.exhausted {
                TriangleStatus::BlockBudgetExceeded
            } else {
                TriangleStatus::Exact
            };
            baked.push(BakedTriangle {
                opacity: BakedOpacity::Map(v.map),
                status,
                counts: v.counts,
                widened: v.widened,
                work: if baked.is_empty() { work } else { 0 },
                speculative_work: 0,
            });
        }
        Ok(baked)
    }

    /// Whether its texel classes hold for a triangle with vertex alphas
    /// `alphas` (made by [`new_on_vertex`](Self::new_on_vertex) for a range
    /// holding theirs, under linear filtering by value): the condition for
    /// baking or verifying it with them.
    pub(super) fn covers(&self, alphas: [f32; 3]) -> bool {
        let test = &self.classifier.classes.test;
        test.by_value
            && test.vertex.is_some_and(|v| {
                let whole = VertexScale::of_triangle(alphas);
                v.lo <= whole.lo && whole.hi <= v.hi
            })
    }

    /// The top-down walk of [`bake`](Self::bake) from the whole triangle
    /// `root` (on the grid of `level`), in coordinates of type `C`: fills
    /// the map and counts of `out`, and says how it went, what it spent
    /// and what it spent besides (speculative work thrown away by a split
    /// walk). The caller picks `C` so that the walk stays in range (see
    /// [`NARROW_WALK_COORDINATE`](super::classify)); the result is the same in every
    /// type, split ([`super::split`]) or not.
    #[allow(clippy::too_many_arguments)]
    fn walk<C: GridInt>(
        classifier: &Classifier,
        root: Placed<C>,
        (level, grid): (u32, Grid),
        two_state: UnknownPolicy,
        max_work: u64,
        split: bool,
        out: (&mut Micromap, &mut [u64; 4]),
    ) -> Result<(Spent, u64), BakeError> {
        if split {
            let s = walk_split(classifier, (root, level, grid), two_state, max_work, out)?;
            Ok((s.spent, s.speculative))
        } else {
            let spent = walk_whole(classifier, (root, level, grid), two_state, max_work, out)?;
            Ok((spent, 0))
        }
    }
}

#[cfg(test)]
mod tests;
