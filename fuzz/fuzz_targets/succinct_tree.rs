//! The succinct-tree readers and encoders on any bytes: no panic, checked
//! bytes round-trip, both layouts agree with the flat micromap
//! (`micromap_index_lab::fuzzing::succinct_tree`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| micromap_index_lab::fuzzing::succinct_tree(data));
