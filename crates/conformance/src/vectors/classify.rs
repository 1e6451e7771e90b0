//! Exact geometry for the vectors: where a point lies in a level's lattice
//! ([`place_of`]: inside one micro-triangle, on a shared edge or vertex,
//! outside the triangle) and why an answer differs from the expected index
//! ([`classify`], [`MismatchClass`]). All of it in exact rational arithmetic
//! on the inputs as written, with the answered micro-triangle's exact
//! vertices from [`micromap_index::inverse::micro_triangle`].

use super::Answer;
use crate::eval::Variant;
use crate::value::Value;
use micromap_index::inverse::micro_triangle;
use micromap_index::{spec, Level};
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};
use std::fmt;

/// Where a point of the plane lies with respect to a level's micro-triangles.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Place {
    /// Not in the closed base triangle (`u < 0`, `v < 0` or `u + v > 1`).
    Outside,
    /// In exactly one closed micro-triangle: its interior, or an edge or
    /// corner on the base triangle's boundary that no other micro-triangle
    /// touches.
    OneMicroTriangle,
    /// On an edge shared by two micro-triangles (not at a vertex).
    SharedEdge,
    /// On a lattice vertex shared by two or more micro-triangles (every
    /// lattice vertex but the base triangle's three corners).
    SharedVertex,
}

/// Where `(u, v)` lies at `level`, exactly.
///
/// ```
/// use micromap_index_conformance::vectors::{place_of, Place};
/// use micromap_index::Level;
/// use num_rational::BigRational;
/// let r = |p: i64, q: i64| BigRational::new(p.into(), q.into());
/// let level = Level::new(1).unwrap();
/// assert_eq!(place_of(&r(1, 2), &r(0, 1), level), Place::SharedVertex);
/// assert_eq!(place_of(&r(1, 4), &r(1, 4), level), Place::SharedEdge); // on u + v = 1/2
/// assert_eq!(place_of(&r(1, 4), &r(0, 1), level), Place::OneMicroTriangle); // outer edge
/// assert_eq!(place_of(&r(0, 1), &r(0, 1), level), Place::OneMicroTriangle); // corner
/// assert_eq!(place_of(&r(3, 4), &r(1, 2), level), Place::Outside);
/// ```
#[must_use]
pub fn place_of(u: &BigRational, v: &BigRational, level: Level) -> Place {
    if u.is_negative() || v.is_negative() || u + v > BigRational::one() {
        return Place::Outside;
    }
    let side = BigRational::from_integer(BigInt::one() << level.get());
    let (x, y) = (u * &side, v * &side);
    let sum = &x + &y;
    let on_lines = [&x, &y, &sum]
        .iter()
        .filter(|coordinate| coordinate.is_integer())
        .count();
    let corner =
        (x.is_zero() && y.is_zero()) || (x.is_zero() && y == side) || (y.is_zero() && x == side);
    let outer_edge = x.is_zero() || y.is_zero() || sum == side;
    match on_lines {
        0 => Place::OneMicroTriangle,
        // One line only: an edge; shared unless it is the base triangle's.
        1 if outer_edge => Place::OneMicroTriangle,
        1 => Place::SharedEdge,
        // Two lines meet only at vertices (then all three hold).
        _ if corner => Place::OneMicroTriangle,
        _ => Place::SharedVertex,
    }
}

/// Whether the closed micro-triangle `index` at `level` contains `(u, v)`,
/// exactly; `None` if `index >= 4^level`.
///
/// ```
/// use micromap_index_conformance::vectors::micro_triangle_contains;
/// use micromap_index::Level;
/// use num_rational::BigRational;
/// let r = |p: i64, q: i64| BigRational::new(p.into(), q.into());
/// let level = Level::new(1).unwrap();
/// // (1/4, 1/4) lies on the edge between triangles 0 and 1 of level 1.
/// assert_eq!(micro_triangle_contains(level, 0, &r(1, 4), &r(1, 4)), Some(true));
/// assert_eq!(micro_triangle_contains(level, 1, &r(1, 4), &r(1, 4)), Some(true));
/// assert_eq!(micro_triangle_contains(level, 3, &r(1, 4), &r(1, 4)), Some(false));
/// assert_eq!(micro_triangle_contains(level, 4, &r(1, 4), &r(1, 4)), None);
/// ```
#[must_use]
pub fn micro_triangle_contains(
    level: Level,
    index: u64,
    u: &BigRational,
    v: &BigRational,
) -> Option<bool> {
    let triangle = micro_triangle(level, index).ok()?;
    let side = BigRational::from_integer(BigInt::one() << level.get());
    let point = (u * &side, v * &side);
    let vertices = triangle.vertices_scaled().map(|(a, b)| {
        (
            BigRational::from_integer(a.into()),
            BigRational::from_integer(b.into()),
        )
    });
    // The sign of the cross product (b - a) x (p - a) for each edge: the
    // point is in the closed triangle iff the signs never disagree.
    let mut positive = false;
    let mut negative = false;
    for k in 0..3 {
        let (a, b) = (&vertices[k], &vertices[(k + 1) % 3]);
        let cross = (&b.0 - &a.0) * (&point.1 - &a.1) - (&b.1 - &a.1) * (&point.0 - &a.0);
        positive |= cross.is_positive();
        negative |= cross.is_negative();
    }
    Some(!(positive && negative))
}

