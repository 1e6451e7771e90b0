//! The top-down walk of one triangle's micro-triangles: from the whole
//! triangle, a node whose bounding block is uniform decides its whole
//! subtree (a contiguous index range) at once; under linear filtering by
//! value, so does a small node whose filtered value passes (fails)
//! everywhere, unless its vertices' readings (shared with its neighbours
//! and children) already do both; mixed nodes descend; the leaves are
//! classified four at a time, sharing their vertices' reads.
//! Every node first checks the work budget: once it is spent, the node and
//! everything not yet visited become unknown (sound).
//!
//! The walk can stop at a depth and set the nodes there aside
//! ([`Split::Collect`]), and can take those nodes' subtrees from walks made
//! elsewhere ([`Split::Replay`]): the split walk of [`super::split`] runs
//! them in parallel with the serial walk's result.

use super::classify::{is_small, Block, Classes, Classifier, Grid, Placed, Points};
use super::triangle::{BakeError, TriangleStatus};
use crate::micromap::{Format, Micromap, MicromapError, State, UnknownPolicy};
use crate::num::wide::GridInt;
use crate::Level;
use alloc::vec::Vec;
use core::sync::atomic::{AtomicU64, Ordering};

/// The midpoint of two grid points of a node above the map's level (exact:
/// see [`Walk::visit`]).
#[inline]
pub(crate) fn midpoint<C: GridInt>(a: (C, C), b: (C, C)) -> (C, C) {
    ((a.0 + b.0) >> 1, (a.1 + b.1) >> 1)
}

/// Which of a node's six points (its corners `0, 1, 2`, then the
/// midpoints of corners 0-1, 1-2, 2-0) lies between its corners `i` and
/// `j`.
#[inline]
pub(crate) fn between(i: usize, j: usize) -> usize {
    match i + j {
        1 => 3,
        3 => 4,
        _ => 5,
    }
}

/// What a node's six points (see [`between`]) read, where known.
pub(crate) type PointReads = [Option<Classes>; 6];

/// Sets `count` states of `map` from `first`: one leaf (most calls) by
/// [`Micromap::set`], a range by [`Micromap::fill`].
#[inline]
pub(crate) fn put(
    map: &mut Micromap,
    first: u64,
    count: u64,
    state: State,
) -> Result<(), MicromapError> {
    if count == 1 {
        map.set(first, state)
    } else {
        map.fill(first, count, state)
    }
}

/// A node of the walk set aside at the split depth: its index at that
/// depth, its grid vertices and its `top_flip`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Node<C> {
    pub(crate) index: u64,
    pub(crate) vertices: [(C, C); 3],
    pub(crate) top_flip: bool,
}

/// What the walk of one subtree made and found (its own map, indexed from
/// its root).
#[derive(Clone, Debug)]
pub(crate) struct Subtree {
    pub(crate) map: Micromap,
    pub(crate) counts: [u64; 4],
    pub(crate) work: u64,
    pub(crate) widened: u64,
    pub(crate) exhausted: bool,
    pub(crate) out_of_work: bool,
    /// The work spent at the walk's last budget check that passed: the
    /// walk is what any budget above this would give ([`Walk::check`]).
    pub(crate) last_check: u64,
    /// Stopped by [`SharedStop`] (a speculative walk given up): the map is
    /// not the walk of any budget.
    pub(crate) stopped: bool,
}

/// A cap on the work of several walks together (the speculative subtrees
/// of a split walk): each publishes what it spent every so often, and
/// stops once the sum reaches `limit`.
#[derive(Debug)]
pub(crate) struct SharedStop {
    spent: AtomicU64,
    limit: u64,
}

/// Work units a walk under a [`SharedStop`] spends between two
/// publications (an atomic add on a shared line: rarely).
const PUBLISH_EVERY: u64 = 1 << 12;

impl SharedStop {
    pub(crate) fn new(limit: u64) -> SharedStop {
        SharedStop {
            spent: AtomicU64::new(0),
            limit,
        }
    }
}

