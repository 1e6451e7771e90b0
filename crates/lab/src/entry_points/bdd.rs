//! Reduced ordered binary decision diagrams: the decision procedure of the
//! entry-point proofs. Two Boolean functions of the same variables are equal
//! exactly when their reduced diagrams are the same node (Bryant 1986), so
//! equality of two bit-level computations is a comparison of node handles.
//!
//! One diagram store per thread ([`reset`] empties it): the operators on
//! [`Node`] (`&`, `|`, `^`, `!`) need no context, so the words of
//! [`super::word`] can implement the crate's `LaneWord` and `ReferenceWord`
//! traits and run the library's own code.
//!
//! Contract: every node handle belongs to the store it was made in; a handle
//! kept across [`reset`] is meaningless (and [`Node`]'s operators panic on
//! one beyond the store).

use std::cell::RefCell;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::ops::{BitAnd, BitOr, BitXor, Not};

/// A node of the thread's diagram store: a Boolean function of the
/// variables `0, 1, 2, ...` (lower indices tested first).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Node(u32);

impl std::hash::Hash for Node {
    fn hash<H: Hasher>(&self, state: &mut H) {
        state.write_u32(self.0);
    }
}

impl Node {
    /// The constant false.
    pub const FALSE: Node = Node(0);
    /// The constant true.
    pub const TRUE: Node = Node(1);

    /// The constant `value`.
    #[must_use]
    pub fn constant(value: bool) -> Node {
        if value {
            Node::TRUE
        } else {
            Node::FALSE
        }
    }

    /// The function that is variable `index`.
    #[must_use]
    pub fn variable(index: u32) -> Node {
        with_store(|store| store.make(index, Node::FALSE, Node::TRUE))
    }

    /// `if self { if_true } else { if_false }`.
    #[must_use]
    pub fn select(self, if_true: Node, if_false: Node) -> Node {
        with_store(|store| store.ite(self, if_true, if_false))
    }

    /// `Some(value)` when the function is a constant.
    #[must_use]
    pub fn as_constant(self) -> Option<bool> {
        match self {
            Node::FALSE => Some(false),
            Node::TRUE => Some(true),
            _ => None,
        }
    }

    /// The function's value under `assignment` (variables it does not
    /// name read false).
    #[must_use]
    pub fn evaluate(self, assignment: &[(u32, bool)]) -> bool {
        with_store(|store| {
            let mut node = self;
            while node != Node::TRUE && node != Node::FALSE {
                let (variable, low, high) = store.nodes[node.0 as usize];
                let value = assignment
                    .iter()
                    .any(|&(named, value)| named == variable && value);
                node = if value { high } else { low };
            }
            node == Node::TRUE
        })
    }

    /// One assignment that makes the function true (variables it does not
    /// test are left out: any value does), or `None` for false.
    #[must_use]
    pub fn satisfying_assignment(self) -> Option<Vec<(u32, bool)>> {
        with_store(|store| {
            if self == Node::FALSE {
                return None;
            }
            let mut assignment = Vec::new();
            let mut node = self;
            while node != Node::TRUE {
                let (variable, low, high) = store.nodes[node.0 as usize];
                // Reduced: a non-terminal's two children differ, so one is
                // not FALSE, and every non-FALSE node reaches TRUE.
                if low == Node::FALSE {
                    assignment.push((variable, true));
                    node = high;
                } else {
                    assignment.push((variable, false));
                    node = low;
                }
            }
            Some(assignment)
        })
    }
}

impl BitAnd for Node {
    type Output = Node;
    fn bitand(self, other: Node) -> Node {
        self.select(other, Node::FALSE)
    }
}

impl BitOr for Node {
    type Output = Node;
    fn bitor(self, other: Node) -> Node {
        self.select(Node::TRUE, other)
    }
}

impl Not for Node {
    type Output = Node;
    fn not(self) -> Node {
        self.select(Node::FALSE, Node::TRUE)
    }
}

impl BitXor for Node {
    type Output = Node;
    fn bitxor(self, other: Node) -> Node {
        self.select(!other, other)
    }
}

/// Empties the thread's store: every node made before is invalid after.
pub fn reset() {
    STORE.with(|store| *store.borrow_mut() = Store::new());
}

/// [`reset`] when the store holds more than `nodes` nodes: proofs that
/// build the same inputs case after case share the earlier cases' work
/// until memory calls for a fresh start.
pub fn reset_above(nodes: usize) {
    if node_count() > nodes {
        reset();
    }
}

/// A multiplicative hash of the tables' small integer keys (the `FxHash`
/// scheme): the tables are this module's inner loop, and `SipHash`'s
/// resistance to chosen keys buys nothing here.
#[derive(Default)]
struct KeyHasher(u64);

