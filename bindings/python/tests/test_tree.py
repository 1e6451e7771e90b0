"""`Tree`: the succinct tree answers as the flat micromap it encodes."""

import numpy as np
import pytest

import micromap_index as mmi


@pytest.mark.parametrize("layout", ["paper", "level-order"])
@pytest.mark.parametrize("level", [0, 1, 3, 6])
def test_lookup_equals_the_states(layout, level):
    rng = np.random.default_rng(level)
    # Runs of equal states, so that subtrees collapse.
    states = np.repeat(rng.integers(0, 4, 4 ** level // 4 + 1, dtype=np.uint8), 4)[: 4 ** level]
    tree = mmi.Tree.encode(states, level, format=4, layout=layout)
    assert (tree.level, tree.format, tree.layout) == (level, 4, layout)
    assert np.array_equal(tree.decode(), states)
    everything = np.arange(4 ** level, dtype=np.uint64)
    assert np.array_equal(tree.lookup(everything), states)
    assert np.array_equal(tree.lookup(everything.astype(np.int64).reshape(-1, 1)), states.reshape(-1, 1))
    assert [tree.lookup(int(i)) for i in everything[:50]] == states[:50].tolist()
    again = mmi.Tree.from_bytes(tree.to_bytes())
    assert again.to_bytes() == tree.to_bytes() and again.layout == layout
    assert tree.leaf_count <= 4 ** level and tree.total_bits > 0


def test_state_at_is_index_then_lookup():
    level = 4
    states = (np.arange(4 ** level) % 3).astype(np.uint8)
    tree = mmi.Tree.encode(states, level)
    rng = np.random.default_rng(7)
    u = rng.random(300, dtype=np.float32)
    v = rng.random(300, dtype=np.float32)
    expected = states[mmi.index(u, v, level)]
    assert [tree.state_at(a, b) for a, b in zip(u, v)] == expected.tolist()
    assert np.array_equal(tree.lookup(mmi.index(u, v, level).astype(np.uint64)), expected)


def test_two_state_trees_hold_known_states_only():
    states = np.array([mmi.OPAQUE, mmi.TRANSPARENT] * 8, np.uint8)
    tree = mmi.Tree.encode(states.tobytes(), 2, format=2)
    assert tree.format == 2 and np.array_equal(tree.decode(), states)


def test_sizes_and_lookups_equal_the_cli():
    from conftest import run_cli
    import json

    rng = np.random.default_rng(22)
    for level in range(5):
        states = np.repeat(rng.integers(0, 4, 4 ** level, dtype=np.uint8), 1)
        states[: 4 ** level // 2] = mmi.OPAQUE  # a uniform half collapses
        text = "".join(map(str, states.tolist()))
        cli = json.loads(run_cli("tree", "encode", "--format", "4", "--level", level,
                                 "--states", text).stdout)
        paper = mmi.Tree.encode(states, level, layout="paper")
        level_order = mmi.Tree.encode(states, level, layout="level-order")
        assert paper.total_bits == cli["paper_bits"]
        assert level_order.total_bits == cli["level_order_bits"]
        u, v = rng.random(2, dtype=np.float32)
        found = json.loads(run_cli("tree", "lookup", "--format", "4", "--level", level,
                                   "--tree", cli["tree"], "--data", cli["data"],
                                   "--u", f"0x{int(u.view(np.uint32)):08x}", "--v", f"0x{int(v.view(np.uint32)):08x}").stdout)
        assert paper.state_at(u, v) == level_order.state_at(u, v) == found["state"]
