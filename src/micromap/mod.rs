//! Opacity micromaps as data: states, formats, special indices.

#[cfg(feature = "alloc")]
mod map;
mod state;

#[cfg(feature = "alloc")]
pub use map::{MergeRule, Micromap, MicromapError, UnknownPolicy};
pub use state::{Format, State};
