//! The resistance tensors of Eq. 19's exact parts from their scalar functions (Kim &
//! Karrila 1991, sec. 7.2; Jeffrey & Onishi 1984, eqs. 1.4, 1.9): the sphere-wall block
//! `R^W` from the five sphere-wall functions, the two-sphere block `R^P` from the 22
//! two-sphere functions seen from each sphere, and the mirror map of a plane.

use super::sphere_wall::wall_functions;
use super::two_sphere::PairScalars;
use kernels::{basis_both, basis_rows};
use nalgebra::{DMatrix, SMatrix};
use std::f64::consts::PI;

/// A `6 x 6` block: the force-torque resistance of one sphere or one pair seen from one sphere.
pub type M6 = SMatrix<f64, 6, 6>;

fn eps3(i: usize, j: usize, k: usize) -> f64 {
    ((i as i64 - j as i64) * (j as i64 - k as i64) * (k as i64 - i as i64)) as f64 / 2.0
}

fn delta(i: usize, j: usize) -> f64 {
    if i == j {
        1.0
    } else {
        0.0
    }
}

/// `R^W` of a sphere of radius `a` at gap `eps` from a wall with normal `n` (into the
/// fluid), 6x6 in the order `[U, Omega]`.
pub fn wall_block(eta: f64, a: f64, eps: f64, n: [f64; 3]) -> M6 {
    let w = wall_functions(eps);
    let mut r = M6::zeros();
    for i in 0..3 {
        for j in 0..3 {
            let nn = n[i] * n[j];
            r[(i, j)] = 6.0 * PI * eta * a * (w.xa * nn + w.ya * (delta(i, j) - nn));
            r[(i + 3, j + 3)] =
                8.0 * PI * eta * a.powi(3) * (w.xc * nn + w.yc * (delta(i, j) - nn));
            let fo: f64 = (0..3)
                .map(|k| -6.0 * PI * eta * a * a * w.fr * eps3(i, j, k) * n[k])
                .sum();
            r[(i, j + 3)] = fo; // R_FO
            r[(j + 3, i)] = fo; // R_LU = R_FO^T
        }
    }
    r
}

type M3 = SMatrix<f64, 3, 3>;

/// The force-torque-stresslet resistance tensors of the ordered pair `(alpha, beta)`
/// from the two-sphere functions `f` seen from `alpha` (`f` at `lambda = a_beta/a_alpha`,
/// Kim & Karrila normalisation with `a_alpha`), `d` the unit vector from `alpha` to
/// the other sphere, `same` for the "11" functions: `A, B (= R_LU), C` (3x3) and the
/// stresslet rows `S-U` (`G`), `S-Omega` (`H`), `S-E` (`M`) contracted with the
/// orthonormal strain basis (5x3, 5x3, 5x5). Tensor forms: Kim & Karrila
/// (1991), sec. 7.2. Without `stresslets` (FT) the stresslet rows are left zero.
struct OrderedPair {
    a: M3,
    b: M3,
    c: M3,
    g: SMatrix<f64, 5, 3>,
    h: SMatrix<f64, 5, 3>,
    m: SMatrix<f64, 5, 5>,
}

