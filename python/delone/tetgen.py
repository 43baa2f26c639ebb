"""Drop-in replacement for pyvista's ``tetgen`` package.

``from delone.tetgen import TetGen`` and existing code runs unchanged:
``TetGen(points, faces)`` (or a triangulated ``pyvista.PolyData``), then
``tetrahedralize(**kwargs)`` with the package's main keyword arguments,
returning ``(nodes, elems, attributes, triface_markers)``; ``.grid`` gives a
``pyvista.UnstructuredGrid`` when pyvista is installed.

>>> import numpy as np
>>> from delone.tetgen import TetGen
>>> v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
...               [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
>>> f = np.array([[0, 1, 2], [2, 3, 0], [0, 1, 5], [5, 4, 0], [1, 2, 6], [6, 5, 1],
...               [2, 3, 7], [7, 6, 2], [3, 0, 4], [4, 7, 3], [4, 5, 6], [6, 7, 4]])
>>> nodes, elems, attr, markers = TetGen(v, f).tetrahedralize(mindihedral=20, minratio=1.5)
>>> elems.dtype, elems.shape[1]
(dtype('int32'), 4)

The keyword arguments that change the mesh map to TetGen's switches:
``plc`` (``p``), ``quality`` with ``minratio`` and ``mindihedral``
(``q<minratio>/<mindihedral>``), ``maxvolume`` (``a``), ``fixedvolume`` /
``varvolume`` (``a``, with the regions' volumes), ``nobisect`` (``Y``),
``steinerleft`` (``S``), ``regionattrib`` (``A``), ``convex`` (``c``),
``nomergefacet`` (``M``), ``switches`` (used as given, overriding the
rest). The others tune TetGen's internal algorithms and are accepted without
effect; ``order=2`` (quadratic tetrahedra) raises
:class:`delone.InvalidInput`. Tetrahedra are positively oriented (VTK's
convention), ``triface_markers`` are the boundary faces' markers.
"""

from __future__ import annotations

from typing import Any, Optional, Sequence

import numpy as np

from . import InvalidInput, Mesh, tetrahedralize

__all__ = ["TetGen", "MeshNotTetrahedralizedError"]


class MeshNotTetrahedralizedError(RuntimeError):
    """Raised when the result is read before :meth:`TetGen.tetrahedralize`."""

    def __init__(self, msg: str = "Tetrahedralize the surface mesh first with `tetrahedralize`."):
        super().__init__(msg)


