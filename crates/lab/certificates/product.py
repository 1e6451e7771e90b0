#!/usr/bin/env python3
"""Independent checker of the all-levels product certificate
(docs/verification.md 10.11): the file `micromap-lab prove --all-levels
--certificate FILE` writes, committed as
docs/results/all_levels_certificate.json.

The certificate lists product states (what each claims about the point:
the rest after the columns read, the walk's local u, v, w as forms in the
remainders and its two flags, the reference's parity and guess), starts
and transitions (column, the two digits, target). Nothing of it is
trusted. The checker proves:

 1. every start: the first column is one of a point of the closed
    triangle, and its state is the walk at the root (`Walk::new`) and the
    reference before any digit, with the cell's top column zero;
 2. every transition, by one z3 query (linear real arithmetic): for all
    remainders consistent with the source state's rest, the column and
    the target's rest, this checker's model of `Walk::step` (below; the
    code of src/uv2index/mod.rs must be exactly the modelled lines) on the
    source's coordinates emits the claimed walk digit and gives the
    target's coordinates and flags; the query's premise must be
    satisfiable (no vacuous transition); the reference digit and parity
    follow the digit table of lemmas.py with the borrow of "minus one";
 3. closure: it recomputes itself which rests a point can have, which
    columns can follow, where a level can end (the cell rule of lemmas.py)
    and so which (rest, guess) a run of a point at some level can pass
    through, and requires a start for every possible first column and
    guess and a transition for every such column from every state;
 4. acceptance: every transition's two digits are equal.

By induction over the columns, a point's run at level n, with the guess
the cell rule makes for it, starts in a certified start and follows
certified transitions whose digits are the walk's and the reference's
true digits (lemmas 1-3 of lemmas.py tie the reference's digits and cell
to its code), and they are equal: the walk equals the reference at every
dyadic point, so at every real point (docs/verification.md 10.1).

Then it mutates the certificate in memory (a wrong target, both digits of
a transition changed alike, a transition or a start dropped, a wrong form,
a flipped parity or flag) and checks the certificate under a wrong walk
model (the tie rule without mid_flip), and requires each to be refused
(negative controls; `--no-controls` skips them).

The source check (MODELLED_FUNCTIONS) reads structure, as lemmas.py's
does (rust_source.py): `new`, `step`, `enter_middle` and `mod digit` are
cut from the source by brace matching and must be the modelled lines of
tokens exactly, in order; product_mutants.py checks that mutants of them
are refused.

Usage: python3 crates/lab/certificates/product.py [FILE] [--no-controls] [--source-only]
(exit 0: the certificate holds and every mutant is refused; --source-only:
the source check alone; PRODUCT_SOURCE=FILE reads FILE instead of
src/uv2index/mod.rs)
"""
import copy
import functools
import json
import os
import sys
import time

import z3

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import lemmas  # noqa: E402  (TABLE, documented_rule: one model of the reference)
from rust_source import refuse_unless_modelled  # noqa: E402  (the structural source check)

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")
DEFAULT = os.path.join(ROOT, "docs/results/all_levels_certificate.json")
WALK_SOURCE = os.environ.get("PRODUCT_SOURCE", os.path.join(ROOT, "src/uv2index/mod.rs"))
COORDINATES = "uvw"
LEFT, MIDDLE, RIGHT, TOP = 0, 1, 2, 3

