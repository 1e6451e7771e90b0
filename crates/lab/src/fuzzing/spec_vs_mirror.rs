//! The body of the fuzz target `spec_vs_mirror`, replayed on stable by
//! `crates/lab/tests/fuzz_corpus.rs`.

#[allow(clippy::wildcard_imports)]
use super::*;

/// `x` clamped to `[0, 1]` with NaN -> 0, as the reference clamps.
#[allow(clippy::manual_clamp)] // `f32::clamp` keeps NaN
fn clamp_unit_f32(x: f32) -> f32 {
    x.max(0.0).min(1.0)
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
        v = step_ulps(
            complement_fraction(u, v, level % 32),
            i32::from(bytes.byte() as i8),
        );
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
