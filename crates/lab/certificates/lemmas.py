#!/usr/bin/env python3
"""Independent SMT certificates (z3) for the lemmas behind
`prove --all-levels` (docs/verification.md, section 10.7).

The reference's integer half is read from src/spec/integer_half.rs: its
word constants (prefix-XOR shifts, interleave steps) are parsed from the
source, and the steps of `reference_cell` / `reference_digits` are
modelled line for line. The source check reads structure: each modelled
function (those two, with the `spread` closure, and the two callers that
pick the word constants) is cut from the source by brace matching, outside
comments and literals, and its lines, as tokens, must equal the model's
lines in order (MODELLED_FUNCTIONS): an inserted, deleted, duplicated,
reordered or changed line fails the script, with a diff, until the model
is updated. lemmas_mutants.py checks that it does.

Lemmas (each an unsatisfiable negation; `sat` prints a counterexample):
 1. digits: for every level 0..=32 the 64-bit `reference_digits` equals
    the column table of docs/verification.md 10.3 (digit per column and
    parity of the Top digits above) on every cell below 2^level (iw's
    bits above the level free); for the 32-bit code at 0..=16; refuted at
    17 for the 32-bit code (negative control: must be sat).
 2. borrow: for every 64-bit x >= 1 and bit k, bit k of x - 1 is bit k of
    x xor [x mod 2^k = 0] ("minus one" read from the top).
 3. cell: for every level 0..=32 (64-bit; 0..=16 32-bit) and every point
    class (integer parts U, V, W, rest sum D, zero flags), `reference_cell`
    with the real diagonal outcome gives the point's integer parts with
    exactly the documented coordinate decremented.
 4. binary32 rounding (the first halves' diagonal, docs/verification.md
    10.12): for binary32 a, b in [0, 1), the binary32 sum (round to
    nearest even) reaches 1.0 exactly when the real a + b reaches
    1 - 2^-25 (the kernel's T = 2^31 - 2^6); refuted with 1 in place of
    1 - 2^-25 (negative control: must be sat).
 5. floored fractions: for reals X_u, X_v >= 0 (fractions times 2^P) and
    their floors F_u, F_v, each exact or X below 2^(P - t), F_u + F_v >= T
    exactly when X_u + X_v >= T, for binary32's (P, t) = (31, 7) with
    T = 2^31 and 2^31 - 2^6 and binary64's (62, 9) with T = 2^62 (the
    per-coordinate property is what prove --all-levels proves of the
    code); refuted without the exact-or-tiny property (must be sat).
 6. scaling: for every normal binary32 c below 1 and level 0..=16, the
    binary32 product c * 2^level is exact (its bits are c's with the
    exponent raised by the level): the kernel's float first half's
    `clamp_flushed(bits) * params.scale`; refuted when c may be
    subnormal (must be sat: why the clamp flushes them).
 7. tiny fraction: for binary32 g in [0, 1) and t in [-0, 2^-110], the
    binary32 g + t and t + g are below 1.0 and the real g + t below
    1 - 2^-25: the float clamp's flush (to 2^-126, fraction 2^(level -
    126)) and the reference's subnormals never make the diagonal true;
    refuted for t up to 2^-24 (must be sat).
 8. literal scaling: for every binary32 c in [+0, 1] (subnormals and 1
    included) and level 0..=32, the binary32 product c * 2^level is finite
    and has the value c 2^level: the literal port's (spec::cell_f32)
    multiply; refuted for c up to 2^97 (must be sat: the product overflows).
Usage: python3 crates/lab/certificates/lemmas.py [--source-only]
(exit 0: the source is the model and all lemmas hold; --source-only: the
source check alone; LEMMAS_SOURCE=FILE reads FILE instead of the source)
"""
import os
import re
import sys

import z3

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rust_source import refuse_unless_modelled  # noqa: E402  (shared with product.py)

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")
SOURCE_PATH = os.environ.get("LEMMAS_SOURCE", os.path.join(ROOT, "src/spec/integer_half.rs"))
SOURCE = open(SOURCE_PATH).read()

