//! Switch strings: the letters of `delone tri` (Triangle's) and `delone tet`
//! (TetGen's), parsed into [`crate::tri::TriOptions`] and
//! [`crate::tet::TetOptions`] by their `from_switches`.
//!
//! A switch string is a run of letters, some followed by a number (`-q30`,
//! `-a0.1`, `-S100`, tet `-q1.414/20`, `-O2`, tri `-o2`). The letters that
//! shape only the output files (`-z`, `-Q`, `-V`, `-C`, `-e`, `-n`, `-N`,
//! `-E`, `-I`, `-B`) are the same in both programs and live in
//! [`OutputSwitches`]. A switch that is unknown, not implemented, badly
//! numbered, or that a combination makes impossible or useless is refused
//! with a [`SwitchError`] naming it.

use std::fmt;

/// Which program's switches a string holds.
///
/// ```
/// assert_eq!(delone::switches::Program::Tet.name(), "tet");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Program {
    /// `delone tri`: Triangle's switches, 2D.
    Tri,
    /// `delone tet`: TetGen's switches, 3D.
    Tet,
}

impl Program {
    /// The subcommand's name: `tri` or `tet`.
    ///
    /// ```
    /// assert_eq!(delone::switches::Program::Tri.name(), "tri");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            Program::Tri => "tri",
            Program::Tet => "tet",
        }
    }
}

/// A refused switch string: the switch, and why.
///
/// ```
/// use delone::{switches::SwitchError, tri::TriOptions};
/// let e = TriOptions::from_switches("pk").unwrap_err();
/// assert!(matches!(e, SwitchError::Unknown { letter: 'k', .. }));
/// assert_eq!(e.to_string(), "unknown switch -k for delone tri (see delone tri --help)");
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SwitchError {
    /// A letter the program does not know.
    Unknown {
        /// The program.
        program: Program,
        /// The letter.
        letter: char,
    },
    /// A letter of Triangle/TetGen that delone does not implement.
    NotImplemented {
        /// The letter.
        letter: char,
        /// What it does in the original program.
        what: &'static str,
    },
    /// The text after a letter is not a non-negative number.
    NotANumber {
        /// The letter.
        letter: char,
        /// The text.
        text: String,
    },
    /// The number after a letter is outside the values the switch takes.
    OutOfRange {
        /// The letter.
        letter: char,
        /// The text after the letter.
        text: String,
        /// Which values the switch takes.
        why: &'static str,
    },
    /// Triangle's `-u`: the user's triangle test is a closure, given
    /// through the library ([`crate::tri::refine::refine_with`]).
    UserTest,
    /// Switches that do not go together, or a switch that needs another.
    Conflict {
        /// What is wrong.
        why: &'static str,
    },
    /// A switch that would change nothing in the run asked for.
    NoEffect {
        /// The switch as written (`-e`, `--keep-ratio`, ...).
        switch: &'static str,
        /// Why it has no effect.
        why: &'static str,
    },
}

impl fmt::Display for SwitchError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SwitchError::Unknown { program, letter } => {
                let p = program.name();
                write!(
                    f,
                    "unknown switch -{letter} for delone {p} (see delone {p} --help)"
                )
            }
            SwitchError::NotImplemented { letter, what } => {
                write!(f, "switch -{letter} ({what}) is not implemented yet")
            }
            SwitchError::NotANumber { letter, text } => {
                write!(f, "-{letter}{text}: {text} is not a number")
            }
            SwitchError::OutOfRange { letter, text, why } => write!(f, "-{letter}{text}: {why}"),
            SwitchError::UserTest => f.write_str(
                "-u (user-defined triangle test) needs the library API refine_with \
                 (delone::tri::refine::refine_with takes the test as a closure); \
                 the command line has no way to give one",
            ),
            SwitchError::Conflict { why } => f.write_str(why),
            SwitchError::NoEffect { switch, why } => {
                write!(f, "{switch} has no effect {why}; leave it out")
            }
        }
    }
}

impl std::error::Error for SwitchError {}

