//! Linear filtering by value: what the bilinear filter's value may do (pass
//! the cutoff, fail it) at a point, and over a micro-triangle dilated by
//! the grid's margin.
//!
//! The filter's value at texel coordinate `(u, v)` is the bilinear mix of
//! the 2x2 texels from `floor(u - 1/2), floor(v - 1/2)`, with weights
//! `u - 1/2 - i` and `v - 1/2 - j`: in each cell between four texel
//! centres, a bilinear function. On a convex piece of a cell a bilinear
//! function takes its extremes at the piece's vertices or at the one
//! stationary point of an edge (along a segment it is a quadratic; inside,
//! it has no extremum: its Hessian's determinant is `-K^2 <= 0`). So, for a
//! region:
//!
//! 1. **The region.** The micro-triangle's vertices, each moved to the four
//!    corners of the margin's box, and their convex hull: the dilated
//!    micro-triangle (a Minkowski sum of the triangle and the box).
//! 2. **A quick bound.** Per cell its bounding box meets, the value at the
//!    corners of the box's part in the cell (on a box, a bilinear function's
//!    extremes are at its corners): a range that holds the region's. Most
//!    regions are decided here.
//! 3. **The exact extremes** where the quick bound does not decide: the
//!    region clipped to each cell, the value at each piece's vertices and
//!    its edges' stationary points.
//!
//! The values are the texels' highest binary32 values; the lowest are at
//! most [`TexelClasses::spread`] below, and a mix of them (weights summing
//! to 1) too, so the lowest value is taken as the highest's minus the
//! spread.
//!
//! In `f64` from the exact grid, relative to the region's first texel: the
//! coordinates are below 64 texels there (the callers pass small blocks
//! only), so each rounding moves a point by at most `2^-46` texels, and a
//! value (whose gradient is below twice the largest texel value per texel)
//! by less than `2^-44` of the largest value; the few roundings of
//! clipping and evaluation add less than that again. [`VALUE_SLACK`]
//! (`2^-36` of the largest value, at least 1) covers all of it, with room:
//! the extremes are widened by it.

use super::classes::{margin_in, Block, Grid, Placed};
use super::tables::TexelClasses;
use crate::bake::alpha_test::{CompareBounds, VertexScale};
use crate::bake::float::{abs, exp2};
use crate::num::wide::GridInt;

/// The widening of the extremes for this module's own `f64` arithmetic, in
/// units of the largest texel value (at least 1): see the module docs.
const VALUE_SLACK: f64 = 1.0 / (1u64 << 36) as f64;

/// `c` as `f64`: through `i64` where it fits (an `i128` conversion is a
/// library call).
#[inline]
fn to_f64(c: i128) -> f64 {
    if let Ok(c) = i64::try_from(c) {
        return c as f64;
    }
    // The top 63 bits, scaled back: one more rounding (below 2^-62
    // relative), far inside the module's slack.
    let bits = 128 - c.unsigned_abs().leading_zeros();
    let shift = bits.saturating_sub(62);
    ((c >> shift) as i64) as f64 * exp2(shift as i32)
}

/// `floor(t)` for the small `t` of a region.
#[inline]
fn floor(t: f64) -> i128 {
    let i = t as i64;
    i128::from(if (i as f64) > t { i - 1 } else { i })
}

/// What a region's filtered value may do, as class bits (bit 0: may pass,
/// bit 1: may fail), with a point of it where the value is lowest and one
/// where it is highest (texel coordinates from the texture's corner; the
/// corners of the quick bound's box when that decided).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct RegionValue {
    pub(crate) bits: u8,
    pub(crate) argmin: (f64, f64),
    pub(crate) argmax: (f64, f64),
    /// Cells evaluated (work units).
    pub(crate) cells: u32,
}

/// What a point reads ([`TexelClasses::point_reading`]): its footprint's
/// classes when they are one (whatever the vertex alpha: the texel classes
/// hold for all of it), else its value's bounds.
#[derive(Clone, Copy, Debug)]
pub(crate) enum PointReading {
    Classes(u8),
    Value(CompareBounds),
}

impl PointReading {
    /// The class bits, times a vertex alpha in `scale` (none: 1).
    #[inline]
    pub(crate) fn bits(self, classes: &TexelClasses, scale: Option<VertexScale>) -> u8 {
        match self {
            PointReading::Classes(bits) => bits,
            PointReading::Value(bounds) => bounds.bits(&classes.test, scale),
        }
    }
}

