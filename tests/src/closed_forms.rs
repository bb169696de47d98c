//! Free-space far-field grand mobility of two spheres of unequal radii, in closed form.
//!
//! An independent reference for the generated free-space kernels: every block is written out
//! as scalar mobility functions of the distance and the radii times isotropic tensors built
//! from `e`, `delta` and `eps`, in the style of Durlofsky, Brady & Bossis (J. Fluid Mech. 180,
//! 21, 1987; "DBB") and Kim & Karrila (Microhydrodynamics, 1991; "KK"). Nothing
//! here differentiates anything; the formulas were derived by hand and are checked against a
//! symbolic differentiation of the definitions in `tests/derivations/free_space_check.py`
//! (identical for all `r != 0` and all radii, exactly, by polynomial reduction).
//!
//! # Conventions
//!
//! Sphere `a` (radius `aa`, centre `xa`) is the field point, sphere `b` (radius `ab`, centre
//! `xb`) the source; `r = xa - xb`, `e = r/|r|`, `C = 1/(8 pi eta)`. Blocks are dimensional.
//! The Oseen tensor is `G_ij(x, y) = J_ij(x - y)`, `J_ij(r) = C (delta_ij/r + r_i r_j/r^3)`;
//! `d/dx` acts at `x = xa`, `d/dy` at `y = xb`, so `d/dx = d/dr` and `d/dy = -d/dr`; `eps` is
//! right-handed (`eps_123 = +1`). The blocks are defined as
//!
//! ```text
//! UF_ij   = (1 + aa^2/6 Lap_x)(1 + ab^2/6 Lap_y) G_ij
//! UL_im   = (1 + aa^2/6 Lap_x) V_im,                  V_im  = 1/2 eps_mkj d/dy_k G_ij
//! US_ikl  = (1 + aa^2/6 Lap_x)(1 + ab^2/10 Lap_y) W_ikl,  W_ikl = 1/2 (d/dy_k G_il + d/dy_l G_ik)
//! OF_mj   = 1/2 eps_mki d/dx_k (1 + ab^2/6 Lap_y) G_ij
//! OL_mn   = 1/2 eps_mki d/dx_k V_in
//! OS_mkl  = 1/2 eps_mpi d/dx_p (1 + ab^2/10 Lap_y) W_ikl
//! EF_pqj  = 1/2 (d/dx_p G_qj + d/dx_q G_pj), with (1 + aa^2/10 Lap_x)(1 + ab^2/6 Lap_y)
//! EL_pqm  = 1/2 (d/dx_p V_qm + d/dx_q V_pm), with (1 + aa^2/10 Lap_x)
//! ES_pqkl = 1/2 (d/dx_p W_qkl + d/dx_q W_pkl), with (1 + aa^2/10 Lap_x)(1 + ab^2/10 Lap_y)
//! ```
//!
//! # Why only a few radius combinations appear (the unequal-radius generalisation)
//!
//! All operators commute and act on functions of `r` only, so `Lap_x = Lap_y = Lap`. For
//! `r != 0`: `Lap Lap J = 0` (J is biharmonic), so a Faxen factor at each end collapses to
//! one, `(1 + alpha Lap)(1 + beta Lap) J = (1 + (alpha + beta) Lap) J`; `Lap J = -2 C grad grad
//! (1/r)` is a pure gradient, so its curl vanishes (no Faxen correction in OF, OS); the rotlet
//! `V` is harmonic, `Lap V = 0` (no Faxen correction in UL, OL, EL). Hence the radii enter
//! only through
//!
//! ```text
//! UF: aa^2/6 + ab^2/6    -> s   = aa^2 + ab^2
//! US: aa^2/6 + ab^2/10   -> t_u = aa^2 + 3 ab^2/5
//! EF: aa^2/10 + ab^2/6   -> t_e = 3 aa^2/5 + ab^2
//! ES: aa^2/10 + ab^2/10  -> s   = aa^2 + ab^2
//! UL, OF, OL, EL, OS: no radius dependence
//! ```
//!
//! and each block is the equal-radius DBB/KK far-field form with the equal-radius value of
//! the combination (`s = 2 a^2`, `t_u = t_e = 8 a^2/5`) replaced by the one above (the same generalisation as the polydisperse far-field mobility of
//! Rotne-Prager-Yamakawa and of A. K. Townsend's thesis, UCL 2017, table 2.1).
//!
//! # Relation to the literature's normalisation
//!
//! For comparison with the equal-radius tables of DBB and KK (dimensionless, mobilities
//! scaled by `6 pi eta a^n`, distances by `a`): with `aa = ab = a` and `rho = |r|/a`, `6 pi
//! eta a^n` times our scalar functions (`n` = 1 for a, 2 for b and g, 3 for c, h and m) is
//! `x^a = 3/(2 rho) - 1/rho^3`, `y^a = 3/(4 rho) + 1/(2 rho^3)`, `y^b = 3/(4 rho^2)`, `x^c =
//! 3/(4 rho^3)`, `y^c = -3/(8 rho^3)`, `x^g = -9/(4 rho^2) + 18/(5 rho^4)`, `y^g = -6/(5
//! rho^4)` (for EF; US has the opposite sign), `y^h = -9/(8 rho^3)`, `x^m = -9/(2 rho^3) +
//! 54/(5 rho^5)`, `y^m = 9/(4 rho^3) - 36/(5 rho^5)`, `z^m = 9/(5 rho^5)`. The signs here
//! follow from the definitions above and from `r = xa - xb`, never from a printed table;
//! the functions odd in `e` (b, g) change sign with the direction of `e` and with the
//! ordering of the pair, in which printed tables differ.
//!
//! # Trace parts
//!
//! Every block with a strain or stresslet index pair is traceless in that pair, identically
//! for `r != 0`: `US_ikk = 0`, `OS_mkk = 0`, `EF_ppj = 0`, `EL_ppm = 0`, `ES_ppkl = 0`,
//! `ES_pqkk = 0`. Reason: `W_ikk = -d/dr_k J_ik = 0` and `d/dx_p G_pj = 0` (incompressibility,
//! J symmetric), and the Faxen Laplacians commute with the traces. So these blocks, though not
//! projected, equal their projections onto symmetric-traceless pairs; their Cartesian entries
//! still contain `delta_pq`, `delta_kl` terms, which are what makes them traceless.
//!
//! # Accuracy
//!
//! Each scalar is evaluated as `C / |r|^n` times a polynomial in the dimensionless `(aa/|r|)^2`
//! and `(ab/|r|)^2`, and `|r|` is computed with scaling, so there is no overflow or underflow
//! beyond that of the result itself and no catastrophic cancellation for `|r| >= 2 max(aa,
//! ab)` (the worst case, `3 - 24 s/(5 r^2)` in `y^m` at contact of equal spheres, loses a
//! factor of about 5). Measured against 50-digit references: relative Frobenius error below
//! `2e-15` per block for `|r|/max(aa, ab)` in `[2.01, 1000]` and radius ratios up to 10.
//!
//! `r` must be non-zero (the self blocks are not pair interactions); for `r = 0` the results
//! are NaN.

