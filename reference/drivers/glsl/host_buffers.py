#!/usr/bin/env python3
"""Buffers for reference/drivers/glsl/spec_f32.comp, for any GPU API.

  host_buffers.py pack reference/vectors/spec-f32.json cases.bin
      writes binding 0 (one uvec4 (u_bits, v_bits, level, 0) per case,
      little-endian) and prints case_count: the host must declare a 4-byte
      VK_SHADER_STAGE_COMPUTE_BIT push-constant range and push this uint32,
      then dispatch ceil(case_count / 64) x 1 x 1 workgroups with binding 1
      a buffer of case_count uint32.
  host_buffers.py answers reference/vectors/spec-f32.json indices.bin > answers.jsonl
      turns binding 1, read back to a file, into answer lines for
      `micromap-index check`.
"""
import json
import struct
import sys


def cases(path):
    return json.load(open(path))["cases"]


def main(argv):
    if len(argv) != 4 or argv[1] not in ("pack", "answers"):
        sys.exit(__doc__)
    all_cases = cases(argv[2])
    if argv[1] == "pack":
        with open(argv[3], "wb") as out:
            for c in all_cases:
                out.write(struct.pack("<4I", int(c["u"], 16), int(c["v"], 16), c["level"], 0))
        print(len(all_cases))
    else:
        data = open(argv[3], "rb").read()
        if len(data) != 4 * len(all_cases):
            sys.exit(f"{argv[3]}: {len(data)} bytes, expected {4 * len(all_cases)}")
        indices = struct.unpack(f"<{len(all_cases)}I", data)
        for c, index in zip(all_cases, indices):
            print(json.dumps({"id": c["id"], "index": index}))


if __name__ == "__main__":
    main(sys.argv)
