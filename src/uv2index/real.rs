//! The walk over exact rationals (feature `exact`).

use super::index;
use crate::num::rational::{over_common_denominator, BigShared, SmallRational};
use crate::{Error, Level};
use num_rational::BigRational;

/// The walk over exact rationals: the paper's algorithm over the reals.
///
/// Runs on `i128` numerators over one common denominator when both
/// coordinates fit below `2^64`, on big-integer numerators over one common
/// denominator otherwise: each step costs a few big-integer additions and
/// shifts, so the time grows with the inputs' digits times the level, never
/// with repeated gcds. (The all-[`BigRational`] walk is kept as a test
/// oracle.)
///
/// ```
/// use micromap_index::{uv2index, Level, Error, Outside};
/// use num_rational::BigRational;
/// let r = |s: &str| s.parse::<BigRational>().unwrap();
/// let level = Level::new(32).unwrap();
/// assert_eq!(uv2index::index_real(&r("0"), &r("0"), level), Ok(0));
/// assert_eq!(uv2index::index_real(&r("3/10"), &r("3/10"), Level::new(2).unwrap()), Ok(5));
/// assert_eq!(
///     uv2index::index_real(&r("2/3"), &r("1/2"), level),
///     Err(Error::OutsideTriangle { reason: Outside::SumAboveOne })
/// );
/// ```
pub fn index_real(u: &BigRational, v: &BigRational, level: Level) -> Result<u64, Error> {
    if let Some((u, v, denominator)) = over_common_denominator(u, v) {
        index(
            SmallRational::new(u, denominator),
            SmallRational::new(v, denominator),
            level,
        )
    } else {
        let (u, v) = BigShared::pair(u, v);
        index(u, v, level)
    }
}

unstable_pub_fn! {
    /// [`index_real`] computed entirely on [`BigRational`]: the slow, obviously
    /// exact twin.
    fn index_real_ref(u: &BigRational, v: &BigRational, level: Level) -> Result<u64, Error> {
        index(u.clone(), v.clone(), level)
    }
}
