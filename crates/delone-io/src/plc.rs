//! Readers for TetGen's 3D `.poly` and `.smesh` files (piecewise linear
//! complexes).

use crate::read::{check_index, parse_count, parse_f64, parse_int, Records};
use crate::IoError;

/// One facet of a [`PlcFile`]: a planar polygon with optional holes, as
/// TetGen describes it.
///
/// ```
/// let f = delone_io::PlcFacet { polygons: vec![vec![0, 1, 2]], holes: vec![], marker: 0, line: 1 };
/// assert_eq!(f.polygons[0].len(), 3);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct PlcFacet {
    /// Polygons of the facet (0-based point indices): the outer boundary and
    /// holes' boundaries, or any segments/points the facet must contain.
    pub polygons: Vec<Vec<u32>>,
    /// One point inside each hole of the facet.
    pub holes: Vec<[f64; 3]>,
    /// Boundary marker (0 when the file has none).
    pub marker: i32,
    /// 1-based line of the facet record (for messages).
    pub line: usize,
}

/// A region of a [`PlcFile`]: a point inside it, its attribute and an
/// optional maximum tetrahedron volume.
///
/// ```
/// let r = delone_io::PlcRegion { point: [0.5; 3], attribute: 1.0, max_volume: Some(0.1) };
/// assert_eq!(r.max_volume, Some(0.1));
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct PlcRegion {
    /// A point inside the region.
    pub point: [f64; 3],
    /// Regional attribute.
    pub attribute: f64,
    /// Maximum tetrahedron volume in the region, if given (TetGen treats a
    /// negative value as "no constraint"; it is kept as read).
    pub max_volume: Option<f64>,
}

/// The content of a TetGen `.poly` or `.smesh` file.
///
/// ```
/// let f = delone_io::read_smesh(b"3 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n1 0\n3 0 1 2\n0\n0\n").unwrap();
/// assert_eq!((f.points.len(), f.facets.len(), f.first_index), (3, 1, 0));
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PlcFile {
    /// Point coordinates.
    pub points: Vec<[f64; 3]>,
    /// Boundary markers of the points, if the node header announces them.
    pub point_markers: Option<Vec<i32>>,
    /// Index of the first point in the file (0 or 1); facet indices are
    /// converted to 0-based.
    pub first_index: u32,
    /// The facets.
    pub facets: Vec<PlcFacet>,
    /// Volume holes: one point inside each.
    pub holes: Vec<[f64; 3]>,
    /// Regions (attributes and volume constraints).
    pub regions: Vec<PlcRegion>,
}

/// Reads a TetGen `.poly` file (3D).
///
/// Sections: nodes (`<#points> 3 <#attributes> <#markers>`, then
/// `<i> x y z …`), facets (`<#facets> <#markers>`, each facet
/// `<#polygons> [<#holes>] [<marker>]` followed by its polygons
/// `<#corners> i1 … in` and hole points `<j> x y z`), volume holes
/// (`<#holes>`, `<j> x y z`) and regions (`<#regions>`,
/// `<j> x y z <attribute> [<max volume>]`). The hole and region sections may
/// be missing at the end of the file. A node count of 0 (points in a separate
/// `.node` file) is not supported.
///
/// # Errors
/// [`IoError::Syntax`] with the line for a malformed record or a point index
/// out of range; [`IoError::UnexpectedEnd`] when a section is shorter than
/// its header; [`IoError::Unsupported`] for a dimension other than 3 or a
/// node count of 0.
///
/// ```
/// let text = b"4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n4 1\n1 0 1\n3 1 2 3\n1\n3 1 2 4\n1 0 2\n3 1 3 4\n1 0\n3 2 3 4\n0\n1\n1 0.1 0.1 0.1 5 0.01\n";
/// let f = delone_io::read_poly3d(text).unwrap();
/// assert_eq!(f.facets[0].polygons, vec![vec![0, 1, 2]]);
/// assert_eq!(f.facets[2].marker, 2);
/// assert_eq!(f.regions[0].max_volume, Some(0.01));
///
/// let e = delone_io::read_poly3d(b"3 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n1 0\n1\n3 1 2 9\n").unwrap_err();
/// assert_eq!(e.to_string(), "line 7: expected a point index between 1 and 3, found 9");
/// ```
pub fn read_poly3d(input: &[u8]) -> Result<PlcFile, IoError> {
    read(input, false)
}

