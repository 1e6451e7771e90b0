//! `batch::index_f32` / `wide_index_f32` on every backend against the scalar
//! port (`spec::reference_bits_f32`, `spec::wide_index_f32`) and the C
//! reference, and the scalar entry points built on the same kernel
//! (`spec::index_f32`, `batch::index_f32_one`) against the port:
//! arbitrary bit patterns (proptest), every pair of a structured set (NaN
//! payloads, ±0, ±inf, subnormals, lattice lines and their neighbours,
//! values outside `[0, 1]`) at every level, and pairs straddling the
//! binary32 rounding window of `uf + vf`.
//!
//! `backend_tests!` stamps the same tests on each backend. A backend this
//! CPU cannot run is checked to refuse with `BackendUnavailable` (and says
//! so on stderr); `every_available_backend_is_covered` fails if a backend
//! exists that the macro did not stamp.

use micromap_index::batch::{self, Backend, BatchError};
use micromap_index::spec;
use micromap_index::{Level, SpecLevel};
use micromap_index_c_reference::spec_index;
use micromap_index_test_support::{edge_values, step_ulps, SplitMix64};
use proptest::prelude::*;
use std::io::Write;

/// Pairs `(u, v) = (fu, fv) * 2^-level` whose fractions `fu + fv` straddle
/// `1 - 2^-25`, where binary32 rounding decides the reference's diagonal test.
fn rounding_window(level: u32) -> (Vec<f32>, Vec<f32>) {
    let scale = 2f32.powi(-(level as i32));
    let mut u = Vec::new();
    let mut v = Vec::new();
    for base in [0.5f32, 0.25, 0.75, 0.125, 1.0 - 2f32.powi(-24)] {
        let partner = (1.0 - f64::from(base) - 2f64.powi(-25)) as f32;
        for du in -2i32..=2 {
            for dv in -3i32..=3 {
                let (fu, fv) = (step_ulps(base, du), step_ulps(partner, dv));
                u.push(fu * scale);
                v.push(fv * scale);
            }
        }
    }
    (u, v)
}

/// Runs `backend` on the slices; `None` if the backend is not available here
/// (after checking that it refuses with the right error).
fn run_narrow(backend: Backend, u: &[f32], v: &[f32], level: u32) -> Option<Vec<u32>> {
    let mut out = vec![0u32; u.len()];
    let result = batch::index_f32_with(backend, u, v, SpecLevel::new(level).unwrap(), &mut out);
    if backend.is_available() {
        result.unwrap();
        Some(out)
    } else {
        assert_eq!(result, Err(BatchError::BackendUnavailable(backend)));
        None
    }
}

fn run_wide(backend: Backend, u: &[f32], v: &[f32], level: u32) -> Option<Vec<u64>> {
    let mut out = vec![0u64; u.len()];
    let result = batch::wide_index_f32_with(backend, u, v, Level::new(level).unwrap(), &mut out);
    if backend.is_available() {
        result.unwrap();
        Some(out)
    } else {
        assert_eq!(result, Err(BatchError::BackendUnavailable(backend)));
        None
    }
}

/// Asserts that the batch results equal the scalar port, element by
/// element, printing the bits of the first mismatch.
fn assert_narrow(backend: Backend, u: &[f32], v: &[f32], level: u32) -> bool {
    let Some(out) = run_narrow(backend, u, v, level) else {
        return false;
    };
    for (i, &got) in out.iter().enumerate() {
        let expected = spec::reference_bits_f32(u[i], v[i], level);
        assert_eq!(
            got,
            expected,
            "{backend}: u = {:#010x}, v = {:#010x}, level {level}: batch {got} != spec {expected}",
            u[i].to_bits(),
            v[i].to_bits()
        );
        let lvl = SpecLevel::new(level).unwrap();
        for (name, scalar) in [
            ("spec::index_f32", spec::index_f32(u[i], v[i], lvl)),
            (
                "batch::index_f32_one",
                batch::index_f32_one(u[i], v[i], lvl),
            ),
        ] {
            assert_eq!(
                scalar,
                expected,
                "{name}: u = {:#010x}, v = {:#010x}, level {level}: {scalar} != port {expected}",
                u[i].to_bits(),
                v[i].to_bits()
            );
        }
    }
    true
}

