//! Subdivision levels.

use crate::Error;
use core::fmt;

/// A subdivision level: the micromap has `4^level` micro-triangles.
///
/// Every level `0..=32` can be represented (the index of a level-32
/// micro-triangle fills a `u64`); functions with a lower limit, such as the
/// Vulkan reference (16), check it themselves and say so in their error.
///
/// ```
/// use micromap_index::{Level, Error};
/// assert_eq!(Level::new(12).unwrap().get(), 12);
/// assert_eq!(Level::new(33), Err(Error::LevelTooHigh { level: 33, max: 32 }));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Level(pub(crate) u8);

impl Level {
    /// The highest level any function in this crate accepts.
    pub const MAX: u32 = 32;

    /// A level, or [`Error::LevelTooHigh`] above [`Level::MAX`].
    #[inline]
    pub const fn new(level: u32) -> Result<Level, Error> {
        if level > Self::MAX {
            Err(Error::LevelTooHigh {
                level,
                max: Self::MAX,
            })
        } else {
            Ok(Level(level as u8))
        }
    }

    /// The level as a number.
    #[inline]
    #[must_use]
    pub const fn get(self) -> u32 {
        self.0 as u32
    }

    /// The number of micro-triangles, `4^level`.
    #[inline]
    #[must_use]
    pub const fn micro_triangle_count(self) -> u128 {
        1u128 << (2 * self.0 as u32)
    }
}

impl fmt::Display for Level {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.fmt(f)
    }
}

/// A level the Vulkan reference computes valid indices for: `0..=16`.
///
/// The reference's prefix-XOR and bit interleave handle 16 bits, so its
/// 32-bit code is wrong from level 17 on. Functions that run the reference
/// in 32-bit words take this type: the level is validated once, where the
/// value is made, and the per-hit functions return a plain index with no
/// `Result` on the hot path. Vulkan devices report at most
/// `maxOpacity2StateSubdivisionLevel` / `maxOpacity4StateSubdivisionLevel`
/// (at least 3 required) and DXR fixes 12, so every level an API accepts fits.
///
/// ```
/// use micromap_index::{Error, Level, SpecLevel};
/// let level = SpecLevel::new(12).unwrap();
/// assert_eq!(level.get(), 12);
/// assert_eq!(Level::from(level), Level::new(12).unwrap());
/// assert_eq!(SpecLevel::new(17), Err(Error::LevelTooHigh { level: 17, max: 16 }));
/// assert_eq!(SpecLevel::try_from(Level::new(20).unwrap()), Err(Error::LevelTooHigh { level: 20, max: 16 }));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct SpecLevel(pub(crate) u8);

impl SpecLevel {
    /// The highest level the 32-bit reference computes valid indices for.
    pub const MAX: u32 = 16;

    /// A level, or [`Error::LevelTooHigh`] above [`SpecLevel::MAX`].
    #[inline]
    pub const fn new(level: u32) -> Result<SpecLevel, Error> {
        if level > Self::MAX {
            Err(Error::LevelTooHigh {
                level,
                max: Self::MAX,
            })
        } else {
            Ok(SpecLevel(level as u8))
        }
    }

    /// The level as a number.
    #[inline]
    #[must_use]
    pub const fn get(self) -> u32 {
        self.0 as u32
    }

    /// The same level as a [`Level`].
    #[inline]
    #[must_use]
    pub const fn level(self) -> Level {
        Level(self.0)
    }
}

impl From<SpecLevel> for Level {
    #[inline]
    fn from(level: SpecLevel) -> Level {
        level.level()
    }
}

impl TryFrom<Level> for SpecLevel {
    type Error = Error;
    #[inline]
    fn try_from(level: Level) -> Result<SpecLevel, Error> {
        SpecLevel::new(level.get())
    }
}

impl fmt::Display for SpecLevel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.fmt(f)
    }
}
