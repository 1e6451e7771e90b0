#!/usr/bin/env python3
"""Writes bake_grid.c's raw inputs from a PNG and a TRIS.json (C has no PNG
decoder): the converter that ships with the example, standard library only.

    python3 bindings/c/examples/make_inputs.py TEXTURE.png TRIS.json OUTDIR

writes OUTDIR/texture.raw and OUTDIR/uvs.bin (native endian, the layout
bake_grid.c reads):

    texture.raw  uint32 width, height, format (0: MMI_TEXEL_UNORM8,
                 1: MMI_TEXEL_UNORM16), row pitch in bytes; then the rows
    uvs.bin      uint32 vertex count, floats per vertex (2); then (u, v) per
                 vertex, vertices 3t..3t+2 being triangle t

The texels are the PNG's alpha channel, or its grey value when it has no
alpha (what `micromap-index bake --texture` reads); 8- and 16-bit grey,
grey + alpha and RGBA PNGs, not interlaced, are read, anything else refused
(exit 2). Each TRIS.json coordinate is rounded once from its decimal text to
binary32, as the CLI reads it, so bake_grid's output equals
`micromap-index bake --texture TEXTURE.png --triangles TRIS.json` byte for
byte (bindings/c/tests/c_api.rs checks it on the committed assets).
"""
import json
import math
import os
import struct
import sys
import zlib
from fractions import Fraction

# PNG colour types read: grey, grey + alpha, RGBA (channels, alpha channel or None).
COLOUR_TYPES = {0: (1, None), 4: (2, 1), 6: (4, 3)}


def fail(message):
    print(f"make_inputs.py: {message}", file=sys.stderr)
    sys.exit(2)


def paeth(a, b, c):
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    if pa <= pb and pa <= pc:
        return a
    return b if pb <= pc else c


def decode_png(data):
    """(width, height, bytes per sample, one sample per texel, big endian)."""
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        fail("not a PNG")
    at, idat, header = 8, b"", None
    while at + 8 <= len(data):
        length, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + length]
        at += 12 + length
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        elif kind == b"IEND":
            break
    if header is None:
        fail("no IHDR chunk")
    width, height, depth, colour, _, _, interlace = header
    if colour not in COLOUR_TYPES or depth not in (8, 16) or interlace != 0:
        fail(f"colour type {colour}, depth {depth}, interlace {interlace}: "
             "only 8- or 16-bit grey, grey + alpha or RGBA, not interlaced")
    channels, alpha = COLOUR_TYPES[colour]
    sample = depth // 8
    pixel = channels * sample
    stride = width * pixel
    raw = zlib.decompress(idat)
    if len(raw) != height * (stride + 1):
        fail("image data of the wrong length")
    rows, previous = [], bytearray(stride)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        row = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = row[i - pixel] if i >= pixel else 0
            b = previous[i]
            c = previous[i - pixel] if i >= pixel else 0
            if kind == 1:
                row[i] = (row[i] + a) & 0xFF
            elif kind == 2:
                row[i] = (row[i] + b) & 0xFF
            elif kind == 3:
                row[i] = (row[i] + (a + b) // 2) & 0xFF
            elif kind == 4:
                row[i] = (row[i] + paeth(a, b, c)) & 0xFF
            elif kind != 0:
                fail(f"row {y}: filter type {kind}")
        rows.append(row)
        previous = row
    channel = alpha if alpha is not None else 0
    texels = bytearray()
    for row in rows:
        for x in range(width):
            at = x * pixel + channel * sample
            texels += row[at:at + sample]
    return width, height, sample, bytes(texels)


def binary32(text):
    """The binary32 nearest the JSON number `text` (ties to even), as its 4
    native-endian bytes: one rounding from the decimal text, the sign kept
    (`-0` and negative underflow give -0.0, as Rust's parser does)."""
    negative = text.strip().startswith("-")
    value = abs(Fraction(text.strip()))
    sign = -1.0 if negative else 1.0
    if value == 0:
        return struct.pack("=f", math.copysign(0.0, sign))
    exponent = value.numerator.bit_length() - value.denominator.bit_length()
    if Fraction(2) ** exponent > value:
        exponent -= 1
    # 24 significant bits, or fewer below the normal range (2^-126).
    exponent = max(exponent, -126)
    scaled = value / Fraction(2) ** (exponent - 23)
    whole, rest = divmod(scaled.numerator, scaled.denominator)
    rest = Fraction(rest, scaled.denominator)
    if rest > Fraction(1, 2) or (rest == Fraction(1, 2) and whole % 2 == 1):
        whole += 1
    result = whole * Fraction(2) ** (exponent - 23)
    if result >= Fraction(2) ** 128:
        return struct.pack("=f", sign * math.inf)
    # Exactly representable now: float() and the packing are exact.
    return struct.pack("=f", math.copysign(float(result), sign))


def main():
    if len(sys.argv) != 4:
        fail("usage: make_inputs.py TEXTURE.png TRIS.json OUTDIR")
    png, tris, out = sys.argv[1:]
    with open(png, "rb") as f:
        width, height, sample, texels = decode_png(f.read())
    # PNG samples are big endian; the C side reads native uint16.
    if sample == 2:
        words = struct.unpack(f">{len(texels) // 2}H", texels)
        texels = struct.pack(f"={len(words)}H", *words)
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "texture.raw"), "wb") as f:
        f.write(struct.pack("=IIII", width, height, sample - 1, width * sample))
        f.write(texels)
    with open(tris, encoding="utf-8") as f:
        triangles = json.load(f, parse_float=str, parse_int=str)["triangles"]
    with open(os.path.join(out, "uvs.bin"), "wb") as f:
        f.write(struct.pack("=II", 3 * len(triangles), 2))
        for triangle in triangles:
            if len(triangle) != 3 or any(len(corner) != 2 for corner in triangle):
                fail("a triangle is not three (u, v) pairs")
            for corner in triangle:
                for coordinate in corner:
                    if not isinstance(coordinate, str):
                        fail("a coordinate is not a number")
                    f.write(binary32(coordinate))


if __name__ == "__main__":
    main()
