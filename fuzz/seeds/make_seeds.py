#!/usr/bin/env python3
"""Writes the hand-made seeds into fuzz/corpus/<target>/seed-*.

Run from the repository root: python3 fuzz/seeds/make_seeds.py
The encodings follow the decoders documented in src/fuzzing.rs.
"""
import os
import struct

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "corpus")


def f32(x):
    return struct.pack("<f", x)


def f32_bits(b):
    return struct.pack("<I", b)


def f64(x):
    return struct.pack("<d", x)


def f64_bits(b):
    return struct.pack("<Q", b)


def write(target, name, data):
    d = os.path.join(ROOT, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, "seed-" + name), "wb") as f:
        f.write(data)


# spec_vs_mirror: u bits, v bits, level byte, mode byte, delta byte.
S = "spec_vs_mirror"
write(S, "half-quarter-l1", f32(0.5) + f32(0.25) + bytes([1]))
write(S, "nan-inf-l1", f32_bits(0x7FC00000) + f32_bits(0x7F800000) + bytes([1]))
write(S, "negzero-one-l2", f32_bits(0x80000000) + f32(1.0) + bytes([2]))
write(S, "subnormal-zero-l0", f32_bits(1) + f32(0.0) + bytes([0]))
# 1/8 - 2^-27 below the diagonal, binary32 rounds the sum up (README).
write(S, "rounding-window-l2", f32(0.125) + f32_bits(0x3DFFFFFF) + bytes([2]))
write(S, "one-one-l16", f32(1.0) + f32(1.0) + bytes([16]))
write(S, "two-pow-32-l31", f32(2.0**32) + f32(0.3) + bytes([31]))
write(S, "level-32", f32(0.3) + f32(0.6) + bytes([32]))
write(S, "level-255", f32(0.7) + f32(0.1) + bytes([255]))
write(S, "neg-nan-neg-inf-l5", f32_bits(0xFFC00001) + f32_bits(0xFF800000) + bytes([5]))
for level, delta in [(0, 0), (2, 1), (7, 0xFF), (16, 0x80), (24, 3), (31, 0x7F)]:
    write(S, f"diagonal-mode-l{level}-d{delta}", f32(0.3) + f32(0.2) + bytes([level, 1, delta]))

# exact_walk_vs_fixed: level, flags, u, v, du, dv.
E = "exact_walk_vs_fixed"
def ew(name, level, flags, u, v, du=0, dv=0):
    write(E, name, bytes([level, flags]) + u + v + bytes([du & 0xFF, dv & 0xFF]))

ew("f32-origin-l32", 32, 0, f32(0.0), f32(0.0))
ew("f32-half-half-l32", 32, 0, f32(0.5), f32(0.5))
ew("f32-one-zero-l1", 1, 0, f32(1.0), f32(0.0))
ew("f32-subnormals-l32", 32, 0, f32_bits(1), f32_bits(0x7FFFFF))
ew("f32-third-l20", 20, 0, f32(1 / 3), f32(1 / 3))
ew("f32-raw-outside-l3", 3, 8, f32(-0.5), f32(0.2))
ew("f32-raw-sum-above-l3", 3, 8, f32(0.6), f32(0.6))
ew("f32-raw-negzero-l3", 3, 8, f32_bits(0x80000000), f32(1.0))
ew("f32-snap-l17", 17, 2, f32(0.3), f32(0.2), -1, 0)
ew("f32-near-diagonal-l25", 25, 4, f32(0.3), f32(0.6), 0, 1)
ew("f32-snap-near-l32", 32, 6, f32(0.1), f32(0.7), 1, -1)
ew("f64-origin-l32", 32, 1, f64(0.0), f64(0.0))
ew("f64-full-range-subnormals-l32", 32, 17, f64_bits(1), f64_bits(0xFFFFFFFFFFFFF))
ew("f64-third-l32", 32, 1, f64(1 / 3), f64(2 / 3))
ew("f64-full-range-l32", 32, 17, f64(2.0**-600), f64(0.75))
ew("f32-full-range-l32", 32, 16, f32(2.0**-100), f32(0.5))
ew("f64-raw-tiny-above-l9", 9, 9, f64(1.0), f64_bits(1))
ew("f64-snap-near-l32", 32, 7, f64(0.3), f64(0.6), -2, 2)
ew("f64-near-diagonal-l16", 16, 5, f64(0.25), f64(0.5), 0, -1)

