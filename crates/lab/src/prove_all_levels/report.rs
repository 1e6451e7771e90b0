//! What the search reports (verdict, counts, the product it explored),
//! the real functions at a face, and the printing of states and
//! transitions (for `micromap-lab prove --all-levels --list` and the
//! docs).

#[allow(clippy::wildcard_imports)]
use super::*;

/// The verdict of [`prove_all_levels`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// No reachable state of the product emits two different digits: the
    /// walk equals the reference at every point of every level.
    Proved,
    /// A reachable column where the digits differ, completed to a point and
    /// a level.
    Counterexample(Box<Counterexample>),
    /// A reachable state where a transducer cannot go on (see the message).
    Failed(ModelError),
}

/// A point and level where the walk and the reference differ, found by the
/// search and recomputed with the real functions.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Counterexample {
    /// The level.
    pub level: Level,
    /// The face of the level's lattice the point lies in (its
    /// representative point, kind).
    pub face: Face,
    /// The point found: `(x, y) / 2^scale_log2`.
    pub point: (u128, u128, u32),
    /// The walk transducer's index.
    pub walk_index: u64,
    /// The reference transducer's index.
    pub reference_index: u64,
    /// The real functions at the face's representative: the walk
    /// ([`uv2index::index_unchecked`] or `internals::index_version1_unchecked` on
    /// [`micromap_index::num::Fixed64`]) and [`spec::wide_index_dyadic`]. `None` for a mutated
    /// machine (no real walk to run).
    pub real: Option<(u64, u64)>,
}

/// Counts of what the search reached.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StateCounts {
    /// Checker states (remainder sum and zero flags) that can still end
    /// in a valid word.
    pub checker: usize,
    /// Checker x reference-guess states from which a level can end.
    pub live_guesses: usize,
    /// Distinct walk transducer states reached.
    pub walk: usize,
    /// Distinct reference transducer states reached.
    pub reference: usize,
    /// Product states reached.
    pub product: usize,
    /// Product transitions explored (each compares two digits).
    pub transitions: usize,
    /// Start states (first column and guess).
    pub starts: usize,
}

/// The outcome of [`prove_all_levels`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AllLevelsReport {
    /// The walk checked (`None` for a mutated machine).
    pub walk: Option<WalkVersion>,
    /// What was reached.
    pub counts: StateCounts,
    /// The verdict.
    pub verdict: Verdict,
    /// The walk transducer's reachable states, sorted (for the docs).
    pub walk_states: Vec<WalkState>,
    /// Every product state reached, in the order the search found them.
    pub product_states: Vec<ProductState>,
    /// Every transition compared, between indices of `product_states`.
    pub transitions: Vec<Transition>,
    /// The start of each state reached from a start (`None` for the others).
    pub starts: Vec<Option<Start>>,
}

/// One transition of the product: both transducers read `column` in state
/// `from` and emit `digit` (the same digit, or the search would have
/// stopped).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Transition {
    /// Index of the source state.
    pub from: usize,
    /// The column read.
    pub column: Column,
    /// The walk's digit.
    pub walk_digit: u8,
    /// The reference's digit.
    pub reference_digit: u8,
    /// Index of the target state.
    pub to: usize,
}

impl AllLevelsReport {
    /// Whether the walk is proved equal to the reference at every level.
    #[must_use]
    pub fn is_proof(&self) -> bool {
        self.verdict == Verdict::Proved
    }
}

/// The real walk and the real reference at the face's representative
/// (an error only for a face finer than `spec::MAX_SCALE_LOG2`, above
/// level 60).
pub fn real_indices(version: WalkVersion, face: &Face) -> Result<(u64, u64), Error> {
    let (u, v) = face.to_fixed64();
    let walk = match version {
        WalkVersion::Version2 => uv2index::index_unchecked(u, v, face.level),
        WalkVersion::Version1 => internals::index_version1_unchecked(u, v, face.level),
    };
    let reference = spec::wide_index_dyadic(face.x, face.y, face.scale_log2(), face.level)?;
    Ok((walk, reference))
}

