//! Writer for the Gmsh `.msh` format, version 4.1 (ASCII).
//!
//! Layout written (sections of the 4.1 specification):
//!
//! ```text
//! $MeshFormat
//! 4.1 0 8
//! $EndMeshFormat
//! $Entities
//! <#points> <#curves> <#surfaces> <#volumes>
//! <tag> <x y z> 0                                                        (each point)
//! <tag> <min x y z> <max x y z> 0 <#points> <point tags>                 (each curve)
//! <tag> <min x y z> <max x y z> <#physical> [<physical>] <#curves> <curve tags>
//! <tag> <min x y z> <max x y z> <#physical> [<physical>] <#surfaces> <surface tags>
//! $EndEntities
//! $Nodes
//! <#blocks> <#nodes> 1 <#nodes>
//! <dim> <entity tag> 0 <#nodes in block>    (one block per entity holding nodes)
//! <node tags, one per line> then <x y z, one per line>
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
//! volume entity. Element tags run over the triangles first, then the
//! tetrahedra.
//!
//! Below the surfaces: a curve entity per set of surfaces that meet along
//! edges (an edge of one surface's border, or shared by several surfaces),
//! and a point entity per node where two or more curves meet. Each surface
//! lists its bounding curves, each curve its bounding points, each volume
//! the surfaces with a triangle on one of its tetrahedra. Every node is
//! classified on the lowest-dimensional entity holding it (point, curve,
//! surface, else the volume of its first tetrahedron), so that Gmsh's
//! `getNodes(2, tag, includeBoundary=True)` returns exactly the nodes of a
//! surface's triangles. Curves and points carry no elements.

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
    bounding: &[Vec<usize>],
) -> Result<(), IoError> {
    for (i, ((&v, b), bd)) in values.iter().zip(boxes).zip(bounding).enumerate() {
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
        o.byte(b' ');
        o.uint(bd.len() as u64);
        for &e in bd {
            o.byte(b' ');
            o.uint(e as u64 + 1);
        }
        o.nl()?;
    }
    Ok(())
}

/// The geometric entities below the surfaces and the classification of
/// the nodes (all indices 0-based).
struct Topology {
    /// Nodes where two or more curves meet: one point entity each.
    point_nodes: Vec<u32>,
    /// Per curve: its edges.
    curves: Vec<Vec<[u32; 2]>>,
    /// Per curve: its bounding point entities.
    curve_points: Vec<Vec<usize>>,
    /// Per surface: its bounding curves.
    surface_curves: Vec<Vec<usize>>,
    /// Per volume: its bounding surfaces.
    volume_surfaces: Vec<Vec<usize>>,
    /// Per node: the lowest-dimensional entity holding it (dimension, index).
    node_entity: Vec<(u8, usize)>,
}

