//! Bodies of the fuzz targets in `fuzz/` (cargo feature `fuzzing`).
//!
//! Each function takes arbitrary bytes, decodes them deterministically into
//! an input (documented on the function; missing bytes read as zero, extra
//! bytes are ignored unless stated otherwise) and checks a differential
//! property. It panics **only** when that property fails, with a message
//! giving the input exactly (float bits in hex, rationals as `p/q`); on every
//! other input it returns normally, whatever the bytes.
//!
//! The same bodies run under libFuzzer (`cargo +nightly fuzz run <target>`,
//! see `docs/fuzzing.md`) and on stable, where `tests/fuzz_corpus.rs` replays
//! every committed seed of `fuzz/corpus/<target>/` and
//! `fuzz/regressions/<target>/`.
//!
//! | function | fuzz target | property |
//! |---|---|---|
//! | [`spec_vs_mirror`] | `spec_vs_mirror` | [`spec::index_f32`] = [`spec::reference_bits_f32_by_integers`] (and, in the target, = the C reference) for every `f32` pair and level |
//! | [`exact_walk_vs_fixed`] | `exact_walk_vs_fixed` | [`internals::index_real_ref`] (BigRational) = [`uv2index::index_real`] = [`uv2index::exact_index_f32`] / [`uv2index::exact_index_f64`] on finite floats, levels `0..=32`, errors included |
//! | [`inverse_round_trip`] | `inverse_round_trip` | [`inverse::micro_triangle`] and the walk invert each other |
//! | [`eval_input`] | `eval_input` | [`eval::eval_line_bytes`] never panics and writes one JSON object line; [`Value::parse`] round-trips |
//! | [`vector_reader`] | `vector_reader` | [`vectors::parse_vector_file`] and [`vectors::parse_answers`] never panic; what they accept round-trips; [`vectors::check`] adds up |
//! | [`micromap_buffers`] | `micromap_buffers` | `micromap::read_buffers` never panics; what it accepts is consistent and rebuilds |
//! | [`succinct_tree`] | `succinct_tree` | the succinct-tree readers never panic; both layouts round-trip and agree with the flat micromap |
//! | [`alpha_image`] | `alpha_image` | [`assets::decode_alpha_image`] never panics, stays within [`FUZZ_LIMITS`], and what it accepts has `width * height` texels |
//! | [`triangles_json`] | `triangles_json` | [`assets::read_triangles_json`] never panics; what it accepts writes back and reads back bit for bit |
//! | [`gltf_asset`] | `gltf_asset` | [`assets::read_gltf_bytes`] (URIs served [`FUZZ_PNG`]) never panics, stays within [`FUZZ_LIMITS`], and what it accepts is consistent |
//!
//! ```
//! use micromap_index_lab::fuzzing;
//! // Every body accepts any bytes, the empty input included.
//! for data in [&[][..], &[0xff; 40][..], b"{\"u\": \"0.5\"}"] {
//!     fuzzing::spec_vs_mirror(data);
//!     fuzzing::exact_walk_vs_fixed(data);
//!     fuzzing::inverse_round_trip(data);
//!     fuzzing::eval_input(data);
//!     fuzzing::vector_reader(data);
//!     fuzzing::alpha_image(data);
//!     fuzzing::triangles_json(data);
//!     fuzzing::gltf_asset(data);
//! }
//! ```
//!
//! [`spec::index_f32`]: micromap_index::spec::index_f32
//! [`spec::reference_bits_f32_by_integers`]: micromap_index::spec::reference_bits_f32_by_integers
//! [`internals::index_real_ref`]: micromap_index::internals::index_real_ref
//! [`uv2index::index_real`]: micromap_index::uv2index::index_real
//! [`uv2index::exact_index_f32`]: micromap_index::uv2index::exact_index_f32
//! [`uv2index::exact_index_f64`]: micromap_index::uv2index::exact_index_f64
//! [`inverse::micro_triangle`]: micromap_index::inverse::micro_triangle
//! [`eval::eval_line_bytes`]: crate::eval::eval_line_bytes
//! [`Value::parse`]: crate::value::Value::parse
//! [`vectors::parse_vector_file`]: crate::vectors::parse_vector_file
//! [`vectors::parse_answers`]: crate::vectors::parse_answers
//! [`vectors::check`]: crate::vectors::check
//! [`assets::decode_alpha_image`]: micromap_index_assets::decode_alpha_image
//! [`assets::read_triangles_json`]: micromap_index_assets::read_triangles_json
//! [`assets::read_gltf_bytes`]: micromap_index_assets::read_gltf_bytes

mod assets;
mod micromap_buffers;
mod succinct_tree;
pub use assets::{alpha_image, gltf_asset, triangles_json, FUZZ_LIMITS, FUZZ_PNG};
pub use micromap_buffers::micromap_buffers;
pub use succinct_tree::succinct_tree;

use crate::eval::{eval_line_bytes, Variant};
use crate::value::{Value, MAX_VALUE_LEN};
use crate::vectors;
use micromap_index::inverse::{micro_triangle, MicroTriangle};
use micromap_index::{spec, uv2index, Level, SpecLevel};
use num_bigint::BigInt;
use num_rational::BigRational;

/// Reads the fuzzer's bytes front to back; past the end every byte is 0.
struct Bytes<'a> {
    rest: &'a [u8],
}

impl<'a> Bytes<'a> {
    fn new(data: &'a [u8]) -> Self {
        Bytes { rest: data }
    }

