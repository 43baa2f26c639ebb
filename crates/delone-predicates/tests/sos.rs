//! Simulation of Simplicity: never zero, agrees with the plain sign when that is
//! nonzero, antisymmetric, equal to an explicit tiny perturbation evaluated
//! exactly, and consistent as a whole (chirotope identities).

mod common;

use common::*;
use delone_predicates::*;

/// Distinct pseudo-random indices (a shuffled prefix of 0..1000).
fn indices<const N: usize>(r: &mut Rng) -> [u32; N] {
    let mut out = [0u32; N];
    let mut k = 0;
    while k < N {
        let v = r.int(0, 999) as u32;
        if !out[..k].contains(&v) {
            out[k] = v;
            k += 1;
        }
    }
    out
}

fn g2(r: &mut Rng) -> [f64; 2] {
    [r.int(0, 2) as f64, r.int(0, 2) as f64]
}
fn g3(r: &mut Rng) -> [f64; 3] {
    [r.int(0, 1) as f64, r.int(0, 1) as f64, r.int(0, 1) as f64]
}

fn o2s(p: &[[f64; 2]], i: &[u32]) -> i32 {
    orient2d_sos(&p[0], &p[1], &p[2], i[0], i[1], i[2])
}
fn o3s(p: &[[f64; 3]], i: &[u32]) -> i32 {
    orient3d_sos(&p[0], &p[1], &p[2], &p[3], i[0], i[1], i[2], i[3])
}
fn ics(p: &[[f64; 2]], i: &[u32]) -> i32 {
    incircle_sos(&p[0], &p[1], &p[2], &p[3], i[0], i[1], i[2], i[3])
}
fn iss(p: &[[f64; 3]], i: &[u32]) -> i32 {
    insphere_sos(
        &p[0], &p[1], &p[2], &p[3], &p[4], i[0], i[1], i[2], i[3], i[4],
    )
}
fn icws(p: &[[f64; 2]], w: &[f64], i: &[u32]) -> i32 {
    incircle_weighted_sos(
        &p[0], &p[1], &p[2], &p[3], w[0], w[1], w[2], w[3], i[0], i[1], i[2], i[3],
    )
}
fn isws(p: &[[f64; 3]], w: &[f64], i: &[u32]) -> i32 {
    insphere_weighted_sos(
        &p[0], &p[1], &p[2], &p[3], &p[4], w[0], w[1], w[2], w[3], w[4], i[0], i[1], i[2], i[3],
        i[4],
    )
}

/// Calls `f` on `(points, indices)` and on every transposition of it, checking
/// that the result is ±1, equals `plain` when that is nonzero, and flips sign.
fn check<P: Copy, const N: usize>(
    pts: [P; N],
    idx: [u32; N],
    plain: i32,
    f: &dyn Fn(&[P], &[u32]) -> i32,
) {
    let s = f(&pts, &idx);
    assert!(s == 1 || s == -1, "SoS returned {s}");
    if plain != 0 {
        assert_eq!(s, plain, "SoS must agree with the exact sign");
    }
    for i in 0..N {
        for j in i + 1..N {
            let (mut p, mut q) = (pts, idx);
            p.swap(i, j);
            q.swap(i, j);
            assert_eq!(f(&p, &q), -s, "antisymmetry under swapping {i} and {j}");
        }
    }
}

#[test]
fn nonzero_agreeing_and_antisymmetric_on_grids() {
    let mut r = Rng(21);
    let mut ties = [0usize; 6];
    for _ in 0..4_000 {
        let p: [[f64; 2]; 4] = std::array::from_fn(|_| g2(&mut r));
        let q: [[f64; 3]; 5] = std::array::from_fn(|_| g3(&mut r));
        let w2: [f64; 4] = std::array::from_fn(|_| r.int(-1, 1) as f64);
        let w3: [f64; 5] = std::array::from_fn(|_| r.int(-1, 1) as f64);
        let i4: [u32; 4] = indices(&mut r);
        let i5: [u32; 5] = indices(&mut r);
        let plain = [
            sign(orient2d(&p[0], &p[1], &p[2])),
            sign(orient3d(&q[0], &q[1], &q[2], &q[3])),
            sign(incircle(&p[0], &p[1], &p[2], &p[3])),
            sign(insphere(&q[0], &q[1], &q[2], &q[3], &q[4])),
            sign(incircle_weighted(
                &p[0], &p[1], &p[2], &p[3], w2[0], w2[1], w2[2], w2[3],
            )),
            sign(insphere_weighted(
                &q[0], &q[1], &q[2], &q[3], &q[4], w3[0], w3[1], w3[2], w3[3], w3[4],
            )),
        ];
        for (t, &s) in ties.iter_mut().zip(&plain) {
            *t += (s == 0) as usize;
        }
        check([p[0], p[1], p[2]], [i4[0], i4[1], i4[2]], plain[0], &o2s);
        check(
            [q[0], q[1], q[2], q[3]],
            [i5[0], i5[1], i5[2], i5[3]],
            plain[1],
            &o3s,
        );
        check(p, i4, plain[2], &ics);
        check(q, i5, plain[3], &iss);
        // Weights travel with their points.
        let pw: [([f64; 2], f64); 4] = std::array::from_fn(|k| (p[k], w2[k]));
        check(pw, i4, plain[4], &|a: &[([f64; 2], f64)], i: &[u32]| {
            icws(
                &a.iter().map(|x| x.0).collect::<Vec<_>>(),
                &a.iter().map(|x| x.1).collect::<Vec<_>>(),
                i,
            )
        });
        let qw: [([f64; 3], f64); 5] = std::array::from_fn(|k| (q[k], w3[k]));
        check(qw, i5, plain[5], &|a: &[([f64; 3], f64)], i: &[u32]| {
            isws(
                &a.iter().map(|x| x.0).collect::<Vec<_>>(),
                &a.iter().map(|x| x.1).collect::<Vec<_>>(),
                i,
            )
        });
    }
    assert!(
        ties.iter().all(|&t| t > 100),
        "grids must produce many exact ties: {ties:?}"
    );
}

