#!/usr/bin/env python3
"""Plots of a render table (render_table.py's TSV; docs/render.md), written
as PNG with the standard library only (zlib): no plotting package needed.

  render_plot.py TABLE.tsv [--time cpu|wall|device] [--tracer T] [--out PREFIX]

  PREFIXsaved.png  per level: texture fetches saved against the alpha test
                   (solid) and candidates decided without the texture
                   (dotted) by the flat 4-state micromap, one colour per
                   asset; y from 0 to 100%.
  PREFIXcost.png   per level: time per frame over the alpha test's (log2
                   scale, 0.5x to 512x; a black line at 1x), one colour
                   per method, solid for the first asset and dotted for the
                   second.

Defaults: the time clock is device where the table has it, else cpu; the
tracer is the table's first; PREFIX is the table's path up to its last
"_levels.tsv" or ".tsv" plus "_" (docs/results/render_levels.tsv gives
docs/results/render_saved.png). Every plot has a title naming the device,
axis titles with units and a legend. Text is drawn with a 5x7 font in
capitals; coordinates are rounded half up (Python's round() would send
x.5 to the even neighbour and stripe every other tick).
"""
import math
import struct
import sys
import zlib

W, H = 980, 540
LEFT, RIGHT, TOP, BOTTOM = 96, 300, 74, 70
GLYPHS = {
    "A": ".###.|#...#|#...#|#####|#...#|#...#|#...#", "B": "####.|#...#|#...#|####.|#...#|#...#|####.",
    "C": ".###.|#...#|#....|#....|#....|#...#|.###.", "D": "####.|#...#|#...#|#...#|#...#|#...#|####.",
    "E": "#####|#....|#....|####.|#....|#....|#####", "F": "#####|#....|#....|####.|#....|#....|#....",
    "G": ".###.|#...#|#....|#.###|#...#|#...#|.####", "H": "#...#|#...#|#...#|#####|#...#|#...#|#...#",
    "I": ".###.|..#..|..#..|..#..|..#..|..#..|.###.", "J": "..###|...#.|...#.|...#.|...#.|#..#.|.##..",
    "K": "#...#|#..#.|#.#..|##...|#.#..|#..#.|#...#", "L": "#....|#....|#....|#....|#....|#....|#####",
    "M": "#...#|##.##|#.#.#|#.#.#|#...#|#...#|#...#", "N": "#...#|#...#|##..#|#.#.#|#..##|#...#|#...#",
    "O": ".###.|#...#|#...#|#...#|#...#|#...#|.###.", "P": "####.|#...#|#...#|####.|#....|#....|#....",
    "Q": ".###.|#...#|#...#|#...#|#.#.#|#..#.|.##.#", "R": "####.|#...#|#...#|####.|#.#..|#..#.|#...#",
    "S": ".####|#....|#....|.###.|....#|....#|####.", "T": "#####|..#..|..#..|..#..|..#..|..#..|..#..",
    "U": "#...#|#...#|#...#|#...#|#...#|#...#|.###.", "V": "#...#|#...#|#...#|#...#|#...#|.#.#.|..#..",
    "W": "#...#|#...#|#...#|#.#.#|#.#.#|#.#.#|.#.#.", "X": "#...#|#...#|.#.#.|..#..|.#.#.|#...#|#...#",
    "Y": "#...#|#...#|.#.#.|..#..|..#..|..#..|..#..", "Z": "#####|....#|...#.|..#..|.#...|#....|#####",
    "0": ".###.|#...#|#..##|#.#.#|##..#|#...#|.###.", "1": "..#..|.##..|..#..|..#..|..#..|..#..|.###.",
    "2": ".###.|#...#|....#|...#.|..#..|.#...|#####", "3": "####.|....#|....#|.###.|....#|....#|####.",
    "4": "...#.|..##.|.#.#.|#..#.|#####|...#.|...#.", "5": "#####|#....|####.|....#|....#|#...#|.###.",
    "6": "..##.|.#...|#....|####.|#...#|#...#|.###.", "7": "#####|....#|...#.|..#..|.#...|.#...|.#...",
    "8": ".###.|#...#|#...#|.###.|#...#|#...#|.###.", "9": ".###.|#...#|#...#|.####|....#|...#.|.##..",
    ".": ".....|.....|.....|.....|.....|.##..|.##..", ",": ".....|.....|.....|.....|.##..|..#..|.#...",
    ":": ".....|.##..|.##..|.....|.##..|.##..|.....", "/": "....#|....#|...#.|..#..|.#...|#....|#....",
    "(": "...#.|..#..|.#...|.#...|.#...|..#..|...#.", ")": ".#...|..#..|...#.|...#.|...#.|..#..|.#...",
    "%": "##..#|##..#|...#.|..#..|.#...|#..##|#..##", "-": ".....|.....|.....|#####|.....|.....|.....",
    "+": ".....|..#..|..#..|#####|..#..|..#..|.....", "'": "..#..|..#..|.#...|.....|.....|.....|.....",
    "=": ".....|.....|#####|.....|#####|.....|.....", "_": ".....|.....|.....|.....|.....|.....|#####",
    " ": ".....|.....|.....|.....|.....|.....|.....", "~": ".....|.....|.#..#|#.##.|.....|.....|.....",
    "[": ".###.|.#...|.#...|.#...|.#...|.#...|.###.", "]": ".###.|...#.|...#.|...#.|...#.|...#.|.###.",
}
BLACK, GREY, LIGHT = (0, 0, 0), (110, 110, 110), (228, 228, 228)
ASSET_COLOURS = [(40, 140, 60), (230, 130, 20), (90, 60, 170)]
METHOD_COLOURS = {"flat-4-state": (40, 140, 60), "flat-2-state": (150, 150, 40),
                  "level-order-tree": (40, 90, 220), "paper-tree": (220, 40, 40),
                  "hardware": (140, 40, 160), "hardware-2-state": (60, 170, 170)}