    fn byte(&mut self) -> u8 {
        match self.rest.split_first() {
            Some((&first, rest)) => {
                self.rest = rest;
                first
            }
            None => 0,
        }
    }

    /// `N` bytes, little-endian, zero-padded.
    fn le<const N: usize>(&mut self) -> [u8; N] {
        let mut out = [0u8; N];
        for slot in &mut out {
            *slot = self.byte();
        }
        out
    }

    fn u32(&mut self) -> u32 {
        u32::from_le_bytes(self.le())
    }

    fn u64(&mut self) -> u64 {
        u64::from_le_bytes(self.le())
    }
}

/// `x` clamped to `[0, 1]` with NaN -> 0, as the reference clamps.
#[allow(clippy::manual_clamp)] // `f32::clamp` keeps NaN
fn clamp_unit_f32(x: f32) -> f32 {
    x.max(0.0).min(1.0)
}

/// `x` moved by `delta` steps of its bit pattern, saturating at the
/// pattern's ends (for non-negative `x`: `delta` ulps, never below `+0`).
fn nudge_f32(x: f32, delta: i8) -> f32 {
    let bits = i64::from(x.to_bits()) + i64::from(delta);
    f32::from_bits(bits.clamp(0, i64::from(u32::MAX)) as u32)
}

/// One decoded input of [`spec_vs_mirror`] and the index both
/// implementations agreed on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpecCase {
    /// The `u` coordinate given to both implementations.
    pub u: f32,
    /// The `v` coordinate given to both implementations.
    pub v: f32,
    /// The level, any `u32` (the reference shifts by `level % 32`).
    pub level: u32,
    /// The index both returned.
    pub index: u32,
}

impl SpecCase {
    /// The case as `u = 0x..., v = 0x..., level = ...` with exact bits,
    /// for assertion messages.
    ///
    /// ```
    /// use micromap_index_lab::fuzzing::SpecCase;
    /// let case = SpecCase { u: 0.5, v: 0.25, level: 3, index: 0 };
    /// assert_eq!(case.describe(), "u = 0x3f000000, v = 0x3e800000, level = 3");
    /// ```
    #[must_use]
    pub fn describe(&self) -> String {
        format!(
            "u = 0x{:08x}, v = 0x{:08x}, level = {}",
            self.u.to_bits(),
            self.v.to_bits(),
            self.level
        )
    }

    /// Panics unless `other` (named `name` in the message) returns this
    /// case's index for its inputs. The fuzz target and its stable corpus
    /// replay use it to add the C reference, which the library cannot call.
    ///
    /// ```
    /// use micromap_index::spec;
    /// use micromap_index_lab::fuzzing::SpecCase;
    /// let case = SpecCase { u: 0.5, v: 0.25, level: 1, index: 2 };
    /// case.assert_agrees("spec::reference_bits_f32", spec::reference_bits_f32);
    /// ```
    ///
    /// A disagreeing implementation panics, naming the inputs' bits:
    ///
    /// ```should_panic
    /// use micromap_index_lab::fuzzing::SpecCase;
    /// let case = SpecCase { u: 0.5, v: 0.25, level: 1, index: 2 };
    /// case.assert_agrees("always zero", |_, _, _| 0);
    /// ```
    pub fn assert_agrees(&self, name: &str, other: impl Fn(f32, f32, u32) -> u32) {
        let by_other = other(self.u, self.v, self.level);
        assert_eq!(
            self.index,
            by_other,
            "spec::index_f32 = {} but {name} = {by_other} at {}",
            self.index,
            self.describe()
        );
    }
}

/// Differential: the Vulkan reference in binary32 ([`spec::index_f32`])
/// against its integer-only mirror ([`spec::reference_bits_f32_by_integers`]) on any pair
/// of `f32` bit patterns (NaN, ±inf, subnormals, outside the triangle) and
/// any level (taken modulo 32 by both). Returns the case so that the fuzz
/// target can also compare the C reference.
///
/// Decoding:
///
/// * bytes `0..4`: `u` bits (little-endian), bytes `4..8`: `v` bits;
/// * byte `8`: the level, `0..=255`;
/// * byte `9`, if odd: *diagonal mode*. `v` is replaced by the `f32`
///   nearest to `(iv + 1 - uf) / 2^(level % 32)` (computed in binary64; `iv`
///   the cell of the clamped decoded `v`, `uf` the exact fraction of the
///   clamped `u * 2^level`), then moved by byte `10` (as `i8`) steps of its
///   bit pattern. This puts `uf + vf` next to 1, where binary32 rounds the
///   reference's diagonal test (`docs/fixed.md`).
///
/// ```
/// use micromap_index_lab::fuzzing::spec_vs_mirror;
/// // u = 0.5, v = 0.25, level 1.
/// let case = spec_vs_mirror(&[0, 0, 0, 0x3f, 0, 0, 0x80, 0x3e, 1]);
/// assert_eq!((case.u, case.v, case.level, case.index), (0.5, 0.25, 1, 2));
/// ```
///
/// # Panics
///
/// When the two implementations disagree.
pub fn spec_vs_mirror(data: &[u8]) -> SpecCase {
    let mut bytes = Bytes::new(data);
    let u = f32::from_bits(bytes.u32());
    let mut v = f32::from_bits(bytes.u32());
    let level = u32::from(bytes.byte());
    if bytes.byte() & 1 == 1 {
        v = nudge_f32(complement_fraction(u, v, level % 32), bytes.byte() as i8);
    }
    let index = spec::reference_bits_f32(u, v, level);
    let case = SpecCase { u, v, level, index };
    case.assert_agrees(
        "spec::reference_bits_f32_by_integers",
        spec::reference_bits_f32_by_integers,
    );
    case
}

