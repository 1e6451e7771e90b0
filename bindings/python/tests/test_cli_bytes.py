"""The package bakes the committed assets to exactly the CLI's bytes."""

from pathlib import Path

import numpy as np
import pytest

import micromap_index as mmi
from conftest import FILES, GRID, SPONZA, THORN, ROOT, run_cli, summary


def assert_same_files(result, cli_files):
    mine = result.files()
    assert list(mine) == list(cli_files)
    for name, cli in cli_files.items():
        assert mine[name] == cli, (
            f"{name}: {len(mine[name])} bytes from the package, {len(cli)} from the CLI"
        )


@pytest.mark.parametrize(
    "options, flags",
    [
        ({"level": 4}, ["--level", "4"]),
        ({}, []),
        (
            {"level": 5, "format": 2, "unknown": "opaque", "filter": "linear",
             "address": "clamp-to-edge", "cutoff": 0.3, "opaque_above": True,
             "index_width": 16},
            ["--level", "5", "--format", "2", "--unknown-as", "opaque", "--filter", "linear",
             "--address", "clamp-to-edge", "--cutoff", "0.3", "--opaque-above",
             "--index-width", "16"],
        ),
        ({"level": 3, "model": "exact", "address": ("mirrored-repeat", "clamp-to-border"),
          "border_alpha": 1.0},
         ["--level", "3", "--model", "exact", "--address-u", "mirrored-repeat",
          "--address-v", "clamp-to-border", "--border", "1"]),
        ({"budget": 4096}, ["--budget", "4096"]),
        ({"level": 4, "filter": "linear", "subtexel_bits": 4, "interpolation": "f16",
          "filter_error": 2.0**-10, "linear": "footprint"},
         ["--level", "4", "--filter", "linear", "--subtexel-bits", "4", "--interpolation",
          "f16", "--filter-error", "0.0009765625", "--linear", "footprint"]),
    ],
    ids=["level4", "auto", "2state-linear-clamp", "exact-mixed-address", "budget",
         "texture-unit"],
)
def test_texture_and_triangles_equal_the_cli(cli_bake, options, flags):
    alpha = mmi.read_alpha(THORN)
    uvs = mmi.read_triangles(GRID)
    assert alpha.shape == (512, 512) and alpha.dtype == np.uint8
    assert uvs.shape == (128, 3, 2) and uvs.dtype == np.float32
    result = mmi.bake(alpha, uvs, **options)
    files, out = cli_bake("--texture", THORN, "--triangles", GRID, *flags)
    assert_same_files(result, files)
    s = summary(out)
    for key in ("triangles", "levels", "micromaps_after_dedup", "bytes_flat",
                "special_index_triangles", "known_fraction", "status",
                "distinct_triangles", "work_units"):
        assert result.stats[key] == s[key], key
    assert result.stats["micro_triangles"] == s["micro_triangles"]
    assert result.indices.dtype == (np.int16 if options.get("index_width") == 16 else np.int32)
    assert len(result.indices) == len(uvs)


def test_float_and_unorm16_alpha_bake_as_the_library_reads_them():
    """The same mask as uint8, uint16 (c * 257: the same quotient) gives
    the same bytes; float32 c/255 too, at a cutoff no rounding reaches."""
    alpha8 = mmi.read_alpha(THORN)
    uvs = mmi.read_triangles(GRID)
    ref = mmi.bake(alpha8, uvs, level=4).files()
    alpha16 = alpha8.astype(np.uint16) * np.uint16(257)
    assert mmi.bake(alpha16, uvs, level=4).files() == ref
    alpha32 = (alpha8 / np.float32(255)).astype(np.float32)
    assert mmi.bake(alpha32, uvs, level=4).files() == ref
    # Fortran order and strided views read as numpy shows them.
    assert mmi.bake(np.asfortranarray(alpha8), np.asfortranarray(uvs), level=4).files() == ref
    rgba = np.zeros(alpha8.shape + (4,), np.uint8)
    rgba[:, :, 3] = alpha8
    assert mmi.bake(rgba[:, :, 3], uvs, level=4).files() == ref
    assert mmi.bake(alpha8.T.copy().T, uvs, level=4).files() == ref
    # A transposed texture is another texture.
    assert mmi.bake(alpha8.T, uvs, level=4).files() != ref