class TetGen:
    """A surface to tetrahedralize: ``TetGen(points, faces[, face_markers])``
    or ``TetGen(polydata)`` (a triangulated ``pyvista.PolyData``)."""

    def __init__(self, arg0: Any, arg1: Any = None, arg2: Any = None) -> None:
        if hasattr(arg0, "points") and hasattr(arg0, "faces"):
            if hasattr(arg0, "is_all_triangles") and not arg0.is_all_triangles:
                raise RuntimeError("Invalid mesh. Must be an all triangular mesh.")
            points = np.asarray(arg0.points, dtype=np.float64)
            faces = np.asarray(arg0.faces).reshape(-1, 4)[:, 1:]
        elif arg1 is not None:
            points, faces = np.asarray(arg0, dtype=np.float64), np.asarray(arg1)
        else:
            raise TypeError("Invalid input. Must be a pyvista.PolyData or points and faces arrays.")
        if points.ndim != 2 or points.shape[1] != 3:
            raise InvalidInput(f"Invalid vertex format. Shape should be (npoints, 3), got {points.shape}")
        if faces.ndim != 2 or faces.shape[1] != 3:
            raise InvalidInput(f"Invalid face format. Shape should be (nfaces, 3), got {faces.shape}")
        if points.shape[0] < 4:
            raise ValueError(
                f"The vertex array should contain at least 4 points. Found {points.shape[0]}."
            )
        self.v = points
        self.f = faces
        self.fmarkers = None if arg2 is None else np.asarray(arg2, dtype=np.int32).reshape(-1)
        self.holes: list[Sequence[float]] = []
        self.regions: list[tuple[int, Sequence[float], float]] = []
        self._result: Optional[Mesh] = None
        self._attributes = False
        self._grid: Any = None

    def add_region(self, id: int, point_in_region: Sequence[float], max_vol: float = 0.0) -> None:
        """Adds a region: the tetrahedra reachable from the point get
        attribute ``id`` (with ``regionattrib``) and volume bound ``max_vol``
        (with ``fixedvolume``/``varvolume``; ``0``: none)."""
        self.regions.append((id, point_in_region, max_vol))

    def add_hole(self, point_in_hole: Sequence[float]) -> None:
        """Adds a hole: the tetrahedra reachable from the point are removed."""
        self.holes.append(point_in_hole)

    def make_manifold(self, verbose: bool = False) -> None:
        """Accepted for compatibility; delone checks the surface itself and
        names a defect (open edge, self-intersection) in its exception."""

    def tetrahedralize(
        self,
        plc: bool = True,
        quality: bool = True,
        minratio: float = 2.0,
        mindihedral: float = 0.0,
        maxvolume: float = -1.0,
        fixedvolume: bool = False,
        varvolume: bool = False,
        nobisect: bool = False,
        steinerleft: Optional[int] = None,
        regionattrib: bool = False,
        convex: bool = False,
        nomergefacet: bool = False,
        order: int = 1,
        switches: str = "",
        verbose: int = 0,
        progress: Any = None,
        **ignored: Any,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Tetrahedralizes the surface; returns ``(nodes, elems, attributes,
        triface_markers)`` (see the module docs for the keyword arguments;
        ``progress=True`` shows a tqdm bar, as ``verbose`` > 0 does)."""
        if order != 1:
            raise InvalidInput("order=2 (quadratic tetrahedra) is not supported")
        if not switches:
            s = "p" if plc else ""
            if quality:
                s += f"q{minratio:g}" + (f"/{mindihedral:g}" if mindihedral > 0 else "")
            if maxvolume > 0:
                s += f"a{maxvolume:g}"
            if fixedvolume or varvolume:
                s += "a"
            if nobisect:
                s += "Y"
            if steinerleft is not None and steinerleft >= 0:
                s += f"S{steinerleft}"
            if regionattrib:
                s += "A"
            if convex:
                s += "c"
            if nomergefacet:
                s += "M"
            switches = s
        switches = "".join(c for c in switches if c not in "QVz")
        regions = (
            np.array([[*p, i, v] for i, p, v in self.regions], dtype=np.float64)
            if self.regions
            else None
        )
        holes = np.array(self.holes, dtype=np.float64) if self.holes else None
        self._result = tetrahedralize(
            self.v,
            self.f,
            switches,
            face_markers=self.fmarkers,
            holes=holes,
            regions=regions,
            progress=progress if progress is not None else (verbose > 0 or None),
        )
        self._grid = None
        self._attributes = "A" in switches and bool(self.regions)
        return self.node, self.elem, self.attributes, self.triface_markers

    def _mesh(self) -> Mesh:
        if self._result is None:
            raise MeshNotTetrahedralizedError
        return self._result

    @property
    def is_tetrahedralized(self) -> bool:
        """True once :meth:`tetrahedralize` has run."""
        return self._result is not None

    @property
    def node(self) -> np.ndarray:
        """The mesh's points, ``(n, 3)`` float64."""
        return self._mesh().points

    @property
    def elem(self) -> np.ndarray:
        """The tetrahedra, ``(m, 4)`` int32."""
        return self._mesh().elements

    @property
    def attributes(self) -> np.ndarray:
        """The regional attribute of every tetrahedron, ``(m, 1)`` float64,
        when regions were given with ``regionattrib``; ``(0, 0)`` otherwise."""
        m = self._mesh()
        if not self._attributes:
            return np.zeros((0, 0))
        return m.attributes.reshape(-1, 1)

    @property
    def trifaces(self) -> np.ndarray:
        """The boundary (and internal facet) triangles, ``(k, 3)`` int32."""
        return self._mesh().boundary

    @property
    def triface_markers(self) -> np.ndarray:
        """The markers of :attr:`trifaces`, ``(k,)`` int32."""
        return self._mesh().boundary_markers

    @property
    def mesh(self) -> Any:
        """The input surface as a ``pyvista.PolyData`` (needs pyvista)."""
        import pyvista as pv

        f = np.hstack([np.full((len(self.f), 1), 3), self.f]).ravel()
        return pv.PolyData(self.v, f)

    @property
    def grid(self) -> Any:
        """The tetrahedral mesh as a ``pyvista.UnstructuredGrid`` (needs pyvista)."""
        if self._grid is None:
            import pyvista as pv

            e = self.elem
            cells = np.hstack([np.full((len(e), 1), 4, e.dtype), e]).ravel()
            types = np.full(len(e), pv.CellType.TETRA, np.uint8)
            self._grid = pv.UnstructuredGrid(cells, types, self.node)
        return self._grid

    def write(self, filename: str, binary: bool = True) -> None:
        """Writes the mesh with pyvista (``.vtk``, ``.vtu``)."""
        self.grid.save(filename, binary)
