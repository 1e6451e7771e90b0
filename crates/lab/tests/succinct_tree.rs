//! The succinct trees against the flat micromap (the naive oracle) and
//! against slow recursive twins of their encoders. One macro stamps the
//! same checks on every layout: encode -> decode is the identity, every
//! lookup equals the flat map, the bytes read back, the other layout holds
//! the same tree.

use micromap_index_lab::succinct_maps;

use micromap_index::micromap::{Format, State};
use micromap_index::succinct::{LevelOrderTree, PaperTree, Section, TreeError};
use micromap_index::{spec, Level};
use micromap_index_test_support::SplitMix64;
use proptest::prelude::*;
use succinct_maps::*;

fn lvl(level: u32) -> Level {
    Level::new(level).unwrap()
}

fn state_chars(states: &[State]) -> String {
    states.iter().map(|s| char::from(b'0' + s.bits())).collect()
}

/// The slow twin of Algorithms 1 and 2: recursion over index ranges, a
/// subtree is a leaf when all of its micro-triangles have one state.
fn paper_encode_ref(states: &[State]) -> (String, Vec<State>) {
    fn walk(states: &[State], bits: &mut String, leaves: &mut Vec<State>) {
        if states.iter().all(|&s| s == states[0]) {
            bits.push('0');
            leaves.push(states[0]);
        } else {
            bits.push('1');
            for quarter in states.chunks(states.len() / 4) {
                walk(quarter, bits, leaves);
            }
        }
    }
    let (mut bits, mut leaves) = (String::new(), Vec::new());
    walk(states, &mut bits, &mut leaves);
    (bits, leaves)
}

/// The slow twin of the level-order encoder: breadth-first over index
/// ranges; (internal bits above the map's level, leaf states).
fn level_order_encode_ref(level: u32, states: &[State]) -> (u64, Vec<State>) {
    let mut nodes = vec![states];
    let (mut internal_bits, mut leaves) = (0u64, Vec::new());
    for depth in 0..=level {
        let mut next = Vec::new();
        for node in nodes {
            if depth < level {
                internal_bits += 1;
            }
            if node.iter().all(|&s| s == node[0]) {
                leaves.push(node[0]);
            } else {
                next.extend(node.chunks(node.len() / 4));
            }
        }
        nodes = next;
    }
    (internal_bits, leaves)
}

/// The indices whose lookups are checked: all up to level 6, above it the
/// first and last micro-triangle of every depth-3 subtree plus 1024 random
/// ones (Algorithm 3 scans up to the whole tree per lookup; `decode` covers
/// every index).
fn checked_indices(level: u32, seed: u64) -> Vec<u64> {
    let n = count(level) as u64;
    if level <= 6 {
        return (0..n).collect();
    }
    let span = n / 64;
    let mut rng = SplitMix64::new(seed);
    (0..64)
        .flat_map(|q| [q * span, q * span + span - 1])
        .chain((0..1024).map(|_| rng.below(n)))
        .collect()
}

