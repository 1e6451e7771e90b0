//! index -> micro-triangle -> points -> index
//! (`micromap_index_lab::fuzzing::inverse_round_trip`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| micromap_index_lab::fuzzing::inverse_round_trip(data));
