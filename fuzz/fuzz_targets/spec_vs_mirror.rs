//! `spec::index_f32` = `fixed::index_mirror_f32` = the C reference, bit for
//! bit, on any `f32` pair and level (decoding: `micromap_index_lab::fuzzing::spec_vs_mirror`).
#![no_main]

use libfuzzer_sys::fuzz_target;
use micromap_index_lab::fuzzing;
use micromap_index_c_reference::spec_index;

fuzz_target!(|data: &[u8]| {
    fuzzing::spec_vs_mirror(data).assert_agrees("the C reference", spec_index);
});
