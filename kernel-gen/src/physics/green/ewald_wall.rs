//! A plane no-slip wall, the real part of the Ewald split of Blake's image system: every
//! Stokeslet of the wall's Green's function (the direct one and the three image terms of
//! Eq. 5) replaced by the screened real part of Beenakker's split ([`super::ewald`]),
//!
//! `G^R(x, y) = J^R(r) - J^R(R) + h^2 P . lap J^R(R) - 2 h (P . grad J^R(R) . e3)^T`,
//!
//! `r = x - y`, `R = x - y'`, `y' = y - 2 h e3`, `h = y3 - H`, `P = diag(1, 1, -1)`. Every
//! term decays like `exp(-xi^2 |r|^2)` or `exp(-xi^2 |R|^2)`, `|R| >= |r|` on the fluid
//! side: a building block of the mobility of spheres above a wall in a box periodic along
//! the wall (summed over the lateral images within a cut-off; the smooth remainder, the
//! same image system with `J^K = J - J^R`, goes to the solver's reciprocal sum).
//!
//! For `J^R = A delta + b r r` (`b = B/r^2`, `A`, `B` of [`super::ewald`]), with
//! `E = erfc(xi r)` and `e = exp(-xi^2 r^2)/sqrt(pi)`:
//!
//! - `d_k J^R_ij = alpha r_k delta_ij + beta r_i r_j r_k + b (delta_ik r_j + delta_jk r_i)`,
//!   `alpha = A'/r = -E/r^3 + (-2 xi/r^2 + 20 xi^3 - 8 xi^5 r^2) e`,
//!   `beta = (B/r^2)'/r = -3 E/r^5 + (-6 xi/r^4 - 4 xi^3/r^2 + 8 xi^5) e`;
//! - `lap J^R = (delta lap - d d) g`, `g = lap(r erfc(xi r)) = 2 E/r + (4 xi^3 r^2 - 8 xi) e`,
//!   so `lap J^R = (lap g - g'/r) delta + (3 g'/r - lap g) r r / r^2` with
//!   `g'/r = -2 E/r^3 + (-4 xi/r^2 + 24 xi^3 - 8 xi^5 r^2) e` and
//!   `lap g = xi^3 (80 - 88 xi^2 r^2 + 16 xi^4 r^4) e`.
//!
//! As `xi -> 0` these tend to the Stokeslet's gradient and Laplacian (the unit tests check
//! them against finite differences of `J^R`). They make [`Green::full`], the generic
//! path's closed form (the tests' reference); the pair kernels take the structured path,
//! declared as what the Green's function is made of: the wall's image terms
//! ([`blake_terms`], Eq. 10 with the explicit heights) and the screened radial potential
//! of [`super::ewald`] ([`screened_laplacian`]).
//!
//! Self kernels take the reflected field `G^R - J = W(r) + ` the screened image, `W = J^R -
//! J` as the power series of [`super::ewald`] (exact at `r = 0`), the image in closed form
//! at `R = 2 h e3`.

use super::ewald::{reflected_series, screened, screened_laplacian, separation, SIGMA};
use super::wall::{blake_terms, image_system, WithDerivatives};
use super::{Green, ImageTerm, Mat3, Param, Plane};
use crate::number::dd::Dd;
use crate::number::scalar::Scalar;

/// The real part of the Ewald split of the wall's Green's function.
pub struct EwaldWall;

