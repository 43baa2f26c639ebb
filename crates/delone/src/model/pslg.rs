//! Planar straight-line graphs (2D meshing input).
