//! [`TetOptions`]: what [`crate::tet::mesh()`] does, as a plain struct or as
//! the switch string of `delone tet` (TetGen's letters).

use crate::switches::{
    self, first_unused, number, out_of_range, positive, Letters, OutputSwitches, Program,
    SwitchError,
};
use crate::tet::refine::sizing::Sizing;
use crate::tet::refine::RefineOptions;
use crate::Error;

/// The options of the 3D pipeline ([`crate::tet::mesh()`]) and of
/// `delone tet`. Every field names its switch letter and default; "off" is
/// `false` or `None`. [`TetOptions::from_switches`] reads the switch string
/// of `delone tet`, output-shaping letters included.
///
/// ```
/// use delone::tet::TetOptions;
/// let o = TetOptions::from_switches("pq1.414/20a0.1").unwrap();
/// assert!(o.plc);
/// assert_eq!(o.max_radius_edge, Some(1.414));
/// assert_eq!(o.min_dihedral, Some(20.0));
/// assert_eq!((o.max_volume, o.regional_volumes), (Some(0.1), true));
/// assert_eq!(TetOptions::from_switches("pq").unwrap().max_radius_edge, Some(2.0));
/// ```
#[derive(Debug, Clone, Default)]
pub struct TetOptions {
    /// `-p`: the input is a PLC or surface to mesh the inside of. Default
    /// off: a point set is tetrahedralized.
    pub plc: bool,
    /// `-r`: refine an existing mesh (`delone tet -r`,
    /// [`crate::tet::refine::existing::refine_mesh`]). Default off.
    pub refine_mesh: bool,
    /// `-q[ratio]`: largest radius-edge ratio (2 when no number follows).
    /// Default `None`: no quality refinement.
    pub max_radius_edge: Option<f64>,
    /// `-q[ratio]/[angle]`: the dihedral bound of the optimisation and its
    /// report, degrees (between 0 and 70.5). Default `None`: the
    /// optimisation's own target.
    pub min_dihedral: Option<f64>,
    /// `-a`: the regions' volume bounds apply. Default off.
    pub regional_volumes: bool,
    /// `-a<volume>`: global maximum tetrahedron volume (positive; also
    /// sets [`Self::regional_volumes`]). Default `None`.
    pub max_volume: Option<f64>,
    /// `-m`: refine to a size field ([`Self::size_field`], read by the
    /// caller from `FILE.mtr` or a background mesh). Default off.
    pub sizing: bool,
    /// `-O[level]`: optimisation level (`-O0` off; 3 when no number
    /// follows). Default `None`: 3 after refinement, off after recovery
    /// alone.
    pub optimize: Option<u32>,
    /// `-S<n>`: Steiner point budget of the refinement. Default `None`:
    /// [`crate::tet::refine::default_budget`].
    pub max_steiner: Option<usize>,
    /// `-Y`: no Steiner point on the input surface. Default off.
    pub preserve_surface: bool,
    /// `-M`: no merging of coplanar facets. Default off (merged).
    pub no_merge: bool,
    /// `-c`: keep the convex hull. Default off.
    pub convex_hull: bool,
    /// `-d`: only detect self-intersections (`delone tet -d`). Default off.
    pub detect: bool,
    /// `-A`: output, the regional attribute of each tetrahedron in the
    /// `.ele`. Default off.
    pub region_attributes: bool,
    /// `-v`: output, the Voronoi (power, with `-w`) diagram. Default off.
    pub voronoi: bool,
    /// `-w`: regular (weighted) tetrahedralization of a point set. Default
    /// off.
    pub weights: bool,
    /// `-f`: output, every face in the `.face`. Default off.
    pub all_faces: bool,
    /// `-F`: output, no `.face` and `.edge`. Default off.
    pub no_face: bool,
    /// `-k`: output, legacy VTK `.vtk`. Default off.
    pub vtk_legacy: bool,
    /// `-g`: output, Medit `.mesh`. Default off.
    pub medit: bool,
    /// `-h`: help was asked for (the rest of the string is not read).
    pub help: bool,
    /// The output letters shared with `delone tri` (`-zQVCenNEIB`).
    pub output: OutputSwitches,
    /// The optimisation keeps the `-q` bound (`delone tet --keep-ratio`; no
    /// letter). Default off: it trades the ratio for dihedral angles.
    pub keep_ratio: bool,
    /// The size field of `-m` (no letter; `delone tet` reads it from
    /// `FILE.mtr` or `FILE.b.*`). Default `None`.
    pub size_field: Option<Sizing>,
    /// Leave out of the refinement's and the optimisation's reports what
    /// only explains the result ([`RefineOptions::diagnostics`],
    /// [`crate::tet::optimize::OptimizeOptions::diagnostics`]; no letter:
    /// the Python package sets it, `delone tet` never does): the mesh is
    /// the same, a large `-pq` run about 5% faster. Default off.
    pub no_diagnostics: bool,
}

