#!/usr/bin/env python3
"""Plots of docs/results/render_levels.tsv (docs/render.md), written as PNG
with the standard library only (zlib): no plotting package needed.

  render_saved.png  per level: texture fetches saved against the alpha test
                    (solid) and candidates decided without the texture
                    (dotted), cards (green) and fern (orange); y 0..1.
  render_cost.png   per level: CPU time per frame over the alpha test's,
                    flat 4-state (green), level-order tree (blue), paper
                    tree (red); cards solid, fern dotted; y on a log2 scale
                    from 0.5 to 128, a line at 1 (as fast as the alpha
                    test).

Tick labels are digits drawn from a 3x5 font: levels along x, the y axis
in tenths (saved) or whole ratios (cost)."""
import struct
import sys
import zlib

W, H = 640, 400
LEFT, RIGHT, TOP, BOTTOM = 60, 20, 20, 40
FONT = {
    "0": ["111", "101", "101", "101", "111"], "1": ["010", "110", "010", "010", "111"],
    "2": ["111", "001", "111", "100", "111"], "3": ["111", "001", "111", "001", "111"],
    "4": ["101", "101", "111", "001", "001"], "5": ["111", "100", "111", "001", "111"],
    "6": ["111", "100", "111", "101", "111"], "7": ["111", "001", "010", "010", "010"],
    "8": ["111", "101", "111", "101", "111"], "9": ["111", "101", "111", "001", "111"],
    ".": ["000", "000", "000", "000", "010"],
}


class Canvas:
    def __init__(self):
        self.px = bytearray([255] * (W * H * 3))

    def dot(self, x, y, c):
        x, y = int(round(x)), int(round(y))
        if 0 <= x < W and 0 <= y < H:
            self.px[3 * (y * W + x):3 * (y * W + x) + 3] = bytes(c)

    def line(self, a, b, c, dotted=False, width=2):
        n = int(max(abs(b[0] - a[0]), abs(b[1] - a[1]))) + 1
        for i in range(n + 1):
            if dotted and (i // 4) % 2:
                continue
            x = a[0] + (b[0] - a[0]) * i / n
            y = a[1] + (b[1] - a[1]) * i / n
            for dx in range(width):
                for dy in range(width):
                    self.dot(x + dx, y + dy, c)

    def text(self, x, y, s, c=(0, 0, 0), scale=3):
        for k, ch in enumerate(s):
            for r, row in enumerate(FONT.get(ch, ["000"] * 5)):
                for q, bit in enumerate(row):
                    if bit == "1":
                        for i in range(scale):
                            for j in range(scale):
                                self.dot(x + (4 * k + q) * scale + i, y + r * scale + j, c)

    def png(self, path):
        raw = b"".join(b"\0" + bytes(self.px[3 * W * y:3 * W * (y + 1)]) for y in range(H))
        def chunk(tag, data):
            return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data))
        with open(path, "wb") as f:
            f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 8, 2, 0, 0, 0))
                    + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def axes(cv, levels, ymax, ystep, label):
    x0, x1, y0, y1 = LEFT, W - RIGHT, H - BOTTOM, TOP
    cv.line((x0, y0), (x1, y0), (0, 0, 0), width=1)
    cv.line((x0, y0), (x0, y1), (0, 0, 0), width=1)
    fx = lambda l: x0 + (l - levels[0]) * (x1 - x0 - 20) / max(1, levels[-1] - levels[0]) + 10
    fy = lambda v: y0 - min(v, ymax) * (y0 - y1) / ymax
    for l in levels:
        cv.line((fx(l), y0), (fx(l), y0 + 5), (0, 0, 0), width=1)
        cv.text(fx(l) - 5, y0 + 10, str(l))
    v = 0.0
    while v <= ymax + 1e-9:
        cv.line((x0 - 5, fy(v)), (x0, fy(v)), (0, 0, 0), width=1)
        cv.line((x0 + 1, fy(v)), (x1, fy(v)), (225, 225, 225), width=1)
        cv.text(4, fy(v) - 7, label(v))
        v += ystep
    return fx, fy


def series(cv, fx, fy, points, colour, dotted=False):
    points = sorted(points)
    for a, b in zip(points, points[1:]):
        cv.line((fx(a[0]), fy(a[1])), (fx(b[0]), fy(b[1])), colour, dotted)
    for l, v in points:
        for dx in range(-3, 4):
            for dy in range(-3, 4):
                cv.dot(fx(l) + dx, fy(v) + dy, colour)


def main(tsv):
    rows = [line.rstrip("\n").split("\t") for line in open(tsv) if not line.startswith("#")]
    head, rows = rows[0], rows[1:]
    rows = [dict(zip(head, r)) for r in rows]
    levels = sorted({int(r["level"]) for r in rows})
    get = lambda asset, method, key: [(int(r["level"]), float(r[key])) for r in rows
                                      if r["asset"] == asset and r["method"] == method]
    assets = [("cards", (60, 150, 60)), ("fern_02", (230, 140, 30))]

    cv = Canvas()
    fx, fy = axes(cv, levels, 1.0, 0.1, lambda v: "%.1f" % v)
    for asset, colour in assets:
        series(cv, fx, fy, get(asset, "flat-4-state", "fetches_saved"), colour)
        series(cv, fx, fy, get(asset, "flat-4-state", "decided_without_texture"), colour, True)
    cv.png(tsv.replace("render_levels.tsv", "render_saved.png"))

    alpha = {(r["asset"], int(r["level"])): float(r["cpu_ms_per_frame"]) for r in rows
             if r["method"] == "alpha-test"}
    ratios = {}
    for r in rows:
        base = alpha[(r["asset"], int(r["level"]))]
        ratios.setdefault((r["asset"], r["method"]), []).append(
            (int(r["level"]), float(r["cpu_ms_per_frame"]) / base if base > 0 else 0.0))
    # log2 scale: tick k is a ratio of 2^(k - 1), 0.5 at the bottom.
    import math
    log = lambda points: [(l, max(0.0, math.log2(max(v, 1e-9)) + 1)) for l, v in points]
    cv = Canvas()
    fx, fy = axes(cv, levels, 8.0, 1.0, lambda v: "%g" % 2 ** (v - 1) if v >= 1 else ".5")
    cv.line((fx(levels[0]), fy(1.0)), (fx(levels[-1]), fy(1.0)), (0, 0, 0), width=1)
    for method, colour in [("flat-4-state", (60, 150, 60)), ("level-order-tree", (40, 90, 220)),
                           ("paper-tree", (220, 40, 40))]:
        for asset, dotted in [("cards", False), ("fern_02", True)]:
            series(cv, fx, fy, log(ratios.get((asset, method), [])), colour, dotted)
    cv.png(tsv.replace("render_levels.tsv", "render_cost.png"))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "docs/results/render_levels.tsv")
