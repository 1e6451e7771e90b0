#!/usr/bin/env python3
"""Lists import circles between the source files of each crate: two files
that each use a name of the other (issue 32's rule). Exit 1 if any.

A file "uses" another when its code (comments and strings stripped) names a
path `crate::a::b::X`, `super::...::X` or `self::...::X` whose item `X` is
defined in that other file: the path's longest module prefix that is a
file, followed through `pub use` re-exports to the file that defines `X`.
`mod x;` declarations do not count (a parent declaring a child is not a
use).

Usage: import_circles.py [crate-src-dir ...]   (default: every src/ below
the repository root, excluding target/ and fuzz/).
"""
import os
import re
import sys

PATH = re.compile(r"\b(crate|super|self)((?:::[A-Za-z_][A-Za-z0-9_]*)+)")
USE_GROUP = re.compile(r"((?:\bpub(?:\([^)]*\))?\s+)?)\buse\s+((?:crate|super|self)|[A-Za-z_][A-Za-z0-9_]*)((?:::[A-Za-z_][A-Za-z0-9_]*)*)::\{([^;]*)\};", re.S)


def strip(code):
    """Comments, strings and char literals removed (roughly, enough here)."""
    code = re.sub(r"//[^\n]*", "", code)
    code = re.sub(r"/\*.*?\*/", "", code, flags=re.S)
    code = re.sub(r'r#*"(?:.|\n)*?"#*', '""', code)
    code = re.sub(r'"(?:\\.|[^"\\])*"', '""', code)
    return code


def module_files(src):
    """{module path tuple: file} for one crate's src dir."""
    modules = {}
    for root, _, files in os.walk(src):
        for f in files:
            if not f.endswith(".rs"):
                continue
            full = os.path.join(root, f)
            rel = os.path.relpath(full, src)[:-3].split(os.sep)
            if rel[-1] in ("mod", "lib", "main"):
                rel = rel[:-1]
            if rel and rel[0] == "bin":
                continue
            modules[tuple(rel)] = full
    return modules


def expand_groups(code):
    """`use super::a::{b::C, D}` -> `super::a::b::C super::a::D` (one level
    of braces; nested braces are rare here and expanded again by a second
    pass)."""
    for _ in range(3):
        def repl(m):
            vis = m.group(1)
            head = m.group(2) + m.group(3)
            items = []
            depth = 0
            cur = ""
            for ch in m.group(4):
                if ch == "{":
                    depth += 1
                elif ch == "}":
                    depth -= 1
                if ch == "," and depth == 0:
                    items.append(cur)
                    cur = ""
                else:
                    cur += ch
            items.append(cur)
            out = []
            for item in items:
                item = item.strip()
                if not item:
                    continue
                item = item.split(" as ")[0].strip()
                if item == "self":
                    out.append(f"{vis}use {head};")
                else:
                    out.append(f"{vis}use {head}::{item};")
            return " ".join(out)
        code = USE_GROUP.sub(repl, code)
    return code


DEF = r"\b(?:fn|struct|enum|trait|type|const|static|union|mod|macro_rules!)\s+{}\b"


def resolve(module, head, rest):
    """A path's module steps from `module`: `(base, rest)`."""
    if head == "crate":
        return [], rest
    if head == "self":
        return list(module), rest
    base = list(module)
    while True:
        base = base[:-1]
        if rest and rest[0] == "super":
            rest = rest[1:]
            continue
        return base, rest


def definer(path, modules, codes, seen=None):
    """The module (file) that defines the item `path` names: the longest
    module prefix that is a file, then through its `pub use` of the last
    name, if it only re-exports it."""
    seen = seen or set()
    for k in range(len(path), -1, -1):
        target = tuple(path[:k])
        if target not in modules:
            continue
        if k == len(path) or k + 1 < len(path):
            return target
        name = path[k]
        code = codes[target]
        if re.search(DEF.format(re.escape(name)), code) or (target, name) in seen:
            return target
        seen.add((target, name))
        reexports = r"\bpub(?:\([^)]*\))?\s+use\s+([A-Za-z_][A-Za-z0-9_]*)((?:::[A-Za-z_][A-Za-z0-9_]*)*)\s*;"
        for m in re.finditer(reexports, expand_groups(code)):
            head = m.group(1)
            parts = [p for p in m.group(2).split("::") if p]
            if head not in ("crate", "super", "self"):
                # A path without `crate`/`super`/`self` starts at a child.
                parts = [head] + parts
                head = "self"
            if parts and parts[-1] == name:
                base, rest = resolve(target, head, parts)
                return definer(base + rest, modules, codes, seen)
        return target
    return None


def uses(module, code, modules, codes):
    """The modules (files) a file's code names."""
    found = set()
    code = expand_groups(code)
    # Paths from a child module without `self::` (`use child::X;`,
    # `child::f()`): a use of the child, except in a `pub use` re-export
    # (a parent that only re-exports its children does not use them).
    children = {m[-1] for m in modules if len(m) == len(module) + 1 and m[:-1] == module}
    if children:
        child_path = re.compile(
            r"(?<![:\w])(" + "|".join(map(re.escape, sorted(children))) + r")((?:::[A-Za-z_][A-Za-z0-9_]*)+)"
        )
        for line in code.split(";"):
            if re.search(r"\bpub(?:\([^)]*\))?\s+use\b", line) or re.match(r"\s*(pub(\([^)]*\))?\s+)?mod\s", line.strip() + " "):
                continue
            for m in child_path.finditer(line):
                parts = [m.group(1)] + [p for p in m.group(2).split("::") if p]
                target = definer(list(module) + parts, modules, codes)
                if target is not None and target != module:
                    found.add(target)
    for m in PATH.finditer(code):
        base, rest = resolve(module, m.group(1), [p for p in m.group(2).split("::") if p])
        target = definer(base + rest, modules, codes)
        if target is not None and target != module:
            found.add(target)
    return found


def check(src):
    modules = module_files(src)
    codes = {}
    for module, path in modules.items():
        with open(path, encoding="utf-8") as f:
            codes[module] = strip(f.read())
    # Inline `#[cfg(test)] mod tests { ... }` blocks count as their file.
    graph = {module: uses(module, code, modules, codes) for module, code in codes.items()}
    circles = []
    for a, targets in graph.items():
        for b in targets:
            if a < b and a in graph.get(b, set()):
                circles.append((modules[a], modules[b]))
    return circles


def main():
    roots = sys.argv[1:]
    if not roots:
        top = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
        roots = []
        for base in ["."] + [os.path.join(d, x) for d in ("crates", "bindings") for x in sorted(os.listdir(os.path.join(top, d)))]:
            src = os.path.join(top, base, "src")
            if os.path.isdir(src) and "other-bakers" not in base:
                roots.append(src)
    bad = []
    for src in roots:
        bad += check(src)
    for a, b in bad:
        print(f"import circle: {a} <-> {b}")
    print(f"{len(bad)} import circles in {len(roots)} crates")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