# ---- the structure of the modelled functions ----
#
# Each function below is cut from the source by brace matching, outside
# comments and literals, split into logical lines of tokens and compared
# with the modelled lines exactly, in order (rust_source.py, shared with
# product.py): an inserted, deleted, duplicated, reordered or changed line
# is refused. Comments, blank lines and whitespace between tokens are free.
#
# Z(...): a step the z3 model below encodes (the name of its counterpart
# follows); S(...): structure the model follows without a step of its own
# (braces, the `mut` rebindings, the closure's binding).


def Z(line):
    return ("z3", line)


def S(line):
    return ("structure", line)


MODELLED_FUNCTIONS = {
    # cell_lemma, "reference_cell, step by step" (U, V: iu, iv; n: level).
    "fn reference_cell": [
        S("pub fn reference_cell<W: ReferenceWord>(iu: W, iv: W, diagonal: bool, level: u32) -> (W, W, W) {"),
        Z("let one = W::constant(1);"),  # one
        Z("let cells = W::power_of_two(level);"),  # cells = N
        Z("let last = cells.wrapping_sub(one);"),  # last = N - one
        S("let mut iu = iu;"),
        S("let mut iv = iv;"),
        Z("if iu.at_least(cells) {"),  # iu = If(UGE(U, cells), last, U)
        Z("iu = last;"),
        S("}"),
        Z("if iv.at_least(cells) {"),  # iv = If(UGE(V, cells), last, V)
        Z("iv = last;"),
        S("}"),
        Z("let iuv = iu.wrapping_add(iv);"),  # iuv = iu + iv
        Z("if iuv.at_least(cells) {"),  # iu = If(UGE(iuv, cells), ...)
        Z("iu = iu.wrapping_sub(iuv.wrapping_sub(cells).wrapping_add(one));"),
        S("}"),
        Z("let mut iw = iu.wrapping_add(iv).complement();"),  # iw = ~(iu + iv)
        Z("if diagonal && !iuv.at_least(last) {"),  # If(And(diagonal, ULT(iuv, last)), ...)
        Z("iw = iw.wrapping_sub(one);"),
        S("}"),
        Z("(iu, iv, iw)"),  # the claim on iu, iv, iw
    ],
    # digits(iu, iv, iw, level, bits).
    "fn reference_digits": [
        S(
            "pub fn reference_digits<W: ReferenceWord>(iu: W, iv: W, iw: W, level: u32,"
            " prefix_xor: &[u32], interleave: &[(u32, u64)],) -> W {"
        ),
        Z("let last = W::power_of_two(level).wrapping_sub(W::constant(1));"),  # last
        Z("let b0 = iu.xor(iw).complement().and(last);"),  # b0
        Z("let t = iu.xor(iv).and(b0);"),  # t
        Z("let mut f = t;"),  # f = t
        Z("for &shift in prefix_xor {"),  # for shift in prefix
        Z("f = f.xor(f.shift_right(shift));"),  # f ^ LShR(f, shift)
        S("}"),
        Z("let b1 = f.xor(iu).and(b0.complement()).or(t);"),  # b1
        Z("let spread = |x: W| {"),  # def spread(x)
        S("let mut x = x;"),
        Z("for &(shift, mask) in interleave {"),  # for shift, mask in interleave
        Z("x = x.or(x.shift_left(shift)).and(W::constant(mask));"),
        S("}"),
        Z("x"),  # return x
        S("};"),
        Z("spread(b0).or(spread(b1).shift_left(1))"),  # spread(b0) | (spread(b1) << 1)
    ],
    # WIDTHS[32]: the 32-bit code runs the NARROW constants.
    "fn index_from_cell": [
        Z("pub fn index_from_cell(iu: u32, iv: u32, diagonal: bool, level: u32) -> u32 {"),
        S("let (iu, iv, iw) = reference_cell(iu, iv, diagonal, level);"),
        Z("reference_digits(iu, iv, iw, level, &NARROW_PREFIX_XOR, &NARROW_INTERLEAVE)"),
    ],
    # WIDTHS[64]: the 64-bit widening runs the WIDE constants.
    "fn wide_index_from_cell": [
        Z("pub fn wide_index_from_cell(iu: u64, iv: u64, diagonal: bool, level: u32) -> u64 {"),
        S("let (iu, iv, iw) = reference_cell(iu, iv, diagonal, level);"),
        Z("reference_digits(iu, iv, iw, level, &WIDE_PREFIX_XOR, &WIDE_INTERLEAVE)"),
    ],
}

