//! Free space, the real part of Beenakker's Ewald split (J. Chem. Phys. 85, 1581, 1986):
//! the Stokeslet `J = (delta lap - d d) r` with `r = r erfc(xi r) + r erf(xi r)`, of
//! which this Green's function is the screened first part,
//! `J^R = (delta lap - d d)[r erfc(xi r)]`, `xi = 1/sigma`. It is a building block of the
//! triply periodic sum (summed over the images within a cut-off), not a confinement.
//!
//! For a radial `F(r)`, `(delta lap - d d) F = (F'' + F'/r) delta - (F'' - F'/r) rhat rhat`;
//! with `E = erfc(xi r)` and `e = exp(-xi^2 r^2)/sqrt(pi)`,
//! `J^R = A delta + B rhat rhat`, `A = E/r + (4 xi^3 r^2 - 6 xi) e`,
//! `B = E/r + (2 xi - 4 xi^3 r^2) e` ([`Green::full`], in closed form: the generic path's,
//! the tests' reference). The pair kernels take the structured path with the radial
//! potential `r erfc(xi r)` and its Laplacians in closed form ([`screened_laplacian`],
//! [`Green::radial`]; docs/generator.md, "Radial potentials"): `J^R` itself, never
//! `J + (J^R - J)`, which would cancel to `eps J` where `J^R` is small.
//!
//! The reflected field is `W = J^R - J = -(delta lap - d d)[r erf(xi r)]`, entire, with
//! `W(0) = -8 xi/sqrt(pi) I`: the self kernel is the isolated sphere plus the operators
//! applied to `W` at `r = 0`. `W` is written as the power series of `F = r erf(xi r)`
//! in `s = r.r`, `F = (2/sqrt(pi)) sum_n (-1)^n xi^(2n+1) s^(n+1) / (n! (2n+1))`
//! (no square root, so its jets exist at `r = 0`): with `F'`, `F''` the derivatives in
//! `s`, `(delta lap - d d) F = (4 F' + 4 s F'') delta - 4 r r F''`. The series keeps
//! [`SERIES_TERMS`] terms (`F` to `s^6`), so `W` is exact in every derivative up to order
//! 11 at `r = 0` (the FTS blocks need 6; the jets drop the orders above theirs at no
//! cost) and an approximation away from it, where nothing evaluates it: the self kernels
//! take it by the generic path.

use super::{Dimension, Green, ImageTerm, Mat3, Param};
use crate::number::dd::Dd;
use crate::number::scalar::Scalar;

/// The real part of the Ewald split of free space.
pub struct EwaldReal;

/// The screening length of the split, a parameter of every Ewald building block.
pub const SIGMA: Param = Param {
    name: "sigma",
    doc: "screening length sigma = 1/xi of the Ewald split (the real part decays like exp(-r^2/sigma^2))",
    dimension: Dimension::Length,
    default: None,
    example: 1.3,
};

/// Terms kept in the series of `r erf(xi r)` in `s = r.r` (up to `s^SERIES_TERMS`).
pub const SERIES_TERMS: usize = 6;

/// `r = x - y` and `s = r.r`.
pub(crate) fn separation<S: Scalar>(x: &[S; 3], y: &[S; 3]) -> ([S; 3], S) {
    let r: [S; 3] = std::array::from_fn(|k| x[k].clone() - y[k].clone());
    let s = r[0].clone() * r[0].clone() + r[1].clone() * r[1].clone() + r[2].clone() * r[2].clone();
    (r, s)
}

/// `a delta_ij + b r_i r_j`, each of the six distinct entries formed once (on jets,
/// `(b r_i) r_j` and `(b r_j) r_i` would be different nodes).
fn isotropic_plus_dyad<S: Scalar>(a: &S, b: &S, r: &[S; 3]) -> Mat3<S> {
    let br: [S; 3] = std::array::from_fn(|i| b.clone() * r[i].clone());
    let entry = |i: usize, j: usize| -> S {
        let d = br[i].clone() * r[j].clone();
        if i == j {
            a.clone() + d
        } else {
            d
        }
    };
    let upper: [[Option<S>; 3]; 3] =
        std::array::from_fn(|i| std::array::from_fn(|j| (i <= j).then(|| entry(i, j))));
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let (p, q) = if i <= j { (i, j) } else { (j, i) };
            upper[p][q].clone().expect("upper triangle")
        })
    })
}

/// `J^R(r)` in closed form, `xi = 1/sigma` (module documentation).
pub fn screened<S: Scalar>(r: &[S; 3], s: &S, sigma: &S) -> Mat3<S> {
    let xi = sigma.recip();
    let rr = s.sqrt();
    let inv_r = rr.recip();
    let xr = xi.clone() * rr;
    let big_e = xr.erfc() * inv_r.clone();
    // the exponential of erfc's own jet rule, `exp(-(xi r)(xi r))`: one node
    let e = (-(xr.clone() * xr)).exp() * S::from_dd(Dd::two_over_sqrt_pi() * Dd::new(0.5));
    let xi3r2 = S::cst(4.0) * xi.clone() * xi.clone() * xi.clone() * s.clone();
    let a = big_e.clone() + (xi3r2.clone() - S::cst(6.0) * xi.clone()) * e.clone();
    let b = big_e + (S::cst(2.0) * xi - xi3r2) * e;
    let b = b * inv_r.clone() * inv_r;
    isotropic_plus_dyad(&a, &b, r)
}