/// The `f32` nearest to `(iv + 1 - uf) / 2^level` (see [`spec_vs_mirror`]).
fn complement_fraction(u: f32, v: f32, level: u32) -> f32 {
    let scale = (1u64 << level) as f64;
    // Exact: a binary32 value times a power of two <= 2^31.
    let scaled_u = f64::from(clamp_unit_f32(u)) * scale;
    let fraction_u = scaled_u - scaled_u.floor();
    let cell_v = (f64::from(clamp_unit_f32(v)) * scale).floor();
    ((cell_v + 1.0 - fraction_u) / scale) as f32
}

/// A binary format the exact-walk target draws points from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    F32,
    F64,
}

impl Format {
    /// The bits of `1.0`.
    fn one_bits(self) -> u64 {
        match self {
            Format::F32 => u64::from(1f32.to_bits()),
            Format::F64 => 1f64.to_bits(),
        }
    }

    fn sign_bit(self) -> u64 {
        match self {
            Format::F32 => 1 << 31,
            Format::F64 => 1 << 63,
        }
    }

    /// The value of a bit pattern, widened to `f64` (exact).
    fn value(self, bits: u64) -> f64 {
        match self {
            Format::F32 => f64::from(f32::from_bits(bits as u32)),
            Format::F64 => f64::from_bits(bits),
        }
    }

    /// The bit pattern of `x` rounded to this format.
    fn bits(self, x: f64) -> u64 {
        match self {
            Format::F32 => u64::from((x as f32).to_bits()),
            Format::F64 => x.to_bits(),
        }
    }

    /// Significand (fraction) bits of the format.
    fn fraction_bits(self) -> u32 {
        match self {
            Format::F32 => 23,
            Format::F64 => 52,
        }
    }

    /// How many binades below 1 [`Format::fold_near`] reaches.
    fn near_binades(self) -> u64 {
        match self {
            Format::F32 => 48,
            Format::F64 => 64,
        }
    }

    /// Folds a bit pattern into `[0, 1]` over the whole range: the sign is
    /// cleared and a magnitude above `1.0` (NaN and inf included) is
    /// reduced modulo `bits(1.0) + 1`, so every finite pattern in `[0, 1]`
    /// can come out.
    fn fold_full(self, bits: u64) -> u64 {
        let magnitude = bits & !self.sign_bit();
        magnitude % (self.one_bits() + 1)
    }

    /// Folds a bit pattern into `[0, 1]` keeping normal numbers within
    /// [`Format::near_binades`] binades below 1, where the lattice lines of
    /// levels up to 32 are (and exact arithmetic is cheap): the sign is
    /// cleared; zero and subnormal patterns stay; a biased exponent `e`
    /// equal to that of 1, or all ones (inf, NaN), gives `1.0`; any other
    /// `e` becomes `e(1) - 1 - e % near_binades`, keeping the fraction.
    fn fold_near(self, bits: u64) -> u64 {
        let magnitude = bits & !self.sign_bit();
        let shift = self.fraction_bits();
        let exponent = magnitude >> shift;
        let one_exponent = self.one_bits() >> shift;
        let all_ones = (self.sign_bit() - 1) >> shift;
        if exponent == 0 {
            magnitude
        } else if exponent == one_exponent || exponent == all_ones {
            self.one_bits()
        } else {
            let fraction = magnitude & ((1 << shift) - 1);
            ((one_exponent - 1 - exponent % self.near_binades()) << shift) | fraction
        }
    }

    /// `bits` moved by `delta` steps of the magnitude (never below `+0`
    /// or `-0`), keeping the sign.
    fn nudge(self, bits: u64, delta: i8) -> u64 {
        let sign = bits & self.sign_bit();
        let magnitude = i128::from(bits & !self.sign_bit()) + i128::from(delta);
        let max = i128::from(self.sign_bit() - 1);
        sign | magnitude.clamp(0, max) as u64
    }

    fn hex(self, bits: u64) -> String {
        match self {
            Format::F32 => format!("0x{bits:08x} (f32)"),
            Format::F64 => format!("0x{bits:016x} (f64)"),
        }
    }
}

