//! Data and helpers shared by the integration tests (not a test target
//! itself); each test uses a part.
#![allow(dead_code)]

pub mod cli;

/// Faces per kind where the talk's version 1 differs from the reference,
/// levels 0..=10: (vertex, horizontal edge, vertical edge, diagonal edge).
/// Version 1 never differs inside a micro-triangle. `tests/lattice.rs`
/// finds these by walking every face directly, `tests/prove.rs` with the
/// prover's descent; one table keeps the two enumerations held to the same
/// numbers.
pub const VERSION1_MISMATCHES: [(u32, [u64; 4]); 11] = [
    (0, [0, 0, 0, 0]),
    (1, [0, 0, 0, 0]),
    (2, [2, 1, 1, 1]),
    (3, [14, 8, 8, 8]),
    (4, [72, 44, 44, 44]),
    (5, [328, 208, 208, 208]),
    (6, [1408, 912, 912, 912]),
    (7, [5856, 3840, 3840, 3840]),
    (8, [23936, 15808, 15808, 15808]),
    (9, [96896, 64256, 64256, 64256]),
    (10, [390144, 259328, 259328, 259328]),
];
