//! The walk of one triangle for several vertex-alpha variants at once
//! (linear filtering by value): the same UV triangle, level and baker,
//! with different `COLOR_0` alphas, as the instances of a mesh have.
//!
//! Every variant reads the same texel tables and the same filtered values
//! over the same micro-triangles; only the alpha each value is multiplied
//! by differs ([`VertexScale`]). So the walk is made once:
//!
//! 1. **A node** decided by its bounding block's texel classes (which hold
//!    for every alpha the bake reads this way) is decided for every
//!    variant still open there.
//! 2. **Otherwise, a node with a footprint of at most 3 x 3 texels** has
//!    its vertices' values read (once per point for every variant, shared
//!    with its neighbours and children); the variants they show both
//!    passing and failing descend at once. For the others its filtered
//!    value's extremes are read once
//!    ([`region_read`](super::classify::TexelClasses::region_read)),
//!    and each is decided by them times its own alpha range over the
//!    node; the variants left open descend.
//! 3. **A leaf** first by its corners' values (read once per point for
//!    every variant, as bit masks): a variant they show both passing and
//!    failing has it unknown; the others the same way as a node, with the
//!    leaf's dilated region; a variant left
//!    unknown there is classified on the exact grid too, for the widening's
//!    count (as [`Classifier::classify_leaf`] does). A leaf whose bounding
//!    block is too large for the value is classified per variant by
//!    [`Classifier::classify_leaf`].
//!
//! Contract: a variant's states do not depend on the variants walked with
//! it (each is decided at a node by its own tests, with the answers it
//! alone gets, and descends exactly where it is undecided), unless the
//! work budget runs out: the work is shared and counted once.

use super::alpha_test::{alpha_at, largest_alpha, VertexScale};
use super::classify::{is_small, Block, Classes, Classifier, Grid, Placed, PointReading, Points};
use super::triangle::BakeError;
use super::walk::{between, midpoint, put};
use crate::micromap::{Format, Micromap, State, UnknownPolicy};
use crate::num::wide::GridInt;
use alloc::vec::Vec;

/// The most variants one walk takes (the open ones are a bit mask).
pub(crate) const MAX_VARIANTS: usize = 64;

/// What one variant's walk made and found.
#[derive(Clone, Debug)]
pub(crate) struct VariantOut {
    pub(crate) map: Micromap,
    pub(crate) counts: [u64; 4],
    /// Unknown leaves the exact model knows.
    pub(crate) widened: u64,
    /// A leaf ran out of its block budget.
    pub(crate) exhausted: bool,
}

/// The walk: the classifier, the level and grid, the work spent and
/// allowed, and per variant its alphas, the largest of them, and what it
/// made.
pub(crate) struct VariantWalk<'a> {
    classifier: &'a Classifier,
    level: u32,
    grid: Grid,
    two_state: UnknownPolicy,
    pub(crate) work: u64,
    max_work: u64,
    pub(crate) out_of_work: bool,
    alphas: &'a [[f32; 3]],
    largest: Vec<f64>,
    pub(crate) out: Vec<VariantOut>,
    stack: Vec<Block>,
    /// [`decide`](Self::decide)'s answers: variant, and its state when
    /// known.
    decided: Vec<(usize, Option<State>)>,
    /// Every variant's alpha range over its whole triangle, together.
    wide: VertexScale,
    /// [`decide`](Self::decide)'s scratch: per open variant, its range and
    /// its quick bits.
    scales: Vec<(usize, VertexScale, u8)>,
}

/// What a node's six points (see [`between`]) read, where known: per
/// point, the variants whose value there may pass and those whose value
/// may fail.
type PointMasks = [Option<(u64, u64)>; 6];

/// A node's grid vertices.
type Triangle<C> = [(C, C); 3];

/// A node's corners `(a, b)` on the barycentric grid of the map's level
/// (`2^level` per side, vertex 0 at the origin).
type Bary = [(u64, u64); 3];

/// The midpoint of two corners `(a, b)` of the barycentric grid of the
/// map's level (exact above the leaves: see [`super::walk::Walk::visit`]).
#[inline]
fn bary_midpoint(p: (u64, u64), q: (u64, u64)) -> (u64, u64) {
    ((p.0 + q.0) / 2, (p.1 + q.1) / 2)
}

