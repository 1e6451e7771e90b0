//! A signed 256-bit integer ([`Wide`]) and the integer types grid
//! coordinates are held in ([`GridInt`]): the exact arithmetic of the
//! baker's texel-space geometry (`bake`), where products of two
//! coordinates need up to 2 x 101 bits.

use core::cmp::Ordering;
use core::ops::{Add, Mul, Shl, Shr, Sub};

/// A signed 256-bit integer, enough for the product of two coordinates
/// below `2^126` plus a sum of two such products. Ordered as integers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Wide {
    hi: i128,
    lo: u128,
}

impl Ord for Wide {
    fn cmp(&self, other: &Self) -> Ordering {
        self.hi.cmp(&other.hi).then(self.lo.cmp(&other.lo))
    }
}

impl PartialOrd for Wide {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Wide {
    #[inline]
    fn from_i128(x: i128) -> Wide {
        Wide {
            hi: if x < 0 { -1 } else { 0 },
            lo: x as u128,
        }
    }

    /// The exact product `a * b`.
    #[inline]
    pub(crate) fn mul(a: i128, b: i128) -> Wide {
        // Most products of a bake fit in 128 bits (coordinates near the
        // texture's scale); the 4-limb path is the general case.
        const SMALL: i128 = 1 << 62;
        if (-SMALL..SMALL).contains(&a) && (-SMALL..SMALL).contains(&b) {
            return Wide::from_i128(a * b);
        }
        let negative = (a < 0) != (b < 0);
        let (x, y) = (a.unsigned_abs(), b.unsigned_abs());
        let (x1, x0) = (x >> 64, x & u128::from(u64::MAX));
        let (y1, y0) = (y >> 64, y & u128::from(u64::MAX));
        let p00 = x0 * y0;
        let p01 = x0 * y1;
        let p10 = x1 * y0;
        let p11 = x1 * y1;
        // Sum the middle terms with their carries into the high half.
        let (mid, carry_mid) = p01.overflowing_add(p10);
        let (lo, carry_lo) = p00.overflowing_add(mid << 64);
        let hi = p11 + (mid >> 64) + (u128::from(carry_mid) << 64) + u128::from(carry_lo);
        let magnitude = Wide { hi: hi as i128, lo };
        if negative {
            magnitude.neg()
        } else {
            magnitude
        }
    }

    #[inline]
    fn neg(self) -> Wide {
        let lo = (!self.lo).wrapping_add(1);
        let hi = (!self.hi).wrapping_add(i128::from(lo == 0));
        Wide { hi, lo }
    }

    /// `self + other`; exact while the sum stays below `2^254` in
    /// magnitude, which products of coordinates below `2^126` guarantee.
    #[inline]
    pub(crate) fn add(self, other: Wide) -> Wide {
        let (lo, carry) = self.lo.overflowing_add(other.lo);
        Wide {
            hi: self
                .hi
                .wrapping_add(other.hi)
                .wrapping_add(i128::from(carry)),
            lo,
        }
    }
}

/// An integer type grid coordinates are held in: `i64` where a bound
/// checked by the caller keeps every value it forms in range (the common
/// case, and much cheaper: a bake's coordinates are small), `i128`
/// otherwise. Every operation is the exact integer one in either type.
pub(crate) trait GridInt:
    Copy
    + Send
    + Sync
    + Ord
    + From<u32>
    + Into<i128>
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Shl<u32, Output = Self>
    + Shr<u32, Output = Self>
{
}

impl<T> GridInt for T where
    T: Copy
        + Send
        + Sync
        + Ord
        + From<u32>
        + Into<i128>
        + Add<Output = T>
        + Sub<Output = T>
        + Mul<Output = T>
        + Shl<u32, Output = T>
        + Shr<u32, Output = T>
{
}

impl Default for Wide {
    fn default() -> Wide {
        Wide::from_i128(0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wide_products_match_i128_where_they_fit_and_big_ones_compare() {
        let values = [
            0i128,
            1,
            -1,
            (1 << 62) - 1,
            -(1 << 62),
            1 << 62,
            (1 << 100) + 12345,
            -(1 << 100) - 7,
            (1 << 63) + 1,
        ];
        for &a in &values {
            for &b in &values {
                if let Some(p) = a.checked_mul(b) {
                    assert_eq!(Wide::mul(a, b), Wide::from_i128(p), "{a} * {b}");
                }
                // Sign and order agree with a split computation.
                let w = Wide::mul(a, b);
                let zero = Wide::from_i128(0);
                assert_eq!(w.cmp(&zero), (a.signum() * b.signum()).cmp(&0), "{a} * {b}");
                assert_eq!(w.add(w.neg()), zero);
            }
        }
        // (2^100 + 1)^2 = 2^200 + 2^101 + 1 > 2^200.
        let big = Wide::mul((1 << 100) + 1, (1 << 100) + 1);
        let p200 = Wide::mul(1 << 100, 1 << 100);
        assert!(big > p200);
        assert_eq!(big.add(p200.neg()), Wide::from_i128((1 << 101) + 1));
        assert!(p200.neg() < Wide::from_i128(i128::MIN));
    }
}
