//! The reference's steps rewritten without branches on the bits of the
//! floats, in safe code, in two shapes:
//!
//! * **Point by point** ([`narrow`], [`wide`]): one lane at a time, written
//!   so that a loop over slices vectorises; `spec::index_f32`,
//!   `batch::index_f32_one`, the exact entry points of `uv2index` and the
//!   batch loops' short tails run it.
//! * **In chunks** ([`chunked`], the batch loops, in two forms: [`Narrow`]
//!   for levels `0..=16`, [`Wide`] for `0..=32`): [`CHUNK`] points go
//!   through three stages, each its own loop. The narrow first half
//!   (float) and both interleaves come from a [`Lanes`]: the safe
//!   `PortableLanes` here, or [`super::arch`]'s SSE2, AVX2 and AVX-512
//!   ones with intrinsics. The wide first half ([`wide_cells`]) and the
//!   integer half ([`integer_half_u16`], [`integer_half_u32`]) are safe
//!   code for every backend; the narrow one runs in 16-bit words, since
//!   every value is below `2^16` at its levels, so a vector holds twice as
//!   many points as in 32-bit words.
//!
//! Everything here is `#[inline(always)]` so that each caller gets its own
//! copy under its own target features.
//!
//! # The first half in floats
//!
//! [`narrow`] takes the cell and fraction as `CELL` says. The vector
//! backends use the reference's own binary32 steps (a truncating
//! conversion in [`super::arch`], [`coordinate_float`]'s `2^23` rounding
//! trick in safe code), after a float clamp that flushes subnormals and
//! stops below 1 ([`clamp_flushed`] says why neither changes the index),
//! and decide `uf + vf >= 1.0f` as the reference does: fewer operations
//! than the shifts below, which serve the wide form (levels above 16) and
//! `batch::index_f32_one`.
//!
//! # The first half on the bits
//!
//! The Vulkan reference clamps `x` to `[0, 1]`, multiplies by `2^level`,
//! truncates to the cell and keeps the fraction; every one of those binary32
//! operations is exact. Only `uf + vf >= 1.0f` rounds: binary32
//! round-to-nearest-even lifts every real sum in `[1 - 2^-25, 1)` to `1.0`
//! and no smaller one, so the test is `uf + vf >= 1 - 2^-25` over the reals
//! (`docs/fixed.md`).
//!
//! * **Clamp.** As an unsigned integer, every NaN and every negative value
//!   (sign bit set) is above the bits of `+inf`, `0x7f80_0000`: they become
//!   `+0`. Everything else is `min(bits, bits of 1.0)` (bits of non-negative
//!   floats order like the floats; `+inf` becomes 1).
//! * **Cell and fraction.** The clamped `x` is `m * 2^(e - 150)` with `m`
//!   the 24-bit significand (hidden bit included) and `e = max(biased
//!   exponent, 1)`. With `P` fraction bits, `floor(x * 2^(level + P)) =
//!   floor(m * 2^(P - s))`, `s = 150 - level - e`: the cell is its integer
//!   part and the fraction its low `P` bits, floored.
//! * **Diagonal.** With `P = 31` the fractions are `Fu = floor(uf * 2^31)`,
//!   `Fv` likewise, and the test is `Fu + Fv >= T` with `T = 2^31 - 2^6`
//!   (`(1 - 2^-25) * 2^31`; the `exact` variants use `T = 2^31`, the real
//!   `uf + vf >= 1`). Flooring keeps it exact: a fraction loses bits only if
//!   its lowest bit is below `2^-31`, and then, having at most 24 significant
//!   bits, it is below `2^-7`. If both lose bits the sum is below `2^-6`, far
//!   from `T`. If one does, the other is exact, so `Fu + Fv` is the integer
//!   part of the real `(uf + vf) * 2^31`, and an integer threshold `T` is
//!   reached by a real number exactly when it is reached by its integer part.
//!
//! # The integer half
//!
//! From the cell `(iu, iv)` clamped to `last = 2^level - 1` and the diagonal
//! outcome, the reference folds a cell past the hypotenuse back
//! (`iu -= iu + iv - last`, i.e. `iu = min(iu, last - iv)`), subtracts one
//! from `iw = ~(iu + iv)` on the diagonal when `iu + iv < last` (so
//! `~iw = iu + iv + d` with `d` that outcome), and then
//! `b0 = ~(iu ^ iw) & last = (iu ^ (iu + iv + d)) & last`. Nothing exceeds
//! `last`, so 32-bit words hold every level `0..=32`. The prefix XOR and the
//! bit interleave are the reference's; the interleave of `b0` and `b1` is one
//! perfect shuffle of the word holding both (Hacker's Delight, 7-2).

