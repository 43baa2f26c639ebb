//! `delone tet -d FILE`: detects self-intersections of the input facets
//! (exactly: facets crossing, a vertex inside a facet, overlapping
//! coplanar facets), degenerate facets (zero area, too few or repeated
//! vertices: reported, not fatal) and, for surfaces (OFF, STL, PLY, OBJ,
//! Medit), open and non-manifold edges; nothing is meshed. Facets and
//! points are numbered as the file numbers them (see
//! [`crate::numbering`]), as in `-p`'s messages. Exit code 1 when anything
//! is found, 0 for a clean input.

use delone::tet::intersect::{manifold_report, self_intersections};

use crate::args::Opts;
use crate::fail::Failure;

/// Runs `delone tet -d`.
pub fn run(o: &Opts) -> Result<i32, Failure> {
    let (
        crate::plc::Input {
            path,
            ext,
            plc,
            msg_first,
            ..
        },
        (triangles, facet_of),
        defects,
    ) = crate::plc::load_lenient(o)?;
    let name = path.display();
    let first = msg_first as usize;
    let si = self_intersections(&plc.points, &triangles);
    let facet = |t: u32| facet_of[t as usize] as usize + first;
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
    // Degenerate facets: those set aside when reading (zero area, too few
    // or repeated vertices, ...) and those with a zero-area triangle.
    let mut degenerate: Vec<(usize, String)> = defects
        .iter()
        .map(|&(f, d)| {
            (
                f + first,
                crate::numbering::renumber_defect(d, msg_first).to_string(),
            )
        })
        .collect();
    degenerate.extend(
        si.degenerate
            .iter()
            .map(|&t| (facet(t), "has a zero-area triangle".to_string())),
    );
    degenerate.sort();
    degenerate.dedup_by_key(|d| d.0);
    let m = manifold_report(&triangles);
    // PLC facets may end inside the domain (slits) or meet in threes
    // (internal facets between regions); a surface must be closed.
    let plc_format = ext == "poly" || ext == "smesh";
    let open = if plc_format {
        0
    } else {
        m.boundary_edges.len() + m.nonmanifold_edges.len()
    };
    let found = !pairs.is_empty() || !degenerate.is_empty() || open > 0;
    if o.out().quiet {
        if found {
            eprintln!(
                "delone: {name}: {} intersecting facet pair(s), {} degenerate facet(s), {} open or non-manifold edge(s)",
                pairs.len(),
                degenerate.len(),
                open
            );
        }
        return Ok(i32::from(found));
    }
    println!(
        "delone tet -d: {name} ({} points, {} facets, {} triangles; facets and points numbered from {first} as in the file)",
        plc.points.len(),
        plc.facets.len() + defects.len(),
        triangles.len()
    );
    println!(
        "  {} intersecting facet pair(s), {} degenerate facet(s); surface: {}",
        pairs.len(),
        degenerate.len(),
        if m.is_closed() {
            "closed".to_string()
        } else if plc_format {
            // PLC facets have no orientation.
            format!(
                "{} boundary edge(s), {} edge(s) with more than two facets (allowed in a PLC)",
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
    let shown = if o.out().verbose > 0 { usize::MAX } else { 20 };
    for (a, b) in pairs.iter().take(shown) {
        println!("  facets {a} and {b} intersect");
    }
    if pairs.len() > shown {
        println!("  ... {} more pair(s) (-V lists all)", pairs.len() - shown);
    }
    for (f, what) in degenerate.iter().take(shown) {
        println!("  facet {f} {what}");
    }
    if !plc_format {
        let p = |v: u32| v as usize + first;
        for e in m.boundary_edges.iter().take(shown) {
            println!(
                "  edge {}-{} has only one facet (open surface)",
                p(e[0]),
                p(e[1])
            );
        }
        for e in m.nonmanifold_edges.iter().take(shown) {
            println!("  edge {}-{} has more than two facets", p(e[0]), p(e[1]));
        }
    }
    Ok(i32::from(found))
}
