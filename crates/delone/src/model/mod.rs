//! Input models shared by the file readers (`delone-io`) and the meshers:
//! planar straight-line graphs in 2D ([`pslg`]) and piecewise linear complexes
//! in 3D ([`plc`]).

pub mod plc;
pub mod pslg;
