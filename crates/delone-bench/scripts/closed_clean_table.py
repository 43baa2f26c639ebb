#!/usr/bin/env python3
"""Two programs side by side on the corpus' closed-clean surfaces, one run.

  python3 crates/delone-bench/scripts/closed_clean_table.py A B [--sw -pq1.414]
      [--min 0] [--max 8000] [--models a,b] [--tetgen PATH] [--tg-sw SW]

A and B are `delone` binaries (an older and a newer build, say) or `tg` for TetGen 1.6's
command-line program (built by ../shared/reference/build-tetgen.sh unless --tetgen names
it). Each model of ../shared/data/sets/closed_clean.txt with min <= triangles < max is
copied to a temporary folder and meshed there by A, then by B (`delone tet SW -Q
--stats-json`, `tetgen -Q SW`) under /usr/bin/time: wall time, peak resident memory,
tetrahedra and (delone) minimum dihedral angle per model, then the sums and the median
time ratio B/A. Exit code 3 of delone (a bound missed) counts as a run.

--tg-sw gives TetGen other switches than delone's: `--sw=-p --tg-sw=-pM` compares
delone `-p` (which merges only exactly coplanar triangles) with TetGen keeping every
input triangle (`-M`); TetGen's `-p` alone merges neighbouring triangles that are
coplanar up to an angle and re-triangulates them, so it solves another problem.
"""
import sys, os, subprocess, json, shutil, statistics, argparse, tempfile, re
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
ap = argparse.ArgumentParser()
ap.add_argument('a'); ap.add_argument('b')
ap.add_argument('--sw', default='-pq1.414'); ap.add_argument('--max', type=int, default=8000)
ap.add_argument('--min', type=int, default=0)
ap.add_argument('--models', default=''); ap.add_argument('--timeout', type=int, default=600)
ap.add_argument('--tetgen', default='')
ap.add_argument('--tg-sw', default='', help="TetGen's switches when they differ from --sw")
a = ap.parse_args()
if 'tg' in (a.a, a.b) and not a.tetgen:
    a.tetgen = subprocess.run(['sh', os.path.join(os.path.dirname(ROOT), 'shared', 'reference', 'build-tetgen.sh')],
                              capture_output=True, text=True, check=True).stdout.strip().splitlines()[-1]
D = os.path.join(os.path.dirname(ROOT), 'shared', 'data') + '/'
rows = [l.split() for l in open(D + 'sets/closed_clean.txt')]
if a.models:
    want = a.models.split(',')
    rows = [r for r in rows if os.path.basename(r[0])[:-4] in want]
else:
    rows = [r for r in rows if a.min <= int(r[1]) < a.max]
work = tempfile.mkdtemp(prefix='t3d-')
def run(binary, model):
    d = os.path.join(work, os.path.basename(binary) + '-' + model)
    os.makedirs(d, exist_ok=True)
    src = D + 'surf/off/' + model + '.off'
    shutil.copy(src, d)
    f = os.path.join(d, model + '.off')
    if binary == 'tg':
        cmd = [a.tetgen, '-Q' + (a.tg_sw or a.sw).lstrip('-'), f]
    else:
        cmd = [binary, 'tet', a.sw, '-Q', '--stats-json', d + '/s.json', f]
    try:
        p = subprocess.run(['/usr/bin/time', '-f', 'TIME %e %U %M'] + cmd, capture_output=True, text=True, timeout=a.timeout)
    except subprocess.TimeoutExpired:
        return None
    m = re.search(r'TIME (\S+) (\S+) (\S+)', p.stderr)
    t, u, rss = float(m.group(1)), float(m.group(2)), int(m.group(3)) / 1024
    tets, mind = None, None
    if binary == 'tg':
        ele = os.path.join(d, model + '.1.ele')
        if os.path.exists(ele):
            tets = int(open(ele).readline().split()[0])
    else:
        try:
            s = json.load(open(d + '/s.json')); tets = s['tets']; mind = s['min_dihedral']
        except Exception:
            pass
    shutil.rmtree(d, ignore_errors=True)
    return t, rss, tets, mind, p.returncode
print(f"{'model':24} {'tris':>7} | {'A s':>7} {'A MB':>7} {'A tets':>8} {'A min':>6} | {'B s':>7} {'B MB':>7} {'B tets':>8} {'B min':>6} | t B/A  MB B/A")
ta = tb = ma = mb = 0; ratios = []
for path, n in rows:
    model = os.path.basename(path)[:-4]
    ra = run(a.a, model); rb = run(a.b, model)
    if ra is None or rb is None:
        print(f'{model:24} timeout', ra, rb); continue
    ta += ra[0]; tb += rb[0]; ma += ra[1]; mb += rb[1]
    ratios.append(rb[0] / max(ra[0], 1e-3))
    f = lambda r: f"{r[0]:7.2f} {r[1]:7.1f} {str(r[2]):>8} {('%6.2f' % r[3]) if r[3] is not None else '     -'}" + ('' if r[4] in (0, 3) else f' rc{r[4]}')
    print(f'{model:24} {n:>7} | {f(ra)} | {f(rb)} | {rb[0]/max(ra[0],1e-3):5.2f} {rb[1]/ra[1]:5.3f}', flush=True)
print(f'sum time A {ta:.1f} B {tb:.1f} ({tb/ta:.3f}); sum MB A {ma:.1f} B {mb:.1f} ({mb/ma:.4f}); median time B/A {statistics.median(ratios):.3f}')
shutil.rmtree(work, ignore_errors=True)
