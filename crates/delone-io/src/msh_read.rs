//! Reader for Gmsh `.msh` 4.1 (ASCII) meshes of triangles or tetrahedra,
//! into a [`MeditMesh`]: the references are the entities' physical tags.

use std::collections::HashMap;

use crate::medit::MeditMesh;
use crate::read::show;
use crate::surface::Tokens;
use crate::IoError;

/// Reads a Gmsh `.msh` 4.1 ASCII mesh: its nodes, and its point (type 15),
/// line (1), triangle (2) and tetrahedron (4) elements as the corners,
/// edges, triangles and tetrahedra of a [`MeditMesh`]. The reference of an
/// element is the first physical tag of its entity (`$Entities`), 0 for an
/// entity without one; without an `$Entities` section, the entity tag
/// itself. The dimension is 3 when there are tetrahedra, else 2 (the points
/// must then lie in the plane z = 0). Other sections are skipped.
///
/// # Errors
/// [`IoError::Syntax`] naming the line of a malformed number, a node tag
/// that is not defined, or a missing section end; [`IoError::Unsupported`]
/// for a binary file, another version than 4.x, or an element type other
/// than those above (naming the line); [`IoError::InvalidInput`] for
/// triangles off the plane z = 0 without tetrahedra.
///
/// ```
/// let msh = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n\
///     $Entities\n0 0 1 0\n1 0 0 0 1 1 0 1 5 0\n$EndEntities\n\
///     $Nodes\n1 3 1 3\n2 1 0 3\n1\n2\n3\n0 0 0\n1 0 0\n0 1 0\n$EndNodes\n\
///     $Elements\n1 1 1 1\n2 1 2 1\n1 1 2 3\n$EndElements\n";
/// let m = delone_io::read_gmsh(msh.as_bytes()).unwrap();
/// assert_eq!((m.dimension, m.triangles.clone(), m.triangle_refs.clone()), (2, vec![[0, 1, 2]], vec![5]));
/// ```
pub fn read_gmsh(input: &[u8]) -> Result<MeditMesh, IoError> {
    let mut tk = Tokens::new(input, false);
    let mut m = MeditMesh::default();
    // Physical tag of each (dimension, entity tag).
    let mut physical: Option<HashMap<(i64, i64), i32>> = None;
    let mut node: HashMap<i64, u32> = HashMap::new();
    let mut version = false;
    while let Some((t, line)) = tk.next_tok() {
        match t {
            b"$MeshFormat" => {
                let (v, l) = tk.expect("the version")?;
                if !v.starts_with(b"4") {
                    return Err(IoError::Unsupported {
                        line: l,
                        message: format!("Gmsh format version {} (4.1 is read)", show(v)),
                    });
                }
                let (kind, l) = tk.int("the file type")?;
                if kind != 0 {
                    return Err(IoError::Unsupported {
                        line: l,
                        message: "a binary .msh file (write it as ASCII)".into(),
                    });
                }
                tk.int("the data size")?;
                end(&mut tk, b"$EndMeshFormat")?;
                version = true;
            }
            b"$Entities" => {
                let mut map = HashMap::new();
                let counts = [
                    tk.count("the number of points")?.0,
                    tk.count("the number of curves")?.0,
                    tk.count("the number of surfaces")?.0,
                    tk.count("the number of volumes")?.0,
                ];
                for (dim, &n) in counts.iter().enumerate() {
                    for _ in 0..n {
                        let (tag, _) = tk.int("an entity tag")?;
                        for _ in 0..if dim == 0 { 3 } else { 6 } {
                            tk.f64("a coordinate of the entity's box")?;
                        }
                        let (np, _) = tk.count("the number of physical tags")?;
                        let mut first = 0;
                        for k in 0..np {
                            let (p, _) = tk.int("a physical tag")?;
                            if k == 0 {
                                first = p as i32;
                            }
                        }
                        if dim > 0 {
                            let (nb, _) = tk.count("the number of bounding entities")?;
                            for _ in 0..nb {
                                tk.int("a bounding entity tag")?;
                            }
                        }
                        map.insert((dim as i64, tag), first);
                    }
                }
                end(&mut tk, b"$EndEntities")?;
                physical = Some(map);
            }
            b"$Nodes" => {
                let (blocks, _) = tk.count("the number of node blocks")?;
                let (n, _) = tk.count("the number of nodes")?;
                tk.int("the smallest node tag")?;
                tk.int("the largest node tag")?;
                m.points.reserve(crate::surface::cap(n, input.len(), 6));
                for _ in 0..blocks {
                    let (dim, _) = tk.int("the entity dimension")?;
                    tk.int("the entity tag")?;
                    let (param, _) = tk.int("0 or 1 (parametric)")?;
                    let (k, _) = tk.count("the number of nodes in the block")?;
                    let mut tags = Vec::with_capacity(crate::surface::cap(k, input.len(), 2));
                    for _ in 0..k {
                        tags.push(tk.int("a node tag")?);
                    }
                    for (tag, l) in tags {
                        let p = [tk.f64("x")?, tk.f64("y")?, tk.f64("z")?];
                        for _ in 0..if param == 1 { dim.clamp(0, 3) } else { 0 } {
                            tk.f64("a parametric coordinate")?;
                        }
                        if node.insert(tag, m.points.len() as u32).is_some() {
                            return Err(IoError::syntax(l, "a new node tag", tag.to_string()));
                        }
                        m.points.push(p);
                    }
                }
                end(&mut tk, b"$EndNodes")?;
            }
            b"$Elements" => {
                let (blocks, _) = tk.count("the number of element blocks")?;
                for _ in 0..3 {
                    tk.int("the element counts and tags")?;
                }
                for _ in 0..blocks {
                    let (dim, _) = tk.int("the entity dimension")?;
                    let (tag, _) = tk.int("the entity tag")?;
                    let (ty, l) = tk.int("the element type")?;
                    let (k, _) = tk.count("the number of elements in the block")?;
                    let r = match &physical {
                        Some(p) => p.get(&(dim, tag)).copied().unwrap_or(0),
                        None => tag as i32,
                    };
                    let nodes = match ty {
                        15 => 1,
                        1 => 2,
                        2 => 3,
                        4 => 4,
                        _ => {
                            return Err(IoError::Unsupported {
                                line: l,
                                message: format!(
                                    "Gmsh element type {ty} (points 15, lines 1, triangles 2 and tetrahedra 4 are read)"
                                ),
                            })
                        }
                    };
                    for _ in 0..k {
                        tk.int("an element tag")?;
                        let mut v = [0u32; 4];
                        for x in v.iter_mut().take(nodes) {
                            let (t, l) = tk.int("a node tag")?;
                            *x = *node.get(&t).ok_or_else(|| {
                                IoError::syntax(l, "a node tag of $Nodes", t.to_string())
                            })?;
                        }
                        match nodes {
                            1 => m.corners.push(v[0]),
                            2 => {
                                m.edges.push([v[0], v[1]]);
                                m.edge_refs.push(r);
                            }
                            3 => {
                                m.triangles.push([v[0], v[1], v[2]]);
                                m.triangle_refs.push(r);
                            }
                            _ => {
                                m.tetrahedra.push(v);
                                m.tetrahedron_refs.push(r);
                            }
                        }
                    }
                }
                end(&mut tk, b"$EndElements")?;
            }
            s if s.starts_with(b"$") && !s.starts_with(b"$End") => {
                let mut closing = b"$End".to_vec();
                closing.extend_from_slice(&s[1..]);
                end_after(&mut tk, &closing, line)?;
            }
            _ => return Err(IoError::syntax(line, "a section ($Name)", show(t))),
        }
    }
    if !version {
        return Err(IoError::syntax(1, "$MeshFormat", "no such section"));
    }
    m.point_refs = vec![0; m.points.len()];
    m.dimension = if m.tetrahedra.is_empty() { 2 } else { 3 };
    if m.dimension == 2 {
        if let Some(i) = m.points.iter().position(|p| p[2] != 0.0) {
            return Err(IoError::invalid(format!(
                "node {} is off the plane z = 0 in a mesh without tetrahedra (a surface mesh)",
                i + 1
            )));
        }
    }
    Ok(m)
}

