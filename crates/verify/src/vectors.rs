//! Conformance vectors: deterministic test cases for other implementations
//! of the mapping (GPU drivers, shaders, emulation layers, ports), a reader
//! for the files and for another implementation's answers, and the check
//! that compares them.
//!
//! # The sets
//!
//! [`generate_sets`] builds one [`VectorFile`] per [`VectorSet`]:
//!
//! * `spec-f32` — the Vulkan reference in binary32 ([`spec::index_f32`]):
//!   what a GPU must return. Coordinates are binary32 bit patterns
//!   (`"0x3e000000"`), including NaN, ±inf, -0, subnormals and points outside
//!   the triangle.
//! * `spec-exact` — the reference's steps over the reals
//!   ([`spec::index_real`]). Coordinates are exact rationals `"p/q"`: the
//!   finite points of `spec-f32` (so the two sets disagree exactly on the
//!   cases tagged `rounding-window`) and the exact centroids.
//! * `uv2index-exact` — the paper's walk over the reals
//!   ([`uv2index::index_real`]), only on points of the closed triangle (the
//!   walk rejects the others, so the clamping classes are left out). Every
//!   coordinate is also exactly a binary32 value, so float implementations of
//!   the walk can be run on it without rounding their input.
//!
//! Every set covers every level `0..=16`: all lattice faces up to level
//! [`ALL_FACES_MAX_LEVEL`], sampled cells above. Each case carries tags
//! naming its classes (see [`tag`]); `docs/vectors.md` has the schema.
//!
//! ```
//! use micromap_index_verify::vectors::{check, compute_answers, generate_sets, AnswerSource};
//!
//! let sets = generate_sets();
//! let spec_f32 = &sets[0];
//! assert_eq!(spec_f32.function, "spec-f32");
//! // The fixed-point mirror of the GPU passes the binary32 set ...
//! let mirror = AnswerSource::from_name("fixed-mirror").unwrap();
//! assert!(check(spec_f32, &compute_answers(mirror, spec_f32)).passed());
//! // ... the exact reading of the reference does not: binary32 rounding.
//! let exact = AnswerSource::from_name("spec-exact").unwrap();
//! let report = check(spec_f32, &compute_answers(exact, spec_f32));
//! assert!(!report.passed());
//! assert!(report.mismatches.iter().all(|m| m.tags.iter().any(|t| t == "clamp" || t == "rounding-window")));
//! ```

use crate::eval::Variant;
use crate::lattice::FaceKind;
use crate::rng::SplitMix64;
use crate::value::Value;
use micromap_index::uv2index::{self, WalkNumber};
use micromap_index::{spec, Level, SpecLevel};
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::One;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};
use std::fmt;
use std::fmt::Write as _;

/// The `format` field of every vector file.
pub const FORMAT: &str = "micromap-index-vectors";
/// The `version` field this crate writes and reads.
pub const VERSION: u64 = 1;
/// The levels every set covers.
pub const LEVELS: std::ops::RangeInclusive<u32> = 0..=16;
/// Up to this level every face of the lattice is in the sets; above it, the
/// faces of [`sampled_anchors`] cells.
pub const ALL_FACES_MAX_LEVEL: u32 = 3;
/// Pseudo-random anchor cells per sampled level (on top of the fixed ones).
pub const RANDOM_ANCHORS_PER_LEVEL: usize = 6;
/// Uniform random points of the triangle per level.
pub const RANDOM_POINTS_PER_LEVEL: usize = 16;
/// The seed of every pseudo-random choice (mixed with the level and class).
pub const SEED: u64 = 0x6d69_6372_6f6d_6170; // "micromap"

/// The tags a case can carry. A case has one or more; a point that belongs
/// to several classes (a ±1 ulp neighbour of 0 is also subnormal and maybe
/// outside the triangle) carries all of them.
pub mod tag {
    /// A lattice vertex `(a, b) / 2^level`.
    pub const VERTEX: &str = "vertex";
    /// The midpoint of a lattice edge (with one of the three edge tags).
    pub const EDGE_MIDPOINT: &str = "edge-midpoint";
    /// On a line `v = k / 2^level`.
    pub const HORIZONTAL_EDGE: &str = "horizontal-edge";
    /// On a line `u = k / 2^level`.
    pub const VERTICAL_EDGE: &str = "vertical-edge";
    /// On a line `u + v = k / 2^level`.
    pub const DIAGONAL_EDGE: &str = "diagonal-edge";
    /// The centroid of a micro-triangle (exact in `spec-exact`, the nearest
    /// binary32 point elsewhere), with `upright` or `upside-down`.
    pub const CENTROID: &str = "centroid";
    /// A micro-triangle with the right angle at its lower left.
    pub const UPRIGHT: &str = "upright";
    /// A micro-triangle with the right angle at its upper right.
    pub const UPSIDE_DOWN: &str = "upside-down";
    /// One binary32 ulp away from a lattice point, in `u`, `v` or both.
    pub const ULP_NEIGHBOUR: &str = "ulp-neighbour";
    /// ... of a vertex (all 8 directions).
    pub const NEAR_VERTEX: &str = "near-vertex";
    /// ... of a horizontal edge's midpoint (`v` ± 1 ulp).
    pub const NEAR_HORIZONTAL_EDGE: &str = "near-horizontal-edge";
    /// ... of a vertical edge's midpoint (`u` ± 1 ulp).
    pub const NEAR_VERTICAL_EDGE: &str = "near-vertical-edge";
    /// ... of a diagonal edge's midpoint (`u` or `v` ± 1 ulp).
    pub const NEAR_DIAGONAL_EDGE: &str = "near-diagonal-edge";
    /// The reference in binary32 differs from its exact reading: the real
    /// `uf + vf` is in `[1 - 2^-25, 1)` and `iu + iv < 2^level - 1`.
    pub const ROUNDING_WINDOW: &str = "rounding-window";
    /// The real `uf + vf` is in the window but the reference ignores the
    /// diagonal test there (`iu + iv >= 2^level - 1`): no difference.
    pub const ROUNDING_WINDOW_IGNORED: &str = "rounding-window-ignored";
    /// Probes just outside the window (`uf + vf` exactly 1, or just below
    /// `1 - 2^-25`): binary32 and exact agree.
    pub const ROUNDING_WINDOW_EDGE: &str = "rounding-window-edge";
    /// Not a finite point of the closed triangle: the reference's clamping
    /// decides (with one or more of the next five tags).
    pub const CLAMP: &str = "clamp";
    /// A coordinate is NaN (quiet, signalling or negative).
    pub const NAN: &str = "nan";
    /// A coordinate is a signalling NaN (quiet bit clear). The reference
    /// clamps it to 0 with IEEE 754-2019 `maximumNumber` / SPIR-V `NMax`
    /// semantics (what this crate implements); IEEE 754-2008 `maxNum`, as
    /// glibc's `fmaxf`, returns a quiet NaN for it instead, which the
    /// following `min` turns into 1.
    pub const SIGNALLING_NAN: &str = "signalling-nan";
    /// A coordinate is +inf or -inf.
    pub const INFINITY: &str = "infinity";
    /// A finite coordinate below zero.
    pub const NEGATIVE: &str = "negative";
    /// A finite coordinate above one.
    pub const ABOVE_ONE: &str = "above-one";
    /// Both coordinates in `[0, 1]` but `u + v > 1` (decided exactly).
    pub const SUM_ABOVE_ONE: &str = "sum-above-one";
    /// A coordinate is `-0.0` (binary32 set only).
    pub const SIGNED_ZERO: &str = "signed-zero";
    /// A coordinate is a nonzero binary32 subnormal.
    pub const SUBNORMAL: &str = "subnormal";
    /// A seeded uniform point of the triangle.
    pub const RANDOM: &str = "random";

