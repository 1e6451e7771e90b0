//! Why a [`Micromap`](super::Micromap) could not be built, read or changed.

use super::state::{Format, State};
use core::fmt;

/// What went wrong building, reading or changing a [`Micromap`](crate::micromap::Micromap).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum MicromapError {
    /// The level is above [`Micromap::MAX_LEVEL`](crate::micromap::Micromap::MAX_LEVEL).
    LevelTooHigh {
        /// The level asked for.
        level: u32,
        /// The highest level supported.
        max: u32,
    },
    /// A micro-triangle index is not below `4^level`.
    IndexOutOfRange {
        /// The index asked for.
        index: u64,
        /// The number of micro-triangles, `4^level`.
        len: u64,
    },
    /// A 2-state micromap cannot hold an unknown state.
    StateNotInFormat {
        /// The state that was offered.
        state: State,
        /// The micromap's format.
        format: Format,
    },
    /// [`Micromap::from_states`](crate::micromap::Micromap::from_states) got fewer states than `4^level`.
    TooFewStates {
        /// `4^level`.
        expected: u64,
        /// How many came.
        got: u64,
    },
    /// [`Micromap::from_states`](crate::micromap::Micromap::from_states) got more than `4^level` states.
    TooManyStates {
        /// `4^level`.
        expected: u64,
    },
    /// Packed bytes have the wrong length for the level and format.
    WrongByteLength {
        /// [`Micromap::byte_len`](crate::micromap::Micromap::byte_len) of the level and format.
        expected: usize,
        /// The length given.
        got: usize,
    },
    /// Packed bytes set bits past the last micro-triangle (only a level-0 or
    /// level-1 2-state map and a level-0 4-state map have such bits).
    UnusedBitsSet {
        /// The byte holding them (always the only byte).
        byte: u8,
    },
    /// The operation needs a coarser level than 0 ([`Micromap::merge_one_level`](crate::micromap::Micromap::merge_one_level)).
    NoCoarserLevel,
    /// The allocator refused the packed data.
    AllocationFailed {
        /// The number of bytes asked for.
        bytes: usize,
    },
}

impl fmt::Display for MicromapError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MicromapError::LevelTooHigh { level, max } => {
                write!(
                    f,
                    "level {level} is too high: micromaps have levels 0..={max}"
                )
            }
            MicromapError::IndexOutOfRange { index, len } => {
                write!(f, "micro-triangle index {index} is out of range 0..{len}")
            }
            MicromapError::StateNotInFormat { state, format } => {
                write!(f, "a {format} micromap cannot hold the state {state}")
            }
            MicromapError::TooFewStates { expected, got } => {
                write!(f, "expected {expected} states, got {got}")
            }
            MicromapError::TooManyStates { expected } => {
                write!(f, "expected {expected} states, got more")
            }
            MicromapError::WrongByteLength { expected, got } => {
                write!(f, "expected {expected} bytes of micromap data, got {got}")
            }
            MicromapError::UnusedBitsSet { byte } => {
                write!(
                    f,
                    "micromap byte {byte:#04x} sets bits past the last micro-triangle"
                )
            }
            MicromapError::NoCoarserLevel => f.write_str("a level-0 micromap has no coarser level"),
            MicromapError::AllocationFailed { bytes } => {
                write!(f, "could not allocate {bytes} bytes of micromap data")
            }
        }
    }
}

impl core::error::Error for MicromapError {}
