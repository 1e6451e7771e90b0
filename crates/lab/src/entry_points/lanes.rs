//! The x86-64 SIMD lanes (`src/arch/x86_64.rs`: the `simd_lanes!` macro
//! stamped for SSE2, AVX2 and AVX-512, the chunked loops of
//! `batch::index_f32` and `batch::wide_index_f32` on x86-64) compute what
//! the proved kernel computes, in two parts:
//!
//! * **Structure, from the source users run.** Everything from `macro_rules!
//!   simd_lanes` up to the file's tests (the lanes' bodies, the
//!   `sse2_ops` / `avx2_ops` / `avx512_ops` name lists with `pack_u16` and
//!   `order_for_unpack`, the three stampings, the `feature_loop!` entry
//!   points and the probe below) is cut from the source the lab was built
//!   with (`include_str!`), split into tokens as [`super::fold`] does
//!   (comments and whitespace dropped) and compared with the model
//!   (`x86_64_model.txt`, the same code with every statement's meaning in
//!   scalar terms as comments). Any changed, inserted, deleted or reordered
//!   token is refused with its source line until the model is updated.
//! * **Semantics, by running the intrinsics.** The model reads each
//!   intrinsic by Intel's documented per-lane operation; those readings are
//!   checked on the machine, on every backend this CPU runs (the others
//!   are named as SKIPPED), through `micromap_index::internals::lanes`
//!   (each backend's own lane methods, or one step of them with their
//!   intrinsics and constant operands, compiled with its features), every
//!   lane of a vector holding a different input, on every core:
//!   - the clamp `min_ps(max_ps(x, 2^-126), 1 - 2^-24)` at all `2^32` bit
//!     patterns equals the proved `clamp_flushed` (Intel: `MAX(a, b) = a >
//!     b ? a : b`, `MIN(a, b) = a < b ? a : b`, the second operand on NaN);
//!   - `mul_ps` by `Params::new(level).scale` at every clamped input (every
//!     binary32 in `[2^-126, 1 - 2^-24]`) and level `0..=16` is the exact
//!     product `x 2^level` (its exponent raised by `level`);
//!   - `cvttps_epi32` at every binary32 in `[0, 2^16)` (every product, and
//!     every diagonal sum, which is below 2) is `floor(x)`: on the sums in
//!     `[0, 2)` that is `x >= 1`;
//!   - `sub_ps(x, cvtepi32_ps(cvttps_epi32(x)))` at the same inputs is
//!     exactly `x - floor(x)` (compared in binary64);
//!   - `pack_u16` on every value `0..2^16` in every lane keeps the value and
//!     puts lane `l` of each 128-bit lane of the first vector before those
//!     of the second (distinct values in every lane fix the movement);
//!   - `cells` then `interleave` on tagged cells write every point's index
//!     back to its own position (the pack's order undone);
//!   - `interleave` on every pair of bytes at every byte position of every
//!     position of a chunk (`2^16` chunks, each with distinct 16-bit words
//!     at every position) equals `kernel::word::interleave_16`, its index
//!     written where `cells` took the point from: `pairs` works on each
//!     16-bit word (the model), so it is checked on all `2^16` words at
//!     every word of every vector, and the unpacks' data movement, which
//!     does not depend on the values, is fixed by the distinct words;
//!   - `wide_interleave` the same way (four bytes per point) equals
//!     `kernel::word::interleave_32`, points in order.
//!
//!   The one operation not run exhaustively is the diagonal's two-operand
//!   `add_ps`: the documented assumption is that it is IEEE 754 binary32
//!   addition rounding to nearest even under the default MXCSR, which is
//!   Rust's `+` on `f32`, the operation lemma 4 of
//!   `crates/lab/certificates/lemmas.py` is about.
//!
//! With the structure, those readings make `cells` the kernel's float first
//! half (`clamp_flushed`, the exact multiply, `truncate_float`'s cell and
//! fraction, `uf + vf >= 1.0f`) and the interleaves the proved
//! `interleave_16` / `interleave_32` (`docs/verification.md` 10.12).

use super::fold::{first_difference, occurrences, tokenize, Token};
use std::fmt;

/// The source of `src/arch/x86_64.rs` this lab was built with.
pub(super) const SOURCE: &str = include_str!("../../../../src/arch/x86_64.rs");

