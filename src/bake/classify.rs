//! Which texel classes (opaque, transparent) a closed micro-triangle can
//! sample: texel classes with prefix sums, the image of a block of texel
//! coordinates under the address modes, and an exact block search.

use super::exact::{narrowed_below, ExactTriangle};
use super::parallel::Runner;
use super::texture::{AddressMode, AlphaTexture, Cutoff, Filter, Sampler, TextureError};
use crate::micromap::State;
use crate::num::wide::GridInt;
use alloc::vec::Vec;

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

    fn of(opaque: bool) -> Classes {
        Classes {
            opaque,
            transparent: !opaque,
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

    fn contains(self, other: Classes) -> bool {
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
    pub(crate) margin: (Option<u32>, Option<u32>),
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

/// A margin `2^k` grid units (0 for `None`) in the type `C`.
#[inline]
fn margin_in<C: GridInt>(margin: Option<u32>) -> C {
    margin.map_or(C::from(0), |k| C::from(1) << k)
}

/// A texel coordinate known to be in `0..size` (`size < 2^32`), as `u32`.
#[inline]
fn texel_in_range<C: GridInt>(c: C) -> u32 {
    Into::<i128>::into(c) as u32
}

impl Block {
    /// The same block in `i64`, when its coordinates are below `2^62` in
    /// magnitude: then so is every coordinate in it.
    fn narrowed(self) -> Option<Block<i64>> {
        let [x0, x1, y0, y1] = narrowed_below([self.x0, self.x1, self.y0, self.y1], 1 << 62)?;
        Some(Block { x0, x1, y0, y1 })
    }
}

impl<C: GridInt> Block<C> {
    /// The same block in `i128` (exact).
    #[inline]
    fn wide(self) -> Block {
        Block {
            x0: self.x0.into(),
            x1: self.x1.into(),
            y0: self.y0.into(),
            y1: self.y1.into(),
        }
    }
}

/// The image of `lo..=hi` under an address mode: at most two ranges of
/// `0..size`, and whether some coordinate reads the border.
#[derive(Clone, Copy, Debug)]
struct AxisImage {
    ranges: [(u32, u32); 2],
    count: usize,
    border: bool,
}

impl AxisImage {
    fn one(lo: i128, hi: i128) -> AxisImage {
        AxisImage {
            ranges: [(lo as u32, hi as u32), (0, 0)],
            count: 1,
            border: false,
        }
    }
}

/// Does `lo..=hi` hold an integer `≡ r (mod m)`?
fn holds_residue(lo: i128, hi: i128, r: i128, m: i128) -> bool {
    lo + (r - lo).rem_euclid(m) <= hi
}

fn axis_image(mode: AddressMode, lo: i128, hi: i128, size: u32) -> AxisImage {
    let n = i128::from(size);
    // Every mode reads in-range coordinates as they are.
    if lo >= 0 && hi < n {
        return AxisImage::one(lo, hi);
    }
    let full = AxisImage::one(0, n - 1);
    // The wrapped value of one coordinate (the modes below never read the
    // border).
    let at = |i: i128| i128::from(mode.wrap_wide(i, size).unwrap_or(0));
    match mode {
        AddressMode::Repeat => {
            if hi - lo + 1 >= n {
                return full;
            }
            let a = lo.rem_euclid(n);
            let b = a + (hi - lo);
            if b < n {
                AxisImage::one(a, b)
            } else {
                AxisImage {
                    ranges: [(a as u32, (n - 1) as u32), (0, (b - n) as u32)],
                    count: 2,
                    border: false,
                }
            }
        }
        AddressMode::MirroredRepeat => {
            if hi - lo + 1 >= 2 * n {
                return full;
            }
            // Monotone between the folds at t = 0 | 2n - 1 (value 0) and
            // t = n - 1 | n (value n - 1).
            let min = if holds_residue(lo, hi, 0, 2 * n) || holds_residue(lo, hi, 2 * n - 1, 2 * n)
            {
                0
            } else {
                at(lo).min(at(hi))
            };
            let max = if holds_residue(lo, hi, n - 1, 2 * n) || holds_residue(lo, hi, n, 2 * n) {
                n - 1
            } else {
                at(lo).max(at(hi))
            };
            AxisImage::one(min, max)
        }
        AddressMode::ClampToEdge => AxisImage::one(lo.clamp(0, n - 1), hi.clamp(0, n - 1)),
        AddressMode::ClampToBorder => {
            let (a, b) = (lo.max(0), hi.min(n - 1));
            AxisImage {
                ranges: [(a.max(0) as u32, b.max(0) as u32), (0, 0)],
                count: usize::from(a <= b),
                border: lo < 0 || hi >= n,
            }
        }
        AddressMode::MirrorClampToEdge => {
            let min = if lo <= 0 && hi >= -1 {
                0
            } else {
                at(lo).min(at(hi))
            };
            AxisImage::one(min, at(lo).max(at(hi)))
        }
    }
}

/// Every texel classified once, with prefix sums to count the opaque texels
/// of a rectangle in four reads.
#[derive(Clone, Debug)]
pub(crate) struct TexelClasses {
    pub(crate) width: u32,
    pub(crate) height: u32,
    /// `prefix[y * (width + 1) + x]`: opaque texels in `[0, x) x [0, y)`,
    /// modulo `2^16`. Four reads count a rectangle of fewer than `2^16`
    /// texels exactly (the true count fits); half the bytes of `u32` sums
    /// make the tables quicker to build and to read. A larger rectangle
    /// is counted exactly only when its classes depend on it (see
    /// [`TexelClasses::rectangle_classes`]).
    prefix: Vec<u16>,
    /// One byte per texel: 0 transparent, any other value (1 from the
    /// library's textures) opaque (row-major).
    opaque: Vec<u8>,
    pub(crate) sampler: Sampler,
    border_opaque: bool,
}

/// Texels per segment of [`add_row_counts`].
const SEGMENT: usize = 1024;

/// [`add_row_counts`]'s two buffers, each 8 zeros (the texels before a
/// segment) and a segment; made once per table, not once per row.
struct RowScratch([[u16; 8 + SEGMENT]; 2]);

/// Adds to `sums[x]` the opaque texels of `row[..=x]`, modulo `2^16` (the
/// prefix sums' arithmetic). Any byte but 0 is opaque, here and in
/// [`TexelClasses::class_of`].
///
/// A running sum texel by texel is a chain of dependent adds (most of
/// the tables' build); here every pass is element-wise, which the
/// compiler turns into SIMD: per segment, sums of 8-texel windows (three
/// shifted adds), then 8 running sums, one per position modulo 8 (the
/// windows ending at `x, x - 8, ...` tile `row[..=x]`), plus the counts
/// of the segments before.
fn add_row_counts(row: &[u8], sums: &mut [u16], scratch: &mut RowScratch) {
    let [a, b] = &mut scratch.0;
    // `out[k] = inp[k] + inp[k - d]` (`inp[k]` for `k < d`).
    let shifted_add = |out: &mut [u16], inp: &[u16], d: usize| {
        out[..d].copy_from_slice(&inp[..d]);
        for ((o, &x), &y) in out[d..].iter_mut().zip(&inp[d..]).zip(inp) {
            *o = x.wrapping_add(y);
        }
    };
    let mut before = 0u16;
    for (row, sums) in row.chunks(SEGMENT).zip(sums.chunks_mut(SEGMENT)) {
        for (t, &texel) in a[8..].iter_mut().zip(row) {
            *t = u16::from(texel != 0);
        }
        // (After a short last segment, `a` holds older texels: the sums
        // look only back, so they never reach the segment's.)
        shifted_add(b, a, 1);
        shifted_add(a, b, 2);
        shifted_add(b, a, 4);
        // b[8 + x]: opaque texels in row[x - 7..=x].
        let mut running = [before; 8];
        for window in b[8..].chunks_exact_mut(8) {
            for (r, w) in running.iter_mut().zip(window.iter_mut()) {
                *r = r.wrapping_add(*w);
                *w = *r;
            }
        }
        for (sum, &count) in sums.iter_mut().zip(&b[8..]) {
            *sum = sum.wrapping_add(count);
        }
        before = b[8 + row.len() - 1];
    }
}

/// The prefix sums of a band of rows (`classes`, rows of `stride - 1`
/// class bytes) into `sums` (as many rows of `stride`, zero on entry),
/// counted from the band's first row: each row is the one above plus its
/// own counts ([`add_row_counts`]).
fn band_prefix_sums(classes: &[u8], sums: &mut [u16], stride: usize) {
    let mut scratch = RowScratch([[0; 8 + SEGMENT]; 2]);
    for (y, row) in classes.chunks(stride - 1).enumerate() {
        let (above, rest) = sums.split_at_mut(y * stride);
        let out = &mut rest[..stride];
        if y > 0 {
            out.copy_from_slice(&above[(y - 1) * stride..]);
        }
        add_row_counts(row, &mut out[1..], &mut scratch);
    }
}

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

impl TexelClasses {
    #[cfg(test)]
    pub(crate) fn new(
        texture: &(impl AlphaTexture + ?Sized),
        sampler: Sampler,
        cutoff: Cutoff,
    ) -> Result<TexelClasses, TextureError> {
        Self::new_within(texture, sampler, cutoff, u64::MAX, &Runner::serial())
    }

    /// The bytes the tables of a `width x height` texture take: `w h` class
    /// bytes and `2 (w + 1) (h + 1)` bytes of prefix sums (saturated).
    pub(crate) fn table_bytes(width: u32, height: u32) -> u64 {
        let (w, h) = (u64::from(width), u64::from(height));
        (w * h).saturating_add((w + 1) * (h + 1) * 2)
    }

    /// The tables, allocated fallibly (`try_reserve_exact`) and only if
    /// they fit `max_bytes`.
    pub(crate) fn new_within(
        texture: &(impl AlphaTexture + ?Sized),
        sampler: Sampler,
        cutoff: Cutoff,
        max_bytes: u64,
        runner: &Runner,
    ) -> Result<TexelClasses, TextureError> {
        let (width, height) = (texture.width(), texture.height());
        if width == 0 || height == 0 {
            return Err(TextureError::Empty);
        }
        if u64::from(width) * u64::from(height) >= 1 << 32 {
            return Err(TextureError::TooLarge { width, height });
        }
        if sampler.border_alpha.is_nan() {
            return Err(TextureError::NanThreshold);
        }
        let bytes = Self::table_bytes(width, height);
        let failed = TextureError::AllocationFailed {
            bytes,
            limit: max_bytes,
        };
        if bytes > max_bytes {
            return Err(failed);
        }
        // Sizes in `usize` (checked: a 32-bit target cannot hold a 2^31
        // texture's tables), reserved fallibly: never a capacity-overflow
        // panic or an allocation abort.
        let stride = width as usize + 1;
        let texels = usize::try_from(u64::from(width) * u64::from(height));
        let sums_len = usize::try_from((u64::from(width) + 1) * (u64::from(height) + 1));
        let (Ok(texels), Ok(sums_len)) = (texels, sums_len) else {
            return Err(failed);
        };
        // The class bytes are appended row by row (one call per row, so a
        // `dyn` texture costs one dynamic call a row, not a texel), never
        // zero-filled first.
        let mut opaque: Vec<u8> = Vec::new();
        opaque
            .try_reserve_exact(texels)
            .map_err(|_| failed.clone())?;
        let mut prefix: Vec<u16> = Vec::new();
        prefix
            .try_reserve_exact(sums_len)
            .map_err(|_| failed.clone())?;
        for y in 0..height {
            let start = opaque.len();
            texture.extend_opaque_row(y, &cutoff, &mut opaque);
            // A texture whose row is not `width` bytes breaks its contract;
            // refuse it rather than build tables that lie.
            if opaque.len() != start + width as usize {
                return Err(TextureError::WrongLength {
                    expected: u64::from(width),
                    got: opaque.len() - start,
                });
            }
        }
        // The prefix sums by bands of rows, a task each: every band from a
        // row of zeros, then the sums of the bands above added to it (one
        // band when serial: the rows in one pass, no correction).
        prefix.resize(sums_len, 0);
        let rows = height as usize;
        let bands = if runner.threads() > 1 {
            (2 * runner.threads()).min(rows)
        } else {
            1
        };
        let band_rows = rows.div_ceil(bands);
        let mut parts: Vec<(&[u8], &mut [u16])> = opaque
            .chunks(band_rows * (stride - 1))
            .zip(prefix[stride..].chunks_mut(band_rows * stride))
            .collect();
        runner.for_each_mut(&mut parts, |(classes, sums)| {
            band_prefix_sums(classes, sums, stride);
        });
        if parts.len() > 1 {
            // What band k needs added: the last rows of bands 0..k, summed.
            let mut offsets: Vec<u16> = Vec::new();
            offsets
                .try_reserve_exact(parts.len() * stride)
                .map_err(|_| failed.clone())?;
            offsets.resize(stride, 0);
            for k in 1..parts.len() {
                let sums = &parts[k - 1].1;
                let last = &sums[sums.len() - stride..];
                let before = (k - 1) * stride;
                offsets.extend_from_within(before..before + stride);
                for (o, &l) in offsets[k * stride..].iter_mut().zip(last) {
                    *o = o.wrapping_add(l);
                }
            }
            let mut fixes: Vec<(&[u16], &mut [u16])> = offsets
                .chunks(stride)
                .zip(parts.into_iter().map(|(_, sums)| sums))
                .skip(1)
                .collect();
            runner.for_each_mut(&mut fixes, |(offset, sums)| {
                for row in sums.chunks_mut(stride) {
                    for (s, &o) in row.iter_mut().zip(offset.iter()) {
                        *s = s.wrapping_add(o);
                    }
                }
            });
        }
        Ok(TexelClasses {
            width,
            height,
            prefix,
            opaque,
            sampler,
            border_opaque: cutoff.is_opaque(f64::from(sampler.border_alpha)),
        })
    }

    /// Opaque texels in `[x0, x1] x [y0, y1]` (inclusive, in range),
    /// modulo `2^16`: the count itself when the rectangle has fewer than
    /// `2^16` texels.
    #[inline]
    fn opaque_count_mod(&self, (x0, x1): (u32, u32), (y0, y1): (u32, u32)) -> u16 {
        let stride = self.width as usize + 1;
        let at = |x: u32, y: u32| self.prefix[y as usize * stride + x as usize];
        at(x1 + 1, y1 + 1)
            .wrapping_add(at(x0, y0))
            .wrapping_sub(at(x0, y1 + 1))
            .wrapping_sub(at(x1 + 1, y0))
    }

    /// Opaque texels in `[x0, x1] x [y0, y1]` (inclusive, in range),
    /// exactly: the sum over tiles of fewer than `2^16` texels each.
    fn opaque_count(&self, (x0, x1): (u32, u32), (y0, y1): (u32, u32)) -> u64 {
        // Tiles of `tw x th < 2^16` texels (`tw`, `th` >= 1).
        let tw = (x1 - x0).min(u32::from(u16::MAX) - 1) + 1;
        let th = u32::from(u16::MAX) / tw;
        let mut count = 0u64;
        let mut y = y0;
        loop {
            let y_end = y1.min(y.saturating_add(th - 1));
            let mut x = x0;
            loop {
                let x_end = x1.min(x.saturating_add(tw - 1));
                count += u64::from(self.opaque_count_mod((x, x_end), (y, y_end)));
                if x_end == x1 {
                    break;
                }
                x = x_end + 1;
            }
            if y_end == y1 {
                return count;
            }
            y = y_end + 1;
        }
    }

    /// The classes of the texels in `[x0, x1] x [y0, y1]` (inclusive, in
    /// range), from their opaque count.
    #[inline]
    fn rectangle_classes(&self, xr: (u32, u32), yr: (u32, u32)) -> Classes {
        // A linear or nearest footprint of one point (2 x 2 texels at most):
        // its class bytes, from two rows, not four prefix sums.
        if xr.1 - xr.0 <= 1 && yr.1 - yr.0 <= 1 {
            let w = self.width as usize;
            let dx = (xr.1 - xr.0) as usize;
            let (top, bottom) = (
                yr.0 as usize * w + xr.0 as usize,
                yr.1 as usize * w + xr.0 as usize,
            );
            let class = |i: usize| self.opaque[i] != 0;
            let (a, b, c, d) = (
                class(top),
                class(top + dx),
                class(bottom),
                class(bottom + dx),
            );
            return Classes {
                opaque: a | b | c | d,
                transparent: !(a & b & c & d),
            };
        }
        let area = u64::from(xr.1 - xr.0 + 1) * u64::from(yr.1 - yr.0 + 1);
        let residue = self.opaque_count_mod(xr, yr);
        let count = if area < 1 << 16 {
            u64::from(residue)
        } else if residue != 0 && residue != area as u16 {
            // A larger rectangle: a residue other than 0 (other than the
            // area's) still proves an opaque (a transparent) texel.
            return Classes::BOTH;
        } else {
            self.opaque_count(xr, yr)
        };
        Classes {
            opaque: count > 0,
            transparent: count < area,
        }
    }

    /// The classes of a texel, or of the border (`None`).
    pub(crate) fn class_of(&self, texel: Option<(u32, u32)>) -> bool {
        match texel {
            Some((x, y)) => self.opaque[y as usize * self.width as usize + x as usize] != 0,
            None => self.border_opaque,
        }
    }

    /// The texel (or the border, `None`) that texel coordinates read.
    #[inline]
    pub(crate) fn wrap<C: GridInt>(&self, x: C, y: C) -> Option<(u32, u32)> {
        // Every mode reads in-range coordinates as they are (inlined: the
        // common case of the per-texel search).
        let zero = C::from(0);
        if zero <= x && x < C::from(self.width) && zero <= y && y < C::from(self.height) {
            return Some((texel_in_range(x), texel_in_range(y)));
        }
        self.wrap_outside(x.into(), y.into())
    }

    /// [`wrap`](Self::wrap) of coordinates outside the texture.
    #[inline(never)]
    fn wrap_outside(&self, x: i128, y: i128) -> Option<(u32, u32)> {
        let x = self.sampler.address_u.wrap_wide(x, self.width)?;
        let y = self.sampler.address_v.wrap_wide(y, self.height)?;
        Some((x, y))
    }

    /// The classes the texels of `block` read (after wrapping). Always
    /// inlined: the walk reads one block a node, and a call costs a good
    /// part of the lookup itself.
    #[inline(always)]
    fn block_classes<C: GridInt>(&self, block: Block<C>) -> Classes {
        // Inside the texture (the common case, inlined): one rectangle,
        // whose coordinates are below 2^32 (exact casts).
        let (zero, w, h) = (C::from(0), C::from(self.width), C::from(self.height));
        if block.x0 >= zero && block.x1 < w && block.y0 >= zero && block.y1 < h {
            let xr = (texel_in_range(block.x0), texel_in_range(block.x1));
            let yr = (texel_in_range(block.y0), texel_in_range(block.y1));
            return self.rectangle_classes(xr, yr);
        }
        self.wrapped_block_classes(block.wide())
    }

    /// [`block_classes`](Self::block_classes) of a block reaching outside
    /// the texture.
    #[inline(never)]
    fn wrapped_block_classes(&self, block: Block) -> Classes {
        let xs = axis_image(self.sampler.address_u, block.x0, block.x1, self.width);
        let ys = axis_image(self.sampler.address_v, block.y0, block.y1, self.height);
        let mut classes = Classes::default();
        if xs.border || ys.border {
            classes = Classes::of(self.border_opaque);
        }
        for &xr in &xs.ranges[..xs.count] {
            for &yr in &ys.ranges[..ys.count] {
                classes = classes.union(self.rectangle_classes(xr, yr));
            }
        }
        classes
    }

    /// The texel coordinates whose footprint can hold the sample point
    /// `p` in grid units (`unit = 2^shift` per texel): nearest
    /// `floor(p)`; linear `floor(p - 1/2)` and the next one.
    /// In the coordinates' own type `C`: the caller's bound keeps `lo`,
    /// `hi` and half a grid cell's offset from them in range.
    /// With a `margin` (`2^k` grid units), of the interval dilated by it.
    #[inline]
    fn footprint<C: GridInt>(&self, lo: C, hi: C, shift: u32, margin: Option<u32>) -> (C, C) {
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
    fn reach(&self, lo: i128, hi: i128, shift: u32, margin: Option<u32>) -> (i128, i128) {
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
            let classes = if block.x0 == block.x1 && block.y0 == block.y1 {
                Classes::of(self.class_of(self.wrap(block.x0, block.y0)))
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
            if !classes.is_mixed() {
                found.classes = found.classes.union(classes);
                found.witness_block[usize::from(classes.opaque)] = Some(block);
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
            // Mixed: split the longer side (a single texel is never mixed).
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
                let classes = Classes::of(self.class_of(self.wrap(x, y)));
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
                    found.witness_block[usize::from(classes.opaque)] = Some(texel.wide());
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
        let fine = |m: Option<u32>| m.map(|k| k + extra);
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
    use crate::bake::Unorm8Texture;
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
            let classes = TexelClasses::new(&texture, sampler, Cutoff::default()).unwrap();
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

    /// Footprints of up to 2 x 2 texels (read from the class bytes) get
    /// the classes the prefix sums give, everywhere on a random texture,
    /// edges and corners included.
    #[test]
    fn small_footprints_read_what_the_prefix_sums_count() {
        let mut rng = SplitMix64::new(0x2b2);
        let (w, h) = (7u32, 5u32);
        for round in 0..50 {
            let texels: Vec<u8> = (0..w * h)
                .map(|_| (rng.next_u64() % 3 * 127) as u8)
                .collect();
            let texture = Unorm8Texture::new(w, h, &texels).unwrap();
            let classes =
                TexelClasses::new(&texture, Sampler::default(), Cutoff::default()).unwrap();
            for x0 in 0..w {
                for y0 in 0..h {
                    for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                        let (x1, y1) = (x0 + dx, y0 + dy);
                        if x1 >= w || y1 >= h {
                            continue;
                        }
                        let area = u64::from((dx + 1) * (dy + 1));
                        let opaque = classes.opaque_count((x0, x1), (y0, y1));
                        let counted = Classes {
                            opaque: opaque > 0,
                            transparent: opaque < area,
                        };
                        assert_eq!(
                            classes.rectangle_classes((x0, x1), (y0, y1)),
                            counted,
                            "round {round}: [{x0}, {x1}] x [{y0}, {y1}]"
                        );
                    }
                }
            }
        }
    }

    /// Tables built in bands on several threads (each band from zero, then
    /// corrected by the bands above) equal the serial build, on textures
    /// from one row (fewer rows than bands) to many, of several widths.
    #[test]
    fn banded_tables_equal_the_serial_build() {
        use crate::bake::parallel::Threads;
        let mut rng = SplitMix64::new(0xba2d);
        for (w, h) in [
            (1, 1),
            (5, 1),
            (3, 2),
            (7, 5),
            (40, 9),
            (33, 64),
            (1100, 13),
        ] {
            let texels: Vec<u8> = (0..w * h)
                .map(|_| [0, 0, 255, 7][(rng.next_u64() % 4) as usize])
                .collect();
            let texture = Unorm8Texture::new(w, h, &texels).unwrap();
            let (sampler, cutoff) = (Sampler::default(), Cutoff::default());
            let serial = TexelClasses::new(&texture, sampler, cutoff).unwrap();
            for threads in [2, 3, 8] {
                let runner = Runner::new(Threads::Exactly(threads));
                let banded =
                    TexelClasses::new_within(&texture, sampler, cutoff, u64::MAX, &runner).unwrap();
                assert_eq!(banded.prefix, serial.prefix, "{w}x{h}, {threads} threads");
                assert_eq!(banded.opaque, serial.opaque, "{w}x{h}, {threads} threads");
            }
        }
    }

    /// The row counts built in passes equal a running count texel by
    /// texel, modulo 2^16, on rows of every length around the segment
    /// and chunk sizes and bytes of every kind (any but 0 is opaque).
    #[test]
    fn row_counts_equal_a_running_count() {
        let mut rng = SplitMix64::new(0x5e9);
        let mut scratch = RowScratch([[0; 8 + SEGMENT]; 2]);
        for len in [
            0, 1, 7, 8, 9, 15, 16, 17, 1023, 1024, 1025, 2047, 2048, 2049, 5000,
        ] {
            for round in 0..4 {
                let row: Vec<u8> = (0..len)
                    .map(|_| [0, 0, 1, 2, 128, 255][(rng.next_u64() % 6) as usize])
                    .collect();
                let start: Vec<u16> = (0..len).map(|_| rng.next_u64() as u16).collect();
                let mut expected = start.clone();
                let mut run = 0u16;
                for (sum, &texel) in expected.iter_mut().zip(&row) {
                    run = run.wrapping_add(u16::from(texel != 0));
                    *sum = sum.wrapping_add(run);
                }
                let mut sums = start;
                add_row_counts(&row, &mut sums, &mut scratch);
                assert_eq!(sums, expected, "length {len}, round {round}");
            }
        }
    }

    /// A texture's opacity by texel coordinates.
    type Opacity<'a> = &'a dyn Fn(u32, u32) -> bool;

    /// Rectangles of `2^16` texels and more, whose prefix sums (kept
    /// modulo `2^16`) do not give the count: classes and exact counts
    /// equal a texel-by-texel count, on textures whose counts are
    /// multiples of `2^16` (residue 0, or the area's) and on random ones,
    /// including a texture wider than `2^16` (tiles split across a row).
    #[test]
    fn large_rectangles_are_counted_exactly() {
        let mut rng = SplitMix64::new(0x16b);
        // (width, height, texel opacity); 256 x 256 = 2^16 texels.
        let block = |x: u32, y: u32| x < 256 && y < 256;
        let cases: [(u32, u32, Opacity); 6] = [
            (600, 300, &|_, _| false),
            (600, 300, &|_, _| true),
            (600, 300, &block),
            (600, 300, &|x, y| !block(x, y)),
            (70_000, 2, &|x, y| y == 0 && x < 65_536),
            (600, 300, &|x, y| (x * 7 + y * 13) % 11 == 0),
        ];
        for (case, (w, h, opaque_at)) in cases.iter().enumerate() {
            let texels: Vec<u8> = (0..w * h)
                .map(|i| u8::from(opaque_at(i % w, i / w)) * 255)
                .collect();
            let texture = Unorm8Texture::new(*w, *h, &texels).unwrap();
            let classes =
                TexelClasses::new(&texture, Sampler::default(), Cutoff::default()).unwrap();
            let mut rectangles = vec![(0, w - 1, 0, h - 1), (0, 255, 0, 255), (0, 256, 0, 255)];
            for _ in 0..40 {
                let mut pick = |n: u32| {
                    let (a, b) = (rng.next_u64() as u32 % n, rng.next_u64() as u32 % n);
                    (a.min(b), a.max(b))
                };
                let ((x0, x1), (y0, y1)) = (pick(*w), pick(*h));
                rectangles.push((x0, x1, y0, y1));
            }
            for (x0, x1, y0, y1) in rectangles {
                let (x1, y1) = (x1.min(w - 1), y1.min(h - 1));
                let mut count = 0u64;
                for y in y0..=y1 {
                    for x in x0..=x1 {
                        count += u64::from(opaque_at(x, y));
                    }
                }
                let area = u64::from(x1 - x0 + 1) * u64::from(y1 - y0 + 1);
                let at = format!("case {case}: [{x0}, {x1}] x [{y0}, {y1}]");
                assert_eq!(classes.opaque_count((x0, x1), (y0, y1)), count, "{at}");
                let expected = Classes {
                    opaque: count > 0,
                    transparent: count < area,
                };
                let got = classes.rectangle_classes((x0, x1), (y0, y1));
                assert_eq!(got, expected, "{at}: {count} of {area}");
            }
        }
    }

    /// Every address mode's image of every short range equals the set of
    /// wrapped values, computed one coordinate at a time.
    #[test]
    fn axis_images_match_wrapping_each_coordinate() {
        for size in 1..=5u32 {
            for mode in AddressMode::ALL {
                for lo in -13i128..13 {
                    for hi in lo..lo + 13 {
                        let image = axis_image(mode, lo, hi, size);
                        let mut expected = [false; 5];
                        let mut border = false;
                        for i in lo..=hi {
                            match mode.wrap(i as i64, size) {
                                Some(t) => expected[t as usize] = true,
                                None => border = true,
                            }
                        }
                        let mut got = [false; 5];
                        for &(a, b) in &image.ranges[..image.count] {
                            assert!(a <= b && b < size, "{mode:?} {lo}..={hi} size {size}");
                            for t in a..=b {
                                got[t as usize] = true;
                            }
                        }
                        assert_eq!(got, expected, "{mode:?} {lo}..={hi} size {size}");
                        assert_eq!(image.border, border, "{mode:?} {lo}..={hi} size {size}");
                    }
                }
            }
        }
    }

    /// A texture whose rows are not `width` bytes (a broken
    /// `extend_opaque_row`) is refused, never tabled; bytes other than 0
    /// and 1 count as opaque in both the counts and the texel reads.
    #[test]
    fn rows_of_the_wrong_length_are_refused_and_any_nonzero_byte_is_opaque() {
        struct Rows(usize, u8);
        impl AlphaTexture for Rows {
            fn width(&self) -> u32 {
                3
            }
            fn height(&self) -> u32 {
                2
            }
            fn alpha(&self, _: u32, _: u32) -> f64 {
                0.0
            }
            fn extend_opaque_row(&self, _: u32, _: &Cutoff, out: &mut Vec<u8>) {
                out.extend(core::iter::repeat(self.1).take(self.0));
            }
        }
        let (sampler, cutoff) = (Sampler::default(), Cutoff::default());
        for len in [0, 2, 4] {
            assert_eq!(
                TexelClasses::new(&Rows(len, 1), sampler, cutoff).unwrap_err(),
                TextureError::WrongLength {
                    expected: 3,
                    got: len
                }
            );
        }
        for byte in [1, 2, 255] {
            let classes = TexelClasses::new(&Rows(3, byte), sampler, cutoff).unwrap();
            assert_eq!(classes.opaque_count((0, 2), (0, 1)), 6, "byte {byte}");
            assert!(classes.class_of(Some((2, 1))), "byte {byte}");
        }
        let classes = TexelClasses::new(&Rows(3, 0), sampler, cutoff).unwrap();
        assert_eq!(classes.opaque_count((0, 2), (0, 1)), 0);
        assert!(!classes.class_of(Some((0, 0))));
    }
}
