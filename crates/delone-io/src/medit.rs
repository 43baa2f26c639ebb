//! Reader for the ASCII Medit `.mesh` format (surface part).

use crate::surface::{found, Surface, Tokens};
use crate::IoError;

/// A Medit mesh (`.mesh`, 2D or 3D) with its references: what MMG and
/// Gmsh read and write.
///
/// Indices are 0-based (1-based in the file). In 2D the points' third
/// coordinate is 0. `corners` and `required_vertices` name points; `ridges`
/// and `required_edges` name entries of `edges`. Every element array has
/// a reference array of the same length.
///
/// ```
/// let text = b"MeshVersionFormatted 2\nDimension 2\nVertices\n3\n0 0 1\n1 0 1\n0 1 2\n\
///              Edges\n1\n1 2 5\nTriangles\n1\n1 2 3 7\nCorners\n1\n1\nEnd\n";
/// let m = delone_io::read_medit_mesh(text).unwrap();
/// assert_eq!((m.dimension, m.points[2], m.point_refs[2]), (2, [0.0, 1.0, 0.0], 2));
/// assert_eq!((m.edges.clone(), m.edge_refs.clone()), (vec![[0, 1]], vec![5]));
/// assert_eq!((m.triangles.clone(), m.triangle_refs.clone()), (vec![[0, 1, 2]], vec![7]));
/// assert_eq!(m.corners, vec![0]);
/// let mut out = Vec::new();
/// delone_io::write_medit_mesh(&mut out, &m).unwrap();
/// assert_eq!(delone_io::read_medit_mesh(&out).unwrap(), m);
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MeditMesh {
    /// 2 or 3.
    pub dimension: u8,
    /// Point coordinates (third coordinate 0 in 2D).
    pub points: Vec<[f64; 3]>,
    /// One reference per point.
    pub point_refs: Vec<i32>,
    /// Edges (`Edges`).
    pub edges: Vec<[u32; 2]>,
    /// One reference per edge.
    pub edge_refs: Vec<i32>,
    /// Triangles (`Triangles`).
    pub triangles: Vec<[u32; 3]>,
    /// One reference per triangle.
    pub triangle_refs: Vec<i32>,
    /// Quadrilaterals (`Quadrilaterals`).
    pub quadrilaterals: Vec<[u32; 4]>,
    /// One reference per quadrilateral.
    pub quadrilateral_refs: Vec<i32>,
    /// Tetrahedra (`Tetrahedra`).
    pub tetrahedra: Vec<[u32; 4]>,
    /// One reference per tetrahedron.
    pub tetrahedron_refs: Vec<i32>,
    /// Corner points (`Corners`).
    pub corners: Vec<u32>,
    /// Required points (`RequiredVertices`).
    pub required_vertices: Vec<u32>,
    /// Ridge edges (`Ridges`: indices into `edges`).
    pub ridges: Vec<u32>,
    /// Required edges (`RequiredEdges`: indices into `edges`).
    pub required_edges: Vec<u32>,
}

/// Refuses a binary Medit file (`.meshb`, `.solb`): a zero byte near the
/// start.
fn refuse_binary(input: &[u8], ext: &str) -> Result<(), IoError> {
    if input.iter().take(64).any(|&b| b == 0) {
        return Err(IoError::Unsupported {
            line: 1,
            message: format!("binary Medit (.{ext}) is not supported"),
        });
    }
    Ok(())
}

/// The value of a `Dimension` keyword (2 or 3) and its line.
fn dimension(tk: &mut Tokens) -> Result<(u8, usize), IoError> {
    let (d, l) = tk.int("the dimension")?;
    if d != 2 && d != 3 {
        return Err(IoError::Unsupported {
            line: l,
            message: format!("dimension {d} (only 2 or 3)"),
        });
    }
    Ok((d as u8, l))
}

