//! The transition table.

#[allow(clippy::wildcard_imports)]
use super::*;

/// Owned-mask bits: vertex `j` is bit `j`, the open edge opposite vertex
/// `j` is bit `3 + j`. The interior is always owned.
pub(super) const ALL_OWNED: u8 = 0b11_1111;

/// A node's local vertices in the order [`Walk`] weighs them: vertex 0 by
/// `w`, vertex 1 by `u`, vertex 2 by `v`. The parent's level-1 vertices, at
/// scale 8 (`u = x / 8`, `v = y / 8`): V0, V1, V2, M01, M12, M20.
pub(super) const LEVEL1_VERTICES: [(i64, i64); 6] =
    [(0, 0), (8, 0), (0, 8), (4, 0), (4, 4), (0, 4)];

/// Which of a triangle's closed faces a point with these barycentrics is in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum LocalFace {
    Vertex(usize),
    EdgeOpposite(usize),
    Interior,
}

impl LocalFace {
    /// From which barycentrics are zero, in vertex order `[w, u, v]`.
    pub(super) fn from_zeros(zero: [bool; 3]) -> Option<LocalFace> {
        match zero {
            [false, false, false] => Some(LocalFace::Interior),
            [true, false, false] => Some(LocalFace::EdgeOpposite(0)),
            [false, true, false] => Some(LocalFace::EdgeOpposite(1)),
            [false, false, true] => Some(LocalFace::EdgeOpposite(2)),
            [false, true, true] => Some(LocalFace::Vertex(0)),
            [true, false, true] => Some(LocalFace::Vertex(1)),
            [true, true, false] => Some(LocalFace::Vertex(2)),
            [true, true, true] => None,
        }
    }

    /// The owned-mask bit, `None` for the (always owned) interior.
    pub(super) fn mask_bit(self) -> Option<u8> {
        match self {
            LocalFace::Vertex(j) => Some(1 << j),
            LocalFace::EdgeOpposite(j) => Some(1 << (3 + j)),
            LocalFace::Interior => None,
        }
    }
}

/// The walk's state at a node, as far as the rest of the walk cares.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) struct NodeState {
    pub(super) mid_flip: bool,
    pub(super) top_flip: bool,
    pub(super) owned: u8,
}

/// One child of a node, as the step makes it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Child {
    pub(super) digit: u8,
    /// Index of the child's state in [`Table::states`].
    pub(super) state: u16,
    /// The child's owned mask (also in its state; here to save a lookup).
    pub(super) owned: u8,
    /// For each of the child's local vertices 0, 1, 2: which of the
    /// parent's [`LEVEL1_VERTICES`] it is.
    pub(super) corners: [u8; 3],
}

/// The walk's step tabulated per node state: for each reachable (flags,
/// owned mask), the four children in digit order.
///
/// ```
/// use micromap_index_lab::prove::{Table, WalkVersion};
/// let table = Table::build(WalkVersion::Version2).unwrap();
/// assert_eq!(table.state_count(), 8); // flags x owned masks actually reached
/// ```
#[derive(Clone, Debug)]
pub struct Table {
    pub(super) states: Vec<NodeState>,
    pub(super) children: Vec<[Child; 4]>,
    /// Per state, the open edges and vertices its four children own, as
    /// one list (`boundary[boundary_start[s]..boundary_start[s + 1]]`).
    pub(super) boundary: Vec<BoundaryFace>,
    pub(super) boundary_start: Vec<usize>,
}

/// An open edge or a vertex that one child of a node owns: its
/// representative is `2 (P + Q)` at scale `4 * 2^level`, `P`, `Q` two of the
/// node's [`LEVEL1_VERTICES`] (equal for a vertex).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct BoundaryFace {
    pub(super) child: u8,
    pub(super) ends: [u8; 2],
}

/// A walk at `(x, y) / 2^scale_log2` with the given flags.
pub(super) fn walk_at(x: i64, y: i64, scale_log2: u32, state: NodeState) -> Option<Walk<Fixed64>> {
    let mut walk = Walk::new(
        Fixed64::from_scaled(x, scale_log2)?,
        Fixed64::from_scaled(y, scale_log2)?,
    );
    walk.mid_flip = state.mid_flip;
    walk.top_flip = state.top_flip;
    Some(walk)
}

