//! The resistance with lubrication, Swan & Brady Eq. 19:
//! `R = M^-1 + R^P + R^W - (R^{P,inf} + R^{W,inf})`, at the FT and FTS levels.
//!
//! - `R^P`: near-contact two-sphere resistance (Jeffrey & Onishi 1984, as corrected by
//!   Townsend 2023; equal spheres, Kim & Karrila normalisation), for pairs with
//!   `xi = r/a - 2 < pair_cutoff`; `R^{P,inf}` the inverse of the FT mobility of the
//!   isolated pair in unbounded fluid, from our own kernels.
//! - `R^W`: the exact sphere-wall resistance (Brenner 1961; O'Neill 1964; Dean & O'Neill
//!   1963 with Goldman, Cox & Brenner 1967; Jeffery 1915; near-contact forms below
//!   eps = 1e-3), for spheres with `eps = (h - a)/a < wall_cutoff` from a no-slip wall;
//!   `R^{W,inf}` the inverse of the FT self mobility of the sphere with that wall alone,
//!   from our kernels.
//!
//! Coefficients are those collected, with their sources and a second check, in
//! `shared/reference/lubrication.md` (sections 1.5 and 2.2); each is annotated below.
//! Sign: the resistance maps `(U, Omega)` to the force and torque the particles exert
//! on the fluid (the inverse of the mobility's convention), so every lubrication block
//! enters with the sign of a positive-definite resistance.

use crate::assembly::{Moments, System};
use kernels::{pair, self_mobility, Confinement};
use nalgebra::{DMatrix, SMatrix};
use std::f64::consts::PI;
use thiserror::Error;

/// Apery's constant zeta(3) (Jeffery 1915; Cox & Brenner 1967 eq. 3.5).
const ZETA3: f64 = 1.202_056_903_159_594_3;

/// Where lubrication is switched on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lubrication {
    /// Pairs with surface gap over radius `xi < pair_cutoff` get `R^P - R^{P,inf}`.
    pub pair_cutoff: f64,
    /// Spheres with gap over radius `eps < wall_cutoff` from a no-slip wall get
    /// `R^W - R^{W,inf}`.
    pub wall_cutoff: f64,
}

impl Default for Lubrication {
    /// Pairs: `xi < 0.1`, where the near-contact two-sphere forms are accurate (their
    /// neglected terms are O(xi^2 ln xi); Brady's codes switch to them below r = 2.1 a).
    /// Wall: `eps < 1`, with the exact sphere-wall series, as Bossis, Meunier & Sherwood
    /// (1991) tabulate exact values up to eps = 1; beyond, the far-field self mobility
    /// is within 5% (measured, README).
    fn default() -> Self {
        Lubrication {
            pair_cutoff: 0.1,
            wall_cutoff: 1.0,
        }
    }
}

/// Why a resistance cannot be formed.
#[derive(Debug, Error, PartialEq)]
pub enum ResistanceError {
    /// The F level has no rotations, so no resistance with lubrication.
    #[error("lubrication needs torques and rotations: use FT or FTS (asked for {0:?})")]
    Unsupported(Moments),
    /// Pair lubrication needs equal radii so far.
    #[error("particles {first} and {second} are within the lubrication cutoff but have unequal radii ({a1} and {a2}); pair lubrication is implemented for equal spheres only")]
    UnequalRadii {
        /// First particle.
        first: usize,
        /// Second particle.
        second: usize,
        /// Its radius.
        a1: f64,
        /// The other's.
        a2: f64,
    },
    /// The far-field mobility is not positive definite (overlaps, narrow slit).
    #[error("the far-field mobility is not positive definite, so it cannot be inverted (overlapping spheres or a slit too narrow for the superposition)")]
    MobilityNotPositiveDefinite,
    /// The corrected resistance is not positive definite.
    #[error("the resistance with lubrication is not positive definite")]
    ResistanceNotPositiveDefinite,
}