# src/uv2index/mod.rs, item by item: the code that `walk_new`, `walk_step`
# (below) and the digit constants (above) model, as lines of tokens (the item's
# header, then its body). rust_source.py (shared with lemmas.py) cuts each
# item from the source by brace matching, outside comments and literals,
# and requires exactly these lines, in order: an inserted, deleted,
# duplicated, reordered or changed line fails this checker until the model
# is updated. product_mutants.py checks that it does.
MODELLED_FUNCTIONS = {
    # walk_new.
    "fn new": [
        "pub fn new(u: T, v: T) -> Self {",
        "let w = T::one_minus_sum(&u, &v);",
        "Walk {",
        "u,",
        "v,",
        "w,",
        "mid_flip: false,",
        "top_flip: false,",
        "}",
    ],
    # walk_step, its four branches in order (Left, Top, Right, Middle).
    "fn step": [
        "pub fn step(&mut self) -> u8 {",
        "let (left, right) = if self.top_flip {",
        "(digit::RIGHT, digit::LEFT)",
        "} else {",
        "(digit::LEFT, digit::RIGHT)",
        "};",
        "let tie_to_middle = self.mid_flip && self.v.cmp_half() == Ordering::Equal;",
        "if self.w.cmp_half() == Ordering::Greater {",
        "let w = self.w.minus(&self.u).minus(&self.v);",
        "self.u = self.u.twice();",
        "self.v = self.v.twice();",
        "self.w = w;",
        "left",
        "} else if self.v.cmp_half() != Ordering::Less && !tie_to_middle {",
        "let v = self.v.minus(&self.u).minus(&self.w);",
        "self.u = self.u.twice();",
        "self.v = v;",
        "self.w = self.w.twice();",
        "self.top_flip = !self.top_flip;",
        "digit::TOP",
        "} else if self.u.cmp_half() != Ordering::Less && !tie_to_middle {",
        "let u = self.u.minus(&self.v).minus(&self.w);",
        "self.u = u;",
        "self.v = self.v.twice();",
        "self.w = self.w.twice();",
        "right",
        "} else {",
        "self.enter_middle();",
        "self.mid_flip = !self.mid_flip;",
        "digit::MIDDLE",
        "}",
    ],
    # walk_step's Middle branch: (u + v - w, w + u - v, v + w - u).
    "fn enter_middle": [
        "fn enter_middle(&mut self) {",
        "let u = self.u.plus(&self.v).minus(&self.w);",
        "let v = self.w.plus(&self.u).minus(&self.v);",
        "let w = self.v.plus(&self.w).minus(&self.u);",
        "self.u = u;",
        "self.v = v;",
        "self.w = w;",
    ],
    # LEFT, MIDDLE, RIGHT, TOP above.
    "mod digit": [
        "pub mod digit {",
        "pub const LEFT: u8 = 0;",
        "pub const MIDDLE: u8 = 1;",
        "pub const RIGHT: u8 = 2;",
        "pub const TOP: u8 = 3;",
    ],
}


def check_walk_source():
    path = WALK_SOURCE if "PRODUCT_SOURCE" in os.environ else "src/uv2index/mod.rs"
    refuse_unless_modelled(open(WALK_SOURCE).read(), path, MODELLED_FUNCTIONS, "product.py")
    count = sum(len(model) for model in MODELLED_FUNCTIONS.values())
    print(f"source check: {len(MODELLED_FUNCTIONS)} items of {path} are the modelled code, line for line ({count} lines)")


# ---- the model: the walk over the reals, the checker, the reference ----

HALF = z3.RealVal(1) / 2


def walk_new(u, v):
    """`Walk::new` with `one_minus_sum` = 1 - (u + v)."""
    return u, v, 1 - (u + v), False, False


def walk_step(u, v, w, mid_flip, top_flip, tie_needs_mid_flip=True):
    """`Walk::step` over the reals, as its four branches: a list of (path
    condition, digit, (u, v, w), mid_flip, top_flip). `twice` is 2x,
    `plus`/`minus` exact, `cmp_half` the comparison with 1/2.
    `tie_needs_mid_flip=False` is a wrong walk (the tie rule without
    `mid_flip`), only for the negative control of the model."""
    left, right = (RIGHT, LEFT) if top_flip else (LEFT, RIGHT)
    tie_to_middle = z3.And(z3.BoolVal(mid_flip or not tie_needs_mid_flip), v == HALF)
    go_left = w > HALF
    go_top = z3.And(z3.Not(go_left), v >= HALF, z3.Not(tie_to_middle))
    go_right = z3.And(z3.Not(go_left), z3.Not(go_top), u >= HALF, z3.Not(tie_to_middle))
    go_middle = z3.And(z3.Not(go_left), z3.Not(go_top), z3.Not(go_right))
    return [
        (go_left, left, (2 * u, 2 * v, w - u - v), mid_flip, top_flip),
        (go_top, TOP, (2 * u, v - u - w, 2 * w), mid_flip, not top_flip),
        (go_right, right, (u - v - w, 2 * v, 2 * w), mid_flip, top_flip),
        (go_middle, MIDDLE, (u + v - w, w + u - v, v + w - u), not mid_flip, top_flip),
    ]


