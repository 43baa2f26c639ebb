//! Writers for the Triangle/TetGen family: `.node`, `.ele`, `.neigh`,
//! `.edge`, `.face`.
//!
//! All writers take any [`std::io::Write`] (they buffer internally, no need
//! to wrap a file in a `BufWriter`), number items from `first_index` (1 by
//! default in Triangle/TetGen, 0 with their `-z` switch) and print floats in
//! the shortest form that reads back bit for bit.

use std::io::Write;

use crate::out::Out;
use crate::topo::NONE;
use crate::IoError;

fn check_len(what: &str, len: usize, want: usize) -> Result<(), IoError> {
    if len != want {
        return Err(IoError::invalid(format!(
            "{what} has {len} entries, expected {want}"
        )));
    }
    Ok(())
}

/// Writes a `.node` file: header `<#points> <dim> <#attributes> <0|1>`, then
/// `<index> <coords…> <attributes…> [marker]` per point.
///
/// `attributes` holds `n_attributes` values per point, point after point.
///
/// # Errors
/// [`IoError::InvalidInput`] if `attributes` or `markers` do not match the
/// number of points; [`IoError::Io`] if the writer fails.
///
/// ```
/// let mut out = Vec::new();
/// delone_io::write_node(&mut out, &[[0.0, 0.5], [1e-9, 2.0]], &[], 0, Some(&[1, 0]), 1).unwrap();
/// assert_eq!(String::from_utf8(out).unwrap(), "2 2 0 1\n1 0 0.5 1\n2 1e-9 2 0\n");
/// ```
pub fn write_node<W: Write, const D: usize>(
    out: W,
    points: &[[f64; D]],
    attributes: &[f64],
    n_attributes: usize,
    markers: Option<&[i32]>,
    first_index: u32,
) -> Result<(), IoError> {
    write_node_threads(
        out,
        points,
        attributes,
        n_attributes,
        markers,
        first_index,
        1,
    )
}

/// [`write_node`] with the lines formatted on up to `threads` threads (the
/// same bytes for any thread count).
///
/// # Errors
/// As [`write_node`].
///
/// ```
/// let (mut one, mut two) = (Vec::new(), Vec::new());
/// let pts = vec![[0.5, 1e-9, 3.0]; 100_000];
/// delone_io::write_node(&mut one, &pts, &[], 0, None, 1).unwrap();
/// delone_io::write_node_threads(&mut two, &pts, &[], 0, None, 1, 2).unwrap();
/// assert!(one == two);
/// ```
pub fn write_node_threads<W: Write, const D: usize>(
    out: W,
    points: &[[f64; D]],
    attributes: &[f64],
    n_attributes: usize,
    markers: Option<&[i32]>,
    first_index: u32,
    threads: usize,
) -> Result<(), IoError> {
    check_len(
        "the attribute array",
        attributes.len(),
        points.len().saturating_mul(n_attributes),
    )?;
    if let Some(m) = markers {
        check_len("the marker array", m.len(), points.len())?;
    }
    let mut o = Out::new(out);
    o.uint(points.len() as u64);
    o.byte(b' ');
    o.uint(D as u64);
    o.byte(b' ');
    o.uint(n_attributes as u64);
    o.str(if markers.is_some() { " 1" } else { " 0" });
    o.byte(b'\n');
    o.rows(points.len(), u64::from(first_index), threads, |o, i| {
        for &c in &points[i] {
            o.byte(b' ');
            o.float(c);
        }
        for &a in &attributes[i * n_attributes..(i + 1) * n_attributes] {
            o.byte(b' ');
            o.float(a);
        }
        if let Some(m) = markers {
            o.byte(b' ');
            o.int(i64::from(m[i]));
        }
    })?;
    Ok(o.finish()?)
}

/// Writes an `.ele` file: header `<#elements> <nodes per element>
/// <#attributes>`, then `<index> <nodes…> <attributes…>`.
///
/// Node indices are 0-based in `elements` and shifted by `first_index` on
/// output. `attributes` holds `n_attributes` values per element (TetGen's
/// region attribute is `n_attributes == 1`).
///
/// # Errors
/// [`IoError::InvalidInput`] if `attributes` does not match;
/// [`IoError::Io`] if the writer fails.
///
/// ```
/// let mut out = Vec::new();
/// delone_io::write_ele(&mut out, &[[0, 1, 2], [2, 1, 3]], &[], 0, 0).unwrap();
/// assert_eq!(String::from_utf8(out).unwrap(), "2 3 0\n0 0 1 2\n1 2 1 3\n");
/// ```
pub fn write_ele<W: Write, const K: usize>(
    out: W,
    elements: &[[u32; K]],
    attributes: &[f64],
    n_attributes: usize,
    first_index: u32,
) -> Result<(), IoError> {
    write_ele_threads(out, elements, attributes, n_attributes, first_index, 1)
}