impl TetOptions {
    /// Reads switch string `s` (TetGen's letters as `delone tet` takes
    /// them, with or without the leading `-`) and checks the combination
    /// ([`Self::check`]).
    ///
    /// # Errors
    /// A [`SwitchError`] naming the switch: unknown or not implemented
    /// letters, bad numbers (`-q1/90`, `-a0`), and the combinations
    /// `delone tet` refuses (`-q` without `-p` or `-r`, output switches
    /// with `-d`, ...).
    ///
    /// ```
    /// use delone::tet::TetOptions;
    /// let o = TetOptions::from_switches("pYMO2S500").unwrap();
    /// assert!(o.preserve_surface && o.no_merge);
    /// assert_eq!((o.optimize, o.max_steiner), (Some(2), Some(500)));
    /// assert_eq!(TetOptions::from_switches("pq2/80").unwrap_err().to_string(),
    ///            "-q2/80: the dihedral bound must lie between 0 and 70.5 degrees");
    /// ```
    pub fn from_switches(s: &str) -> Result<TetOptions, SwitchError> {
        switches::read(s, Self::check)
    }

    /// Adds the letters of switch string `s` to `self` without checking
    /// the combination (call [`Self::check`] after the last).
    ///
    /// # Errors
    /// As [`Self::from_switches`], for single letters.
    ///
    /// ```
    /// let mut o = delone::tet::TetOptions::default();
    /// o.add_switches("-pq").unwrap();
    /// o.add_switches("-a0.5").unwrap();
    /// o.check().unwrap();
    /// assert_eq!(o.max_volume, Some(0.5));
    /// ```
    pub fn add_switches(&mut self, s: &str) -> Result<(), SwitchError> {
        switches::add(self, s)
    }
}

impl Letters for TetOptions {
    const PROGRAM: Program = Program::Tet;
    const NUMBERED: &'static str = "qaSO";
    const SLASHED: &'static str = "q";

    fn shared(&mut self) -> (&mut OutputSwitches, &mut bool) {
        (&mut self.output, &mut self.help)
    }

    fn letter(&mut self, c: char, num: &str) -> Result<bool, SwitchError> {
        let range = |why| out_of_range(c, num, why);
        match c {
            'q' => {
                let (ratio, angle) = num.split_once('/').unwrap_or((num, ""));
                self.max_radius_edge = Some(number(c, ratio)?.unwrap_or(2.0));
                if num.contains('/') {
                    let d = number(c, angle)?
                        .ok_or_else(|| range("a dihedral angle in degrees follows the /"))?;
                    // The regular tetrahedron's dihedral angle, acos(1/3): no
                    // tetrahedron has a larger smallest dihedral angle.
                    if d <= 0.0 || d >= 70.52 {
                        return Err(range(
                            "the dihedral bound must lie between 0 and 70.5 degrees",
                        ));
                    }
                    self.min_dihedral = Some(d);
                }
            }
            'a' => {
                self.regional_volumes = true;
                let why = "the maximum volume must be positive";
                self.max_volume = positive(c, num, why)?.or(self.max_volume);
            }
            'O' => self.optimize = Some(number(c, num)?.unwrap_or(3.0).max(0.0) as u32),
            'S' => self.max_steiner = Some(number(c, num)?.unwrap_or(0.0) as usize),
            'v' => self.voronoi = true,
            'w' => self.weights = true,
            'p' => self.plc = true,
            'r' => self.refine_mesh = true,
            'm' => self.sizing = true,
            'c' => self.convex_hull = true,
            'A' => self.region_attributes = true,
            'g' => self.medit = true,
            'Y' => self.preserve_surface = true,
            'd' => self.detect = true,
            'M' => self.no_merge = true,
            'F' => self.no_face = true,
            'f' => self.all_faces = true,
            'k' => self.vtk_legacy = true,
            // delone never drops vertices from the output .node, which is
            // what TetGen's -J asks for.
            'J' => {}
            _ => return Ok(false),
        }
        Ok(true)
    }
}

