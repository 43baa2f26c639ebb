#!/usr/bin/env python3
"""delone adapt against MMG on the UGAWG analytic metrics (Ibanez et al.,
IMR 2017): linear, polar-1 and polar-2 on the unit square (--dim 2) or the
unit cube (--dim 3), and a sinusoidal shock (not used to tune delone).

Each case starts from a uniform structured mesh (a grid of cells split into
triangles or tetrahedra, boundary edges/faces with one reference per side,
the corners, and in 3D the twelve edges of the cube as ridges; in 3D the
mesh of the test suite's `cube(10)`),
runs ITERS adapt iterations with each tool, the analytic metric evaluated at
the current vertices before every iteration, and measures both final meshes
the same way: `delone adapt --stats-json` in measure-only mode
(-noinsert -noswap -nomove) against the analytic metric at their vertices.
Time and peak memory are summed / maximised over the iterations (children's
rusage). Pure Python 3, no numpy.

    python3 crates/delone-bench/scripts/adapt_vs_mmg.py \\
        --delone target/release/delone --mmg /tmp/mmgvenv/bin/mmg2d_O3 --dim 2

Metrics (h0 = 0.001; r, theta about the z axis through the origin):
  linear   h_x = h_y = 0.1 (3D), h_z = h0 + 2 (0.1 - h0) |z - 0.5|
           (in 2D: h_x = 0.1, h_y as h_z on y)
  polar-1  h_r = h0 + 2 (0.1 - h0) |r - 0.5|, h_theta = h_z = 0.1
  polar-2  polar-1 with h_theta = 0.025 + 0.075 min(1, 10 |r - 0.5|)
           (h_theta refined near the layer r = 0.5)
  sine     a layer along y = 0.5 + 0.1 sin(2 pi x) (3D: z = ...): size
           h0 + 2 (0.1 - h0) |d| (at most 0.1) across it, d the vertical
           distance to the curve over the length of its normal, 0.1 along it
  circle   a tanh shock on the circle of radius 0.3 about (0.5, 0.5):
           h_n = h0 + (0.1 - h0) tanh(|rho - 0.3| / 0.05) across it,
           h_t = 0.1 along it (3D: a cylinder, h_z = 0.1)
  bl       a boundary layer on the side x = 0: h_x = min(0.1, h0 + 0.2 x)
           (sizes growing geometrically, ratio 1.2 per layer), h_y = 0.05
  cross    two crossing shocks (not used to tune delone): the metric
           intersection of a layer along x = 0.3 + 0.4 y and one along
           y = 0.6 - 0.2 x, each h_n = 0.002 + 2 (0.1 - 0.002) |d| (at most
           0.1) across it, d the distance to its line, 0.1 along it

Each row also shows `unit`: the number of triangles (tetrahedra) a mesh of
unit metric edges needs, ∫ sqrt(det M) over the domain divided by the metric
volume of the regular unit simplex (sqrt(3)/4 in 2D, sqrt(2)/12 in 3D),
summed over that tool's final mesh with the metric at each element's
centroid; `el/unit` is the element count over it.
"""

import argparse
import itertools
import json
import math
import os
import resource
import subprocess
import sys
import time

H0 = 0.001


