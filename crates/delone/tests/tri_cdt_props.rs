//! Property tests of the constrained triangulation on random PSLGs with
//! crossing segments, collinear overlapping segments, vertices on segments,
//! tiny angles and duplicate points, plus hand cases.

use delone::model::pslg::{Pslg, Region};
use delone::tri::constrain::{check_cdt, constrained_triangulation, CdtOptions};
use delone::{Error, NONE};

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn run(g: &Pslg, what: &str) -> Result<(), Error> {
    for convex_hull in [true, false] {
        match constrained_triangulation(g, CdtOptions { convex_hull }) {
            Ok(cdt) => {
                check_cdt(g, &cdt).unwrap_or_else(|v| {
                    panic!(
                        "{what} c={convex_hull}: {v}\n{g:?}\n{:?}\n{:?}\nPTS {:?}",
                        cdt.report,
                        cdt.segments
                            .iter()
                            .map(|s| (s.v, s.segment))
                            .collect::<Vec<_>>(),
                        &cdt.points
                    )
                });
                // Every reported crossing vertex is a new point.
                for c in &cdt.report.crossings {
                    assert!(c.vertex as usize >= g.points.len());
                }
                assert_eq!(
                    cdt.points.len(),
                    g.points.len() + cdt.report.crossings.len()
                );
            }
            Err(e) => return Err(e),
        }
    }
    Ok(())
}

#[test]
fn grid_pslgs_with_collinear_overlaps_and_vertices_on_segments() {
    // Small integer grids: many collinear points, overlapping segments,
    // segments through vertices, duplicates, and exact crossings.
    let mut rng = Rng(1);
    for case in 0..cases(3000) {
        let side = 3 + rng.below(6);
        let n = 4 + rng.below(30) as usize;
        let points: Vec<[f64; 2]> = (0..n)
            .map(|_| [rng.below(side) as f64, rng.below(side) as f64])
            .collect();
        let m = rng.below(12) as usize;
        let segments: Vec<[u32; 2]> = (0..m)
            .map(|_| [rng.below(n as u64) as u32, rng.below(n as u64) as u32])
            .collect();
        let mut g = Pslg::new(points, segments);
        if case % 3 == 0 {
            g.holes
                .push([rng.unit() * side as f64, rng.unit() * side as f64]);
        }
        if case % 4 == 0 {
            g.regions.push(Region {
                point: [rng.unit() * side as f64, rng.unit() * side as f64],
                attribute: case as f64,
                max_area: -1.0,
            });
        }
        match run(&g, &format!("grid case {case}")) {
            Ok(()) => {}
            Err(Error::Degenerate { .. } | Error::TooFewPoints { .. }) => {}
            // Crossings are always resolved: no SegmentIntersection error.
            Err(e) => panic!("grid case {case}: {e}\n{g:?}"),
        }
    }
}

#[test]
fn random_crossing_segments() {
    let mut rng = Rng(7);
    for case in 0..cases(2000) {
        let n = 6 + rng.below(60) as usize;
        let points: Vec<[f64; 2]> = (0..n).map(|_| [rng.unit(), rng.unit()]).collect();
        let m = 1 + rng.below(25) as usize;
        let segments: Vec<[u32; 2]> = (0..m)
            .map(|_| [rng.below(n as u64) as u32, rng.below(n as u64) as u32])
            .collect();
        let g = Pslg::new(points, segments);
        if let Err(e) = run(&g, &format!("random case {case}")) {
            panic!("random case {case}: {e}\n{g:?}");
        }
    }
}

/// Random points at a scale, many long segments (dozens of crossings each).
fn dense_case(rng: &mut Rng, scale: f64, offset: f64) -> Pslg {
    let n = 10 + rng.below(50) as usize;
    let points: Vec<[f64; 2]> = (0..n)
        .map(|_| [offset + rng.unit() * scale, offset + rng.unit() * scale])
        .collect();
    let m = 10 + rng.below(50) as usize;
    let segments: Vec<[u32; 2]> = (0..m)
        .map(|_| [rng.below(n as u64) as u32, rng.below(n as u64) as u32])
        .collect();
    Pslg::new(points, segments)
}

#[test]
fn many_crossings_every_scale() {
    // About 1% of these ended in SegmentIntersection before crossings were
    // inserted as vertices of the triangulation.
    let mut rng = Rng(11);
    for case in 0..cases(1000) {
        let (scale, offset) = match case % 5 {
            0 => (1.0, 0.0),
            1 => (1e-200, 0.0),
            2 => (1e200, -1e200),
            3 => (1e-3, 1e3), // far from the origin: few bits left
            _ => (1e9, 0.0),
        };
        let g = dense_case(&mut rng, scale, offset);
        if let Err(e) = run(&g, &format!("dense case {case}")) {
            panic!("dense case {case}: {e}\n{g:?}");
        }
    }
}

