//! Micro-triangles for bakers: index → exact vertices in constant time
//! ([`triangle`]), and every micro-triangle of a level in curve order
//! ([`triangles`]). Integers only, no allocation, `no_std`.
//!
//! Both return the same vertices, in the same order, as
//! [`inverse::micro_triangle`](crate::inverse::micro_triangle) (which
//! replays the walk digit by digit and is their oracle): `(u, v)` numerators
//! over `2^level`, in the walk's local order (`vertices[0]`, `[1]`, `[2]`
//! carry the walk's weights `w`, `u`, `v`). That order depends only on the
//! orientation: every child of the walk is its parent's affine image, so an
//! upright micro-triangle in cell `(a, b)` is always `(a, b), (a + 1, b),
//! (a, b + 1)` and an upside-down one `(a, b + 1), (a + 1, b + 1),
//! (a + 1, b)`.
//!
//! # Inverting the reference
//!
//! [`triangle`] inverts the reference's integer half instead of replaying
//! the walk. Deinterleaving the index gives `b0` (even bits) and `b1` (odd
//! bits). The reference computes `b0 = iu ^ (iu + iv + d)` (`d` = 1 for the
//! upside-down triangle of the cell), `t = (iu ^ iv) & b0`, the suffix XOR
//! `f` of `t`, and `b1 = ((f ^ iu) & !b0) | t`. So `t = b0 & b1`, and where
//! `b0` is clear `iu = b1 ^ f`. Writing the sum bit by bit with carries `c`
//! (`c_0 = d`), `iu ^ (iu + iv + d) = iv ^ c`, so `iv = b0 ^ c`; a carry
//! passes unchanged where `b0` is clear and becomes `iu_k = !(t_k ^ c_k)`
//! where it is set. Hence `c_k = d ^ (parity of (b0 & !t) below k)`, a
//! prefix XOR, and since the sum stays below `2^level` (no carry out), `d` is
//! the parity of all of `b0 & !t`. Everything is a fixed number of word
//! operations, whatever the level.
//!
//! At levels `0..=19` the walk and the reference agree at every point
//! (`docs/verification.md`), so inverting one inverts the other; the tests
//! also compare every index of levels `0..=10` with the replay, and random
//! indices of every level up to 32.
//!
//! ```
//! use micromap_index::microtri;
//! use micromap_index::Level;
//!
//! let level = Level::new(2).unwrap();
//! let t = microtri::triangle(level, 5).unwrap();
//! assert_eq!(t.vertices_scaled(), [(1, 1), (2, 1), (1, 2)]);
//! assert!(t.upright());
//! // The iterator visits the same triangles in index order.
//! assert_eq!(microtri::triangles(level).nth(5), Some(t));
//! assert_eq!(microtri::triangles(level).count(), 16);
//! ```

use crate::{Error, Level};
use core::iter::FusedIterator;

/// One micro-triangle: its index and exact vertices.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Triangle {
    index: u64,
    /// `vertices[0]` as numerators over `2^level`.
    origin: (u64, u64),
    upright: bool,
}

impl Triangle {
    /// The index on the space-filling curve.
    ///
    /// ```
    /// use micromap_index::{microtri, Level};
    /// assert_eq!(microtri::triangle(Level::new(7).unwrap(), 100).unwrap().index(), 100);
    /// ```
    #[inline]
    #[must_use]
    pub fn index(&self) -> u64 {
        self.index
    }

    /// Whether the micro-triangle has the base triangle's orientation.
    ///
    /// ```
    /// use micromap_index::{microtri, Level};
    /// let level = Level::new(1).unwrap();
    /// let upright: Vec<bool> = microtri::triangles(level).map(|t| t.upright()).collect();
    /// assert_eq!(upright, [true, false, true, true]);
    /// ```
    #[inline]
    #[must_use]
    pub fn upright(&self) -> bool {
        self.upright
    }