    /// Every tag, in the order the docs list them.
    pub const ALL: [&str; 26] = [
        VERTEX,
        EDGE_MIDPOINT,
        HORIZONTAL_EDGE,
        VERTICAL_EDGE,
        DIAGONAL_EDGE,
        CENTROID,
        UPRIGHT,
        UPSIDE_DOWN,
        ULP_NEIGHBOUR,
        NEAR_VERTEX,
        NEAR_HORIZONTAL_EDGE,
        NEAR_VERTICAL_EDGE,
        NEAR_DIAGONAL_EDGE,
        ROUNDING_WINDOW,
        ROUNDING_WINDOW_IGNORED,
        ROUNDING_WINDOW_EDGE,
        CLAMP,
        NAN,
        SIGNALLING_NAN,
        INFINITY,
        NEGATIVE,
        ABOVE_ONE,
        SUM_ABOVE_ONE,
        SIGNED_ZERO,
        SUBNORMAL,
        RANDOM,
    ];
}

/// One vector file: a function and its cases.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct VectorFile {
    /// Always [`FORMAT`].
    pub format: String,
    /// Always [`VERSION`].
    pub version: u64,
    /// The function the expected indices are of: an `eval` variant name
    /// (`spec-f32`, `spec-exact`, `uv2index-exact`).
    pub function: String,
    /// What the function is, in a sentence.
    #[serde(default)]
    pub description: String,
    /// The cases, in id order.
    pub cases: Vec<Case>,
}

/// One input and its expected index.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Case {
    /// Unique within the file.
    pub id: u64,
    /// `u` in the `eval` value syntax ([`Value::parse`]).
    pub u: String,
    /// `v` in the `eval` value syntax.
    pub v: String,
    /// The subdivision level.
    pub level: u32,
    /// The expected micro-triangle index.
    pub index: u64,
    /// The classes the case belongs to ([`tag`]).
    pub tags: Vec<String>,
    /// For reading only: the shortest decimal that reads back as the same
    /// binary32 value (binary32 set); `u` is normative.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub u_decimal: Option<String>,
    /// For reading only, like `u_decimal`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub v_decimal: Option<String>,
}

/// The three sets [`generate_sets`] writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VectorSet {
    /// [`spec::index_f32`] on binary32 bit patterns.
    SpecF32,
    /// [`spec::index_real`] on exact rationals.
    SpecExact,
    /// [`uv2index::index_real`] on exact rationals of the closed triangle.
    Uv2indexExact,
}

impl VectorSet {
    /// Every set, in file order.
    pub const ALL: [VectorSet; 3] = [
        VectorSet::SpecF32,
        VectorSet::SpecExact,
        VectorSet::Uv2indexExact,
    ];

    /// The `function` field: the name of the `eval` variant that computes
    /// the set, as the published format (version 1) has it: the variant's
    /// legacy name where it has one (`spec-exact` for `spec-real`,
    /// `uv2index-exact` for `walk-real`), so published files and scripts keep
    /// working.
    pub fn function(self) -> &'static str {
        let variant = self.variant();
        variant.legacy_name().unwrap_or(variant.name())
    }

    /// The `eval` variant that computes the set.
    pub fn variant(self) -> Variant {
        match self {
            VectorSet::SpecF32 => Variant::SpecF32,
            VectorSet::SpecExact => Variant::SpecReal,
            VectorSet::Uv2indexExact => Variant::WalkReal,
        }
    }

    /// The file name the set is written to: `FUNCTION.json`.
    ///
    /// ```
    /// use micromap_index_verify::vectors::VectorSet;
    /// assert_eq!(VectorSet::SpecF32.file_name(), "spec-f32.json");
    /// ```
    pub fn file_name(self) -> String {
        format!("{}.json", self.function())
    }

    /// The `description` field.
    pub fn description(self) -> &'static str {
        match self {
            VectorSet::SpecF32 => {
                "Vulkan BarycentricsToSpaceFillingCurveIndex evaluated in IEEE binary32 \
                 (round to nearest even, no FMA contraction, NaN clamps to 0): what a GPU \
                 must return. u, v: binary32 bit patterns."
            }
            VectorSet::SpecExact => {
                "The Vulkan reference's steps over the reals: exact products, floors and \
                 fractions, exact uf + vf >= 1. u, v: exact rationals p/q."
            }
            VectorSet::Uv2indexExact => {
                "The paper's uv2index walk (Algorithm 4) over the reals, on points of the \
                 closed triangle only. u, v: exact rationals p/q, each exactly a binary32 value."
            }
        }
    }

    /// The case for one candidate point, or `None` if the set leaves it out.
    fn case_for(self, point: &Candidate) -> Option<Case> {
        let level = Level::new(point.level).ok()?;
        let tags = point.tags.iter().map(|t| t.to_string()).collect();
        let in_exact_sets =
            point.u.is_finite() && point.v.is_finite() && !point.tags.contains(&tag::SIGNED_ZERO);
        match self {
            VectorSet::SpecF32 => Some(Case {
                id: 0,
                u: f32_text(point.u),
                v: f32_text(point.v),
                level: point.level,
                index: u64::from(spec::reference_bits_f32(point.u, point.v, point.level)),
                tags,
                u_decimal: Some(format!("{:?}", point.u)),
                v_decimal: Some(format!("{:?}", point.v)),
            }),
            VectorSet::SpecExact if in_exact_sets => {
                let (u, v) = match &point.exact {
                    Some(exact) => exact.clone(),
                    None => (exact_of_f32(point.u)?, exact_of_f32(point.v)?),
                };
                let index = spec::index_real(&u, &v, SpecLevel::try_from(level).ok()?);
                Some(exact_case(u, v, point.level, u64::from(index), tags))
            }
            VectorSet::Uv2indexExact if in_exact_sets && !point.tags.contains(&tag::CLAMP) => {
                let (u, v) = (exact_of_f32(point.u)?, exact_of_f32(point.v)?);
                let index = uv2index::index_real(&u, &v, level).ok()?;
                Some(exact_case(u, v, point.level, index, tags))
            }
            _ => None,
        }
    }

    /// The set's file built from the candidates: duplicates (same level and
    /// coordinates) merged with their tags, ids assigned in order.
    fn build(self, candidates: &[Candidate]) -> VectorFile {
        let mut cases: Vec<Case> = Vec::new();
        let mut position: BTreeMap<(u32, String, String), usize> = BTreeMap::new();
        for case in candidates.iter().filter_map(|c| self.case_for(c)) {
            let key = (case.level, case.u.clone(), case.v.clone());
            match position.get(&key) {
                Some(&at) => {
                    for t in case.tags {
                        if !cases[at].tags.contains(&t) {
                            cases[at].tags.push(t);
                        }
                    }
                }
                None => {
                    position.insert(key, cases.len());
                    cases.push(case);
                }
            }
        }
        for (id, case) in cases.iter_mut().enumerate() {
            case.id = id as u64;
        }
        VectorFile {
            format: FORMAT.to_owned(),
            version: VERSION,
            function: self.function().to_owned(),
            description: self.description().to_owned(),
            cases,
        }
    }
}

