//! The PNG back end of the picture scene ([`SvgLayer`]s): a small
//! rasterizer of our own and the `png` crate for the encoding.
//!
//! * Filled triangles and polygons: scanline fill sampling pixel centres
//!   with a half-open rule (a pixel centre on an edge shared by two
//!   triangles belongs to exactly one of them), no anti-aliasing, so a
//!   triangle's interior pixels have exactly its colour.
//! * Lines (triangle edges, segments, polygon outlines, crosses):
//!   anti-aliased by the distance from the pixel centre to the segment,
//!   round caps, walked along the major axis so a long line costs its
//!   length times its width. Triangle edges shared by two triangles are
//!   drawn once.
//! * Dots: anti-aliased discs.
//! * The legend: swatches and labels in a built-in 3×5 pixel font (scaled
//!   2×) that knows digits, `.`, `-`, `<`, `>`, `=`, `+` and `°`.
//!
//! Colours are non-premultiplied RGBA; a transparent background
//! ([`SvgStyle::background`] `None`) stays transparent where nothing is drawn.

use std::io::Write;

use crate::svg::{
    check_scene, parse_colour, Frame, LegendBox, SvgLayer, SvgStyle, LEGEND_ROW, LEGEND_SWATCH,
};
use crate::IoError;

/// Largest picture the rasterizer accepts, in pixels.
const MAX_PIXELS: u64 = 1 << 28;

/// A rendered picture: `width × height` RGBA pixels, row by row from the
/// top.
///
/// ```
/// let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
/// let layers = [delone_io::SvgLayer::FilledTriangles {
///     points: &pts, triangles: &[[0, 1, 2]], fills: &[[255, 0, 0]] }];
/// let style = delone_io::SvgStyle { width: 100.0, margin: 0.0, ..Default::default() };
/// let img = delone_io::render(&[[0.0, 0.0], [1.0, 1.0]], &layers, &style).unwrap();
/// assert_eq!((img.width, img.height), (100, 100));
/// assert_eq!(img.pixel(10, 80), [255, 0, 0, 255]); // inside, near (0.1, 0.2)
/// assert_eq!(img.pixel(90, 10), [255, 255, 255, 255]); // background
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Raster {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// RGBA bytes, `4 * width * height`, top row first.
    pub rgba: Vec<u8>,
}

