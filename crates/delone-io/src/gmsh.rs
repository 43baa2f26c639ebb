//! Writer for the Gmsh `.msh` format, version 4.1 (ASCII).
//!
//! Layout written (sections of the 4.1 specification):
//!
//! ```text
//! $MeshFormat
//! 4.1 0 8
//! $EndMeshFormat
//! $Entities
//! 0 0 <#surfaces> <#volumes>
//! <tag> <min x y z> <max x y z> <#physical tags> [<physical tag>] 0   (each surface)
//! <tag> <min x y z> <max x y z> <#physical tags> [<physical tag>] 0   (each volume)
//! $EndEntities
//! $Nodes
//! 1 <#nodes> 1 <#nodes>
//! 3 1 0 <#nodes>            (one block, classified on volume 1)
//! <tags 1..n, one per line> then <x y z, one per line>
//! $EndNodes
//! $Elements
//! <#blocks> <#elements> 1 <#elements>
//! 2 <surface> 2 <#triangles>   then  <element tag> <n1> <n2> <n3>
//! 3 <volume> 4 <#tets>         then  <element tag> <n1> <n2> <n3> <n4>
//! $EndElements
//! ```
//!
//! Elements are grouped into one entity per distinct tag value (surfaces for
//! triangles, volumes for tetrahedra), numbered from 1 in increasing tag
//! order; an entity's physical tag is its value when positive (Gmsh's
//! physical tags are positive), none otherwise. There is always at least one
//! volume entity (it holds the nodes). Element tags run over the triangles
//! first, then the tetrahedra. Bounding curves/surfaces are not listed.

use std::io::Write;

use crate::medit::check_cells;
use crate::out::Out;
use crate::IoError;

/// One entity per distinct tag (sorted), and per element its entity index.
fn group(tags: &[i32]) -> (Vec<i32>, Vec<usize>) {
    let mut values: Vec<i32> = tags.to_vec();
    values.sort_unstable();
    values.dedup();
    let idx = tags
        .iter()
        .map(|t| values.binary_search(t).unwrap_or(0))
        .collect();
    (values, idx)
}

fn bbox<const K: usize>(
    points: &[[f64; 3]],
    cells: &[[u32; K]],
    entity: &[usize],
    n: usize,
) -> Vec<[f64; 6]> {
    let mut b = vec![
        [
            f64::INFINITY,
            f64::INFINITY,
            f64::INFINITY,
            -f64::INFINITY,
            -f64::INFINITY,
            -f64::INFINITY
        ];
        n
    ];
    for (c, &e) in cells.iter().zip(entity) {
        for &v in c {
            let p = points[v as usize];
            for k in 0..3 {
                b[e][k] = b[e][k].min(p[k]);
                b[e][k + 3] = b[e][k + 3].max(p[k]);
            }
        }
    }
    for x in &mut b {
        if x[0] > x[3] {
            *x = [0.0; 6];
        }
    }
    b
}

fn entity_lines<W: Write>(
    o: &mut Out<W>,
    values: &[i32],
    boxes: &[[f64; 6]],
) -> Result<(), IoError> {
    for (i, (&v, b)) in values.iter().zip(boxes).enumerate() {
        o.uint(i as u64 + 1);
        for &c in b {
            o.byte(b' ');
            o.float(c);
        }
        if v > 0 {
            o.str(" 1 ");
            o.int(i64::from(v));
        } else {
            o.str(" 0");
        }
        o.str(" 0");
        o.nl()?;
    }
    Ok(())
}

