"""Shared inputs and mesh checks for the delone test suite."""

import numpy as np
import pytest

SQUARE = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
SQUARE_SEGS = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])
CUBE = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], dtype=float)
CUBE_QUADS = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
CUBE_TRIS = np.array([t for q in CUBE_QUADS for t in ([q[0], q[1], q[2]], [q[0], q[2], q[3]])])


def triangle_angles(p, t):
    """Angles (degrees) of every triangle, (m, 3)."""
    a, b, c = p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]

    def ang(u, v, w):
        x, y = v - u, w - u
        cos = (x * y).sum(1) / np.linalg.norm(x, axis=1) / np.linalg.norm(y, axis=1)
        return np.degrees(np.arccos(np.clip(cos, -1, 1)))

    return np.stack([ang(a, b, c), ang(b, c, a), ang(c, a, b)], 1)


def areas(p, t):
    """Signed areas (counterclockwise positive)."""
    a, b, c = p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def volumes(p, t):
    """Signed volumes (positive: (b-a)x(c-a).(d-a) > 0)."""
    a, b, c, d = (p[t[:, k]] for k in range(4))
    return np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) / 6.0


def check_neighbors(simplices, neighbors, limit=None):
    """neighbors[i][k] shares the face opposite vertex k, symmetrically
    (for the first `limit` simplices)."""
    k = simplices.shape[1]
    for i, (s, n) in enumerate(zip(simplices[:limit], neighbors[:limit])):
        for j in range(k):
            if n[j] == -1:
                continue
            face = set(s) - {s[j]}
            assert face <= set(simplices[n[j]]), (i, j)
            assert i in neighbors[n[j]], (i, j)


@pytest.fixture
def rng():
    return np.random.default_rng(12345)