/// The output-shaping letters both programs share. They change the files
/// written and the report, not the mesh.
///
/// ```
/// let o = delone::tri::TriOptions::from_switches("zQVVCenNEIB").unwrap();
/// assert!(o.output.zero && o.output.quiet && o.output.check && o.output.no_bound);
/// assert_eq!(o.output.verbose, 2);
/// ```
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct OutputSwitches {
    /// `-z`: number the output from 0 (default: the input's first index).
    pub zero: bool,
    /// `-Q`: no report on stdout (default off).
    pub quiet: bool,
    /// `-V` (repeatable): a longer report (default 0).
    pub verbose: u8,
    /// `-C`: check the mesh with delone's validator (default off).
    pub check: bool,
    /// `-e`: write the edges (`.edge`; default off).
    pub edges: bool,
    /// `-n`: write the neighbours (`.neigh`; default off).
    pub neigh: bool,
    /// `-N`: no `.node` output (default off).
    pub no_node: bool,
    /// `-E`: no `.ele` output (default off).
    pub no_ele: bool,
    /// `-I`: no iteration number in the output name (`FILE`, not `FILE.1`;
    /// default off).
    pub no_iteration: bool,
    /// `-B`: no boundary markers in the output (default off).
    pub no_bound: bool,
}

impl OutputSwitches {
    /// Takes `letter` if it is one of the shared output letters.
    fn letter(&mut self, letter: char) -> bool {
        match letter {
            'z' => self.zero = true,
            'Q' => self.quiet = true,
            'V' => self.verbose = self.verbose.saturating_add(1),
            'C' => self.check = true,
            'e' => self.edges = true,
            'n' => self.neigh = true,
            'N' => self.no_node = true,
            'E' => self.no_ele = true,
            'I' => self.no_iteration = true,
            'B' => self.no_bound = true,
            _ => return false,
        }
        true
    }
}

/// Where the number glued to a switch letter, starting at `chars[start]`,
/// ends: digits and `.`; with `slash` (tet `-q`) also `/` between two
/// numbers; and an exponent, `e`/`E` followed by a digit or by `+`/`-` and
/// a digit, after a digit of the same number. Any other `e`/`E` is the next
/// switch: `-pq1.2e` is `-q1.2` then `-e`, `-pq1.2e-3`... is `-q0.0012`.
fn number_end(chars: &[char], start: usize, slash: bool) -> usize {
    let mut k = start;
    let mut digit = false;
    while let Some(&ch) = chars.get(k) {
        if ch.is_ascii_digit() {
            digit = true;
            k += 1;
        } else if ch == '.' {
            k += 1;
        } else if slash && ch == '/' {
            digit = false;
            k += 1;
        } else if matches!(ch, 'e' | 'E') && digit {
            let d = |i: usize| chars.get(i).is_some_and(|c| c.is_ascii_digit());
            if d(k + 1) {
                k += 2;
            } else if matches!(chars.get(k + 1), Some('+' | '-')) && d(k + 2) {
                k += 3;
            } else {
                break;
            }
            // One exponent per number.
            while chars.get(k).is_some_and(|c| c.is_ascii_digit()) {
                k += 1;
            }
            if !(slash && chars.get(k) == Some(&'/')) {
                break;
            }
        } else {
            break;
        }
    }
    k
}

/// A number glued to switch letter `letter` (`-q30`, `-a0.01`, `-S100`),
/// if any: finite and not negative.
pub(crate) fn number(letter: char, text: &str) -> Result<Option<f64>, SwitchError> {
    if text.is_empty() {
        return Ok(None);
    }
    match text.parse::<f64>() {
        Ok(x) if x.is_finite() && x >= 0.0 => Ok(Some(x)),
        _ => Err(SwitchError::NotANumber {
            letter,
            text: text.to_string(),
        }),
    }
}

/// [`SwitchError::OutOfRange`]: `text` after `letter` is not a value the
/// switch takes, `why` says which are.
pub(crate) fn out_of_range(letter: char, text: &str, why: &'static str) -> SwitchError {
    SwitchError::OutOfRange {
        letter,
        text: text.to_string(),
        why,
    }
}

