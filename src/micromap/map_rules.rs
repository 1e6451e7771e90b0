//! The rules a micromap's conversions follow: what an unknown state becomes
//! in 2 states ([`UnknownPolicy`]) and how four children merge into their
//! parent ([`MergeRule`]).

use super::state::State;
use crate::names::named_enum;

/// How [`Micromap::to_format`](crate::micromap::Micromap::to_format) turns an unknown state into a known one when
/// it converts a 4-state micromap to 2 states.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum UnknownPolicy {
    /// Each unknown state becomes the state it falls back to
    /// ([`State::to_two_state`]): unknown-transparent → transparent,
    /// unknown-opaque → opaque. This is what the hardware does under the
    /// APIs' "force 2-state" ray and instance flags, so a converted map
    /// answers exactly as the 4-state one does with any-hit shaders skipped.
    #[default]
    Fallback,
    /// Every unknown state becomes opaque (shadows never leak; holes close).
    Opaque,
    /// Every unknown state becomes transparent (holes never close).
    Transparent,
}

named_enum!(
    UnknownPolicy,
    "unknown policy",
    "fallback, opaque or transparent",
    [
        (Fallback, "fallback"),
        (Opaque, "opaque"),
        (Transparent, "transparent"),
    ]
);

impl UnknownPolicy {
    /// The known state `state` becomes under this policy (known states stay).
    ///
    /// ```
    /// use micromap_index::micromap::{State, UnknownPolicy};
    /// assert_eq!(UnknownPolicy::Fallback.resolve(State::UnknownTransparent), State::Transparent);
    /// assert_eq!(UnknownPolicy::Opaque.resolve(State::UnknownTransparent), State::Opaque);
    /// assert_eq!(UnknownPolicy::Transparent.resolve(State::Opaque), State::Opaque);
    /// ```
    #[inline]
    #[must_use]
    pub const fn resolve(self, state: State) -> State {
        if state.is_known() {
            return state;
        }
        match self {
            UnknownPolicy::Fallback => state.to_two_state(),
            UnknownPolicy::Opaque => State::Opaque,
            UnknownPolicy::Transparent => State::Transparent,
        }
    }
}

/// How [`Micromap::merge_one_level`](crate::micromap::Micromap::merge_one_level) combines four children that are not
/// all equal. Four equal children always keep their state (the paper's
/// lossless merge of a uniform quadrant); the rules differ only on mixed
/// children.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum MergeRule {
    /// Mixed children become unknown-opaque if any child is opaque or
    /// unknown-opaque, else unknown-transparent. The parent is unknown, so an
    /// any-hit shader still decides every hit exactly; the choice only
    /// matters where any-hit is skipped, and then a parent covering any
    /// opaque part falls back to opaque (no light leaks through geometry that
    /// was partly opaque), while a parent over only transparent and
    /// unknown-transparent children keeps their common fallback.
    #[default]
    Conservative,
    /// Mixed children become unknown-opaque: the rule of the OMM SDK's
    /// one-level downsampling (which also turns four equal *unknown* children
    /// into unknown-opaque; this rule keeps them, like every rule here).
    UnknownOpaque,
}

impl MergeRule {
    /// The parent state of four children at the next finer level.
    ///
    /// ```
    /// use micromap_index::micromap::{MergeRule, State::*};
    /// assert_eq!(MergeRule::Conservative.merge([Opaque; 4]), Opaque);
    /// assert_eq!(MergeRule::Conservative.merge([Transparent, Transparent, Transparent, UnknownTransparent]), UnknownTransparent);
    /// assert_eq!(MergeRule::Conservative.merge([Transparent, Transparent, Transparent, Opaque]), UnknownOpaque);
    /// assert_eq!(MergeRule::UnknownOpaque.merge([Transparent, UnknownTransparent, Transparent, Transparent]), UnknownOpaque);
    /// ```
    #[inline]
    #[must_use]
    pub const fn merge(self, children: [State; 4]) -> State {
        let [a, b, c, d] = children;
        let (a, b, c, d) = (a as u8, b as u8, c as u8, d as u8);
        if a == b && b == c && c == d {
            // Equal children keep their state; `from_bits` of a state's bits
            // is always `Some`.
            return children[0];
        }
        match self {
            MergeRule::Conservative => {
                // Opaque (1) and unknown-opaque (3) have the low bit set.
                if (a | b | c | d) & 1 == 1 {
                    State::UnknownOpaque
                } else {
                    State::UnknownTransparent
                }
            }
            MergeRule::UnknownOpaque => State::UnknownOpaque,
        }
    }
}