fn exact_case(u: BigRational, v: BigRational, level: u32, index: u64, tags: Vec<String>) -> Case {
    Case {
        id: 0,
        u: rational_text(&u),
        v: rational_text(&v),
        level,
        index,
        tags,
        u_decimal: None,
        v_decimal: None,
    }
}

/// `"0x"` and the 8 hex digits of the bits.
fn f32_text(x: f32) -> String {
    format!("0x{:08x}", x.to_bits())
}

/// Always `p/q`, also for integers (`0/1`), so readers need one form only.
fn rational_text(r: &BigRational) -> String {
    format!("{}/{}", r.numer(), r.denom())
}

fn exact_of_f32(x: f32) -> Option<BigRational> {
    BigRational::from_float(f64::from(x))
}

impl VectorFile {
    /// The file's canonical text: the header fields one per line, then one
    /// case per line as compact JSON (fields in [`Case`] order), so diffs
    /// are per case and line-based readers work. Ends with a newline.
    ///
    /// ```
    /// use micromap_index_verify::vectors::{parse_vector_file, VectorFile, FORMAT, VERSION};
    /// let file = VectorFile {
    ///     format: FORMAT.into(), version: VERSION, function: "spec-f32".into(),
    ///     description: String::new(), cases: vec![],
    /// };
    /// assert_eq!(parse_vector_file(file.to_json_text().as_bytes()).unwrap(), file);
    /// ```
    pub fn to_json_text(&self) -> String {
        let string = |s: &str| serde_json::Value::from(s).to_string();
        let mut text = String::new();
        text.push_str("{\n");
        let _ = writeln!(text, "  \"format\": {},", string(&self.format));
        let _ = writeln!(text, "  \"version\": {},", self.version);
        let _ = writeln!(text, "  \"function\": {},", string(&self.function));
        let _ = writeln!(text, "  \"description\": {},", string(&self.description));
        text.push_str("  \"cases\": [\n");
        for (n, case) in self.cases.iter().enumerate() {
            // A derived Serialize of strings and integers cannot fail.
            let line = serde_json::to_string(case).unwrap_or_default();
            let comma = if n + 1 < self.cases.len() { "," } else { "" };
            let _ = writeln!(text, "    {line}{comma}");
        }
        text.push_str("  ]\n}\n");
        text
    }
}

/// Every set, freshly generated (deterministic: same bytes on every run and
/// machine), in [`VectorSet::ALL`] order.
///
/// ```
/// use micromap_index_verify::vectors::generate_sets;
/// let sets = generate_sets();
/// let functions: Vec<&str> = sets.iter().map(|s| s.function.as_str()).collect();
/// assert_eq!(functions, ["spec-f32", "spec-exact", "uv2index-exact"]);
/// assert!(sets.iter().all(|s| (0..=16).all(|l| s.cases.iter().any(|c| c.level == l))));
/// ```
pub fn generate_sets() -> Vec<VectorFile> {
    let candidates = candidates();
    VectorSet::ALL
        .iter()
        .map(|set| set.build(&candidates))
        .collect()
}

// ---------------------------------------------------------------------------
// Case generation

/// A generated point before a set picks its form: the binary32 point, and
/// for centroids the exact point it approximates.
struct Candidate {
    u: f32,
    v: f32,
    exact: Option<(BigRational, BigRational)>,
    level: u32,
    tags: Vec<&'static str>,
}

/// The stream for one level and case class (the crate-wide SplitMix64, so
/// the files depend on no crate's random-number algorithm).
fn class_rng(level: u32, class: u64) -> SplitMix64 {
    SplitMix64::new(SEED ^ (u64::from(level) << 32) ^ class)
}

/// Sampling helpers the generators share.
trait Sampling {
    /// Uniform multiple of `2^-24` in `[0, 1)`: exactly a binary32 value.
    fn unit_f32(&mut self) -> f32;
}

impl Sampling for SplitMix64 {
    fn unit_f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u32 << 24) as f32
    }
}

/// Every candidate of every level, level by level.
fn candidates() -> Vec<Candidate> {
    let mut out = Vec::new();
    for level in LEVELS {
        lattice_candidates(level, &mut out);
        rounding_window_candidates(level, &mut out);
        clamping_candidates(level, &mut out);
        subnormal_candidates(level, &mut out);
        random_candidates(level, &mut out);
    }
    for candidate in &mut out {
        add_derived_tags(candidate);
    }
    out
}

