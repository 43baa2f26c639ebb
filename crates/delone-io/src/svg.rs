//! 2D pictures: a scene (a view rectangle, [`SvgLayer`]s drawn in order, a
//! [`SvgStyle`]) and two back ends, [`write_svg`] here and
//! [`write_png`](crate::write_png) (our own rasterizer), which draw the same
//! scene the same way.
//!
//! Colours are SVG colour strings; both back ends understand `#rrggbb`,
//! `#rgb` and the names in [`parse_colour`] (the SVG writer passes any other
//! string through, the PNG writer rejects it).

use std::io::Write;

use crate::out::Out;
use crate::IoError;

/// Picture settings for [`write_svg`].
#[derive(Debug, Clone, PartialEq)]
pub struct SvgStyle {
    /// Width of the picture in pixels (the height follows the view's aspect
    /// ratio).
    pub width: f64,
    /// Blank border around the view, in pixels.
    pub margin: f64,
    /// Background colour (any SVG colour), or `None` for transparent.
    pub background: Option<String>,
}

impl Default for SvgStyle {
    /// 800 pixels wide, a 10 pixel margin, white background.
    ///
    /// ```
    /// let s = delone_io::SvgStyle::default();
    /// assert_eq!(s.width, 800.0);
    /// ```
    fn default() -> Self {
        SvgStyle {
            width: 800.0,
            margin: 10.0,
            background: Some("white".into()),
        }
    }
}

/// One layer of a picture; layers are drawn in order (later on top).
/// Colours are SVG colour strings (`"black"`, `"#336699"`); widths and radii
/// are in pixels.
#[derive(Debug, Clone, PartialEq)]
pub enum SvgLayer<'a> {
    /// Triangle outlines.
    Triangles {
        /// Vertex coordinates.
        points: &'a [[f64; 2]],
        /// Triangles as vertex triples.
        triangles: &'a [[u32; 3]],
        /// Stroke colour.
        stroke: &'a str,
        /// Stroke width.
        width: f64,
    },
    /// Polygons given by their corners: polygon `i` is
    /// `points[offsets[i]..offsets[i + 1]]`.
    Polygons {
        /// Corner coordinates, polygon after polygon.
        points: &'a [[f64; 2]],
        /// Polygon ranges (one more entry than polygons).
        offsets: &'a [u32],
        /// Fill colour per polygon as RGB, or empty for no fill.
        fills: &'a [[u8; 3]],
        /// Stroke colour.
        stroke: &'a str,
        /// Stroke width.
        width: f64,
    },
    /// Dots.
    Points {
        /// Dot centres.
        points: &'a [[f64; 2]],
        /// Dot radius.
        radius: f64,
        /// Fill colour.
        fill: &'a str,
    },
    /// Triangles filled with one colour each (no outline; draw a
    /// [`SvgLayer::Triangles`] layer on top for the edges).
    FilledTriangles {
        /// Vertex coordinates.
        points: &'a [[f64; 2]],
        /// Triangles as vertex triples.
        triangles: &'a [[u32; 3]],
        /// Fill colour (RGB) per triangle.
        fills: &'a [[u8; 3]],
    },
    /// Line segments between points (e.g. the input segments of a PSLG,
    /// drawn thick).
    Segments {
        /// Vertex coordinates.
        points: &'a [[f64; 2]],
        /// Segments as vertex pairs.
        segments: &'a [[u32; 2]],
        /// Stroke colour.
        stroke: &'a str,
        /// Stroke width.
        width: f64,
    },
    /// `×` marks (e.g. hole seed points).
    Crosses {
        /// Mark centres.
        points: &'a [[f64; 2]],
        /// Half the size of a mark, in pixels.
        size: f64,
        /// Stroke colour.
        stroke: &'a str,
        /// Stroke width.
        width: f64,
    },
    /// A legend box in the top left corner of the picture: one colour
    /// swatch and label per entry (the PNG back end draws the swatches and
    /// labels made of digits, `.`, `-`, `<`, `>`, `=`, `+` and spaces in a
    /// small built-in font; other characters are left out).
    Legend {
        /// Swatch colours and labels.
        entries: &'a [([u8; 3], &'a str)],
    },
}

