"""The Blender-style example bakes to the CLI's bytes."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import FILES, GRID, THORN

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "blender_bake_step.py"


@pytest.mark.parametrize("level", ["4", "auto"])
def test_example_writes_the_clis_bytes(tmp_path, cli_bake, level):
    out = tmp_path / "example"
    done = subprocess.run([sys.executable, EXAMPLE, "--out", out, "--level", level],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "sound" in done.stdout
    flags = [] if level == "auto" else ["--level", level]
    files, _ = cli_bake("--texture", THORN, "--triangles", GRID, *flags)
    for name in FILES:
        assert (out / name).read_bytes() == files[name], name
    assert json.loads((out / "summary.json").read_text())["sound"] is True
