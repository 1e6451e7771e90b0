//! `spec::index_f32` = `fixed::index_mirror_f32` = the C reference, bit for
//! bit, on any `f32` pair and level (decoding: `micromap_index::fuzzing::spec_vs_mirror`).
#![no_main]

use libfuzzer_sys::fuzz_target;
use micromap_index::fuzzing;
use micromap_index_c_reference::spec_index;

fuzz_target!(|data: &[u8]| {
    let case = fuzzing::spec_vs_mirror(data);
    let by_c = spec_index(case.u, case.v, case.level);
    assert_eq!(
        case.index,
        by_c,
        "spec::index_f32 = {} but the C reference = {by_c} at {}",
        case.index,
        case.describe()
    );
});