/// Writes a Gmsh `.msh` 4.1 ASCII file with the points, the triangles
/// (`face_tags`, e.g. facet markers) and the tetrahedra (`tet_tags`, e.g.
/// region numbers); sections MeshFormat, Entities (one per tag), Nodes and Elements.
///
/// # Errors
/// [`IoError::InvalidInput`] if a tag array does not match its elements or
/// an element names a missing point; [`IoError::Io`] if the writer fails.
///
/// ```
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// let mut out = Vec::new();
/// delone_io::write_gmsh(&mut out, &pts, &[[0, 2, 1]], &[5], &[[0, 1, 2, 3]], &[2]).unwrap();
/// let text = String::from_utf8(out).unwrap();
/// assert!(text.starts_with("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 0 1 1\n"));
/// assert!(text.contains("$Elements\n2 2 1 2\n2 1 2 1\n1 1 3 2\n3 1 4 1\n2 1 2 3 4\n$EndElements\n"));
/// ```
pub fn write_gmsh<W: Write>(
    out: W,
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    face_tags: &[i32],
    tets: &[[u32; 4]],
    tet_tags: &[i32],
) -> Result<(), IoError> {
    check_cells("triangle", triangles, face_tags, points.len())?;
    check_cells("tetrahedron", tets, tet_tags, points.len())?;
    let (svals, sidx) = group(face_tags);
    let (mut vvals, vidx) = group(tet_tags);
    if vvals.is_empty() {
        vvals.push(0);
    }
    let mut o = Out::new(out);
    o.str("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 0 ");
    o.uint(svals.len() as u64);
    o.byte(b' ');
    o.uint(vvals.len() as u64);
    o.nl()?;
    entity_lines(&mut o, &svals, &bbox(points, triangles, &sidx, svals.len()))?;
    entity_lines(&mut o, &vvals, &bbox(points, tets, &vidx, vvals.len()))?;
    o.str("$EndEntities\n$Nodes\n");
    let n = points.len() as u64;
    if n == 0 {
        o.str("0 0 0 0\n");
    } else {
        o.str("1 ");
        o.uint(n);
        o.str(" 1 ");
        o.uint(n);
        o.str("\n3 1 0 ");
        o.uint(n);
        o.nl()?;
        for i in 1..=n {
            o.uint(i);
            o.nl()?;
        }
        for p in points {
            o.float(p[0]);
            o.byte(b' ');
            o.float(p[1]);
            o.byte(b' ');
            o.float(p[2]);
            o.nl()?;
        }
    }
    o.str("$EndNodes\n$Elements\n");
    let ne = (triangles.len() + tets.len()) as u64;
    let mut used = vec![false; vvals.len()];
    for &e in &vidx {
        used[e] = true;
    }
    let nonempty_volumes = used.iter().filter(|&&u| u).count();
    o.uint((svals.len() + nonempty_volumes) as u64);
    o.byte(b' ');
    o.uint(ne);
    o.str(if ne == 0 { " 0 0" } else { " 1 " });
    if ne > 0 {
        o.uint(ne);
    }
    o.nl()?;
    let mut tag = 1u64;
    block(&mut o, 2, 2, triangles, &sidx, svals.len(), &mut tag)?;
    block(&mut o, 3, 4, tets, &vidx, vvals.len(), &mut tag)?;
    o.str("$EndElements\n");
    Ok(o.finish()?)
}