use std::array::from_fn;
use std::f64::consts::PI;

/// `e = r/|r|` and `1/|r|`, with `|r|` computed from the scaled vector (no overflow or
/// underflow of the squares).
fn unit(r: [f64; 3]) -> ([f64; 3], f64) {
    let m = r[0].abs().max(r[1].abs()).max(r[2].abs());
    let v = [r[0] / m, r[1] / m, r[2] / m];
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    ([v[0] / n, v[1] / n, v[2] / n], 1.0 / (m * n))
}

/// `C = 1/(8 pi eta)`, the Oseen prefactor.
fn oseen(eta: f64) -> f64 {
    1.0 / (8.0 * PI * eta)
}

/// Kronecker delta.
fn delta(i: usize, j: usize) -> f64 {
    if i == j {
        1.0
    } else {
        0.0
    }
}

/// Levi-Civita symbol, right-handed: `eps(0, 1, 2) = +1`.
fn eps(i: usize, j: usize, k: usize) -> f64 {
    match (i, j, k) {
        (0, 1, 2) | (1, 2, 0) | (2, 0, 1) => 1.0,
        (0, 2, 1) | (2, 1, 0) | (1, 0, 2) => -1.0,
        _ => 0.0,
    }
}

/// `eps_ijk e_k`.
fn eps_e(e: &[f64; 3], i: usize, j: usize) -> f64 {
    (0..3).map(|k| eps(i, j, k) * e[k]).sum()
}

