"""The Ray bake farm (micromap_index.farm) on a local two-CPU Ray cluster:
the committed assets bake to the CLI's bytes, one task per asset, a
failing asset is reported without stopping the others, and the
content-addressed cache bakes nothing twice."""

import json
import logging
import shutil
from pathlib import Path

import pytest

from conftest import FILES, ROOT, run_cli

ray = pytest.importorskip("ray", reason="SKIPPED: ray is not installed (bindings/python/ci.sh installs it)")
if not hasattr(ray, "init"):  # a folder named ray (Ray's own /tmp/ray) on sys.path
    pytest.skip("SKIPPED: ray is not installed (a folder named ray was found instead)",
                allow_module_level=True)

from micromap_index import farm  # noqa: E402


@pytest.fixture(scope="module")
def local_ray():
    ray.init(num_cpus=2, include_dashboard=False, logging_level=logging.WARNING)
    yield
    ray.shutdown()


def cli_gltf_bake(asset, out, *flags):
    """`micromap-index bake --gltf ASSET --gltf-out asset.glb --out OUT`."""
    run_cli("bake", "--gltf", asset, "--gltf-out", "asset.glb", *flags, "--no-preview",
            "--quiet", "--out", out)
    return {name: (Path(out) / name).read_bytes() for name in FILES + ("asset.glb",)}


def test_farm_bakes_the_committed_assets_as_the_cli(local_ray, tmp_path):
    cache = tmp_path / "cache"
    seen = []
    report = farm.bake_assets([ROOT / "assets"], cache, max_level=5,
                              progress=lambda d, t, r: seen.append((d, t, r.status)))
    by_name = {Path(r.asset).name: r for r in report.results}
    assert sorted(by_name) == ["cards.glb", "cards.gltf", "fern_02.gltf",
                               "fern_02_1k.original.gltf"]
    # The published fern's JPEGs are not committed: that asset fails, alone.
    failed = by_name.pop("fern_02_1k.original.gltf")
    assert failed.status == "failed" and "jpg" in failed.error and failed.directory is None
    assert all(r.status == "baked" for r in by_name.values())
    assert (report.tasks, report.baked, report.failed) == (4, 3, 1)
    assert [(d, t) for d, t, _ in seen] == [(i, 4) for i in range(1, 5)]

    for i, r in enumerate(by_name.values()):
        entry = Path(r.directory)
        assert entry.parent == cache.resolve() and entry.name == r.key
        # The CLI's out dir at the entry's depth: the same relative URIs.
        cli = cli_gltf_bake(r.asset, tmp_path / "cli" / str(i), "--max-level", "5")
        for name, content in cli.items():
            assert (entry / name).read_bytes() == content, f"{r.asset}: {name}"
        stats = json.loads((entry / "result.json").read_text())["stats"]
        assert stats["triangles"] > 0

    again = farm.bake_assets([ROOT / "assets"], cache, max_level=5, progress=None)
    # Only the unreadable asset is tried again (an I/O failure is not cached).
    assert (again.tasks, again.baked, again.cached, again.failed) == (1, 0, 3, 1)
    assert [r.key for r in again.results] == [r.key for r in report.results]


def test_cache_follows_content_and_remembers_refusals(local_ray, tmp_path):
    src = tmp_path / "src"
    shutil.copytree(ROOT / "assets" / "crytek-sponza", src)
    (src / "bad.gltf").write_text('{"asset": {"version": "2.0"}}')
    assets = [src / "cards.gltf", src / "cards.glb", src / "bad.gltf"]
    cache = tmp_path / "cache"

    first = farm.bake_assets(assets, cache, level=3, progress=None)
    assert [r.status for r in first.results] == ["baked", "baked", "failed"]
    assert "no primitive with an alphaMode MASK material" in first.results[2].error

    second = farm.bake_assets(assets, cache, level=3, progress=None)
    assert second.tasks == 0
    assert [r.status for r in second.results] == ["cached", "cached", "failed"]
    assert second.results[2].cached_failure

    # cards.gltf names chain.png: new bytes there make a new key and a new
    # bake; cards.glb (its images inside) stays cached.
    shutil.copyfile(src / "sponza_thorn.png", src / "chain.png")
    third = farm.bake_assets(assets, cache, level=3, progress=None)
    assert third.tasks == 1
    assert [r.status for r in third.results] == ["baked", "cached", "failed"]
    assert third.results[0].key != first.results[0].key
    old, new = (Path(r.directory) / "micromap-data.bin" for r in (first.results[0], third.results[0]))
    assert old.read_bytes() != new.read_bytes()

    # Other options, another key; the thread count is not part of it.
    options = {"level": 3, "threads": 1}
    assert farm.cache_key(assets[1], options, cache) != farm.cache_key(assets[1], {"level": 4}, cache)
    assert farm.cache_key(assets[1], options, cache) == farm.cache_key(assets[1], {"level": 3}, cache)
    assert farm.referenced_files(src / "cards.gltf") == ["cards.bin", "chain.png", "sponza_thorn.png"]