/// Skips an unknown section: its numbers up to the next keyword.
fn skip_section(tk: &mut Tokens) {
    while let Some((u, _)) = tk.peek() {
        if u[0].is_ascii_alphabetic() {
            break;
        }
        tk.next_tok();
    }
}

fn reference(tk: &mut Tokens) -> Result<i32, IoError> {
    let (r, l) = tk.int("a reference")?;
    i32::try_from(r)
        .map_err(|_| IoError::syntax(l, "a reference that fits in 32 bits", r.to_string()))
}

fn one_based(tk: &mut Tokens, what: &str, n: usize) -> Result<u32, IoError> {
    let (i, l) = tk.int(what)?;
    if i < 1 || i as u64 > n as u64 {
        return Err(IoError::syntax(
            l,
            format!("{what} between 1 and {n}"),
            i.to_string(),
        ));
    }
    Ok((i - 1) as u32)
}

/// Reads the elements of one section: `K` vertex indices and a reference
/// each. Indices are checked against `n_points` when the points came first,
/// or put on `later` to be checked at the end of the file.
fn cells<const K: usize>(
    tk: &mut Tokens,
    (len, n_points): (usize, Option<usize>),
    cells: &mut Vec<[u32; K]>,
    refs: &mut Vec<i32>,
    later: &mut Vec<(usize, i64)>,
) -> Result<(), IoError> {
    let (n, _) = tk.count("the number of elements")?;
    cells.reserve(crate::surface::cap(n, len, 2 * K));
    for _ in 0..n {
        let mut c = [0u32; K];
        for v in &mut c {
            let (i, l) = tk.int("a vertex index")?;
            match n_points {
                Some(n) if i < 1 || i as u64 > n as u64 => {
                    return Err(IoError::syntax(
                        l,
                        format!("a vertex index between 1 and {n}"),
                        i.to_string(),
                    ))
                }
                Some(_) => {}
                None => later.push((l, i)),
            }
            *v = i.clamp(1, u32::MAX as i64) as u32 - 1;
        }
        cells.push(c);
        refs.push(reference(tk)?);
    }
    Ok(())
}

