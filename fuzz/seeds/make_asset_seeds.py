#!/usr/bin/env python3
"""Writes the hand-made seeds of the asset targets into fuzz/seeds/<target>/:

  alpha_image/     small PNGs (grey, grey+alpha, RGB, RGBA, 16-bit, palette
                   with tRNS, 1-bit, Adam7-interlaced) and JPEGs (grey, YCbCr)
  triangles_json/  small TRIS.json files
  gltf_asset/      small .gltf (data: buffers, an image URI the fuzz body
                   resolves to a fixed PNG) and .glb files

Run from anywhere: python3 fuzz/seeds/make_asset_seeds.py
The output is deterministic. The inputs follow
micromap_index_lab::fuzzing::{alpha_image, triangles_json, gltf_asset}: the
whole input is the file. crates/lab/src/assets/tests.rs also reads the
two JPEGs, which a small baseline encoder below writes (flat 8 x 8 blocks:
DC coefficients only, all quantizers 1).
"""
import base64
import json
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def write(target, name, data):
    folder = os.path.join(HERE, target)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, name), "wb") as f:
        f.write(bytes(data))


# ---------------------------------------------------------------- PNG

def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def png(width, height, color, depth, rows, plte=None, trns=None, interlaced=False):
    """rows: a list of `height` byte strings (packed samples, no filter byte).
    Interlaced: `rows` is a list of passes, each a list of packed rows."""
    ihdr = struct.pack(">IIBBBBB", width, height, depth, color, 0, 0, 1 if interlaced else 0)
    if interlaced:
        raw = b"".join(b"\x00" + row for rows_of_pass in rows for row in rows_of_pass)
    else:
        raw = b"".join(b"\x00" + row for row in rows)
    out = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr)
    if plte is not None:
        out += chunk(b"PLTE", plte)
    if trns is not None:
        out += chunk(b"tRNS", trns)
    return out + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")


# A 2 x 2 grey + alpha PNG: the image the gltf_asset body serves for every URI.
TINY_PNG = png(2, 2, 4, 8, [bytes([0, 0, 0, 85]), bytes([0, 170, 0, 255])])


def adam7(width, height, pixel):
    """The passes of an Adam7-interlaced image of `pixel(x, y)` bytes."""
    passes = []
    for x0, y0, dx, dy in [(0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4),
                           (0, 2, 2, 4), (1, 0, 2, 2), (0, 1, 1, 2)]:
        xs = range(x0, width, dx)
        ys = range(y0, height, dy)
        if len(xs) == 0 or len(ys) == 0:
            continue
        passes.append([b"".join(pixel(x, y) for x in xs) for y in ys])
    return passes


def png_seeds():
    write("alpha_image", "grey-2x2.png", png(2, 2, 0, 8, [b"\x00\x40", b"\x80\xff"]))
    write("alpha_image", "grey-alpha-2x2.png", TINY_PNG)
    write("alpha_image", "rgb-3x1.png", png(3, 1, 2, 8, [bytes([255, 0, 0, 0, 255, 0, 0, 0, 255])]))
    write("alpha_image", "rgba-3x2.png", png(3, 2, 6, 8, [bytes(range(12)), bytes(range(100, 112))]))
    write("alpha_image", "grey16-2x1.png", png(2, 1, 0, 16, [b"\x12\x34\xff\xff"]))
    write("alpha_image", "rgb16-trns-2x1.png",
          png(2, 1, 2, 16, [b"\x00\x01\x00\x02\x00\x03" + b"\xff\xff" * 3], trns=b"\x00\x01\x00\x02\x00\x03"))
    write("alpha_image", "palette-trns-4x1.png",
          png(4, 1, 3, 2, [bytes([0b00011011])], plte=bytes([0, 0, 0, 255, 0, 0, 0, 255, 0, 0, 0, 255]),
              trns=bytes([0, 128])))
    write("alpha_image", "grey1-8x2.png", png(8, 2, 0, 1, [b"\xa5", b"\x5a"]))
    write("alpha_image", "grey-alpha-adam7-5x5.png",
          png(5, 5, 4, 8, adam7(5, 5, lambda x, y: bytes([x * 50, y * 60])), interlaced=True))


# ---------------------------------------------------------------- JPEG

def huffman_codes(bits, values):
    """(code, length) of each value, from the BITS/HUFFVAL lists (JPEG Annex C)."""
    codes, code, k = {}, 0, 0
    for length in range(1, 17):
        for _ in range(bits[length - 1]):
            codes[values[k]] = (code, length)
            code += 1
            k += 1
        code <<= 1
    return codes


DC_BITS = [0, 1, 5, 1, 1, 1, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0]
DC_VALUES = list(range(12))
AC_BITS = [1] + [0] * 15   # one code, "0", for EOB (symbol 0x00)
AC_VALUES = [0]


