//! Planar straight-line graphs (2D meshing input).
//!
//! A [`Pslg`] is plain data: points (with optional markers), segments joining
//! two points (with optional markers), hole points and region points. It is
//! what a Triangle `.poly` file holds; `delone-io` reads the file and the
//! caller fills a `Pslg` from it.

use crate::Error;

/// A region seed: every triangle reachable from `point` without crossing a
/// segment gets `attribute` (Triangle's `-A`) and `max_area` (`-a`).
///
/// ```
/// let r = delone::model::pslg::Region { point: [0.5, 0.5], attribute: 2.0, max_area: -1.0 };
/// assert_eq!(r.attribute, 2.0);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Region {
    /// A point inside the region.
    pub point: [f64; 2],
    /// Regional attribute given to the region's triangles.
    pub attribute: f64,
    /// Area bound of the region's triangles (negative: none).
    pub max_area: f64,
}

/// A planar straight-line graph: the input of the constrained triangulation.
///
/// `point_markers` and `segment_markers` are either empty (all zero) or as
/// long as `points` / `segments`.
///
/// ```
/// use delone::model::pslg::Pslg;
/// let mut g = Pslg::default();
/// g.points = vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
/// g.segments = vec![[0, 1], [1, 2], [2, 0]];
/// g.validate().unwrap();
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Pslg {
    /// Vertex coordinates.
    pub points: Vec<[f64; 2]>,
    /// Boundary marker of every point (empty: all zero).
    pub point_markers: Vec<i32>,
    /// Segments as pairs of 0-based point indices.
    pub segments: Vec<[u32; 2]>,
    /// Boundary marker of every segment (empty: all zero).
    pub segment_markers: Vec<i32>,
    /// Hole points: the triangles reachable from them without crossing a
    /// segment are removed.
    pub holes: Vec<[f64; 2]>,
    /// Region seeds (attributes and area bounds).
    pub regions: Vec<Region>,
}

impl Pslg {
    /// A PSLG with the given points and segments, no markers, holes or regions.
    ///
    /// ```
    /// let g = delone::model::pslg::Pslg::new(vec![[0.0, 0.0], [1.0, 0.0]], vec![[0, 1]]);
    /// assert_eq!(g.segment_marker(0), 0);
    /// ```
    pub fn new(points: Vec<[f64; 2]>, segments: Vec<[u32; 2]>) -> Self {
        Pslg {
            points,
            segments,
            ..Pslg::default()
        }
    }

    /// Marker of point `i` (0 if markers are absent).
    ///
    /// ```
    /// let mut g = delone::model::pslg::Pslg::new(vec![[0.0, 0.0]], vec![]);
    /// g.point_markers = vec![7];
    /// assert_eq!(g.point_marker(0), 7);
    /// ```
    pub fn point_marker(&self, i: usize) -> i32 {
        self.point_markers.get(i).copied().unwrap_or(0)
    }

    /// Marker of segment `s` (0 if markers are absent).
    ///
    /// ```
    /// let mut g = delone::model::pslg::Pslg::new(vec![[0.0, 0.0], [1.0, 1.0]], vec![[0, 1]]);
    /// g.segment_markers = vec![3];
    /// assert_eq!(g.segment_marker(0), 3);
    /// ```
    pub fn segment_marker(&self, s: usize) -> i32 {
        self.segment_markers.get(s).copied().unwrap_or(0)
    }

