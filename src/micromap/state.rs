//! Micro-triangle states, micromap formats and special indices, with the
//! values the Vulkan (`VK_EXT_opacity_micromap`, `VK_KHR_opacity_micromap`)
//! and DXR 1.2 APIs give them.

use core::fmt;

/// The opacity state of one micro-triangle, with its API value.
///
/// Vulkan's `VkOpacityMicromapSpecialIndexEXT` and DXR's
/// `D3D12_RAYTRACING_OPACITY_MICROMAP_STATE` use the same numbers: a 2-state
/// micromap stores only the low bit (0 or 1), a 4-state micromap all four.
///
/// ```
/// use micromap_index::micromap::State;
/// assert_eq!(State::from_bits(3), Some(State::UnknownOpaque));
/// assert_eq!(State::Opaque.bits(), 1);
/// assert_eq!(State::UnknownTransparent.special_index(), -3);
/// assert_eq!(State::from_bits(4), None);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(u8)]
pub enum State {
    /// Transparent (0): the hit is ignored.
    Transparent = 0,
    /// Opaque (1): the hit is accepted.
    Opaque = 1,
    /// Unknown, transparent when the any-hit shader is skipped (2).
    UnknownTransparent = 2,
    /// Unknown, opaque when the any-hit shader is skipped (3).
    UnknownOpaque = 3,
}

impl State {
    /// Every state, in the order of its value.
    pub const ALL: [State; 4] = [
        State::Transparent,
        State::Opaque,
        State::UnknownTransparent,
        State::UnknownOpaque,
    ];

    /// The state with API value `bits`, or `None` above 3.
    #[inline]
    #[must_use]
    pub const fn from_bits(bits: u8) -> Option<State> {
        match bits {
            0 => Some(State::Transparent),
            1 => Some(State::Opaque),
            2 => Some(State::UnknownTransparent),
            3 => Some(State::UnknownOpaque),
            _ => None,
        }
    }

    /// The API value, 0..=3.
    #[inline]
    #[must_use]
    pub const fn bits(self) -> u8 {
        self as u8
    }

    /// Whether the state is known: transparent or opaque.
    #[inline]
    #[must_use]
    pub const fn is_known(self) -> bool {
        (self as u8) < 2
    }

    /// The special index that marks a whole triangle as this state without
    /// micromap data: `-(state + 1)`, so -1 transparent, -2 opaque,
    /// -3 unknown-transparent, -4 unknown-opaque (Vulkan
    /// `VK_OPACITY_MICROMAP_SPECIAL_INDEX_*`, DXR
    /// `D3D12_RAYTRACING_OPACITY_MICROMAP_SPECIAL_INDEX_*`).
    #[inline]
    #[must_use]
    pub const fn special_index(self) -> i32 {
        -(self as i32) - 1
    }

    /// The state a special index stands for, or `None` unless `index` is in
    /// `-4..=-1`.
    ///
    /// ```
    /// use micromap_index::micromap::State;
    /// assert_eq!(State::from_special_index(-2), Some(State::Opaque));
    /// assert_eq!(State::from_special_index(0), None);
    /// ```
    #[inline]
    #[must_use]
    pub const fn from_special_index(index: i32) -> Option<State> {
        match index {
            -4..=-1 => State::from_bits((-index - 1) as u8),
            _ => None,
        }
    }

    /// The state a 2-state micromap can hold for this one: an unknown state
    /// becomes the known state it falls back to (unknown-transparent →
    /// transparent, unknown-opaque → opaque), the rule of the APIs' "force
    /// 2-state" override and of the OMM SDK.
    #[inline]
    #[must_use]
    pub const fn to_two_state(self) -> State {
        match self {
            State::Transparent | State::UnknownTransparent => State::Transparent,
            State::Opaque | State::UnknownOpaque => State::Opaque,
        }
    }
}

impl fmt::Display for State {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            State::Transparent => "transparent",
            State::Opaque => "opaque",
            State::UnknownTransparent => "unknown-transparent",
            State::UnknownOpaque => "unknown-opaque",
        })
    }
}

/// A micromap's format: how many bits each micro-triangle's state takes.
///
/// The values are Vulkan's `VkOpacityMicromapFormatEXT` and DXR's
/// `D3D12_RAYTRACING_OPACITY_MICROMAP_FORMAT`, the `format` field of a
/// triangle record.
///
/// ```
/// use micromap_index::micromap::Format;
/// assert_eq!(Format::from_raw(2), Some(Format::FourState));
/// assert_eq!(Format::TwoState.bits_per_state(), 1);
/// assert_eq!(Format::from_raw(0), None);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(u16)]
pub enum Format {
    /// One bit per micro-triangle: transparent (0) or opaque (1).
    TwoState = 1,
    /// Two bits per micro-triangle: any [`State`].
    FourState = 2,
}

impl Format {
    /// The format with API value `raw`, or `None` unless it is 1 or 2.
    #[inline]
    #[must_use]
    pub const fn from_raw(raw: u16) -> Option<Format> {
        match raw {
            1 => Some(Format::TwoState),
            2 => Some(Format::FourState),
            _ => None,
        }
    }

    /// The API value (1 or 2).
    #[inline]
    #[must_use]
    pub const fn raw(self) -> u16 {
        self as u16
    }

    /// Bits per micro-triangle: 1 or 2.
    #[inline]
    #[must_use]
    pub const fn bits_per_state(self) -> u32 {
        self as u32
    }

    /// Whether this format can hold `state` (a 2-state micromap holds only
    /// the known states).
    #[inline]
    #[must_use]
    pub const fn holds(self, state: State) -> bool {
        matches!(self, Format::FourState) || state.is_known()
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Format::TwoState => "2-state",
            Format::FourState => "4-state",
        })
    }
}

impl core::str::FromStr for Format {
    type Err = crate::names::ParseNameError;

    /// `2` or `4`, its number of states (the CLI's `--format`); `Display`
    /// writes `2-state` / `4-state`.
    ///
    /// ```
    /// use micromap_index::micromap::Format;
    /// assert_eq!("4".parse(), Ok(Format::FourState));
    /// assert_eq!(Format::TwoState.states(), 2);
    /// assert_eq!("3".parse::<Format>().unwrap_err().to_string(), "expected 2 or 4");
    /// ```
    fn from_str(text: &str) -> Result<Format, Self::Err> {
        match text {
            "2" => Ok(Format::TwoState),
            "4" => Ok(Format::FourState),
            _ => Err(crate::names::ParseNameError::new("format", "2 or 4")),
        }
    }
}

impl Format {
    /// Its number of states: 2 or 4 (what [`FromStr`](core::str::FromStr)
    /// reads).
    #[must_use]
    pub const fn states(self) -> u32 {
        match self {
            Format::TwoState => 2,
            Format::FourState => 4,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn special_indices_round_trip_and_match_the_api_values() {
        let api = [-1, -2, -3, -4];
        for (state, want) in State::ALL.into_iter().zip(api) {
            assert_eq!(state.special_index(), want, "{state}");
            assert_eq!(State::from_special_index(want), Some(state));
            assert_eq!(State::from_bits(state.bits()), Some(state));
        }
        for bad in [-5, 0, 1, i32::MIN, i32::MAX] {
            assert_eq!(State::from_special_index(bad), None, "{bad}");
        }
    }

    #[test]
    fn two_state_format_holds_known_states_only() {
        for state in State::ALL {
            assert_eq!(Format::TwoState.holds(state), state.is_known());
            assert!(Format::FourState.holds(state));
            assert!(Format::TwoState.holds(state.to_two_state()));
        }
    }
}
