//! Micromap API buffers read from any bytes: no panic, accepted buffers are
//! consistent and survive a rebuild
//! (`micromap_index::micromap::fuzz_body::micromap_buffers`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| micromap_index::micromap::fuzz_body::micromap_buffers(data));
