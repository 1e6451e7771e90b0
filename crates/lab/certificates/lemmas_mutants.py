#!/usr/bin/env python3
"""Mutation self-test of lemmas.py's source check (issue 36).

Copies src/spec/integer_half.rs to a temporary file, applies one mutation
at a time and runs `lemmas.py --source-only` on it (LEMMAS_SOURCE): every
mutant (an inserted, deleted, moved, duplicated, reordered or changed
line of a modelled function) must be refused, and every control (comments,
blank lines, whitespace: the same tokens) and the unmodified source must
pass. Each mutation must apply to exactly one line, so a stale anchor
fails the script instead of testing nothing. product_mutants.py runs the
same self-test (these helpers) on product.py's check of
src/uv2index/mod.rs.

Usage: python3 crates/lab/certificates/lemmas_mutants.py [-v]
(exit 0: every mutant refused, every control accepted; -v prints
lemmas.py's report for each)
"""
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..", "..")
SOURCE = os.path.join(ROOT, "src/spec/integer_half.rs")
LEMMAS = os.path.join(HERE, "lemmas.py")


class Stale(Exception):
    pass


def find(lines, anchor):
    """The index of the one line whose stripped text is `anchor`; for an
    anchor (after, text), of the first line `text` after the one line
    `after` (a line that also occurs elsewhere, in a later function)."""
    if isinstance(anchor, tuple):
        after, text = anchor
        start = find(lines, after) + 1
        hits = [i for i in range(start, len(lines)) if lines[i].strip() == text][:1]
        if not hits:
            raise Stale(f"`{text}` is on no line after `{after}`")
        return hits[0]
    hits = [i for i, line in enumerate(lines) if line.strip() == anchor]
    if len(hits) != 1:
        raise Stale(f"`{anchor}` is on {len(hits)} lines of the source, not one")
    return hits[0]


def indent(line):
    return line[: len(line) - len(line.lstrip())]


def insert(anchor, new, offset=1):
    """Insert `new` (indented like the anchor) `offset` lines after it."""

    def apply(lines):
        i = find(lines, anchor)
        return lines[: i + offset] + [indent(lines[i]) + new] + lines[i + offset :]

    return apply


def delete(anchor, offset=0):
    def apply(lines):
        i = find(lines, anchor) + offset
        return lines[:i] + lines[i + 1 :]

    return apply


def move_out(anchor, before=("fn _moved<W: ReferenceWord>(mut iu: W, iuv: W, cells: W, one: W) {",), after=("}",)):
    """Delete the line and keep it, verbatim, in a new item (the lines
    `before`, it, `after`) at the end of the file (the line still occurs
    in the source)."""

    def apply(lines):
        i = find(lines, anchor)
        return lines[:i] + lines[i + 1 :] + [""] + list(before) + [lines[i]] + list(after)

    return apply


def swap(anchor, offset=1):
    """Swap the anchor's line with the line `offset` lines from it (+1, -1)."""

    def apply(lines):
        i = find(lines, anchor)
        j = i + offset
        lines = list(lines)
        lines[i], lines[j] = lines[j], lines[i]
        return lines

    return apply


def duplicate(anchor):
    def apply(lines):
        i = find(lines, anchor)
        return lines[: i + 1] + [lines[i]] + lines[i + 1 :]

    return apply


def replace(anchor, old, new):
    """Replace `old` by `new` in the anchor's line (exactly once)."""

    def apply(lines):
        i = find(lines, anchor)
        if lines[i].count(old) != 1:
            raise Stale(f"`{old}` is not once in `{lines[i].strip()}`")
        return lines[:i] + [lines[i].replace(old, new)] + lines[i + 1 :]

    return apply


def both(first, second):
    def apply(lines):
        return second(first(lines))

    return apply


def reindent(first, last, extra):
    """Add `extra` to the indentation of the lines first..=last."""

    def apply(lines):
        i, j = find(lines, first), find(lines, last)
        return lines[:i] + [extra + line if line else line for line in lines[i : j + 1]] + lines[j + 1 :]

    return apply


def join(first, last):
    """Put the lines first..=last on one line (a wrapped signature)."""

    def apply(lines):
        i, j = find(lines, first), find(lines, last)
        return lines[:i] + [" ".join(line.strip() for line in lines[i : j + 1])] + lines[j + 1 :]

    return apply


CELL_SIG = "pub fn reference_cell<W: ReferenceWord>(iu: W, iv: W, diagonal: bool, level: u32) -> (W, W, W) {"
PREFIX = "f = f.xor(f.shift_right(shift));"
INTERLEAVE = "x = x.or(x.shift_left(shift)).and(W::constant(mask));"
MOVE = "iu = iu.wrapping_sub(iuv.wrapping_sub(cells).wrapping_add(one));"