/// Differential: the walk over exact rationals, all-BigRational
/// ([`internals::index_real_ref`](micromap_index::internals::index_real_ref)), against the machine-integer fast path
/// ([`uv2index::index_real`], where the point has one) and the fixed-point engine
/// ([`uv2index::exact_index_f32`] / [`uv2index::exact_index_f64`]) on finite binary32 or
/// binary64 points, levels `0..=32`; the full `Result` must agree, so points
/// outside the triangle must be rejected for the same reason. Also checks
/// [`spec::cell_real`] against [`micromap_index::internals::cell_real_ref`] and, inside the
/// triangle, the 64-bit reference over the reals ([`spec::wide_index_real`])
/// against the walk.
///
/// Decoding:
///
/// * byte `0`: level `= byte % 33`;
/// * byte `1`: flags. Bit 0: binary64 (else binary32). Bit 3: *raw*: the
///   bit patterns are used as they are and a non-finite coordinate skips
///   the input. Otherwise each pattern is folded into `[0, 1]`: with bit 4,
///   over the whole range (sign cleared, a magnitude above `1.0` reduced
///   modulo `bits(1.0) + 1`: mostly tiny values, and binary64 subnormals
///   make the `BigRational` walk slow); without it, near 1 (sign cleared,
///   zero and subnormals kept, the exponent of 1 and of inf/NaN give `1.0`,
///   any other biased exponent `e` becomes `e(1) - 1 - e % K` with `K = 48`
///   for binary32 and 64 for binary64, fraction kept);
/// * then `u` bits and `v` bits, little-endian, 4 bytes each for binary32,
///   8 for binary64;
/// * then two bytes `du`, `dv` (as `i8`);
/// * flag bit 1, *snap u*: `u` becomes `floor(u * 2^level) / 2^level`, a
///   lattice line, moved by `du` steps of its bit pattern;
/// * flag bit 2, *near a diagonal*: `v` becomes `s - u` rounded to the
///   format, with `s = floor(v * 2^level) / 2^level`, moved by `dv` steps:
///   the point sits next to the lattice line `u + v = s`;
/// * after each of these steps the point is folded again (or skipped when
///   raw and no longer finite).
///
/// ```
/// use micromap_index_lab::fuzzing::exact_walk_vs_fixed;
/// // Level 32, binary32, snap u and put v next to a diagonal.
/// exact_walk_vs_fixed(&[32, 0b110, 0x9a, 0x99, 0x99, 0x3e, 0xcd, 0xcc, 0x4c, 0x3e, 1, 0xff]);
/// ```
///
/// # Panics
///
/// When two implementations disagree.
pub fn exact_walk_vs_fixed(data: &[u8]) {
    let mut bytes = Bytes::new(data);
    let Ok(level) = Level::new(u32::from(bytes.byte()) % 33) else {
        return;
    };
    let flags = bytes.byte();
    let format = if flags & 1 == 1 {
        Format::F64
    } else {
        Format::F32
    };
    let raw = flags & 8 != 0;
    let full_range = flags & 16 != 0;
    let (u_bits, v_bits) = match format {
        Format::F32 => (u64::from(bytes.u32()), u64::from(bytes.u32())),
        Format::F64 => (bytes.u64(), bytes.u64()),
    };
    let (du, dv) = (bytes.byte() as i8, bytes.byte() as i8);
    // A finite (folded unless raw) pattern, or None to skip the input.
    let settle = |bits: u64| {
        let bits = if raw {
            bits
        } else if full_range {
            format.fold_full(bits)
        } else {
            format.fold_near(bits)
        };
        format.value(bits).is_finite().then_some(bits)
    };
    let Some(mut u_bits) = settle(u_bits) else {
        return;
    };
    let Some(mut v_bits) = settle(v_bits) else {
        return;
    };
    let scale = (1u64 << level.get()) as f64;
    if flags & 2 != 0 {
        // Exact unless |u| * 2^32 overflows, which only a raw pattern can.
        let snapped = (format.value(u_bits) * scale).floor() / scale;
        let Some(bits) = settle(format.nudge(format.bits(snapped), du)) else {
            return;
        };
        u_bits = bits;
    }
    if flags & 4 != 0 {
        let sum = (format.value(v_bits) * scale).floor() / scale;
        let near = sum - format.value(u_bits);
        let Some(bits) = settle(format.nudge(format.bits(near), dv)) else {
            return;
        };
        v_bits = bits;
    }
    let (u, v) = (format.value(u_bits), format.value(v_bits));
    let (Some(u_exact), Some(v_exact)) = (BigRational::from_float(u), BigRational::from_float(v))
    else {
        return; // unreachable: both are finite
    };
    let describe = || {
        format!(
            "u = {} = {u_exact}, v = {} = {v_exact}, level = {level}",
            format.hex(u_bits),
            format.hex(v_bits)
        )
    };

    // Without a small common denominator the fast paths are the `*_ref`
    // functions themselves: compare them only when they differ.
    let has_fast_path =
        micromap_index::internals::over_common_denominator(&u_exact, &v_exact).is_some();
    let reference = micromap_index::internals::index_real_ref(&u_exact, &v_exact, level);
    if has_fast_path {
        let fast = uv2index::index_real(&u_exact, &v_exact, level);
        assert_eq!(
            reference,
            fast,
            "micromap_index::internals::index_real_ref = {reference:?} but uv2index::index_real = {fast:?} at {}",
            describe()
        );
    }
    let by_fixed = match format {
        Format::F32 => uv2index::exact_index_f32(u as f32, v as f32, level),
        Format::F64 => uv2index::exact_index_f64(u, v, level),
    };
    assert_eq!(
        reference,
        by_fixed,
        "micromap_index::internals::index_real_ref = {reference:?} but fixed::index_{format:?} = {by_fixed:?} at {}",
        describe()
    );
    if format == Format::F32 {
        let widened = uv2index::exact_index_f64(u, v, level);
        assert_eq!(
            reference,
            widened,
            "micromap_index::internals::index_real_ref = {reference:?} but uv2index::exact_index_f64 (widened) = {widened:?} at {}",
            describe()
        );
    }

    if has_fast_path {
        let cell = spec::cell_real(&u_exact, &v_exact, level);
        let cell_ref = micromap_index::internals::cell_real_ref(&u_exact, &v_exact, level);
        assert_eq!(
            cell,
            cell_ref,
            "spec::cell_real = {cell:?} but micromap_index::internals::cell_real_ref = {cell_ref:?} at {}",
            describe()
        );
    }
    if let Ok(walk) = reference {
        let wide = spec::wide_index_real(&u_exact, &v_exact, level);
        assert_eq!(
            walk,
            wide,
            "micromap_index::internals::index_real_ref = {walk} but spec::wide_index_real = {wide} at {}",
            describe()
        );
    }
}