/// The model: the modelled region's code, every statement read in scalar
/// terms in its comments.
const MODEL: &str = include_str!("x86_64_model.txt");

/// The instruction sets of the x86-64 lanes, as [`LanesProof`] names them.
pub(super) const INSTRUCTION_SETS: [&str; 3] = ["SSE2", "AVX2", "AVX-512"];

/// Where the modelled region starts (`macro_rules! simd_lanes`).
const START: [&str; 3] = ["macro_rules", "!", "simd_lanes"];
/// Where it ends (not included): the file's unit tests.
const END: [&str; 9] = ["#", "[", "cfg", "(", "test", ")", "]", "mod", "tests"];

/// Where the source departs from the model.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LanesMismatch {
    /// The source line (1-based) of the first differing token, or of the
    /// region's end when the source is shorter; 0 when the region cannot
    /// be cut out.
    pub line: usize,
    /// What was expected and what was found there.
    pub detail: String,
}

impl fmt::Display for LanesMismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "the SIMD lanes are not the modelled code (src/arch/x86_64.rs line {}): {}",
            self.line, self.detail
        )
    }
}

/// Checks the structure of a source text against the model; the number of
/// tokens compared.
///
/// # Errors
/// The first token where the source departs from the model.
pub fn check_lanes_source(source: &str) -> Result<usize, LanesMismatch> {
    let tokens = tokenize(source).map_err(|(line, why)| LanesMismatch {
        line,
        detail: format!("the source cannot be split into tokens: {why}"),
    })?;
    let expected = tokenize(MODEL).expect("the model tokenizes");
    let found = cut_region(&tokens).map_err(|detail| LanesMismatch { line: 0, detail })?;
    if let Some((line, detail)) = first_difference(&expected, found) {
        return Err(LanesMismatch { line, detail });
    }
    Ok(found.len())
}

/// The tokens from [`START`] up to [`END`], each of which must occur once.
fn cut_region(tokens: &[Token]) -> Result<&[Token], String> {
    let find = |marker: &[&str]| -> Result<usize, String> {
        let at = occurrences(tokens, marker);
        match at.as_slice() {
            &[i] => Ok(i),
            _ => Err(format!(
                "{} occurrences of `{}` found, expected 1",
                at.len(),
                marker.join(" ")
            )),
        }
    };
    let (start, end) = (find(&START)?, find(&END)?);
    if end < start {
        return Err("the tests precede `macro_rules! simd_lanes`".to_owned());
    }
    Ok(&tokens[start..end])
}

/// A lane input where an intrinsic departs from the model's reading.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LanesCounterexample {
    /// The instruction set (`SSE2`, `AVX2`, `AVX-512`).
    pub backend: &'static str,
    /// The check (the step and its reading).
    pub check: String,
    /// The input, the result and the expected result.
    pub detail: String,
}

impl fmt::Display for LanesCounterexample {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "the {} lanes: {} fails: {}",
            self.backend, self.check, self.detail
        )
    }
}

/// Why the SIMD lanes are not proved.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum LanesError {
    /// The source is not the model.
    Structure(LanesMismatch),
    /// An intrinsic is not what the model reads.
    Semantics(LanesCounterexample),
}

impl fmt::Display for LanesError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LanesError::Structure(e) => e.fmt(f),
            LanesError::Semantics(e) => e.fmt(f),
        }
    }
}

/// What was proved.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LanesProof {
    /// Tokens of `src/arch/x86_64.rs` compared with the model.
    pub tokens: usize,
    /// The instruction sets whose intrinsics were run.
    pub checked: Vec<&'static str>,
    /// The instruction sets this CPU or build does not run: their
    /// structure is checked, their intrinsics are not.
    pub skipped: Vec<&'static str>,
    /// Lane inputs checked per instruction set.
    pub inputs: u64,
}