/// `lap^m [r erfc(xi r)]` as a function of `s = r.r`, in closed form, `xi = 1/sigma`
/// (with `E = erfc(xi r)`, `e = exp(-xi^2 s)/sqrt(pi)`): `r E`, then
/// `2 E/r + (4 xi^3 s - 8 xi) e`, then for `m >= 2` the Gaussian times a polynomial,
/// `xi^(2m - 1) Q_m(xi^2 s) e`, `Q_2 = 80 - 88 u + 16 u^2` and, from
/// `lap f(s) = 4 s f'' + 6 f'`, `Q_{m+1} = 4 u (Q_m'' - 2 Q_m' + Q_m) + 6 (Q_m' - Q_m)`
/// (integer coefficients, exact in `f64`). The radial potential of the screened kernels
/// ([`Green::radial`]): every `lap^m` with `m >= 2` is entire and of order `xi^(2m - 1)`,
/// where the derivatives of `r E` it is made of are of order `r^(1 - 2m)`. The Gaussian
/// is `erfc`'s own (`exp(-(xi r)(xi r))`), one node with the one inside `erfc`'s jet rule.
pub fn screened_laplacian<S: Scalar>(m: u8, s: &S, sigma: &S) -> S {
    let xi = sigma.recip();
    let r = s.sqrt();
    let xr = xi.clone() * r.clone();
    let u = xr.clone() * xr.clone();
    let e = (-u.clone()).exp() * S::from_dd(Dd::two_over_sqrt_pi() * Dd::new(0.5));
    match m {
        0 => r * xr.erfc(),
        1 => {
            let c = S::cst;
            c(2.0) * xr.erfc() * r.recip() + (c(4.0) * u - c(8.0)) * xi * e
        }
        _ => {
            // Q_m by the recurrence, lowest power first
            let mut q: Vec<f64> = vec![80.0, -88.0, 16.0];
            for _ in 2..m {
                let d1: Vec<f64> = (1..q.len()).map(|k| k as f64 * q[k]).collect();
                let d2: Vec<f64> = (1..d1.len()).map(|k| k as f64 * d1[k]).collect();
                let at = |v: &[f64], k: usize| v.get(k).copied().unwrap_or(0.0);
                q = (0..=q.len())
                    .map(|k| {
                        let inner = |k: usize| at(&d2, k) - 2.0 * at(&d1, k) + at(&q, k);
                        let shifted = if k == 0 { 0.0 } else { 4.0 * inner(k - 1) };
                        shifted + 6.0 * (at(&d1, k) - at(&q, k))
                    })
                    .collect();
            }
            let poly = q
                .iter()
                .rev()
                .fold(S::cst(0.0), |acc, &c| acc * u.clone() + S::cst(c));
            let xi_power = (1..2 * m - 1).fold(xi.clone(), |a, _| a * xi.clone());
            xi_power * poly * e
        }
    }
}

/// `W = J^R - J` from the power series of `r erf(xi r)` in `s` (module documentation).
pub fn reflected_series<S: Scalar>(r: &[S; 3], s: &S, sigma: &S) -> Mat3<S> {
    let xi = sigma.recip();
    let xi2 = xi.clone() * xi.clone();
    // F = sum_n f_n s^(n+1), f_n = (2/sqrt(pi)) (-1)^n xi^(2n+1) / (n! (2n+1));
    // F' = sum_n (n+1) f_n s^n, F'' = sum_n (n+1) n f_n s^(n-1)
    let mut weight = Dd::two_over_sqrt_pi();
    let mut xi_power = xi;
    let mut f1: Option<S> = None;
    let mut f2: Option<S> = None;
    let mut s_power = S::cst(1.0);
    let mut s_before = S::cst(0.0);
    for n in 0..SERIES_TERMS {
        if n > 0 {
            weight = -weight / Dd::new(n as f64);
            xi_power = xi_power * xi2.clone();
            s_before = s_power.clone();
            s_power = s_power * s.clone();
        }
        let f = S::from_dd(weight / Dd::new((2 * n + 1) as f64)) * xi_power.clone();
        let t1 = S::cst((n + 1) as f64) * f.clone() * s_power.clone();
        f1 = Some(match f1 {
            None => t1,
            Some(v) => v + t1,
        });
        if n > 0 {
            let t2 = S::cst(((n + 1) * n) as f64) * f * s_before.clone();
            f2 = Some(match f2 {
                None => t2,
                Some(v) => v + t2,
            });
        }
    }
    let (f1, f2) = (f1.expect("a term"), f2.expect("two terms"));
    let four = S::cst(4.0);
    let a = -(four.clone() * f1 + four.clone() * s.clone() * f2.clone());
    let b = four * f2;
    isotropic_plus_dyad(&a, &b, r)
}

impl Green for EwaldReal {
    fn name(&self) -> &'static str {
        "ewald_real"
    }
    fn title(&self) -> &'static str {
        "free space, the real part of Beenakker's Ewald split: (delta lap - d d)[r erfc(r/sigma)]"
    }
    fn params(&self) -> &'static [Param] {
        &[SIGMA]
    }
    fn full<S: Scalar>(&self, x: &[S; 3], y: &[S; 3], p: &[S]) -> Mat3<S> {
        let (r, s) = separation(x, y);
        screened(&r, &s, &p[0])
    }
    fn reflected<S: Scalar>(&self, x: &[S; 3], y: &[S; 3], p: &[S]) -> Mat3<S> {
        let (r, s) = separation(x, y);
        reflected_series(&r, &s, &p[0])
    }
    /// The free kernel alone, no image.
    fn image_terms(&self) -> Option<Vec<ImageTerm>> {
        Some(Vec::new())
    }
    fn radial<S: Scalar>(&self, m: u8, s: &S, p: &[S]) -> Option<S> {
        Some(screened_laplacian(m, s, &p[0]))
    }
    fn axisymmetric(&self) -> bool {
        true
    }
    fn translation_invariant(&self) -> bool {
        true
    }
}