/// Sphere-wall resistance functions at `eps = (h - a)/a`: the exact bispherical series
/// ([`crate::exact`]: Brenner 1961, O'Neill 1964, Dean & O'Neill 1963 as corrected by
/// Goldman, Cox & Brenner 1967, Jeffery 1915) for `eps >= 1e-3`, and the near-contact
/// forms of [`wall_near_contact`] below, where they agree with the series to 3e-6
/// (measured at eps = 1e-3: X^A 4e-11, Y^A 1e-8, F^r 7e-7, Y^C 5e-7, X^C 2.8e-6) and the
/// series would need thousands of terms.
pub fn wall_functions(eps: f64) -> WallFunctions {
    if eps < 1e-3 {
        return wall_near_contact(eps);
    }
    let h = 1.0 + eps;
    let (ya, _) = crate::exact::oneill_parallel(h);
    let (fr, yc) = crate::exact::rotation_parallel(h);
    WallFunctions {
        xa: crate::exact::brenner_xa_wall(h),
        ya,
        fr,
        yc,
        xc: crate::exact::jeffery_xc_wall(h),
    }
}

/// Near-contact sphere-wall resistance functions at `eps = (h - a)/a`, normalised as
/// `R_FU = 6 pi eta a [X^A nn + Y^A (I - nn)]`, `R_LO = 8 pi eta a^3 [X^C nn + Y^C (I - nn)]`,
/// `(R_FO)_ij = -6 pi eta a^2 F^r eps_ijk n_k`, `R_LU = R_FO^T`; `n` the wall normal
/// into the fluid. Singular and `eps ln eps` terms: Brenner 1961, Cox & Brenner 1967
/// eq. 2.49 (X^A); Goldman, Cox & Brenner 1967 eqs. 2.59, 2.65, 3.6-3.13 (Y^A, F^r,
/// Y^C); Jeffery 1915 / Cox & Brenner 1967 eq. 3.5 (X^C); checked against the
/// lambda -> infinity limits of the two-sphere functions. O(1) constants and O(eps)
/// terms: fits to the exact bispherical series (lubrication.md 2.2), which GCB's
/// constants (0.9588, -0.2526, 0.3817) approximate at their last tabulated gap.
pub fn wall_near_contact(eps: f64) -> WallFunctions {
    let l = (1.0 / eps).ln();
    WallFunctions {
        xa: 1.0 / eps + l / 5.0 + 0.971_279_9 + eps * l / 21.0 + 0.167_02 * eps,
        ya: 8.0 / 15.0 * l + 0.954_293_7 + 64.0 / 375.0 * eps * l + 0.429_45 * eps,
        fr: 2.0 / 15.0 * l - 0.257_270_3 + 86.0 / 375.0 * eps * l + 0.134_11 * eps,
        yc: 2.0 / 5.0 * l + 0.370_892_6 + 66.0 / 125.0 * eps * l + 0.340_09 * eps,
        xc: ZETA3 - 0.5 * eps * l + 0.444_93 * eps,
    }
}

/// The five sphere-wall resistance functions (see [`wall_functions`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallFunctions {
    /// Translation normal to the wall.
    pub xa: f64,
    /// Translation parallel to the wall.
    pub ya: f64,
    /// Translation-rotation coupling.
    pub fr: f64,
    /// Rotation about an axis parallel to the wall.
    pub yc: f64,
    /// Rotation about the wall normal.
    pub xc: f64,
}

/// Near-contact resistance functions of two equal spheres at `xi = r/a - 2`, Kim &
/// Karrila normalisation (A by 6 pi eta a, B by 4 pi eta a^2, C by 8 pi eta a^3),
/// lubrication.md 1.5 (Jeffrey & Onishi 1984; Townsend 2023; singular terms checked
/// against the Swan & Brady Fortran code; X^A constants against the exact bispherical
/// solutions, X^C from Jeffery 1915).
pub fn pair_functions(xi: f64) -> PairFunctions {
    let l = (1.0 / xi).ln();
    PairFunctions {
        xa11: 1.0 / (4.0 * xi) + 9.0 / 40.0 * l + 0.995_36 + 3.0 / 112.0 * xi * l,
        xa12: -1.0 / (4.0 * xi) - 9.0 / 40.0 * l - 0.350_22 - 3.0 / 112.0 * xi * l,
        ya11: l / 6.0 + 0.9983,
        ya12: -l / 6.0 - 0.2737,
        yb11: -l / 4.0 + 0.2390 - xi * l / 8.0,
        yb12: l / 4.0 - 0.0016 + xi * l / 8.0,
        xc11: 7.0 / 8.0 * ZETA3 - xi * l / 8.0,
        xc12: -ZETA3 / 8.0 + xi * l / 8.0,
        yc11: l / 5.0 + 0.7028 + 47.0 / 250.0 * xi * l,
        yc12: l / 20.0 - 0.0274 + 31.0 / 500.0 * xi * l,
    }
}