/// Reads a TetGen `.smesh` file: like [`read_poly3d`] but each facet is a
/// single polygon on one line, `<#corners> i1 … in [<marker>]`, and facets
/// have no holes.
///
/// # Errors
/// As [`read_poly3d`].
///
/// ```
/// let text = b"# tet\n4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n4 1\n3 0 2 1 5\n3 0 1 3 5\n3 1 2 3 5\n3 0 3 2 5\n0\n0\n";
/// let f = delone_io::read_smesh(text).unwrap();
/// assert_eq!(f.facets.len(), 4);
/// assert!(f.facets.iter().all(|f| f.marker == 5));
/// ```
pub fn read_smesh(input: &[u8]) -> Result<PlcFile, IoError> {
    read(input, true)
}

fn read(input: &[u8], smesh: bool) -> Result<PlcFile, IoError> {
    let mut rec = Records::new(input);
    let mut toks = Vec::with_capacity(16);
    let Some(hline) = rec.next(&mut toks) else {
        return Err(IoError::syntax(1, "a node header line", "an empty file"));
    };
    let n = parse_count(toks[0], hline, "the number of points")?;
    let dim = match toks.get(1) {
        Some(t) => parse_count(t, hline, "the dimension (3)")?,
        None => 3,
    };
    if dim != 3 {
        return Err(IoError::Unsupported {
            line: hline,
            message: format!("dimension {dim} (only 3)"),
        });
    }
    if n == 0 {
        return Err(IoError::Unsupported {
            line: hline,
            message: "points in a separate .node file are not supported".into(),
        });
    }
    let nattr = match toks.get(2) {
        Some(t) => parse_count(t, hline, "the number of attributes")?,
        None => 0,
    };
    let nmark = match toks.get(3) {
        Some(t) => parse_count(t, hline, "the number of boundary markers (0 or 1)")?,
        None => 0,
    };
    let mut points = Vec::with_capacity(crate::surface::cap(n, input.len(), 8));
    let mut markers = (nmark > 0).then(Vec::new);
    let mut first = None;
    for k in 0..n {
        let Some(line) = rec.next(&mut toks) else {
            return Err(IoError::UnexpectedEnd {
                line: hline,
                what: "points",
                declared: n,
                found: k,
            });
        };
        check_index(toks[0], line, k, &mut first, "point")?;
        if toks.len() < 4 {
            return Err(IoError::syntax(
                line,
                "3 coordinates",
                (toks.len() - 1).to_string(),
            ));
        }
        points.push([
            parse_f64(toks[1], line, "a coordinate")?,
            parse_f64(toks[2], line, "a coordinate")?,
            parse_f64(toks[3], line, "a coordinate")?,
        ]);
        if let Some(m) = markers.as_mut() {
            m.push(match toks.get(nattr.saturating_add(4)) {
                Some(t) => marker(t, line)?,
                None => 0,
            });
        }
    }
    let first = first.unwrap_or(1);
    let idx = |t: &[u8], line: usize| -> Result<u32, IoError> {
        let i = parse_int(t, line, "a point index")?;
        let z = i - first as i64;
        if z < 0 || z >= n as i64 {
            return Err(IoError::syntax(
                line,
                format!(
                    "a point index between {first} and {}",
                    n as i64 - 1 + first as i64
                ),
                i.to_string(),
            ));
        }
        Ok(z as u32)
    };
    let Some(fline) = rec.next(&mut toks) else {
        return Err(IoError::syntax(
            rec_line(input),
            "the facet header",
            "the end of the file",
        ));
    };
    let nf = parse_count(toks[0], fline, "the number of facets")?;
    let fmark = match toks.get(1) {
        Some(t) => parse_count(t, fline, "the number of boundary markers (0 or 1)")?,
        None => 0,
    };
    let mut facets = Vec::with_capacity(crate::surface::cap(nf, input.len(), 6));
    for k in 0..nf {
        let Some(line) = rec.next(&mut toks) else {
            return Err(IoError::UnexpectedEnd {
                line: fline,
                what: "facets",
                declared: nf,
                found: k,
            });
        };
        if smesh {
            let c = parse_count(toks[0], line, "the number of corners")?;
            if toks.len() <= c {
                return Err(IoError::syntax(
                    line,
                    format!("{c} point indices"),
                    (toks.len() - 1).to_string(),
                ));
            }
            let poly = toks[1..=c]
                .iter()
                .map(|t| idx(t, line))
                .collect::<Result<Vec<_>, _>>()?;
            let marker = match (fmark, toks.get(c + 1)) {
                (1.., Some(t)) => marker(t, line)?,
                _ => 0,
            };
            facets.push(PlcFacet {
                polygons: vec![poly],
                holes: Vec::new(),
                marker,
                line,
            });
            continue;
        }
        let np = parse_count(toks[0], line, "the number of polygons")?;
        let nh = match toks.get(1) {
            Some(t) => parse_count(t, line, "the number of facet holes")?,
            None => 0,
        };
        let marker = match (fmark, toks.get(2)) {
            (1.., Some(t)) => marker(t, line)?,
            _ => 0,
        };
        let mut polygons = Vec::with_capacity(np.min(64));
        for j in 0..np {
            let Some(pl) = rec.next(&mut toks) else {
                return Err(IoError::UnexpectedEnd {
                    line,
                    what: "polygons",
                    declared: np,
                    found: j,
                });
            };
            let c = parse_count(toks[0], pl, "the number of corners")?;
            if toks.len() <= c {
                return Err(IoError::syntax(
                    pl,
                    format!("{c} point indices"),
                    (toks.len() - 1).to_string(),
                ));
            }
            polygons.push(
                toks[1..=c]
                    .iter()
                    .map(|t| idx(t, pl))
                    .collect::<Result<Vec<_>, _>>()?,
            );
        }
        let mut holes = Vec::with_capacity(nh.min(64));
        for j in 0..nh {
            let Some(hl) = rec.next(&mut toks) else {
                return Err(IoError::UnexpectedEnd {
                    line,
                    what: "facet holes",
                    declared: nh,
                    found: j,
                });
            };
            holes.push(xyz(&toks, hl)?);
        }
        facets.push(PlcFacet {
            polygons,
            holes,
            marker,
            line,
        });
    }
    let mut holes = Vec::new();
    let mut regions = Vec::new();
    if let Some(hl) = rec.next(&mut toks) {
        let nh = parse_count(toks[0], hl, "the number of holes")?;
        for j in 0..nh {
            let Some(l) = rec.next(&mut toks) else {
                return Err(IoError::UnexpectedEnd {
                    line: hl,
                    what: "holes",
                    declared: nh,
                    found: j,
                });
            };
            holes.push(xyz(&toks, l)?);
        }
        if let Some(rl) = rec.next(&mut toks) {
            let nr = parse_count(toks[0], rl, "the number of regions")?;
            for j in 0..nr {
                let Some(l) = rec.next(&mut toks) else {
                    return Err(IoError::UnexpectedEnd {
                        line: rl,
                        what: "regions",
                        declared: nr,
                        found: j,
                    });
                };
                let point = xyz(&toks, l)?;
                let attribute = match toks.get(4) {
                    Some(t) => parse_f64(t, l, "a region attribute")?,
                    None => 0.0,
                };
                let max_volume = match toks.get(5) {
                    Some(t) => Some(parse_f64(t, l, "a maximum volume")?),
                    None => None,
                };
                regions.push(PlcRegion {
                    point,
                    attribute,
                    max_volume,
                });
            }
        }
    }
    Ok(PlcFile {
        points,
        point_markers: markers,
        first_index: first,
        facets,
        holes,
        regions,
    })
}

fn rec_line(input: &[u8]) -> usize {
    input.iter().filter(|&&b| b == b'\n').count() + 1
}

fn marker(t: &[u8], line: usize) -> Result<i32, IoError> {
    let v = parse_int(t, line, "a boundary marker (integer)")?;
    i32::try_from(v)
        .map_err(|_| IoError::syntax(line, "a boundary marker in the i32 range", v.to_string()))
}

/// `<index> x y z` (the index is not checked).
fn xyz(toks: &[&[u8]], line: usize) -> Result<[f64; 3], IoError> {
    if toks.len() < 4 {
        return Err(IoError::syntax(
            line,
            "an index and 3 coordinates",
            format!("{} fields", toks.len()),
        ));
    }
    Ok([
        parse_f64(toks[1], line, "a coordinate")?,
        parse_f64(toks[2], line, "a coordinate")?,
        parse_f64(toks[3], line, "a coordinate")?,
    ])
}
