use kernel_gen::physics::operators::*;

#[test]
fn basis_is_orthonormal_symmetric_traceless() {
    for (m, bm) in STRAIN_BASIS.iter().enumerate() {
        let tr: f64 = (0..3).map(|k| bm[k][k]).sum();
        assert!(tr.abs() < 1e-15);
        for p in 0..3 {
            for q in 0..3 {
                assert_eq!(bm[p][q], bm[q][p]);
            }
        }
        for (n, bn) in STRAIN_BASIS.iter().enumerate() {
            let ip: f64 = (0..9).map(|k| bm[k / 3][k % 3] * bn[k / 3][k % 3]).sum();
            let want = if m == n { 1.0 } else { 0.0 };
            assert!((ip - want).abs() < 1e-15, "<B{m}, B{n}> = {ip}");
        }
    }
}

#[test]
fn levi_civita_right_handed() {
    assert_eq!(eps(0, 1, 2), 1.0);
    assert_eq!(eps(1, 2, 0), 1.0);
    assert_eq!(eps(1, 0, 2), -1.0);
    assert_eq!(eps(0, 0, 2), 0.0);
}

#[test]
fn orders_each_block_needs() {
    // UF: lap_x lap_y = 4; ES: grad lap at both ends = 6; OL: 2; EF: 1 + 2 + 2 = 5.
    assert_eq!(max_order(Response::U, Moment::F), 4);
    assert_eq!(max_order(Response::Omega, Moment::L), 2);
    assert_eq!(max_order(Response::E, Moment::F), 5);
    assert_eq!(max_order(Response::E, Moment::S), 6);
    assert_eq!(max_order(Response::Omega, Moment::S), 4);
}

#[test]
fn orthonormal_strain_is_projection_of_cartesian() {
    // Each orthonormal component's terms equal sum_pq B_pq * (Cartesian pq terms).
    let o = field(Response::E, Basis::Orthonormal);
    assert_eq!(o.len(), 5);
    // B5 involves d_1 G_1, d_2 G_2 (coef -1 before the normalisation 1/sqrt6) and
    // d_3 G_3 (2) at order 1.
    let first: Vec<&Side> = o[4].iter().filter(|s| s.a2 == 0).collect();
    assert_eq!(first.len(), 3);
    for s in first {
        let want = if s.comp == 2 { 2.0 } else { -1.0 };
        assert_eq!(s.coef, want);
    }
    // the normalised basis is the integer one over its norm, to round-off (one
    // rounding of the literal and two of `want`: within 2 ulps of values below 1)
    for p in 0..5 {
        for k in 0..9 {
            let (i, j) = (k / 3, k % 3);
            let want = STRAIN_INTEGER[p][i][j] / STRAIN_NORM2[p].sqrt();
            assert!((STRAIN_BASIS[p][i][j] - want).abs() <= 2.0 * f64::EPSILON);
        }
    }
    assert_eq!(
        norm(Response::E, Moment::S, Basis::Orthonormal, 4, 4),
        1.0 / 6.0
    );
    let s12 = norm(Response::E, Moment::S, Basis::Orthonormal, 0, 4);
    // correctly rounded 1/sqrt(12) = 0.28867513459481288225457439025097872782...
    assert_eq!(s12, 0.288_675_134_594_812_87);
}