def step_partials(u, v, w):
    """Every value the modelled lines of `fn step` and `fn enter_middle`
    form, per branch in walk_step's order (Left, Top, Right, Middle): each
    `minus` chain's first and second result and each `twice`."""
    return [
        [w - u, w - u - v, 2 * u, 2 * v],
        [v - u, v - u - w, 2 * u, 2 * w],
        [u - v, u - v - w, 2 * v, 2 * w],
        [u + v, u + v - w, w + u, w + u - v, v + w, v + w - u],
    ]


def walk_range(step=walk_step, with_conditions=True):
    """The walk's numbers stay in [0, 1] (docs/verification.md 10.12: why
    the fixed-point walk on `Fixed64` / `Fixed128` is exact): `Walk::new`
    at a point of the closed triangle (u, v >= 0, u + v <= 1) forms u + v
    and 1 - (u + v) in [0, 1], and from every state whose u, v, w are >= 0
    and sum to 1, with either flag, each branch of the modelled step whose
    condition holds forms only values in [0, 1] and gives u, v, w >= 0
    summing to 1 again. By induction every value of a walk of such a point
    lies in [0, 1]. `with_conditions=False` takes every branch from every
    state (the negative control: must be refused). Returns the reasons it
    fails (empty: it holds)."""
    u, v, w = z3.Reals("u v w")
    unit = lambda x: z3.And(0 <= x, x <= 1)
    errors = []
    start = z3.And(u >= 0, v >= 0, u + v <= 1)
    holds, why = valid(start, z3.And(unit(u + v), unit(1 - (u + v))))
    if not holds:
        errors.append(f"Walk::new: {why}")
    state = z3.And(u >= 0, v >= 0, w >= 0, u + v + w == 1)
    for mid_flip in (False, True):
        for top_flip in (False, True):
            branches = step(u, v, w, mid_flip, top_flip)
            for (condition, digit, new, _, _), partials in zip(branches, step_partials(u, v, w)):
                premise = z3.And(state, condition) if with_conditions else state
                claim = z3.And(*[unit(x) for x in list(new) + partials], z3.Sum(list(new)) == 1)
                holds, why = valid(premise, claim)
                if not holds:
                    errors.append(f"digit {digit}, mid_flip {mid_flip}, top_flip {top_flip}: {why}")
    return errors


def remainders(name):
    return [z3.Real(f"{name}_{c}") for c in COORDINATES]


def rest_holds(r, rest):
    """The remainders `r` are those the rest annotation describes: each in
    [0, 1), zero exactly where flagged, summing to D."""
    zero = rest["zero"]
    parts = [z3.And(0 <= x, x < 1, (x == 0) == (c in zero)) for x, c in zip(r, COORDINATES)]
    return z3.And(*parts, z3.Sum(r) == rest["sum"])


def form(f, r):
    a, b, c = f
    return a * r[0] + b * r[1] + c


def bits_of(text):
    return [ch == "1" for ch in text]


def column_follows(r0, bits, r1):
    """The column's bits: 2 R(k-1) = bit(k) + R(k)."""
    return z3.And(*[2 * x0 == int(b) + x1 for x0, b, x1 in zip(r0, bits, r1)])


def satisfiable(*facts):
    solver = z3.Solver()
    solver.add(*facts)
    return solver.check() == z3.sat


def valid(premise, claim):
    solver = z3.Solver()
    solver.add(premise, z3.Not(claim))
    result = solver.check()
    if result != z3.sat:
        return result == z3.unsat, f"z3 says {result}"
    model = solver.model()
    return False, ", ".join(sorted(f"{d.name()} = {model[d]}" for d in model.decls()))


def reference_digit(parity, guess, bits, rest_after):
    """The reference's digit and parity for one column of its cell: the
    point's bit, flipped for the decremented coordinate where its rest
    after the column is zero (lemma 2), read in lemmas.TABLE (lemma 1)."""
    effective = [b != (guess == c and c in rest_after["zero"]) for b, c in zip(bits, COORDINATES)]
    digit = lemmas.TABLE[parity]["".join("1" if b else "0" for b in effective)]
    return digit, parity ^ (digit == 3)


