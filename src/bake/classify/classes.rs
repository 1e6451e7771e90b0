//! The values the classifier reasons with: sets of texel classes
//! ([`Classes`]), inclusive blocks of texel coordinates ([`Block`]), a
//! triangle's grid ([`Grid`]), and a micro-triangle placed on it
//! ([`Placed`]).

use crate::bake::exact::narrowed_below;
use crate::micromap::State;
use crate::num::wide::GridInt;

/// Mixed blocks of at most this many texels are searched texel by texel.
const SMALL_BLOCK: u32 = 36;

/// Does `block` hold at most [`SMALL_BLOCK`] texels? Such a block is
/// searched texel by texel, which never runs out of budget. (Each side
/// first, so that the product of two sides never overflows.)
#[inline]
pub(crate) fn is_small<C: GridInt>(block: Block<C>) -> bool {
    let small = C::from(SMALL_BLOCK);
    let (w, h) = (block.x1 - block.x0, block.y1 - block.y0);
    w < small && h < small && (w + C::from(1)) * (h + C::from(1)) <= small
}

/// The set of texel classes a region samples.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Classes {
    pub(crate) opaque: bool,
    pub(crate) transparent: bool,
}

impl Classes {
    pub(crate) const BOTH: Classes = Classes {
        opaque: true,
        transparent: true,
    };

    /// The classes of class bits: bit 0, may pass (opaque); bit 1, may
    /// fail (transparent).
    pub(crate) fn of_bits(bits: u8) -> Classes {
        Classes {
            opaque: bits & 1 != 0,
            transparent: bits & 2 != 0,
        }
    }

    pub(crate) fn union(self, other: Classes) -> Classes {
        Classes {
            opaque: self.opaque || other.opaque,
            transparent: self.transparent || other.transparent,
        }
    }

    /// The state a region reading these classes has when it is known:
    /// opaque or transparent for one class, `None` for both (or none).
    pub(crate) fn known_state(self) -> Option<State> {
        match (self.opaque, self.transparent) {
            (true, false) => Some(State::Opaque),
            (false, true) => Some(State::Transparent),
            _ => None,
        }
    }

    /// The classes not in `self`.
    pub(crate) fn complement(self) -> Classes {
        Classes {
            opaque: !self.opaque,
            transparent: !self.transparent,
        }
    }

    pub(crate) fn contains(self, other: Classes) -> bool {
        (self.opaque || !other.opaque) && (self.transparent || !other.transparent)
    }

    pub(crate) fn is_mixed(self) -> bool {
        self.opaque && self.transparent
    }
}

/// An inclusive block of texel coordinates `[x0, x1] x [y0, y1]`, before
/// wrapping (they may lie anywhere); in the walk's coordinate type (see
/// [`GridInt`]), `i128` elsewhere.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Block<C = i128> {
    pub(crate) x0: C,
    pub(crate) x1: C,
    pub(crate) y0: C,
    pub(crate) y1: C,
}

/// One triangle's grid: `2^shift` grid units per texel on each axis, and
/// the margin by which the GPU model dilates every micro-triangle, `2^k`
/// grid units per axis (`None`: no margin, the exact model). The dilated
/// region `T + [-mx, mx] x [-my, my]` meets a half-open rectangle
/// `[x0, x1) x [y0, y1)` iff `T` meets `[x0 - mx, x1 + mx) x [y0 - my,
/// y1 + my)`, so the search only widens its rectangles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Grid {
    pub(crate) shifts: (u32, u32),
    pub(crate) margin: (Option<Margin>, Option<Margin>),
}

/// A margin of `units * 2^shift` grid units (`units` in `1..=8`, see
/// [`TexelMargin`](crate::bake::gpu::TexelMargin)).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Margin {
    pub(crate) units: u32,
    pub(crate) shift: u32,
}

impl Margin {
    /// The same margin on a grid `2^extra` times finer.
    pub(crate) fn finer(self, extra: u32) -> Margin {
        Margin {
            shift: self.shift + extra,
            ..self
        }
    }

    /// The margin's bits: it is below `2^(shift + 4)`.
    pub(crate) fn bits(self) -> u32 {
        self.shift + 4
    }
}

impl Grid {
    /// The exact model's grid (no margin).
    pub(crate) fn exact(shifts: (u32, u32)) -> Grid {
        Grid {
            shifts,
            margin: (None, None),
        }
    }
}

/// A margin in grid units (0 for `None`) in the type `C`.
#[inline]
pub(crate) fn margin_in<C: GridInt>(margin: Option<Margin>) -> C {
    margin.map_or(C::from(0), |m| C::from(m.units) << m.shift)
}

/// A texel coordinate known to be in `0..size` (`size < 2^32`), as `u32`.
#[inline]
pub(crate) fn texel_in_range<C: GridInt>(c: C) -> u32 {
    Into::<i128>::into(c) as u32
}

impl Block {
    /// The same block in `i64`, when its coordinates are below `2^62` in
    /// magnitude: then so is every coordinate in it.
    pub(crate) fn narrowed(self) -> Option<Block<i64>> {
        let [x0, x1, y0, y1] = narrowed_below([self.x0, self.x1, self.y0, self.y1], 1 << 62)?;
        Some(Block { x0, x1, y0, y1 })
    }
}

impl<C: GridInt> Block<C> {
    /// The same block in `i128` (exact).
    #[inline]
    pub(crate) fn wide(self) -> Block {
        Block {
            x0: self.x0.into(),
            x1: self.x1.into(),
            y0: self.y0.into(),
            y1: self.y1.into(),
        }
    }
}

/// One micro-triangle placed on the grid, in coordinates of type `C`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Placed<C> {
    pub(crate) x: [C; 3],
    pub(crate) y: [C; 3],
}

/// The walk of [`Baker::bake`](crate::bake::Baker::bake) runs in `i64` when the root's coordinates
/// are below this in magnitude and both shifts at most [`NARROW_SHIFT`].
/// Why nothing overflows then: every node vertex is a convex combination
/// of the root's (midpoints of midpoints), so below `2^59` too; the largest
/// values formed are a sum of three vertices (the centroid, below
/// `3 * 2^59 < 2^61`) and a sum of two minus half a cell of the twice
/// finer grid (`2^shift <= 2^58`: below `2^61`).
pub(crate) const NARROW_WALK_COORDINATE: i128 = 1 << 59;

/// See [`NARROW_WALK_COORDINATE`]; also keeps `1 << shift` in `i64`.
pub(crate) const NARROW_SHIFT: u32 = 58;

/// The largest margin (`2^k` grid units) the `i64` walk takes: a
/// coordinate below `2^59` minus half a cell (`2^57`) and the margin stays
/// below `2^60`.
pub(crate) const NARROW_MARGIN: u32 = 57;

impl Placed<i128> {
    /// The same triangle in `i64`, when the walk from it (as the root)
    /// stays in range: see [`NARROW_WALK_COORDINATE`].
    pub(crate) fn narrowed(&self, grid: Grid) -> Option<Placed<i64>> {
        let (sx, sy) = grid.shifts;
        let wide_margin = |m: Option<Margin>| m.is_some_and(|m| m.bits() > NARROW_MARGIN + 1);
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
    pub(crate) fn wide(&self) -> Placed<i128> {
        Placed {
            x: self.x.map(Into::into),
            y: self.y.map(Into::into),
        }
    }
}
