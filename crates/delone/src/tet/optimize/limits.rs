//! The size and shape bounds of the refinement that the optimisation must
//! keep: the largest volume per region (`-a`, global and regional) and the
//! largest radius-edge ratio (`-q`).
//!
//! Refinement leaves every tetrahedron within these bounds (except a few it
//! reports, near small input features); flips, smoothing, insertion and
//! collapse may otherwise make tetrahedra larger or rounder-but-longer, so
//! a refined mesh would break the user's `-a` or `-q` after `-O`. Every
//! operation therefore compares the **excess** of the tetrahedra it makes
//! (the largest of volume ÷ bound and ratio ÷ bound; at most 1 is within
//! the bounds) with those it removes: it is refused when a new tetrahedron
//! exceeds 1 and also exceeds the worst removed one. So an output that was
//! within the bounds stays within them, and a tetrahedron left above them
//! by the refinement is never made worse.

use crate::tet::quality;

/// The bounds, in the optimiser's rescaled coordinates.
#[derive(Debug, Clone, Default)]
pub(super) struct Limits {
    /// Largest volume per region index (infinite: no bound); empty: none.
    pub vol: Vec<f64>,
    /// Largest radius-edge ratio (infinite: none).
    pub ratio: f64,
}

impl Limits {
    /// No bounds.
    pub(super) fn none() -> Limits {
        Limits {
            vol: Vec::new(),
            ratio: f64::INFINITY,
        }
    }

    /// True when there is nothing to check.
    #[inline]
    pub(super) fn is_none(&self) -> bool {
        self.vol.is_empty() && self.ratio == f64::INFINITY
    }

    /// The excess of a tetrahedron of `region` with points `p` (see the
    /// module doc); 0 without bounds.
    pub(super) fn excess(&self, p: &[[f64; 3]; 4], region: u32) -> f64 {
        let mut e: f64 = 0.0;
        if let Some(&mv) = self.vol.get(region as usize) {
            if mv.is_finite() {
                e = e.max(quality::volume(p).abs() / mv);
            }
        }
        if self.ratio.is_finite() {
            e = e.max(quality::radius_edge_ratio(p) / self.ratio);
        }
        e
    }

    /// May tetrahedra of excess `new` replace ones of worst excess `old`?
    #[inline]
    pub(super) fn allows(new: f64, old: f64) -> bool {
        new <= 1.0 || new <= old
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn excess_of_volume_and_ratio() {
        let reg = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let none = Limits::none();
        assert!(none.is_none());
        assert_eq!(none.excess(&reg, 0), 0.0);
        let l = Limits {
            vol: vec![1.0 / 12.0, f64::INFINITY],
            ratio: f64::INFINITY,
        };
        assert!(!l.is_none());
        assert!((l.excess(&reg, 0) - 2.0).abs() < 1e-12);
        assert_eq!(l.excess(&reg, 1), 0.0);
        assert_eq!(l.excess(&reg, 7), 0.0);
        let r = Limits {
            vol: Vec::new(),
            ratio: 1.0,
        };
        let want = quality::radius_edge_ratio(&reg);
        assert!((r.excess(&reg, 0) - want).abs() < 1e-12);
        assert!(Limits::allows(0.9, 3.0) && Limits::allows(2.0, 3.0));
        assert!(!Limits::allows(1.5, 1.2) && !Limits::allows(1.5, 0.5));
    }
}
