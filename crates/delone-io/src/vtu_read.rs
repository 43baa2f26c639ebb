//! Reader for VTK XML unstructured grids (`.vtu`) of triangles or
//! tetrahedra, into a [`MeditMesh`] and the grid's point-data arrays.

use crate::medit::MeditMesh;
use crate::read::show;
use crate::IoError;

/// A point-data array of a `.vtu` file: `components` values per point.
///
/// ```
/// let a = delone_io::VtuArray { name: "u".into(), components: 1, values: vec![0.5] };
/// assert_eq!(a.values.len(), a.components);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct VtuArray {
    /// The array's `Name`.
    pub name: String,
    /// `NumberOfComponents` (1 when absent).
    pub components: usize,
    /// The values, point after point.
    pub values: Vec<f64>,
}

/// Names of the cell-data array read as the cells' references, first found
/// first.
const REF_NAMES: [&str; 5] = ["ref", "medit:ref", "gmsh:physical", "region", "marker"];

/// Reads a VTK XML `UnstructuredGrid` (`.vtu`, one piece, little endian):
/// its vertex (VTK type 1), line (3), triangle (5) and tetrahedron (10)
/// cells as the corners, edges, triangles and tetrahedra of a
/// [`MeditMesh`], and its point-data arrays. Data arrays may be `ascii`,
/// inline `binary` (base64, as VTK and meshio write them) or `appended`
/// (raw, as [`crate::write_vtu`] writes them); not compressed. The cells'
/// references come from the first cell-data array named `ref`,
/// `medit:ref`, `gmsh:physical`, `region` or `marker` (0 without one). The
/// dimension is 3 when there are tetrahedra, else 2 (points in z = 0).
///
/// # Errors
/// [`IoError::Syntax`] naming the line of a malformed tag, number or
/// base64 text, or the array that is missing or of the wrong length;
/// [`IoError::Unsupported`] for compressed data, big-endian data, appended
/// base64 data or another cell type (naming the cell).
///
/// ```
/// let mut out = Vec::new();
/// let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
/// let u = [1.0, 2.0, 3.0];
/// let data = [delone_io::DataArray { name: "u", values: delone_io::Values::Float64(&u) }];
/// delone_io::write_vtu(&mut out, &pts, &[[0, 1, 2]], &data, &[], delone_io::VtuFormat::Binary).unwrap();
/// let (m, arrays) = delone_io::read_vtu(&out).unwrap();
/// assert_eq!((m.dimension, m.triangles.clone()), (2, vec![[0, 1, 2]]));
/// assert_eq!((arrays[0].name.as_str(), arrays[0].values.clone()), ("u", u.to_vec()));
/// ```
pub fn read_vtu(input: &[u8]) -> Result<(MeditMesh, Vec<VtuArray>), IoError> {
    let x = Xml::new(input);
    let file = x.tag("VTKFile", 0)?;
    let attr = |name: &str| x.attr(&file, name);
    if attr("compressor").is_some() {
        return Err(x.unsupported(
            file.at,
            "compressed data (write the .vtu without compression)",
        ));
    }
    if attr("byte_order").is_some_and(|b| b != "LittleEndian") {
        return Err(x.unsupported(file.at, "big-endian data"));
    }
    let wide = attr("header_type").is_some_and(|h| h == "UInt64");
    let appended = x.appended()?;
    let mut section = "";
    let mut point_data = Vec::new();
    let mut cell_data = Vec::new();
    let (mut points, mut conn, mut offsets, mut types) = (None, None, None, None);
    let mut pos = file.end;
    while let Some(t) = x.next_tag(pos)? {
        pos = t.end;
        match t.name {
            "PointData" | "CellData" | "Points" | "Cells" | "FieldData" => section = t.name,
            "/PointData" | "/CellData" | "/Points" | "/Cells" | "/FieldData" => section = "",
            "AppendedData" => break,
            "DataArray" => {
                let name = x.attr(&t, "Name").unwrap_or_default();
                let comps = match x.attr(&t, "NumberOfComponents") {
                    Some(c) => c
                        .parse()
                        .map_err(|_| x.syntax(t.at, "a number of components", &c))?,
                    None => 1,
                };
                let values = x.values(&t, wide, appended)?;
                if t.content {
                    pos = x.close(&t)?;
                }
                let a = VtuArray {
                    name: name.clone(),
                    components: comps,
                    values,
                };
                match (section, name.as_str()) {
                    ("PointData", _) => point_data.push(a),
                    ("CellData", _) => cell_data.push(a),
                    ("Points", _) => points = Some((a, t.at)),
                    ("Cells", "connectivity") => conn = Some(a),
                    ("Cells", "offsets") => offsets = Some(a),
                    ("Cells", "types") => types = Some(a),
                    _ => {}
                }
            }
            _ => {}
        }
    }
    let missing = |what: &str| x.syntax(file.at, &format!("a {what} array"), "none");
    let (points, at) = points.ok_or_else(|| missing("Points"))?;
    let conn = conn.ok_or_else(|| missing("connectivity"))?.values;
    let offsets = offsets.ok_or_else(|| missing("offsets"))?.values;
    let types = types.ok_or_else(|| missing("types"))?.values;
    if points.components != 3 || points.values.len() % 3 != 0 {
        return Err(x.syntax(at, "points of 3 components", &points.components.to_string()));
    }
    let n = points.values.len() / 3;
    let mut m = MeditMesh {
        points: points
            .values
            .chunks(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect(),
        point_refs: vec![0; n],
        ..Default::default()
    };
    if offsets.len() != types.len() {
        return Err(x.syntax(
            file.at,
            &format!("{} cell offsets", types.len()),
            &offsets.len().to_string(),
        ));
    }
    let refs = REF_NAMES.iter().find_map(|r| {
        cell_data
            .iter()
            .find(|a| a.name == *r && a.values.len() == types.len())
    });
    let mut start = 0usize;
    for (c, (&off, &ty)) in offsets.iter().zip(&types).enumerate() {
        let stop = off as usize;
        let ids = conn
            .get(start..stop)
            .filter(|_| off >= 0.0)
            .ok_or_else(|| {
                IoError::invalid(format!("cell {c}: offset {off} out of the connectivity"))
            })?;
        let mut v = [0u32; 4];
        for (k, &i) in ids.iter().take(4).enumerate() {
            if !(i >= 0.0 && (i as usize) < n) {
                return Err(IoError::invalid(format!("cell {c}: point {i} of {n}")));
            }
            v[k] = i as u32;
        }
        let r = refs.map_or(0, |a| a.values[c] as i32);
        match (ty as u8, ids.len()) {
            (1, 1) => m.corners.push(v[0]),
            (3, 2) => {
                m.edges.push([v[0], v[1]]);
                m.edge_refs.push(r);
            }
            (5, 3) => {
                m.triangles.push([v[0], v[1], v[2]]);
                m.triangle_refs.push(r);
            }
            (10, 4) => {
                m.tetrahedra.push(v);
                m.tetrahedron_refs.push(r);
            }
            _ => {
                return Err(IoError::invalid(format!(
                    "cell {c}: VTK type {ty} of {} points (vertices 1, lines 3, triangles 5 and tetrahedra 10 are read)",
                    ids.len()
                )))
            }
        }
        start = stop;
    }
    m.dimension = if m.tetrahedra.is_empty() { 2 } else { 3 };
    if m.dimension == 2 {
        if let Some(i) = m.points.iter().position(|p| p[2] != 0.0) {
            return Err(IoError::invalid(format!(
                "point {i} is off the plane z = 0 in a grid without tetrahedra (a surface mesh)"
            )));
        }
    }
    Ok((m, point_data))
}

/// A tag: its name (`/Name` for a closing tag), its attribute text, the
/// byte offsets of its `<` and after its `>`, and whether it has content
/// (not `/>`).
struct Tag<'a> {
    name: &'a str,
    attrs: &'a str,
    at: usize,
    end: usize,
    content: bool,
}

