"""Opacity micromaps for ray tracing, from Python (docs/python.md).

A thin layer over the Rust library micromap-index: every answer is the
library's. Numpy in, numpy out:

* :func:`index` / :func:`wide_index` -- barycentrics to the micro-triangle
  index, bit for bit the Vulkan reference in binary32 (SIMD batch kernels on
  arrays);
* :func:`bake` / :func:`bake_gltf` -- an alpha texture and UV triangles (or a
  glTF asset) to the API buffers ``micromap-index bake`` writes, sound for
  binary32 GPU hits (model ``"gpu-binary32"``) or for the exact real points
  (``"exact"``);
* :func:`verify` -- anyone's micromap buffers checked against the texture;
* :class:`Tree` -- one micromap as a succinct tree;
* :func:`read_alpha`, :func:`read_triangles` -- the CLI's PNG/JPEG and
  TRIS.json readers, as arrays.

Bad input raises ``TypeError`` (wrong type or dtype), ``ValueError`` (wrong
shape or value, malformed buffers or assets, a limit exceeded),
``OSError`` (files) or ``MemoryError`` (an input whose copy or result does
not fit in memory), with the library's message; it never crashes the
interpreter. Bakes and
verification release the GIL.
"""

from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._native import Tree, index, read_alpha, read_triangles, wide_index

__version__: str = _native.__version__

__all__ = [
    "BakeResult",
    "FILE_NAMES",
    "OPAQUE",
    "TRANSPARENT",
    "TRIANGLE_DTYPE",
    "Tree",
    "UNKNOWN_OPAQUE",
    "UNKNOWN_TRANSPARENT",
    "USAGE_DTYPE",
    "VerifyReport",
    "bake",
    "bake_gltf",
    "index",
    "read_alpha",
    "read_triangles",
    "verify",
    "wide_index",
]

#: Micro-triangle states (the API values).
TRANSPARENT = 0
OPAQUE = 1
UNKNOWN_TRANSPARENT = 2
UNKNOWN_OPAQUE = 3

#: One triangle record, as ``VkMicromapTriangleEXT`` / DXR's
#: ``D3D12_RAYTRACING_OPACITY_MICROMAP_DESC`` (8 bytes, little endian).
TRIANGLE_DTYPE = np.dtype(
    [("data_offset", "<u4"), ("subdivision_level", "<u2"), ("format", "<u2")]
)
#: One usage count, as ``VkMicromapUsageEXT`` (12 bytes, little endian).
USAGE_DTYPE = np.dtype(
    [("count", "<u4"), ("subdivision_level", "<u4"), ("format", "<u4")]
)
#: The files ``micromap-index bake`` writes, by :meth:`BakeResult.files` key.
FILE_NAMES = (
    "micromap-data.bin",
    "micromap-triangles.bin",
    "micromap-indices.bin",
    "micromap-usage.bin",
)

Address = Union[str, Tuple[str, str]]
# KHR_texture_transform's (offset, rotation, scale).
UvTransformParams = Tuple[Tuple[float, float], float, Tuple[float, float]]