impl Topology {
    #[allow(clippy::too_many_arguments)]
    fn new(
        n: usize,
        triangles: &[[u32; 3]],
        sidx: &[usize],
        ns: usize,
        tets: &[[u32; 4]],
        vidx: &[usize],
        nv: usize,
    ) -> Topology {
        use std::collections::{BTreeMap, HashMap};
        // Per edge: the surfaces of its triangles, with multiplicity.
        let mut edge_surfaces: BTreeMap<[u32; 2], Vec<usize>> = BTreeMap::new();
        for (t, &s) in triangles.iter().zip(sidx) {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                edge_surfaces
                    .entry([a.min(b), a.max(b)])
                    .or_default()
                    .push(s);
            }
        }
        // An edge is on a curve when it joins two surfaces or borders one
        // (in a single triangle of it); the curve is named by the set.
        let mut curve_of: BTreeMap<Vec<usize>, Vec<[u32; 2]>> = BTreeMap::new();
        for (e, mut ss) in edge_surfaces {
            ss.sort_unstable();
            let borders = ss.chunk_by(|a, b| a == b).any(|c| c.len() == 1);
            ss.dedup();
            if ss.len() > 1 || borders {
                curve_of.entry(ss).or_default().push(e);
            }
        }
        let mut surface_curves = vec![Vec::new(); ns];
        let mut curves = Vec::with_capacity(curve_of.len());
        let mut node_curves: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (c, (ss, edges)) in curve_of.into_iter().enumerate() {
            for s in ss {
                surface_curves[s].push(c);
            }
            for e in &edges {
                for v in e {
                    let l = &mut node_curves[*v as usize];
                    if !l.contains(&c) {
                        l.push(c);
                    }
                }
            }
            curves.push(edges);
        }
        let mut node_entity = vec![(3u8, 0usize); n];
        for (t, &v) in tets.iter().zip(vidx).rev() {
            for &x in t {
                node_entity[x as usize] = (3, v);
            }
        }
        for (t, &s) in triangles.iter().zip(sidx).rev() {
            for &x in t {
                node_entity[x as usize] = (2, s);
            }
        }
        let mut point_nodes = Vec::new();
        let mut point_of = HashMap::new();
        for (v, cs) in node_curves.iter().enumerate() {
            match cs.len() {
                0 => {}
                1 => node_entity[v] = (1, cs[0]),
                _ => {
                    point_of.insert(v as u32, point_nodes.len());
                    node_entity[v] = (0, point_nodes.len());
                    point_nodes.push(v as u32);
                }
            }
        }
        let curve_points = curves
            .iter()
            .map(|edges| {
                let mut p: Vec<usize> = edges
                    .iter()
                    .flatten()
                    .filter_map(|v| point_of.get(v).copied())
                    .collect();
                p.sort_unstable();
                p.dedup();
                p
            })
            .collect();
        // Volumes: the surfaces with a triangle that is a face of one of
        // their tetrahedra.
        let face_surface: HashMap<[u32; 3], usize> = triangles
            .iter()
            .zip(sidx)
            .map(|(t, &s)| {
                let mut k = *t;
                k.sort_unstable();
                (k, s)
            })
            .collect();
        let mut volume_surfaces = vec![Vec::new(); nv];
        for (t, &v) in tets.iter().zip(vidx) {
            for skip in 0..4 {
                let mut k = [0u32; 3];
                let mut j = 0;
                for (i, &x) in t.iter().enumerate() {
                    if i != skip {
                        k[j] = x;
                        j += 1;
                    }
                }
                k.sort_unstable();
                if let Some(&s) = face_surface.get(&k) {
                    volume_surfaces[v].push(s);
                }
            }
        }
        for l in &mut volume_surfaces {
            l.sort_unstable();
            l.dedup();
        }
        Topology {
            point_nodes,
            curves,
            curve_points,
            surface_curves,
            volume_surfaces,
            node_entity,
        }
    }

    fn curve_boxes(&self, points: &[[f64; 3]]) -> Vec<[f64; 6]> {
        let idx: Vec<usize> = self
            .curves
            .iter()
            .enumerate()
            .flat_map(|(c, e)| std::iter::repeat_n(c, e.len()))
            .collect();
        let edges: Vec<[u32; 2]> = self.curves.iter().flatten().copied().collect();
        bbox(points, &edges, &idx, self.curves.len())
    }
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
/// // No point entity, one curve (the triangle's border), one surface, one volume.
/// assert!(text.starts_with("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 1 1 1\n"));
/// // The volume (tag 1, physical 2) is bounded by surface 1.
/// assert!(text.contains("\n1 0 0 0 1 1 1 1 2 1 1\n$EndEntities"));
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
    let topo = Topology::new(
        points.len(),
        triangles,
        &sidx,
        svals.len(),
        tets,
        &vidx,
        vvals.len(),
    );
    let mut o = Out::new(out);
    o.str("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n");
    for (i, n) in [
        topo.point_nodes.len(),
        topo.curves.len(),
        svals.len(),
        vvals.len(),
    ]
    .into_iter()
    .enumerate()
    {
        if i > 0 {
            o.byte(b' ');
        }
        o.uint(n as u64);
    }
    o.nl()?;
    for (i, &v) in topo.point_nodes.iter().enumerate() {
        o.uint(i as u64 + 1);
        for c in points[v as usize] {
            o.byte(b' ');
            o.float(c);
        }
        o.str(" 0");
        o.nl()?;
    }
    let curve_tags = vec![0; topo.curves.len()];
    entity_lines(
        &mut o,
        &curve_tags,
        &topo.curve_boxes(points),
        &topo.curve_points,
    )?;
    entity_lines(
        &mut o,
        &svals,
        &bbox(points, triangles, &sidx, svals.len()),
        &topo.surface_curves,
    )?;
    entity_lines(
        &mut o,
        &vvals,
        &bbox(points, tets, &vidx, vvals.len()),
        &topo.volume_surfaces,
    )?;
    o.str("$EndEntities\n");
    nodes(&mut o, points, &topo.node_entity)?;
    elements(
        &mut o,
        (2, 2, triangles, &sidx, svals.len()),
        (3, 4, tets, &vidx, vvals.len()),
    )?;
    Ok(o.finish()?)
}