/// The walk's local barycentrics in vertex order `[w, u, v]`, raw.
pub(super) fn barycentrics(walk: &Walk<Fixed64>) -> [i64; 3] {
    [walk.w.raw(), walk.u.raw(), walk.v.raw()]
}

/// Which local face of the child a point with these raw barycentrics is
/// in, if it is in the closed child at all.
pub(super) fn child_face(raw: [i64; 3]) -> Option<LocalFace> {
    let one = Fixed64::ONE.raw();
    if raw.iter().any(|&c| !(0..=one).contains(&c)) {
        return None;
    }
    LocalFace::from_zeros(raw.map(|c| c == 0))
}

/// What one step does to one face of the parent's level-1 lattice.
pub(super) struct StepOutcome {
    pub(super) digit: u8,
    pub(super) flags: (bool, bool),
    pub(super) barycentrics: [i64; 3],
}

pub(super) fn step_once(
    version: WalkVersion,
    x: i64,
    y: i64,
    scale_log2: u32,
    state: NodeState,
) -> Option<StepOutcome> {
    let mut walk = walk_at(x, y, scale_log2, state)?;
    let digit = version.step(&mut walk);
    Some(StepOutcome {
        digit,
        flags: (walk.mid_flip, walk.top_flip),
        barycentrics: barycentrics(&walk),
    })
}

/// What is known about one child while a state is being tabulated.
#[derive(Clone, Copy)]
pub(super) struct ChildDraft {
    pub(super) flags: (bool, bool),
    pub(super) owned: u8,
    /// A point of the open child, at scale 8.
    pub(super) interior: Option<(i64, i64)>,
}

impl Table {
    /// Tabulates `version`'s step over all node states reachable from the
    /// root (no flags, every face owned).
    pub fn build(version: WalkVersion) -> Result<Table, ProveError> {
        let fail = |why: String| ProveError::Table(why);
        let root = NodeState {
            mid_flip: false,
            top_flip: false,
            owned: ALL_OWNED,
        };
        let mut states = vec![root];
        let mut children = Vec::new();
        let level1 = Level::new(1).map_err(ProveError::Level)?;
        // The 19 faces of the local level-1 lattice, one point each, scale 8.
        let faces: Vec<(i64, i64)> = lattice::faces(level1)
            .map(|face| (face.x as i64, face.y as i64))
            .collect();
        let mut next = 0;
        while next < states.len() {
            let state = states[next];
            next += 1;
            let mut drafts: [Option<ChildDraft>; 4] = [None; 4];
            for &(x, y) in &faces {
                let parent_face = LocalFace::from_zeros([x + y == 8, x == 0, y == 0])
                    .ok_or_else(|| fail(format!("face ({x}, {y})/8 is not in the triangle")))?;
                if let Some(bit) = parent_face.mask_bit() {
                    if state.owned & bit == 0 {
                        continue;
                    }
                }
                let outcome = step_once(version, x, y, 3, state)
                    .ok_or_else(|| fail(format!("({x}, {y})/8 does not fit Fixed64")))?;
                let face = child_face(outcome.barycentrics)
                    .ok_or_else(|| fail(format!("step sends ({x}, {y})/8 outside its child")))?;
                let draft = drafts
                    .get_mut(usize::from(outcome.digit))
                    .ok_or_else(|| fail(format!("digit {} out of range", outcome.digit)))?;
                let draft = draft.get_or_insert(ChildDraft {
                    flags: outcome.flags,
                    owned: 0,
                    interior: None,
                });
                if draft.flags != outcome.flags {
                    return Err(fail(format!(
                        "digit {} reached with two flag sets",
                        outcome.digit
                    )));
                }
                match face.mask_bit() {
                    Some(bit) if draft.owned & bit != 0 => {
                        return Err(fail(format!(
                            "two faces land on one face of child {}",
                            outcome.digit
                        )));
                    }
                    Some(bit) => draft.owned |= bit,
                    None if draft.interior.is_some() => {
                        return Err(fail(format!(
                            "two interiors land in child {}",
                            outcome.digit
                        )));
                    }
                    None => draft.interior = Some((x, y)),
                }
            }
            let mut row = [Child {
                digit: 0,
                state: 0,
                owned: 0,
                corners: [0; 3],
            }; 4];
            for (digit, draft) in drafts.iter().enumerate() {
                let draft = draft.ok_or_else(|| fail(format!("no face reaches child {digit}")))?;
                let interior = draft
                    .interior
                    .ok_or_else(|| fail(format!("child {digit} does not own its interior")))?;
                let child_state = NodeState {
                    mid_flip: draft.flags.0,
                    top_flip: draft.flags.1,
                    owned: draft.owned,
                };
                let index = if let Some(index) = states.iter().position(|&s| s == child_state) {
                    index
                } else {
                    states.push(child_state);
                    states.len() - 1
                };
                row[digit] = Child {
                    digit: digit as u8,
                    state: u16::try_from(index).map_err(|_| fail("too many states".into()))?,
                    owned: child_state.owned,
                    corners: corners_of_child(version, state, digit as u8, interior)?,
                };
            }
            children.push(row);
        }
        let mut boundary = Vec::new();
        let mut boundary_start = vec![0];
        for row in &children {
            for (position, child) in row.iter().enumerate() {
                let [a, b, c] = child.corners;
                // In the order of CANDIDATE_BITS: edges opposite 0, 1, 2,
                // then vertices 0, 1, 2.
                let candidates = [[b, c], [c, a], [a, b], [a, a], [b, b], [c, c]];
                for (ends, bit) in candidates.into_iter().zip(CANDIDATE_BITS) {
                    if child.owned & (1 << bit) != 0 {
                        boundary.push(BoundaryFace {
                            child: position as u8,
                            ends,
                        });
                    }
                }
            }
            boundary_start.push(boundary.len());
        }
        Ok(Table {
            states,
            children,
            boundary,
            boundary_start,
        })
    }