/// The two-sphere FT resistance functions (see [`pair_functions`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(missing_docs)]
pub struct PairFunctions {
    pub xa11: f64,
    pub xa12: f64,
    pub ya11: f64,
    pub ya12: f64,
    pub yb11: f64,
    pub yb12: f64,
    pub xc11: f64,
    pub xc12: f64,
    pub yc11: f64,
    pub yc12: f64,
}

type M6 = SMatrix<f64, 6, 6>;
type M12 = SMatrix<f64, 12, 12>;

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
fn wall_block(eta: f64, a: f64, eps: f64, n: [f64; 3]) -> M6 {
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

/// `R^P` of two equal spheres (radius `a`, gap `xi`, `d` the unit vector from sphere 1
/// to sphere 2), 12x12 in the order `[U_1, Omega_1, U_2, Omega_2]`. Each ordered block
/// `(alpha, beta)` uses the 11 or 12 functions with `d` pointing from alpha to beta
/// (Townsend's rule, lubrication.md 1.3); `R_FO^{ab} = (B^{ba})^T`.
fn pair_block(eta: f64, a: f64, xi: f64, d: [f64; 3]) -> M12 {
    let f = pair_functions(xi);
    let (sa, sb, sc) = (
        6.0 * PI * eta * a,
        4.0 * PI * eta * a * a,
        8.0 * PI * eta * a.powi(3),
    );
    let mut r = M12::zeros();
    // (alpha, beta, same particle, sign of d)
    let mut b_blocks = [[SMatrix::<f64, 3, 3>::zeros(); 2]; 2];
    for (al, be) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
        let s = if al == 0 { 1.0 } else { -1.0 }; // d from alpha towards the other sphere
        let dd = [s * d[0], s * d[1], s * d[2]];
        let (xa, ya, yb, xc, yc) = if al == be {
            (f.xa11, f.ya11, f.yb11, f.xc11, f.yc11)
        } else {
            (f.xa12, f.ya12, f.yb12, f.xc12, f.yc12)
        };
        for i in 0..3 {
            for j in 0..3 {
                let p = dd[i] * dd[j];
                r[(6 * al + i, 6 * be + j)] = sa * (xa * p + ya * (delta(i, j) - p));
                r[(6 * al + 3 + i, 6 * be + 3 + j)] = sc * (xc * p + yc * (delta(i, j) - p));
                b_blocks[al][be][(i, j)] =
                    sb * yb * (0..3).map(|k| eps3(i, j, k) * dd[k]).sum::<f64>();
            }
        }
    }
    for al in 0..2 {
        for be in 0..2 {
            for i in 0..3 {
                for j in 0..3 {
                    r[(6 * al + 3 + i, 6 * be + j)] = b_blocks[al][be][(i, j)]; // R_LU = B
                    r[(6 * al + i, 6 * be + 3 + j)] = b_blocks[be][al][(j, i)]; // R_FO = B~
                }
            }
        }
    }
    r
}

/// The self mobility (per-particle layout `[U, Omega, E]`, truncated to `k` = 6 or 11
/// components) of a sphere with one no-slip wall at height `plane`.
fn single_wall_self(eta: f64, x: [f64; 3], a: f64, plane: f64, k: usize) -> DMatrix<f64> {
    // Blake's image holds on either side of its plane (see kernel-gen green::slit).
    let m = self_mobility(&Confinement::Wall { height: plane }, eta, x, a).matrix();
    DMatrix::from_fn(k, k, |i, j| m[(i, j)])
}

/// The mobility of an isolated pair of spheres in unbounded fluid, per-particle layout
/// `[U_1, Omega_1, E_1, U_2, Omega_2, E_2]` truncated to `k` = 6 or 11 components each.
fn free_pair_mobility(
    eta: f64,
    (x1, a1): ([f64; 3], f64),
    (x2, a2): ([f64; 3], f64),
    k: usize,
) -> DMatrix<f64> {
    let s1 = self_mobility(&Confinement::Free, eta, x1, a1).matrix();
    let s2 = self_mobility(&Confinement::Free, eta, x2, a2).matrix();
    let p = pair(&Confinement::Free, eta, x1, a1, x2, a2).matrix();
    DMatrix::from_fn(2 * k, 2 * k, |i, j| match (i / k, j / k) {
        (0, 0) => s1[(i, j)],
        (1, 1) => s2[(i - k, j - k)],
        (0, 1) => p[(i, j - k)],
        _ => p[(j, i - k)],
    })
}