/// How a walk treats the nodes at a split depth.
pub(crate) enum Split<'s, C> {
    /// A plain walk.
    None,
    /// Sets the nodes at `depth` aside (in walk order) instead of walking
    /// them, with the work spent before each.
    Collect {
        depth: u32,
        nodes: Vec<Node<C>>,
        work_before: Vec<u64>,
    },
    /// Takes the nodes at `depth` (after their budget check) from
    /// `subtrees`, in walk order, each walked with exactly the budget this
    /// walk has left there ([`super::split`] guarantees it).
    Replay {
        depth: u32,
        subtrees: &'s mut dyn Iterator<Item = Subtree>,
        subtree_level: u32,
    },
}

/// What the walk carries from node to node: the classifier, the level,
/// the work spent and allowed, the grid, the 2-state policy, the map and
/// counts it fills, and how it went.
pub(crate) struct Walk<'a, C> {
    classifier: &'a Classifier,
    level: u32,
    /// Work units spent and allowed ([bounded work](crate::bake#bounded-work)).
    pub(crate) work: u64,
    max_work: u64,
    pub(crate) out_of_work: bool,
    /// See [`Subtree::last_check`].
    last_check: u64,
    grid: Grid,
    two_state: UnknownPolicy,
    pub(crate) map: &'a mut Micromap,
    pub(crate) counts: &'a mut [u64; 4],
    /// A micro-triangle ran out of its block budget.
    pub(crate) exhausted: bool,
    /// Unknown leaves the exact model knows (see
    /// [`BakedTriangle::widened`](crate::bake::BakedTriangle::widened)).
    pub(crate) widened: u64,
    stack: Vec<Block>,
    pub(crate) split: Split<'a, C>,
    /// A cap shared with other walks, and what this walk has published
    /// to it.
    shared: Option<(&'a SharedStop, u64)>,
    stopped: bool,
}

/// How a walk went: its status, the work units it spent, and the unknown
/// leaves the exact model knows.
pub(crate) struct Spent {
    pub(crate) status: TriangleStatus,
    pub(crate) work: u64,
    pub(crate) widened: u64,
}

impl<'a, C: GridInt> Walk<'a, C> {
    /// A walk of `level` on `grid` with `max_work` units, filling `map`
    /// and `counts`, not split.
    pub(crate) fn new(
        classifier: &'a Classifier,
        (level, grid): (u32, Grid),
        two_state: UnknownPolicy,
        max_work: u64,
        map: &'a mut Micromap,
        counts: &'a mut [u64; 4],
    ) -> Self {
        Walk {
            classifier,
            level,
            work: 0,
            max_work,
            out_of_work: false,
            last_check: 0,
            grid,
            two_state,
            map,
            counts,
            exhausted: false,
            widened: 0,
            stack: Vec::new(),
            split: Split::None,
            shared: None,
            stopped: false,
        }
    }

    /// The same walk, also stopped once the walks sharing `stop` have spent
    /// its limit together.
    pub(crate) fn sharing(mut self, stop: &'a SharedStop) -> Self {
        self.shared = Some((stop, 0));
        self
    }

    /// How it went.
    pub(crate) fn spent(&self) -> Spent {
        let status = if self.out_of_work {
            TriangleStatus::WorkBudgetExceeded
        } else if self.exhausted {
            TriangleStatus::BlockBudgetExceeded
        } else {
            TriangleStatus::Exact
        };
        Spent {
            status,
            work: self.work,
            widened: self.widened,
        }
    }

    /// The budget check before a node (and before each leaf of
    /// [`visit_leaves`](Self::visit_leaves)): `true` when the work is spent
    /// (or a shared cap is reached), and the node must be unknown. Every
    /// check that passes records the work so far: a walk whose checks all
    /// passed below some budget is the walk of every budget above
    /// [`Subtree::last_check`].
    #[inline]
    fn out_of_work_here(&mut self) -> bool {
        if self.work >= self.max_work {
            self.out_of_work = true;
            return true;
        }
        if let Some((stop, published)) = &mut self.shared {
            let unpublished = self.work - *published;
            let spent = if unpublished >= PUBLISH_EVERY {
                *published = self.work;
                stop.spent.fetch_add(unpublished, Ordering::Relaxed) + unpublished
            } else {
                stop.spent.load(Ordering::Relaxed) + unpublished
            };
            if spent >= stop.limit {
                // Published whole, so that the walks after this one stop at
                // their first check.
                stop.spent
                    .fetch_add(self.work - *published, Ordering::Relaxed);
                *published = self.work;
                self.stopped = true;
                self.out_of_work = true;
                return true;
            }
        }
        self.last_check = self.work;
        false
    }

