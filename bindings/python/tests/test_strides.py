"""verify reads strided record and index buffers as the tight ones, and
refuses strides the APIs do not allow with a ValueError."""

import numpy as np
import pytest

import micromap_index as mmi
from conftest import GRID, THORN


def spread(buffer, element, stride, whole):
    """``element``-byte elements of ``buffer`` laid ``stride`` bytes apart,
    junk in the gaps, ending with a whole stride or right after the last
    element."""
    out = bytearray()
    for i in range(0, len(buffer), element):
        out += buffer[i : i + element]
        out += bytes((0xA5 ^ k) & 0xFF for k in range(stride - element))
    if not whole and out:
        del out[len(out) - (stride - element) :]
    return bytes(out)


@pytest.fixture(scope="module")
def scene():
    alpha = mmi.read_alpha(THORN)
    uvs = mmi.read_triangles(GRID)
    return alpha, uvs


def flipped(data):
    """Every 4-state byte flipped between transparent and opaque states:
    buffers with contradictions, so that reports carry witnesses."""
    return bytes(b ^ 0b01010101 for b in data)


@pytest.mark.parametrize(
    "index_width, record_stride, index_stride, whole",
    [(32, 8, 4, True), (32, 12, 8, False), (32, 40, 12, True), (16, 16, 6, False),
     (16, 8, 2, True), (16, 20, 16, True)],
)
@pytest.mark.parametrize("broken", [False, True], ids=["sound", "broken"])
def test_strided_buffers_verify_as_the_tight_ones(
    scene, index_width, record_stride, index_stride, whole, broken
):
    alpha, uvs = scene
    result = mmi.bake(alpha, uvs, level=4, index_width=index_width)
    data = flipped(result.data) if broken else result.data
    tight = mmi.verify(alpha, uvs, data=data, triangles=result.triangles,
                       indices=result.indices, usage=result.usage, max_report=5)
    assert tight.sound != broken
    width = index_width // 8
    strided = mmi.verify(
        alpha, uvs, data=data,
        triangles=spread(result.triangles.tobytes(), 8, record_stride, whole),
        indices=spread(result.indices.tobytes(), width, index_stride, whole),
        index_width=index_width, usage=result.usage, max_report=5,
        record_stride=record_stride, index_stride=index_stride,
    )
    assert strided == tight


def test_bad_strides_raise_value_error(scene):
    alpha, uvs = scene
    result = mmi.bake(alpha, uvs, level=4)
    buffers = dict(data=result.data, triangles=result.triangles, indices=result.indices)
    for options, match in [
        ({"record_stride": 0}, "record stride 0"),
        ({"record_stride": 4}, "record stride 4"),
        ({"record_stride": 10}, "record stride 10"),
        ({"index_stride": 0}, "index stride 0"),
        ({"index_stride": 2}, "index stride 2"),
        ({"index_stride": 6}, "index stride 6"),
        ({"record_stride": -8}, "record_stride -8"),
        ({"index_stride": -4}, "index_stride -4"),
    ]:
        with pytest.raises(ValueError, match=match):
            mmi.verify(alpha, uvs, **buffers, **options)
    # A bad stride is refused even when the bytes are malformed too.
    with pytest.raises(ValueError, match="index stride 6"):
        mmi.verify(alpha, uvs, data=result.data, triangles=b"\x00" * 3,
                   indices=result.indices, index_stride=6)
    # Neither whole strides nor ending right after a record.
    records = spread(result.triangles.tobytes(), 8, 16, True)[:-1]
    with pytest.raises(ValueError, match="whole 16-byte strides"):
        mmi.verify(alpha, uvs, data=result.data, triangles=records,
                   indices=result.indices, record_stride=16)
    # Junk between tight-read records is malformed, not silently read.
    with pytest.raises(ValueError):
        mmi.verify(alpha, uvs, data=result.data, triangles=records + b"\x00",
                   indices=result.indices)
    # A BakeResult is tight.
    with pytest.raises(TypeError, match="strides"):
        mmi.verify(alpha, uvs, result, record_stride=16)
