//! [`Baker`]: one texture, sampler and cutoff; bakes and verifies triangles.

use super::classify::{is_small, Block, Classes, Grid, Search, TexelClasses};
use super::exact::{narrowed_below, AxisFrame, ExactTriangle, FrameError, TexelPoint};
use super::gpu::{margin_exponent, Model};
use super::parallel::Runner;
use super::texture::{AlphaTexture, Cutoff, Sampler, TextureError};
use super::triangle::{BakeError, BakedOpacity, BakedTriangle, TriangleStatus, UvTriangle};
use super::work::DEFAULT_TRIANGLE_WORK_BUDGET;
use crate::inverse::micro_triangles;
use crate::micromap::{Format, Micromap, MicromapError, State, TriangleOpacity, UnknownPolicy};
use crate::num::wide::GridInt;
use crate::Level;
use alloc::vec::Vec;

/// Block tests a micro-triangle may use before the baker calls it unknown
/// (see [`Baker::with_block_budget`]).
pub const DEFAULT_BLOCK_BUDGET: u32 = 4096;

/// A micro-triangle whose known state the texture contradicts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Contradiction {
    /// The micro-triangle's index (0 for a special index).
    pub micro_triangle: u64,
    /// The state the micromap gives it.
    pub state: State,
    /// A point of the closed micro-triangle whose footprint holds a texel of
    /// the other class; under [`Model::GpuBinary32`] the footprint of the
    /// point dilated by the model's margin, so the point itself may lie
    /// just outside that texel's own footprint (`None` only if the exact
    /// point search gave up, in which case the block search alone proved
    /// the contradiction).
    pub witness: Option<TexelPoint>,
    /// The texel of the other class in that (dilated) footprint, after
    /// wrapping (`None`: the border colour).
    pub texel: Option<(u32, u32)>,
}

/// What [`Baker::verify`] found for one triangle.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Verification {
    /// Micro-triangles whose known state the texture contradicts.
    pub contradictions: Vec<Contradiction>,
    /// Known micro-triangles checked.
    pub known: u64,
    /// Unknown micro-triangles (nothing to check).
    pub unknown: u64,
    /// Known micro-triangles the block budget could not decide (neither
    /// confirmed nor contradicted).
    pub undecided: u64,
    /// `false` when the coordinates are not finite or off the exact grid:
    /// then nothing was checked.
    pub checked: bool,
}

/// What [`Baker::verify_each`] counted for one triangle (the contradictions
/// themselves went to its callback).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub struct VerifyCounts {
    /// Known micro-triangles whose state the texture contradicts (every
    /// one, also those the callback did not keep).
    pub contradictions: u64,
    /// Known micro-triangles checked.
    pub known: u64,
    /// Known micro-triangles past the caller's cap: not checked.
    pub unchecked: u64,
    /// Unknown micro-triangles (nothing to check).
    pub unknown: u64,
    /// Known micro-triangles the block budget could not decide (neither
    /// confirmed nor contradicted).
    pub undecided: u64,
    /// `false` when the coordinates are not finite or off the exact grid:
    /// then nothing was checked.
    pub checked: bool,
}

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
    classes: TexelClasses,
    budget: u32,
    work_budget: u64,
    model: Model,
}

/// `floor(q / 3)`, in `i64` where `q` fits (an `i128` division is a
/// library call; texel coordinates nearly always fit).
#[inline]
fn floor_third(q: i128) -> i128 {
    match i64::try_from(q) {
        Ok(q) => i128::from(q.div_euclid(3)),
        Err(_) => q.div_euclid(3),
    }
}

/// Sets a node aside at the split depth (see [`Baker::walk`]); out of the
/// walk's hot path.
#[cold]
#[inline(never)]
fn set_aside<C>(walk: &mut Walk<'_, C>, index: u64, vertices: [(C, C); 3], top_flip: bool) {
    walk.frontier.push(Node {
        index,
        vertices,
        top_flip,
    });
}

/// The midpoint of two grid points of a node above the map's level (exact:
/// see [`Baker::visit`]).
#[inline]
fn midpoint<C: GridInt>(a: (C, C), b: (C, C)) -> (C, C) {
    ((a.0 + b.0) >> 1, (a.1 + b.1) >> 1)
}

/// Sets `count` states of `map` from `first`: one leaf (most calls) by
/// [`Micromap::set`], a range by [`Micromap::fill`].
#[inline]
fn put(map: &mut Micromap, first: u64, count: u64, state: State) -> Result<(), MicromapError> {
    if count == 1 {
        map.set(first, state)
    } else {
        map.fill(first, count, state)
    }
}

/// What the walk of [`Baker::bake`] carries from node to node: the level,
/// the frames' shifts, the 2-state policy, the map and counts it fills,
/// whether a micro-triangle ran out of budget, and the search's stack.
struct Walk<'a, C> {
    level: u32,
    /// Work units spent and allowed ([bounded work](crate::bake#bounded-work)).
    work: u64,
    max_work: u64,
    out_of_work: bool,
    grid: Grid,
    two_state: UnknownPolicy,
    map: &'a mut Micromap,
    counts: &'a mut [u64; 4],
    exhausted: bool,
    /// Unknown leaves the exact model knows (see [`BakedTriangle::widened`]).
    widened: u64,
    stack: Vec<Block>,
    /// While the top of a split walk is walked ([`SPLIT_FROM_LEVEL`]):
    /// the depth whose nodes are set aside for walks of their own
    /// (`u32::MAX` otherwise), and those nodes.
    split_depth: u32,
    frontier: Vec<Node<C>>,
}

