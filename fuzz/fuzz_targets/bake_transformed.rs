//! A bake of transformed texture coordinates: no panic, refusals exact,
//! no known state the binary32 shader oracle contradicts
//! (`micromap_index_lab::fuzzing::bake_transformed`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| micromap_index_lab::fuzzing::bake_transformed(data));
