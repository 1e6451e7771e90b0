//! Every micro-triangle of a level in curve order, walking the tree's path
//! incrementally.

use super::MicroTriangle;
use crate::Level;
use core::iter::FusedIterator;

/// Flag bits of a node of the walk's tree.
const DOWN: u8 = 1;
const TOP_FLIP: u8 = 2;

/// One entry of [`CHILDREN`]: the child's origin is the parent's plus
/// `h * (du, dv)` (`h` half the parent's side), and its flags.
#[derive(Clone, Copy)]
struct Step {
    du: u64,
    /// `1`, `0` or `-1` as a wrapping `u64`.
    dv: u64,
    flags: u8,
}

/// The walk's children for every `flags | digit << 2`: Left keeps the
/// origin, Right moves it by `(h, 0)`, Top and Middle by `h` times the
/// direction from `vertices[0]` to `vertices[2]` (`(0, 1)` upright,
/// `(1, -1)` upside down); Top toggles the flip of Left and Right, Middle
/// the orientation. Derived from `inverse`'s child vertices (module docs).
const CHILDREN: [Step; 16] = {
    let mut table = [Step {
        du: 0,
        dv: 0,
        flags: 0,
    }; 16];
    let mut entry = 0;
    while entry < 16 {
        let flags = (entry & 3) as u8;
        let digit = entry >> 2;
        let down = flags & DOWN != 0;
        let flipped = flags & TOP_FLIP != 0;
        // 0 Left, 1 Middle, 2 Right, 3 Top, with Left and Right swapped by
        // the flip.
        let kind = match digit {
            0 if flipped => 2,
            2 if flipped => 0,
            d => d,
        };
        let (du, dv) = match kind {
            0 => (0, 0),
            2 => (1, 0),
            _ if down => (1, u64::MAX),
            _ => (0, 1),
        };
        let flags = match kind {
            1 => flags ^ DOWN,
            3 => flags ^ TOP_FLIP,
            _ => flags,
        };
        table[entry] = Step { du, dv, flags };
        entry += 1;
    }
    table
};

/// A node of the walk's tree: origin numerators and flags.
#[derive(Clone, Copy, Debug, Default)]
struct Node {
    u: u64,
    v: u64,
    flags: u8,
}

impl Node {
    /// The child with the lowest two bits of `digit`, whose parent's half
    /// side is `2^half_log2` (`const`: [`LEAVES`] is built from it).
    #[inline(always)]
    const fn child(self, digit: u64, half_log2: u32) -> Node {
        let step = CHILDREN[self.flags as usize | ((digit as usize & 3) << 2)];
        Node {
            u: self.u + (step.du << half_log2),
            v: self.v.wrapping_add(step.dv << half_log2),
            flags: step.flags,
        }
    }
}

/// The digits below the iterator's anchor node: its leaves are read from
/// [`LEAVES`], one table entry per micro-triangle.
const GROUP_DIGITS: u32 = 3;

/// A leaf `GROUP_DIGITS` levels below a node: its origin's offset from the
/// node's, in leaf units, and its flags.
#[derive(Clone, Copy)]
struct Leaf {
    du: u8,
    dv: i8,
    flags: u8,
}

/// `LEAVES[flags][s]`: the leaf that the digits of `s` (the last
/// `GROUP_DIGITS` digits of an index) reach from a node with `flags`,
/// by [`Node::child`] one digit at a time. The offsets stay within
/// `0..8` and `-8..8`. A suffix with leading zero digits from the root
/// (flags 0, so digit 0 is Left: same origin, same flags) is also the leaf
/// of a shorter suffix, which serves levels below `GROUP_DIGITS`.
const LEAVES: [[Leaf; 64]; 4] = {
    let mut table = [[Leaf {
        du: 0,
        dv: 0,
        flags: 0,
    }; 64]; 4];
    let mut flags = 0;
    while flags < 4 {
        let mut suffix = 0;
        while suffix < 64 {
            // The walk from a node at the origin, one digit at a time.
            let mut node = Node {
                u: 0,
                v: 0,
                flags: flags as u8,
            };
            let mut below = GROUP_DIGITS;
            while below > 0 {
                below -= 1;
                node = node.child((suffix >> (2 * below)) as u64, below);
            }
            table[flags][suffix] = Leaf {
                du: node.u as u8,
                dv: node.v as i64 as i8,
                flags: node.flags,
            };
            suffix += 1;
        }
        flags += 1;
    }
    table
};