# (description, mutation): each must be refused.
MUTANTS = [
    ("insert `iu = iu;` after `iu = last;` (reference_cell)", insert("iu = last;", "iu = iu;")),
    ("insert `let _x = 0;` at the top of reference_cell", insert(CELL_SIG, "    let _x = 0;")),
    ("insert `let _x = 0;` in the spread closure", insert("let mut x = x;", "let _x = 0;")),
    ("append `iu = iu;` to the line `iu = last;`", replace("iu = last;", "iu = last;", "iu = last; iu = iu;")),
    ("insert `let _s = \"}\";` (a brace in a string)", insert("iw = iw.wrapping_sub(one);", "let _s = \"}\";", 2)),
    ("insert `/* } */ iw = iw;` (a brace in a comment)", insert("iw = iw.wrapping_sub(one);", "/* } */ iw = iw;", 2)),
    ("delete `iv = last;`", delete("iv = last;")),
    ("delete `let mut f = t;`", delete("let mut f = t;")),
    ("delete the `}` closing the prefix-XOR loop", delete(PREFIX, 1)),
    ("move the hypotenuse move into another function (the line stays in the file)", move_out(MOVE)),
    ("swap `let iuv = ...;` with the `}` above it (iuv before iv's clamp)", swap("let iuv = iu.wrapping_add(iv);", -1)),
    ("swap the prefix-XOR step with the `}` below it (out of the loop)", swap(PREFIX, 1)),
    ("swap `let mut iu = iu;` and `let mut iv = iv;` (a harmless reorder)", swap("let mut iu = iu;", 1)),
    ("swap `let b0` and `let t`", swap("let b0 = iu.xor(iw).complement().and(last);", 1)),
    ("duplicate the prefix-XOR step", duplicate(PREFIX)),
    ("duplicate the interleave step", duplicate(INTERLEAVE)),
    ("duplicate `iw = iw.wrapping_sub(one);`", duplicate("iw = iw.wrapping_sub(one);")),
    ("change `let one = W::constant(1)` to 2", replace("let one = W::constant(1);", "(1)", "(2)")),
    ("change `spread(b1).shift_left(1)` to shift_left(2)", replace("spread(b0).or(spread(b1).shift_left(1))", "left(1)", "left(2)")),
    ("change the prefix XOR's shift_right to shift_left", replace(PREFIX, "shift_right", "shift_left")),
    ("change `!iuv.at_least(last)` to `!iuv.at_least(cells)`", replace("if diagonal && !iuv.at_least(last) {", "(last)", "(cells)")),
    ("change `iu.at_least(cells)` to `iu.at_least(last)`", replace("if iu.at_least(cells) {", "(cells)", "(last)")),
    ("swap reference_cell's parameters iu and iv", replace(CELL_SIG, "(iu: W, iv: W,", "(iv: W, iu: W,")),
    ("the 64-bit code with the 32-bit interleave",
     replace("reference_digits(iu, iv, iw, level, &WIDE_PREFIX_XOR, &WIDE_INTERLEAVE)", "&WIDE_INTERLEAVE", "&NARROW_INTERLEAVE")),
]

# (description, mutation): the same tokens, each must be accepted.
CONTROLS = [
    ("a `//` comment line in reference_cell", insert("iu = last;", "// a comment: iu = iu; }")),
    ("a blank line and a trailing `// }` comment",
     both(insert("let iuv = iu.wrapping_add(iv);", "", 0), replace("let iuv = iu.wrapping_add(iv);", ";", "; // }"))),
    ("a `/* { */` block comment line in reference_digits", insert("let mut f = t;", "/* { */")),
    ("reference_cell re-indented", reindent(CELL_SIG, "(iu, iv, iw)", "    ")),
    ("reference_digits' signature on one line", join("pub fn reference_digits<W: ReferenceWord>(", ") -> W {")),
    ("spaces inside a line", replace(PREFIX, "f.xor(f", "f . xor( f")),
]


def run(text, script, variable):
    """`script --source-only` with `variable` naming a file holding
    `text`: (verdict, its output)."""
    with tempfile.NamedTemporaryFile("w", suffix=".rs", delete=False) as file:
        file.write(text)
    try:
        env = dict(os.environ, **{variable: file.name})
        result = subprocess.run([sys.executable, script, "--source-only"], env=env, capture_output=True, text=True)
    finally:
        os.unlink(file.name)
    output = result.stdout + result.stderr
    if result.returncode == 0:
        return "accepted", output
    if result.returncode == 1 and "source check: REFUSED" in output and "Traceback" not in output:
        return "refused", output
    return f"crashed (exit {result.returncode})", output


def self_test(script, variable, source, mutants, controls):
    """Run the unmodified source, every mutant (must be refused) and every
    control (must be accepted) through `script`'s source check; exits 0
    when all are as they must be."""
    verbose = "-v" in sys.argv[1:]
    start = time.time()
    original = open(source).read()
    lines = original.splitlines()
    ok = True
    verdict, output = run(original, script, variable)
    name = os.path.basename(script)
    print(f"{name} source check, mutation self-test ({len(mutants)} mutants, {len(controls)} controls):")
    print(f"  unmodified source: {verdict}")
    if verdict != "accepted":
        print(output)
        ok = False
    for kind, cases, want in (("mutant", mutants, "refused"), ("control", controls, "accepted")):
        for description, mutation in cases:
            try:
                text = "\n".join(mutation(lines)) + "\n"
            except Stale as e:
                print(f"  {kind} does not apply ({e}): {description}")
                ok = False
                continue
            if text == original:
                print(f"  {kind} changes nothing: {description}")
                ok = False
                continue
            verdict, output = run(text, script, variable)
            good = verdict == want
            ok &= good
            print(f"  {kind}, {description}: {verdict}" + ("" if good else f", NOT {want}"))
            if verbose or not good:
                print("    " + output.strip().replace("\n", "\n    "))
    print(f"{'all mutants refused, all controls accepted' if ok else 'SELF-TEST FAILS'} ({time.time() - start:.1f} s)")
    sys.exit(0 if ok else 1)


def main():
    self_test(LEMMAS, "LEMMAS_SOURCE", SOURCE, MUTANTS, CONTROLS)


if __name__ == "__main__":
    main()