fn assert_wide(backend: Backend, u: &[f32], v: &[f32], level: u32) -> bool {
    let Some(out) = run_wide(backend, u, v, level) else {
        return false;
    };
    let lvl = Level::new(level).unwrap();
    for (i, &got) in out.iter().enumerate() {
        let expected = spec::wide_index_f32(u[i], v[i], lvl);
        assert_eq!(
            got,
            expected,
            "{backend}: u = {:#010x}, v = {:#010x}, level {level}: batch wide {got} != spec {expected}",
            u[i].to_bits(),
            v[i].to_bits()
        );
    }
    true
}

fn note_skipped(backend: Backend) {
    let _ = writeln!(
        std::io::stderr(),
        "skipped: the {backend} backend is not available on this CPU (checked that it refuses)"
    );
}

/// All pairs of the structured values, as two slices.
fn all_pairs(values: &[f32]) -> (Vec<f32>, Vec<f32>) {
    let mut u = Vec::with_capacity(values.len() * values.len());
    let mut v = Vec::with_capacity(values.len() * values.len());
    for &a in values {
        for &b in values {
            u.push(a);
            v.push(b);
        }
    }
    (u, v)
}

macro_rules! backend_tests {
    ($($name:ident => $backend:expr),* $(,)?) => {
        /// The backends the macro stamped tests on.
        const COVERED: &[Backend] = &[$($backend),*];

        $(
            mod $name {
                use super::*;

                const BACKEND: Backend = $backend;

                #[test]
                fn structured_pairs_every_level() {
                    let (u, v) = all_pairs(&edge_values());
                    for level in 0..=16 {
                        if !assert_narrow(BACKEND, &u, &v, level) {
                            return note_skipped(BACKEND);
                        }
                    }
                    for level in 0..=32 {
                        assert_wide(BACKEND, &u, &v, level);
                    }
                }

                #[test]
                fn rounding_window_every_level() {
                    for level in 0..=16 {
                        let (u, v) = rounding_window(level);
                        if !assert_narrow(BACKEND, &u, &v, level) {
                            return note_skipped(BACKEND);
                        }
                    }
                    for level in 0..=32 {
                        let (u, v) = rounding_window(level);
                        assert_wide(BACKEND, &u, &v, level);
                    }
                }

                #[test]
                fn agrees_with_the_c_reference() {
                    let (u, v) = all_pairs(&edge_values());
                    for level in 0..=16 {
                        let Some(out) = run_narrow(BACKEND, &u, &v, level) else {
                            return note_skipped(BACKEND);
                        };
                        for (i, &got) in out.iter().enumerate() {
                            let c = spec_index(u[i], v[i], level);
                            assert_eq!(
                                got, c,
                                "{BACKEND}: u = {:#010x}, v = {:#010x}, level {level}: batch {got} != C {c}",
                                u[i].to_bits(), v[i].to_bits()
                            );
                        }
                    }
                }

                /// Every length from 0 to past two chunks of the kernel
                /// (256 points): full chunks, a padded last chunk and a
                /// short tail run point by point, both forms.
                #[test]
                fn every_length_around_the_chunks() {
                    let values = edge_values();
                    let mut rng = SplitMix64::new(0x2545_f491_4f6c_dd1d);
                    let mut next = move || rng.next_u64();
                    for len in (0..=530).chain([767, 768, 769, 1000]) {
                        let level = (next() % 17) as u32;
                        let mut pick = || {
                            let r = next();
                            if r % 3 == 0 {
                                values[(r >> 8) as usize % values.len()]
                            } else {
                                f32::from_bits((r >> 16) as u32 % 0x3f80_0001)
                            }
                        };
                        let u: Vec<f32> = (0..len).map(|_| pick()).collect();
                        let v: Vec<f32> = (0..len).map(|_| pick()).collect();
                        if !assert_narrow(BACKEND, &u, &v, level) {
                            return note_skipped(BACKEND);
                        }
                        assert_wide(BACKEND, &u, &v, (next() % 33) as u32);
                    }
                }

                proptest! {
                    #![proptest_config(ProptestConfig::with_cases(256))]

                    #[test]
                    fn arbitrary_bits(
                        bits in prop::collection::vec((any::<u32>(), any::<u32>()), 0..100),
                        level in 0u32..=16,
                        wide_level in 0u32..=32,
                    ) {
                        let u: Vec<f32> = bits.iter().map(|p| f32::from_bits(p.0)).collect();
                        let v: Vec<f32> = bits.iter().map(|p| f32::from_bits(p.1)).collect();
                        assert_narrow(BACKEND, &u, &v, level);
                        assert_wide(BACKEND, &u, &v, wide_level);
                        if let Some(out) = run_narrow(BACKEND, &u, &v, level) {
                            for i in 0..u.len() {
                                prop_assert_eq!(out[i], spec_index(u[i], v[i], level));
                            }
                        }
                    }

                    #[test]
                    fn unit_square(
                        points in prop::collection::vec((0f32..=1.0, 0f32..=1.0), 0..100),
                        level in 0u32..=16,
                        wide_level in 0u32..=32,
                    ) {
                        let u: Vec<f32> = points.iter().map(|p| p.0).collect();
                        let v: Vec<f32> = points.iter().map(|p| p.1).collect();
                        assert_narrow(BACKEND, &u, &v, level);
                        assert_wide(BACKEND, &u, &v, wide_level);
                    }

                    #[test]
                    fn near_lattice_lines(
                        cells in prop::collection::vec((any::<u32>(), any::<u32>(), -4i32..=4, -4i32..=4), 1..64),
                        level in 0u32..=16,
                    ) {
                        // k / 2^level moved by a few ulps: the lines the cell and
                        // diagonal decisions turn on.
                        let scale = 2f32.powi(-(level as i32));
                        let nudge = |k: u32, steps: i32| {
                            let x = (k % ((1 << level) + 1)) as f32 * scale;
                            step_ulps(x, steps)
                        };
                        let u: Vec<f32> = cells.iter().map(|c| nudge(c.0, c.2)).collect();
                        let v: Vec<f32> = cells.iter().map(|c| nudge(c.1, c.3)).collect();
                        assert_narrow(BACKEND, &u, &v, level);
                        assert_wide(BACKEND, &u, &v, level);
                    }
                }
            }
        )*
    };
}