@dataclass(frozen=True)
class BakeResult:
    """A finished bake, in the API layouts.

    ``data``: the packed micromap data (``micromap-data.bin``).
    ``triangles``: one :data:`TRIANGLE_DTYPE` record per micromap.
    ``indices``: one index per input triangle (``int32``, or ``int16`` with
    ``index_width=16``), all meshes concatenated; ``-1`` .. ``-4`` are the
    special indices (fully transparent, fully opaque, unknown transparent,
    unknown opaque).
    ``usage``: :data:`USAGE_DTYPE` counts per (level, format).
    ``stats``: the bake's statistics, with the keys of the CLI's
    ``summary.json`` (``triangles``, ``levels``, ``micro_triangles``,
    ``known_fraction``, ``status``, ``micromaps_after_dedup``, ...).
    ``meshes``: per mesh its name, texture size, sampler, cutoff, triangle
    count, ``first_index`` into ``indices`` and ``mixed_special_indices``
    (whether its geometry mixes special indices with records).
    ``warnings``: what the glTF reader warned about (empty for :func:`bake`).
    ``refused_primitives``: :func:`bake_gltf`'s primitives left out, each a
    dict of ``mesh``, ``primitive`` and ``reason`` (the CLI's
    ``summary.json`` ``refused_primitives``; empty for :func:`bake`).
    ``gltf_out``: the paths :func:`bake_gltf` wrote with ``gltf_out`` (the
    glTF first, then its sidecar files; empty otherwise).
    """

    data: bytes
    triangles: np.ndarray
    indices: np.ndarray
    usage: np.ndarray
    index_width: int
    stats: Dict[str, Any]
    meshes: List[Dict[str, Any]]
    warnings: List[str] = field(default_factory=list)
    gltf_out: List[str] = field(default_factory=list)
    refused_primitives: List[Dict[str, Any]] = field(default_factory=list)

    def files(self) -> Dict[str, bytes]:
        """The bytes of the four files ``micromap-index bake`` writes, by
        name (:data:`FILE_NAMES`); equal to the CLI's for the same inputs."""
        return {
            "micromap-data.bin": self.data,
            "micromap-triangles.bin": self.triangles.tobytes(),
            "micromap-indices.bin": self.indices.tobytes(),
            "micromap-usage.bin": self.usage.tobytes(),
        }


def _write_all(directory: str, files: Sequence[Tuple[str, bytes]]) -> List[str]:
    """Writes ``files`` (name, bytes) into ``directory``: every file to a
    temporary first, then each renamed over its name, so that a failure
    before the renames leaves every old file as it was (and no temporary)."""
    temporaries: List[str] = []
    try:
        for name, content in files:
            fd, temporary = tempfile.mkstemp(prefix=f".{name}.", suffix=".tmp", dir=directory)
            temporaries.append(temporary)
            with os.fdopen(fd, "wb") as f:
                f.write(content)
        written = []
        for (name, _), temporary in zip(files, temporaries):
            os.replace(temporary, os.path.join(directory, name))
            written.append(os.path.join(directory, name))
        temporaries.clear()
        return written
    finally:
        for temporary in temporaries:
            try:
                os.unlink(temporary)
            except OSError:
                pass


def _options(
    level: Union[int, str],
    max_level: int,
    format: int,
    unknown: str,
    model: str,
    unit: Dict[str, Any],
    budget: Optional[int],
    index_width: int,
    max_bytes: int,
    no_mixed_special: bool,
    mips: Union[int, str],
    threads: Optional[int],
    work_budget: Optional[int],
    bake_work_budget: Optional[int],
) -> Dict[str, Any]:
    """The options both bakes hand to the extension, as one dict."""
    return dict(
        level=level, max_level=max_level, format=format, unknown=unknown, model=model,
        **unit, budget=budget, index_width=index_width, max_bytes=max_bytes,
        no_mixed_special=no_mixed_special, mips=mips, threads=threads,
        work_budget=work_budget, bake_work_budget=bake_work_budget,
    )


def _unit(
    subtexel_bits: int, interpolation: str, filter_error: float, linear: str
) -> Dict[str, Any]:
    """The texture-unit keywords, as the extension takes them."""
    return dict(
        subtexel_bits=subtexel_bits,
        interpolation=interpolation,
        filter_error=filter_error,
        linear=linear,
    )


def _result(raw: Dict[str, Any], gltf_out: Sequence[str] = ()) -> BakeResult:
    width = raw["index_width"]
    indices = np.frombuffer(raw["indices"], dtype="<i4" if width == 32 else "<i2")
    return BakeResult(
        data=raw["data"],
        triangles=np.frombuffer(raw["triangles"], dtype=TRIANGLE_DTYPE),
        indices=indices,
        usage=np.frombuffer(raw["usage"], dtype=USAGE_DTYPE),
        index_width=width,
        stats=raw["stats"],
        meshes=raw["meshes"],
        warnings=list(raw.get("warnings", [])),
        gltf_out=list(gltf_out),
        refused_primitives=list(raw.get("refused_primitives", [])),
    )


