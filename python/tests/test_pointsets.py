"""delone.delaunay, regular, voronoi, convex_hull in 2D and 3D."""

import numpy as np
import pytest

import delone
from conftest import areas, check_neighbors, volumes


@pytest.mark.parametrize("dim", [2, 3])
def test_delaunay_is_a_valid_triangulation(rng, dim):
    p = rng.random((300, dim))
    t = delone.delaunay(p)
    assert t.simplices.dtype == np.int32 and t.neighbors.dtype == np.int32
    assert t.simplices.shape[1] == dim + 1 and t.neighbors.shape == t.simplices.shape
    assert t.dim == dim
    size = areas(p, t.simplices) if dim == 2 else volumes(p, t.simplices)
    assert (size > 0).all()
    check_neighbors(t.simplices, t.neighbors, 200)
    assert len(np.unique(t.simplices)) == len(p)


@pytest.mark.parametrize("dim", [2, 3])
def test_delaunay_matches_scipy(rng, dim):
    spatial = pytest.importorskip("scipy.spatial")
    p = rng.random((500, dim))
    ours = np.sort(delone.delaunay(p).simplices, axis=1)
    theirs = np.sort(spatial.Delaunay(p).simplices, axis=1)
    assert sorted(map(tuple, ours)) == sorted(map(tuple, theirs))
    size = areas(p, delone.delaunay(p).simplices) if dim == 2 else volumes(p, delone.delaunay(p).simplices)
    assert size.sum() == pytest.approx(spatial.ConvexHull(p).volume, rel=1e-9)


def test_empty_circumcircles(rng):
    p = rng.random((200, 2))
    t = delone.delaunay(p).simplices
    a, b, c = p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]
    d = 2 * (a[:, 0] * (b[:, 1] - c[:, 1]) + b[:, 0] * (c[:, 1] - a[:, 1]) + c[:, 0] * (a[:, 1] - b[:, 1]))
    sq = lambda q: (q**2).sum(1)
    ux = (sq(a) * (b[:, 1] - c[:, 1]) + sq(b) * (c[:, 1] - a[:, 1]) + sq(c) * (a[:, 1] - b[:, 1])) / d
    uy = (sq(a) * (c[:, 0] - b[:, 0]) + sq(b) * (a[:, 0] - c[:, 0]) + sq(c) * (b[:, 0] - a[:, 0])) / d
    r2 = (a[:, 0] - ux) ** 2 + (a[:, 1] - uy) ** 2
    dist = (p[None, :, 0] - ux[:, None]) ** 2 + (p[None, :, 1] - uy[:, None]) ** 2
    assert (dist >= r2[:, None] * (1 - 1e-9)).all()


def test_duplicates_are_merged_and_reported():
    p = [[0, 0], [1, 0], [0, 1], [1, 0], [1, 1]]
    t = delone.delaunay(p)
    assert t.duplicates.tolist() == [[3, 1]]
    assert 3 not in t.simplices


def test_grid_points_cocircular():
    g = np.array([[x, y] for x in range(10) for y in range(10)], float)
    assert len(delone.delaunay(g).simplices) == 2 * 81


def test_regular_hides_points_and_zero_weights_give_delaunay(rng):
    p = rng.random((100, 2))
    assert (delone.regular(p, np.zeros(100)).simplices == delone.delaunay(p).simplices).all()
    sq = np.array([[0, 0], [1, 0], [0, 1], [1, 1], [0.5, 0.5]])
    r = delone.regular(sq, [0, 0, 0, 0, -1])
    assert r.hidden.tolist() == [4] and len(r.simplices) == 2
    r3 = delone.regular(rng.random((50, 3)), rng.random(50) * 0.01)
    assert r3.simplices.shape[1] == 4


def test_voronoi_2d():
    v = delone.voronoi([[0, 0], [0, 1], [0.5, 0.5], [1, 1], [1, 0]])
    assert v.vertices.shape == (4, 2) and v.edges.shape == (8, 2)
    rays = v.edges[:, 1] == -1
    assert rays.sum() == 4
    assert (np.linalg.norm(v.directions[rays], axis=1) > 0).all()
    assert (v.directions[~rays] == 0).all()
    assert sorted(map(tuple, np.round(v.vertices, 12).tolist())) == [(0, 0.5), (0.5, 0), (0.5, 1), (1, 0.5)]


def test_voronoi_3d_and_power(rng):
    p = rng.random((60, 3))
    v = delone.voronoi(p)
    t = delone.delaunay(p)
    assert len(v.vertices) == len(t.simplices)
    assert v.edge_sites.shape[1] == 3
    assert len(v.face_offsets) == len(v.face_sites) + 1
    # Open faces (Delaunay hull edges) may have a single vertex and two rays.
    assert all(len(v.face(f)) >= 1 for f in range(len(v.face_sites)))
    w = delone.voronoi(p, rng.random(60) * 1e-3)
    assert w.vertices.shape[1] == 3


def test_convex_hull(rng):
    p = rng.random((200, 2))
    h = delone.convex_hull(p)
    assert h.dtype == np.int32 and h.shape[1] == 2
    # Every point is left of (or on) every counterclockwise hull edge.
    a, b = p[h[:, 0]], p[h[:, 1]]
    cross = (b[:, 0] - a[:, 0])[:, None] * (p[None, :, 1] - a[:, 1, None]) - (b[:, 1] - a[:, 1])[:, None] * (
        p[None, :, 0] - a[:, 0, None]
    )
    assert (cross >= -1e-12).all()
    q = rng.random((200, 3))
    f = delone.convex_hull(q)
    assert f.shape[1] == 3
    spatial = pytest.importorskip("scipy.spatial")
    assert len(f) == len(spatial.ConvexHull(q).simplices)
