//! What the `micromap-index` command (`crates/cli`) and the lab's
//! `micromap-lab` binary (`crates/lab`) share, so that both parse, print,
//! fail and write the same way: the flag tables ([`args`]), the output layer
//! and exit codes ([`output`]), bounded input ([`input`]) and all-or-nothing
//! output directories ([`write_all_or_nothing`]); with feature `testing`,
//! the spawn helpers of both binaries' integration tests ([`testing`]).
//!
//! Nothing here knows which program runs: each binary passes its
//! [`output::Program`] (its name, which every message on stderr starts
//! with, and its usage text after a usage error) to what reports.
#![forbid(unsafe_code)]

pub mod args;
mod dir_lock;
pub mod input;
pub mod output;
#[cfg(feature = "testing")]
pub mod testing;
pub mod write_all_or_nothing;