/// Reads an ASCII Medit `.mesh` file (`MeshVersionFormatted`,
/// `Dimension 2` or `3`, `Vertices`, `Edges`, `Triangles`,
/// `Quadrilaterals`, `Tetrahedra`, `Corners`, `RequiredVertices`,
/// `Ridges`, `RequiredEdges`, `End`). Other sections (`Normals`,
/// `Tangents`, `Hexahedra`, …) are skipped.
///
/// # Errors
/// [`IoError::Syntax`] with the line for a malformed record, an index
/// outside its range or a reference beyond 32 bits;
/// [`IoError::Unsupported`] for a dimension other than 2 or 3 or a binary
/// `.meshb` file.
pub fn read_medit_mesh(input: &[u8]) -> Result<MeditMesh, IoError> {
    refuse_binary(input, "meshb")?;
    let mut tk = Tokens::new(input, true);
    let mut m = MeditMesh {
        dimension: 3,
        ..MeditMesh::default()
    };
    // (line, 1-based index) of every vertex index read before the points;
    // checked at the end.
    let mut idx: Vec<(usize, i64)> = Vec::new();
    let mut seen_points = false;
    while let Some((t, line)) = tk.next_tok() {
        let at = (input.len(), seen_points.then_some(m.points.len()));
        match t {
            b"End" => break,
            b"MeshVersionFormatted" => {
                tk.int("a format version")?;
            }
            b"Dimension" => {
                let (d, l) = dimension(&mut tk)?;
                if seen_points && d != m.dimension {
                    return Err(IoError::syntax(
                        l,
                        format!("the dimension of the vertices read ({})", m.dimension),
                        d.to_string(),
                    ));
                }
                m.dimension = d;
            }
            b"Vertices" => {
                let (n, _) = tk.count("the number of vertices")?;
                let c = crate::surface::cap(n, input.len(), 4 * usize::from(m.dimension));
                m.points.reserve(c);
                m.point_refs.reserve(c);
                for _ in 0..n {
                    let mut p = [0.0; 3];
                    for x in &mut p[..usize::from(m.dimension)] {
                        *x = tk.f64("a coordinate")?;
                    }
                    m.points.push(p);
                    m.point_refs.push(reference(&mut tk)?);
                }
                seen_points = true;
            }
            b"Edges" => cells(&mut tk, at, &mut m.edges, &mut m.edge_refs, &mut idx)?,
            b"Triangles" => cells(
                &mut tk,
                at,
                &mut m.triangles,
                &mut m.triangle_refs,
                &mut idx,
            )?,
            b"Quadrilaterals" => cells(
                &mut tk,
                at,
                &mut m.quadrilaterals,
                &mut m.quadrilateral_refs,
                &mut idx,
            )?,
            b"Tetrahedra" => cells(
                &mut tk,
                at,
                &mut m.tetrahedra,
                &mut m.tetrahedron_refs,
                &mut idx,
            )?,
            b"Corners" | b"RequiredVertices" | b"Ridges" | b"RequiredEdges" => {
                let (n, _) = tk.count("the number of entries")?;
                let (list, bound, what) = match t {
                    b"Corners" => (&mut m.corners, m.points.len(), "a vertex index"),
                    b"RequiredVertices" => {
                        (&mut m.required_vertices, m.points.len(), "a vertex index")
                    }
                    b"Ridges" => (&mut m.ridges, m.edges.len(), "an edge index"),
                    _ => (&mut m.required_edges, m.edges.len(), "an edge index"),
                };
                list.reserve(crate::surface::cap(n, input.len(), 2));
                for _ in 0..n {
                    list.push(one_based(&mut tk, what, bound)?);
                }
            }
            _ if t[0].is_ascii_alphabetic() => skip_section(&mut tk),
            _ => return Err(IoError::syntax(line, "a Medit keyword", found(t))),
        }
    }
    let n = m.points.len();
    if let Some(&(l, i)) = idx.iter().find(|&&(_, i)| i < 1 || i as u64 > n as u64) {
        return Err(IoError::syntax(
            l,
            format!("a vertex index between 1 and {n}"),
            i.to_string(),
        ));
    }
    Ok(m)
}

/// Reads the `Vertices`, `Triangles` and `Quadrilaterals` of an ASCII
/// Medit `.mesh` file (see [`read_medit_mesh`]) as a surface: triangles
/// first, then quadrilaterals; references are dropped.
///
/// # Errors
/// Those of [`read_medit_mesh`], and [`IoError::Unsupported`] for a 2D
/// file.
///
/// ```
/// let text = b"MeshVersionFormatted 1\nDimension 3\nVertices\n3\n0 0 0 1\n1 0 0 1\n0 1 0 1\nTriangles\n1\n1 2 3 7\nEnd\n";
/// let s = delone_io::read_medit(text).unwrap();
/// assert_eq!(s.faces, vec![vec![0, 1, 2]]);
///
/// let bad = b"Dimension 3\nVertices\n1\n0 0 0 0\nTriangles\n1\n1 1 5 0\n";
/// let e = delone_io::read_medit(bad).unwrap_err();
/// assert_eq!(e.to_string(), "line 7: expected a vertex index between 1 and 1, found 5");
/// ```
pub fn read_medit(input: &[u8]) -> Result<Surface, IoError> {
    let m = read_medit_mesh(input)?;
    if m.dimension != 3 {
        return Err(IoError::Unsupported {
            line: 1,
            message: format!("dimension {} (only 3)", m.dimension),
        });
    }
    let faces = m
        .triangles
        .iter()
        .map(|t| t.to_vec())
        .chain(m.quadrilaterals.iter().map(|q| q.to_vec()))
        .collect();
    Ok(Surface {
        points: m.points,
        faces,
    })
}

