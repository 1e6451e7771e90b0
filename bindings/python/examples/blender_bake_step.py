"""The bake step of a Blender add-on, with numpy only.

A Blender operator would gather its inputs with ``foreach_get``::

    uv = np.empty(len(mesh.loops) * 2, np.float32)
    mesh.uv_layers.active.data.foreach_get("uv", uv)
    mesh.calc_loop_triangles()
    tris = np.empty(len(mesh.loop_triangles) * 3, np.int32)
    mesh.loop_triangles.foreach_get("loops", tris)
    pixels = np.empty(image.size[0] * image.size[1] * 4, np.float32)
    image.pixels.foreach_get(pixels)

and hand them to :func:`bake_step`. Blender stores pixel rows bottom-up and
its UV ``v`` points up; micromap_index reads row 0 at ``v = 0``, so
Blender's arrays go in as they are, with no flip.

Run as a script, it feeds the committed Crytek Sponza thorn texture's rows
as the image and ``grid.tris.json``'s UVs as the loop UVs (the numbers
``micromap-index bake --texture --triangles`` reads), bakes, verifies, and
writes the four buffer files and ``summary.json`` to ``--out``::

    python blender_bake_step.py --out /tmp/omm [--level 4]
"""

import argparse
import json
import os
import sys
import tempfile
from pathlib import Path

import numpy as np

import micromap_index as mmi

ASSETS = Path(__file__).resolve().parents[3] / "assets" / "crytek-sponza"


def bake_step(pixels, width, height, uv, loop_triangles, *, level="auto", cutoff=0.5):
    """Bakes one material's micromaps from Blender-layout arrays: ``pixels``
    flat RGBA float32 (``width * height * 4``), ``uv`` flat float32 per loop
    (``2 * loops``), ``loop_triangles`` flat loop indices (``3 * triangles``).
    Returns the bake and its verification."""
    alpha = pixels.reshape(height, width, 4)[:, :, 3]  # a strided view: read as it is
    uvs = uv.reshape(-1, 2)[loop_triangles.reshape(-1, 3)]  # (N, 3, 2) float32
    result = mmi.bake(alpha, uvs, level=level, cutoff=cutoff)
    report = mmi.verify(alpha, uvs, result, cutoff=cutoff)
    return result, report


def write_files(result, out):
    """Writes the buffers, each file whole or not at all (temporary file,
    then rename)."""
    out.mkdir(parents=True, exist_ok=True)
    for name, content in result.files().items():
        with tempfile.NamedTemporaryFile(dir=out, delete=False) as f:
            f.write(content)
        os.replace(f.name, out / name)


def demo_inputs():
    """The committed texture and triangles in Blender's layouts."""
    alpha = mmi.read_alpha(ASSETS / "sponza_thorn.png")
    height, width = alpha.shape
    pixels = np.ones((height, width, 4), np.float32)
    pixels[:, :, 3] = alpha / np.float32(255)
    triangles = mmi.read_triangles(ASSETS / "grid.tris.json")
    # One loop per triangle corner, as an unwelded UV layer.
    uv = triangles.reshape(-1)
    loop_triangles = np.arange(len(triangles) * 3, dtype=np.int32)
    return pixels.reshape(-1), width, height, uv, loop_triangles


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--level", default="auto")
    args = parser.parse_args(argv)
    level = args.level if args.level == "auto" else int(args.level)
    result, report = bake_step(*demo_inputs(), level=level)
    write_files(result, args.out)
    summary = {"stats": result.stats, "sound": report.sound,
               "contradictions": report.contradictions}
    (args.out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    print(f"{result.stats['triangles']} triangles, {len(result.triangles)} micromaps, "
          f"known fraction {result.stats['known_fraction']:.4f}, "
          f"{'sound' if report.sound else 'NOT SOUND'}")
    return 0 if report.sound else 1


if __name__ == "__main__":
    sys.exit(main())
