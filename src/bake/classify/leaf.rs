//! The classifier the walk calls: the texel tables and the block budget,
//! and how one placed micro-triangle (or a node above the leaves) is
//! classified: its bounding block first, then the footprints of its
//! vertices and edge midpoints, then the exact search; under the GPU model
//! the exact model's classification first and the dilated search after.

use super::classes::{is_small, Block, Classes, Grid, Placed};
use super::search::Search;
use super::tables::TexelClasses;
use crate::bake::alpha_test::VertexScale;
use crate::bake::exact::ExactTriangle;
use crate::num::wide::GridInt;
use alloc::vec::Vec;

/// `floor(q / 3)`, in `i64` where `q` fits (an `i128` division is a
/// library call; texel coordinates nearly always fit).
#[inline]
fn floor_third(q: i128) -> i128 {
    match i64::try_from(q) {
        Ok(q) => i128::from(q.div_euclid(3)),
        Err(_) => q.div_euclid(3),
    }
}

/// The points of a micro-triangle whose footprints
/// [`Classifier::classify_mixed_block`] reads before its search.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Points {
    /// None: this model's exact grid read them already, and found that the
    /// micro-triangle reads these classes (not both; none if unsure).
    None(Classes),
    /// Its vertices, then its edge midpoints.
    All,
    /// Its edge midpoints: the walk read its vertices, whose footprints
    /// hold these classes (not both).
    Midpoints(Classes),
}

/// The texel tables and the cap on block tests per micro-triangle: what
/// classifies a placed micro-triangle.
#[derive(Clone, Debug)]
pub(crate) struct Classifier {
    pub(crate) classes: TexelClasses,
    /// Block tests a micro-triangle may use before it is unknown.
    pub(crate) block_budget: u32,
}

impl Classifier {
    /// The classes a placed micro-triangle samples: the bounding block
    /// first (most micro-triangles end there), then the footprints of its
    /// vertices and edge midpoints, then the exact search if still mixed.
    /// With vertex alpha, `scale` is its range over `p` (the texel classes
    /// hold for every alpha of the texture's: the points and the value
    /// take `p`'s own).
    pub(crate) fn classify<C: GridInt>(
        &self,
        p: &Placed<C>,
        grid: Grid,
        (points, scale): (Points, Option<VertexScale>),
        stack: &mut Vec<Block>,
    ) -> (Classes, bool, u64) {
        let bounding = self.bounding_block(p, grid);
        let quick = self.classes.quick(bounding);
        if !quick.is_mixed() {
            return (quick, false, 1);
        }
        let (classes, exhausted, work) =
            self.classify_mixed_block(p, grid, bounding, (points, scale), stack);
        (classes, exhausted, 1 + work)
    }

