"""delone.tetgen.TetGen against pyvista's `tetgen` package: same return
values, shapes and dtypes; meshes that conform and meet the bounds."""

import numpy as np
import pytest

from conftest import CUBE, CUBE_TRIS, volumes
from delone import InvalidInput
from delone.tetgen import MeshNotTetrahedralizedError, TetGen


def icosphere(levels=2):
    """A closed triangulated sphere (outward-oriented)."""
    t = (1 + 5**0.5) / 2
    v = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
         [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]]
    f = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
         [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8],
         [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]]
    v = [np.array(p, float) / np.linalg.norm(p) for p in v]
    for _ in range(levels):
        mid, nf = {}, []

        def m(a, b):
            k = (min(a, b), max(a, b))
            if k not in mid:
                p = v[a] + v[b]
                v.append(p / np.linalg.norm(p))
                mid[k] = len(v) - 1
            return mid[k]

        for a, b, c in f:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            nf += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        f = nf
    return np.array(v), np.array(f)


SURFACES = {"cube": (CUBE, CUBE_TRIS), "sphere": icosphere(2)}


def min_dihedral(p, t):
    """The smallest dihedral angle (degrees), computed here independently."""
    best = 180.0
    for i, j in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]:
        k, l = [x for x in range(4) if x not in (i, j)]
        a, b, c, d = p[t[:, i]], p[t[:, j]], p[t[:, k]], p[t[:, l]]
        e = b - a
        n1, n2 = np.cross(e, c - a), np.cross(e, d - a)
        cos = (n1 * n2).sum(1) / np.linalg.norm(n1, axis=1) / np.linalg.norm(n2, axis=1)
        best = min(best, np.degrees(np.arccos(np.clip(cos, -1, 1))).min())
    return best


@pytest.mark.parametrize("name", sorted(SURFACES))
def test_mindihedral_minratio_call(name):
    v, f = SURFACES[name]
    tg = TetGen(v, f)
    nodes, elems, attr, markers = tg.tetrahedralize(order=1, mindihedral=20, minratio=1.5)
    assert nodes.dtype == np.float64 and elems.dtype == np.int32 and markers.dtype == np.int32
    assert attr.shape == (0, 0)
    vol = volumes(nodes, elems)
    assert (vol > 0).all()
    # Conforms: the enclosed volume is the surface's (divergence theorem).
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    enclosed = abs(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6)
    assert vol.sum() == pytest.approx(enclosed, rel=1e-9)
    assert min_dihedral(nodes, elems) >= 20 - 1e-6
    assert len(tg.trifaces) == len(markers)


@pytest.mark.parametrize("name", sorted(SURFACES))
def test_same_returns_as_tetgen(name):
    tetgen = pytest.importorskip("tetgen")
    v, f = SURFACES[name]
    ours = TetGen(v, f).tetrahedralize(order=1, mindihedral=20, minratio=1.5)
    theirs = tetgen.TetGen(v, f).tetrahedralize(order=1, mindihedral=20, minratio=1.5, quiet=True)
    assert len(ours) == len(theirs) == 4
    for a, b in zip(ours, theirs):
        assert a.dtype == b.dtype and a.ndim == b.ndim
        assert a.shape[1:] == b.shape[1:]


def test_regions_holes_and_switches():
    v, f = CUBE, CUBE_TRIS
    tg = TetGen(v, f)
    tg.add_region(7, [0.5, 0.5, 0.5], 0.01)
    nodes, elems, attr, _ = tg.tetrahedralize(regionattrib=True, fixedvolume=True)
    assert attr.shape == (len(elems), 1) and (attr == 7).all()
    assert volumes(nodes, elems).max() <= 0.01
    tetgen = pytest.importorskip("tetgen")
    theirs = tetgen.TetGen(v, f)
    theirs.add_region(7, [0.5, 0.5, 0.5], 0.01)
    r = theirs.tetrahedralize(regionattrib=True, quiet=True)
    assert r[2].shape[1:] == attr.shape[1:] and r[2].dtype == attr.dtype


def test_switches_override_and_nobisect():
    tg = TetGen(*SURFACES["sphere"])
    nodes, elems, _, markers = tg.tetrahedralize(switches="pq1.2/10Y")
    # -Y keeps the surface: every boundary face is an input triangle.
    surf = {tuple(sorted(t)) for t in SURFACES["sphere"][1]}
    assert {tuple(sorted(t)) for t in tg.trifaces} == surf
    nodes, elems, _, _ = tg.tetrahedralize(nobisect=True, quality=True, minratio=1.1, mindihedral=10)
    assert len(elems) > 0


def test_errors():
    with pytest.raises(MeshNotTetrahedralizedError):
        TetGen(CUBE, CUBE_TRIS).elem
    with pytest.raises(InvalidInput, match="not closed"):
        TetGen(CUBE, CUBE_TRIS[:-1]).tetrahedralize()
    with pytest.raises(InvalidInput):
        TetGen(CUBE, CUBE_TRIS).tetrahedralize(order=2)
    with pytest.raises(ValueError):
        TetGen(CUBE[:3], CUBE_TRIS[:1])


def test_grid_with_pyvista():
    pv = pytest.importorskip("pyvista")
    tg = TetGen(CUBE, CUBE_TRIS)
    tg.tetrahedralize()
    assert isinstance(tg.grid, pv.UnstructuredGrid) and tg.grid.n_cells == len(tg.elem)