    /// One micro-triangle of the walk: its depth and index in the tree,
    /// its grid vertices `(x, y)`, and the walk's `top_flip` (which numbers
    /// its children). A micro-triangle of a coarser level contains its
    /// descendants, so a uniform one decides all of them (a contiguous
    /// index range) at once; only mixed ones descend, by recursion (depth
    /// at most the level). A child's vertices are its parent's and their
    /// midpoints (exact: at depth d < n every grid coordinate is a
    /// multiple of 2^(n - d), see `AxisFrame::at`, so the sums are even and
    /// halving is a shift), so no vertex is placed from scratch.
    pub(crate) fn visit(
        &mut self,
        depth: u32,
        index: u64,
        vertices: [(C, C); 3],
        top_flip: bool,
    ) -> Result<(), BakeError> {
        self.visit_node(
            depth,
            index,
            vertices,
            top_flip,
            (&mut [None; 6], [0, 1, 2]),
        )
    }

    /// [`visit`](Self::visit), with what the node's vertices read as far
    /// as its parent knows: `reads.0[reads.1[k]]` is vertex `k`'s reading
    /// when some node read it before (the parent's corners and edge
    /// midpoints: siblings share them). A reading is a pure function of
    /// the point, and a node charges the same work whether it finds its
    /// vertices' readings there or makes them, so the walk (its states and
    /// its work) does not depend on what was shared.
    fn visit_node(
        &mut self,
        depth: u32,
        index: u64,
        vertices: [(C, C); 3],
        top_flip: bool,
        reads: (&mut PointReads, [usize; 3]),
    ) -> Result<(), BakeError> {
        if let Split::Collect {
            depth: at,
            nodes,
            work_before,
        } = &mut self.split
        {
            if depth == *at {
                nodes.push(Node {
                    index,
                    vertices,
                    top_flip,
                });
                work_before.push(self.work);
                return Ok(());
            }
        }
        let n = self.level;
        let up = n - depth;
        let p = Placed {
            x: vertices.map(|v| v.0),
            y: vertices.map(|v| v.1),
        };
        if self.out_of_work_here() {
            // Out of work: this node's whole subtree is unknown (sound).
            let count = 1u64 << (2 * up);
            return self.set_unknown(&p, index << (2 * up), count);
        }
        if let Split::Replay { depth: at, .. } = self.split {
            if depth == at {
                return self.replay(index);
            }
        }
        if depth == n {
            // A level-0 map: its one leaf (deeper leaves are read four at a
            // time by `visit_leaves`).
            return self.visit_leaf(&p, index, Points::All);
        }
        // Above the finest level only the bounding block is read: a mixed
        // block descends, and the children decide more cheaply than an
        // exact search over a large triangle would.
        let classes = self.classifier.quick_classes(&p, self.grid);
        self.work += 1;
        if let Some(state) = classes.known_state() {
            return self.set_known(index, up, state);
        }
        // Linear filtering by value: a node reading both classes may still
        // have a value that passes (fails) everywhere; then so do all its
        // leaves, which are not visited. Not when its vertices (points of
        // it) already read both: its value does both too, and the cheaper
        // readings are shared with its neighbours and children.
        let (shared, at) = reads;
        if self.classifier.value_applies(&p, self.grid) {
            let vertex_reads = self.vertex_classes(&vertices, shared, at);
            if !vertex_reads.is_mixed() {
                let (state, work) = self.classifier.value_state(&p, self.grid);
                self.work += work;
                if let Some(state) = state {
                    return self.set_known(index, up, state);
                }
            }
        }
        let corners = at.map(|k| shared[k]);
        if depth + 1 == n {
            return self.visit_leaves(index, vertices, top_flip, corners);
        }
        let [a, b, c] = vertices;
        let points = [a, b, c, midpoint(a, b), midpoint(b, c), midpoint(c, a)];
        let mut known: PointReads = [corners[0], corners[1], corners[2], None, None, None];
        for child in 0..4 {
            let (at, top_flip) =
                crate::inverse::child_vertices(child, top_flip, [0, 1, 2], between);
            let vertices = at.map(|k| points[k]);
            let index = 4 * index + u64::from(child);
            self.visit_node(depth + 1, index, vertices, top_flip, (&mut known, at))?;
        }
        Ok(())
    }