#[test]
fn near_parallel_crossings() {
    // Fans of nearly parallel segments crossed by nearly parallel ones.
    let mut rng = Rng(5);
    for case in 0..cases(300) {
        let k = 3 + rng.below(8) as usize;
        let eps = [1e-3, 1e-8, 1e-13, 1e-15][case % 4];
        let mut points = Vec::new();
        let mut segments = Vec::new();
        for j in 0..k {
            let y0 = (rng.unit() - 0.5) * eps;
            let y1 = (rng.unit() - 0.5) * eps;
            points.push([0.0, y0 + j as f64 * eps]);
            points.push([1.0, y1 - j as f64 * eps]);
            segments.push([2 * j as u32, 2 * j as u32 + 1]);
        }
        let base = points.len() as u32;
        for j in 0..k {
            points.push([rng.unit(), -1.0]);
            points.push([rng.unit(), 1.0]);
            segments.push([base + 2 * j as u32, base + 2 * j as u32 + 1]);
        }
        let g = Pslg::new(points, segments);
        if let Err(e) = run(&g, &format!("near-parallel case {case}")) {
            panic!("near-parallel case {case}: {e}\n{g:?}");
        }
    }
}

#[test]
fn collinear_overlaps_duplicates_and_vertices_on_crossed_segments() {
    // Points on a few lines, segments along the lines (overlapping), across
    // them (crossing), duplicated points and duplicated segments.
    let mut rng = Rng(9);
    for case in 0..cases(500) {
        let mut points = Vec::new();
        for _ in 0..3 {
            let (x0, y0) = (rng.unit(), rng.unit());
            let (dx, dy) = (rng.unit() - 0.5, rng.unit() - 0.5);
            for _ in 0..4 {
                let t = rng.below(8) as f64 / 4.0;
                points.push([x0 + t * dx, y0 + t * dy]);
            }
        }
        let n = points.len();
        for _ in 0..3 {
            let i = rng.below(n as u64) as usize;
            points.push(points[i]);
        }
        let n = points.len() as u64;
        let mut segments: Vec<[u32; 2]> = (0..12)
            .map(|_| [rng.below(n) as u32, rng.below(n) as u32])
            .collect();
        segments.push(segments[0]);
        segments.push([segments[1][1], segments[1][0]]);
        let g = Pslg::new(points, segments);
        match run(&g, &format!("collinear case {case}")) {
            Ok(()) | Err(Error::Degenerate { .. }) => {}
            Err(e) => panic!("collinear case {case}: {e}\n{g:?}"),
        }
    }
}

#[test]
fn tiny_angles_and_fans() {
    // Many segments from one vertex at tiny angles to each other, crossed by
    // a long segment.
    let mut pts = vec![[0.0, 0.0]];
    for k in 0..40 {
        let a = 1e-9 * k as f64;
        pts.push([a.cos(), a.sin()]);
    }
    pts.push([0.5, -0.1]);
    pts.push([0.5, 0.1]);
    let mut segs: Vec<[u32; 2]> = (1..=40).map(|k| [0, k]).collect();
    segs.push([41, 42]);
    let g = Pslg::new(pts, segs);
    run(&g, "fan").unwrap();
}

#[test]
fn scales() {
    for s in [1e-9, 1.0, 1e9, 1e-200, 1e200] {
        let pts: Vec<[f64; 2]> = [
            [0.0, 0.0],
            [3.0, 0.0],
            [3.0, 3.0],
            [0.0, 3.0],
            [1.0, 1.0],
            [2.0, 2.0],
        ]
        .iter()
        .map(|p| [p[0] * s, p[1] * s])
        .collect();
        let g = Pslg::new(pts, vec![[0, 2], [1, 3], [4, 5]]);
        let cdt = constrained_triangulation(&g, CdtOptions { convex_hull: true }).unwrap();
        check_cdt(&g, &cdt).unwrap();
        // [0,2] passes through 4 and 5; [1,3] crosses it at the centre.
        assert_eq!(cdt.report.crossings.len(), 1, "scale {s}");
        assert_eq!(cdt.points[6], [1.5 * s, 1.5 * s]);
    }
}

#[test]
fn errors_name_the_item() {
    let g = Pslg::new(
        vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
        vec![[0, 1], [1, 9]],
    );
    assert_eq!(
        constrained_triangulation(&g, CdtOptions::default()),
        Err(Error::SegmentOutOfRange {
            segment: 1,
            point: 9
        })
    );
    let g = Pslg::new(vec![[0.0, 0.0], [f64::NAN, 0.0], [0.0, 1.0]], vec![]);
    assert_eq!(
        constrained_triangulation(&g, CdtOptions::default()),
        Err(Error::InvalidCoordinate { index: 1 })
    );
    let mut g = Pslg::new(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], vec![]);
    g.holes.push([f64::NAN, 0.0]);
    assert_eq!(
        constrained_triangulation(&g, CdtOptions::default()),
        Err(Error::InvalidSeedPoint {
            kind: "hole",
            index: 0
        })
    );
    // Duplicates and zero-length segments are merged and reported.
    let g = Pslg::new(
        vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 0.0]],
        vec![[1, 3], [0, 3], [0, 1]],
    );
    let cdt = constrained_triangulation(&g, CdtOptions { convex_hull: true }).unwrap();
    assert_eq!(cdt.report.duplicate_points, vec![(3, 1)]);
    assert_eq!(cdt.report.skipped_segments, vec![0]);
    check_cdt(&g, &cdt).unwrap();
}