def half_up(x):
    """Nearest integer, halves up (never to even)."""
    return int(math.floor(x + 0.5))


class Canvas:
    def __init__(self):
        self.px = bytearray([255] * (W * H * 3))

    def dot(self, x, y, c):
        x, y = half_up(x), half_up(y)
        if 0 <= x < W and 0 <= y < H:
            self.px[3 * (y * W + x):3 * (y * W + x) + 3] = bytes(c)

    def line(self, a, b, c, dotted=False, width=2):
        n = int(max(abs(b[0] - a[0]), abs(b[1] - a[1]))) + 1
        for i in range(n + 1):
            if dotted and (i // 5) % 2:
                continue
            x = a[0] + (b[0] - a[0]) * i / n
            y = a[1] + (b[1] - a[1]) * i / n
            for dx in range(width):
                for dy in range(width):
                    self.dot(x + dx, y + dy, c)

    def text(self, x, y, s, c=BLACK, scale=2, vertical=False):
        """`s` in capitals from (x, y), its top left (rotated a quarter turn
        counter-clockwise when vertical: reading upwards)."""
        for k, ch in enumerate(s.upper()):
            rows = GLYPHS.get(ch, GLYPHS[" "]).split("|")
            for r, row in enumerate(rows):
                for q, bit in enumerate(row):
                    if bit != "#":
                        continue
                    for i in range(scale):
                        for j in range(scale):
                            u, v = (6 * k + q) * scale + i, r * scale + j
                            if vertical:
                                self.dot(x + v, y - u, c)
                            else:
                                self.dot(x + u, y + v, c)

    @staticmethod
    def width(s, scale=2):
        return 6 * len(s) * scale

    def png(self, path):
        raw = b"".join(b"\0" + bytes(self.px[3 * W * y:3 * W * (y + 1)]) for y in range(H))

        def chunk(tag, data):
            return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data))
        with open(path, "wb") as f:
            f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 8, 2, 0, 0, 0))
                    + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def axes(cv, levels, ticks, title, subtitle, x_title, y_title):
    """The frame, ticks and titles; returns the maps level -> x, value -> y
    (values in tick units: ticks is [(value, label)])."""
    x0, x1, y0, y1 = LEFT, W - RIGHT, H - BOTTOM, TOP
    lo, hi = ticks[0][0], ticks[-1][0]
    fx = lambda l: x0 + 14 + (l - levels[0]) * (x1 - x0 - 28) / max(1, levels[-1] - levels[0])
    fy = lambda v: y0 - (min(max(v, lo), hi) - lo) * (y0 - y1) / (hi - lo)
    for v, label in ticks:
        cv.line((x0 + 1, fy(v)), (x1, fy(v)), LIGHT, width=1)
        cv.line((x0 - 6, fy(v)), (x0, fy(v)), BLACK, width=1)
        cv.text(x0 - 10 - cv.width(label), half_up(fy(v)) - 7, label)
    for l in levels:
        cv.line((fx(l), y0), (fx(l), y0 + 6), BLACK, width=1)
        cv.text(half_up(fx(l)) - cv.width(str(l)) // 2, y0 + 12, str(l))
    cv.line((x0, y0), (x1, y0), BLACK, width=1)
    cv.line((x0, y0), (x0, y1), BLACK, width=1)
    cv.text(12, 10, title, scale=2)
    # The subtitle on as many lines as it needs, broken after commas.
    line, y = "", 34
    for part in subtitle.split(", "):
        candidate = part if not line else line + ", " + part
        if line and cv.width(candidate, 1) > W - 24:
            cv.text(12, y, line + ",", GREY, scale=1)
            line, y = part, y + 12
        else:
            line = candidate
    cv.text(12, y, line, GREY, scale=1)
    cv.text((x0 + x1) // 2 - cv.width(x_title) // 2, H - 28, x_title)
    cv.text(12, (y0 + y1) // 2 + cv.width(y_title) // 2, y_title, vertical=True)
    return fx, fy


def series(cv, fx, fy, points, colour, dotted=False):
    points = sorted(points)
    for a, b in zip(points, points[1:]):
        cv.line((fx(a[0]), fy(a[1])), (fx(b[0]), fy(b[1])), colour, dotted)
    for l, v in points:
        for dx in range(-3, 4):
            for dy in range(-3, 4):
                cv.dot(fx(l) + dx, fy(v) + dy, colour)


def legend(cv, entries):
    """[(label, colour, dotted)] at the right."""
    x, y = W - RIGHT + 20, TOP + 4
    for label, colour, dotted in entries:
        cv.line((x, y + 6), (x + 34, y + 6), colour, dotted)
        cv.text(x + 42, y, label)
        y += 24


def read(path):
    comments, rows = [], []
    head = None
    for line in open(path):
        line = line.rstrip("\n")
        if line.startswith("#"):
            comments.append(line[1:].strip())
        elif head is None:
            head = line.split("\t")
        else:
            rows.append(dict(zip(head, line.split("\t"))))
    return comments, [r for r in rows if r.get("status") in ("ok", "failed")]


def main(argv):
    if not argv or argv[0].startswith("-"):
        sys.exit(__doc__)
    path = argv[0]
    opt = lambda name: argv[argv.index(name) + 1] if name in argv else None
    comments, rows = read(path)
    clock = (opt("--time") or ("device" if any(r.get("device_ms") for r in rows) else "cpu")) + "_ms"
    tracer = opt("--tracer") or rows[0]["tracer"]
    rows = [r for r in rows if r["tracer"] == tracer]
    prefix = opt("--out") or (path[:-len("levels.tsv")] if path.endswith("_levels.tsv") else path[:-4] + "_")
    device = next((c[len("device: "):] for c in comments if c.startswith("device: ")), "?")
    size = next((c[len("size: "):] for c in comments if c.startswith("size: ")), "?")
    subtitle = "%s, %s rays, %s tracer" % (device, size, tracer)
    levels = sorted({int(r["level"]) for r in rows})
    assets = sorted({r["asset"] for r in rows}, key=lambda a: (a != "cards", a))
    get = lambda asset, method, key: [(int(r["level"]), float(r[key])) for r in rows
                                      if r["asset"] == asset and r["method"] == method and r[key]]

    cv = Canvas()
    fx, fy = axes(cv, levels, [(v / 10, "%d%%" % (10 * v)) for v in range(0, 11)],
                  "Texture fetches saved by the flat 4-state micromap", subtitle,
                  "subdivision level", "fetches saved (% of the alpha test's)")
    entries = []
    for asset, colour in zip(assets, ASSET_COLOURS):
        series(cv, fx, fy, get(asset, "flat-4-state", "fetches_saved"), colour)
        series(cv, fx, fy, get(asset, "flat-4-state", "decided_without_texture"), colour, True)
        entries += [("%s saved" % asset, colour, False), ("%s no texture" % asset, colour, True)]
    legend(cv, entries)
    cv.png(prefix + "saved.png")

    base = {(r["asset"], int(r["level"])): float(r[clock]) for r in rows
            if r["method"] == "alpha-test" and r[clock]}
    cv = Canvas()
    # log2 scale: tick value k is a ratio of 2^k.
    fx, fy = axes(cv, levels, [(k, "%gx" % 2 ** k) for k in range(-1, 10)],
                  "Time per frame over the alpha test's", subtitle + ", " + {"cpu_ms": "process CPU time", "wall_ms": "wall time",
                                 "device_ms": "device timestamps"}[clock],
                  "subdivision level", "time / alpha test's (log2 scale)")
    cv.line((fx(levels[0]), fy(0)), (fx(levels[-1]), fy(0)), BLACK, width=1)
    entries = []
    methods = [m for m in METHOD_COLOURS if any(r["method"] == m for r in rows)]
    for method in methods:
        for asset, dotted in zip(assets, [False, True, True]):
            points = [(l, math.log2(max(v / base[(asset, l)], 1e-9)))
                      for l, v in get(asset, method, clock) if base.get((asset, l), 0) > 0]
            series(cv, fx, fy, points, METHOD_COLOURS[method], dotted)
        entries.append((method, METHOD_COLOURS[method], False))
    entries += [(assets[0] + ": solid", GREY, False)]
    if len(assets) > 1:
        entries.append((", ".join(assets[1:]) + ": dotted", GREY, True))
    legend(cv, entries)
    cv.png(prefix + "cost.png")


if __name__ == "__main__":
    main(sys.argv[1:])