/// Why an answer differs from the expected index, from the most dangerous
/// class to the most benign (the order of [`MismatchClass::ALL`] and of the
/// report). Every mismatch has exactly one class.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum MismatchClass {
    /// The answered index is `>= 4^level`: a micromap lookup with it reads
    /// past the end of the level's data.
    OutOfRange,
    /// The answered micro-triangle does not contain the point (a point of
    /// the closed base triangle), and the difference is not the binary32
    /// rounding window's.
    WrongTriangle,
    /// The point lies on an edge shared by two micro-triangles and the
    /// answer is the other one: a different tie-break.
    TieBreakEdge,
    /// The point is a lattice vertex and the answer is another of the
    /// micro-triangles that share it: a different tie-break.
    TieBreakVertex,
    /// Expected and answer are the reference's binary32 and exact answers
    /// at this point (in either order): the rounding of `uf + vf` decides.
    RoundingWindow,
    /// The input is not a point of the closed triangle (negative, above
    /// one, infinite, `u + v > 1`) and no coordinate is NaN: the
    /// reference's clamping decides.
    Clamp,
    /// A coordinate is NaN: this project's reading of the clamp (every NaN
    /// to 0) decides.
    Nan,
    /// The implementation answered `"error"`: it refused the input.
    Refused,
}

impl MismatchClass {
    /// Every class, most dangerous first.
    pub const ALL: [MismatchClass; 8] = [
        MismatchClass::OutOfRange,
        MismatchClass::WrongTriangle,
        MismatchClass::TieBreakEdge,
        MismatchClass::TieBreakVertex,
        MismatchClass::RoundingWindow,
        MismatchClass::Clamp,
        MismatchClass::Nan,
        MismatchClass::Refused,
    ];

    /// The class's name in reports: `out-of-range`, `wrong-triangle`, ...
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            MismatchClass::OutOfRange => "out-of-range",
            MismatchClass::WrongTriangle => "wrong-triangle",
            MismatchClass::TieBreakEdge => "tie-break-edge",
            MismatchClass::TieBreakVertex => "tie-break-vertex",
            MismatchClass::RoundingWindow => "rounding-window",
            MismatchClass::Clamp => "clamp",
            MismatchClass::Nan => "nan",
            MismatchClass::Refused => "refused",
        }
    }

    /// One line saying what the class means for an implementation.
    #[must_use]
    pub fn meaning(self) -> &'static str {
        match self {
            MismatchClass::OutOfRange => {
                "index >= 4^level: a micromap lookup reads past the end of the buffer"
            }
            MismatchClass::WrongTriangle => {
                "the answered micro-triangle does not contain the point"
            }
            MismatchClass::TieBreakEdge => {
                "point on a shared edge; the answer is the other micro-triangle (tie-break)"
            }
            MismatchClass::TieBreakVertex => {
                "point on a shared vertex; the answer is another micro-triangle at it (tie-break)"
            }
            MismatchClass::RoundingWindow => {
                "binary32 vs exact: the rounding of uf + vf decides (answer is the other reading)"
            }
            MismatchClass::Clamp => "input outside the triangle: the reference's clamp decides",
            MismatchClass::Nan => "NaN input: this project's reading (NaN clamps to 0) decides",
            MismatchClass::Refused => "the implementation refused the input (\"error\")",
        }
    }

    /// Out of range or not containing the point: the answer names memory or
    /// a micro-triangle that a correct lookup never would.
    #[must_use]
    pub fn is_dangerous(self) -> bool {
        matches!(
            self,
            MismatchClass::OutOfRange | MismatchClass::WrongTriangle
        )
    }
}

