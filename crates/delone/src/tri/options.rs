//! [`TriOptions`]: what [`crate::tri::mesh()`] does, as a plain struct or as
//! the switch string of `delone tri` (Triangle's letters).

use crate::switches::{
    self, first_unused, number, out_of_range, positive, Letters, OutputSwitches, Program,
    SwitchError,
};
use crate::tri::refine::SegmentSplits;

/// The options of the 2D pipeline ([`crate::tri::mesh()`]) and of
/// `delone tri`. Every field names its switch letter and default; "off" is
/// `false` or `None`. [`TriOptions::from_switches`] reads the switch string
/// of `delone tri`, output-shaping letters included (they are kept in
/// [`Self::output`] and in the fields marked "output" for the writers).
///
/// ```
/// use delone::tri::TriOptions;
/// let o = TriOptions::from_switches("pq30a0.1").unwrap();
/// assert!(o.pslg);
/// assert_eq!((o.min_angle, o.max_area, o.regional_areas), (Some(30.0), Some(0.1), true));
/// assert_eq!(TriOptions::from_switches("p").unwrap(), TriOptions { pslg: true, ..TriOptions::default() });
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TriOptions {
    /// `-p`: the input is a PSLG; its segments are kept and the outside
    /// and the holes are removed. Default off: the points are triangulated.
    pub pslg: bool,
    /// `-r`: refine an existing mesh (`delone tri -r`; the pipeline meshes a
    /// PSLG, so this only shapes the command line). Default off.
    pub refine_mesh: bool,
    /// `-q[angle]`: minimum angle in degrees (20 when no number follows,
    /// at most 60). Default `None`: no angle bound.
    pub min_angle: Option<f64>,
    /// `-a`: the regions' area bounds apply. Default off.
    pub regional_areas: bool,
    /// `-a<area>`: global maximum triangle area (positive; also sets
    /// [`Self::regional_areas`]). Default `None`.
    pub max_area: Option<f64>,
    /// `-S<n>`: Steiner point budget of the refinement. Default `None`: the
    /// library's budget ([`crate::tri::refine::default_budget`]).
    pub max_steiner: Option<usize>,
    /// `-c`: keep the convex hull. Default off.
    pub convex_hull: bool,
    /// `-A`: output, the regional attribute of each triangle in the `.ele`.
    /// Default off.
    pub region_attributes: bool,
    /// `-D`: conforming Delaunay. Default off.
    pub conforming_delaunay: bool,
    /// `-Y` ([`SegmentSplits::Interior`]) / `-YY` ([`SegmentSplits::None`]):
    /// which subsegments the refinement may split. Default
    /// [`SegmentSplits::All`].
    pub segment_splits: SegmentSplits,
    /// `-j`: output, vertices of no triangle left out of the `.node`.
    /// Default off.
    pub jettison: bool,
    /// `-P`: output, no `.poly`. Default off.
    pub no_poly: bool,
    /// `-o2`: output, quadratic (6-node) triangles. Default off.
    pub second_order: bool,
    /// `-F`: Fortune's sweepline asked for (accepted; delone inserts
    /// incrementally). Default off.
    pub fortune: bool,
    /// `-v`: output, the Voronoi (power, with `-w`) diagram. Default off.
    pub voronoi: bool,
    /// `-w`: regular (weighted) triangulation of a point set. Default off.
    pub weights: bool,
    /// `-h`: help was asked for (the rest of the string is not read).
    pub help: bool,
    /// The output letters shared with `delone tet` (`-zQVCenNEIB`).
    pub output: OutputSwitches,
    /// Threads for the quality refinement (`delone tri --threads N`; no
    /// letter). Default `None`: [`crate::tri::refine::default_threads`].
    pub threads: Option<usize>,
    /// Keep the mesh before refinement in [`crate::tri::TriResult::unrefined`]
    /// (to interpolate point data at Steiner points; no letter). Default off.
    pub keep_unrefined: bool,
}

