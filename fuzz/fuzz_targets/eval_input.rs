//! The CLI's `eval` input path on any bytes: one JSON object line per
//! variant, never a panic (`micromap_index_lab::fuzzing::eval_input`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| micromap_index_lab::fuzzing::eval_input(data));