/// Writes an ASCII Medit `.mesh` file (`MeshVersionFormatted 2`, double
/// precision): `Vertices` (reference 0), `Triangles` with `face_refs`,
/// `Tetrahedra` with `tet_refs` (an empty section is left out), `End`.
/// Indices are 0-based in the arrays, 1-based in the file.
///
/// # Errors
/// [`IoError::InvalidInput`] if a reference array does not match its
/// elements or an element names a missing point; [`IoError::Io`] if the
/// writer fails.
///
/// ```
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.5]];
/// let mut out = Vec::new();
/// delone_io::write_medit(&mut out, &pts, &[[0, 2, 1]], &[3], &[[0, 1, 2, 3]], &[7]).unwrap();
/// let text = String::from_utf8(out).unwrap();
/// assert_eq!(
///     text,
///     "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 0.5 0\n\
///      Triangles\n1\n1 3 2 3\nTetrahedra\n1\n1 2 3 4 7\nEnd\n"
/// );
/// // Our reader gets the surface part back.
/// let s = delone_io::read_medit(text.as_bytes()).unwrap();
/// assert_eq!((s.points.len(), s.faces.clone()), (4, vec![vec![0, 2, 1]]));
/// ```
pub fn write_medit<W: std::io::Write>(
    out: W,
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    face_refs: &[i32],
    tets: &[[u32; 4]],
    tet_refs: &[i32],
) -> Result<(), IoError> {
    check_cells("triangle", triangles, face_refs, points.len())?;
    check_cells("tetrahedron", tets, tet_refs, points.len())?;
    let mut o = crate::out::Out::new(out);
    o.str("MeshVersionFormatted 2\nDimension 3\nVertices\n");
    o.uint(points.len() as u64);
    o.nl()?;
    for p in points {
        for &c in p {
            o.float(c);
            o.byte(b' ');
        }
        o.byte(b'0');
        o.nl()?;
    }
    write_section(&mut o, "Triangles", triangles, face_refs)?;
    write_section(&mut o, "Tetrahedra", tets, tet_refs)?;
    o.str("End");
    o.nl()?;
    Ok(o.finish()?)
}

/// Lengths and indices of one element array of a writer.
pub(crate) fn check_cells<const K: usize>(
    what: &str,
    cells: &[[u32; K]],
    refs: &[i32],
    n_points: usize,
) -> Result<(), IoError> {
    if cells.len() != refs.len() {
        return Err(IoError::invalid(format!(
            "{} {what} references for {} elements",
            refs.len(),
            cells.len()
        )));
    }
    if let Some((i, &v)) = cells
        .iter()
        .enumerate()
        .find_map(|(i, c)| c.iter().find(|&&v| v as usize >= n_points).map(|v| (i, v)))
    {
        return Err(IoError::invalid(format!(
            "{what} {i} names point {v}, but there are {n_points} points"
        )));
    }
    Ok(())
}

fn write_section<W: std::io::Write, const K: usize>(
    o: &mut crate::out::Out<W>,
    name: &str,
    cells: &[[u32; K]],
    refs: &[i32],
) -> Result<(), IoError> {
    if cells.is_empty() {
        return Ok(());
    }
    o.str(name);
    o.nl()?;
    o.uint(cells.len() as u64);
    o.nl()?;
    for (c, &r) in cells.iter().zip(refs) {
        for &v in c {
            o.uint(u64::from(v) + 1);
            o.byte(b' ');
        }
        o.int(i64::from(r));
        o.nl()?;
    }
    Ok(())
}

fn write_list<W: std::io::Write>(
    o: &mut crate::out::Out<W>,
    name: &str,
    list: &[u32],
) -> Result<(), IoError> {
    if list.is_empty() {
        return Ok(());
    }
    o.str(name);
    o.nl()?;
    o.uint(list.len() as u64);
    o.nl()?;
    for &i in list {
        o.uint(u64::from(i) + 1);
        o.nl()?;
    }
    Ok(())
}

