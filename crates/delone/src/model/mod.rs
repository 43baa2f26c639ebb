//! Input models shared by the file readers (`delone-io`) and the meshers:
//! planar straight-line graphs in 2D ([`pslg`]) and piecewise linear complexes
//! in 3D ([`plc`]).

pub mod plc;
pub mod pslg;

use crate::Error;

/// The checks both models start with: finite points within the range the
/// predicates allow (`range`, see [`crate::geom::scale::check_range`]),
/// then finite hole and region points ([`Error::InvalidCoordinate`],
/// [`Error::CoordinateRange`], [`Error::InvalidSeedPoint`]).
pub(crate) fn check_coordinates<const D: usize>(
    points: &[[f64; D]],
    range: i32,
    holes: &[[f64; D]],
    mut regions: impl Iterator<Item = [f64; D]>,
) -> Result<(), Error> {
    let finite = |p: &[f64; D]| p.iter().all(|c| c.is_finite());
    if let Some(index) = points.iter().position(|p| !finite(p)) {
        return Err(Error::InvalidCoordinate { index });
    }
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
