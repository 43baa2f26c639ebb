#!/usr/bin/env python3
"""Closed, self-intersection-free surfaces that are hard for boundary recovery
(made here, never tuned on), and a side-by-side run of delone and TetGen 1.6.

The models are the classes CAD users bring: extrusions of polygons whose caps are
ear-clipped into long thin triangles (cylinders, gears, a comb of thin slots),
twisted prisms (Schönhardt bands stacked), latitude-longitude spheres (pole fans),
and boxes whose faces are fine grids with tiny off-plane noise (near-coplanar
triangles).

    python3 crates/delone-bench/scripts/hard_surfaces.py --out /tmp/hard   # write only
    python3 crates/delone-bench/scripts/hard_surfaces.py --out /tmp/hard \
        --delone target/release/delone --tetgen /tmp/tg16/tetgen --switches=-pY,-p

For each model and switch: exit code, wall time, Steiner points (delone's
`--stats-json`) and minimum dihedral angle; TetGen's exit code, time and its
Steiner summary lines; the time ratio. A run past `--timeout` seconds is `TO`.
TetGen 1.6: `sh ../shared/reference/build-tetgen.sh /tmp/tg16`.
"""
import argparse, json, math, os, random, shutil, subprocess, time

def write_off(name, V, F):
    with open(name, 'w') as f:
        f.write(f"OFF\n{len(V)} {len(F)} 0\n")
        for v in V: f.write(f"{v[0]:.17g} {v[1]:.17g} {v[2]:.17g}\n")
        for t in F: f.write(f"3 {t[0]} {t[1]} {t[2]}\n")

def extrude(poly, h, twist=0.0, levels=1):
    """Prism over a simple ccw polygon, `levels` bands twisted by `twist` in
    all, caps ear-clipped (thin triangles)."""
    n = len(poly); V = []; F = []
    for l in range(levels + 1):
        a = twist * l / levels; c, s = math.cos(a), math.sin(a)
        for x, y in poly: V.append((c * x - s * y, s * x + c * y, h * l / levels))
    for l in range(levels):
        for i in range(n):
            j = (i + 1) % n; a, b = l * n + i, l * n + j; c_, d = a + n, b + n
            F += [(a, b, d), (a, d, c_)]
    top = levels * n
    for a, b, c in ears(poly):
        F.append((a, c, b)); F.append((top + a, top + b, top + c))
    return V, F

def ears(poly):
    """Ear clipping of a simple ccw polygon, always clipping the first ear
    from the lowest index (long thin fan-like triangles, like CAD caps)."""
    idx = list(range(len(poly)))
    cross = lambda o, a, b: (a[0]-o[0])*(b[1]-o[1]) - (a[1]-o[1])*(b[0]-o[0])
    def inside(p, a, b, c):
        return cross(a, b, p) >= 0 and cross(b, c, p) >= 0 and cross(c, a, p) >= 0
    T = []
    while len(idx) > 3:
        for k in range(len(idx)):
            i, j, l = idx[k - 1], idx[k], idx[(k + 1) % len(idx)]
            a, b, c = poly[i], poly[j], poly[l]
            if cross(a, b, c) <= 0: continue
            if any(inside(poly[m], a, b, c) for m in idx if m not in (i, j, l)): continue
            T.append((i, j, l)); idx.pop(k); break
        else:
            raise SystemExit('no ear')
    T.append(tuple(idx)); return T

def gear(teeth=40, r1=1.0, r2=1.15):
    poly = []
    for k in range(teeth):
        for t, r in [(0, r1), (0.2, r2), (0.5, r2), (0.7, r1)]:
            a = 2 * math.pi * (k + t) / teeth; poly.append((r * math.cos(a), r * math.sin(a)))
    return extrude(poly, 0.3)

def cylinder(n=200, h=1.0, levels=1):
    poly = [(math.cos(2 * math.pi * i / n), math.sin(2 * math.pi * i / n)) for i in range(n)]
    return extrude(poly, h, levels=levels)

def twisted(n=3, levels=8, twist=math.pi / 3):
    poly = [(math.cos(2 * math.pi * i / n), math.sin(2 * math.pi * i / n)) for i in range(n)]
    # Side quads split along the diagonal that makes each band a Schönhardt band.
    return extrude(poly, 2.0, twist=twist, levels=levels)

def latlong(nu=64, nv=32):
    V = [(0, 0, 1)]; F = []
    for j in range(1, nv):
        th = math.pi * j / nv
        for i in range(nu):
            ph = 2 * math.pi * i / nu
            V.append((math.sin(th) * math.cos(ph), math.sin(th) * math.sin(ph), math.cos(th)))
    V.append((0, 0, -1)); S = len(V) - 1
    idx = lambda j, i: 1 + (j - 1) * nu + i % nu
    for i in range(nu): F.append((0, idx(1, i), idx(1, i + 1)))
    for j in range(1, nv - 1):
        for i in range(nu):
            a, b, c, d = idx(j, i), idx(j, i + 1), idx(j + 1, i), idx(j + 1, i + 1)
            F += [(a, c, d), (a, d, b)]
    for i in range(nu): F.append((S, idx(nv - 1, i + 1), idx(nv - 1, i)))
    return V, F

