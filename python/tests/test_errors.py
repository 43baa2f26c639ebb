"""Bad input raises delone.InvalidInput (a ValueError) naming the item; never a crash."""

import numpy as np
import pytest

import delone
from conftest import CUBE, CUBE_QUADS, SQUARE, SQUARE_SEGS

BAD = [
    ("nan point", lambda: delone.delaunay([[0, 0], [1, np.nan], [0, 1]]), "point 1"),
    ("inf point", lambda: delone.delaunay([[0, 0, 0], [1, 0, 0], [0, np.inf, 0], [0, 0, 1]]), "point 2"),
    ("empty", lambda: delone.delaunay([]), "shape"),
    ("empty 2d", lambda: delone.delaunay(np.zeros((0, 2))), "point"),
    ("wrong width", lambda: delone.delaunay(np.zeros((5, 4))), "(n, 2) or (n, 3)"),
    ("strings", lambda: delone.delaunay([["a", "b"]]), "numbers"),
    ("too few", lambda: delone.delaunay([[0, 0], [1, 1]]), "point"),
    ("collinear", lambda: delone.delaunay([[0, 0], [1, 1], [2, 2]]), "collinear"),
    ("coplanar", lambda: delone.delaunay([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]), "coplanar"),
    ("weights count", lambda: delone.regular(SQUARE, [1, 2]), "weights"),
    ("nan weight", lambda: delone.regular(SQUARE, [0, np.nan, 0, 0]), "weight"),
    ("segment index", lambda: delone.triangulate(SQUARE, [[0, 1], [1, 7]]), "segment 1"),
    ("negative index", lambda: delone.triangulate(SQUARE, [[0, 1], [1, -2]]), "segment 1"),
    ("fractional index", lambda: delone.triangulate(SQUARE, [[0, 1], [1, 2.5]]), "whole"),
    ("segment shape", lambda: delone.triangulate(SQUARE, [[0, 1, 2]]), "(m, 2)"),
    ("bad switch", lambda: delone.triangulate(SQUARE, SQUARE_SEGS, "pk"), "-k"),
    ("bad angle", lambda: delone.triangulate(SQUARE, SQUARE_SEGS, "pq70"), "60"),
    ("bad area", lambda: delone.triangulate(SQUARE, SQUARE_SEGS, "pa-1"), ""),
    ("marker count", lambda: delone.triangulate(SQUARE, SQUARE_SEGS, segment_markers=[1, 2]), "segment_markers"),
    ("hole nan", lambda: delone.triangulate(SQUARE, SQUARE_SEGS, holes=[[np.nan, 0]]), "hole"),
    ("open surface", lambda: delone.tetrahedralize(CUBE, CUBE_QUADS[:-1]), "not closed"),
    ("face index", lambda: delone.tetrahedralize(CUBE, CUBE_QUADS + [[0, 1, 9]]), "face 6"),
    ("self-intersecting", lambda: delone.tetrahedralize(CUBE, CUBE_QUADS + [[0, 7, 3], [1, 6, 4]]), "intersect"),
    ("nan 3d", lambda: delone.tetrahedralize(np.where(CUBE == 1, np.nan, CUBE), CUBE_QUADS), "point 1"),
    ("no faces", lambda: delone.tetrahedralize(CUBE, np.zeros((0, 3), int)), ""),
    ("2d points to 3d", lambda: delone.tetrahedralize(SQUARE, CUBE_QUADS), "(n, 3)"),
    ("bad tet switch", lambda: delone.tetrahedralize(CUBE, CUBE_QUADS, "pq1.414?"), "-?"),
    ("degenerate facet", lambda: delone.tetrahedralize(CUBE, CUBE_QUADS + [[0, 1, 1]]), "facet 6"),
    ("r without triangles", lambda: delone.triangulate(SQUARE, SQUARE_SEGS, "rq"), "triangles"),
]


@pytest.mark.parametrize("name,call,needle", BAD, ids=[b[0] for b in BAD])
def test_invalid_input_is_named(name, call, needle):
    with pytest.raises(delone.InvalidInput) as e:
        call()
    assert isinstance(e.value, ValueError)
    assert needle in str(e.value)


def test_exception_classes():
    assert issubclass(delone.InvalidInput, ValueError)
    assert issubclass(delone.MeshingError, RuntimeError)
    assert not issubclass(delone.MeshingError, delone.InvalidInput)


def test_steiner_budget_is_a_meshing_error_or_a_partial_mesh():
    # -S0 forbids Steiner points: the square meets q30 only with some.
    m = delone.triangulate(SQUARE, SQUARE_SEGS, "pq30S0")
    assert len(m.points) == 4
