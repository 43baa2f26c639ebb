//! Piecewise linear complexes (3D meshing input).
