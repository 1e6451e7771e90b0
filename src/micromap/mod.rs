//! Opacity micromaps as data: states, formats, special indices.

mod state;

pub use state::{Format, State};
