"""Type stubs of the native module (crates/delone-py). Use the wrappers in
:mod:`delone`, which accept any array-like and check shapes and dtypes."""

from typing import Any, Callable, Optional

import numpy as np
import numpy.typing as npt

F64 = npt.NDArray[np.float64]
I32 = npt.NDArray[np.int32]
I64 = npt.NDArray[np.int64]
Progress = Optional[Callable[[str, int, Optional[int], str], Any]]

class InvalidInput(ValueError): ...
class MeshingError(RuntimeError): ...

def delaunay(points: F64, weights: Optional[F64] = None) -> dict[str, I32]: ...
def convex_hull(points: F64) -> I32: ...
def voronoi(points: F64, weights: Optional[F64] = None) -> dict[str, npt.NDArray[Any]]: ...
def triangulate(
    points: F64,
    switches: str,
    segments: I64,
    point_markers: Optional[I32] = None,
    segment_markers: Optional[I32] = None,
    holes: Optional[F64] = None,
    regions: Optional[F64] = None,
    triangles: Optional[I64] = None,
    triangle_attributes: Optional[F64] = None,
    triangle_max_area: Optional[F64] = None,
    edges: bool = False,
    progress: Progress = None,
) -> dict[str, Any]: ...
def tetrahedralize(
    points: F64,
    face_vertices: I64,
    face_offsets: I64,
    switches: str,
    face_markers: Optional[I32] = None,
    holes: Optional[F64] = None,
    regions: Optional[F64] = None,
    progress: Progress = None,
) -> dict[str, Any]:
    """Keys ``points``, ``tetrahedra``, ``neighbors``, ``faces``,
    ``face_markers``, ``attributes``, ``regions`` and ``quality``: the final
    mesh's statistics (``tetrahedra``, ``min_dihedral``, ``max_dihedral``,
    radius-edge ratios, volumes, edge lengths) and ``optimization_stages``,
    a list of dicts shaped like :class:`delone.OptimizationStage`."""
    ...

def adapt(
    points: F64,
    elements: I64,
    metric: Optional[F64] = None,
    faces: Optional[I64] = None,
    face_markers: Optional[I32] = None,
    element_markers: Optional[I32] = None,
    corners: Optional[I64] = None,
    required: Optional[I64] = None,
    ridges: Optional[I64] = None,
    hmin: Optional[float] = None,
    hmax: Optional[float] = None,
    hgrad: Optional[float] = None,
    insert: bool = True,
    swap: bool = True,
    smooth: bool = True,
    max_passes: int = 30,
    max_vertices: Optional[int] = None,
    progress: Progress = None,
) -> dict[str, Any]: ...
def metric_from_field(
    points: F64,
    elements: I64,
    values: F64,
    complexity: Optional[float] = None,
    error: Optional[float] = None,
    p: float = 2.0,
    hmin: float = 1e-12,
    hmax: float = 1e12,
    hgrad: Optional[float] = None,
) -> F64: ...
def metric_stats(points: F64, elements: I64, metric: F64) -> dict[str, Any]: ...