def bake(
    alpha: np.ndarray,
    uvs: np.ndarray,
    *,
    level: Union[int, str] = "auto",
    max_level: int = 12,
    format: int = 4,
    unknown: str = "fallback",
    filter: str = "nearest",
    address: Address = "repeat",
    border_alpha: float = 0.0,
    cutoff: float = 0.5,
    opaque_above: bool = False,
    model: str = "gpu-binary32",
    subtexel_bits: int = 8,
    interpolation: str = "f32",
    filter_error: float = 2.0**-7,
    linear: str = "value",
    budget: Optional[int] = None,
    index_width: int = 32,
    alpha_factor: float = 1.0,
    max_bytes: int = 1 << 30,
    no_mixed_special: bool = False,
    mips: Union[int, str] = 0,
    threads: Optional[int] = None,
    work_budget: Optional[int] = None,
    bake_work_budget: Optional[int] = None,
    uv_transform: Optional[UvTransformParams] = None,
) -> BakeResult:
    """Bakes opacity micromaps for ``uvs`` over the alpha texture ``alpha``.

    ``alpha``: a 2-D ``uint8`` (unorm8), ``uint16`` (unorm16) or ``float32``
    array of shape ``(height, width)``, row 0 the image's top row (``v = 0``),
    as an image library returns it. ``uvs``: a ``float32`` array of shape
    ``(N, 3, 2)``, triangle ``t``'s vertex ``i`` at ``uvs[t, i]`` (the order
    of the triangle's barycentrics: vertex 0 has weight ``1 - u - v``).

    Options as ``micromap-index bake``'s flags: ``level`` an int 0..=12 (the
    highest DXR allows and Vulkan devices report) or ``"auto"`` (each triangle's useful level up to ``max_level``); ``format``
    2 or 4; ``unknown`` (2-state) ``"fallback"``, ``"opaque"`` or
    ``"transparent"``; ``filter`` ``"nearest"`` or ``"linear"``; ``address``
    one mode or a ``(u, v)`` pair of ``"repeat"``, ``"mirrored-repeat"``,
    ``"clamp-to-edge"``, ``"clamp-to-border"``, ``"mirror-clamp-to-edge"``;
    ``border_alpha`` for clamp-to-border; opaque where ``alpha >= cutoff``
    (glTF's rule) or ``alpha > cutoff`` with ``opaque_above``; ``model``
    ``"gpu-binary32"`` (the default: sound for every binary32 hit a GPU
    assigns to a micro-triangle) or ``"exact"``; ``subtexel_bits``
    (``--subtexel-bits``, 4..=16, default 8), ``interpolation``
    (``--interpolation``, ``"f32"`` or ``"f16"``), ``filter_error``
    (``--filter-error``, default ``2**-7``) and ``linear`` (``--linear``,
    ``"value"`` or ``"footprint"``): the texture unit ``gpu-binary32`` holds
    for (sub-texel snapping to ``2**-k`` texels, the shader's interpolation
    precision, the linear filter's arithmetic error, and whether a linear
    filter is judged by its value or by its whole 2x2 footprint; see
    ``docs/bake.md``, "The texture unit"); ``budget`` at most that many
    bytes of micromap data (with ``level="auto"``); ``index_width`` 16 or 32;
    ``alpha_factor`` multiplies every texel's alpha (glTF's
    ``baseColorFactor[3]``); ``max_bytes`` (default 1 GiB, as the CLI's
    ``--max-bytes``) refuses, before baking, a bake whose output may exceed
    it (a ``ValueError``; so is a ``uvs`` whose indices alone exceed it,
    before it is copied); ``no_mixed_special`` (``--no-mixed-special``): no
    geometry mixes special indices with records -- in a geometry that
    references any record each special index becomes a shared level-0
    record of its state, for Vulkan KHR pipelines created with
    ``VK_PIPELINE_CREATE_2_OPACITY_MICROMAP_DISALLOW_MIXED_SPECIAL_INDEX_BIT_KHR``
    (``meshes[i]["mixed_special_indices"]`` says whether a geometry mixes
    them); ``mips`` (``--mips``) the mip levels known states hold for: 0
    (level 0 only, under the sampler's filter), ``N`` (levels 0..=N under
    either filter) or ``"all"``; ``threads`` (``--threads``) the threads to
    bake on, ``None`` for every core (rayon's pool, ``RAYON_NUM_THREADS``),
    1 for serial: the bytes are the same for every count; ``work_budget``
    (``--work-budget``, default 67,108,864) work units one triangle may
    spend, the rest left unknown; ``bake_work_budget``
    (``--bake-work-budget``, default 17,179,869,184) all triangles
    together; ``uv_transform`` ``(offset, rotation, scale)`` (glTF's
    ``KHR_texture_transform``: ``offset`` and ``scale`` pairs, ``rotation``
    in radians), which the renderer's shader applies to the interpolated
    coordinate: ``uvs`` are then the stored coordinates, and the bake models
    the shader's binary32 transform (``docs/bake.md``, "Texture
    transforms"; a ``ValueError`` for values that are not finite or a
    rotation beyond 65,536 radians).

    Releases the GIL while baking, on copies of ``alpha`` and ``uvs``.
    Raises ``TypeError`` / ``ValueError``, or ``MemoryError`` when a copy
    does not fit in memory.
    """
    return _result(
        _native.bake(
            alpha,
            uvs,
            _options(level, max_level, format, unknown, model,
                     _unit(subtexel_bits, interpolation, filter_error, linear), budget,
                     index_width, max_bytes, no_mixed_special, mips, threads, work_budget,
                     bake_work_budget),
            filter=filter,
            address=address,
            border_alpha=border_alpha,
            cutoff=cutoff,
            opaque_above=opaque_above,
            alpha_factor=alpha_factor,
            uv_transform=uv_transform,
        )
    )


