//! Times Voronoi extraction against triangulation on seeded uniform random
//! points (2D, and 3D with `--3d`).
//!
//! `cargo run --release -p delone --example voronoi_timing -- [n] [repeats] [--3d] [--no-clip] [--threads N]`
//!
//! `--threads N`: the extraction's thread count (default: the available
//! parallelism, at most 8, in 3D; two in 2D). `--phases` (3D): also the
//! wall time of each phase of the extraction; `--hash`: a digest of
//! the whole diagram (to compare versions bit for bit). 3D also prints the
//! bytes of the diagram's arrays and the fresh pages each extraction touches. `--regular`: times
//! the regular (weighted) triangulation against the unweighted one instead,
//! weights uniform in `[0, n^(-2/d))` (the squared point spacing). Wall times are the best of the
//! repeats; CPU times (user + system, all threads) cover all repeats.
use std::time::Instant;

use delone::geom::SplitMix64;

/// CPU seconds (user + system, all threads) of this process so far, from
/// `/proc/self/stat` (Linux; 0 elsewhere). On a loaded machine the CPU time
/// of a phase is steadier than its wall time.
fn cpu_seconds() -> f64 {
    let (u, s) = cpu_split();
    u + s
}

/// User and system CPU seconds (all threads) of this process so far, from
/// `/proc/self/stat` (Linux; zeros elsewhere).
fn cpu_split() -> (f64, f64) {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return (0.0, 0.0);
    };
    // Fields after the parenthesised command name; utime and stime are
    // fields 14 and 15 of the whole line, in clock ticks (100 per second).
    let rest = stat.rsplit_once(')').map_or("", |r| r.1);
    let f: Vec<f64> = rest
        .split_whitespace()
        .map(|x| x.parse().unwrap_or(0.0))
        .collect();
    if f.len() < 13 {
        return (0.0, 0.0);
    }
    (f[11] / 100.0, f[12] / 100.0)
}

/// Minor page faults of this process so far (`/proc/self/stat`; 0
/// elsewhere): fresh memory touched, a large part of the extraction's
/// system time.
fn minor_faults() -> u64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return 0;
    };
    let rest = stat.rsplit_once(')').map_or("", |r| r.1);
    rest.split_whitespace()
        .nth(7)
        .and_then(|x| x.parse().ok())
        .unwrap_or(0)
}

/// The bytes of the arrays of a 3D diagram (their lengths, not
/// capacities).
fn output_bytes(v: &delone::tet::Voronoi3) -> usize {
    use std::mem::size_of_val;
    size_of_val(&v.vertices[..])
        + size_of_val(&v.edges[..])
        + size_of_val(&v.ray_edges[..])
        + size_of_val(&v.ray_directions[..])
        + size_of_val(&v.faces[..])
        + size_of_val(&v.open_faces[..])
        + size_of_val(&v.open_face_rays[..])
        + size_of_val(&v.face_offsets[..])
        + size_of_val(&v.face_vertices[..])
        + size_of_val(&v.open_face_edges[..])
        + size_of_val(&v.vertex_edges[..])
        + size_of_val(&v.cell_offsets[..])
        + size_of_val(&v.cell_face_ids[..])
        + size_of_val(&v.unbounded[..])
        + size_of_val(&v.vertex_map[..])
        + size_of_val(&v.weights[..])
}

fn best<T>(reps: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut out = None;
    for _ in 0..reps {
        let t0 = Instant::now();
        let r = f();
        best = best.min(t0.elapsed().as_secs_f64());
        out = Some(r);
    }
    (best, out.expect("at least one repeat"))
}