/// The face of the level's lattice holding the point `(x, y) /
/// 2^scale_log2` of the closed triangle (`scale_log2 <= 62`), as
/// [`crate::lattice::faces`] names it.
///
/// ```
/// use micromap_index_lab::lattice::FaceKind;
/// use micromap_index_lab::prove_all_levels::face_containing;
/// use micromap_index::Level;
/// let level = Level::new(2).unwrap();
/// // (1/16, 1/16): inside the upright micro-triangle of cell (0, 0) ...
/// let face = face_containing(1, 1, 4, level);
/// assert_eq!((face.x, face.y, face.kind), (1, 1, FaceKind::Upright));
/// // ... (3/16, 1/16): on its diagonal edge u + v = 1/4.
/// let face = face_containing(3, 1, 4, level);
/// assert_eq!((face.x, face.y, face.kind), (2, 2, FaceKind::DiagonalEdge));
/// ```
#[must_use]
pub fn face_containing(x: u64, y: u64, scale_log2: u32, level: Level) -> Face {
    let n = level.get();
    let (x, y, m) = if scale_log2 < n {
        (x << (n - scale_log2), y << (n - scale_log2), n)
    } else {
        (x, y, scale_log2)
    };
    let below = m - n;
    let unit = 1u64 << below;
    let (a, b) = (x >> below, y >> below);
    let (ru, rv) = (x & (unit - 1), y & (unit - 1));
    let kind = match (ru == 0, rv == 0) {
        (true, true) => FaceKind::Vertex,
        (true, false) => FaceKind::VerticalEdge,
        (false, true) => FaceKind::HorizontalEdge,
        _ => match (ru + rv).cmp(&unit) {
            Ordering::Equal => FaceKind::DiagonalEdge,
            Ordering::Less => FaceKind::Upright,
            Ordering::Greater => FaceKind::UpsideDown,
        },
    };
    let (dx, dy) = kind.offset();
    Face {
        level,
        x: 4 * a + dx,
        y: 4 * b + dy,
        kind,
    }
}

/// The point's value as `x / 2^scale_log2` (for messages).
fn fraction(numerator: u128, scale_log2: u32) -> String {
    let shift = numerator.trailing_zeros().min(scale_log2);
    let (numerator, scale) = (numerator >> shift, scale_log2 - shift);
    if scale == 0 {
        numerator.to_string()
    } else {
        format!("{numerator}/{}", 1u128 << scale)
    }
}

impl Counterexample {
    /// `u`, `v` of the face's representative as exact fractions.
    #[must_use]
    pub fn representative(&self) -> (String, String) {
        let scale = self.face.scale_log2();
        (
            fraction(u128::from(self.face.x), scale),
            fraction(u128::from(self.face.y), scale),
        )
    }
}

impl fmt::Display for Rest {
    /// `D1 z=u-v` lists the sum and the coordinates whose rest is zero.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "D{} z={}", self.sum, coordinate_list(self.zero))
    }
}

/// The names of the coordinates with a flag set, `-` for none.
fn coordinate_list(flags: [bool; 3]) -> String {
    let names: String = ["u", "v", "w"]
        .iter()
        .zip(flags)
        .filter(|(_, set)| *set)
        .map(|(name, _)| *name)
        .collect();
    if names.is_empty() {
        "-".into()
    } else {
        names
    }
}

impl fmt::Display for Column {
    /// `bits uvw=010 then D1 z=u`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let bits: String = self
            .bits
            .iter()
            .map(|&b| if b { '1' } else { '0' })
            .collect();
        write!(f, "bits {bits} then {}", self.rest)
    }
}

impl fmt::Display for Form {
    /// `1 - Ru - Rv` style.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut text = String::new();
        for (coefficient, name) in [(self.constant, ""), (self.ru, "Ru"), (self.rv, "Rv")] {
            if coefficient == 0 {
                continue;
            }
            let sign = if coefficient < 0 { "-" } else { "+" };
            let magnitude = coefficient.abs();
            let term = match (magnitude, name) {
                (m, "") => m.to_string(),
                (1, n) => n.to_string(),
                (m, n) => format!("{m}{n}"),
            };
            if text.is_empty() {
                text = if coefficient < 0 {
                    format!("-{term}")
                } else {
                    term
                };
            } else {
                text.push(' ');
                text.push_str(sign);
                text.push(' ');
                text.push_str(&term);
            }
        }
        if text.is_empty() {
            text.push('0');
        }
        f.write_str(&text)
    }
}

impl fmt::Display for WalkState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "u={}, v={}, w={}", self.u, self.v, self.w)?;
        match (self.mid_flip, self.top_flip) {
            (false, false) => Ok(()),
            (true, false) => f.write_str(", mid_flip"),
            (false, true) => f.write_str(", top_flip"),
            (true, true) => f.write_str(", mid_flip, top_flip"),
        }
    }
}

impl fmt::Display for ReferenceState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let guess = self.decremented.map_or("-", |c| ["u", "v", "w"][c]);
        write!(
            f,
            "parity {}, minus one on {guess}, zero: {}",
            u8::from(self.parity),
            coordinate_list([self.u_zero, false, self.w_zero])
        )
    }
}

impl AllLevelsReport {
    /// Every state and transition of the product, one per line (what
    /// `micromap-lab prove --all-levels --list` prints).
    #[must_use]
    pub fn listing(&self) -> Vec<String> {
        let mut lines = Vec::new();
        for (id, state) in self.product_states.iter().enumerate() {
            let start = match self.starts.get(id).copied().flatten() {
                Some(start) => format!("  <- start: integer {}", start.column),
                None => String::new(),
            };
            lines.push(format!(
                "S{id}: {} | {} | {}{start}",
                state.rest, state.walk, state.reference
            ));
        }
        for t in &self.transitions {
            lines.push(format!(
                "S{} --[{}]--> S{}  digits walk {} reference {}",
                t.from, t.column, t.to, t.walk_digit, t.reference_digit
            ));
        }
        lines
    }
}