def check_source():
    path = SOURCE_PATH if "LEMMAS_SOURCE" in os.environ else "src/spec/integer_half.rs"
    model = {item: [line for _, line in lines] for item, lines in MODELLED_FUNCTIONS.items()}
    refuse_unless_modelled(SOURCE, path, model, "lemmas.py")
    count = sum(len(model) for model in MODELLED_FUNCTIONS.values())
    encoded = sum(kind == "z3" for model in MODELLED_FUNCTIONS.values() for kind, _ in model)
    print(
        f"source check: {len(MODELLED_FUNCTIONS)} functions of {path} are the modelled code, "
        f"line for line ({count} lines, {encoded} of them z3 steps)"
    )


def constants(name):
    match = re.search(name + r": \[[^\]]*\] = \[(.*?)\];", SOURCE, re.S)
    if not match:
        sys.exit(f"{name} not found in src/spec/integer_half.rs")
    body = match.group(1).replace("_", "")
    if "(" in body:
        return [(int(a), int(b, 0)) for a, b in re.findall(r"\((\d+),\s*(0x[0-9a-f]+|\d+)\)", body)]
    return [int(x) for x in re.findall(r"\d+", body)]


WIDTHS = {
    64: (constants("WIDE_PREFIX_XOR"), constants("WIDE_INTERLEAVE")),
    32: (constants("NARROW_PREFIX_XOR"), constants("NARROW_INTERLEAVE")),
}

# docs/verification.md 10.3: digit per column (u, v, w) for parity 0 / 1.
TABLE = {
    0: {"000": 1, "111": 1, "010": 3, "101": 3, "100": 2, "110": 2, "001": 0, "011": 0},
    1: {"000": 1, "111": 1, "010": 3, "101": 3, "100": 0, "110": 0, "001": 2, "011": 2},
}


def digits(iu, iv, iw, level, bits):
    prefix, interleave = WIDTHS[bits]
    one = z3.BitVecVal(1, bits)
    last = (one << level) - one
    b0 = ~(iu ^ iw) & last
    t = (iu ^ iv) & b0
    f = t
    for shift in prefix:
        f = f ^ z3.LShR(f, shift)
    b1 = ((f ^ iu) & ~b0) | t

    def spread(x):
        for shift, mask in interleave:
            x = (x | (x << shift)) & z3.BitVecVal(mask, bits)
        return x

    return spread(b0) | (spread(b1) << 1)


def prove(claim, name, expect_sat=False):
    solver = z3.Solver()
    solver.add(z3.Not(claim))
    result = solver.check()
    ok = (result == z3.sat) if expect_sat else (result == z3.unsat)
    verdict = "refuted (expected)" if expect_sat and ok else ("holds" if ok else f"FAILS ({result})")
    print(f"  {name}: {verdict}", flush=True)
    if not ok and result == z3.sat:
        print(f"    counterexample: {solver.model()}")
    return ok


def digits_lemma(level, bits, expect_sat=False):
    iu, iv, iw = z3.BitVecs("iu iv iw", bits)
    below = z3.BitVecVal((1 << level) - 1, bits) if level < bits else z3.BitVecVal(-1, bits)
    index = digits(iu, iv, iw, level, bits)
    claims = [iu & ~below == 0, iv & ~below == 0]
    parity = z3.BoolVal(False)
    expected = []
    for j in reversed(range(level)):
        u, v, w = (z3.Extract(j, j, x) == 1 for x in (iu, iv, iw))
        digit = z3.BitVecVal(0, 2)
        for key, d0 in TABLE[0].items():
            d1 = TABLE[1][key]
            match = z3.And(*[(x if c == "1" else z3.Not(x)) for x, c in zip((u, v, w), key)])
            digit = z3.If(match, z3.If(parity, z3.BitVecVal(d1, 2), z3.BitVecVal(d0, 2)), digit)
        expected.append((j, digit))
        parity = z3.Xor(parity, digit == 3)
    out = []
    for j, digit in expected:
        if 2 * j + 1 < bits:
            out.append(z3.Extract(2 * j + 1, 2 * j, index) == digit)
        else:
            out.append(z3.BoolVal(False))
    if 2 * level < bits:
        out.append(z3.Extract(bits - 1, 2 * level, index) == 0)
    # One query per digit (smaller cones: much faster than one conjunction).
    premise = z3.And(*claims)
    ok = all(solve(z3.Implies(premise, part)) for part in out)
    ok = (not ok) if expect_sat else ok
    verdict = ("refuted (expected)" if expect_sat else "holds") if ok else "FAILS"
    print(f"  digits, {bits}-bit code, level {level}: {verdict}", flush=True)
    return ok


