//! `delone tet -pq[B] -a[V] -S[n]`: Delaunay refinement after recovery, and
//! the quality statistics (`-V`, `--stats-json FILE`).

use delone::tet::quality::{TetStats, DIHEDRAL_BINS};
use delone::tet::recover::{recover_marked, Domain, RecoverOptions, Recovered};
use delone::tet::refine::{refine_recovered, RefineOptions, RefineReport};

use crate::args::Opts;

/// Recovery alone (`-p`), or recovery and refinement when `-q`/`-a` is
/// given (`markers`: per input triangle, its facet's marker). Returns the mesh, the refinement report if any, and the name of
/// the stage for timing lines.
pub fn mesh(
    o: &Opts,
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    markers: &[i32],
    ropts: &RecoverOptions,
    domain: &Domain,
) -> Result<(Recovered, Option<RefineReport>), String> {
    if o.tet_ratio.is_none() && o.max_area.is_none() {
        return recover_marked(points, triangles, markers, ropts, domain)
            .map(|r| (r, None))
            .map_err(|e| e.to_string());
    }
    if domain.convex_hull {
        return Err("refinement (-q/-a) with -c is not implemented yet".into());
    }
    if ropts.preserve_surface {
        return Err("refinement (-q/-a) with -Y is not implemented yet".into());
    }
    let mut opts = RefineOptions {
        max_radius_edge: o.tet_ratio.unwrap_or(f64::INFINITY),
        max_volume: o.max_area,
        ..RefineOptions::default()
    };
    if let Some(s) = o.max_steiner {
        opts.max_steiner = s;
    }
    // The refinement's subfaces are the input triangles: no coplanar merging
    // before it (yet).
    let ropts = RecoverOptions {
        merge_coplanar: false,
        ..ropts.clone()
    };
    let rec = recover_marked(points, triangles, markers, &ropts, domain).map_err(|e| e.to_string())?;
    let r = refine_recovered(points, triangles, &rec, &opts).map_err(|e| e.to_string())?;
    Ok((r.rec, Some(r.report)))
}

/// Report lines for `-V` (and the refinement summary), and the JSON file.
pub fn report(
    o: &Opts,
    rec: &Recovered,
    refined: Option<&RefineReport>,
) -> Result<Vec<String>, String> {
    let mut lines = Vec::new();
    if let Some(r) = refined {
        lines.push(format!(
            "refinement: {} points (on segments {}, on facets {}, interior {}); {} circumcentres rejected, {} bad tetrahedra skipped, {} above the bound ({} flat on a plane of the input){}",
            r.steiner(),
            r.on_segments,
            r.on_facets,
            r.interior,
            r.rejected,
            r.skipped,
            r.remaining_bad,
            r.flat,
            if r.budget_exhausted { "; Steiner budget exhausted" } else { "" }
        ));
    }
    let want_stats = o.verbose > 0 || o.stats_json.is_some();
    if !want_stats {
        return Ok(lines);
    }
    let s = TetStats::of(&rec.points, &rec.mesh.tets);
    if o.verbose > 0 {
        lines.push(format!(
            "quality: dihedral {:.2}..{:.2} deg, radius-edge {:.3}..{:.3} (mean {:.3}), shape min {:.4} mean {:.4}, volume {:.4e}..{:.4e} (total {:.6e})",
            s.min_dihedral,
            s.max_dihedral,
            s.min_radius_edge,
            s.max_radius_edge,
            s.mean_radius_edge,
            s.min_shape,
            s.mean_shape,
            s.min_volume,
            s.max_volume,
            s.total_volume
        ));
        let mut lo = 0.0;
        let mut h = String::from("dihedral histogram:");
        for (b, n) in DIHEDRAL_BINS.iter().zip(&s.dihedral_histogram) {
            h.push_str(&format!(" {lo}-{b}:{n}"));
            lo = *b;
        }
        lines.push(h);
    }
    if let Some(p) = &o.stats_json {
        std::fs::write(p, s.to_json() + "\n")
            .map_err(|e| format!("cannot write {}: {e}", p.display()))?;
    }
    Ok(lines)
}
