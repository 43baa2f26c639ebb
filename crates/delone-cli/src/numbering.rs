//! Messages in the input file's own numbering. The library numbers points,
//! segments and facets from 0; a `.node`/`.poly`/`.ele`/`.smesh`/`.face`
//! file numbers them from its first index (0 or 1), a Medit `.mesh` from 1,
//! OFF/STL/PLY/OBJ facets and points from 0. Every library error about an
//! input goes through [`renumber`] before the CLI prints it.

use delone::{Error, FacetDefect};

/// `e` with every index of an input item shifted by `first` (the file's
/// first index), so that its message names the items as the file does.
pub fn renumber(e: Error, first: u32) -> Error {
    let f = first as usize;
    let v = |x: u32| x.saturating_add(first);
    match e {
        Error::InvalidCoordinate { index } => Error::InvalidCoordinate { index: index + f },
        Error::InvalidWeight { index } => Error::InvalidWeight { index: index + f },
        Error::InvalidSeedPoint { kind, index } => Error::InvalidSeedPoint {
            kind,
            index: index + f,
        },
        Error::IndexOutOfRange {
            item,
            index,
            vertex,
            points,
        } => Error::IndexOutOfRange {
            item,
            index: index + f,
            vertex: v(vertex),
            points,
        },
        Error::DegenerateFacet { index, defect } => Error::DegenerateFacet {
            index: index + f,
            defect: renumber_defect(defect, first),
        },
        Error::SelfIntersection { facets, count } => Error::SelfIntersection {
            facets: (facets.0 + f, facets.1 + f),
            count,
        },
        Error::SegmentOutOfRange { segment, point } => Error::SegmentOutOfRange {
            segment: segment + f,
            point: point + f,
        },
        Error::ZeroLengthSegment { segment } => Error::ZeroLengthSegment {
            segment: segment + f,
        },
        Error::DuplicateVertex { index, original } => Error::DuplicateVertex {
            index: index + f,
            original: original + f,
        },
        Error::DuplicateSegment { index, original } => Error::DuplicateSegment {
            index: index + f,
            original: original + f,
        },
        Error::SegmentIntersection { segment, other } => Error::SegmentIntersection {
            segment: segment + f,
            other: other + f,
        },
        other => other,
    }
}

/// A facet defect with its point index shifted by `first`.
pub fn renumber_defect(d: FacetDefect, first: u32) -> FacetDefect {
    let v = |x: u32| x.saturating_add(first);
    match d {
        FacetDefect::RepeatedVertex { vertex } => FacetDefect::RepeatedVertex { vertex: v(vertex) },
        FacetDefect::NonPlanar { vertex } => FacetDefect::NonPlanar { vertex: v(vertex) },
        FacetDefect::PointOutside { vertex } => FacetDefect::PointOutside { vertex: v(vertex) },
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shifts_every_index() {
        let e = renumber(
            Error::SegmentOutOfRange {
                segment: 3,
                point: 98,
            },
            1,
        );
        assert_eq!(
            e,
            Error::SegmentOutOfRange {
                segment: 4,
                point: 99
            }
        );
        let e = renumber(
            Error::DegenerateFacet {
                index: 0,
                defect: FacetDefect::RepeatedVertex { vertex: 2 },
            },
            1,
        );
        assert_eq!(e.to_string(), renumber(e.clone(), 0).to_string());
        assert!(
            e.to_string().contains('1') && e.to_string().contains('3'),
            "{e}"
        );
        assert_eq!(
            renumber(Error::Degenerate { dimension: 1 }, 1),
            Error::Degenerate { dimension: 1 }
        );
    }
}
