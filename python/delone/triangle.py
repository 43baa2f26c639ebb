"""Drop-in replacement for the ``triangle`` package (Shewchuk's Triangle).

``import delone.triangle as triangle`` and existing code runs unchanged:
:func:`triangulate` takes the same dictionary (``vertices``,
``vertex_markers``, ``segments``, ``segment_markers``, ``holes``,
``regions``, and for ``r`` the mesh's ``triangles``, ``triangle_attributes``,
``triangle_max_area``) and the same switch letters, and returns a dictionary
with the same keys, shapes and dtypes (``vertices``, ``vertex_markers``,
``triangles``, ``triangle_attributes``, ``segments``, ``segment_markers``,
``holes``, ``regions``, ``neighbors`` with ``n``, ``edges`` and
``edge_markers`` with ``e``).

>>> import delone.triangle as triangle
>>> v = [[0, 0], [0, 1], [1, 1], [1, 0]]
>>> t = triangle.triangulate({'vertices': v}, 'a0.2')
>>> sorted(t)
['triangles', 'vertex_markers', 'vertices']
>>> bool(t['triangles'].shape[0] >= 8)
True

Letters that only choose Triangle's internal algorithm or its console output
(``Q V z X i l F C``) are accepted and have no effect. Vertex attributes are
not interpolated (``vertex_attributes`` is not returned); ``u``, ``s``,
``O``, ``g``, ``v`` and ``o2`` raise :class:`delone.InvalidInput`.
The meshes differ from Triangle's (other Steiner points), but meet the same
switches: minimum angle, maximum area, conformity to the segments.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from . import InvalidInput, _column, _delone, _indices, _points, _rows

__all__ = ["triangulate", "delaunay", "convex_hull", "voronoi", "loads", "load", "get_data", "plot", "compare", "comparev"]

# Letters with no effect on the mesh: algorithm choices and console output.
_IGNORED = set("QVzXilFC")


def _switches(opts: str) -> str:
    return "".join(c for c in opts if c not in _IGNORED)


def _col(a: np.ndarray) -> np.ndarray:
    return a.reshape(-1, 1)


def triangulate(tri: dict, opts: str = "") -> dict:
    """Triangulates ``tri`` with Triangle's switches ``opts`` (see the module
    docs); returns Triangle's output dictionary.

    >>> import delone.triangle as triangle
    >>> A = dict(vertices=[[0, 0], [1, 0], [1, 1], [0, 1]], segments=[[0, 1], [1, 2], [2, 3], [3, 0]])
    >>> B = triangle.triangulate(A, 'pq30a0.05')
    >>> sorted(B)
    ['segment_markers', 'segments', 'triangles', 'vertex_markers', 'vertices']
    """
    if not isinstance(tri, dict) or "vertices" not in tri:
        raise InvalidInput("tri must be a dict with at least 'vertices'")
    sw = _switches(opts)
    pslg, refine = "p" in sw, "r" in sw
    points = _points(tri["vertices"], "vertices", (2,))
    segments = tri.get("segments")
    if refine:
        sw = sw.replace("p", "")
    elif not pslg:
        # Triangle without -p meshes the convex hull of the vertices and
        # ignores the segments.
        sw = "p" + sw + ("" if "c" in sw else "c")
        segments = None
    seg = (
        np.zeros((0, 2), np.int64)
        if segments is None
        else _indices(segments, "segments", 2)
    )
    if pslg and not refine and len(seg) == 0 and "c" not in sw:
        # Without segments nor -c, Triangle's -p carves every triangle away
        # and returns the vertices alone.
        markers = _column(tri.get("vertex_markers"), "vertex_markers", np.int32)
        if markers is None:
            markers = np.zeros(len(points), np.int32)
        return {"vertices": points, "vertex_markers": _col(markers)}
    triangles = tri.get("triangles")
    d = _delone.triangulate(
        points,
        sw,
        seg,
        point_markers=_column(tri.get("vertex_markers"), "vertex_markers", np.int32),
        segment_markers=None
        if segments is None
        else _column(tri.get("segment_markers"), "segment_markers", np.int32),
        holes=_rows(tri.get("holes"), "holes", 2) if pslg else None,
        regions=_rows(tri.get("regions"), "regions", 4) if pslg else None,
        triangles=None if triangles is None else _indices(triangles, "triangles", 3),
        triangle_attributes=_column(
            _first_column(tri.get("triangle_attributes")), "triangle_attributes", np.float64
        ),
        triangle_max_area=_column(tri.get("triangle_max_area"), "triangle_max_area", np.float64),
        edges="e" in sw,
    )
    out = {
        "vertices": d["points"],
        "vertex_markers": _col(d["point_markers"]),
        "triangles": d["triangles"],
    }
    has_regions = tri.get("regions") is not None and len(tri["regions"]) > 0
    if ("A" in sw and has_regions and pslg) or (refine and tri.get("triangle_attributes") is not None):
        out["triangle_attributes"] = _col(d["attributes"])
    if "n" in sw:
        out["neighbors"] = d["neighbors"]
    if pslg or "c" in opts:
        out["segments"] = d["segments"]
        out["segment_markers"] = _col(d["segment_markers"])
    if pslg:
        for k in ("holes", "regions"):
            if tri.get(k) is not None and len(tri[k]) > 0:
                out[k] = np.asarray(tri[k], dtype=np.float64)
    if "e" in sw:
        out["edges"] = d["edges"]
        out["edge_markers"] = _col(d["edge_markers"])
    return out


def _first_column(a: Any) -> Any:
    if a is None:
        return None
    a = np.asarray(a, dtype=np.float64)
    return a[:, 0] if a.ndim == 2 else a


def delaunay(pts: Any) -> np.ndarray:
    """The Delaunay triangles of ``pts`` (int32, ``(m, 3)``).

    >>> import delone.triangle as triangle
    >>> triangle.delaunay([[0, 0], [0, 1], [0.5, 0.5], [1, 1], [1, 0]]).shape
    (4, 3)
    """
    return _delone.delaunay(_points(pts, "pts", (2,)))["simplices"]


def convex_hull(pts: Any) -> np.ndarray:
    """The convex hull's edges (int32, ``(k, 2)``).

    >>> import delone.triangle as triangle
    >>> triangle.convex_hull([[0, 0], [0, 1], [1, 1], [1, 0]]).shape
    (4, 2)
    """
    return _delone.convex_hull(_points(pts, "pts", (2,)))


def voronoi(pts: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The Voronoi diagram as Triangle gives it: ``points`` (the Voronoi
    vertices), the finite ``edges``, and the rays as ``ray_origin`` (vertex
    ids) and ``ray_direct`` (directions).

    >>> import delone.triangle as triangle
    >>> points, edges, ray_origin, ray_direct = triangle.voronoi(
    ...     [[0, 0], [0, 1], [0.5, 0.5], [1, 1], [1, 0]])
    >>> points.shape, edges.shape, ray_origin.shape, ray_direct.shape
    ((4, 2), (4, 2), (4,), (4, 2))
    """
    d = _delone.voronoi(_points(pts, "pts", (2,)), None)
    e = d["edges"]
    finite = e[:, 1] != -1
    return (
        d["vertices"],
        e[finite],
        np.ascontiguousarray(e[~finite][:, 0]),
        d["directions"][~finite],
    )