/// A polygon of at most 16 vertices (the hull has at most 12; each of four
/// clips adds at most one).
#[derive(Clone, Copy)]
struct Polygon {
    points: [(f64, f64); 16],
    len: usize,
}

impl Polygon {
    fn push(&mut self, p: (f64, f64)) {
        if self.len < self.points.len() {
            self.points[self.len] = p;
            self.len += 1;
        }
    }

    /// The part where `inside(p) >= 0` (`inside` affine), by
    /// Sutherland-Hodgman.
    fn clip(&self, inside: impl Fn((f64, f64)) -> f64) -> Polygon {
        let mut out = Polygon {
            points: [(0.0, 0.0); 16],
            len: 0,
        };
        let n = self.len;
        for k in 0..n {
            let (p, q) = (self.points[k], self.points[(k + 1) % n]);
            let (dp, dq) = (inside(p), inside(q));
            if dp >= 0.0 {
                out.push(p);
            }
            if (dp >= 0.0) != (dq >= 0.0) {
                let t = dp / (dp - dq);
                out.push((p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1)));
            }
        }
        out
    }
}

/// The convex hull (Andrew's monotone chain) of `points`; degenerate
/// inputs keep what the chain keeps (a segment's ends, a point).
fn hull(points: &mut [(f64, f64)]) -> Polygon {
    points.sort_unstable_by(|a, b| a.partial_cmp(b).unwrap_or(core::cmp::Ordering::Equal));
    let cross = |o: (f64, f64), a: (f64, f64), b: (f64, f64)| {
        (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
    };
    let mut h = [(0.0, 0.0); 32];
    let mut k = 0;
    for &p in points.iter() {
        while k >= 2 && cross(h[k - 2], h[k - 1], p) <= 0.0 {
            k -= 1;
        }
        h[k] = p;
        k += 1;
    }
    let lower = k + 1;
    for &p in points.iter().rev().skip(1) {
        while k >= lower && cross(h[k - 2], h[k - 1], p) <= 0.0 {
            k -= 1;
        }
        h[k] = p;
        k += 1;
    }
    let mut out = Polygon {
        points: [(0.0, 0.0); 16],
        len: 0,
    };
    // The last point repeats the first.
    for &p in &h[..k.saturating_sub(1).max(1)] {
        out.push(p);
    }
    out
}

/// The triangle `t` dilated by the box `[-mx, mx] x [-my, my]` (their
/// Minkowski sum): walking the triangle counter-clockwise, each vertex
/// moved to the box corners whose quadrants its edges' outward normals
/// sweep (at most seven vertices). A degenerate triangle, or no box, goes
/// through [`hull`].
fn dilated(t: [(f64, f64); 3], (mx, my): (f64, f64)) -> Polygon {
    let cross = (t[1].0 - t[0].0) * (t[2].1 - t[0].1) - (t[1].1 - t[0].1) * (t[2].0 - t[0].0);
    if mx == 0.0 && my == 0.0 {
        let mut out = Polygon {
            points: [(0.0, 0.0); 16],
            len: 0,
        };
        for p in t {
            out.push(p);
        }
        return out;
    }
    if cross == 0.0 || cross.is_nan() {
        let mut corners = [(0.0, 0.0); 12];
        for (k, p) in t.iter().enumerate() {
            for (c, (ex, ey)) in [(-mx, -my), (mx, -my), (mx, my), (-mx, my)]
                .into_iter()
                .enumerate()
            {
                corners[4 * k + c] = (p.0 + ex, p.1 + ey);
            }
        }
        return hull(&mut corners);
    }
    let t = if cross > 0.0 { t } else { [t[0], t[2], t[1]] };
    // Box corners counter-clockwise, and the one an outward normal's
    // quadrant picks.
    let corner = [(mx, -my), (mx, my), (-mx, my), (-mx, -my)];
    let quadrant = |n: (f64, f64)| -> usize {
        if n.0 > 0.0 && n.1 <= 0.0 {
            0
        } else if n.0 >= 0.0 && n.1 > 0.0 {
            1
        } else if n.0 < 0.0 && n.1 >= 0.0 {
            2
        } else {
            3
        }
    };
    let normal = |a: (f64, f64), b: (f64, f64)| (b.1 - a.1, -(b.0 - a.0));
    let mut out = Polygon {
        points: [(0.0, 0.0); 16],
        len: 0,
    };
    for i in 0..3 {
        let (prev, here, next) = (t[(i + 2) % 3], t[i], t[(i + 1) % 3]);
        let (from, to) = (quadrant(normal(prev, here)), quadrant(normal(here, next)));
        let mut q = from;
        loop {
            out.push((here.0 + corner[q].0, here.1 + corner[q].1));
            if q == to {
                break;
            }
            q = (q + 1) % 4;
        }
    }
    out
}

/// The bilinear value at `(a, b)` in `[0, 1]^2` of a cell whose corners
/// hold `v = [v00, v10, v01, v11]`.
#[inline]
fn bilinear(v: [f64; 4], a: f64, b: f64) -> f64 {
    let k = v[0] - v[1] - v[2] + v[3];
    v[0] + a * (v[1] - v[0]) + b * (v[2] - v[0]) + a * b * k
}

/// The candidate points of one clipped piece (cell coordinates): its
/// vertices and its edges' stationary points; `visit` gets each.
fn candidates(piece: &Polygon, v: [f64; 4], mut visit: impl FnMut(f64, f64)) {
    let k = v[0] - v[1] - v[2] + v[3];
    let n = piece.len;
    for i in 0..n {
        let (a0, b0) = piece.points[i];
        visit(a0, b0);
        let (a1, b1) = piece.points[(i + 1) % n];
        let (da, db) = (a1 - a0, b1 - b0);
        let curvature = k * da * db;
        if curvature != 0.0 {
            // d/dt of the value along the edge, at t = 0, and its zero.
            let slope = (v[1] - v[0]) * da + (v[2] - v[0]) * db + k * (a0 * db + b0 * da);
            let t = -slope / (2.0 * curvature);
            if t > 0.0 && t < 1.0 {
                visit(a0 + t * da, b0 + t * db);
            }
        }
    }
}

/// Where a value was taken: the cell's centre offset `(ci, cj)` (from the
/// region's first texel) and the weights `(a, b)`.
type Where = (f64, f64, f64, f64);

/// Running extremes and where they are.
struct Running {
    min: f64,
    max: f64,
    /// Where the extremes are, as given to [`add`](Self::add) (turned
    /// into points only for the one reported: most regions report none).
    argmin: Where,
    argmax: Where,
    largest: f64,
    nan: bool,
}

impl Running {
    fn new() -> Running {
        Running {
            min: f64::INFINITY,
            max: f64::NEG_INFINITY,
            argmin: Where::default(),
            argmax: Where::default(),
            largest: 1.0,
            nan: false,
        }
    }

    #[inline]
    fn add(&mut self, value: f64, at: Where) {
        if value.is_nan() {
            self.nan = true;
        } else {
            if value < self.min {
                self.min = value;
                self.argmin = at;
            }
            if value > self.max {
                self.max = value;
                self.argmax = at;
            }
        }
    }

    /// The class bits under `classes`' test, times a vertex alpha in
    /// `scale`: the lowest value less the spread and the slack, the
    /// highest plus the slack. A NaN texel gives a NaN mix, which passes
    /// no cutoff: a value that fails.
    fn bits(&self, classes: &TexelClasses, scale: Option<VertexScale>) -> u8 {
        self.bounds(classes).bits(&classes.test, scale)
    }

    /// What [`bits`](Self::bits) compares, before the vertex alpha.
    fn bounds(&self, classes: &TexelClasses) -> CompareBounds {
        let slack = VALUE_SLACK * self.largest;
        let min = if self.nan {
            f64::NAN
        } else {
            self.min - classes.spread - slack
        };
        classes.test.bounds(min, self.max + slack)
    }
}

impl TexelClasses {
    /// The highest values of the texels around cell `(i, j)` (texel
    /// coordinates of its top-left texel, before wrapping),
    /// `[v00, v10, v01, v11]`, and the largest magnitude among them.
    #[inline]
    fn cell_values(&self, i: i128, j: i128) -> [f64; 4] {
        let v = |dx: i128, dy: i128| f64::from(self.value_of(self.wrap(i + dx, j + dy)));
        [v(0, 0), v(1, 0), v(0, 1), v(1, 1)]
    }

    /// What the filtered value may do at the grid point `(x, y)` (grid
    /// `shifts`), as class bits: its footprint's classes when they are one,
    /// else the value itself, widened as the module docs say, times a
    /// vertex alpha in `scale` (none: 1).
    pub(crate) fn point_bits<C: GridInt>(
        &self,
        point: (C, C),
        shifts: (u32, u32),
        scale: Option<VertexScale>,
    ) -> u8 {
        self.point_reading(point, shifts).bits(self, scale)
    }

    /// What [`point_bits`](Self::point_bits) reads at a point, before the
    /// vertex alpha.
    pub(crate) fn point_reading<C: GridInt>(
        &self,
        (x, y): (C, C),
        (sx, sy): (u32, u32),
    ) -> PointReading {
        let block: Block<C> = self.bounding_block((x, x), (y, y), Grid::exact((sx, sy)));
        let classes = self.quick(block);
        if !classes.is_mixed() {
            return PointReading::Classes(
                u8::from(classes.opaque) | (u8::from(classes.transparent) << 1),
            );
        }
        let block = block.wide();
        let (x, y): (i128, i128) = (x.into(), y.into());
        // The weights: the point's offset from the centre of texel x0.
        let frac =
            |c: i128, i: i128, s: u32| to_f64(c - ((2 * i + 1) << (s - 1))) * exp2(-(s as i32));
        let (a, b) = (frac(x, block.x0, sx), frac(y, block.y0, sy));
        let v = self.cell_values(block.x0, block.y0);
        let mut running = Running::new();
        for value in v {
            running.largest = running.largest.max(abs(value));
        }
        running.add(
            bilinear(v, a.clamp(0.0, 1.0), b.clamp(0.0, 1.0)),
            Where::default(),
        );
        PointReading::Value(running.bounds(self))
    }

    /// What the filtered value may do over `p` dilated by `grid`'s margin
    /// (see the [module docs](self)). Only for a micro-triangle whose
    /// bounding block of texels is small (below 64 texels on a side) and
    /// a table holding values. With `scale`, the value times a vertex
    /// alpha in it.
    pub(crate) fn region_value<C: GridInt>(
        &self,
        p: &Placed<C>,
        grid: Grid,
        scale: Option<VertexScale>,
    ) -> RegionValue {
        let region = Region::new(p, grid);
        let mut cells = 0u32;
        // 2. The quick bound.
        let quick = region.quick(self, &mut cells);
        let bits = quick.bits(self, scale);
        if bits != 3 {
            return RegionValue {
                bits,
                argmin: region.at(quick.argmin),
                argmax: region.at(quick.argmax),
                cells,
            };
        }
        // 3. The exact extremes, per cell and only where they can tell:
        //    a cell whose quick range cannot fail (pass) is not searched
        //    for a failing (passing) point, and the search stops once the
        //    region is known to do both. The class bits are those of the
        //    region's exact extremes (the test is monotone in the value, so
        //    the region may pass iff some cell's part may); the points are a
        //    lowest point of a part that may fail and a highest point of one
        //    that may pass.
        let (mut bits, mut argmin, mut argmax) = (0u8, (0.0, 0.0), (0.0, 0.0));
        let polygon = region.polygon();
        'cells: for j in region.cells_y.clone() {
            for i in region.cells_x.clone() {
                let need = |range: &Running| range.bits(self, scale) & !bits;
                let Some(exact) = region.exact_cell(self, &polygon, (i, j), &quick, need) else {
                    continue;
                };
                cells += 1;
                let found = exact.bits(self, scale) & need(&exact.range);
                if found & 2 != 0 {
                    argmin = region.at(exact.running.argmin);
                }
                if found & 1 != 0 {
                    argmax = region.at(exact.running.argmax);
                }
                bits |= found;
                if bits == 3 {
                    break 'cells;
                }
            }
        }
        RegionValue {
            bits,
            argmin,
            argmax,
            cells,
        }
    }

    /// The first read of [`region_value`](Self::region_value) for many
    /// vertex alphas at once (the same region times several alphas): the
    /// region and its quick bound, with the cells read (work units); the
    /// exact extremes follow on demand ([`RegionRead::exact`]).
    pub(crate) fn region_read<C: GridInt>(&self, p: &Placed<C>, grid: Grid) -> (RegionRead, u32) {
        let region = Region::new(p, grid);
        let mut cells = 0u32;
        let quick = region.quick(self, &mut cells);
        (RegionRead { region, quick }, cells)
    }
}

