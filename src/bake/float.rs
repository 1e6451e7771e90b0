//! `f64` helpers without `std` (the core builds without it): powers of two
//! and magnitudes by their bits, for the bounds of the bake's models.

/// `2^k` as `f64`, for `-1022 <= k <= 1023`.
#[inline]
pub(crate) fn exp2(k: i32) -> f64 {
    f64::from_bits(((1023 + k) as u64) << 52)
}

/// `|x|` (NaN stays NaN).
#[inline]
pub(crate) fn abs(x: f64) -> f64 {
    f64::from_bits(x.to_bits() & !(1 << 63))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn powers_and_magnitudes_are_exact() {
        assert_eq!(exp2(0), 1.0);
        assert_eq!(exp2(-1022), f64::MIN_POSITIVE);
        assert_eq!(exp2(1023), 2.0 * exp2(1022));
        assert_eq!(exp2(-20), 1.0 / 1_048_576.0);
        assert_eq!(abs(-2.5), 2.5);
        assert_eq!(abs(-0.0).to_bits(), 0);
        assert!(abs(f64::NAN).is_nan());
        assert_eq!(abs(f64::NEG_INFINITY), f64::INFINITY);
    }
}