fn push(out: &mut Vec<Candidate>, level: u32, u: f32, v: f32, tags: &[&'static str]) {
    out.push(Candidate {
        u,
        v,
        exact: None,
        level,
        tags: tags.to_vec(),
    });
}

/// The anchor cells `(a, b)` whose faces a sampled level contributes: the
/// corners, the middle and quarter points, cells beside the hypotenuse, a
/// few odd cells and [`RANDOM_ANCHORS_PER_LEVEL`] seeded cells; in row
/// order. Levels up to [`ALL_FACES_MAX_LEVEL`] take every anchor
/// `a + b <= 2^level`; levels above 32 are taken as 32.
///
/// ```
/// use micromap_index_verify::vectors::sampled_anchors;
/// assert_eq!(sampled_anchors(1), [(0, 0), (1, 0), (2, 0), (0, 1), (1, 1), (0, 2)]);
/// assert!(sampled_anchors(16).contains(&(32767, 32768)));
/// ```
pub fn sampled_anchors(level: u32) -> Vec<(u64, u64)> {
    let cells = 1u64 << level.min(32);
    let mut anchors = BTreeSet::new();
    if level <= ALL_FACES_MAX_LEVEL {
        for b in 0..=cells {
            for a in 0..=cells - b {
                anchors.insert((b, a));
            }
        }
    } else {
        let (half, quarter) = (cells / 2, cells / 4);
        for (a, b) in [
            (0, 0),
            (1, 0),
            (0, 1),
            (cells - 1, 0),
            (0, cells - 1),
            (cells, 0),
            (0, cells),
            (cells - 2, 1),
            (1, cells - 2),
            (half - 1, half),
            (half, half - 1),
            (half - 1, half - 1),
            (half, half),
            (half, 0),
            (0, half),
            (quarter, quarter),
            // Odd cells: vertices new at this level (the coarse ones above
            // are also vertices of lower levels).
            (1, 1),
            (3, 2),
            (half + 1, quarter - 1),
            (quarter - 1, half + 1),
        ] {
            anchors.insert((b, a));
        }
        let mut rng = class_rng(level, 1);
        for _ in 0..RANDOM_ANCHORS_PER_LEVEL {
            let b = rng.up_to(cells - 1);
            let a = rng.up_to(cells - 1 - b);
            anchors.insert((b, a));
        }
    }
    anchors.into_iter().map(|(b, a)| (a, b)).collect()
}

/// The next binary32 value up (`+1`) or down (`-1`); NaN and the infinity
/// in that direction stay put.
fn ulp_step(x: f32, direction: i32) -> f32 {
    match direction {
        1 => crate::value::next_up_f32(x),
        -1 => crate::value::next_down_f32(x),
        _ => x,
    }
}

/// Vertices, edge midpoints and centroids of the anchors' faces, and the
/// ±1 ulp neighbours of the vertices and edge midpoints.
fn lattice_candidates(level: u32, out: &mut Vec<Candidate>) {
    let cells = 1u64 << level;
    // Face points are multiples of 2^-(level+2) <= 2^-18 below 2: exact in binary32.
    let unit = 1.0 / (4 * cells) as f32;
    // `level` is one of LEVELS (0..=16).
    let Ok(checked_level) = Level::new(level) else {
        return;
    };
    for (a, b) in sampled_anchors(level) {
        for crate::lattice::Face { x, y, kind, .. } in
            crate::lattice::faces_of_cell(checked_level, a, b)
        {
            let (u, v) = (x as f32 * unit, y as f32 * unit);
            let near = |out: &mut Vec<Candidate>, steps: &[(i32, i32)], near_tag| {
                for &(du, dv) in steps {
                    let tags = [tag::ULP_NEIGHBOUR, near_tag];
                    push(out, level, ulp_step(u, du), ulp_step(v, dv), &tags);
                }
            };
            match kind {
                FaceKind::Vertex => {
                    push(out, level, u, v, &[tag::VERTEX]);
                    let all_eight: Vec<(i32, i32)> = (-1..=1)
                        .flat_map(|du| (-1..=1).map(move |dv| (du, dv)))
                        .filter(|&step| step != (0, 0))
                        .collect();
                    near(out, &all_eight, tag::NEAR_VERTEX);
                }
                FaceKind::HorizontalEdge => {
                    push(
                        out,
                        level,
                        u,
                        v,
                        &[tag::EDGE_MIDPOINT, tag::HORIZONTAL_EDGE],
                    );
                    near(out, &[(0, -1), (0, 1)], tag::NEAR_HORIZONTAL_EDGE);
                }
                FaceKind::VerticalEdge => {
                    push(out, level, u, v, &[tag::EDGE_MIDPOINT, tag::VERTICAL_EDGE]);
                    near(out, &[(-1, 0), (1, 0)], tag::NEAR_VERTICAL_EDGE);
                }
                FaceKind::DiagonalEdge => {
                    push(out, level, u, v, &[tag::EDGE_MIDPOINT, tag::DIAGONAL_EDGE]);
                    let steps = [(-1, 0), (1, 0), (0, -1), (0, 1)];
                    near(out, &steps, tag::NEAR_DIAGONAL_EDGE);
                }
                FaceKind::Upright | FaceKind::UpsideDown => {
                    out.push(centroid(level, a, b, kind));
                }
            }
        }
    }
}

/// The centroid of the micro-triangle of cell `(a, b)`: `(a + 1/3, b + 1/3)`
/// (upright) or `(a + 2/3, b + 2/3)` (upside-down) over `2^level`, exactly
/// and as the binary32 point nearest it (at most half an ulp of binary64
/// off, far inside the micro-triangle).
fn centroid(level: u32, a: u64, b: u64, kind: FaceKind) -> Candidate {
    let (third, shape) = match kind {
        FaceKind::Upright => (1, tag::UPRIGHT),
        _ => (2, tag::UPSIDE_DOWN),
    };
    let denominator = 3 * (1u64 << level);
    let exact = |k: u64| BigRational::new(BigInt::from(3 * k + third), BigInt::from(denominator));
    let float = |k: u64| ((3 * k + third) as f64 / denominator as f64) as f32;
    Candidate {
        u: float(a),
        v: float(b),
        exact: Some((exact(a), exact(b))),
        level,
        tags: vec![tag::CENTROID, shape],
    }
}

/// Points whose scaled fractions sum to just below, into and just above
/// the binary32 rounding window `[1 - 2^-25, 1)` of the reference's
/// `uf + vf >= 1`, in the cells `(0, b)` and `(b, 0)` for `b` in
/// `{0, 1, 2^level - 2, 2^level - 1}` (the window needs a zero cell
/// coordinate: two fractions of cells `>= 1` have no bits below `2^-23`).
fn rounding_window_candidates(level: u32, out: &mut Vec<Candidate>) {
    let cells = 1u64 << level;
    let rows: BTreeSet<u64> = [0, 1, cells.saturating_sub(2), cells - 1]
        .into_iter()
        .filter(|&b| b < cells)
        .collect();
    for b in rows {
        // `vf = 1 - q`, with `q` the binary32 spacing in [b, b + 1) (for
        // b = 0 any fraction is representable; take vf = 3/4).
        let q = if b == 0 {
            0.25
        } else {
            2f64.powi(b.ilog2() as i32 - 23)
        };
        let spacing_of_uf = q * 2f64.powi(-24);
        let half_window = 2f64.powi(-25);
        // uf = q - delta, so uf + vf = 1 - delta exactly.
        for delta in [0.0, spacing_of_uf, half_window, half_window + spacing_of_uf] {
            let uf = q - delta;
            let vf = 1.0 - q;
            let scaled_u = uf / cells as f64;
            let scaled_v = (b as f64 + vf) / cells as f64;
            let (u, v) = (scaled_u as f32, scaled_v as f32);
            if f64::from(u) != scaled_u || f64::from(v) != scaled_v {
                continue; // not a binary32 point; by construction never
            }
            for (u, v) in [(u, v), (v, u)] {
                let mut tags = vec![];
                if binary32_rounding_tag(u, v, level).is_none() {
                    tags.push(tag::ROUNDING_WINDOW_EDGE);
                }
                push(out, level, u, v, &tags);
            }
        }
    }
}

/// The reference's clamping: NaN (quiet, signalling, negative), ±inf,
/// negatives, values above one, `-0` and `u + v > 1`, each paired with a
/// seeded ordinary coordinate on either side.
fn clamping_candidates(level: u32, out: &mut Vec<Candidate>) {
    let mut rng = class_rng(level, 2);
    let partner = rng.unit_f32();
    let specials = [
        f32::from_bits(0x7fc0_0000), // quiet NaN
        f32::from_bits(0xffc0_0000), // negative quiet NaN
        f32::from_bits(0x7f80_0001), // signalling NaN
        f32::INFINITY,
        f32::NEG_INFINITY,
        -1.0,
        -f32::from_bits(1), // the negative subnormal next to -0
        -0.0,
        ulp_step(1.0, 1),
        2.0,
        f32::MAX,
    ];
    for special in specials {
        push(out, level, special, partner, &[]);
        push(out, level, partner, special, &[]);
    }
    let both = [
        (f32::NAN, f32::NAN),
        (f32::INFINITY, f32::INFINITY),
        (f32::NEG_INFINITY, f32::INFINITY),
        (f32::INFINITY, f32::NAN),
        (2.0, 2.0),
        (-1.0, -1.0),
    ];
    for (u, v) in both {
        push(out, level, u, v, &[]);
    }
    let mut sum_above_one = vec![
        (0.75, 0.5),
        (1.0, 1.0),
        (0.5, ulp_step(0.5, 1)),
        (1.0, f32::from_bits(1)),
    ];
    while sum_above_one.len() < 6 {
        let (u, v) = (rng.unit_f32(), rng.unit_f32());
        if f64::from(u) + f64::from(v) > 1.0 {
            sum_above_one.push((u, v));
        }
    }
    for (u, v) in sum_above_one {
        push(out, level, u, v, &[]);
    }
}

/// Subnormal coordinates inside the triangle.
fn subnormal_candidates(level: u32, out: &mut Vec<Candidate>) {
    let tiny = f32::from_bits(1);
    let largest_subnormal = f32::from_bits(0x007f_ffff);
    for (u, v) in [
        (tiny, 0.0),
        (0.0, tiny),
        (tiny, tiny),
        (largest_subnormal, f32::MIN_POSITIVE),
        (largest_subnormal, 0.5),
        (ulp_step(1.0, -1), tiny),
    ] {
        push(out, level, u, v, &[]);
    }
}

/// Seeded uniform points of the triangle (multiples of `2^-24`).
fn random_candidates(level: u32, out: &mut Vec<Candidate>) {
    let mut rng = class_rng(level, 3);
    for _ in 0..RANDOM_POINTS_PER_LEVEL {
        let (mut u, mut v) = (rng.unit_f32(), rng.unit_f32());
        if f64::from(u) + f64::from(v) > 1.0 {
            // Reflect into the triangle; 1 - k 2^-24 is exact.
            (u, v) = (1.0 - u, 1.0 - v);
        }
        push(out, level, u, v, &[tag::RANDOM]);
    }
}

/// `rounding-window` if binary32 rounding of `uf + vf` changes the
/// reference's index at this point, `rounding-window-ignored` if it changes
/// only the (then unused) diagonal test, else `None`. `None` for non-finite
/// points.
fn binary32_rounding_tag(u: f32, v: f32, level: u32) -> Option<&'static str> {
    let lv = Level::new(level).ok()?;
    let (exact_u, exact_v) = (exact_of_f32(u)?, exact_of_f32(v)?);
    let exact_index = spec::index_real(&exact_u, &exact_v, SpecLevel::try_from(lv).ok()?);
    if spec::reference_bits_f32(u, v, level) != exact_index {
        Some(tag::ROUNDING_WINDOW)
    } else if spec::cell_f32(u, v, level).diagonal
        != spec::cell_real(&exact_u, &exact_v, lv).diagonal
    {
        Some(tag::ROUNDING_WINDOW_IGNORED)
    } else {
        None
    }
}