/// The point `(x, y) / 2^scale_log2` as exact rationals.
fn dyadic(x: u64, y: u64, scale_log2: u32) -> (BigRational, BigRational) {
    let denominator = BigInt::from(1u8) << scale_log2;
    (
        BigRational::new(x.into(), denominator.clone()),
        BigRational::new(y.into(), denominator),
    )
}

/// Every index the crate's exact implementations give the dyadic point
/// `(x, y) / 2^scale_log2` at `level`, checked equal (the slow all-BigRational
/// walk only `with_ref`); `what` names the point in messages. Returns the
/// walk's index.
fn index_of_dyadic(
    x: u64,
    y: u64,
    scale_log2: u32,
    level: Level,
    what: &str,
    with_ref: bool,
) -> u64 {
    let (u, v) = dyadic(x, y, scale_log2);
    let at = || format!("{what} ({u}, {v}) at level {level}");
    let walk = uv2index::index_real(&u, &v, level);
    if with_ref {
        let walk_ref = micromap_index::internals::index_real_ref(&u, &v, level);
        assert_eq!(
            walk,
            walk_ref,
            "uv2index::index_real = {walk:?} but index_real_ref = {walk_ref:?} at {}",
            at()
        );
    }
    let Ok(walk) = walk else {
        panic!("{} is not in the triangle: {walk:?}", at());
    };
    // Numerators have at most 35 bits: exact in binary64.
    let scale = 1.0 / (1u64 << scale_log2) as f64;
    let (uf, vf) = (x as f64 * scale, y as f64 * scale);
    let by_fixed = uv2index::exact_index_f64(uf, vf, level);
    assert_eq!(
        by_fixed,
        Ok(walk),
        "uv2index::exact_index_f64 = {by_fixed:?} but the walk says {walk} at {}",
        at()
    );
    if let Ok(spec_level) = SpecLevel::try_from(level) {
        let by_spec = u64::from(spec::index_real(&u, &v, spec_level));
        let by_dyadic = spec::index_dyadic(x, y, scale_log2, spec_level).map(u64::from);
        assert_eq!(
            (by_spec, by_dyadic),
            (walk, Ok(walk)),
            "spec::index_real / index_dyadic disagree with the walk ({walk}) at {}",
            at()
        );
    } else {
        let wide = spec::wide_index_real(&u, &v, level);
        let wide_dyadic = spec::wide_index_dyadic(x, y, scale_log2, level);
        assert_eq!(
            (wide, wide_dyadic),
            (walk, Ok(walk)),
            "spec::wide_index_real / wide_index_dyadic disagree with the walk ({walk}) at {}",
            at()
        );
    }
    walk
}

/// The vertex set of a micro-triangle, sorted.
fn vertex_set(triangle: &MicroTriangle) -> [(u64, u64); 3] {
    let mut vertices = triangle.vertices_scaled();
    vertices.sort_unstable();
    vertices
}