/// Writes a [`MeditMesh`] as an ASCII Medit `.mesh` file
/// (`MeshVersionFormatted 2`, its dimension; empty sections are left out).
///
/// # Errors
/// [`IoError::InvalidInput`] if the dimension is not 2 or 3, a reference
/// array does not match its elements, an element names a missing point, or
/// a corner, ridge or required entry is out of range; [`IoError::Io`] if the
/// writer fails.
///
/// ```
/// let m = delone_io::MeditMesh {
///     dimension: 2,
///     points: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
///     point_refs: vec![0; 3],
///     triangles: vec![[0, 1, 2]],
///     triangle_refs: vec![4],
///     ..Default::default()
/// };
/// let mut out = Vec::new();
/// delone_io::write_medit_mesh(&mut out, &m).unwrap();
/// assert_eq!(
///     String::from_utf8(out).unwrap(),
///     "MeshVersionFormatted 2\nDimension 2\nVertices\n3\n0 0 0\n1 0 0\n0 1 0\nTriangles\n1\n1 2 3 4\nEnd\n"
/// );
/// ```
pub fn write_medit_mesh<W: std::io::Write>(out: W, m: &MeditMesh) -> Result<(), IoError> {
    let d = usize::from(m.dimension);
    if d != 2 && d != 3 {
        return Err(IoError::invalid(format!("dimension {d} (only 2 or 3)")));
    }
    let n = m.points.len();
    if m.point_refs.len() != n {
        return Err(IoError::invalid(format!(
            "{} point references for {n} points",
            m.point_refs.len()
        )));
    }
    check_cells("edge", &m.edges, &m.edge_refs, n)?;
    check_cells("triangle", &m.triangles, &m.triangle_refs, n)?;
    check_cells("quadrilateral", &m.quadrilaterals, &m.quadrilateral_refs, n)?;
    check_cells("tetrahedron", &m.tetrahedra, &m.tetrahedron_refs, n)?;
    for (what, list, bound) in [
        ("corner", &m.corners, n),
        ("required vertex", &m.required_vertices, n),
        ("ridge", &m.ridges, m.edges.len()),
        ("required edge", &m.required_edges, m.edges.len()),
    ] {
        if let Some(&i) = list.iter().find(|&&i| i as usize >= bound) {
            return Err(IoError::invalid(format!(
                "{what} {i} is out of range (below {bound})"
            )));
        }
    }
    let mut o = crate::out::Out::new(out);
    o.str("MeshVersionFormatted 2\nDimension ");
    o.uint(d as u64);
    o.str("\nVertices\n");
    o.uint(n as u64);
    o.nl()?;
    for (p, &r) in m.points.iter().zip(&m.point_refs) {
        for &c in &p[..d] {
            o.float(c);
            o.byte(b' ');
        }
        o.int(i64::from(r));
        o.nl()?;
    }
    write_section(&mut o, "Edges", &m.edges, &m.edge_refs)?;
    write_section(&mut o, "Triangles", &m.triangles, &m.triangle_refs)?;
    write_section(
        &mut o,
        "Quadrilaterals",
        &m.quadrilaterals,
        &m.quadrilateral_refs,
    )?;
    write_section(&mut o, "Tetrahedra", &m.tetrahedra, &m.tetrahedron_refs)?;
    write_list(&mut o, "Corners", &m.corners)?;
    write_list(&mut o, "RequiredVertices", &m.required_vertices)?;
    write_list(&mut o, "Ridges", &m.ridges)?;
    write_list(&mut o, "RequiredEdges", &m.required_edges)?;
    o.str("End");
    o.nl()?;
    Ok(o.finish()?)
}

/// The kind of a field of a Medit `.sol` file, with Medit's type code.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SolKind {
    /// One value per vertex (type 1): a size, or a solution field.
    Scalar,
    /// `dimension` values per vertex (type 2).
    Vector,
    /// A symmetric tensor (type 3): `m11 m12 m22` in 2D,
    /// `m11 m12 m22 m13 m23 m33` in 3D (Medit's order), e.g. a metric.
    Tensor,
}

