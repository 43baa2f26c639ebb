"""delone.triangle against the `triangle` package: same keys, shapes and
dtypes; valid meshes that meet the switches."""

import numpy as np
import pytest

import delone.triangle as dtr
from conftest import areas, check_neighbors, triangle_angles

V = np.array([[0, 0], [0, 1], [1, 1], [1, 0], [0.4, 0.4], [0.6, 0.4], [0.6, 0.6], [0.4, 0.6], [0.2, 0.2], [0.3, 0.2]])
S = np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4], [8, 9]])
INPUTS = {
    "points": dict(vertices=V),
    "pslg": dict(vertices=V, segments=S),
    "hole": dict(vertices=V, segments=S, holes=[[0.5, 0.5]]),
    "regions": dict(vertices=V, segments=S, regions=[[0.1, 0.1, 3.0, 0.01], [0.5, 0.5, 5.0, 0.001]]),
    "markers": dict(vertices=V, vertex_markers=np.arange(10), segments=S, segment_markers=np.arange(9) + 10),
}
OPTS = ["", "p", "pq", "pq30a0.01", "pe", "pn", "pc", "q", "a0.05", "c", "e", "n", "pA", "pa", "pqAa", "pD", "pY", "pqQ"]
CASES = [(i, o) for i in INPUTS for o in OPTS if not ("a" == o[-1:] and i != "regions")]


def _check_mesh(inp, opts, out):
    v, t = out["vertices"], out["triangles"]
    a = areas(v, t)
    assert (a > 0).all()
    if "q" in opts:
        angle = float(opts.split("q")[1][:2]) if opts.split("q")[1][:2].isdigit() else 20.0
        # Triangle (and delone) may leave small angles next to small input angles.
        assert triangle_angles(v, t).min() >= angle - 1e-6 or "segments" in inp
    if "a0." in opts:
        bound = float(opts.split("a")[1])
        assert a.max() <= bound * (1 + 1e-9)
    if "n" in opts:
        check_neighbors(t, out["neighbors"])
    # Every input vertex is in the output, at the same place.
    assert np.array_equal(v[: len(inp["vertices"])], np.asarray(inp["vertices"], float))


@pytest.mark.parametrize("name,opts", CASES, ids=[f"{i}-{o or 'none'}" for i, o in CASES])
def test_same_keys_shapes_dtypes_as_triangle(name, opts):
    inp = INPUTS[name]
    ours = dtr.triangulate(inp, opts)
    if "triangles" in ours:
        _check_mesh(inp, opts, ours)
    else:
        # -p without segments: Triangle carves everything away.
        assert name == "points" and "p" in opts
    triangle = pytest.importorskip("triangle")
    theirs = triangle.triangulate(inp, opts)
    assert sorted(ours) == sorted(theirs)
    for k in theirs:
        assert ours[k].dtype == theirs[k].dtype, k
        assert ours[k].shape[1:] == theirs[k].shape[1:], k
    # Without refinement the meshes have the same size.
    if not any(c in opts for c in "qaD") and "triangles" in theirs:
        assert len(ours["vertices"]) == len(theirs["vertices"])
        assert len(ours["triangles"]) == len(theirs["triangles"])


def test_refine_r_with_triangle_max_area():
    t0 = dtr.triangulate(dict(vertices=V), "")
    t0["triangle_max_area"] = np.full(len(t0["triangles"]), 0.01)
    t1 = dtr.triangulate(t0, "ra")
    assert areas(t1["vertices"], t1["triangles"]).max() <= 0.01
    assert sorted(t1) == ["triangles", "vertex_markers", "vertices"]
    q = dtr.triangulate(t0, "rq30")
    assert triangle_angles(q["vertices"], q["triangles"]).min() >= 30 - 1e-9
    triangle = pytest.importorskip("triangle")
    theirs = triangle.triangulate(t0, "ra")
    assert sorted(theirs) == sorted(t1)


def test_regional_attributes_and_areas():
    out = dtr.triangulate(INPUTS["regions"], "pqAa")
    attrs = out["triangle_attributes"][:, 0]
    assert set(attrs.tolist()) <= {0.0, 3.0, 5.0} and 5.0 in attrs and 3.0 in attrs
    a = areas(out["vertices"], out["triangles"])
    assert a[attrs == 5.0].max() <= 0.001 and a[attrs == 3.0].max() <= 0.01


