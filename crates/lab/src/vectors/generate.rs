//! The generator: the candidate points of every class and level, the
//! derived tags, and each set's cases ([`generate_sets`]).

use super::{exact_of_f32, f32_text, place_of, rational_text, Place};
use super::{tag, Case, VectorFile, VectorSet};
use super::{
    ALL_FACES_MAX_LEVEL, FORMAT, LEVELS, RANDOM_ANCHORS_PER_LEVEL, RANDOM_POINTS_PER_LEVEL, SEED,
    VERSION,
};
use crate::lattice::FaceKind;
use crate::rng::SplitMix64;
use micromap_index::uv2index;
use micromap_index::{spec, Level, SpecLevel};
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::One;
use std::collections::{BTreeMap, BTreeSet};

/// The case of `set` for one candidate point, or `None` if the set leaves
/// it out.
fn case_for(set: VectorSet, point: &Candidate) -> Option<Case> {
    let level = Level::new(point.level).ok()?;
    let tags = point.tags.iter().map(|t| (*t).to_string()).collect();
    let in_exact_sets =
        point.u.is_finite() && point.v.is_finite() && !point.tags.contains(&tag::SIGNED_ZERO);
    match set {
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
            Some(exact_case(&u, &v, point.level, u64::from(index), tags))
        }
        VectorSet::Uv2indexExact if in_exact_sets && !point.tags.contains(&tag::CLAMP) => {
            let (u, v) = (exact_of_f32(point.u)?, exact_of_f32(point.v)?);
            let index = uv2index::index_real(&u, &v, level).ok()?;
            Some(exact_case(&u, &v, point.level, index, tags))
        }
        _ => None,
    }
}

/// The file of `set` built from the candidates: duplicates (same level and
/// coordinates) merged with their tags, ids assigned in order.
fn build(set: VectorSet, candidates: &[Candidate]) -> VectorFile {
    let mut cases: Vec<Case> = Vec::new();
    let mut position: BTreeMap<(u32, String, String), usize> = BTreeMap::new();
    for case in candidates.iter().filter_map(|c| case_for(set, c)) {
        let key = (case.level, case.u.clone(), case.v.clone());
        if let Some(&at) = position.get(&key) {
            for t in case.tags {
                if !cases[at].tags.contains(&t) {
                    cases[at].tags.push(t);
                }
            }
        } else {
            position.insert(key, cases.len());
            cases.push(case);
        }
    }
    for (id, case) in cases.iter_mut().enumerate() {
        case.id = id as u64;
    }
    VectorFile {
        format: FORMAT.to_owned(),
        version: VERSION,
        function: set.function().to_owned(),
        description: set.description().to_owned(),
        cases,
    }
}

fn exact_case(u: &BigRational, v: &BigRational, level: u32, index: u64, tags: Vec<String>) -> Case {
    Case {
        id: 0,
        u: rational_text(u),
        v: rational_text(v),
        level,
        index,
        tags,
        u_decimal: None,
        v_decimal: None,
    }
}

/// Every set, freshly generated (deterministic: same bytes on every run and
/// machine), in [`VectorSet::ALL`] order.
///
/// ```
/// use micromap_index_lab::vectors::generate_sets;
/// let sets = generate_sets();
/// let functions: Vec<&str> = sets.iter().map(|s| s.function.as_str()).collect();
/// assert_eq!(functions, ["spec-f32", "spec-exact", "uv2index-exact"]);
/// assert!(sets.iter().all(|s| (0..=16).all(|l| s.cases.iter().any(|c| c.level == l))));
/// ```
#[must_use]
pub fn generate_sets() -> Vec<VectorFile> {
    let candidates = candidates();
    VectorSet::ALL
        .iter()
        .map(|&set| build(set, &candidates))
        .collect()
}

/// A generated point before a set picks its form: the binary32 point, and
/// for centroids the exact point it approximates.
struct Candidate {
    u: f32,
    v: f32,
    exact: Option<(BigRational, BigRational)>,
    level: u32,
    tags: Vec<&'static str>,
}

/// The stream for one level and case class (the crate-wide `SplitMix64`, so
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
/// use micromap_index_lab::vectors::sampled_anchors;
/// assert_eq!(sampled_anchors(1), [(0, 0), (1, 0), (2, 0), (0, 1), (1, 1), (0, 2)]);
/// assert!(sampled_anchors(16).contains(&(32767, 32768)));
/// ```
#[must_use]
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
        1 => micromap_index_conformance::value::next_up_f32(x),
        -1 => micromap_index_conformance::value::next_down_f32(x),
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
    let exact = match &candidate.exact {
        Some(exact) => Some(exact.clone()),
        None => exact_of_f32(u).zip(exact_of_f32(v)),
    };
    if let (Some((u, v)), Ok(level)) = (exact, Level::new(candidate.level)) {
        match place_of(&u, &v, level) {
            Place::SharedEdge => derived.push(tag::SHARED_EDGE),
            Place::SharedVertex => derived.push(tag::SHARED_VERTEX),
            Place::Outside | Place::OneMicroTriangle => {}
        }
    }
    for name in derived {
        if !candidate.tags.contains(&name) {
            candidate.tags.push(name);
        }
    }
}