#[test]
fn hole_and_region_by_hand() {
    // A 4x4 square with a 2x2 square hole in the middle, split by a vertical
    // segment into two regions (attributes 1 and 2).
    let pts = vec![
        [0.0, 0.0],
        [4.0, 0.0],
        [4.0, 4.0],
        [0.0, 4.0], // outer 0..3
        [1.0, 1.0],
        [3.0, 1.0],
        [3.0, 3.0],
        [1.0, 3.0], // hole 4..7
        [2.0, 0.0],
        [2.0, 4.0], // divider ends 8, 9
    ];
    let segs = vec![
        [0, 8],
        [8, 1],
        [1, 2],
        [2, 9],
        [9, 3],
        [3, 0],
        [4, 5],
        [5, 6],
        [6, 7],
        [7, 4],
        [8, 9], // crosses the hole's edges 4-5 and 6-7 at (2,1) and (2,3)
    ];
    let mut g = Pslg::new(pts, segs);
    g.segment_markers = (0..11).collect();
    // The divider cuts the hole in two: one hole point on each side.
    g.holes.push([2.5, 2.0]);
    g.holes.push([1.5, 2.0]);
    g.regions.push(Region {
        point: [0.5, 2.0],
        attribute: 1.0,
        max_area: 0.5,
    });
    g.regions.push(Region {
        point: [3.5, 2.0],
        attribute: 2.0,
        max_area: -1.0,
    });
    let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
    check_cdt(&g, &cdt).unwrap();
    assert_eq!(
        cdt.report.crossings.len(),
        2,
        "{:?} {:?}",
        cdt.report,
        &cdt.points[10..]
    );
    let mut xs: Vec<[f64; 2]> = cdt
        .report
        .crossings
        .iter()
        .map(|c| cdt.points[c.vertex as usize])
        .collect();
    xs.sort_by(|a, b| a.partial_cmp(b).unwrap());
    assert_eq!(xs, vec![[2.0, 1.0], [2.0, 3.0]]);
    // Area: 16 - 4 = 12, half on each side.
    let area = |t: &[u32; 3]| {
        let [a, b, c] = t.map(|v| cdt.points[v as usize]);
        0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]))
    };
    let total: f64 = cdt.triangles.iter().map(area).sum();
    assert!((total - 12.0).abs() < 1e-12, "{total}");
    for r in 0..2u32 {
        let a: f64 = cdt
            .triangles
            .iter()
            .zip(&cdt.regions)
            .filter(|(_, &x)| x == r)
            .map(|(t, _)| area(t))
            .sum();
        assert!((a - 6.0).abs() < 1e-12, "region {r}: {a}");
    }
    assert!(cdt.regions.iter().all(|&r| r != NONE));
    for (t, &r) in cdt.regions.iter().enumerate() {
        assert_eq!(cdt.attributes[t], [1.0, 2.0][r as usize]);
        assert_eq!(cdt.max_areas[t], [0.5, -1.0][r as usize]);
    }
    // The divider inside the hole is kept as a non-bounding subsegment.
    assert!(cdt.segments.iter().any(|s| s.segment == 10 && !s.bounding));
    assert!(cdt.segments.iter().all(|s| s.marker == s.segment as i32));
}

#[test]
fn checker_catches_a_missing_segment_and_a_non_delaunay_edge() {
    let g = Pslg::new(
        vec![[0.0, 0.0], [4.0, 0.0], [4.0, 1.0], [0.0, 1.0], [2.0, 0.45]],
        vec![[0, 2]],
    );
    let cdt = constrained_triangulation(&g, CdtOptions { convex_hull: true }).unwrap();
    check_cdt(&g, &cdt).unwrap();
    let mut bad = cdt.clone();
    bad.segments.clear();
    assert!(check_cdt(&g, &bad).is_err());
    // Without the segment, the mesh is not the DT, so dropping the segment
    // labels breaks the Delaunay property.
    let g2 = Pslg::new(g.points.clone(), vec![]);
    assert!(check_cdt(&g2, &bad).is_err());
}

/// Case count, scaled by `DELONE_PROP_SCALE` (e.g. 10 for a long local run).
fn cases(n: usize) -> usize {
    let k: usize = std::env::var("DELONE_PROP_SCALE")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    n * k.max(1)
}
