//! The Vulkan specification's reference `BarycentricsToSpaceFillingCurveIndex`,
//! compiled from C (`reference/c/spec_reference.c`), as an independent oracle
//! for `micromap_index::spec::reference_bits_f32`. A dev-dependency of the
//! verification crate (`crates/lab`) only; never part of the library.

// The one unsafe operation in this crate is the call in `spec_index`: the
// C oracle is reached through FFI (the workspace denies unsafe elsewhere).
#![allow(unsafe_code)]
extern "C" {
    fn micromap_spec_reference_index(u: f32, v: f32, level: u32) -> u32;
}

/// The reference index of `(u, v)` at `level`, as the C reference computes
/// it in binary32. Total: levels `>= 32` use `level % 32` (C's `1u << level`
/// is undefined there); indices are only meaningful for levels `0..=16`.
///
/// ```
/// use micromap_index_c_reference::spec_index;
/// // Level 1: left = 0, middle = 1, right = 2, top = 3.
/// assert_eq!(spec_index(0.4, 0.4, 1), 1);
/// assert_eq!(spec_index(f32::NAN, f32::INFINITY, 1), 3);
/// ```
#[must_use]
pub fn spec_index(u: f32, v: f32, level: u32) -> u32 {
    // SAFETY: the C function takes plain values, touches no memory but its
    // locals, and is defined for every input (it shifts by `level % 32`).
    unsafe { micromap_spec_reference_index(u, v, level) }
}

#[cfg(test)]
mod tests {
    use super::spec_index;

    #[test]
    fn level_two_corners_and_centre() {
        // Level 2 counts 16 micro-triangles; (0, 0) is the first, (0, 1) the last.
        assert_eq!(spec_index(0.0, 0.0, 2), 0);
        assert_eq!(spec_index(0.0, 1.0, 2), 15);
        assert_eq!(spec_index(0.3, 0.3, 2), 5);
    }

    #[test]
    fn levels_wrap_modulo_32() {
        for level in 0..32 {
            assert_eq!(
                spec_index(0.3, 0.6, level),
                spec_index(0.3, 0.6, level + 32)
            );
        }
    }
}