/// A region and its quick bound ([`TexelClasses::region_read`]).
pub(crate) struct RegionRead {
    region: Region,
    quick: Running,
}

impl RegionRead {
    /// What the quick bound compares: [`region_value`](TexelClasses::region_value)'s
    /// answer for every alpha range it decides (bits other than both).
    pub(crate) fn quick(&self, classes: &TexelClasses) -> CompareBounds {
        self.quick.bounds(classes)
    }

    /// What the exact extremes compare, for alpha ranges inside `wide`
    /// whose quick bits are both, each no narrower than `narrow` (low at
    /// most `narrow.lo`, high at least `narrow.hi`): for each, the bits
    /// [`region_value`](TexelClasses::region_value) gives it alone (the
    /// union of the cells' parts' bits). The cells are skipped and the
    /// search stopped as there, for all the ranges at once: a cell is
    /// skipped when its quick range at `wide` adds nothing to what the
    /// parts so far give at `narrow`, and the search stops when that is
    /// both (the bits are monotone in the range), so neither changes an
    /// answer. Adds the cells read to `cells`.
    pub(crate) fn exact(
        &self,
        classes: &TexelClasses,
        (wide, narrow): (VertexScale, VertexScale),
        cells: &mut u32,
    ) -> CompareBounds {
        let region = &self.region;
        let polygon = region.polygon();
        let mut all = Running::new();
        all.largest = self.quick.largest;
        'cells: for j in region.cells_y.clone() {
            for i in region.cells_x.clone() {
                let so_far = all.bits(classes, Some(narrow));
                let need = |range: &Running| range.bits(classes, Some(wide)) & !so_far;
                let Some(exact) = region.exact_cell(classes, &polygon, (i, j), &self.quick, need)
                else {
                    continue;
                };
                *cells += 1;
                all.nan |= exact.running.nan;
                all.min = all.min.min(exact.running.min);
                all.max = all.max.max(exact.running.max);
                if all.bits(classes, Some(narrow)) == 3 {
                    break 'cells;
                }
            }
        }
        all.bounds(classes)
    }
}

