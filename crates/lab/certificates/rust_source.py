"""The structural source check shared by lemmas.py and product.py
(issue 36: the checkers read structure, not substrings).

Each modelled item (a `fn`, or a `mod` such as `uv2index::digit`) is read
from the Rust source as a token stream (comments dropped, so braces inside
comments and string/char literals do not count), its body found by brace
matching, and split into logical lines: the tokens of one source line,
joined with the next while a `(` or `[` is open (a wrapped argument list
is one line). The result must equal the modelled lines exactly, in order:
an inserted, deleted, duplicated, reordered or changed line is refused.
Comments, blank lines and whitespace between tokens are free.

A model is a dict from "fn NAME" (or "mod NAME") to its lines: first the
item's header (the tokens from the start of its line to the body's `{`),
then the body's lines. lemmas_mutants.py and product_mutants.py check that
mutants of the modelled code are refused.
"""
import difflib
import sys
import re

PUNCTUATION = sorted(
    "<<= >>= ... ..= :: -> => == != <= >= && || += -= *= /= %= ^= &= |= << >> ..".split(),
    key=len,
    reverse=True,
)
CHAR = re.compile(r"'(?:\\(?:x[0-9a-fA-F]{2}|u\{[0-9a-fA-F_]{1,8}\}|[^\n])|[^\\'\n])'")
RAW_STRING = re.compile(r'(?:b|c)?r(#*)"')
IDENT = re.compile(r"(?:r#)?[^\W\d]\w*")
NUMBER = re.compile(r"\d\w*(?:\.\d\w*)?")


class SourceError(Exception):
    pass


def tokenize(text):
    """Rust tokens as (text, line): comments (nested block ones included)
    and whitespace dropped; string, char and number literals one token
    each, verbatim; lifetimes one token."""
    tokens, i, line, n = [], 0, 1, len(text)
    while i < n:
        c = text[i]
        start, start_line = i, line
        if c == "\n":
            line += 1
            i += 1
            continue
        if c.isspace():
            i += 1
            continue
        if text.startswith("//", i):
            end = text.find("\n", i)
            i = n if end < 0 else end
            continue
        if text.startswith("/*", i):
            depth, i = 1, i + 2
            while depth:
                if i >= n:
                    raise SourceError(f"line {start_line}: unterminated block comment")
                if text.startswith("/*", i):
                    depth, i = depth + 1, i + 2
                elif text.startswith("*/", i):
                    depth, i = depth - 1, i + 2
                else:
                    line += text[i] == "\n"
                    i += 1
            continue
        raw = RAW_STRING.match(text, i)
        if raw:
            close = '"' + raw.group(1)
            end = text.find(close, raw.end())
            if end < 0:
                raise SourceError(f"line {start_line}: unterminated raw string")
            i = end + len(close)
        elif c == '"' or (c in "bc" and text.startswith('"', i + 1)):
            i = text.index('"', i) + 1
            while i < n and text[i] != '"':
                i += 2 if text[i] == "\\" else 1
            if i >= n:
                raise SourceError(f"line {start_line}: unterminated string")
            i += 1
        elif c == "'" or (c == "b" and text.startswith("'", i + 1)):
            char = CHAR.match(text, i + (c == "b"))
            if char:
                i = char.end()
            else:  # a lifetime or label
                ident = IDENT.match(text, i + 1)
                i = ident.end() if ident else i + 1
        elif IDENT.match(text, i):
            i = IDENT.match(text, i).end()
        elif c.isdigit():
            i = NUMBER.match(text, i).end()
        else:
            i += next((len(p) for p in PUNCTUATION if text.startswith(p, i)), 1)
        tokens.append((text[start:i], start_line))
        line += text.count("\n", start, i)
    return tokens


def canonical(tokens):
    return " ".join(t for t, _ in tokens)


