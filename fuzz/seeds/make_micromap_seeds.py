#!/usr/bin/env python3
"""Writes hand-made seeds for the micromap_buffers target into
fuzz/corpus/micromap_buffers/seed-*, and for the strided_buffers target
(each seed behind a record stride, an index stride, a junk byte and a flags
byte: bit 0 strided buffers end with a whole stride) into
fuzz/corpus/strided_buffers/seed-*.

Run from the repository root: python3 fuzz/seeds/make_micromap_seeds.py
The encoding follows the decoder documented in src/micromap/fuzz_body.rs:
flags byte (bits 0-1 index width none/u8/u16/u32, bit 2 usage counts,
bit 3 allow overlap, bits 4-5 base triangle), three u16 lengths (records,
usage counts, indices), the three slices, then the data.
"""
import os
import struct

CORPUS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "corpus")
ROOT = os.path.join(CORPUS, "micromap_buffers")
STRIDED = os.path.join(CORPUS, "strided_buffers")
# (name, record stride, index stride (0: tight), junk, flags): allowed
# strides, both endings, and strides the APIs refuse.
STRIDES = [
    ("tight", 8, 0, 0x00, 0),
    ("r12-i2x-whole", 12, 1, 0xEE, 1),
    ("r16-i4x-end", 16, 3, 0x5A, 0),
    ("r7-refused", 7, 1, 0xFF, 0),
    ("r10-refused", 10, 2, 0x11, 1),
    ("i3-refused", 8, 3, 0x22, 0),
    ("r36-tight-indices", 36, 0, 0x33, 1),
    ("r0-refused", 0, 4, 0x44, 0),
]


def rec(offset, level, fmt):
    return struct.pack("<IHH", offset, level, fmt)


def usage(count, level, fmt):
    return struct.pack("<III", count, level, fmt)


def seed(name, flags, records=b"", usage_counts=b"", indices=b"", data=b""):
    os.makedirs(ROOT, exist_ok=True)
    body = bytes([flags]) + struct.pack("<HHH", len(records), len(usage_counts), len(indices))
    body += records + usage_counts + indices + data
    with open(os.path.join(ROOT, "seed-" + name), "wb") as f:
        f.write(body)
    os.makedirs(STRIDED, exist_ok=True)
    for variant, record_stride, index_stride, junk, bits in STRIDES:
        head = bytes([record_stride, index_stride, junk, bits])
        with open(os.path.join(STRIDED, f"seed-{name}-{variant}"), "wb") as f:
            f.write(head + body)


U8, U16, U32, USAGE, ALLOW = 1, 2, 3, 4, 8

# Valid: sizes 16, 4, 2, 1 naturally aligned, usage counts, u16 indices with specials.
records = rec(0, 3, 2) + rec(16, 2, 2) + rec(20, 2, 1) + rec(22, 1, 1)
counts = usage(1, 1, 1) + usage(1, 2, 1) + usage(1, 2, 2) + usage(1, 3, 2)
idx16 = struct.pack("<8H", 0, 1, 2, 3, 0xFFFF, 0xFFFE, 0xFFFD, 0xFFFC)
data = bytes(range(16)) + b"\x1b\xe4\x39\x8d" + b"\xa5\x5a" + b"\x0f"
seed("valid-u16-usage", U16 | USAGE, records, counts, idx16, data)
seed("valid-u8", U8, records, b"", bytes([3, 2, 1, 0, 0xFF, 0xFC]), data)
seed("valid-u32-base1", U32 | (1 << 4), records, b"", struct.pack("<3I", 0, 2, 0xFFFFFFFE), data)
seed("valid-no-indices", 0, records, b"", b"", data)
seed("level0-unused-bits", U8, rec(0, 0, 1) + rec(1, 0, 2), b"", bytes([0, 1]), b"\xff\xff")
# Invalid, one reason each.
seed("records-length", 0, records[:7], b"", b"", data)
seed("format-0", 0, rec(0, 1, 0), b"", b"", data)
seed("level-17", 0, rec(0, 17, 1), b"", b"", data)
seed("out-of-bounds", 0, rec(20, 3, 2), b"", b"", data)
seed("overlap", 0, rec(0, 2, 2) + rec(2, 1, 1), b"", b"", data)
seed("overlap-allowed", ALLOW, rec(0, 2, 2) + rec(2, 1, 1) + rec(2, 1, 1), b"", b"", data)
seed("usage-mismatch", USAGE, records, usage(2, 1, 1), b"", data)
seed("index-past-records", U16, records, b"", struct.pack("<H", 4), data)
seed("index-reserved-minus-5", U8, records, b"", bytes([0xFB]), data)
seed("index-odd-length", U16, records, b"", b"\x00", data)
