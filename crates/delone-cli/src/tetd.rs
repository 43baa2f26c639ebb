//! `delone tet -d FILE`: detects self-intersections of the input facets
//! (exactly: facets crossing, a vertex inside a facet, overlapping
//! coplanar facets) and zero-area facets, and reports them by input facet
//! index, with the surface's closedness; nothing is meshed. Exit code 1
//! when anything is found, 0 for a clean input.

use delone::tet::intersect::{manifold_report, self_intersections};

use crate::args::Opts;
use crate::run::Failure;

/// Runs `delone tet -d`.
pub fn run(o: &Opts) -> Result<i32, Failure> {
    let crate::plc::Input {
        path,
        ext,
        plc,
        first,
        triangles,
        facet_of,
        ..
    } = crate::plc::load(o)?;
    let name = path.display();
    let si = self_intersections(&plc.points, &triangles);
    let facet = |t: u32| facet_of[t as usize] as usize + first as usize;
    // Facet pairs (a facet's own triangles never intersect each other).
    let mut pairs: Vec<(usize, usize)> = si
        .pairs
        .iter()
        .map(|&(i, j)| {
            let (a, b) = (facet(i), facet(j));
            (a.min(b), a.max(b))
        })
        .filter(|(a, b)| a != b)
        .collect();
    pairs.sort_unstable();
    pairs.dedup();
    let mut degenerate: Vec<usize> = si.degenerate.iter().map(|&t| facet(t)).collect();
    degenerate.dedup();
    let m = manifold_report(&triangles);
    let found = !pairs.is_empty() || !degenerate.is_empty();
    if o.quiet {
        if found {
            eprintln!(
                "delone: {name}: {} intersecting facet pair(s), {} zero-area facet(s)",
                pairs.len(),
                degenerate.len()
            );
        }
        return Ok(i32::from(found));
    }
    println!(
        "delone tet -d: {name} ({} points, {} facets, {} triangles)",
        plc.points.len(),
        plc.facets.len(),
        triangles.len()
    );
    println!(
        "  {} intersecting facet pair(s), {} zero-area facet(s); surface: {}",
        pairs.len(),
        degenerate.len(),
        if m.is_closed() {
            "closed".to_string()
        } else if ext == "poly" || ext == "smesh" {
            // PLC facets have no orientation; internal facets make edges
            // with more than two facets.
            format!(
                "{} boundary edge(s), {} edge(s) with more than two facets",
                m.boundary_edges.len(),
                m.nonmanifold_edges.len()
            )
        } else {
            format!(
                "{} boundary edge(s), {} edge(s) with more than two facets, {} inconsistently oriented",
                m.boundary_edges.len(),
                m.nonmanifold_edges.len(),
                m.inconsistent_edges.len()
            )
        }
    );
    let shown = if o.verbose > 0 { usize::MAX } else { 20 };
    for (a, b) in pairs.iter().take(shown) {
        println!("  facets {a} and {b} intersect");
    }
    if pairs.len() > shown {
        println!("  ... {} more pair(s) (-V lists all)", pairs.len() - shown);
    }
    for f in degenerate.iter().take(shown) {
        println!("  facet {f} has a zero-area triangle");
    }
    Ok(i32::from(found))
}