/// Adds the tags that follow from the point itself (clamping classes,
/// `-0`, subnormals, binary32 rounding), so they are true by construction.
fn add_derived_tags(candidate: &mut Candidate) {
    let (u, v) = (candidate.u, candidate.v);
    let both = [u, v];
    let mut derived = vec![];
    let nan = both.iter().any(|x| x.is_nan());
    let signalling_nan = both
        .iter()
        .any(|x| x.is_nan() && x.to_bits() & 0x0040_0000 == 0);
    let infinite = both.iter().any(|x| x.is_infinite());
    let negative = both.iter().any(|x| x.is_finite() && *x < 0.0);
    let above_one = both.iter().any(|x| x.is_finite() && *x > 1.0);
    let sum_above_one = both.iter().all(|x| (0.0..=1.0).contains(x))
        && match (exact_of_f32(u), exact_of_f32(v)) {
            (Some(u), Some(v)) => u + v > BigRational::one(),
            _ => false,
        };
    for (holds, name) in [
        (nan, tag::NAN),
        (signalling_nan, tag::SIGNALLING_NAN),
        (infinite, tag::INFINITY),
        (negative, tag::NEGATIVE),
        (above_one, tag::ABOVE_ONE),
        (sum_above_one, tag::SUM_ABOVE_ONE),
    ] {
        if holds {
            derived.push(name);
        }
    }
    if !derived.is_empty() {
        derived.insert(0, tag::CLAMP);
    }
    if both.iter().any(|x| x.to_bits() == 0x8000_0000) {
        derived.push(tag::SIGNED_ZERO);
    }
    if both.iter().any(|x| x.is_subnormal()) {
        derived.push(tag::SUBNORMAL);
    }
    if let Some(rounding) = binary32_rounding_tag(u, v, candidate.level) {
        derived.push(rounding);
    }
    for name in derived {
        if !candidate.tags.contains(&name) {
            candidate.tags.push(name);
        }
    }
}

// ---------------------------------------------------------------------------
// Reading files

/// Why a vector or answers file could not be read.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum VectorError {
    /// The bytes (of the file, or of one answers line) are not UTF-8.
    NotUtf8 {
        /// The answers line (1-based), if it is about one.
        line: Option<usize>,
    },
    /// Not JSON of the expected shape.
    Json {
        /// The answers line (1-based), if it is about one.
        line: Option<usize>,
        /// serde_json's message (with its own line and column for a vector file).
        message: String,
    },
    /// Valid JSON, but not a vector file this crate reads (format, version,
    /// a value or level of a case).
    Schema(String),
    /// Two cases, or two answers, with the same id.
    DuplicateId {
        /// The id.
        id: u64,
        /// The answers line (1-based) of the second one, if about answers.
        line: Option<usize>,
    },
    /// An answers line with neither or both of `index` and `error`.
    BadAnswer {
        /// The line (1-based).
        line: usize,
        /// What is wrong.
        message: String,
    },
}

impl fmt::Display for VectorError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let at = |line: &Option<usize>| match line {
            Some(line) => format!("line {line}: "),
            None => String::new(),
        };
        match self {
            VectorError::NotUtf8 { line } => write!(f, "{}not UTF-8", at(line)),
            VectorError::Json { line, message } => write!(f, "{}bad JSON: {message}", at(line)),
            VectorError::Schema(message) => f.write_str(message),
            VectorError::DuplicateId { id, line } => write!(f, "{}duplicate id {id}", at(line)),
            VectorError::BadAnswer { line, message } => write!(f, "line {line}: {message}"),
        }
    }
}

impl std::error::Error for VectorError {}

