#!/usr/bin/env python3
"""The Python package's benchmark (issue targets), one run, one table.

  python scripts/bench-python.py [--n 1000000] [--models N] [--timeout S]

1. 2D Delaunay of n uniform random points from a numpy array: delone vs
   scipy.spatial.Delaunay and triangle.delaunay.
2. 3D Delaunay of n points: delone vs scipy.
3. The package's own overhead at n points: the call's time minus the
   library's (`seconds` reported by the native module).
4. ``TetGen(v, f).tetrahedralize(order=1, mindihedral=20, minratio=1.5)`` on
   the corpus' closed-clean surfaces above 50k triangles
   (../shared/data/sets/closed_clean.txt): delone.tetgen vs the tetgen
   package: time, tetrahedra, minimum dihedral angle.

Each case runs in its own process (fresh memory, a timeout); a package that
is not installed is reported as such.
"""
import argparse
import json
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(os.path.dirname(ROOT), "shared", "data")

CASE = r"""
import json, sys, time
import numpy as np
kind, arg = sys.argv[1], sys.argv[2]
out = {}
if kind in ("2d", "3d"):
    prog, n = arg.split(":")
    dim = 2 if kind == "2d" else 3
    p = np.random.default_rng(7).random((int(n), dim))
    # Imports before the clock starts.
    if prog == "delone":
        import delone
    elif prog == "scipy":
        from scipy.spatial import Delaunay
    elif prog == "triangle":
        import triangle
    t = time.perf_counter()
    if prog == "delone":
        d = delone._delone.delaunay(np.ascontiguousarray(p))
        out["lib"] = d["seconds"]
        out["simplices"] = len(d["simplices"])
    elif prog == "scipy":
        out["simplices"] = len(Delaunay(p).simplices)
    elif prog == "triangle":
        out["simplices"] = len(triangle.delaunay(p))
    out["time"] = time.perf_counter() - t
else:
    prog, path = arg.split(":", 1)
    with open(path) as f:
        lines = [l for l in (l.split("#")[0].strip() for l in f) if l]
    nv, nf = map(int, lines[1].split()[:2]) if lines[0].upper() == "OFF" else map(int, lines[0][3:].split()[:2])
    start = 2 if lines[0].upper() == "OFF" else 1
    v = np.array([l.split()[:3] for l in lines[start:start + nv]], float)
    f = np.array([l.split()[1:4] for l in lines[start + nv:start + nv + nf]], int)
    if prog == "delone":
        from delone.tetgen import TetGen
    else:
        from tetgen import TetGen
    t = time.perf_counter()
    kw = dict(order=1, mindihedral=20, minratio=1.5)
    if prog == "tetgen":
        kw["quiet"] = True
    nodes, elems, _, _ = TetGen(v, f).tetrahedralize(**kw)
    out["time"] = time.perf_counter() - t
    out["simplices"] = len(elems)
    import delone
    # Minimum dihedral angle, computed the same way for both.
    P = nodes
    best = 180.0
    for i, j in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]:
        k, l = [x for x in range(4) if x not in (i, j)]
        a, b, c, d = P[elems[:, i]], P[elems[:, j]], P[elems[:, k]], P[elems[:, l]]
        e = b - a
        n1, n2 = np.cross(e, c - a), np.cross(e, d - a)
        cos = (n1 * n2).sum(1) / np.linalg.norm(n1, axis=1) / np.linalg.norm(n2, axis=1)
        best = min(best, float(np.degrees(np.arccos(np.clip(cos, -1, 1))).min()))
    out["min_dihedral"] = best
print("RESULT " + json.dumps(out))
"""


def case(kind, arg, timeout):
    t = time.perf_counter()
    try:
        p = subprocess.run([sys.executable, "-c", CASE, kind, arg], capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"error": f"timeout {timeout} s"}
    for line in p.stdout.splitlines():
        if line.startswith("RESULT "):
            return json.loads(line[7:])
    err = (p.stderr.strip().splitlines() or ["failed"])[-1]
    return {"error": err[:60], "wall": time.perf_counter() - t}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=1_000_000)
    ap.add_argument("--models", type=int, default=4)
    ap.add_argument("--timeout", type=float, default=600)
    a = ap.parse_args()
    print(f"## Delaunay of {a.n} uniform random points (numpy in, numpy out)\n")
    print("| dim | program | simplices | time s | delone / program |")
    print("|---|---|---:|---:|---:|")
    overhead = {}
    for kind, progs in (("2d", ["delone", "scipy", "triangle"]), ("3d", ["delone", "scipy"])):
        res = {p: case(kind, f"{p}:{a.n}", a.timeout) for p in progs}
        base = res["delone"].get("time")
        if "lib" in res["delone"]:
            overhead[kind] = (res["delone"]["time"], res["delone"]["lib"])
        for p, r in res.items():
            if "error" in r:
                print(f"| {kind} | {p} | | {r['error']} | |")
                continue
            ratio = f"{base / r['time']:.3f}" if base and p != "delone" else ""
            print(f"| {kind} | {p} | {r['simplices']} | {r['time']:.3f} | {ratio} |")
    print("\n## The package's overhead (conversions, thread, checks) at that size\n")
    print("| dim | call s | library s | overhead |")
    print("|---|---:|---:|---:|")
    for kind, (call, lib) in overhead.items():
        print(f"| {kind} | {call:.3f} | {lib:.3f} | {100 * (call - lib) / lib:.1f}% |")
    sets = os.path.join(DATA, "sets", "closed_clean.txt")
    if not os.path.exists(sets):
        print(f"\n(no corpus at {DATA}: TetGen table skipped)")
        return
    models = [l.split() for l in open(sets) if l.strip()]
    models = [(m, int(n)) for m, n in models if int(n) > 50_000][: a.models]
    print("\n## TetGen(v, f).tetrahedralize(order=1, mindihedral=20, minratio=1.5)\n")
    print("| model | triangles | program | tets | min dihedral | time s |")
    print("|---|---:|---|---:|---:|---:|")
    for m, n in models:
        for p in ("delone", "tetgen"):
            r = case("tet", f"{p}:{os.path.join(DATA, m)}", a.timeout)
            name = os.path.basename(m).rsplit(".", 1)[0]
            if "error" in r:
                print(f"| {name} | {n} | {p} | | | {r['error']} |")
            else:
                print(f"| {name} | {n} | {p} | {r['simplices']} | {r['min_dihedral']:.2f} | {r['time']:.2f} |")


if __name__ == "__main__":
    main()