# ------------------------------------------------------------------ files and pictures


def _tokens(text: str) -> list[list[str]]:
    rows = []
    for line in text.splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            rows.append(line.split())
    return rows


def loads(node: str = "", ele: str = "", poly: str = "", area: str = "", **_: str) -> dict:
    """Reads Triangle's file formats from strings (``.node``, ``.ele``,
    ``.poly``, ``.area``) into a :func:`triangulate` dictionary; indices
    become 0-based.

    >>> import delone.triangle as triangle
    >>> d = triangle.loads(node="3 2 0 0\\n1 0 0\\n2 1 0\\n3 0 1\\n", ele="1 3 0\\n1 1 2 3\\n")
    >>> d["triangles"].tolist()
    [[0, 1, 2]]
    """
    out: dict = {}
    first = 0

    def vertices(rows: list[list[str]]) -> list[list[str]]:
        nonlocal first
        n, _, na, nm = (int(x) for x in (rows[0] + ["0", "0", "0"])[:4])
        body = rows[1 : n + 1]
        if n:
            first = int(body[0][0])
            a = np.array([r[1 : 3 + na + nm] for r in body], dtype=np.float64)
            out["vertices"] = a[:, :2]
            if na:
                out["vertex_attributes"] = a[:, 2 : 2 + na]
            if nm:
                out["vertex_markers"] = a[:, 2 + na :].astype(np.int32)
        return rows[n + 1 :]

    if node:
        vertices(_tokens(node))
    if poly:
        rest = vertices(_tokens(poly))
        m, nm = (int(x) for x in (rest[0] + ["0"])[:2])
        seg = rest[1 : m + 1]
        out["segments"] = np.array([r[1:3] for r in seg], dtype=np.int32).reshape(-1, 2) - first
        if nm:
            out["segment_markers"] = np.array([r[3:4] for r in seg], dtype=np.int32)
        rest = rest[m + 1 :]
        if rest:
            h = int(rest[0][0])
            if h:
                out["holes"] = np.array([r[1:3] for r in rest[1 : h + 1]], dtype=np.float64)
            rest = rest[h + 1 :]
        if rest and int(rest[0][0]):
            r = int(rest[0][0])
            # A row of three numbers is `x y max_area` (as the triangle package reads it).
            out["regions"] = np.array(
                [row[1:5] if len(row) >= 5 else [row[1], row[2], "0", row[3]] for row in rest[1 : r + 1]],
                dtype=np.float64,
            )
    if ele:
        rows = _tokens(ele)
        m, k, na = (int(x) for x in (rows[0] + ["3", "0"])[:3])
        body = rows[1 : m + 1]
        out["triangles"] = np.array([r[1:4] for r in body], dtype=np.int32).reshape(-1, 3) - first
        if na:
            out["triangle_attributes"] = np.array([r[1 + k : 1 + k + na] for r in body], dtype=np.float64)
    if area:
        rows = _tokens(area)
        out["triangle_max_area"] = np.array([r[1] for r in rows[1 : int(rows[0][0]) + 1]], dtype=np.float64)
    return out