/// Parses `#rrggbb`, `#rgb` or one of the names `black`, `white`, `red`,
/// `green`, `blue`, `gray`/`grey`, `orange`, `yellow`, `purple` into RGB.
///
/// ```
/// assert_eq!(delone_io::parse_colour("#3366aa"), Some([0x33, 0x66, 0xaa]));
/// assert_eq!(delone_io::parse_colour("#f00"), Some([255, 0, 0]));
/// assert_eq!(delone_io::parse_colour("grey"), Some([128, 128, 128]));
/// assert_eq!(delone_io::parse_colour("teal-ish"), None);
/// ```
pub fn parse_colour(s: &str) -> Option<[u8; 3]> {
    let s = s.trim();
    if let Some(h) = s.strip_prefix('#') {
        let d: Option<Vec<u8>> = h.chars().map(|c| c.to_digit(16).map(|v| v as u8)).collect();
        return match d?.as_slice() {
            [r, g, b] => Some([r * 17, g * 17, b * 17]),
            [r1, r2, g1, g2, b1, b2] => Some([r1 * 16 + r2, g1 * 16 + g2, b1 * 16 + b2]),
            _ => None,
        };
    }
    Some(match s.to_ascii_lowercase().as_str() {
        "black" => [0, 0, 0],
        "white" => [255, 255, 255],
        "red" => [255, 0, 0],
        "green" => [0, 128, 0],
        "blue" => [0, 0, 255],
        "gray" | "grey" => [128, 128, 128],
        "orange" => [255, 165, 0],
        "yellow" => [255, 255, 0],
        "purple" => [128, 0, 128],
        _ => return None,
    })
}

/// The mapping from the view to pixels shared by both back ends: `y` grows
/// upwards in the view and downwards in the picture.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Frame {
    pub(crate) lo: [f64; 2],
    pub(crate) hi: [f64; 2],
    pub(crate) scale: f64,
    pub(crate) margin: f64,
    /// Picture size in pixels (fractional for SVG).
    pub(crate) size: [f64; 2],
}

impl Frame {
    #[inline]
    pub(crate) fn tx(&self, p: &[f64; 2]) -> [f64; 2] {
        [
            self.margin + (p[0] - self.lo[0]) * self.scale,
            self.margin + (self.hi[1] - p[1]) * self.scale,
        ]
    }
}