    /// Checks the input strictly: finite coordinates (points, holes,
    /// regions), segment ends in range, no zero-length segment, no duplicate
    /// points (same coordinates), no duplicate segments (same two ends in
    /// either order). Reports the first problem found, naming the item.
    ///
    /// The constrained triangulation itself is more lenient (it merges
    /// duplicate points and skips duplicate segments, reporting both); this
    /// is the check for callers who want clean input.
    ///
    /// # Errors
    /// [`Error::InvalidCoordinate`], [`Error::InvalidSeedPoint`],
    /// [`Error::SegmentOutOfRange`], [`Error::ZeroLengthSegment`],
    /// [`Error::DuplicateVertex`], [`Error::DuplicateSegment`].
    ///
    /// ```
    /// use delone::{model::pslg::Pslg, Error};
    /// let g = Pslg::new(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 0.0]], vec![[0, 1]]);
    /// assert_eq!(g.validate(), Err(Error::DuplicateVertex { index: 2, original: 0 }));
    /// let g = Pslg::new(vec![[0.0, 0.0], [1.0, 0.0]], vec![[0, 1], [1, 0]]);
    /// assert_eq!(g.validate(), Err(Error::DuplicateSegment { index: 1, original: 0 }));
    /// let g = Pslg::new(vec![[0.0, 0.0], [1.0, 0.0]], vec![[0, 5]]);
    /// assert_eq!(g.validate(), Err(Error::SegmentOutOfRange { segment: 0, point: 5 }));
    /// ```
    pub fn validate(&self) -> Result<(), Error> {
        self.check_values()?;
        // Duplicate points: the first point that is not its own canonical id.
        let canon = super::canonical_ids(&self.points);
        if let Some(index) = (0..canon.len()).find(|&i| canon[i] as usize != i) {
            let original = canon[index] as usize;
            return Err(Error::DuplicateVertex { index, original });
        }
        for (s, seg) in self.segments.iter().enumerate() {
            if seg[0] == seg[1] {
                return Err(Error::ZeroLengthSegment { segment: s });
            }
        }
        let mut segs: Vec<(u32, u32, u32)> = self
            .segments
            .iter()
            .enumerate()
            .map(|(s, e)| (e[0].min(e[1]), e[0].max(e[1]), s as u32))
            .collect();
        segs.sort_unstable();
        // The smallest index that repeats an earlier segment (the first of
        // its run).
        let first = (segs.chunk_by(|a, b| (a.0, a.1) == (b.0, b.1)))
            .flat_map(|run| run[1..].iter().map(|x| (x.2 as usize, run[0].2 as usize)))
            .min();
        if let Some((index, original)) = first {
            return Err(Error::DuplicateSegment { index, original });
        }
        Ok(())
    }

    /// The checks every mesher needs: finite points within the range the
    /// predicates allow, finite hole and region points, segment ends in
    /// range ([`Error::InvalidCoordinate`], [`Error::InvalidSeedPoint`],
    /// [`Error::SegmentOutOfRange`]; duplicates are the mesher's business).
    pub(crate) fn check_values(&self) -> Result<(), Error> {
        super::check_coordinates(
            &self.points,
            &self.holes,
            self.regions.iter().map(|r| r.point),
        )?;
        self.check_segment_ends()
    }

    /// Segment ends in range.
    fn check_segment_ends(&self) -> Result<(), Error> {
        let n = self.points.len();
        for (s, seg) in self.segments.iter().enumerate() {
            for &v in seg {
                if v as usize >= n {
                    return Err(Error::SegmentOutOfRange {
                        segment: s,
                        point: v as usize,
                    });
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validate_reports_each_problem() {
        let mut g = Pslg::new(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], vec![[0, 1]]);
        assert_eq!(g.validate(), Ok(()));
        g.points[1][0] = f64::NAN;
        assert_eq!(g.validate(), Err(Error::InvalidCoordinate { index: 1 }));
        g.points[1][0] = 1.0;
        g.segments.push([2, 2]);
        assert_eq!(g.validate(), Err(Error::ZeroLengthSegment { segment: 1 }));
        g.segments.pop();
        g.holes.push([f64::INFINITY, 0.0]);
        assert_eq!(
            g.validate(),
            Err(Error::InvalidSeedPoint {
                kind: "hole",
                index: 0
            })
        );
        g.holes.clear();
        g.points.push([0.0, 1.0]);
        g.points.push([0.0, 1.0]);
        assert_eq!(
            g.validate(),
            Err(Error::DuplicateVertex {
                index: 3,
                original: 2
            })
        );
    }
}