impl<'a> VariantWalk<'a> {
    /// A walk of `level` on `grid` with `max_work` units for the variants
    /// `alphas` (at most [`MAX_VARIANTS`]), each into a map of `format`.
    pub(crate) fn new(
        classifier: &'a Classifier,
        (level, grid): (u32, Grid),
        (two_state, format): (UnknownPolicy, Format),
        max_work: u64,
        alphas: &'a [[f32; 3]],
    ) -> Result<Self, BakeError> {
        debug_assert!(alphas.len() <= MAX_VARIANTS);
        let mut out = Vec::with_capacity(alphas.len());
        for _ in alphas {
            out.push(VariantOut {
                map: Micromap::new(crate::Level(level as u8), format)?,
                counts: [0; 4],
                widened: 0,
                exhausted: false,
            });
        }
        Ok(VariantWalk {
            classifier,
            level,
            grid,
            two_state,
            work: 0,
            max_work,
            out_of_work: false,
            alphas,
            largest: alphas.iter().copied().map(largest_alpha).collect(),
            out,
            stack: Vec::new(),
            decided: Vec::new(),
            scales: Vec::new(),
            wide: VertexScale::over_all(alphas),
        })
    }

    /// Every variant open.
    pub(crate) fn all(&self) -> u64 {
        if self.alphas.len() == 64 {
            u64::MAX
        } else {
            (1u64 << self.alphas.len()) - 1
        }
    }

    /// Variant `k`'s alpha range over the part with barycentric corners
    /// `bary` (`(a, b)` of `2^level` per side, vertex 0 at the origin).
    #[inline]
    fn scale(&self, k: usize, bary: Bary) -> VertexScale {
        let side = (1u64 << self.level) as f64;
        let v = self.alphas[k].map(f64::from);
        VertexScale::over(bary.map(|c| alpha_at(v, side, c)), self.largest[k])
    }

    /// The open variants of `open`, by index, lowest first.
    #[inline]
    fn each(mut open: u64) -> impl Iterator<Item = usize> {
        core::iter::from_fn(move || {
            if open == 0 {
                return None;
            }
            let k = open.trailing_zeros() as usize;
            open &= open - 1;
            Some(k)
        })
    }

    /// The budget check before a node: `true` when the work is spent.
    #[inline]
    fn out_of_work_here(&mut self) -> bool {
        if self.work >= self.max_work {
            self.out_of_work = true;
        }
        self.out_of_work
    }

    /// Marks node `index` (`up` levels above the map's) `state` for the
    /// variants of `open`.
    fn set_known(&mut self, open: u64, index: u64, up: u32, state: State) -> Result<(), BakeError> {
        let count = 1u64 << (2 * up);
        for k in Self::each(open) {
            let v = &mut self.out[k];
            v.counts[state.bits() as usize] += count;
            put(&mut v.map, index << (2 * up), count, state)?;
        }
        Ok(())
    }

    /// Marks `count` micro-triangles from `first` unknown for the variants
    /// of `open`, split by the placed node `p`'s centroid texel.
    fn set_unknown<C: GridInt>(
        &mut self,
        open: u64,
        p: &Placed<C>,
        first: u64,
        count: u64,
    ) -> Result<(), BakeError> {
        let state = if self.classifier.centroid_is_opaque(p, self.grid.shifts) {
            State::UnknownOpaque
        } else {
            State::UnknownTransparent
        };
        for k in Self::each(open) {
            let v = &mut self.out[k];
            v.counts[state.bits() as usize] += count;
            let stored = match v.map.format() {
                Format::FourState => state,
                Format::TwoState => self.two_state.resolve(state),
            };
            put(&mut v.map, first, count, stored)?;
        }
        Ok(())
    }