macro_rules! layout_tests {
    ($module:ident, $Tree:ty) => {
        mod $module {
            use super::*;

            type Tree = $Tree;

            /// Every property of one map; `what` names it in failures.
            fn check(level: u32, format: Format, states: &[State], what: &str) {
                let show = || {
                    if states.len() <= 256 {
                        format!("{what}: level {level} {format} states {}", state_chars(states))
                    } else {
                        format!("{what}: level {level} {format}")
                    }
                };
                let tree = Tree::encode(lvl(level), format, states)
                    .unwrap_or_else(|e| panic!("{}: encode: {e}", show()));
                assert_eq!(tree.level(), lvl(level));
                assert_eq!(tree.format(), format);
                assert!(tree.decode().as_deref() == Ok(states), "{}: decode differs", show());
                for index in checked_indices(level, states.len() as u64) {
                    let want = states[index as usize];
                    assert_eq!(tree.get(index), Some(want), "{}: index {index}", show());
                }
                assert_eq!(tree.get(count(level) as u64), None, "{}", show());
                assert_eq!(tree.get(u64::MAX), None, "{}", show());
                let bytes = tree.to_bytes();
                assert_eq!(Tree::from_bytes(&bytes).as_ref(), Ok(&tree), "{}", show());
                // The same tree in the other layout.
                let paper = PaperTree::encode(lvl(level), format, states).unwrap();
                let fast = LevelOrderTree::encode(lvl(level), format, states).unwrap();
                assert_eq!(LevelOrderTree::from_paper(&paper), fast, "{}", show());
                assert_eq!(PaperTree::from_level_order(&fast), paper, "{}", show());
                // Both against the recursive twins.
                let (bits, leaves) = paper_encode_ref(states);
                assert_eq!(paper.tree_bit_string(), bits, "{}", show());
                assert_eq!(paper.leaf_states(), leaves, "{}", show());
                let (internal_bits, leaves) = level_order_encode_ref(level, states);
                assert_eq!(fast.internal_bits(), internal_bits, "{}", show());
                assert_eq!(fast.leaf_count(), leaves.len() as u64, "{}", show());
                assert_eq!(fast.data_bits(), leaves.len() as u64 * u64::from(format.bits_per_state()));
            }

            #[test]
            fn every_two_state_map_of_levels_0_to_2() {
                for level in 0..=2 {
                    let n = count(level);
                    for bits in 0..1u32 << n {
                        let states: Vec<State> =
                            (0..n).map(|i| State::ALL[(bits >> i & 1) as usize]).collect();
                        check(level, Format::TwoState, &states, "exhaustive 2-state");
                    }
                }
            }

            #[test]
            fn every_four_state_map_of_level_1() {
                for bits in 0..256u32 {
                    let states: Vec<State> =
                        (0..4).map(|i| State::ALL[(bits >> (2 * i) & 3) as usize]).collect();
                    check(1, Format::FourState, &states, "exhaustive 4-state");
                }
            }

            #[test]
            fn structured_maps_of_levels_0_to_7() {
                for level in 0..=7 {
                    for format in [Format::TwoState, Format::FourState] {
                        for state in State::ALL.into_iter().filter(|&s| format.holds(s)) {
                            check(level, format, &uniform(level, state), "uniform");
                        }
                        check(level, format, &alternating(level, format), "alternating");
                        check(level, format, &disc(level, format), "disc");
                        for density in [0, 10, 100, 500, 900, 1000] {
                            let map = noise(level, format, density, u64::from(level) * 1000 + density);
                            check(level, format, &map, &format!("noise {density}/1000"));
                        }
                    }
                }
            }

            #[test]
            fn single_state_changes_of_uniform_and_disc_maps() {
                for level in 1..=5 {
                    for format in [Format::TwoState, Format::FourState] {
                        let maps = [uniform(level, State::Opaque), disc(level, format)];
                        for map in &maps {
                            for index in 0..count(level) {
                                let changed = with_one_change(map, format, index);
                                check(level, format, &changed, &format!("change at {index}"));
                            }
                        }
                    }
                }
            }

            /// Level 12 in CI: a disc, a sparse noise map and one change of
            /// a uniform map (sampled lookups, full decode).
            #[test]
            fn a_few_level_12_maps() {
                check(12, Format::TwoState, &disc(12, Format::TwoState), "disc");
                check(12, Format::FourState, &noise(12, Format::FourState, 5, 12), "noise 5/1000");
                let changed = with_one_change(&uniform(12, State::Opaque), Format::TwoState, 4_000_000);
                check(12, Format::TwoState, &changed, "one change");
            }

            #[test]
            #[ignore = "slow: the structured maps of levels 8..=12 (minutes in the test profile)"]
            fn structured_maps_of_levels_8_to_12() {
                for level in 8..=12 {
                    for format in [Format::TwoState, Format::FourState] {
                        check(level, format, &uniform(level, State::Transparent), "uniform");
                        check(level, format, &alternating(level, format), "alternating");
                        check(level, format, &disc(level, format), "disc");
                        for density in [10, 500, 990] {
                            let map = noise(level, format, density, u64::from(level) * 1000 + density);
                            check(level, format, &map, &format!("noise {density}/1000"));
                        }
                    }
                }
            }

            proptest! {
                #![proptest_config(ProptestConfig::with_cases(300))]

                /// Random maps from a few runs of states, so that merges happen.
                #[test]
                fn random_maps(level in 0u32..=6, four in any::<bool>(), seed in any::<u64>(), runs in 1usize..40) {
                    let format = if four { Format::FourState } else { Format::TwoState };
                    let mut rng = SplitMix64::new(seed);
                    let n = count(level);
                    let mut states = Vec::with_capacity(n);
                    while states.len() < n {
                        let state = State::ALL[rng.below(2 * u64::from(format.bits_per_state())) as usize];
                        let run = 1 + rng.below((n / runs).max(1) as u64) as usize;
                        states.extend(std::iter::repeat(state).take(run.min(n - states.len())));
                    }
                    check(level, format, &states, "random runs");
                }

                /// A hit at `(u, v)` reads what the flat map holds at the
                /// spec's binary32 index.
                #[test]
                fn f32_hits_read_the_spec_index(level in 0u32..=8, u in 0.0f32..=1.0, v in 0.0f32..=1.0, seed in any::<u64>()) {
                    let map = noise(level, Format::FourState, 400, seed);
                    let tree = Tree::encode(lvl(level), Format::FourState, &map).unwrap();
                    let index = spec::index_f32(u, v, micromap_index::SpecLevel::try_from(lvl(level)).unwrap());
                    prop_assert_eq!(tree.get_f32(u, v), Some(map[index as usize]));
                }
            }

            /// Flipping any bit of an encoding gives an error or another
            /// valid tree that writes back to the flipped bytes; truncating
            /// or extending it is an error. Never a panic.
            #[test]
            fn damaged_bytes_are_rejected_or_round_trip() {
                for (level, format, map) in [
                    (3, Format::FourState, disc(3, Format::FourState)),
                    (2, Format::TwoState, noise(2, Format::TwoState, 500, 7)),
                    (4, Format::TwoState, with_one_change(&uniform(4, State::Opaque), Format::TwoState, 77)),
                    (0, Format::FourState, uniform(0, State::UnknownTransparent)),
                ] {
                    let bytes = Tree::encode(lvl(level), format, &map).unwrap().to_bytes();
                    for bit in 0..bytes.len() * 8 {
                        let mut damaged = bytes.clone();
                        damaged[bit / 8] ^= 1 << (bit % 8);
                        if let Ok(tree) = Tree::from_bytes(&damaged) {
                            assert_eq!(tree.to_bytes(), damaged, "bit {bit}");
                        }
                    }
                    for len in 0..bytes.len() {
                        assert!(Tree::from_bytes(&bytes[..len]).is_err(), "{len} bytes");
                    }
                    let mut longer = bytes.clone();
                    longer.push(0);
                    assert!(matches!(
                        Tree::from_bytes(&longer),
                        Err(TreeError::TrailingBytes { .. })
                    ));
                }
            }

            #[test]
            fn encode_rejects_wrong_inputs() {
                assert_eq!(
                    Tree::encode(lvl(1), Format::TwoState, &[State::Opaque; 3]),
                    Err(TreeError::StateCount { level: 1, expected: 4, actual: 3 })
                );
                let mut map = uniform(2, State::Opaque);
                map[9] = State::UnknownTransparent;
                assert_eq!(
                    Tree::encode(lvl(2), Format::TwoState, &map),
                    Err(TreeError::StateNotInFormat { position: 9, state: State::UnknownTransparent })
                );
                assert!(Tree::encode(lvl(2), Format::FourState, &map).is_ok());
                assert_eq!(
                    Tree::encode(lvl(17), Format::TwoState, &[]),
                    Err(TreeError::LevelTooHigh { level: 17, max: 16 })
                );
            }
        }
    };
}

