//! Cut-away pictures of tetrahedral meshes: the way people look inside a
//! 3D mesh.
//!
//! [`render_tets`] keeps the tetrahedra whose centroid lies on the near
//! side of an axis-aligned cutting plane (or all of them), collects the
//! faces of that set that are not shared by two kept tetrahedra (the
//! domain's boundary and the faces exposed by the cut), and draws them with
//! an orthographic camera, flat Lambert shading and a depth buffer, then
//! the visible edges anti-aliased on top. Faces exposed by the cut take the
//! colour of their tetrahedron (e.g. by minimum dihedral angle), boundary
//! faces [`CutawayStyle::surface`].
//!
//! Edges fade with their projected length (an edge shorter than a few
//! pixels is drawn faintly), so a mesh of a million tetrahedra still shows
//! its shape instead of a black blot. Everything is plain `f64` arithmetic
//! in a fixed order: the same input gives the same pixels.

use crate::raster::Raster;
use crate::IoError;

/// Camera, cut and colours of [`render_tets`].
///
/// ```
/// let s = delone_io::CutawayStyle::default();
/// assert_eq!((s.width, s.height), (800, 600));
/// assert_eq!(s.cut, Some((0, 0.5)));
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct CutawayStyle {
    /// Picture width in pixels (16..=16384).
    pub width: u32,
    /// Picture height in pixels (16..=16384).
    pub height: u32,
    /// Camera azimuth about the z axis, degrees (0 looks from +x).
    pub azimuth: f64,
    /// Camera elevation above the xy plane, degrees.
    pub elevation: f64,
    /// Cutting plane: `(axis, fraction)` keeps the tetrahedra whose
    /// centroid's coordinate `axis` (0, 1, 2) is at most the bounding box's
    /// minimum plus `fraction` of its extent; `None` keeps all.
    pub cut: Option<(usize, f64)>,
    /// Colour of faces on the domain's boundary.
    pub surface: [u8; 3],
    /// Colour of faces exposed by the cut when no per-tetrahedron colours
    /// are given.
    pub interior: [u8; 3],
    /// Edge colour; `None` draws no edges.
    pub edges: Option<[u8; 3]>,
    /// Background; `None` leaves it transparent.
    pub background: Option<[u8; 3]>,
}

impl Default for CutawayStyle {
    fn default() -> Self {
        CutawayStyle {
            width: 800,
            height: 600,
            azimuth: -60.0,
            elevation: 25.0,
            cut: Some((0, 0.5)),
            surface: [170, 190, 215],
            interior: [240, 200, 120],
            edges: Some([30, 30, 40]),
            background: Some([255, 255, 255]),
        }
    }
}

/// A face to draw: its corners (outward from its kept tetrahedron) and
/// colour.
struct Face {
    v: [u32; 3],
    colour: [u8; 3],
}

/// Renders a cut-away picture of the tetrahedral mesh (`points`, `tets`)
/// (boundary faces and the faces exposed by the cut, depth-buffered and flat shaded). `tet_colour`, when given, has
/// one colour per tetrahedron for the faces the cut exposes.
///
/// # Errors
/// [`IoError::InvalidInput`] for a vertex index out of range, a
/// non-finite coordinate, a `tet_colour` of the wrong length, a picture size
/// outside 16..=16384, or a cut axis above 2.
///
/// ```
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// let style = delone_io::CutawayStyle { cut: None, width: 64, height: 64, ..Default::default() };
/// let img = delone_io::render_tets(&pts, &[[0, 1, 2, 3]], None, &style).unwrap();
/// assert_eq!((img.width, img.height), (64, 64));
/// // the tetrahedron covers the middle of the picture, not the corners
/// assert_ne!(img.pixel(32, 36), [255, 255, 255, 255]);
/// assert_eq!(img.pixel(1, 1), [255, 255, 255, 255]);
/// ```
pub fn render_tets(
    points: &[[f64; 3]],
    tets: &[[u32; 4]],
    tet_colour: Option<&[[u8; 3]]>,
    style: &CutawayStyle,
) -> Result<Raster, IoError> {
    check(points, tets, tet_colour, style)?;
    let kept = keep(points, tets, style);
    let faces = exposed_faces(points, tets, &kept, tet_colour, style);
    Ok(draw(points, &faces, style))
}