/// `(a/|r|)^2` from `a` and `1/|r|`.
fn ratio2(a: f64, ir: f64) -> f64 {
    let x = a * ir;
    x * x
}

/// Velocity of sphere a due to a force on sphere b: the Rotne-Prager-Yamakawa tensor for
/// unequal radii, `UF[i][j]` (velocity `i`, force `j`).
///
/// ```text
/// UF_ij = x^a e_i e_j + y^a (delta_ij - e_i e_j)
/// x^a = C (2/r - 2 s/(3 r^3)),   y^a = C (1/r + s/(3 r^3)),   s = aa^2 + ab^2
/// ```
///
/// Source: Rotne & Prager (1969), Yamakawa (1970); DBB (1987) `x^a_12`, `y^a_12`; KK.
/// Unequal radii: `Lap_x Lap_y J = 0` for `r != 0`, so the two Faxen factors give
/// `J + (aa^2 + ab^2)/6 Lap J` with `Lap J_ij = C (2 delta_ij - 6 e_i e_j)/r^3`; only `aa^2 +
/// ab^2` appears (the Rotne-Prager-Yamakawa form for `r >= aa + ab`).
pub fn uf(r: [f64; 3], aa: f64, ab: f64, eta: f64) -> [[f64; 3]; 3] {
    let (e, ir) = unit(r);
    let c = oseen(eta);
    let s = ratio2(aa, ir) + ratio2(ab, ir);
    let xa = c * ir * (2.0 - 2.0 / 3.0 * s);
    let ya = c * ir * (1.0 + s / 3.0);
    from_fn(|i| {
        from_fn(|j| {
            let ee = e[i] * e[j];
            xa * ee + ya * (delta(i, j) - ee)
        })
    })
}

/// Velocity of sphere a due to a torque on sphere b (the rotlet), `UL[i][m]` (velocity `i`,
/// torque `m`).
///
/// ```text
/// UL_im = y^b eps_imk e_k,   y^b = C/r^2
/// ```
///
/// i.e. `u = L x r / (8 pi eta r^3)`. Source: the rotlet, KK (`b~` coupling);
/// DBB `y^b_12`. No radius dependence: the Faxen Laplacian at a acts on the rotlet `V_im =
/// 1/2 eps_mkj d/dy_k J_ij`, which is harmonic. Reciprocal of [`of`]: `UL^{ab}(r) =
/// OF^{ba}(-r)^T`.
pub fn ul(r: [f64; 3], aa: f64, ab: f64, eta: f64) -> [[f64; 3]; 3] {
    let _ = (aa, ab);
    let (e, ir) = unit(r);
    let yb = oseen(eta) * ir * ir;
    from_fn(|i| from_fn(|m| yb * eps_e(&e, i, m)))
}