/// Global index (moment-major layout of [`System::mobility`]) of component `c` of
/// `[U, Omega, E]` (0..3, 3..6, 6..11) of particle `a` among `n`.
fn global_index(n: usize, a: usize, c: usize) -> usize {
    match c {
        0..=2 => 3 * a + c,
        3..=5 => 3 * n + 3 * a + (c - 3),
        _ => 6 * n + 5 * a + (c - 6),
    }
}

/// Add `exact - far^-1` to `r` on the rows and columns `idx` (per-particle blocks of
/// `k` components): where the exact resistance is known, which is the leading `known`
/// components of each particle (`known` = 6: force-torque only); elsewhere the
/// far-field inverse is kept (the correction is zero).
fn add_correction(
    r: &mut DMatrix<f64>,
    idx: &[usize],
    exact: &DMatrix<f64>,
    far: DMatrix<f64>,
    k: usize,
    known: usize,
) -> Result<(), ResistanceError> {
    let far_inv = far
        .cholesky()
        .ok_or(ResistanceError::MobilityNotPositiveDefinite)?
        .inverse();
    let ek = exact.nrows() / (idx.len() / k); // components per particle in `exact`
    let local = |i: usize| (i / k) * ek + i % k;
    for i in 0..idx.len() {
        for j in 0..idx.len() {
            if i % k < known && j % k < known {
                r[(idx[i], idx[j])] += exact[(local(i), local(j))] - far_inv[(i, j)];
            }
        }
    }
    Ok(())
}

impl System {
    /// The grand resistance with lubrication (Eq. 19) at the FT or FTS level, in the
    /// layout of [`System::mobility`] with rows `(F, L[, S])` and columns
    /// `(U, Omega[, -E_inf])`. At FTS the lubrication corrections act on the force-torque
    /// blocks (the exact two-sphere and sphere-wall functions used here are those of
    /// translation and rotation); the stresslet rows and columns keep the far-field
    /// inverse. Overlapping spheres are rejected at construction unless allowed; pairs
    /// within the cutoff must have equal radii.
    pub fn resistance(
        &self,
        moments: Moments,
        lub: &Lubrication,
    ) -> Result<DMatrix<f64>, ResistanceError> {
        let k = match moments {
            Moments::FT => 6,
            Moments::FTS => 11,
            Moments::F => return Err(ResistanceError::Unsupported(moments)),
        };
        let n = self.len();
        let eta = self.viscosity();
        let ps = self.particles();
        let m = self.mobility(moments);
        let mut r = m
            .cholesky()
            .ok_or(ResistanceError::MobilityNotPositiveDefinite)?
            .inverse();
        let no_slip: Vec<(f64, bool)> = match *self.confinement() {
            Confinement::Wall { height } => vec![(height, true)],
            Confinement::Slit { height, gap } => vec![(height, true), (height + gap, false)],
            _ => vec![],
        };
        // R^W - R^{W,inf}, per sphere and no-slip wall.
        for (a, p) in ps.iter().enumerate() {
            for &(plane, above) in &no_slip {
                let h = if above {
                    p.x[2] - plane
                } else {
                    plane - p.x[2]
                };
                let eps = (h - p.a) / p.a;
                if eps >= lub.wall_cutoff {
                    continue;
                }
                let nrm = [0.0, 0.0, if above { 1.0 } else { -1.0 }];
                let exact = DMatrix::from_fn(6, 6, |i, j| wall_block(eta, p.a, eps, nrm)[(i, j)]);
                let idx: Vec<usize> = (0..k).map(|c| global_index(n, a, c)).collect();
                let far = single_wall_self(eta, p.x, p.a, plane, k);
                add_correction(&mut r, &idx, &exact, far, k, 6)?;
            }
        }
        // R^P - R^{P,inf}, per close pair.
        for a in 0..n {
            for b in a + 1..n {
                let (p, q) = (&ps[a], &ps[b]);
                let dx: [f64; 3] = std::array::from_fn(|c| q.x[c] - p.x[c]);
                let dist = (dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2]).sqrt();
                let mean = 0.5 * (p.a + q.a);
                let xi = (dist - p.a - q.a) / mean;
                if xi >= lub.pair_cutoff {
                    continue;
                }
                if p.a != q.a {
                    return Err(ResistanceError::UnequalRadii {
                        first: a,
                        second: b,
                        a1: p.a,
                        a2: q.a,
                    });
                }
                let d = [dx[0] / dist, dx[1] / dist, dx[2] / dist];
                let exact = DMatrix::from_fn(12, 12, |i, j| pair_block(eta, p.a, xi, d)[(i, j)]);
                let idx: Vec<usize> = (0..2 * k)
                    .map(|i| global_index(n, if i < k { a } else { b }, i % k))
                    .collect();
                let far = free_pair_mobility(eta, (p.x, p.a), (q.x, q.a), k);
                add_correction(&mut r, &idx, &exact, far, k, 6)?;
            }
        }
        // Exact symmetry (the corrections are symmetric to round-off).
        let r = (&r + r.transpose()) * 0.5;
        Ok(r)
    }
}