/// Reads a vector file: the JSON object, checked for [`FORMAT`],
/// [`VERSION`], unique ids, levels `0..=32` and coordinates in the value
/// syntax. Never panics, whatever the bytes.
///
/// ```
/// use micromap_index_verify::vectors::{parse_vector_file, VectorError};
/// let text = r#"{"format": "micromap-index-vectors", "version": 1, "function": "spec-f32",
///   "cases": [{"id": 7, "u": "0x3e800000", "v": "0x3e800000", "level": 2, "index": 5, "tags": ["vertex"]}]}"#;
/// let file = parse_vector_file(text.as_bytes()).unwrap();
/// assert_eq!(file.cases[0].index, 5);
/// assert!(matches!(parse_vector_file(b"{"), Err(VectorError::Json { .. })));
/// assert!(matches!(parse_vector_file(b"{\"format\": 1}"), Err(VectorError::Json { .. })));
/// ```
pub fn parse_vector_file(bytes: &[u8]) -> Result<VectorFile, VectorError> {
    let text = std::str::from_utf8(bytes).map_err(|_| VectorError::NotUtf8 { line: None })?;
    let json = |e: serde_json::Error| VectorError::Json {
        line: None,
        message: e.to_string(),
    };
    let value: serde_json::Value = serde_json::from_str(text).map_err(json)?;
    // serde would also read a struct from an array; the schema says objects.
    let cases_are_objects = match value.get("cases") {
        Some(serde_json::Value::Array(cases)) => cases.iter().all(|c| c.is_object()),
        _ => true, // missing or not an array: from_value says so
    };
    if !value.is_object() || !cases_are_objects {
        return Err(VectorError::Schema(
            "expected a JSON object whose \"cases\" are objects".into(),
        ));
    }
    let file: VectorFile = serde_json::from_value(value).map_err(json)?;
    if file.format != FORMAT {
        return Err(VectorError::Schema(format!(
            "format is {:?}, expected {FORMAT:?}",
            file.format
        )));
    }
    if file.version != VERSION {
        return Err(VectorError::Schema(format!(
            "version {} is not supported (this reader knows version {VERSION})",
            file.version
        )));
    }
    let mut ids = BTreeSet::new();
    for case in &file.cases {
        if !ids.insert(case.id) {
            return Err(VectorError::DuplicateId {
                id: case.id,
                line: None,
            });
        }
        if Level::new(case.level).is_err() {
            return Err(VectorError::Schema(format!(
                "case {}: level {} is above {}",
                case.id,
                case.level,
                Level::MAX
            )));
        }
        for (name, text) in [("u", &case.u), ("v", &case.v)] {
            Value::parse(text)
                .map_err(|e| VectorError::Schema(format!("case {}: {name}: {e}", case.id)))?;
        }
    }
    Ok(file)
}

/// What another implementation answered for one case.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Answer {
    /// `{"id": N, "index": I}`.
    Index(u64),
    /// `{"id": N, "error": "..."}`: the implementation refused the input.
    Refused(String),
}

impl fmt::Display for Answer {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Answer::Index(index) => index.fmt(f),
            Answer::Refused(message) => write!(f, "error {message:?}"),
        }
    }
}

/// Another implementation's answers, by id.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Answers {
    /// The answers, by case id.
    pub by_id: BTreeMap<u64, Answer>,
}

impl Answers {
    /// The answers as JSON lines in id order, each ending with a newline:
    /// `{"id":N,"index":I}` or `{"id":N,"error":"..."}`.
    ///
    /// ```
    /// use micromap_index_verify::vectors::{parse_answers, Answer, Answers};
    /// let mut answers = Answers::default();
    /// answers.by_id.insert(3, Answer::Index(12));
    /// answers.by_id.insert(4, Answer::Refused("u is NaN".into()));
    /// let text = answers.to_json_lines();
    /// assert_eq!(text, "{\"id\":3,\"index\":12}\n{\"id\":4,\"error\":\"u is NaN\"}\n");
    /// assert_eq!(parse_answers(text.as_bytes()).unwrap(), answers);
    /// ```
    pub fn to_json_lines(&self) -> String {
        let mut text = String::new();
        for (id, answer) in &self.by_id {
            let _ = match answer {
                Answer::Index(index) => writeln!(text, "{{\"id\":{id},\"index\":{index}}}"),
                Answer::Refused(message) => writeln!(
                    text,
                    "{{\"id\":{id},\"error\":{}}}",
                    serde_json::Value::from(message.as_str())
                ),
            };
        }
        text
    }
}

#[derive(Deserialize)]
struct AnswerLine {
    id: u64,
    #[serde(default)]
    index: Option<u64>,
    #[serde(default)]
    error: Option<String>,
}

/// Reads answers: JSON lines `{"id": N, "index": I}` (or
/// `{"id": N, "error": "..."}` for a refused input), extra fields allowed,
/// blank lines skipped, `\r\n` accepted. A repeated id is an error. Never
/// panics, whatever the bytes.
///
/// ```
/// use micromap_index_verify::vectors::{parse_answers, Answer, VectorError};
/// let answers = parse_answers(b"{\"id\": 1, \"index\": 5, \"ms\": 0.1}\n\n{\"id\": 2, \"index\": 0}\n").unwrap();
/// assert_eq!(answers.by_id[&1], Answer::Index(5));
/// assert_eq!(
///     parse_answers(b"{\"id\": 1, \"index\": 5}\n{\"id\": 1, \"index\": 6}"),
///     Err(VectorError::DuplicateId { id: 1, line: Some(2) })
/// );
/// assert!(parse_answers(b"{\"id\": 1}").is_err());
/// ```
pub fn parse_answers(bytes: &[u8]) -> Result<Answers, VectorError> {
    let mut answers = Answers::default();
    for (number, line) in bytes.split(|&b| b == b'\n').enumerate() {
        let line_number = number + 1;
        let line = line.strip_suffix(b"\r").unwrap_or(line);
        if line.iter().all(u8::is_ascii_whitespace) {
            continue;
        }
        let text = std::str::from_utf8(line).map_err(|_| VectorError::NotUtf8 {
            line: Some(line_number),
        })?;
        let json = |e: serde_json::Error| VectorError::Json {
            line: Some(line_number),
            message: e.to_string(),
        };
        // An object, not any JSON serde could read a struct from (an array).
        let object: serde_json::Map<String, serde_json::Value> =
            serde_json::from_str(text).map_err(json)?;
        let parsed: AnswerLine =
            serde_json::from_value(serde_json::Value::Object(object)).map_err(json)?;
        let answer = match (parsed.index, parsed.error) {
            (Some(index), None) => Answer::Index(index),
            (None, Some(message)) => Answer::Refused(message),
            (Some(_), Some(_)) => {
                return Err(VectorError::BadAnswer {
                    line: line_number,
                    message: "has both \"index\" and \"error\"".into(),
                })
            }
            (None, None) => {
                return Err(VectorError::BadAnswer {
                    line: line_number,
                    message: "needs \"index\" (a non-negative integer) or \"error\"".into(),
                })
            }
        };
        if answers.by_id.insert(parsed.id, answer).is_some() {
            return Err(VectorError::DuplicateId {
                id: parsed.id,
                line: Some(line_number),
            });
        }
    }
    Ok(answers)
}

// ---------------------------------------------------------------------------
// Producing answers with this crate (for demonstrations and self-checks)

