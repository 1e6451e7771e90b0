#!/usr/bin/env python3
"""Mutation self-test of product.py's source check (issue 36).

Copies src/uv2index/mod.rs to a temporary file, applies one mutation at a
time and runs `product.py --source-only` on it (PRODUCT_SOURCE): every
mutant of the modelled items (`Walk::new`, `Walk::step`, `enter_middle`,
`mod digit`: a line inserted, deleted, moved, swapped, duplicated or
changed) must be refused, and every control (comments, blank lines,
whitespace, re-indentation: the same tokens) and the unmodified source
must pass. The helpers and the runner are lemmas_mutants.py's; each
mutation must apply to exactly one line (`step_version1` repeats many of
`step`'s lines, so those are anchored as the first one after a line of
`step`), so a stale anchor fails the script instead of testing nothing.

Usage: python3 crates/lab/certificates/product_mutants.py [-v]
(exit 0: every mutant refused, every control accepted; -v prints
product.py's report for each)
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from lemmas_mutants import (  # noqa: E402  (one implementation of the self-test)
    both,
    delete,
    duplicate,
    find,
    indent,
    insert,
    move_out,
    reindent,
    replace,
    self_test,
    swap,
)

ROOT = os.path.join(HERE, "..", "..", "..")
SOURCE = os.path.join(ROOT, "src/uv2index/mod.rs")
PRODUCT = os.path.join(HERE, "product.py")

NEW_SIG = "pub fn new(u: T, v: T) -> Self {"
STEP_SIG = "pub fn step(&mut self) -> u8 {"
MIDDLE_SIG = "fn enter_middle(&mut self) {"
TIE = "let tie_to_middle = self.mid_flip && self.v.cmp_half() == Ordering::Equal;"
TOP_TEST = "} else if self.v.cmp_half() != Ordering::Less && !tie_to_middle {"
TOP_FLIP = "self.top_flip = !self.top_flip;"
MID_FLIP = "self.mid_flip = !self.mid_flip;"
# Lines `step_version1` repeats: the first one after a line of `step`.
LEFT_TEST = (TIE, "if self.w.cmp_half() == Ordering::Greater {")
LEFT_TWICE_U = (TIE, "self.u = self.u.twice();")
MIDDLE_U = "let u = self.u.plus(&self.v).minus(&self.w);"
MIDDLE_V = "let v = self.w.plus(&self.u).minus(&self.v);"
TOP = "pub const TOP: u8 = 3;"
RIGHT = "pub const RIGHT: u8 = 2;"

def commented_and_changed(anchor, old, new):
    """Keep the line, verbatim, on a line of its own inside a block comment
    and follow it with the line changed (the old line still occurs)."""

    def apply(lines):
        i = find(lines, anchor)
        pad = indent(lines[i])
        return lines[:i] + [pad + "/*", lines[i], pad + "*/", lines[i].replace(old, new)] + lines[i + 1 :]

    return apply


def appended(*extra):
    """Append the lines `extra` at the end of the file."""

    def apply(lines):
        return lines + [""] + list(extra)

    return apply


# (description, mutation): each must be refused.
MUTANTS = [
    ("insert `self.mid_flip = false;` after the Top branch's flip (step)", insert(TOP_FLIP, "self.mid_flip = false;")),
    ("insert `let _x = 0;` at the top of step", insert(STEP_SIG, "    let _x = 0;")),
    ("insert `let _s = \"}\";` in enter_middle (a brace in a string)", insert(MIDDLE_U, "let _s = \"}\";")),
    ("insert `/* } */ self.v = self.u;` in enter_middle (a brace in a comment)", insert(MIDDLE_V, "/* } */ self.v = self.u;")),
    ("append `self.top_flip = false;` to the Middle branch's flip", replace(MID_FLIP, MID_FLIP, MID_FLIP + " self.top_flip = false;")),
    ("insert `pub const BOTTOM: u8 = 4;` in mod digit", insert(TOP, "pub const BOTTOM: u8 = 4;")),
    ("delete the Top branch's `self.top_flip = !self.top_flip;`", delete(TOP_FLIP)),
    ("delete the Middle branch's `self.mid_flip = !self.mid_flip;`", delete(MID_FLIP)),
    ("delete the Middle branch's `self.enter_middle();`", delete(MID_FLIP, -1)),
    ("delete `mid_flip: false,` in new", delete("mid_flip: false,")),
    ("move the Top branch's flip into another impl (the line stays in the file)",
     move_out(TOP_FLIP, ("impl<T: WalkNumber> Walk<T> {", "    fn _moved(&mut self) {"), ("    }", "}"))),
    ("swap the Top branch's flip with `digit::TOP` below it", swap(TOP_FLIP, 1)),
    ("swap `let tie_to_middle` with the `};` above it", swap(TIE, -1)),
    ("swap enter_middle's `let u` and `let v` (a harmless reorder)", swap(MIDDLE_U, 1)),
    ("swap `pub const LEFT` and `pub const MIDDLE` (a harmless reorder)", swap("pub const LEFT: u8 = 0;", 2)),
    ("duplicate the Top branch's flip", duplicate(TOP_FLIP)),
    ("duplicate the Middle branch's flip", duplicate(MID_FLIP)),
    ("duplicate new's `let w = T::one_minus_sum(&u, &v);`", duplicate("let w = T::one_minus_sum(&u, &v);")),
    ("the tie rule without mid_flip (mutant 9 of 10.7)", replace(TIE, "self.mid_flip && ", "")),
    ("the Top test `!= Ordering::Less` made `!= Ordering::Greater`", replace(TOP_TEST, "Less", "Greater")),
    ("the Left test `== Ordering::Greater` made `!= Ordering::Less` (in step)", replace(LEFT_TEST, "== Ordering::Greater", "!= Ordering::Less")),
    ("the Left branch's `self.u.twice()` made `self.u` (in step)", replace(LEFT_TWICE_U, "self.u.twice()", "self.u")),
    ("`mid_flip: true` in new", replace("mid_flip: false,", "false", "true")),
    ("top_flip ignored: `(digit::LEFT, digit::RIGHT)` in both arms", replace("(digit::RIGHT, digit::LEFT)", "(digit::RIGHT, digit::LEFT)", "(digit::LEFT, digit::RIGHT)")),
    ("enter_middle's `v` with `.minus(&self.w)`", replace(MIDDLE_V, "minus(&self.v)", "minus(&self.w)")),
    ("enter_middle's `v` as `self.u.plus(&self.w)` (a harmless commutation)", replace(MIDDLE_V, "self.w.plus(&self.u)", "self.u.plus(&self.w)")),
    ("`TOP` = 4", replace(TOP, "3", "4")),
    ("`TOP` = 4, `pub const TOP: u8 = 3;` kept in another module",
     both(replace(TOP, "3", "4"), appended("pub mod digit_old {", "    " + TOP, "}"))),
    ("`RIGHT` = 1, `pub const RIGHT: u8 = 2;` kept in a block comment", commented_and_changed(RIGHT, "2", "1")),
]

# (description, mutation): the same tokens, each must be accepted.
CONTROLS = [
    ("a `// } else {` comment line in step", insert(TOP_FLIP, "// } else {")),
    ("a blank line and a trailing `// }` comment", both(insert(TIE, "", 0), replace(TIE, ";", "; // }"))),
    ("a `/* { */` block comment line in enter_middle", insert(MIDDLE_U, "/* { */", 0)),
    ("a block comment over two lines in step", insert(TIE, "/* the tie rule:\n        } else { */", 1)),
    ("a doc comment in mod digit", insert(TOP, "/// Bottom: none.")),
    ("step re-indented", reindent(STEP_SIG, (TIE, "digit::MIDDLE"), "    ")),
    ("the whole file indented by a tab", lambda lines: ["\t" + line if line else line for line in lines]),
    ("new's parameters on lines of their own", replace(NEW_SIG, "(u: T, v: T)", "(\n        u: T,\n        v: T\n    )")),
    ("spaces inside a line", replace(TOP_FLIP, "= !self.", "= ! self . ")),
]


def main():
    self_test(PRODUCT, "PRODUCT_SOURCE", SOURCE, MUTANTS, CONTROLS)


if __name__ == "__main__":
    main()
