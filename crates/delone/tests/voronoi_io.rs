//! Voronoi diagrams written in the Triangle/TetGen `-v` formats, read back
//! and checked against the diagrams.

use delone::geom::SplitMix64;
use delone::tet::Voronoi3;
use delone::tri::Voronoi2;
use delone::NONE;

fn lines(buf: Vec<u8>) -> Vec<Vec<String>> {
    String::from_utf8(buf)
        .unwrap()
        .lines()
        .map(|l| l.split_whitespace().map(String::from).collect())
        .collect()
}

#[test]
fn triangle_v_files() {
    let mut r = SplitMix64::new(3);
    let pts: Vec<[f64; 2]> = (0..200)
        .map(|_| [(r.next_u64() >> 11) as f64, (r.next_u64() >> 11) as f64])
        .collect();
    let mesh = delone::triangulate(&pts).unwrap();
    let v = Voronoi2::new(&pts, &mesh).unwrap();
    let mut node = Vec::new();
    delone_io::write_voronoi_node(&mut node, &v.vertices, 1).unwrap();
    let back = delone_io::read_node(&node).unwrap().points::<2>().unwrap();
    assert_eq!(back, v.vertices);
    let ends: Vec<[u32; 2]> = v.edges.iter().map(|e| e.vertices).collect();
    let dirs: Vec<[f64; 2]> = v.edges.iter().map(|e| e.direction(&pts)).collect();
    let mut edge = Vec::new();
    delone_io::write_voronoi_edge(&mut edge, &ends, &dirs, v.vertices.len(), 1).unwrap();
    let l = lines(edge);
    assert_eq!(l[0], [v.edges.len().to_string(), "0".into()]);
    for (i, e) in v.edges.iter().enumerate() {
        let w = &l[i + 1];
        assert_eq!(w[0], (i + 1).to_string());
        assert_eq!(w[1], (e.vertices[0] + 1).to_string());
        if e.is_ray() {
            assert_eq!(w.len(), 5);
            assert_eq!(w[2], "-1");
            let d: Vec<f64> = w[3..].iter().map(|x| x.parse().unwrap()).collect();
            assert_eq!(d, dirs[i]);
        } else {
            assert_eq!(w.len(), 3);
            assert_eq!(w[2], (e.vertices[1] + 1).to_string());
        }
    }
}

#[test]
fn tetgen_v_files() {
    let mut r = SplitMix64::new(4);
    let mut unit = || (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    let pts: Vec<[f64; 3]> = (0..150).map(|_| [unit(), unit(), unit()]).collect();
    let mesh = delone::tetrahedralize(&pts).unwrap();
    let v = Voronoi3::new(&pts, &mesh).unwrap();
    // Face edges join the face's vertices; rays only at the ends of open faces.
    for f in 0..v.faces.len() {
        let face = v.face(f);
        let m = face.vertices.len();
        let open = face.rays.is_some();
        assert_eq!(face.edges.len(), m + usize::from(open), "face {f}");
        let all: Vec<u32> = face.edges.collect();
        let inner = if open { &all[1..m] } else { &all[..] };
        for (k, &e) in inner.iter().enumerate() {
            let e = v.edges[e as usize];
            let mut got = e.vertices;
            let mut want = [face.vertices[k], face.vertices[(k + 1) % m]];
            got.sort_unstable();
            want.sort_unstable();
            assert_eq!(got, want, "face {f} edge {k}");
            // The Voronoi edge's Delaunay triangle contains the face's edge.
            assert!(face.sites.iter().all(|s| e.sites.contains(s)));
        }
        if open {
            let (a, b) = (all[0] as usize, all[m] as usize);
            assert!(v.edges[a].is_ray() && v.edges[b].is_ray());
            assert_eq!(v.edges[a].vertices[0], face.vertices[0]);
            assert_eq!(v.edges[b].vertices[0], face.vertices[m - 1]);
        }
    }
    let ends: Vec<[u32; 2]> = v.edges.iter().map(|e| e.vertices).collect();
    let dirs: Vec<[f64; 3]> = (0..v.edges.len()).map(|e| v.direction(e)).collect();
    let mut edge = Vec::new();
    delone_io::write_voronoi_edge(&mut edge, &ends, &dirs, v.vertices.len(), 0).unwrap();
    let rays = lines(edge)
        .iter()
        .skip(1)
        .filter(|w| w[2] == "-1" && w.len() == 6)
        .count();
    assert_eq!(rays, ends.iter().filter(|e| e[1] == NONE).count());
    let cells: Vec<[u32; 2]> = v.faces.iter().map(|f| f.sites).collect();
    let (mut offsets, mut ids) = (vec![0u32], vec![]);
    for f in 0..v.faces.len() {
        ids.extend(v.face(f).edges);
        offsets.push(ids.len() as u32);
    }
    let mut face = Vec::new();
    delone_io::write_voronoi_face(&mut face, &cells, &offsets, &ids, v.edges.len(), 0).unwrap();
    let l = lines(face);
    assert_eq!(l.len(), v.faces.len() + 1);
    for (f, w) in l[1..].iter().enumerate() {
        let k: usize = w[3].parse().unwrap();
        assert_eq!(k, v.face(f).edges.len());
        assert_eq!(w.len(), 4 + k);
    }
    let mut cell = Vec::new();
    delone_io::write_voronoi_cell(
        &mut cell,
        &v.cell_offsets,
        &v.cell_face_ids,
        v.faces.len(),
        0,
    )
    .unwrap();
    let l = lines(cell);
    assert_eq!(l[0], [pts.len().to_string()]);
    for (s, w) in l[1..].iter().enumerate() {
        let faces: Vec<u32> = w[2..].iter().map(|x| x.parse().unwrap()).collect();
        assert_eq!(faces, v.cell_faces(s));
        for f in faces {
            assert!(v.faces[f as usize].sites.contains(&(s as u32)));
        }
    }
}