/// One cell's part of a region: its exact extremes, and the cell's quick
/// range they were asked for by.
struct CellExtremes {
    running: Running,
    range: Running,
}

impl CellExtremes {
    fn bits(&self, classes: &TexelClasses, scale: Option<VertexScale>) -> u8 {
        self.running.bits(classes, scale)
    }
}

/// A placed micro-triangle dilated by a grid's margin, in `f64` texel
/// coordinates relative to its first texel (steps 1 to 3 of the
/// [module docs](self) read it).
struct Region {
    ox: i128,
    oy: i128,
    vertices: [(f64, f64); 3],
    margin: (f64, f64),
    /// The dilated region's bounding box.
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
    cells_x: core::ops::RangeInclusive<i128>,
    cells_y: core::ops::RangeInclusive<i128>,
}

impl Region {
    fn new<C: GridInt>(p: &Placed<C>, grid: Grid) -> Region {
        let (sx, sy) = grid.shifts;
        let x: [i128; 3] = p.x.map(Into::into);
        let y: [i128; 3] = p.y.map(Into::into);
        // The region's first texel, and coordinates relative to it.
        let ox = x[0].min(x[1]).min(x[2]) >> sx;
        let oy = y[0].min(y[1]).min(y[2]) >> sy;
        let (ux, uy) = (exp2(-(sx as i32)), exp2(-(sy as i32)));
        let mx = to_f64(margin_in::<i128>(grid.margin.0)) * ux;
        let my = to_f64(margin_in::<i128>(grid.margin.1)) * uy;
        let vertices = [0, 1, 2].map(|k| {
            (
                to_f64(x[k] - (ox << sx)) * ux,
                to_f64(y[k] - (oy << sy)) * uy,
            )
        });
        // The dilated region's bounding box: the vertices' box widened by
        // the margin (the same roundings as the region's own vertices).
        let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for &(px, py) in &vertices {
            x0 = x0.min(px - mx);
            x1 = x1.max(px + mx);
            y0 = y0.min(py - my);
            y1 = y1.max(py + my);
        }
        Region {
            ox,
            oy,
            vertices,
            margin: (mx, my),
            x0,
            x1,
            y0,
            y1,
            cells_x: floor(x0 - 0.5)..=floor(x1 - 0.5),
            cells_y: floor(y0 - 0.5)..=floor(y1 - 0.5),
        }
    }