# inverse_round_trip: level, index (u64 LE), heavy vertex.
I = "inverse_round_trip"
for level, index, heavy in [(0, 0, 0), (1, 1, 1), (2, 5, 2), (3, 42, 0), (10, 0x5A5A5, 1),
                            (16, 0xFFFFFFFF, 2), (17, 0x123456789, 0), (24, 2**48 - 1, 1),
                            (31, 0x3FFFFFFFFFFFFFFF, 2), (32, 2**64 - 1, 0), (32, 0x9E3779B97F4A7C15, 1)]:
    write(I, f"l{level}-i{index:x}-h{heavy}", bytes([level]) + struct.pack("<Q", index) + bytes([heavy]))

# eval_input: one line, any bytes.
V = "eval_input"
lines = {
    "readme-spec-exact": b'{"u": "0.28", "v": "0.4", "level": 3}',
    "readme-f32-bits": b'{"u": "0x3e000000", "v": "0x3dffffff", "level": 2}',
    "readme-rational": b'{"u": "1/8", "v": "0.125", "level": 2}',
    "readme-not-f32": b'{"u": "0.1", "v": "0", "level": 2}',
    "readme-nan": b'{"u": "0x3f800000", "v": "0x7fc00000", "level": 2}',
    "f64-bits": b'{"u": "0x3fd0000000000000", "v": "0x0000000000000001", "level": 32}',
    "exponent": b'{"u": "1e-3", "v": "-3/8", "level": 16}',
    "outside": b'{"u": "2/3", "v": "1/2", "level": 17}',
    "level-33": b'{"u": "0", "v": "0", "level": 33}',
    "level-huge": b'{"u": "0", "v": "0", "level": 99999999999999999999}',
    "array-form": b'["0.5", "0.25", 1]',
    "missing-level": b'{"u": "0.5", "v": "0"}',
    "number-not-string": b'{"u": 0.5, "v": "0", "level": 1}',
    "extra-field": b'{"u": "0.5", "v": "0", "level": 1, "w": "x"}',
    "duplicate": b'{"u": "0.5", "u": "0.25", "v": "0", "level": 1}',
    "not-utf8": b'{"u": "\xff\xfe", "v": "0", "level": 1}',
    "empty": b"",
    "value-hex": b"0x3f800000",
    "value-decimal": b"-1.5e-3",
    "value-rational": b"-3/8",
    "value-big-exponent": b"1e4096",
    "value-tiny": b"0.000000000000000000000000000000000000000000001401298464324817070923729583289916131280261941876515771757068283889791082685860601486638188362121582031250",
}
for name, data in lines.items():
    write(V, name, data)

# vector_reader: vector file bytes, NUL, answers bytes (no NUL: both readers
# get everything).
R = "vector_reader"
case = '{"id": %d, "u": "%s", "v": "%s", "level": %d, "index": %d, "tags": [%s]}'
cases = [
    case % (0, "0x3e800000", "0x3e800000", 2, 5, '"vertex"'),
    case % (1, "0x7fc00000", "0x7f800000", 1, 3, '"nan", "infinity"'),
    case % (2, "0x3e000000", "0x3dffffff", 2, 1, '"rounding-window"'),
    case % (3, "1/3", "-3/8", 16, 0, ''),
    '{"id": 4, "u": "0x3f000000", "v": "0x00000000", "level": 0, "index": 0, "tags": [], '
    '"u_decimal": "0.5", "v_decimal": "0"}',
]
vector_file = ('{\n  "format": "micromap-index-vectors",\n  "version": 1,\n  "function": "spec-f32",\n'
               '  "description": "seed",\n  "cases": [\n    ' + ",\n    ".join(cases) + "\n  ]\n}\n").encode()
answers = b'{"id":0,"index":5}\n{"id":1,"index":3}\r\n\n{"id":2,"error":"refused"}\n{"id":9,"index":1,"ms":0.5}\n'
write(R, "file", vector_file)
write(R, "file-and-answers", vector_file + b"\0" + answers)
write(R, "answers-only", b"\0" + answers)
write(R, "one-line-both", b'{"format": "micromap-index-vectors", "version": 1, "function": "spec-f32", "cases": [], "id": 1, "index": 2}')
write(R, "duplicate-id", vector_file.replace(b'"id": 1,', b'"id": 0,'))
write(R, "level-33", vector_file.replace(b'"level": 16', b'"level": 33'))
write(R, "cases-array-of-arrays", b'{"format": "micromap-index-vectors", "version": 1, "function": "spec-f32", "cases": [[0, "0", "0", 0, 0, []]]}')
write(R, "wrong-version", vector_file.replace(b'"version": 1', b'"version": 2'))
write(R, "answers-both-fields", b'\0{"id": 1, "index": 2, "error": "x"}\n')
write(R, "answers-not-utf8", b'\0{"id": 1, "error": "\xff"}\n')
