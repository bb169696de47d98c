//! The dense algebra and the rotations the solver is built from: the Cholesky
//! factorisation and large matrices of `stokesian::linalg`, and the rotation of a plane's
//! frame with its action on the grand-order components (`stokesian::mobility::rotation`).

use nalgebra::DMatrix;
use stokesian::linalg::dense::SMALL;
use stokesian::linalg::{mul_vec, Cholesky, LargeMatrix};
use stokesian::mobility::rotation::{on_components, taking_e3_to};

/// Against nalgebra's Cholesky on a random symmetric positive-definite matrix:
/// 1e-12 relative (both backward stable; condition number about 10 here).
#[test]
fn agrees_with_nalgebra() {
    for n in [1, 22, 40, 2 * SMALL] {
        agrees_with_nalgebra_at(n);
    }
}

fn agrees_with_nalgebra_at(n: usize) {
    let b = DMatrix::from_fn(n, n, |i, j| ((i * 7 + j * 13) % 11) as f64 / 11.0 - 0.5);
    let m = &b * b.transpose() + DMatrix::identity(n, n) * (n as f64 / 4.0);
    let w: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
    let ours = Cholesky::new(&m).expect("positive definite");
    let theirs = m.clone().cholesky().expect("positive definite");
    let wv = nalgebra::DVector::from_column_slice(&w);
    let close = |a: &[f64], b: &[f64]| {
        let d: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
        let s: f64 = b.iter().map(|y| y * y).sum();
        d.sqrt() <= 1e-12 * s.sqrt()
    };
    assert!(close(&ours.l_mul(&w), (theirs.l() * &wv).as_slice()));
    assert!(close(&ours.solve(&w), theirs.solve(&wv).as_slice()));
    let lt = theirs.l().transpose().solve_upper_triangular(&wv).unwrap();
    assert!(close(&ours.lt_solve(&w), lt.as_slice()));
    assert!(close(
        ours.inverse().as_slice(),
        theirs.inverse().as_slice()
    ));
    assert!(close(&mul_vec(&m, &w), (&m * &wv).as_slice()));
    let not_spd = DMatrix::from_fn(3, 3, |i, j| if i == j { -1.0 } else { 0.0 });
    assert!(Cholesky::new(&not_spd).is_none());
}

/// A large matrix starts as zeros of its shape, holds what is written column-major,
/// and an empty one is empty; a shape beyond the address space is an error.
#[test]
fn large_matrices_hold_their_values() {
    let (rows, cols) = (700, 900);
    let mut m = LargeMatrix::zeros(rows, cols).expect("mapped");
    assert!(m.as_slice().iter().all(|&v| v == 0.0));
    for (i, v) in m.as_mut_slice().iter_mut().enumerate() {
        *v = i as f64;
    }
    assert_eq!(m.view().shape(), (rows, cols));
    assert_eq!(m.view()[(3, 2)], (2 * rows + 3) as f64);
    let empty = LargeMatrix::zeros(0, 5).expect("mapped");
    assert!(empty.as_slice().is_empty());
    assert!(LargeMatrix::zeros(usize::MAX, 3).is_err());
}

/// `R` is a rotation taking `e3` to `n`, `Q` is orthogonal, and `Q5` maps the
/// components of a strain `E` to those of `R E R^T`, for normals along the axes and
/// oblique ones; 1e-14: a few roundings of sums of entries of size 1.
#[test]
fn the_rotation_takes_e3_to_the_normal_and_turns_strains() {
    let e = [[0.3, -0.7, 0.2], [-0.7, -0.1, 0.5], [0.2, 0.5, -0.2]];
    let components = |e: &[[f64; 3]; 3]| -> nalgebra::DVector<f64> {
        nalgebra::DVector::from_column_slice(&stokesian::strain_components(e).unwrap())
    };
    for n in [
        [1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
        [0.6, 0.0, 0.8],
        [0.4, -0.4, 0.7],
    ] {
        let len = n.iter().map(|v| v * v).sum::<f64>().sqrt();
        let n = n.map(|v| v / len);
        let r = taking_e3_to(n);
        let m = nalgebra::Matrix3::from_fn(|i, j| r[i][j]);
        assert!((m * m.transpose() - nalgebra::Matrix3::identity()).norm() < 1e-14);
        assert!((m.determinant() - 1.0).abs() < 1e-14);
        for i in 0..3 {
            assert!((r[i][2] - n[i]).abs() < 1e-15);
        }
        let q = on_components(&r, 11);
        assert!((&q * q.transpose() - DMatrix::identity(11, 11)).norm() < 1e-14);
        let turned = m * nalgebra::Matrix3::from_fn(|i, j| e[i][j]) * m.transpose();
        let turned: [[f64; 3]; 3] =
            std::array::from_fn(|i| std::array::from_fn(|j| turned[(i, j)]));
        let q5 = q.view((6, 6), (5, 5));
        assert!((q5 * components(&e) - components(&turned)).norm() < 1e-14);
    }
    assert_eq!(
        taking_e3_to([1.0, 0.0, 0.0]),
        [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    );
}