def rule_guess(rest, u_zero, w_zero):
    """The coordinate the reference's cell decrements at a level end with
    this rest (lemmas.documented_rule, proved by lemma 3), '-' for none."""
    zu, zv, zw = (z3.BoolVal(c in rest["zero"]) for c in COORDINATES)
    decs = lemmas.documented_rule(z3.BoolVal(u_zero), z3.BoolVal(w_zero), zu, zv, zw)
    chosen = [c for c, d in zip(COORDINATES, decs) if z3.is_true(z3.simplify(d))]
    return chosen[0] if chosen else "-"


def all_rests():
    for total in range(3):
        for mask in range(8):
            yield {"sum": total, "zero": "".join(c for i, c in enumerate(COORDINATES) if mask >> i & 1) or "-"}


def key(rest):
    return (rest["sum"], rest["zero"])


def bit_strings():
    return [f"{b & 1}{b >> 1 & 1}{b >> 2 & 1}" for b in range(8)]


class Abstraction:
    """What a point can do, recomputed here from the semantics (z3):
    realisable rests, the columns that can follow each, completable rests,
    possible level ends and live (rest, guess, u = 0, w = 0)."""

    def __init__(self):
        r0, r1 = remainders("a"), remainders("b")
        self.rests = [r for r in all_rests() if satisfiable(rest_holds(r0, r))]
        self.follows = {}
        for r in self.rests:
            for bits in bit_strings():
                for s in self.rests:
                    if satisfiable(rest_holds(r0, r), rest_holds(r1, s), column_follows(r0, bits_of(bits), r1)):
                        self.follows.setdefault(key(r), []).append((bits, s))
        done = (0, "uvw")
        self.completable = {done}
        while True:
            more = {key(r) for r in self.rests if any(key(s) in self.completable for _, s in self.follows.get(key(r), []))}
            if more <= self.completable:
                break
            self.completable |= more
        guesses = ["-", "u", "v", "w"]
        flags = [(False, False), (False, True), (True, False), (True, True)]
        self.live = set()
        for r in self.rests:
            for uz, wz in flags:
                if self.level_may_end(r, uz, wz):
                    self.live.add((key(r), rule_guess(r, uz, wz), uz, wz))
        while True:
            more = set()
            for r in self.rests:
                for g in guesses:
                    for uz, wz in flags:
                        state = (key(r), g, uz, wz)
                        if state not in self.live and any((key(s), g, uz, wz) in self.live for _, s in self.follows.get(key(r), [])):
                            more.add(state)
            if not more:
                break
            self.live |= more

    def level_may_end(self, rest, u_zero, w_zero):
        """A point of some level has this rest at the level and these
        `u = 0`, `w = 0`: the rest can complete, u = 0 (w = 0) needs its
        integer part and rest zero, and U + V + W + D = 2^n has a solution
        with that pattern of zero integer parts (any pattern with a nonzero
        part at a large enough level; all zero needs D = 2^n, 1 or 2)."""
        if key(rest) not in self.completable:
            return False
        zero = rest["zero"]
        for pattern in range(8):
            iu, iv, iw = (pattern >> i & 1 == 1 for i in range(3))
            if u_zero != (iu and "u" in zero) or w_zero != (iw and "w" in zero):
                continue
            if iu and iv and iw and rest["sum"] == 0:
                continue
            return True
        return False