impl TriOptions {
    /// Reads switch string `s` (Triangle's letters as `delone tri` takes
    /// them, with or without the leading `-`) and checks the combination
    /// ([`Self::check`]).
    ///
    /// # Errors
    /// A [`SwitchError`] naming the switch: unknown or not implemented
    /// letters, bad numbers (`-q61`, `-a0`, `-o3`), and the combinations
    /// `delone tri` refuses (`-q` without `-p` or `-r`, `-e` with `-r`, ...).
    ///
    /// ```
    /// use delone::{switches::SwitchError, tri::TriOptions};
    /// let o = TriOptions::from_switches("-pq34.5a0.01eS100").unwrap();
    /// assert_eq!((o.min_angle, o.max_steiner), (Some(34.5), Some(100)));
    /// assert!(o.output.edges);
    /// assert_eq!(TriOptions::from_switches("pq61").unwrap_err().to_string(),
    ///            "-q61: the minimum angle must be at most 60");
    /// assert!(matches!(TriOptions::from_switches("q"), Err(SwitchError::Conflict { .. })));
    /// ```
    pub fn from_switches(s: &str) -> Result<TriOptions, SwitchError> {
        switches::read(s, Self::check)
    }

    /// Adds the letters of switch string `s` to `self` without checking
    /// the combination (for a command line of several switch arguments;
    /// call [`Self::check`] after the last).
    ///
    /// # Errors
    /// As [`Self::from_switches`], for single letters.
    ///
    /// ```
    /// let mut o = delone::tri::TriOptions::default();
    /// o.add_switches("-pq").unwrap();
    /// o.add_switches("-Y").unwrap();
    /// o.check().unwrap();
    /// assert_eq!(o.segment_splits, delone::tri::refine::SegmentSplits::Interior);
    /// ```
    pub fn add_switches(&mut self, s: &str) -> Result<(), SwitchError> {
        switches::add(self, s)
    }
}

impl Letters for TriOptions {
    const PROGRAM: Program = Program::Tri;
    const NUMBERED: &'static str = "qaSo";
    const SLASHED: &'static str = "";

    fn shared(&mut self) -> (&mut OutputSwitches, &mut bool) {
        (&mut self.output, &mut self.help)
    }

    fn letter(&mut self, c: char, num: &str) -> Result<bool, SwitchError> {
        let range = |why| out_of_range(c, num, why);
        match c {
            'q' => {
                let a = number(c, num)?.unwrap_or(20.0);
                if a > 60.0 {
                    return Err(range("the minimum angle must be at most 60"));
                }
                self.min_angle = Some(a)
            }
            'a' => {
                self.regional_areas = true;
                let why = "the maximum area must be positive";
                self.max_area = positive(c, num, why)?.or(self.max_area);
            }
            'S' => self.max_steiner = Some(number(c, num)?.unwrap_or(0.0) as usize),
            'P' => self.no_poly = true,
            'D' => self.conforming_delaunay = true,
            'Y' => {
                self.segment_splits = match self.segment_splits {
                    SegmentSplits::All => SegmentSplits::Interior,
                    _ => SegmentSplits::None,
                }
            }
            'j' => self.jettison = true,
            'u' => return Err(SwitchError::UserTest),
            'o' => {
                if num != "2" {
                    return Err(range(
                        "only -o2 (quadratic triangles) is known; -o FILE takes a separate file name",
                    ));
                }
                self.second_order = true
            }
            'v' => self.voronoi = true,
            'w' => self.weights = true,
            'p' => self.pslg = true,
            'r' => self.refine_mesh = true,
            'c' => self.convex_hull = true,
            'A' => self.region_attributes = true,
            'F' => self.fortune = true,
            _ => return Ok(false),
        }
        Ok(true)
    }
}

impl TriOptions {
    /// Whether the options ask for refinement (`-q`, `-a`, `-S`, `-D` or
    /// `-Y`).
    ///
    /// ```
    /// assert!(delone::tri::TriOptions::from_switches("pD").unwrap().refining());
    /// assert!(!delone::tri::TriOptions::from_switches("p").unwrap().refining());
    /// ```
    pub fn refining(&self) -> bool {
        self.min_angle.is_some()
            || self.regional_areas
            || self.max_steiner.is_some()
            || self.conforming_delaunay
            || self.segment_splits != SegmentSplits::All
    }

