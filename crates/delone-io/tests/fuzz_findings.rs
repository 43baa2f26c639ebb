//! Inputs the fuzz targets (crates/delone-fuzz, fuzz/) found to panic or
//! hang a reader: each must now be a clean error (or a clean result) at once.

use std::time::{Duration, Instant};

const HUGE: &str = "18446744073709551615";

#[test]
fn node_attribute_count_near_usize_max_is_an_error() {
    let t = format!("1 2 {HUGE} 0\n1 0 0\n");
    assert!(delone_io::read_node(t.as_bytes()).is_err());
}

#[test]
fn ele_attribute_count_near_usize_max_is_an_error() {
    let t = format!("1 3 {HUGE}\n1 1 2 3\n");
    assert!(delone_io::read_ele(t.as_bytes(), 1).is_err());
}

#[test]
fn plc_counts_near_usize_max_are_errors() {
    // Point attributes (the marker's position follows them).
    let t = format!("1 3 {HUGE} 1\n1 0 0 0\n");
    assert!(delone_io::read_smesh(t.as_bytes()).is_err());
    // Corners of a .smesh facet and of a .poly polygon.
    let pts = "3 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n";
    let t = format!("{pts}1 0\n{HUGE} 1 2 3\n0\n0\n");
    assert!(delone_io::read_smesh(t.as_bytes()).is_err());
    let t = format!("{pts}1 0\n1 0\n{HUGE} 1 2 3\n0\n0\n");
    assert!(delone_io::read_poly3d(t.as_bytes()).is_err());
}

#[test]
fn off_face_corner_count_near_usize_max_is_an_error() {
    let t = format!("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n{HUGE} 0 1 2\n");
    assert!(delone_io::read_off(t.as_bytes()).is_err());
}

#[test]
fn ply_element_without_properties_and_a_huge_count_reads_at_once() {
    let mut t = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement empty 4294967295\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n".to_vec();
    for c in [0f32, 0., 0., 1., 0., 0., 0., 1., 0.] {
        t.extend_from_slice(&c.to_le_bytes());
    }
    t.push(3);
    for i in [0i32, 1, 2] {
        t.extend_from_slice(&i.to_le_bytes());
    }
    let t0 = Instant::now();
    let s = delone_io::read_ply(&t).unwrap();
    assert!(t0.elapsed() < Duration::from_secs(1), "{:?}", t0.elapsed());
    assert_eq!((s.points.len(), s.faces.clone()), (3, vec![vec![0, 1, 2]]));
}