def check(cert, abstraction, step=walk_step):
    """All reasons the certificate fails (empty: it holds) under the walk
    model `step`."""
    errors = []
    if cert.get("format") != 1:
        return [f"unknown certificate format {cert.get('format')!r}"]
    states = cert["states"]
    if [s["id"] for s in states] != list(range(len(states))):
        return ["state ids are not 0, 1, 2, ... in order"]
    r0, r1 = remainders("r"), remainders("s")

    def reference_of(s):
        ref = s["reference"]
        return (ref["parity"], ref["minus_one_on"], ref["u_zero"], ref["w_zero"])

    # 1. Starts.
    starts = {}
    for start in cert["starts"]:
        where = f"start {start['bits']} {start['rest']} guess {start['minus_one_on']}"
        s = states[start["state"]]
        bits = bits_of(start["bits"])
        rest = start["rest"]
        premise = z3.And(rest_holds(r0, rest), z3.Sum([int(b) + x for b, x in zip(bits, r0)]) == 1)
        if not satisfiable(premise):
            errors.append(f"{where}: no point of the triangle has this first column")
            continue
        u, v, w, mid, top = walk_new(int(bits[0]) + r0[0], int(bits[1]) + r0[1])
        walk = s["walk"]
        ok, model = valid(premise, z3.And(form(walk["u"], r0) == u, form(walk["v"], r0) == v, form(walk["w"], r0) == w))
        if not ok or (walk["mid_flip"], walk["top_flip"]) != (mid, top):
            errors.append(f"{where}: state S{s['id']} is not the walk at the root (counterexample {model})")
        g = start["minus_one_on"]
        u_zero = not bits[0] and "u" in rest["zero"]
        w_zero = not bits[2] and "w" in rest["zero"]
        if s["rest"] != rest or reference_of(s) != (0, g, u_zero, w_zero):
            errors.append(f"{where}: state S{s['id']} is not the reference before any digit")
        if any(b != (g == c and c in rest["zero"]) for b, c in zip(bits, COORDINATES)):
            errors.append(f"{where}: the reference's cell would have a bit at 2^level")
        starts[(start["bits"], key(rest), g)] = s["id"]

    # 2. and 4. Transitions.
    edges = {}
    for i, t in enumerate(cert["transitions"]):
        a, b = states[t["from"]], states[t["to"]]
        bits = bits_of(t["bits"])
        where = f"transition {i} S{a['id']} --[bits {t['bits']} then D{t['rest']['sum']} z={t['rest']['zero']}]--> S{b['id']}"
        if (t["from"], t["bits"], key(t["rest"])) in edges:
            errors.append(f"{where}: a second transition on the same column")
        edges[(t["from"], t["bits"], key(t["rest"]))] = t["to"]
        premise = z3.And(rest_holds(r0, a["rest"]), rest_holds(r1, t["rest"]), column_follows(r0, bits, r1))
        if not satisfiable(premise):
            errors.append(f"{where}: no point reads this column in this state (vacuous)")
            continue
        if b["rest"] != t["rest"]:
            errors.append(f"{where}: the target's rest is not the column's")
        wa, wb = a["walk"], b["walk"]
        old = [form(wa[c], r0) for c in COORDINATES]
        new = [form(wb[c], r1) for c in COORDINATES]
        claims = []
        for condition, digit, values, mid, top in step(*old, wa["mid_flip"], wa["top_flip"]):
            same = digit == t["walk_digit"] and (mid, top) == (wb["mid_flip"], wb["top_flip"])
            outcome = z3.And(*[x == y for x, y in zip(values, new)]) if same else z3.BoolVal(False)
            claims.append(z3.Implies(condition, outcome))
        ok, model = valid(premise, z3.And(*claims))
        if not ok:
            errors.append(f"{where}: the walk's step does not give digit {t['walk_digit']} and the target's coordinates; counterexample {model}")
        parity, g, uz, wz = reference_of(a)
        digit, next_parity = reference_digit(parity, g, bits, t["rest"])
        if digit != t["reference_digit"]:
            errors.append(f"{where}: the reference's digit is {digit}, not {t['reference_digit']}")
        if reference_of(b) != (int(next_parity), g, uz, wz):
            errors.append(f"{where}: the target's reference state is not parity {int(next_parity)}, guess {g}")
        if t["walk_digit"] != t["reference_digit"]:
            errors.append(f"{where}: the digits differ (walk {t['walk_digit']}, reference {t['reference_digit']})")

    # 3. Closure.
    for r in abstraction.rests:
        for bits in bit_strings():
            if sum(int(b) for b in bits) + r["sum"] != 1:
                continue
            for g in ["-", "u", "v", "w"]:
                uz = bits[0] == "0" and "u" in r["zero"]
                wz = bits[2] == "0" and "w" in r["zero"]
                if (key(r), g, uz, wz) in abstraction.live and (bits, key(r), g) not in starts:
                    errors.append(f"no start for the first column {bits} then D{r['sum']} z={r['zero']} with guess {g}")
    for s in states:
        _, g, uz, wz = reference_of(s)
        for bits, nxt in abstraction.follows.get(key(s["rest"]), []):
            if (key(nxt), g, uz, wz) in abstraction.live and (s["id"], bits, key(nxt)) not in edges:
                errors.append(f"S{s['id']} has no transition for the column bits {bits} then D{nxt['sum']} z={nxt['zero']}")
    return errors