backend_tests!(
    portable => Backend::Portable,
    avx2 => Backend::Avx2,
    avx512 => Backend::Avx512,
);

#[test]
fn every_available_backend_is_covered() {
    for backend in Backend::ALL {
        assert!(
            COVERED.contains(&backend),
            "backend {backend} has no tests: add it to backend_tests!"
        );
    }
    let available: Vec<Backend> = Backend::available().collect();
    let _ = writeln!(
        std::io::stderr(),
        "batch backends available on this CPU: {available:?} (best: {})",
        Backend::best()
    );
    assert!(available.contains(&Backend::best()));
}

#[test]
fn errors_write_nothing() {
    let mut out = [7u32; 2];
    let level = SpecLevel::new(3).unwrap();
    assert_eq!(
        batch::index_f32(&[0.5, 0.5], &[0.5], level, &mut out),
        Err(BatchError::LengthMismatch { u: 2, v: 1, out: 2 })
    );
    assert_eq!(
        batch::index_f32(&[0.5], &[0.5, 0.1], level, &mut out),
        Err(BatchError::LengthMismatch { u: 1, v: 2, out: 2 })
    );
    assert_eq!(out, [7, 7]);
    let mut wide = [7u64; 1];
    assert_eq!(
        batch::wide_index_f32(&[0.5], &[0.5], level.level(), &mut wide[..0]),
        Err(BatchError::LengthMismatch { u: 1, v: 1, out: 0 })
    );
    assert_eq!(wide, [7]);
    // Empty slices are fine.
    assert_eq!(batch::index_f32(&[], &[], level, &mut []), Ok(()));
}

proptest! {
    #[test]
    fn one_point_entries_equal_the_port(u in any::<u32>(), v in any::<u32>(), level in 0u32..=16) {
        let (u, v) = (f32::from_bits(u), f32::from_bits(v));
        let port = spec::reference_bits_f32(u, v, level);
        let level = SpecLevel::new(level).unwrap();
        prop_assert_eq!(batch::index_f32_one(u, v, level), port);
        prop_assert_eq!(spec::index_f32(u, v, level), port);
    }
}
