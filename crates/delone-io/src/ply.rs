//! Reader for PLY (Stanford polygon format): ASCII, binary little and big
//! endian.

use crate::surface::{found, index, Surface, Tokens};
use crate::IoError;

#[derive(Clone, Copy, PartialEq, Debug)]
enum Ty {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Ty {
    fn parse(t: &[u8]) -> Option<Ty> {
        Some(match t {
            b"char" | b"int8" => Ty::I8,
            b"uchar" | b"uint8" => Ty::U8,
            b"short" | b"int16" => Ty::I16,
            b"ushort" | b"uint16" => Ty::U16,
            b"int" | b"int32" => Ty::I32,
            b"uint" | b"uint32" => Ty::U32,
            b"float" | b"float32" => Ty::F32,
            b"double" | b"float64" => Ty::F64,
            _ => return None,
        })
    }
    fn size(self) -> usize {
        match self {
            Ty::I8 | Ty::U8 => 1,
            Ty::I16 | Ty::U16 => 2,
            Ty::I32 | Ty::U32 | Ty::F32 => 4,
            Ty::F64 => 8,
        }
    }
}

#[derive(Debug)]
struct Prop {
    name: Vec<u8>,
    /// `Some(count type)` for a list property.
    list: Option<Ty>,
    ty: Ty,
}

#[derive(Debug)]
struct Element {
    name: Vec<u8>,
    count: usize,
    line: usize,
    props: Vec<Prop>,
}

#[derive(Clone, Copy, PartialEq)]
enum Format {
    Ascii,
    Little,
    Big,
}

/// Reads a PLY file (`format ascii 1.0`, `binary_little_endian 1.0` or
/// `binary_big_endian 1.0`).
///
/// Reads the `x`, `y`, `z` properties of the `vertex` element and the
/// `vertex_indices` (or `vertex_index`) list of the `face` element; every
/// other property and element is skipped. Reading stops once both elements
/// are read, so trailing elements (texture data, …) are never parsed.
///
/// # Errors
/// Header and ASCII body: [`IoError::Syntax`] with the line. Binary body:
/// [`IoError::Binary`] with the byte offset. [`IoError::Unsupported`] for
/// an unknown format or property type.
///
/// ```
/// let text = b"ply\nformat ascii 1.0\ncomment hi\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 255\n1 0 0 0\n0 1 0 7\n3 0 1 2\n";
/// let s = delone_io::read_ply(text).unwrap();
/// assert_eq!(s.points[1], [1.0, 0.0, 0.0]);
/// assert_eq!(s.faces, vec![vec![0, 1, 2]]);
/// ```
pub fn read_ply(input: &[u8]) -> Result<Surface, IoError> {
    // Header: line by line up to `end_header`.
    let mut pos = 0;
    let mut line = 0;
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        if pos >= input.len() {
            return Err(IoError::syntax(
                line.max(1),
                "\"end_header\"",
                "the end of the file",
            ));
        }
        line += 1;
        let end = input[pos..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(input.len(), |p| pos + p);
        let text = &input[pos..end];
        pos = (end + 1).min(input.len());
        let toks: Vec<&[u8]> = text
            .split(|b| b.is_ascii_whitespace())
            .filter(|t| !t.is_empty())
            .collect();
        if line == 1 {
            if toks.first() != Some(&&b"ply"[..]) {
                return Err(IoError::syntax(
                    1,
                    "\"ply\"",
                    toks.first().map_or("nothing".into(), |t| found(t)),
                ));
            }
            continue;
        }
        let Some(&kw) = toks.first() else { continue };
        match kw {
            b"format" => {
                format = Some(match toks.get(1).copied() {
                    Some(b"ascii") => Format::Ascii,
                    Some(b"binary_little_endian") => Format::Little,
                    Some(b"binary_big_endian") => Format::Big,
                    other => {
                        return Err(IoError::Unsupported {
                            line,
                            message: format!("PLY format {}", other.map_or("(none)".into(), found)),
                        })
                    }
                });
            }
            b"comment" | b"obj_info" => {}
            b"element" => {
                if toks.len() < 3 {
                    return Err(IoError::syntax(
                        line,
                        "\"element <name> <count>\"",
                        toks.len().to_string() + " fields",
                    ));
                }
                let count = crate::read::parse_count(toks[2], line, "an element count")?;
                elements.push(Element {
                    name: toks[1].to_vec(),
                    count,
                    line,
                    props: Vec::new(),
                });
            }
            b"property" => {
                let Some(el) = elements.last_mut() else {
                    return Err(IoError::syntax(
                        line,
                        "\"element\" before \"property\"",
                        "property",
                    ));
                };
                let bad = |t: Option<&&[u8]>| IoError::Unsupported {
                    line,
                    message: format!(
                        "PLY property type {}",
                        t.map_or("(none)".into(), |t| found(t))
                    ),
                };
                if toks.get(1).copied() == Some(b"list") {
                    let ct = toks
                        .get(2)
                        .and_then(|t| Ty::parse(t))
                        .ok_or_else(|| bad(toks.get(2)))?;
                    let it = toks
                        .get(3)
                        .and_then(|t| Ty::parse(t))
                        .ok_or_else(|| bad(toks.get(3)))?;
                    if matches!(ct, Ty::F32 | Ty::F64) {
                        return Err(bad(toks.get(2)));
                    }
                    let name = toks.get(4).map_or(Vec::new(), |t| t.to_vec());
                    el.props.push(Prop {
                        name,
                        list: Some(ct),
                        ty: it,
                    });
                } else {
                    let ty = toks
                        .get(1)
                        .and_then(|t| Ty::parse(t))
                        .ok_or_else(|| bad(toks.get(1)))?;
                    let name = toks.get(2).map_or(Vec::new(), |t| t.to_vec());
                    el.props.push(Prop {
                        name,
                        list: None,
                        ty,
                    });
                }
            }
            b"end_header" => break,
            other => {
                return Err(IoError::syntax(
                    line,
                    "a PLY header keyword (format, comment, element, property, end_header)",
                    found(other),
                ))
            }
        }
    }
    let Some(format) = format else {
        return Err(IoError::syntax(
            line,
            "a \"format\" line in the header",
            "none",
        ));
    };
    let Some(vi) = elements.iter().position(|e| e.name == b"vertex") else {
        return Err(IoError::syntax(
            line,
            "a \"vertex\" element in the header",
            "none",
        ));
    };
    let pidx = |n: &[u8]| {
        elements[vi]
            .props
            .iter()
            .position(|p| p.name == n && p.list.is_none())
    };
    let (Some(px), Some(py), Some(pz)) = (pidx(b"x"), pidx(b"y"), pidx(b"z")) else {
        return Err(IoError::syntax(
            elements[vi].line,
            "vertex properties x, y and z",
            "some missing",
        ));
    };
    let fi = elements.iter().position(|e| e.name == b"face");
    let fprop = match fi {
        Some(fi) => Some(
            elements[fi]
                .props
                .iter()
                .position(|p| {
                    p.list.is_some() && (p.name == b"vertex_indices" || p.name == b"vertex_index")
                })
                .ok_or_else(|| {
                    IoError::syntax(
                        elements[fi].line,
                        "a face list property vertex_indices",
                        "none",
                    )
                })?,
        ),
        None => None,
    };
    let last = fi.map_or(vi, |f| f.max(vi));
    let mut body = Body {
        input,
        pos,
        format,
        toks: Tokens::new(&input[pos..], false),
        line_base: line,
    };
    let nv = elements[vi].count;
    let mut points = Vec::with_capacity(crate::surface::cap(nv, input.len(), 6));
    let mut faces = Vec::new();
    let mut list = Vec::new();
    for (ei, el) in elements.iter().enumerate().take(last + 1) {
        let is_v = ei == vi;
        let is_f = Some(ei) == fi;
        if is_f {
            faces.reserve(crate::surface::cap(el.count, input.len(), 4));
        }
        if el.props.is_empty() {
            // Its items take no bytes: nothing to read, however many the
            // header declares (a loop over 4e9 of them would hang).
            continue;
        }
        for k in 0..el.count {
            let mut p = [0.0; 3];
            for (pi, prop) in el.props.iter().enumerate() {
                match prop.list {
                    None => {
                        let v = body.scalar(prop.ty, &el.name, k)?;
                        if is_v {
                            if pi == px {
                                p[0] = v;
                            } else if pi == py {
                                p[1] = v;
                            } else if pi == pz {
                                p[2] = v;
                            }
                        }
                    }
                    Some(ct) => {
                        let n = body.scalar(ct, &el.name, k)?;
                        if !(n >= 0.0 && n.fract() == 0.0 && n <= u32::MAX as f64) {
                            return Err(body.err("a list length", &n.to_string()));
                        }
                        let want = is_f && Some(pi) == fprop;
                        list.clear();
                        for _ in 0..n as usize {
                            let v = body.scalar(prop.ty, &el.name, k)?;
                            if want {
                                if v.fract() != 0.0 || !v.is_finite() {
                                    return Err(body.err("an integer point index", &v.to_string()));
                                }
                                let l = body.line();
                                list.push(index(v as i64, nv, l).map_err(|e| body.fix(e))?);
                            }
                        }
                        if want {
                            faces.push(list.clone());
                        }
                    }
                }
            }
            if is_v {
                points.push(p);
            }
        }
    }
    Ok(Surface { points, faces })
}

struct Body<'a> {
    input: &'a [u8],
    pos: usize,
    format: Format,
    toks: Tokens<'a>,
    line_base: usize,
}