/// Velocity of sphere a due to a stresslet on sphere b, `US[i][k][l]` (velocity `i`,
/// stresslet `kl`).
///
/// ```text
/// US_ikl = x^g_u (e_k e_l - delta_kl/3) e_i + y^g_u (e_k delta_il + e_l delta_ik - 2 e_i e_k e_l)
/// x^g_u = 3 C (1/r^2 - t_u/r^4),   y^g_u = C t_u/r^4,   t_u = aa^2 + 3 ab^2/5
/// ```
///
/// Source: DBB `g~` coupling (`x^g`, `y^g`), KK; equal radii give `t_u = 8 a^2/5`.
/// Unequal radii: the Faxen factors `(1 + aa^2/6 Lap)(1 + ab^2/10 Lap)` act on `W_ikl = C (3
/// e_i e_k e_l - delta_kl e_i)/r^2`, which is biharmonic, so they give `W + (aa^2/6 +
/// ab^2/10) Lap W` with `Lap W_ikl = 6 C (delta_kl e_i + delta_ik e_l + delta_il e_k - 5 e_i
/// e_k e_l)/r^4`. Traceless in `kl` (`US_ikk = 0`). Reciprocal of [`ef`]: `US^{ab}(r) =
/// EF^{ba}(-r)^T`, i.e. `US_ikl(r, aa, ab) = -EF_kli(r, ab, aa)`.
pub fn us(r: [f64; 3], aa: f64, ab: f64, eta: f64) -> [[[f64; 3]; 3]; 3] {
    let (e, ir) = unit(r);
    let c = oseen(eta) * ir * ir;
    let t = ratio2(aa, ir) + 0.6 * ratio2(ab, ir);
    let xg = 3.0 * c * (1.0 - t);
    let yg = c * t;
    from_fn(|i| {
        from_fn(|k| {
            from_fn(|l| {
                xg * (e[k] * e[l] - delta(k, l) / 3.0) * e[i]
                    + yg * (e[k] * delta(i, l) + e[l] * delta(i, k) - 2.0 * e[i] * e[k] * e[l])
            })
        })
    })
}

/// Rotation of sphere a due to a force on sphere b, `OF[m][j]` (rotation `m`, force `j`).
///
/// ```text
/// OF_mj = y^b eps_mjk e_k,   y^b = C/r^2
/// ```
///
/// i.e. half the vorticity of the Stokeslet, `Omega = F x r / (8 pi eta r^3)`. Source: KK
/// (`b` coupling), DBB `y^b_12`. No radius dependence: the curl removes the Faxen term
/// at b, since `Lap J = -2 C grad grad (1/r)` is curl-free. Reciprocal of [`ul`].
pub fn of(r: [f64; 3], aa: f64, ab: f64, eta: f64) -> [[f64; 3]; 3] {
    let _ = (aa, ab);
    let (e, ir) = unit(r);
    let yb = oseen(eta) * ir * ir;
    from_fn(|m| from_fn(|j| yb * eps_e(&e, m, j)))
}

/// Rotation of sphere a due to a torque on sphere b (rotlet-rotlet), `OL[m][n]` (rotation
/// `m`, torque `n`).
///
/// ```text
/// OL_mn = x^c e_m e_n + y^c (delta_mn - e_m e_n),   x^c = C/r^3,   y^c = -C/(2 r^3)
/// ```
///
/// i.e. `OL = (3 e e - delta)/(16 pi eta r^3)`. Source: KK (`c` coupling), DBB
/// `x^c_12`, `y^c_12`. No radius dependence (the curl of the harmonic rotlet has no Faxen
/// correction, and the definition carries none).
pub fn ol(r: [f64; 3], aa: f64, ab: f64, eta: f64) -> [[f64; 3]; 3] {
    let _ = (aa, ab);
    let (e, ir) = unit(r);
    let c3 = oseen(eta) * ir * ir * ir;
    let xc = c3;
    let yc = -0.5 * c3;
    from_fn(|m| {
        from_fn(|n| {
            let ee = e[m] * e[n];
            xc * ee + yc * (delta(m, n) - ee)
        })
    })
}