/// Checks the structure and, on every backend this CPU runs, the
/// semantics (module comment).
///
/// # Errors
/// The first departure from the model.
pub fn prove_simd_lanes() -> Result<LanesProof, LanesError> {
    let tokens = check_lanes_source(SOURCE).map_err(LanesError::Structure)?;
    #[cfg(target_arch = "x86_64")]
    {
        use micromap_index::batch::Backend;
        use micromap_index::internals::lanes::LaneProbe;
        let probes: Vec<LaneProbe> = Backend::ALL
            .into_iter()
            .filter_map(LaneProbe::new)
            .collect();
        let skipped = INSTRUCTION_SETS
            .into_iter()
            .filter(|name| probes.iter().all(|p| p.name() != *name))
            .collect();
        let backends: Vec<&dyn LaneBackend> =
            probes.iter().map(|p| p as &dyn LaneBackend).collect();
        let inputs = check_semantics(&backends, &Coverage::FULL).map_err(LanesError::Semantics)?;
        Ok(LanesProof {
            tokens,
            checked: probes.iter().map(LaneProbe::name).collect(),
            skipped,
            inputs,
        })
    }
    #[cfg(not(target_arch = "x86_64"))]
    Ok(LanesProof {
        tokens,
        checked: Vec::new(),
        skipped: INSTRUCTION_SETS.to_vec(),
        inputs: 0,
    })
}

#[cfg(target_arch = "x86_64")]
pub use semantics::*;

#[cfg(target_arch = "x86_64")]
mod semantics {
    use super::LanesCounterexample;
    use micromap_index::internals::kernel::{
        clamp_flushed, interleave_16, interleave_32, Cells, Halves, CHUNK,
    };
    use micromap_index::internals::lanes::{LaneProbe, Step, BLOCK};
    use std::ops::Range;

    /// What the semantic checks run: a backend's lanes (the real ones,
    /// [`LaneProbe`], or a test's changed copy).
    pub trait LaneBackend: Sync {
        /// The instruction set's name.
        fn name(&self) -> &'static str;
        /// 32-bit lanes per vector.
        fn lanes(&self) -> usize;
        /// [`LaneProbe::step`].
        fn step(&self, step: Step, x: &[u32; BLOCK], out: &mut [u32; BLOCK]);
        /// [`LaneProbe::pack`].
        fn pack(&self, a: &[u32; 16], b: &[u32; 16], out: &mut [u16; 32]);
        /// [`LaneProbe::cells`].
        fn cells(&self, u: &[f32; CHUNK], v: &[f32; CHUNK], level: u32, cells: &mut Cells<u16>);
        /// [`LaneProbe::interleave`].
        fn interleave(&self, halves: &Halves<u16>, out: &mut [u32; CHUNK]);
        /// [`LaneProbe::wide_interleave`].
        fn wide_interleave(&self, halves: &Halves<u32>, out: &mut [u64; CHUNK]);
    }

