#!/usr/bin/env python3
"""SMT certificates (z3) for the rationals' first half: `spec::cell_real`
(`spec::index_real`, `spec::wide_index_real`; docs/verification.md 10.12).

`cell_real` puts both coordinates over one denominator below 2^64
(`over_common_denominator`, src/num/rational.rs) and then runs
`cell_over_denominator` (src/spec/real.rs) in `u128` words; otherwise it
runs `cell_real_ref`, the definition written out on `BigRational`
(clamp to [0, 1], exact floor and fractions, exact `uf + vf >= 1`). This
script proves the fast path equal to that definition:

 9a. common denominator: for integers n and den >= 1 (a `BigRational` in
     lowest terms has a positive denominator) and a common multiple D >= 1
     of both denominators (what `lcm` returns), a = n * (D / den) (the
     division exact) satisfies a / D = n / den: the pair (a, d) denotes the
     coordinate exactly (integer arithmetic; `to_u64` and `to_i128` only
     refuse, and then the definition runs).
 9b. cell over the denominator: for every i128 a, b with |a|, |b| <= 2^100,
     u64 d >= 1 and each level 0..=32 (one query each), the modelled steps
     (the clamp `u128::try_from(x).unwrap_or(0).min(d) << level`, `/` and
     `%` by their definition q d + r = n, 0 <= r < d, `as u64`, the u128
     sum) leave neither u128 nor, for the cells, u64, and give the cell i
     with i d <= c 2^level < (i + 1) d for the clamped numerator c =
     min(max(x, 0), d), and the diagonal (c_u 2^level - i_u d) + (c_v
     2^level - i_v d) >= d: the definition's floor and `frac_u + frac_v >=
     1` for c / d. Refuted when d may be as large as 2^100 (the control:
     the shifted numerators no longer fit).
Negative control of the source check: the diagonal's `>=` changed to `>`
in a copy of src/spec/real.rs must be refused.

The source check reads structure as lemmas.py's does (rust_source.py):
`cell_real`, `cell_over_denominator` and `over_common_denominator` are cut
from the source by brace matching and must be the modelled lines of
tokens exactly, in order.

Usage: python3 crates/lab/certificates/rationals.py [--source-only]
(exit 0: the source is the model and the lemmas hold)
"""
import os
import sys

import z3

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lemmas import prove  # noqa: E402  (the verdict lines, shared)
from rust_source import check_structure, refuse_unless_modelled  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")

# Each file's modelled items, as lines of tokens (the item's header, then
# its body's logical lines). The lemmas below encode them step by step.
MODELLED = {
    "src/spec/real.rs": {
        # The dispatch: the fast path when a common denominator fits.
        "fn cell_real": [
            "pub fn cell_real(u: &BigRational, v: &BigRational, level: Level) -> Cell {",
            "match over_common_denominator(u, v) {",
            "Some((a, b, d)) => cell_over_denominator(a, b, d, level.get()),",
            "None => cell_real_ref(u, v, level),",
            "}",
        ],
        # lemma_cell: d128, clamp, su / sv, the cell's fields.
        "fn cell_over_denominator": [
            "fn cell_over_denominator(a: i128, b: i128, d: u64, level: u32) -> Cell {",
            "let d = u128::from(d);",
            "let clamp = |x: i128| u128::try_from(x).unwrap_or(0).min(d) << level;",
            "let (su, sv) = (clamp(a), clamp(b));",
            "Cell {",
            "iu: (su / d) as u64,",
            "iv: (sv / d) as u64,",
            "diagonal: su % d + sv % d >= d,",
            "}",
        ],
    },
    "src/num/rational.rs": {
        # lemma_common_denominator: D, d, a = n * (D / den), the bound.
        "fn over_common_denominator": [
            "pub fn over_common_denominator(u: &BigRational, v: &BigRational) -> Option<(i128, i128, u64)> {",
            "let denominator: BigInt = u.denom().lcm(v.denom());",
            "let d = denominator.to_u64()?;",
            "let scale = |r: &BigRational| -> Option<i128> {",
            "let a = (r.numer() * (&denominator / r.denom())).to_i128()?;",
            "(a.unsigned_abs() <= 1 << 100).then_some(a)",
            "};",
            "Some((scale(u)?, scale(v)?, d))",
        ],
    },
}


