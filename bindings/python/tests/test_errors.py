"""Bad input raises TypeError or ValueError (OSError for files) with the
library's message; it never crashes the interpreter."""

import numpy as np
import pytest

import micromap_index as mmi
from conftest import GRID, SPONZA, THORN

CARDS = SPONZA / "cards.gltf"

F32 = np.zeros(4, np.float32)
ALPHA = np.full((8, 8), 255, np.uint8)
UVS = np.array([[[0, 0], [1, 0], [0, 1]]], np.float32)


@pytest.mark.parametrize(
    "call, error, message",
    [
        (lambda: mmi.index(F32.astype(np.float64), F32, 3), TypeError, "float32"),
        (lambda: mmi.index(F32.astype(">f4"), F32, 3), TypeError, "float32"),
        (lambda: mmi.index(F32, F32.astype(np.float16), 3), TypeError, "float32"),
        (lambda: mmi.index(F32, F32[:3], 3), ValueError, "same shape"),
        (lambda: mmi.index(F32, 0.5, 3), TypeError, "both"),
        (lambda: mmi.index("a", 0.5, 3), TypeError, "number"),
        (lambda: mmi.index(0.5, 0.5, 17), ValueError, "0..=16"),
        (lambda: mmi.index(0.5, 0.5, -1), ValueError, "0..=16"),
        (lambda: mmi.wide_index(0.5, 0.5, 33), ValueError, "0..=32"),
        (lambda: mmi.bake(ALPHA.astype(np.int32), UVS), TypeError, "uint8, uint16 or float32"),
        (lambda: mmi.bake(ALPHA.astype(np.float64), UVS), TypeError, "float64"),
        (lambda: mmi.bake([[1, 2]], UVS), TypeError, "numpy array"),
        (lambda: mmi.bake(ALPHA[0], UVS), ValueError, "2-D"),
        (lambda: mmi.bake(ALPHA[None], UVS), ValueError, "2-D"),
        (lambda: mmi.bake(ALPHA[:0], UVS), ValueError, "no texels"),
        (lambda: mmi.bake(ALPHA, UVS.astype(np.float64)), TypeError, "float32"),
        (lambda: mmi.bake(ALPHA, UVS[0]), ValueError, "(N, 3, 2)"),
        (lambda: mmi.bake(ALPHA, UVS.reshape(1, 2, 3)), ValueError, "(N, 3, 2)"),
        (lambda: mmi.bake(ALPHA, UVS, level=17), ValueError, "0..=12"),
        (lambda: mmi.bake(ALPHA, UVS, subtexel_bits=3), ValueError, "sub-texel bits 3: expected 4..=16"),
        (lambda: mmi.bake(ALPHA, UVS, subtexel_bits=-1), ValueError, "subtexel_bits -1"),
        (lambda: mmi.bake(ALPHA, UVS, interpolation="f8"), ValueError, "interpolation \"f8\""),
        (lambda: mmi.bake(ALPHA, UVS, filter_error=2.0), ValueError, "filter error 2"),
        (lambda: mmi.bake(ALPHA, UVS, linear="bilinear"), ValueError, "linear \"bilinear\""),
        (lambda: mmi.verify(ALPHA, UVS, data=b"", triangles=b"", indices=b"",
                            filter_error=float("nan")), ValueError, "filter error NaN"),
        (lambda: mmi.bake(ALPHA, UVS, level=13), ValueError,
         "level 13: expected a level 0..=12 (the highest DXR allows and Vulkan devices report)"),
        (lambda: mmi.bake(ALPHA, UVS, level=-1), ValueError, "level -1: expected a level 0..=12"),
        (lambda: mmi.bake(ALPHA, UVS, max_level=13), ValueError, "max_level 13: expected a level 0..=12"),
        (lambda: mmi.bake_gltf(GRID, level=13), ValueError, "level 13: expected a level 0..=12"),
        (lambda: mmi.bake(ALPHA, UVS, level="7"), ValueError,
         'level "7": expected a level 0..=12 (the highest DXR allows and Vulkan devices report) or "auto"'),
        (lambda: mmi.bake(ALPHA, UVS, level="high"), ValueError, "auto"),
        (lambda: mmi.bake(ALPHA, UVS, level=2.5), TypeError, "level"),
        (lambda: mmi.bake(ALPHA, UVS, max_level=40), ValueError, "max_level"),
        (lambda: mmi.bake(ALPHA, UVS, format=3), ValueError, "format 3: expected 2 or 4"),
        (lambda: mmi.bake(ALPHA, UVS, unknown="maybe"), ValueError,
         'unknown "maybe": expected fallback, opaque or transparent'),
        (lambda: mmi.bake(ALPHA, UVS, filter="cubic"), ValueError,
         'filter "cubic": expected nearest or linear'),
        (lambda: mmi.bake(ALPHA, UVS, address="wrap"), ValueError, 'address "wrap": expected repeat'),
        (lambda: mmi.bake(ALPHA, UVS, address=("repeat", "wrap")), ValueError, 'address "wrap"'),
        (lambda: mmi.verify(ALPHA, UVS, mmi.bake(ALPHA, UVS), filter="cubic"), ValueError,
         'filter "cubic": expected nearest or linear'),
        (lambda: mmi.verify(ALPHA, UVS, mmi.bake(ALPHA, UVS), alpha_factor=-1.0), ValueError,
         "alpha_factor"),
        (lambda: mmi.bake(ALPHA, UVS, address=3), TypeError, "address"),
        (lambda: mmi.bake(ALPHA, UVS, cutoff=float("nan")), ValueError, "cutoff"),
        (lambda: mmi.bake(ALPHA, UVS, cutoff=1.5), ValueError, "[0, 1]"),
        (lambda: mmi.bake(ALPHA, UVS, border_alpha=float("inf")), ValueError, "finite"),
        (lambda: mmi.bake(ALPHA, UVS, model="cpu"), ValueError,
         'model "cpu": expected gpu-binary32 or exact'),
        (lambda: mmi.bake(ALPHA, UVS, index_width=8), ValueError, "16 or 32"),
        (lambda: mmi.bake(ALPHA, UVS, level=3, budget=100), ValueError, "auto"),
        (lambda: mmi.bake(ALPHA, UVS, budget=-1), ValueError, "count"),
        (lambda: mmi.verify(ALPHA, UVS, mmi.bake(ALPHA, UVS), max_report=-1), ValueError, "count"),
        (lambda: mmi.bake(ALPHA, UVS, alpha_factor=float("nan")), ValueError, "alpha_factor"),
        (lambda: mmi.bake_gltf("/nonexistent/x.gltf"), OSError, "x.gltf"),
        (lambda: mmi.bake(ALPHA, UVS, threads=0), ValueError,
         "threads 0: expected a number of threads, at least 1"),
        (lambda: mmi.bake(ALPHA, UVS, mips="some"), ValueError,
         'mips "some": expected 0, a level N or all'),
        (lambda: mmi.bake(ALPHA, UVS, mips=-1), ValueError, "mips -1: expected 0, a level N or all"),
        (lambda: mmi.bake(ALPHA, UVS, mips=1.5), TypeError, "mips"),
        (lambda: mmi.bake(ALPHA, UVS, work_budget=-1), ValueError, "work_budget -1"),
        (lambda: mmi.bake(ALPHA, UVS, bake_work_budget=-1), ValueError, "bake_work_budget -1"),
        (lambda: mmi.bake_gltf(CARDS, gltf_out="/tmp/x.png"), ValueError,
         'gltf_out "/tmp/x.png": expected a path ending in NAME.gltf or NAME.glb'),
        (lambda: mmi.bake_gltf(CARDS, gltf_out="/tmp/.glb"), ValueError, "NAME.glb"),
        (lambda: mmi.bake_gltf(CARDS, gltf_out="/tmp/x.glb", filter="linear"), ValueError,
         "filter with gltf_out: the micromaps must match the asset's own samplers"),
        (lambda: mmi.bake_gltf(CARDS, gltf_out="/tmp/x.glb", border_alpha=0.0), ValueError,
         "border_alpha with gltf_out"),
        (lambda: mmi.bake_gltf(CARDS, gltf_out="/tmp/x.glb", opaque_above=True), ValueError,
         "opaque_above with gltf_out"),
        (lambda: mmi.bake_gltf(CARDS, level=2, gltf_out="/nonexistent/dir/x.glb"), OSError,
         'gltf_out "x.glb"'),
        (lambda: mmi.bake_gltf(GRID), ValueError, "grid.tris.json"),
        (lambda: mmi.read_alpha(GRID), ValueError, "grid.tris.json"),
        (lambda: mmi.read_alpha("/nonexistent.png"), OSError, "nonexistent"),
        (lambda: mmi.read_triangles(THORN), ValueError, "sponza_thorn.png"),
        (lambda: mmi.Tree.encode(np.zeros(15, np.uint8), 2), ValueError, "16"),
        (lambda: mmi.Tree.encode(np.zeros(16, np.int64), 2), TypeError, "uint8"),
        (lambda: mmi.Tree.encode([0] * 16, 2), TypeError, "uint8"),
        (lambda: mmi.Tree.encode(np.full(16, 4, np.uint8), 2), ValueError, "0..=3"),
        (lambda: mmi.Tree.encode(np.full(16, 2, np.uint8), 2, format=2), ValueError, ""),
        (lambda: mmi.Tree.encode(np.zeros(16, np.uint8), 17), ValueError, "0..=16"),
        (lambda: mmi.Tree.encode(np.zeros(16, np.uint8), 2, layout="bfs"), ValueError, "paper"),
        (lambda: mmi.Tree.from_bytes(b"\x00" * 7), ValueError, ""),
        (lambda: mmi.Tree.from_bytes(b""), ValueError, ""),
        (lambda: mmi.Tree.encode(np.zeros(16, np.uint8), 2).lookup(16), ValueError, "past"),
        (lambda: mmi.Tree.encode(np.zeros(16, np.uint8), 2).lookup(-1), ValueError, "negative"),
        (lambda: mmi.Tree.encode(np.zeros(16, np.uint8), 2).lookup(np.array([-1])), ValueError, "negative"),
        (lambda: mmi.Tree.encode(np.zeros(16, np.uint8), 2).lookup(np.zeros(2, np.float32)), TypeError, "int64"),
        (lambda: mmi.Tree.encode(np.zeros(16, np.uint8), 2).lookup("1"), TypeError, "int"),
    ],
)
def test_bad_input_raises(call, error, message):
    with pytest.raises(error) as raised:
        call()
    assert message in str(raised.value)