/// Bits of `1.0f32`.
const ONE_BITS: u32 = 0x3f80_0000;
/// Bits of `+inf`: everything above (as an unsigned integer) is NaN or negative.
const INF_BITS: u32 = 0x7f80_0000;
/// Fraction bits kept of `uf` and `vf`.
pub(crate) const FRACTION_BITS: u32 = 31;
/// `uf + vf >= 1.0f` in binary32: the real sum at least `1 - 2^-25`.
pub(crate) const BINARY32_THRESHOLD: u32 = (1 << FRACTION_BITS) - (1 << (FRACTION_BITS - 25));
/// `uf + vf >= 1` over the reals.
pub(crate) const EXACT_THRESHOLD: u32 = 1 << FRACTION_BITS;

/// What the per-element kernels need of the level, computed once per call.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Params {
    /// `2^level - 1` (for level 32 all ones).
    pub last: u32,
    /// `150 - level`: `s = shift_base - e`.
    pub shift_base: u32,
    /// `2^level` as a float (levels `0..=16` only).
    pub scale: f32,
    /// The diagonal threshold on `Fu + Fv`.
    pub threshold: u32,
}

impl Params {
    /// The parameters of `level` (`0..=32`, clamped there) and a threshold.
    #[inline(always)]
    pub const fn new(level: u32, threshold: u32) -> Params {
        let level = if level > 32 { 32 } else { level };
        Params {
            last: ((1u64 << level) - 1) as u32,
            shift_base: 150 - level,
            scale: (1u64 << level) as f32,
            threshold,
        }
    }
}

/// The clamped binary32 bits of `x` (as bits): NaN and negatives -> `+0`,
/// `>= 1` (and `+inf`) -> `1.0`.
#[inline(always)]
fn clamp_bits(bits: u32) -> u32 {
    let clamped = if bits < ONE_BITS { bits } else { ONE_BITS };
    if bits > INF_BITS {
        0
    } else {
        clamped
    }
}

/// The significand `m` (24 bits, hidden bit included) and the shift `s`
/// with `x * 2^level = m * 2^-s`, for clamped bits.
#[inline(always)]
fn significand_and_shift(clamped: u32, params: &Params) -> (u32, u32) {
    let biased = clamped >> 23;
    let hidden = if biased == 0 { 0 } else { 1 << 23 };
    let m = (clamped & 0x7f_ffff) | hidden;
    let e = if biased == 0 { 1 } else { biased };
    // e <= 127 and level <= 32: s >= 150 - 32 - 127 = -9, wraps below 0.
    (m, params.shift_base.wrapping_sub(e))
}

/// `x >> n`, or 0 when `n >= 32` (what AVX2's `vpsrlvd` computes).
#[inline(always)]
fn shr_or_zero(x: u32, n: u32) -> u32 {
    if n < 32 {
        x >> n
    } else {
        0
    }
}

/// `x << n`, or 0 when `n >= 32` (what AVX2's `vpsllvd` computes).
#[inline(always)]
fn shl_or_zero(x: u32, n: u32) -> u32 {
    if n < 32 {
        x << n
    } else {
        0
    }
}

/// Cell clamped to `last` and `floor(fraction * 2^31)` of one coordinate,
/// in 32-bit words, every level `0..=32`.
///
/// `s >= 150 - 32 - 127 = -9`. For `s >= 0` the cell is `m >> s`; for
/// `s < 0` (levels above 23 only) it is `m << -s`. Only `x = 1` has a cell
/// beyond `last` (`2^level`, which wraps to 0 at level 32), so `x = 1` takes
/// `last` directly; its fraction then no longer matters, since `iu = last`
/// rules the diagonal out. The fraction `floor(m * 2^(31 - s)) mod 2^31` is `m << (31 - s)`
/// with the bits above 31 dropped when `s <= 31` (0 when `s <= 0`), else
/// `m >> (s - 31)`. Each shift that does not apply has a count `>= 32` as
/// an unsigned number and gives 0.
#[inline(always)]
fn coordinate<const WIDE: bool>(bits: u32, params: &Params) -> (u32, u32) {
    let clamped = clamp_bits(bits);
    let (m, s) = significand_and_shift(clamped, params);
    let mut cell = shr_or_zero(m, s);
    if WIDE {
        cell |= shl_or_zero(m, 0u32.wrapping_sub(s));
    }
    let cell = if clamped == ONE_BITS {
        params.last
    } else {
        cell
    };
    let low = shl_or_zero(m, 31u32.wrapping_sub(s)) & 0x7fff_ffff;
    let high = shr_or_zero(m, s.wrapping_sub(31));
    (cell, low | high)
}