/// A function of this crate that can answer a vector file: any `eval`
/// variant, or the talk's first walk (`walk-version1-real` over exact
/// rationals, `walk-version1-f32-arithmetic` in binary32; the legacy names
/// `uv2index-version1-exact` and `uv2index-version1-f32` are accepted).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AnswerSource {
    /// An `eval` variant.
    Variant(Variant),
    /// [`micromap_index::internals::index_version1_unchecked`] over exact rationals, after the walk's
    /// point check.
    Version1Exact,
    /// [`micromap_index::internals::index_version1_unchecked`] in binary32, after the walk's point check.
    Version1F32,
}

impl AnswerSource {
    /// The source's name: the variant's name, `walk-version1-real` or
    /// `walk-version1-f32-arithmetic`.
    pub fn name(self) -> &'static str {
        match self {
            AnswerSource::Variant(variant) => variant.name(),
            AnswerSource::Version1Exact => "walk-version1-real",
            AnswerSource::Version1F32 => "walk-version1-f32-arithmetic",
        }
    }

    /// The name earlier releases used, if it differs.
    pub fn legacy_name(self) -> Option<&'static str> {
        match self {
            AnswerSource::Variant(variant) => variant.legacy_name(),
            AnswerSource::Version1Exact => Some("uv2index-version1-exact"),
            AnswerSource::Version1F32 => Some("uv2index-version1-f32"),
        }
    }

    /// The source with that name.
    ///
    /// ```
    /// use micromap_index_verify::vectors::AnswerSource;
    /// assert_eq!(AnswerSource::from_name("uv2index-version1-f32"), Some(AnswerSource::Version1F32));
    /// assert_eq!(AnswerSource::from_name("nope"), None);
    /// ```
    pub fn from_name(name: &str) -> Option<AnswerSource> {
        Self::all()
            .into_iter()
            .find(|source| source.name() == name || source.legacy_name() == Some(name))
    }

    /// Every source: the `eval` variants, then the two version-1 walks.
    pub fn all() -> Vec<AnswerSource> {
        let mut all: Vec<AnswerSource> = Variant::ALL.map(AnswerSource::Variant).to_vec();
        all.extend([AnswerSource::Version1Exact, AnswerSource::Version1F32]);
        all
    }

    /// This source's answer for one case (a refusal if it rejects the input).
    pub fn answer(self, case: &Case) -> Answer {
        match self.evaluate(case) {
            Ok(index) => Answer::Index(index),
            Err(message) => Answer::Refused(message),
        }
    }

    fn evaluate(self, case: &Case) -> Result<u64, String> {
        let u = Value::parse(&case.u).map_err(|e| e.to_string())?;
        let v = Value::parse(&case.v).map_err(|e| e.to_string())?;
        let level = Level::new(case.level).map_err(|e| e.to_string())?;
        match self {
            AnswerSource::Variant(variant) => variant
                .evaluate(&u, &v, u64::from(case.level))
                .map_err(|e| e.to_string()),
            AnswerSource::Version1Exact => {
                let u = u.to_exact().map_err(|e| e.to_string())?;
                let v = v.to_exact().map_err(|e| e.to_string())?;
                BigRational::check_point(&u, &v).map_err(|e| e.to_string())?;
                Ok(micromap_index::internals::index_version1_unchecked(
                    u, v, level,
                ))
            }
            AnswerSource::Version1F32 => {
                let u = u.to_f32().map_err(|e| e.to_string())?;
                let v = v.to_f32().map_err(|e| e.to_string())?;
                f32::check_point(&u, &v).map_err(|e| e.to_string())?;
                Ok(micromap_index::internals::index_version1_unchecked(
                    u, v, level,
                ))
            }
        }
    }
}

/// `source`'s answers to every case of `vectors`.
///
/// ```
/// use micromap_index_verify::vectors::{compute_answers, generate_sets, AnswerSource, Answer};
/// let sets = generate_sets();
/// let answers = compute_answers(AnswerSource::from_name("uv2index-exact").unwrap(), &sets[2]);
/// assert!(sets[2].cases.iter().all(|c| answers.by_id[&c.id] == Answer::Index(c.index)));
/// ```
pub fn compute_answers(source: AnswerSource, vectors: &VectorFile) -> Answers {
    Answers {
        by_id: vectors
            .cases
            .iter()
            .map(|case| (case.id, source.answer(case)))
            .collect(),
    }
}

// ---------------------------------------------------------------------------
// Checking answers

/// Cases and failures of one tag or level.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Tally {
    /// Cases with this tag (or level).
    pub cases: usize,
    /// Of those, answered with a different index or refused.
    pub mismatched: usize,
    /// Of those, not answered at all.
    pub missing: usize,
}

/// One case answered wrongly (or refused).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mismatch {
    /// The case's id.
    pub id: u64,
    /// The case's level.
    pub level: u32,
    /// `u` as written in the vector file.
    pub u: String,
    /// `v` as written in the vector file.
    pub v: String,
    /// The case's tags.
    pub tags: Vec<String>,
    /// The expected index.
    pub expected: u64,
    /// What the implementation answered.
    pub got: Answer,
}

/// The outcome of [`check`]; [`CheckReport::render`] (or `Display`) prints
/// it grouped by tag.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CheckReport {
    /// The vector file's function.
    pub function: String,
    /// Cases in the vector file.
    pub cases: usize,
    /// Cases answered with the expected index.
    pub matched: usize,
    /// Cases answered otherwise, in id order.
    pub mismatches: Vec<Mismatch>,
    /// Ids of cases without an answer, in order.
    pub missing: Vec<u64>,
    /// Ids answered that are not in the vector file, in order.
    pub unknown: Vec<u64>,
    /// Per tag (in name order).
    pub by_tag: BTreeMap<String, Tally>,
    /// Per level.
    pub by_level: BTreeMap<u32, Tally>,
}

