//! Quality refinement in parallel parts on random PSLGs: every result is a
//! valid constrained Delaunay mesh meeting the bounds except at small input
//! angles, close to the sequential triangle count, and the same for every
//! thread count (the parts depend on the input and options only).

use delone::model::pslg::Pslg;
use delone::tri::constrain::{check_cdt, constrained_triangulation, Cdt, CdtOptions};
use delone::tri::refine::{refine, RefineOptions, Refined, UnfixableReason};

fn min_angle(p: &[[f64; 2]], v: &[u32; 3]) -> f64 {
    let mut lo = 180.0f64;
    for k in 0..3 {
        let a = p[v[k] as usize];
        let b = p[v[(k + 1) % 3] as usize];
        let c = p[v[(k + 2) % 3] as usize];
        let (ux, uy) = (b[0] - a[0], b[1] - a[1]);
        let (vx, vy) = (c[0] - a[0], c[1] - a[1]);
        lo = lo.min(
            (ux * vy - uy * vx)
                .abs()
                .atan2(ux * vx + uy * vy)
                .to_degrees(),
        );
    }
    lo
}

fn area(p: &[[f64; 2]], v: &[u32; 3]) -> f64 {
    let (a, b, c) = (p[v[0] as usize], p[v[1] as usize], p[v[2] as usize]);
    0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
}

/// Xorshift in [0, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A unit square with `n` random segments inside (crossing ones too), a
/// hole square in one corner, and a point on a segment.
fn random_pslg(rng: &mut Rng, n: usize) -> Pslg {
    let mut pts = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let mut segs = vec![[0, 1], [1, 2], [2, 3], [3, 0]];
    for _ in 0..n {
        let k = pts.len() as u32;
        pts.push([0.05 + 0.9 * rng.next(), 0.05 + 0.9 * rng.next()]);
        pts.push([0.05 + 0.9 * rng.next(), 0.05 + 0.9 * rng.next()]);
        segs.push([k, k + 1]);
    }
    // A point on the bottom side.
    pts.push([0.5 * rng.next() + 0.25, 0.0]);
    Pslg::new(pts, segs)
}

fn check(name: &str, g: &Pslg, r: &Refined, bound: f64, max_area: f64) {
    check_cdt(g, &r.mesh).unwrap_or_else(|v| panic!("{name}: {v}"));
    let m = &r.mesh;
    let mut low = 0;
    for (t, v) in m.triangles.iter().enumerate() {
        assert!(
            area(&m.points, v) <= max_area * (1.0 + 1e-12),
            "{name}: triangle {t} too big"
        );
        if min_angle(&m.points, v) < bound - 1e-9 {
            low += 1;
            let u = r.report.unfixable.iter().find(|u| u.triangle == t as u32);
            assert!(
                matches!(
                    u.map(|u| u.reason),
                    Some(UnfixableReason::SmallInputAngle { .. })
                ),
                "{name}: triangle {t} below {bound}° not reported as at a small input angle: {u:?}"
            );
        }
    }
    assert_eq!(low, r.report.unfixable.len(), "{name}");
    assert!(!r.report.limit_reached, "{name}");
}

fn opts(threads: usize, max_area: f64) -> RefineOptions {
    RefineOptions {
        min_angle: Some(28.0),
        max_area: Some(max_area),
        threads,
        parallel_min_triangles: 0,
        ..Default::default()
    }
}

/// The sequential refinement (no parts, whatever the size).
fn sequential(o: RefineOptions) -> RefineOptions {
    RefineOptions {
        parallel_min_triangles: usize::MAX,
        ..o
    }
}

#[test]
fn random_pslgs_refine_validly_in_parallel() {
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    for case in 0..12 {
        let g = random_pslg(&mut rng, 2 + case % 5);
        let cdt: Cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
        let max_area = 2e-4 * (1.0 + (case % 3) as f64);
        let seq = refine(&cdt, &sequential(opts(1, max_area))).unwrap();
        check(&format!("case {case} sequential"), &g, &seq, 28.0, max_area);
        let n1 = seq.mesh.triangles.len() as f64;
        let one = refine(&cdt, &opts(1, max_area)).unwrap();
        check(&format!("case {case} parts"), &g, &one, 28.0, max_area);
        let n = one.mesh.triangles.len() as f64;
        assert!(
            (n - n1).abs() <= 0.1 * n1,
            "case {case}: {n} triangles vs {n1}"
        );
        for threads in [2, 3, 4] {
            let r = refine(&cdt, &opts(threads, max_area)).unwrap();
            assert!(r == one, "case {case}: {threads} threads differ from one");
        }
    }
}