def bake_gltf(
    path: Union[str, "os.PathLike[str]"],
    *,
    level: Union[int, str] = "auto",
    max_level: int = 12,
    format: int = 4,
    unknown: str = "fallback",
    filter: Optional[str] = None,
    address: Optional[Address] = None,
    border_alpha: Optional[float] = None,
    cutoff: Optional[float] = None,
    opaque_above: bool = False,
    model: str = "gpu-binary32",
    subtexel_bits: int = 8,
    interpolation: str = "f32",
    filter_error: float = 2.0**-7,
    linear: str = "value",
    budget: Optional[int] = None,
    index_width: int = 32,
    max_bytes: int = 1 << 30,
    no_mixed_special: bool = False,
    mips: Union[int, str] = 0,
    threads: Optional[int] = None,
    work_budget: Optional[int] = None,
    bake_work_budget: Optional[int] = None,
    gltf_out: Optional[Union[str, "os.PathLike[str]"]] = None,
    strict: bool = False,
) -> BakeResult:
    """Bakes every alpha-masked primitive of a glTF 2.0 asset (``.gltf`` or
    ``.glb``), as ``micromap-index bake --gltf``: one geometry per primitive,
    in the asset's order, micromaps deduplicated across all. Each primitive
    uses its material's ``alphaCutoff``, ``baseColorFactor`` alpha and its
    texture's sampler unless ``filter``, ``address``, ``border_alpha``
    (default 0), ``cutoff`` or ``opaque_above`` is given. The other options
    are :func:`bake`'s.

    ``gltf_out``: a path ``DIR/NAME.glb`` or ``DIR/NAME.gltf`` (``DIR`` must
    exist): the asset is also written back there with
    ``EXT_mesh_opacity_micromap`` on every baked primitive, as ``bake --gltf
    ASSET --out DIR --gltf-out NAME`` writes it, byte for byte (the same
    library code; ``.gltf`` adds ``NAME.micromap.bin`` and ``NAME.bin``,
    which holds the asset's buffers and images, so ``DIR`` can be moved).
    Not with ``filter``, ``address``,
    ``border_alpha``, ``cutoff`` or ``opaque_above`` (a ``ValueError``: the
    micromaps must match the asset's own sampling). Existing files are
    replaced; every file is written to a temporary first and renamed only
    when all are written. ``result.gltf_out`` lists the paths.

    ``KHR_texture_transform`` (any offset, rotation and scale) is baked as
    the shader applies it (``docs/bake.md``, "Texture transforms"). A
    primitive the model does not cover (a rotation beyond 65,536 radians)
    is left out and
    listed in ``result.refused_primitives`` with its reason (the CLI's exit
    5); with ``strict=True`` it is a ``ValueError`` instead, as ``bake
    --strict``.

    Raises ``OSError`` when a file cannot be read or written and
    ``ValueError`` for a malformed asset."""
    raw = _native.bake_gltf(
        os.fspath(path),
        _options(level, max_level, format, unknown, model,
                 _unit(subtexel_bits, interpolation, filter_error, linear), budget,
                 index_width, max_bytes, no_mixed_special, mips, threads, work_budget,
                 bake_work_budget),
        filter=filter,
        address=address,
        border_alpha=border_alpha,
        cutoff=cutoff,
        opaque_above=opaque_above,
        gltf_out=None if gltf_out is None else os.fspath(gltf_out),
        strict=strict,
    )
    written: List[str] = []
    if "gltf_files" in raw:
        written = _write_all(raw["gltf_dir"], raw["gltf_files"])
    return _result(raw, written)