/// [`write_ele`] with the lines formatted on up to `threads` threads (the
/// same bytes for any thread count).
///
/// # Errors
/// As [`write_ele`].
///
/// ```
/// let (mut one, mut two) = (Vec::new(), Vec::new());
/// let tets = vec![[0, 1, 2, 3]; 100_000];
/// delone_io::write_ele(&mut one, &tets, &[], 0, 1).unwrap();
/// delone_io::write_ele_threads(&mut two, &tets, &[], 0, 1, 2).unwrap();
/// assert!(one == two);
/// ```
pub fn write_ele_threads<W: Write, const K: usize>(
    out: W,
    elements: &[[u32; K]],
    attributes: &[f64],
    n_attributes: usize,
    first_index: u32,
    threads: usize,
) -> Result<(), IoError> {
    check_len(
        "the element attribute array",
        attributes.len(),
        elements.len().saturating_mul(n_attributes),
    )?;
    let mut o = Out::new(out);
    o.uint(elements.len() as u64);
    o.byte(b' ');
    o.uint(K as u64);
    o.byte(b' ');
    o.uint(n_attributes as u64);
    o.byte(b'\n');
    let f = u64::from(first_index);
    if n_attributes == 0 {
        o.rows(elements.len(), f, threads, |o, i| {
            o.space_uints(&elements[i], f)
        })?;
    } else {
        o.rows(elements.len(), f, threads, |o, i| {
            o.space_uints(&elements[i], f);
            for &a in &attributes[i * n_attributes..(i + 1) * n_attributes] {
                o.byte(b' ');
                o.float(a);
            }
        })?;
    }
    Ok(o.finish()?)
}

/// Writes a `.neigh` file: header `<#elements> <K>`, then `<index>
/// <neighbours…>` where neighbour `i` is across the side opposite node `i`,
/// and `-1` marks none ([`NONE`] in `neighbors`), as Triangle and TetGen write.
///
/// # Errors
/// [`IoError::Io`] if the writer fails.
///
/// ```
/// let mut out = Vec::new();
/// delone_io::write_neigh(&mut out, &[[1, u32::MAX, u32::MAX], [u32::MAX, 0, u32::MAX]], 1).unwrap();
/// assert_eq!(String::from_utf8(out).unwrap(), "2 3\n1 2 -1 -1\n2 -1 1 -1\n");
/// ```
pub fn write_neigh<W: Write, const K: usize>(
    out: W,
    neighbors: &[[u32; K]],
    first_index: u32,
) -> Result<(), IoError> {
    let mut o = Out::new(out);
    o.uint(neighbors.len() as u64);
    o.byte(b' ');
    o.uint(K as u64);
    o.nl()?;
    let f = u64::from(first_index);
    for (i, nb) in neighbors.iter().enumerate() {
        o.uint(i as u64 + f);
        for &n in nb {
            if n == NONE {
                o.str(" -1");
            } else {
                o.byte(b' ');
                o.uint(u64::from(n) + f);
            }
        }
        o.nl()?;
    }
    Ok(o.finish()?)
}

fn write_cells<W: Write, const K: usize>(
    out: W,
    cells: &[[u32; K]],
    markers: Option<&[i32]>,
    first_index: u32,
) -> Result<(), IoError> {
    if let Some(m) = markers {
        check_len("the marker array", m.len(), cells.len())?;
    }
    let mut o = Out::new(out);
    o.uint(cells.len() as u64);
    o.str(if markers.is_some() { " 1" } else { " 0" });
    o.nl()?;
    let f = u64::from(first_index);
    for (i, c) in cells.iter().enumerate() {
        o.uint(i as u64 + f);
        for &v in c {
            o.byte(b' ');
            o.uint(u64::from(v) + f);
        }
        if let Some(m) = markers {
            o.byte(b' ');
            o.int(i64::from(m[i]));
        }
        o.nl()?;
    }
    Ok(o.finish()?)
}

