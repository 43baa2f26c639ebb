//! Triangle-compatible outputs of `delone tri -p` (and the pictures and
//! statistics of every `delone tri` run).
//!
//! * `.node`: input attributes copied, Steiner points' attributes linearly
//!   interpolated (crossings along their segment, refinement points in the
//!   triangle of the unrefined triangulation that holds them); boundary
//!   markers by Triangle's documented rule ([`vertex_markers`]).
//! * `.ele`: regional attribute with `-A`; with `-o2` six nodes per
//!   triangle (corners, then the midpoints of the edges opposite corners 1,
//!   2, 3), the midpoints appended to the `.node` file.
//! * `.poly` (unless `-P`): the subsegments and the other boundary edges
//!   with markers ([`edge_markers`]), the holes and regions.
//! * `.edge` (`-e`) with markers, `.neigh` (`-n`), `.vtu` (VTK quadratic
//!   triangles, type 22, with `-o2`).
//! * `-V` statistics ([`delone::tri::quality::TriStats`]), `--stats-json`.
//! * `--svg`, `--png`: the mesh, segments thick, holes as red crosses, with
//!   `--svg-quality` triangles coloured by minimum angle with a legend.

use std::borrow::Cow;
use std::fs::File;
use std::path::{Path, PathBuf};

use delone::model::pslg::Pslg;
use delone::tri::constrain::Cdt;
use delone::tri::pipeline::{edge_key, hull_edge_keys, vertex_markers};
use delone::tri::quality::{SteinerCounts, TriStats, TriangleQuality, ASPECT_BINS};
use delone::NONE;
use delone_io::{DataArray, NodeFile, SvgLayer, SvgStyle, Values, VtuFormat};

use crate::args::Opts;
use crate::fail::{input_err as fail, Failure};
use crate::jettison::Renumber;
use crate::paths::with_ext;

fn write(
    path: &Path,
    written: &mut Vec<PathBuf>,
    f: impl FnOnce(File) -> Result<(), delone_io::IoError>,
) -> Result<(), Failure> {
    let file = crate::guard::create(path)?;
    f(file).map_err(|e| fail(format!("cannot write {}: {e}", path.display())))?;
    written.push(path.to_path_buf());
    Ok(())
}

/// `items` with -j's renumbering applied (borrowed unchanged without -j).
fn renumbered<'a, const K: usize>(
    jet: Option<&Renumber>,
    items: &'a [[u32; K]],
) -> Cow<'a, [[u32; K]]> {
    match jet {
        Some(r) => {
            let mut v = items.to_vec();
            r.apply(&mut v);
            Cow::Owned(v)
        }
        None => Cow::Borrowed(items),
    }
}

/// Subsegment markers by edge key, sorted (the first subsegment of an edge
/// wins, as in the subsegment order).
fn segment_lookup(subsegs: &[([u32; 2], i32)]) -> Vec<(u64, i32)> {
    let mut v: Vec<(u64, i32)> = subsegs
        .iter()
        .map(|&(s, m)| (edge_key(s[0], s[1]), m))
        .collect();
    v.sort_by_key(|&(k, _)| k); // stable: the first one of equal keys first
    v.dedup_by_key(|e| e.0);
    v
}

/// Output edge markers, Triangle's documented rule: the marker of the
/// segment the edge is part of when nonzero; else 1 on the boundary; else 0.
pub fn edge_markers(
    edges: &[[u32; 2]],
    boundary: &[bool],
    subsegs: &[([u32; 2], i32)],
) -> Vec<i32> {
    let look = segment_lookup(subsegs);
    edges
        .iter()
        .zip(boundary)
        .map(|(e, &b)| {
            let s = look
                .binary_search_by_key(&edge_key(e[0], e[1]), |&(k, _)| k)
                .map_or(0, |i| look[i].1);
            if s != 0 {
                s
            } else {
                i32::from(b)
            }
        })
        .collect()
}

/// Quadratic (6-node) triangles: for triangle `[a, b, c]` the nodes `[a, b,
/// c, m_bc, m_ca, m_ab]` (the midpoints of the edges opposite the first,
/// second and third corners, Triangle's `-o2` order). Midpoints are numbered
/// after the `n` existing points, in the order triangles first reach them.
#[derive(Debug, Clone, PartialEq)]
pub struct Quadratic {
    /// The 6-node triangles.
    pub triangles: Vec<[u32; 6]>,
    /// The midpoint of each new node.
    pub points: Vec<[f64; 2]>,
    /// The two end vertices of each new node's edge.
    pub edges: Vec<[u32; 2]>,
}