impl<'a, C> Walk<'a, C> {
    /// A walk of `level` on `grid` with `max_work` units, filling `map`
    /// and `counts`, not split.
    fn new(
        level: u32,
        grid: Grid,
        two_state: UnknownPolicy,
        max_work: u64,
        map: &'a mut Micromap,
        counts: &'a mut [u64; 4],
    ) -> Self {
        Walk {
            level,
            work: 0,
            max_work,
            out_of_work: false,
            grid,
            two_state,
            map,
            counts,
            exhausted: false,
            widened: 0,
            stack: Vec::new(),
            split_depth: u32::MAX,
            frontier: Vec::new(),
        }
    }

    /// How it went.
    fn spent(&self) -> Spent {
        let status = if self.out_of_work {
            TriangleStatus::WorkBudgetExceeded
        } else if self.exhausted {
            TriangleStatus::BudgetExceeded
        } else {
            TriangleStatus::Exact
        };
        Spent {
            status,
            work: self.work,
            widened: self.widened,
        }
    }
}

/// What one subtree of a split walk made and found.
struct Subtree {
    map: Micromap,
    counts: [u64; 4],
    work: u64,
    widened: u64,
    exhausted: bool,
    out_of_work: bool,
}

/// A node of the walk set aside at the split depth: its index at that
/// depth, its grid vertices and its `top_flip`.
#[derive(Clone, Copy, Debug)]
struct Node<C> {
    index: u64,
    vertices: [(C, C); 3],
    top_flip: bool,
}

/// A triangle baked at this level or above, on more than one thread, is
/// split: the walk's top levels run first, and the subtrees of
/// [`SPLIT_SUBTREE_LEVEL`] below them (4^8 micro-triangles each) are
/// walked in parallel, each into a map of its own, copied in after (see
/// [`Baker::walk`]). One level-12 triangle is 16M micro-triangles: one
/// thread's work for seconds otherwise.
const SPLIT_FROM_LEVEL: u32 = 10;

/// The level of the subtrees a split walk hands out.
const SPLIT_SUBTREE_LEVEL: u32 = 8;

/// Subtrees a split walk walks at once: their maps (16 KiB each in 4-state)
/// are what it holds beyond the triangle's own map. (3 in unit tests, so
/// that their level-10 and -11 triangles take several batches.)
const SPLIT_BATCH: usize = if cfg!(test) { 3 } else { 256 };

/// The points of a micro-triangle whose footprints
/// [`Baker::classify_mixed_block`] reads before its search.
#[derive(Clone, Copy, Debug)]
enum Points {
    /// None: this model's exact grid read them already, and found that the
    /// micro-triangle reads these classes (not both; none if unsure).
    None(Classes),
    /// Its vertices, then its edge midpoints.
    All,
    /// Its edge midpoints: the walk read its vertices, whose footprints
    /// hold these classes (not both).
    Midpoints(Classes),
}

/// How a walk went: its status and the work units it spent.
struct Spent {
    status: TriangleStatus,
    work: u64,
    widened: u64,
}

/// One micro-triangle placed on the grid, in coordinates of type `C`.
#[derive(Clone, Copy, Debug)]
struct Placed<C> {
    x: [C; 3],
    y: [C; 3],
}

/// The walk of [`Baker::bake`] runs in `i64` when the root's coordinates
/// are below this in magnitude and both shifts at most [`NARROW_SHIFT`].
/// Why nothing overflows then: every node vertex is a convex combination
/// of the root's (midpoints of midpoints), so below `2^59` too; the largest
/// values formed are a sum of three vertices (the centroid, below
/// `3 * 2^59 < 2^61`) and a sum of two minus half a cell of the twice
/// finer grid (`2^shift <= 2^58`: below `2^61`).
const NARROW_WALK_COORDINATE: i128 = 1 << 59;

/// See [`NARROW_WALK_COORDINATE`]; also keeps `1 << shift` in `i64`.
const NARROW_SHIFT: u32 = 58;

/// The largest margin (`2^k` grid units) the `i64` walk takes: a
/// coordinate below `2^59` minus half a cell (`2^57`) and the margin stays
/// below `2^60`.
const NARROW_MARGIN: u32 = 57;

/// The largest margin (`2^k` grid units) on the exact grid: coordinates
/// below `2^98` plus it stay below [`COORDINATE_LIMIT`](super::exact).
const MARGIN_LIMIT: u32 = 97;

impl Placed<i128> {
    /// The same triangle in `i64`, when the walk from it (as the root)
    /// stays in range: see [`NARROW_WALK_COORDINATE`].
    fn narrowed(&self, grid: Grid) -> Option<Placed<i64>> {
        let (sx, sy) = grid.shifts;
        let wide_margin = |m: Option<u32>| m.is_some_and(|k| k > NARROW_MARGIN);
        if sx.max(sy) > NARROW_SHIFT || wide_margin(grid.margin.0) || wide_margin(grid.margin.1) {
            return None;
        }
        let bound = NARROW_WALK_COORDINATE as u128;
        Some(Placed {
            x: narrowed_below(self.x, bound)?,
            y: narrowed_below(self.y, bound)?,
        })
    }
}

impl<C: GridInt> Placed<C> {
    /// The triangle in `i128` (exact), for the exact search.
    fn wide(&self) -> Placed<i128> {
        Placed {
            x: self.x.map(Into::into),
            y: self.y.map(Into::into),
        }
    }
}

impl Baker {
    /// Classifies every texel of `texture` once (one pass, `2 (w + 1)
    /// (h + 1)` bytes of prefix sums).
    pub fn new(
        texture: &(impl AlphaTexture + ?Sized),
        sampler: Sampler,
        cutoff: Cutoff,
    ) -> Result<Baker, TextureError> {
        Self::new_within(texture, sampler, cutoff, u64::MAX)
    }

