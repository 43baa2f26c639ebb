//! Input models shared by the file readers (`delone-io`) and the meshers:
//! planar straight-line graphs in 2D ([`pslg`]) and piecewise linear complexes
//! in 3D ([`plc`]).

pub mod plc;
pub mod pslg;

use crate::geom::key;
use crate::Error;

/// The checks both models start with: finite points within the range the
/// predicates allow in `D` dimensions (see
/// [`crate::geom::scale::check_range`]), then finite hole and region points
/// ([`Error::InvalidCoordinate`], [`Error::CoordinateRange`],
/// [`Error::InvalidSeedPoint`]).
pub(crate) fn check_coordinates<const D: usize>(
    points: &[[f64; D]],
    holes: &[[f64; D]],
    mut regions: impl Iterator<Item = [f64; D]>,
) -> Result<(), Error> {
    crate::geom::check::finite(points)?;
    let finite = |p: &[f64; D]| p.iter().all(|c| c.is_finite());
    let range = match D {
        2 => crate::geom::scale::RANGE_2D,
        _ => crate::geom::scale::RANGE_3D,
    };
    crate::geom::scale::check_range(points, range)?;
    let seed = |kind, index| Err(Error::InvalidSeedPoint { kind, index });
    if let Some(index) = holes.iter().position(|p| !finite(p)) {
        return seed("hole", index);
    }
    match regions.position(|p| !finite(&p)) {
        Some(index) => seed("region", index),
        None => Ok(()),
    }
}

/// Per point, the smallest index of a point with exactly the same
/// coordinates (`-0.0` and `0.0` are the same): a sort by [`key`], so no
/// hashing and a deterministic result.
pub(crate) fn canonical_ids<const D: usize>(points: &[[f64; D]]) -> Vec<u32> {
    let mut order: Vec<([u64; D], u32)> = points
        .iter()
        .enumerate()
        .map(|(i, p)| (key(p), i as u32))
        .collect();
    order.sort_unstable();
    let mut canon = vec![0u32; points.len()];
    for run in order.chunk_by(|a, b| a.0 == b.0) {
        for &(_, i) in run {
            canon[i as usize] = run[0].1;
        }
    }
    canon
}