    /// The union of the classes `vertices` read (points of the grid, no
    /// margin), stopping once both: each taken from `shared` (at `at`)
    /// when known there, else read and kept there. One work unit per
    /// vertex looked at, found or read (see [`visit_node`](Self::visit_node)).
    fn vertex_classes(
        &mut self,
        vertices: &[(C, C); 3],
        shared: &mut PointReads,
        at: [usize; 3],
    ) -> Classes {
        let classifier = self.classifier;
        let shifts = self.grid.shifts;
        let mut sure = Classes::default();
        for (&(x, y), k) in vertices.iter().zip(at) {
            self.work += 1;
            let classes = *shared[k]
                .get_or_insert_with(|| classifier.point_classes((x + x, y + y), shifts, None));
            sure = sure.union(classes);
            if sure.is_mixed() {
                break;
            }
        }
        sure
    }

    /// The node `index` at the replay depth: its subtree's walk, taken from
    /// the split walk's list, copied in and added up.
    #[cold]
    #[inline(never)]
    fn replay(&mut self, index: u64) -> Result<(), BakeError> {
        let Split::Replay {
            subtrees,
            subtree_level,
            ..
        } = &mut self.split
        else {
            unreachable!("replay outside a replay walk")
        };
        let first = index << (2 * *subtree_level);
        let subtree = subtrees
            .next()
            .expect("the split walk has a subtree for every node the replay reaches");
        self.map.copy_aligned(first, &subtree.map)?;
        for (sum, count) in self.counts.iter_mut().zip(subtree.counts) {
            *sum += count;
        }
        self.work += subtree.work;
        self.widened += subtree.widened;
        self.exhausted |= subtree.exhausted;
        self.out_of_work |= subtree.out_of_work;
        Ok(())
    }

    /// One leaf (finest micro-triangle) `p` with its index: classified
    /// ([`Classifier::classify_leaf`], reading `points`), then set known or
    /// unknown and counted.
    fn visit_leaf(&mut self, p: &Placed<C>, leaf: u64, points: Points) -> Result<(), BakeError> {
        let (classes, out_of_budget, work, widened) =
            self.classifier
                .classify_leaf(p, self.grid, (points, None), &mut self.stack);
        self.work += work;
        self.widened += u64::from(widened);
        if let Some(state) = classes.known_state() {
            return self.set_known(leaf, 0, state);
        }
        self.exhausted |= out_of_budget;
        self.set_unknown(p, leaf, 1)
    }

    /// The four leaves (finest micro-triangles) of a mixed node one level
    /// above the map's: `index`, `vertices`, `top_flip` are the node's, as
    /// in [`visit`](Self::visit). Their vertices are the node's corners
    /// and edge midpoints, six points for twelve corners: each point's
    /// footprint is read once, when a leaf first needs it. A leaf whose
    /// vertices read both classes is unknown (under either model: they
    /// are points of it) without its bounding block; the others are
    /// classified as [`visit`](Self::visit) would, without reading the
    /// vertices again. Only leaves with a small exact bounding block use
    /// them, as [`Classifier::classify_mixed_block`] does.
    fn visit_leaves(
        &mut self,
        index: u64,
        vertices: [(C, C); 3],
        top_flip: bool,
        corners: [Option<Classes>; 3],
    ) -> Result<(), BakeError> {
        let [a, b, c] = vertices;
        let points = [a, b, c, midpoint(a, b), midpoint(b, c), midpoint(c, a)];
        let mut read: PointReads = [corners[0], corners[1], corners[2], None, None, None];
        // Which points this node has charged a work unit for: one per point
        // a leaf needs, found in `read` or not, so that the work does not
        // depend on what the node's parent shared.
        let mut charged = [false; 6];
        let exact_grid = Grid::exact(self.grid.shifts);
        for child in 0..4 {
            let (corners, _) = crate::inverse::child_vertices(child, top_flip, [0, 1, 2], between);
            let leaf = 4 * index + u64::from(child);
            let p = Placed {
                x: corners.map(|i| points[i].0),
                y: corners.map(|i| points[i].1),
            };
            if self.out_of_work_here() {
                self.set_unknown(&p, leaf, 1)?;
                continue;
            }
            let mut vertex_points = Points::All;
            if is_small(self.classifier.bounding_block(&p, exact_grid)) {
                let mut sure = Classes::default();
                for i in corners {
                    if !charged[i] {
                        charged[i] = true;
                        self.work += 1;
                    }
                    let classes = *read[i].get_or_insert_with(|| {
                        let (x, y) = points[i];
                        self.classifier
                            .point_classes((x + x, y + y), self.grid.shifts, None)
                    });
                    sure = sure.union(classes);
                    if sure.is_mixed() {
                        break;
                    }
                }
                if sure.is_mixed() {
                    // One unit for the centroid's texel: every leaf costs
                    // one at least, so a budget of all the work cuts none.
                    self.work += 1;
                    self.set_unknown(&p, leaf, 1)?;
                    continue;
                }
                vertex_points = Points::Midpoints(sure);
            }
            self.visit_leaf(&p, leaf, vertex_points)?;
        }
        Ok(())
    }