    /// A point given to [`Running::add`], in texel coordinates from the
    /// texture's corner.
    fn at(&self, (ci, cj, a, b): Where) -> (f64, f64) {
        (
            to_f64(self.ox) + ci + a.clamp(0.0, 1.0),
            to_f64(self.oy) + cj + b.clamp(0.0, 1.0),
        )
    }

    /// The bounding box's part in the cell centred at `(ci, cj)` (cell
    /// coordinates), at its corners: on a box a bilinear function's
    /// extremes are at its corners. Steps 2 and 3 both read it.
    fn box_corners(&self, v: [f64; 4], ci: f64, cj: f64) -> [(f64, Where); 4] {
        let (a0, a1) = (
            (self.x0 - ci).clamp(0.0, 1.0),
            (self.x1 - ci).clamp(0.0, 1.0),
        );
        let (b0, b1) = (
            (self.y0 - cj).clamp(0.0, 1.0),
            (self.y1 - cj).clamp(0.0, 1.0),
        );
        [(a0, b0), (a1, b0), (a0, b1), (a1, b1)].map(|(a, b)| (bilinear(v, a, b), (ci, cj, a, b)))
    }

    /// 2. The quick bound: the bounding box's part in each cell, at its
    ///    corners (counting the cells in `cells`).
    fn quick(&self, classes: &TexelClasses, cells: &mut u32) -> Running {
        let mut quick = Running::new();
        for j in self.cells_y.clone() {
            for i in self.cells_x.clone() {
                let (ci, cj) = (to_f64(i) + 0.5, to_f64(j) + 0.5);
                let v = classes.cell_values(self.ox + i, self.oy + j);
                *cells += 1;
                for value in v {
                    quick.largest = quick.largest.max(abs(value));
                }
                for (value, at) in self.box_corners(v, ci, cj) {
                    quick.add(value, at);
                }
            }
        }
        quick
    }

