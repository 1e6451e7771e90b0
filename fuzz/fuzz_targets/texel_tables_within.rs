//! The baker's texel tables under a byte limit: built only within it, a
//! typed error otherwise, never an abort
//! (`micromap_index_lab::fuzzing::texel_tables_within`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| micromap_index_lab::fuzzing::texel_tables_within(data));