    /// The variants of `open` the filtered value over `p` (barycentric
    /// corners `bary`) on `grid` decides, with their states, into
    /// `self.decided`; returns the work (cells). Each variant gets the bits
    /// [`region_value`](super::classify::TexelClasses::region_value) gives
    /// it alone: a quick bound that tells alike for every alpha of the
    /// walk's range (its bits at the whole range and at the narrowest are
    /// equal, and the bits are monotone in the range) decides them all at
    /// once; otherwise each variant's own range, with the exact extremes
    /// read once for those the quick bound leaves open.
    fn decide<C: GridInt>(&mut self, open: u64, (p, bary): (&Placed<C>, Bary), grid: Grid) -> u64 {
        let wide = self.wide;
        let classes = &self.classifier.classes;
        let (read, mut cells) = classes.region_read(p, grid);
        let quick = read.quick(classes);
        self.decided.clear();
        let all = quick.bits(&classes.test, Some(wide));
        let none = quick.bits(&classes.test, Some(wide.narrowest()));
        if all != 3 && all == none {
            let state = Classes::of_bits(all).known_state();
            self.decided.extend(Self::each(open).map(|k| (k, state)));
            return u64::from(cells);
        }
        // Each open variant's range, and the quick bound's bits for it;
        // the ranges it leaves open, together (widest and narrowest).
        self.scales.clear();
        let mut pending: Option<(VertexScale, VertexScale)> = None;
        for k in Self::each(open) {
            let scale = self.scale(k, bary);
            let bits = quick.bits(&classes.test, Some(scale));
            if bits == 3 {
                pending = Some(pending.map_or((scale, scale), |(wide, narrow)| {
                    (wide.union(scale), narrow.intersection(scale))
                }));
            }
            self.scales.push((k, scale, bits));
        }
        let exact = pending.map(|ranges| read.exact(classes, ranges, &mut cells));
        for &(k, scale, bits) in &self.scales {
            let bits = match exact {
                Some(exact) if bits == 3 => exact.bits(&classes.test, Some(scale)),
                _ => bits,
            };
            self.decided.push((k, Classes::of_bits(bits).known_state()));
        }
        u64::from(cells)
    }

    /// One node of the walk for the variants of `open`: its depth and
    /// index, its grid vertices, its barycentric corners, and `top_flip`
    /// (as [`super::walk::Walk::visit`]).
    pub(crate) fn visit<C: GridInt>(
        &mut self,
        (depth, index): (u32, u64),
        (vertices, bary): (Triangle<C>, Bary),
        top_flip: bool,
        open: u64,
    ) -> Result<(), BakeError> {
        self.visit_node(
            (depth, index),
            (vertices, bary),
            top_flip,
            (open, (&mut [None; 6], [0, 1, 2])),
        )
    }

    /// [`visit`](Self::visit), with what the node's vertices read as far
    /// as its parent knows, shared as in the plain walk
    /// ([`super::walk::Walk`]'s `visit_node`): `shared[at[k]]` is vertex
    /// `k`'s reading when known. The work charged does not depend on
    /// what was shared.
    fn visit_node<C: GridInt>(
        &mut self,
        (depth, index): (u32, u64),
        (vertices, bary): (Triangle<C>, Bary),
        top_flip: bool,
        (open, reads): (u64, (&mut PointMasks, [usize; 3])),
    ) -> Result<(), BakeError> {
        let n = self.level;
        let up = n - depth;
        let p = Placed {
            x: vertices.map(|v| v.0),
            y: vertices.map(|v| v.1),
        };
        if self.out_of_work_here() {
            return self.set_unknown(open, &p, index << (2 * up), 1u64 << (2 * up));
        }
        if depth == n {
            return self.visit_leaf(&p, bary, index, open);
        }
        // 1. The bounding block's classes decide every variant.
        let classes = self.classifier.quick_classes(&p, self.grid);
        self.work += 1;
        if let Some(state) = classes.known_state() {
            return self.set_known(open, index, up, state);
        }
        // 2. The value, for a footprint of at most 3 x 3 texels (as
        //    `Classifier::value_state`), for the variants its vertices do
        //    not already show both passing and failing (as the plain walk).
        let mut open = open;
        let (shared, at) = reads;
        if self.classifier.value_applies(&p, self.grid) {
            let mut mixed = 0u64;
            let (mut pass, mut fail) = (0u64, 0u64);
            for j in 0..3 {
                self.work += 1;
                let (may_pass, may_fail) =
                    self.point_masks(vertices[j], bary[j], shared, at[j], open);
                pass |= may_pass;
                fail |= may_fail;
                mixed = pass & fail & open;
                if mixed == open {
                    break;
                }
            }
            let to_decide = open & !mixed;
            if to_decide != 0 {
                self.work += self.decide(to_decide, (&p, bary), self.grid);
                for d in 0..self.decided.len() {
                    if let (k, Some(state)) = self.decided[d] {
                        self.set_known(1u64 << k, index, up, state)?;
                        open &= !(1u64 << k);
                    }
                }
                if open == 0 {
                    return Ok(());
                }
            }
        }
        let corners = at.map(|k| shared[k]);
        if depth + 1 == n {
            return self.visit_leaves(index, (vertices, bary), top_flip, (open, corners));
        }
        let [a, b, c] = vertices;
        let points = [a, b, c, midpoint(a, b), midpoint(b, c), midpoint(c, a)];
        let mut known: PointMasks = [corners[0], corners[1], corners[2], None, None, None];
        for child in 0..4 {
            let (child_bary, _) =
                crate::inverse::child_vertices(child, top_flip, bary, bary_midpoint);
            let (at, child_flip) =
                crate::inverse::child_vertices(child, top_flip, [0, 1, 2], between);
            let child_index = 4 * index + u64::from(child);
            self.visit_node(
                (depth + 1, child_index),
                (at.map(|k| points[k]), child_bary),
                child_flip,
                (open, (&mut known, at)),
            )?;
        }
        Ok(())
    }