/// Every micro-triangle of `level` in curve order (index `0, 1, 2, ...`),
/// each equal to [`micro_triangle`](super::micro_triangle) of its index.
/// The iterator keeps the walk's path down to the node three levels above
/// the current triangle and redoes only the part that changes: one table
/// read per micro-triangle (the 64 leaves below a node are tabulated for
/// each of its four orientations), and a node of the path per 48 triangles
/// on average.
///
/// ```
/// use micromap_index::inverse::{micro_triangle, micro_triangles};
/// use micromap_index::Level;
/// let level = Level::new(3).unwrap();
/// assert_eq!(micro_triangles(level).count(), 64);
/// for (i, t) in micro_triangles(level).enumerate() {
///     assert_eq!(t, micro_triangle(level, i as u64).unwrap());
/// }
/// ```
#[must_use]
pub fn micro_triangles(level: Level) -> MicroTriangles {
    let level = level.get();
    let mut iter = MicroTriangles {
        level,
        next: 0,
        last: ((1u128 << (2 * level)) - 1) as u64,
        group_end: (1 << (2 * level.min(GROUP_DIGITS))) - 1,
        done: false,
        anchor: Node::default(),
        path: [Node::default(); 32],
    };
    iter.descend_from(1);
    iter
}

/// The iterator of [`micro_triangles`].
#[derive(Clone, Debug)]
pub struct MicroTriangles {
    level: u32,
    /// The index of the next triangle.
    next: u64,
    /// The last index, `4^level - 1`.
    last: u64,
    /// The index digits below the anchor, all 3: `next` moves the anchor
    /// after an index whose low digits are these.
    group_end: u64,
    done: bool,
    /// The node at depth `level - GROUP_DIGITS` on the way to `next` (the
    /// root below that level), the only node the hot path reads: kept out of
    /// `path` so that it stays at a fixed place.
    anchor: Node,
    /// `path[d]` is the node at depth `d` on the way to `next`, for depths
    /// above the anchor's (the root at depth 0).
    path: [Node; 32],
}

impl MicroTriangles {
    /// Recomputes `path[d]` for `d` in `from..` the anchor's depth, and
    /// the anchor, from `next`.
    #[inline(always)]
    fn descend_from(&mut self, from: u32) {
        let Some(anchor_depth) = self.level.checked_sub(GROUP_DIGITS) else {
            return; // The anchor is the root.
        };
        let mut node = self.path[from as usize - 1];
        for depth in from..=anchor_depth {
            let below = self.level - depth; // digits below this node's
            node = node.child(self.next >> (2 * below), below);
            if depth < anchor_depth {
                self.path[depth as usize] = node;
            }
        }
        self.anchor = node;
    }
}

impl Iterator for MicroTriangles {
    type Item = MicroTriangle;

    #[inline]
    fn next(&mut self) -> Option<MicroTriangle> {
        if self.done {
            return None;
        }
        let index = self.next;
        let leaf = LEAVES[usize::from(self.anchor.flags & 3)][(index & 63) as usize];
        let origin = (
            self.anchor.u + u64::from(leaf.du),
            self.anchor.v.wrapping_add(leaf.dv as u64),
        );
        self.next = index.wrapping_add(1);
        if index & self.group_end == self.group_end {
            if index == self.last {
                self.done = true;
            } else {
                // The lowest `k >= GROUP_DIGITS` digits wrapped to 0: the
                // nodes at depths `level - k ..` changed.
                let wrapped = self.next.trailing_zeros() / 2;
                self.descend_from(self.level.saturating_sub(wrapped).max(1));
            }
        }
        Some(MicroTriangle::from_origin(
            Level(self.level as u8),
            index,
            origin,
            leaf.flags & DOWN == 0,
        ))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        if self.done {
            return (0, Some(0));
        }
        let remaining = u128::from(self.last - self.next) + 1;
        match usize::try_from(remaining) {
            Ok(n) => (n, Some(n)),
            Err(_) => (usize::MAX, None),
        }
    }
}

impl FusedIterator for MicroTriangles {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn iterator_ends_at_the_last_index() {
        let level = Level::new(2).unwrap();
        let mut all = micro_triangles(level);
        assert_eq!(all.size_hint(), (16, Some(16)));
        assert_eq!(all.by_ref().last().map(|t| t.index()), Some(15));
        assert_eq!(all.next(), None);
        let mut root = micro_triangles(Level::new(0).unwrap());
        assert_eq!(
            root.next().map(|t| t.vertices_scaled()),
            Some([(0, 0), (1, 0), (0, 1)])
        );
        assert_eq!(root.next(), None);
    }
}
