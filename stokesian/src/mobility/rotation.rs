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