/// Round trip: index → [`inverse::micro_triangle`](micromap_index::inverse::micro_triangle) → points → the walk.
///
/// Decoding: byte `0`: level `= byte % 33`; bytes `1..9`: the index
/// (little-endian `u64`) reduced modulo `4^level`; byte `9`: which vertex
/// (`byte % 3`) gets weight 2 in the interior point.
///
/// Checks, with `V0, V1, V2` the micro-triangle's vertices:
///
/// * the interior point `(2 Va + Vb + Vc) / 4` and the centroid map back to
///   the index under the exact walk (`BigRational` and fast path; for the
///   centroid the fast path), the
///   fixed-point walk, and the reference over the reals (32-bit words up to
///   level 16, 64-bit words above; rational and dyadic versions); up to
///   level 16 also under the reference in binary32 and its integer mirror;
/// * the vertices have the shape `upright()` claims (`(a, b), (a+1, b),
///   (a, b+1)` or `(a+1, b), (a, b+1), (a+1, b+1)`, each a lattice point of
///   the closed triangle) and wind counter-clockwise exactly when upright;
/// * each vertex maps, under every exact implementation alike (but the
///   slow all-BigRational walk), to a micro-triangle that has it as a
///   vertex;
/// * each neighbour is `None` exactly for edges on the base triangle's
///   boundary, otherwise another valid index whose micro-triangle shares
///   the edge; each edge midpoint maps to this index or that neighbour.
///
/// ```
/// use micromap_index_lab::fuzzing::inverse_round_trip;
/// // Level 3, index 42, weight 2 on vertex 1.
/// inverse_round_trip(&[3, 42, 0, 0, 0, 0, 0, 0, 0, 1]);
/// ```
///
/// # Panics
///
/// When a property fails.
pub fn inverse_round_trip(data: &[u8]) {
    let mut bytes = Bytes::new(data);
    let Ok(level) = Level::new(u32::from(bytes.byte()) % 33) else {
        return;
    };
    let index = (u128::from(bytes.u64()) % level.micro_triangle_count()) as u64;
    let heavy = usize::from(bytes.byte() % 3);
    let triangle = match micro_triangle(level, index) {
        Ok(triangle) => triangle,
        Err(e) => panic!("micro_triangle(level {level}, index {index}) failed: {e}"),
    };
    assert_eq!(
        (triangle.level(), triangle.index()),
        (level, index),
        "micro_triangle(level {level}, index {index}) reports another level or index"
    );
    let vertices = triangle.vertices_scaled();
    let side = 1u64 << level.get();

    // Shape and orientation.
    let [p, q, r] = vertices;
    let corner = (
        vertices.iter().map(|v| v.0).min().unwrap_or(0),
        vertices.iter().map(|v| v.1).min().unwrap_or(0),
    );
    let (a, b) = corner;
    let mut expected = if triangle.upright() {
        [(a, b), (a + 1, b), (a, b + 1)]
    } else {
        [(a + 1, b), (a, b + 1), (a + 1, b + 1)]
    };
    expected.sort_unstable();
    assert_eq!(
        vertex_set(&triangle),
        expected,
        "level {level} index {index}: vertices {vertices:?} do not have the shape upright() = {} claims",
        triangle.upright()
    );
    for (x, y) in vertices {
        assert!(
            x + y <= side,
            "level {level} index {index}: vertex ({x}, {y}) / 2^{level} is outside the triangle"
        );
    }
    let cross = |o: (u64, u64), s: (u64, u64), t: (u64, u64)| {
        let d = |m: (u64, u64)| {
            (
                i128::from(m.0) - i128::from(o.0),
                i128::from(m.1) - i128::from(o.1),
            )
        };
        let (s, t) = (d(s), d(t));
        s.0 * t.1 - s.1 * t.0
    };
    assert_eq!(
        cross(p, q, r) > 0,
        triangle.upright(),
        "level {level} index {index}: vertices {vertices:?} wind against upright() = {}",
        triangle.upright()
    );

    // Interior points map back.
    let (b1, b2) = ((heavy + 1) % 3, (heavy + 2) % 3);
    let x = 2 * vertices[heavy].0 + vertices[b1].0 + vertices[b2].0;
    let y = 2 * vertices[heavy].1 + vertices[b1].1 + vertices[b2].1;
    let back = index_of_dyadic(x, y, level.get() + 2, level, "interior point", true);
    assert_eq!(
        back,
        index,
        "level {level} index {index}: interior point ({x}, {y}) / 2^{} walks to {back}",
        level.get() + 2
    );
    let (cu, cv) = triangle.centroid_rational();
    let by_centroid = uv2index::index_real(&cu, &cv, level);
    assert_eq!(
        by_centroid,
        Ok(index),
        "level {level} index {index}: centroid ({cu}, {cv}) walks to {by_centroid:?}"
    );
    if level.get() <= spec::MAX_LEVEL {
        // (x, y) / 2^(level + 2) has at most 19 significant bits: exact in
        // binary32, and its fractions are multiples of 1/4, far from where
        // binary32 rounds the reference's diagonal test.
        let scale = 1.0 / (1u64 << (level.get() + 2)) as f32;
        let (uf, vf) = (x as f32 * scale, y as f32 * scale);
        let by_f32 = spec::reference_bits_f32(uf, vf, level.get());
        let by_mirror = spec::reference_bits_f32_by_integers(uf, vf, level.get());
        assert_eq!(
            (u64::from(by_f32), u64::from(by_mirror)),
            (index, index),
            "level {level} index {index}: spec::index_f32 / index_mirror_f32 at (0x{:08x}, 0x{:08x})",
            uf.to_bits(),
            vf.to_bits()
        );
    }

    // Vertices map to a micro-triangle having them as a vertex.
    for (i, &(vx, vy)) in vertices.iter().enumerate() {
        let owner = index_of_dyadic(vx, vy, level.get(), level, "vertex", false);
        let owner_vertices = match micro_triangle(level, owner) {
            Ok(t) => t.vertices_scaled(),
            Err(e) => panic!("level {level}: vertex {i} walks to {owner}, which fails: {e}"),
        };
        assert!(
            owner_vertices.contains(&(vx, vy)),
            "level {level} index {index}: vertex {i} ({vx}, {vy}) / 2^{level} walks to {owner} with vertices {owner_vertices:?}"
        );
    }

    // Neighbours and edge midpoints.
    let neighbours = triangle.neighbours();
    for (i, neighbour) in neighbours.into_iter().enumerate() {
        let (s, t) = (vertices[(i + 1) % 3], vertices[(i + 2) % 3]);
        let on_boundary = (s.0 == 0 && t.0 == 0)
            || (s.1 == 0 && t.1 == 0)
            || (s.0 + s.1 == side && t.0 + t.1 == side);
        assert_eq!(
            neighbour.is_none(),
            on_boundary,
            "level {level} index {index}: neighbour {i} is {neighbour:?} for edge {s:?}-{t:?}"
        );
        if let Some(n) = neighbour {
            let shared = match micro_triangle(level, n) {
                Ok(other) => other.vertices_scaled(),
                Err(e) => panic!("level {level} index {index}: neighbour {i} = {n} fails: {e}"),
            };
            assert!(
                n != index && shared.contains(&s) && shared.contains(&t),
                "level {level} index {index}: neighbour {i} = {n} (vertices {shared:?}) does not share edge {s:?}-{t:?}"
            );
        }
        let midpoint = index_of_dyadic(
            s.0 + t.0,
            s.1 + t.1,
            level.get() + 1,
            level,
            "midpoint",
            false,
        );
        assert!(
            midpoint == index || Some(midpoint) == neighbour,
            "level {level} index {index}: midpoint of edge {i} walks to {midpoint}, neither this nor neighbour {neighbour:?}"
        );
    }
}