def logical_lines(tokens):
    """Group tokens by the source line they start on, joining a line with
    the next while a `(` or `[` is open. Returns [(first line, last line,
    tokens)]."""
    groups, depth, end = [], 0, 0
    for token in tokens:
        if groups and (depth > 0 or token[1] == end):
            groups[-1][2].append(token)
        else:
            groups.append([token[1], token[1], [token]])
        end = token[1] + token[0].count("\n")
        groups[-1][1] = end
        if token[0] in ("(", "["):
            depth += 1
        elif token[0] in (")", "]"):
            depth -= 1
    return groups


def item_lines(tokens, item):
    """The modelled form of `item` ("fn NAME" or "mod NAME"): its header
    (the tokens from the start of the keyword's line to the body's `{`) as
    one line, then its body's logical lines. Returns [(first line, last
    line, canonical text)]."""
    keyword, name = item.split()
    where = [i for i in range(len(tokens) - 1) if tokens[i][0] == keyword and tokens[i + 1][0] == name]
    if len(where) != 1:
        raise SourceError(f"`{item}` occurs {len(where)} times, not once")
    at = where[0]
    first = at
    while first > 0 and tokens[first - 1][1] == tokens[at][1]:
        first -= 1
    # The body's `{`: the first one outside parentheses and brackets; a `;`
    # there first means a declaration without a body.
    open_, nesting = None, 0
    for i in range(at, len(tokens)):
        t = tokens[i][0]
        nesting += (t in ("(", "[")) - (t in (")", "]"))
        if nesting == 0 and t in ("{", ";"):
            open_ = i if t == "{" else None
            break
    if open_ is None:
        raise SourceError(f"`{item}` (line {tokens[at][1]}) has no body")
    depth = 0
    for close in range(open_, len(tokens)):
        depth += {"{": 1, "}": -1}.get(tokens[close][0], 0)
        if depth == 0:
            break
    else:
        raise SourceError(f"`{item}` (line {tokens[at][1]}): its `{{` is never closed")
    lines = [(tokens[first][1], tokens[open_][1], canonical(tokens[first : open_ + 1]))]
    lines += [(a, b, canonical(group)) for a, b, group in logical_lines(tokens[open_ + 1 : close])]
    return lines


def check_structure(source, path, modelled, checker):
    """Compare each modelled item (dict "fn NAME" -> its lines) with the
    source; returns the error messages (empty: every item is exactly the
    model). `checker` names the script whose model to update."""
    raw = source.splitlines()
    try:
        tokens = tokenize(source)
    except SourceError as e:
        return [f"{path}: {e}"]
    errors = []
    for item, model in modelled.items():
        try:
            found = item_lines(tokens, item)
            expected = [canonical(tokenize(line)) for line in model]
        except SourceError as e:
            errors.append(f"{path}: {e}")
            continue
        got = [text for _, _, text in found]
        if got == expected:
            continue

        def show(g, mark):
            a, b, _ = found[g]
            text = " ".join(line.strip() for line in raw[a - 1 : b])
            return f"  {mark} line {a:>4}  {text}"

        report = [
            f"{path}:{found[0][0]}: `{item}` is not the modelled code "
            f"(- expected by {checker}, + found; update the model in {checker}):"
        ]
        shown = set()
        for tag, e0, e1, g0, g1 in difflib.SequenceMatcher(None, expected, got, autojunk=False).get_opcodes():
            if tag == "equal":
                continue
            if g0 > 0 and g0 - 1 not in shown:
                report.append(show(g0 - 1, " "))
            report += [f"  - expected   {model[e]}" for e in range(e0, e1)]
            report += [show(g, "+") for g in range(g0, g1)]
            shown.update(range(g0 - 1, g1 + 1))
            if g1 < len(got):
                report.append(show(g1, " "))
        errors.append("\n".join(report))
    return errors


def refuse_unless_modelled(source, path, modelled, checker):
    """`check_structure`, then: any error is printed to stderr under
    `source check: REFUSED` and exits 1 (the checkers' one way to refuse)."""
    errors = check_structure(source, path, modelled, checker)
    if errors:
        print("source check: REFUSED", file=sys.stderr)
        for error in errors:
            print(error, file=sys.stderr)
        sys.exit(1)
