"""Shared fixtures: the repository's files and the CLI whose bytes the
package must reproduce."""

import json
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
SPONZA = ROOT / "assets" / "crytek-sponza"
THORN = SPONZA / "sponza_thorn.png"
GRID = SPONZA / "grid.tris.json"
FILES = (
    "micromap-data.bin",
    "micromap-triangles.bin",
    "micromap-indices.bin",
    "micromap-usage.bin",
)


def cli_command():
    """`micromap-index`: $MICROMAP_INDEX_CLI (CI builds it once), else the
    CLI crate run by cargo in a target directory of its own (so the
    workspace's own test binaries are not rebuilt)."""
    exe = os.environ.get("MICROMAP_INDEX_CLI")
    if exe:
        return [exe]
    return [
        os.environ.get("CARGO", "cargo"), "run", "-q", "--profile", "test",
        "-p", "micromap-index-cli", "--bin", "micromap-index",
        "--target-dir", str(ROOT / "target" / "python-cli"), "--",
    ]


def run_cli(*args, check=True):
    """Runs the CLI from the repository root; returns the finished process."""
    done = subprocess.run(
        cli_command() + [str(a) for a in args],
        cwd=ROOT, capture_output=True, text=True,
    )
    if check and done.returncode != 0:
        raise AssertionError(f"micromap-index {args} failed ({done.returncode}):\n{done.stderr}")
    return done


@pytest.fixture
def cli_bake(tmp_path):
    """`micromap-index bake ARGS --out DIR`: the four files' bytes, by name."""

    def bake(*args):
        out = tmp_path / f"cli-{len(list(tmp_path.iterdir()))}"
        run_cli("bake", *args, "--no-preview", "--quiet", "--out", out)
        return {name: (out / name).read_bytes() for name in FILES}, out

    return bake


def summary(out):
    return json.loads((Path(out) / "summary.json").read_text())
