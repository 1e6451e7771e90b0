//! The texel tables: every texel classified once under the alpha test
//! (one byte each: may it pass, may it fail), with prefix sums that count
//! a rectangle's texels of each kind in four reads, and under linear
//! filtering by value the texels' binary32 values; the classes of a block
//! of texel coordinates after wrapping.

use super::classes::{texel_in_range, Block, Classes};
use super::wrap::axis_image;
use crate::bake::alpha_test::AlphaTest;
use crate::bake::parallel::Runner;
use crate::bake::texture::{AlphaTexture, Sampler, TextureError};
use crate::num::wide::GridInt;
use alloc::vec::Vec;

/// Every texel classified once, with prefix sums to count a rectangle's
/// texels of each class in four reads.
#[derive(Clone, Debug)]
pub(crate) struct TexelClasses {
    pub(crate) width: u32,
    pub(crate) height: u32,
    /// `prefix[y * (width + 1) + x]`: texels that may pass (class bit 0)
    /// in `[0, x) x [0, y)`, modulo `2^16`. Four reads count a rectangle of
    /// fewer than `2^16` texels exactly (the true count fits); half the
    /// bytes of `u32` sums make the tables quicker to build and to read. A
    /// larger rectangle is counted exactly only when its classes depend on
    /// it (see [`TexelClasses::rectangle_classes`]).
    prefix: Vec<u16>,
    /// The same for the texels that may fail (bit 1), when some texel may
    /// do both (its binary32 values straddle the cutoff); otherwise a texel
    /// may fail exactly when it may not pass, and `prefix` tells both.
    prefix_fail: Option<Vec<u16>>,
    /// One byte per texel (row-major): bit 0, it may pass; bit 1, it may
    /// fail ([`AlphaTest::class_bits`]).
    bits: Vec<u8>,
    /// Under linear filtering by value, each texel's highest binary32
    /// value ([`AlphaTexture::gpu_alpha`]), row-major; its lowest is at
    /// most [`spread`](Self::spread) below.
    pub(crate) values: Option<Vec<f32>>,
    /// The largest difference between a texel's (or the border's) highest
    /// and lowest binary32 value: a binary32 ulp or two for unorm texels,
    /// 0 for `f32` ones.
    pub(crate) spread: f64,
    pub(crate) sampler: Sampler,
    pub(crate) test: AlphaTest,
    border_bits: u8,
    /// The border's highest value (clamp to border).
    pub(crate) border_value: f32,
}

/// Texels per segment of [`add_row_counts`].
const SEGMENT: usize = 1024;

/// [`add_row_counts`]'s two buffers, each 8 zeros (the texels before a
/// segment) and a segment; made once per table, not once per row.
struct RowScratch([[u16; 8 + SEGMENT]; 2]);

/// Adds to `sums[x]` the texels of `row[..=x]` with class bit `bit` set,
/// modulo `2^16` (the prefix sums' arithmetic).
///
/// A running sum texel by texel is a chain of dependent adds (most of
/// the tables' build); here every pass is element-wise, which the
/// compiler turns into SIMD: per segment, sums of 8-texel windows (three
/// shifted adds), then 8 running sums, one per position modulo 8 (the
/// windows ending at `x, x - 8, ...` tile `row[..=x]`), plus the counts
/// of the segments before.
fn add_row_counts(row: &[u8], bit: u8, sums: &mut [u16], scratch: &mut RowScratch) {
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
            *t = u16::from((texel >> bit) & 1);
        }
        // (After a short last segment, `a` holds older texels: the sums
        // look only back, so they never reach the segment's.)
        shifted_add(b, a, 1);
        shifted_add(a, b, 2);
        shifted_add(b, a, 4);
        // b[8 + x]: texels with the bit in row[x - 7..=x].
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