@dataclass(frozen=True)
class VerifyReport:
    """What :func:`verify` found (the keys of ``micromap-index verify-bake
    --json``). ``sound`` is true when no known micro-triangle is contradicted
    and every one was checked."""

    model: str
    texture_unit: Dict[str, Any]
    triangles: int
    triangles_checked: int
    known_micro_triangles: int
    unknown_micro_triangles: int
    unknown_fraction: float
    undecided: int
    unchecked_micro_triangles: int
    complete: bool
    contradictions: int
    first_contradictions: List[Dict[str, Any]]
    usage_counts_checked: bool
    sound: bool


_Buffer = Union[bytes, bytearray, memoryview, np.ndarray]


def _buffer_bytes(value: _Buffer, name: str, dtypes: Sequence[np.dtype]) -> bytes:
    if isinstance(value, (bytes, bytearray, memoryview)):
        return bytes(value)
    if isinstance(value, np.ndarray):
        if value.dtype not in dtypes and value.dtype != np.uint8:
            expected = ", ".join(str(d) for d in dtypes)
            raise TypeError(
                f"{name} must be bytes or an array of dtype {expected} or uint8, "
                f"not {value.dtype}"
            )
        return np.ascontiguousarray(value).tobytes()
    raise TypeError(f"{name} must be bytes or a numpy array, not {type(value).__name__}")


def _index_width(indices: _Buffer, index_width: Optional[int]) -> int:
    if index_width is not None:
        return index_width
    if isinstance(indices, np.ndarray) and indices.dtype.itemsize == 2:
        return 16
    return 32