impl fmt::Display for MismatchClass {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The class of the answer `got` to the case `(u, v, level)` whose expected
/// index is `expected` (`got` differs from it) in a file of `function`
/// (an `eval` variant name). `u`, `v` in the value syntax, as the file
/// writes them; a `u` or `v` that does not parse is classed by the rest.
///
/// ```
/// use micromap_index_conformance::vectors::{classify, Answer, MismatchClass};
/// // (1/4, 1/4) at level 1 is on the edge between triangles 0 and 1.
/// let class = |got| classify("spec-exact", "1/4", "1/4", 1, 1, &Answer::Index(got));
/// assert_eq!(class(0), MismatchClass::TieBreakEdge);
/// assert_eq!(class(3), MismatchClass::WrongTriangle);
/// assert_eq!(class(4), MismatchClass::OutOfRange);
/// assert_eq!(classify("spec-f32", "0x7fc00000", "0x3e800000", 1, 0, &Answer::Index(2)), MismatchClass::Nan);
/// ```
#[must_use]
pub fn classify(
    function: &str,
    u: &str,
    v: &str,
    level: u32,
    expected: u64,
    got: &Answer,
) -> MismatchClass {
    let got = match got {
        Answer::Index(index) => *index,
        Answer::Refused(_) | Answer::Unsupported => return MismatchClass::Refused,
    };
    let Ok(checked_level) = Level::new(level) else {
        return MismatchClass::OutOfRange;
    };
    if micro_triangle(checked_level, got).is_err() {
        return MismatchClass::OutOfRange;
    }
    let (Ok(u), Ok(v)) = (Value::parse(u), Value::parse(v)) else {
        return MismatchClass::WrongTriangle;
    };
    if is_nan(&u) || is_nan(&v) {
        return MismatchClass::Nan;
    }
    let (Ok(exact_u), Ok(exact_v)) = (u.to_exact(), v.to_exact()) else {
        return MismatchClass::Clamp; // an infinity
    };
    let place = place_of(&exact_u, &exact_v, checked_level);
    if place == Place::Outside {
        return MismatchClass::Clamp;
    }
    // The reference's two readings at this point: exact, and binary32 when
    // the point is a binary32 value (inputs of spec-f32, and of the exact
    // sets' binary32 points).
    let exact = spec::wide_index_real(&exact_u, &exact_v, checked_level);
    let binary32 = match (u.to_f32(), v.to_f32(), binary32_function(function)) {
        (Ok(fu), Ok(fv), _) if level <= 16 => {
            Some(u64::from(spec::reference_bits_f32(fu, fv, level)))
        }
        (Ok(fu), Ok(fv), Some(Variant::SpecWideF32)) => {
            Some(spec::wide_index_f32(fu, fv, checked_level))
        }
        _ => None,
    };
    if let Some(binary32) = binary32 {
        if binary32 != exact
            && ((got == exact && expected == binary32) || (got == binary32 && expected == exact))
        {
            return MismatchClass::RoundingWindow;
        }
    }
    match micro_triangle_contains(checked_level, got, &exact_u, &exact_v) {
        Some(true) => match place {
            Place::SharedEdge => MismatchClass::TieBreakEdge,
            Place::SharedVertex => MismatchClass::TieBreakVertex,
            // The point's only micro-triangle is the answer: the expected
            // index is not the exact one, so binary32 rounding made it.
            _ => MismatchClass::RoundingWindow,
        },
        _ => MismatchClass::WrongTriangle,
    }
}

fn is_nan(value: &Value) -> bool {
    match value {
        Value::F32Bits(bits) => f32::from_bits(*bits).is_nan(),
        Value::F64Bits(bits) => f64::from_bits(*bits).is_nan(),
        Value::Exact(_) => false,
    }
}

/// The variant if `function` names one that evaluates in binary32.
fn binary32_function(function: &str) -> Option<Variant> {
    Variant::from_name(function).filter(|variant| {
        matches!(
            variant,
            Variant::SpecF32 | Variant::SpecF32ByIntegers | Variant::SpecWideF32
        )
    })
}