/// The sum of the phase times (the extraction's wall time when non-empty).
fn tt_of(phases: &[(&str, f64)], whole: f64) -> f64 {
    let s: f64 = phases.iter().map(|p| p.1).sum();
    if s > 0.0 {
        s
    } else {
        whole
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args
        .get(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let reps: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(3).max(1);
    let threads: usize = args
        .iter()
        .position(|a| a == "--threads")
        .and_then(|i| args.get(i + 1))
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    let mut rng = SplitMix64::new(42);
    let mut unit = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    if args.iter().any(|a| a == "--regular") {
        // Regular against unweighted triangulation of the same points, the
        // weights uniform in [0, spacing²) (a few percent hidden).
        let d3 = args.iter().any(|a| a == "--3d");
        let dim = if d3 { 3 } else { 2 };
        let pts: Vec<Vec<f64>> = (0..n).map(|_| (0..dim).map(|_| unit()).collect()).collect();
        let spacing2 = (n as f64).powf(-2.0 / dim as f64);
        let w: Vec<f64> = (0..n).map(|_| unit() * spacing2).collect();
        let c0 = cpu_seconds();
        let (tu, hidden) = if d3 {
            let p: Vec<[f64; 3]> = pts.iter().map(|q| [q[0], q[1], q[2]]).collect();
            let (tu, _) = best(reps, || delone::tetrahedralize(&p).expect("tetrahedralize"));
            let c1 = cpu_seconds();
            let (tr, m) = best(reps, || {
                delone::tet::regular_tetrahedralization(&p, &w).expect("regular")
            });
            ((tu, tr, c1), m.hidden.len())
        } else {
            let p: Vec<[f64; 2]> = pts.iter().map(|q| [q[0], q[1]]).collect();
            let (tu, _) = best(reps, || delone::triangulate(&p).expect("triangulate"));
            let c1 = cpu_seconds();
            let (tr, m) = best(reps, || {
                delone::tri::regular_triangulation(&p, &w).expect("regular")
            });
            ((tu, tr, c1), m.hidden.len())
        };
        let ((tu, tr, c1), c2) = (tu, cpu_seconds());
        println!(
            "{dim}D n={n} regular/unweighted: wall {tr:.3}s / {tu:.3}s ({:.2}x), CPU {:.2}s / {:.2}s ({:.2}x); {hidden} hidden",
            tr / tu,
            c2 - c1,
            c1 - c0,
            (c2 - c1) / (c1 - c0)
        );
        return;
    }
    if args.iter().any(|a| a == "--3d") {
        let pts: Vec<[f64; 3]> = (0..n).map(|_| [unit(), unit(), unit()]).collect();
        let (c0, s0) = (cpu_seconds(), cpu_split().1);
        let (tt, mesh) = best(reps, || {
            delone::tetrahedralize(&pts).expect("tetrahedralize")
        });
        let (c1, f1, s1) = (cpu_seconds(), minor_faults(), cpu_split().1);
        let (tv, (v, phases)) = best(reps, || {
            delone::tet::Voronoi3::with_phase_times(&pts, &mesh, threads).unwrap()
        });
        let (c2, f2, s2) = (cpu_seconds(), minor_faults(), cpu_split().1);
        if args.iter().any(|a| a == "--hash") {
            // A digest of the whole diagram, to compare versions bit for bit.
            let mut h = 0xcbf2_9ce4_8422_2325u64;
            let mut eat = |x: u64| h = (h ^ x).wrapping_mul(0x100_0000_01b3);
            v.vertices.iter().flatten().for_each(|x| eat(x.to_bits()));
            for e in &v.edges {
                e.sites
                    .iter()
                    .chain(&e.vertices)
                    .for_each(|&x| eat(x as u64));
            }
            v.ray_directions
                .iter()
                .flatten()
                .for_each(|x| eat(x.to_bits()));
            v.faces
                .iter()
                .for_each(|f| f.sites.iter().for_each(|&x| eat(x as u64)));
            v.open_face_rays
                .iter()
                .flatten()
                .flatten()
                .for_each(|x| eat(x.to_bits()));
            // The faces' edges as a flat list and offsets (derived from
            // `vertex_edges`), so the digest covers them.
            let (mut edge_offsets, mut edge_ids) = (vec![0u32], vec![]);
            for f in 0..v.faces.len() {
                edge_ids.extend(v.face(f).edges);
                edge_offsets.push(edge_ids.len() as u32);
            }
            for a in [
                &v.ray_edges,
                &v.open_faces,
                &v.face_offsets,
                &v.face_vertices,
                &edge_offsets,
                &edge_ids,
                &v.cell_offsets,
                &v.cell_face_ids,
            ] {
                a.iter().for_each(|&x| eat(x as u64));
            }
            v.unbounded.iter().for_each(|&x| eat(x as u64));
            println!("3D digest {h:016x}");
        }
        let list: Vec<String> = phases
            .iter()
            .map(|(name, t)| format!("{name} {t:.3}s ({:.2}x)", t / tt_of(&phases, tv)))
            .collect();
        if args.iter().any(|a| a == "--phases") {
            println!(
                "3D phases (last repeat; share of the extraction): {}",
                list.join(", ")
            );
        }
        let (ct, cv) = (c1 - c0, c2 - c1);
        println!(
            "3D n={n}: output {:.0} MB ({} bytes)",
            output_bytes(&v) as f64 / 1e6,
            output_bytes(&v)
        );
        println!(
            "3D n={n}: CPU time (all repeats) tetrahedralize {ct:.2}s (system {:.2}s), Voronoi3 {cv:.2}s (system {:.2}s) ({:.2}x), {} threads; {:.0} MB of fresh pages per extraction",
            s1 - s0,
            s2 - s1,
            cv / ct,
            if threads == 0 {
                delone::tet::Voronoi3::default_threads()
            } else {
                threads
            },
            (f2 - f1) as f64 * 4096.0 / 1e6 / reps as f64
        );
        let bbox = [[0.0; 3], [1.0; 3]];
        // Without clipping the unbounded cells have no volume: "-".
        let (tc, vol) = if args.iter().any(|a| a == "--no-clip") {
            (0.0, "-".to_string())
        } else {
            let (tc, c) = best(1, || v.cells_clipped(&pts, bbox));
            (tc, c.volume.iter().sum::<f64>().to_string())
        };
        println!(
            "3D n={n}: wall tetrahedralize {tt:.3}s, Voronoi3 {tv:.3}s ({:.2}x), clip {tc:.3}s; {} faces, volume sum {vol}",
            tv / tt,
            v.faces.len()
        );
    } else {
        let pts: Vec<[f64; 2]> = (0..n).map(|_| [unit(), unit()]).collect();
        let c0 = cpu_seconds();
        let (tt, mesh) = best(reps, || delone::triangulate(&pts).expect("triangulate"));
        let c1 = cpu_seconds();
        let (tv, v) = best(reps, || {
            delone::tri::Voronoi2::with_threads(&pts, &mesh, threads).unwrap()
        });
        let c2 = cpu_seconds();
        if args.iter().any(|a| a == "--hash") {
            // A digest of the whole diagram, to compare versions bit for bit.
            let mut h = 0xcbf2_9ce4_8422_2325u64;
            let mut eat = |x: u64| h = (h ^ x).wrapping_mul(0x100_0000_01b3);
            v.vertices.iter().flatten().for_each(|x| eat(x.to_bits()));
            for e in &v.edges {
                e.sites
                    .iter()
                    .chain(&e.vertices)
                    .for_each(|&x| eat(x as u64));
            }
            v.cell_ranges.iter().flatten().for_each(|&x| eat(x as u64));
            v.cell_vertices.iter().for_each(|&x| eat(x as u64));
            v.cell_neighbors.iter().for_each(|&x| eat(x as u64));
            for (s, rays, o) in &v.hull_cells {
                eat(*s as u64);
                rays.iter().flatten().for_each(|x| eat(x.to_bits()));
                eat(*o as u64);
            }
            println!("2D digest {h:016x}");
        }
        let (ct, cv) = (c1 - c0, c2 - c1);
        println!(
            "2D n={n}: CPU time (all repeats) triangulate {ct:.2}s, Voronoi2 {cv:.2}s ({:.2}x)",
            cv / ct
        );
        let bbox = [[0.0; 2], [1.0; 2]];
        let (tc, c) = best(reps, || v.cells_clipped(&pts, bbox));
        let area: f64 = c.area.iter().sum();
        println!(
            "2D n={n}: wall triangulate {tt:.3}s, Voronoi2 {tv:.3}s ({:.2}x), clip {tc:.3}s ({:.2}x); {} edges, area sum {area}",
            tv / tt,
            tc / tt,
            v.edges.len()
        );
    }
}