/// Checks the view, the style and every layer's indices; returns the frame.
pub(crate) fn check_scene(
    view: [[f64; 2]; 2],
    layers: &[SvgLayer<'_>],
    style: &SvgStyle,
) -> Result<Frame, IoError> {
    let [lo, hi] = view;
    let (w, h) = (hi[0] - lo[0], hi[1] - lo[1]);
    if !(w.is_finite() && h.is_finite() && w > 0.0 && h > 0.0)
        || !(style.width.is_finite()
            && style.width > 0.0
            && style.margin.is_finite()
            && style.margin >= 0.0)
    {
        return Err(IoError::invalid(format!(
            "the picture view {view:?} (width {} px) is empty or not finite",
            style.width
        )));
    }
    for (k, layer) in layers.iter().enumerate() {
        match layer {
            SvgLayer::Triangles {
                points, triangles, ..
            } => {
                if let Some(t) = triangles
                    .iter()
                    .position(|t| t.iter().any(|&v| v as usize >= points.len()))
                {
                    return Err(IoError::invalid(format!(
                        "picture layer {k}: triangle {t} refers to a missing point"
                    )));
                }
            }
            SvgLayer::Polygons {
                points,
                offsets,
                fills,
                ..
            } => {
                let ok = (offsets.is_empty() || offsets[0] == 0)
                    && offsets.windows(2).all(|w| w[0] <= w[1])
                    && offsets.last().map_or(0, |&o| o as usize) == points.len();
                let n = offsets.len().saturating_sub(1);
                if !ok || !(fills.is_empty() || fills.len() == n) {
                    return Err(IoError::invalid(format!(
                        "picture layer {k}: offsets or fills do not match {} points",
                        points.len()
                    )));
                }
            }
            SvgLayer::FilledTriangles {
                points,
                triangles,
                fills,
            } => {
                if let Some(t) = triangles
                    .iter()
                    .position(|t| t.iter().any(|&v| v as usize >= points.len()))
                {
                    return Err(IoError::invalid(format!(
                        "picture layer {k}: triangle {t} refers to a missing point"
                    )));
                }
                if fills.len() != triangles.len() {
                    return Err(IoError::invalid(format!(
                        "picture layer {k}: {} fills for {} triangles",
                        fills.len(),
                        triangles.len()
                    )));
                }
            }
            SvgLayer::Segments {
                points, segments, ..
            } => {
                if let Some(t) = segments
                    .iter()
                    .position(|t| t.iter().any(|&v| v as usize >= points.len()))
                {
                    return Err(IoError::invalid(format!(
                        "picture layer {k}: segment {t} refers to a missing point"
                    )));
                }
            }
            SvgLayer::Points { .. } | SvgLayer::Crosses { .. } | SvgLayer::Legend { .. } => {}
        }
    }
    let scale = style.width / w;
    let size = [
        style.width + 2.0 * style.margin,
        h * scale + 2.0 * style.margin,
    ];
    if !(size[1].is_finite() && size[1] < 1e7) {
        return Err(IoError::invalid(format!(
            "the picture view {view:?} is too tall for a {} px wide picture",
            style.width
        )));
    }
    Ok(Frame {
        lo,
        hi,
        scale,
        margin: style.margin,
        size,
    })
}

/// Appends `x` with two decimals (pixel coordinates).
fn px(o: &mut Vec<u8>, x: f64) {
    let _ = write!(o, "{:.2}", x);
}

/// Escapes a colour string for an attribute value (drops quotes and angle
/// brackets, which no valid colour contains).
fn colour(s: &str) -> String {
    s.chars()
        .filter(|c| !matches!(c, '"' | '<' | '>' | '&'))
        .collect()
}

/// Height of one legend row, in pixels.
pub(crate) const LEGEND_ROW: f64 = 16.0;
/// Side of a legend swatch, in pixels.
pub(crate) const LEGEND_SWATCH: f64 = 11.0;

/// Where the legend box and its rows go (shared by both back ends).
pub(crate) struct LegendBox {
    pub(crate) x: f64,
    pub(crate) y: f64,
    pub(crate) w: f64,
    pub(crate) h: f64,
}

impl LegendBox {
    pub(crate) fn new(rows: usize, margin: f64) -> Self {
        LegendBox {
            x: margin + 4.0,
            y: margin + 4.0,
            w: 112.0,
            h: rows as f64 * LEGEND_ROW + 8.0,
        }
    }

    /// Top left corner of swatch `i`.
    pub(crate) fn swatch(&self, i: usize) -> [f64; 2] {
        [
            self.x + 6.0,
            self.y + 4.0 + i as f64 * LEGEND_ROW + (LEGEND_ROW - LEGEND_SWATCH) / 2.0,
        ]
    }
}

/// Writes an SVG picture of `layers` showing the region `view = [min, max]`
/// (mathematical orientation: y grows upwards).
///
/// # Errors
/// [`IoError::InvalidInput`] if the view is empty or not finite, or a layer
/// refers to missing points, has inconsistent offsets or fills;
/// [`IoError::Io`] if the writer fails.
///
/// ```
/// let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
/// let mut out = Vec::new();
/// delone_io::write_svg(
///     &mut out,
///     [[0.0, 0.0], [1.0, 1.0]],
///     &[
///         delone_io::SvgLayer::Triangles { points: &pts, triangles: &[[0, 1, 2]], stroke: "black", width: 1.0 },
///         delone_io::SvgLayer::Points { points: &pts, radius: 2.0, fill: "red" },
///     ],
///     &delone_io::SvgStyle::default(),
/// )
/// .unwrap();
/// let svg = String::from_utf8(out).unwrap();
/// assert!(svg.starts_with("<svg"));
/// assert_eq!(svg.matches("<circle").count(), 3);
/// ```
pub fn write_svg<W: Write>(
    out: W,
    view: [[f64; 2]; 2],
    layers: &[SvgLayer<'_>],
    style: &SvgStyle,
) -> Result<(), IoError> {
    let frame = check_scene(view, layers, style)?;
    let [mw, mh] = frame.size;
    let tx = |p: &[f64; 2]| frame.tx(p);
    let mut o = Out::new(out);
    o.str("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"");
    px(&mut o.buf, mw);
    o.str("\" height=\"");
    px(&mut o.buf, mh);
    o.str("\" viewBox=\"0 0 ");
    px(&mut o.buf, mw);
    o.byte(b' ');
    px(&mut o.buf, mh);
    o.str("\">");
    o.nl()?;
    if let Some(bg) = &style.background {
        o.str("<rect width=\"100%\" height=\"100%\" fill=\"");
        o.str(&colour(bg));
        o.str("\"/>");
        o.nl()?;
    }
    let path_point = |o: &mut Out<W>, cmd: u8, p: &[f64; 2]| {
        let q = tx(p);
        o.byte(cmd);
        px(&mut o.buf, q[0]);
        o.byte(b' ');
        px(&mut o.buf, q[1]);
    };
    for layer in layers {
        match layer {
            SvgLayer::Triangles {
                points,
                triangles,
                stroke,
                width,
            } => {
                o.str("<path fill=\"none\" stroke-linejoin=\"round\" stroke=\"");
                o.str(&colour(stroke));
                o.str("\" stroke-width=\"");
                px(&mut o.buf, *width);
                o.str("\" d=\"");
                for t in triangles.iter() {
                    for (k, &v) in t.iter().enumerate() {
                        path_point(
                            &mut o,
                            if k == 0 { b'M' } else { b'L' },
                            &points[v as usize],
                        );
                    }
                    o.byte(b'Z');
                    o.maybe_flush()?;
                }
                o.str("\"/>");
                o.nl()?;
            }
            SvgLayer::Polygons {
                points,
                offsets,
                fills,
                stroke,
                width,
            } => {
                o.str("<g stroke-linejoin=\"round\" stroke=\"");
                o.str(&colour(stroke));
                o.str("\" stroke-width=\"");
                px(&mut o.buf, *width);
                o.str("\">");
                o.nl()?;
                for i in 0..offsets.len().saturating_sub(1) {
                    let poly = &points[offsets[i] as usize..offsets[i + 1] as usize];
                    if poly.len() < 2 {
                        continue;
                    }
                    o.str("<path fill=\"");
                    match fills.get(i) {
                        Some(c) => {
                            let _ = write!(o.buf, "#{:02x}{:02x}{:02x}", c[0], c[1], c[2]);
                        }
                        None => o.str("none"),
                    }
                    o.str("\" d=\"");
                    for (k, p) in poly.iter().enumerate() {
                        path_point(&mut o, if k == 0 { b'M' } else { b'L' }, p);
                    }
                    o.str("Z\"/>");
                    o.nl()?;
                }
                o.str("</g>");
                o.nl()?;
            }
            SvgLayer::Points {
                points,
                radius,
                fill,
            } => {
                o.str("<g fill=\"");
                o.str(&colour(fill));
                o.str("\">");
                o.nl()?;
                for p in points.iter() {
                    let q = tx(p);
                    o.str("<circle cx=\"");
                    px(&mut o.buf, q[0]);
                    o.str("\" cy=\"");
                    px(&mut o.buf, q[1]);
                    o.str("\" r=\"");
                    px(&mut o.buf, *radius);
                    o.str("\"/>");
                    o.nl()?;
                }
                o.str("</g>");
                o.nl()?;
            }
            SvgLayer::FilledTriangles {
                points,
                triangles,
                fills,
            } => {
                // One path per colour, colours in order of first use.
                let mut order: Vec<[u8; 3]> = Vec::new();
                let mut by: std::collections::BTreeMap<[u8; 3], Vec<usize>> =
                    std::collections::BTreeMap::new();
                for (t, c) in fills.iter().enumerate() {
                    by.entry(*c)
                        .or_insert_with(|| {
                            order.push(*c);
                            Vec::new()
                        })
                        .push(t);
                }
                for c in &order {
                    let _ = write!(
                        o.buf,
                        "<path stroke=\"none\" fill=\"#{:02x}{:02x}{:02x}\" d=\"",
                        c[0], c[1], c[2]
                    );
                    for &t in &by[c] {
                        for (k, &v) in triangles[t].iter().enumerate() {
                            path_point(
                                &mut o,
                                if k == 0 { b'M' } else { b'L' },
                                &points[v as usize],
                            );
                        }
                        o.byte(b'Z');
                        o.maybe_flush()?;
                    }
                    o.str("\"/>");
                    o.nl()?;
                }
            }
            SvgLayer::Segments {
                points,
                segments,
                stroke,
                width,
            } => {
                o.str("<path fill=\"none\" stroke-linecap=\"round\" stroke=\"");
                o.str(&colour(stroke));
                o.str("\" stroke-width=\"");
                px(&mut o.buf, *width);
                o.str("\" d=\"");
                for s in segments.iter() {
                    path_point(&mut o, b'M', &points[s[0] as usize]);
                    path_point(&mut o, b'L', &points[s[1] as usize]);
                    o.maybe_flush()?;
                }
                o.str("\"/>");
                o.nl()?;
            }
            SvgLayer::Crosses {
                points,
                size,
                stroke,
                width,
            } => {
                o.str("<path fill=\"none\" stroke-linecap=\"round\" stroke=\"");
                o.str(&colour(stroke));
                o.str("\" stroke-width=\"");
                px(&mut o.buf, *width);
                o.str("\" d=\"");
                for p in points.iter() {
                    let q = tx(p);
                    for (a, b) in [([-1.0, -1.0], [1.0, 1.0]), ([-1.0, 1.0], [1.0, -1.0])] {
                        o.byte(b'M');
                        px(&mut o.buf, q[0] + a[0] * size);
                        o.byte(b' ');
                        px(&mut o.buf, q[1] + a[1] * size);
                        o.byte(b'L');
                        px(&mut o.buf, q[0] + b[0] * size);
                        o.byte(b' ');
                        px(&mut o.buf, q[1] + b[1] * size);
                    }
                }
                o.str("\"/>");
                o.nl()?;
            }
            SvgLayer::Legend { entries } => {
                let lg = LegendBox::new(entries.len(), frame.margin);
                o.str("<g font-family=\"sans-serif\" font-size=\"");
                px(&mut o.buf, LEGEND_ROW - 4.0);
                o.str("\"><rect fill=\"white\" fill-opacity=\"0.85\" stroke=\"#444444\" x=\"");
                px(&mut o.buf, lg.x);
                o.str("\" y=\"");
                px(&mut o.buf, lg.y);
                o.str("\" width=\"");
                px(&mut o.buf, lg.w);
                o.str("\" height=\"");
                px(&mut o.buf, lg.h);
                o.str("\"/>");
                o.nl()?;
                for (i, (c, label)) in entries.iter().enumerate() {
                    let [sx, sy] = lg.swatch(i);
                    let _ = write!(
                        o.buf,
                        "<rect fill=\"#{:02x}{:02x}{:02x}\" stroke=\"#444444\" x=\"{sx:.2}\" y=\"{sy:.2}\" width=\"{s:.2}\" height=\"{s:.2}\"/>",
                        c[0],
                        c[1],
                        c[2],
                        s = LEGEND_SWATCH
                    );
                    let _ = write!(
                        o.buf,
                        "<text x=\"{:.2}\" y=\"{:.2}\">",
                        sx + LEGEND_SWATCH + 6.0,
                        sy + LEGEND_SWATCH - 1.0
                    );
                    for ch in label.chars() {
                        match ch {
                            '<' => o.str("&lt;"),
                            '>' => o.str("&gt;"),
                            '&' => o.str("&amp;"),
                            c => {
                                let mut b = [0u8; 4];
                                o.str(c.encode_utf8(&mut b));
                            }
                        }
                    }
                    o.str("</text>");
                    o.nl()?;
                }
                o.str("</g>");
                o.nl()?;
            }
        }
    }
    o.str("</svg>");
    o.nl()?;
    Ok(o.finish()?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_input() {
        let pts = [[0.0, 0.0], [1.0, 0.0]];
        let s = SvgStyle::default();
        let tri = SvgLayer::Triangles {
            points: &pts,
            triangles: &[[0, 1, 2]],
            stroke: "black",
            width: 1.0,
        };
        let mut out = Vec::new();
        assert!(write_svg(&mut out, [[0.0, 0.0], [1.0, 1.0]], &[tri], &s).is_err());
        assert!(write_svg(&mut out, [[0.0, 0.0], [0.0, 1.0]], &[], &s).is_err());
        let poly = SvgLayer::Polygons {
            points: &pts,
            offsets: &[0, 1],
            fills: &[],
            stroke: "black",
            width: 1.0,
        };
        assert!(write_svg(&mut out, [[0.0, 0.0], [1.0, 1.0]], &[poly], &s).is_err());
    }

    #[test]
    fn polygons_are_filled_and_flipped() {
        let pts = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]];
        let poly = SvgLayer::Polygons {
            points: &pts,
            offsets: &[0, 3],
            fills: &[[255, 0, 16]],
            stroke: "black",
            width: 0.5,
        };
        let style = SvgStyle {
            width: 100.0,
            margin: 0.0,
            background: None,
        };
        let mut out = Vec::new();
        write_svg(&mut out, [[0.0, 0.0], [1.0, 1.0]], &[poly], &style).unwrap();
        let s = String::from_utf8(out).unwrap();
        assert!(s.contains("fill=\"#ff0010\""), "{s}");
        // y is flipped: (1, 1) is the top right corner.
        assert!(s.contains("M0.00 100.00L100.00 100.00L100.00 0.00Z"), "{s}");
    }
}