fn ordered_pair(
    eta: f64,
    radius: f64,
    f: &PairScalars,
    same: bool,
    d: [f64; 3],
    stresslets: bool,
) -> OrderedPair {
    let pick = |one: f64, two: f64| if same { one } else { two };
    let (xa, ya) = (pick(f.x11a, f.x12a), pick(f.y11a, f.y12a));
    let yb = pick(f.y11b, f.y12b);
    let (xc, yc) = (pick(f.x11c, f.x12c), pick(f.y11c, f.y12c));
    let (xg, yg, yh) = (
        pick(f.x11g, f.x12g),
        pick(f.y11g, f.y12g),
        pick(f.y11h, f.y12h),
    );
    let (xm, ym, zm) = (
        pick(f.x11m, f.x12m),
        pick(f.y11m, f.y12m),
        pick(f.z11m, f.z12m),
    );
    let (sa, sb, sc) = (
        6.0 * PI * eta * radius,
        4.0 * PI * eta * radius * radius,
        8.0 * PI * eta * radius.powi(3),
    );
    let (sg, sh, sm) = (sb, sc, 20.0 / 3.0 * PI * eta * radius.powi(3));
    let dl = delta;
    let a = M3::from_fn(|i, j| sa * (xa * d[i] * d[j] + ya * (dl(i, j) - d[i] * d[j])));
    let c = M3::from_fn(|i, j| sc * (xc * d[i] * d[j] + yc * (dl(i, j) - d[i] * d[j])));
    let b = M3::from_fn(|i, j| sb * yb * (0..3).map(|k| eps3(i, j, k) * d[k]).sum::<f64>());
    if !stresslets {
        return OrderedPair {
            a,
            b,
            c,
            g: SMatrix::zeros(),
            h: SMatrix::zeros(),
            m: SMatrix::zeros(),
        };
    }
    let g3 = |i: usize, j: usize, k: usize| {
        sg * (xg * (d[i] * d[j] - dl(i, j) / 3.0) * d[k]
            + yg * (d[i] * dl(j, k) + d[j] * dl(i, k) - 2.0 * d[i] * d[j] * d[k]))
    };
    let h3 = |i: usize, j: usize, k: usize| {
        sh * yh
            * (0..3)
                .map(|l| eps3(i, k, l) * d[l] * d[j] + eps3(j, k, l) * d[l] * d[i])
                .sum::<f64>()
    };
    let m4 = |i: usize, j: usize, k: usize, l: usize| {
        let (di, dj, dk, dd) = (d[i], d[j], d[k], d[l]);
        sm * (xm * 1.5 * (di * dj - dl(i, j) / 3.0) * (dk * dd - dl(k, l) / 3.0)
            + ym * 0.5
                * (di * dl(j, l) * dk
                    + dj * dl(i, l) * dk
                    + di * dl(j, k) * dd
                    + dj * dl(i, k) * dd
                    - 4.0 * di * dj * dk * dd)
            + zm * 0.5
                * (dl(i, k) * dl(j, l) + dl(j, k) * dl(i, l) - dl(i, j) * dl(k, l)
                    + di * dj * dl(k, l)
                    + dl(i, j) * dk * dd
                    - di * dl(j, l) * dk
                    - dj * dl(i, l) * dk
                    - di * dl(j, k) * dd
                    - dj * dl(i, k) * dd
                    + di * dj * dk * dd))
    };
    let g: [[[f64; 3]; 3]; 3] =
        std::array::from_fn(|i| std::array::from_fn(|j| std::array::from_fn(|k| g3(i, j, k))));
    let h: [[[f64; 3]; 3]; 3] =
        std::array::from_fn(|i| std::array::from_fn(|j| std::array::from_fn(|k| h3(i, j, k))));
    let m: [[[[f64; 3]; 3]; 3]; 3] = std::array::from_fn(|i| {
        std::array::from_fn(|j| std::array::from_fn(|k| std::array::from_fn(|l| m4(i, j, k, l))))
    });
    let (g, h, m) = (basis_rows(&g), basis_rows(&h), basis_both(&m));
    OrderedPair {
        a,
        b,
        c,
        g: SMatrix::from_fn(|r, k| g[r][k]),
        h: SMatrix::from_fn(|r, k| h[r][k]),
        m: SMatrix::from_fn(|r, n| m[r][n]),
    }
}

