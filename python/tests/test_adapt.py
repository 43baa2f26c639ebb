"""delone.adapt, delone.metric_from_field and delone.metric_stats."""

import numpy as np
import pytest

import delone


def grid2(n):
    g = np.linspace(0.0, 1.0, n + 1)
    pts = np.array([[x, y] for y in g for x in g])
    tris = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            b, c, d = a + 1, a + n + 2, a + n + 1
            tris += [[a, b, c], [a, c, d]]
    return pts, np.array(tris)


def boundary2(pts, n):
    """The square's boundary edges with markers 1..4 (bottom, right, top, left)."""
    edges, marks = [], []
    for i in range(n):
        edges.append([i, i + 1])
        marks.append(1)
        edges.append([i * (n + 1) + n, (i + 1) * (n + 1) + n])
        marks.append(2)
        edges.append([n * (n + 1) + i + 1, n * (n + 1) + i])
        marks.append(3)
        edges.append([(i + 1) * (n + 1), i * (n + 1)])
        marks.append(4)
    return np.array(edges), np.array(marks)


def grid3(n):
    g = np.linspace(0.0, 1.0, n + 1)
    pts = np.array([[x, y, z] for z in g for y in g for x in g])
    idx = lambda i, j, k: (k * (n + 1) + j) * (n + 1) + i  # noqa: E731
    tets = []
    for k in range(n):
        for j in range(n):
            for i in range(n):
                c = [idx(i + a, j + b, k + d) for d in (0, 1) for b in (0, 1) for a in (0, 1)]
                # Kuhn subdivision of the cube along its main diagonal c0-c7.
                for p in ([1, 3], [3, 2], [2, 6], [6, 4], [4, 5], [5, 1]):
                    tets.append([c[0], c[p[0]], c[p[1]], c[7]])
    tets = np.array(tets)
    v = pts[tets]
    vol = np.einsum("ij,ij->i", np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]), v[:, 3] - v[:, 0])
    neg = vol < 0
    tets[neg, 1], tets[neg, 2] = tets[neg, 2].copy(), tets[neg, 1].copy()
    return pts, tets


def areas(a):
    v = a.points[a.elements]
    u, w = v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]
    return 0.5 * (u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0])


def volumes(a):
    v = a.points[a.elements]
    return np.einsum("ij,ij->i", np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]), v[:, 3] - v[:, 0]) / 6


def test_isotropic_2d_keeps_area_and_boundary_markers():
    pts, tris = grid2(4)
    edges, marks = boundary2(pts, 4)
    a = delone.adapt(pts, tris, np.full(len(pts), 0.08), faces=edges, face_markers=marks,
                     element_markers=np.full(len(tris), 7))
    assert a.dim == 2 and a.elements.dtype == np.int32 and a.points.dtype == np.float64
    assert areas(a).min() > 0
    assert abs(areas(a).sum() - 1.0) < 1e-12
    assert set(a.element_markers.tolist()) == {7}
    assert sorted(set(a.face_markers.tolist())) == [1, 2, 3, 4]
    # The boundary edges of each marker still cover their side of the square exactly.
    for m, (axis, value) in {1: (1, 0.0), 2: (0, 1.0), 3: (1, 1.0), 4: (0, 0.0)}.items():
        e = a.faces[a.face_markers == m]
        assert np.all(a.points[e][:, :, axis] == value)
        other = 1 - axis
        assert abs(np.abs(a.points[e[:, 1], other] - a.points[e[:, 0], other]).sum() - 1.0) < 1e-12
    r = a.report
    assert r["after"]["in_range_share"] > 0.85
    assert r["after"]["quality_min"] > 0.4
    assert r["after"]["vertices"] > r["before"]["vertices"]
    assert a.metric.shape == (len(a.points), 3)


def test_anisotropic_2d_stretches_elements():
    pts, tris = grid2(4)
    # Size 0.02 along y, 0.2 along x.
    m = np.tile([1 / 0.2**2, 0.0, 1 / 0.02**2], (len(pts), 1))
    a = delone.adapt(pts, tris, m)
    assert areas(a).min() > 0 and abs(areas(a).sum() - 1.0) < 1e-12
    s = a.report["after"]
    assert s["in_range_share"] > 0.8 and s["quality_min"] > 0.3
    e = np.vstack([a.elements[:, [0, 1]], a.elements[:, [1, 2]], a.elements[:, [2, 0]]])
    d = np.abs(a.points[e[:, 1]] - a.points[e[:, 0]])
    assert np.median(d[:, 0]) > 3 * np.median(d[:, 1])


def test_isotropic_3d_keeps_volume():
    pts, tets = grid3(2)
    a = delone.adapt(pts, tets, np.full(len(pts), 0.2))
    assert a.dim == 3 and a.metric.shape == (len(a.points), 6)
    vol = volumes(a)
    assert vol.min() > 0 and abs(vol.sum() - 1.0) < 1e-12
    assert a.report["after"]["in_range_share"] > 0.8