def comb(teeth=12):
    """A comb of `teeth` teeth (1 wide, 9 long, slots 1 wide) on a 1-wide
    back, extruded 0.05: long thin slots and strips, a CAD-like model."""
    w = 2 * teeth + 1
    poly = [(0, 0), (w, 0)]
    for k in range(teeth):
        x = w - 2 * k
        poly += [(x, 10), (x - 1, 10), (x - 1, 1), (x - 2, 1)]
    poly[-1] = (0, 1)
    return extrude(poly, 0.05)


def perturbed_box(n=20, eps=1e-9, seed=1):
    """Unit cube, each face an n×n grid whose inner points move off it by up to
    eps along its normal (near-coplanar triangles)."""
    r = random.Random(seed); V = {}; F = []
    def vid(p):
        if p not in V: V[p] = len(V)
        return V[p]
    pts = []
    for axis in range(3):
        for side in (0, 1):
            for i in range(n):
                for j in range(n):
                    q = []
                    for (a, b) in [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]:
                        p = [0, 0, 0]; p[axis] = side; p[(axis + 1) % 3] = a / n; p[(axis + 2) % 3] = b / n
                        q.append(vid(tuple(p)))
                    if side == 0: q = q[::-1]
                    F += [(q[0], q[1], q[2]), (q[0], q[2], q[3])]
    Vl = [None] * len(V)
    for p, k in V.items():
        p = list(p)
        inner = [c for c in p if 0 < c < 1]
        if len(inner) == 2:
            ax = [d for d in range(3) if p[d] in (0, 1)][0]
            p[ax] += (r.random() - 0.5) * eps * 2 * (1 if p[ax] == 0 else 1)
            p[ax] = min(max(p[ax], -eps), 1 + eps)
        Vl[k] = tuple(p)
    return Vl, F


MODELS = {
    "cyl24": lambda: cylinder(24), "cyl50": lambda: cylinder(50), "cyl100": lambda: cylinder(100),
    "cyl200": lambda: cylinder(200), "cyl400x3": lambda: cylinder(400, 1.0, 3),
    "gear40": lambda: gear(), "gear120": lambda: gear(120), "comb12": comb,
    "twist3x8": twisted, "twist5x12": lambda: twisted(5, 12, math.pi / 2),
    "latlong": latlong, "latlong256": lambda: latlong(256, 16),
    "pbox20": perturbed_box, "pbox40e6": lambda: perturbed_box(40, 1e-6, 2),
}


def run(cmd, timeout):
    t0 = time.perf_counter()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        return p.returncode, time.perf_counter() - t0, p.stdout + p.stderr
    except subprocess.TimeoutExpired:
        return "TO", time.perf_counter() - t0, ""


def arguments(default_out, models):
    """The command line shared with `cad_shapes.py`."""
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=default_out)
    ap.add_argument("--delone")
    ap.add_argument("--tetgen")
    ap.add_argument("--switches", default="-p,-pY,-pq1.414")
    ap.add_argument("--models", default=",".join(models))
    ap.add_argument("--timeout", type=float, default=60.0)
    return ap


def main():
    a = arguments("/tmp/hard_surfaces", MODELS).parse_args()
    os.makedirs(a.out, exist_ok=True)
    names = a.models.split(",")
    for m in names:
        write_off(os.path.join(a.out, m + ".off"), *MODELS[m]())
    compare(a, names)


def compare(a, names):
    """Runs delone (and TetGen) on the models `names` written in `a.out`,
    one line per model and switch."""
    if not a.delone:
        print(f"wrote {len(names)} models to {a.out}")
        return
    for sw in a.switches.split(","):
        for m in names:
            d = os.path.join(a.out, f"{m}{sw}")
            shutil.rmtree(d, ignore_errors=True)
            os.makedirs(d)
            f = shutil.copy(os.path.join(a.out, m + ".off"), d)
            js = os.path.join(d, "s.json")
            rd, td, _ = run([a.delone, "tet", sw, "-Q", "--stats-json", js, f], a.timeout)
            info = ""
            if os.path.exists(js):
                s = json.load(open(js))
                r = s.get("steiner", {}).get("recovery", {})
                info = (f"Steiner e{r.get('on_edges')} f{r.get('on_facets')} i{r.get('interior')}"
                        f" min {s.get('min_dihedral', float('nan')):.2f}")
            line = f"{m:11} {sw:9} delone {rd!s:>3} {td:7.2f} s {info:34}"
            if a.tetgen:
                rt, tt, out = run([a.tetgen, sw + "V", f], a.timeout)
                st = "; ".join(x.strip() for x in out.splitlines() if "Steiner" in x)
                line += f"| tetgen {rt!s:>3} {tt:7.2f} s | ratio {td / tt:6.2f} | {st[:70]}"
            print(line, flush=True)


if __name__ == "__main__":
    main()