layout_tests!(paper_dfs, PaperTree);
layout_tests!(level_order, LevelOrderTree);
layout_tests!(level_order_deepest_table, DeepestTable);

/// The level-order tree with the deepest top table it takes
/// (`with_top_depth(7)`), which resolves up to seven levels per lookup from
/// the table instead of the default's few: the same checks.
#[derive(Debug, PartialEq)]
struct DeepestTable(LevelOrderTree);

impl DeepestTable {
    fn encode(level: Level, format: Format, states: &[State]) -> Result<Self, TreeError> {
        LevelOrderTree::encode(level, format, states).map(|t| DeepestTable(t.with_top_depth(7)))
    }
    fn from_bytes(bytes: &[u8]) -> Result<Self, TreeError> {
        LevelOrderTree::from_bytes(bytes).map(|t| DeepestTable(t.with_top_depth(7)))
    }
    fn to_bytes(&self) -> Vec<u8> {
        self.0.to_bytes()
    }
    fn level(&self) -> Level {
        self.0.level()
    }
    fn format(&self) -> Format {
        self.0.format()
    }
    fn decode(&self) -> Result<Vec<State>, TreeError> {
        self.0.decode()
    }
    fn get(&self, index: u64) -> Option<State> {
        assert_eq!(
            self.0.top_depth(),
            7.min(self.0.level().get().saturating_sub(1))
        );
        self.0.get(index)
    }
    fn get_f32(&self, u: f32, v: f32) -> Option<State> {
        self.0.get_f32(u, v)
    }
}

