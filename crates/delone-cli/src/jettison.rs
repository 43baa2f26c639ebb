//! `delone tri -j` (jettison the vertices no triangle uses from the output
//! .node, renumbering the rest) and plain `delone tri -c FILE.node` (the
//! convex hull written as .poly segments, as Triangle does).

use std::path::{Path, PathBuf};

use delone::NONE;
use delone_io::NodeFile;

use crate::fail::Failure;

/// Old → new vertex ids when the vertices no cell uses are dropped.
pub struct Renumber {
    /// New id of each old vertex, `NONE` if dropped.
    pub new: Vec<u32>,
    /// Old id of each kept vertex, in order.
    pub kept: Vec<u32>,
}

impl Renumber {
    /// Keeps the vertices below `n` that `cells` use, plus every vertex at
    /// or above `always` (appended points such as -o2 midpoints).
    pub fn new<const K: usize>(n: usize, cells: &[[u32; K]], always: usize) -> Renumber {
        let mut used = vec![false; n];
        for c in cells {
            for &v in c {
                if let Some(u) = used.get_mut(v as usize) {
                    *u = true;
                }
            }
        }
        for u in used.iter_mut().skip(always) {
            *u = true;
        }
        let mut new = vec![NONE; n];
        let mut kept = Vec::new();
        for (i, &u) in used.iter().enumerate() {
            if u {
                new[i] = kept.len() as u32;
                kept.push(i as u32);
            }
        }
        Renumber { new, kept }
    }

    /// Renumbers `items` in place (every vertex must be kept).
    pub fn apply<const K: usize>(&self, items: &mut [[u32; K]]) {
        for it in items {
            for v in it.iter_mut() {
                *v = self.new[*v as usize];
            }
        }
    }

    /// The kept rows of a flat array with `width` values per vertex.
    pub fn rows<T: Copy>(&self, v: &[T], width: usize) -> Vec<T> {
        if width == 0 {
            return Vec::new();
        }
        self.kept
            .iter()
            .flat_map(|&i| {
                v[i as usize * width..(i as usize + 1) * width]
                    .iter()
                    .copied()
            })
            .collect()
    }

    /// How many vertices were dropped.
    pub fn dropped(&self) -> usize {
        self.new.len() - self.kept.len()
    }
}

/// A `.node` file restricted to the kept vertices.
pub fn node_file(node: &NodeFile, r: &Renumber) -> NodeFile {
    NodeFile {
        dim: node.dim,
        coords: r.rows(&node.coords, node.dim),
        n_attributes: node.n_attributes,
        attributes: r.rows(&node.attributes, node.n_attributes),
        markers: node.markers.as_ref().map(|m| r.rows(m, 1)),
        first_index: node.first_index,
        header_line: node.header_line,
        lines: r.rows(&node.lines, 1),
    }
}

/// Plain `-c`: writes the hull edges (`boundary` flags of `edges`) as the
/// segments of `base.poly`, marker 1 (none with `-B`), no holes.
pub fn write_hull_poly(
    base: &Path,
    edges: &[[u32; 2]],
    boundary: &[bool],
    markers: bool,
    first: u32,
    written: &mut Vec<PathBuf>,
) -> Result<(), Failure> {
    let segs: Vec<[u32; 2]> = edges
        .iter()
        .zip(boundary)
        .filter(|(_, &b)| b)
        .map(|(e, _)| *e)
        .collect();
    let sm = vec![1i32; segs.len()];
    let mut s = base.as_os_str().to_owned();
    s.push(".poly");
    let path = PathBuf::from(s);
    let fail = |message: String| Failure { message, code: 1 };
    let f = crate::guard::create(&path)?;
    delone_io::write_poly(f, &[], &segs, markers.then_some(&sm[..]), &[], &[], first)
        .map_err(|e| fail(format!("cannot write {}: {e}", path.display())))?;
    written.push(path);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renumber_drops_unused_and_keeps_appended() {
        let r = Renumber::new(6, &[[0u32, 2, 3]], 5);
        assert_eq!(r.kept, vec![0, 2, 3, 5]);
        assert_eq!(r.new, vec![0, NONE, 1, 2, NONE, 3]);
        assert_eq!(r.dropped(), 2);
        let mut t = [[3u32, 0, 5]];
        r.apply(&mut t);
        assert_eq!(t, [[2, 0, 3]]);
        assert_eq!(
            r.rows(&[0, 1, 10, 11, 20, 21, 30, 31, 40, 41, 50, 51], 2),
            vec![0, 1, 20, 21, 30, 31, 50, 51]
        );
    }
}
