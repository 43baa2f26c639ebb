//! VTK output: XML `.vtu` (UnstructuredGrid; ASCII or raw binary appended
//! data) and the legacy ASCII `.vtk` format TetGen writes with `-k`.
//!
//! Points of 2D meshes get `z = 0` (VTK points always have 3 components).
//! Cell types: triangles are VTK type 5, tetrahedra type 10, edges type 3,
//! 6-node cells quadratic triangles (type 22: corners, then the midpoints of
//! edges 0–1, 1–2, 2–0).

use std::io::Write;

use crate::out::Out;
use crate::IoError;

/// Values of a point- or cell-data array.
///
/// ```
/// let q = [0.5, 0.9];
/// let v = delone_io::Values::Float64(&q);
/// assert!(matches!(v, delone_io::Values::Float64(s) if s.len() == 2));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Values<'a> {
    /// 32-bit integers (markers, region ids).
    Int32(&'a [i32]),
    /// 64-bit floats (attributes, quality measures).
    Float64(&'a [f64]),
}

impl Values<'_> {
    fn len(&self) -> usize {
        match self {
            Values::Int32(v) => v.len(),
            Values::Float64(v) => v.len(),
        }
    }
}

/// A named scalar array attached to the points or the cells.
///
/// ```
/// let markers = [1, 0, 1];
/// let a = delone_io::DataArray { name: "marker", values: delone_io::Values::Int32(&markers) };
/// assert_eq!(a.name, "marker");
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DataArray<'a> {
    /// Array name shown by ParaView / VisIt.
    pub name: &'a str,
    /// One value per point (point data) or per cell (cell data).
    pub values: Values<'a>,
}

/// Encoding of the data arrays of a `.vtu` file.
///
/// ```
/// assert_eq!(delone_io::VtuFormat::default(), delone_io::VtuFormat::Binary);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum VtuFormat {
    /// Human-readable text inside each `<DataArray>`.
    Ascii,
    /// Raw little-endian binary in one `<AppendedData encoding="raw">` block,
    /// each array preceded by its byte count as a `UInt64`. Compact and fast.
    #[default]
    Binary,
}

fn cell_type(k: usize) -> Result<u8, IoError> {
    match k {
        2 => Ok(3),
        3 => Ok(5),
        4 => Ok(10),
        6 => Ok(22),
        _ => Err(IoError::invalid(format!(
            "VTK output supports cells of 2, 3, 4 or 6 vertices, not {k}"
        ))),
    }
}

/// Cell blocks: per block the flat connectivity and its vertices per cell.
type Blocks<'a> = [(&'a [u32], usize)];