def test_markers_follow_triangle():
    out = dtr.triangulate(INPUTS["markers"], "p")
    assert out["vertex_markers"][:, 0].tolist()[1:] == list(range(1, 10))
    assert sorted(out["segment_markers"][:, 0].tolist()) == list(range(10, 19))
    triangle = pytest.importorskip("triangle")
    theirs = triangle.triangulate(INPUTS["markers"], "p")
    # Vertex 0 ends two segments (markers 10 and 13): Triangle takes the first
    # input segment's, delone the first subsegment's; the others agree.
    assert np.array_equal(out["vertex_markers"][1:], theirs["vertex_markers"][1:])


def test_documented_examples():
    # The `triangle` package's docstring examples, unchanged.
    v = [[0, 0], [0, 1], [1, 1], [1, 0]]
    t = dtr.triangulate({"vertices": v}, "a0.2")
    assert t["vertices"][:4].tolist() == [[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]]
    assert areas(t["vertices"], t["triangles"]).max() <= 0.2
    assert (t["vertex_markers"][:4] == 1).all()
    pts = [[0, 0], [0, 1], [0.5, 0.5], [1, 1], [1, 0]]
    tri = dtr.delaunay(pts)
    assert sorted(map(sorted, tri.tolist())) == sorted(map(sorted, [[1, 0, 2], [2, 4, 3], [4, 2, 0], [2, 3, 1]]))
    segments = dtr.convex_hull([[0, 0], [0, 1], [1, 1], [1, 0]])
    assert sorted(map(sorted, segments.tolist())) == [[0, 1], [0, 3], [1, 2], [2, 3]]
    points, edges, ray_origin, ray_direct = dtr.voronoi(pts)
    assert sorted(points.tolist()) == [[0.0, 0.5], [0.5, 0.0], [0.5, 1.0], [1.0, 0.5]]
    assert len(edges) == 4 and len(ray_origin) == 4
    # Rays point away from the centre, along the axes.
    d = ray_direct / np.linalg.norm(ray_direct, axis=1)[:, None]
    assert sorted(np.round(d, 12).tolist()) == [[-1.0, 0.0], [0.0, -1.0], [0.0, 1.0], [1.0, 0.0]]


@pytest.mark.parametrize("fn", ["delaunay", "convex_hull", "voronoi"])
def test_point_functions_match_triangle(fn, rng):
    triangle = pytest.importorskip("triangle")
    p = rng.random((200, 2))
    ours, theirs = getattr(dtr, fn)(p), getattr(triangle, fn)(p)
    if fn == "voronoi":
        for a, b in zip(ours, theirs):
            assert a.dtype == b.dtype and a.shape == b.shape
    else:
        assert ours.dtype == theirs.dtype and ours.shape == theirs.shape
        assert sorted(map(sorted, ours.tolist())) == sorted(map(sorted, theirs.tolist()))


EXAMPLES = ["A", "box", "face", "double_hex", "double_hex2", "double_hex3", "la", "square_circle_hole", "dots", "spiral", "ell"]


@pytest.mark.parametrize("name", EXAMPLES)
def test_get_data_reads_the_examples_like_triangle(name):
    triangle = pytest.importorskip("triangle")
    ours, theirs = dtr.get_data(name), triangle.get_data(name)
    assert sorted(ours) == sorted(theirs)
    for k in theirs:
        assert np.array_equal(np.asarray(theirs[k]).reshape(ours[k].shape), ours[k]), k


@pytest.mark.parametrize("name,opts", [("A", "pq"), ("face", "pq30a5"), ("double_hex", "pqa.01"), ("la", "pqa"), ("dots", "q"), ("ell", "rpa.1".replace("p", ""))])
def test_documented_example_runs_unchanged(name, opts, tmp_path):
    # The shape of the triangle package's documented examples:
    #   A = tr.get_data(name); B = tr.triangulate(A, opts); tr.compare(plt, A, B)
    pytest.importorskip("triangle")
    plt = pytest.importorskip("matplotlib.pyplot")
    A = dtr.get_data(name)
    if "r" in opts:
        A["triangle_max_area"] = np.full(len(A["triangles"]), 0.1)
    B = dtr.triangulate(A, opts)
    a = areas(B["vertices"], B["triangles"])
    assert (a > 0).all()
    if "q" in opts:
        assert triangle_angles(B["vertices"], B["triangles"]).min() >= 20 - 1e-6 or name in ("la",)
    dtr.compare(plt, A, B)
    plt.savefig(tmp_path / "cmp.png")
    plt.close("all")
    assert (tmp_path / "cmp.png").stat().st_size > 1000
