//! A mesh bake under work budgets: no panic, budgets kept, cut triangles
//! counted, every bake sound (`micromap_index_lab::fuzzing::bake_budgets`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| micromap_index_lab::fuzzing::bake_budgets(data));