def solve(claim):
    """True if the claim holds (its negation is unsatisfiable)."""
    solver = z3.Then("simplify", "bit-blast", "sat").solver()
    solver.add(z3.Not(claim))
    return solver.check() == z3.unsat


def borrow_lemma():
    x, k = z3.BitVecs("x k", 64)
    bit = lambda y: z3.LShR(y, k) & 1
    low_zero = (x & ((z3.BitVecVal(1, 64) << k) - 1)) == 0
    claim = z3.Implies(
        z3.And(x != 0, z3.ULT(k, 64)),
        bit(x - 1) == bit(x) ^ z3.If(low_zero, z3.BitVecVal(1, 64), z3.BitVecVal(0, 64)),
    )
    return prove(claim, "borrow of minus one, 64-bit, every bit k")


def documented_rule(u_zero, w_zero, zu, zv, zw):
    """The cell rule of docs/verification.md 10.3 (lemma 3 proves the code
    follows it; product.py uses it for the level ends): whether the
    reference's cell decrements u, v, w, from u = 0, w = 0 and the zero
    flags of the rest at the level (z3 Booleans)."""
    dec_w = z3.And(z3.Not(w_zero), zw)
    hyp = z3.And(z3.Not(dec_w), w_zero, zu, zv)
    return z3.And(hyp, z3.Not(u_zero)), z3.And(hyp, u_zero), dec_w


def cell_lemma(bits, max_level):
    n = z3.BitVec("n", bits)
    U, V, W = z3.BitVecs("U V W", bits)
    D = z3.BitVec("D", bits)
    zu, zv, zw = z3.Bools("zu zv zw")
    one = z3.BitVecVal(1, bits)
    N = one << n
    # A point class at level n: U + V + W + D = N, D in 0..=2 with the
    # completable rests (D0: all zero; D1: at most one zero; D2: none).
    count_zero = z3.Sum([z3.If(z, 1, 0) for z in (zu, zv, zw)])
    facts = z3.And(
        z3.ULE(n, max_level),
        z3.ULE(U, N), z3.ULE(V, N), z3.ULE(W, N), z3.ULE(D, 2),
        U + V + W + D == N,
        z3.Implies(D == 0, z3.And(zu, zv, zw)),
        z3.Implies(D == 1, count_zero <= 1),
        z3.Implies(D == 2, count_zero == 0),
    )
    # The dyadic diagonal test: R_u + R_v >= 1, i.e. D - R_w >= 1.
    diagonal = z3.Or(D == 2, z3.And(D == 1, zw))
    # reference_cell, step by step.
    cells, last = N, N - one
    iu = z3.If(z3.UGE(U, cells), last, U)
    iv = z3.If(z3.UGE(V, cells), last, V)
    iuv = iu + iv
    iu = z3.If(z3.UGE(iuv, cells), iu - (iuv - cells + one), iu)
    iw = ~(iu + iv)
    iw = z3.If(z3.And(diagonal, z3.ULT(iuv, last)), iw - one, iw)
    u_zero, w_zero = z3.And(U == 0, zu), z3.And(W == 0, zw)
    dec_u, dec_v, dec_w = documented_rule(u_zero, w_zero, zu, zv, zw)
    minus = lambda x, d: x - z3.If(d, one, z3.BitVecVal(0, bits))
    claim = z3.Implies(
        facts,
        z3.And(iu == minus(U, dec_u), iv == minus(V, dec_v), (iw & last) == minus(W, dec_w),
               z3.ULT(minus(W, dec_w), N), z3.ULT(iu, N), z3.ULT(iv, N)),
    )
    return prove(claim, f"cell rule, {bits}-bit code, every level 0..={max_level}")