impl Body<'_> {
    fn line(&self) -> usize {
        self.line_base + self.toks.line()
    }

    fn err(&self, expected: &str, found: &str) -> IoError {
        match self.format {
            Format::Ascii => IoError::syntax(self.line(), expected.to_string(), found.to_string()),
            _ => IoError::Binary {
                offset: self.pos,
                expected: expected.into(),
                found: found.into(),
            },
        }
    }

    /// Binary errors cannot carry a line: convert a syntax error to an offset.
    fn fix(&self, e: IoError) -> IoError {
        match (self.format, e) {
            (Format::Ascii, e) => e,
            (
                _,
                IoError::Syntax {
                    expected, found, ..
                },
            ) => IoError::Binary {
                offset: self.pos,
                expected,
                found,
            },
            (_, e) => e,
        }
    }

    fn scalar(&mut self, ty: Ty, el: &[u8], k: usize) -> Result<f64, IoError> {
        if self.format == Format::Ascii {
            let l = self.line();
            let Some((t, _)) = self.toks.next_tok() else {
                return Err(IoError::syntax(
                    l,
                    format!("more values for {} {k}", String::from_utf8_lossy(el)),
                    "the end of the file",
                ));
            };
            // A `float` property holds a single-precision value: round the
            // text once, to f32, as a PLY writer/reader pair does.
            if ty == Ty::F32 {
                return std::str::from_utf8(t)
                    .ok()
                    .and_then(|s| s.parse::<f32>().ok())
                    .map(f64::from)
                    .ok_or_else(|| IoError::syntax(l, "a number", found(t)));
            }
            return crate::read::parse_f64(t, l, "a number");
        }
        let n = ty.size();
        let Some(b) = self.input.get(self.pos..self.pos + n) else {
            return Err(IoError::Binary {
                offset: self.input.len(),
                expected: format!("{n} more bytes for {} {k}", String::from_utf8_lossy(el)),
                found: "the end of the file".into(),
            });
        };
        self.pos += n;
        let mut a = [0u8; 8];
        a[..n].copy_from_slice(b);
        if self.format == Format::Big {
            a[..n].reverse();
        }
        Ok(match ty {
            Ty::I8 => a[0] as i8 as f64,
            Ty::U8 => a[0] as f64,
            Ty::I16 => i16::from_le_bytes([a[0], a[1]]) as f64,
            Ty::U16 => u16::from_le_bytes([a[0], a[1]]) as f64,
            Ty::I32 => i32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
            Ty::U32 => u32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
            Ty::F32 => f32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
            Ty::F64 => f64::from_le_bytes(a),
        })
    }
}