impl Quadratic {
    /// The 6-node triangles of `tris` over `points`, sharing midpoints with
    /// the neighbour across each edge.
    pub fn new(points: &[[f64; 2]], tris: &[[u32; 3]], nbrs: &[[u32; 3]]) -> Quadratic {
        let n = points.len() as u32;
        let mut q = Quadratic {
            triangles: Vec::with_capacity(tris.len()),
            points: Vec::new(),
            edges: Vec::new(),
        };
        for (t, tri) in tris.iter().enumerate() {
            let mut six = [tri[0], tri[1], tri[2], 0, 0, 0];
            for k in 0..3 {
                let (a, b) = (tri[(k + 1) % 3], tri[(k + 2) % 3]);
                let nb = nbrs[t][k];
                let shared = (nb != NONE && (nb as usize) < t)
                    .then(|| {
                        let other = &tris[nb as usize];
                        // The corner of the neighbour that is not on the edge.
                        (0..3)
                            .find(|&j| other[j] != a && other[j] != b)
                            .map(|j| q.triangles[nb as usize][3 + j])
                    })
                    .flatten();
                six[3 + k] = match shared {
                    Some(m) => m,
                    None => {
                        let (pa, pb) = (points[a as usize], points[b as usize]);
                        q.points
                            .push([0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])]);
                        q.edges.push([a, b]);
                        n + q.points.len() as u32 - 1
                    }
                };
            }
            q.triangles.push(six);
        }
        q
    }

    /// The triangles in VTK's quadratic-triangle order (corners, then the
    /// midpoints of edges 0–1, 1–2, 2–0).
    pub fn vtk_order(&self) -> Vec<[u32; 6]> {
        self.triangles
            .iter()
            .map(|t| [t[0], t[1], t[2], t[5], t[3], t[4]])
            .collect()
    }
}

/// A uniform grid of triangle bounding boxes for point location.
struct Locator<'a> {
    pts: &'a [[f64; 2]],
    tris: &'a [[u32; 3]],
    lo: [f64; 2],
    cell: f64,
    nx: usize,
    ny: usize,
    start: Vec<u32>,
    items: Vec<u32>,
}