    /// The boundary faces the children of a node in `state` own.
    #[inline(always)]
    pub(super) fn boundary_of(&self, state: u16) -> &[BoundaryFace] {
        let state = usize::from(state);
        &self.boundary[self.boundary_start[state]..self.boundary_start[state + 1]]
    }

    /// The number of reachable node states.
    #[must_use]
    pub fn state_count(&self) -> usize {
        self.states.len()
    }
}

/// Where the child's local vertices are among the parent's level-1
/// vertices, learnt from the step itself: the step is one affine map `A`
/// on the open child, so for a parent vertex `X` and the child's interior
/// point `p`, the midpoint `q = (p + X) / 2` (inside the child when `X` is
/// one of its corners) gives `A(X) = 2 A(q) - A(p)`; `X` is the child's
/// vertex `j` when `A(X)` is the `j`-th unit vector.
pub(super) fn corners_of_child(
    version: WalkVersion,
    state: NodeState,
    digit: u8,
    interior: (i64, i64),
) -> Result<[u8; 3], ProveError> {
    let fail = |why: String| ProveError::Table(why);
    let (px, py) = interior;
    let at_interior = step_once(version, px, py, 3, state)
        .ok_or_else(|| fail("interior point does not fit".into()))?;
    let one = Fixed64::ONE.raw();
    let mut corners = [None; 3];
    for (source, &(vx, vy)) in LEVEL1_VERTICES.iter().enumerate() {
        // (p + X) / 2 at scale 16.
        let Some(halfway) = step_once(version, px + vx, py + vy, 4, state) else {
            continue;
        };
        if halfway.digit != digit || halfway.flags != at_interior.flags {
            continue; // `q` is in another child: `X` is not a corner of this one.
        }
        let image: [i64; 3] =
            std::array::from_fn(|c| 2 * halfway.barycentrics[c] - at_interior.barycentrics[c]);
        for (j, corner) in corners.iter_mut().enumerate() {
            let unit: [i64; 3] = std::array::from_fn(|c| if c == j { one } else { 0 });
            if image == unit {
                if corner.is_some() {
                    return Err(fail(format!("child {digit} has two vertices {j}")));
                }
                *corner = Some(source as u8);
            }
        }
    }
    let mut found = [0u8; 3];
    for (j, corner) in corners.iter().enumerate() {
        found[j] = corner.ok_or_else(|| fail(format!("child {digit}: vertex {j} not found")))?;
    }
    Ok(found)
}