impl Raster {
    /// The RGBA value of pixel `(x, y)` (`y` counted from the top);
    /// transparent black outside the picture.
    ///
    /// ```
    /// let r = delone_io::Raster { width: 1, height: 1, rgba: vec![1, 2, 3, 4] };
    /// assert_eq!(r.pixel(0, 0), [1, 2, 3, 4]);
    /// assert_eq!(r.pixel(5, 0), [0, 0, 0, 0]);
    /// ```
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        if x >= self.width || y >= self.height {
            return [0; 4];
        }
        let i = 4 * (y as usize * self.width as usize + x as usize);
        [
            self.rgba[i],
            self.rgba[i + 1],
            self.rgba[i + 2],
            self.rgba[i + 3],
        ]
    }

    /// Blends `c` with opacity `a` (0..=1) over pixel `(x, y)`; ignores
    /// pixels outside.
    #[inline]
    pub(crate) fn blend(&mut self, x: i64, y: i64, c: [u8; 3], a: f64) {
        if x < 0 || y < 0 || x >= i64::from(self.width) || y >= i64::from(self.height) || a <= 0.0 {
            return;
        }
        let i = 4 * (y as usize * self.width as usize + x as usize);
        let a = a.min(1.0);
        if a >= 1.0 {
            self.rgba[i..i + 3].copy_from_slice(&c);
            self.rgba[i + 3] = 255;
            return;
        }
        let da = f64::from(self.rgba[i + 3]) / 255.0;
        let oa = a + da * (1.0 - a);
        for (k, &ck) in c.iter().enumerate() {
            let v = (f64::from(ck) * a + f64::from(self.rgba[i + k]) * da * (1.0 - a)) / oa;
            // `as u8` saturates; +0.5 rounds the non-negative value (cheaper
            // than `round`, a library call on baseline x86-64).
            self.rgba[i + k] = (v + 0.5) as u8;
        }
        self.rgba[i + 3] = (oa * 255.0 + 0.5) as u8;
    }

    /// Fills a polygon (pixel coordinates, even-odd rule) with `c`: a pixel
    /// is filled when its centre is inside, or on a left/top edge.
    fn fill_polygon(&mut self, poly: &[[f64; 2]], c: [u8; 3]) {
        if poly.len() < 3 {
            return;
        }
        let (mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY);
        for p in poly {
            y0 = y0.min(p[1]);
            y1 = y1.max(p[1]);
        }
        if !(y0.is_finite() && y1.is_finite()) {
            return;
        }
        // Rows whose centre y + 0.5 lies in [y0, y1).
        let r0 = ((y0 - 0.5).ceil().max(0.0)) as i64;
        let r1 = ((y1 - 0.5).ceil().min(f64::from(self.height))) as i64;
        let mut xs: Vec<f64> = Vec::with_capacity(8);
        for row in r0..r1 {
            let yc = row as f64 + 0.5;
            xs.clear();
            for k in 0..poly.len() {
                let a = poly[k];
                let b = poly[(k + 1) % poly.len()];
                let (lo, hi) = if a[1] <= b[1] { (a, b) } else { (b, a) };
                if lo[1] <= yc && yc < hi[1] {
                    xs.push(lo[0] + (yc - lo[1]) / (hi[1] - lo[1]) * (hi[0] - lo[0]));
                }
            }
            xs.sort_by(f64::total_cmp);
            for pair in xs.chunks_exact(2) {
                let c0 = ceil_pos(pair[0] - 0.5);
                let c1 = ceil_pos((pair[1] - 0.5).min(f64::from(self.width)));
                for x in c0..c1 {
                    self.blend(x, row, c, 1.0);
                }
            }
        }
    }

    /// An anti-aliased line of width `w` pixels with round caps.
    fn line(&mut self, a: [f64; 2], b: [f64; 2], w: f64, c: [u8; 3]) {
        if !(a[0].is_finite() && a[1].is_finite() && b[0].is_finite() && b[1].is_finite()) {
            return;
        }
        let alpha = w.clamp(0.0, 1.0);
        let r = (0.5 * w).max(0.5);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len2 = dx * dx + dy * dy;
        let inv = if len2 > 0.0 { 1.0 / len2 } else { 0.0 };
        let dist2 = |px: f64, py: f64| -> f64 {
            let t = (((px - a[0]) * dx + (py - a[1]) * dy) * inv).clamp(0.0, 1.0);
            let (qx, qy) = (a[0] + t * dx - px, a[1] + t * dy - py);
            qx * qx + qy * qy
        };
        let far2 = (r + 0.5) * (r + 0.5);
        let reach = r + 1.0;
        // Walk the major axis; `sw` swaps x and y.
        let sw = dy.abs() > dx.abs();
        let (a2, b2) = if sw {
            ([a[1], a[0]], [b[1], b[0]])
        } else {
            (a, b)
        };
        let (p, q) = if a2[0] <= b2[0] { (a2, b2) } else { (b2, a2) };
        let lim_major = f64::from(if sw { self.height } else { self.width });
        let lim_minor = f64::from(if sw { self.width } else { self.height });
        let m0 = (p[0] - reach).floor().max(0.0);
        let m1 = (q[0] + reach).ceil().min(lim_major);
        let len = len2.sqrt();
        let cos = if len > 0.0 { (q[0] - p[0]) / len } else { 1.0 };
        let half = reach / cos.max(1e-9) + 0.5;
        let mut m = m0;
        while m < m1 {
            let xc = (m + 0.5).clamp(p[0], q[0]);
            let yc = if q[0] > p[0] {
                p[1] + (xc - p[0]) / (q[0] - p[0]) * (q[1] - p[1])
            } else {
                p[1].min(q[1])
            };
            let (lo, hi) = if q[0] > p[0] {
                (yc - half, yc + half)
            } else {
                (p[1].min(q[1]) - reach, p[1].max(q[1]) + reach)
            };
            let n0 = floor_pos(lo);
            let n1 = ceil_pos(hi.min(lim_minor));
            for n in n0..n1 {
                let (x, y) = if sw { (n, m as i64) } else { (m as i64, n) };
                let d2 = dist2(x as f64 + 0.5, y as f64 + 0.5);
                if d2 < far2 {
                    let cov = (r + 0.5 - d2.sqrt()).min(1.0);
                    self.blend(x, y, c, cov * alpha);
                }
            }
            m += 1.0;
        }
    }

    /// An anti-aliased disc.
    fn disc(&mut self, p: [f64; 2], radius: f64, c: [u8; 3]) {
        if !(p[0].is_finite() && p[1].is_finite() && radius > 0.0) {
            return;
        }
        let x0 = (p[0] - radius - 1.0).floor().max(0.0) as i64;
        let x1 = (p[0] + radius + 1.0).ceil().min(f64::from(self.width)) as i64;
        let y0 = (p[1] - radius - 1.0).floor().max(0.0) as i64;
        let y1 = (p[1] + radius + 1.0).ceil().min(f64::from(self.height)) as i64;
        for y in y0..y1 {
            for x in x0..x1 {
                let d = ((x as f64 + 0.5 - p[0]).powi(2) + (y as f64 + 0.5 - p[1]).powi(2)).sqrt();
                self.blend(x, y, c, (radius + 0.5 - d).clamp(0.0, 1.0));
            }
        }
    }

    /// A filled axis-aligned rectangle with opacity `a`.
    fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, c: [u8; 3], a: f64) {
        let (x0, x1) = (x.round() as i64, (x + w).round() as i64);
        let (y0, y1) = (y.round() as i64, (y + h).round() as i64);
        for yy in y0..y1 {
            for xx in x0..x1 {
                self.blend(xx, yy, c, a);
            }
        }
    }

    /// A one-pixel rectangle outline.
    fn frame_rect(&mut self, x: f64, y: f64, w: f64, h: f64, c: [u8; 3]) {
        let (x0, x1) = (x.round() as i64, (x + w).round() as i64 - 1);
        let (y0, y1) = (y.round() as i64, (y + h).round() as i64 - 1);
        for xx in x0..=x1 {
            self.blend(xx, y0, c, 1.0);
            self.blend(xx, y1, c, 1.0);
        }
        for yy in y0..=y1 {
            self.blend(x0, yy, c, 1.0);
            self.blend(x1, yy, c, 1.0);
        }
    }

    /// Text in the built-in font, `scale` pixels per font pixel, top left
    /// corner at `(x, y)`.
    fn text(&mut self, x: f64, y: f64, s: &str, scale: i64, c: [u8; 3]) {
        let (mut cx, cy) = (x.round() as i64, y.round() as i64);
        for ch in s.chars() {
            if let Some(rows) = glyph(ch) {
                for (j, row) in rows.iter().enumerate() {
                    for i in 0..3 {
                        if row & (4 >> i) != 0 {
                            for sy in 0..scale {
                                for sx in 0..scale {
                                    self.blend(
                                        cx + i as i64 * scale + sx,
                                        cy + j as i64 * scale + sy,
                                        c,
                                        1.0,
                                    );
                                }
                            }
                        }
                    }
                }
                cx += 4 * scale;
            }
        }
    }
}

