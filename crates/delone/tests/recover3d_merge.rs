//! Merging of coplanar input triangles before 3D recovery
//! (`RecoverOptions::merge_coplanar`, TetGen's default; `-M` turns it off):
//! Steiner counts with and without merging, the replaced surface checked
//! by `check_recovered`, markers, and tampered surfaces rejected.

use delone::tet::recover::{
    check_recovered, recover, recover_marked, Domain, RecoverError, RecoverOptions, Recovered,
};

mod solids;
use solids::{chazelle, grid_cube};

fn no_merge() -> RecoverOptions {
    RecoverOptions {
        merge_coplanar: false,
        ..RecoverOptions::default()
    }
}

fn checked(pts: &[[f64; 3]], tris: &[[u32; 3]], o: &RecoverOptions) -> Recovered {
    let r = recover(pts, tris, o).unwrap();
    check_recovered(pts, tris, &r).unwrap();
    r
}

#[test]
fn merged_surface_covers_the_input() {
    let (pts, tris) = grid_cube(4, true);
    let r = checked(&pts, &tris, &RecoverOptions::default());
    assert_eq!(r.report.coplanar_groups, 6);
    assert_eq!(r.report.coplanar_kept, 0);
    assert_eq!(r.surface.len(), tris.len());
    assert_eq!(r.surface_origin.len(), r.surface.len());
    // Every boundary face names a surface triangle.
    assert!(r
        .boundary_triangle
        .iter()
        .all(|&t| (t as usize) < r.surface.len()));
    // Without merging the surface is the input.
    let m = checked(&pts, &tris, &no_merge());
    assert_eq!(m.surface, tris);
    assert_eq!(m.surface_origin, (0..tris.len() as u32).collect::<Vec<_>>());
    assert_eq!(m.report.coplanar_groups, 0);
    // Surface preservation never merges.
    let y = RecoverOptions {
        preserve_surface: true,
        ..RecoverOptions::default()
    };
    let ry = checked(&pts, &tris, &y);
    assert_eq!(ry.surface, tris);
}

#[test]
fn chazelle_box_needs_no_steiner_point_when_merged() {
    let (pts, tris, _) = chazelle(3, 1.0, 1.0, 0.45);
    let merged = checked(&pts, &tris, &RecoverOptions::default());
    let plain = checked(&pts, &tris, &no_merge());
    println!(
        "chazelle k=3: Steiner points {} merged, {} with -M",
        merged.report.steiner(),
        plain.report.steiner()
    );
    assert_eq!(merged.report.steiner(), 0);
    assert!(plain.report.steiner() > 0);
    assert!(merged.report.coplanar_groups > 0);
    // Deterministic.
    let again = checked(&pts, &tris, &RecoverOptions::default());
    assert_eq!(again, merged);
}

#[test]
#[ignore = "slow in debug builds (the unmerged run needs thousands of Steiner points)"]
fn chazelle_five_grooves_merged_vs_not() {
    let (pts, tris, _) = chazelle(5, 1.0, 1.0, 0.48);
    let merged = checked(&pts, &tris, &RecoverOptions::default());
    assert_eq!(merged.report.steiner(), 0);
    let plain = checked(&pts, &tris, &no_merge());
    assert!(plain.report.steiner() > 1000);
}

#[test]
fn markers_keep_facets_apart() {
    let (pts, tris) = grid_cube(2, true);
    // Half of the side x = 0 gets another marker: seven groups.
    let mut markers = vec![1; tris.len()];
    for m in markers.iter_mut().take(4) {
        *m = 2;
    }
    let r = recover_marked(
        &pts,
        &tris,
        &markers,
        &RecoverOptions::default(),
        &Domain::default(),
    )
    .unwrap();
    check_recovered(&pts, &tris, &r).unwrap();
    assert_eq!(r.report.coplanar_groups, 7);
    // Surface triangles of the marked half come from marked triangles.
    for (s, &o) in r.surface.iter().zip(&r.surface_origin) {
        let from_marked = markers[o as usize] == 2;
        let in_half = tris[..4].iter().any(|t| {
            let mut a = *t;
            let mut b = *s;
            a.sort_unstable();
            b.sort_unstable();
            a == b
        });
        if in_half {
            assert!(from_marked);
        }
    }
    let e = recover_marked(
        &pts,
        &tris,
        &markers[1..],
        &RecoverOptions::default(),
        &Domain::default(),
    )
    .unwrap_err();
    assert!(matches!(e, RecoverError::MarkerCount { .. }));
}