def check_source():
    for path, model in MODELLED.items():
        refuse_unless_modelled(open(os.path.join(ROOT, path)).read(), path, model, "rationals.py")
    path = "src/spec/real.rs"
    source = open(os.path.join(ROOT, path)).read()
    mutant = source.replace("diagonal: su % d + sv % d >= d,", "diagonal: su % d + sv % d > d,")
    if mutant == source or not check_structure(mutant, path, MODELLED[path], "rationals.py"):
        print("source check: the negative control (`>=` to `>`) was NOT refused", file=sys.stderr)
        sys.exit(1)
    count = sum(len(lines) for model in MODELLED.values() for lines in model.values())
    print(
        f"source check: 3 functions of src/spec/real.rs and src/num/rational.rs are the modelled code "
        f"({count} lines; a changed diagonal test is refused)"
    )


def lemma_common_denominator():
    """9a over the integers."""
    n, den, big_d = z3.Ints("n den D")
    facts = z3.And(den >= 1, big_d >= 1, big_d % den == 0)
    a = n * (big_d / den)  # `&denominator / r.denom()`: exact here
    return prove(z3.Implies(facts, a * den == n * big_d), "9a: (n * (D / den)) / D = n / den for every common multiple D")


def lemma_cell(d_limit=2**64, name="9b: cell_over_denominator is the definition's cell and diagonal, levels 0..=32"):
    """9b over the integers, one query per level: the code's `u128` steps
    as integer operations plus the claims that none leaves `u128` (or, for
    `as u64`, `u64`), Rust's `/` and `%` by their definition (q d + r = n,
    0 <= r < d)."""
    ok = True
    for level in range(33):
        a, b, d = z3.Ints("a b d")
        qu, ru, qv, rv = z3.Ints("q_u r_u q_v r_v")
        facts = [d >= 1, d < d_limit]
        facts += [x <= 2**100 for x in (a, b)] + [x >= -(2**100) for x in (a, b)]

        # `u128::try_from(x).unwrap_or(0).min(d) << level`
        def clamp(x):
            return z3.If(x < 0, 0, z3.If(x < d, x, d)) * 2**level

        su, sv = clamp(a), clamp(b)
        # `su / d`, `su % d` (and for sv): unsigned division's definition.
        for n, q, r in ((su, qu, ru), (sv, qv, rv)):
            facts += [n == q * d + r, 0 <= r, r < d]
        claims = [
            su < 2**128, sv < 2**128,  # the shifts keep every bit
            qu < 2**64, qv < 2**64,  # `as u64` keeps the cells
            ru + rv < 2**128,  # the u128 sum does not overflow
            # The definition: the floor of c 2^level / d and the
            # fractions' sum reaching 1.
            qu * d <= su, su < (qu + 1) * d, qv * d <= sv, sv < (qv + 1) * d,
            (ru + rv >= d) == ((su - qu * d) + (sv - qv * d) >= d),
        ]
        solver = z3.Solver()
        solver.add(*facts, z3.Not(z3.And(*claims)))
        result = solver.check()
        if d_limit == 2**64 and result != z3.unsat:
            print(f"  {name}: FAILS at level {level} ({result})")
            if result == z3.sat:
                print(f"    counterexample: {solver.model()}")
            return False
        if d_limit != 2**64 and result == z3.sat:
            print(f"  {name}: refuted (expected) at level {level}")
            return True
    if d_limit != 2**64:
        print(f"  {name}: NOT refuted (the control fails)")
        return False
    print(f"  {name}: holds", flush=True)
    return ok


def main():
    check_source()
    if "--source-only" in sys.argv[1:]:
        return
    print("SMT certificates, the rationals' first half (z3 " + z3.get_version_string() + "):")
    ok = lemma_common_denominator()
    ok &= lemma_cell()
    ok &= lemma_cell(d_limit=2**100 + 1, name="9b with d up to 2^100 (control)")
    print("all lemmas hold" if ok else "SOME LEMMA FAILS")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
