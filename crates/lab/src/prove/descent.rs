//! The descent.

#[allow(clippy::wildcard_imports)]
use super::*;

/// A node of the subdivision tree: state, owned mask, index prefix and its
/// corners in global coordinates at scale `2^level` (`x = u * 2^level`).
#[derive(Clone, Copy, Debug)]
pub(super) struct Node {
    pub(super) state: u16,
    pub(super) owned: u8,
    pub(super) index: u64,
    pub(super) corners: [[u64; 2]; 3],
}

impl Node {
    pub(super) fn root(level: Level) -> Node {
        let side = 1u64 << level.get();
        Node {
            state: 0,
            owned: ALL_OWNED,
            index: 0,
            corners: [[0, 0], [side, 0], [0, side]],
        }
    }
}

/// What the descent does at each node it reaches (a trait, not a closure,
/// so that the hot visitor is inlined into the descent).
pub(super) trait Visitor {
    fn visit(&mut self, node: &Node);
}

/// A node's corners and edge midpoints in the order of
/// [`LEVEL1_VERTICES`]: the corners of its children.
#[inline(always)]
pub(super) fn level1_points(corners: [[u64; 2]; 3]) -> [[u64; 2]; 6] {
    let [a, b, c] = corners;
    // Corners are multiples of 2 above the leaves: the halves are exact.
    let mid = |p: [u64; 2], q: [u64; 2]| [(p[0] + q[0]) / 2, (p[1] + q[1]) / 2];
    [a, b, c, mid(a, b), mid(b, c), mid(c, a)]
}

/// The child of `node` at `position` (the children are in digit order).
#[inline(always)]
pub(super) fn child_node(node: &Node, child: &Child, points: &[[u64; 2]; 6]) -> Node {
    Node {
        state: child.state,
        owned: child.owned,
        index: (node.index << 2) | u64::from(child.digit),
        corners: child.corners.map(|k| points[usize::from(k)]),
    }
}

/// The four children of `node`, in digit order.
#[inline(always)]
pub(super) fn children(table: &Table, node: &Node) -> [Node; 4] {
    let points = level1_points(node.corners);
    table.children[usize::from(node.state)].map(|child| child_node(node, &child, &points))
}

/// Visits every node `depth` levels below `node`, in index order.
pub(super) fn descend<V: Visitor>(table: &Table, node: &Node, depth: u32, visitor: &mut V) {
    if depth == 0 {
        visitor.visit(node);
    } else {
        for child in &children(table, node) {
            descend(table, child, depth - 1, visitor);
        }
    }
}

/// A leaf's faces, one representative point each at scale `4 * 2^level`:
/// `(4a + 1, 4b + 1)` / `(4a + 3, 4b + 3)` for the upright / upside-down
/// micro-triangle of cell `(a, b)`, then `2(A + B)` for each edge `AB` and
/// `4P` for each vertex `P` (the points [`lattice::faces`] uses), in the
/// order of the owned-mask bits [`CANDIDATE_BITS`].
pub(super) fn leaf_candidates(corners: [[u64; 2]; 3]) -> ([u64; 2], [[u64; 2]; 6]) {
    let [a, b, c] = corners;
    let vertex = |p: [u64; 2]| [4 * p[0], 4 * p[1]];
    (
        interior_point(corners),
        [
            edge(b, c),
            edge(c, a),
            edge(a, b),
            vertex(a),
            vertex(b),
            vertex(c),
        ],
    )
}

/// The representative of a leaf's interior at scale `4 * 2^level`.
#[inline(always)]
pub(super) fn interior_point([a, b, c]: [[u64; 2]; 3]) -> [u64; 2] {
    // Upright: the corner sums are 3a+1 with minimum a; upside-down 3a+2.
    // Both give 2 * sum - 2 * min - 1 = 4a+1 resp. 4a+3.
    let coordinate = |i: usize| {
        let sum = a[i] + b[i] + c[i];
        2 * sum - 2 * a[i].min(b[i]).min(c[i]) - 1
    };
    [coordinate(0), coordinate(1)]
}

/// The representative of the edge `PQ` (of the vertex `P` if `P == Q`) at
/// scale `4 * 2^level`.
#[inline(always)]
pub(super) fn edge(p: [u64; 2], q: [u64; 2]) -> [u64; 2] {
    [2 * (p[0] + q[0]), 2 * (p[1] + q[1])]
}

/// The owned-mask bit of each of [`leaf_candidates`]' six boundary faces:
/// the edges opposite vertices 0, 1, 2, then the vertices 0, 1, 2.
pub(super) const CANDIDATE_BITS: [u8; 6] = [3, 4, 5, 0, 1, 2];

/// The number of faces a leaf with each owned mask has: its interior and
/// one per set bit.
pub(super) const OWNED_FACES: [u8; 64] = {
    let mut counts = [0; 64];
    let mut mask = 0;
    while mask < 64 {
        counts[mask] = 1 + (mask as u8).count_ones() as u8;
        mask += 1;
    }
    counts
};