@pytest.mark.parametrize(
    "asset", [SPONZA / "cards.gltf", SPONZA / "cards.glb",
              ROOT / "assets" / "polyhaven-fern02" / "fern_02.gltf"],
    ids=lambda p: p.name,
)
def test_gltf_equals_the_cli(cli_bake, asset):
    result = mmi.bake_gltf(asset, max_level=6)
    files, out = cli_bake("--gltf", asset, "--max-level", "6")
    assert_same_files(result, files)
    s = summary(out)
    assert [m["name"] for m in result.meshes] == [j["name"] for j in s["jobs"]]
    assert [m["first_index"] for m in result.meshes] == [j["first_index"] for j in s["jobs"]]
    assert result.warnings == s["warnings"]


def test_gltf_overrides_equal_the_cli(cli_bake):
    asset = SPONZA / "cards.gltf"
    result = mmi.bake_gltf(asset, level=3, filter="nearest", address="clamp-to-edge",
                           cutoff=0.25, format=2)
    files, _ = cli_bake("--gltf", asset, "--level", "3", "--filter", "nearest",
                        "--address", "clamp-to-edge", "--cutoff", "0.25", "--format", "2")
    assert_same_files(result, files)


def test_verify_agrees_with_verify_bake(cli_bake, tmp_path):
    alpha = mmi.read_alpha(THORN)
    uvs = mmi.read_triangles(GRID)
    result = mmi.bake(alpha, uvs, level=4)
    report = mmi.verify(alpha, uvs, result)
    assert report.sound and report.contradictions == 0
    assert report.known_micro_triangles > 0
    assert report.texture_unit == {"subtexel_bits": 8, "interpolation": "f32",
                                   "filter_error": 2.0**-7, "linear": "value"}

    # Break a known state: every 4-state byte flipped between transparent
    # (0b00) and opaque (0b01) states, then both verifiers must agree.
    data = bytearray(result.data)
    for i in range(len(data)):
        data[i] ^= 0b01010101
    files = result.files()
    files["micromap-data.bin"] = bytes(data)
    directory = tmp_path / "broken"
    directory.mkdir()
    for name, content in files.items():
        (directory / name).write_bytes(content)
    broken = mmi.verify(alpha, uvs, data=bytes(data), triangles=result.triangles,
                        indices=result.indices, usage=result.usage, max_report=5)
    assert not broken.sound and broken.contradictions > 0
    done = run_cli("verify-bake", "--micromaps", directory, "--texture", THORN,
                   "--triangles", GRID, "--json", "--max-report", "5", check=False)
    assert done.returncode != 0
    import json
    cli = json.loads(done.stdout)
    mine = broken.__dict__
    for key, value in mine.items():
        assert cli[key] == (list(map(list_of, value)) if key == "first_contradictions" else value), key


def list_of(contradiction):
    """A contradiction as the CLI's JSON writes it (tuples as lists, the
    exact witness numerators as decimal strings)."""
    c = dict(contradiction)
    w = c["witness_texel_space"]
    c["witness_texel_space"] = None if w is None else [[str(n), s] for n, s in w]
    c["witness_uv"] = None if c["witness_uv"] is None else list(c["witness_uv"])
    c["texel"] = None if c["texel"] is None else list(c["texel"])
    return c


def test_max_bytes_refuses_where_the_cli_does(cli_bake, tmp_path):
    alpha = mmi.read_alpha(THORN)
    uvs = mmi.read_triangles(GRID)
    # 128 level-4 4-state maps of 64 bytes, records, 32-bit indices, usage.
    bound = 128 * (64 + 8 + 4) + 34 * 12
    with pytest.raises(ValueError, match=f"up to {bound} bytes"):
        mmi.bake(alpha, uvs, level=4, max_bytes=bound - 1)
    files, _ = cli_bake("--texture", THORN, "--triangles", GRID, "--level", "4",
                        "--max-bytes", bound)
    assert mmi.bake(alpha, uvs, level=4, max_bytes=bound).files() == files
    refused = run_cli("bake", "--texture", THORN, "--triangles", GRID, "--level", "4",
                      "--max-bytes", bound - 1, "--no-preview", "--out", tmp_path / "no",
                      check=False)
    assert refused.returncode != 0 and f"up to {bound} bytes" in refused.stderr
    # The default limit (1 GiB) refuses 384 level-12 maps (4 MiB each).
    with pytest.raises(ValueError, match="max_bytes"):
        mmi.bake(alpha, np.concatenate([uvs] * 3), level=12)