/// Rotation of sphere a due to a stresslet on sphere b, `OS[m][k][l]` (rotation `m`,
/// stresslet `kl`).
///
/// ```text
/// OS_mkl = -y^h (eps_mki e_i e_l + eps_mli e_i e_k),   y^h = -3 C/(2 r^3)
/// ```
///
/// Source: KK (`h~` coupling), DBB `y^h_12`. No radius dependence: `Lap W` is a third
/// gradient of `1/r`, so its curl vanishes. Traceless in `kl`. Reciprocal of [`el`]:
/// `OS^{ab}(r) = EL^{ba}(-r)^T`, and since both are even in `e` and radius-free,
/// `OS_mkl = EL_klm`.
pub fn os(r: [f64; 3], aa: f64, ab: f64, eta: f64) -> [[[f64; 3]; 3]; 3] {
    let _ = (aa, ab);
    let (e, ir) = unit(r);
    let yh = -1.5 * oseen(eta) * ir * ir * ir;
    from_fn(|m| from_fn(|k| from_fn(|l| -yh * (eps_e(&e, m, k) * e[l] + eps_e(&e, m, l) * e[k]))))
}

/// Rate of strain at sphere a due to a force on sphere b, `EF[p][q][j]` (strain `pq`, force
/// `j`).
///
/// ```text
/// EF_pqj = x^g (e_p e_q - delta_pq/3) e_j + y^g (e_p delta_qj + e_q delta_pj - 2 e_p e_q e_j)
/// x^g = -3 C (1/r^2 - t_e/r^4),   y^g = -C t_e/r^4,   t_e = 3 aa^2/5 + ab^2
/// ```
///
/// Source: DBB `g` coupling (`x^g_12`, `y^g_12`; equal radii `t_e = 8 a^2/5`), KK.
/// Unequal radii: the symmetric gradient of `J` is `C (delta_pq e_j - 3 e_p e_q e_j)/r^2`,
/// biharmonic, so the factors `(1 + aa^2/10 Lap)(1 + ab^2/6 Lap)` collapse to `1 + (aa^2/10 +
/// ab^2/6) Lap`. Traceless in `pq` (`EF_ppj = 0`). Reciprocal of [`us`].
pub fn ef(r: [f64; 3], aa: f64, ab: f64, eta: f64) -> [[[f64; 3]; 3]; 3] {
    let (e, ir) = unit(r);
    let c = oseen(eta) * ir * ir;
    let t = 0.6 * ratio2(aa, ir) + ratio2(ab, ir);
    let xg = -3.0 * c * (1.0 - t);
    let yg = -c * t;
    from_fn(|p| {
        from_fn(|q| {
            from_fn(|j| {
                xg * (e[p] * e[q] - delta(p, q) / 3.0) * e[j]
                    + yg * (e[p] * delta(q, j) + e[q] * delta(p, j) - 2.0 * e[p] * e[q] * e[j])
            })
        })
    })
}

/// Rate of strain at sphere a due to a torque on sphere b, `EL[p][q][m]` (strain `pq`,
/// torque `m`).
///
/// ```text
/// EL_pqm = y^h (e_p eps_qmk e_k + e_q eps_pmk e_k),   y^h = -3 C/(2 r^3)
/// ```
///
/// Source: KK (`h` coupling), DBB `y^h_12`. No radius dependence: the Faxen Laplacian
/// at a acts on the harmonic rotlet. The antisymmetric part `eps_qmp/r^3` of the rotlet
/// gradient drops out of the symmetrisation. Traceless in `pq`. Reciprocal of [`os`].
pub fn el(r: [f64; 3], aa: f64, ab: f64, eta: f64) -> [[[f64; 3]; 3]; 3] {
    let _ = (aa, ab);
    let (e, ir) = unit(r);
    let yh = -1.5 * oseen(eta) * ir * ir * ir;
    from_fn(|p| from_fn(|q| from_fn(|m| yh * (e[p] * eps_e(&e, q, m) + e[q] * eps_e(&e, p, m)))))
}

