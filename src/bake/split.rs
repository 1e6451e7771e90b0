//! The split walk: one large triangle on the pool's threads, with the
//! serial walk's result, whatever the work budget.
//!
//! 1. **Collect.** The levels above the subtrees are walked first, with no
//!    budget, setting the nodes at the split depth aside in walk order,
//!    each with the work the top had spent before it.
//! 2. **Subtrees, in order.** The set-aside subtrees are walked on the
//!    pool's threads, [`SPLIT_BATCH`] at a time, each thread taking the
//!    next one in order ([`map_claimed_in_order`]). A batch's first
//!    subtree (the leader) knows exactly what the serial walk would have
//!    left there (the work before it is all done), so it is walked with
//!    that budget and is exactly the serial walk's. The others are walked
//!    speculatively with the leader's budget (at least their own) and, all
//!    together, at most half of it ([`SharedStop`]): one whose every budget
//!    check passed below what the serial walk leaves it
//!    ([`Subtree::last_check`]) is the serial walk's; at the first that is
//!    not, the next batch starts, with it as the leader (the walks after
//!    it are kept, and judged when their turn comes). The first subtree
//!    that runs out ends the step: the serial walk runs out there.
//! 3. **Assemble.** If all of it, top and subtrees, spent less than the
//!    budget, no check of the serial walk failed: the subtrees are copied
//!    into the top's map. Otherwise the top is walked again with the
//!    budget, taking each subtree it reaches from step 2
//!    ([`Split::Replay`]): the serial walk, node for node.
//!
//! So the map, counts, status and work are the serial walk's for every
//! budget. Work done and thrown away (speculative subtrees walked again or
//! past the cut, the top walked twice) is counted apart
//! ([`SplitSpent::speculative`]): at most half the budget left at the cut's
//! batch, plus the top.

use super::classify::{Classifier, Grid, Placed};
use super::parallel::map_claimed_in_order;
use super::triangle::BakeError;
use super::walk::{walk_subtree, Node, SharedStop, Spent, Split, Subtree, Walk};
use crate::micromap::{Micromap, UnknownPolicy};
use crate::num::wide::GridInt;
use alloc::vec::Vec;

/// A triangle baked at this level or above, on more than one thread, is
/// split (see the [module docs](self)). One level-12 triangle is 16M
/// micro-triangles: one thread's work for seconds otherwise.
pub(crate) const SPLIT_FROM_LEVEL: u32 = 10;

/// The level of the subtrees a split walk hands out, at most: 4^8
/// micro-triangles each, a few milliseconds of work.
const MAX_SUBTREE_LEVEL: u32 = 8;

/// The level of the subtrees at least (smaller ones cost more to hand out
/// than to walk).
const MIN_SUBTREE_LEVEL: u32 = 4;

/// Depth of the split at most: at most 4^7 subtrees, so that the top (walked
/// twice where the budget cuts) stays small next to the subtrees.
const MAX_SPLIT_DEPTH: u32 = 7;

/// Work units per leaf that the subtree size plans for: a subtree of
/// `4^L` leaves is planned to cost at most `4^L` times this, and is made
/// small enough for that to be at most the budget / 2^5 (so that a
/// speculative subtree thrown away at the cut costs little next to the
/// budget).
const PLANNED_UNITS_PER_LEAF: u64 = 1 << 6;

/// Subtrees a split walk walks at once: their maps (16 KiB each in 4-state
/// at level 8) are what it holds beyond the triangle's own map. (3 in unit
/// tests, so that their level-10 and -11 triangles take several batches.)
const SPLIT_BATCH: usize = if cfg!(test) { 3 } else { 256 };

/// The subtrees' level for a walk of `level` with `max_work` units: the
/// largest in `MIN_SUBTREE_LEVEL..=MAX_SUBTREE_LEVEL`, and at least
/// `level - MAX_SPLIT_DEPTH`, whose planned cost is at most
/// `max_work / 2^5`; below `level`.
fn subtree_level(level: u32, max_work: u64) -> u32 {
    let least = MIN_SUBTREE_LEVEL.max(level.saturating_sub(MAX_SPLIT_DEPTH));
    let mut l = MAX_SUBTREE_LEVEL;
    while l > least && (1u64 << (2 * l)).saturating_mul(PLANNED_UNITS_PER_LEAF) > max_work >> 5 {
        l -= 1;
    }
    l.min(level - 1)
}

/// How a split walk went: the serial walk's [`Spent`], and the work done
/// besides (thrown away: speculative subtrees, the top walked twice).
pub(crate) struct SplitSpent {
    pub(crate) spent: Spent,
    pub(crate) speculative: u64,
}

