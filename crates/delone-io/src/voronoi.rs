//! Writers for Voronoi diagrams in the Triangle (`-v`: `.v.node`, `.v.edge`)
//! and TetGen (`-v`: `.v.node`, `.v.edge`, `.v.face`, `.v.cell`) formats, on
//! plain slices.
//!
//! The layouts, as both programs document them:
//!
//! * `.v.node` — an ordinary `.node` file of the Voronoi vertices
//!   ([`write_voronoi_node`]).
//! * `.v.edge` — header `<#edges> 0`, then `<index> <v1> <v2>` for a finite
//!   edge and `<index> <v1> -1 <direction…>` for an infinite ray
//!   ([`write_voronoi_edge`], 2D and 3D).
//! * `.v.face` (3D) — header `<#faces> 0`, then
//!   `<index> <cell1> <cell2> <#edges> <edge…>`: the two cells (sites) the
//!   face separates and its boundary edges in order ([`write_voronoi_face`]).
//! * `.v.cell` (3D) — header `<#cells>`, then `<index> <#faces> <face…>`
//!   ([`write_voronoi_cell`]).
//!
//! Every index is shifted by `first_index` (1 in Triangle/TetGen by default,
//! 0 with their `-z` switch); the ray marker `-1` is not.
//!
//! Checked against the real programs (built by `delone-bench`'s `refbin`):
//! the layouts match. TetGen ends the edge list of an *unbounded* face, and
//! the face list of an unbounded cell, with a `-1` entry (counted in the
//! length): pass `u32::MAX` as that entry and it is written as `-1`. TetGen
//! writes 3D ray directions as unit vectors, Triangle 2D ones unnormalised
//! (the callers in `delone` follow both). The *order* of vertices, edges and
//! faces differs from theirs (ours follows delone's tetrahedra/triangles);
//! the counts agree for points in general position.

use std::io::Write;

use crate::out::Out;
use crate::topo::NONE;
use crate::IoError;

/// Writes a `.v.node` file: the Voronoi vertices as an ordinary `.node` file
/// (no attributes, no markers).
///
/// # Errors
/// [`IoError::Io`] if the writer fails.
///
/// ```
/// let mut out = Vec::new();
/// delone_io::write_voronoi_node(&mut out, &[[0.5, 0.5]], 1).unwrap();
/// assert_eq!(String::from_utf8(out).unwrap(), "1 2 0 0\n1 0.5 0.5\n");
/// ```
pub fn write_voronoi_node<W: Write, const D: usize>(
    out: W,
    vertices: &[[f64; D]],
    first_index: u32,
) -> Result<(), IoError> {
    crate::write_node(out, vertices, &[], 0, None, first_index)
}

/// Writes a `.v.edge` file (2D or 3D): `edges[i] = [v1, v2]` with
/// `v2 == u32::MAX` for a ray, whose direction is `directions[i]`
/// (`directions` may be empty when there are no rays; otherwise it has one
/// entry per edge, ignored for finite edges).
///
/// # Errors
/// [`IoError::InvalidInput`] if a ray has no direction or a vertex id is
/// not below `n_vertices`; [`IoError::Io`] if the writer fails.
///
/// ```
/// let mut out = Vec::new();
/// let edges = [[0, 1], [1, u32::MAX]];
/// let dirs = [[0.0, 0.0], [1.0, -2.0]];
/// delone_io::write_voronoi_edge(&mut out, &edges, &dirs, 2, 1).unwrap();
/// assert_eq!(String::from_utf8(out).unwrap(), "2 0\n1 1 2\n2 2 -1 1 -2\n");
/// ```
pub fn write_voronoi_edge<W: Write, const D: usize>(
    out: W,
    edges: &[[u32; 2]],
    directions: &[[f64; D]],
    n_vertices: usize,
    first_index: u32,
) -> Result<(), IoError> {
    for (i, e) in edges.iter().enumerate() {
        if e[0] as usize >= n_vertices || (e[1] != NONE && e[1] as usize >= n_vertices) {
            return Err(IoError::invalid(format!(
                "Voronoi edge {i} {e:?} refers to a vertex beyond {n_vertices}"
            )));
        }
        if e[1] == NONE && i >= directions.len() {
            return Err(IoError::invalid(format!(
                "Voronoi edge {i} is a ray without a direction"
            )));
        }
    }
    let f = u64::from(first_index);
    let mut o = Out::new(out);
    o.uint(edges.len() as u64);
    o.str(" 0");
    o.nl()?;
    for (i, e) in edges.iter().enumerate() {
        o.uint(i as u64 + f);
        o.byte(b' ');
        o.uint(u64::from(e[0]) + f);
        if e[1] == NONE {
            o.str(" -1");
            for &c in &directions[i] {
                o.byte(b' ');
                o.float(c);
            }
        } else {
            o.byte(b' ');
            o.uint(u64::from(e[1]) + f);
        }
        o.nl()?;
    }
    Ok(o.finish()?)
}