    /// The vertices as `(u, v)` numerators over `2^level`, in the walk's
    /// local order (see the [module docs](self)); every numerator is at most
    /// `2^level`.
    ///
    /// ```
    /// use micromap_index::{microtri, Level};
    /// let middle = microtri::triangle(Level::new(1).unwrap(), 1).unwrap();
    /// assert_eq!(middle.vertices_scaled(), [(0, 1), (1, 1), (1, 0)]);
    /// ```
    #[inline]
    #[must_use]
    pub fn vertices_scaled(&self) -> [(u64, u64); 3] {
        let (a, b) = self.origin;
        // Third vertex (a, b + 1) upright, (a + 1, b - 1) upside down,
        // without a branch (the orientation is irregular along the curve).
        let down = u64::from(!self.upright);
        [(a, b), (a + 1, b), (a + down, (b + 1).wrapping_sub(2 * down))]
    }

    /// The grid cell `(iu, iv)` holding the micro-triangle: numerators of the
    /// lower-left corner of the square it lies in (the upside-down triangle
    /// is the upper-right half of its cell).
    ///
    /// ```
    /// use micromap_index::{microtri, Level};
    /// let level = Level::new(1).unwrap();
    /// assert_eq!(microtri::triangle(level, 1).unwrap().cell(), (0, 0));
    /// assert_eq!(microtri::triangle(level, 3).unwrap().cell(), (0, 1));
    /// ```
    #[inline]
    #[must_use]
    pub fn cell(&self) -> (u64, u64) {
        let (a, b) = self.origin;
        if self.upright {
            (a, b)
        } else {
            (a, b - 1)
        }
    }
}

/// The micro-triangle with index `index` at `level`, in constant time (see
/// the [module docs](self)). Every level `0..=32`; an index `>= 4^level` is
/// [`Error::IndexOutOfRange`]. Never panics.
///
/// ```
/// use micromap_index::{microtri, Error, Level};
/// let level = Level::new(1).unwrap();
/// assert_eq!(microtri::triangle(level, 3).unwrap().vertices_scaled(), [(0, 1), (1, 1), (0, 2)]);
/// assert_eq!(microtri::triangle(level, 4), Err(Error::IndexOutOfRange { index: 4, level: 1 }));
/// ```
#[inline]
pub fn triangle(level: Level, index: u64) -> Result<Triangle, Error> {
    if u128::from(index) >= level.micro_triangle_count() {
        return Err(Error::IndexOutOfRange {
            index,
            level: level.get(),
        });
    }
    let last = ((1u64 << level.get()) - 1) as u32;
    let (b0, b1) = deinterleave(index);
    let t = b0 & b1;
    let mut f = t;
    f ^= f >> 1;
    f ^= f >> 2;
    f ^= f >> 4;
    f ^= f >> 8;
    f ^= f >> 16;
    // Inclusive prefix XOR from the bottom: bit k is the parity of
    // `b0 & !t` at bits 0..=k, bit 31 the parity of all of it, which is `d`.
    let mut p = b0 & !t;
    p ^= p << 1;
    p ^= p << 2;
    p ^= p << 4;
    p ^= p << 8;
    p ^= p << 16;
    let d = p >> 31;
    let carries = (0u32.wrapping_sub(d)) ^ (p << 1);
    let iv = (b0 ^ carries) & last;
    let iu = (((b1 ^ f) & !b0) | ((t ^ !carries) & b0)) & last;
    let (iu, iv) = (u64::from(iu), u64::from(iv));
    Ok(Triangle {
        index,
        origin: if d == 0 { (iu, iv) } else { (iu, iv + 1) },
        upright: d == 0,
    })
}

/// The even bits of `x` (packed, low to high) and the odd bits: the inverse
/// perfect shuffle (Hacker's Delight, 7-2).
#[inline]
fn deinterleave(x: u64) -> (u32, u32) {
    let mut x = x;
    let mut t;
    t = (x ^ (x >> 1)) & 0x2222_2222_2222_2222;
    x ^= t ^ (t << 1);
    t = (x ^ (x >> 2)) & 0x0c0c_0c0c_0c0c_0c0c;
    x ^= t ^ (t << 2);
    t = (x ^ (x >> 4)) & 0x00f0_00f0_00f0_00f0;
    x ^= t ^ (t << 4);
    t = (x ^ (x >> 8)) & 0x0000_ff00_0000_ff00;
    x ^= t ^ (t << 8);
    t = (x ^ (x >> 16)) & 0x0000_0000_ffff_0000;
    x ^= t ^ (t << 16);
    (x as u32, (x >> 32) as u32)
}

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
    #[inline(always)]
    fn child(self, digit: u64, half_log2: u32) -> Node {
        let step = CHILDREN[usize::from(self.flags) | ((digit as usize & 3) << 2)];
        Node {
            u: self.u + (step.du << half_log2),
            v: self.v.wrapping_add(step.dv << half_log2),
            flags: step.flags,
        }
    }
}