/// The CLI's input path on arbitrary bytes: [`eval_line_bytes`] for every
/// [`Variant`], and [`Value::parse`] on the same bytes.
///
/// The whole input is one line (no decoding). Checks:
///
/// * every variant returns a single line holding a JSON object with exactly
///   one member, `"index"` (an unsigned integer below `4^level`, the input's
///   `level`) or `"error"` (a string);
/// * variants that must agree do: `spec-f32` and `fixed-mirror` give the
///   same line; where two of `uv2index-exact`, `fixed-exact`, `spec-exact`
///   and `spec-wide` all return an index, the indices are equal;
/// * if the bytes are UTF-8 and [`Value::parse`] accepts them, the value's
///   text parses back to the same value, and its `f32`, `f64` and exact
///   readings are consistent (NaN and infinities have no exact reading but
///   both float readings).
///
/// ```
/// use micromap_index_lab::fuzzing::eval_input;
/// eval_input(br#"{"u": "0x3e000000", "v": "1/8", "level": 2}"#);
/// eval_input(b"\xff\xfe not UTF-8");
/// eval_input(b"-3/8");
/// ```
///
/// # Panics
///
/// When a property fails.
pub fn eval_input(data: &[u8]) {
    let input_level = std::str::from_utf8(data)
        .ok()
        .and_then(|text| serde_json::from_str::<serde_json::Value>(text).ok())
        .and_then(|json| {
            // The line's serde reading also accepts `[u, v, level]`.
            match &json {
                serde_json::Value::Array(items) => items.get(2).and_then(serde_json::Value::as_u64),
                _ => json.get("level").and_then(serde_json::Value::as_u64),
            }
        });
    let mut lines = Vec::with_capacity(Variant::ALL.len());
    for variant in Variant::ALL {
        let line = eval_line_bytes(variant, data);
        assert!(
            !line.contains(['\n', '\r']),
            "{variant} wrote more than one line: {line:?} for input {data:?}"
        );
        let json: serde_json::Value = match serde_json::from_str(&line) {
            Ok(json) => json,
            Err(e) => panic!("{variant} wrote invalid JSON {line:?} ({e}) for input {data:?}"),
        };
        let member = json
            .as_object()
            .filter(|object| object.len() == 1)
            .and_then(|object| object.iter().next());
        let index = match member {
            Some((key, serde_json::Value::String(_))) if key == "error" => None,
            Some((key, value)) if key == "index" && value.as_u64().is_some() => value.as_u64(),
            _ => panic!("{variant} wrote {line:?}, not one index or error, for input {data:?}"),
        };
        if let Some(index) = index {
            let Some(level) = input_level.filter(|&level| level <= 32) else {
                panic!("{variant} wrote {line:?} for input {data:?} without a level 0..=32");
            };
            assert!(
                u128::from(index) < 1u128 << (2 * level),
                "{variant} wrote index {index} >= 4^{level} for input {data:?}"
            );
        }
        lines.push((variant, line, index));
    }
    let line_of = |wanted: Variant| {
        lines
            .iter()
            .find(|(variant, _, _)| *variant == wanted)
            .map(|(_, line, index)| (line.as_str(), *index))
    };
    if let (Some((spec_line, _)), Some((mirror_line, _))) = (
        line_of(Variant::SpecF32),
        line_of(Variant::SpecF32ByIntegers),
    ) {
        assert_eq!(
            naming_no_variant(spec_line, Variant::SpecF32),
            naming_no_variant(mirror_line, Variant::SpecF32ByIntegers),
            "spec-f32 and fixed-mirror differ for input {data:?}"
        );
    }
    let exact: Vec<(Variant, u64)> = [
        Variant::WalkReal,
        Variant::WalkExactFloat,
        Variant::SpecReal,
        Variant::SpecWideReal,
    ]
    .into_iter()
    .filter_map(|variant| Some((variant, line_of(variant)?.1?)))
    .collect();
    if let Some(&(first, first_index)) = exact.first() {
        for &(variant, index) in &exact {
            assert_eq!(
                index, first_index,
                "{variant} says {index} but {first} says {first_index} for input {data:?}"
            );
        }
    }

    if let Some(value) = std::str::from_utf8(data)
        .ok()
        .and_then(|text| Value::parse(text).ok())
    {
        check_value(&value);
    }
}

/// The consistency of one parsed value's readings (see [`eval_input`]).
fn check_value(value: &Value) {
    let text = value.to_string();
    let reparsed = Value::parse(&text);
    // Finding F1 (docs/fuzzing.md), fixed: the canonical text of every
    // parsed value parses back, however long.
    assert!(
        text.len() <= MAX_VALUE_LEN,
        "{value:?} prints as {} characters",
        text.len()
    );
    assert_eq!(
        reparsed.as_ref(),
        Ok(value),
        "{value:?} prints as {text:?}, which does not parse back"
    );
    let as_f32 = value.to_f32();
    let as_f64 = value.to_f64();
    if let Ok(exact) = value.to_exact() {
        if let Ok(x) = as_f32 {
            assert_eq!(
                BigRational::from_float(x).as_ref(),
                Some(&exact),
                "{text}: to_f32 = 0x{:08x} but to_exact = {exact}",
                x.to_bits()
            );
        }
        if let Ok(x) = as_f64 {
            assert_eq!(
                BigRational::from_float(x).as_ref(),
                Some(&exact),
                "{text}: to_f64 = 0x{:016x} but to_exact = {exact}",
                x.to_bits()
            );
        }
    } else {
        let non_finite = |x: Result<f64, _>| x.is_ok_and(|x: f64| !x.is_finite());
        assert!(
            non_finite(as_f32.clone().map(f64::from)) && non_finite(as_f64.clone()),
            "{text}: no exact reading, but to_f32 = {as_f32:?}, to_f64 = {as_f64:?}"
        );
    }
    if let Ok(x) = as_f32 {
        let widened = as_f64.clone().map(f64::to_bits);
        let expected = f64::from(x);
        assert!(
            as_f64.is_ok_and(|y| y == expected || (y.is_nan() && x.is_nan())),
            "{text}: to_f32 = 0x{:08x} but to_f64 = {widened:x?}",
            x.to_bits()
        );
    }
}