/// A refinement large enough for parts at the default size threshold (and
/// for more than two of them) gives the same mesh with 1, 2 and 5 threads.
#[test]
fn the_thread_count_does_not_change_the_mesh() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let g = random_pslg(&mut rng, 6);
    let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
    // 1.6 triangles predicted per unit of area over the bound: about 530,000
    // (PARALLEL_MIN_TRIANGLES is 50,000; above 400,000 there are 4 parts).
    let o = |threads| RefineOptions {
        min_angle: Some(30.0),
        max_area: Some(3e-6),
        threads,
        ..Default::default()
    };
    let one = refine(&cdt, &o(1)).unwrap();
    let n = one.mesh.triangles.len();
    assert!(n > 450_000, "{n} triangles: too few for 4 parts");
    check_cdt(&g, &one.mesh).unwrap();
    assert!(
        one.report.met,
        "{:?}",
        &one.report.unfixable[..3.min(one.report.unfixable.len())]
    );
    // The parts really ran: the sequential refinement differs.
    let seq = refine(&cdt, &sequential(o(1))).unwrap();
    assert_ne!(seq.mesh.points, one.mesh.points);
    let ns = seq.mesh.triangles.len() as f64;
    assert!(
        (n as f64 - ns).abs() <= 0.01 * ns,
        "{n} triangles in parts, {ns} sequential"
    );
    for threads in [2, 5] {
        let r = refine(&cdt, &o(threads)).unwrap();
        assert!(
            r.mesh.triangles == one.mesh.triangles,
            "{threads} threads: other triangles"
        );
        assert!(
            r.mesh.points == one.mesh.points,
            "{threads} threads: other points"
        );
        assert!(r == one, "{threads} threads: other result");
    }
}

#[test]
fn small_meshes_and_budgets_are_sequential() {
    let mut rng = Rng(7);
    let g = random_pslg(&mut rng, 4);
    let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
    let seq = refine(&cdt, &sequential(opts(1, 1e-3))).unwrap();
    // Below the size threshold there are no parts, whatever the threads.
    let small = RefineOptions {
        parallel_min_triangles: 1_000_000,
        ..opts(4, 1e-3)
    };
    assert_eq!(refine(&cdt, &small).unwrap(), seq);
    // Options the parts do not support are sequential too.
    let budget = RefineOptions {
        max_steiner: Some(1_000_000),
        ..opts(2, 1e-3)
    };
    assert_eq!(
        refine(&cdt, &budget).unwrap(),
        refine(&cdt, &sequential(budget)).unwrap()
    );
    // The parts really differ from the sequential path (they are exercised).
    let par = refine(&cdt, &opts(2, 1e-3)).unwrap();
    assert_ne!(par.mesh.points, seq.mesh.points);
}

/// Regions with their own area bounds and a hole, in 2 parts.
#[test]
fn regions_and_holes_in_parallel() {
    use delone::model::pslg::Region;
    let mut g = Pslg::new(
        vec![
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [0.0, 1.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [1.4, 0.4],
            [1.6, 0.4],
            [1.6, 0.6],
            [1.4, 0.6],
        ],
        vec![
            [0, 4],
            [4, 1],
            [1, 2],
            [2, 5],
            [5, 3],
            [3, 0],
            [4, 5],
            [6, 7],
            [7, 8],
            [8, 9],
            [9, 6],
        ],
    );
    g.holes = vec![[1.5, 0.5]];
    g.regions = vec![
        Region {
            point: [0.5, 0.5],
            attribute: 1.0,
            max_area: 2e-4,
        },
        Region {
            point: [1.2, 0.5],
            attribute: 2.0,
            max_area: -1.0,
        },
    ];
    let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
    let o = RefineOptions {
        regional_areas: true,
        ..opts(2, 1e-3)
    };
    let r = refine(&cdt, &o).unwrap();
    check("regions", &g, &r, 28.0, 1e-3);
    let m = &r.mesh;
    for (t, v) in m.triangles.iter().enumerate() {
        let c = [0, 1].map(|k| v.iter().map(|&i| m.points[i as usize][k]).sum::<f64>() / 3.0);
        assert!(
            !(c[0] > 1.4 && c[0] < 1.6 && c[1] > 0.4 && c[1] < 0.6),
            "triangle {t} in the hole"
        );
        let want = if c[0] < 1.0 { 1.0 } else { 2.0 };
        assert_eq!(m.attributes[t], want, "triangle {t} region");
        if want == 1.0 {
            assert!(area(&m.points, v) <= 2e-4 * (1.0 + 1e-12), "triangle {t}");
        }
    }
}