/// The sizes of the paper's examples: an alternating level-1 map costs more
/// than flat (5 tree bits + 4 data bits against 4 flat bits), a uniform map
/// of any level one node.
#[test]
fn alternating_costs_more_than_flat_and_uniform_costs_one_node() {
    let paper =
        PaperTree::encode(lvl(1), Format::TwoState, &alternating(1, Format::TwoState)).unwrap();
    assert_eq!(paper.tree_bit_string(), "10000");
    assert_eq!(paper.total_bits(), 9);
    let paper = PaperTree::encode(
        lvl(12),
        Format::FourState,
        &uniform(12, State::UnknownOpaque),
    )
    .unwrap();
    assert_eq!((paper.tree_bits(), paper.data_bits()), (1, 2));
    let fast = LevelOrderTree::from_paper(&paper);
    assert_eq!(
        (
            fast.internal_bits(),
            fast.directory_bits(),
            fast.data_bits()
        ),
        (1, 0, 2)
    );
    // Alternating at level L: every node of the perfect tree is a node.
    let level = 5;
    let paper = PaperTree::encode(
        lvl(level),
        Format::TwoState,
        &alternating(level, Format::TwoState),
    )
    .unwrap();
    assert_eq!(paper.tree_bits(), (4u64.pow(level + 1) - 1) / 3);
    assert_eq!(paper.data_bits(), 4u64.pow(level));
}