/// Writes an `.edge` file: header `<#edges> <0|1>`, then `<index> <a> <b>
/// [marker]`. Get the edges from [`crate::topo::tri_edges`] or
/// [`crate::topo::tet_edges`] (markers: [`crate::topo::Entities::markers`]).
///
/// # Errors
/// [`IoError::InvalidInput`] if `markers` does not match;
/// [`IoError::Io`] if the writer fails.
///
/// ```
/// let mut out = Vec::new();
/// delone_io::write_edge(&mut out, &[[0, 1], [1, 2]], Some(&[1, 0]), 1).unwrap();
/// assert_eq!(String::from_utf8(out).unwrap(), "2 1\n1 1 2 1\n2 2 3 0\n");
/// ```
pub fn write_edge<W: Write>(
    out: W,
    edges: &[[u32; 2]],
    markers: Option<&[i32]>,
    first_index: u32,
) -> Result<(), IoError> {
    write_cells(out, edges, markers, first_index)
}

/// Writes a `.face` file (TetGen): header `<#faces> <0|1>`, then `<index>
/// <a> <b> <c> [marker]`. Get the faces from [`crate::topo::tet_faces`].
///
/// # Errors
/// [`IoError::InvalidInput`] if `markers` does not match;
/// [`IoError::Io`] if the writer fails.
///
/// ```
/// let mut out = Vec::new();
/// delone_io::write_face(&mut out, &[[1, 2, 3]], None, 0).unwrap();
/// assert_eq!(String::from_utf8(out).unwrap(), "1 0\n0 1 2 3\n");
/// ```
pub fn write_face<W: Write>(
    out: W,
    faces: &[[u32; 3]],
    markers: Option<&[i32]>,
    first_index: u32,
) -> Result<(), IoError> {
    write_cells(out, faces, markers, first_index)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{read_ele, read_node, read_node_threads};

    #[test]
    fn node_round_trip_bit_exact() {
        let mut s: u64 = 12345;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            f64::from_bits((s >> 2) | 0x3000_0000_0000_0000) * if s & 1 == 1 { -1.0 } else { 1.0 }
        };
        // Three blocks of rows: the threaded writer and reader give the same.
        let n: usize = 70_000;
        let pts: Vec<[f64; 3]> = (0..n).map(|_| [rnd(), rnd(), rnd()]).collect();
        let attrs: Vec<f64> = (0..2 * n).map(|_| rnd()).collect();
        let marks: Vec<i32> = (0..n as i32).map(|i| i * 7 - 900).collect();
        for first in [0, 1] {
            let mut buf = Vec::new();
            write_node(&mut buf, &pts, &attrs, 2, Some(&marks), first).unwrap();
            for threads in [2, 3] {
                let mut par = Vec::new();
                write_node_threads(&mut par, &pts, &attrs, 2, Some(&marks), first, threads)
                    .unwrap();
                assert!(par == buf);
                assert_eq!(
                    read_node_threads(&buf, threads).unwrap(),
                    read_node(&buf).unwrap()
                );
            }
            let f = read_node(&buf).unwrap();
            assert_eq!(f.first_index, first);
            assert_eq!(f.points::<3>().unwrap(), pts);
            assert_eq!(f.attributes, attrs);
            assert_eq!(f.markers.as_deref(), Some(&marks[..]));
        }
    }

    #[test]
    fn ele_round_trip() {
        let tets = vec![[0u32, 1, 2, 3], [4, 3, 2, 1], [7, 8, 9, 10]];
        let mut buf = Vec::new();
        write_ele(&mut buf, &tets, &[1.0, 2.0, -3.5], 1, 1).unwrap();
        let f = read_ele(&buf, 1).unwrap();
        assert_eq!(f.nodes_per_element, 4);
        assert_eq!(f.elements, tets.concat());
        assert_eq!(f.attributes, vec![1.0, 2.0, -3.5]);
    }

    #[test]
    fn mismatched_lengths_are_errors() {
        let e = write_node(Vec::new(), &[[0.0, 0.0]], &[], 0, Some(&[1, 2]), 1).unwrap_err();
        assert_eq!(e.to_string(), "the marker array has 2 entries, expected 1");
        assert!(write_ele(Vec::new(), &[[0u32, 1, 2]], &[1.0], 2, 1).is_err());
        assert!(write_face(Vec::new(), &[[0, 1, 2]], Some(&[]), 1).is_err());
    }
}