/// The faces a leaf owns, interior first.
#[derive(Clone, Copy)]
pub(super) struct LeafFaces {
    pub(super) points: [[u64; 2]; 7],
    pub(super) len: usize,
}

impl LeafFaces {
    pub(super) fn of(corners: [[u64; 2]; 3], owned: u8) -> LeafFaces {
        let (interior, candidates) = leaf_candidates(corners);
        let mut points = [interior; 7];
        let mut len = 1;
        for (point, bit) in candidates.into_iter().zip(CANDIDATE_BITS) {
            if owned & (1 << bit) != 0 {
                points[len] = point;
                len += 1;
            }
        }
        LeafFaces { points, len }
    }

    pub(super) fn as_slice(&self) -> &[[u64; 2]] {
        &self.points[..self.len]
    }
}

/// A node one level above the leaves, with its four leaves' faces: what
/// the hot loop walks (faces come from the table's lists, so there is no
/// branch per leaf).
pub(super) struct Twig<'t> {
    pub(super) node: Node,
    /// [`level1_points`], padded to 8 so that `k & 7` indexes without a
    /// bounds check.
    pub(super) points: [[u64; 2]; 8],
    pub(super) children: &'t [Child; 4],
    pub(super) boundary: &'t [BoundaryFace],
}

impl<'t> Twig<'t> {
    #[inline(always)]
    pub(super) fn new(table: &'t Table, node: &Node) -> Twig<'t> {
        let [a, b, c, ab, bc, ca] = level1_points(node.corners);
        Twig {
            node: *node,
            points: [a, b, c, ab, bc, ca, a, a],
            children: &table.children[usize::from(node.state)],
            boundary: table.boundary_of(node.state),
        }
    }

    /// The leaf at `position` (in digit order).
    pub(super) fn leaf(&self, position: usize) -> Node {
        let [a, b, c, ab, bc, ca, ..] = self.points;
        child_node(&self.node, &self.children[position], &[a, b, c, ab, bc, ca])
    }

    /// The walk's index of the leaf at `position`.
    #[inline(always)]
    pub(super) fn leaf_index(&self, position: usize) -> u64 {
        (self.node.index << 2) | u64::from(self.children[position].digit)
    }

    /// The interior representative of the leaf at `position`.
    #[inline(always)]
    pub(super) fn interior(&self, position: usize) -> [u64; 2] {
        let corners = self.children[position].corners;
        interior_point(corners.map(|k| self.points[usize::from(k & 7)]))
    }

    /// The owned open edges and vertices: (leaf position, representative).
    #[inline(always)]
    pub(super) fn boundary_faces(&self) -> impl Iterator<Item = (usize, [u64; 2])> + '_ {
        self.boundary.iter().map(|face| {
            let [p, q] = face.ends.map(|k| self.points[usize::from(k & 7)]);
            (usize::from(face.child & 3), edge(p, q))
        })
    }
}

/// Calls `visit` with every face of the level's lattice and the index the
/// walk gives it, on one thread. These are the faces and indices the hot
/// loop of [`prove_level`] compares, exposed so that they can be checked
/// against the direct walk.
///
/// ```
/// use micromap_index_lab::prove::{for_each_face, WalkVersion};
/// use micromap_index::{uv2index, Level};
/// let level = Level::new(3).unwrap();
/// let mut faces = 0;
/// for_each_face(level, WalkVersion::Version2, |face, index| {
///     let (u, v) = face.to_fixed64();
///     assert_eq!(uv2index::index_unchecked(u, v, level), index);
///     faces += 1;
/// }).unwrap();
/// assert_eq!(faces, 217);
/// ```
pub fn for_each_face(
    level: Level,
    version: WalkVersion,
    visit: impl FnMut(Face, u64),
) -> Result<(), ProveError> {
    struct EveryFace<'t, F> {
        table: &'t Table,
        level: Level,
        visit: F,
    }
    impl<F: FnMut(Face, u64)> EveryFace<'_, F> {
        fn face(&mut self, [x, y]: [u64; 2], index: u64) {
            let kind = FaceKind::at(x, y);
            let level = self.level;
            (self.visit)(Face { level, x, y, kind }, index);
        }
    }
    impl<F: FnMut(Face, u64)> Visitor for EveryFace<'_, F> {
        fn visit(&mut self, node: &Node) {
            let twig = Twig::new(self.table, node);
            for position in 0..4 {
                self.face(twig.interior(position), twig.leaf_index(position));
            }
            for (position, point) in twig.boundary_faces() {
                self.face(point, twig.leaf_index(position));
            }
        }
    }
    let table = Table::build(version)?;
    let mut every_face = EveryFace {
        table: &table,
        level,
        visit,
    };
    if let Some(twig_depth) = level.get().checked_sub(1) {
        descend(&table, &Node::root(level), twig_depth, &mut every_face);
    } else {
        // Level 0: the root is the only leaf.
        let root = Node::root(level);
        for &point in LeafFaces::of(root.corners, root.owned).as_slice() {
            every_face.face(point, root.index);
        }
    }
    Ok(())
}