def sizes(case, p, dim):
    """(eigen sizes, eigen directions) of the analytic metric at p."""
    layer = lambda s: H0 + 2.0 * (0.1 - H0) * abs(s - 0.5)
    if case == "linear":
        if dim == 2:
            return [0.1, layer(p[1])], [[1, 0], [0, 1]]
        return [0.1, 0.1, layer(p[2])], [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    if case == "sine":
        k = 2.0 * math.pi
        f, df = 0.5 + 0.1 * math.sin(k * p[0]), 0.1 * k * math.cos(k * p[0])
        q = math.hypot(1.0, df)
        hn = min(0.1, layer(0.5 + (p[dim - 1] - f) / q))
        if dim == 2:
            return [0.1, hn], [[1 / q, df / q], [-df / q, 1 / q]]
        return [0.1, 0.1, hn], [[1 / q, 0, df / q], [0, 1, 0], [-df / q, 0, 1 / q]]
    if case == "circle":
        x, y = p[0] - 0.5, p[1] - 0.5
        rho = math.hypot(x, y)
        c, s = (x / rho, y / rho) if rho > 0 else (1.0, 0.0)
        hn = H0 + (0.1 - H0) * math.tanh(abs(rho - 0.3) / 0.05)
        if dim == 2:
            return [hn, 0.1], [[c, s], [-s, c]]
        return [hn, 0.1, 0.1], [[c, s, 0], [-s, c, 0], [0, 0, 1]]
    if case == "bl":
        hx = min(0.1, H0 + 0.2 * p[0])
        if dim == 2:
            return [hx, 0.05], [[1, 0], [0, 1]]
        return [hx, 0.05, 0.1], [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    r = math.hypot(p[0], p[1])
    t = math.atan2(p[1], p[0])
    c, s = math.cos(t), math.sin(t)
    hr = layer(r)
    ht = 0.1 if case == "polar1" else 0.025 + 0.075 * min(1.0, 10.0 * abs(r - 0.5))
    if dim == 2:
        return [hr, ht], [[c, s], [-s, c]]
    return [hr, ht, 0.1], [[c, s, 0], [-s, c, 0], [0, 0, 1]]


def layer_matrix(normal, d):
    """The 2x2 metric of a layer: size 0.002 + 2 (0.1 - 0.002) |d| (at most
    0.1) along the unit `normal`, 0.1 across it."""
    hn = min(0.1, 0.002 + 2.0 * (0.1 - 0.002) * abs(d))
    a, b = 1.0 / (hn * hn), 100.0
    n0, n1 = normal
    return [[a * n0 * n0 + b * n1 * n1, (a - b) * n0 * n1], [(a - b) * n0 * n1, a * n1 * n1 + b * n0 * n0]]


def intersect(m1, m2):
    """The metric intersection of two 2x2 metrics (simultaneous reduction):
    in the eigenvectors of m1^-1 m2, the larger of the two lengths."""
    det1 = m1[0][0] * m1[1][1] - m1[0][1] * m1[1][0]
    inv = [[m1[1][1] / det1, -m1[0][1] / det1], [-m1[1][0] / det1, m1[0][0] / det1]]
    n = [[sum(inv[i][k] * m2[k][j] for k in range(2)) for j in range(2)] for i in range(2)]
    tr, det = n[0][0] + n[1][1], n[0][0] * n[1][1] - n[0][1] * n[1][0]
    disc = math.sqrt(max(0.0, tr * tr / 4 - det))
    vecs = []
    for lam in (tr / 2 + disc, tr / 2 - disc):
        # (n - lam I) v = 0: the larger row of n - lam I gives v.
        r0, r1 = [n[0][0] - lam, n[0][1]], [n[1][0], n[1][1] - lam]
        r = r0 if abs(r0[0]) + abs(r0[1]) >= abs(r1[0]) + abs(r1[1]) else r1
        v = [-r[1], r[0]] if abs(r[0]) + abs(r[1]) > 1e-14 * (abs(tr) + 1) else None
        vecs.append(v)
    if vecs[0] is None or vecs[1] is None or disc <= 1e-12 * abs(tr):
        # m2 = c m1: the larger of the two.
        return m2 if tr > 2 else m1
    quad = lambda m, v: sum(v[i] * m[i][j] * v[j] for i in range(2) for j in range(2))
    lam = [max(quad(m1, v), quad(m2, v)) for v in vecs]
    # M = P^-T diag(lam) P^-1 with P = [v0 v1] (columns).
    p = [[vecs[0][0], vecs[1][0]], [vecs[0][1], vecs[1][1]]]
    dp = p[0][0] * p[1][1] - p[0][1] * p[1][0]
    pinv = [[p[1][1] / dp, -p[0][1] / dp], [-p[1][0] / dp, p[0][0] / dp]]
    return [[sum(pinv[k][i] * lam[k] * pinv[k][j] for k in range(2)) for j in range(2)] for i in range(2)]


def metric_matrix(case, p, dim):
    """The analytic metric at p as a dim x dim matrix."""
    if case == "cross":
        q1 = math.hypot(1.0, 0.4)
        m1 = layer_matrix((1 / q1, -0.4 / q1), (p[0] - 0.3 - 0.4 * p[1]) / q1)
        q2 = math.hypot(1.0, 0.2)
        m2 = layer_matrix((0.2 / q2, 1 / q2), (p[1] - 0.6 + 0.2 * p[0]) / q2)
        m = intersect(m1, m2)
        if dim == 2:
            return m
        return [m[0] + [0.0], m[1] + [0.0], [0.0, 0.0, 100.0]]
    h, v = sizes(case, p, dim)
    return [[sum(v[k][i] * v[k][j] / (h[k] * h[k]) for k in range(dim)) for j in range(dim)] for i in range(dim)]


def metric(case, p, dim):
    """Medit components: m11 m12 m22 (2D), m11 m12 m22 m13 m23 m33 (3D)."""
    m = metric_matrix(case, p, dim)
    if dim == 2:
        return [m[0][0], m[0][1], m[1][1]]
    return [m[0][0], m[0][1], m[1][1], m[0][2], m[1][2], m[2][2]]


def grid_mesh(path, n, dim):
    """A uniform n^dim grid of the unit square/cube, split into simplices,
    with boundary edges/faces (reference = side 1..2*dim) and corners."""
    pts, els, bnd, ridges = [], [], [], []
    if dim == 2:
        idx = lambda i, j: j * (n + 1) + i + 1
        for j in range(n + 1):
            for i in range(n + 1):
                pts.append((i / n, j / n, 0.0))
        for j in range(n):
            for i in range(n):
                a, b, c, d = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
                els += [(a, b, c), (a, c, d)]
        for k in range(n):
            bnd += [((idx(k, 0), idx(k + 1, 0)), 1), ((idx(n, k), idx(n, k + 1)), 2),
                    ((idx(k + 1, n), idx(k, n)), 3), ((idx(0, k + 1), idx(0, k)), 4)]
        corners = [idx(0, 0), idx(n, 0), idx(n, n), idx(0, n)]
    else:
        idx = lambda i, j, k: (k * (n + 1) + j) * (n + 1) + i + 1
        for k in range(n + 1):
            for j in range(n + 1):
                for i in range(n + 1):
                    pts.append((i / n, j / n, k / n))
        # Each cube as six tetrahedra around its diagonal 0-6 (Kuhn).
        paths = list(itertools.permutations((1, 2, 4)))
        for k in range(n):
            for j in range(n):
                for i in range(n):
                    c = [idx(i + (q & 1), j + (q >> 1 & 1), k + (q >> 2 & 1)) for q in range(8)]
                    for a, b, _ in paths:
                        els.append([c[0], c[a], c[a | b], c[7]])
        # Orient every tetrahedron positively.
        def vol(t):
            a, b, c_, d = (pts[x - 1] for x in t)
            u = [b[q] - a[q] for q in range(3)]
            v = [c_[q] - a[q] for q in range(3)]
            w = [d[q] - a[q] for q in range(3)]
            return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
                    + u[2] * (v[0] * w[1] - v[1] * w[0]))
        els = [t if vol(t) > 0 else [t[1], t[0], t[2], t[3]] for t in els]
        faces = {}
        for t in els:
            for f in ((t[1], t[2], t[3]), (t[0], t[3], t[2]), (t[0], t[1], t[3]), (t[0], t[2], t[1])):
                key = tuple(sorted(f))
                faces[key] = None if key in faces else f
        for f in faces.values():
            if f is None:
                continue
            c = [sum(pts[x - 1][q] for x in f) / 3 for q in range(3)]
            side = next(s for s, (q, v) in enumerate([(0, 0), (0, 1), (1, 0), (1, 1), (2, 0), (2, 1)]) if abs(c[q] - v) < 1e-12)
            bnd.append((f, side + 1))
        bnd.sort()
        corners = [idx(i, j, k) for k in (0, n) for j in (0, n) for i in (0, n)]
        # The twelve edges of the cube, as ridges.
        for a in range(3):
            for u in (0, n):
                for v in (0, n):
                    for t in range(n):
                        ends = []
                        for w in (t, t + 1):
                            c = [0, 0, 0]
                            c[a], c[(a + 1) % 3], c[(a + 2) % 3] = w, u, v
                            ends.append(idx(*c))
                        ridges.append(tuple(ends))
    with open(path, "w") as out:
        out.write(f"MeshVersionFormatted 2\nDimension {dim}\nVertices\n{len(pts)}\n")
        for p in pts:
            out.write(" ".join(repr(x) for x in p[:dim]) + " 0\n")
        kind = ("Edges", "Triangles") if dim == 2 else ("Triangles", "Tetrahedra")
        out.write(f"{kind[0]}\n{len(bnd)}\n")
        for f, r in bnd:
            out.write(" ".join(map(str, f)) + f" {r}\n")
        out.write(f"{kind[1]}\n{len(els)}\n")
        for t in els:
            out.write(" ".join(map(str, t)) + " 0\n")
        if ridges:
            out.write(f"Edges\n{len(ridges)}\n" + "".join(f"{a} {b} 0\n" for a, b in ridges))
            out.write(f"Ridges\n{len(ridges)}\n" + "".join(f"{i + 1}\n" for i in range(len(ridges))))
        out.write(f"Corners\n{len(corners)}\n" + "".join(f"{c}\n" for c in corners) + "End\n")


def read_vertices(path, dim):
    """The vertices of a Medit .mesh (ASCII)."""
    tok = open(path).read().split()
    k = tok.index("Vertices")
    n = int(tok[k + 1])
    out = []
    for i in range(n):
        base = k + 2 + i * (dim + 1)
        out.append([float(x) for x in tok[base:base + dim]])
    return out


def unit_count(path, case, dim):
    """The number of elements of a unit mesh of the analytic metric:
    sum over the mesh's elements of volume * sqrt(det M(centroid)), over
    the metric volume of the regular unit simplex."""
    pts = read_vertices(path, dim)
    tok = open(path).read().split()
    k = tok.index("Triangles" if dim == 2 else "Tetrahedra")
    n = int(tok[k + 1])
    total = 0.0
    for i in range(n):
        base = k + 2 + i * (dim + 2)
        c = [pts[int(x) - 1] for x in tok[base:base + dim + 1]]
        e = [[c[j][q] - c[0][q] for q in range(dim)] for j in range(1, dim + 1)]
        g = [sum(x[q] for x in c) / (dim + 1) for q in range(dim)]
        m = metric_matrix(case, g, dim)
        if dim == 2:
            vol = abs(e[0][0] * e[1][1] - e[0][1] * e[1][0]) / 2
            det = m[0][0] * m[1][1] - m[0][1] * m[1][0]
        else:
            d3 = lambda a: (a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
                            - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
                            + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]))
            vol, det = abs(d3(e)) / 6, d3(m)
        total += vol * math.sqrt(max(det, 0.0))
    return total / (math.sqrt(3) / 4 if dim == 2 else math.sqrt(2) / 12)