SCALED_WIDTH = 152


def scaled(bits, width=SCALED_WIDTH):
    """A non-negative binary32 from its bits (below 2 for the default
    width), times 2^149, as an integer: a = m 2^(max(e, 1) - 150), so
    a 2^149 is m << (max(e, 1) - 1), below 2^(max(e, 1) + 23)."""
    e = z3.ZeroExt(width - 8, z3.Extract(30, 23, bits))
    m = z3.ZeroExt(width - 23, z3.Extract(22, 0, bits))
    m = z3.If(e == 0, m, m | (z3.BitVecVal(1, width) << 23))
    return m << z3.If(e == 0, z3.BitVecVal(0, width), e - 1)


def binary32_rounding_lemma(threshold_is_one=False):
    """Lemma 4 on the bits (scaled: fractions times 2^149)."""
    width = SCALED_WIDTH
    f32 = z3.Float32()
    a_bits, b_bits = z3.BitVecs("a b", 32)
    one = z3.BitVecVal(1, width)
    below_one = z3.And(z3.ULT(a_bits, 0x3F80_0000), z3.ULT(b_bits, 0x3F80_0000))
    rounded = z3.fpAdd(z3.RNE(), z3.fpBVToFP(a_bits, f32), z3.fpBVToFP(b_bits, f32))
    reaches = z3.fpGEQ(rounded, z3.FPVal(1.0, f32))
    threshold = (one << 149) if threshold_is_one else (one << 149) - (one << 124)
    claim = z3.Implies(below_one, reaches == z3.UGE(scaled(a_bits) + scaled(b_bits), threshold))
    name = "binary32 sum of two fractions reaches 1.0 iff the real sum reaches "
    name += "1 (control)" if threshold_is_one else "1 - 2^-25"
    return prove(claim, name, expect_sat=threshold_is_one)


def floored_fractions_lemma(bits, tiny_log2, threshold, name, exact_or_tiny=True):
    """Lemma 5 for one format and threshold."""
    x_u, x_v = z3.Reals("X_u X_v")
    f_u, f_v = z3.Ints("F_u F_v")
    facts = []
    for x, f in ((x_u, f_u), (x_v, f_v)):
        facts += [x >= 0, x < 2**bits, f <= x, x < f + 1]
        if exact_or_tiny:
            facts.append(z3.Or(x == f, x < 2 ** (bits - tiny_log2)))
    claim = z3.Implies(z3.And(*facts), (f_u + f_v >= threshold) == (x_u + x_v >= threshold))
    return prove(claim, name, expect_sat=not exact_or_tiny)


def scaling_lemma(subnormal_too=False):
    """Lemma 6: c * 2^level in binary32 is c with its exponent raised."""
    f32 = z3.Float32()
    c_bits, level = z3.BitVecs("c level", 32)
    scale = z3.fpBVToFP((level + 127) << 23, f32)
    product = z3.fpMul(z3.RNE(), z3.fpBVToFP(c_bits, f32), scale)
    exact = z3.fpBVToFP(c_bits + (level << 23), f32)
    smallest = 1 if subnormal_too else 0x0080_0000
    facts = z3.And(z3.UGE(c_bits, smallest), z3.ULT(c_bits, 0x3F80_0000), z3.ULE(level, 16))
    claim = z3.Implies(facts, z3.fpToIEEEBV(product) == z3.fpToIEEEBV(exact))
    if subnormal_too:
        return prove(claim, "binary32 c * 2^level for subnormal c too (control)", expect_sat=True)
    return prove(claim, "binary32 c * 2^level exact for normal c < 1, level 0..=16")