/// `J^R`, its gradient (indexed `[k][i][j]`) and its Laplacian at `r` (module
/// documentation), `xi = 1/sigma`.
pub fn screened_with_derivatives<S: Scalar>(r: &[S; 3], sigma: &S) -> WithDerivatives<S> {
    let s = r[0].clone() * r[0].clone() + r[1].clone() * r[1].clone() + r[2].clone() * r[2].clone();
    let j = screened(r, &s, sigma);
    let xi = sigma.recip();
    let xi2 = xi.clone() * xi.clone();
    let xi3 = xi2.clone() * xi.clone();
    let xi5 = xi3.clone() * xi2.clone();
    let rr = s.sqrt();
    let inv_r = rr.recip();
    let inv_r2 = inv_r.clone() * inv_r.clone();
    let xr = xi.clone() * rr;
    let big_e = xr.erfc();
    let e = (-(xr.clone() * xr)).exp() * S::from_dd(Dd::two_over_sqrt_pi() * Dd::new(0.5));
    let c = S::cst;
    // E/r^3, and the B of `J^R = A delta + B r r / r^2` (as in `screened`)
    let e_r3 = big_e.clone() * inv_r2.clone() * inv_r.clone();
    let b_over_r2 = (big_e.clone() * inv_r.clone()
        + (c(2.0) * xi.clone() - c(4.0) * xi3.clone() * s.clone()) * e.clone())
        * inv_r2.clone();
    let alpha = -e_r3.clone()
        + (c(-2.0) * xi.clone() * inv_r2.clone() + c(20.0) * xi3.clone()
            - c(8.0) * xi5.clone() * s.clone())
            * e.clone();
    let beta = c(-3.0) * e_r3.clone() * inv_r2.clone()
        + (c(-6.0) * xi.clone() * inv_r2.clone() * inv_r2.clone()
            - c(4.0) * xi3.clone() * inv_r2.clone()
            + c(8.0) * xi5.clone())
            * e.clone();
    let g1_r = c(-2.0) * e_r3
        + (c(-4.0) * xi * inv_r2.clone() + c(24.0) * xi3.clone() - c(8.0) * xi5 * s.clone())
            * e.clone();
    let lap_g = xi3
        * (c(80.0) - c(88.0) * xi2.clone() * s.clone()
            + c(16.0) * xi2.clone() * xi2 * s.clone() * s)
        * e;
    let iso = lap_g.clone() - g1_r.clone();
    let dyad = (c(3.0) * g1_r - lap_g) * inv_r2;
    let delta = |i: usize, j: usize| i == j;
    let gradient: [Mat3<S>; 3] = std::array::from_fn(|k| {
        std::array::from_fn(|i| {
            std::array::from_fn(|l| {
                let mut v = beta.clone() * r[i].clone() * r[l].clone() * r[k].clone();
                if delta(i, l) {
                    v = v + alpha.clone() * r[k].clone();
                }
                if delta(i, k) {
                    v = v + b_over_r2.clone() * r[l].clone();
                }
                if delta(l, k) {
                    v = v + b_over_r2.clone() * r[i].clone();
                }
                v
            })
        })
    });
    let laplacian: Mat3<S> = std::array::from_fn(|i| {
        std::array::from_fn(|l| {
            let v = dyad.clone() * r[i].clone() * r[l].clone();
            if delta(i, l) {
                iso.clone() + v
            } else {
                v
            }
        })
    });
    (j, gradient, laplacian)
}

/// The screened image system about `x3 = height` (module documentation).
fn screened_image<S: Scalar>(x: &[S; 3], y: &[S; 3], height: &S, sigma: &S) -> Mat3<S> {
    image_system(x, y, height, |r| screened_with_derivatives(r, sigma))
}

impl Green for EwaldWall {
    fn name(&self) -> &'static str {
        "ewald_wall"
    }
    fn title(&self) -> &'static str {
        "plane no-slip wall at x3 = height, the real part of the Ewald split of Blake's image system (every Stokeslet screened by erfc(r/sigma))"
    }
    fn params(&self) -> &'static [Param] {
        &[Param::HEIGHT, SIGMA]
    }
    fn full<S: Scalar>(&self, x: &[S; 3], y: &[S; 3], p: &[S]) -> Mat3<S> {
        let (r, s) = separation(x, y);
        let direct = screened(&r, &s, &p[1]);
        let image = screened_image(x, y, &p[0], &p[1]);
        std::array::from_fn(|i| std::array::from_fn(|l| direct[i][l].clone() + image[i][l].clone()))
    }
    fn reflected<S: Scalar>(&self, x: &[S; 3], y: &[S; 3], p: &[S]) -> Mat3<S> {
        let (r, s) = separation(x, y);
        let w = reflected_series(&r, &s, &p[1]);
        let image = screened_image(x, y, &p[0], &p[1]);
        std::array::from_fn(|i| std::array::from_fn(|l| w[i][l].clone() + image[i][l].clone()))
    }
    /// Blake's image system, every Stokeslet screened: the wall's terms
    /// ([`blake_terms`]) made of the screened kernel ([`Green::radial`]).
    fn image_terms(&self) -> Option<Vec<ImageTerm>> {
        Some(blake_terms(0, 0))
    }
    fn radial<S: Scalar>(&self, m: u8, s: &S, p: &[S]) -> Option<S> {
        Some(screened_laplacian(m, s, &p[1]))
    }
    fn mirrors<S: Scalar>(&self, p: &[S]) -> Vec<Plane<S>> {
        vec![Plane::horizontal(p[0].clone())]
    }
    fn axisymmetric(&self) -> bool {
        true
    }
}