/// `R^P` of two spheres (exact two-sphere resistance, [`crate::two_sphere`]), per-particle
/// layout `[U_1, Omega_1, E_1, U_2, Omega_2, E_2]` truncated to `k` = 6 or 11 components
/// each. Each ordered block `(alpha, beta)` takes the "11" or "12" functions seen from
/// `alpha` (`lambda = a_beta/a_alpha`, scaled with `a_alpha`, `d` from `alpha` to the
/// other sphere; JO84 eq. 1.9); the force rows' rotation and strain
/// columns are the transposes of the other ordered pair's torque and stresslet rows
/// (`B~^{ab} = (B^{ba})^T`, `G~^{ab} = (G^{ba})^T`, `H~^{ab} = (H^{ba})^T`, JO84 eq. 1.4).
/// `spheres` holds each sphere's radius and the functions seen from it ([`PairFunctions`]).
pub fn pair_block(
    eta: f64,
    spheres: [(f64, PairScalars); 2],
    d: [f64; 3],
    k: usize,
) -> DMatrix<f64> {
    let mut blocks = Vec::with_capacity(4);
    for al in 0..2 {
        let (radius, f) = spheres[al];
        let dd = if al == 0 { d } else { d.map(|v| -v) };
        for be in 0..2 {
            blocks.push(ordered_pair(eta, radius, &f, al == be, dd, k == 11));
        }
    }
    let blk = |al: usize, be: usize| &blocks[2 * al + be];
    let mut r = DMatrix::zeros(2 * k, 2 * k);
    for al in 0..2 {
        for be in 0..2 {
            let (p, q) = (blk(al, be), blk(be, al));
            let (r0, c0) = (k * al, k * be);
            for i in 0..3 {
                for j in 0..3 {
                    r[(r0 + i, c0 + j)] = p.a[(i, j)];
                    r[(r0 + 3 + i, c0 + j)] = p.b[(i, j)];
                    r[(r0 + i, c0 + 3 + j)] = q.b[(j, i)];
                    r[(r0 + 3 + i, c0 + 3 + j)] = p.c[(i, j)];
                }
            }
            if k == 11 {
                for m in 0..5 {
                    for j in 0..3 {
                        r[(r0 + 6 + m, c0 + j)] = p.g[(m, j)];
                        r[(r0 + 6 + m, c0 + 3 + j)] = p.h[(m, j)];
                        r[(r0 + j, c0 + 6 + m)] = q.g[(m, j)];
                        r[(r0 + 3 + j, c0 + 6 + m)] = q.h[(m, j)];
                    }
                    for n in 0..5 {
                        r[(r0 + 6 + m, c0 + 6 + n)] = p.m[(m, n)];
                    }
                }
            }
        }
    }
    r
}

/// The mirror image in a horizontal plane on the per-particle components `[U, Omega,
/// E]` (`k` = 6 or 11): `U -> P U`, `Omega -> -P Omega` (an axial vector),
/// `E -> P E P` in the orthonormal strain basis, `P = diag(1, 1, -1)`.
pub fn mirror(k: usize) -> DMatrix<f64> {
    let p = |i: usize| if i == 2 { -1.0 } else { 1.0 };
    let mut t = [[[[0.0; 3]; 3]; 3]; 3];
    for (i, ti) in t.iter_mut().enumerate() {
        for (j, tij) in ti.iter_mut().enumerate() {
            tij[i][j] = p(i) * p(j);
        }
    }
    let strain = basis_both(&t);
    DMatrix::from_fn(k, k, |i, j| match (i, j) {
        (0..=2, 0..=2) if i == j => p(i),
        (3..=5, 3..=5) if i == j => -p(i - 3),
        (6.., 6..) => strain[i - 6][j - 6],
        _ => 0.0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::two_sphere::PairSeries;

    /// unequal spheres at FTS, which checks the lambda -> 1/lambda rule and the
    /// transposed force rows; 1e-12 relative: the series satisfy reciprocity to
    /// 7e-14 (two_sphere_exact).
    #[test]
    fn pair_block_is_symmetric() {
        let (a1, a2) = (1.0, 2.5);
        let (s1, s2) = (
            PairSeries::new(a2 / a1).unwrap(),
            PairSeries::new(a1 / a2).unwrap(),
        );
        let d = [0.6, 0.0, 0.8];
        let (f1, f2) = (s1.scalars(2.2).unwrap(), s2.scalars(2.2).unwrap());
        let r = pair_block(1.3, [(a1, f1), (a2, f2)], d, 11);
        assert!((&r - r.transpose()).norm() < 1e-12 * r.norm());
        let w = wall_block(1.0, 1.0, 1e-3, [0.0, 0.0, 1.0]);
        assert!((w - w.transpose()).norm() < 1e-14 * w.norm());
    }
}
