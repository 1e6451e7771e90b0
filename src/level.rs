//! Subdivision levels, validated once by their type.

use crate::Error;
use core::fmt;

/// A level type: a `u8` below a maximum, made only by `new`, which checks it.
/// Written once for both [`Level`] and [`SpecLevel`].
macro_rules! level_type {
    ($(#[$doc:meta])* $name:ident, max: $max:expr, $max_doc:literal) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub struct $name(pub(crate) u8);

        impl $name {
            #[doc = $max_doc]
            pub const MAX: u32 = $max;

            #[doc = concat!("A level, or [`Error::LevelTooHigh`] above [`", stringify!($name), "::MAX`].")]
            #[inline]
            pub const fn new(level: u32) -> Result<$name, Error> {
                if level > Self::MAX {
                    Err(Error::LevelTooHigh {
                        level,
                        max: Self::MAX,
                    })
                } else {
                    Ok($name(level as u8))
                }
            }

            /// The level as a number.
            #[inline]
            #[must_use]
            pub const fn get(self) -> u32 {
                self.0 as u32
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                self.0.fmt(f)
            }
        }
    };
}

level_type!(
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
    Level,
    max: 32,
    "The highest level any function in this crate accepts."
);

impl Level {
    /// The number of micro-triangles, `4^level`.
    #[inline]
    #[must_use]
    pub const fn micro_triangle_count(self) -> u128 {
        1u128 << (2 * self.0 as u32)
    }
}

level_type!(
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
    SpecLevel,
    max: 16,
    "The highest level the 32-bit reference computes valid indices for."
);

impl SpecLevel {
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
