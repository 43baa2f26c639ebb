//! Output and input file names: Triangle's and TetGen's iteration numbers
//! (`FILE` → `FILE.1`), `--output-dir`, extensions.

use std::path::{Path, PathBuf};

use crate::fail::{usage_err, Failure};

/// Input file and output base name, as Triangle/TetGen derive them.
#[derive(Debug, PartialEq)]
pub struct Names {
    /// The `.node` file to read.
    pub node: PathBuf,
    /// Output files are `<out_base>.node`, `<out_base>.ele`, ...
    pub out_base: PathBuf,
}

const OTHER_FORMATS: &[&str] = &[
    "poly", "smesh", "off", "ply", "stl", "obj", "mesh", "vtk", "vtu", "ele", "face", "edge",
    "neigh", "msh", "medit",
];

/// `FILE` or `FILE.node` → (`FILE.node`, `FILE.1`); `FILE.1.node` → `FILE.2`;
/// with `no_iteration` the output base is `FILE` itself.
pub fn names(
    input: &Path,
    no_iteration: bool,
    output_dir: Option<&Path>,
) -> Result<Names, Failure> {
    let s = input.to_string_lossy();
    let base: String = if let Some(b) = s.strip_suffix(".node") {
        b.to_string()
    } else {
        if let Some(ext) = input.extension().and_then(|e| e.to_str()) {
            if OTHER_FORMATS.contains(&ext.to_ascii_lowercase().as_str()) {
                return Err(usage_err(format!(
                    "{s}: .{ext} input needs -p (delone tri -p reads .poly PSLGs; \
                     other formats are not supported yet)"
                )));
            }
        }
        s.to_string()
    };
    if base.is_empty() || base.ends_with('/') {
        return Err(usage_err(format!("{s}: not a file name")));
    }
    let node = PathBuf::from(format!("{base}.node"));
    let out_base = output_base(&base, no_iteration, output_dir);
    Ok(Names { node, out_base })
}

/// The output base for input base name `base` (no extension): Triangle's
/// and TetGen's iteration number (`FILE` → `FILE.1`, `FILE.1` → `FILE.2`)
/// unless `no_iteration`, moved into `output_dir` when given.
pub fn output_base(base: &str, no_iteration: bool, output_dir: Option<&Path>) -> PathBuf {
    let out = if no_iteration {
        base.to_string()
    } else {
        // An iteration number is a trailing ".<digits>" in the file name.
        let (stem, num) = match base.rsplit_once('.') {
            Some((stem, n))
                if !n.is_empty()
                    && n.len() < 10
                    && n.bytes().all(|b| b.is_ascii_digit())
                    && !stem.is_empty()
                    && !stem.ends_with('/') =>
            {
                (stem, n.parse::<u64>().unwrap_or(0))
            }
            _ => (base, 0),
        };
        format!("{stem}.{}", num + 1)
    };
    match output_dir {
        Some(dir) => {
            let file = Path::new(&out)
                .file_name()
                .map(PathBuf::from)
                .unwrap_or_default();
            dir.join(file)
        }
        None => PathBuf::from(out),
    }
}

/// `base` + `.` + `ext`.
pub fn with_ext(base: &Path, ext: &str) -> PathBuf {
    let mut s = base.as_os_str().to_owned();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

/// `mesh.face.vtu` beside `mesh.vtu` (`mesh.face.vtk` beside `mesh.vtk`):
/// the faces on input facets, as triangles with a `boundary_marker` cell
/// array, on the same points as the tetrahedra.
pub fn face_companion(p: &Path) -> PathBuf {
    let ext = p.extension().and_then(|e| e.to_str()).unwrap_or("vtu");
    let ext = if ext.eq_ignore_ascii_case("vtk") {
        "vtk"
    } else {
        "vtu"
    };
    p.with_extension(format!("face.{ext}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nm(s: &str, i: bool, d: Option<&str>) -> (String, String) {
        let n = names(Path::new(s), i, d.map(Path::new)).unwrap();
        (
            n.node.display().to_string(),
            n.out_base.display().to_string(),
        )
    }

    #[test]
    fn output_naming() {
        assert_eq!(
            nm("a/box.node", false, None),
            ("a/box.node".into(), "a/box.1".into())
        );
        assert_eq!(
            nm("a/box", false, None),
            ("a/box.node".into(), "a/box.1".into())
        );
        assert_eq!(
            nm("box.1.node", false, None),
            ("box.1.node".into(), "box.2".into())
        );
        assert_eq!(
            nm("box.9", false, None),
            ("box.9.node".into(), "box.10".into())
        );
        assert_eq!(
            nm("box.node", true, None),
            ("box.node".into(), "box".into())
        );
        assert_eq!(
            nm("v1.2/pts", false, None),
            ("v1.2/pts.node".into(), "v1.2/pts.1".into())
        );
        assert_eq!(
            nm("in/box.node", false, Some("out")),
            ("in/box.node".into(), "out/box.1".into())
        );
        assert!(names(Path::new("x.poly"), false, None).is_err());
    }
}
