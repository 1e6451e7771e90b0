//! The exact search: every class a closed triangle (dilated by the grid's
//! margin) samples, by splitting its bounding block of texels until each
//! part is uniform or misses it; and the footprints and reaches it tests
//! with.

use super::classes::{is_small, margin_in, Block, Classes, Grid, Margin};
use super::tables::TexelClasses;
use crate::bake::exact::ExactTriangle;
use crate::bake::texture::Filter;
use crate::num::wide::GridInt;
use alloc::vec::Vec;

/// What [`TexelClasses::search`] found.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Search {
    pub(crate) classes: Classes,
    /// The search ran out of block tests before it could rule out the
    /// classes it had not found; those classes are then included in
    /// `classes` (unknown is always sound).
    pub(crate) exhausted: bool,
    /// The first block of one class found to meet the triangle, per class
    /// (`[transparent, opaque]`).
    pub(crate) witness_block: [Option<Block>; 2],
    /// Block and texel tests made (work units, [bounded work](crate::bake#bounded-work)).
    pub(crate) tests: u32,
}

impl Search {
    /// Records `block` as the witness of each of `classes`.
    fn witness(&mut self, classes: Classes, block: Block) {
        if classes.opaque {
            self.witness_block[1] = Some(block);
        }
        if classes.transparent {
            self.witness_block[0] = Some(block);
        }
    }
}

impl TexelClasses {
    /// The texel coordinates whose footprint can hold the sample point
    /// `p` in grid units (`unit = 2^shift` per texel): nearest
    /// `floor(p)`; linear `floor(p - 1/2)` and the next one.
    /// In the coordinates' own type `C`: the caller's bound keeps `lo`,
    /// `hi` and half a grid cell's offset from them in range.
    /// With a `margin` (`2^k` grid units), of the interval dilated by it.
    #[inline]
    fn footprint<C: GridInt>(&self, lo: C, hi: C, shift: u32, margin: Option<Margin>) -> (C, C) {
        let m = margin_in::<C>(margin);
        let (lo, hi) = (lo - m, hi + m);
        match self.sampler.filter {
            Filter::Nearest => (lo >> shift, hi >> shift),
            Filter::Linear => {
                let half = C::from(1) << (shift - 1);
                ((lo - half) >> shift, ((hi - half) >> shift) + C::from(1))
            }
        }
    }

    /// The geometric half-open rectangle (grid units) of the points whose
    /// footprint meets the texel range `lo..=hi`, widened by `margin`
    /// (`2^k` grid units) on both sides.
    #[inline]
    fn reach(&self, lo: i128, hi: i128, shift: u32, margin: Option<Margin>) -> (i128, i128) {
        let m = margin_in::<i128>(margin);
        match self.sampler.filter {
            Filter::Nearest => ((lo << shift) - m, ((hi + 1) << shift) + m),
            Filter::Linear => {
                let half = 1i128 << (shift - 1);
                ((lo << shift) - half - m, ((hi + 1) << shift) + half + m)
            }
        }
    }

    /// The footprint block of a point set with grid bounding box
    /// `[min_x, max_x] x [min_y, max_y]`, dilated by the grid's margin.
    #[inline]
    pub(crate) fn bounding_block<C: GridInt>(
        &self,
        (min_x, max_x): (C, C),
        (min_y, max_y): (C, C),
        grid: Grid,
    ) -> Block<C> {
        let (sx, sy) = grid.shifts;
        let (x0, x1) = self.footprint(min_x, max_x, sx, grid.margin.0);
        let (y0, y1) = self.footprint(min_y, max_y, sy, grid.margin.1);
        Block { x0, x1, y0, y1 }
    }

    /// The classes of the whole block only: decides a micro-triangle
    /// without geometry when its bounding block is uniform.
    pub(crate) fn quick<C: GridInt>(&self, block: Block<C>) -> Classes {
        self.block_classes(block)
    }