fn check_input<const D: usize>(
    points: &[[f64; D]],
    blocks: &Blocks<'_>,
    point_data: &[DataArray<'_>],
    cell_data: &[DataArray<'_>],
) -> Result<Vec<u8>, IoError> {
    if D != 2 && D != 3 {
        return Err(IoError::invalid(format!(
            "VTK output supports 2D and 3D points, not {D}D"
        )));
    }
    let n = points.len();
    let mut types = Vec::with_capacity(blocks.len());
    let mut first = 0;
    for (i, &(flat, k)) in blocks.iter().enumerate() {
        // An empty block of faces may have any width but 0.
        types.push(if i > 0 && flat.is_empty() && k != 0 {
            0
        } else {
            cell_type(k)?
        });
        for (c, cell) in flat.chunks_exact(k).enumerate() {
            if let Some(&v) = cell.iter().find(|&&v| v as usize >= n) {
                let c = first + c;
                return Err(IoError::invalid(format!(
                    "cell {c} refers to point {v}, but there are only {n} points"
                )));
            }
        }
        first += flat.len() / k;
    }
    for (arrays, count, kind) in [(point_data, n, "point"), (cell_data, first, "cell")] {
        for a in arrays {
            if a.values.len() != count {
                return Err(IoError::invalid(format!(
                    "{kind} data \"{}\" has {} values, expected {count}",
                    a.name,
                    a.values.len()
                )));
            }
        }
    }
    Ok(types)
}

fn xml_escape(s: &str) -> String {
    let mut r = String::with_capacity(s.len());
    for ch in s.chars() {
        match ch {
            '&' => r.push_str("&amp;"),
            '<' => r.push_str("&lt;"),
            '>' => r.push_str("&gt;"),
            '"' => r.push_str("&quot;"),
            c => r.push(c),
        }
    }
    r
}

fn vtk_name(s: &str) -> String {
    let r: String = s
        .chars()
        .map(|c| if c.is_ascii_graphic() { c } else { '_' })
        .collect();
    if r.is_empty() {
        "data".to_string()
    } else {
        r
    }
}

/// Writes an XML VTK UnstructuredGrid (`.vtu`, version 1.0, little endian,
/// `header_type="UInt64"`, `Int64` connectivity and offsets).
///
/// # Errors
/// [`IoError::InvalidInput`] if a cell refers to a missing point, a data
/// array has the wrong length, or `K` is not 2, 3 or 4;
/// [`IoError::Io`] if the writer fails.
///
/// ```
/// use delone_io::{write_vtu, DataArray, Values, VtuFormat};
/// let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
/// let marker = [1, 1, 1];
/// let mut out = Vec::new();
/// write_vtu(&mut out, &pts, &[[0, 1, 2]],
///           &[DataArray { name: "marker", values: Values::Int32(&marker) }], &[], VtuFormat::Ascii).unwrap();
/// let text = String::from_utf8(out).unwrap();
/// assert!(text.contains(r#"<Piece NumberOfPoints="3" NumberOfCells="1">"#));
/// ```
pub fn write_vtu<W: Write, const D: usize, const K: usize>(
    out: W,
    points: &[[f64; D]],
    cells: &[[u32; K]],
    point_data: &[DataArray<'_>],
    cell_data: &[DataArray<'_>],
    format: VtuFormat,
) -> Result<(), IoError> {
    let blocks = [(cells.as_flattened(), K)];
    write_blocks(out, points, &blocks, point_data, cell_data, format)
}

/// Writes a `.vtu` like [`write_vtu`] with a second block of lower-dimensional
/// cells after the elements — the boundary edges of a triangle mesh or the
/// boundary triangles of a tetrahedral mesh — so that readers (ParaView,
/// meshio, [`crate::read_vtu`]) see both. `cell_data` arrays hold one value
/// per element, then one per face.
///
/// # Errors
/// As [`write_vtu`]; `F` must also be 2, 3, 4 or 6 unless `faces` is empty.
///
/// ```
/// use delone_io::{write_vtu_with_faces, DataArray, Values, VtuFormat};
/// let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
/// let refs = [7, 1, 2, 3];
/// let mut out = Vec::new();
/// write_vtu_with_faces(&mut out, &pts, &[[0, 1, 2]], &[[0, 1], [1, 2], [2, 0]], &[],
///     &[DataArray { name: "ref", values: Values::Int32(&refs) }], VtuFormat::Ascii).unwrap();
/// let text = String::from_utf8(out).unwrap();
/// assert!(text.contains(r#"NumberOfCells="4""#));
/// let (mesh, _) = delone_io::read_vtu(text.as_bytes()).unwrap();
/// assert_eq!((mesh.triangle_refs, mesh.edge_refs), (vec![7], vec![1, 2, 3]));
/// ```
pub fn write_vtu_with_faces<W: Write, const D: usize, const K: usize, const F: usize>(
    out: W,
    points: &[[f64; D]],
    cells: &[[u32; K]],
    faces: &[[u32; F]],
    point_data: &[DataArray<'_>],
    cell_data: &[DataArray<'_>],
    format: VtuFormat,
) -> Result<(), IoError> {
    let blocks = [(cells.as_flattened(), K), (faces.as_flattened(), F)];
    write_blocks(out, points, &blocks, point_data, cell_data, format)
}

fn write_blocks<W: Write, const D: usize>(
    out: W,
    points: &[[f64; D]],
    blocks: &Blocks<'_>,
    point_data: &[DataArray<'_>],
    cell_data: &[DataArray<'_>],
    format: VtuFormat,
) -> Result<(), IoError> {
    let types = check_input(points, blocks, point_data, cell_data)?;
    let cells = || blocks.iter().flat_map(|&(flat, k)| flat.chunks_exact(k));
    // Per cell: its offset's end and type.
    let ends = || {
        let mut end = 0u64;
        blocks
            .iter()
            .zip(&types)
            .flat_map(|(&(flat, k), &ty)| std::iter::repeat_n((k as u64, ty), flat.len() / k))
            .map(move |(k, ty)| {
                end += k;
                (end, ty)
            })
    };
    let conn: u64 = blocks.iter().map(|b| b.0.len() as u64).sum();
    let n = points.len() as u64;
    let m = cells().count() as u64;
    let mut o = Out::new(out);
    o.str("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"");
    o.uint(n);
    o.str("\" NumberOfCells=\"");
    o.uint(m);
    o.str("\">\n");

    // Appended layout: every array's byte size, in document order.
    let mut offset: u64 = 0;
    let mut header = |o: &mut Out<W>, ty_name: &str, name: &str, comps: usize, bytes: u64| {
        o.str("<DataArray type=\"");
        o.str(ty_name);
        o.str("\" Name=\"");
        o.str(&xml_escape(name));
        o.str("\"");
        if comps > 1 {
            o.str(" NumberOfComponents=\"");
            o.uint(comps as u64);
            o.str("\"");
        }
        match format {
            VtuFormat::Ascii => o.str(" format=\"ascii\">\n"),
            VtuFormat::Binary => {
                o.str(" format=\"appended\" offset=\"");
                o.uint(offset);
                o.str("\"/>\n");
                offset += 8 + bytes;
            }
        }
    };
    let ascii = format == VtuFormat::Ascii;
    for (tag, arrays) in [("PointData", point_data), ("CellData", cell_data)] {
        if arrays.is_empty() {
            continue;
        }
        o.str("<");
        o.str(tag);
        o.str(">\n");
        for a in arrays {
            match a.values {
                Values::Int32(v) => {
                    header(&mut o, "Int32", a.name, 1, 4 * v.len() as u64);
                    if ascii {
                        ascii_ints(&mut o, v.iter().map(|&x| i64::from(x)))?;
                    }
                }
                Values::Float64(v) => {
                    header(&mut o, "Float64", a.name, 1, 8 * v.len() as u64);
                    if ascii {
                        for (i, &x) in v.iter().enumerate() {
                            o.float(x);
                            o.byte(if i % 8 == 7 { b'\n' } else { b' ' });
                            o.maybe_flush()?;
                        }
                        o.str("\n</DataArray>\n");
                    }
                }
            }
        }
        o.str("</");
        o.str(tag);
        o.str(">\n");
    }
    o.str("<Points>\n");
    header(&mut o, "Float64", "Points", 3, 24 * n);
    if ascii {
        for p in points {
            o.float(p[0]);
            o.byte(b' ');
            o.float(p[1]);
            o.byte(b' ');
            o.float(if D == 3 { p[D - 1] } else { 0.0 });
            o.nl()?;
        }
        o.str("</DataArray>\n");
    }
    o.str("</Points>\n<Cells>\n");
    header(&mut o, "Int64", "connectivity", 1, 8 * conn);
    if ascii {
        for c in cells() {
            for (j, &v) in c.iter().enumerate() {
                if j > 0 {
                    o.byte(b' ');
                }
                o.uint(u64::from(v));
            }
            o.nl()?;
        }
        o.str("</DataArray>\n");
    }
    header(&mut o, "Int64", "offsets", 1, 8 * m);
    if ascii {
        ascii_ints(&mut o, ends().map(|(e, _)| e as i64))?;
    }
    header(&mut o, "UInt8", "types", 1, m);
    if ascii {
        ascii_ints(&mut o, ends().map(|(_, ty)| i64::from(ty)))?;
    }
    o.str("</Cells>\n</Piece>\n</UnstructuredGrid>\n");
    if !ascii {
        o.str("<AppendedData encoding=\"raw\">\n_");
        for arrays in [point_data, cell_data] {
            for a in arrays {
                match a.values {
                    Values::Int32(v) => {
                        o.buf.extend_from_slice(&(4 * v.len() as u64).to_le_bytes());
                        for &x in v {
                            o.buf.extend_from_slice(&x.to_le_bytes());
                            o.maybe_flush()?;
                        }
                    }
                    Values::Float64(v) => {
                        o.buf.extend_from_slice(&(8 * v.len() as u64).to_le_bytes());
                        for &x in v {
                            o.buf.extend_from_slice(&x.to_le_bytes());
                            o.maybe_flush()?;
                        }
                    }
                }
            }
        }
        o.buf.extend_from_slice(&(24 * n).to_le_bytes());
        for p in points {
            let z = if D == 3 { p[D - 1] } else { 0.0 };
            for c in [p[0], p[1], z] {
                o.buf.extend_from_slice(&c.to_le_bytes());
            }
            o.maybe_flush()?;
        }
        o.buf.extend_from_slice(&(8 * conn).to_le_bytes());
        for c in cells() {
            for &v in c {
                o.buf.extend_from_slice(&i64::from(v).to_le_bytes());
            }
            o.maybe_flush()?;
        }
        o.buf.extend_from_slice(&(8 * m).to_le_bytes());
        for (e, _) in ends() {
            o.buf.extend_from_slice(&e.to_le_bytes());
            o.maybe_flush()?;
        }
        o.buf.extend_from_slice(&m.to_le_bytes());
        for (_, ty) in ends() {
            o.buf.push(ty);
            o.maybe_flush()?;
        }
        o.str("\n</AppendedData>\n");
    }
    o.str("</VTKFile>\n");
    Ok(o.finish()?)
}

fn ascii_ints<W: Write>(o: &mut Out<W>, vals: impl Iterator<Item = i64>) -> Result<(), IoError> {
    for (i, x) in vals.enumerate() {
        o.int(x);
        o.byte(if i % 16 == 15 { b'\n' } else { b' ' });
        o.maybe_flush()?;
    }
    o.str("\n</DataArray>\n");
    Ok(())
}

/// Writes a legacy ASCII VTK file (`# vtk DataFile Version 2.0`,
/// `DATASET UNSTRUCTURED_GRID`), the format of TetGen's `-k` output:
/// `POINTS n double`, `CELLS m size`, `CELL_TYPES m`, then optional
/// `POINT_DATA` / `CELL_DATA` scalars (`int` or `double`, default lookup table).
/// Point indices are 0-based, as VTK requires.
///
/// # Errors
/// As [`write_vtu`].
///
/// ```
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// let mut out = Vec::new();
/// delone_io::write_vtk_legacy(&mut out, &pts, &[[0, 1, 2, 3]], &[], &[], "one tet").unwrap();
/// let text = String::from_utf8(out).unwrap();
/// assert!(text.contains("CELLS 1 5\n4 0 1 2 3\n"));
/// assert!(text.contains("CELL_TYPES 1\n10\n"));
/// ```
pub fn write_vtk_legacy<W: Write, const D: usize, const K: usize>(
    out: W,
    points: &[[f64; D]],
    cells: &[[u32; K]],
    point_data: &[DataArray<'_>],
    cell_data: &[DataArray<'_>],
    title: &str,
) -> Result<(), IoError> {
    let ty = check_input(points, &[(cells.as_flattened(), K)], point_data, cell_data)?[0];
    let mut o = Out::new(out);
    o.str("# vtk DataFile Version 2.0\n");
    // The title line is at most 256 characters, without line breaks.
    let title: String = title
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .take(255)
        .collect();
    o.str(&title);
    o.str("\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS ");
    o.uint(points.len() as u64);
    o.str(" double\n");
    for p in points {
        o.float(p[0]);
        o.byte(b' ');
        o.float(p[1]);
        o.byte(b' ');
        o.float(if D == 3 { p[D - 1] } else { 0.0 });
        o.nl()?;
    }
    o.str("\nCELLS ");
    o.uint(cells.len() as u64);
    o.byte(b' ');
    o.uint(cells.len() as u64 * (K as u64 + 1));
    o.nl()?;
    for c in cells {
        o.uint(K as u64);
        for &v in c {
            o.byte(b' ');
            o.uint(u64::from(v));
        }
        o.nl()?;
    }
    o.str("\nCELL_TYPES ");
    o.uint(cells.len() as u64);
    o.nl()?;
    for _ in cells {
        o.uint(u64::from(ty));
        o.nl()?;
    }
    for (tag, arrays, count) in [
        ("POINT_DATA ", point_data, points.len()),
        ("CELL_DATA ", cell_data, cells.len()),
    ] {
        if arrays.is_empty() {
            continue;
        }
        o.byte(b'\n');
        o.str(tag);
        o.uint(count as u64);
        o.nl()?;
        for a in arrays {
            o.str("SCALARS ");
            o.str(&vtk_name(a.name));
            match a.values {
                Values::Int32(v) => {
                    o.str(" int 1\nLOOKUP_TABLE default\n");
                    for &x in v {
                        o.int(i64::from(x));
                        o.nl()?;
                    }
                }
                Values::Float64(v) => {
                    o.str(" double 1\nLOOKUP_TABLE default\n");
                    for &x in v {
                        o.float(x);
                        o.nl()?;
                    }
                }
            }
        }
    }
    Ok(o.finish()?)
}

/// One polyhedron for [`write_vtu_polyhedra`]: its corner coordinates and
/// its faces as lists of indices into those corners (counterclockwise seen
/// from outside).
pub type PolyhedronRef<'a> = (&'a [[f64; 3]], &'a [Vec<u32>]);

/// Writes convex (or any closed) polyhedra, e.g. clipped Voronoi or power
/// cells, as a `.vtu` of VTK_POLYHEDRON cells (type 42, with the `faces` and
/// `faceoffsets` arrays ParaView reads). Each polyhedron keeps its own
/// corners. Empty polyhedra (no faces) are skipped; `cell_data` arrays then
/// hold one value per *written* cell.
///
/// # Errors
/// [`IoError::InvalidInput`] if a face names a missing corner or a data array
/// has the wrong length; [`IoError::Io`] if the writer fails.
///
/// ```
/// use delone_io::{write_vtu_polyhedra, VtuFormat};
/// // A unit tetrahedron.
/// let v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// let f = vec![vec![0, 2, 1], vec![0, 1, 3], vec![1, 2, 3], vec![0, 3, 2]];
/// let mut out = Vec::new();
/// write_vtu_polyhedra(&mut out, &[(&v[..], &f[..])], &[], VtuFormat::Ascii).unwrap();
/// let text = String::from_utf8(out).unwrap();
/// assert!(text.contains("Name=\"faces\"") && text.contains("42"));
/// ```
pub fn write_vtu_polyhedra<W: Write>(
    out: W,
    polys: &[PolyhedronRef<'_>],
    cell_data: &[DataArray<'_>],
    format: VtuFormat,
) -> Result<(), IoError> {
    let kept: Vec<&PolyhedronRef<'_>> = polys.iter().filter(|p| !p.1.is_empty()).collect();
    let m = kept.len();
    if let Some(a) = cell_data.iter().find(|a| a.values.len() != m) {
        return Err(IoError::InvalidInput {
            message: format!(
                "cell data {:?} has {} values for {m} polyhedra",
                a.name,
                a.values.len()
            ),
        });
    }
    let mut points: Vec<f64> = Vec::new();
    let mut connectivity: Vec<i64> = Vec::new();
    let mut offsets: Vec<i64> = Vec::with_capacity(m);
    let mut faces: Vec<i64> = Vec::new();
    let mut faceoffsets: Vec<i64> = Vec::with_capacity(m);
    for (k, (verts, fs)) in kept.iter().enumerate() {
        let base = (points.len() / 3) as i64;
        for p in verts.iter() {
            points.extend_from_slice(p);
        }
        connectivity.extend((0..verts.len() as i64).map(|i| base + i));
        offsets.push(connectivity.len() as i64);
        faces.push(fs.len() as i64);
        for f in fs.iter() {
            if let Some(&bad) = f.iter().find(|&&v| v as usize >= verts.len()) {
                return Err(IoError::InvalidInput {
                    message: format!(
                        "polyhedron {k}: a face names corner {bad} of {}",
                        verts.len()
                    ),
                });
            }
            faces.push(f.len() as i64);
            faces.extend(f.iter().map(|&v| base + i64::from(v)));
        }
        faceoffsets.push(faces.len() as i64);
    }
    let n = points.len() / 3;
    let mut o = Out::new(out);
    o.str("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"");
    o.uint(n as u64);
    o.str("\" NumberOfCells=\"");
    o.uint(m as u64);
    o.str("\">\n");
    let ascii = format == VtuFormat::Ascii;
    // Every array in document order: (section to open first, type, name,
    // components, values).
    let mut arrays: Vec<(&str, &str, &str, usize, PolyArr<'_>)> = Vec::new();
    for a in cell_data {
        let v = match a.values {
            Values::Int32(v) => ("Int32", PolyArr::I32(v)),
            Values::Float64(v) => ("Float64", PolyArr::F64(v)),
        };
        arrays.push(("CellData", v.0, a.name, 1, v.1));
    }
    arrays.push(("Points", "Float64", "Points", 3, PolyArr::F64(&points)));
    arrays.push((
        "Cells",
        "Int64",
        "connectivity",
        1,
        PolyArr::I64(&connectivity),
    ));
    arrays.push(("Cells", "Int64", "offsets", 1, PolyArr::I64(&offsets)));
    arrays.push(("Cells", "UInt8", "types", 1, PolyArr::U8(42, m)));
    arrays.push(("Cells", "Int64", "faces", 1, PolyArr::I64(&faces)));
    arrays.push((
        "Cells",
        "Int64",
        "faceoffsets",
        1,
        PolyArr::I64(&faceoffsets),
    ));
    let mut offset: u64 = 0;
    let mut section = "";
    for (sec, ty, name, comps, a) in &arrays {
        if *sec != section {
            if !section.is_empty() {
                o.str("</");
                o.str(section);
                o.str(">\n");
            }
            o.str("<");
            o.str(sec);
            o.str(">\n");
            section = sec;
        }
        o.str("<DataArray type=\"");
        o.str(ty);
        o.str("\" Name=\"");
        o.str(&xml_escape(name));
        o.str("\"");
        if *comps > 1 {
            o.str(" NumberOfComponents=\"");
            o.uint(*comps as u64);
            o.str("\"");
        }
        if ascii {
            o.str(" format=\"ascii\">\n");
            match a {
                PolyArr::I32(v) => ascii_ints(&mut o, v.iter().map(|&x| i64::from(x)))?,
                PolyArr::I64(v) => ascii_ints(&mut o, v.iter().copied())?,
                PolyArr::U8(t, k) => ascii_ints(&mut o, (0..*k).map(|_| i64::from(*t)))?,
                PolyArr::F64(v) => {
                    for (i, &x) in v.iter().enumerate() {
                        o.float(x);
                        o.byte(if i % 8 == 7 { b'\n' } else { b' ' });
                        o.maybe_flush()?;
                    }
                    o.str("\n</DataArray>\n");
                }
            }
        } else {
            o.str(" format=\"appended\" offset=\"");
            o.uint(offset);
            o.str("\"/>\n");
            offset += 8 + a.bytes();
        }
    }
    o.str("</Cells>\n</Piece>\n</UnstructuredGrid>\n");
    if !ascii {
        o.str("<AppendedData encoding=\"raw\">\n_");
        for (_, _, _, _, a) in arrays {
            o.buf.extend_from_slice(&a.bytes().to_le_bytes());
            match a {
                PolyArr::I32(v) => v
                    .iter()
                    .for_each(|x| o.buf.extend_from_slice(&x.to_le_bytes())),
                PolyArr::F64(v) => v
                    .iter()
                    .for_each(|x| o.buf.extend_from_slice(&x.to_le_bytes())),
                PolyArr::I64(v) => v
                    .iter()
                    .for_each(|x| o.buf.extend_from_slice(&x.to_le_bytes())),
                PolyArr::U8(t, k) => o.buf.extend(std::iter::repeat_n(t, k)),
            }
            o.maybe_flush()?;
        }
        o.str("\n</AppendedData>\n");
    }
    o.str("</VTKFile>\n");
    Ok(o.finish()?)
}

/// A data array of [`write_vtu_polyhedra`].
enum PolyArr<'b> {
    I32(&'b [i32]),
    F64(&'b [f64]),
    I64(&'b [i64]),
    /// A constant byte repeated.
    U8(u8, usize),
}

impl PolyArr<'_> {
    /// Size in bytes of the raw appended data.
    fn bytes(&self) -> u64 {
        match self {
            PolyArr::I32(v) => 4 * v.len() as u64,
            PolyArr::F64(v) => 8 * v.len() as u64,
            PolyArr::I64(v) => 8 * v.len() as u64,
            PolyArr::U8(_, k) => *k as u64,
        }
    }
}
