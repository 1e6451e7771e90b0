#!/usr/bin/env python3
"""Writes the hand-made seeds of the succinct_tree target into
fuzz/corpus/succinct_tree/seed-*.

Run from the repository root: python3 fuzz/seeds/make_succinct_seeds.py
The inputs follow micromap_index::succinct::fuzzing::succinct_tree: the
whole input is read as tree bytes (the format in src/succinct/mod.rs), and
also as a micromap (level byte, format byte, states two bits each).
A small independent encoder below writes valid tree bytes.
"""
import os
import struct

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "corpus", "succinct_tree")


def write(name, data):
    os.makedirs(ROOT, exist_ok=True)
    with open(os.path.join(ROOT, "seed-" + name), "wb") as f:
        f.write(bytes(data))


def pack(bits):
    out = bytearray((len(bits) + 7) // 8)
    for i, b in enumerate(bits):
        if b:
            out[i // 8] |= 1 << (i % 8)
    return bytes(out)


def uniform(states):
    return all(s == states[0] for s in states)


def paper(states):
    tree, leaves = [], []

    def walk(s):
        if uniform(s):
            tree.append(0)
            leaves.append(s[0])
        else:
            tree.append(1)
            q = len(s) // 4
            for c in range(4):
                walk(s[c * q:(c + 1) * q])

    walk(states)
    return tree, leaves


def level_order(states, level):
    tree, leaves, nodes = [], [], [states]
    for depth in range(level + 1):
        nxt = []
        for s in nodes:
            if depth < level:
                tree.append(0 if uniform(s) else 1)
            if uniform(s):
                leaves.append(s[0])
            else:
                q = len(s) // 4
                nxt += [s[c * q:(c + 1) * q] for c in range(4)]
        nodes = nxt
    return tree, leaves


def tree_bytes(layout, level, fmt, states):
    tree, leaves = paper(states) if layout == 0 else level_order(states, level)
    data = []
    for s in leaves:
        data += [s & 1] if fmt == 1 else [s & 1, s >> 1]
    header = b"SOMT" + bytes([1, layout, level, fmt]) + struct.pack("<QQ", len(tree), len(leaves))
    return header + pack(tree) + pack(data)


MAPS = {
    "uniform-l0": (0, 2, [3]),
    "alternating-l1": (1, 1, [0, 1, 0, 1]),
    "four-states-l1": (1, 2, [0, 1, 2, 3]),
    "one-mixed-quadrant-l2": (2, 2, [1] * 5 + [3] + [1] * 10),
    "corner-l3": (3, 1, [1] + [0] * 63),
    "stripes-l3": (3, 2, [(i // 8) % 4 for i in range(64)]),
}
for name, (level, fmt, states) in MAPS.items():
    for layout, tag in [(0, "paper"), (1, "level-order")]:
        write(f"{tag}-{name}", tree_bytes(layout, level, fmt, states))

# Map mode: level byte, format byte (bit 0: 4-state), states; the flip
# position and mask come from bytes 2..5.
write("map-l2-two-state", [2, 0, 0xF0, 0x0F, 0x33, 0x00])
write("map-l3-four-state", [3, 1, 0x1B, 0xE4, 0x55, 0xAA] + [0] * 12)
write("map-l6-sparse", [6, 1] + [0] * 100 + [0x40])
write("empty", [])
