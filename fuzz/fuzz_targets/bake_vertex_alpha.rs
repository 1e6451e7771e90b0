//! A mesh with vertex alpha read per part (linear filtering by value): no
//! panic, each triangle baked alone as in its mesh, every known state
//! holding at sampled points, the verifier finding it sound
//! (`micromap_index_lab::fuzzing::bake_vertex_alpha`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| micromap_index_lab::fuzzing::bake_vertex_alpha(data));