/// A hand-checked level-2 map: quadrant 0 uniform opaque, quadrant 1
/// mixed, quadrants 2 and 3 uniform transparent.
#[test]
fn hand_checked_level_2_tree() {
    use State::*;
    let states = [
        [Opaque; 4],
        [Opaque, Transparent, Transparent, Opaque],
        [Transparent; 4],
        [Transparent; 4],
    ]
    .concat();
    let paper = PaperTree::encode(lvl(2), Format::TwoState, &states).unwrap();
    assert_eq!(paper.tree_bit_string(), "101000000");
    assert_eq!(state_chars(&paper.leaf_states()), "1100100");
    let fast = LevelOrderTree::encode(lvl(2), Format::TwoState, &states).unwrap();
    // Level order: root 1; depth 1: 0 1 0 0; leaves: depth 1 (1, 0, 0) then depth 2 (1 0 0 1).
    assert_eq!(fast.internal_bits(), 5);
    assert_eq!(fast.leaf_count(), 7);
    let bytes = fast.to_bytes();
    assert_eq!(&bytes[..8], b"SOMT\x01\x01\x02\x01");
    assert_eq!(
        bytes[8..24],
        [5, 0, 0, 0, 0, 0, 0, 0, 7, 0, 0, 0, 0, 0, 0, 0]
    );
    assert_eq!(bytes[24..], [0b0_0101, 0b100_1001]);
}

/// `from_parts` checks the paper's bits: each malformed shape has its error.
#[test]
fn paper_bits_that_are_not_a_tree_are_rejected() {
    use State::*;
    let bits = |s: &str| s.bytes().map(|b| b == b'1').collect::<Vec<_>>();
    let parts = |level: u32, tree: &str, leaves: &[State]| {
        PaperTree::from_parts(lvl(level), Format::FourState, bits(tree), leaves)
    };
    let four = [Opaque, Transparent, Opaque, Opaque];
    assert!(parts(1, "10000", &four).is_ok());
    assert_eq!(
        parts(1, "1000", &four[..3]),
        Err(TreeError::TreeEndsEarly { tree_bits: 4 })
    );
    assert_eq!(
        parts(1, "", &[]),
        Err(TreeError::TreeEndsEarly { tree_bits: 0 })
    );
    assert_eq!(
        parts(1, "100000", &four),
        Err(TreeError::TreeBitsLeftOver {
            used: 5,
            tree_bits: 6
        })
    );
    assert_eq!(
        parts(1, "110000", &four),
        Err(TreeError::DeeperThanLevel {
            position: 1,
            level: 1
        })
    );
    assert_eq!(
        parts(1, "10000", &four[..3]),
        Err(TreeError::LeafCount { leaves: 4, data: 3 })
    );
    assert_eq!(
        parts(1, "10000", &[Opaque; 4]),
        Err(TreeError::Unmerged { position: 0 })
    );
    assert_eq!(
        parts(
            2,
            "1010000",
            &[Opaque, Opaque, Opaque, Opaque, Transparent, Opaque, Opaque]
        ),
        Err(TreeError::TreeEndsEarly { tree_bits: 7 })
    );
    assert_eq!(
        parts(
            2,
            "10100000000",
            &[
                Opaque,
                UnknownOpaque,
                UnknownOpaque,
                UnknownOpaque,
                UnknownOpaque,
                Opaque,
                Opaque
            ]
        ),
        Err(TreeError::Unmerged { position: 2 })
    );
    assert_eq!(
        PaperTree::from_parts(
            lvl(1),
            Format::TwoState,
            bits("10000"),
            &[Opaque, UnknownOpaque, Opaque, Opaque]
        ),
        Err(TreeError::StateNotInFormat {
            position: 1,
            state: UnknownOpaque
        })
    );
}