    /// Marks the `4^up` micro-triangles of the node `index` (`up` levels
    /// above the map's) `state`, and counts them.
    fn set_known(&mut self, index: u64, up: u32, state: State) -> Result<(), BakeError> {
        let count = 1u64 << (2 * up);
        self.counts[state.bits() as usize] += count;
        put(self.map, index << (2 * up), count, state)?;
        Ok(())
    }

    /// Marks `count` micro-triangles from `first` (the placed node `p`'s
    /// finest-level range) unknown, split by `p`'s centroid texel, and
    /// counts them.
    fn set_unknown(&mut self, p: &Placed<C>, first: u64, count: u64) -> Result<(), BakeError> {
        let state = if self.classifier.centroid_is_opaque(p, self.grid.shifts) {
            State::UnknownOpaque
        } else {
            State::UnknownTransparent
        };
        self.counts[state.bits() as usize] += count;
        let stored = match self.map.format() {
            Format::FourState => state,
            Format::TwoState => self.two_state.resolve(state),
        };
        put(self.map, first, count, stored)?;
        Ok(())
    }
}

/// The walk of a whole triangle `root` at `level` on `grid`, serial:
/// fills `map` and `counts`, and says how it went.
pub(crate) fn walk_whole<C: GridInt>(
    classifier: &Classifier,
    (root, level, grid): (Placed<C>, u32, Grid),
    two_state: UnknownPolicy,
    max_work: u64,
    (map, counts): (&mut Micromap, &mut [u64; 4]),
) -> Result<Spent, BakeError> {
    let vertices = [0, 1, 2].map(|k| (root.x[k], root.y[k]));
    let mut walk = Walk::new(classifier, (level, grid), two_state, max_work, map, counts);
    walk.visit(0, 0, vertices, false)?;
    Ok(walk.spent())
}

/// The walk of one node's subtree (`node` at `depth` of a walk of
/// `level` on `grid`), into a map of its own of `subtree_level`, with
/// `max_work` units, also stopped by `shared` when given.
pub(crate) fn walk_subtree<C: GridInt>(
    classifier: &Classifier,
    (node, depth, level, grid): (&Node<C>, u32, u32, Grid),
    (two_state, format): (UnknownPolicy, Format),
    max_work: u64,
    shared: Option<&SharedStop>,
) -> Result<Subtree, BakeError> {
    let subtree_level = level - depth;
    let mut map = Micromap::new(Level(subtree_level as u8), format)?;
    let mut counts = [0u64; 4];
    let mut walk = Walk::new(
        classifier,
        (level, grid),
        two_state,
        max_work,
        &mut map,
        &mut counts,
    );
    if let Some(stop) = shared {
        walk = walk.sharing(stop);
    }
    walk.visit(depth, 0, node.vertices, node.top_flip)?;
    let Walk {
        work,
        widened,
        exhausted,
        out_of_work,
        last_check,
        stopped,
        ..
    } = walk;
    Ok(Subtree {
        map,
        counts,
        work,
        widened,
        exhausted,
        out_of_work,
        last_check,
        stopped,
    })
}