    /// Every class the closed triangle `t` samples, exactly, by splitting
    /// its bounding block until each part is uniform or misses `t`.
    /// `budget` caps the block tests; past it the missing classes are
    /// assumed (sound) and `exhausted` is set. Only the classes in `want`
    /// are looked for: texels of the others are never tested (nor
    /// reported), and the search stops once it has found them all.
    pub(crate) fn search(
        &self,
        t: &ExactTriangle,
        grid: Grid,
        want: Classes,
        budget: u32,
        stack: &mut Vec<Block>,
    ) -> Search {
        let (sx, sy) = grid.shifts;
        let (mx, my) = grid.margin;
        let start = self.bounding_block((t.min_x(), t.max_x()), (t.min_y(), t.max_y()), grid);
        let mut found = Search::default();
        // A small footprint (most micro-triangles at useful levels): its
        // texels one by one, without the block stack.
        if is_small(start) {
            return match start.narrowed() {
                Some(narrow) => self.search_texels(t, narrow, grid, want),
                None => self.search_texels(t, start, grid, want),
            };
        }
        stack.clear();
        stack.push(start);
        let mut tests = 0u32;
        while let Some(block) = stack.pop() {
            if found.classes.contains(want) {
                break;
            }
            tests += 1;
            if tests > budget {
                tests = budget;
                found.exhausted = true;
                found.classes = found.classes.union(want);
                break;
            }
            // Classes first: a block that can add nothing needs no geometry.
            let single = block.x0 == block.x1 && block.y0 == block.y1;
            let classes = if single {
                self.class_of(self.wrap(block.x0, block.y0))
            } else {
                self.block_classes(block)
            };
            if found.classes.union(want.complement()).contains(classes) {
                continue;
            }
            let (rx0, rx1) = self.reach(block.x0, block.x1, sx, mx);
            let (ry0, ry1) = self.reach(block.y0, block.y1, sy, my);
            if !t.meets(rx0, rx1, ry0, ry1) {
                continue;
            }
            // Uniform, or one texel (which may pass and fail both, when its
            // binary32 values straddle the cutoff).
            if !classes.is_mixed() || single {
                found.classes = found.classes.union(classes);
                found.witness(classes, block);
                continue;
            }
            // Mixed and small: test its texels one by one (cheaper than
            // splitting through mixed halves).
            if is_small(block) {
                for y in block.y0..=block.y1 {
                    for x in block.x0..=block.x1 {
                        stack.push(Block {
                            x0: x,
                            x1: x,
                            y0: y,
                            y1: y,
                        });
                    }
                }
                continue;
            }
            // Mixed: split the longer side (a single texel was handled).
            if block.x1 - block.x0 >= block.y1 - block.y0 {
                let mid = block.x0 + (block.x1 - block.x0) / 2;
                stack.push(Block {
                    x0: mid + 1,
                    ..block
                });
                stack.push(Block { x1: mid, ..block });
            } else {
                let mid = block.y0 + (block.y1 - block.y0) / 2;
                stack.push(Block {
                    y0: mid + 1,
                    ..block
                });
                stack.push(Block { y1: mid, ..block });
            }
        }
        found.tests = tests;
        found
    }

    /// [`search`](Self::search) of a small `block`: its texels one by one,
    /// in coordinates of type `C` (any that holds the block's).
    fn search_texels<C: GridInt>(
        &self,
        t: &ExactTriangle,
        block: Block<C>,
        grid: Grid,
        want: Classes,
    ) -> Search {
        let (sx, sy) = grid.shifts;
        let (mx, my) = grid.margin;
        let mut found = Search::default();
        // A small block's sides are below SMALL_BLOCK: exact casts.
        let side = |lo: C, hi: C| Into::<i128>::into(hi - lo) as u32;
        for dy in 0..=side(block.y0, block.y1) {
            let y = block.y0 + C::from(dy);
            for dx in 0..=side(block.x0, block.x1) {
                let x = block.x0 + C::from(dx);
                found.tests += 1;
                let classes = self.class_of(self.wrap(x, y));
                if found.classes.union(want.complement()).contains(classes) {
                    continue;
                }
                let (rx0, rx1) = self.reach(x.into(), x.into(), sx, mx);
                let (ry0, ry1) = self.reach(y.into(), y.into(), sy, my);
                if t.meets(rx0, rx1, ry0, ry1) {
                    found.classes = found.classes.union(classes);
                    let texel = Block {
                        x0: x,
                        x1: x,
                        y0: y,
                        y1: y,
                    };
                    found.witness(classes, texel.wide());
                    if found.classes.contains(want) {
                        return found;
                    }
                }
            }
        }
        found
    }

    /// The point set's reach rectangle for a block (grid units), public to
    /// the witness search.
    pub(crate) fn block_reach(&self, block: Block, grid: Grid) -> [i128; 4] {
        let (sx, sy) = grid.shifts;
        let (x0, x1) = self.reach(block.x0, block.x1, sx, grid.margin.0);
        let (y0, y1) = self.reach(block.y0, block.y1, sy, grid.margin.1);
        [x0, x1, y0, y1]
    }