/// Every micro-triangle of `level` in curve order (index `0, 1, 2, ...`),
/// each equal to [`triangle`] of its index. The iterator keeps the walk's
/// path to the current triangle and redoes only the part that changes, a
/// third of a node per triangle on average.
///
/// ```
/// use micromap_index::{microtri, Level};
/// let level = Level::new(3).unwrap();
/// for (i, t) in microtri::triangles(level).enumerate() {
///     assert_eq!(t, microtri::triangle(level, i as u64).unwrap());
/// }
/// ```
#[must_use]
pub fn triangles(level: Level) -> Triangles {
    let mut iter = Triangles {
        level: level.get(),
        next: 0,
        last: ((1u128 << (2 * level.get())) - 1) as u64,
        done: false,
        path: [Node::default(); 32],
    };
    iter.descend_from(1);
    iter
}

/// The iterator of [`triangles`].
#[derive(Clone, Debug)]
pub struct Triangles {
    level: u32,
    /// The index of the next triangle.
    next: u64,
    /// The last index, `4^level - 1`.
    last: u64,
    done: bool,
    /// `path[d]` is the node at depth `d` on the way to `next`, for
    /// `d < level` (the root at depth 0).
    path: [Node; 32],
}

impl Triangles {
    /// Recomputes `path[d]` for `d` in `from..level` from `next`.
    #[inline(always)]
    fn descend_from(&mut self, from: u32) {
        for depth in from..self.level {
            let below = self.level - depth; // digits below this node's
            let digit = self.next >> (2 * below);
            self.path[depth as usize] = self.path[depth as usize - 1].child(digit, below);
        }
    }
}

impl Iterator for Triangles {
    type Item = Triangle;

    #[inline]
    fn next(&mut self) -> Option<Triangle> {
        if self.done {
            return None;
        }
        let index = self.next;
        let leaf = if self.level == 0 {
            Node::default()
        } else {
            self.path[self.level as usize - 1].child(index, 0)
        };
        if index == self.last {
            self.done = true;
        } else {
            self.next = index + 1;
            if self.next & 3 == 0 {
                // The lowest `k` digits wrapped to 0: the nodes at depths
                // `level - k ..` changed.
                let wrapped = self.next.trailing_zeros() / 2;
                self.descend_from(self.level.saturating_sub(wrapped).max(1));
            }
        }
        Some(Triangle {
            index,
            origin: (leaf.u, leaf.v),
            upright: leaf.flags & DOWN == 0,
        })
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

impl FusedIterator for Triangles {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deinterleave_splits_even_and_odd_bits() {
        assert_eq!(deinterleave(0x5555_5555_5555_5555), (u32::MAX, 0));
        assert_eq!(deinterleave(0xaaaa_aaaa_aaaa_aaaa), (0, u32::MAX));
        assert_eq!(deinterleave(0b0110), (0b10, 0b01));
        assert_eq!(deinterleave(1 << 63), (0, 1 << 31));
    }

    #[test]
    fn iterator_ends_at_the_last_index() {
        let level = Level::new(2).unwrap();
        let mut all = triangles(level);
        assert_eq!(all.size_hint(), (16, Some(16)));
        assert_eq!(all.by_ref().last().map(|t| t.index()), Some(15));
        assert_eq!(all.next(), None);
        let mut root = triangles(Level::new(0).unwrap());
        assert_eq!(
            root.next().map(|t| t.vertices_scaled()),
            Some([(0, 0), (1, 0), (0, 1)])
        );
        assert_eq!(root.next(), None);
    }
}
