"""delone.triangulate and delone.tetrahedralize: the meshes meet their switches."""

import numpy as np
import pytest

import delone
from conftest import CUBE, CUBE_QUADS, CUBE_TRIS, SQUARE, SQUARE_SEGS, areas, check_neighbors, triangle_angles, volumes


def test_quality_mesh_meets_angle_and_area():
    m = delone.triangulate(SQUARE, SQUARE_SEGS, "pq30a0.01")
    assert m.points.dtype == np.float64 and m.elements.dtype == np.int32
    assert triangle_angles(m.points, m.elements).min() >= 30 - 1e-9
    a = areas(m.points, m.elements)
    assert (a > 0).all() and a.max() <= 0.01 and a.sum() == pytest.approx(1.0)
    assert m.quality["min_angle"] >= 30 and m.quality["triangles"] == len(m.elements)
    check_neighbors(m.elements, m.neighbors)
    # The boundary is the subdivided square, marked 1 (Triangle's default).
    assert (m.boundary_markers == 1).all()
    assert (m.point_markers[:4] == 1).all()


def test_without_segments_the_convex_hull_is_meshed(rng):
    m = delone.triangulate(rng.random((50, 2)), switches="pq25")
    assert triangle_angles(m.points, m.elements).min() >= 25 - 1e-9


def test_holes_regions_and_markers():
    outer = [[0, 0], [3, 0], [3, 3], [0, 3]]
    inner = [[1, 1], [2, 1], [2, 2], [1, 2]]
    p = np.array(outer + inner, float)
    s = [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]]
    m = delone.triangulate(p, s, "pqA", holes=[[1.5, 1.5]], regions=[[0.5, 0.5, 7.0, 0]],
                           segment_markers=[5] * 4 + [9] * 4, edges=True)
    assert areas(m.points, m.elements).sum() == pytest.approx(8.0)
    assert (m.attributes == 7.0).all() and (m.regions == 0).all()
    assert set(m.boundary_markers.tolist()) == {5, 9}
    assert m.edges is not None and len(m.edges) == len(m.edge_markers)
    assert set(m.edge_markers.tolist()) == {0, 5, 9}


def test_regional_area_bound():
    m = delone.triangulate(SQUARE, SQUARE_SEGS, "pa", regions=[[0.5, 0.5, 0, 0.005]])
    assert areas(m.points, m.elements).max() <= 0.005


def test_to_meshio():
    meshio = pytest.importorskip("meshio")
    m = delone.triangulate(SQUARE, SQUARE_SEGS, "pq")
    mm = m.to_meshio()
    assert isinstance(mm, meshio.Mesh) and len(mm.cells[0].data) == len(m.elements)
    t = delone.tetrahedralize(CUBE, CUBE_QUADS).to_meshio()
    assert t.cells[0].type == "tetra"


@pytest.mark.parametrize("faces", [CUBE_QUADS, CUBE_TRIS])
def test_tetrahedralize_cube(faces):
    m = delone.tetrahedralize(CUBE, faces, "pq1.414a0.005")
    assert m.elements.shape[1] == 4 and m.elements.dtype == np.int32
    v = volumes(m.points, m.elements)
    assert (v > 0).all() and v.sum() == pytest.approx(1.0) and v.max() <= 0.005
    assert m.quality["max_radius_edge"] <= 1.414 + 1e-9 or m.quality["min_dihedral"] > 5
    check_neighbors(m.elements, m.neighbors, 300)
    # The boundary faces cover the cube's surface.
    f = m.boundary
    a = 0.5 * np.linalg.norm(np.cross(m.points[f[:, 1]] - m.points[f[:, 0]], m.points[f[:, 2]] - m.points[f[:, 0]]), axis=1)
    assert a.sum() == pytest.approx(6.0)


def test_tetrahedralize_reaches_dihedral_bound():
    m = delone.tetrahedralize(CUBE, CUBE_QUADS, "pq1.5/20")
    assert m.quality["min_dihedral"] >= 20


