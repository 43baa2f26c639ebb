//! Output files of `delone tet -p`: `.ele` (with `-A` region attributes),
//! `.face` (boundary faces and faces on internal facets with their facet
//! markers; every face with `-f`), `.edge` (`-e`), `.neigh` (`-n`), `.vtu`,
//! Medit `.mesh` (`-g`, `--medit`) and Gmsh `.msh` 4.1 (`--gmsh`).
//!
//! Markers: a face on an input facet carries the facet's marker, any other
//! face 0; an edge carries the marker of the lowest-numbered facet holding
//! it, else 0. Medit references and Gmsh physical tags of the tetrahedra
//! are the region attributes when they are integers (else the region
//! number, from 1).

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use delone::tet::recover::Recovered;
use delone::NONE;

use crate::args::Opts;
use crate::fail::Failure;
use crate::guard::write;
use crate::paths::{face_companion, with_ext};

fn fkey(f: [u32; 3]) -> [u32; 3] {
    let mut k = f;
    k.sort_unstable();
    k
}

/// The recovered mesh with the per-item data its output files need.
pub struct TetOutput<'a> {
    rec: &'a Recovered,
    /// Faces on input facets (boundary first, then interior) and hull faces.
    faces: Vec<[u32; 3]>,
    /// Their markers.
    face_marker: Vec<i32>,
    /// Input triangle of each constraint face (`NONE` for hull faces), via
    /// `Recovered::surface_origin`.
    face_triangle: Vec<u32>,
    /// Per input triangle: its facet's marker.
    tri_marker: &'a [i32],
}

impl<'a> TetOutput<'a> {
    /// The mesh `rec` with its faces on input triangles, their markers
    /// and input triangles (`marked`, as
    /// [`delone::tet::pipeline::marked_faces`] gives them); `tri_marker[t]`
    /// is the marker of input triangle `t`'s facet.
    pub fn new(
        rec: &'a Recovered,
        tri_marker: &'a [i32],
        marked: (Vec<[u32; 3]>, Vec<i32>, Vec<u32>),
    ) -> Self {
        let (faces, face_marker, face_triangle) = marked;
        TetOutput {
            rec,
            faces,
            face_marker,
            face_triangle,
            tri_marker,
        }
    }

    /// Per tetrahedron: its region attribute.
    pub fn attributes(&self) -> Vec<f64> {
        self.rec
            .tet_region
            .iter()
            .map(|&g| self.rec.regions[g as usize].attribute)
            .collect()
    }

    /// Per tetrahedron: an integer reference (attribute if integral, else
    /// region number from 1).
    pub fn tet_refs(&self) -> Vec<i32> {
        self.rec
            .tet_region
            .iter()
            .map(|&g| {
                let a = self.rec.regions[g as usize].attribute;
                if a.fract() == 0.0 && a.abs() <= f64::from(i32::MAX) {
                    a as i32
                } else {
                    g as i32 + 1
                }
            })
            .collect()
    }

    /// Whether the VTK outputs carry the region attribute: with `-A`, or
    /// when the input names regions or the domain has several.
    fn has_regions(&self, o: &Opts) -> bool {
        o.region_attributes()
            || self.rec.regions.len() > 1
            || self.rec.regions.iter().any(|r| r.seed.is_some())
    }

    /// Every face of the mesh once (TetGen `-f`), with markers.
    fn all_faces(&self) -> Result<(Vec<[u32; 3]>, Vec<i32>), Failure> {
        let m = &self.rec.mesh;
        let e = delone_io::topo::tet_faces(&m.tets, &m.neighbors, true).map_err(|e| Failure {
            message: format!("face extraction: {e}"),
            code: 1,
        })?;
        let by: HashMap<[u32; 3], i32> = self
            .faces
            .iter()
            .zip(&self.face_marker)
            .map(|(f, &mk)| (fkey(*f), mk))
            .collect();
        let markers = e
            .items
            .iter()
            .map(|f| by.get(&fkey(*f)).copied().unwrap_or(0))
            .collect();
        Ok((e.items, markers))
    }

    /// Every edge once, with the marker of the lowest-numbered input
    /// triangle (so facet) holding it, else 0.
    fn edges(&self) -> Result<(Vec<[u32; 2]>, Vec<i32>), Failure> {
        let m = &self.rec.mesh;
        let e = delone_io::topo::tet_edges(&m.tets, &m.neighbors).map_err(|e| Failure {
            message: format!("edge extraction: {e}"),
            code: 1,
        })?;
        let mut by: HashMap<(u32, u32), u32> = HashMap::new();
        for (f, &t) in self.faces.iter().zip(&self.face_triangle) {
            if t == NONE {
                continue;
            }
            for k in 0..3 {
                let (a, b) = (f[k], f[(k + 1) % 3]);
                let slot = by.entry((a.min(b), a.max(b))).or_insert(t);
                *slot = (*slot).min(t);
            }
        }
        let markers = e
            .items
            .iter()
            .map(|&[a, b]| {
                by.get(&(a.min(b), a.max(b)))
                    .and_then(|&t| self.tri_marker.get(t as usize).copied())
                    .unwrap_or(0)
            })
            .collect();
        Ok((e.items, markers))
    }