def test_level_range_is_the_clis(tmp_path):
    """Levels past 12 are refused by the range, in the CLI's words, not by
    the byte limit."""
    alpha = mmi.read_alpha(THORN)
    uvs = mmi.read_triangles(GRID)
    words = "expected a level 0..=12 (the highest DXR allows and Vulkan devices report)"
    for keyword, flag in [("level", "--level"), ("max_level", "--max-level")]:
        with pytest.raises(ValueError) as raised:
            mmi.bake(alpha, uvs, **{keyword: 13})
        assert str(raised.value) == f"{keyword} 13: {words}"
        done = run_cli("bake", "--texture", THORN, "--triangles", GRID, flag, "13",
                       "--out", tmp_path / "no", check=False)
        assert done.returncode == 2 and words in done.stderr


def test_no_mixed_special_equals_the_cli(cli_bake):
    """``no_mixed_special=True`` is ``bake --no-mixed-special``, byte for
    byte, on a bake that mixes special indices with records without it
    (at level 1 some of the grid's triangles are uniform)."""
    alpha = mmi.read_alpha(THORN)
    uvs = mmi.read_triangles(GRID)
    mixed = mmi.bake(alpha, uvs, level=1)
    assert mixed.meshes[0]["mixed_special_indices"], "the option has nothing to do"
    assert (mixed.indices < 0).any()
    result = mmi.bake(alpha, uvs, level=1, no_mixed_special=True)
    assert not result.meshes[0]["mixed_special_indices"]
    assert (result.indices >= 0).all()
    assert len(result.triangles) > len(mixed.triangles)
    files, out = cli_bake("--texture", THORN, "--triangles", GRID, "--level", "1",
                          "--no-mixed-special")
    assert_same_files(result, files)
    jobs = summary(out)["jobs"]
    assert [m["mixed_special_indices"] for m in result.meshes] == [
        j["mixed_special_indices"] for j in jobs
    ]
    assert mmi.verify(alpha, uvs, result).sound


@pytest.mark.parametrize("no_mixed", [False, True], ids=["mixed", "no-mixed"])
def test_gltf_no_mixed_special_equals_the_cli(cli_bake, no_mixed):
    # The fern's primitives mix special indices with records by default.
    asset = ROOT / "assets" / "polyhaven-fern02" / "fern_02.gltf"
    flags = ["--no-mixed-special"] if no_mixed else []
    result = mmi.bake_gltf(asset, max_level=6, no_mixed_special=no_mixed)
    files, out = cli_bake("--gltf", asset, "--max-level", "6", *flags)
    assert_same_files(result, files)
    assert [m["mixed_special_indices"] for m in result.meshes] == [
        j["mixed_special_indices"] for j in summary(out)["jobs"]
    ]
    assert any(m["mixed_special_indices"] for m in result.meshes) != no_mixed


def test_verify_applies_alpha_factor_as_the_bake():
    """verify goes through the library's verify_mesh: a bake with an alpha
    factor is sound under the same factor and contradicted without it."""
    alpha = mmi.read_alpha(THORN)
    uvs = mmi.read_triangles(GRID)
    result = mmi.bake(alpha, uvs, level=4, alpha_factor=0.6)
    assert mmi.verify(alpha, uvs, result, alpha_factor=0.6).sound
    plain = mmi.verify(alpha, uvs, result)
    assert not plain.sound and plain.contradictions > 0


@pytest.mark.parametrize(
    "asset, name",
    [(SPONZA / "cards.gltf", "omm.glb"), (SPONZA / "cards.gltf", "omm.gltf"),
     (SPONZA / "cards.glb", "omm.gltf"), (SPONZA / "cards.glb", "omm.glb"),
     (ROOT / "assets" / "polyhaven-fern02" / "fern_02.gltf", "fern-omm.glb")],
    ids=["gltf-to-glb", "gltf-to-gltf", "glb-to-gltf", "glb-to-glb", "fern-to-glb"],
)
def test_gltf_out_equals_the_cli(cli_bake, tmp_path, asset, name):
    """``bake_gltf(gltf_out=DIR/NAME)`` writes the files ``bake --gltf-out
    NAME --out DIR`` writes, byte for byte (DIRs at the same depth, so the
    relative URIs back to the asset are the same)."""
    py_dir = tmp_path / "py"
    py_dir.mkdir()
    result = mmi.bake_gltf(asset, max_level=5, gltf_out=py_dir / name)
    files, out = cli_bake("--gltf", asset, "--max-level", "5", "--gltf-out", name)
    assert_same_files(result, files)
    cli_gltf = sorted(p.name for p in out.iterdir()
                      if p.name not in FILES and p.name not in
                      ("summary.json", "micromap-geometry-usage.bin"))
    assert sorted(p.name for p in py_dir.iterdir()) == cli_gltf
    assert sorted(Path(p).name for p in result.gltf_out) == cli_gltf
    for n in cli_gltf:
        assert (py_dir / n).read_bytes() == (out / n).read_bytes(), n
    assert Path(result.gltf_out[0]).name == name
    # The written asset is sound by the CLI's own verifier.
    done = run_cli("verify-bake", "--gltf", py_dir / name)
    assert done.stdout.startswith("sound")


