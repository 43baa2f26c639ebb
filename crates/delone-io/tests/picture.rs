//! The picture scene through both back ends: the PNG decodes (with the `png`
//! crate's decoder) to the expected size and colours, the SVG holds the
//! same layers.

use delone_io::{render, write_png, write_svg, SvgLayer, SvgStyle};

/// A 2×1 rectangle in two triangles, one segment along the bottom, a hole mark.
fn scene<'a>(
    pts: &'a [[f64; 2]],
    tris: &'a [[u32; 3]],
    fills: &'a [[u8; 3]],
    segs: &'a [[u32; 2]],
    holes: &'a [[f64; 2]],
    legend: &'a [([u8; 3], &'a str)],
) -> Vec<SvgLayer<'a>> {
    vec![
        SvgLayer::FilledTriangles {
            points: pts,
            triangles: tris,
            fills,
        },
        SvgLayer::Triangles {
            points: pts,
            triangles: tris,
            stroke: "black",
            width: 1.0,
        },
        SvgLayer::Segments {
            points: pts,
            segments: segs,
            stroke: "#0000ff",
            width: 3.0,
        },
        SvgLayer::Crosses {
            points: holes,
            size: 4.0,
            stroke: "red",
            width: 1.5,
        },
        SvgLayer::Legend { entries: legend },
    ]
}

fn decode(bytes: &[u8]) -> (u32, u32, Vec<u8>) {
    let dec = png::Decoder::new(bytes);
    let mut reader = dec.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgba);
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

#[test]
fn png_decodes_with_the_right_pixels() {
    let pts = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]];
    let tris = [[0, 1, 2], [0, 2, 3]];
    let fills = [[200, 30, 30], [30, 200, 30]];
    let segs = [[0, 1]];
    let holes = [[1.5, 0.8]];
    let layers = scene(&pts, &tris, &fills, &segs, &holes, &[]);
    let style = SvgStyle {
        width: 200.0,
        margin: 10.0,
        background: Some("white".into()),
    };
    let view = [[0.0, 0.0], [2.0, 1.0]];
    let mut out = Vec::new();
    write_png(&mut out, view, &layers, &style).unwrap();
    let (w, h, px) = decode(&out);
    // 200 px for 2 units: 100 px per unit, plus the margins.
    assert_eq!((w, h), (220, 120));
    let at = |x: u32, y: u32| -> [u8; 4] {
        let i = 4 * (y * w + x) as usize;
        [px[i], px[i + 1], px[i + 2], px[i + 3]]
    };
    // Margin: background.
    assert_eq!(at(3, 3), [255, 255, 255, 255]);
    assert_eq!(at(216, 116), [255, 255, 255, 255]);
    // Triangle 0 (lower right): view (1.6, 0.3) -> pixel (170, 80).
    assert_eq!(at(170, 80), [200, 30, 30, 255]);
    // Triangle 1 (upper left): view (0.4, 0.7) -> pixel (50, 40).
    assert_eq!(at(50, 40), [30, 200, 30, 255]);
    // The segment y = 0 runs along pixel row 110 (blue, 3 px thick).
    assert_eq!(at(100, 110), [0, 0, 255, 255]);
    assert_eq!(at(100, 109), [0, 0, 255, 255]);
    // The diagonal edge (0,0)-(2,1) passes near pixel (110, 60): the
    // darkest pixel of that column there is dark (anti-aliased).
    let d = (58..63).map(|y| at(110, y)[1]).min().unwrap();
    assert!(d < 60, "{d}");
    // The hole cross centred at pixel (160, 30) is red.
    let c = at(160, 30);
    assert!(c[0] > 200 && c[1] < 100, "{c:?}");
    // The decoded image equals the rendered raster.
    let r = render(&view, &layers, &style).unwrap();
    assert_eq!(r.rgba, px);
}

#[test]
fn svg_has_the_same_layers() {
    let pts = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]];
    let tris = [[0, 1, 2], [0, 2, 3]];
    let fills = [[200, 30, 30], [200, 30, 30]];
    let legend = [([200u8, 30, 30], "< 10°")];
    let layers = scene(&pts, &tris, &fills, &[[0, 1]], &[[1.5, 0.8]], &legend);
    let mut out = Vec::new();
    write_svg(
        &mut out,
        [[0.0, 0.0], [2.0, 1.0]],
        &layers,
        &SvgStyle::default(),
    )
    .unwrap();
    let s = String::from_utf8(out).unwrap();
    // One fill path for the one colour, holding both triangles.
    assert_eq!(s.matches("fill=\"#c81e1e\" d=").count(), 1);
    assert_eq!(s.matches("stroke-width=\"3.00\"").count(), 1);
    assert!(s.contains("&lt; 10°</text>"), "{s}");
    assert!(s.ends_with("</svg>\n"));
}

#[test]
fn bad_scenes_are_errors() {
    let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    let view = [[0.0, 0.0], [1.0, 1.0]];
    let st = SvgStyle::default();
    let bad_fills = [SvgLayer::FilledTriangles {
        points: &pts,
        triangles: &[[0, 1, 2]],
        fills: &[],
    }];
    assert!(render(&view, &bad_fills, &st).is_err());
    let bad_seg = [SvgLayer::Segments {
        points: &pts,
        segments: &[[0, 3]],
        stroke: "black",
        width: 1.0,
    }];
    let e = render(&view, &bad_seg, &st).unwrap_err().to_string();
    assert!(e.contains("segment 0"), "{e}");
    let mut out = Vec::new();
    assert!(write_svg(&mut out, view, &bad_seg, &st).is_err());
    let huge = SvgStyle {
        width: 1e6,
        ..SvgStyle::default()
    };
    assert!(render(&view, &[], &huge).is_err());
}
