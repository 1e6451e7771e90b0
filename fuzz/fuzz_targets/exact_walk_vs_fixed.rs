//! The exact walk on BigRational = its fast path = the fixed-point engine on
//! finite floats, levels 0..=32 (`micromap_index_lab::fuzzing::exact_walk_vs_fixed`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| micromap_index_lab::fuzzing::exact_walk_vs_fixed(data));
