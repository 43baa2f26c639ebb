//! Consistency of a (points, mesh) pair handed to post-processing
//! (Voronoi and power diagrams), and the vertex bookkeeping the 2D and 3D
//! validators share (`check_vertices`).

use crate::geom::key;
use crate::{Error, Violation, NONE};

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

/// The vertex bookkeeping of a flat mesh of `points` (with `weights`, a
/// regular one) whose elements use the points `used`: equal points (with
/// equal weights) are represented by the smallest index; every point maps
/// in `vertex_map` to its representative, which is a vertex, or (with
/// weights) to [`NONE`] when the representative is no vertex (hidden,
/// with its duplicates); no duplicate is a vertex; `duplicates` and
/// `hidden` list exactly the duplicates and the hidden points, in order.
pub(crate) fn check_vertices<const D: usize>(
    points: &[[f64; D]],
    weights: Option<&[f64]>,
    used: &[bool],
    vertex_map: &[u32],
    duplicates: &[(u32, u32)],
    hidden: &[u32],
) -> Result<(), Violation> {
    let n = points.len();
    let err = |kind, detail: String| Err(Violation::new(kind, detail));
    let wkey = |i: usize| weights.map_or(0, |w| (w[i] + 0.0).to_bits());
    let mut ids: Vec<u32> = (0..n as u32).collect();
    ids.sort_unstable_by_key(|&i| (key(&points[i as usize]), wkey(i as usize), i));
    let same = |i: u32, j: u32| {
        key(&points[i as usize]) == key(&points[j as usize]) && wkey(i as usize) == wkey(j as usize)
    };
    let mut rep = vec![0u32; n];
    for (k, &i) in ids.iter().enumerate() {
        rep[i as usize] = if k > 0 && same(ids[k - 1], i) {
            rep[ids[k - 1] as usize]
        } else {
            i
        };
    }
    let mut expected_dups = Vec::new();
    let mut expected_hidden = Vec::new();
    for i in 0..n {
        let (r, m) = (rep[i], vertex_map[i]);
        if weights.is_some() && !used[r as usize] {
            // Hidden (with all its duplicates).
            if m != NONE {
                return err(
                    "vertex_map",
                    format!("point {i} is not a vertex, but maps to {m}"),
                );
            }
            expected_hidden.push(i as u32);
            continue;
        }
        if m != r {
            return err(
                "vertex_map",
                format!("point {i} maps to {m} instead of {r}"),
            );
        }
        if r as usize == i {
            if !used[i] {
                return err("vertex", format!("point {i} is not used by any element"));
            }
        } else {
            if used[i] {
                return err(
                    "vertex",
                    format!("duplicate point {i} (of {r}) is used by an element"),
                );
            }
            expected_dups.push((i as u32, r));
        }
    }
    let list = |kind: &'static str, got: usize, want: usize| {
        err(
            kind,
            format!("{kind} list has {got} entries, expected {want}"),
        )
    };
    if duplicates != expected_dups {
        return list("duplicates", duplicates.len(), expected_dups.len());
    }
    if hidden != expected_hidden {
        return list("hidden", hidden.len(), expected_hidden.len());
    }
    Ok(())
}
