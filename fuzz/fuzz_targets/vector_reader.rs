//! The conformance-vector readers on any bytes: no panic, round trips
//! (`micromap_index_lab::fuzzing::vector_reader`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| micromap_index_lab::fuzzing::vector_reader(data));