def write_metric(mesh, sol, case, dim):
    pts = read_vertices(mesh, dim)
    with open(sol, "w") as out:
        out.write(f"MeshVersionFormatted 2\nDimension {dim}\nSolAtVertices\n{len(pts)}\n1 3\n")
        for p in pts:
            out.write(" ".join(repr(x) for x in metric(case, p, dim)) + "\n")
        out.write("End\n")


def timed(cmd):
    """Runs cmd; (seconds, peak RSS in MB of this child)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    res = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    dt = time.perf_counter() - t
    if res.returncode != 0:
        sys.exit(f"failed ({res.returncode}): {' '.join(cmd)}\n{res.stdout}")
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return dt, max(after.ru_maxrss, before.ru_maxrss) / 1024.0


def peak_of(cmd):
    """Peak RSS (MB) of one run, by /usr/bin/time when present."""
    if os.path.exists("/usr/bin/time"):
        res = subprocess.run(["/usr/bin/time", "-f", "%e %M"] + cmd, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
        if res.returncode != 0:
            sys.exit(f"failed ({res.returncode}): {' '.join(cmd)}\n{res.stdout}{res.stderr}")
        e, m = res.stderr.strip().splitlines()[-1].split()
        return float(e), float(m) / 1024.0
    return timed(cmd)


def run_case(args, case, tool):
    d = os.path.join(args.work, f"{case}-{tool}")
    os.makedirs(d, exist_ok=True)
    cur = os.path.join(d, "it0.mesh")
    grid_mesh(cur, args.n, args.dim)
    total, peak = 0.0, 0.0
    for it in range(1, args.iters + 1):
        sol = cur[:-5] + ".sol"
        write_metric(cur, sol, case, args.dim)
        nxt = os.path.join(d, f"it{it}.mesh")
        if tool == "delone":
            cmd = [args.delone, "adapt", cur, "--metric", sol, "-o", nxt, "-hgrad", str(args.hgrad), "-Q"]
        else:
            cmd = [args.mmg, "-in", cur, "-sol", sol, "-out", nxt, "-hgrad", str(args.hgrad), "-v", "-1"]
        dt, mem = peak_of(cmd)
        total += dt
        peak = max(peak, mem)
        cur = nxt
    sol = cur[:-5] + ".measure.sol"
    write_metric(cur, sol, case, args.dim)
    stats = os.path.join(d, "stats.json")
    subprocess.run([args.delone, "adapt", cur, "--metric", sol, "-noinsert", "-noswap", "-nomove",
                    "--stats-json", stats, "-Q"], check=True)
    s = json.load(open(stats))["after"]
    return {"in": s["in_range_share"], "qmin": s["quality_min"], "qmean": s["quality_mean"],
            "el": s["elements"], "time": total, "mem": peak, "unit": unit_count(cur, case, args.dim)}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--delone", default="target/release/delone")
    ap.add_argument("--mmg", default=None, help="mmg2d_O3 or mmg3d_O3 (default: by --dim in /tmp/mmgvenv/bin)")
    ap.add_argument("--dim", type=int, default=2, choices=(2, 3))
    ap.add_argument("--cases", default="linear,polar1,polar2,sine")
    ap.add_argument("--iters", type=int, default=5)
    ap.add_argument("--n", type=int, default=0, help="cells per side of the start mesh (default 10)")
    ap.add_argument("--hgrad", type=float, default=-1, help="both tools' -hgrad (-1: none)")
    ap.add_argument("--work", default="/tmp/adapt_vs_mmg")
    args = ap.parse_args()
    args.n = args.n or 10
    args.mmg = args.mmg or f"/tmp/mmgvenv/bin/mmg{args.dim}d_O3"
    os.makedirs(args.work, exist_ok=True)
    print(f"{args.dim}D, {args.iters} iterations from a {args.n}^{args.dim} grid, -hgrad {args.hgrad}")
    head = f"{'case':8} {'tool':7} {'in range':>9} {'q min':>7} {'q mean':>7} {'elements':>9} {'time s':>8} {'MB':>7} {'unit':>7} {'el/unit':>7}"
    print(head)
    for case in args.cases.split(","):
        r = {tool: run_case(args, case, tool) for tool in ("delone", "mmg")}
        for tool in ("delone", "mmg"):
            x = r[tool]
            print(f"{case:8} {tool:7} {100 * x['in']:8.1f}% {x['qmin']:7.3f} {x['qmean']:7.3f} {x['el']:9d} {x['time']:8.3f} {x['mem']:7.1f} {x['unit']:7.0f} {x['el'] / x['unit']:7.3f}")
        d, m = r["delone"], r["mmg"]
        ratio = lambda a, b: a / b if b else float("nan")
        print(f"{case:8} {'ratio':7} {ratio(d['in'], m['in']):9.3f} {ratio(d['qmin'], m['qmin']):7.3f} "
              f"{ratio(d['qmean'], m['qmean']):7.3f} {ratio(d['el'], m['el']):9.3f} "
              f"{ratio(d['time'], m['time']):8.3f} {ratio(d['mem'], m['mem']):7.3f}")


if __name__ == "__main__":
    main()