@pytest.mark.parametrize(
    "options, flags",
    [
        ({"level": 5, "mips": "all", "threads": 1}, ["--level", "5", "--mips", "all", "--threads", "1"]),
        ({"level": 5, "mips": 2, "threads": 2}, ["--level", "5", "--mips", "2", "--threads", "2"]),
        ({"level": 7, "work_budget": 3000}, ["--level", "7", "--work-budget", "3000"]),
        ({"level": 7, "bake_work_budget": 20000}, ["--level", "7", "--bake-work-budget", "20000"]),
        ({"filter": "linear", "mips": 3}, ["--filter", "linear", "--mips", "3"]),
    ],
    ids=["mips-all-serial", "mips-2-two-threads", "work-budget", "bake-work-budget", "auto-linear-mips"],
)
def test_mips_threads_and_work_budgets_equal_the_cli(cli_bake, options, flags):
    alpha = mmi.read_alpha(THORN)
    uvs = mmi.read_triangles(GRID)
    result = mmi.bake(alpha, uvs, **options)
    files, out = cli_bake("--texture", THORN, "--triangles", GRID, *flags)
    assert_same_files(result, files)
    s = summary(out)
    for key in ("work_units", "status", "micro_triangles", "known_fraction"):
        assert result.stats[key] == s[key], key
    # The bytes are the same on every thread count.
    for threads in (1, 2, None):
        assert mmi.bake(alpha, uvs, **{**options, "threads": threads}).files() == files


def test_work_budgets_bite():
    """The budgets above are small enough to change the bake: the tests
    compare bakes that differ from the default one."""
    alpha = mmi.read_alpha(THORN)
    uvs = mmi.read_triangles(GRID)
    default = mmi.bake(alpha, uvs, level=7)
    for options in ({"work_budget": 3000}, {"bake_work_budget": 20000}):
        cut = mmi.bake(alpha, uvs, level=7, **options)
        assert cut.stats["status"]["work_budget_exceeded"] > 0
        assert cut.files() != default.files()
    assert mmi.bake(alpha, uvs, level=5, mips="all").files() != mmi.bake(alpha, uvs, level=5).files()


def test_gltf_mips_and_threads_equal_the_cli(cli_bake):
    asset = ROOT / "assets" / "polyhaven-fern02" / "fern_02.gltf"
    result = mmi.bake_gltf(asset, max_level=6, mips="all", threads=2)
    files, _ = cli_bake("--gltf", asset, "--max-level", "6", "--mips", "all", "--threads", "2")
    assert_same_files(result, files)


def test_uv_transform_is_baked_as_the_shader_applies_it():
    """``uv_transform`` (glTF's KHR_texture_transform) goes through the
    library's ``Material::uv_transform``: under the exact model an exact
    transform bakes the bytes of the transformed coordinates; under the GPU
    model a rotated one bakes sound under the same transform and is
    contradicted without it; values the model refuses are a ValueError."""
    alpha = mmi.read_alpha(THORN)
    uvs = mmi.read_triangles(GRID)
    exact = ((0.25, 0.0), 0.0, (0.5, 0.5))
    moved = uvs * np.float32(0.5) + np.array([0.25, 0.0], dtype=np.float32)
    a = mmi.bake(alpha, uvs, level=4, model="exact", uv_transform=exact)
    b = mmi.bake(alpha, moved, level=4, model="exact")
    assert a.files() == b.files()
    turned = ((0.705, 0.285), 0.3, (0.35, 0.35))
    result = mmi.bake(alpha, uvs, level=4, uv_transform=turned)
    assert mmi.verify(alpha, uvs, result, uv_transform=turned).sound
    plain = mmi.verify(alpha, uvs, result)
    assert not plain.sound and plain.contradictions > 0
    with pytest.raises(ValueError, match="uv_transform: texture transform rotation"):
        mmi.bake(alpha, uvs, level=2, uv_transform=((0.0, 0.0), 1e6, (1.0, 1.0)))
    with pytest.raises(ValueError, match="must be finite"):
        mmi.verify(alpha, uvs, result, uv_transform=((float("nan"), 0.0), 0.0, (1.0, 1.0)))