struct Xml<'a> {
    s: &'a [u8],
}

impl<'a> Xml<'a> {
    fn new(s: &'a [u8]) -> Self {
        Xml { s }
    }

    fn line(&self, at: usize) -> usize {
        1 + self.s[..at.min(self.s.len())]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
    }

    fn syntax(&self, at: usize, expected: &str, found: &str) -> IoError {
        IoError::syntax(self.line(at), expected, found)
    }

    fn unsupported(&self, at: usize, what: &str) -> IoError {
        IoError::Unsupported {
            line: self.line(at),
            message: what.to_string(),
        }
    }

    /// The next tag from `pos` (declarations and comments skipped).
    fn next_tag(&self, mut pos: usize) -> Result<Option<Tag<'a>>, IoError> {
        loop {
            let Some(lt) = self.s[pos.min(self.s.len())..]
                .iter()
                .position(|&b| b == b'<')
            else {
                return Ok(None);
            };
            let at = pos + lt;
            let Some(gt) = self.s[at..].iter().position(|&b| b == b'>') else {
                return Err(self.syntax(at, "a tag closed by >", "the end of the file"));
            };
            let body = &self.s[at + 1..at + gt];
            pos = at + gt + 1;
            if body.starts_with(b"?") || body.starts_with(b"!") {
                continue;
            }
            let body = std::str::from_utf8(body)
                .map_err(|_| self.syntax(at, "a tag in UTF-8", "other bytes"))?;
            let closed = !body.ends_with('/');
            let body = body.trim_end_matches('/');
            let (name, attrs) = body.split_once(char::is_whitespace).unwrap_or((body, ""));
            return Ok(Some(Tag {
                name,
                attrs,
                at,
                end: pos,
                content: closed,
            }));
        }
    }

    /// The first tag named `name` from `pos`.
    fn tag(&self, name: &str, mut pos: usize) -> Result<Tag<'a>, IoError> {
        while let Some(t) = self.next_tag(pos)? {
            if t.name == name {
                return Ok(t);
            }
            pos = t.end;
        }
        Err(self.syntax(pos, &format!("a <{name}> tag"), "none"))
    }

    fn attr(&self, t: &Tag, name: &str) -> Option<String> {
        let mut rest = t.attrs;
        while let Some(eq) = rest.find('=') {
            let key = rest[..eq].trim();
            let after = rest[eq + 1..].trim_start();
            let quote = after.chars().next()?;
            let close = after[1..].find(quote)?;
            if key == name {
                return Some(after[1..1 + close].to_string());
            }
            rest = &after[close + 2..];
        }
        None
    }

    /// The end of the content of `t` (after its `</DataArray>`).
    fn close(&self, t: &Tag) -> Result<usize, IoError> {
        let end = self.content_end(t)?;
        Ok(end + b"</DataArray>".len())
    }

    fn content_end(&self, t: &Tag) -> Result<usize, IoError> {
        let needle = b"</DataArray>";
        self.s[t.end..]
            .windows(needle.len())
            .position(|w| w == needle)
            .map(|p| t.end + p)
            .ok_or_else(|| self.syntax(t.at, "</DataArray>", "the end of the file"))
    }

    /// The raw appended data (after `_`), when there is an `<AppendedData>`.
    fn appended(&self) -> Result<Option<&'a [u8]>, IoError> {
        let needle = b"<AppendedData";
        let Some(p) = self.s.windows(needle.len()).position(|w| w == needle) else {
            return Ok(None);
        };
        let t = self.tag("AppendedData", p)?;
        if self.attr(&t, "encoding").is_some_and(|e| e != "raw") {
            return Err(self.unsupported(t.at, "appended data not raw (base64)"));
        }
        let u = self.s[t.end..]
            .iter()
            .position(|&b| b == b'_')
            .ok_or_else(|| self.syntax(t.at, "_ before the appended data", "none"))?;
        Ok(Some(&self.s[t.end + u + 1..]))
    }

    /// The values of a `DataArray`, as numbers.
    fn values(&self, t: &Tag, wide: bool, appended: Option<&[u8]>) -> Result<Vec<f64>, IoError> {
        let ty = self.attr(t, "type").unwrap_or_default();
        let size = match ty.as_str() {
            "Int8" | "UInt8" => 1,
            "Int16" | "UInt16" => 2,
            "Int32" | "UInt32" | "Float32" => 4,
            "Int64" | "UInt64" | "Float64" => 8,
            _ => return Err(self.syntax(t.at, "a VTK data type", &show(ty.as_bytes()))),
        };
        let format = self.attr(t, "format").unwrap_or_default();
        let header = if wide { 8 } else { 4 };
        let bytes: Vec<u8> = match format.as_str() {
            "ascii" => {
                let text = &self.s[t.end..self.content_end(t)?];
                let line = self.line(t.end);
                return text
                    .split(|b| b.is_ascii_whitespace())
                    .filter(|w| !w.is_empty())
                    .map(|w| crate::read::parse_f64(w, line, "a number of the DataArray"))
                    .collect();
            }
            "binary" => {
                let text = &self.s[t.end..self.content_end(t)?];
                let raw = base64(text)
                    .ok_or_else(|| self.syntax(t.end, "base64 data", "other characters"))?;
                let n = le(&raw, 0, header)
                    .ok_or_else(|| self.syntax(t.end, "a byte count", "too few bytes"))?;
                raw.get(header..header + n as usize)
                    .ok_or_else(|| self.syntax(t.end, &format!("{n} bytes"), "fewer"))?
                    .to_vec()
            }
            "appended" => {
                let data =
                    appended.ok_or_else(|| self.syntax(t.at, "an <AppendedData> block", "none"))?;
                let off: usize = self
                    .attr(t, "offset")
                    .and_then(|o| o.parse().ok())
                    .ok_or_else(|| self.syntax(t.at, "an offset", "none"))?;
                let n = le(data, off, header)
                    .ok_or_else(|| self.syntax(t.at, "appended data at the offset", "the end"))?;
                data.get(off + header..off + header + n as usize)
                    .ok_or_else(|| self.syntax(t.at, &format!("{n} appended bytes"), "fewer"))?
                    .to_vec()
            }
            f => {
                return Err(self.syntax(
                    t.at,
                    "format ascii, binary or appended",
                    &show(f.as_bytes()),
                ))
            }
        };
        Ok(bytes
            .chunks_exact(size)
            .map(|c| {
                let mut b = [0u8; 8];
                b[..size].copy_from_slice(c);
                match ty.as_str() {
                    "Int8" => f64::from(c[0] as i8),
                    "UInt8" => f64::from(c[0]),
                    "Int16" => f64::from(i16::from_le_bytes([c[0], c[1]])),
                    "UInt16" => f64::from(u16::from_le_bytes([c[0], c[1]])),
                    "Int32" => f64::from(i32::from_le_bytes([c[0], c[1], c[2], c[3]])),
                    "UInt32" => f64::from(u32::from_le_bytes([c[0], c[1], c[2], c[3]])),
                    "Float32" => f64::from(f32::from_le_bytes([c[0], c[1], c[2], c[3]])),
                    "Int64" => i64::from_le_bytes(b) as f64,
                    "UInt64" => u64::from_le_bytes(b) as f64,
                    _ => f64::from_le_bytes(b),
                }
            })
            .collect())
    }
}