fn check(
    points: &[[f64; 3]],
    tets: &[[u32; 4]],
    tet_colour: Option<&[[u8; 3]]>,
    style: &CutawayStyle,
) -> Result<(), IoError> {
    for (name, v) in [("width", style.width), ("height", style.height)] {
        if !(16..=16384).contains(&v) {
            return Err(IoError::invalid(format!(
                "picture {name} must be 16 to 16384 pixels, not {v}"
            )));
        }
    }
    if let Some((axis, f)) = style.cut {
        if axis > 2 || !f.is_finite() {
            return Err(IoError::invalid(format!(
                "cut axis must be 0, 1 or 2 and its position finite, not ({axis}, {f})"
            )));
        }
    }
    if !(style.azimuth.is_finite() && style.elevation.is_finite()) {
        return Err(IoError::invalid("camera angles must be finite"));
    }
    if let Some(c) = tet_colour {
        if c.len() != tets.len() {
            return Err(IoError::invalid(format!(
                "{} tetrahedron colours for {} tetrahedra",
                c.len(),
                tets.len()
            )));
        }
    }
    for (i, p) in points.iter().enumerate() {
        if !p.iter().all(|x| x.is_finite()) {
            return Err(IoError::invalid(format!(
                "point {i} has a non-finite coordinate"
            )));
        }
    }
    for (t, tv) in tets.iter().enumerate() {
        if let Some(&v) = tv.iter().find(|&&v| v as usize >= points.len()) {
            return Err(IoError::invalid(format!(
                "tetrahedron {t} refers to vertex {v}, but there are {} points",
                points.len()
            )));
        }
    }
    Ok(())
}