    /// What the grid point `(x, y)` (barycentric corner `bary`) reads for
    /// the variants of `open`, kept in `shared[k]` (found there when some
    /// node read it before, for the same variants or more): the variants
    /// whose value there may pass, and those whose value may fail (bit
    /// `k`: variant `k`, at its alpha there).
    fn point_masks<C: GridInt>(
        &self,
        (x, y): (C, C),
        bary: (u64, u64),
        shared: &mut PointMasks,
        k: usize,
        open: u64,
    ) -> (u64, u64) {
        *shared[k].get_or_insert_with(|| {
            let (sx, sy) = self.grid.shifts;
            let classes = &self.classifier.classes;
            let reading: PointReading = classes.point_reading((x + x, y + y), (sx + 1, sy + 1));
            let (mut may_pass, mut may_fail) = (0u64, 0u64);
            // Alike for every alpha of the walk: all at once.
            let wide = self.wide;
            let all = reading.bits(classes, Some(wide));
            let none = reading.bits(classes, Some(wide.narrowest()));
            if all == none {
                let every = |bit: u8| if bit != 0 { open } else { 0 };
                return (every(all & 1), every(all & 2));
            }
            let side = (1u64 << self.level) as f64;
            for k in Self::each(open) {
                let alpha = alpha_at(self.alphas[k].map(f64::from), side, bary);
                let scale = VertexScale::over([alpha; 3], self.largest[k]);
                let bits = reading.bits(classes, Some(scale));
                may_pass |= u64::from(bits & 1) << k;
                may_fail |= u64::from(bits >> 1) << k;
            }
            (may_pass, may_fail)
        })
    }