/// `floor(max(x, 0))` without a library call (NaN gives 0).
#[inline]
fn floor_pos(x: f64) -> i64 {
    x.max(0.0) as i64
}

/// `ceil(max(x, 0))` without a library call (NaN gives 0).
#[inline]
fn ceil_pos(x: f64) -> i64 {
    let x = x.max(0.0);
    let i = x as i64;
    i + i64::from((i as f64) < x)
}

/// The 3×5 glyph of `c` (rows top to bottom, bit 2 = left column).
fn glyph(c: char) -> Option<[u8; 5]> {
    Some(match c {
        '0' => [7, 5, 5, 5, 7],
        '1' => [2, 6, 2, 2, 7],
        '2' => [7, 1, 7, 4, 7],
        '3' => [7, 1, 7, 1, 7],
        '4' => [5, 5, 7, 1, 1],
        '5' => [7, 4, 7, 1, 7],
        '6' => [7, 4, 7, 5, 7],
        '7' => [7, 1, 1, 1, 1],
        '8' => [7, 5, 7, 5, 7],
        '9' => [7, 5, 7, 1, 7],
        '.' => [0, 0, 0, 0, 2],
        '-' => [0, 0, 7, 0, 0],
        '<' => [1, 2, 4, 2, 1],
        '>' => [4, 2, 1, 2, 4],
        '=' => [0, 7, 0, 7, 0],
        '+' => [0, 2, 7, 2, 0],
        '°' => [2, 5, 2, 0, 0],
        ' ' => [0, 0, 0, 0, 0],
        _ => return None,
    })
}