/// Which tetrahedra the cut keeps.
fn keep(points: &[[f64; 3]], tets: &[[u32; 4]], style: &CutawayStyle) -> Vec<bool> {
    let Some((axis, frac)) = style.cut else {
        return vec![true; tets.len()];
    };
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for tv in tets {
        for &v in tv {
            let x = points[v as usize][axis];
            lo = lo.min(x);
            hi = hi.max(x);
        }
    }
    let at = lo + frac * (hi - lo);
    tets.iter()
        .map(|tv| tv.iter().map(|&v| points[v as usize][axis]).sum::<f64>() <= 4.0 * at)
        .collect()
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The faces of the kept set that are not shared by two kept tetrahedra,
/// oriented outward from their kept tetrahedron, in a deterministic order.
fn exposed_faces(
    points: &[[f64; 3]],
    tets: &[[u32; 4]],
    kept: &[bool],
    tet_colour: Option<&[[u8; 3]]>,
    style: &CutawayStyle,
) -> Vec<Face> {
    // (sorted face, tetrahedron, local face) for every face of every tet.
    let mut all: Vec<([u32; 3], u32, u8)> = Vec::with_capacity(4 * tets.len());
    for (t, tv) in tets.iter().enumerate() {
        for f in 0..4u8 {
            let mut k = [0u32; 3];
            let mut j = 0;
            for (i, &v) in tv.iter().enumerate() {
                if i != usize::from(f) {
                    k[j] = v;
                    j += 1;
                }
            }
            k.sort_unstable();
            all.push((k, t as u32, f));
        }
    }
    all.sort_unstable();
    let mut faces = Vec::new();
    let mut i = 0;
    while i < all.len() {
        let mut j = i + 1;
        while j < all.len() && all[j].0 == all[i].0 {
            j += 1;
        }
        let group = &all[i..j];
        let n_kept = group.iter().filter(|g| kept[g.1 as usize]).count();
        if n_kept == 1 {
            let &(k, t, f) = group.iter().find(|g| kept[g.1 as usize]).unwrap_or(&all[i]);
            let on_boundary = group.len() == 1;
            let colour = if on_boundary {
                style.surface
            } else {
                tet_colour.map_or(style.interior, |c| c[t as usize])
            };
            // Orient away from the tetrahedron's fourth vertex.
            let opp = points[tets[t as usize][usize::from(f)] as usize];
            let p = k.map(|v| points[v as usize]);
            let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
            let v = if dot(n, sub(opp, p[0])) > 0.0 {
                [k[0], k[2], k[1]]
            } else {
                k
            };
            faces.push(Face { v, colour });
        }
        i = j;
    }
    faces
}

/// Camera frame: right, up and toward-viewer unit vectors.
fn frame(style: &CutawayStyle) -> [[f64; 3]; 3] {
    let (sp, cp) = style.azimuth.to_radians().sin_cos();
    let (st, ct) = style.elevation.to_radians().sin_cos();
    [
        [-sp, cp, 0.0],
        [-st * cp, -st * sp, ct],
        [ct * cp, ct * sp, st],
    ]
}

fn draw(points: &[[f64; 3]], faces: &[Face], style: &CutawayStyle) -> Raster {
    let (w, h) = (style.width as usize, style.height as usize);
    let mut img = Raster {
        width: style.width,
        height: style.height,
        rgba: match style.background {
            Some(c) => [c[0], c[1], c[2], 255].repeat(w * h),
            None => vec![0; 4 * w * h],
        },
    };
    if faces.is_empty() {
        return img;
    }
    let [r, u, d] = frame(style);
    // Project the points the faces use; fit them into the picture.
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    let mut used = vec![false; points.len()];
    for f in faces {
        for &v in &f.v {
            used[v as usize] = true;
        }
    }
    let mut proj = vec![[0.0f64; 3]; points.len()];
    for (i, p) in points.iter().enumerate() {
        if used[i] {
            let q = [dot(*p, r), dot(*p, u), dot(*p, d)];
            x0 = x0.min(q[0]);
            x1 = x1.max(q[0]);
            y0 = y0.min(q[1]);
            y1 = y1.max(q[1]);
            proj[i] = q;
        }
    }
    let margin = 0.05 * w.min(h) as f64;
    let sx = (w as f64 - 2.0 * margin) / (x1 - x0).max(f64::MIN_POSITIVE);
    let sy = (h as f64 - 2.0 * margin) / (y1 - y0).max(f64::MIN_POSITIVE);
    let s = sx.min(sy);
    let ox = 0.5 * (w as f64 - s * (x1 - x0));
    let oy = 0.5 * (h as f64 - s * (y1 - y0));
    for (i, q) in proj.iter_mut().enumerate() {
        if used[i] {
            *q = [
                ox + s * (q[0] - x0),
                h as f64 - (oy + s * (q[1] - y0)),
                q[2],
            ];
        }
    }
    let (mut z0, mut z1) = (f64::INFINITY, f64::NEG_INFINITY);
    for (i, q) in proj.iter().enumerate() {
        if used[i] {
            z0 = z0.min(q[2]);
            z1 = z1.max(q[2]);
        }
    }
    let bias = 2e-3 * (z1 - z0).max(f64::MIN_POSITIVE);
    let light = {
        let l = [
            d[0] + 0.4 * u[0] - 0.3 * r[0],
            d[1] + 0.4 * u[1] - 0.3 * r[1],
            d[2] + 0.4 * u[2] - 0.3 * r[2],
        ];
        let n = dot(l, l).sqrt();
        l.map(|x| x / n)
    };
    let mut zbuf = vec![f64::NEG_INFINITY; w * h];
    let mut visible: Vec<usize> = Vec::new();
    for (fi, f) in faces.iter().enumerate() {
        let p = f.v.map(|v| points[v as usize]);
        let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
        let len = dot(n, n).sqrt();
        if len.is_nan() || len <= 0.0 || dot(n, d) <= 0.0 {
            continue; // degenerate or facing away
        }
        visible.push(fi);
        let shade = 0.35 + 0.65 * (dot(n, light) / len).max(0.0);
        let c = f
            .colour
            .map(|x| (f64::from(x) * shade + 0.5).min(255.0) as u8);
        fill(&mut img, &mut zbuf, f.v.map(|v| proj[v as usize]), c);
    }
    if let Some(ec) = style.edges {
        let mut edges: Vec<(u32, u32)> = visible
            .iter()
            .flat_map(|&fi| {
                let v = faces[fi].v;
                [(v[0], v[1]), (v[1], v[2]), (v[2], v[0])]
            })
            .map(|(a, b)| (a.min(b), a.max(b)))
            .collect();
        edges.sort_unstable();
        edges.dedup();
        for (a, b) in edges {
            line(
                &mut img,
                &zbuf,
                proj[a as usize],
                proj[b as usize],
                ec,
                bias,
            );
        }
    }
    img
}

/// Fills a projected triangle with depth test (pixel centres inside or on
/// an edge).
fn fill(img: &mut Raster, zbuf: &mut [f64], q: [[f64; 3]; 3], c: [u8; 3]) {
    let (w, h) = (img.width as i64, img.height as i64);
    let area =
        (q[1][0] - q[0][0]) * (q[2][1] - q[0][1]) - (q[2][0] - q[0][0]) * (q[1][1] - q[0][1]);
    if area == 0.0 || !area.is_finite() {
        return;
    }
    let minx = (q.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min) - 0.5)
        .ceil()
        .max(0.0) as i64;
    let maxx = (q.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max) - 0.5)
        .floor()
        .min((w - 1) as f64) as i64;
    let miny = (q.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min) - 0.5)
        .ceil()
        .max(0.0) as i64;
    let maxy = (q.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max) - 0.5)
        .floor()
        .min((h - 1) as f64) as i64;
    for y in miny..=maxy {
        let yc = y as f64 + 0.5;
        for x in minx..=maxx {
            let xc = x as f64 + 0.5;
            let mut l = [0.0; 3];
            let mut inside = true;
            for i in 0..3 {
                let (a, b) = (q[(i + 1) % 3], q[(i + 2) % 3]);
                l[i] = ((b[0] - a[0]) * (yc - a[1]) - (xc - a[0]) * (b[1] - a[1])) / area;
                if l[i] < 0.0 {
                    inside = false;
                    break;
                }
            }
            if !inside {
                continue;
            }
            let z = l[0] * q[0][2] + l[1] * q[1][2] + l[2] * q[2][2];
            let k = (y * w + x) as usize;
            if z > zbuf[k] {
                zbuf[k] = z;
                img.rgba[4 * k..4 * k + 4].copy_from_slice(&[c[0], c[1], c[2], 255]);
            }
        }
    }
}