def test_malformed_buffers_raise():
    checker = (np.indices((8, 8)).sum(axis=0) % 2 * 255).astype(np.uint8)
    result = mmi.bake(checker, UVS, level=3)
    assert len(result.data) > 0 and len(result.triangles) == 1
    with pytest.raises(ValueError):
        mmi.verify(checker, UVS, data=result.data[:-1], triangles=result.triangles,
                   indices=result.indices, usage=result.usage)
    with pytest.raises(ValueError):
        mmi.verify(checker, UVS, data=result.data, triangles=b"\xff" * 8,
                   indices=result.indices)
    with pytest.raises(ValueError, match="indices"):
        mmi.verify(checker, np.concatenate([UVS, UVS]), result)
    with pytest.raises(TypeError):
        mmi.verify(ALPHA, UVS, data=result.data, triangles=result.triangles.astype("O"),
                   indices=result.indices)
    with pytest.raises(TypeError):
        mmi.verify(ALPHA, UVS)
    # Random bytes never crash the validator.
    rng = np.random.default_rng(24)
    for _ in range(200):
        junk = [rng.integers(0, 256, rng.integers(0, 40), dtype=np.uint8).tobytes() for _ in range(3)]
        try:
            mmi.verify(ALPHA, UVS, data=junk[0], triangles=junk[1], indices=junk[2])
        except ValueError:
            pass
        try:
            mmi.Tree.from_bytes(junk[0] + junk[1])
        except ValueError:
            pass