fn check_csr(what: &str, offsets: &[u32], items: &[u32], bound: usize) -> Result<(), IoError> {
    if offsets.first().is_some_and(|&o| o != 0)
        || offsets.windows(2).any(|w| w[0] > w[1])
        || offsets.last().map_or(0, |&o| o as usize) != items.len()
    {
        return Err(IoError::invalid(format!(
            "the {what} offsets do not partition {} entries",
            items.len()
        )));
    }
    if let Some(k) = items.iter().position(|&x| x != NONE && x as usize >= bound) {
        return Err(IoError::invalid(format!(
            "{what} entry {k} is {}, beyond {bound}",
            items[k]
        )));
    }
    Ok(())
}

/// Writes a TetGen `.v.face` file: face `i` separates the cells
/// `cells[i]` and is bounded by the edges
/// `edge_ids[offsets[i]..offsets[i + 1]]` (indices into the `.v.edge`
/// list). `offsets` has one more entry than `cells` (or is empty when
/// `cells` is).
///
/// # Errors
/// [`IoError::InvalidInput`] if the offsets do not match or an edge id is
/// not below `n_edges`; [`IoError::Io`] if the writer fails.
///
/// ```
/// let mut out = Vec::new();
/// delone_io::write_voronoi_face(&mut out, &[[0, 1]], &[0, 3], &[0, 1, 2], 3, 0).unwrap();
/// assert_eq!(String::from_utf8(out).unwrap(), "1 0\n0 0 1 3 0 1 2\n");
/// ```
pub fn write_voronoi_face<W: Write>(
    out: W,
    cells: &[[u32; 2]],
    offsets: &[u32],
    edge_ids: &[u32],
    n_edges: usize,
    first_index: u32,
) -> Result<(), IoError> {
    if offsets.len() != cells.len() + 1 && !(cells.is_empty() && offsets.is_empty()) {
        return Err(IoError::invalid(format!(
            "{} faces need {} offsets, got {}",
            cells.len(),
            cells.len() + 1,
            offsets.len()
        )));
    }
    check_csr("face edge", offsets, edge_ids, n_edges)?;
    let f = u64::from(first_index);
    let mut o = Out::new(out);
    o.uint(cells.len() as u64);
    o.str(" 0");
    o.nl()?;
    for (i, c) in cells.iter().enumerate() {
        o.uint(i as u64 + f);
        for &x in c {
            o.byte(b' ');
            if x == NONE {
                o.str("-1");
            } else {
                o.uint(u64::from(x) + f);
            }
        }
        let es = &edge_ids[offsets[i] as usize..offsets[i + 1] as usize];
        o.byte(b' ');
        o.uint(es.len() as u64);
        for &e in es {
            o.byte(b' ');
            if e == NONE {
                o.str("-1");
            } else {
                o.uint(u64::from(e) + f);
            }
        }
        o.nl()?;
    }
    Ok(o.finish()?)
}

/// Writes a TetGen `.v.cell` file: cell `i` is bounded by the faces
/// `face_ids[offsets[i]..offsets[i + 1]]` (indices into the `.v.face` list).
///
/// # Errors
/// [`IoError::InvalidInput`] if the offsets do not partition `face_ids` or
/// a face id is not below `n_faces`; [`IoError::Io`] if the writer fails.
///
/// ```
/// let mut out = Vec::new();
/// delone_io::write_voronoi_cell(&mut out, &[0, 2, 3], &[0, 1, 1], 2, 1).unwrap();
/// assert_eq!(String::from_utf8(out).unwrap(), "2\n1 2 1 2\n2 1 2\n");
/// ```
pub fn write_voronoi_cell<W: Write>(
    out: W,
    offsets: &[u32],
    face_ids: &[u32],
    n_faces: usize,
    first_index: u32,
) -> Result<(), IoError> {
    check_csr("cell face", offsets, face_ids, n_faces)?;
    let f = u64::from(first_index);
    let n = offsets.len().saturating_sub(1);
    let mut o = Out::new(out);
    o.uint(n as u64);
    o.nl()?;
    for i in 0..n {
        let fs = &face_ids[offsets[i] as usize..offsets[i + 1] as usize];
        o.uint(i as u64 + f);
        o.byte(b' ');
        o.uint(fs.len() as u64);
        for &x in fs {
            o.byte(b' ');
            if x == NONE {
                o.str("-1");
            } else {
                o.uint(u64::from(x) + f);
            }
        }
        o.nl()?;
    }
    Ok(o.finish()?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_inconsistent_input() {
        let mut out = Vec::new();
        assert!(write_voronoi_edge::<_, 2>(&mut out, &[[0, NONE]], &[], 1, 0).is_err());
        assert!(write_voronoi_edge(&mut out, &[[0, 5]], &[[0.0; 3]], 2, 0).is_err());
        assert!(write_voronoi_face(&mut out, &[[0, 1]], &[0, 2], &[0], 1, 0).is_err());
        assert!(write_voronoi_face(&mut out, &[[0, 1]], &[0, 1], &[7], 2, 0).is_err());
        assert!(write_voronoi_cell(&mut out, &[0, 2, 1], &[0, 1], 2, 0).is_err());
    }

    #[test]
    fn three_d_rays() {
        let mut out = Vec::new();
        write_voronoi_edge(&mut out, &[[0, NONE]], &[[0.5, -1.0, 1e-20]], 1, 0).unwrap();
        assert_eq!(
            String::from_utf8(out).unwrap(),
            "1 0\n0 0 -1 0.5 -1 1e-20\n"
        );
    }
}
