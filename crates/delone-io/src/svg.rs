//! A small SVG writer for 2D pictures: triangles, polygons (e.g. clipped
//! Voronoi cells) and points, drawn in layers, on plain slices.

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
    let [lo, hi] = view;
    let (w, h) = (hi[0] - lo[0], hi[1] - lo[1]);
    if !(w.is_finite() && h.is_finite() && w > 0.0 && h > 0.0)
        || !(style.width.is_finite() && style.width > 0.0 && style.margin.is_finite())
    {
        return Err(IoError::invalid(format!(
            "the SVG view {view:?} (width {} px) is empty or not finite",
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
                        "SVG layer {k}: triangle {t} refers to a missing point"
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
                        "SVG layer {k}: offsets or fills do not match {} points",
                        points.len()
                    )));
                }
            }
            SvgLayer::Points { .. } => {}
        }
    }
    let scale = style.width / w;
    let (mw, mh) = (
        style.width + 2.0 * style.margin,
        h * scale + 2.0 * style.margin,
    );
    let m = style.margin;
    let tx = |p: &[f64; 2]| [m + (p[0] - lo[0]) * scale, m + (hi[1] - p[1]) * scale];
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