/// Rate of strain at sphere a due to a stresslet on sphere b, full Cartesian `ES[p][q][k][l]`
/// (strain `pq`, stresslet `kl`), exactly as defined (not projected).
///
/// ```text
/// ES_pqkl = x^m d0_pqkl + y^m d1_pqkl + z^m d2_pqkl
/// x^m = C (-6/r^3 + 36 s/(5 r^5)),  y^m = C (3/r^3 - 24 s/(5 r^5)),  z^m = C 6 s/(5 r^5),
/// s = aa^2 + ab^2
/// d0 = 3/2 (e_p e_q - delta_pq/3)(e_k e_l - delta_kl/3)
/// d1 = 1/2 (e_p delta_ql e_k + e_q delta_pl e_k + e_p delta_qk e_l + e_q delta_pk e_l
///           - 4 e_p e_q e_k e_l)
/// d2 = 1/2 (delta_pk delta_ql + delta_qk delta_pl - delta_pq delta_kl
///           + e_p e_q delta_kl + delta_pq e_k e_l
///           - e_p delta_ql e_k - e_q delta_pl e_k - e_p delta_qk e_l - e_q delta_pk e_l
///           + e_p e_q e_k e_l)
/// ```
///
/// Source: DBB `m` coupling (`x^m_12`, `y^m_12`, `z^m_12`; equal radii `s = 2 a^2`), KK
/// and the KK basis `d0, d1, d2` of symmetric-traceless fourth-rank tensors. Unequal radii:
/// both Faxen factors are `(1 + a^2/10 Lap)`, the symmetric gradient of `W` is biharmonic,
/// so only `(aa^2 + ab^2)/10` appears; `Lap` of it is `2 C d/dr_p d/dr_q d/dr_k d/dr_l (1/r)`.
///
/// Trace parts: none. `ES_ppkl = 0` (strain of a divergence-free field) and `ES_pqkk = 0`
/// (`W_qkk = 0`), identically, so `ES` as defined lies entirely in the span of `d0, d1,
/// d2`; it is symmetric in `pq`, in `kl`, and under `(pq) <-> (kl)`. Expanded, its Cartesian
/// coefficients are: `delta_pq delta_kl`: `C (-1/r^3 + 3 s/(5 r^5))`; `delta_pk delta_ql +
/// delta_pl delta_qk`: `C 3 s/(5 r^5)`; `delta_kl e_p e_q + delta_pq e_k e_l`: `C (3/r^3 - 3
/// s/r^5)`; the four `delta e e` terms of `d1`: `C (3/(2 r^3) - 3 s/r^5)`; `e_p e_q e_k e_l`:
/// `C (-15/r^3 + 21 s/r^5)`.
pub fn es(r: [f64; 3], aa: f64, ab: f64, eta: f64) -> [[[[f64; 3]; 3]; 3]; 3] {
    let (e, ir) = unit(r);
    let c3 = oseen(eta) * ir * ir * ir;
    let s = ratio2(aa, ir) + ratio2(ab, ir);
    let xm = c3 * (-6.0 + 7.2 * s);
    let ym = c3 * (3.0 - 4.8 * s);
    let zm = c3 * 1.2 * s;
    from_fn(|p| {
        from_fn(|q| {
            from_fn(|k| {
                from_fn(|l| {
                    let epq = e[p] * e[q];
                    let ekl = e[k] * e[l];
                    let e4 = epq * ekl;
                    let four = delta(p, l) * e[q] * e[k]
                        + delta(q, l) * e[p] * e[k]
                        + delta(p, k) * e[q] * e[l]
                        + delta(q, k) * e[p] * e[l];
                    let d0 = 1.5 * (epq - delta(p, q) / 3.0) * (ekl - delta(k, l) / 3.0);
                    let d1 = 0.5 * (four - 4.0 * e4);
                    let d2 = 0.5
                        * (delta(p, k) * delta(q, l) + delta(q, k) * delta(p, l)
                            - delta(p, q) * delta(k, l)
                            + epq * delta(k, l)
                            + delta(p, q) * ekl
                            - four
                            + e4);
                    xm * d0 + ym * d1 + zm * d2
                })
            })
        })
    })
}
