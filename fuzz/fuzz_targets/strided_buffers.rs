//! Micromap API buffers read at record and index strides from the input:
//! no panic, refused strides exactly as `ReadOptions::check_strides`, and
//! buffers re-laid at allowed strides read as the tight ones
//! (`micromap_index_lab::fuzzing::strided_buffers`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| micromap_index_lab::fuzzing::strided_buffers(data));
