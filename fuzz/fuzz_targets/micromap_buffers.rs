//! Micromap API buffers read from any bytes: no panic, accepted buffers are
//! consistent and survive a rebuild
//! (`micromap_index_lab::fuzzing::micromap_buffers`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| micromap_index_lab::fuzzing::micromap_buffers(data));