    impl LaneBackend for LaneProbe {
        fn name(&self) -> &'static str {
            LaneProbe::name(self)
        }
        fn lanes(&self) -> usize {
            LaneProbe::lanes(self)
        }
        fn step(&self, step: Step, x: &[u32; BLOCK], out: &mut [u32; BLOCK]) {
            LaneProbe::step(self, step, x, out);
        }
        fn pack(&self, a: &[u32; 16], b: &[u32; 16], out: &mut [u16; 32]) {
            LaneProbe::pack(self, a, b, out);
        }
        fn cells(&self, u: &[f32; CHUNK], v: &[f32; CHUNK], level: u32, cells: &mut Cells<u16>) {
            LaneProbe::cells(self, u, v, level, cells);
        }
        fn interleave(&self, halves: &Halves<u16>, out: &mut [u32; CHUNK]) {
            LaneProbe::interleave(self, halves, out);
        }
        fn wide_interleave(&self, halves: &Halves<u32>, out: &mut [u64; CHUNK]) {
            LaneProbe::wide_interleave(self, halves, out);
        }
    }

    /// The inputs the semantic checks cover (the tests narrow them).
    #[derive(Clone, Debug, PartialEq, Eq)]
    pub struct Coverage {
        /// Bit patterns for the clamp.
        pub clamp: Range<u64>,
        /// Bit patterns of clamped inputs for the multiply.
        pub scale: Range<u64>,
        /// Levels of the multiply.
        pub levels: Range<u32>,
        /// Bit patterns for the truncation and the fraction.
        pub truncate: Range<u64>,
        /// Calls of the narrow interleave (`2^16`, each on `CHUNK` points).
        pub interleave: Range<u64>,
    }

    impl Coverage {
        /// Everything the module comment states.
        pub const FULL: Coverage = Coverage {
            clamp: 0..1 << 32,
            // [2^-126, 1 - 2^-24]: every value the clamp leaves.
            scale: 0x0080_0000..0x3f80_0000,
            levels: 0..17,
            // [0, 2^16): every product and every diagonal sum.
            truncate: 0..0x4780_0000,
            interleave: 0..1 << 16,
        };
    }

    /// A failure at a unit of a range (the smallest is reported).
    type Failure = (u64, LanesCounterexample);

    fn failure(backend: &dyn LaneBackend, check: &str, detail: String) -> LanesCounterexample {
        LanesCounterexample {
            backend: backend.name(),
            check: check.to_owned(),
            detail,
        }
    }

    /// Runs `check` on `range` split across the available cores (in
    /// pieces that are multiples of `granule`); the failure at the
    /// smallest unit.
    fn on_every_core(
        range: Range<u64>,
        granule: u64,
        check: &(impl Fn(Range<u64>) -> Option<Failure> + Sync),
    ) -> Option<Failure> {
        let threads = std::thread::available_parallelism().map_or(1, usize::from) as u64;
        let share = (range.end - range.start)
            .div_ceil(threads)
            .div_ceil(granule)
            * granule;
        std::thread::scope(|scope| {
            let workers: Vec<_> = (0..threads)
                .map(|t| {
                    let start = (range.start + t * share).min(range.end);
                    let end = (start + share).min(range.end);
                    scope.spawn(move || check(start..end))
                })
                .collect();
            workers
                .into_iter()
                .filter_map(|worker| worker.join().expect("a checking thread panicked"))
                .min_by_key(|(unit, _)| *unit)
        })
    }

    /// Every check of the module comment on every backend; lane inputs
    /// checked per backend.
    ///
    /// # Errors
    /// The first input where a backend departs from the model's reading.
    pub fn check_semantics(
        backends: &[&dyn LaneBackend],
        coverage: &Coverage,
    ) -> Result<u64, LanesCounterexample> {
        let mut inputs = 0;
        for check in [
            check_clamp,
            check_scale,
            check_truncate,
            check_pack,
            check_pipeline_order,
            check_interleave,
            check_wide_interleave,
        ] {
            inputs += check(backends, coverage)?;
        }
        Ok(inputs)
    }

    /// Blocks of `BLOCK` consecutive bit patterns from `range` (a multiple
    /// of `BLOCK` long): `body(first pattern, the block)`.
    fn blocks(
        range: Range<u64>,
        mut body: impl FnMut(u64, &[u32; BLOCK]) -> Option<Failure>,
    ) -> Option<Failure> {
        let mut x = [0u32; BLOCK];
        let mut base = range.start;
        while base < range.end {
            for (i, x) in x.iter_mut().enumerate() {
                *x = (base + i as u64) as u32;
            }
            if let Some(failed) = body(base, &x) {
                return Some(failed);
            }
            base += BLOCK as u64;
        }
        None
    }

    /// The first element where `got` and `expected` differ.
    fn first_difference<T: PartialEq>(got: &[T], expected: &[T]) -> Option<usize> {
        if got == expected {
            return None;
        }
        got.iter().zip(expected).position(|(g, e)| g != e)
    }

    fn show(bits: u32) -> String {
        format!("{bits:#010x} ({:e})", f32::from_bits(bits))
    }

    /// The clamp is `clamp_flushed` at every bit pattern.
    fn check_clamp(
        backends: &[&dyn LaneBackend],
        coverage: &Coverage,
    ) -> Result<u64, LanesCounterexample> {
        const CHECK: &str = "the clamp min_ps(max_ps(x, 2^-126), 1 - 2^-24) = clamp_flushed(x)";
        let failed = on_every_core(coverage.clamp.clone(), BLOCK as u64, &|range| {
            let (mut expected, mut out) = ([0u32; BLOCK], [0u32; BLOCK]);
            blocks(range, |base, x| {
                for (e, &x) in expected.iter_mut().zip(x) {
                    *e = clamp_flushed(x).to_bits();
                }
                for backend in backends {
                    backend.step(Step::Clamp, x, &mut out);
                    if let Some(i) = first_difference(&out, &expected) {
                        let detail = format!(
                            "at {}: {} instead of {}",
                            show(x[i]),
                            show(out[i]),
                            show(expected[i])
                        );
                        return Some((base + i as u64, failure(*backend, CHECK, detail)));
                    }
                }
                None
            })
        });
        failed.map_or(Ok(coverage.clamp.end - coverage.clamp.start), |(_, e)| {
            Err(e)
        })
    }

    /// The multiply by each level's scale is exact: the exponent raised by
    /// `level`.
    fn check_scale(
        backends: &[&dyn LaneBackend],
        coverage: &Coverage,
    ) -> Result<u64, LanesCounterexample> {
        let levels = coverage.levels.clone();
        let failed = on_every_core(coverage.scale.clone(), BLOCK as u64, &|range| {
            let mut out = [0u32; BLOCK];
            blocks(range, |base, x| {
                for level in levels.clone() {
                    // The exact product of a normal by 2^level below 2^16:
                    // its bits with the exponent raised by `level`.
                    let exponent = level << 23;
                    for backend in backends {
                        backend.step(Step::Scale(level), x, &mut out);
                        let differ = out
                            .iter()
                            .zip(x)
                            .fold(0, |differ, (&out, &x)| differ | (out ^ (x + exponent)));
                        if differ != 0 {
                            let i = (0..BLOCK).find(|&i| out[i] != x[i] + exponent).unwrap_or(0);
                            let check = format!("mul_ps(x, 2^{level}) = x 2^{level} exactly");
                            let detail = format!(
                                "at {}: {} instead of {}",
                                show(x[i]),
                                show(out[i]),
                                show(x[i] + exponent)
                            );
                            return Some((base + i as u64, failure(*backend, &check, detail)));
                        }
                    }
                }
                None
            })
        });
        let per_level = coverage.scale.end - coverage.scale.start;
        failed.map_or(
            Ok(per_level * u64::from(levels.end - levels.start)),
            |(_, e)| Err(e),
        )
    }

    /// The truncation is `floor(x)` and the fraction exactly `x - floor(x)`
    /// at every binary32 in `[0, 2^16)`. The exact fraction is computed in
    /// binary64 (both operands have at most 24 significant bits and lie
    /// below `2^16`: exact) and must be a binary32, which is then compared
    /// bit for bit with every backend's.
    fn check_truncate(
        backends: &[&dyn LaneBackend],
        coverage: &Coverage,
    ) -> Result<u64, LanesCounterexample> {
        const FRACTION: &str = "sub_ps(x, cvtepi32_ps(cvttps_epi32(x))) = x - floor(x) exactly";
        let failed = on_every_core(coverage.truncate.clone(), BLOCK as u64, &|range| {
            let (mut floor, mut fraction, mut out) = ([0u32; BLOCK], [0u32; BLOCK], [0u32; BLOCK]);
            blocks(range, |base, x| {
                let mut representable = true;
                for ((floor, fraction), &x) in floor.iter_mut().zip(&mut fraction).zip(x) {
                    // Truncation of a non-negative value below 2^16: floor.
                    let fu = f32::from_bits(x);
                    *floor = fu as u32;
                    let exact = f64::from(fu) - f64::from(*floor);
                    *fraction = (exact as f32).to_bits();
                    representable &= f64::from(exact as f32) == exact;
                }
                if !representable {
                    let i = (0..BLOCK)
                        .find(|&i| {
                            f64::from(f32::from_bits(fraction[i]))
                                != f64::from(f32::from_bits(x[i])) - f64::from(floor[i])
                        })
                        .unwrap_or(0);
                    let detail = format!("at {}: x - floor(x) is not a binary32", show(x[i]));
                    return Some((base + i as u64, failure(backends[0], FRACTION, detail)));
                }
                for backend in backends {
                    backend.step(Step::Truncate, x, &mut out);
                    if let Some(i) = first_difference(&out, &floor) {
                        let detail = format!(
                            "at {}: {} instead of {}",
                            show(x[i]),
                            out[i] as i32,
                            floor[i]
                        );
                        return Some((
                            base + i as u64,
                            failure(*backend, "cvttps_epi32(x) = floor(x)", detail),
                        ));
                    }
                    backend.step(Step::Fraction, x, &mut out);
                    if let Some(i) = first_difference(&out, &fraction) {
                        let detail = format!(
                            "at {}: {} instead of {}",
                            show(x[i]),
                            show(out[i]),
                            show(fraction[i])
                        );
                        return Some((base + i as u64, failure(*backend, FRACTION, detail)));
                    }
                }
                None
            })
        });
        failed.map_or(
            Ok(2 * (coverage.truncate.end - coverage.truncate.start)),
            |(_, e)| Err(e),
        )
    }

    /// Where `pack_u16(a, b)` takes its 16-bit word `word` from: per
    /// 128-bit lane, the first vector's four lanes then the second's
    /// (whether from the second, and the lane).
    fn packed_from(word: usize) -> (bool, usize) {
        let (group, within) = (word / 8, word % 8);
        (within >= 4, group * 4 + within % 4)
    }

    /// The point whose cells `cells` stores at position `at` of a chunk
    /// (two vectors of `lanes` points packed, per 128-bit lane the first
    /// vector's four then the second's), which is
    /// where `interleave` must write the index of the halves at `at`.
    #[must_use]
    pub fn point_at(lanes: usize, at: usize) -> usize {
        let within = at % (2 * lanes);
        let (second, lane) = packed_from(within);
        at - within + usize::from(second) * lanes + lane
    }

    /// `pack_u16` keeps every value `0..2^16` in every lane and moves the
    /// lanes as [`packed_from`] says.
    fn check_pack(backends: &[&dyn LaneBackend], _: &Coverage) -> Result<u64, LanesCounterexample> {
        let (mut a, mut b, mut out) = ([0u32; 16], [0u32; 16], [0u16; 32]);
        for backend in backends {
            let lanes = backend.lanes();
            for j in 0..1u32 << 16 {
                for l in 0..16 {
                    a[l] = (j + 4099 * l as u32) & 0xffff;
                    b[l] = (j + 4099 * (l as u32 + 16)) & 0xffff;
                }
                backend.pack(&a, &b, &mut out);
                for (word, &got) in out.iter().enumerate().take(2 * lanes) {
                    let (second, lane) = packed_from(word);
                    let expected = if second { b[lane] } else { a[lane] };
                    if u32::from(got) != expected {
                        let detail = format!(
                            "word {word} is {got:#06x}, expected lane {lane} of the {} vector, {expected:#06x}",
                            if second { "second" } else { "first" }
                        );
                        return Err(failure(
                            *backend,
                            "pack_u16 keeps the values in the modelled order",
                            detail,
                        ));
                    }
                }
            }
        }
        Ok(1 << 16)
    }

    /// The lanes' `cells` at level 16 on points whose cells are distinct
    /// tags, then their `interleave` of those cells: every point's index
    /// at its own position (and the diagonal outcomes likewise).
    fn check_pipeline_order(
        backends: &[&dyn LaneBackend],
        _: &Coverage,
    ) -> Result<u64, LanesCounterexample> {
        let tag_u = |k: usize| (k * 251 + 7) as u32 & 0xffff;
        let tag_v = |k: usize| (65_535 - k * 257) as u32;
        let (mut u, mut v) = ([0f32; CHUNK], [0f32; CHUNK]);
        for k in 0..CHUNK {
            // Fractions 1/2 and, on every third point, 1/2 again: a sum of 1.
            let fv = if k % 3 == 0 { 0.5 } else { 0.25 };
            u[k] = (tag_u(k) as f32 + 0.5) / 65_536.0;
            v[k] = (tag_v(k) as f32 + fv) / 65_536.0;
        }
        let mut cells = Cells {
            iu: [0; CHUNK],
            iv: [0; CHUNK],
            diagonal: [0; CHUNK],
        };
        let mut out = [0u32; CHUNK];
        for backend in backends {
            backend.cells(&u, &v, 16, &mut cells);
            let halves = Halves {
                b0: cells.iu,
                b1: cells.iv,
            };
            backend.interleave(&halves, &mut out);
            for (k, &got) in out.iter().enumerate() {
                let expected = interleave_16(tag_u(k), tag_v(k));
                if got != expected {
                    let detail = format!("point {k}: {got:#010x} instead of {expected:#010x}");
                    return Err(failure(
                        *backend,
                        "cells then interleave keep every point's place",
                        detail,
                    ));
                }
            }
            let halves = Halves {
                b0: cells.diagonal,
                b1: [0; CHUNK],
            };
            backend.interleave(&halves, &mut out);
            for (k, &got) in out.iter().enumerate() {
                let expected = interleave_16(u32::from(k % 3 == 0), 0);
                if got != expected {
                    let detail = format!("point {k}: {got:#x} instead of {expected:#x}");
                    return Err(failure(
                        *backend,
                        "cells' diagonal then interleave keep every point's place",
                        detail,
                    ));
                }
            }
        }
        Ok(CHUNK as u64)
    }

    /// The narrow interleave: in call `j`, byte `w` (0 or 1) of position
    /// `k`'s `b0` is `j + t` and of its `b1` is `(j >> 8) + (t >> 8)` (mod
    /// 256), `t = 2k + w`: every pair of bytes at every byte position of
    /// every position (so `pairs` at every word of every vector on all
    /// `2^16` words), the words of each call distinct (so the data
    /// movement is fixed). The index of the halves at position `k` belongs
    /// at [`point_at`]`(k)`, the point whose cells `cells` put at `k`.
    fn check_interleave(
        backends: &[&dyn LaneBackend],
        coverage: &Coverage,
    ) -> Result<u64, LanesCounterexample> {
        let failed = on_every_core(coverage.interleave.clone(), 1, &|range| {
            let mut halves = Halves {
                b0: [0u16; CHUNK],
                b1: [0u16; CHUNK],
            };
            let mut out = [0u32; CHUNK];
            let orders: Vec<Vec<usize>> = backends
                .iter()
                .map(|backend| (0..CHUNK).map(|k| point_at(backend.lanes(), k)).collect())
                .collect();
            for j in range {
                for k in 0..CHUNK {
                    let (mut b0, mut b1) = (0u16, 0u16);
                    for w in 0..2 {
                        let t = 2 * k as u64 + w;
                        b0 |= (((j + t) & 0xff) as u16) << (8 * w);
                        b1 |= ((((j >> 8) + (t >> 8)) & 0xff) as u16) << (8 * w);
                    }
                    halves.b0[k] = b0;
                    halves.b1[k] = b1;
                }
                for (backend, order) in backends.iter().zip(&orders) {
                    backend.interleave(&halves, &mut out);
                    for k in 0..CHUNK {
                        let expected =
                            interleave_16(u32::from(halves.b0[k]), u32::from(halves.b1[k]));
                        if out[order[k]] != expected {
                            let detail = format!(
                                "b0 = {:#06x}, b1 = {:#06x} at position {k}: {:#010x} at point {} instead of {expected:#010x}",
                                halves.b0[k], halves.b1[k], out[order[k]], order[k]
                            );
                            return Some((
                                j,
                                failure(*backend, "interleave = interleave_16", detail),
                            ));
                        }
                    }
                }
            }
            None
        });
        let calls = coverage.interleave.end - coverage.interleave.start;
        failed.map_or(Ok(calls * CHUNK as u64), |(_, e)| Err(e))
    }

    /// The wide interleave: in chunk `j`, byte `w` of point `k`'s `b0` is
    /// `j + t` and of its `b1` is `(j >> 8) + (t >> 8)` (mod 256), with
    /// `t = 4k + w`: every pair of bytes at every byte position of every
    /// point, and the words of each chunk distinct.
    fn check_wide_interleave(
        backends: &[&dyn LaneBackend],
        _: &Coverage,
    ) -> Result<u64, LanesCounterexample> {
        let failed = on_every_core(0..1 << 16, 1, &|range| {
            let mut halves = Halves {
                b0: [0u32; CHUNK],
                b1: [0u32; CHUNK],
            };
            let (mut expected, mut out) = ([0u64; CHUNK], [0u64; CHUNK]);
            for j in range {
                for (k, expected) in expected.iter_mut().enumerate() {
                    let (mut b0, mut b1) = (0u32, 0u32);
                    for w in 0..4 {
                        let t = 4 * k as u64 + w;
                        b0 |= (((j + t) & 0xff) as u32) << (8 * w);
                        b1 |= ((((j >> 8) + (t >> 8)) & 0xff) as u32) << (8 * w);
                    }
                    halves.b0[k] = b0;
                    halves.b1[k] = b1;
                    let (low, high) = interleave_32(b0, b1);
                    *expected = u64::from(low) | u64::from(high) << 32;
                }
                for backend in backends {
                    backend.wide_interleave(&halves, &mut out);
                    if let Some(k) = first_difference(&out, &expected) {
                        let detail = format!(
                            "b0 = {:#010x}, b1 = {:#010x} at point {k}: {:#018x} instead of {:#018x}",
                            halves.b0[k], halves.b1[k], out[k], expected[k]
                        );
                        return Some((
                            j,
                            failure(*backend, "wide_interleave = interleave_32", detail),
                        ));
                    }
                }
            }
            None
        });
        failed.map_or(Ok((1 << 16) * CHUNK as u64), |(_, e)| Err(e))
    }
}