def load(directory: str, name: str) -> dict:
    """Reads ``directory/name.{node,ele,poly,area}`` (those that exist)."""
    import os

    texts = {}
    for ext in ("node", "ele", "poly", "area"):
        path = os.path.join(directory, f"{name}.{ext}")
        if os.path.exists(path):
            with open(path) as f:
                texts[ext] = f.read()
    if not texts:
        raise FileNotFoundError(f"no {name}.node/.ele/.poly/.area in {directory}")
    return loads(**texts)


def get_data_dir() -> str:
    """The folder of Triangle's example inputs: the ``triangle`` package's
    data folder (delone does not ship Triangle's example files)."""
    import importlib.util
    import os

    spec = importlib.util.find_spec("triangle")
    if spec is None or spec.origin is None:
        raise FileNotFoundError("Triangle's example data comes with the triangle package: pip install triangle")
    return os.path.join(os.path.dirname(spec.origin), "data")


def get_data(name: str) -> dict:
    """One of Triangle's example inputs by name (``'A'``, ``'face'``,
    ``'double_hex'``, ``'la'``, ...), read with :func:`load`."""
    return load(get_data_dir(), name)


def plot(ax: Any, **kw: Any) -> None:
    """Draws a :func:`triangulate` dictionary on a matplotlib axis:
    triangles, segments, vertices and holes."""
    v = np.asarray(kw["vertices"], dtype=np.float64)
    ax.axes.set_aspect("equal")
    if "triangles" in kw:
        ax.triplot(v[:, 0], v[:, 1], np.asarray(kw["triangles"]), "ko-", lw=0.5, ms=1)
    else:
        ax.scatter(v[:, 0], v[:, 1], s=4, color="k")
    for a, b in np.asarray(kw.get("segments", np.zeros((0, 2), int))):
        ax.plot(v[[a, b], 0], v[[a, b], 1], "b-", lw=1.5)
    h = kw.get("holes")
    if h is not None and len(h):
        h = np.asarray(h, dtype=np.float64)
        ax.scatter(h[:, 0], h[:, 1], s=20, color="r", marker="x")


def compare(plt: Any, A: dict, B: dict, figsize: tuple = (6, 3)) -> None:
    """Draws ``A`` and ``B`` side by side."""
    _, (a, b) = plt.subplots(1, 2, sharex=True, sharey=True, figsize=figsize)
    plot(a, **A)
    plot(b, **B)
    plt.tight_layout()


def comparev(plt: Any, A: dict, B: dict, figsize: tuple = (3, 6)) -> None:
    """Draws ``A`` above ``B``."""
    _, (a, b) = plt.subplots(2, 1, sharex=True, sharey=True, figsize=figsize)
    plot(a, **A)
    plot(b, **B)
    plt.tight_layout()