/// Writes the element blocks of one dimension, one per non-empty entity.
fn block<W: Write, const K: usize>(
    o: &mut Out<W>,
    dim: u64,
    kind: u64,
    cells: &[[u32; K]],
    entity: &[usize],
    n_entities: usize,
    tag: &mut u64,
) -> Result<(), IoError> {
    let mut by: Vec<Vec<usize>> = vec![Vec::new(); n_entities];
    for (i, &e) in entity.iter().enumerate() {
        by[e].push(i);
    }
    for (e, list) in by.iter().enumerate() {
        if list.is_empty() {
            continue;
        }
        o.uint(dim);
        o.byte(b' ');
        o.uint(e as u64 + 1);
        o.byte(b' ');
        o.uint(kind);
        o.byte(b' ');
        o.uint(list.len() as u64);
        o.nl()?;
        for &i in list {
            o.uint(*tag);
            *tag += 1;
            for &v in &cells[i] {
                o.byte(b' ');
                o.uint(u64::from(v) + 1);
            }
            o.nl()?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A minimal independent 4.1 ASCII parser: points, and per element
    /// type the node lists with the physical tag of their entity.
    #[allow(clippy::type_complexity)]
    fn parse(text: &str) -> (Vec<[f64; 3]>, Vec<(u32, Vec<u32>, Option<i64>)>) {
        let lines: Vec<&str> = text.lines().collect();
        let sec = |name: &str| lines.iter().position(|l| *l == name).unwrap() + 1;
        assert_eq!(lines[sec("$MeshFormat")], "4.1 0 8");
        let num =
            |l: &str| -> Vec<f64> { l.split_whitespace().map(|t| t.parse().unwrap()).collect() };
        // Entities: physical tag per (dim, tag).
        let mut k = sec("$Entities");
        let h = num(lines[k]);
        k += 1;
        let mut phys = std::collections::HashMap::new();
        for (dim, count) in [(2, h[2] as usize), (3, h[3] as usize)] {
            for _ in 0..count {
                let v = num(lines[k]);
                k += 1;
                let np = v[7] as usize;
                phys.insert((dim, v[0] as i64), (np > 0).then(|| v[8] as i64));
                assert_eq!(v[8 + np], 0.0, "bounding list");
            }
        }
        assert_eq!(lines[k], "$EndEntities");
        let mut k = sec("$Nodes");
        let h = num(lines[k]);
        k += 1;
        let n = h[1] as usize;
        let mut pts = vec![[f64::NAN; 3]; n];
        for _ in 0..h[0] as usize {
            let b = num(lines[k]);
            k += 1;
            let m = b[3] as usize;
            let tags: Vec<usize> = (0..m).map(|i| num(lines[k + i])[0] as usize).collect();
            k += m;
            for t in tags {
                let c = num(lines[k]);
                k += 1;
                pts[t - 1] = [c[0], c[1], c[2]];
            }
        }
        assert_eq!(lines[k], "$EndNodes");
        let mut k = sec("$Elements");
        let h = num(lines[k]);
        k += 1;
        let mut out = Vec::new();
        let mut seen_tags = Vec::new();
        for _ in 0..h[0] as usize {
            let b = num(lines[k]);
            k += 1;
            for _ in 0..b[3] as usize {
                let v: Vec<u32> = lines[k]
                    .split_whitespace()
                    .map(|t| t.parse().unwrap())
                    .collect();
                k += 1;
                seen_tags.push(v[0]);
                out.push((
                    b[2] as u32,
                    v[1..].to_vec(),
                    phys[&(b[0] as i64, b[1] as i64)],
                ));
            }
        }
        assert_eq!(lines[k], "$EndElements");
        assert_eq!(seen_tags.len(), h[1] as usize);
        seen_tags.sort_unstable();
        seen_tags.dedup();
        assert_eq!(seen_tags.len(), h[1] as usize, "element tags unique");
        (pts, out)
    }

    #[test]
    fn round_trip_through_a_minimal_parser() {
        let pts = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 1.0, 1.0 / 3.0],
        ];
        let tris = [[0, 2, 1], [0, 1, 3], [1, 2, 4]];
        let tets = [[0, 1, 2, 3], [1, 2, 3, 4]];
        let mut out = Vec::new();
        write_gmsh(&mut out, &pts, &tris, &[3, 0, 3], &tets, &[2, 1]).unwrap();
        let text = String::from_utf8(out).unwrap();
        let (p, els) = parse(&text);
        assert_eq!(p, pts.to_vec());
        let mut got: Vec<(u32, Vec<u32>, Option<i64>)> = els;
        got.sort();
        let mut want: Vec<(u32, Vec<u32>, Option<i64>)> = vec![
            (2, vec![1, 3, 2], Some(3)),
            (2, vec![1, 2, 4], None),
            (2, vec![2, 3, 5], Some(3)),
            (4, vec![1, 2, 3, 4], Some(2)),
            (4, vec![2, 3, 4, 5], Some(1)),
        ];
        want.sort();
        assert_eq!(got, want);
    }

    #[test]
    fn empty_and_bad_input() {
        let mut out = Vec::new();
        write_gmsh(&mut out, &[], &[], &[], &[], &[]).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(text.contains("$Nodes\n0 0 0 0\n$EndNodes\n$Elements\n0 0 0 0\n"));
        let pts = [[0.0; 3]; 3];
        assert!(write_gmsh(Vec::new(), &pts, &[[0, 1, 3]], &[1], &[], &[]).is_err());
        assert!(write_gmsh(Vec::new(), &pts, &[[0, 1, 2]], &[], &[], &[]).is_err());
    }
}
