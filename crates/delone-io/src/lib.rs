//! # delone-io
//!
//! File formats for delone, working on plain slices (no dependency on the
//! mesher):
//!
//! * Triangle/TetGen family: [`read_node`], [`read_ele`], [`write_node`],
//!   [`write_ele`], [`write_neigh`], [`write_edge`], [`write_face`],
//!   [`read_poly`], [`write_poly`], [`read_face`], [`read_mtr`] (sizes), with the
//!   derived edges and faces from [`topo`];
//! * 3D PLCs: [`read_poly3d`] (TetGen `.poly`) and [`read_smesh`] into a
//!   [`PlcFile`];
//! * surfaces into a [`Surface`]: [`read_off`], [`read_stl`] (ASCII and
//!   binary), [`read_ply`] (ASCII and binary), [`read_obj`], [`read_medit`],
//!   or [`read_surface`] by file extension;
//! * Voronoi diagrams: [`write_voronoi_node`], [`write_voronoi_edge`]
//!   (Triangle and TetGen `-v`), [`write_voronoi_face`], [`write_voronoi_cell`]
//!   (TetGen);
//! * pictures: [`write_svg`] (2D triangles, polygons, points);
//! * volume meshes for other tools: [`write_medit`] (Medit `.mesh`) and
//!   [`write_gmsh`] and [`write_gmsh_2d`] (Gmsh `.msh` 4.1 ASCII);
//! * Medit meshes and fields as MMG reads and writes them: [`read_medit_mesh`],
//!   [`write_medit_mesh`] (2D and 3D, with references, corners, ridges,
//!   required entities) and [`read_medit_sol`], [`write_medit_sol`]
//!   (`.sol`: sizes, metric tensors, solution fields at the vertices);
//! * pictures: one scene ([`SvgLayer`]s: triangles, filled triangles,
//!   polygons, segments, points, crosses, a legend) and two back ends,
//!   [`write_svg`] and [`write_png`] (our own rasterizer, [`render`]);
//! * cut-away pictures of tetrahedral meshes: [`render_tets`] (depth
//!   buffer, flat shading, faces exposed by the cut coloured per
//!   tetrahedron);
//! * VTK: [`write_vtu`] (XML, ASCII or raw binary appended) and
//!   [`write_vtk_legacy`] (TetGen's `-k` output).
//!
//! Readers never panic on any input and report errors with line numbers;
//! writers buffer internally, format integers by hand and floats in their
//! shortest round-trip form, so output is deterministic and fast.
//!
//! ```
//! let node = delone_io::read_node(b"3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n").unwrap();
//! let pts = node.points::<2>().unwrap();
//! let tris = [[0u32, 1, 2]];
//! let mut ele = Vec::new();
//! delone_io::write_ele(&mut ele, &tris, &[], 0, node.first_index).unwrap();
//! assert_eq!(String::from_utf8(ele).unwrap(), "1 3 0\n1 1 2 3\n");
//! # let _ = pts;
//! ```
#![forbid(unsafe_code)]

mod area;
mod error;
mod gmsh;
mod medit;
mod msh_read;
mod mtr;
mod obj;
mod off;
mod out;
mod par;
mod plc;
mod ply;
mod poly;
mod raster;
mod read;
mod render3d;
mod stl;
mod surface;
mod svg;
pub mod topo;
mod voronoi;
mod vtk;
mod vtu_read;
mod write;

pub use area::read_area;
pub use error::IoError;
pub use gmsh::{write_gmsh, write_gmsh_2d};
pub use medit::{
    read_medit, read_medit_mesh, read_medit_sol, write_medit, write_medit_mesh, write_medit_sol,
    MeditMesh, MeditSol, SolField, SolKind,
};
pub use msh_read::read_gmsh;
pub use mtr::{read_face, read_mtr, FaceFile};
pub use obj::read_obj;
pub use off::read_off;
pub use plc::{read_poly3d, read_smesh, PlcFacet, PlcFile, PlcRegion};
pub use ply::read_ply;
pub use poly::{read_poly, write_poly, PolyFile};
pub use raster::{render, write_png, write_raster_png, Raster};
pub use read::{read_ele, read_node, read_node_threads, EleFile, NodeFile};
pub use render3d::{render_tets, CutawayStyle};
pub use stl::read_stl;
pub use surface::{read_surface, Surface};
pub use svg::{parse_colour, write_svg, SvgLayer, SvgStyle};
pub use voronoi::{write_voronoi_cell, write_voronoi_edge, write_voronoi_face, write_voronoi_node};
pub use vtk::{
    write_vtk_legacy, write_vtu, write_vtu_polyhedra, write_vtu_with_faces, DataArray,
    PolyhedronRef, Values, VtuFormat,
};
pub use vtu_read::{read_vtu, VtuArray};
pub use write::{
    write_edge, write_ele, write_ele_threads, write_face, write_neigh, write_node,
    write_node_threads,
};
