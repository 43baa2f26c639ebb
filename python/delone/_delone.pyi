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
) -> dict[str, Any]: ...