/// Rank of each index among `idx`, 1 for the largest.
fn rank_desc(idx: &[u32]) -> Vec<i32> {
    idx.iter()
        .map(|&i| 1 + idx.iter().filter(|&&j| j > i).count() as i32)
        .collect()
}

/// The lifting perturbation equals the exact weighted predicate with weights
/// `w_i - δ_i`, `δ_i = 2^(-k·rank(i))`, rank 1 for the largest index, when `k` is
/// large enough for each term to dominate the rest.
#[test]
fn lifted_sos_equals_explicit_weight_perturbation() {
    let mut r = Rng(22);
    let mut decided_by_perturbation = 0;
    for n in 0..6_000 {
        let weighted = n % 2 == 1;
        // 2D: coordinates in [0, 3]: |orient2d| <= 18, so k = 20 dominates.
        let p: [[f64; 2]; 4] = std::array::from_fn(|_| [r.int(0, 3) as f64, r.int(0, 3) as f64]);
        let i4: [u32; 4] = indices(&mut r);
        let base: [f64; 4] =
            std::array::from_fn(|_| if weighted { r.int(-3, 3) as f64 } else { 0.0 });
        let k = if weighted { 9 } else { 20 };
        let rk = rank_desc(&i4);
        let w: [f64; 4] = std::array::from_fn(|j| base[j] - (-(k * rk[j]) as f64).exp2());
        let want = sign(incircle_weighted(
            &p[0], &p[1], &p[2], &p[3], w[0], w[1], w[2], w[3],
        ));
        let got = if weighted {
            icws(&p, &base, &i4)
        } else {
            ics(&p, &i4)
        };
        if want == 0 {
            // Only possible when all four points are collinear: documented parity fallback.
            assert_eq!(sign(orient2d(&p[0], &p[1], &p[2])), 0);
            assert_eq!(sign(orient2d(&p[0], &p[1], &p[3])), 0);
        } else {
            assert_eq!(got, want, "incircle SoS {p:?} {base:?} {i4:?}");
        }
        let plain = sign(incircle_weighted(
            &p[0], &p[1], &p[2], &p[3], base[0], base[1], base[2], base[3],
        ));
        decided_by_perturbation += (plain == 0 && want != 0) as usize;

        // 3D: coordinates in [0, 2]: |orient3d| <= 42 (Hadamard), k = 20 (9 with
        // integer weights, where 2^9 > 4 * 42 and 5 * 42 / 2^9 < 1).
        let q: [[f64; 3]; 5] =
            std::array::from_fn(|_| [r.int(0, 2) as f64, r.int(0, 2) as f64, r.int(0, 2) as f64]);
        let i5: [u32; 5] = indices(&mut r);
        let base: [f64; 5] =
            std::array::from_fn(|_| if weighted { r.int(-3, 3) as f64 } else { 0.0 });
        let rk = rank_desc(&i5);
        let w: [f64; 5] = std::array::from_fn(|j| base[j] - (-(k * rk[j]) as f64).exp2());
        let want = sign(insphere_weighted(
            &q[0], &q[1], &q[2], &q[3], &q[4], w[0], w[1], w[2], w[3], w[4],
        ));
        let got = if weighted {
            isws(&q, &base, &i5)
        } else {
            iss(&q, &i5)
        };
        if want == 0 {
            assert_eq!(sign(orient3d(&q[0], &q[1], &q[2], &q[3])), 0);
            assert_eq!(sign(orient3d(&q[0], &q[1], &q[2], &q[4])), 0);
        } else {
            assert_eq!(got, want, "insphere SoS {q:?} {base:?} {i5:?}");
        }
        let plain = sign(insphere_weighted(
            &q[0], &q[1], &q[2], &q[3], &q[4], base[0], base[1], base[2], base[3], base[4],
        ));
        decided_by_perturbation += (plain == 0 && want != 0) as usize;
    }
    assert!(decided_by_perturbation > 500, "{decided_by_perturbation}");
}