/// The little-endian unsigned integer of `width` bytes at `at`.
fn le(s: &[u8], at: usize, width: usize) -> Option<u64> {
    let b = s.get(at..at + width)?;
    Some(b.iter().rev().fold(0u64, |acc, &x| acc << 8 | u64::from(x)))
}

/// Decodes base64 text (whitespace skipped), also several encodings one
/// after the other (VTK encodes the byte count and the data apart).
fn base64(text: &[u8]) -> Option<Vec<u8>> {
    let digit = |c: u8| match c {
        b'A'..=b'Z' => Some(c - b'A'),
        b'a'..=b'z' => Some(c - b'a' + 26),
        b'0'..=b'9' => Some(c - b'0' + 52),
        b'+' => Some(62),
        b'/' => Some(63),
        _ => None,
    };
    let chars: Vec<u8> = text
        .iter()
        .copied()
        .filter(|c| !c.is_ascii_whitespace())
        .collect();
    if !chars.len().is_multiple_of(4) {
        return None;
    }
    let mut out = Vec::with_capacity(chars.len() / 4 * 3);
    for g in chars.chunks(4) {
        let pad = g.iter().rev().take_while(|&&c| c == b'=').count();
        if pad > 2 {
            return None;
        }
        let mut acc = 0u32;
        for &c in &g[..4 - pad] {
            acc = acc << 6 | u32::from(digit(c)?);
        }
        acc <<= 6 * pad as u32;
        let b = acc.to_be_bytes();
        out.extend_from_slice(&b[1..4 - pad]);
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_decodes_concatenated_encodings() {
        // "Ma" + "n": two encodings with padding between.
        assert_eq!(base64(b"TWE=bg==").unwrap(), b"Man".to_vec());
        assert_eq!(base64(b"TWFu\n").unwrap(), b"Man".to_vec());
        assert!(base64(b"TWF").is_none());
        assert!(base64(b"T*Fu").is_none());
    }
}

#[cfg(test)]
mod read_tests {
    use super::*;

    #[test]
    fn reads_ascii_with_references_and_names_bad_items() {
        let vtu = |cells: &str, types: &str| {
            format!(
                "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" byte_order=\"LittleEndian\">\n<UnstructuredGrid><Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">\n\
                 <PointData><DataArray type=\"Float32\" Name=\"h\" format=\"ascii\">0.5 0.5 0.25 1</DataArray></PointData>\n\
                 <CellData><DataArray type=\"Int32\" Name=\"gmsh:physical\" format=\"ascii\">9</DataArray></CellData>\n\
                 <Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">0 0 0 1 0 0 0 1 0 0 0 1</DataArray></Points>\n\
                 <Cells><DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">{cells}</DataArray>\n\
                 <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">4</DataArray>\n\
                 <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">{types}</DataArray></Cells>\n</Piece></UnstructuredGrid></VTKFile>\n"
            )
        };
        let (m, a) = read_vtu(vtu("0 1 2 3", "10").as_bytes()).unwrap();
        assert_eq!(
            (
                m.dimension,
                m.tetrahedra.clone(),
                m.tetrahedron_refs.clone()
            ),
            (3, vec![[0, 1, 2, 3]], vec![9])
        );
        assert_eq!(
            (a[0].name.as_str(), a[0].values.clone()),
            ("h", vec![0.5, 0.5, 0.25, 1.0])
        );
        let e = read_vtu(vtu("0 1 2 3", "12").as_bytes()).unwrap_err();
        assert!(e.to_string().contains("cell 0: VTK type 12"), "{e}");
        let e = read_vtu(vtu("0 1 2 x", "10").as_bytes()).unwrap_err();
        assert_eq!(e.line(), Some(7), "{e}");
        let e = read_vtu(vtu("0 1 2 7", "10").as_bytes()).unwrap_err();
        assert!(e.to_string().contains("cell 0: point 7 of 4"), "{e}");
    }
}