/// Velocities from forces with lubrication: `R x = f` solved by Cholesky.
/// Returns the solution and a condition estimate `(max L_ii / min L_ii)^2` of `R`
/// (a lower bound on the 2-norm condition number, cheap from the factor).
pub fn solve_resistance(r: &DMatrix<f64>, f: &[f64]) -> Result<(Vec<f64>, f64), ResistanceError> {
    let c = r
        .clone()
        .cholesky()
        .ok_or(ResistanceError::ResistanceNotPositiveDefinite)?;
    let l = c.l();
    let diag: Vec<f64> = (0..l.nrows()).map(|i| l[(i, i)]).collect();
    let (mx, mn) = diag.iter().fold((0.0f64, f64::INFINITY), |(mx, mn), &v| {
        (mx.max(v), mn.min(v))
    });
    let x = c.solve(&nalgebra::DVector::from_column_slice(f));
    Ok((x.iter().copied().collect(), (mx / mn).powi(2)))
}

/// Velocities of rigid spheres from forces, torques and an imposed strain with the FTS
/// resistance `r` (`11N x 11N`, rows `F, L, S`, columns `U - U_inf, Omega - Omega_inf,
/// -E_inf`): the force-torque rows give
/// `R_{FL,U Omega} (U - U_inf, Omega - Omega_inf) = (F, L) - R_{FL,E} (-E_inf)`, solved by
/// [`solve_resistance`]. Returns the `6N` velocities (moment-major) and the condition
/// estimate of the force-torque block.
pub fn solve_resistance_fts(
    r: &DMatrix<f64>,
    fl: &[f64],
    e_inf: &[f64; 5],
) -> Result<(Vec<f64>, f64), ResistanceError> {
    let n = r.nrows() / 11;
    let y_e = nalgebra::DVector::from_fn(5 * n, |i, _| -e_inf[i % 5]);
    let rhs = nalgebra::DVector::from_column_slice(fl) - r.view((0, 6 * n), (6 * n, 5 * n)) * y_e;
    let block = r.view((0, 0), (6 * n, 6 * n)).into_owned();
    solve_resistance(&block, rhs.as_slice())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn singular_terms_match_the_wall_limit_of_the_pair_functions() {
        // lubrication.md 2.2: the wall's eps ln eps coefficients are the lambda -> infinity
        // limits of the pair g3's; here a spot check of the wall functions' slopes.
        let (e1, e2) = (1e-6, 1e-7);
        let (w1, w2) = (wall_near_contact(e1), wall_near_contact(e2));
        let dl = (1.0f64 / e2).ln() - (1.0f64 / e1).ln();
        assert!(((w2.ya - w1.ya) / dl - 8.0 / 15.0).abs() < 1e-5);
        assert!(((w2.yc - w1.yc) / dl - 2.0 / 5.0).abs() < 1e-5);
        assert!(((w2.fr - w1.fr) / dl - 2.0 / 15.0).abs() < 1e-5);
    }

    #[test]
    fn pair_block_is_symmetric() {
        let r = pair_block(1.0, 1.0, 1e-3, [0.6, 0.0, 0.8]);
        assert!((r - r.transpose()).norm() < 1e-12 * r.norm());
        let w = wall_block(1.0, 1.0, 1e-3, [0.0, 0.0, 1.0]);
        assert!((w - w.transpose()).norm() < 1e-14 * w.norm());
    }
}