def controls(cert):
    """Mutants of the certificate, each with what it breaks."""
    out = []
    t = cert["transitions"]
    m = copy.deepcopy(cert)
    target = cert["states"][t[0]["to"]]
    other = next(s["id"] for s in cert["states"] if s["rest"] == target["rest"] and s["id"] != target["id"])
    m["transitions"][0]["to"] = other
    out.append((f"transition 0 to S{other} (same rest) instead of S{target['id']}", m))
    m = copy.deepcopy(cert)
    for field in ("walk_digit", "reference_digit"):
        m["transitions"][5][field] = (t[5][field] + 1) % 4
    out.append(("transition 5 with both digits changed alike", m))
    m = copy.deepcopy(cert)
    del m["transitions"][len(t) // 2]
    out.append((f"transition {len(t) // 2} dropped", m))
    m = copy.deepcopy(cert)
    del m["starts"][-1]
    out.append(("the last start dropped", m))
    m = copy.deepcopy(cert)
    m["states"][-1]["walk"]["w"][2] += 1
    out.append(("the last state's w off by one", m))
    m = copy.deepcopy(cert)
    m["states"][-1]["reference"]["parity"] ^= 1
    out.append(("the last state's parity flipped", m))
    m = copy.deepcopy(cert)
    m["states"][-1]["walk"]["top_flip"] ^= True
    out.append(("the last state's top_flip flipped", m))
    return out


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    path = args[0] if args else DEFAULT
    check_walk_source()
    if "--source-only" in sys.argv[1:]:
        return
    started = time.process_time()
    cert = json.load(open(path))
    abstraction = Abstraction()
    print(
        f"product certificate {os.path.relpath(path)} (z3 {z3.get_version_string()}): "
        f"{len(cert['states'])} states, {len(cert['starts'])} starts, {len(cert['transitions'])} transitions"
    )
    print(
        f"  recomputed: {len(abstraction.rests)} realisable rests, {len(abstraction.completable)} completable, "
        f"{len(abstraction.live)} live (rest, guess, u = 0, w = 0)"
    )
    errors = check(cert, abstraction)
    for e in errors:
        print(f"  REFUSED: {e}")
    ok = not errors
    if ok:
        print(
            "  holds: every start is the root, every transition proved (one z3 query each), "
            "every live start and column present, every transition's digits equal"
        )
    range_errors = walk_range()
    for e in range_errors:
        print(f"  walk range REFUSED: {e}")
    if not range_errors:
        print("  walk range: every value the walk forms for a point of the closed triangle lies in [0, 1] (induction over the step, 17 z3 queries)")
    ok &= not range_errors
    if "--no-controls" not in sys.argv:
        unconditional = walk_range(with_conditions=False)
        verdict = f"refused ({unconditional[0]})" if unconditional else "ACCEPTED (the range check cannot fail)"
        print(f"  negative control, the walk range with every branch from every state: {verdict}")
        ok &= bool(unconditional)
        wrong_walk = functools.partial(walk_step, tie_needs_mid_flip=False)
        cases = [(what, mutant, walk_step) for what, mutant in controls(cert)]
        cases.append(("the certificate under a wrong walk model (the tie rule without mid_flip)", cert, wrong_walk))
        for what, mutant, step in cases:
            refused = check(mutant, abstraction, step)
            verdict = f"refused ({refused[0]})" if refused else "ACCEPTED (the checker cannot fail)"
            print(f"  negative control, {what}: {verdict}")
            ok &= bool(refused)
    print(f"{'certificate checked' if ok else 'CERTIFICATE CHECK FAILS'} in {time.process_time() - started:.1f} s CPU")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