    /// The four leaves of a node one level above the map's, for the
    /// variants of `open` (as [`super::walk::Walk::visit_leaves`]): their
    /// corners are the node's corners and edge midpoints, six points each
    /// read once when a leaf first needs it; a variant whose alpha there
    /// makes the points of a leaf read both classes has that leaf unknown
    /// (the region's value would find both too), the others go to
    /// [`visit_leaf`](Self::visit_leaf). Only for leaves with a small
    /// bounding block on the exact grid, as there.
    fn visit_leaves<C: GridInt>(
        &mut self,
        index: u64,
        (vertices, bary): (Triangle<C>, Bary),
        top_flip: bool,
        (open, corners): (u64, [Option<(u64, u64)>; 3]),
    ) -> Result<(), BakeError> {
        let [a, b, c] = vertices;
        let points = [a, b, c, midpoint(a, b), midpoint(b, c), midpoint(c, a)];
        let [ba, bb, bc] = bary;
        let point_bary = [
            ba,
            bb,
            bc,
            bary_midpoint(ba, bb),
            bary_midpoint(bb, bc),
            bary_midpoint(bc, ba),
        ];
        // Per point, once: the variants whose value there may pass, and
        // those whose value may fail; one work unit per point a leaf
        // needs, whether the parent shared it or not.
        let mut read: PointMasks = [corners[0], corners[1], corners[2], None, None, None];
        let mut charged = [false; 6];
        let exact_grid = Grid::exact(self.grid.shifts);
        for child in 0..4 {
            let (corners, _) = crate::inverse::child_vertices(child, top_flip, [0, 1, 2], between);
            let leaf = 4 * index + u64::from(child);
            let p = Placed {
                x: corners.map(|i| points[i].0),
                y: corners.map(|i| points[i].1),
            };
            if self.out_of_work_here() {
                self.set_unknown(open, &p, leaf, 1)?;
                continue;
            }
            let mut leaf_open = open;
            if is_small(self.classifier.bounding_block(&p, exact_grid)) {
                let (mut pass, mut fail) = (0u64, 0u64);
                for i in corners {
                    if !charged[i] {
                        charged[i] = true;
                        self.work += 1;
                    }
                    let (may_pass, may_fail) =
                        self.point_masks(points[i], point_bary[i], &mut read, i, open);
                    pass |= may_pass;
                    fail |= may_fail;
                }
                let mixed = pass & fail & open;
                if mixed != 0 {
                    // One unit for the centroid's texel, as there.
                    self.work += 1;
                    self.set_unknown(mixed, &p, leaf, 1)?;
                    leaf_open &= !mixed;
                }
            }
            if leaf_open != 0 {
                let leaf_bary = corners.map(|i| point_bary[i]);
                self.visit_leaf(&p, leaf_bary, leaf, leaf_open)?;
            }
        }
        Ok(())
    }

    /// 3. One leaf for the variants of `open`.
    fn visit_leaf<C: GridInt>(
        &mut self,
        p: &Placed<C>,
        bary: Bary,
        leaf: u64,
        open: u64,
    ) -> Result<(), BakeError> {
        let grid = self.grid;
        let bounding = self.classifier.bounding_block(p, grid);
        let quick = self.classifier.classes.quick(bounding);
        self.work += 1;
        if !quick.is_mixed() {
            return match quick.known_state() {
                Some(state) => self.set_known(open, leaf, 0, state),
                None => self.set_unknown(open, p, leaf, 1),
            };
        }
        if !is_small(bounding) {
            // Per variant, as the plain walk classifies it.
            for k in Self::each(open) {
                let scale = self.scale(k, bary);
                let (classes, exhausted, work, widened) = self.classifier.classify_leaf(
                    p,
                    grid,
                    (Points::All, Some(scale)),
                    &mut self.stack,
                );
                self.work += work;
                self.out[k].widened += u64::from(widened);
                if let Some(state) = classes.known_state() {
                    self.set_known(1u64 << k, leaf, 0, state)?;
                } else {
                    self.out[k].exhausted |= exhausted;
                    self.set_unknown(1u64 << k, p, leaf, 1)?;
                }
            }
            return Ok(());
        }
        self.work += self.decide(open, (p, bary), grid);
        let mut unknown = 0u64;
        for d in 0..self.decided.len() {
            match self.decided[d] {
                (k, Some(state)) => self.set_known(1u64 << k, leaf, 0, state)?,
                (k, None) => unknown |= 1u64 << k,
            }
        }
        if unknown == 0 {
            return Ok(());
        }
        if grid.margin != (None, None) {
            // The widening's count: what the exact model knows of them.
            let exact_grid = Grid::exact(grid.shifts);
            let exact_quick = self
                .classifier
                .classes
                .quick(self.classifier.bounding_block(p, exact_grid));
            self.work += 1;
            if exact_quick.is_mixed() {
                self.work += self.decide(unknown, (p, bary), exact_grid);
                for d in 0..self.decided.len() {
                    let (k, state) = self.decided[d];
                    self.out[k].widened += u64::from(state.is_some());
                }
            } else if exact_quick.known_state().is_some() {
                for k in Self::each(unknown) {
                    self.out[k].widened += 1;
                }
            }
        }
        self.set_unknown(unknown, p, leaf, 1)
    }
}
