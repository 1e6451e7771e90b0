//! One spelling for every user-facing enum: the names the CLI's flags, the
//! C API's documentation and the Python keywords use, with `FromStr` and
//! `Display` on the enum itself so that no front end writes a name table
//! of its own.
//!
//! The crate-private macro `named_enum!` implements both for an enum from one list of
//! `(variant, name)` pairs, plus `NAMES` (every name, in the list's order)
//! and `name()`. A rejected name is a [`ParseNameError`], whose message
//! lists what was expected in the same words everywhere:
//!
//! ```
//! # #[cfg(feature = "alloc")] {
//! use micromap_index::bake::{AddressMode, Filter};
//! assert_eq!("linear".parse::<Filter>(), Ok(Filter::Linear));
//! assert_eq!(AddressMode::ClampToEdge.to_string(), "clamp-to-edge");
//! let e = "bilinear".parse::<Filter>().unwrap_err();
//! assert_eq!(e.to_string(), "expected nearest or linear");
//! assert_eq!(e.what(), "filter");
//! # }
//! ```

use core::fmt;

/// A name that is none of an enum's (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ParseNameError {
    what: &'static str,
    expected: &'static str,
}

impl ParseNameError {
    /// The error for a value of `what` (e.g. `"filter"`), whose names are
    /// `expected` written out (e.g. `"nearest or linear"`).
    #[must_use]
    pub const fn new(what: &'static str, expected: &'static str) -> Self {
        ParseNameError { what, expected }
    }

    /// What was being named: `"filter"`, `"address mode"`, ...
    #[must_use]
    pub const fn what(&self) -> &'static str {
        self.what
    }

    /// The accepted names, written out: `"nearest or linear"`.
    #[must_use]
    pub const fn expected(&self) -> &'static str {
        self.expected
    }
}

impl fmt::Display for ParseNameError {
    /// `expected <names>`: front ends put the flag or keyword and the
    /// rejected text before it (`--filter "x": expected nearest or linear`).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "expected {}", self.expected)
    }
}

impl core::error::Error for ParseNameError {}

/// `FromStr`, `Display`, `NAMES` and `name()` for a fieldless enum from
/// one list: `named_enum!(Type, "what", "expected names", [(Variant,
/// "name"), ...]);`. The `expected` text is written by hand (it reads as
/// prose: "a, b or c"); a unit test per enum checks it lists `NAMES`.
#[cfg(feature = "alloc")]
macro_rules! named_enum {
    ($ty:ty, $what:literal, $expected:literal, [$(($variant:ident, $name:literal)),+ $(,)?]) => {
        impl $ty {
            /// Every name, in declaration order (the CLI's, C's and
            /// Python's spelling).
            pub const NAMES: &'static [&'static str] = &[$($name),+];

            /// The value's name (its `Display`).
            #[must_use]
            pub const fn name(self) -> &'static str {
                match self {
                    $(<$ty>::$variant => $name),+
                }
            }
        }

        impl core::str::FromStr for $ty {
            type Err = $crate::names::ParseNameError;

            fn from_str(text: &str) -> Result<Self, Self::Err> {
                match text {
                    $($name => Ok(<$ty>::$variant),)+
                    _ => Err($crate::names::ParseNameError::new($what, $expected)),
                }
            }
        }

        impl core::fmt::Display for $ty {
            fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
                f.write_str(self.name())
            }
        }
    };
}

#[cfg(feature = "alloc")]
pub(crate) use named_enum;

/// Checks that `expected` names every one of `names` (and so that the
/// hand-written prose of [`named_enum!`] stays true).
#[cfg(all(test, feature = "alloc"))]
pub(crate) fn lists_every_name(expected: &str, names: &[&str]) -> bool {
    names.iter().all(|name| {
        expected
            .split([',', ' '])
            .any(|word| word.trim_matches('"') == *name)
    })
}

#[cfg(all(test, feature = "alloc"))]
mod tests {
    use super::lists_every_name;
    use crate::bake::mesh::Mips;
    use crate::bake::{AddressMode, Comparison, Filter, Model};
    use crate::micromap::{Format, UnknownPolicy};
    use core::str::FromStr;

    /// Every name parses back to its value, and the error's prose lists
    /// every name.
    fn round_trips<
        T: FromStr<Err = super::ParseNameError>
            + core::fmt::Display
            + PartialEq
            + core::fmt::Debug
            + Copy,
    >(
        values: &[T],
    ) {
        for &v in values {
            assert_eq!(v.to_string().parse::<T>(), Ok(v));
        }
        let e = "no such name".parse::<T>().unwrap_err();
        let names: alloc::vec::Vec<alloc::string::String> =
            values.iter().map(ToString::to_string).collect();
        let names: alloc::vec::Vec<&str> =
            names.iter().map(alloc::string::String::as_str).collect();
        assert!(lists_every_name(e.expected(), &names), "{e}: {names:?}");
    }

    #[test]
    fn every_enum_round_trips_and_its_error_lists_every_name() {
        round_trips(&[Filter::Nearest, Filter::Linear]);
        round_trips(&AddressMode::ALL);
        round_trips(&[Comparison::AtLeast, Comparison::Above]);
        round_trips(&Model::ALL);
        round_trips(&[
            UnknownPolicy::Fallback,
            UnknownPolicy::Opaque,
            UnknownPolicy::Transparent,
        ]);
        round_trips(&[Mips::Level0, Mips::All]);
        assert_eq!(Filter::NAMES, ["nearest", "linear"]);
        for format in [Format::TwoState, Format::FourState] {
            assert_eq!(format.states().to_string().parse(), Ok(format));
        }
    }
}
