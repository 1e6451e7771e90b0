//! The PNG and JPEG alpha reader on any bytes: no panic, limits kept,
//! `width * height` texels (`micromap_index_lab::fuzzing::alpha_image`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| micromap_index_lab::fuzzing::alpha_image(data));