def test_measure_only_changes_nothing():
    pts, tris = grid2(3)
    a = delone.adapt(pts, tris, np.full(len(pts), 0.1), insert=False, swap=False, smooth=False)
    assert len(a.points) == len(pts) and len(a.elements) == len(tris)
    assert a.report["before"] == a.report["after"]


def test_no_metric_adapts_to_the_mesh_sizes_and_hsiz_to_one_size():
    pts, tris = grid2(3)
    # Each point's mean incident edge length.
    e = np.unique(np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [0, 2]]]), axis=1), axis=0)
    length = np.linalg.norm(pts[e[:, 0]] - pts[e[:, 1]], axis=1)
    total = np.bincount(e.ravel(), np.repeat(length, 2), len(pts))
    mean = total / np.bincount(e.ravel(), minlength=len(pts))
    assert mean.min() < mean.max()
    still = dict(hgrad=None, insert=False, swap=False, smooth=False)
    a = delone.adapt(pts, tris, **still)
    assert np.allclose(a.metric[:, 0], 1 / mean**2) and np.allclose(a.metric[:, 2], 1 / mean**2)
    b = delone.adapt(pts, tris, hmax=0.4, **still)
    assert np.allclose(b.metric[:, 0], 1 / np.minimum(mean, 0.4) ** 2)
    # Adapted: the edges come out about as long as the input's.
    c = delone.adapt(pts, tris, hgrad=None)
    assert c.report["after"]["in_range_share"] > 0.9
    # hsiz: one size everywhere, as the same size given per point.
    h = delone.adapt(pts, tris, hsiz=0.1)
    m = delone.adapt(pts, tris, np.full(len(pts), 0.1))
    assert np.array_equal(h.points, m.points) and np.array_equal(h.elements, m.elements)
    with pytest.raises(delone.InvalidInput, match="not both"):
        delone.adapt(pts, tris, np.full(len(pts), 0.1), hsiz=0.1)


def test_metric_from_field_and_loop():
    pts, tris = grid2(8)
    for _ in range(3):
        u = np.tanh(20 * (pts[:, 0] - 0.5))
        m = delone.metric_from_field(pts, tris, u, complexity=300, hmin=1e-3, hmax=0.3, hgrad=1.5)
        a = delone.adapt(pts, tris, m)
        pts, tris = a.points, a.elements
    assert abs(areas(a).sum() - 1.0) < 1e-12
    # Finer in x near the layer than far from it.
    near = (np.abs(pts[:, 0] - 0.5) < 0.05).sum()
    far = (pts[:, 0] < 0.1).sum()
    assert near > 3 * far


def test_metric_stats_matches_report():
    pts, tris = grid2(3)
    m = np.full(len(pts), 0.25)
    s = delone.metric_stats(pts, tris, m)
    a = delone.adapt(pts, tris, m, hgrad=None, insert=False, swap=False, smooth=False)
    assert s == a.report["before"]
    assert s["edges"] == 3 * 3 * 3 + 2 * 3
    assert sum(s["length_histogram"]) == s["edges"]
    assert sum(s["quality_histogram"]) == s["elements"]


@pytest.mark.parametrize(
    "metric, message",
    [
        (np.zeros(16), "vertex 0 is not positive definite"),
        (np.r_[np.ones(5), np.nan, np.ones(10)], "vertex 5 has a NaN"),
        (np.tile([1.0, 2.0, 1.0], (16, 1)), "vertex 0"),
        (np.ones(5), "one row per point"),
        (np.ones((16, 4)), "tensor components"),
    ],
)
def test_bad_metric_is_invalid_input(metric, message):
    pts, tris = grid2(3)
    with pytest.raises(delone.InvalidInput, match=message):
        delone.adapt(pts, tris, metric)


def test_bad_mesh_is_invalid_input():
    pts, tris = grid2(2)
    bad = tris.copy()
    bad[3, 1] = 99
    with pytest.raises(delone.InvalidInput, match="element 3"):
        delone.adapt(pts, bad, np.ones(len(pts)))
    with pytest.raises(delone.InvalidInput, match="face 0"):
        delone.adapt(pts, tris, np.ones(len(pts)), faces=[[0, 50]])
    with pytest.raises(delone.InvalidInput, match="complexity"):
        delone.metric_from_field(pts, tris, pts[:, 0])


def test_progress_reports_passes_and_a_raising_callback_stops():
    pts, tris = grid2(4)
    seen = []
    delone.adapt(pts, tris, np.full(len(pts), 0.05), progress=lambda *r: seen.append(r))
    assert seen and all(r[0] == "adapting" and r[3] == "passes" for r in seen)

    class Stop(Exception):
        pass

    def stop(*_):
        raise Stop

    with pytest.raises(Stop):
        delone.adapt(pts, tris, np.full(len(pts), 0.01), progress=stop)