fn colour_of(k: usize, s: &str) -> Result<[u8; 3], IoError> {
    parse_colour(s).ok_or_else(|| {
        IoError::invalid(format!(
            "picture layer {k}: colour {s:?} is not #rrggbb, #rgb or a known name"
        ))
    })
}

/// Renders the scene `view`, `layers`, `style` (the same arguments as
/// [`write_svg`](crate::write_svg)) to pixels; the picture is
/// `ceil(width + 2 margin)` pixels wide.
///
/// # Errors
/// Those of [`write_svg`](crate::write_svg), plus [`IoError::InvalidInput`]
/// for a colour [`parse_colour`] does not know or a picture of more than
/// 2²⁸ pixels.
///
/// ```
/// let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
/// let layers = [delone_io::SvgLayer::Triangles {
///     points: &pts, triangles: &[[0, 1, 2]], stroke: "hot pink", width: 1.0 }];
/// assert!(delone_io::render(&[[0.0, 0.0], [1.0, 1.0]], &layers, &Default::default()).is_err());
/// ```
pub fn render(
    view: &[[f64; 2]; 2],
    layers: &[SvgLayer<'_>],
    style: &SvgStyle,
) -> Result<Raster, IoError> {
    let frame: Frame = check_scene(*view, layers, style)?;
    let width = frame.size[0].ceil().max(1.0) as u64;
    let height = frame.size[1].ceil().max(1.0) as u64;
    if width * height > MAX_PIXELS {
        return Err(IoError::invalid(format!(
            "a {width} × {height} pixel picture is too large"
        )));
    }
    let bg = match &style.background {
        Some(b) => Some(parse_colour(b).ok_or_else(|| {
            IoError::invalid(format!(
                "background colour {b:?} is not #rrggbb, #rgb or a known name"
            ))
        })?),
        None => None,
    };
    let mut img = Raster {
        width: width as u32,
        height: height as u32,
        rgba: match bg {
            Some(c) => [c[0], c[1], c[2], 255].repeat((width * height) as usize),
            None => vec![0; (4 * width * height) as usize],
        },
    };
    for (k, layer) in layers.iter().enumerate() {
        match layer {
            SvgLayer::Triangles {
                points,
                triangles,
                stroke,
                width,
            } => {
                let c = colour_of(k, stroke)?;
                let mut edges: Vec<u64> = triangles
                    .iter()
                    .flat_map(|t| {
                        (0..3).map(move |i| {
                            let (a, b) = (t[i], t[(i + 1) % 3]);
                            (u64::from(a.min(b)) << 32) | u64::from(a.max(b))
                        })
                    })
                    .collect();
                edges.sort_unstable();
                edges.dedup();
                for e in edges {
                    let (a, b) = ((e >> 32) as usize, (e & 0xffff_ffff) as usize);
                    img.line(frame.tx(&points[a]), frame.tx(&points[b]), *width, c);
                }
            }
            SvgLayer::FilledTriangles {
                points,
                triangles,
                fills,
            } => {
                for (t, c) in triangles.iter().zip(fills.iter()) {
                    let poly = t.map(|v| frame.tx(&points[v as usize]));
                    img.fill_polygon(&poly, *c);
                }
            }
            SvgLayer::Polygons {
                points,
                offsets,
                fills,
                stroke,
                width,
            } => {
                let c = colour_of(k, stroke)?;
                for i in 0..offsets.len().saturating_sub(1) {
                    let poly: Vec<[f64; 2]> = points[offsets[i] as usize..offsets[i + 1] as usize]
                        .iter()
                        .map(|p| frame.tx(p))
                        .collect();
                    if poly.len() < 2 {
                        continue;
                    }
                    if let Some(f) = fills.get(i) {
                        img.fill_polygon(&poly, *f);
                    }
                    for j in 0..poly.len() {
                        img.line(poly[j], poly[(j + 1) % poly.len()], *width, c);
                    }
                }
            }
            SvgLayer::Segments {
                points,
                segments,
                stroke,
                width,
            } => {
                let c = colour_of(k, stroke)?;
                for s in segments.iter() {
                    img.line(
                        frame.tx(&points[s[0] as usize]),
                        frame.tx(&points[s[1] as usize]),
                        *width,
                        c,
                    );
                }
            }
            SvgLayer::Points {
                points,
                radius,
                fill,
            } => {
                let c = colour_of(k, fill)?;
                for p in points.iter() {
                    img.disc(frame.tx(p), *radius, c);
                }
            }
            SvgLayer::Crosses {
                points,
                size,
                stroke,
                width,
            } => {
                let c = colour_of(k, stroke)?;
                for p in points.iter() {
                    let q = frame.tx(p);
                    img.line(
                        [q[0] - size, q[1] - size],
                        [q[0] + size, q[1] + size],
                        *width,
                        c,
                    );
                    img.line(
                        [q[0] - size, q[1] + size],
                        [q[0] + size, q[1] - size],
                        *width,
                        c,
                    );
                }
            }
            SvgLayer::Legend { entries } => {
                let lg = LegendBox::new(entries.len(), frame.margin);
                let edge = [0x44, 0x44, 0x44];
                img.rect(lg.x, lg.y, lg.w, lg.h, [255, 255, 255], 0.85);
                img.frame_rect(lg.x, lg.y, lg.w, lg.h, edge);
                for (i, (c, label)) in entries.iter().enumerate() {
                    let [sx, sy] = lg.swatch(i);
                    img.rect(sx, sy, LEGEND_SWATCH, LEGEND_SWATCH, *c, 1.0);
                    img.frame_rect(sx, sy, LEGEND_SWATCH, LEGEND_SWATCH, edge);
                    img.text(
                        sx + LEGEND_SWATCH + 6.0,
                        sy + 0.5 * (LEGEND_SWATCH - 10.0),
                        label,
                        2,
                        [0, 0, 0],
                    );
                }
                let _ = LEGEND_ROW;
            }
        }
    }
    Ok(img)
}

/// Writes the scene as an 8-bit RGBA PNG: the picture [`render`] makes,
/// encoded by the `png` crate.
///
/// # Errors
/// Those of [`render`]; [`IoError::Io`] if the writer fails.
///
/// ```
/// let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
/// let mut out = Vec::new();
/// delone_io::write_png(
///     &mut out,
///     [[0.0, 0.0], [1.0, 1.0]],
///     &[delone_io::SvgLayer::Triangles { points: &pts, triangles: &[[0, 1, 2]], stroke: "black", width: 1.0 }],
///     &delone_io::SvgStyle::default(),
/// )
/// .unwrap();
/// assert_eq!(&out[..8], b"\x89PNG\r\n\x1a\n");
/// ```
pub fn write_png<W: Write>(
    out: W,
    view: [[f64; 2]; 2],
    layers: &[SvgLayer<'_>],
    style: &SvgStyle,
) -> Result<(), IoError> {
    let img = render(&view, layers, style)?;
    write_raster_png(out, &img)
}

/// Encodes a [`Raster`] as an RGBA PNG.
///
/// # Errors
/// [`IoError::Io`] when writing fails.
///
/// ```
/// let img = delone_io::Raster { width: 1, height: 1, rgba: vec![9, 9, 9, 255] };
/// let mut out = Vec::new();
/// delone_io::write_raster_png(&mut out, &img).unwrap();
/// assert_eq!(&out[..8], b"\x89PNG\r\n\x1a\n");
/// ```
pub fn write_raster_png<W: Write>(out: W, img: &Raster) -> Result<(), IoError> {
    let mut enc = png::Encoder::new(out, img.width, img.height);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    let conv = |e: png::EncodingError| match e {
        png::EncodingError::IoError(io) => IoError::Io(io),
        other => IoError::invalid(format!("PNG encoding failed: {other}")),
    };
    let mut w = enc.write_header().map_err(conv)?;
    w.write_image_data(&img.rgba).map_err(conv)?;
    w.finish().map_err(conv)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn style(w: f64) -> SvgStyle {
        SvgStyle {
            width: w,
            margin: 0.0,
            background: Some("white".into()),
        }
    }

    #[test]
    fn rounding_helpers() {
        for x in [0.0, 0.2, 1.0, 1.5, 7.999, 1e6 + 0.5] {
            assert_eq!(floor_pos(x), x.floor() as i64);
            assert_eq!(ceil_pos(x), x.ceil() as i64);
        }
        assert_eq!((floor_pos(-3.5), ceil_pos(-3.5)), (0, 0));
        assert_eq!(ceil_pos(f64::NAN), 0);
    }

    #[test]
    fn shared_edges_fill_every_pixel_once() {
        // Two triangles covering the unit square: every pixel is filled by
        // exactly one of them (no gaps, no double coverage visible as a
        // third colour).
        let pts = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let tris = [[0, 1, 2], [0, 2, 3]];
        let fills = [[255, 0, 0], [0, 0, 255]];
        let img = render(
            &[[0.0, 0.0], [1.0, 1.0]],
            &[SvgLayer::FilledTriangles {
                points: &pts,
                triangles: &tris,
                fills: &fills,
            }],
            &style(37.0),
        )
        .unwrap();
        assert_eq!((img.width, img.height), (37, 37));
        let (mut red, mut blue) = (0, 0);
        for y in 0..37 {
            for x in 0..37 {
                match img.pixel(x, y) {
                    [255, 0, 0, 255] => red += 1,
                    [0, 0, 255, 255] => blue += 1,
                    p => panic!("pixel {x} {y} is {p:?}"),
                }
                // Triangle 0 is below the anti-diagonal x + y = 37 (pixels).
                if x + y > 38 {
                    assert_eq!(img.pixel(x, y)[0], 255, "{x} {y}");
                }
            }
        }
        assert_eq!(red + blue, 37 * 37);
        assert!((red as i64 - blue as i64).abs() <= 37);
    }

    #[test]
    fn lines_cover_their_pixels_and_nothing_far() {
        let pts = [[0.0, 0.5], [1.0, 0.5]];
        let img = render(
            &[[0.0, 0.0], [1.0, 1.0]],
            &[SvgLayer::Segments {
                points: &pts,
                segments: &[[0, 1]],
                stroke: "#000",
                width: 3.0,
            }],
            &style(20.0),
        )
        .unwrap();
        // The line is y = 10 px, 3 px wide: rows 9 and 10 fully black.
        for x in 2..18 {
            assert_eq!(img.pixel(x, 9), [0, 0, 0, 255]);
            assert_eq!(img.pixel(x, 10), [0, 0, 0, 255]);
            assert_eq!(img.pixel(x, 3), [255, 255, 255, 255]);
            assert_eq!(img.pixel(x, 16), [255, 255, 255, 255]);
        }
        // A steep line is walked along y.
        let pts = [[0.3, 0.0], [0.31, 1.0]];
        let img = render(
            &[[0.0, 0.0], [1.0, 1.0]],
            &[SvgLayer::Segments {
                points: &pts,
                segments: &[[0, 1]],
                stroke: "black",
                width: 1.0,
            }],
            &style(100.0),
        )
        .unwrap();
        for y in 1..99 {
            let dark = (25..36).filter(|&x| img.pixel(x, y)[0] < 128).count();
            assert!(dark >= 1, "row {y}");
        }
    }

    #[test]
    fn transparent_background_and_font() {
        let s = SvgStyle {
            width: 130.0,
            margin: 0.0,
            background: None,
        };
        let entries = [([255u8, 0, 0], "< 10°"), ([0, 255, 0], "30-40")];
        let img = render(
            &[[0.0, 0.0], [1.0, 1.0]],
            &[SvgLayer::Legend { entries: &entries }],
            &s,
        )
        .unwrap();
        assert_eq!(img.pixel(128, 128), [0, 0, 0, 0]);
        let lg = LegendBox::new(2, 0.0);
        let [sx, sy] = lg.swatch(0);
        assert_eq!(
            img.pixel((sx + 5.0) as u32, (sy + 5.0) as u32),
            [255, 0, 0, 255]
        );
        // Some black text pixels right of the first swatch.
        let x0 = (sx + LEGEND_SWATCH + 6.0) as u32;
        let black = (x0..x0 + 40)
            .flat_map(|x| (sy as u32..sy as u32 + 11).map(move |y| (x, y)))
            .filter(|&(x, y)| img.pixel(x, y) == [0, 0, 0, 255])
            .count();
        assert!(black > 10, "{black}");
    }
}