/// Cells of one dimension for [`elements`]: (dimension, Gmsh element
/// type, cells, each cell's entity index, number of entities).
type Cells<'a, const K: usize> = (u64, u64, &'a [[u32; K]], &'a [usize], usize);

/// The `$Elements` section of the cells of two dimensions, lower first:
/// one block per entity holding cells.
fn elements<W: Write, const A: usize, const B: usize>(
    o: &mut Out<W>,
    lower: Cells<'_, A>,
    upper: Cells<'_, B>,
) -> Result<(), IoError> {
    let nonempty = |entity: &[usize], n: usize| {
        let mut used = vec![false; n];
        for &e in entity {
            used[e] = true;
        }
        used.iter().filter(|&&u| u).count()
    };
    o.str("$Elements\n");
    let ne = (lower.2.len() + upper.2.len()) as u64;
    o.uint((nonempty(lower.3, lower.4) + nonempty(upper.3, upper.4)) as u64);
    o.byte(b' ');
    o.uint(ne);
    o.str(if ne == 0 { " 0 0" } else { " 1 " });
    if ne > 0 {
        o.uint(ne);
    }
    o.nl()?;
    let mut tag = 1u64;
    let (dim, kind, cells, entity, n) = lower;
    block(o, dim, kind, cells, entity, n, &mut tag)?;
    let (dim, kind, cells, entity, n) = upper;
    block(o, dim, kind, cells, entity, n, &mut tag)?;
    o.str("$EndElements\n");
    Ok(())
}

/// The `$Nodes` section: one block per entity holding nodes, in
/// (dimension, index) order, each node on the entity `node_entity` gives it.
fn nodes<W: Write>(
    o: &mut Out<W>,
    points: &[[f64; 3]],
    node_entity: &[(u8, usize)],
) -> Result<(), IoError> {
    o.str("$Nodes\n");
    let n = points.len() as u64;
    if n == 0 {
        o.str("0 0 0 0\n");
    } else {
        // One block per entity holding nodes, in (dimension, tag) order.
        let mut order: Vec<u32> = (0..n as u32).collect();
        order.sort_by_key(|&v| node_entity[v as usize]);
        let blocks: Vec<&[u32]> = order
            .chunk_by(|&a, &b| node_entity[a as usize] == node_entity[b as usize])
            .collect();
        o.uint(blocks.len() as u64);
        o.byte(b' ');
        o.uint(n);
        o.str(" 1 ");
        o.uint(n);
        o.nl()?;
        for b in blocks {
            let (dim, tag) = node_entity[b[0] as usize];
            o.uint(u64::from(dim));
            o.byte(b' ');
            o.uint(tag as u64 + 1);
            o.str(" 0 ");
            o.uint(b.len() as u64);
            o.nl()?;
            for &v in b {
                o.uint(u64::from(v) + 1);
                o.nl()?;
            }
            for &v in b {
                let p = points[v as usize];
                o.float(p[0]);
                o.byte(b' ');
                o.float(p[1]);
                o.byte(b' ');
                o.float(p[2]);
                o.nl()?;
            }
        }
    }
    o.str("$EndNodes\n");
    Ok(())
}

