"""delone: robust, fast Delaunay triangulation and quality meshing in 2D and 3D.

numpy arrays in and out: float64 coordinates, int32 indices (``-1`` for
"none"). Every function works in 2D or 3D by the shape of ``points``
(``(n, 2)`` or ``(n, 3)``).

>>> import numpy as np, delone
>>> pts = np.array([[0, 0], [1, 0], [0, 1], [1, 1]], dtype=float)
>>> delone.delaunay(pts).simplices.shape
(2, 3)
>>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
>>> m = delone.triangulate(square, [[0, 1], [1, 2], [2, 3], [3, 0]], switches="pq30a0.01")
>>> m.quality["min_angle"] >= 30
True

The meshers run on a worker thread with the GIL released; Ctrl-C stops
them (``KeyboardInterrupt``), and ``progress=`` takes a callback
``f(stage, done, total, unit)`` or ``True`` for a tqdm bar. Invalid input
raises :class:`InvalidInput` (a ``ValueError``) naming the offending item;
other failures raise :class:`MeshingError`.

Drop-in modules: :mod:`delone.triangle` (the ``triangle`` package's API) and
:mod:`delone.tetgen` (``tetgen.TetGen``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Optional, Sequence, Tuple, TypedDict, Union

import numpy as np

from . import _delone
from ._delone import InvalidInput, MeshingError

try:
    from importlib.metadata import version as _version

    __version__ = _version("delone")
except Exception:  # not installed as a distribution (a source checkout)
    __version__ = "unknown"

__all__ = [
    "InvalidInput",
    "MeshingError",
    "Triangulation",
    "Voronoi",
    "Mesh",
    "OptimizationStage",
    "delaunay",
    "regular",
    "voronoi",
    "convex_hull",
    "triangulate",
    "tetrahedralize",
    "Adapted",
    "adapt",
    "metric_from_field",
    "metric_stats",
]

Progress = Union[None, bool, Callable[[str, int, Optional[int], str], Any]]


# ------------------------------------------------------------------ input


def _points(points: Any, name: str = "points", dims: Sequence[int] = (2, 3)) -> np.ndarray:
    try:
        a = np.ascontiguousarray(points, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise InvalidInput(f"{name} must be an array of numbers: {e}") from None
    if a.ndim != 2 or a.shape[1] not in dims:
        want = " or ".join(f"(n, {d})" for d in dims)
        raise InvalidInput(f"{name} must be an {want} array, got shape {a.shape}")
    return a


def _indices(x: Any, name: str, width: Optional[int] = None) -> np.ndarray:
    """An int64 array of indices; floats must hold whole numbers."""
    try:
        a = np.asarray(x)
    except (TypeError, ValueError) as e:
        raise InvalidInput(f"{name} must be an array of indices: {e}") from None
    if a.size == 0:
        a = a.reshape(0, width) if width else a.reshape(0)
    if a.dtype.kind == "f":
        if not np.all(np.isfinite(a)) or np.any(a != np.round(a)):
            raise InvalidInput(f"{name} must hold whole numbers")
    elif a.dtype.kind not in "iub":
        raise InvalidInput(f"{name} must be an integer array, got dtype {a.dtype}")
    a = np.ascontiguousarray(a, dtype=np.int64)
    if width is not None and (a.ndim != 2 or a.shape[1] != width):
        raise InvalidInput(f"{name} must be an (m, {width}) array, got shape {a.shape}")
    return a


def _column(x: Any, name: str, dtype: Any) -> Optional[np.ndarray]:
    if x is None:
        return None
    try:
        return np.ascontiguousarray(np.asarray(x).reshape(-1), dtype=dtype)
    except (TypeError, ValueError) as e:
        raise InvalidInput(f"{name}: {e}") from None


def _rows(x: Any, name: str, width: int) -> Optional[np.ndarray]:
    if x is None:
        return None
    a = np.asarray(x, dtype=np.float64)
    if a.size == 0:
        return None
    return _points(a, name, (width,))


def _progress(progress: Progress) -> tuple[Optional[Callable[..., Any]], Callable[[], None]]:
    """The callback for the native module and a function that closes it."""
    if progress is None or progress is False:
        return None, lambda: None
    if callable(progress):
        return progress, lambda: None
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return None, lambda: None
    bars: dict[str, Any] = {}

    def update(stage: str, done: int, total: Optional[int], unit: str) -> None:
        bar = bars.get("bar")
        if bar is None or bars.get("stage") != stage:
            if bar is not None:
                bar.close()
            bar = tqdm(total=total, desc=stage, unit=f" {unit}", leave=False)
            bars.update(bar=bar, stage=stage)
        bar.n = done
        bar.refresh()

    def close() -> None:
        if bars.get("bar") is not None:
            bars["bar"].close()

    return update, close


# ------------------------------------------------------------------ results


@dataclass
class Triangulation:
    """A Delaunay or regular triangulation (2D) or tetrahedralization (3D).

    ``simplices[i]`` are the vertex ids of simplex ``i`` (counterclockwise
    triangles, positively oriented tetrahedra); ``neighbors[i][k]`` is the
    simplex across the face opposite vertex ``k`` (``-1`` on the hull).
    ``duplicates`` lists ``(duplicate, original)`` input points that were
    merged; ``hidden`` the points a regular triangulation leaves out.
    """

    points: np.ndarray
    simplices: np.ndarray
    neighbors: np.ndarray
    duplicates: np.ndarray
    hidden: np.ndarray

    @property
    def dim(self) -> int:
        """2 or 3."""
        return int(self.points.shape[1])


@dataclass
class Voronoi:
    """A Voronoi (or power) diagram.

    ``vertices`` are the circumcentres of the Delaunay simplices; ``edges``
    join two vertices, or are rays from ``edges[i, 0]`` along
    ``directions[i]`` when ``edges[i, 1] == -1``. ``edge_sites`` are the input
    points whose cells share the edge (2 in 2D, 3 in 3D). In 3D the faces
    (one per Delaunay edge, between the two ``face_sites``) are
    ``face_vertices[face_offsets[f]:face_offsets[f + 1]]``; empty in 2D.
    """

    points: np.ndarray
    vertices: np.ndarray
    edges: np.ndarray
    directions: np.ndarray
    edge_sites: np.ndarray
    face_offsets: np.ndarray = field(default_factory=lambda: np.zeros(1, np.int32))
    face_vertices: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int32))
    face_sites: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), np.int32))

    def face(self, f: int) -> np.ndarray:
        """The vertex ids of 3D face ``f`` (in order around it)."""
        return self.face_vertices[self.face_offsets[f] : self.face_offsets[f + 1]]


class OptimizationStage(TypedDict):
    """One stage of the optimisation that follows 3D refinement (an entry of
    ``Mesh.quality["optimization_stages"]``).

    ``threshold``: the stage works on the tetrahedra with a dihedral angle
    below it or above ``180 -`` it (degrees). ``second_run``: a stage of the
    second run of a small mesh. ``evaluations``: the quality evaluations it
    spent, ``undone_evaluations`` of them in trial insertions that were
    undone, and ``worst_reached`` of them until its worst angle last rose
    (the rest went to the tetrahedra above the worst, or to tries that
    failed). ``attempts`` and ``successes``: its tries. ``worst``: the mesh's
    worst angle (the smaller of its smallest dihedral angle and 180° minus
    its largest) at the stage's start and end; ``below``: the tetrahedra
    below its threshold at its start and end. ``stop``: why it ended
    (``"nothing left to improve"``, ``"attempts spent"``, ``"stopped
    paying"``, ``"effort budget spent"`` or ``"interrupted"``).
    """

    threshold: float
    second_run: bool
    evaluations: int
    undone_evaluations: int
    worst_reached: int
    attempts: int
    successes: int
    worst: Tuple[float, float]
    below: Tuple[int, int]
    stop: str


@dataclass
class Mesh:
    """The result of :func:`triangulate` or :func:`tetrahedralize`.

    ``elements``: triangles ``(m, 3)`` or tetrahedra ``(m, 4)``; ``neighbors``
    as in :class:`Triangulation`. ``boundary``: the segments (2D, pieces of
    the input segments) or faces (3D, boundary and internal facets' triangles)
    with ``boundary_markers``. ``attributes`` and ``regions`` are per element
    (the regional attribute, and the index of the region or ``-1``).
    ``point_markers``: Triangle's vertex markers (2D; empty in 3D).
    ``quality``: minimum/maximum angles, areas or volumes, edge lengths; in
    3D also ``optimization_stages``, the stages of the optimisation
    (a list of :class:`OptimizationStage`; empty when it did not run).
    """

    points: np.ndarray
    elements: np.ndarray
    neighbors: np.ndarray
    boundary: np.ndarray
    boundary_markers: np.ndarray
    attributes: np.ndarray
    regions: np.ndarray
    quality: dict
    point_markers: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int32))
    edges: Optional[np.ndarray] = None
    edge_markers: Optional[np.ndarray] = None

    @property
    def dim(self) -> int:
        """2 or 3."""
        return int(self.points.shape[1])

    def to_meshio(self) -> Any:
        """The mesh as a ``meshio.Mesh`` (needs ``pip install meshio``), with
        the attributes and regions as cell data and the boundary markers on
        the boundary cells."""
        import meshio

        kind, bkind = ("triangle", "line") if self.dim == 2 else ("tetra", "triangle")
        cells = [(kind, self.elements), (bkind, self.boundary)]
        nb = len(self.boundary)
        return meshio.Mesh(
            self.points,
            cells,
            cell_data={
                "attribute": [self.attributes, np.zeros(nb)],
                "region": [self.regions, np.full(nb, -1, np.int32)],
                "marker": [np.zeros(len(self.elements), np.int32), self.boundary_markers],
            },
        )


# ------------------------------------------------------------------ point sets


def delaunay(points: Any) -> Triangulation:
    """Delaunay triangulation (``(n, 2)`` points) or tetrahedralization
    (``(n, 3)``). Duplicate points are merged (see ``duplicates``); NaN,
    fewer than 3 (4) points or all points collinear (coplanar) raise
    :class:`InvalidInput`.

    >>> import numpy as np, delone
    >>> t = delone.delaunay(np.random.default_rng(1).random((100, 3)))
    >>> t.simplices.dtype, t.simplices.shape[1]
    (dtype('int32'), 4)
    """
    p = _points(points)
    d = _delone.delaunay(p)
    return Triangulation(p, d["simplices"], d["neighbors"], d["duplicates"], d["hidden"])


def regular(points: Any, weights: Any) -> Triangulation:
    """Regular (weighted Delaunay) triangulation: points whose power cell is
    empty are left out (``hidden``). Zero weights give :func:`delaunay`.

    >>> import numpy as np, delone
    >>> p = np.array([[0, 0], [1, 0], [0, 1], [1, 1], [0.5, 0.5]])
    >>> delone.regular(p, [0, 0, 0, 0, -1]).hidden.tolist()
    [4]
    """
    p = _points(points)
    w = _column(weights, "weights", np.float64)
    d = _delone.delaunay(p, w)
    return Triangulation(p, d["simplices"], d["neighbors"], d["duplicates"], d["hidden"])


def voronoi(points: Any, weights: Any = None) -> Voronoi:
    """Voronoi diagram (with ``weights``: power diagram) in 2D or 3D.

    >>> import numpy as np, delone
    >>> v = delone.voronoi(np.array([[0, 0], [1, 0], [0, 1], [1, 1], [0.5, 0.5]]))
    >>> len(v.vertices), int((v.edges[:, 1] == -1).sum())
    (4, 4)
    """
    p = _points(points)
    d = _delone.voronoi(p, _column(weights, "weights", np.float64))
    return Voronoi(p, **d)


def convex_hull(points: Any) -> np.ndarray:
    """The convex hull: its edges ``(k, 2)`` in 2D (counterclockwise around
    the hull), its triangles ``(k, 3)`` in 3D (counterclockwise seen from
    outside), as int32 indices into ``points``.

    >>> import numpy as np, delone
    >>> len(delone.convex_hull(np.array([[0, 0], [1, 0], [0, 1], [1, 1], [0.5, 0.5]])))
    4
    """
    return _delone.convex_hull(_points(points))


# ------------------------------------------------------------------ meshing


def triangulate(
    points: Any,
    segments: Any = None,
    switches: str = "pq",
    *,
    holes: Any = None,
    regions: Any = None,
    point_markers: Any = None,
    segment_markers: Any = None,
    triangles: Any = None,
    triangle_attributes: Any = None,
    triangle_max_area: Any = None,
    edges: bool = False,
    progress: Progress = None,
) -> Mesh:
    """Constrained (quality) triangulation of a planar straight-line graph.

    ``switches`` are Triangle's (``p`` PSLG, ``q[angle]``, ``a[area]``,
    ``c`` keep the convex hull, ``A`` regional attributes, ``D``, ``Y``,
    ``S[n]``, ``e`` edges). Without ``segments`` the convex hull of the points
    is meshed. ``holes``: ``(h, 2)`` points inside holes; ``regions``:
    ``(r, 4)`` rows ``x, y, attribute, max_area`` (``max_area <= 0``: none).
    With ``r`` the mesh given by ``points`` and counterclockwise ``triangles``
    is refined (``triangle_max_area``: per-triangle bounds for ``a``;
    ``segments``, if any, must be edges of it).

    >>> import numpy as np, delone
    >>> square = [[0, 0], [1, 0], [1, 1], [0, 1]]
    >>> m = delone.triangulate(square, [[0, 1], [1, 2], [2, 3], [3, 0]], "pq30a0.01")
    >>> m.elements.shape[1], bool(m.quality["max_area"] <= 0.01)
    (3, True)
    """
    p = _points(points, dims=(2,))
    if segments is None:
        seg = np.zeros((0, 2), np.int64)
        if "c" not in switches and "r" not in switches:
            switches += "c"
    else:
        seg = _indices(segments, "segments", 2)
    cb, close = _progress(progress)
    try:
        d = _delone.triangulate(
            p,
            switches,
            seg,
            point_markers=_column(point_markers, "point_markers", np.int32),
            segment_markers=_column(segment_markers, "segment_markers", np.int32),
            holes=_rows(holes, "holes", 2),
            regions=_rows(regions, "regions", 4),
            triangles=None if triangles is None else _indices(triangles, "triangles", 3),
            triangle_attributes=_column(triangle_attributes, "triangle_attributes", np.float64),
            triangle_max_area=_column(triangle_max_area, "triangle_max_area", np.float64),
            edges=edges,
            progress=cb,
        )
    finally:
        close()
    return _mesh2(d)


def _mesh2(d: dict) -> Mesh:
    return Mesh(
        points=d["points"],
        elements=d["triangles"],
        neighbors=d["neighbors"],
        boundary=d["segments"],
        boundary_markers=d["segment_markers"],
        attributes=d["attributes"],
        regions=d["regions"],
        quality=d["quality"],
        point_markers=d["point_markers"],
        edges=d.get("edges"),
        edge_markers=d.get("edge_markers"),
    )


def _faces(faces: Any) -> tuple[np.ndarray, np.ndarray]:
    """Faces (an ``(m, k)`` array or a list of polygons) as flat vertex ids
    and offsets."""
    if isinstance(faces, np.ndarray) or (
        len(faces) > 0 and len({len(f) for f in faces}) == 1
    ):
        a = _indices(faces, "faces")
        if a.ndim != 2:
            raise InvalidInput(f"faces must be an (m, k) array, got shape {a.shape}")
        m, k = a.shape
        return a.reshape(-1), np.arange(0, m * k + 1, max(k, 1), dtype=np.int64)[: m + 1]
    polys = [_indices(f, f"face {i}").reshape(-1) for i, f in enumerate(faces)]
    offsets = np.zeros(len(polys) + 1, np.int64)
    offsets[1:] = np.cumsum([len(f) for f in polys])
    flat = np.concatenate(polys) if polys else np.zeros(0, np.int64)
    return flat, offsets


def tetrahedralize(
    points: Any,
    faces: Any,
    switches: str = "pq1.414",
    *,
    face_markers: Any = None,
    holes: Any = None,
    regions: Any = None,
    progress: Progress = None,
) -> Mesh:
    """Tetrahedral mesh of the inside of a closed surface or PLC.

    ``faces``: an ``(m, 3)`` triangle array or a list of polygons (facets).
    ``switches`` are TetGen's (``p``, ``q[ratio][/dihedral]``, ``a[volume]``,
    ``Y`` keep the surface, ``A`` regions, ``c`` convex hull, ``O`` ...).
    ``holes``: ``(h, 3)``; ``regions``: ``(r, 5)`` rows
    ``x, y, z, attribute, max_volume`` (``max_volume <= 0``: none).
    An open or self-intersecting surface raises :class:`InvalidInput`.

    >>> import numpy as np, delone
    >>> cube = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], float)
    >>> quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
    >>> m = delone.tetrahedralize(cube, quads, "pq1.414a0.01")
    >>> abs(m.quality["total_volume"] - 1.0) < 1e-9
    True
    """
    p = _points(points, dims=(3,))
    fv, fo = _faces(faces)
    if "p" not in switches:
        switches = "p" + switches
    cb, close = _progress(progress)
    try:
        d = _delone.tetrahedralize(
            p,
            fv,
            fo,
            switches,
            face_markers=_column(face_markers, "face_markers", np.int32),
            holes=_rows(holes, "holes", 3),
            regions=_rows(regions, "regions", 5),
            progress=cb,
        )
    finally:
        close()
    return Mesh(
        points=d["points"],
        elements=d["tetrahedra"],
        neighbors=d["neighbors"],
        boundary=d["faces"],
        boundary_markers=d["face_markers"],
        attributes=d["attributes"],
        regions=d["regions"],
        quality=d["quality"],
    )


# ------------------------------------------------------------------ adaptation


@dataclass
class Adapted:
    """The result of :func:`adapt`.

    ``elements``: triangles ``(m, 3)`` or tetrahedra ``(m, 4)`` with their
    ``element_markers`` (references, kept from the input); ``faces``: the
    boundary and interface edges (2D) or triangles (3D) with
    ``face_markers``; ``metric``: the metric at each output point, ``(n, 3)``
    in 2D and ``(n, 6)`` in 3D, in Medit's order (``m11 m12 m22`` and
    ``m11 m12 m22 m13 m23 m33``); ``report``: edge lengths and element
    quality in the metric ``before`` and ``after`` (dicts), operation counts
    and the time per phase.
    """

    points: np.ndarray
    elements: np.ndarray
    element_markers: np.ndarray
    faces: np.ndarray
    face_markers: np.ndarray
    metric: np.ndarray
    report: dict

    @property
    def dim(self) -> int:
        """2 or 3."""
        return int(self.points.shape[1])


def _metric(metric: Any, n: int) -> np.ndarray:
    try:
        a = np.asarray(metric, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise InvalidInput(f"metric must be an array of numbers: {e}") from None
    if a.ndim == 1:
        a = a.reshape(-1, 1)
    if a.ndim != 2 or a.shape[0] != n:
        raise InvalidInput(f"metric must have one row per point ({n}), got shape {a.shape}")
    return np.ascontiguousarray(a)


def adapt(
    points: Any,
    elements: Any,
    metric: Any = None,
    *,
    hsiz: Optional[float] = None,
    faces: Any = None,
    face_markers: Any = None,
    element_markers: Any = None,
    corners: Any = None,
    required: Any = None,
    ridges: Any = None,
    hmin: Optional[float] = None,
    hmax: Optional[float] = None,
    hgrad: Optional[float] = 1.3,
    insert: bool = True,
    swap: bool = True,
    smooth: bool = True,
    max_passes: int = 30,
    max_vertices: Optional[int] = None,
    progress: Progress = None,
) -> Adapted:
    """Adapts a triangle mesh (``points`` ``(n, 2)``, ``elements`` ``(m, 3)``)
    or a tetrahedral mesh (``(n, 3)``, ``(m, 4)``) to a metric at its points,
    so that its edges have unit length and its elements are regular in the
    metric.

    ``metric``: a size per point ``(n,)`` (isotropic), or a symmetric tensor
    per point in Medit's order (``(n, 3)`` in 2D, ``(n, 6)`` in 3D); or
    ``hsiz``, one size everywhere; with neither, each point's mean incident
    edge length, bounded by ``hmin``/``hmax`` (as MMG without a metric). The
    boundary is kept: ``faces`` (edges in 2D, triangles in 3D) with
    ``face_markers``, ``corners`` and ``required`` points that never move,
    ``ridges`` (3D feature edges). ``hmin``/``hmax`` bound the sizes,
    ``hgrad`` limits their growth along edges (``None``: off);
    ``insert``/``swap``/``smooth`` turn operations off (MMG's
    ``-noinsert``/``-noswap``/``-nomove``).

    >>> import numpy as np, delone
    >>> g = np.linspace(0.0, 1.0, 5)
    >>> pts = np.array([[x, y] for y in g for x in g])
    >>> tri = delone.delaunay(pts).simplices
    >>> a = delone.adapt(pts, tri, np.full(len(pts), 0.05))
    >>> a.report["after"]["in_range_share"] > 0.8
    True
    >>> v = a.points[a.elements]
    >>> u, w = v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]
    >>> areas = 0.5 * (u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0])
    >>> bool(areas.min() > 0 and abs(areas.sum() - 1.0) < 1e-12)
    True
    """
    p = _points(points)
    d = p.shape[1]
    e = _indices(elements, "elements", d + 1)
    f = None if faces is None else _indices(faces, "faces", d)
    r = None if ridges is None else _indices(ridges, "ridges", 2)
    if metric is not None and hsiz is not None:
        raise InvalidInput("give metric= or hsiz=, not both")
    if hsiz is not None:
        metric = np.full(len(p), float(hsiz))
    cb, close = _progress(progress)
    try:
        out = _delone.adapt(
            p,
            e,
            None if metric is None else _metric(metric, len(p)),
            f,
            _column(face_markers, "face_markers", np.int32),
            _column(element_markers, "element_markers", np.int32),
            None if corners is None else _indices(corners, "corners").reshape(-1),
            None if required is None else _indices(required, "required").reshape(-1),
            r,
            hmin,
            hmax,
            hgrad,
            insert,
            swap,
            smooth,
            max_passes,
            max_vertices,
            cb,
        )
    finally:
        close()
    return Adapted(**out)


def metric_from_field(
    points: Any,
    elements: Any,
    values: Any,
    *,
    complexity: Optional[float] = None,
    error: Optional[float] = None,
    p: float = 2.0,
    hmin: float = 1e-12,
    hmax: float = 1e12,
    hgrad: Optional[float] = None,
) -> np.ndarray:
    """The metric that minimises the interpolation error of a scalar field
    given at the points of a triangle or tetrahedral mesh: its Hessian
    (recovered by least-squares fits), scaled for a ``complexity`` (about
    the number of vertices) in the L^``p`` norm or for an ``error`` level,
    bounded by ``hmin``/``hmax``, optionally graded (``hgrad``). Returns
    ``(n, 3)`` or ``(n, 6)`` tensors in Medit's order, for :func:`adapt`.

    >>> import numpy as np, delone
    >>> g = np.linspace(0.0, 1.0, 11)
    >>> pts = np.array([[x, y] for y in g for x in g])
    >>> tri = delone.delaunay(pts).simplices
    >>> m = delone.metric_from_field(pts, tri, np.tanh(10 * (pts[:, 0] - 0.5)), complexity=200)
    >>> m.shape
    (121, 3)
    """
    pts = _points(points)
    e = _indices(elements, "elements", pts.shape[1] + 1)
    v = _column(values, "values", np.float64)
    return _delone.metric_from_field(pts, e, v, complexity, error, p, hmin, hmax, hgrad)


def metric_stats(points: Any, elements: Any, metric: Any) -> dict:
    """Edge lengths and element quality (mean ratio, 1 for the regular
    simplex) of a mesh in a metric given at its points (sizes ``(n,)`` or
    tensors in Medit's order): counts, ``length_min/max/mean``,
    ``in_range`` and ``in_range_share`` (edges with length in
    [1/√2, √2]), ``quality_min/mean`` and histograms.

    >>> import numpy as np, delone
    >>> s = delone.metric_stats([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [1.0, 1.0, 1.0])
    >>> s["edges"], s["in_range"]
    (3, 3)
    """
    pts = _points(points)
    e = _indices(elements, "elements", pts.shape[1] + 1)
    return _delone.metric_stats(pts, e, _metric(metric, len(pts)))
