//! The chunked pipeline: [`CHUNK`] points at a time through three stages,
//! each its own loop, with the stages that differ between instruction sets
//! behind [`Lanes`].

use super::point::{coordinate, narrow, wide, CELL_BY_FLOAT};
use super::word::{narrow_lane, wide_lane};
use super::Params;

/// Points per chunk of the chunked pipeline: enough that each stage's loop
/// keeps its vector registers busy and is not unrolled into straight-line
/// code (which the compiler vectorises worse), small enough that a chunk's
/// buffers (3 to 6 KiB) stay in L1.
pub const CHUNK: usize = 256;

/// The first half's output for one chunk: clamped cells (at most `last`)
/// and the diagonal outcome (0 or 1), in the order a backend's `Lanes`
/// chose (the integer half works point by point, so any order the
/// backend's interleave undoes is fine). `W` is `u16` for levels `0..=16`,
/// `u32` for the wide form.
pub struct Cells<W> {
    /// `min(trunc(u * 2^level), last)` per point.
    pub iu: [W; CHUNK],
    /// `min(trunc(v * 2^level), last)` per point.
    pub iv: [W; CHUNK],
    /// `uf + vf >= 1.0f` per point, as 0 or 1.
    pub diagonal: [W; CHUNK],
}

/// The integer half's output for one chunk: `b0` and `b1` before the
/// interleave, in the order of `Cells`.
pub struct Halves<W> {
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
/// `iu, iv <= last`: the form's lane function (`kernel::word`) on every
/// lane.
macro_rules! integer_half_chunk {
    ($(#[$doc:meta])* $name:ident, $word:ty, $lane:ident) => {
        $(#[$doc])*
        #[inline(always)]
        pub(crate) fn $name(cells: &Cells<$word>, last: $word, halves: &mut Halves<$word>) {
            for k in 0..CHUNK {
                let (b0, b1) = $lane(cells.iu[k], cells.iv[k], cells.diagonal[k], last);
                halves.b0[k] = b0;
                halves.b1[k] = b1;
            }
        }
    };
}

integer_half_chunk!(
    /// The integer half of levels `0..=16` in 16-bit words: every value is
    /// at most `last <= 2^16 - 1`, so a vector holds twice as many points
    /// as in 32-bit words.
    integer_half_u16,
    u16,
    narrow_lane
);
integer_half_chunk!(
    /// The integer half of the wide form (levels `0..=32`) in 32-bit words.
    integer_half_u32,
    u32,
    wide_lane
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