/// The collinear / coplanar fallback is the parity of the index permutation.
#[test]
fn all_collinear_or_coplanar_fallback_is_index_parity() {
    let p = [[0.0, 0.0], [1.0, 1.0], [2.0, 2.0], [5.0, 5.0]];
    assert_eq!(ics(&p, &[0, 1, 2, 3]), 1);
    assert_eq!(ics(&p, &[1, 0, 2, 3]), -1);
    assert_eq!(ics(&p, &[3, 1, 2, 0]), -1);
    let q = [
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [0.0, 1.0, 1.0],
        [3.0, 3.0, 1.0],
        [1.0, 1.0, 1.0],
    ];
    assert_eq!(iss(&q, &[0, 1, 2, 3, 4]), 1);
    assert_eq!(iss(&q, &[4, 1, 2, 3, 0]), -1);
    assert_eq!(iss(&q, &[1, 2, 0, 3, 4]), 1);
}

/// `orient2d_sos` equals the exact sign of the determinant with the explicit
/// perturbation `ε^(2^(2·rank + j))`, `ε = 2^-16`, rank 0 for the largest index,
/// evaluated with big integers.
#[test]
fn orient2d_sos_equals_explicit_coordinate_perturbation() {
    let mut r = Rng(23);
    const K: u32 = 16;
    const S: u32 = K * 32; // 2^S * ε^(2^5) is the smallest perturbation, an integer.
    for n in 0..3_000 {
        // Many coincident and collinear triples.
        let p: [[f64; 2]; 3] =
            std::array::from_fn(|_| [r.int(0, 1 + n % 3) as f64, r.int(0, 1 + n % 3) as f64]);
        let idx: [u32; 3] = indices(&mut r);
        let rank: Vec<u32> = rank_desc(&idx).iter().map(|&x| (x - 1) as u32).collect();
        let rows: Vec<Vec<Big>> = (0..3)
            .map(|row| {
                let mut v: Vec<Big> = (0..2)
                    .map(|j| {
                        let pos = 2 * rank[row] + j as u32;
                        let x = Big::from_f64_shifted(p[row][j], S as i32);
                        x.add(&Big::from_f64_shifted(1.0, (S - K * (1 << pos)) as i32))
                    })
                    .collect();
                v.push(Big::from_i64(1));
                v
            })
            .collect();
        let want = big_det(&rows).sign();
        assert_ne!(want, 0);
        assert_eq!(o2s(&p, &idx), want, "{p:?} {idx:?}");
    }
}

/// Perturbed orientations must come from one point set: for any 4 points in the
/// plane, `o(bcd) - o(acd) + o(abd) - o(abc) = 0`, so those four signed terms can
/// never all have the same sign; likewise for 5 points in space.
#[test]
fn orient_sos_is_a_consistent_chirotope() {
    let mut r = Rng(24);
    for _ in 0..20_000 {
        let p: [[f64; 2]; 4] = std::array::from_fn(|_| g2(&mut r));
        let i: [u32; 4] = indices(&mut r);
        let t: Vec<i32> = (0..4)
            .map(|skip| {
                let rows: Vec<usize> = (0..4).filter(|&k| k != skip).collect();
                let s = orient2d_sos(
                    &p[rows[0]],
                    &p[rows[1]],
                    &p[rows[2]],
                    i[rows[0]],
                    i[rows[1]],
                    i[rows[2]],
                );
                if skip % 2 == 0 {
                    s
                } else {
                    -s
                }
            })
            .collect();
        assert!(
            t.iter().any(|&s| s != t[0]),
            "inconsistent 2D SoS {p:?} {i:?} {t:?}"
        );

        let q: [[f64; 3]; 5] = std::array::from_fn(|_| g3(&mut r));
        let i: [u32; 5] = indices(&mut r);
        let t: Vec<i32> = (0..5)
            .map(|skip| {
                let w: Vec<usize> = (0..5).filter(|&k| k != skip).collect();
                let s = orient3d_sos(
                    &q[w[0]], &q[w[1]], &q[w[2]], &q[w[3]], i[w[0]], i[w[1]], i[w[2]], i[w[3]],
                );
                if skip % 2 == 0 {
                    s
                } else {
                    -s
                }
            })
            .collect();
        assert!(
            t.iter().any(|&s| s != t[0]),
            "inconsistent 3D SoS {q:?} {i:?} {t:?}"
        );
    }
}