impl<'a> Locator<'a> {
    fn new(pts: &'a [[f64; 2]], tris: &'a [[u32; 3]]) -> Self {
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for t in tris {
            for &v in t {
                let p = pts[v as usize];
                for k in 0..2 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
        }
        let side = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(f64::MIN_POSITIVE);
        let cells = ((tris.len() as f64).sqrt().ceil() as usize).clamp(1, 4096);
        let cell = side / cells as f64;
        let nx = (((hi[0] - lo[0]) / cell) as usize + 1).min(4097);
        let ny = (((hi[1] - lo[1]) / cell) as usize + 1).min(4097);
        let mut me = Locator {
            pts,
            tris,
            lo,
            cell,
            nx,
            ny,
            start: vec![0; nx * ny + 1],
            items: Vec::new(),
        };
        // Two passes: count, then fill (counting sort by cell).
        let ranges: Vec<[usize; 4]> = tris.iter().map(|t| me.range(t)).collect();
        for r in &ranges {
            for y in r[2]..=r[3] {
                for x in r[0]..=r[1] {
                    me.start[y * nx + x + 1] += 1;
                }
            }
        }
        for i in 0..nx * ny {
            me.start[i + 1] += me.start[i];
        }
        let mut fill = me.start.clone();
        me.items = vec![0; me.start[nx * ny] as usize];
        for (t, r) in ranges.iter().enumerate() {
            for y in r[2]..=r[3] {
                for x in r[0]..=r[1] {
                    let c = y * nx + x;
                    me.items[fill[c] as usize] = t as u32;
                    fill[c] += 1;
                }
            }
        }
        me
    }

    fn cell_of(&self, p: [f64; 2]) -> [usize; 2] {
        let f = |v: f64, lo: f64, n: usize| (((v - lo) / self.cell).max(0.0) as usize).min(n - 1);
        [f(p[0], self.lo[0], self.nx), f(p[1], self.lo[1], self.ny)]
    }

    fn range(&self, t: &[u32; 3]) -> [usize; 4] {
        let mut lo = [usize::MAX; 2];
        let mut hi = [0usize; 2];
        for &v in t {
            let c = self.cell_of(self.pts[v as usize]);
            for k in 0..2 {
                lo[k] = lo[k].min(c[k]);
                hi[k] = hi[k].max(c[k]);
            }
        }
        [lo[0], hi[0], lo[1], hi[1]]
    }

    /// The triangle of `p`'s cell whose smallest barycentric coordinate is
    /// largest (the one containing `p` when there is one), with the
    /// barycentric coordinates.
    fn locate(&self, p: [f64; 2]) -> Option<(u32, [f64; 3])> {
        let c = self.cell_of(p);
        let i = c[1] * self.nx + c[0];
        let mut best: Option<(u32, [f64; 3])> = None;
        let mut best_min = f64::NEG_INFINITY;
        for &t in &self.items[self.start[i] as usize..self.start[i + 1] as usize] {
            let [a, b, cc] = self.tris[t as usize].map(|v| self.pts[v as usize]);
            let d = (b[0] - a[0]) * (cc[1] - a[1]) - (b[1] - a[1]) * (cc[0] - a[0]);
            if d == 0.0 {
                continue;
            }
            let l1 = ((b[0] - p[0]) * (cc[1] - p[1]) - (b[1] - p[1]) * (cc[0] - p[0])) / d;
            let l2 = ((cc[0] - p[0]) * (a[1] - p[1]) - (cc[1] - p[1]) * (a[0] - p[0])) / d;
            let l3 = 1.0 - l1 - l2;
            let m = l1.min(l2).min(l3);
            if m > best_min {
                best_min = m;
                best = Some((t, [l1, l2, l3]));
            }
        }
        best
    }
}

/// Attributes of every output point (`n_attr` per point): the input
/// points' own, then for each Steiner point a linear interpolation (a
/// crossing along its first segment; a refinement point in the triangle of
/// `initial` holding it, whose own Steiner points are crossings).
pub fn point_attributes(
    g: &Pslg,
    node: &NodeFile,
    initial: &Cdt,
    out_points: &[[f64; 2]],
) -> Vec<f64> {
    let na = node.n_attributes;
    if na == 0 {
        return Vec::new();
    }
    let n_in = g.points.len();
    let mut attrs = vec![0.0; out_points.len() * na];
    attrs[..n_in * na].copy_from_slice(&node.attributes[..n_in * na]);
    // Crossings of the initial triangulation.
    for c in &initial.report.crossings {
        let s = g.segments[c.segments[0] as usize];
        let (a, b) = (s[0] as usize, s[1] as usize);
        let (pa, pb, p) = (g.points[a], g.points[b], initial.points[c.vertex as usize]);
        let len2 = (pb[0] - pa[0]).powi(2) + (pb[1] - pa[1]).powi(2);
        let t = if len2 > 0.0 {
            (((p[0] - pa[0]) * (pb[0] - pa[0]) + (p[1] - pa[1]) * (pb[1] - pa[1])) / len2)
                .clamp(0.0, 1.0)
        } else {
            0.0
        };
        let v = c.vertex as usize;
        for k in 0..na {
            attrs[v * na + k] = (1.0 - t) * attrs[a * na + k] + t * attrs[b * na + k];
        }
    }
    let n0 = initial.points.len();
    if out_points.len() > n0 && !initial.triangles.is_empty() {
        let loc = Locator::new(&initial.points, &initial.triangles);
        for (v, &p) in out_points.iter().enumerate().skip(n0) {
            if let Some((t, l)) = loc.locate(p) {
                let tri = initial.triangles[t as usize];
                for k in 0..na {
                    attrs[v * na + k] = (0..3)
                        .map(|j| l[j] * attrs[tri[j] as usize * na + k])
                        .sum::<f64>();
                }
            }
        }
    }
    attrs
}

/// Everything the `-p` writers need.
pub struct PslgOut<'a> {
    /// Switches.
    pub o: &'a Opts,
    /// Output base name (`FILE.1`).
    pub out: &'a Path,
    /// The input PSLG.
    pub g: &'a Pslg,
    /// The input points' file (attributes).
    pub node: &'a NodeFile,
    /// The output mesh.
    pub cdt: &'a Cdt,
    /// The unrefined triangulation (for attribute interpolation), when the
    /// points have attributes and the mesh was refined.
    pub initial: Option<&'a Cdt>,
    /// First index of the output numbering.
    pub first: u32,
    /// Steiner points by kind.
    pub steiner: SteinerCounts,
}

