//! The grand mobility in a rotated frame: the rotation `R` taking `e3` to a plane's unit
//! normal `n`, and its representation `Q` on one particle's components `[U, Omega, E]`
//! (equally `[F, L, S]`). A proper rotation turns the velocity and the angular velocity
//! (an axial vector) alike, `U -> R U`, `Omega -> R Omega`, and a strain or stresslet as
//! `E -> R E R^T`, which in the orthonormal basis [`kernels::STRAIN_BASIS`] is the 5x5
//! matrix `Q5_ab = B_a : (R B_b R^T)` (orthogonal: the basis is orthonormal and the map
//! keeps `A : B`). So `Q = diag(R, R, Q5)` is orthogonal, and a confinement turned by `R`
//! has the blocks `M'(x, y) = Q M(R^T x, R^T y) Q^T` and the resistance `Q R(..) Q^T`
//! ([`on_system`]: `Q` on every particle of a system).
//!
//! Any rotation taking `e3` to `n` serves a plane (its images are unchanged by turns about
//! its normal); this one is the frame the generator writes a plane's image in (kernel-gen
//! `green::frame`: columns `t1, t2, n`, `t1` the coordinate axis least aligned with `n`
//! made orthogonal to it, `t2 = n x t1`), so that for a plane normal to an axis `R` is a
//! signed permutation and turns positions exactly.

use crate::system::{global, Moments};
use kernels::basis_both;
use nalgebra::DMatrix;

/// The rotation (row-major 3x3) whose columns are `t1, t2, n`: it takes `e3` to the unit
/// vector `n`, `e1` to `t1` (the coordinate axis least aligned with `n`, the first of
/// equals, made orthogonal to `n`) and `e2` to `t2 = n x t1`. For `n = e3` the identity;
/// for `n = e1` the cyclic permutation `e1 -> e2 -> e3 -> e1`.
pub fn taking_e3_to(n: [f64; 3]) -> [[f64; 3]; 3] {
    let k = (0..3)
        .min_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs()))
        .expect("three axes");
    let t: [f64; 3] = std::array::from_fn(|i| if i == k { 1.0 } else { 0.0 } - n[k] * n[i]);
    let norm = t.iter().map(|v| v * v).sum::<f64>().sqrt();
    let t1 = t.map(|v| v / norm);
    let t2 = [
        n[1] * t1[2] - n[2] * t1[1],
        n[2] * t1[0] - n[0] * t1[2],
        n[0] * t1[1] - n[1] * t1[0],
    ];
    std::array::from_fn(|i| [t1[i], t2[i], n[i]])
}

/// `Q = diag(R, R, Q5)` on one particle's `k` = 3 (`U`), 6 (`U, Omega`) or 11
/// (`U, Omega, E`) components, for a proper rotation `r` (row-major): `Q5_ab =
/// B_a : (R B_b R^T)`, from the 4-tensor `R_pk R_ql` in the strain basis.
pub fn on_components(r: &[[f64; 3]; 3], k: usize) -> DMatrix<f64> {
    assert!(
        matches!(k, 3 | 6 | 11),
        "3, 6 or 11 components per particle, not {k}"
    );
    let t: [[[[f64; 3]; 3]; 3]; 3] = std::array::from_fn(|p| {
        std::array::from_fn(|q| std::array::from_fn(|a| std::array::from_fn(|b| r[p][a] * r[q][b])))
    });
    let strain = basis_both(&t);
    DMatrix::from_fn(k, k, |i, j| match (i, j) {
        (0..=2, 0..=2) => r[i][j],
        (3..=5, 3..=5) => r[i - 3][j - 3],
        (6.., 6..) => strain[i - 6][j - 6],
        _ => 0.0,
    })
}

/// `Q` on each of `n` particles in the moment-major layout of `System::mobility` at
/// `moments`: the spheres of a system turned by `r` have the mobility `Q M Q^T` and the
/// resistance `Q R Q^T`.
pub fn on_system(r: &[[f64; 3]; 3], moments: Moments, n: usize) -> DMatrix<f64> {
    let k = moments.per_particle();
    let q = on_components(r, k);
    let parts = moments.parts();
    let mut out = DMatrix::zeros(k * n, k * n);
    for a in 0..n {
        for i in 0..k {
            for j in 0..k {
                out[(global(parts, n, a, i), global(parts, n, a, j))] = q[(i, j)];
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `R` is a rotation taking `e3` to `n`, `Q` is orthogonal, and `Q5` maps the
    /// components of a strain `E` to those of `R E R^T`, for normals along the axes and
    /// oblique ones; 1e-14: a few roundings of sums of entries of size 1.
    #[test]
    fn the_rotation_takes_e3_to_the_normal_and_turns_strains() {
        let e = [[0.3, -0.7, 0.2], [-0.7, -0.1, 0.5], [0.2, 0.5, -0.2]];
        let components = |e: &[[f64; 3]; 3]| -> nalgebra::DVector<f64> {
            nalgebra::DVector::from_column_slice(&crate::strain_components(e).unwrap())
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
}