    /// The dilated region as a polygon.
    fn polygon(&self) -> Polygon {
        dilated(self.vertices, self.margin)
    }

    /// 3. The exact extremes of the region's part in cell `(i, j)`, when
    ///    `need` (of the cell's quick range) asks for some class and the
    ///    part is not empty.
    fn exact_cell(
        &self,
        classes: &TexelClasses,
        polygon: &Polygon,
        (i, j): (i128, i128),
        quick: &Running,
        need: impl Fn(&Running) -> u8,
    ) -> Option<CellExtremes> {
        let (ci, cj) = (to_f64(i) + 0.5, to_f64(j) + 0.5);
        // The cell's quick range again (step 2's, read anew: few regions
        // get here).
        let v = classes.cell_values(self.ox + i, self.oy + j);
        let mut range = Running::new();
        range.largest = quick.largest;
        for (value, at) in self.box_corners(v, ci, cj) {
            range.add(value, at);
        }
        if need(&range) == 0 {
            return None;
        }
        let mut piece = *polygon;
        for q in &mut piece.points[..piece.len] {
            *q = (q.0 - ci, q.1 - cj);
        }
        // Clipped only by the cell's sides the region crosses (a side the
        // bounding box stays within removes nothing).
        if self.x0 < ci {
            piece = piece.clip(|q| q.0);
        }
        if self.x1 > ci + 1.0 {
            piece = piece.clip(|q| 1.0 - q.0);
        }
        if self.y0 < cj {
            piece = piece.clip(|q| q.1);
        }
        if self.y1 > cj + 1.0 {
            piece = piece.clip(|q| 1.0 - q.1);
        }
        if piece.len == 0 {
            return None;
        }
        let mut running = Running::new();
        running.largest = quick.largest;
        candidates(&piece, v, |a, b| {
            let value = bilinear(v, a.clamp(0.0, 1.0), b.clamp(0.0, 1.0));
            running.add(value, (ci, cj, a, b));
        });
        Some(CellExtremes { running, range })
    }
}