/// The split walk of the whole triangle `root` at `level` on `grid` (see
/// the [module docs](self)): fills `map` and `counts` as the serial walk
/// with `max_work` units does.
pub(crate) fn walk_split<C: GridInt>(
    classifier: &Classifier,
    (root, level, grid): (Placed<C>, u32, Grid),
    two_state: UnknownPolicy,
    max_work: u64,
    (map, counts): (&mut Micromap, &mut [u64; 4]),
) -> Result<SplitSpent, BakeError> {
    let vertices = [0, 1, 2].map(|k| (root.x[k], root.y[k]));
    let format = map.format();
    let sub = subtree_level(level, max_work);
    let depth = level - sub;

    // 1. Collect: the top, no budget, the nodes at `depth` set aside.
    let mut top = Walk::new(classifier, (level, grid), two_state, u64::MAX, map, counts);
    top.split = Split::Collect {
        depth,
        nodes: Vec::new(),
        work_before: Vec::new(),
    };
    top.visit(0, 0, vertices, false)?;
    let top_work = top.work;
    let Split::Collect {
        nodes, work_before, ..
    } = core::mem::replace(&mut top.split, Split::None)
    else {
        unreachable!("the top walk collects")
    };

    // 2. The subtrees in order, each the serial walk's, until one runs out
    //    or the serial walk would have run out before the next.
    let walk = |node: &Node<C>, budget: u64, shared: Option<&SharedStop>| {
        walk_subtree(
            classifier,
            (node, depth, level, grid),
            (two_state, format),
            budget,
            shared,
        )
    };
    let mut done: Vec<Subtree> = Vec::new();
    // Speculative walks not yet judged (kept past a batch that ended
    // before them: their budget is known once the subtrees before them
    // are done).
    let mut pending: Vec<Option<Subtree>> = Vec::new();
    pending.resize_with(nodes.len(), || None);
    let (mut before, mut speculative) = (0u64, 0u64);
    let mut cut = false;
    let mut next = 0;
    while next < nodes.len() && !cut {
        let first = next;
        let end = nodes.len().min(first + SPLIT_BATCH);
        let Some(left) = max_work
            .checked_sub(work_before[first] + before)
            .filter(|&l| l > 0)
        else {
            cut = true;
            break;
        };
        // The leader, and the batch's subtrees not walked yet (or stopped).
        let todo: Vec<usize> = (first..end)
            .filter(|&k| k == first || pending[k].is_none())
            .collect();
        let shared = SharedStop::new(left / 2);
        let walked = map_claimed_in_order(&todo, |_, &k| {
            walk(&nodes[k], left, (k > first).then_some(&shared))
        });
        for (&k, subtree) in todo.iter().zip(walked) {
            let subtree = subtree?;
            // A stopped walk is of no budget: walked again when its turn
            // comes.
            if subtree.stopped {
                speculative += subtree.work;
            } else if let Some(thrown) = pending[k].replace(subtree) {
                speculative += thrown.work;
            }
        }
        for k in first..end {
            let Some(subtree) = pending[k].take() else {
                next = k;
                break;
            };
            let at = work_before[k] + before;
            // The leader was walked with its exact budget; another is the
            // serial walk's if every check it made passes under its own.
            let exact = max_work.checked_sub(at).is_some_and(|budget| {
                k == first
                    || (!subtree.stopped && !subtree.out_of_work && subtree.last_check < budget)
            });
            if !exact {
                // The next batch starts here, with this one its leader
                // (walked with its exact budget, or found past the cut).
                speculative += subtree.work;
                next = k;
                break;
            }
            before += subtree.work;
            cut = subtree.out_of_work;
            done.push(subtree);
            next = k + 1;
            if cut {
                break;
            }
        }
    }
    speculative += pending.iter().flatten().map(|s| s.work).sum::<u64>();

    // 3. Assemble: the subtrees copied into the top's map, unless the
    //    serial walk could have run out somewhere; then the top again, with
    //    the budget, taking the subtrees in order.
    if !cut && top_work + before < max_work {
        for (node, subtree) in nodes.iter().zip(&done) {
            top.map
                .copy_aligned(node.index << (2 * sub), &subtree.map)?;
            for (sum, count) in top.counts.iter_mut().zip(subtree.counts) {
                *sum += count;
            }
            top.widened += subtree.widened;
            top.exhausted |= subtree.exhausted;
        }
        top.work += before;
        return Ok(SplitSpent {
            spent: top.spent(),
            speculative,
        });
    }
    let Walk { map, counts, .. } = top;
    *counts = [0; 4];
    let mut subtrees = done.into_iter();
    let mut replay = Walk::new(classifier, (level, grid), two_state, max_work, map, counts);
    replay.split = Split::Replay {
        depth,
        subtrees: &mut subtrees,
        subtree_level: sub,
    };
    replay.visit(0, 0, vertices, false)?;
    Ok(SplitSpent {
        spent: replay.spent(),
        speculative: speculative + top_work,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subtrees_shrink_with_small_budgets() {
        assert_eq!(subtree_level(12, u64::MAX), 8);
        // 4^L * 2^6 <= 2^26 / 2^5: L = 7.
        assert_eq!(subtree_level(12, 1 << 26), 7);
        // 4^L * 2^6 <= 2^20 / 2^5 gives 4, but at most 4^7 subtrees.
        assert_eq!(subtree_level(12, 1 << 20), 5);
        assert_eq!(subtree_level(12, 0), 5);
        assert_eq!(subtree_level(16, 1 << 20), 8);
        assert_eq!(subtree_level(10, 0), 4);
        assert_eq!(subtree_level(10, u64::MAX), 8);
    }
}