def verify(
    alpha: np.ndarray,
    uvs: np.ndarray,
    buffers: Optional[BakeResult] = None,
    *,
    data: Optional[_Buffer] = None,
    triangles: Optional[_Buffer] = None,
    indices: Optional[_Buffer] = None,
    usage: Optional[_Buffer] = None,
    index_width: Optional[int] = None,
    filter: str = "nearest",
    address: Address = "repeat",
    border_alpha: float = 0.0,
    cutoff: float = 0.5,
    opaque_above: bool = False,
    alpha_factor: float = 1.0,
    model: str = "gpu-binary32",
    subtexel_bits: int = 8,
    interpolation: str = "f32",
    filter_error: float = 2.0**-7,
    linear: str = "value",
    max_report: int = 20,
    max_checks: Optional[int] = None,
    lenient_layout: bool = False,
    record_stride: Optional[int] = None,
    index_stride: Optional[int] = None,
    uv_transform: Optional[UvTransformParams] = None,
) -> VerifyReport:
    """Checks micromap buffers -- a :class:`BakeResult`, or ``data``,
    ``triangles``, ``indices`` and (optionally) ``usage`` from any baker, as
    bytes or arrays -- against ``alpha`` and ``uvs`` (as :func:`bake`
    takes them), as ``micromap-index verify-bake``: the buffers are validated
    (a malformed one is a ``ValueError``), then every known micro-triangle is
    checked exactly against the texture under the sampler, the cutoff, the
    alpha factor (``alpha_factor``, as :func:`bake` takes it), the model and
    its texture unit (``subtexel_bits``, ``interpolation``, ``filter_error``,
    ``linear``, as :func:`bake` takes them; ``texture_unit`` in the report),
    by the library's ``bake::mesh::verify_mesh``, the verifier of every front
    end. The first ``max_report`` contradictions are reported with an exact
    witness point; ``max_checks`` caps the known micro-triangles checked
    (then ``complete`` is false). ``lenient_layout`` accepts overlapping
    records. ``index_width`` defaults to the ``indices`` array's (16 for
    2-byte dtypes) or 32. ``record_stride`` and ``index_stride`` are the
    bytes from one triangle record (Vulkan's ``triangleArrayStride``) or
    index (``indexStride``) to the next in ``triangles`` and ``indices``
    (``None``: tight): a record stride is at least 8 and a multiple of 4, an
    index stride a multiple of the index width (else a ``ValueError``); the
    bytes between elements are ignored and a buffer holds whole strides or
    ends right after its last element. ``uv_transform`` as :func:`bake`
    takes it. Releases the GIL while checking."""
    if buffers is not None:
        if any(x is not None for x in (data, triangles, indices, usage)):
            raise TypeError("give either a BakeResult or data/triangles/indices/usage, not both")
        if record_stride is not None or index_stride is not None:
            raise TypeError("a BakeResult is tight: strides go with data/triangles/indices")
        data, triangles, indices, usage = (
            buffers.data,
            buffers.triangles,
            buffers.indices,
            buffers.usage,
        )
        index_width = buffers.index_width
    if data is None or triangles is None or indices is None:
        raise TypeError("verify needs a BakeResult or data, triangles and indices")
    index_dtypes = [np.dtype(t) for t in ("<i4", "<u4", "<i2", "<u2")]
    raw = _native.verify(
        alpha,
        uvs,
        data=_buffer_bytes(data, "data", []),
        triangles=_buffer_bytes(triangles, "triangles", [TRIANGLE_DTYPE]),
        indices=_buffer_bytes(indices, "indices", index_dtypes),
        index_width=_index_width(indices, index_width),
        usage=None if usage is None else _buffer_bytes(usage, "usage", [USAGE_DTYPE]),
        filter=filter,
        address=address,
        border_alpha=border_alpha,
        cutoff=cutoff,
        opaque_above=opaque_above,
        alpha_factor=alpha_factor,
        model=model,
        **_unit(subtexel_bits, interpolation, filter_error, linear),
        max_report=max_report,
        max_checks=max_checks,
        lenient_layout=lenient_layout,
        record_stride=record_stride,
        index_stride=index_stride,
        uv_transform=uv_transform,
    )
    return VerifyReport(**raw)