impl SolKind {
    /// Medit's type code (1, 2, 3).
    ///
    /// ```
    /// assert_eq!(delone_io::SolKind::Tensor.code(), 3);
    /// ```
    pub fn code(self) -> u32 {
        match self {
            SolKind::Scalar => 1,
            SolKind::Vector => 2,
            SolKind::Tensor => 3,
        }
    }

    /// Values per vertex in `dimension` (2 or 3).
    ///
    /// ```
    /// use delone_io::SolKind;
    /// assert_eq!([SolKind::Scalar.width(3), SolKind::Vector.width(3), SolKind::Tensor.width(2)], [1, 3, 3]);
    /// assert_eq!(SolKind::Tensor.width(3), 6);
    /// ```
    pub fn width(self, dimension: u8) -> usize {
        let d = usize::from(dimension);
        match self {
            SolKind::Scalar => 1,
            SolKind::Vector => d,
            SolKind::Tensor => d * (d + 1) / 2,
        }
    }
}

/// One field of a `.sol` file: `width` values per vertex, vertex after
/// vertex.
#[derive(Debug, Clone, PartialEq)]
pub struct SolField {
    /// What the values are.
    pub kind: SolKind,
    /// `kind.width(dimension)` values per vertex.
    pub values: Vec<f64>,
}

/// A Medit `.sol` file's fields at the vertices (`SolAtVertices`): sizes,
/// metrics or solution fields, as MMG reads and writes them.
///
/// ```
/// let text = b"MeshVersionFormatted 2\nDimension 2\nSolAtVertices\n2\n1 3\n1 0 4\n2 0.5 1\nEnd\n";
/// let s = delone_io::read_medit_sol(text).unwrap();
/// assert_eq!((s.dimension, s.vertices), (2, 2));
/// assert_eq!(s.fields[0].kind, delone_io::SolKind::Tensor);
/// assert_eq!(s.fields[0].values, vec![1.0, 0.0, 4.0, 2.0, 0.5, 1.0]);
/// let mut out = Vec::new();
/// delone_io::write_medit_sol(&mut out, &s).unwrap();
/// assert_eq!(delone_io::read_medit_sol(&out).unwrap(), s);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct MeditSol {
    /// 2 or 3.
    pub dimension: u8,
    /// Number of vertices.
    pub vertices: usize,
    /// The fields, in file order.
    pub fields: Vec<SolField>,
}

/// Reads an ASCII Medit `.sol` file: `Dimension`, then `SolAtVertices`
/// (the number of vertices, the number of fields and their type codes,
/// then every vertex's values, field after field). Sections at other
/// entities (`SolAtTriangles`, …) are skipped.
///
/// # Errors
/// [`IoError::Syntax`] with the line for a malformed value, no field or an
/// unknown type code; [`IoError::Unsupported`] for a dimension other than 2 or 3,
/// a binary `.solb` file, or a file with no `SolAtVertices`.
pub fn read_medit_sol(input: &[u8]) -> Result<MeditSol, IoError> {
    refuse_binary(input, "solb")?;
    let mut tk = Tokens::new(input, true);
    let mut dimension = 3u8;
    let mut sol: Option<MeditSol> = None;
    while let Some((t, line)) = tk.next_tok() {
        match t {
            b"End" => break,
            b"MeshVersionFormatted" => {
                tk.int("a format version")?;
            }
            b"Dimension" => dimension = self::dimension(&mut tk)?.0,
            b"SolAtVertices" => {
                let (n, _) = tk.count("the number of vertices")?;
                let (k, l) = tk.count("the number of fields")?;
                if k == 0 {
                    return Err(IoError::syntax(l, "a number of fields of at least 1", "0"));
                }
                let mut fields = Vec::with_capacity(k.min(16));
                for _ in 0..k {
                    let kind = match tk.int("a field type (1, 2 or 3)")? {
                        (1, _) => SolKind::Scalar,
                        (2, _) => SolKind::Vector,
                        (3, _) => SolKind::Tensor,
                        (c, l) => {
                            return Err(IoError::syntax(
                                l,
                                "a field type (1, 2 or 3)",
                                c.to_string(),
                            ))
                        }
                    };
                    let w = kind.width(dimension);
                    let values = Vec::with_capacity(crate::surface::cap(
                        n.saturating_mul(w),
                        input.len(),
                        2,
                    ));
                    fields.push(SolField { kind, values });
                }
                for _ in 0..n {
                    for f in &mut fields {
                        for _ in 0..f.kind.width(dimension) {
                            f.values.push(tk.f64("a value")?);
                        }
                    }
                }
                sol = Some(MeditSol {
                    dimension,
                    vertices: n,
                    fields,
                });
            }
            _ if t[0].is_ascii_alphabetic() => skip_section(&mut tk),
            _ => return Err(IoError::syntax(line, "a Medit keyword", found(t))),
        }
    }
    sol.ok_or_else(|| IoError::Unsupported {
        line: tk.line(),
        message: "no SolAtVertices section".into(),
    })
}