/// The prefix sums of class bit `bit` over a band of rows (`classes`, rows
/// of `stride - 1` class bytes) into `sums` (as many rows of `stride`,
/// zero on entry), counted from the band's first row: each row is the one
/// above plus its own counts ([`add_row_counts`]).
fn band_prefix_sums(classes: &[u8], bit: u8, sums: &mut [u16], stride: usize) {
    let mut scratch = RowScratch([[0; 8 + SEGMENT]; 2]);
    for (y, row) in classes.chunks(stride - 1).enumerate() {
        let (above, rest) = sums.split_at_mut(y * stride);
        let out = &mut rest[..stride];
        if y > 0 {
            out.copy_from_slice(&above[(y - 1) * stride..]);
        }
        add_row_counts(row, bit, &mut out[1..], &mut scratch);
    }
}

/// The prefix sums of class bit `bit` of `classes` (`width x height`),
/// allocated fallibly (`failed` otherwise), by bands of rows on `runner`'s
/// threads: every band from a row of zeros, then the sums of the bands
/// above added to it (one band when serial: the rows in one pass, no
/// correction).
fn prefix_sums(
    classes: &[u8],
    bit: u8,
    (width, height): (u32, u32),
    runner: &Runner,
    failed: &TextureError,
) -> Result<Vec<u16>, TextureError> {
    let stride = width as usize + 1;
    let sums_len = usize::try_from((u64::from(width) + 1) * (u64::from(height) + 1))
        .map_err(|_| failed.clone())?;
    let mut prefix: Vec<u16> = Vec::new();
    prefix
        .try_reserve_exact(sums_len)
        .map_err(|_| failed.clone())?;
    prefix.resize(sums_len, 0);
    let rows = height as usize;
    let bands = if runner.threads() > 1 {
        (2 * runner.threads()).min(rows)
    } else {
        1
    };
    let band_rows = rows.div_ceil(bands);
    let mut parts: Vec<(&[u8], &mut [u16])> = classes
        .chunks(band_rows * (stride - 1))
        .zip(prefix[stride..].chunks_mut(band_rows * stride))
        .collect();
    runner.for_each_mut(&mut parts, |(classes, sums)| {
        band_prefix_sums(classes, bit, sums, stride);
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
    Ok(prefix)
}

impl TexelClasses {
    #[cfg(test)]
    pub(crate) fn new(
        texture: &(impl AlphaTexture + ?Sized),
        sampler: Sampler,
        test: AlphaTest,
    ) -> Result<TexelClasses, TextureError> {
        Self::new_within(texture, sampler, test, u64::MAX, &Runner::serial())
    }

    /// The bytes the tables of a `width x height` texture take: `w h` class
    /// bytes and `2 (w + 1) (h + 1)` bytes of prefix sums, and for linear
    /// filtering by value 4 bytes of values per texel (saturated). Where
    /// some texel may both pass and fail, a second table of prefix sums
    /// follows, within the same limit.
    pub(crate) fn table_bytes(width: u32, height: u32, values: bool) -> u64 {
        let (w, h) = (u64::from(width), u64::from(height));
        let per_texel = if values { 5 } else { 1 };
        (w * h)
            .saturating_mul(per_texel)
            .saturating_add((w + 1) * (h + 1) * 2)
    }

    /// The tables, allocated fallibly (`try_reserve_exact`) and only if
    /// they fit `max_bytes`.
    pub(crate) fn new_within(
        texture: &(impl AlphaTexture + ?Sized),
        sampler: Sampler,
        test: AlphaTest,
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
        let keep_values = test.by_value;
        let bytes = Self::table_bytes(width, height, keep_values);
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
        let Ok(texels) = usize::try_from(u64::from(width) * u64::from(height)) else {
            return Err(failed);
        };
        let reserve = |len: usize| -> Result<Vec<f32>, TextureError> {
            let mut v = Vec::new();
            v.try_reserve_exact(len).map_err(|_| failed.clone())?;
            Ok(v)
        };
        // The class bytes are appended row by row from the row's values (one
        // call per row, so a `dyn` texture costs one dynamic call a row, not
        // a texel), never zero-filled first; the values are kept, or a row's
        // worth reused.
        let mut bits: Vec<u8> = Vec::new();
        bits.try_reserve_exact(texels).map_err(|_| failed.clone())?;
        let (mut low, mut high) = (reserve(width as usize)?, reserve(width as usize)?);
        let mut values = if keep_values {
            Some(reserve(texels)?)
        } else {
            None
        };
        let mut both = false;
        let mut spread = 0f64;
        // The last texel's values (their bits) and classes.
        let mut last: Option<((u32, u32), u8)> = None;
        for y in 0..height {
            low.clear();
            high.clear();
            texture.extend_gpu_alpha_row(y, &mut low, &mut high);
            // A texture whose row is not `width` values breaks its
            // contract; refuse it rather than build tables that lie.
            if low.len() != width as usize || high.len() != low.len() {
                return Err(TextureError::WrongLength {
                    expected: u64::from(width),
                    got: low.len().max(high.len()),
                });
            }
            // Texels come in runs of equal values (most alpha textures are
            // mostly 0 and 1): a texel equal to the one before takes its
            // classes without the test.
            bits.extend(low.iter().zip(&high).map(|(&lo, &hi)| {
                let key = (lo.to_bits(), hi.to_bits());
                match last {
                    Some((at, b)) if at == key => b,
                    _ => {
                        let b = test.class_bits(lo, hi);
                        both |= b == 3;
                        last = Some((key, b));
                        b
                    }
                }
            }));
            if let Some(values) = &mut values {
                // NaN stays NaN in the values; its spread is nothing
                // (`max` takes the other operand).
                spread = low
                    .iter()
                    .zip(&high)
                    .map(|(&lo, &hi)| f64::from(hi) - f64::from(lo))
                    .fold(spread, f64::max);
                values.extend_from_slice(&high);
            }
        }
        let prefix = prefix_sums(&bits, 0, (width, height), runner, &failed)?;
        let prefix_fail = if both {
            let failed = TextureError::AllocationFailed {
                bytes: bytes.saturating_add(((u64::from(width) + 1) * (u64::from(height) + 1)) * 2),
                limit: max_bytes,
            };
            if let TextureError::AllocationFailed { bytes, .. } = failed {
                if bytes > max_bytes {
                    return Err(failed);
                }
            }
            Some(prefix_sums(&bits, 1, (width, height), runner, &failed)?)
        } else {
            None
        };
        let border = crate::bake::texture::faithful_f32(f64::from(sampler.border_alpha));
        spread = spread.max(f64::from(border.1) - f64::from(border.0));
        Ok(TexelClasses {
            width,
            height,
            prefix,
            prefix_fail,
            bits,
            values,
            spread,
            sampler,
            test,
            border_bits: test.class_bits(border.0, border.1),
            border_value: border.1,
        })
    }

    /// Texels of `prefix` (one class bit's sums) in `[x0, x1] x [y0, y1]`
    /// (inclusive, in range), modulo `2^16`: the count itself when the
    /// rectangle has fewer than `2^16` texels.
    #[inline]
    fn count_mod(&self, prefix: &[u16], (x0, x1): (u32, u32), (y0, y1): (u32, u32)) -> u16 {
        let stride = self.width as usize + 1;
        let at = |x: u32, y: u32| prefix[y as usize * stride + x as usize];
        at(x1 + 1, y1 + 1)
            .wrapping_add(at(x0, y0))
            .wrapping_sub(at(x0, y1 + 1))
            .wrapping_sub(at(x1 + 1, y0))
    }

    /// Texels of `prefix` in `[x0, x1] x [y0, y1]` (inclusive, in range),
    /// exactly: the sum over tiles of fewer than `2^16` texels each.
    fn count(&self, prefix: &[u16], (x0, x1): (u32, u32), (y0, y1): (u32, u32)) -> u64 {
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
                count += u64::from(self.count_mod(prefix, (x, x_end), (y, y_end)));
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

    /// Whether `prefix` counts any texel in the rectangle (`all`: every
    /// one) of `area` texels: from the residue alone below `2^16` texels,
    /// or where the residue already proves it; else counted exactly.
    #[inline]
    fn counts(&self, prefix: &[u16], xr: (u32, u32), yr: (u32, u32), area: u64) -> (bool, bool) {
        let residue = self.count_mod(prefix, xr, yr);
        let count = if area < 1 << 16 {
            u64::from(residue)
        } else if residue != 0 && residue != area as u16 {
            // A larger rectangle: a residue other than 0 (other than the
            // area's) proves some texel with the bit (some without).
            return (true, false);
        } else {
            self.count(prefix, xr, yr)
        };
        (count > 0, count == area)
    }

    /// The classes of the texels in `[x0, x1] x [y0, y1]` (inclusive, in
    /// range), from their counts.
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
            let bits =
                self.bits[top] | self.bits[top + dx] | self.bits[bottom] | self.bits[bottom + dx];
            return Classes::of_bits(bits);
        }
        let area = u64::from(xr.1 - xr.0 + 1) * u64::from(yr.1 - yr.0 + 1);
        let (any_pass, all_pass) = self.counts(&self.prefix, xr, yr, area);
        let transparent = match &self.prefix_fail {
            None => !all_pass,
            Some(fail) => self.counts(fail, xr, yr, area).0,
        };
        Classes {
            opaque: any_pass,
            transparent,
        }
    }

    /// The classes of a texel, or of the border (`None`).
    pub(crate) fn class_of(&self, texel: Option<(u32, u32)>) -> Classes {
        Classes::of_bits(match texel {
            Some((x, y)) => self.bits[y as usize * self.width as usize + x as usize],
            None => self.border_bits,
        })
    }

    /// The highest binary32 value of a texel, or of the border (`None`);
    /// under linear filtering by value only.
    #[inline]
    pub(crate) fn value_of(&self, texel: Option<(u32, u32)>) -> f32 {
        match (texel, &self.values) {
            (Some((x, y)), Some(values)) => values[y as usize * self.width as usize + x as usize],
            _ => self.border_value,
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
    pub(super) fn block_classes<C: GridInt>(&self, block: Block<C>) -> Classes {
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
            classes = self.class_of(None);
        }
        for &xr in &xs.ranges[..xs.count] {
            for &yr in &ys.ranges[..ys.count] {
                classes = classes.union(self.rectangle_classes(xr, yr));
            }
        }
        classes
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bake::texture::Cutoff;
    use crate::bake::texture_unit::TextureUnit;
    use crate::bake::Unorm8Texture;

    /// The default alpha test for `sampler`.
    fn test(sampler: Sampler) -> AlphaTest {
        AlphaTest::new(
            Cutoff::default(),
            sampler.filter,
            &TextureUnit::default(),
            1.0,
        )
    }

    impl TexelClasses {
        /// Texels that may pass in the rectangle, exactly.
        fn pass_count(&self, xr: (u32, u32), yr: (u32, u32)) -> u64 {
            self.count(&self.prefix, xr, yr)
        }
    }
    use micromap_index_test_support::SplitMix64;

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
                TexelClasses::new(&texture, Sampler::default(), test(Sampler::default())).unwrap();
            for x0 in 0..w {
                for y0 in 0..h {
                    for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                        let (x1, y1) = (x0 + dx, y0 + dy);
                        if x1 >= w || y1 >= h {
                            continue;
                        }
                        let area = u64::from((dx + 1) * (dy + 1));
                        let opaque = classes.pass_count((x0, x1), (y0, y1));
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
            let sampler = Sampler::default();
            let serial = TexelClasses::new(&texture, sampler, test(sampler)).unwrap();
            for threads in [2, 3, 8] {
                let runner = Runner::new(Threads::Exactly(threads));
                let banded =
                    TexelClasses::new_within(&texture, sampler, test(sampler), u64::MAX, &runner)
                        .unwrap();
                assert_eq!(banded.prefix, serial.prefix, "{w}x{h}, {threads} threads");
                assert_eq!(banded.bits, serial.bits, "{w}x{h}, {threads} threads");
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
                for bit in [0, 1] {
                    let mut expected = start.clone();
                    let mut run = 0u16;
                    for (sum, &texel) in expected.iter_mut().zip(&row) {
                        run = run.wrapping_add(u16::from((texel >> bit) & 1));
                        *sum = sum.wrapping_add(run);
                    }
                    let mut sums = start.clone();
                    add_row_counts(&row, bit, &mut sums, &mut scratch);
                    assert_eq!(sums, expected, "length {len}, round {round}, bit {bit}");
                }
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
                TexelClasses::new(&texture, Sampler::default(), test(Sampler::default())).unwrap();
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
                assert_eq!(classes.pass_count((x0, x1), (y0, y1)), count, "{at}");
                let expected = Classes {
                    opaque: count > 0,
                    transparent: count < area,
                };
                let got = classes.rectangle_classes((x0, x1), (y0, y1));
                assert_eq!(got, expected, "{at}: {count} of {area}");
            }
        }
    }

    /// A texture whose rows are not `width` values (a broken
    /// `extend_gpu_alpha_row`) is refused, never tabled; values that pass
    /// count in the prefix sums and the texel reads.
    #[test]
    fn rows_of_the_wrong_length_are_refused() {
        struct Rows(usize, f32);
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
            fn extend_gpu_alpha_row(&self, _: u32, low: &mut Vec<f32>, high: &mut Vec<f32>) {
                low.extend(core::iter::repeat(self.1).take(self.0));
                high.extend(core::iter::repeat(self.1).take(self.0));
            }
        }
        let sampler = Sampler::default();
        for len in [0, 2, 4] {
            assert_eq!(
                TexelClasses::new(&Rows(len, 1.0), sampler, test(sampler)).unwrap_err(),
                TextureError::WrongLength {
                    expected: 3,
                    got: len
                }
            );
        }
        for value in [0.5f32, 1.0, 7.0] {
            let classes = TexelClasses::new(&Rows(3, value), sampler, test(sampler)).unwrap();
            assert_eq!(classes.pass_count((0, 2), (0, 1)), 6, "value {value}");
            assert_eq!(classes.class_of(Some((2, 1))), Classes::of_bits(1));
        }
        let classes = TexelClasses::new(&Rows(3, 0.0), sampler, test(sampler)).unwrap();
        assert_eq!(classes.pass_count((0, 2), (0, 1)), 0);
        assert_eq!(classes.class_of(Some((0, 0))), Classes::of_bits(2));
    }

    /// Texels whose binary32 values straddle the cutoff (51 at `0.2`) may
    /// pass and fail: a block holding one reads both classes, through the
    /// second table of prefix sums, on blocks of every size.
    #[test]
    fn straddling_texels_read_both_classes() {
        let (w, h) = (300u32, 260u32);
        let texels: Vec<u8> = (0..w * h)
            .map(|i| {
                if i == 5 * w + 7 {
                    51
                } else if i % 2 == 0 {
                    255
                } else {
                    0
                }
            })
            .collect();
        let texture = Unorm8Texture::new(w, h, &texels).unwrap();
        let sampler = Sampler::default();
        let cutoff = Cutoff::new(0.2, crate::bake::Comparison::AtLeast).unwrap();
        let test = AlphaTest::new(cutoff, sampler.filter, &TextureUnit::default(), 1.0);
        let classes = TexelClasses::new(&texture, sampler, test).unwrap();
        assert!(classes.prefix_fail.is_some());
        assert_eq!(classes.class_of(Some((7, 5))), Classes::BOTH);
        assert_eq!(classes.rectangle_classes((7, 7), (5, 5)), Classes::BOTH);
        assert_eq!(classes.rectangle_classes((7, 8), (5, 6)), Classes::BOTH);
        // An even row of opaque texels only, and one that holds 51.
        assert_eq!(
            classes.rectangle_classes((8, 8), (5, 5)),
            Classes::of_bits(1)
        );
        assert_eq!(classes.rectangle_classes((0, 299), (0, 259)), Classes::BOTH);
        let only_opaque = |x: u32| Classes::of_bits(if x % 2 == 0 { 1 } else { 2 });
        assert_eq!(classes.rectangle_classes((10, 10), (0, 0)), only_opaque(10));
    }
}