/// The next token must be `what` (a section's end).
fn end(tk: &mut Tokens, what: &[u8]) -> Result<(), IoError> {
    let (t, l) = tk.expect(&show(what))?;
    if t != what {
        return Err(IoError::syntax(l, show(what), show(t)));
    }
    Ok(())
}

/// Skips to the token `what` (the end of a section opened at `line`).
fn end_after(tk: &mut Tokens, what: &[u8], line: usize) -> Result<(), IoError> {
    while let Some((t, _)) = tk.next_tok() {
        if t == what {
            return Ok(());
        }
    }
    Err(IoError::syntax(
        line,
        format!("a section closed by {}", show(what)),
        "the end of the file",
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEAD: &str = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
    const NODES: &str =
        "$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n";

    #[test]
    fn reads_tetrahedra_and_faces_with_physical_tags() {
        let msh = format!(
            "{HEAD}$PhysicalNames\n1\n3 7 \"solid one\"\n$EndPhysicalNames\n\
             $Entities\n0 0 1 1\n2 0 0 0 1 1 0 1 4 0\n1 0 0 0 1 1 1 1 7 1 2\n$EndEntities\n{NODES}\
             $Elements\n2 2 1 2\n2 2 2 1\n1 1 3 2\n3 1 4 1\n2 1 2 3 4\n$EndElements\n"
        );
        let m = read_gmsh(msh.as_bytes()).unwrap();
        assert_eq!(m.dimension, 3);
        assert_eq!(
            (m.tetrahedra.clone(), m.tetrahedron_refs.clone()),
            (vec![[0, 1, 2, 3]], vec![7])
        );
        assert_eq!(
            (m.triangles.clone(), m.triangle_refs.clone()),
            (vec![[0, 2, 1]], vec![4])
        );
    }

    #[test]
    fn errors_name_the_line() {
        let bad = [
            (
                format!("{HEAD}$Nodes\n1 1 1 1\n2 1 0 1\n1\n0 x 0\n$EndNodes\n"),
                8,
                "y",
            ),
            (
                format!("{HEAD}{NODES}$Elements\n1 1 1 1\n2 1 3 1\n1 1 2 3 4\n$EndElements\n"),
                18,
                "type 3",
            ),
            (
                format!("{HEAD}{NODES}$Elements\n1 1 1 1\n2 1 2 1\n1 1 2 9\n$EndElements\n"),
                19,
                "node tag",
            ),
            (
                "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n".to_string(),
                2,
                "version",
            ),
            (
                "$MeshFormat\n4.1 1 8\n$EndMeshFormat\n".to_string(),
                2,
                "binary",
            ),
            (format!("{HEAD}$Nodes\n1 1 1 1\n"), 5, "the end of the file"),
        ];
        for (text, line, what) in bad {
            let e = read_gmsh(text.as_bytes()).unwrap_err();
            assert_eq!(e.line(), Some(line), "{e}");
            assert!(e.to_string().contains(what), "{e}");
        }
        let e = read_gmsh(
            format!("{HEAD}{NODES}$Elements\n1 1 1 1\n2 1 2 1\n1 1 2 4\n$EndElements\n").as_bytes(),
        )
        .unwrap_err();
        assert!(e.to_string().contains("off the plane z = 0"), "{e}");
    }
}