class BitWriter:
    def __init__(self):
        self.out, self.acc, self.n = bytearray(), 0, 0

    def put(self, value, length):
        for i in range(length - 1, -1, -1):
            self.acc = (self.acc << 1) | ((value >> i) & 1)
            self.n += 1
            if self.n == 8:
                self.out.append(self.acc)
                if self.acc == 0xFF:
                    self.out.append(0)   # byte stuffing
                self.acc, self.n = 0, 0

    def flush(self):
        while self.n:
            self.put(1, 1)
        return bytes(self.out)


def segment(marker, payload):
    return bytes([0xFF, marker]) + struct.pack(">H", len(payload) + 2) + payload


def jpeg(width, height, blocks):
    """Baseline JPEG, one 8 x 8 block per component per MCU (no subsampling).
    blocks[row][col] = tuple of flat sample values, one per component."""
    components = len(blocks[0][0])
    dc = huffman_codes(DC_BITS, DC_VALUES)
    ac = huffman_codes(AC_BITS, AC_VALUES)
    out = b"\xff\xd8"
    out += segment(0xDB, b"\x00" + b"\x01" * 64)
    sof = struct.pack(">BHHB", 8, height, width, components)
    for c in range(components):
        sof += bytes([c + 1, 0x11, 0])
    out += segment(0xC0, sof)
    out += segment(0xC4, b"\x00" + bytes(DC_BITS) + bytes(DC_VALUES)
                   + b"\x10" + bytes(AC_BITS) + bytes(AC_VALUES))
    sos = bytes([components])
    for c in range(components):
        sos += bytes([c + 1, 0x00])
    out += segment(0xDA, sos + b"\x00\x3f\x00")
    writer, previous = BitWriter(), [0] * components
    for row in blocks:
        for block in row:
            for c, value in enumerate(block):
                coefficient = 8 * (value - 128)   # the DC of a flat block
                diff = coefficient - previous[c]
                previous[c] = coefficient
                size = abs(diff).bit_length()
                writer.put(*dc[size])
                if size:
                    writer.put(diff if diff > 0 else diff + (1 << size) - 1, size)
                writer.put(*ac[0])   # end of block
    return out + writer.flush() + b"\xff\xd9"


def jpeg_seeds():
    write("alpha_image", "grey-16x8.jpg", jpeg(16, 8, [[(64,), (200,)]]))
    write("alpha_image", "rgb-8x8.jpg", jpeg(8, 8, [[(100, 90, 160)]]))


# ---------------------------------------------------------------- TRIS.json

def triangles_seeds():
    write("triangles_json", "one.json", b'{"triangles": [[[0, 0], [1, 0], [0, 1]]]}')
    write("triangles_json", "two-extra-key.json",
          b'{"name": "grid", "triangles": [[[0.125, 0.25], [0.5, 0.25], [0.125, 1]], '
          b'[[-0.5, 1e-3], [1.5E+0, 2], [0.1, 0.30000001192092896]]]}')
    write("triangles_json", "edge-numbers.json",
          b'{"triangles": [[[1e39, -1e39], [1e-46, -0.0], [1.00000005960464477539062500001, 3.4028235e38]]]}')
    write("triangles_json", "empty.json", b'{"triangles": []}')
    write("triangles_json", "bad-vertex.json", b'{"triangles": [[[0, 0], [1, 0], [0, "1"]]]}')


# ---------------------------------------------------------------- glTF

def floats(values):
    return struct.pack("<%df" % len(values), *values)


