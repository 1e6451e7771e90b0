# Type stubs of micromap_index (docs/python.md).
import os
from dataclasses import dataclass
from typing import Any, Dict, List, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

from ._native import Tree as Tree
from ._native import index as index
from ._native import read_alpha as read_alpha
from ._native import read_triangles as read_triangles
from ._native import wide_index as wide_index

__version__: str
TRANSPARENT: int
OPAQUE: int
UNKNOWN_TRANSPARENT: int
UNKNOWN_OPAQUE: int
TRIANGLE_DTYPE: np.dtype
USAGE_DTYPE: np.dtype
FILE_NAMES: Tuple[str, str, str, str]

Address = Union[str, Tuple[str, str]]
UvTransformParams = Tuple[Tuple[float, float], float, Tuple[float, float]]
_Buffer = Union[bytes, bytearray, memoryview, np.ndarray]
_Alpha = Union[npt.NDArray[np.uint8], npt.NDArray[np.uint16], npt.NDArray[np.float32]]

@dataclass(frozen=True)
class BakeResult:
    data: bytes
    triangles: np.ndarray
    indices: Union[npt.NDArray[np.int32], npt.NDArray[np.int16]]
    usage: np.ndarray
    index_width: int
    stats: Dict[str, Any]
    meshes: List[Dict[str, Any]]
    warnings: List[str] = ...
    gltf_out: List[str] = ...
    refused_primitives: List[Dict[str, Any]] = ...
    def files(self) -> Dict[str, bytes]: ...

@dataclass(frozen=True)
class VerifyReport:
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

def bake(
    alpha: _Alpha,
    uvs: npt.NDArray[np.float32],
    *,
    level: Union[int, str] = ...,
    max_level: int = ...,
    format: int = ...,
    unknown: str = ...,
    filter: str = ...,
    address: Address = ...,
    border_alpha: float = ...,
    cutoff: float = ...,
    opaque_above: bool = ...,
    model: str = ...,
    subtexel_bits: int = ...,
    interpolation: str = ...,
    filter_error: float = ...,
    linear: str = ...,
    budget: Optional[int] = ...,
    index_width: int = ...,
    alpha_factor: float = ...,
    max_bytes: int = ...,
    no_mixed_special: bool = ...,
    mips: Union[int, str] = ...,
    threads: Optional[int] = ...,
    work_budget: Optional[int] = ...,
    bake_work_budget: Optional[int] = ...,
    uv_transform: Optional[UvTransformParams] = ...,
) -> BakeResult: ...
def bake_gltf(
    path: Union[str, "os.PathLike[str]"],
    *,
    level: Union[int, str] = ...,
    max_level: int = ...,
    format: int = ...,
    unknown: str = ...,
    filter: Optional[str] = ...,
    address: Optional[Address] = ...,
    border_alpha: Optional[float] = ...,
    cutoff: Optional[float] = ...,
    opaque_above: bool = ...,
    model: str = ...,
    subtexel_bits: int = ...,
    interpolation: str = ...,
    filter_error: float = ...,
    linear: str = ...,
    budget: Optional[int] = ...,
    index_width: int = ...,
    max_bytes: int = ...,
    no_mixed_special: bool = ...,
    mips: Union[int, str] = ...,
    threads: Optional[int] = ...,
    work_budget: Optional[int] = ...,
    bake_work_budget: Optional[int] = ...,
    gltf_out: Optional[Union[str, "os.PathLike[str]"]] = ...,
    strict: bool = ...,
) -> BakeResult: ...
def verify(
    alpha: _Alpha,
    uvs: npt.NDArray[np.float32],
    buffers: Optional[BakeResult] = ...,
    *,
    data: Optional[_Buffer] = ...,
    triangles: Optional[_Buffer] = ...,
    indices: Optional[_Buffer] = ...,
    usage: Optional[_Buffer] = ...,
    index_width: Optional[int] = ...,
    filter: str = ...,
    address: Address = ...,
    border_alpha: float = ...,
    cutoff: float = ...,
    opaque_above: bool = ...,
    alpha_factor: float = ...,
    model: str = ...,
    subtexel_bits: int = ...,
    interpolation: str = ...,
    filter_error: float = ...,
    linear: str = ...,
    max_report: int = ...,
    max_checks: Optional[int] = ...,
    lenient_layout: bool = ...,
    record_stride: Optional[int] = ...,
    index_stride: Optional[int] = ...,
    uv_transform: Optional[UvTransformParams] = ...,
) -> VerifyReport: ...