/// The conformance-vector readers on arbitrary bytes:
/// [`vectors::parse_vector_file`] and [`vectors::parse_answers`] never
/// panic, and what they accept survives a write-and-read round trip.
///
/// Decoding: the bytes before the first NUL byte are the vector file, the
/// bytes after it the answers; without a NUL, all the bytes are given to
/// both readers. Checks:
///
/// * an accepted vector file equals the result of reading its
///   [`to_json_text`](vectors::VectorFile::to_json_text) again, and so do
///   accepted answers and their
///   [`to_json_lines`](vectors::Answers::to_json_lines);
/// * on an accepted file, the answers of `spec-f32` and `fixed-mirror`
///   ([`vectors::compute_answers`]) are equal, read back equal, and
///   [`vectors::check`] of them (and of the accepted answers, if any) adds
///   up: every case is matched, mismatched or missing, the tallies by level
///   count every case once, and rendering the report does not panic.
///
/// ```
/// use micromap_index_lab::fuzzing::vector_reader;
/// let file = br#"{"format": "micromap-index-vectors", "version": 1, "function": "spec-f32",
///   "cases": [{"id": 7, "u": "0x3e800000", "v": "0x3e800000", "level": 2, "index": 5, "tags": ["vertex"]}]}"#;
/// let mut data = file.to_vec();
/// data.extend(b"\0{\"id\": 7, \"index\": 5}\n");
/// vector_reader(&data);
/// vector_reader(b"\xff{");
/// ```
///
/// # Panics
///
/// When a property fails.
pub fn vector_reader(data: &[u8]) {
    let (file_bytes, answer_bytes) = match data.iter().position(|&b| b == 0) {
        Some(nul) => (&data[..nul], &data[nul + 1..]),
        None => (data, data),
    };
    let file = vectors::parse_vector_file(file_bytes).ok();
    if let Some(file) = &file {
        let text = file.to_json_text();
        let again = vectors::parse_vector_file(text.as_bytes());
        assert_eq!(
            again.as_ref(),
            Ok(file),
            "vector file {file:?} writes as {text:?}, which reads back differently"
        );
    }
    let answers = vectors::parse_answers(answer_bytes).ok();
    if let Some(answers) = &answers {
        check_answers_round_trip(answers);
    }
    let Some(file) = file else {
        return;
    };
    let source = |name| vectors::AnswerSource::from_name(name);
    if let (Some(spec_f32), Some(mirror)) = (source("spec-f32"), source("fixed-mirror")) {
        let by_spec = vectors::compute_answers(spec_f32, &file);
        let by_mirror = vectors::compute_answers(mirror, &file);
        let neutral = |answers: &vectors::Answers, variant| -> Vec<(u64, String)> {
            answers
                .by_id
                .iter()
                .map(|(id, answer)| (*id, naming_no_variant(&answer.to_string(), variant)))
                .collect()
        };
        assert_eq!(
            neutral(&by_spec, Variant::SpecF32),
            neutral(&by_mirror, Variant::SpecF32ByIntegers),
            "spec-f32 and fixed-mirror answer {file:?} differently"
        );
        check_answers_round_trip(&by_spec);
        check_report_adds_up(&file, &by_spec);
    }
    if let Some(answers) = &answers {
        check_report_adds_up(&file, answers);
    }
}

/// Answers read back from their own JSON lines unchanged.
fn check_answers_round_trip(answers: &vectors::Answers) {
    let lines = answers.to_json_lines();
    let again = vectors::parse_answers(lines.as_bytes());
    assert_eq!(
        again.as_ref(),
        Ok(answers),
        "answers {answers:?} write as {lines:?}, which read back differently"
    );
}

/// The counts of [`vectors::check`] are consistent.
fn check_report_adds_up(file: &vectors::VectorFile, answers: &vectors::Answers) {
    let report = vectors::check(file, answers);
    let accounted = report.matched + report.unsupported + report.mismatches.len() + report.missing;
    let by_level: usize = report.by_level.values().map(|tally| tally.cases).sum();
    let by_class: usize = report.by_class.values().sum();
    assert!(
        report.cases == file.cases.len()
            && report.checked == report.cases
            && accounted == report.cases
            && by_level == report.cases
            && by_class == report.mismatches.len()
            && report.passed()
                == (report.matched > 0
                    && accounted == report.matched + report.unsupported
                    && report.unknown.is_empty()),
        "check of {file:?} against {answers:?} does not add up: {report:?}"
    );
    let _ = report.render(3);
    let _ = report.to_json(3);
}

/// `text` with the variant's name in a level message ("spec-f32 supports
/// levels 0..=16") replaced by `VARIANT`: two variants that agree give the
/// same text.
fn naming_no_variant(text: &str, variant: Variant) -> String {
    text.replace(&format!(" {variant} supports"), " VARIANT supports")
}