/// Draws an anti-aliased line (two pixels across the minor axis, weighted
/// by distance) where it is not hidden behind a face; its opacity fades with
/// its projected length below 6 pixels.
fn line(img: &mut Raster, zbuf: &[f64], a: [f64; 3], b: [f64; 3], c: [u8; 3], bias: f64) {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len = (dx * dx + dy * dy).sqrt();
    if len.is_nan() || len <= 0.0 {
        return;
    }
    let alpha = 0.85 * (len / 6.0).min(1.0);
    let steep = dy.abs() > dx.abs();
    let n = (if steep { dy.abs() } else { dx.abs() }).ceil().max(1.0) as i64;
    let w = i64::from(img.width);
    let h = i64::from(img.height);
    for i in 0..=n {
        let t = i as f64 / n as f64;
        let (px, py, z) = (a[0] + t * dx, a[1] + t * dy, a[2] + t * (b[2] - a[2]));
        // Pixel centres at k + 0.5: split the minor coordinate between two.
        let (major, minor) = if steep { (py, px) } else { (px, py) };
        let m = (major - 0.5).round() as i64;
        let f = minor - 0.5;
        let k0 = f.floor() as i64;
        let frac = f - k0 as f64;
        for (k, cov) in [(k0, 1.0 - frac), (k0 + 1, frac)] {
            let (x, y) = if steep { (k, m) } else { (m, k) };
            if x < 0 || y < 0 || x >= w || y >= h {
                continue;
            }
            let idx = (y * w + x) as usize;
            if z + bias < zbuf[idx] {
                continue; // hidden
            }
            img.blend(x, y, c, alpha * cov);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> (Vec<[f64; 3]>, Vec<[u32; 4]>) {
        let pts: Vec<[f64; 3]> = (0..8)
            .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
            .collect();
        // Six tetrahedra around the diagonal 0–7.
        let tets = vec![
            [0, 1, 3, 7],
            [0, 3, 2, 7],
            [0, 2, 6, 7],
            [0, 6, 4, 7],
            [0, 4, 5, 7],
            [0, 5, 1, 7],
        ];
        (pts, tets)
    }

    #[test]
    fn cut_exposes_interior_colour_and_is_deterministic() {
        let (pts, tets) = cube();
        let red = vec![[255, 0, 0]; tets.len()];
        let style = CutawayStyle {
            width: 120,
            height: 120,
            edges: None,
            cut: Some((0, 0.5)),
            azimuth: 0.0, // looking from +x at the cut
            elevation: 0.0,
            ..Default::default()
        };
        let a = render_tets(&pts, &tets, Some(&red), &style).unwrap();
        let b = render_tets(&pts, &tets, Some(&red), &style).unwrap();
        assert_eq!(a, b);
        // Seen from +x the kept half shows faces exposed by the cut: reddish.
        let reddish = a
            .rgba
            .chunks(4)
            .filter(|p| u16::from(p[0]) > 2 * u16::from(p[1]) && p[0] > 60)
            .count();
        assert!(reddish > 1000, "{reddish}");
        // Without the cut only the boundary (surface colour) is visible.
        let all = render_tets(
            &pts,
            &tets,
            Some(&red),
            &CutawayStyle { cut: None, ..style },
        )
        .unwrap();
        let reddish = all
            .rgba
            .chunks(4)
            .filter(|p| u16::from(p[0]) > 2 * u16::from(p[1]) && p[0] > 60)
            .count();
        assert_eq!(reddish, 0);
    }

    #[test]
    fn edges_are_drawn() {
        let (pts, tets) = cube();
        let style = CutawayStyle {
            width: 100,
            height: 100,
            cut: None,
            azimuth: 0.0,
            elevation: 0.0,
            edges: Some([0, 0, 0]),
            ..Default::default()
        };
        let img = render_tets(&pts, &tets, None, &style).unwrap();
        // The cube seen face-on: its outline and the front face's diagonal
        // (bottom left to top right) are dark.
        let dark = img.rgba.chunks(4).filter(|p| p[0] < 100).count();
        assert!(dark > 100, "{dark}");
        // A pixel off every front edge stays the shaded surface colour.
        let p = img.pixel(30, 40);
        assert!(p[0] > 100, "{p:?}");
    }

    #[test]
    fn occluded_tetrahedra_leave_no_trace() {
        // A big tetrahedron in front (seen from +x) hides a small one behind.
        let pts = [
            [1.0, -5.0, -5.0],
            [1.0, 5.0, -5.0],
            [1.0, 0.0, 5.0],
            [0.5, 0.0, 0.0],
            [-3.0, 0.0, 0.0],
            [-3.0, 0.5, 0.0],
            [-3.0, 0.0, 0.5],
            [-3.5, 0.1, 0.1],
        ];
        let style = CutawayStyle {
            width: 80,
            height: 80,
            cut: None,
            azimuth: 0.0,
            elevation: 0.0,
            edges: Some([0, 0, 0]),
            ..Default::default()
        };
        let front = render_tets(&pts, &[[0, 1, 2, 3]], None, &style).unwrap();
        let both = render_tets(&pts, &[[0, 1, 2, 3], [4, 5, 6, 7]], None, &style).unwrap();
        assert_eq!(front, both);
        // Seen from behind, the small one shows.
        let back = CutawayStyle {
            azimuth: 180.0,
            ..style
        };
        let a = render_tets(&pts, &[[0, 1, 2, 3]], None, &back).unwrap();
        let b = render_tets(&pts, &[[0, 1, 2, 3], [4, 5, 6, 7]], None, &back).unwrap();
        assert_ne!(a, b);
    }

    #[test]
    fn bad_input_is_named() {
        let (pts, tets) = cube();
        let e = render_tets(&pts, &[[0, 1, 2, 9]], None, &CutawayStyle::default()).unwrap_err();
        assert!(
            e.to_string().contains("tetrahedron 0 refers to vertex 9"),
            "{e}"
        );
        let e = render_tets(&pts, &tets, Some(&[[0, 0, 0]]), &CutawayStyle::default()).unwrap_err();
        assert!(e.to_string().contains("1 tetrahedron colours for 6"), "{e}");
        let e = render_tets(
            &pts,
            &tets,
            None,
            &CutawayStyle {
                width: 3,
                ..Default::default()
            },
        )
        .unwrap_err();
        assert!(e.to_string().contains("width"), "{e}");
        let mut bad = pts.clone();
        bad[2][1] = f64::NAN;
        assert!(render_tets(&bad, &tets, None, &CutawayStyle::default()).is_err());
    }
}