    /// The refinement options these switches ask for: their bounds, budget,
    /// segment splitting and threads, with off-centres.
    ///
    /// ```
    /// let o = delone::tri::TriOptions::from_switches("pq30a0.1").unwrap().refine_options();
    /// assert_eq!((o.min_angle, o.max_area, o.off_centers), (Some(30.0), Some(0.1), true));
    /// ```
    pub fn refine_options(&self) -> crate::tri::refine::RefineOptions {
        let defaults = crate::tri::refine::RefineOptions::default();
        crate::tri::refine::RefineOptions {
            min_angle: self.min_angle,
            max_area: self.max_area,
            regional_areas: self.regional_areas,
            max_steiner: self.max_steiner,
            off_centers: true,
            segment_splits: self.segment_splits,
            conforming_delaunay: self.conforming_delaunay,
            threads: self.threads.unwrap_or(defaults.threads),
            ..defaults
        }
    }

    /// Refuses the combinations `delone tri` refuses: switches that need
    /// another (`-q`, `-a`, `-S`, `-D`, `-Y` need `-p` or `-r`), that
    /// exclude each other (`-p` with `-r`, `-j` with `-r`), or that would
    /// change nothing (`-e`, `-n`, `-o2`, `-c`, `-A`, `-v`, `-w` with `-r`;
    /// [`Self::threads`] without refinement).
    ///
    /// # Errors
    /// [`SwitchError::Conflict`] or [`SwitchError::NoEffect`] for the first
    /// rule broken.
    ///
    /// ```
    /// let mut o = delone::tri::TriOptions::from_switches("r").unwrap();
    /// o.output.edges = true;
    /// assert_eq!(o.check().unwrap_err().to_string(),
    ///     "-e has no effect with -r: delone tri -r writes only the .node, .ele and .poly files; leave it out");
    /// ```
    pub fn check(&self) -> Result<(), SwitchError> {
        let domain = self.pslg || self.refine_mesh;
        let conflict = |why| Err(SwitchError::Conflict { why });
        if (self.min_angle.is_some() || self.regional_areas || self.max_steiner.is_some())
            && !domain
        {
            return conflict("-q, -a and -S refine a PSLG (-p) or an existing mesh (-r)");
        }
        if (self.conforming_delaunay || self.segment_splits != SegmentSplits::All) && !domain {
            return conflict(
                "-D and -Y apply to segments: use them with a PSLG (-p) or an existing mesh (-r)",
            );
        }
        if self.jettison && self.refine_mesh {
            return conflict(
                "-j with -r is not supported: -r keeps every vertex of the input mesh",
            );
        }
        if self.pslg && self.refine_mesh {
            return conflict(
                "-p and -r together are not supported: -r reads FILE.poly's segments itself",
            );
        }
        let mut rules = vec![(
            self.threads.is_some() && !self.refining(),
            "--threads",
            "without refinement (-q, -a, -S, -D or -Y): only refinement runs in threads",
        )];
        if self.refine_mesh {
            let why = "with -r: delone tri -r writes only the .node, .ele and .poly files";
            rules.extend([
                (self.output.edges, "-e", why),
                (self.output.neigh, "-n", why),
                (self.second_order, "-o2", why),
                (
                    self.convex_hull,
                    "-c",
                    "with -r: the input mesh's own boundary is kept",
                ),
                (
                    self.region_attributes,
                    "-A",
                    "with -r: the .ele keeps the input mesh's attributes",
                ),
                (
                    self.voronoi,
                    "-v",
                    "with -r: no Voronoi diagram of a refined mesh",
                ),
                (
                    self.weights,
                    "-w",
                    "with -r: the input mesh is refined as it is",
                ),
            ]);
        }
        first_unused(&rules)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_and_exponents() {
        let o = TriOptions::from_switches("pq1.2e").unwrap();
        assert_eq!(o.min_angle, Some(1.2));
        assert!(o.output.edges);
        let o = TriOptions::from_switches("pqa.5").unwrap();
        assert_eq!((o.min_angle, o.max_area), (Some(20.0), Some(0.5)));
        let o = TriOptions::from_switches("pa1e-3").unwrap();
        assert_eq!(o.max_area, Some(0.001));
        assert_eq!(
            TriOptions::from_switches("pq3.0.1")
                .unwrap_err()
                .to_string(),
            "-q3.0.1: 3.0.1 is not a number"
        );
        assert_eq!(
            TriOptions::from_switches("g").unwrap_err().to_string(),
            "switch -g (OFF output) is not implemented yet"
        );
        let o = TriOptions::from_switches("pqYYY").unwrap();
        assert_eq!(o.segment_splits, SegmentSplits::None);
        assert!(TriOptions::from_switches("zhk").unwrap().help);
    }
}
