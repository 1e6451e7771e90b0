//! The TRIS.json reader on any bytes: no panic, what it accepts reads back
//! bit for bit (`micromap_index_lab::fuzzing::triangles_json`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| micromap_index_lab::fuzzing::triangles_json(data));