/// Writes the `-p` outputs; returns the files written and, with `-V` or
/// `--stats-json`, the statistics.
pub fn write_pslg(p: &PslgOut<'_>) -> Result<(Vec<PathBuf>, Option<TriStats>), Failure> {
    let (o, cdt, g) = (p.o, p.cdt, p.g);
    let bound = !o.out().no_bound;
    let mut written = Vec::new();
    let n = cdt.points.len();
    let n_in = g.points.len();
    let input_markers: Vec<i32> = (0..n_in).map(|i| g.point_marker(i)).collect();
    let bounding: Vec<([u32; 2], i32)> = cdt
        .segments
        .iter()
        .filter(|s| s.bounding)
        .map(|s| (s.v, s.marker))
        .collect();
    let markers = vertex_markers(n, &input_markers, &bounding, &cdt.triangles, &cdt.neighbors);
    let na = p.node.n_attributes;
    let attrs = if na > 0 {
        point_attributes(g, p.node, p.initial.unwrap_or(cdt), &cdt.points)
    } else {
        Vec::new()
    };
    let edges = delone_io::topo::tri_edges(&cdt.triangles, &cdt.neighbors)
        .map_err(|e| fail(format!("internal error: {e}")))?;
    let emark = edge_markers(&edges.items, &edges.boundary, &bounding);
    let quad = o
        .tri
        .second_order
        .then(|| Quadratic::new(&cdt.points, &cdt.triangles, &cdt.neighbors));
    // Points, attributes and markers, with the midpoints appended for -o2.
    let (all_pts, all_attrs, all_markers) = match &quad {
        None => (None, None, None),
        Some(q) => {
            let mut pts = cdt.points.clone();
            pts.extend_from_slice(&q.points);
            let mut at = attrs.clone();
            for e in &q.edges {
                for k in 0..na {
                    at.push(0.5 * (attrs[e[0] as usize * na + k] + attrs[e[1] as usize * na + k]));
                }
            }
            let look: Vec<(u64, i32)> = {
                let mut v: Vec<(u64, i32)> = edges
                    .items
                    .iter()
                    .zip(&emark)
                    .map(|(e, &m)| (edge_key(e[0], e[1]), m))
                    .collect();
                v.sort_unstable();
                v
            };
            let mut mk = markers.clone();
            for e in &q.edges {
                let k = edge_key(e[0], e[1]);
                mk.push(
                    look.binary_search_by_key(&k, |&(x, _)| x)
                        .map_or(0, |i| look[i].1),
                );
            }
            (Some(pts), Some(at), Some(mk))
        }
    };
    let pts = all_pts.as_deref().unwrap_or(&cdt.points);
    let at = all_attrs.as_deref().unwrap_or(&attrs);
    let mk = all_markers.as_deref().unwrap_or(&markers);
    // -j: only the vertices of the triangles (and the -o2 midpoints), renumbered.
    let jet = o
        .tri
        .jettison
        .then(|| Renumber::new(pts.len(), &cdt.triangles, cdt.points.len()));
    let jrows = jet
        .as_ref()
        .map(|r| (r.rows(pts, 1), r.rows(at, na), r.rows(mk, 1)));
    let (pts, at, mk) = match &jrows {
        Some((p, a, m)) => (&p[..], &a[..], &m[..]),
        None => (pts, at, mk),
    };
    let jet = jet.as_ref();
    let first = p.first;
    if !o.out().no_node {
        write(&with_ext(p.out, "node"), &mut written, |f| {
            delone_io::write_node(f, pts, at, na, bound.then_some(mk), first)
        })?;
    }
    let (eattrs, nea) = if o.region_attributes() {
        (cdt.attributes.clone(), 1)
    } else {
        (Vec::new(), 0)
    };
    if !o.out().no_ele {
        write(&with_ext(p.out, "ele"), &mut written, |f| match &quad {
            Some(q) => delone_io::write_ele(f, &renumbered(jet, &q.triangles), &eattrs, nea, first),
            None => delone_io::write_ele(f, &renumbered(jet, &cdt.triangles), &eattrs, nea, first),
        })?;
    }
    if !o.tri.no_poly {
        // The subsegments, then the boundary edges that are not (-c hulls).
        let look = segment_lookup(&bounding);
        let hull = hull_edge_keys(&cdt.triangles, &cdt.neighbors);
        let mut segs: Vec<[u32; 2]> = bounding.iter().map(|s| s.0).collect();
        let mut sm: Vec<i32> = bounding
            .iter()
            .map(|&(s, m)| {
                if m != 0 {
                    m
                } else {
                    i32::from(hull.binary_search(&edge_key(s[0], s[1])).is_ok())
                }
            })
            .collect();
        for (e, &b) in edges.items.iter().zip(&edges.boundary) {
            if b && look
                .binary_search_by_key(&edge_key(e[0], e[1]), |&(k, _)| k)
                .is_err()
            {
                segs.push(*e);
                sm.push(1);
            }
        }
        let regions: Vec<[f64; 4]> = g
            .regions
            .iter()
            .map(|r| [r.point[0], r.point[1], r.attribute, r.max_area])
            .collect();
        let segs = renumbered(jet, &segs);
        write(&with_ext(p.out, "poly"), &mut written, |f| {
            delone_io::write_poly(
                f,
                &[],
                &segs,
                bound.then_some(&sm[..]),
                &g.holes,
                &regions,
                first,
            )
        })?;
    }
    if o.out().edges {
        write(&with_ext(p.out, "edge"), &mut written, |f| {
            delone_io::write_edge(
                f,
                &renumbered(jet, &edges.items),
                bound.then_some(&emark[..]),
                first,
            )
        })?;
    }
    if o.out().neigh {
        write(&with_ext(p.out, "neigh"), &mut written, |f| {
            delone_io::write_neigh(f, &cdt.neighbors, first)
        })?;
    }
    let vtu_path = match (&o.vtu, o.vtu_ascii) {
        (Some(v), _) => Some(v.clone()),
        (None, true) => Some(with_ext(p.out, "vtu")),
        (None, false) => None,
    };
    if let Some(path) = vtu_path {
        let names: Vec<String> = (0..na).map(|k| format!("attribute_{}", k + 1)).collect();
        let cols: Vec<Vec<f64>> = (0..na)
            .map(|k| at.iter().skip(k).step_by(na).copied().collect())
            .collect();
        let mut pd = Vec::new();
        if bound {
            pd.push(DataArray {
                name: "marker",
                values: Values::Int32(mk),
            });
        }
        for (name, col) in names.iter().zip(&cols) {
            pd.push(DataArray {
                name,
                values: Values::Float64(col),
            });
        }
        let min_angle: Vec<f64> = cdt
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| cdt.points[v as usize]);
                TriangleQuality::new(a, b, c).min_angle
            })
            .collect();
        let mut cd = vec![DataArray {
            name: "min_angle",
            values: Values::Float64(&min_angle),
        }];
        if o.region_attributes() {
            cd.push(DataArray {
                name: "region_attribute",
                values: Values::Float64(&cdt.attributes),
            });
        }
        let fmt = if o.vtu_ascii {
            VtuFormat::Ascii
        } else {
            VtuFormat::Binary
        };
        write(&path, &mut written, |f| match &quad {
            Some(q) => {
                delone_io::write_vtu(f, pts, &renumbered(jet, &q.vtk_order()), &pd, &cd, fmt)
            }
            None => delone_io::write_vtu(f, pts, &renumbered(jet, &cdt.triangles), &pd, &cd, fmt),
        })?;
    }
    let stats = stats_if(
        o,
        &cdt.points,
        &cdt.triangles,
        Some(p.steiner),
        &mut written,
    )?;
    let segs: Vec<[u32; 2]> = bounding.iter().map(|s| s.0).collect();
    pictures(
        o,
        &Picture {
            points: &cdt.points,
            triangles: &cdt.triangles,
            segments: &segs,
            holes: &g.holes,
        },
        &mut written,
    )?;
    Ok((written, stats))
}