/// [`coordinate`] for bits already in `[0, 1]` (`bits <= ONE_BITS`: no
/// clamp) at levels `0..=16`, in one 64-bit shift instead of three 32-bit
/// ones, for scalar callers: `floor(x * 2^(level + 31)) = (m << 31) >> s`
/// (`m < 2^24`, and `s >= 150 - 16 - 127 = 7`, so nothing shifts left) holds
/// the cell above its low 31 bits and the fraction in them. Only `x = 1`
/// has a cell beyond `last` (`2^level`, fraction 0), clamped back.
#[inline(always)]
pub(crate) fn unit_coordinate(bits: u32, params: &Params) -> (u32, u32) {
    let biased = bits >> 23;
    let hidden = if biased == 0 { 0 } else { 1 << 23 };
    let m = u64::from((bits & 0x7f_ffff) | hidden);
    let s = params.shift_base - biased.max(1);
    let scaled = (m << FRACTION_BITS).checked_shr(s).unwrap_or(0);
    let cell = ((scaled >> FRACTION_BITS) as u32).min(params.last);
    (cell, scaled as u32 & 0x7fff_ffff)
}

/// The reference's clamp to `[0, 1]` on floats, with two changes that
/// leave its index alone:
///
/// * Everything below the smallest normal, `2^-126`, becomes `2^-126`:
///   subnormals, zeros, negatives and NaN (which compares false), in one
///   `max` whose NaN operand is the first (x86's `maxps` then returns the
///   second). This keeps the float steps after it off the slow paths CPUs
///   take on subnormals. Every such value has cell 0 and a fraction below
///   `2^-110` at level 16 (the reference's is 0 or a subnormal's
///   `2^level` multiple, below `2^-110` too), and a fraction that small
///   cannot move `uf + vf` across `1 - 2^-25`: the other fraction is at
///   most `1 - 2^-24`, so the real sum stays below `1 - 2^-25` and the
///   binary32 sum below 1 either way.
/// * Everything from 1 up (`+inf` too) becomes `1 - 2^-24`, the float below
///   1, whose cell is `last` at every level `0..=16`: the cell the
///   reference clamps `x = 1` to, so no cell needs clamping afterwards. Its
///   fraction differs from `x = 1`'s 0 but is never read: a cell of `last`
///   makes `iu + iv < last` false, which rules the diagonal step out.
#[inline(always)]
fn clamp_flushed(bits: u32) -> f32 {
    let x = f32::from_bits(bits);
    let x = if x > f32::MIN_POSITIVE {
        x
    } else {
        f32::MIN_POSITIVE
    };
    if x < BELOW_ONE {
        x
    } else {
        BELOW_ONE
    }
}

/// `1 - 2^-24`, the float below 1: where [`clamp_flushed`] stops.
pub(crate) const BELOW_ONE: f32 = 1.0 - f32::EPSILON / 2.0;

/// `2^23`: adding it to a float in `[0, 2^23)` leaves an integer in the low
/// bits of the sum's significand.
const MAGIC: f32 = 8_388_608.0;

/// Cell (at most `last`) and the exact binary32 fraction, by the
/// reference's own float operations (every one exact): `fu = x * 2^level`,
/// `iu = trunc(fu)`, `uf = fu - iu`. Levels `0..=16` (`fu <= 2^16`).
///
/// The truncation avoids a float-to-integer conversion, which baselines
/// without a vector form of it (SSE2) do one lane at a time: adding `2^23`
/// rounds `fu < 2^23` to an integer `r` in the low bits of the sum (exact),
/// and `r - 1` is taken when `r > fu`.
#[inline(always)]
fn coordinate_float(bits: u32, params: &Params) -> (u32, f32) {
    let fu = clamp_flushed(bits) * params.scale;
    let sum = fu + MAGIC;
    let rounded = sum - MAGIC;
    let above = rounded > fu;
    let truncated = rounded - if above { 1.0 } else { 0.0 };
    let cell = (sum.to_bits() & 0x7f_ffff) - u32::from(above);
    (cell, fu - truncated)
}

/// The reference's integer half from clamped cells (`iu, iv <= last`):
/// returns `(b0, b1)` before the interleave. `WIDE` adds the fifth
/// prefix-XOR step that levels above 16 need.
#[inline(always)]
fn integer_half<const WIDE: bool>(iu: u32, iv: u32, diagonal: bool, last: u32) -> (u32, u32) {
    let room = last - iv;
    // Below level 17 every value is under 2^16, so a signed compare (one
    // instruction in SSE2 and AVX2, which lack unsigned ones) is the same.
    let below_room = if WIDE {
        iu < room
    } else {
        (iu as i32) < (room as i32)
    };
    let d = u32::from(diagonal && below_room);
    let iu = if below_room { iu } else { room };
    let b0 = (iu ^ (iu + iv + d)) & last;
    let t = (iu ^ iv) & b0;
    let mut f = t;
    f ^= f >> 1;
    f ^= f >> 2;
    f ^= f >> 4;
    f ^= f >> 8;
    if WIDE {
        f ^= f >> 16;
    }
    let b1 = ((f ^ iu) & !b0) | t;
    (b0, b1)
}

