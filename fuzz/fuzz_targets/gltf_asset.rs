//! The glTF / GLB reader on any bytes, every URI served a fixed PNG: no
//! panic, limits kept, a consistent asset
//! (`micromap_index_lab::fuzzing::gltf_asset`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| micromap_index_lab::fuzzing::gltf_asset(data));