    /// The texel coordinates of `block` in the footprint of the grid point
    /// `(px, py)` on a grid `2^extra` times finer than `grid`, dilated by
    /// the grid's margin (`2^(k + extra)` units there): one exists when the
    /// point is in the block's reach, which is dilated by the same margin.
    /// (The undilated footprint can miss the block: a GPU-model witness
    /// may lie up to the margin outside it, and clamping would then name a
    /// neighbour of the other class.)
    pub(crate) fn footprint_texel_in(
        &self,
        block: Block,
        (px, py): (i128, i128),
        grid: Grid,
        extra: u32,
    ) -> (i128, i128) {
        let (sx, sy) = grid.shifts;
        let fine = |m: Option<Margin>| m.map(|m| m.finer(extra));
        let (fx0, fx1) = self.footprint(px, px, sx + extra, fine(grid.margin.0));
        let (fy0, fy1) = self.footprint(py, py, sy + extra, fine(grid.margin.1));
        (
            fx0.max(block.x0).min(fx1.min(block.x1)),
            fy0.max(block.y0).min(fy1.min(block.y1)),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bake::{AddressMode, Cutoff, Sampler, Unorm8Texture};
    use micromap_index_test_support::SplitMix64;

    /// The per-texel search in `i64` finds what the one in `i128` finds
    /// (classes and witnesses) on small blocks just inside `+-2^62`, where
    /// [`Block::narrowed`] stops; a block reaching `2^62` is not narrowed.
    #[test]
    fn narrow_and_wide_texel_searches_agree_near_their_threshold() {
        let mut rng = SplitMix64::new(0x7e57);
        let mut next = move || rng.next_u64();
        let texels: Vec<u8> = (0..16).map(|_| (next() % 256) as u8).collect();
        let texture = Unorm8Texture::new(4, 4, &texels).unwrap();
        let edge = 1i128 << 62;
        let mut met = [0u32; 2];
        for case in 0..4000 {
            let filter = if case % 2 == 0 {
                Filter::Nearest
            } else {
                Filter::Linear
            };
            let address = AddressMode::ALL[case / 2 % 5];
            let sampler = Sampler {
                filter,
                address_u: address,
                address_v: address,
                border_alpha: 0.0,
            };
            let test = crate::bake::alpha_test::AlphaTest::new(
                Cutoff::default(),
                sampler.filter,
                &crate::bake::TextureUnit::default(),
                1.0,
            );
            let classes = TexelClasses::new(&texture, sampler, test).unwrap();
            let shifts = Grid::exact((1 + (next() % 4) as u32, 1 + (next() % 4) as u32));
            // A block of up to 6 x 6 texels ending just inside +-2^62.
            let side = |r: u64, sign: i128| {
                let (far, len) = (1 + i128::from(r % 3), i128::from(r / 3 % 6));
                if sign > 0 {
                    (edge - far - len, edge - far)
                } else {
                    (-edge + far, -edge + far + len)
                }
            };
            let sign = |r: u64| if r % 2 == 0 { 1 } else { -1 };
            let (x0, x1) = side(next(), sign(next()));
            let (y0, y1) = side(next(), sign(next()));
            let block = Block { x0, x1, y0, y1 };
            // A triangle with vertices around the block's reach.
            let [rx0, rx1, ry0, ry1] = classes.block_reach(block, shifts);
            let mut point = |lo: i128, hi: i128| {
                let span = (hi - lo) * 2;
                lo - span / 4 + (i128::from(next()) % span)
            };
            let x = [point(rx0, rx1), point(rx0, rx1), point(rx0, rx1)];
            let y = [point(ry0, ry1), point(ry0, ry1), point(ry0, ry1)];
            let t = ExactTriangle::new(x, y);
            let narrow = block.narrowed().unwrap();
            let a = classes.search_texels(&t, narrow, shifts, Classes::BOTH);
            let b = classes.search_texels(&t, block, shifts, Classes::BOTH);
            assert_eq!(
                (a.classes, a.witness_block),
                (b.classes, b.witness_block),
                "{block:?} {t:?}"
            );
            met[usize::from(b.classes != Classes::default())] += 1;
            let over = Block {
                x1: if x1 > 0 { edge } else { x1 },
                x0: if x0 < 0 { -edge } else { x0 },
                ..block
            };
            assert!(over.narrowed().is_none());
        }
        // Both outcomes, many times.
        assert!(met[0] > 100 && met[1] > 100, "{met:?}");
    }
}
