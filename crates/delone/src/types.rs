//! Small types shared by the 2D and 3D kernels.

/// What became of a point given to an incremental kernel
/// ([`crate::tri::Delaunay2::insert`], [`crate::tet::Delaunay3::insert`]). Ids are indices
/// among all points given so far.
///
/// ```
/// use delone::{tri::Delaunay2, Inserted};
/// let mut d = Delaunay2::new();
/// assert_eq!(d.insert([0.0, 0.0]).unwrap(), Inserted::Pending(0));
/// assert_eq!(d.insert([0.0, 0.0]).unwrap(), Inserted::Duplicate { id: 1, original: 0 });
/// assert_eq!(d.insert([1.0, 0.0]).unwrap(), Inserted::Pending(2));
/// assert_eq!(d.insert([0.0, 1.0]).unwrap(), Inserted::Vertex(3));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Inserted {
    /// The point became vertex `id`.
    Vertex(u32),
    /// The point has the same coordinates as an earlier point and was not
    /// inserted (it still gets an id).
    Duplicate {
        /// Id of the duplicate point.
        id: u32,
        /// The vertex (or pending point) it coincides with.
        original: u32,
    },
    /// No triangle/tetrahedron exists yet (all points so far are collinear /
    /// coplanar); the point is kept and becomes a vertex as soon as one does.
    Pending(u32),
    /// Regular (weighted) triangulations only: the point's power cell is
    /// empty, so it is not a vertex ("hidden" or redundant point).
    Hidden(u32),
}

/// Marker for "no element" in index arrays (a missing neighbour, an unused slot).
pub const NONE: u32 = u32::MAX;