/// `b0` to the even bits and `b1` to the odd bits, for 16-bit halves: the
/// outer perfect shuffle of `b1:b0`.
#[inline(always)]
fn interleave_16(b0: u32, b1: u32) -> u32 {
    let mut x = b0 | (b1 << 16);
    let t = (x ^ (x >> 8)) & 0x0000_ff00;
    x ^= t ^ (t << 8);
    shuffle_half_bytes(x)
}

/// The perfect shuffle of each 16-bit half of `x` on its own: the half's
/// low byte to its even bits, its high byte to its odd bits (the last three
/// steps of [`interleave_16`]).
#[inline(always)]
fn shuffle_half_bytes(x: u32) -> u32 {
    let mut x = x;
    let mut t;
    t = (x ^ (x >> 4)) & 0x00f0_00f0;
    x ^= t ^ (t << 4);
    t = (x ^ (x >> 2)) & 0x0c0c_0c0c;
    x ^= t ^ (t << 2);
    t = (x ^ (x >> 1)) & 0x2222_2222;
    x ^= t ^ (t << 1);
    x
}

/// How [`narrow`] takes the cell and fraction: the bits clamped, then
/// [`unit_coordinate`]'s one 64-bit shift (scalar callers).
pub(crate) const CELL_BY_SHIFTS: u8 = 0;
/// [`coordinate_float`]'s float steps (SSE2 has no per-lane shifts).
pub(crate) const CELL_BY_FLOAT: u8 = 1;

/// The reference in binary32 for one pair of bit patterns, levels `0..=16`:
/// the same bits as `spec::index_f32`, the cell and fraction taken as `CELL`
/// says.
#[inline(always)]
pub(crate) fn narrow<const CELL: u8>(u_bits: u32, v_bits: u32, params: &Params) -> u32 {
    if CELL == CELL_BY_FLOAT {
        narrow_by_floats(u_bits, v_bits, params, coordinate_float)
    } else {
        narrow_in_unit(clamp_bits(u_bits), clamp_bits(v_bits), params)
    }
}

/// [`narrow`] from a float first half: `coordinate` gives each cell (at
/// most `last`) and exact binary32 fraction, and the diagonal test is the
/// reference's own `uf + vf >= 1.0f`.
#[inline(always)]
fn narrow_by_floats(
    u_bits: u32,
    v_bits: u32,
    params: &Params,
    coordinate: impl Fn(u32, &Params) -> (u32, f32),
) -> u32 {
    let (iu, uf) = coordinate(u_bits, params);
    let (iv, vf) = coordinate(v_bits, params);
    narrow_from_clamped_cell(iu, iv, uf + vf >= 1.0, params.last)
}

/// [`narrow`] for bits already in `[0, 1]` (callers check `bits <=
/// ONE_BITS`), scalar: [`unit_coordinate`]'s one shift per coordinate.
#[inline(always)]
pub(crate) fn narrow_in_unit(u_bits: u32, v_bits: u32, params: &Params) -> u32 {
    let (iu, uf) = unit_coordinate(u_bits, params);
    let (iv, vf) = unit_coordinate(v_bits, params);
    narrow_from_clamped_cell(iu, iv, uf + vf >= params.threshold, params.last)
}

/// The integer half and interleave of levels `0..=16` from cells already
/// clamped to `last` (`iu, iv <= last`): [`wide_from_clamped_cell`]'s
/// value there.
#[inline(always)]
pub(crate) fn narrow_from_clamped_cell(iu: u32, iv: u32, diagonal: bool, last: u32) -> u32 {
    let (b0, b1) = integer_half::<false>(iu, iv, diagonal, last);
    interleave_16(b0, b1)
}

/// The reference widened to 64 bits for one pair of bit patterns, levels
/// `0..=32`: the same bits as `spec::wide_index_f32` (binary32 threshold) or
/// the exact reading of the reference (exact threshold).
#[inline(always)]
pub(crate) fn wide(u_bits: u32, v_bits: u32, params: &Params) -> u64 {
    let (iu, uf) = coordinate::<true>(u_bits, params);
    let (iv, vf) = coordinate::<true>(v_bits, params);
    wide_from_clamped_cell(iu, iv, uf + vf >= params.threshold, params.last)
}

/// The wide integer half and interleave (two 16-bit interleaves in 32-bit
/// words, then one widening) from cells already clamped to
/// `last` (`iu, iv <= last`): `spec::wide_index_from_cell` on such cells.
#[inline(always)]
pub(crate) fn wide_from_clamped_cell(iu: u32, iv: u32, diagonal: bool, last: u32) -> u64 {
    let (b0, b1) = integer_half::<true>(iu, iv, diagonal, last);
    interleave_32(b0, b1)
}

/// `b0` to the even bits and `b1` to the odd bits, for 32-bit halves: two
/// 16-bit interleaves.
#[inline(always)]
fn interleave_32(b0: u32, b1: u32) -> u64 {
    let low = interleave_16(b0 & 0xffff, b1 & 0xffff);
    let high = interleave_16(b0 >> 16, b1 >> 16);
    u64::from(low) | (u64::from(high) << 32)
}