def literal_scaling_lemma(max_c=0x3F80_0000, name="binary32 c * 2^level exact in value for every c in [0, 1], level 0..=32"):
    """Lemma 8: the literal port's `clamp_unit(x) * scale` (spec::cell_f32)
    is exact: for every binary32 c in [+0, 1] (subnormals, zero and 1
    included) and level 0..=32 the binary32 product c * 2^level has the
    value c 2^level (compared as integers times 2^149). Refuted for c up to
    2^97, whose products overflow (the control)."""
    f32 = z3.Float32()
    width = 300
    c_bits, level = z3.BitVecs("c level", 32)
    scale = z3.fpBVToFP((level + 127) << 23, f32)
    product = z3.fpToIEEEBV(z3.fpMul(z3.RNE(), z3.fpBVToFP(c_bits, f32), scale))
    facts = z3.And(z3.ULE(c_bits, max_c), z3.ULE(level, 32), z3.ULT(product, 0x7F80_0000))
    shifted = scaled(c_bits, width) << z3.ZeroExt(width - 32, level)
    exact = z3.Implies(facts, scaled(product, width) == shifted)
    finite = z3.Implies(z3.And(z3.ULE(c_bits, max_c), z3.ULE(level, 32)), z3.ULT(product, 0x7F80_0000))
    return prove(z3.And(exact, finite), name, expect_sat=max_c != 0x3F80_0000)


def tiny_fraction_lemma(tiny_log2=110):
    """Lemma 7: a fraction t <= 2^-tiny_log2 (a binary32: the float clamp's
    flushed 2^(level - 126), or a subnormal's exact x 2^level) never makes
    the diagonal true against another fraction g in [0, 1): binary32's
    g + t and t + g stay below 1.0, and the real g + t below 1 - 2^-25
    (docs/verification.md 10.12, entry_points/clamp.rs). At 2^-24 it fails
    (the control)."""
    f32 = z3.Float32()
    g_bits, t_bits = z3.BitVecs("g t", 32)
    g, t = z3.fpBVToFP(g_bits, f32), z3.fpBVToFP(t_bits, f32)
    tiny = (127 - tiny_log2) << 23
    # -0.0 too: the literal port's clamp may give it (Rust leaves the sign
    # of max(-0.0, 0.0) open), and then its fraction.
    facts = z3.And(z3.ULT(g_bits, 0x3F80_0000), z3.Or(z3.ULE(t_bits, tiny), t_bits == 0x8000_0000))
    one = z3.FPVal(1.0, f32)
    below = z3.And(z3.fpLT(z3.fpAdd(z3.RNE(), g, t), one), z3.fpLT(z3.fpAdd(z3.RNE(), t, g), one))
    width = SCALED_WIDTH
    threshold = (z3.BitVecVal(1, width) << 149) - (z3.BitVecVal(1, width) << 124)
    real_below = z3.ULT(scaled(g_bits) + scaled(t_bits), threshold)
    claim = z3.Implies(facts, z3.And(below, real_below))
    if tiny_log2 == 110:
        return prove(claim, "a fraction at most 2^-110 never reaches the diagonal (binary32 and real)")
    return prove(claim, f"a fraction at most 2^-{tiny_log2} (control)", expect_sat=True)


def main():
    check_source()
    if "--source-only" in sys.argv[1:]:
        return
    print("SMT certificates (z3 " + z3.get_version_string() + "):")
    ok = borrow_lemma()
    ok &= cell_lemma(64, 32)
    ok &= cell_lemma(32, 16)
    for level in range(0, 33):
        ok &= digits_lemma(level, 64)
    for level in range(0, 17):
        ok &= digits_lemma(level, 32)
    ok &= digits_lemma(17, 32, expect_sat=True)
    ok &= binary32_rounding_lemma()
    ok &= binary32_rounding_lemma(threshold_is_one=True)
    ok &= floored_fractions_lemma(31, 7, 2**31, "floored fractions, binary32, T = 2^31")
    ok &= floored_fractions_lemma(31, 7, 2**31 - 2**6, "floored fractions, binary32, T = 2^31 - 2^6")
    ok &= floored_fractions_lemma(62, 9, 2**62, "floored fractions, binary64, T = 2^62")
    ok &= floored_fractions_lemma(
        31, 7, 2**31 - 2**6, "floored fractions without exact-or-tiny (control)", exact_or_tiny=False
    )
    ok &= scaling_lemma()
    ok &= scaling_lemma(subnormal_too=True)
    ok &= tiny_fraction_lemma()
    ok &= literal_scaling_lemma()
    ok &= literal_scaling_lemma(max_c=0x7000_0000, name="binary32 c * 2^level for c up to 2^97 (control)")
    ok &= tiny_fraction_lemma(tiny_log2=24)
    print("all lemmas hold" if ok else "SOME LEMMA FAILS")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