    /// Writes the files `o` asks for (all but `.node`) next to `out`;
    /// returns their paths.
    pub fn write_all(&self, o: &Opts, out: &Path, first: u32) -> Result<Vec<PathBuf>, Failure> {
        let rec = self.rec;
        let mut written = Vec::new();
        if !o.out().no_ele {
            let p = with_ext(out, "ele");
            let attrs = if o.region_attributes() {
                self.attributes()
            } else {
                Vec::new()
            };
            let n = usize::from(o.region_attributes());
            write(&p, |f| {
                delone_io::write_ele(f, &rec.mesh.tets, &attrs, n, first)
            })?;
            written.push(p);
        }
        if !o.tet.no_face {
            let p = with_ext(out, "face");
            let (faces, markers) = if o.tet.all_faces {
                self.all_faces()?
            } else {
                (self.faces.clone(), self.face_marker.clone())
            };
            write(&p, |f| {
                delone_io::write_face(
                    f,
                    &faces,
                    (!o.out().no_bound).then_some(&markers[..]),
                    first,
                )
            })?;
            written.push(p);
            if o.out().edges {
                let p = with_ext(out, "edge");
                let (edges, markers) = self.edges()?;
                write(&p, |f| {
                    delone_io::write_edge(
                        f,
                        &edges,
                        (!o.out().no_bound).then_some(&markers[..]),
                        first,
                    )
                })?;
                written.push(p);
            }
        }
        if o.out().neigh {
            let p = with_ext(out, "neigh");
            write(&p, |f| {
                delone_io::write_neigh(f, &rec.mesh.neighbors, first)
            })?;
            written.push(p);
        }
        // VTK: the tetrahedra with their region attribute as cell data (with
        // -A, or when the input has regions), and a companion file of the
        // faces on input facets with their markers.
        let attrs = if self.has_regions(o) {
            self.attributes()
        } else {
            Vec::new()
        };
        let cd = [delone_io::DataArray {
            name: "region_attribute",
            values: delone_io::Values::Float64(&attrs),
        }];
        let cd = if attrs.is_empty() { &cd[..0] } else { &cd[..] };
        let fd = [delone_io::DataArray {
            name: "boundary_marker",
            values: delone_io::Values::Int32(&self.face_marker),
        }];
        let fmt = if o.vtu_ascii {
            delone_io::VtuFormat::Ascii
        } else {
            delone_io::VtuFormat::Binary
        };
        // --vtu-ascii alone names the .vtu after the output base (as in 2D).
        let vtu = o
            .vtu
            .clone()
            .or_else(|| o.vtu_ascii.then(|| with_ext(out, "vtu")));
        if let Some(p) = &vtu {
            write(p, |f| {
                delone_io::write_vtu(f, &rec.points, &rec.mesh.tets, &[], cd, fmt)
            })?;
            written.push(p.clone());
            let p = face_companion(p);
            write(&p, |f| {
                delone_io::write_vtu(f, &rec.points, &self.faces, &[], &fd, fmt)
            })?;
            written.push(p);
        }
        if o.tet.vtk_legacy {
            let p = with_ext(out, "vtk");
            write(&p, |f| {
                delone_io::write_vtk_legacy(
                    f,
                    &rec.points,
                    &rec.mesh.tets,
                    &[],
                    cd,
                    "delone tet -p",
                )
            })?;
            written.push(p.clone());
            let p = face_companion(&p);
            write(&p, |f| {
                delone_io::write_vtk_legacy(
                    f,
                    &rec.points,
                    &self.faces,
                    &[],
                    &fd,
                    "delone tet -p: faces on input facets",
                )
            })?;
            written.push(p);
        }
        let mut medit = o.medit.clone();
        if o.tet.medit && medit.is_none() {
            medit = Some(with_ext(out, "mesh"));
        }
        if let Some(p) = &medit {
            let refs = self.tet_refs();
            write(p, |f| {
                delone_io::write_medit(
                    f,
                    &rec.points,
                    &self.faces,
                    &self.face_marker,
                    &rec.mesh.tets,
                    &refs,
                )
            })?;
            written.push(p.clone());
        }
        if let Some(p) = &o.gmsh {
            let refs = self.tet_refs();
            write(p, |f| {
                delone_io::write_gmsh(
                    f,
                    &rec.points,
                    &self.faces,
                    &self.face_marker,
                    &rec.mesh.tets,
                    &refs,
                )
            })?;
            written.push(p.clone());
        }
        if let Some(p) = &o.png {
            crate::cutaway::write_png(o, p, &rec.points, &rec.mesh.tets, &mut written)?;
        }
        Ok(written)
    }
}