/// Points per chunk of the chunked pipeline: enough that each stage's loop
/// keeps its vector registers busy and is not unrolled into straight-line
/// code (which the compiler vectorises worse), small enough that a chunk's
/// buffers (3 to 6 KiB) stay in L1.
pub(crate) const CHUNK: usize = 256;

/// The first half's output for one chunk: clamped cells (at most `last`)
/// and the diagonal outcome (0 or 1), in the order a backend's [`Lanes`]
/// chose (the integer half works point by point, so any order the
/// backend's interleave undoes is fine). `W` is `u16` for levels `0..=16`,
/// `u32` for the wide form.
pub(crate) struct Cells<W> {
    /// `min(trunc(u * 2^level), last)` per point.
    pub iu: [W; CHUNK],
    /// `min(trunc(v * 2^level), last)` per point.
    pub iv: [W; CHUNK],
    /// `uf + vf >= 1.0f` per point, as 0 or 1.
    pub diagonal: [W; CHUNK],
}

/// The integer half's output for one chunk: `b0` and `b1` before the
/// interleave, in the order of [`Cells`].
pub(crate) struct Halves<W> {
    /// `b0` per point.
    pub b0: [W; CHUNK],
    /// `b1` per point.
    pub b1: [W; CHUNK],
}

/// The stages of the chunked pipeline that differ between instruction
/// sets: the float first half of levels `0..=16` and the bit interleave of
/// both forms. The integer half between them ([`integer_half_u16`],
/// [`integer_half_u32`]) and the wide form's first half ([`wide_cells`],
/// which needs variable shifts) are this module's safe code for every
/// backend.
///
/// An implementation's [`Lanes::cells`] may store the points of a chunk in
/// any fixed order (packing instructions work within 128-bit lanes) as long
/// as its [`Lanes::interleave`] writes each point's index back to the
/// point's position; the wide form's cells are in order.
pub(crate) trait Lanes {
    /// The cells and diagonal outcomes of the chunk's points, levels
    /// `0..=16`.
    fn cells(&self, u: &[f32; CHUNK], v: &[f32; CHUNK], params: &Params, cells: &mut Cells<u16>);
    /// `out[i] = spread(b0) | spread(b1) << 1` for every point, 16-bit halves.
    fn interleave(&self, halves: &Halves<u16>, out: &mut [u32; CHUNK]);
    /// The same for 32-bit halves, points in order.
    fn wide_interleave(&self, halves: &Halves<u32>, out: &mut [u64; CHUNK]);
}

/// [`Lanes`] in safe code, points in order: the first half by
/// [`coordinate_float`] (no float-to-integer conversion, which baselines
/// without a vector form of it would do one lane at a time) and the
/// interleave of [`narrow`] and [`wide`]. The portable backend of targets
/// without [`super::arch`] (x86-64 has SSE2 in its baseline, whose
/// [`super::arch`] lanes it runs instead); tested on every target.
#[cfg(any(test, not(target_arch = "x86_64")))]
pub(crate) struct PortableLanes;

#[cfg(any(test, not(target_arch = "x86_64")))]
impl Lanes for PortableLanes {
    #[inline(always)]
    fn cells(&self, u: &[f32; CHUNK], v: &[f32; CHUNK], params: &Params, cells: &mut Cells<u16>) {
        for k in 0..CHUNK {
            let (iu, uf) = coordinate_float(u[k].to_bits(), params);
            let (iv, vf) = coordinate_float(v[k].to_bits(), params);
            // Cells are at most 2^16 - 1 (levels 0..=16, x < 1).
            cells.iu[k] = iu as u16;
            cells.iv[k] = iv as u16;
            cells.diagonal[k] = u16::from(uf + vf >= 1.0);
        }
    }

    #[inline(always)]
    fn interleave(&self, halves: &Halves<u16>, out: &mut [u32; CHUNK]) {
        for ((out, &b0), &b1) in out.iter_mut().zip(&halves.b0).zip(&halves.b1) {
            *out = interleave_16(u32::from(b0), u32::from(b1));
        }
    }

    #[inline(always)]
    fn wide_interleave(&self, halves: &Halves<u32>, out: &mut [u64; CHUNK]) {
        for ((out, &b0), &b1) in out.iter_mut().zip(&halves.b0).zip(&halves.b1) {
            *out = interleave_32(b0, b1);
        }
    }
}

