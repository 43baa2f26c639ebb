//! Consistency of a (points, mesh) pair handed to post-processing
//! (Voronoi and power diagrams).

use crate::{Error, NONE};

/// Checks that `cells` name only existing points, that `neighbors` has one
/// row per cell naming existing cells (or [`NONE`]), that `vertex_map` has
/// one entry per point, and that `weights` (if any) has one per point.
///
/// ```
/// use delone::geom::check::mesh_fits;
/// let cells = [[0u32, 1, 2]];
/// let nb = [[delone::NONE; 3]];
/// assert!(mesh_fits(3, &cells, &nb, 3, None).is_ok());
/// assert!(mesh_fits(2, &cells, &nb, 2, None).is_err());
/// ```
pub fn mesh_fits<const K: usize>(
    points: usize,
    cells: &[[u32; K]],
    neighbors: &[[u32; K]],
    vertex_map: usize,
    weights: Option<usize>,
) -> Result<(), Error> {
    let bad = |reason: String| Err(Error::InconsistentMesh { reason });
    if neighbors.len() != cells.len() {
        return bad(format!(
            "{} cells but {} neighbour rows",
            cells.len(),
            neighbors.len()
        ));
    }
    if vertex_map != points {
        return bad(format!("{points} points but a vertex map of {vertex_map}"));
    }
    if let Some(w) = weights {
        if w != points {
            return Err(Error::WeightCount { points, weights: w });
        }
    }
    for (t, (c, nb)) in cells.iter().zip(neighbors).enumerate() {
        if let Some(&v) = c.iter().find(|&&v| v as usize >= points) {
            return bad(format!(
                "cell {t} names point {v}, but there are {points} points"
            ));
        }
        if let Some(&u) = nb.iter().find(|&&u| u != NONE && u as usize >= cells.len()) {
            return bad(format!(
                "cell {t} names neighbour {u}, but there are {} cells",
                cells.len()
            ));
        }
    }
    Ok(())
}

/// [`Error::InvalidCoordinate`] naming the first point of `points` with a
/// NaN or infinite coordinate.
pub(crate) fn finite<const D: usize>(points: &[[f64; D]]) -> Result<(), Error> {
    match points.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
        Some(index) => Err(Error::InvalidCoordinate { index }),
        None => Ok(()),
    }
}

/// [`Error::IndexOutOfRange`] naming the first of `ids` (the corners of
/// item `index`, e.g. a `"facet"`) that is not below `points`.
pub(crate) fn ids_in_range(
    item: &'static str,
    index: usize,
    ids: &[u32],
    points: usize,
) -> Result<(), Error> {
    match ids.iter().find(|&&v| v as usize >= points) {
        Some(&vertex) => Err(Error::IndexOutOfRange {
            item,
            index,
            vertex,
            points,
        }),
        None => Ok(()),
    }
}

/// Every corner of every element of `elements` (items `item`) names a point
/// of `points` with finite coordinates: else, for the first corner in order
/// that does not, [`Error::IndexOutOfRange`] or [`Error::InvalidCoordinate`].
pub(crate) fn corners_valid<const D: usize, const K: usize>(
    item: &'static str,
    points: &[[f64; D]],
    elements: &[[u32; K]],
) -> Result<(), Error> {
    for (index, e) in elements.iter().enumerate() {
        for &v in e {
            ids_in_range(item, index, &[v], points.len())?;
            if !points[v as usize].iter().all(|c| c.is_finite()) {
                return Err(Error::InvalidCoordinate { index: v as usize });
            }
        }
    }
    Ok(())
}
