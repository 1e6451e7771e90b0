//! The body of the fuzz target `exact_walk_vs_fixed`, replayed on stable
//! by `crates/lab/tests/fuzz_corpus.rs`.

#[allow(clippy::wildcard_imports)]
use super::*;

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