    /// A leaf of the walk: `(classes, exhausted, work, widened)` (see
    /// [`classify_dilated_leaf`](Self::classify_dilated_leaf)).
    pub(crate) fn classify_leaf<C: GridInt>(
        &self,
        p: &Placed<C>,
        grid: Grid,
        points: (Points, Option<VertexScale>),
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
        (points, scale): (Points, Option<VertexScale>),
        stack: &mut Vec<Block>,
    ) -> (Classes, bool, u64, bool) {
        let bounding = self.bounding_block(p, grid);
        let quick = self.classes.quick(bounding);
        if !quick.is_mixed() {
            return (quick, false, 1, false);
        }
        // Linear filtering by value, a small block: the value over the
        // dilated region decides at once (one evaluation for the many
        // leaves it knows); only a leaf it leaves unknown is classified
        // under the exact model, for the widening's count. The states are
        // those of the order below (exact model first): the dilated
        // region decides the state either way.
        if self.classes.test.by_value && is_small(bounding) {
            let r = self.classes.region_value(p, grid, scale);
            let classes = Classes::of_bits(r.bits);
            let work = 1 + u64::from(r.cells);
            if classes.opaque != classes.transparent {
                return (classes, false, work, false);
            }
            let exact_grid = Grid::exact(grid.shifts);
            let (exact, exact_exhausted, exact_work) =
                self.classify(p, exact_grid, (points, scale), stack);
            let widened = !exact_exhausted && exact.opaque != exact.transparent;
            return (classes, false, work + exact_work, widened);
        }
        // The exact model's bounding block is inside this one, and mostly
        // the same block (the margin is a small part of a texel): then it
        // is mixed too, and is not read again.
        let exact_grid = Grid::exact(grid.shifts);
        let exact_bounding = self.bounding_block(p, exact_grid);
        let (exact, exact_exhausted, exact_work) = if exact_bounding == bounding {
            self.classify_mixed_block(p, exact_grid, exact_bounding, (points, scale), stack)
        } else {
            self.classify(p, exact_grid, (points, scale), stack)
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
            self.classify_mixed_block(p, grid, bounding, (Points::None(known), scale), stack);
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
        (points, scale): (Points, Option<VertexScale>),
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
                sure = sure.union(self.point_classes(doubled, grid.shifts, scale));
                work += 1;
                if sure.is_mixed() {
                    return (sure, false, work);
                }
            }
        }
        // Linear filtering by value, a small block: the value over the
        // region decides, not which texels it reads.
        if self.classes.test.by_value && is_small(bounding) {
            let r = self.classes.region_value(p, grid, scale);
            return (Classes::of_bits(r.bits), false, work + u64::from(r.cells));
        }
        // Only the classes the points did not read are searched for.
        let wide = p.wide();
        let t = ExactTriangle::new(wide.x, wide.y);
        let want = if sure == Classes::default() {
            Classes::BOTH
        } else {
            sure.complement()
        };
        let s: Search = self
            .classes
            .search(&t, grid, want, self.block_budget, stack);
        (
            s.classes.union(sure),
            s.exhausted,
            work + u64::from(s.tests),
        )
    }

    /// Under linear filtering by value, the state the filtered value gives
    /// the placed node (dilated by `grid`'s margin) when it is known and its
    /// bounding block small, with the work spent; `(None, 0)` otherwise.
    pub(crate) fn value_state<C: GridInt>(
        &self,
        p: &Placed<C>,
        grid: Grid,
    ) -> (Option<crate::micromap::State>, u64) {
        if !self.value_applies(p, grid) {
            return (None, 0);
        }
        let r = self.classes.region_value(p, grid, None);
        (Classes::of_bits(r.bits).known_state(), u64::from(r.cells))
    }

    /// Whether [`value_state`](Self::value_state) reads the placed node's
    /// value: under linear filtering by value, for nodes whose footprint is
    /// at most 3 x 3 texels (larger ones mostly meet the cutoff's level
    /// line, and cost more cells).
    pub(crate) fn value_applies<C: GridInt>(&self, p: &Placed<C>, grid: Grid) -> bool {
        if !self.classes.test.by_value {
            return false;
        }
        let b = self.bounding_block(p, grid);
        let three = C::from(2);
        b.x1 - b.x0 <= three && b.y1 - b.y0 <= three
    }

    /// The classes the grid point `doubled / 2` (a point of the twice
    /// finer grid, `shifts + 1`: vertices and edge midpoints are) reads,
    /// without margin: its footprint's, or under linear filtering by value
    /// what its filtered value may do (pass, fail).
    #[inline]
    pub(crate) fn point_classes<C: GridInt>(
        &self,
        (x, y): (C, C),
        (sx, sy): (u32, u32),
        scale: Option<VertexScale>,
    ) -> Classes {
        if self.classes.test.by_value {
            return Classes::of_bits(self.classes.point_bits((x, y), (sx + 1, sy + 1), scale));
        }
        let fine = Grid::exact((sx + 1, sy + 1));
        self.classes
            .quick(self.classes.bounding_block((x, x), (y, y), fine))
    }

    /// The classes of the placed triangle's bounding block of texels: a
    /// superset of what it reads (exact when not mixed).
    pub(crate) fn quick_classes<C: GridInt>(&self, p: &Placed<C>, grid: Grid) -> Classes {
        self.classes.quick(self.bounding_block(p, grid))
    }

    /// The placed triangle's bounding block of texels.
    pub(crate) fn bounding_block<C: GridInt>(&self, p: &Placed<C>, grid: Grid) -> Block<C> {
        let min_max = |c: [C; 3]| (c[0].min(c[1]).min(c[2]), c[0].max(c[1]).max(c[2]));
        self.classes
            .bounding_block(min_max(p.x), min_max(p.y), grid)
    }

    /// The known state to split an unknown micro-triangle by: the class of
    /// the texel holding its centroid (nearest sampling of the centroid,
    /// for either filter). A heuristic; soundness does not depend on it.
    pub(crate) fn centroid_is_opaque<C: GridInt>(
        &self,
        p: &Placed<C>,
        (sx, sy): (u32, u32),
    ) -> bool {
        // floor(s / (3 2^shift)) = floor(floor(s / 2^shift) / 3).
        let cx = floor_third(((p.x[0] + p.x[1] + p.x[2]) >> sx).into());
        let cy = floor_third(((p.y[0] + p.y[1] + p.y[2]) >> sy).into());
        self.classes.class_of(self.classes.wrap(cx, cy)).opaque
    }
}