/// Writes a [`MeditSol`] as an ASCII Medit `.sol` file
/// (`MeshVersionFormatted 2`).
///
/// # Errors
/// [`IoError::InvalidInput`] if the dimension is not 2 or 3, there is no
/// field, or a field does not hold `width × vertices` values; [`IoError::Io`] if the writer fails.
pub fn write_medit_sol<W: std::io::Write>(out: W, s: &MeditSol) -> Result<(), IoError> {
    if s.dimension != 2 && s.dimension != 3 {
        return Err(IoError::invalid(format!(
            "dimension {} (only 2 or 3)",
            s.dimension
        )));
    }
    if s.fields.is_empty() {
        return Err(IoError::invalid("a solution without fields"));
    }
    for (i, f) in s.fields.iter().enumerate() {
        let want = f.kind.width(s.dimension).saturating_mul(s.vertices);
        if f.values.len() != want {
            return Err(IoError::invalid(format!(
                "field {i} holds {} values, {want} expected",
                f.values.len()
            )));
        }
    }
    let mut o = crate::out::Out::new(out);
    o.str("MeshVersionFormatted 2\nDimension ");
    o.uint(u64::from(s.dimension));
    o.str("\nSolAtVertices\n");
    o.uint(s.vertices as u64);
    o.nl()?;
    o.uint(s.fields.len() as u64);
    for f in &s.fields {
        o.byte(b' ');
        o.uint(u64::from(f.kind.code()));
    }
    o.nl()?;
    for v in 0..s.vertices {
        let mut first = true;
        for f in &s.fields {
            let w = f.kind.width(s.dimension);
            for &x in &f.values[v * w..(v + 1) * w] {
                if !first {
                    o.byte(b' ');
                }
                first = false;
                o.float(x);
            }
        }
        o.nl()?;
    }
    o.str("End");
    o.nl()?;
    Ok(o.finish()?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mesh_errors_name_the_line() {
        let cases: [(&[u8], &str); 7] = [
            (b"Dimension 4\n", "line 1: dimension 4 (only 2 or 3)"),
            (
                b"Vertices\n1\n0 0 1 0\nDimension 2\n",
                "line 4: expected the dimension of the vertices read (3), found 2",
            ),
            (
                b"Dimension 2\nTriangles\n1\n1 2 3 0\nVertices\n2\n0 0 0\n1 0 0\nEnd\n",
                "line 4: expected a vertex index between 1 and 2, found 3",
            ),
            (
                b"Dimension 2\nVertices\n1\n0 0 0\nEdges\n1\n1 2 0\n",
                "line 7: expected a vertex index between 1 and 1, found 2",
            ),
            (
                b"Dimension 2\nVertices\n1\n0 0 9999999999\n",
                "line 4: expected a reference that fits in 32 bits, found 9999999999",
            ),
            (
                b"Dimension 2\nVertices\n2\n0 0 0\n1 0 0\nEdges\n1\n1 2 0\nRidges\n1\n2\n",
                "line 11: expected an edge index between 1 and 1, found 2",
            ),
            (
                b"Dimension 3\nVertices\n1\n0 0\n",
                "line 4: expected a coordinate, found the end of the file",
            ),
        ];
        for (text, want) in cases {
            let e = read_medit_mesh(text).unwrap_err();
            assert_eq!(e.to_string(), want);
        }
        let two_d = b"Dimension 2\nVertices\n0\nEnd\n";
        assert!(read_medit_mesh(two_d).is_ok());
        assert_eq!(
            read_medit(two_d).unwrap_err().to_string(),
            "line 1: dimension 2 (only 3)"
        );
    }

    #[test]
    fn mesh_round_trip_in_3d_with_every_section() {
        let m = MeditMesh {
            dimension: 3,
            points: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.5],
            ],
            point_refs: vec![1, 2, 3, -4],
            edges: vec![[0, 1], [1, 2]],
            edge_refs: vec![10, 11],
            triangles: vec![[0, 2, 1]],
            triangle_refs: vec![5],
            quadrilaterals: vec![[0, 1, 2, 3]],
            quadrilateral_refs: vec![6],
            tetrahedra: vec![[0, 1, 2, 3]],
            tetrahedron_refs: vec![7],
            corners: vec![0, 3],
            required_vertices: vec![2],
            ridges: vec![1],
            required_edges: vec![0],
        };
        let mut out = Vec::new();
        write_medit_mesh(&mut out, &m).unwrap();
        assert_eq!(read_medit_mesh(&out).unwrap(), m);
        // Sections MMG writes that delone skips.
        let text = String::from_utf8(out)
            .unwrap()
            .replace("End", "Normals\n1\n0 0 1\nNormalAtVertices\n1\n1 1\nEnd");
        assert_eq!(read_medit_mesh(text.as_bytes()).unwrap(), m);
        let bad = MeditMesh {
            ridges: vec![2],
            ..m.clone()
        };
        let e = write_medit_mesh(&mut Vec::new(), &bad).unwrap_err();
        assert_eq!(e.to_string(), "ridge 2 is out of range (below 2)");
    }

    #[test]
    fn sol_errors_and_skipped_sections() {
        let cases: [(&[u8], &str); 4] = [
            (
                b"Dimension 2\nSolAtVertices\n1\n1 4\n1\n",
                "line 4: expected a field type (1, 2 or 3), found 4",
            ),
            (
                b"Dimension 2\nSolAtVertices\n2\n1 3\n1 0 1\n",
                "line 5: expected a value, found the end of the file",
            ),
            (
                b"Dimension 3\nSolAtTetrahedra\n1\n1 1\n0.5\nEnd\n",
                "line 6: no SolAtVertices section",
            ),
            (
                b"Dimension 3\nSolAtVertices\n5\n0\n",
                "line 4: expected a number of fields of at least 1, found 0",
            ),
        ];
        for (text, want) in cases {
            assert_eq!(read_medit_sol(text).unwrap_err().to_string(), want);
        }
        let text = b"MeshVersionFormatted 2\nDimension 3\nSolAtTriangles\n1\n1 1\n9\nSolAtVertices\n1\n2 2 1\n1 2 3 4\nEnd\n";
        let s = read_medit_sol(text).unwrap();
        assert_eq!(s.fields.len(), 2);
        assert_eq!(
            (s.fields[0].kind, s.fields[0].values.clone()),
            (SolKind::Vector, vec![1.0, 2.0, 3.0])
        );
        assert_eq!(s.fields[1].values, vec![4.0]);
        let short = MeditSol { vertices: 2, ..s };
        let e = write_medit_sol(&mut Vec::new(), &short).unwrap_err();
        assert_eq!(e.to_string(), "field 0 holds 3 values, 6 expected");
    }
}