/// The wide form's first half for one chunk, points in order: the cells
/// and 31-bit fractions by [`coordinate`]'s shifts (levels up to 32 have
/// cells up to `2^32 - 1`, beyond a signed float conversion) and the
/// diagonal test on the fractions, as [`wide`] does.
#[inline(always)]
pub(crate) fn wide_cells(
    u: &[f32; CHUNK],
    v: &[f32; CHUNK],
    params: &Params,
    cells: &mut Cells<u32>,
) {
    for k in 0..CHUNK {
        let (iu, uf) = coordinate::<true>(u[k].to_bits(), params);
        let (iv, vf) = coordinate::<true>(v[k].to_bits(), params);
        cells.iu[k] = iu;
        cells.iv[k] = iv;
        cells.diagonal[k] = u32::from(uf + vf >= params.threshold);
    }
}

/// Stamps the integer half of one chunk for one word width, from cells
/// `iu, iv <= last`:
///
/// * the fold is `iu = min(iu, last - iv)`;
/// * `~iw` is `s = min(iu + iv + d, last)` after the fold: when the sum is
///   below `last` the reference subtracts `d` from `iw`; when it is `last`
///   (on the hypotenuse, folded or not) it does not, and the `min` takes
///   `last` back (at level 0 too, where `last` is 0). The addition of `d`
///   saturates, so `last + 1` does not wrap at level 16 in 16-bit words or
///   at level 32 in 32-bit ones;
/// * `b0 = iu ^ s` (both at most `last`, so the reference's `& last` changes
///   nothing), then `t`, the prefix XOR and `b1` as the reference has them.
macro_rules! integer_half_chunk {
    ($(#[$doc:meta])* $name:ident, $word:ty, prefix_xor: [$($prefix:expr),*]) => {
        $(#[$doc])*
        #[inline(always)]
        pub(crate) fn $name(cells: &Cells<$word>, last: $word, halves: &mut Halves<$word>) {
            for k in 0..CHUNK {
                let (iu, iv, d) = (cells.iu[k], cells.iv[k], cells.diagonal[k]);
                let room = last - iv;
                let iu = iu.min(room);
                let s = (iu + iv).saturating_add(d).min(last);
                let b0 = iu ^ s;
                let t = (iu ^ iv) & b0;
                let mut f = t;
                $(f ^= f >> $prefix;)*
                halves.b0[k] = b0;
                halves.b1[k] = ((f ^ iu) & !b0) | t;
            }
        }
    };
}

integer_half_chunk!(
    /// The integer half of levels `0..=16` in 16-bit words: every value is
    /// at most `last <= 2^16 - 1`, so a vector holds twice as many points
    /// as in the 32-bit [`integer_half`].
    integer_half_u16,
    u16,
    prefix_xor: [1, 2, 4, 8]
);
integer_half_chunk!(
    /// The integer half of the wide form (levels `0..=32`) in 32-bit words.
    integer_half_u32,
    u32,
    prefix_xor: [1, 2, 4, 8, 16]
);

/// One form of the chunked pipeline: its word, its output and its stages.
pub(crate) trait Form {
    /// The integer half's word.
    type Word: Copy + Default;
    /// The index type.
    type Out: Copy + Default;
    /// The first half.
    fn cells<L: Lanes>(
        lanes: &L,
        chunk: (&[f32; CHUNK], &[f32; CHUNK]),
        params: &Params,
        cells: &mut Cells<Self::Word>,
    );
    /// The integer half.
    fn integer_half(cells: &Cells<Self::Word>, params: &Params, halves: &mut Halves<Self::Word>);
    /// The interleave.
    fn interleave<L: Lanes>(lanes: &L, halves: &Halves<Self::Word>, out: &mut [Self::Out; CHUNK]);
    /// One point by the point kernel (short tails).
    fn point(u_bits: u32, v_bits: u32, params: &Params) -> Self::Out;
}

/// Levels `0..=16`, 32-bit indices: [`narrow`]'s bits.
pub(crate) struct Narrow;

impl Form for Narrow {
    type Word = u16;
    type Out = u32;
    #[inline(always)]
    fn cells<L: Lanes>(
        lanes: &L,
        (u, v): (&[f32; CHUNK], &[f32; CHUNK]),
        params: &Params,
        cells: &mut Cells<u16>,
    ) {
        lanes.cells(u, v, params, cells);
    }
    #[inline(always)]
    fn integer_half(cells: &Cells<u16>, params: &Params, halves: &mut Halves<u16>) {
        // Levels 0..=16: `last` fits 16 bits.
        integer_half_u16(cells, params.last as u16, halves);
    }
    #[inline(always)]
    fn interleave<L: Lanes>(lanes: &L, halves: &Halves<u16>, out: &mut [u32; CHUNK]) {
        lanes.interleave(halves, out);
    }
    #[inline(always)]
    fn point(u_bits: u32, v_bits: u32, params: &Params) -> u32 {
        narrow::<CELL_BY_FLOAT>(u_bits, v_bits, params)
    }
}

/// Levels `0..=32`, 64-bit indices: [`wide`]'s bits.
pub(crate) struct Wide;

impl Form for Wide {
    type Word = u32;
    type Out = u64;
    #[inline(always)]
    fn cells<L: Lanes>(
        _: &L,
        (u, v): (&[f32; CHUNK], &[f32; CHUNK]),
        params: &Params,
        cells: &mut Cells<u32>,
    ) {
        wide_cells(u, v, params, cells);
    }
    #[inline(always)]
    fn integer_half(cells: &Cells<u32>, params: &Params, halves: &mut Halves<u32>) {
        integer_half_u32(cells, params.last, halves);
    }
    #[inline(always)]
    fn interleave<L: Lanes>(lanes: &L, halves: &Halves<u32>, out: &mut [u64; CHUNK]) {
        lanes.wide_interleave(halves, out);
    }
    #[inline(always)]
    fn point(u_bits: u32, v_bits: u32, params: &Params) -> u64 {
        wide(u_bits, v_bits, params)
    }
}

/// One chunk through the three stages. A function, not a closure in
/// [`chunked`]: closures do not inherit the caller's target features on
/// every supported compiler, and the intrinsics in `lanes` must inline into
/// the `#[target_feature]` loop.
#[inline(always)]
fn run_chunk<F: Form, L: Lanes>(
    lanes: &L,
    (u, v, out): (&[f32; CHUNK], &[f32; CHUNK], &mut [F::Out; CHUNK]),
    params: &Params,
    (cells, halves): (&mut Cells<F::Word>, &mut Halves<F::Word>),
) {
    F::cells(lanes, (u, v), params, cells);
    F::integer_half(cells, params, halves);
    F::interleave(lanes, halves, out);
}

/// The reference over slices of equal length (checked by the caller) in
/// form `F`, in chunks of [`CHUNK`] points through `lanes`' stages; a last
/// partial chunk runs padded with zeros, unless it is so short that the
/// point kernel costs less.
#[inline(always)]
pub(crate) fn chunked<F: Form, L: Lanes>(
    lanes: &L,
    u: &[f32],
    v: &[f32],
    out: &mut [F::Out],
    params: &Params,
) {
    /// Below this many points a padded chunk costs more than the points.
    const SHORT: usize = 16;
    let zero = F::Word::default();
    let mut cells = Cells {
        iu: [zero; CHUNK],
        iv: [zero; CHUNK],
        diagonal: [zero; CHUNK],
    };
    let mut halves = Halves {
        b0: [zero; CHUNK],
        b1: [zero; CHUNK],
    };
    let mut outs = out.chunks_exact_mut(CHUNK);
    let mut us = u.chunks_exact(CHUNK);
    let mut vs = v.chunks_exact(CHUNK);
    for ((out, u), v) in (&mut outs).zip(&mut us).zip(&mut vs) {
        // `chunks_exact` yields slices of exactly `CHUNK` elements.
        if let (Ok(u), Ok(v), Ok(out)) = (u.try_into(), v.try_into(), out.try_into()) {
            run_chunk::<F, L>(lanes, (u, v, out), params, (&mut cells, &mut halves));
        }
    }
    let (out, u, v) = (outs.into_remainder(), us.remainder(), vs.remainder());
    if out.len() < SHORT {
        for ((out, u), v) in out.iter_mut().zip(u).zip(v) {
            *out = F::point(u.to_bits(), v.to_bits(), params);
        }
    } else {
        let (mut padded_u, mut padded_v) = ([0f32; CHUNK], [0f32; CHUNK]);
        let mut padded_out = [F::Out::default(); CHUNK];
        padded_u[..u.len()].copy_from_slice(u);
        padded_v[..v.len()].copy_from_slice(v);
        let chunk = (&padded_u, &padded_v, &mut padded_out);
        run_chunk::<F, L>(lanes, chunk, params, (&mut cells, &mut halves));
        out.copy_from_slice(&padded_out[..out.len()]);
    }
}

/// [`chunked`] through [`PortableLanes`]: the portable backend where no
/// instruction set of [`super::arch`] applies.
#[cfg(not(target_arch = "x86_64"))]
pub(crate) fn narrow_slice_portable(u: &[f32], v: &[f32], out: &mut [u32], params: &Params) {
    chunked::<Narrow, _>(&PortableLanes, u, v, out, params);
}

/// The wide form through [`PortableLanes`].
#[cfg(not(target_arch = "x86_64"))]
pub(crate) fn wide_slice_portable(u: &[f32], v: &[f32], out: &mut [u64], params: &Params) {
    chunked::<Wide, _>(&PortableLanes, u, v, out, params);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interleave_puts_b0_on_even_bits() {
        assert_eq!(interleave_16(0xffff, 0), 0x5555_5555);
        assert_eq!(interleave_16(0, 0xffff), 0xaaaa_aaaa);
        assert_eq!(interleave_16(0b10, 0b01), 0b0110);
    }

    #[test]
    fn unit_coordinate_is_coordinate_in_the_unit_interval() {
        // No allocation: the lib's tests also run without `alloc`.
        let check = |b: u32| {
            if b > ONE_BITS {
                return;
            }
            for level in 0..=16 {
                let p = Params::new(level, EXACT_THRESHOLD);
                assert_eq!(
                    unit_coordinate(b, &p),
                    coordinate::<false>(b, &p),
                    "level {level}, bits {b:#010x}"
                );
            }
        };
        for b in [0, 1, 0x7f_ffff, 0x80_0000, ONE_BITS - 1, ONE_BITS] {
            check(b);
        }
        for e in 0..=127u32 {
            for b in [e << 23, (e << 23) | 0x7f_ffff, (e << 23) | 0x40_0001] {
                check(b);
            }
        }
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..20_000 {
            crate::xorshift(&mut x);
            check((x as u32) % (ONE_BITS + 1));
        }
    }

    /// The chunked pipeline with the safe stages (the portable backend of
    /// targets other than x86-64, which CI does not run) against [`narrow`]
    /// point by point: full chunks, a padded tail and a short one, special
    /// values and random bits, every level.
    #[test]
    fn portable_lanes_equal_the_point_kernel() {
        const POINTS: usize = 2 * CHUNK + 40;
        let special = [
            f32::NAN,
            -f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            -0.0,
            0.0,
            f32::from_bits(1),
            f32::from_bits(0x7f_ffff),
            f32::MIN_POSITIVE,
            BELOW_ONE,
            1.0,
            1.5,
            -0.25,
            0.5,
        ];
        let mut x = 0x0123_4567_89ab_cdefu64;
        let (mut u, mut v) = ([0f32; POINTS], [0f32; POINTS]);
        let mut out = [0u32; POINTS];
        for level in 0..=16 {
            let params = Params::new(level, BINARY32_THRESHOLD);
            for (k, (u, v)) in u.iter_mut().zip(v.iter_mut()).enumerate() {
                crate::xorshift(&mut x);
                *u = special
                    .get(k % 29)
                    .copied()
                    .unwrap_or(f32::from_bits(x as u32));
                *v = f32::from_bits((x >> 32) as u32 % (ONE_BITS + 1));
            }
            for len in [POINTS, 2 * CHUNK + 17, CHUNK + 3, 15, 0] {
                chunked::<Narrow, _>(
                    &PortableLanes,
                    &u[..len],
                    &v[..len],
                    &mut out[..len],
                    &params,
                );
                let mut wide_out = [0u64; POINTS];
                for wide_level in [level, 2 * level, 32 - level] {
                    let params = Params::new(wide_level, BINARY32_THRESHOLD);
                    chunked::<Wide, _>(
                        &PortableLanes,
                        &u[..len],
                        &v[..len],
                        &mut wide_out[..len],
                        &params,
                    );
                    for k in 0..len {
                        let expected = wide(u[k].to_bits(), v[k].to_bits(), &params);
                        assert_eq!(
                            wide_out[k], expected,
                            "wide level {wide_level}, length {len}, point {k}"
                        );
                    }
                }
                for k in 0..len {
                    let expected =
                        narrow::<CELL_BY_SHIFTS>(u[k].to_bits(), v[k].to_bits(), &params);
                    assert_eq!(
                        out[k],
                        expected,
                        "level {level}, length {len}, point {k}: u {:#010x}, v {:#010x}",
                        u[k].to_bits(),
                        v[k].to_bits()
                    );
                }
            }
        }
    }

    #[test]
    fn coordinates_split_cell_and_fraction() {
        let p = Params::new(1, BINARY32_THRESHOLD);
        assert_eq!(coordinate::<false>(0.75f32.to_bits(), &p), (1, 1 << 30));
        assert_eq!(coordinate::<false>(1.0f32.to_bits(), &p), (1, 0));
        assert_eq!(coordinate::<false>(f32::NAN.to_bits(), &p), (0, 0));
        assert_eq!(coordinate::<false>((-0.5f32).to_bits(), &p), (0, 0));
        assert_eq!(coordinate::<false>(f32::INFINITY.to_bits(), &p), (1, 0));
        // 2^-149 * 2: far below 2^-31, floors to 0.
        assert_eq!(coordinate::<false>(1, &p), (0, 0));
        let p = Params::new(32, BINARY32_THRESHOLD);
        assert_eq!(coordinate::<true>(1.0f32.to_bits(), &p), (u32::MAX, 0));
        assert_eq!(coordinate::<true>(0.5f32.to_bits(), &p), (1 << 31, 0));
        // 2^-40 * 2^32 = 2^-8: fraction 2^-8 * 2^31.
        assert_eq!(
            coordinate::<true>(2f32.powi(-40).to_bits(), &p),
            (0, 1 << 23)
        );
        assert_eq!(coordinate::<true>(1, &p), (0, 0));
    }
}