/// Writes a planar mesh as a Gmsh `.msh` 4.1 ASCII file: the triangles
/// (`tri_tags`, e.g. region numbers) as surfaces and the boundary and
/// interface edges (`edge_tags`, e.g. boundary markers) as line elements
/// on curves, one entity per distinct tag (physical tag = the tag when
/// positive). Each surface lists the curves with an edge of one of its
/// triangles; a node lies on the curve of its first edge, else on the
/// surface of its first triangle. Points are written with their `z`.
///
/// # Errors
/// [`IoError::InvalidInput`] if a tag array does not match its elements or
/// an element names a missing point; [`IoError::Io`] if the writer fails.
///
/// ```
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// let mut out = Vec::new();
/// let edges = [[0, 1], [1, 2], [2, 0]];
/// delone_io::write_gmsh_2d(&mut out, &pts, &[[0, 1, 2]], &[4], &edges, &[1, 1, 2]).unwrap();
/// let m = delone_io::read_gmsh(&out).unwrap();
/// assert_eq!((m.edges.clone(), m.edge_refs.clone()), (edges.to_vec(), vec![1, 1, 2]));
/// assert_eq!(m.triangle_refs, vec![4]);
/// ```
pub fn write_gmsh_2d<W: Write>(
    out: W,
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    tri_tags: &[i32],
    edges: &[[u32; 2]],
    edge_tags: &[i32],
) -> Result<(), IoError> {
    check_cells("triangle", triangles, tri_tags, points.len())?;
    check_cells("edge", edges, edge_tags, points.len())?;
    let (cvals, cidx) = group(edge_tags);
    let (mut svals, sidx) = group(tri_tags);
    if svals.is_empty() {
        svals.push(0);
    }
    let mut node_entity = vec![(2u8, 0usize); points.len()];
    for (t, &s) in triangles.iter().zip(&sidx).rev() {
        for &x in t {
            node_entity[x as usize] = (2, s);
        }
    }
    for (e, &c) in edges.iter().zip(&cidx).rev() {
        for &x in e {
            node_entity[x as usize] = (1, c);
        }
    }
    // Each surface: the curves with an edge of one of its triangles.
    let mut curve_of: Vec<([u32; 2], usize)> = edges
        .iter()
        .zip(&cidx)
        .map(|(e, &c)| ([e[0].min(e[1]), e[0].max(e[1])], c))
        .collect();
    curve_of.sort_unstable();
    let mut surface_curves = vec![Vec::new(); svals.len()];
    for (t, &s) in triangles.iter().zip(&sidx) {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let key = [a.min(b), a.max(b)];
            let i = curve_of.partition_point(|x| x.0 < key);
            for x in curve_of[i..].iter().take_while(|x| x.0 == key) {
                surface_curves[s].push(x.1);
            }
        }
    }
    for l in &mut surface_curves {
        l.sort_unstable();
        l.dedup();
    }
    let mut o = Out::new(out);
    o.str("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 ");
    o.uint(cvals.len() as u64);
    o.byte(b' ');
    o.uint(svals.len() as u64);
    o.str(" 0");
    o.nl()?;
    let no_points = vec![Vec::new(); cvals.len()];
    let curve_boxes = bbox(points, edges, &cidx, cvals.len());
    entity_lines(&mut o, &cvals, &curve_boxes, &no_points)?;
    let surface_boxes = bbox(points, triangles, &sidx, svals.len());
    entity_lines(&mut o, &svals, &surface_boxes, &surface_curves)?;
    o.str("$EndEntities\n");
    nodes(&mut o, points, &node_entity)?;
    elements(
        &mut o,
        (1, 1, edges, &cidx, cvals.len()),
        (2, 2, triangles, &sidx, svals.len()),
    )?;
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
        let p = parse_full(text);
        (p.points, p.elements)
    }

    #[allow(clippy::type_complexity)]
    struct Parsed {
        points: Vec<[f64; 3]>,
        elements: Vec<(u32, Vec<u32>, Option<i64>)>,
        /// Per node (0-based): the entity it is classified on.
        on: Vec<Option<(i64, i64)>>,
        /// Bounding entities of each (dim, tag), dim >= 1.
        bounds: std::collections::HashMap<(i64, i64), Vec<i64>>,
        /// Per element: its entity.
        element_entity: Vec<(i64, i64)>,
    }

    /// Nodes of entity `e` and of everything on its boundary, recursively
    /// (Gmsh's `getNodes(dim, tag, includeBoundary=True)`), 1-based.
    fn nodes_with_boundary(p: &Parsed, e: (i64, i64)) -> Vec<u32> {
        let mut stack = vec![e];
        let mut seen = std::collections::HashSet::new();
        while let Some(x) = stack.pop() {
            if seen.insert(x) {
                for &b in p.bounds.get(&x).map(|v| &v[..]).unwrap_or(&[]) {
                    stack.push((x.0 - 1, b.abs()));
                }
            }
        }
        let mut out: Vec<u32> = (0..p.on.len())
            .filter(|&i| p.on[i].is_some_and(|o| seen.contains(&o)))
            .map(|i| i as u32 + 1)
            .collect();
        out.sort_unstable();
        out
    }

    #[allow(clippy::type_complexity)]
    fn parse_full(text: &str) -> Parsed {
        let lines: Vec<&str> = text.lines().collect();
        let sec = |name: &str| lines.iter().position(|l| *l == name).unwrap() + 1;
        assert_eq!(lines[sec("$MeshFormat")], "4.1 0 8");
        let num =
            |l: &str| -> Vec<f64> { l.split_whitespace().map(|t| t.parse().unwrap()).collect() };
        // Entities: physical tag and bounding entities per (dim, tag).
        let mut k = sec("$Entities");
        let h = num(lines[k]);
        k += 1;
        let mut phys = std::collections::HashMap::new();
        let mut bounds = std::collections::HashMap::new();
        for (dim, count) in [(0, h[0]), (1, h[1]), (2, h[2]), (3, h[3])] {
            for _ in 0..count as usize {
                let v = num(lines[k]);
                k += 1;
                let at = if dim == 0 { 4 } else { 7 };
                let np = v[at] as usize;
                phys.insert((dim, v[0] as i64), (np > 0).then(|| v[at + 1] as i64));
                if dim > 0 {
                    let nb = v[at + 1 + np] as usize;
                    let b: Vec<i64> = v[at + 2 + np..].iter().map(|&x| x as i64).collect();
                    assert_eq!(b.len(), nb, "bounding list of ({dim}, {})", v[0]);
                    bounds.insert((dim, v[0] as i64), b);
                } else {
                    assert_eq!(v.len(), 5 + np);
                }
            }
        }
        assert_eq!(lines[k], "$EndEntities");
        let mut k = sec("$Nodes");
        let h = num(lines[k]);
        k += 1;
        let n = h[1] as usize;
        let mut pts = vec![[f64::NAN; 3]; n];
        let mut on = vec![None; n];
        for _ in 0..h[0] as usize {
            let b = num(lines[k]);
            k += 1;
            let m = b[3] as usize;
            let tags: Vec<usize> = (0..m).map(|i| num(lines[k + i])[0] as usize).collect();
            k += m;
            assert!(
                phys.contains_key(&(b[0] as i64, b[1] as i64)),
                "nodes on a listed entity"
            );
            for &t in &tags {
                assert!(on[t - 1].is_none(), "node {t} in two blocks");
                on[t - 1] = Some((b[0] as i64, b[1] as i64));
            }
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
        let mut element_entity = Vec::new();
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
                element_entity.push((b[0] as i64, b[1] as i64));
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
        assert!(on.iter().all(|o| o.is_some()), "every node classified");
        Parsed {
            points: pts,
            elements: out,
            on,
            bounds,
            element_entity,
        }
    }

    /// A cube of 6 tetrahedra around its diagonal, each face of the cube a
    /// surface of its own (marker 1..6), plus an interior node: every
    /// surface's nodes (with its boundary) are exactly the corners of its
    /// triangles, the volume is bounded by the 6 surfaces, and the interior
    /// node lies on the volume.
    #[test]
    fn entities_classify_nodes_and_list_bounding_entities() {
        let mut pts: Vec<[f64; 3]> = (0..8)
            .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
            .collect();
        pts.push([0.5, 0.5, 0.5]);
        let q = |a: u32, b: u32, c: u32, d: u32| [[a, b, c], [a, c, d]];
        let mut tris = Vec::new();
        let mut marks = Vec::new();
        for (m, f) in [
            q(0, 2, 3, 1),
            q(4, 5, 7, 6),
            q(0, 1, 5, 4),
            q(2, 6, 7, 3),
            q(0, 4, 6, 2),
            q(1, 3, 7, 5),
        ]
        .into_iter()
        .enumerate()
        {
            tris.extend(f);
            marks.extend([m as i32 + 1; 2]);
        }
        // Tetrahedra: the centre with each triangle (orientation is not
        // this writer's business).
        let tets: Vec<[u32; 4]> = tris.iter().map(|t| [t[0], t[1], t[2], 8]).collect();
        let mut out = Vec::new();
        write_gmsh(&mut out, &pts, &tris, &marks, &tets, &vec![7; tets.len()]).unwrap();
        let p = parse_full(&String::from_utf8(out).unwrap());
        for s in 1..=6i64 {
            let mut want: Vec<u32> = tris
                .iter()
                .zip(&p.element_entity)
                .filter(|(_, e)| **e == (2, s))
                .flat_map(|(t, _)| t.iter().map(|v| v + 1))
                .collect();
            want.sort_unstable();
            want.dedup();
            assert_eq!(want.len(), 4, "surface {s}");
            assert_eq!(nodes_with_boundary(&p, (2, s)), want, "surface {s}");
        }
        assert_eq!(p.bounds[&(3, 1)], vec![1, 2, 3, 4, 5, 6]);
        assert_eq!(p.on[8], Some((3, 1)));
        assert_eq!(nodes_with_boundary(&p, (3, 1)).len(), 9);
        // Corners meet three curves: point entities; edge curves join two
        // surfaces each.
        assert_eq!(
            (0..8)
                .filter(|&i| p.on[i].is_some_and(|o| o.0 == 0))
                .count(),
            8
        );
        assert_eq!(p.bounds.keys().filter(|k| k.0 == 1).count(), 12);
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
        assert!(text.contains("$Entities\n0 0 0 1\n"), "{text}");
        assert!(text.contains("$Nodes\n0 0 0 0\n$EndNodes\n$Elements\n0 0 0 0\n"));
        let pts = [[0.0; 3]; 3];
        assert!(write_gmsh(Vec::new(), &pts, &[[0, 1, 3]], &[1], &[], &[]).is_err());
        assert!(write_gmsh(Vec::new(), &pts, &[[0, 1, 2]], &[], &[], &[]).is_err());
    }

    /// A square of two triangles (regions 1 and 2) with its four sides
    /// tagged 1..4 and the diagonal between the regions tagged 9: read
    /// back, the lines keep their tags and the triangles theirs; each
    /// surface is bounded by its two sides and the diagonal.
    #[test]
    fn planar_mesh_with_boundary_lines_reads_back() {
        let pts = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let tris = [[0, 1, 2], [0, 2, 3]];
        let edges = [[0, 1], [1, 2], [2, 3], [3, 0], [0, 2]];
        let edge_tags = [1, 2, 3, 4, 9];
        let mut out = Vec::new();
        write_gmsh_2d(&mut out, &pts, &tris, &[1, 2], &edges, &edge_tags).unwrap();
        let m = crate::read_gmsh(&out).unwrap();
        assert_eq!(m.dimension, 2);
        assert_eq!(m.points.len(), 4);
        let mut got: Vec<([u32; 2], i32)> =
            m.edges.iter().copied().zip(m.edge_refs.clone()).collect();
        got.sort_unstable();
        let mut want: Vec<([u32; 2], i32)> = edges.iter().copied().zip(edge_tags).collect();
        want.sort_unstable();
        // Node numbers are kept (tags are 1-based indices).
        assert_eq!(got, want);
        assert_eq!(m.triangles, tris.to_vec());
        assert_eq!(m.triangle_refs, vec![1, 2]);
        let p = parse_full(&String::from_utf8(out).unwrap());
        assert_eq!(p.bounds[&(2, 1)], vec![1, 2, 5]);
        assert_eq!(p.bounds[&(2, 2)], vec![3, 4, 5]);
        assert!(p
            .elements
            .iter()
            .filter(|e| e.0 == 1)
            .all(|e| e.2.is_some()));
    }
}