def gltf_doc(bin_uri, extra_views=(), image=None, uv_accessor=None, sparse=False):
    uvs = floats([0, 0, 1, 0, 1, 1, 0, 1])
    indices = struct.pack("<6H", 0, 1, 2, 0, 2, 3) + b"\0\0"
    quantized = bytes([0, 0, 255, 0, 255, 255, 0, 255])
    sparse_indices = bytes([1, 3, 0, 0])
    sparse_values = floats([0.25, 0.5, 0.75, 1.0])
    data = uvs + indices + quantized + sparse_indices + sparse_values
    views = [
        {"buffer": 0, "byteOffset": 0, "byteLength": 32, "byteStride": 8},
        {"buffer": 0, "byteOffset": 32, "byteLength": 12},
        {"buffer": 0, "byteOffset": 44, "byteLength": 8},
        {"buffer": 0, "byteOffset": 52, "byteLength": 4},
        {"buffer": 0, "byteOffset": 56, "byteLength": 16},
    ]
    accessors = [
        {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC2"},
        {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"},
        {"bufferView": 2, "componentType": 5121, "normalized": True, "count": 4, "type": "VEC2"},
        {"componentType": 5126, "count": 4, "type": "VEC2",
         "sparse": {"count": 2, "indices": {"bufferView": 3, "componentType": 5121}, "values": {"bufferView": 4}}},
    ]
    doc = {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_mesh_quantization"],
        "buffers": [{"byteLength": len(data)}],
        "bufferViews": views,
        "accessors": accessors,
        "images": [image or {"uri": "a.png"}],
        "samplers": [{"magFilter": 9728, "minFilter": 9729, "wrapS": 33648, "wrapT": 33071}],
        "textures": [{"source": 0, "sampler": 0}, {"source": 0}],
        "materials": [
            {"alphaMode": "MASK", "alphaCutoff": 0.3,
             "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.5], "baseColorTexture": {"index": 0}}},
            {"alphaMode": "MASK", "pbrMetallicRoughness": {"baseColorTexture": {"index": 1, "texCoord": 1}}},
            {"alphaMode": "BLEND"},
        ],
        "meshes": [{"primitives": [
            {"attributes": {"TEXCOORD_0": 0}, "indices": 1, "material": 0},
            {"attributes": {"TEXCOORD_0": 0, "TEXCOORD_1": 2}, "material": 1, "mode": 4},
            {"attributes": {"TEXCOORD_0": 3}, "indices": 1, "material": 0},
            {"attributes": {"TEXCOORD_0": 0}, "material": 2},
            {"attributes": {"TEXCOORD_0": 0}, "material": 0, "mode": 1},
        ]}],
    }
    if bin_uri is not None:
        doc["buffers"][0]["uri"] = bin_uri(data)
    return doc, data


def glb(doc, data):
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    data = data + b"\0" * (-len(data) % 4)
    total = 12 + 8 + len(text) + 8 + len(data)
    return (b"glTF" + struct.pack("<II", 2, total) + struct.pack("<I", len(text)) + b"JSON" + text
            + struct.pack("<I", len(data)) + b"BIN\0" + data)


def gltf_seeds():
    data_uri = lambda data: "data:application/octet-stream;base64," + base64.b64encode(data).decode()
    doc, _ = gltf_doc(data_uri)
    write("gltf_asset", "quad.gltf", json.dumps(doc, indent=1).encode())
    doc, _ = gltf_doc(lambda data: "quad%20data.bin")
    write("gltf_asset", "external-buffer.gltf", json.dumps(doc).encode())
    doc, data = gltf_doc(None)
    # The image in the BIN chunk, after the geometry.
    image_offset = len(data) + (-len(data) % 4)
    data = data + b"\0" * (-len(data) % 4) + TINY_PNG
    doc["bufferViews"].append({"buffer": 0, "byteOffset": image_offset, "byteLength": len(TINY_PNG)})
    doc["images"] = [{"bufferView": 5, "mimeType": "image/png"}]
    doc["buffers"][0]["byteLength"] = len(data)
    write("gltf_asset", "quad.glb", glb(doc, data))
    # Materials as a renderer reads them: COLOR_0 alpha (normalized bytes,
    # and floats), KHR_texture_transform (exact scale and offset, texCoord
    # override), an RGB image without alpha in a data: URI.
    doc, data = gltf_doc(None)
    colours = bytes([255, 255, 255, 51, 255, 255, 255, 102, 255, 255, 255, 204, 255, 255, 255, 255])
    float_colours = floats([1, 1, 1, 0.25, 1, 1, 1, 0.5, 1, 1, 1, 0.75, 1, 1, 1, 1])
    offset = len(data)
    data = data + colours + float_colours
    doc["buffers"][0]["byteLength"] = len(data)
    doc["buffers"][0]["uri"] = data_uri(data)
    doc["bufferViews"] += [
        {"buffer": 0, "byteOffset": offset, "byteLength": 16},
        {"buffer": 0, "byteOffset": offset + 16, "byteLength": 64},
    ]
    doc["accessors"] += [
        {"bufferView": 5, "componentType": 5121, "normalized": True, "count": 4, "type": "VEC4"},
        {"bufferView": 6, "componentType": 5126, "count": 4, "type": "VEC4"},
    ]
    rgb = png(1, 1, 2, 8, [bytes([0, 0, 0])])
    doc["images"].append({"uri": "data:image/png;base64," + base64.b64encode(rgb).decode()})
    doc["textures"].append({"source": 1})
    doc["extensionsUsed"].append("KHR_texture_transform")
    doc["extensionsRequired"] = ["KHR_texture_transform"]
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
        "KHR_texture_transform": {"offset": [0.25, 0], "scale": [0.5, 0.5], "texCoord": 0}}
    doc["materials"].append({"alphaMode": "MASK", "pbrMetallicRoughness": {"baseColorTexture": {"index": 2}}})
    prims = doc["meshes"][0]["primitives"]
    prims[0]["attributes"]["COLOR_0"] = 4
    prims[1]["attributes"]["COLOR_0"] = 5
    # Not the sparse accessor (its views do not match the data's layout).
    del prims[2]
    prims.append({"attributes": {"TEXCOORD_0": 0}, "indices": 1, "material": 3})
    write("gltf_asset", "materials.gltf", json.dumps(doc, indent=1).encode())
    write("gltf_asset", "minimal.gltf",
          b'{"asset": {"version": "2.0"}, "meshes": [{"primitives": [{"attributes": {}}]}]}')


if __name__ == "__main__":
    png_seeds()
    jpeg_seeds()
    triangles_seeds()
    gltf_seeds()
