#!/usr/bin/env python3
"""CAD-like closed surfaces built by constructive solid geometry, with fresh
dimensions and angles per seed, and a side-by-side run of delone and TetGen 1.6.

The classes are those CAD users bring and boundary recovery finds hard: tubes
with rings of radial holes or with one (long strips on both cylinders, the
bore a twisted prism broken by the holes), a gear with a keyway and a bracket with holes
turned to arbitrary angles (no coordinate plane exact), stacked plates whose
faces are 1e-4 apart (near-coplanar, not coplanar), a revolved vase with a
slot, a twisted hexagonal extrusion with two bores and a sphere with cubes cut
out. Every seed gives other instances of the same classes: held-out inputs
for a change tuned on another seed.

Needs `manifold3d` and `numpy` (PyPI), for instance in a virtual environment:

    python3 -m venv /tmp/cadvenv && /tmp/cadvenv/bin/pip install manifold3d numpy
    /tmp/cadvenv/bin/python crates/delone-bench/scripts/cad_shapes.py --seed 7 --out /tmp/cad7
    /tmp/cadvenv/bin/python crates/delone-bench/scripts/cad_shapes.py --seed 7 --out /tmp/cad7 \
        --delone target/release/delone --tetgen /tmp/tg16/tetgen --switches=-p,-pY

The run (the same as `hard_surfaces.py`'s) prints per model and switch the exit
code, time and Steiner points of delone, TetGen's, and the time ratio.
"""
import math
import os
import sys

import manifold3d as m
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import hard_surfaces  # noqa: E402

M = m.Manifold
CS = m.CrossSection


def circle(r, n, cx=0.0, cy=0.0, phase=0.0):
    return [(cx + r * math.cos(phase + 2 * math.pi * i / n), cy + r * math.sin(phase + 2 * math.pi * i / n))
            for i in range(n)]


def gear_profile(teeth, r_root, r_tip):
    pts = []
    for t in range(teeth):
        a0, w = 2 * math.pi * t / teeth, 2 * math.pi / teeth
        for f, r in ((0.0, r_root), (0.25, r_tip), (0.5, r_tip), (0.75, r_root)):
            pts.append((r * math.cos(a0 + f * w), r * math.sin(a0 + f * w)))
    return pts


def tube_rings(rng):
    seg = int(rng.integers(32, 57))
    rings, per = int(rng.integers(1, 4)), int(rng.integers(4, 8))
    R, wall = 0.5, 0.06 + 0.04 * rng.random()
    t = M.cylinder(2.0, R, -1, seg) - M.cylinder(2.2, R - wall, -1, seg).translate((0, 0, -0.1))
    hr, hseg = 0.05 + 0.03 * rng.random(), int(rng.integers(8, 14))
    for k in range(rings):
        z = 0.4 + 1.2 * (k + 0.5) / rings
        for j in range(per):
            a = 360.0 * j / per + 40.0 * rng.random()
            t = t - M.cylinder(1.2, hr, -1, hseg).rotate((0, 90, 0)).rotate((0, 0, a)).translate((0, 0, z))
    return t


def tube_one_hole(rng):
    """The smallest of the tubes: 12–20 sides, one radial hole. Its bore is a
    twisted prism (every side quad split the same way round) opened by the
    hole; TetGen's flips recover it without Steiner points."""
    seg = int(rng.integers(12, 21))
    t = M.cylinder(2.0, 0.5, -1, seg) - M.cylinder(2.2, 0.42, -1, seg).translate((0, 0, -0.1))
    a = float(360.0 * rng.random())
    return t - M.cylinder(1.2, 0.06, -1, 8).rotate((0, 90, 0)).rotate((0, 0, a)).translate((0, 0, 1.0))


def bracket_turned(rng):
    b = M.cube((2.0, 1.0, 0.15)) + M.cube((0.15, 1.0, 1.2))
    for i in range(3):
        b = b - M.cylinder(0.5, 0.06 + 0.03 * rng.random(), -1, 14).translate((0.6 + 0.5 * i, 0.5, -0.1))
    b = b - M.cylinder(0.5, 0.1, -1, 16).rotate((0, 90, 0)).translate((-0.1, 0.5, 0.7))
    return b.rotate(tuple(float(x) for x in 90 * rng.random(3)))


def gear_key_turned(rng):
    teeth = int(rng.integers(17, 41))
    key = [(0.3, 0.05), (0.25, 0.05), (0.25, -0.05), (0.3, -0.05)]
    g = M.extrude(CS([gear_profile(teeth, 1.0, 1.12), key]), 0.4)
    g = g - M.cylinder(1.0, 0.25, -1, int(rng.integers(20, 40))).translate((0, 0, -0.2))
    return g.rotate(tuple(float(x) for x in 90 * rng.random(3)))


def stacked_plates(rng):
    e = 1e-4 * (0.5 + rng.random())
    s = M.cube((2.0, 1.5, 0.2))
    s = s + M.cube((1.5, 1.0, 0.2)).translate((0.25, 0.25, 0.2 + e))
    s = s + M.cube((1.0, 0.5, 0.3)).translate((0.5, 0.5, 0.4 - e))
    for i in range(4):
        s = s - M.cylinder(1.0, 0.06, -1, 12).translate((0.15 + 1.7 * (i % 2), 0.15 + 1.2 * (i // 2), -0.2))
    return s


def vase_slot(rng):
    w = 0.08 + 0.04 * rng.random()
    prof = [(0.0, 0.0), (0.6, 0.0), (0.7, 0.3), (0.5, 0.8), (0.55, 1.2), (0.45, 1.2), (0.4, 0.8),
            (0.6, 0.3), (0.5, 0.1), (0.0, 0.1)]
    v = M.revolve(CS([prof]), int(rng.integers(48, 97)))
    return v - M.cube((w, 2.0, 0.4)).translate((-w / 2, -1.0, 0.5))


def twisted_hex(rng):
    hexa = circle(1.0, 6, phase=0.1)
    h1 = list(reversed(circle(0.2, 12, 0.4, 0.0)))
    h2 = list(reversed(circle(0.15, 10, -0.4, 0.1)))
    return M.extrude(CS([hexa, h1, h2]), 1.5, int(rng.integers(4, 12)), float(20 + 40 * rng.random()))


def sphere_cuts(rng):
    sp = M.sphere(1.0, int(rng.integers(24, 48)))
    for c in [(0.5, 0.5, 0.5), (-0.9, 0.0, 0.2), (0.0, -0.7, -0.6)]:
        sp = sp - M.cube((0.8, 0.8, 0.8), True).rotate(tuple(float(x) for x in 40 * rng.random(3))).translate(c)
    return sp


MODELS = {
    "tube_rings": tube_rings, "bracket_turned": bracket_turned, "gear_key_turned": gear_key_turned,
    "stacked_plates": stacked_plates, "vase_slot": vase_slot, "twisted_hex": twisted_hex,
    "sphere_cuts": sphere_cuts, "tube_one_hole": tube_one_hole,
}


def write(man, path):
    mesh = man.to_mesh()
    V = np.asarray(mesh.vert_properties)[:, :3]
    F = np.asarray(mesh.tri_verts)
    hard_surfaces.write_off(path, [tuple(p) for p in V], [tuple(int(x) for x in t) for t in F])


def main():
    ap = hard_surfaces.arguments("/tmp/cad_shapes", MODELS)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    names = a.models.split(",")
    for name in names:
        rng = np.random.default_rng([a.seed, list(MODELS).index(name)])
        write(MODELS[name](rng), os.path.join(a.out, name + ".off"))
    hard_surfaces.compare(a, names)


if __name__ == "__main__":
    main()
