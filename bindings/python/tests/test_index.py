"""`index` on the committed conformance vectors (docs/vectors.md)."""

import json

import numpy as np
import pytest

import micromap_index as mmi
from conftest import ROOT

VECTORS = ROOT / "reference" / "vectors" / "spec-f32.json"


@pytest.fixture(scope="module")
def cases():
    document = json.loads(VECTORS.read_text())
    assert document["format"] == "micromap-index-vectors" and document["function"] == "spec-f32"
    cases = document["cases"]
    assert len(cases) > 9000
    bits = lambda key: np.array([int(c[key], 16) for c in cases], dtype=np.uint32)
    return {
        # The bit patterns reinterpreted, never converted: NaN payloads,
        # -0 and subnormals matter.
        "u": bits("u").view(np.float32),
        "v": bits("v").view(np.float32),
        "level": np.array([c["level"] for c in cases]),
        "index": np.array([c["index"] for c in cases], dtype=np.uint32),
        "id": [c["id"] for c in cases],
    }


def test_arrays_equal_the_vectors(cases):
    levels = sorted(set(cases["level"].tolist()))
    assert levels == list(range(17))
    for level in levels:
        at = cases["level"] == level
        got = mmi.index(cases["u"][at], cases["v"][at], level)
        assert got.dtype == np.uint32
        expected = cases["index"][at]
        wrong = np.flatnonzero(got != expected)
        assert wrong.size == 0, [
            (np.array(cases["id"])[at][i], hex(cases["u"][at][i:i + 1].view(np.uint32)[0]),
             hex(cases["v"][at][i:i + 1].view(np.uint32)[0]), int(got[i]), int(expected[i]))
            for i in wrong[:5]
        ]
        # The widened reference agrees on levels 0..=16.
        assert np.array_equal(mmi.wide_index(cases["u"][at], cases["v"][at], level), expected)


def test_scalars_equal_the_vectors(cases):
    for i in range(0, len(cases["id"]), 7):
        u, v, level = cases["u"][i], cases["v"][i], int(cases["level"][i])
        got = mmi.index(u, v, level)
        assert isinstance(got, int)
        assert got == cases["index"][i], (cases["id"][i], hex(u.view(np.uint32)), hex(v.view(np.uint32)))


def test_shapes_and_strides_are_kept(cases):
    u = cases["u"][:1200].reshape(30, 40)
    v = cases["v"][:1200].reshape(30, 40)
    flat = mmi.index(cases["u"][:1200], cases["v"][:1200], 9)
    assert np.array_equal(mmi.index(u, v, 9), flat.reshape(30, 40))
    # A transposed (non-contiguous) view reads as numpy shows it.
    assert np.array_equal(mmi.index(u.T, v.T, 9), flat.reshape(30, 40).T)
    assert np.array_equal(mmi.index(u[:, ::3], v[:, ::3], 9), flat.reshape(30, 40)[:, ::3])
    empty = mmi.index(np.zeros(0, np.float32), np.zeros(0, np.float32), 3)
    assert empty.shape == (0,)


def test_python_floats_round_to_float32():
    # The docs' example: (0.28, 0.4) at level 3 is micro-triangle 23.
    assert mmi.index(0.28, 0.4, 3) == 23
    assert mmi.index(0.3, 0.3, 2) == 5
    assert mmi.index(float("nan"), 1.0, 2) == 15
    assert mmi.index(0.28, 0.4, 3) == mmi.index(np.float32(0.28), np.float32(0.4), 3)


def test_wide_levels_above_16():
    u = np.array([0.25, 0.1], np.float32)
    v = np.array([0.5, 0.2], np.float32)
    got = mmi.wide_index(u, v, 32)
    assert got.dtype == np.uint64
    assert [mmi.wide_index(a, b, 32) for a, b in zip(u, v)] == got.tolist()