def test_a_primitive_that_cannot_be_baked_is_left_out_or_refused(tmp_path):
    # meshes[2].primitives[0] alone uses materials[3]; a rotation there
    # beyond 65536 radians is not modelled: left out and listed, or a ValueError with strict=True.
    import json
    import shutil

    for name in ("cards.bin", "sponza_thorn.png", "chain.png"):
        shutil.copy(SPONZA / name, tmp_path / name)
    gltf = json.loads(CARDS.read_text())
    gltf["materials"][3]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
        "KHR_texture_transform": {"rotation": 1e6}}
    gltf["extensionsUsed"] = ["KHR_texture_transform"]
    asset = tmp_path / "rotated.gltf"
    asset.write_text(json.dumps(gltf))
    reason = ("materials[3].pbrMetallicRoughness.baseColorTexture.extensions."
              "KHR_texture_transform: texture transform rotation 1000000: "
              "expected at most 65536 radians")
    result = mmi.bake_gltf(asset, level=3)
    assert len(result.meshes) == 5
    assert [(r["mesh"], r["primitive"]) for r in result.refused_primitives] == [(2, 0)]
    assert result.refused_primitives[0]["reason"].startswith(reason)
    with pytest.raises(ValueError, match="meshes\\[2\\].primitives\\[0\\] cannot be baked soundly"):
        mmi.bake_gltf(asset, level=3, strict=True)
    assert mmi.bake_gltf(CARDS, level=3).refused_primitives == []