/// The header checks, one error each.
#[test]
fn malformed_headers_have_typed_errors() {
    let good = PaperTree::encode(
        lvl(1),
        Format::FourState,
        &alternating(1, Format::FourState),
    )
    .unwrap()
    .to_bytes();
    assert!(PaperTree::from_bytes(&good).is_ok());
    let with = |at: usize, value: u8| {
        let mut bytes = good.clone();
        bytes[at] = value;
        PaperTree::from_bytes(&bytes)
    };
    assert_eq!(with(0, b'X'), Err(TreeError::BadMagic));
    assert_eq!(
        with(4, 2),
        Err(TreeError::UnsupportedVersion { version: 2 })
    );
    assert!(matches!(
        with(5, 1),
        Err(TreeError::WrongLayout { found: 1, .. })
    ));
    assert!(matches!(
        LevelOrderTree::from_bytes(&good),
        Err(TreeError::WrongLayout { found: 0, .. })
    ));
    assert_eq!(
        with(6, 17),
        Err(TreeError::LevelTooHigh { level: 17, max: 16 })
    );
    assert_eq!(with(7, 3), Err(TreeError::BadFormat { raw: 3 }));
    // A 2-state reading of 4-state data: 4 states in 4 bits, the high 4 set.
    assert_eq!(
        with(7, 1),
        Err(TreeError::UnusedBitsSet {
            section: Section::Data
        })
    );
    assert_eq!(
        PaperTree::from_bytes(&good[..10]),
        Err(TreeError::Truncated {
            needed: 24,
            available: 10
        })
    );
    assert_eq!(
        with(8, 200),
        Err(TreeError::Truncated {
            needed: 24 + 25 + 1,
            available: 26
        })
    );
    let mut huge = good.clone();
    huge[8..16].copy_from_slice(&u64::MAX.to_le_bytes());
    assert!(matches!(
        PaperTree::from_bytes(&huge),
        Err(TreeError::Truncated { .. })
    ));
    // 5 tree bits: bits 5..8 of byte 24 are unused.
    assert_eq!(
        with(24, good[24] | 0x80),
        Err(TreeError::UnusedBitsSet {
            section: Section::Tree
        })
    );
}

/// A tree whose root is a leaf: 26 bytes at any level (the committed
/// regression inputs `fuzz/regressions/succinct_tree/level16-root-leaf-*`).
fn root_leaf_bytes(layout: u8, level: u8) -> Vec<u8> {
    let mut bytes = b"SOMT".to_vec();
    bytes.extend_from_slice(&[1, layout, level, 2]);
    bytes.extend_from_slice(&1u64.to_le_bytes()); // one tree bit
    bytes.extend_from_slice(&1u64.to_le_bytes()); // one state
    bytes.extend_from_slice(&[0, 3]); // the bit "leaf"; state 3
    bytes
}

/// 26 bytes of level 16 stand for 4^16 states: the runs say so without
/// the 4 GiB a flat decode takes (the fuzz harness and the C and Python
/// decoders fill from the runs), and the runs fill a packed micromap like
/// the flat states do.
#[test]
fn a_tiny_deep_tree_is_one_run() {
    for layout in [0u8, 1] {
        let bytes = root_leaf_bytes(layout, 16);
        assert_eq!(bytes.len(), 26);
        let file = if layout == 0 { "paper" } else { "level-order" };
        let committed = std::fs::read(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../../fuzz/regressions/succinct_tree")
                .join(format!("level16-root-leaf-{file}")),
        )
        .unwrap();
        assert_eq!(committed, bytes, "{file}");
        let mut runs = Vec::new();
        let mut collect = |first, count, state| runs.push((first, count, state));
        if layout == 0 {
            PaperTree::from_bytes(&bytes)
                .unwrap()
                .for_each_run(&mut collect);
        } else {
            LevelOrderTree::from_bytes(&bytes)
                .unwrap()
                .for_each_run(&mut collect);
        }
        assert_eq!(runs, [(0, 1u64 << 32, State::UnknownOpaque)], "{file}");
        // At level 6 the flat decode is small: runs, decode and the
        // packed map agree.
        let small = root_leaf_bytes(layout, 6);
        let (decoded, map) = if layout == 0 {
            let t = PaperTree::from_bytes(&small).unwrap();
            (t.decode().unwrap(), t.to_micromap().unwrap())
        } else {
            let t = LevelOrderTree::from_bytes(&small).unwrap();
            (t.decode().unwrap(), t.to_micromap().unwrap())
        };
        assert_eq!(decoded, vec![State::UnknownOpaque; 4096]);
        assert_eq!(map.states().collect::<Vec<_>>(), decoded);
    }
}
