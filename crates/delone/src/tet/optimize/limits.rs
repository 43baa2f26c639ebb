//! The size and shape bounds of the refinement that the optimisation must
//! keep: the largest volume per region (`-a`, global and regional), the
//! sizing function (`-m`: circumradius at most 0.612 h at the
//! circumcentre, the refinement's rule) and, on request, the largest
//! radius-edge ratio (`-q`).
//!
//! Refinement leaves every tetrahedron within these bounds (except a few it
//! reports, near small input features); flips, smoothing, insertion and
//! collapse may otherwise make tetrahedra larger or rounder-but-longer, so
//! a refined mesh would break the user's `-a` or `-q` after `-O`. Every
//! operation therefore compares the **excess** of the tetrahedra it makes
//! (the largest of volume ÷ bound, circumradius ÷ sized bound and
//! ratio ÷ bound; at most 1 is within the bounds) with those it removes: it is refused when a new tetrahedron
//! exceeds 1 and also exceeds the worst removed one. So an output that was
//! within the bounds stays within them, and a tetrahedron left above them
//! by the refinement is never made worse.

use crate::tet::quality;
use crate::tet::refine::sizing::{cell_radius_bound, Sizing};

/// The bounds, in the optimiser's rescaled coordinates.
#[derive(Debug, Clone, Default)]
pub(super) struct Limits {
    /// Largest volume per region index (infinite: no bound); empty: none.
    pub vol: Vec<f64>,
    /// Largest radius-edge ratio (infinite: none).
    pub ratio: f64,
    /// Target edge length, in the input's coordinates.
    pub sizing: Sizing,
    /// The rescaling factor of the optimiser's coordinates.
    pub scale: f64,
}

impl Limits {
    /// No bounds.
    pub(super) fn none() -> Limits {
        Limits {
            vol: Vec::new(),
            ratio: f64::INFINITY,
            sizing: Sizing::None,
            scale: 1.0,
        }
    }

    /// True when there is nothing to check.
    #[inline]
    pub(super) fn is_none(&self) -> bool {
        self.vol.is_empty() && self.ratio == f64::INFINITY && self.sizing.is_none()
    }

    /// The excess of a tetrahedron of `region` with points `p` (see the
    /// module doc); 0 without bounds.
    pub(super) fn excess(&self, p: &[[f64; 3]; 4], region: u32) -> f64 {
        let mut e: f64 = 0.0;
        if let Some(&mv) = self.vol.get(region as usize).filter(|v| v.is_finite()) {
            e = e.max(quality::volume(p).abs() / mv);
        }
        if self.ratio.is_finite() {
            e = e.max(quality::radius_edge_ratio(p) / self.ratio);
        }
        if !self.sizing.is_none() {
            if let Some(c) = quality::circumcenter(p) {
                let r = (0..3).map(|k| (c[k] - p[0][k]).powi(2)).sum::<f64>().sqrt();
                if let Some(h) = self.sizing.size_at(c.map(|x| x / self.scale)) {
                    e = e.max(r / (cell_radius_bound(h) * self.scale));
                }
            }
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
        let reg = crate::geom::vec3::corner_tet(1.0);
        let none = Limits::none();
        assert!(none.is_none());
        assert_eq!(none.excess(&reg, 0), 0.0);
        let l = Limits {
            vol: vec![1.0 / 12.0, f64::INFINITY],
            ..Limits::none()
        };
        assert!(!l.is_none());
        assert!((l.excess(&reg, 0) - 2.0).abs() < 1e-12);
        assert_eq!(l.excess(&reg, 1), 0.0);
        assert_eq!(l.excess(&reg, 7), 0.0);
        let r = Limits {
            ratio: 1.0,
            ..Limits::none()
        };
        let want = quality::radius_edge_ratio(&reg);
        assert!((r.excess(&reg, 0) - want).abs() < 1e-12);
        // Sizing h = 1 everywhere: circumradius √3/2 of this corner
        // tetrahedron against 0.612 h, in coordinates scaled by 2.
        let sz = Limits {
            sizing: Sizing::function(|_| 1.0),
            scale: 2.0,
            ..Limits::none()
        };
        let big = reg.map(|q| q.map(|c| 2.0 * c));
        let want = 0.75f64.sqrt() / cell_radius_bound(1.0);
        assert!((sz.excess(&big, 0) - want).abs() < 1e-12);
        assert!(Limits::allows(0.9, 3.0) && Limits::allows(2.0, 3.0));
        assert!(!Limits::allows(1.5, 1.2) && !Limits::allows(1.5, 0.5));
    }
}