/// Compares `answers` with the expected indices of `vectors`.
///
/// ```
/// use micromap_index_verify::vectors::{check, parse_answers, parse_vector_file};
/// let vectors = parse_vector_file(br#"{"format": "micromap-index-vectors", "version": 1,
///   "function": "spec-f32", "cases": [
///     {"id": 0, "u": "0x3e000000", "v": "0x3dffffff", "level": 2, "index": 1, "tags": ["rounding-window"]},
///     {"id": 1, "u": "0x3e800000", "v": "0x3e800000", "level": 2, "index": 5, "tags": ["vertex"]}]}"#).unwrap();
/// let report = check(&vectors, &parse_answers(b"{\"id\":0,\"index\":0}\n{\"id\":9,\"index\":0}").unwrap());
/// assert!(!report.passed());
/// assert_eq!(report.mismatches[0].id, 0);
/// assert_eq!((report.missing.as_slice(), report.unknown.as_slice()), (&[1][..], &[9][..]));
/// assert!(report.to_string().contains("u = 0x3e000000 (1/8)"));
/// ```
pub fn check(vectors: &VectorFile, answers: &Answers) -> CheckReport {
    let mut report = CheckReport {
        function: vectors.function.clone(),
        cases: vectors.cases.len(),
        matched: 0,
        mismatches: vec![],
        missing: vec![],
        unknown: vec![],
        by_tag: BTreeMap::new(),
        by_level: BTreeMap::new(),
    };
    for case in &vectors.cases {
        let outcome = match answers.by_id.get(&case.id) {
            Some(Answer::Index(index)) if *index == case.index => Outcome::Matched,
            Some(answer) => Outcome::Mismatched(answer.clone()),
            None => Outcome::Missing,
        };
        report
            .by_level
            .entry(case.level)
            .or_default()
            .count(&outcome);
        let distinct_tags: BTreeSet<&String> = case.tags.iter().collect();
        for name in distinct_tags {
            report
                .by_tag
                .entry(name.clone())
                .or_default()
                .count(&outcome);
        }
        match outcome {
            Outcome::Matched => report.matched += 1,
            Outcome::Mismatched(got) => report.mismatches.push(Mismatch {
                id: case.id,
                level: case.level,
                u: case.u.clone(),
                v: case.v.clone(),
                tags: case.tags.clone(),
                expected: case.index,
                got,
            }),
            Outcome::Missing => report.missing.push(case.id),
        }
    }
    let ids: BTreeSet<u64> = vectors.cases.iter().map(|c| c.id).collect();
    report.unknown = answers
        .by_id
        .keys()
        .filter(|id| !ids.contains(id))
        .copied()
        .collect();
    report
}

/// How one case fared.
enum Outcome {
    Matched,
    Mismatched(Answer),
    Missing,
}

impl Tally {
    fn count(&mut self, outcome: &Outcome) {
        self.cases += 1;
        match outcome {
            Outcome::Matched => {}
            Outcome::Mismatched(_) => self.mismatched += 1,
            Outcome::Missing => self.missing += 1,
        }
    }
}

/// Ids listed in full before a report abbreviates.
const MAX_LISTED_IDS: usize = 20;

impl CheckReport {
    /// Every case answered with its expected index, and nothing else answered.
    pub fn passed(&self) -> bool {
        self.mismatches.is_empty() && self.missing.is_empty() && self.unknown.is_empty()
    }

    /// The report as text: a summary line, a table of cases and failures
    /// per tag and per failing level, then for every tag with mismatches
    /// its first `examples_per_tag` cases with the inputs in exact form,
    /// then the missing and unknown ids.
    pub fn render(&self, examples_per_tag: usize) -> String {
        let mut text = String::new();
        let _ = writeln!(
            text,
            "{}: {} cases, {} match, {} mismatch, {} missing, {} unknown ids: {}",
            self.function,
            self.cases,
            self.matched,
            self.mismatches.len(),
            self.missing.len(),
            self.unknown.len(),
            if self.passed() { "PASS" } else { "FAIL" }
        );
        let _ = writeln!(
            text,
            "\n{:<26} {:>7} {:>9} {:>8}",
            "tag", "cases", "mismatch", "missing"
        );
        for (name, tally) in &self.by_tag {
            let _ = writeln!(
                text,
                "{:<26} {:>7} {:>9} {:>8}",
                name, tally.cases, tally.mismatched, tally.missing
            );
        }
        let failing_levels: Vec<(&u32, &Tally)> = self
            .by_level
            .iter()
            .filter(|(_, t)| t.mismatched + t.missing > 0)
            .collect();
        if !failing_levels.is_empty() {
            let _ = writeln!(
                text,
                "\n{:<26} {:>7} {:>9} {:>8}",
                "failing level", "cases", "mismatch", "missing"
            );
            for (level, tally) in failing_levels {
                let _ = writeln!(
                    text,
                    "{:<26} {:>7} {:>9} {:>8}",
                    level, tally.cases, tally.mismatched, tally.missing
                );
            }
        }
        for (name, tally) in self.by_tag.iter().filter(|(_, t)| t.mismatched > 0) {
            let shown = examples_per_tag.min(tally.mismatched);
            let _ = writeln!(
                text,
                "\nmismatches tagged {name} ({} of {} cases; first {shown}):",
                tally.mismatched, tally.cases
            );
            let examples = self.mismatches.iter().filter(|m| m.tags.contains(name));
            for mismatch in examples.take(examples_per_tag) {
                let _ = writeln!(
                    text,
                    "  id {} level {}: u = {}, v = {}: expected {}, got {}  [{}]",
                    mismatch.id,
                    mismatch.level,
                    exact_form(&mismatch.u),
                    exact_form(&mismatch.v),
                    mismatch.expected,
                    mismatch.got,
                    mismatch.tags.join(", ")
                );
            }
        }
        for (what, ids) in [("missing", &self.missing), ("unknown", &self.unknown)] {
            if !ids.is_empty() {
                let listed: Vec<String> = ids
                    .iter()
                    .take(MAX_LISTED_IDS)
                    .map(u64::to_string)
                    .collect();
                let more = if ids.len() > MAX_LISTED_IDS {
                    ", …"
                } else {
                    ""
                };
                let _ = writeln!(
                    text,
                    "\n{what} ids ({}): {}{more}",
                    ids.len(),
                    listed.join(", ")
                );
            }
        }
        text
    }
}

impl fmt::Display for CheckReport {
    /// [`CheckReport::render`] with 5 examples per tag.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.render(5))
    }
}

/// A coordinate as written plus its exact value: `0x3dffffff (16777215/134217728)`,
/// `0x7fc00000 (NaN)`, `0.375 (3/8)`; `p/q` text as is.
///
/// ```
/// use micromap_index_verify::vectors::exact_form;
/// assert_eq!(exact_form("0x3e000000"), "0x3e000000 (1/8)");
/// assert_eq!(exact_form("0xff800000"), "0xff800000 (-inf)");
/// assert_eq!(exact_form("0x80000000"), "0x80000000 (-0)");
/// assert_eq!(exact_form("3/8"), "3/8");
/// assert_eq!(exact_form("0.375"), "0.375 (3/8)");
/// ```
pub fn exact_form(text: &str) -> String {
    let value = match Value::parse(text) {
        Ok(value) => value,
        Err(_) => return text.to_owned(),
    };
    let float = match value {
        Value::F32Bits(bits) => Some(f64::from(f32::from_bits(bits))),
        Value::F64Bits(bits) => Some(f64::from_bits(bits)),
        Value::Exact(_) => None,
    };
    let exact = match (float, value.to_exact()) {
        (Some(x), _) if x.is_nan() => "NaN".to_owned(),
        (Some(x), _) if x.is_infinite() => if x > 0.0 { "+inf" } else { "-inf" }.to_owned(),
        (Some(x), _) if x == 0.0 && x.is_sign_negative() => "-0".to_owned(),
        (_, Ok(r)) if r.is_integer() => r.numer().to_string(),
        (_, Ok(r)) => rational_text(&r),
        (_, Err(_)) => return text.to_owned(),
    };
    if exact == text || (float.is_none() && text.contains('/')) {
        text.to_owned()
    } else {
        format!("{text} ({exact})")
    }
}