impl Hasher for KeyHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            self.write_u64(u64::from(byte));
        }
    }
    fn write_u32(&mut self, value: u32) {
        self.write_u64(u64::from(value));
    }
    fn write_u64(&mut self, value: u64) {
        self.0 = (self.0.rotate_left(5) ^ value).wrapping_mul(0x517c_c1b7_2722_0a95);
    }
}

type Table<K> = HashMap<K, Node, BuildHasherDefault<KeyHasher>>;

/// How many nodes the thread's store holds (terminals included).
#[must_use]
pub fn node_count() -> usize {
    with_store(|store| store.nodes.len())
}

/// The variable of the terminals: after every real variable.
const TERMINAL: u32 = u32::MAX;

/// The diagrams: nodes `(variable, low, high)` made unique by a table, and
/// the memo of `ite`.
struct Store {
    nodes: Vec<(u32, Node, Node)>,
    unique: Table<(u32, Node, Node)>,
    memo: Table<(Node, Node, Node)>,
}

impl Store {
    fn new() -> Store {
        Store {
            nodes: vec![
                (TERMINAL, Node::FALSE, Node::FALSE),
                (TERMINAL, Node::TRUE, Node::TRUE),
            ],
            unique: Table::default(),
            memo: Table::default(),
        }
    }

    /// The node testing `variable`, reduced: equal children collapse and an
    /// existing node is shared.
    fn make(&mut self, variable: u32, low: Node, high: Node) -> Node {
        if low == high {
            return low;
        }
        let next = Node(u32::try_from(self.nodes.len()).expect("more than 2^32 diagram nodes"));
        let nodes = &mut self.nodes;
        *self.unique.entry((variable, low, high)).or_insert_with(|| {
            nodes.push((variable, low, high));
            next
        })
    }

    fn variable_of(&self, node: Node) -> u32 {
        self.nodes[node.0 as usize].0
    }

    /// The cofactors of `node` for `variable` (the node itself when it does
    /// not test it: variables are tested in increasing order).
    fn cofactors(&self, node: Node, variable: u32) -> (Node, Node) {
        let (tested, low, high) = self.nodes[node.0 as usize];
        if tested == variable {
            (low, high)
        } else {
            (node, node)
        }
    }

    /// `if f { g } else { h }` by Shannon expansion on the first variable
    /// any of the three tests.
    fn ite(&mut self, f: Node, g: Node, h: Node) -> Node {
        match (f, g, h) {
            (Node::TRUE, _, _) => return g,
            (Node::FALSE, _, _) => return h,
            _ if g == h => return g,
            (_, Node::TRUE, Node::FALSE) => return f,
            _ => {}
        }
        if let Some(&known) = self.memo.get(&(f, g, h)) {
            return known;
        }
        let variable = self
            .variable_of(f)
            .min(self.variable_of(g))
            .min(self.variable_of(h));
        let (f0, f1) = self.cofactors(f, variable);
        let (g0, g1) = self.cofactors(g, variable);
        let (h0, h1) = self.cofactors(h, variable);
        let low = self.ite(f0, g0, h0);
        let high = self.ite(f1, g1, h1);
        let result = self.make(variable, low, high);
        self.memo.insert((f, g, h), result);
        result
    }
}

thread_local! {
    static STORE: RefCell<Store> = RefCell::new(Store::new());
}

fn with_store<R>(body: impl FnOnce(&mut Store) -> R) -> R {
    STORE.with(|store| body(&mut store.borrow_mut()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_functions_are_the_same_node() {
        reset();
        let (a, b, c) = (Node::variable(0), Node::variable(1), Node::variable(2));
        // Distributivity and De Morgan, built two ways.
        assert_eq!(a & (b | c), (a & b) | (a & c));
        assert_eq!(!(a & b), !a | !b);
        assert_eq!(a ^ b ^ a, b);
        assert_ne!(a & b, a | b);
        assert_eq!(a & !a, Node::FALSE);
        assert_eq!(a | !a, Node::TRUE);
    }

    #[test]
    fn satisfying_assignments_satisfy() {
        reset();
        let (a, b, c) = (Node::variable(0), Node::variable(1), Node::variable(2));
        let f = (a ^ b) & !c & b;
        let assignment = f.satisfying_assignment().unwrap();
        let value = |v: u32| assignment.iter().find(|&&(x, _)| x == v).map(|&(_, b)| b);
        assert_eq!(value(0), Some(false));
        assert_eq!(value(1), Some(true));
        assert_eq!(value(2), Some(false));
        assert_eq!((a & !a).satisfying_assignment(), None);
    }
}