/// A bound glued to switch letter `letter` (`-a0.1`), if any: positive;
/// `why` says so when it is not.
pub(crate) fn positive(
    letter: char,
    text: &str,
    why: &'static str,
) -> Result<Option<f64>, SwitchError> {
    match number(letter, text)? {
        Some(x) if x <= 0.0 => Err(out_of_range(letter, text, why)),
        x => Ok(x),
    }
}

/// A program's options as its switch letters ([`read`], [`add`]).
pub(crate) trait Letters: Default {
    /// The program whose letters these are.
    const PROGRAM: Program;
    /// The letters followed by a number.
    const NUMBERED: &'static str;
    /// The letters followed by two numbers split by `/`.
    const SLASHED: &'static str;
    /// Takes letter `c` with the number glued to it; `Ok(false)` when `c`
    /// is not one of the program's own letters.
    fn letter(&mut self, c: char, num: &str) -> Result<bool, SwitchError>;
    /// The shared output letters and the `-h` flag.
    fn shared(&mut self) -> (&mut OutputSwitches, &mut bool);
}

/// The options of switch string `s`, their combination checked by `check`.
pub(crate) fn read<O: Letters>(
    s: &str,
    check: fn(&O) -> Result<(), SwitchError>,
) -> Result<O, SwitchError> {
    let mut o = O::default();
    add(&mut o, s)?;
    check(&o)?;
    Ok(o)
}

/// Adds switch string `s` (an optional leading `-`, then letters) to `o`:
/// the program's own letters with the numbers glued to them, the shared
/// output letters, `-h` (which stops the reading); the letters of the
/// original program that delone lacks are refused.
pub(crate) fn add<O: Letters>(o: &mut O, s: &str) -> Result<(), SwitchError> {
    let chars: Vec<char> = s.strip_prefix('-').unwrap_or(s).chars().collect();
    let mut k = 0;
    while k < chars.len() {
        let c = chars[k];
        k += 1;
        let start = k;
        if O::NUMBERED.contains(c) {
            k = number_end(&chars, k, O::SLASHED.contains(c));
        }
        let num: String = chars[start..k].iter().collect();
        if o.letter(c, &num)? {
            continue;
        }
        let (output, help) = o.shared();
        if c == 'h' {
            *help = true;
            return Ok(());
        }
        if !output.letter(c) {
            let program = O::PROGRAM;
            return Err(match unimplemented(program, c) {
                Some(what) => SwitchError::NotImplemented { letter: c, what },
                None => SwitchError::Unknown { program, letter: c },
            });
        }
    }
    Ok(())
}

/// Switches of the original program that delone does not implement yet,
/// with a few words on what they do.
fn unimplemented(program: Program, c: char) -> Option<&'static str> {
    Some(match (program, c) {
        (Program::Tri, 'g') => "OFF output",
        (Program::Tri, 'O') => "ignore holes",
        (Program::Tri, 'X') => "no exact arithmetic",
        (Program::Tri, 'i') => "incremental algorithm choice",
        (Program::Tri, 'l') => "vertical cuts only in divide-and-conquer",
        (Program::Tri, 's') => "segment splitting",
        (Program::Tet, 'R') => "mesh coarsening",
        (Program::Tet, 'i') => "insertion of additional points",
        (Program::Tet, 'T') => "coplanarity tolerance",
        (Program::Tet, 'X') => "no exact arithmetic",
        (Program::Tet, 'D') => "conforming Delaunay",
        (Program::Tet, 'o') => "second-order elements (-o2) / dihedral bound (-o/)",
        _ => return None,
    })
}

/// The first rule that holds, as [`SwitchError::NoEffect`]: each rule is
/// (given, switch, why it has no effect in this run).
pub(crate) fn first_unused(
    rules: &[(bool, &'static str, &'static str)],
) -> Result<(), SwitchError> {
    match rules.iter().find(|r| r.0) {
        Some(&(_, switch, why)) => Err(SwitchError::NoEffect { switch, why }),
        None => Ok(()),
    }
}