#[test]
fn tampered_surfaces_are_rejected() {
    let (pts, tris) = grid_cube(3, true);
    let r = checked(&pts, &tris, &RecoverOptions::default());
    // A flipped surface triangle.
    let mut bad = r.clone();
    bad.surface[0].swap(1, 2);
    assert!(check_recovered(&pts, &tris, &bad).is_err());
    // A surface triangle moved to another side's vertices.
    let mut bad = r.clone();
    let other = (0..r.surface.len())
        .find(|&i| r.surface_origin[i] != r.surface_origin[0])
        .unwrap();
    bad.surface[0] = r.surface[other];
    assert!(check_recovered(&pts, &tris, &bad).is_err());
    // An origin out of range, and lengths that disagree.
    let mut bad = r.clone();
    bad.surface_origin[0] = tris.len() as u32;
    assert!(check_recovered(&pts, &tris, &bad).is_err());
    let mut bad = r.clone();
    bad.surface_origin.pop();
    assert!(check_recovered(&pts, &tris, &bad).is_err());
    // A triangle dropped from a group (its region no longer covered).
    let mut bad = r.clone();
    bad.surface.remove(0);
    bad.surface_origin.remove(0);
    assert!(check_recovered(&pts, &tris, &bad).is_err());
}

/// A merged group is recovered as one polygon: its faces are listed on its
/// first surface triangle, and `check_recovered` checks their union against
/// the group — faces relabelled to a coplanar neighbouring group (another
/// marker) break both groups' unions and are rejected.
#[test]
fn groups_are_checked_as_polygons() {
    let (pts, tris) = grid_cube(2, true);
    // The side x = 0 (triangles 0..8) becomes two groups: 0..4 and 4..8.
    let mut markers = vec![1; tris.len()];
    for m in markers.iter_mut().take(4) {
        *m = 2;
    }
    let r = recover_marked(
        &pts,
        &tris,
        &markers,
        &RecoverOptions::default(),
        &Domain::default(),
    )
    .unwrap();
    check_recovered(&pts, &tris, &r).unwrap();
    let first = |o: u32| r.surface_origin.iter().position(|&x| x == o).unwrap() as u32;
    let (a, b) = (first(0), first(4));
    // Every face of a group names its first triangle.
    let group_of = |t: u32| r.surface_origin[t as usize];
    assert!(r.boundary_triangle.iter().all(|&t| t == first(group_of(t))));
    let on_a = r.boundary_triangle.iter().filter(|&&t| t == a).count();
    assert!(on_a >= 4);
    // Naming another triangle of the same group is fine.
    let mut ok = r.clone();
    let other_a = (0..r.surface.len() as u32)
        .find(|&t| group_of(t) == 0 && t != a)
        .unwrap();
    for t in ok.boundary_triangle.iter_mut().filter(|t| **t == a) {
        *t = other_a;
    }
    check_recovered(&pts, &tris, &ok).unwrap();
    // Moving one face of group A to group B (same plane) breaks the unions.
    let mut bad = r.clone();
    let i = bad.boundary_triangle.iter().position(|&t| t == a).unwrap();
    bad.boundary_triangle[i] = b;
    let e = check_recovered(&pts, &tris, &bad).unwrap_err();
    assert!(format!("{e:?}").contains("constraint"), "{e:?}");
}

/// cgal_oblong (840 triangles, many coplanar groups): recovering each
/// merged group as a polygon needs no more Steiner points than TetGen's
/// `-p` (18); recovering the groups' triangles needed 559.
#[test]
fn oblong_needs_few_steiner_points() {
    let Some(path) =
        delone_testdata::corpus_path(env!("CARGO_MANIFEST_DIR"), "surf/off/cgal_oblong.off")
    else {
        return;
    };
    let text = std::fs::read_to_string(path).unwrap();
    let mut toks = text
        .lines()
        .map(|l| l.split('#').next().unwrap_or(""))
        .flat_map(str::split_whitespace);
    assert_eq!(toks.next(), Some("OFF"));
    let mut num = || toks.next().unwrap().parse::<f64>().unwrap();
    let (nv, nf, _) = (num() as usize, num() as usize, num());
    let pts: Vec<[f64; 3]> = (0..nv).map(|_| [num(), num(), num()]).collect();
    let tris: Vec<[u32; 3]> = (0..nf)
        .map(|_| {
            assert_eq!(num(), 3.0);
            [num() as u32, num() as u32, num() as u32]
        })
        .collect();
    let r = checked(&pts, &tris, &RecoverOptions::default());
    println!(
        "cgal_oblong: {} Steiner points, {} groups",
        r.report.steiner(),
        r.report.coplanar_groups
    );
    assert!(r.report.steiner() <= 18);
    assert!(r.report.coplanar_groups > 100);
}