def dihedral_angles(p, t):
    """All six dihedral angles (degrees) of each tetrahedron."""
    out = []
    for i, j, k, l in [(0, 1, 2, 3), (0, 2, 1, 3), (0, 3, 1, 2), (1, 2, 0, 3), (1, 3, 0, 2), (2, 3, 0, 1)]:
        a, e = p[t[:, i]], p[t[:, j]] - p[t[:, i]]
        n1 = np.cross(e, p[t[:, k]] - a)
        n2 = np.cross(e, p[t[:, l]] - a)
        c = (n1 * n2).sum(1) / (np.linalg.norm(n1, axis=1) * np.linalg.norm(n2, axis=1))
        out.append(np.degrees(np.arccos(np.clip(c, -1, 1))))
    return np.stack(out, 1)


def test_quality_report_and_optimizer_stages():
    m = delone.tetrahedralize(CUBE, CUBE_QUADS, "pq1.5/20a0.01")
    q = m.quality
    d = dihedral_angles(m.points, m.elements)
    # The statistics are those of the mesh returned.
    assert q["tetrahedra"] == len(m.elements)
    assert q["min_dihedral"] == pytest.approx(d.min(), abs=1e-6)
    assert q["max_dihedral"] == pytest.approx(d.max(), abs=1e-6)
    assert q["total_volume"] == pytest.approx(volumes(m.points, m.elements).sum())
    stages = q["optimization_stages"]
    assert stages, "the optimisation runs after -q"
    first = [s for s in stages if not s["second_run"]]
    thresholds = [s["threshold"] for s in first]
    assert thresholds == sorted(thresholds) and 20.0 in thresholds
    for s in stages:
        assert set(s) == {"threshold", "second_run", "evaluations", "undone_evaluations",
                          "worst_reached", "attempts", "successes", "worst", "below", "stop"}
        assert 0 <= s["undone_evaluations"] <= s["evaluations"]
        assert 0 <= s["worst_reached"] <= s["evaluations"]
        assert 0 <= s["successes"] <= s["attempts"]
        assert len(s["worst"]) == 2 and len(s["below"]) == 2
        assert all(0 <= w <= 90 for w in s["worst"])
        assert s["stop"] in {"nothing left to improve", "attempts spent", "stopped paying",
                             "effort budget spent", "interrupted"}
    # Without the optimisation there are no stages.
    assert delone.tetrahedralize(CUBE, CUBE_QUADS, "pq1.5/20a0.01O0").quality["optimization_stages"] == []
    assert delone.tetrahedralize(CUBE, CUBE_QUADS, "p").quality["optimization_stages"] == []


def test_face_markers_holes_and_regions():
    big = CUBE * 3
    small = CUBE + 1
    p = np.vstack([big, small])
    faces = CUBE_QUADS + [[i + 8 for i in q] for q in CUBE_QUADS]
    markers = [1] * 6 + [2] * 6
    m = delone.tetrahedralize(p, faces, "pqA", face_markers=markers, holes=[[1.5, 1.5, 1.5]],
                              regions=[[0.5, 0.5, 0.5, 4.0, 0]])
    assert volumes(m.points, m.elements).sum() == pytest.approx(27 - 1)
    assert set(m.boundary_markers.tolist()) == {1, 2}
    assert (m.attributes == 4.0).all()


def test_refine_an_existing_mesh_with_r():
    d = delone.delaunay(SQUARE)
    m = delone.triangulate(SQUARE, switches="rq30a", triangles=d.simplices,
                           triangle_max_area=[0.01, 0.002])
    a = areas(m.points, m.elements)
    assert (a > 0).all() and a.sum() == pytest.approx(1.0)
    assert triangle_angles(m.points, m.elements).min() >= 30 - 1e-9
    # Each input triangle's bound holds inside it: the finest half is finer.
    assert a.min() <= 0.002 and a.max() <= 0.01


def test_r_refuses_a_clockwise_triangle():
    with pytest.raises(delone.InvalidInput, match="triangle"):
        delone.triangulate(SQUARE, switches="rq", triangles=[[0, 2, 1]])