impl TetOptions {
    /// Whether the options ask for refinement after recovery (`-q`, `-a`
    /// or `-m`).
    ///
    /// ```
    /// assert!(delone::tet::TetOptions::from_switches("pa").unwrap().refining());
    /// assert!(!delone::tet::TetOptions::from_switches("pS9").unwrap().refining());
    /// ```
    pub fn refining(&self) -> bool {
        self.max_radius_edge.is_some() || self.regional_volumes || self.sizing
    }

    /// Refuses `-q`/`-a` bounds no mesh can meet (a radius-edge ratio
    /// below the regular tetrahedron's, NaN), as the refinement would
    /// ([`RefineOptions::check_bounds`]), before any work.
    ///
    /// # Errors
    /// [`Error::InvalidBound`] naming the switch.
    ///
    /// ```
    /// use delone::tet::TetOptions;
    /// assert!(TetOptions::from_switches("pq2a1").unwrap().check_bounds().is_ok());
    /// assert!(matches!(TetOptions::from_switches("pq0.5").unwrap().check_bounds(),
    ///                  Err(delone::Error::InvalidBound { .. })));
    /// ```
    pub fn check_bounds(&self) -> Result<(), Error> {
        RefineOptions {
            max_radius_edge: self.max_radius_edge,
            max_volume: self.max_volume,
            ..RefineOptions::default()
        }
        .check_bounds()
    }

    /// Refuses the combinations `delone tet` refuses: `-q`, `-a`, `-m`,
    /// `-S` without `-p` or `-r`, and switches that would change nothing
    /// (output switches with `-d`, `-O`/`-M`/`-Y`/[`Self::keep_ratio`]
    /// for a point set, `-c`/`-M`/`-Y`/`-v`/`-w` with `-r`,
    /// [`Self::keep_ratio`] without `-q`).
    ///
    /// # Errors
    /// [`SwitchError::Conflict`] or [`SwitchError::NoEffect`] for the first
    /// rule broken.
    ///
    /// ```
    /// let e = delone::tet::TetOptions::from_switches("de").unwrap_err();
    /// assert_eq!(e.to_string(), "-e has no effect with -d: nothing is meshed and no file is written; leave it out");
    /// ```
    pub fn check(&self) -> Result<(), SwitchError> {
        let domain = self.plc || self.refine_mesh;
        if (self.refining() || self.max_steiner.is_some()) && !domain {
            return Err(SwitchError::Conflict {
                why: "-q, -a, -m and -S refine a PLC or surface (-p) or an existing mesh (-r)",
            });
        }
        let out = &self.output;
        let mut rules = Vec::new();
        if self.detect {
            let why = "with -d: nothing is meshed and no file is written";
            rules.extend([
                (out.edges, "-e", why),
                (out.neigh, "-n", why),
                (self.all_faces, "-f", why),
                (self.vtk_legacy, "-k", why),
                (self.medit, "-g", why),
                (out.no_node, "-N", why),
                (out.no_ele, "-E", why),
                (self.no_face, "-F", why),
                (out.no_bound, "-B", why),
                (out.no_iteration, "-I", why),
                (
                    out.zero,
                    "-z",
                    "with -d: findings use the input file's own numbering",
                ),
                (self.region_attributes, "-A", why),
                (self.convex_hull, "-c", why),
                (self.no_merge, "-M", why),
                (self.preserve_surface, "-Y", why),
                (self.max_radius_edge.is_some(), "-q", why),
                (self.regional_volumes, "-a", why),
                (self.sizing, "-m", why),
                (self.max_steiner.is_some(), "-S", why),
                (self.optimize.is_some(), "-O", why),
                (self.keep_ratio, "--keep-ratio", why),
                (out.check, "-C", why),
                (self.voronoi, "-v", why),
                (self.weights, "-w", why),
                (self.refine_mesh, "-r", why),
            ]);
        }
        if !domain {
            let why = "without -p or -r: a point set is only tetrahedralized";
            rules.extend([
                (self.optimize.is_some(), "-O", why),
                (self.keep_ratio, "--keep-ratio", why),
                (self.no_merge, "-M", why),
                (self.preserve_surface, "-Y", why),
            ]);
        }
        rules.push((
            self.keep_ratio && self.max_radius_edge.is_none(),
            "--keep-ratio",
            "without -q: there is no radius-edge bound to keep",
        ));
        if self.refine_mesh {
            rules.extend([
                (
                    self.convex_hull,
                    "-c",
                    "with -r: the input mesh is the domain",
                ),
                (
                    self.no_merge,
                    "-M",
                    "with -r: the input mesh's faces are kept as they are",
                ),
                (
                    self.preserve_surface,
                    "-Y",
                    "with -r: not supported when refining a mesh",
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