/// A plain `delone tri` mesh (no `-p`) for `-o2`.
pub struct Plain<'a> {
    /// The input `.node` file (attributes).
    pub node: &'a NodeFile,
    /// Points.
    pub points: &'a [[f64; 2]],
    /// Triangles.
    pub triangles: &'a [[u32; 3]],
    /// Neighbours.
    pub neighbors: &'a [[u32; 3]],
    /// Output point markers.
    pub markers: &'a [i32],
    /// First index of the output numbering.
    pub first: u32,
}

/// `-o2` without `-p`: the planned `.node`, `.ele` and `.vtu` files with
/// quadratic triangles (midpoint markers 1 on the hull, attributes averaged).
pub fn write_plain_second_order(
    o: &Opts,
    planned: &[(&'static str, PathBuf)],
    m: &Plain<'_>,
    written: &mut Vec<PathBuf>,
) -> Result<(), Failure> {
    let q = Quadratic::new(m.points, m.triangles, m.neighbors);
    let hull = hull_edge_keys(m.triangles, m.neighbors);
    let na = m.node.n_attributes;
    let mut pts = m.points.to_vec();
    pts.extend_from_slice(&q.points);
    let mut at = m.node.attributes.clone();
    let mut mk = m.markers.to_vec();
    for e in &q.edges {
        for k in 0..na {
            at.push(0.5 * (at[e[0] as usize * na + k] + at[e[1] as usize * na + k]));
        }
        mk.push(i32::from(hull.binary_search(&edge_key(e[0], e[1])).is_ok()));
    }
    let bound = !o.out().no_bound;
    for (kind, path) in planned {
        match *kind {
            "node" => write(path, written, |f| {
                delone_io::write_node(f, &pts, &at, na, bound.then_some(&mk[..]), m.first)
            })?,
            "ele" => write(path, written, |f| {
                delone_io::write_ele(f, &q.triangles, &[], 0, m.first)
            })?,
            "vtu" => {
                let pd = [DataArray {
                    name: "marker",
                    values: Values::Int32(&mk),
                }];
                let fmt = if o.vtu_ascii {
                    VtuFormat::Ascii
                } else {
                    VtuFormat::Binary
                };
                write(path, written, |f| {
                    delone_io::write_vtu(
                        f,
                        &pts,
                        &q.vtk_order(),
                        &pd[..usize::from(bound)],
                        &[],
                        fmt,
                    )
                })?
            }
            _ => {}
        }
    }
    Ok(())
}

/// With `-V` or `--stats-json FILE`: the statistics (JSON written to FILE).
pub fn stats_if(
    o: &Opts,
    points: &[[f64; 2]],
    triangles: &[[u32; 3]],
    steiner: Option<SteinerCounts>,
    written: &mut Vec<PathBuf>,
) -> Result<Option<TriStats>, Failure> {
    if o.out().verbose == 0 && o.stats_json.is_none() {
        return Ok(None);
    }
    let mut s =
        TriStats::new(points, triangles).map_err(|e| fail(format!("internal error: {e}")))?;
    if let Some(st) = steiner {
        s = s.with_steiner(st);
    }
    if let Some(path) = &o.stats_json {
        let text = stats_json(&s);
        crate::guard::write_bytes(path, text.as_bytes())?;
        written.push(path.clone());
    }
    Ok(Some(s))
}

fn json_num(x: f64) -> String {
    if x.is_finite() {
        format!("{x:?}")
    } else {
        "null".into()
    }
}

/// Adds the refinement's outcome to the `--stats-json` file `path` (a
/// `"refinement"` object: whether the bounds are met, whether the Steiner
/// budget stopped it, the budget, and the triangles missing the bounds by
/// bound and by reason).
pub fn add_refinement_json(
    path: &Path,
    min_angle: Option<f64>,
    r: &delone::tri::refine::RefineReport,
) -> Result<(), Failure> {
    use delone::tri::refine::UnfixableReason as U;
    let text = std::fs::read_to_string(path)
        .map_err(|e| fail(format!("cannot read {}: {e}", path.display())))?;
    let Some(body) = text.trim_end().strip_suffix('}') else {
        return Ok(());
    };
    let q = min_angle.unwrap_or(0.0);
    let below = r
        .unfixable
        .iter()
        .filter(|u| q > 0.0 && u.min_angle < q)
        .count();
    let n = |f: fn(&U) -> bool| r.unfixable.iter().filter(|u| f(&u.reason)).count();
    let j = format!(
        "{},\n  \"refinement\": {{\"met\": {}, \"budget_exhausted\": {}, \"steiner_budget\": {}, \"steiner_points\": {}, \"unmet_triangles\": {}, \"below_min_angle\": {below}, \"above_max_area\": {}, \"by_reason\": {{\"small_input_angle\": {}, \"steiner_budget\": {}, \"precision\": {}, \"no_segment_splits\": {}, \"conforming_delaunay\": {}}}}}\n}}\n",
        body.trim_end(),
        r.met,
        r.limit_reached,
        r.steiner_budget,
        r.segment_splits + r.circumcenters,
        r.unfixable.len(),
        r.unfixable.len() - below,
        n(|x| matches!(x, U::SmallInputAngle { .. })),
        n(|x| matches!(x, U::SteinerLimit)),
        n(|x| matches!(x, U::Precision)),
        n(|x| matches!(x, U::NoSegmentSplits)),
        n(|x| matches!(x, U::ConformingDelaunay)),
    );
    std::fs::write(path, j).map_err(|e| fail(format!("cannot write {}: {e}", path.display())))
}

/// The statistics as JSON with a fixed key order.
pub fn stats_json(s: &TriStats) -> String {
    let mut j = String::from("{\n");
    let ints = [
        ("vertices", s.vertices),
        ("triangles", s.triangles),
        ("edges", s.edges),
        ("boundary_edges", s.boundary_edges),
    ];
    for (k, v) in ints {
        j += &format!("  \"{k}\": {v},\n");
    }
    let floats = [
        ("min_area", s.min_area),
        ("max_area", s.max_area),
        ("total_area", s.total_area),
        ("shortest_edge", s.shortest_edge),
        ("longest_edge", s.longest_edge),
        ("shortest_altitude", s.shortest_altitude),
        ("min_angle", s.min_angle),
        ("max_angle", s.max_angle),
        ("min_aspect_ratio", s.min_aspect_ratio),
        ("max_aspect_ratio", s.max_aspect_ratio),
        ("max_radius_edge", s.max_radius_edge),
    ];
    for (k, v) in floats {
        j += &format!("  \"{k}\": {},\n", json_num(v));
    }
    let list = |v: &[usize]| {
        v.iter()
            .map(|c| c.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    j += &format!(
        "  \"angle_histogram\": {{\"bin_degrees\": 10, \"counts\": [{}]}},\n",
        list(&s.angle_histogram)
    );
    let bounds: Vec<String> = ASPECT_BINS.iter().map(|&b| json_num(b)).collect();
    j += &format!(
        "  \"aspect_ratio_histogram\": {{\"measure\": \"longest edge / shortest altitude\", \"upper_bounds\": [{}], \"counts\": [{}]}},\n",
        bounds.join(", "),
        list(&s.aspect_histogram)
    );
    match &s.steiner {
        Some(st) => {
            j += &format!(
                "  \"steiner_points\": {{\"crossings\": {}, \"segment_splits\": {}, \"interior\": {}, \"total\": {}}}\n",
                st.crossings,
                st.segment_splits,
                st.interior,
                st.total()
            )
        }
        None => j += "  \"steiner_points\": null\n",
    }
    j += "}\n";
    j
}

/// The minimum-angle colour classes of `--svg-quality`: upper bound
/// (degrees), colour, legend label.
pub const QUALITY_CLASSES: [(f64, [u8; 3], &str); 6] = [
    (10.0, [215, 25, 28], "< 10°"),
    (20.0, [253, 174, 97], "10-20°"),
    (30.0, [255, 255, 191], "20-30°"),
    (40.0, [171, 221, 164], "30-40°"),
    (50.0, [102, 194, 165], "40-50°"),
    (f64::INFINITY, [50, 136, 189], ">= 50°"),
];

/// The `--svg-quality` colour of a triangle with this minimum angle.
pub fn quality_colour(min_angle: f64) -> [u8; 3] {
    QUALITY_CLASSES
        .iter()
        .find(|c| min_angle < c.0)
        .map_or(QUALITY_CLASSES[5].1, |c| c.1)
}

/// What a `-p` picture shows.
pub struct Picture<'a> {
    /// Mesh points.
    pub points: &'a [[f64; 2]],
    /// Mesh triangles.
    pub triangles: &'a [[u32; 3]],
    /// Segments drawn thick.
    pub segments: &'a [[u32; 2]],
    /// Hole seeds drawn as crosses.
    pub holes: &'a [[f64; 2]],
}

/// The picture style for `o` (`--png-width`).
pub fn style(o: &Opts) -> SvgStyle {
    SvgStyle {
        width: o.png_width.map_or(800.0, f64::from),
        ..SvgStyle::default()
    }
}

/// Writes `layers` to `--svg FILE` and `--png FILE`.
pub fn emit(
    o: &Opts,
    view: [[f64; 2]; 2],
    layers: &[SvgLayer<'_>],
    written: &mut Vec<PathBuf>,
) -> Result<(), Failure> {
    let st = style(o);
    if let Some(path) = &o.svg {
        write(path, written, |f| {
            delone_io::write_svg(f, view, layers, &st)
        })?;
    }
    if let Some(path) = &o.png {
        write(path, written, |f| {
            delone_io::write_png(std::io::BufWriter::new(f), view, layers, &st)
        })?;
    }
    Ok(())
}

/// The view widened on the left so that the legend box (about 124 px from
/// the picture's left margin) does not cover the mesh.
pub fn legend_room(view: [[f64; 2]; 2], o: &Opts) -> [[f64; 2]; 2] {
    let px = style(o).width;
    let w = view[1][0] - view[0][0];
    let room = 124.0;
    if px <= 2.0 * room {
        return view;
    }
    let e = room * w / (px - room);
    [[view[0][0] - e, view[0][1]], view[1]]
}

/// `--svg` / `--png` of a `-p` mesh.
pub fn pictures(o: &Opts, pic: &Picture<'_>, written: &mut Vec<PathBuf>) -> Result<(), Failure> {
    if o.svg.is_none() && o.png.is_none() {
        return Ok(());
    }
    let used: Vec<[f64; 2]> = pic
        .triangles
        .iter()
        .flatten()
        .map(|&v| pic.points[v as usize])
        .chain(
            pic.segments
                .iter()
                .flatten()
                .map(|&v| pic.points[v as usize]),
        )
        .collect();
    let b = crate::tri_out::bbox(if used.is_empty() { pic.points } else { &used });
    let pad = 0.02 * (b[1][0] - b[0][0]).max(b[1][1] - b[0][1]);
    let view = [
        [b[0][0] - pad, b[0][1] - pad],
        [b[1][0] + pad, b[1][1] + pad],
    ];
    let fills: Vec<[u8; 3]> = if o.svg_quality {
        pic.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| pic.points[v as usize]);
                quality_colour(TriangleQuality::new(a, b, c).min_angle)
            })
            .collect()
    } else {
        vec![[232, 238, 247]; pic.triangles.len()]
    };
    let nt = pic.triangles.len().max(1) as f64;
    let thin = (40.0 / nt.sqrt()).clamp(0.15, 0.8);
    let legend: Vec<([u8; 3], &str)> = QUALITY_CLASSES.iter().map(|c| (c.1, c.2)).collect();
    let mut layers = vec![
        SvgLayer::FilledTriangles {
            points: pic.points,
            triangles: pic.triangles,
            fills: &fills,
        },
        SvgLayer::Triangles {
            points: pic.points,
            triangles: pic.triangles,
            stroke: "#333333",
            width: thin,
        },
        SvgLayer::Segments {
            points: pic.points,
            segments: pic.segments,
            stroke: "#1f3f9f",
            width: 2.0,
        },
        SvgLayer::Crosses {
            points: pic.holes,
            size: 5.0,
            stroke: "#d00000",
            width: 2.0,
        },
    ];
    if o.svg_quality {
        layers.push(SvgLayer::Legend { entries: &legend });
    }
    let view = if o.svg_quality {
        legend_room(view, o)
    } else {
        view
    };
    emit(o, view, &layers, written)
}

/// Bounding box of `pts` (a unit box around a single point).
pub fn bbox(pts: &[[f64; 2]]) -> [[f64; 2]; 2] {
    let mut b = [[f64::INFINITY; 2], [f64::NEG_INFINITY; 2]];
    for p in pts {
        for k in 0..2 {
            b[0][k] = b[0][k].min(p[k]);
            b[1][k] = b[1][k].max(p[k]);
        }
    }
    let [mut lo, mut hi] = b;
    for (l, h) in lo.iter_mut().zip(hi.iter_mut()) {
        // An empty or flat extent (no points, or all on one line).
        if (*h).partial_cmp(l) != Some(std::cmp::Ordering::Greater) {
            let c = if l.is_finite() { *l } else { 0.0 };
            *l = c - 0.5;
            *h = c + 0.5;
        }
    }
    [lo, hi]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit square split by its diagonal 0-2, plus the midpoint 4 of
    /// the bottom edge: triangles [0,4,2], [4,1,2], [0,2,3].
    type Mesh = (Vec<[f64; 2]>, Vec<[u32; 3]>, Vec<[u32; 3]>);

    fn square() -> Mesh {
        let pts = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.0]];
        let tris = vec![[0, 4, 2], [4, 1, 2], [0, 2, 3]];
        let nbrs = vec![[1, 2, NONE], [NONE, 0, NONE], [NONE, NONE, 0]];
        (pts, tris, nbrs)
    }

    #[test]
    fn markers_follow_triangles_rule() {
        let (pts, tris, nbrs) = square();
        // Bottom segment 0-1 (split at 4) has marker 5; right side 1-2 has
        // marker 0; point 3 has its own marker 7; the diagonal is a segment
        // with marker 9 (interior).
        let subsegs = [([0, 4], 5), ([4, 1], 5), ([1, 2], 0), ([0, 2], 9)];
        let m = vertex_markers(pts.len(), &[0, 0, 0, 7], &subsegs, &tris, &nbrs);
        assert_eq!(m, vec![5, 5, 9, 7, 5]);
        let edges = [[0, 4], [4, 2], [2, 0], [4, 1], [1, 2], [2, 3], [3, 0]];
        let boundary = [true, false, false, true, true, true, true];
        let em = edge_markers(&edges, &boundary, &subsegs);
        assert_eq!(em, vec![5, 0, 9, 5, 1, 1, 1]);
    }

    #[test]
    fn quadratic_nodes_in_triangle_order() {
        let (pts, tris, nbrs) = square();
        let q = Quadratic::new(&pts, &tris, &nbrs);
        // Triangle 0 = [0,4,2]: midpoints of 4-2 (5), 2-0 (6), 0-4 (7).
        assert_eq!(q.triangles[0], [0, 4, 2, 5, 6, 7]);
        // Triangle 1 = [4,1,2]: 1-2 new (8), 2-4 shared with triangle 0's
        // node 5, 4-1 new (9).
        assert_eq!(q.triangles[1], [4, 1, 2, 8, 5, 9]);
        // Triangle 2 = [0,2,3]: 2-3 (10), 3-0 (11), 0-2 shared (6).
        assert_eq!(q.triangles[2], [0, 2, 3, 10, 11, 6]);
        assert_eq!(q.points.len(), 7);
        assert_eq!(q.points[0], [0.75, 0.5]);
        assert_eq!(q.points[1], [0.5, 0.5]);
        assert_eq!(q.points[2], [0.25, 0.0]);
        assert_eq!(q.vtk_order()[0], [0, 4, 2, 7, 5, 6]);
    }

    #[test]
    fn locator_finds_containing_triangle() {
        let (pts, tris, _) = square();
        let loc = Locator::new(&pts, &tris);
        let (t, l) = loc.locate([0.9, 0.5]).unwrap();
        assert_eq!(t, 1);
        assert!(l.iter().all(|&x| x >= 0.0));
        let (t, _) = loc.locate([0.1, 0.6]).unwrap();
        assert_eq!(t, 2);
    }

    #[test]
    fn json_is_ordered_and_null_for_infinity() {
        let s = TriStats::new(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], &[[0, 1, 2]]).unwrap();
        let j = stats_json(&s);
        assert!(j.starts_with("{\n  \"vertices\": 3,\n  \"triangles\": 1,"));
        assert!(j.contains("\"min_angle\": 45.0"), "{j}");
        assert!(j.contains("\"counts\": [0, 0, 0, 0, 2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0]"));
        assert!(j.contains("1000.0, null]"), "{j}");
        assert!(j.contains("\"steiner_points\": null"));
        assert_eq!(quality_colour(5.0), QUALITY_CLASSES[0].1);
        assert_eq!(quality_colour(35.0), QUALITY_CLASSES[3].1);
        assert_eq!(quality_colour(60.0), QUALITY_CLASSES[5].1);
    }
}