    /// [`new`](Self::new) with the tables held to `max_bytes` (`w h +
    /// 2 (w + 1) (h + 1)` bytes): over it, or refused by the allocator,
    /// the answer is [`TextureError::AllocationFailed`], never an abort
    /// (`new` gives the same error when the allocator refuses).
    pub fn new_within(
        texture: &(impl AlphaTexture + ?Sized),
        sampler: Sampler,
        cutoff: Cutoff,
        max_bytes: u64,
    ) -> Result<Baker, TextureError> {
        Self::new_on(texture, sampler, cutoff, max_bytes, &Runner::serial())
    }

    /// [`new_within`](Self::new_within), its tables built on `runner`'s
    /// threads (the same tables on any).
    pub(crate) fn new_on(
        texture: &(impl AlphaTexture + ?Sized),
        sampler: Sampler,
        cutoff: Cutoff,
        max_bytes: u64,
        runner: &Runner,
    ) -> Result<Baker, TextureError> {
        Ok(Baker {
            classes: TexelClasses::new_within(texture, sampler, cutoff, max_bytes, runner)?,
            budget: DEFAULT_BLOCK_BUDGET,
            work_budget: DEFAULT_TRIANGLE_WORK_BUDGET,
            model: Model::default(),
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

    /// The model it bakes and verifies for.
    #[must_use]
    pub fn model(&self) -> Model {
        self.model
    }

    /// The same baker with another cap on block tests per micro-triangle
    /// (at least 1).
    #[must_use]
    pub fn with_block_budget(mut self, budget: u32) -> Baker {
        self.budget = budget.max(1);
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
        (self.classes.width, self.classes.height)
    }

    /// The sampler.
    #[must_use]
    pub fn sampler(&self) -> Sampler {
        self.classes.sampler
    }

    /// Is the texel `(x, y)` (or the border, `None`) opaque under the
    /// cutoff? `false` for coordinates outside the texture.
    #[must_use]
    pub fn texel_is_opaque(&self, texel: Option<(u32, u32)>) -> bool {
        match texel {
            Some((x, y)) if x >= self.classes.width || y >= self.classes.height => false,
            t => self.classes.class_of(t),
        }
    }

    /// The triangle's frames on both axes and their grid: for the GPU
    /// model, fine enough to hold the margin `2^e` texels of
    /// [`margin_exponent`] (a grid unit of at most `2^e`), which is then
    /// `2^(shift + e)` grid units.
    fn frames(
        &self,
        model: Model,
        uv: &UvTriangle,
        level: Level,
    ) -> Result<(AxisFrame, AxisFrame, Grid), FrameError> {
        let n = level.get();
        let axis = |k: usize, size: u32| -> Result<(AxisFrame, Option<u32>), FrameError> {
            let c = uv.map(|c| c[k]);
            match model {
                Model::Exact => Ok((AxisFrame::new(c, size, n, 0)?, None)),
                Model::GpuBinary32 => {
                    if c.iter().any(|x| !x.is_finite()) {
                        return Err(FrameError::NotFinite);
                    }
                    let e = margin_exponent(c, size, n);
                    let frame = AxisFrame::new(c, size, n, (-e).max(0) as u32)?;
                    let k = frame.shift as i32 + e;
                    if k > MARGIN_LIMIT as i32 {
                        return Err(FrameError::OutOfRange);
                    }
                    Ok((frame, Some(k as u32)))
                }
            }
        };
        let (fx, mx) = axis(0, self.classes.width)?;
        let (fy, my) = axis(1, self.classes.height)?;
        let grid = Grid {
            shifts: (fx.shift, fy.shift),
            margin: (mx, my),
        };
        Ok((fx, fy, grid))
    }

    fn place(
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

    /// The classes a placed micro-triangle samples: the bounding block
    /// first (most micro-triangles end there), then the footprints of its
    /// vertices and edge midpoints, then the exact search if still mixed.
    fn classify<C: GridInt>(
        &self,
        p: &Placed<C>,
        grid: Grid,
        points: Points,
        stack: &mut Vec<Block>,
    ) -> (Classes, bool, u64) {
        let bounding = self.bounding_block(p, grid);
        let quick = self.classes.quick(bounding);
        if !quick.is_mixed() {
            return (quick, false, 1);
        }
        let (classes, exhausted, work) =
            self.classify_mixed_block(p, grid, bounding, points, stack);
        (classes, exhausted, 1 + work)
    }

    /// A leaf of the walk: `(classes, exhausted, work, widened)` (see
    /// [`classify_dilated_leaf`](Self::classify_dilated_leaf)).
    fn classify_leaf<C: GridInt>(
        &self,
        p: &Placed<C>,
        grid: Grid,
        points: Points,
        stack: &mut Vec<Block>,
    ) -> (Classes, bool, u64, bool) {
        if grid.margin == (None, None) {
            let (classes, exhausted, work) = self.classify(p, grid, points, stack);
            (classes, exhausted, work, false)
        } else {
            self.classify_dilated_leaf(p, grid, points, stack)
        }
    }

    /// A leaf under a dilating grid (the GPU model), with the widening's
    /// cost: `(classes, exhausted, work, widened)`, where `widened` says
    /// the leaf is unknown here but known to the exact model on the same
    /// grid. The exact model's region is inside the dilated one, so when
    /// it already reads both classes the leaf is unknown under both and
    /// the dilated search is skipped (most unknown leaves end there); only
    /// the rest are classified under both models.
    fn classify_dilated_leaf<C: GridInt>(
        &self,
        p: &Placed<C>,
        grid: Grid,
        points: Points,
        stack: &mut Vec<Block>,
    ) -> (Classes, bool, u64, bool) {
        let bounding = self.bounding_block(p, grid);
        let quick = self.classes.quick(bounding);
        if !quick.is_mixed() {
            return (quick, false, 1, false);
        }
        // The exact model's bounding block is inside this one, and mostly
        // the same block (the margin is a small part of a texel): then it
        // is mixed too, and is not read again.
        let exact_grid = Grid::exact(grid.shifts);
        let exact_bounding = self.bounding_block(p, exact_grid);
        let (exact, exact_exhausted, exact_work) = if exact_bounding == bounding {
            self.classify_mixed_block(p, exact_grid, exact_bounding, points, stack)
        } else {
            self.classify(p, exact_grid, points, stack)
        };
        if exact.is_mixed() && !exact_exhausted {
            return (Classes::BOTH, false, 1 + exact_work, false);
        }
        // The points read there are the same here (undilated): skip them.
        // What the exact model read is read here too (its region is
        // inside): search for the rest, unless its search ran out.
        let known = if exact_exhausted {
            Classes::default()
        } else {
            exact
        };
        let (classes, exhausted, work) =
            self.classify_mixed_block(p, grid, bounding, Points::None(known), stack);
        let unknown = classes.opaque == classes.transparent;
        let exact_known = exact.opaque != exact.transparent;
        let widened = unknown && !exhausted && !exact_exhausted && exact_known;
        (classes, exhausted, 1 + exact_work + work, widened)
    }

    /// [`classify`](Self::classify) of a micro-triangle whose bounding
    /// block `bounding` holds both classes: the vertex and midpoint
    /// footprints `points` names, then the exact search for the classes
    /// they (or `points`) have not shown it to read. Returns the
    /// classes, whether the search ran out of budget, and the work after
    /// the bounding block.
    fn classify_mixed_block<C: GridInt>(
        &self,
        p: &Placed<C>,
        grid: Grid,
        bounding: Block<C>,
        points: Points,
        stack: &mut Vec<Block>,
    ) -> (Classes, bool, u64) {
        let mut work = 0;
        // Every texel in the footprint of a vertex or an edge midpoint is
        // read (both are points of the closed micro-triangle): when these
        // already hold both classes the micro-triangle is mixed, with no
        // geometry (most mixed ones at useful levels). Only for a small
        // footprint, whose search could not run out of budget: the answer
        // is the search's. A midpoint `(a + b) / 2` is a grid point of the
        // twice finer grid (shift + 1).
        // (Points of the micro-triangle are points of its dilation too.)
        let (mut sure, first) = match points {
            Points::None(known) => (known, 6),
            Points::All => (Classes::default(), 0),
            Points::Midpoints(vertices) => (vertices, 3),
        };
        if first < 6 && is_small(bounding) {
            for k in first..6 {
                let (a, b) = (k % 3, if k < 3 { k % 3 } else { (k + 1) % 3 });
                let doubled = (p.x[a] + p.x[b], p.y[a] + p.y[b]);
                sure = sure.union(self.point_classes(doubled, grid.shifts));
                work += 1;
                if sure.is_mixed() {
                    return (sure, false, work);
                }
            }
        }
        // Only the classes the points did not read are searched for.
        let wide = p.wide();
        let t = ExactTriangle::new(wide.x, wide.y);
        let want = if sure == Classes::default() {
            Classes::BOTH
        } else {
            sure.complement()
        };
        let s: Search = self.classes.search(&t, grid, want, self.budget, stack);
        (
            s.classes.union(sure),
            s.exhausted,
            work + u64::from(s.tests),
        )
    }

    /// The classes of the footprint of the grid point `doubled / 2` (a
    /// point of the twice finer grid, `shifts + 1`: vertices and edge
    /// midpoints are), without margin.
    #[inline]
    fn point_classes<C: GridInt>(&self, (x, y): (C, C), (sx, sy): (u32, u32)) -> Classes {
        let fine = Grid::exact((sx + 1, sy + 1));
        self.classes
            .quick(self.classes.bounding_block((x, x), (y, y), fine))
    }

    /// The classes of the placed triangle's bounding block of texels: a
    /// superset of what it reads (exact when not mixed).
    fn quick_classes<C: GridInt>(&self, p: &Placed<C>, grid: Grid) -> Classes {
        self.classes.quick(self.bounding_block(p, grid))
    }

    /// The placed triangle's bounding block of texels.
    fn bounding_block<C: GridInt>(&self, p: &Placed<C>, grid: Grid) -> Block<C> {
        let min_max = |c: [C; 3]| (c[0].min(c[1]).min(c[2]), c[0].max(c[1]).max(c[2]));
        self.classes
            .bounding_block(min_max(p.x), min_max(p.y), grid)
    }

    /// The known state to split an unknown micro-triangle by: the class of
    /// the texel holding its centroid (nearest sampling of the centroid,
    /// for either filter). A heuristic; soundness does not depend on it.
    fn centroid_is_opaque<C: GridInt>(&self, p: &Placed<C>, (sx, sy): (u32, u32)) -> bool {
        // floor(s / (3 2^shift)) = floor(floor(s / 2^shift) / 3).
        let cx = floor_third(((p.x[0] + p.x[1] + p.x[2]) >> sx).into());
        let cy = floor_third(((p.y[0] + p.y[1] + p.y[2]) >> sy).into());
        self.classes.class_of(self.classes.wrap(cx, cy))
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
    /// threads when `split` (the same result: see [`walk`](Self::walk)).
    pub(crate) fn bake_split(
        &self,
        uv: &UvTriangle,
        level: Level,
        format: Format,
        two_state: UnknownPolicy,
        max_work: u64,
        split: bool,
    ) -> Result<BakedTriangle, BakeError> {
        self.bake_as(self.model, uv, level, format, two_state, max_work, split)
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
        let whole_unknown = |status| {
            let mut counts = [0u64; 4];
            counts[State::UnknownOpaque.bits() as usize] = level.micro_triangle_count() as u64;
            BakedTriangle {
                opacity: BakedOpacity::Special(State::UnknownOpaque),
                status,
                counts,
                widened: 0,
                work: 0,
            }
        };
        let mut map = Micromap::new(level, format)?;
        let (fx, fy, grid) = match self.frames(model, uv, level) {
            Ok(frames) => frames,
            Err(FrameError::NotFinite) => return Ok(whole_unknown(TriangleStatus::NotFinite)),
            Err(FrameError::OutOfRange) => {
                let mut unknown = whole_unknown(TriangleStatus::OutOfExactRange);
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
        let spent = match root.narrowed(grid) {
            Some(narrow) => self.walk(narrow, n, grid, two_state, max_work, split, out)?,
            None => self.walk(root, n, grid, two_state, max_work, split, out)?,
        };
        Ok(BakedTriangle {
            opacity: BakedOpacity::Map(map),
            status: spent.status,
            counts,
            widened: spent.widened,
            work: spent.work,
        })
    }

    /// The top-down walk of [`bake`](Self::bake) from the whole triangle
    /// `root` (on the grid of `level`), in coordinates of type `C`: fills
    /// the map and counts of `out`, and says how it went and what it spent.
    /// The caller picks `C` so that the walk stays in range (see
    /// [`NARROW_WALK_COORDINATE`]); the result is the same in every type.
    ///
    /// A `split` walk runs the levels above [`SPLIT_SUBTREE_LEVEL`] first,
    /// setting the nodes it reaches there aside, then walks those subtrees
    /// ([`walk_set_aside`](Self::walk_set_aside)). Counts, widening and
    /// work are sums, so the result is the serial walk's, unless the work
    /// budget could have cut the serial walk: then the serial walk runs,
    /// from scratch.
    #[allow(clippy::too_many_arguments)]
    fn walk<C: GridInt>(
        &self,
        root: Placed<C>,
        level: u32,
        grid: Grid,
        two_state: UnknownPolicy,
        max_work: u64,
        split: bool,
        (map, counts): (&mut Micromap, &mut [u64; 4]),
    ) -> Result<Spent, BakeError> {
        let vertices = [0, 1, 2].map(|k| (root.x[k], root.y[k]));
        if split {
            let mut walk = Walk::new(level, grid, two_state, max_work, map, counts);
            walk.split_depth = level - SPLIT_SUBTREE_LEVEL;
            self.visit(&mut walk, 0, 0, vertices, false)?;
            if self.walk_set_aside(&mut walk)? {
                return Ok(walk.spent());
            }
            // The budget could have cut the serial walk: walk it.
            let (level, format) = (walk.map.level(), walk.map.format());
            *walk.map = Micromap::new(level, format)?;
            *walk.counts = [0; 4];
        }
        let mut walk = Walk::new(level, grid, two_state, max_work, map, counts);
        self.visit(&mut walk, 0, 0, vertices, false)?;
        Ok(walk.spent())
    }

    /// The second half of a split walk (see [`walk`](Self::walk)): the
    /// subtrees its top set aside, walked in parallel ([`SPLIT_BATCH`] at a
    /// time, so that the maps in flight stay small: a level-16 triangle has
    /// 65,536) and copied in. `false` when the work budget could have cut
    /// the serial walk (the top or a subtree ran out, or all together
    /// reached the budget); the walk is then partly filled. A subtree that
    /// does not run out of its budget is what the serial walk gives it,
    /// whatever the budget.
    fn walk_set_aside<C: GridInt>(&self, walk: &mut Walk<'_, C>) -> Result<bool, BakeError> {
        if walk.out_of_work {
            return Ok(false);
        }
        let nodes = core::mem::take(&mut walk.frontier);
        let left = walk.max_work - walk.work;
        let mut spent = 0u64;
        for batch in nodes.chunks(SPLIT_BATCH) {
            let budget = left - spent;
            let subtrees = super::parallel::map_on_current_pool(batch, |node| {
                self.walk_subtree(node, walk.split_depth, walk, budget)
            });
            for (node, subtree) in batch.iter().zip(subtrees) {
                let subtree = subtree?;
                spent = spent.saturating_add(subtree.work);
                if subtree.out_of_work || spent >= left {
                    return Ok(false);
                }
                let first = node.index << (2 * SPLIT_SUBTREE_LEVEL);
                walk.map.copy_aligned(first, &subtree.map)?;
                for (sum, count) in walk.counts.iter_mut().zip(subtree.counts) {
                    *sum += count;
                }
                walk.widened += subtree.widened;
                walk.exhausted |= subtree.exhausted;
            }
        }
        walk.work += spent;
        Ok(true)
    }

    /// One subtree of a split walk (see [`walk`](Self::walk)): `node` at
    /// `depth`, walked into a map of [`SPLIT_SUBTREE_LEVEL`] (its own
    /// indices) with `max_work` units, on the grid and policy of `top`.
    fn walk_subtree<C: GridInt>(
        &self,
        node: &Node<C>,
        depth: u32,
        top: &Walk<'_, C>,
        max_work: u64,
    ) -> Result<Subtree, BakeError> {
        let mut map = Micromap::new(Level(SPLIT_SUBTREE_LEVEL as u8), top.map.format())?;
        let mut counts = [0u64; 4];
        let (level, grid, two_state) = (top.level, top.grid, top.two_state);
        let mut walk = Walk::new(level, grid, two_state, max_work, &mut map, &mut counts);
        self.visit(&mut walk, depth, 0, node.vertices, node.top_flip)?;
        let (work, widened) = (walk.work, walk.widened);
        let (exhausted, out_of_work) = (walk.exhausted, walk.out_of_work);
        Ok(Subtree {
            map,
            counts,
            work,
            widened,
            exhausted,
            out_of_work,
        })
    }

    /// One micro-triangle of the walk: its depth and index in the tree,
    /// its grid vertices `(x, y)`, and the walk's `top_flip` (which numbers
    /// its children). A micro-triangle of a coarser level contains its
    /// descendants, so a uniform one decides all of them (a contiguous
    /// index range) at once; only mixed ones descend, by recursion (depth
    /// at most the level). A child's vertices are its parent's and their
    /// midpoints (exact: at depth d < n every grid coordinate is a
    /// multiple of 2^(n - d), see `AxisFrame::at`, so the sums are even and
    /// halving is a shift), so no vertex is placed from scratch.
    fn visit<C: GridInt>(
        &self,
        walk: &mut Walk<'_, C>,
        depth: u32,
        index: u64,
        vertices: [(C, C); 3],
        top_flip: bool,
    ) -> Result<(), BakeError> {
        if depth == walk.split_depth {
            set_aside(walk, index, vertices, top_flip);
            return Ok(());
        }
        let n = walk.level;
        let up = n - depth;
        let p = Placed {
            x: vertices.map(|v| v.0),
            y: vertices.map(|v| v.1),
        };
        if walk.work >= walk.max_work {
            // Out of work: this node's whole subtree is unknown (sound).
            walk.out_of_work = true;
            let count = 1u64 << (2 * up);
            return self.set_unknown(walk, &p, index << (2 * up), count);
        }
        if depth == n {
            // A level-0 map: its one leaf (deeper leaves are read four at a
            // time by `visit_leaves`).
            return self.visit_leaf(walk, &p, index, Points::All);
        }
        // Above the finest level only the bounding block is read: a mixed
        // block descends, and the children decide more cheaply than an
        // exact search over a large triangle would.
        let classes = self.quick_classes(&p, walk.grid);
        walk.work += 1;
        if let Some(state) = classes.known_state() {
            return Self::set_known(walk, index, up, state);
        }
        if depth + 1 == n {
            return self.visit_leaves(walk, index, vertices, top_flip);
        }
        for child in 0..4 {
            let (vertices, top_flip) =
                crate::inverse::child_vertices(child, top_flip, vertices, midpoint);
            let index = 4 * index + u64::from(child);
            self.visit(walk, depth + 1, index, vertices, top_flip)?;
        }
        Ok(())
    }

    /// One leaf (finest micro-triangle) `p` with its index: classified
    /// ([`classify_leaf`](Self::classify_leaf), reading `points`), then
    /// set known or unknown and counted.
    fn visit_leaf<C: GridInt>(
        &self,
        walk: &mut Walk<'_, C>,
        p: &Placed<C>,
        leaf: u64,
        points: Points,
    ) -> Result<(), BakeError> {
        let (classes, out_of_budget, work, widened) =
            self.classify_leaf(p, walk.grid, points, &mut walk.stack);
        walk.work += work;
        walk.widened += u64::from(widened);
        if let Some(state) = classes.known_state() {
            return Self::set_known(walk, leaf, 0, state);
        }
        walk.exhausted |= out_of_budget;
        self.set_unknown(walk, p, leaf, 1)
    }

    /// The four leaves (finest micro-triangles) of a mixed node one level
    /// above the map's: `index`, `vertices`, `top_flip` are the node's, as
    /// in [`visit`](Self::visit). Their vertices are the node's corners
    /// and edge midpoints, six points for twelve corners: each point's
    /// footprint is read once, when a leaf first needs it. A leaf whose
    /// vertices read both classes is unknown (under either model: they
    /// are points of it) without its bounding block; the others are
    /// classified as [`visit`](Self::visit) would, without reading the
    /// vertices again. Only leaves with a small exact bounding block use
    /// them, as [`classify_mixed_block`](Self::classify_mixed_block) does.
    fn visit_leaves<C: GridInt>(
        &self,
        walk: &mut Walk<'_, C>,
        index: u64,
        vertices: [(C, C); 3],
        top_flip: bool,
    ) -> Result<(), BakeError> {
        let [a, b, c] = vertices;
        let points = [a, b, c, midpoint(a, b), midpoint(b, c), midpoint(c, a)];
        // Which of `points` the midpoint of two corners is.
        let between = |i: u8, j: u8| match i + j {
            1 => 3,
            3 => 4,
            _ => 5,
        };
        let mut read: [Option<Classes>; 6] = [None; 6];
        let exact_grid = Grid::exact(walk.grid.shifts);
        for child in 0..4 {
            let (corners, _) = crate::inverse::child_vertices(child, top_flip, [0, 1, 2], between);
            let leaf = 4 * index + u64::from(child);
            let p = Placed {
                x: corners.map(|i| points[usize::from(i)].0),
                y: corners.map(|i| points[usize::from(i)].1),
            };
            if walk.work >= walk.max_work {
                walk.out_of_work = true;
                self.set_unknown(walk, &p, leaf, 1)?;
                continue;
            }
            let mut vertex_points = Points::All;
            if is_small(self.bounding_block(&p, exact_grid)) {
                let mut sure = Classes::default();
                for i in corners.map(usize::from) {
                    let classes = *read[i].get_or_insert_with(|| {
                        walk.work += 1;
                        let (x, y) = points[i];
                        self.point_classes((x + x, y + y), walk.grid.shifts)
                    });
                    sure = sure.union(classes);
                    if sure.is_mixed() {
                        break;
                    }
                }
                if sure.is_mixed() {
                    // One unit for the centroid's texel: every leaf costs
                    // one at least, so a budget of all the work cuts none.
                    walk.work += 1;
                    self.set_unknown(walk, &p, leaf, 1)?;
                    continue;
                }
                vertex_points = Points::Midpoints(sure);
            }
            self.visit_leaf(walk, &p, leaf, vertex_points)?;
        }
        Ok(())
    }

    /// Marks the `4^up` micro-triangles of the node `index` (`up` levels
    /// above the map's) `state`, and counts them.
    fn set_known<C>(
        walk: &mut Walk<'_, C>,
        index: u64,
        up: u32,
        state: State,
    ) -> Result<(), BakeError> {
        let count = 1u64 << (2 * up);
        walk.counts[state.bits() as usize] += count;
        put(walk.map, index << (2 * up), count, state)?;
        Ok(())
    }

    /// Marks `count` micro-triangles from `first` (the placed node `p`'s
    /// finest-level range) unknown, split by `p`'s centroid texel, and
    /// counts them.
    fn set_unknown<C: GridInt>(
        &self,
        walk: &mut Walk<'_, C>,
        p: &Placed<C>,
        first: u64,
        count: u64,
    ) -> Result<(), BakeError> {
        let state = if self.centroid_is_opaque(p, walk.grid.shifts) {
            State::UnknownOpaque
        } else {
            State::UnknownTransparent
        };
        walk.counts[state.bits() as usize] += count;
        let stored = match walk.map.format() {
            Format::FourState => state,
            Format::TwoState => walk.two_state.resolve(state),
        };
        put(walk.map, first, count, stored)?;
        Ok(())
    }

    /// Checks another baker's answer for one triangle: every micro-triangle
    /// with a known state (opaque, transparent; a special index counts as a
    /// level-0 map) whose closed area can read a texel of the other class
    /// under this baker's sampler model is a [`Contradiction`], with an
    /// exact witness point. Unknown states are never contradicted.
    ///
    /// This form keeps every contradiction: its memory grows with their
    /// number (about 40 bytes each; a wrong level-16 map can have 2^32).
    /// [`verify_each`](Self::verify_each) hands each one to a callback
    /// instead and caps the work.
    #[must_use]
    pub fn verify(&self, uv: &UvTriangle, opacity: &TriangleOpacity<'_>) -> Verification {
        let mut contradictions = Vec::new();
        let counts = self.verify_each(uv, opacity, u64::MAX, |c| contradictions.push(c));
        Verification {
            contradictions,
            known: counts.known,
            unknown: counts.unknown,
            undecided: counts.undecided,
            checked: counts.checked,
        }
    }

    /// [`verify`](Self::verify) in bounded memory: each contradiction is
    /// passed to `visit` as it is found (keep the first few, count the rest)
    /// and only counts are returned. At most `max_known` known
    /// micro-triangles are checked; the known ones past that cap are
    /// counted in [`VerifyCounts::unchecked`], never silently dropped (a
    /// caller must not call a triangle with `unchecked > 0` sound).
    pub fn verify_each(
        &self,
        uv: &UvTriangle,
        opacity: &TriangleOpacity<'_>,
        max_known: u64,
        mut visit: impl FnMut(Contradiction),
    ) -> VerifyCounts {
        let level = match opacity {
            TriangleOpacity::Micromap(map) => map.level(),
            TriangleOpacity::Special(_) => Level(0),
        };
        let state_of = |index: u64| match opacity {
            TriangleOpacity::Micromap(map) => map.get(index).unwrap_or(State::UnknownOpaque),
            TriangleOpacity::Special(state) => *state,
        };
        let mut report = VerifyCounts::default();
        let Ok((fx, fy, grid)) = self.frames(self.model, uv, level) else {
            return report;
        };
        report.checked = true;
        let mut stack = Vec::new();
        for t in micro_triangles(level) {
            let state = state_of(t.index());
            if !state.is_known() {
                report.unknown += 1;
                continue;
            }
            if report.known >= max_known {
                report.unchecked += 1;
                continue;
            }
            report.known += 1;
            let other = Classes {
                opaque: state == State::Transparent,
                transparent: state == State::Opaque,
            };
            let p = Self::place(&fx, &fy, level.get(), t.vertices_scaled());
            let exact = ExactTriangle::new(p.x, p.y);
            // A larger budget than baking: a verdict, not a bake.
            let search = self.classes.search(
                &exact,
                grid,
                other,
                self.budget.saturating_mul(16),
                &mut stack,
            );
            let witness_block = search.witness_block[usize::from(other.opaque)];
            match witness_block {
                Some(found) => {
                    let (block, witness) = self.witness(&exact, found, grid, other.opaque);
                    let texel = witness.map_or_else(
                        || self.classes.wrap(block.x0, block.y0),
                        |w| {
                            // The witness is on a grid 2^w.2 times finer.
                            let (tx, ty) =
                                self.classes
                                    .footprint_texel_in(block, (w.0, w.1), grid, w.2);
                            self.classes.wrap(tx, ty)
                        },
                    );
                    report.contradictions += 1;
                    visit(Contradiction {
                        micro_triangle: t.index(),
                        state,
                        witness: witness.map(|(x, y, extra)| TexelPoint {
                            x,
                            shift_x: fx.shift + extra,
                            y,
                            shift_y: fy.shift + extra,
                        }),
                        texel,
                    });
                }
                None if search.exhausted => report.undecided += 1,
                None => {}
            }
        }
        report
    }

    /// A witness for a contradiction: a point of `t` reading a texel of
    /// the class `opaque`, searched in `found` (the block the search
    /// reported) and then in every single texel of that class in `t`'s
    /// footprint (a contact region can be far smaller than the finest grid
    /// of [`witness_in`](Self::witness_in) in one texel and hold a vertex
    /// in another).
    fn witness(
        &self,
        t: &ExactTriangle,
        found: Block,
        grid: Grid,
        opaque: bool,
    ) -> (Block, Option<(i128, i128, u32)>) {
        if let Some(w) = self.witness_in(t, found, grid) {
            return (found, Some(w));
        }
        let b = self
            .classes
            .bounding_block((t.min_x(), t.max_x()), (t.min_y(), t.max_y()), grid);
        if (b.x1 - b.x0 + 1).saturating_mul(b.y1 - b.y0 + 1) <= 4096 {
            for y in b.y0..=b.y1 {
                for x in b.x0..=b.x1 {
                    if self.classes.class_of(self.classes.wrap(x, y)) != opaque {
                        continue;
                    }
                    let texel = Block {
                        x0: x,
                        x1: x,
                        y0: y,
                        y1: y,
                    };
                    let [rx0, rx1, ry0, ry1] = self.classes.block_reach(texel, grid);
                    if !t.meets(rx0, rx1, ry0, ry1) {
                        continue;
                    }
                    if let Some(w) = self.witness_in(t, texel, grid) {
                        return (texel, Some(w));
                    }
                }
            }
        }
        (found, None)
    }

    /// A point of `t` (closed) in the reach of `block`, on a grid `2^extra`
    /// times finer: the block's included corner, a vertex, or a vertex of
    /// a sub-triangle found by subdividing `t` where it meets the reach.
    /// Every contact of a triangle with a half-open rectangle contains one
    /// of these (a 2-D overlap holds fine-grid points; a contact along an
    /// edge holds dyadic points of that edge; a single-point contact is a
    /// vertex or the corner).
    fn witness_in(&self, t: &ExactTriangle, block: Block, grid: Grid) -> Option<(i128, i128, u32)> {
        const EXTRA: u32 = 20;
        let [x0, x1, y0, y1] = self.classes.block_reach(block, grid);
        let inside = |px: i128, py: i128| x0 <= px && px < x1 && y0 <= py && py < y1;
        if t.contains(x0, y0) {
            return Some((x0, y0, 0));
        }
        for k in 0..3 {
            if inside(t.x[k], t.y[k]) {
                return Some((t.x[k], t.y[k], 0));
            }
        }
        // Finer grid: everything times 2^EXTRA, if it stays in range.
        let limit = 1i128 << 120;
        let up = |c: i128| c.checked_mul(1 << EXTRA).filter(|v| v.abs() < limit);
        let scale3 =
            |c: [i128; 3]| -> Option<[i128; 3]> { Some([up(c[0])?, up(c[1])?, up(c[2])?]) };
        let (rx0, rx1, ry0, ry1) = (up(x0)?, up(x1)?, up(y0)?, up(y1)?);
        let inside_fine = |px: i128, py: i128| rx0 <= px && px < rx1 && ry0 <= py && py < ry1;
        let mut stack = Vec::new();
        stack.push((scale3(t.x)?, scale3(t.y)?, 0u32));
        let mut tests = 0u32;
        while let Some((x, y, depth)) = stack.pop() {
            tests += 1;
            if tests > 1 << 16 {
                return None;
            }
            let sub = ExactTriangle::new(x, y);
            if !sub.meets(rx0, rx1, ry0, ry1) {
                continue;
            }
            for k in 0..3 {
                if inside_fine(x[k], y[k]) {
                    return Some((x[k], y[k], EXTRA));
                }
            }
            if depth == EXTRA {
                continue;
            }
            let mid = |a: usize, b: usize| ((x[a] + x[b]) / 2, (y[a] + y[b]) / 2);
            let (m01, m12, m20) = (mid(0, 1), mid(1, 2), mid(2, 0));
            let p = [(x[0], y[0]), (x[1], y[1]), (x[2], y[2])];
            for tri in [
                [p[0], m01, m20],
                [m01, p[1], m12],
                [m20, m12, p[2]],
                [m01, m12, m20],
            ] {
                stack.push((tri.map(|q| q.0), tri.map(|q| q.1), depth + 1));
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bake::{AddressMode, Filter, Unorm8Texture};
    use micromap_index_test_support::SplitMix64;

    /// A split walk (levels 10 and 11, subtrees on the pool's threads)
    /// gives the serial walk's map, counts, widening, status and work,
    /// under both models and formats, on textures with structure at
    /// every scale; and where the work budget cuts the serial walk (half
    /// its work, a unit short of it, a few units) the split walk falls
    /// back to it, giving the same again. Budgets just above the serial
    /// work keep the split result.
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
            assert!(
                serial.work > 1000,
                "case {case}: too easy ({} units)",
                serial.work
            );
            let full = serial.work;
            for budget in [full / 2, full - 1, full, full + 1, 3, 0] {
                let serial = baker
                    .bake_as(model, &uv, level, format, policy, budget, false)
                    .unwrap();
                let split = baker
                    .bake_as(model, &uv, level, format, policy, budget, true)
                    .unwrap();
                assert_eq!(split, serial, "case {case}: budget {budget} of {full}");
                split_kept += u32::from(serial.status != TriangleStatus::WorkBudgetExceeded);
            }
        }
        // Budgets at or above the work kept every split bake (no cut).
        assert!(split_kept >= 12, "{split_kept}");
    }

    /// Every micro-triangle of a bake (whose leaves are read four at a
    /// time, sharing their vertices: [`Baker::visit_leaves`], and whose
    /// searches look only for the classes its points did not read) has
    /// the state the plain search gives it alone: every class its closed
    /// (for the GPU model, dilated) area reads, with no points, no
    /// shortcut and no budget. Known where that is one class, else unknown
    /// by its centroid texel. Random blobby textures, both filters, wrapping and
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
                let search = baker
                    .classes
                    .search(&t, grid, Classes::BOTH, u32::MAX, &mut stack);
                assert!(!search.exhausted);
                let expected = match search.classes.known_state() {
                    Some(state) => state,
                    None if baker.centroid_is_opaque(&p, grid.shifts) => State::UnknownOpaque,
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
            let wide = bake(&|map, counts| {
                baker
                    .walk(root, level, grid, policy, u64::MAX, false, (map, counts))
                    .unwrap()
            });
            let narrowed = bake(&|map, counts| {
                baker
                    .walk(narrow, level, grid, policy, u64::MAX, false, (map, counts))
                    .unwrap()
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
}
