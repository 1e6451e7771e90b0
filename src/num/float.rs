//! [`WalkNumber`] for `f32` and `f64`: each operation rounds as the type
//! does, and the triangle test is decided exactly.

use super::{check_finite, check_signs, WalkNumber};
use crate::Error;
use core::cmp::Ordering;

macro_rules! impl_walk_number_for_float {
    ($float:ty, $exact_sum_above_one:expr) => {
        impl WalkNumber for $float {
            fn one_minus_sum(u: &Self, v: &Self) -> Self {
                1.0 - (u + v)
            }
            fn twice(&self) -> Self {
                2.0 * self
            }
            fn plus(&self, other: &Self) -> Self {
                self + other
            }
            fn minus(&self, other: &Self) -> Self {
                self - other
            }
            fn cmp_half(&self) -> Ordering {
                self.partial_cmp(&0.5).unwrap_or(Ordering::Less)
            }
            fn check_point(u: &Self, v: &Self) -> Result<(), Error> {
                check_finite(f64::from(*u), f64::from(*v))?;
                let sum_above_one: fn($float, $float) -> bool = $exact_sum_above_one;
                let above = if sum_above_one(*u, *v) {
                    Ordering::Greater
                } else {
                    Ordering::Equal
                };
                check_signs(u.sign(), v.sign(), above)
            }
        }
    };
}

/// Sign of a finite float against zero (`-0.0` counts as zero).
trait SignOfFinite {
    fn sign(&self) -> Ordering;
}

impl SignOfFinite for f32 {
    fn sign(&self) -> Ordering {
        self.partial_cmp(&0.0).unwrap_or(Ordering::Equal)
    }
}

impl SignOfFinite for f64 {
    fn sign(&self) -> Ordering {
        self.partial_cmp(&0.0).unwrap_or(Ordering::Equal)
    }
}

// f32 -> f64 is exact, and the two-sum decides the f64 sum exactly.
impl_walk_number_for_float!(f32, |u, v| sum_above_one_f64(f64::from(u), f64::from(v)));
impl_walk_number_for_float!(f64, sum_above_one_f64);

/// `u + v > 1` decided exactly for finite `u`, `v`: the rounded sum plus its
/// exact rounding error (Knuth's two-sum, exact in round-to-nearest when the
/// sum does not overflow, which it cannot once the sum is compared to 1:
/// an overflowing sum is `inf > 1` either way).
fn sum_above_one_f64(u: f64, v: f64) -> bool {
    let sum = u + v;
    let v_part = sum - u;
    let u_part = sum - v_part;
    let error = (u - u_part) + (v - v_part);
    sum > 1.0 || (sum == 1.0 && error > 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Outside;

    #[test]
    fn exact_sum_test_catches_rounding() {
        // 0.5 + (0.5 + 2^-53) rounds to 1.0 in f64 but is above 1.
        let v = 0.5 + 2f64.powi(-53);
        assert!(sum_above_one_f64(0.5, v));
        assert!(!sum_above_one_f64(0.5, 0.5));
        let tiny = 2f64.powi(-80);
        assert!(sum_above_one_f64(1.0, tiny));
        assert!(!sum_above_one_f64(1.0 - 2f64.powi(-53), tiny));
        assert_eq!(
            f64::check_point(&1.0, &tiny),
            Err(Error::OutsideTriangle {
                reason: Outside::SumAboveOne
            })
        );
        assert_eq!(f32::check_point(&-0.0, &1.0), Ok(()));
        assert_eq!(
            f32::check_point(&1.0, &f32::from_bits(1)),
            Err(Error::OutsideTriangle {
                reason: Outside::SumAboveOne
            })
        );
    }
}
