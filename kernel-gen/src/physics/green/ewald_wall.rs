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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::{evaluate_direct, trace, Interaction, KernelSpec, Path};
    use crate::physics::green::wall::Wall;
    use crate::physics::operators::{moment_dim, response_dim, Basis, Moment, Response};

    const FT: [(Response, Moment); 4] = [
        (Response::U, Moment::F),
        (Response::U, Moment::L),
        (Response::Omega, Moment::F),
        (Response::Omega, Moment::L),
    ];

    fn spec(interaction: Interaction) -> KernelSpec {
        KernelSpec {
            interaction,
            basis: Basis::Orthonormal,
            equal_radii: false,
            blocks: FT.to_vec(),
            path: Path::Structured,
            product: false,
            drift: None,
        }
    }

    /// The largest entry of each FT block of `v`, repeated for each of its entries.
    fn block_scales(v: &[Dd]) -> Vec<f64> {
        let mut out = Vec::new();
        let mut at = 0;
        for &(r, m) in &FT {
            let n = response_dim(r, Basis::Orthonormal) * moment_dim(m, Basis::Orthonormal);
            let scale = v[at..at + n]
                .iter()
                .map(|x| x.to_f64().abs())
                .fold(0.0, f64::max);
            out.extend(std::iter::repeat_n(scale, n));
            at += n;
        }
        out
    }

    /// The gradient and Laplacian of `J^R` against central differences of [`screened`] in
    /// double-double (step `1e-6`: truncation about `1e-12` of the third derivatives,
    /// round-off `1e-32/1e-12`), to 1e-9 of the largest entry, at `xi r` from 0.3 to 4.
    #[test]
    fn derivatives_equal_finite_differences() {
        let sigma = Dd::new(1.3);
        let h = Dd::new(1e-6);
        let at = |r: [Dd; 3]| {
            let s = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
            screened(&r, &s, &sigma)
        };
        for r in [[0.3, -0.2, 0.1], [1.1, 0.7, -0.4], [2.0, -3.0, 3.5]] {
            let r = r.map(Dd::new);
            let (_, grad, lap) = screened_with_derivatives(&r, &sigma);
            let shifted = |k: usize, t: Dd| {
                let mut q = r;
                q[k] = q[k] + t;
                at(q)
            };
            let mut fd_grad = [[[Dd::new(0.0); 3]; 3]; 3];
            let mut fd_lap = [[Dd::new(0.0); 3]; 3];
            let centre = at(r);
            for (k, fd_k) in fd_grad.iter_mut().enumerate() {
                let (p, m) = (shifted(k, h), shifted(k, -h));
                for i in 0..3 {
                    for l in 0..3 {
                        fd_k[i][l] = (p[i][l] - m[i][l]) / (Dd::new(2.0) * h);
                        fd_lap[i][l] = fd_lap[i][l]
                            + (p[i][l] - Dd::new(2.0) * centre[i][l] + m[i][l]) / (h * h);
                    }
                }
            }
            let scale = |m: &[Mat3<Dd>]| {
                m.iter()
                    .flatten()
                    .flatten()
                    .map(|v| v.to_f64().abs())
                    .fold(0.0, f64::max)
            };
            let (sg, sl) = (scale(&grad), scale(std::slice::from_ref(&lap)));
            for k in 0..3 {
                for i in 0..3 {
                    for l in 0..3 {
                        let e = (grad[k][i][l] - fd_grad[k][i][l]).to_f64().abs();
                        assert!(e < 1e-9 * sg, "d{k} J{i}{l} at {r:?}: {e:e}");
                    }
                }
            }
            for i in 0..3 {
                for l in 0..3 {
                    let e = (lap[i][l] - fd_lap[i][l]).to_f64().abs();
                    assert!(e < 1e-6 * sl, "lap J{i}{l} at {r:?}: {e:e}");
                }
            }
        }
    }

    /// The structured path (Blake's image terms by Eq. 10, made of the atoms of the
    /// screened potential) against the generic six-variable jets of the closed form
    /// [`Green::full`], every derivative to order 4 (the FT pair kernels'; the image terms
    /// add 2 more to the potential's), in double-double, pairs from near the wall to
    /// `xi |R|` of 5: to 1e-24 of the largest derivative of its order (round-off of about
    /// 1e-31 of the terms, which exceed the result where `J^R(r)` and the screened
    /// image cancel).
    #[test]
    fn structured_terms_equal_the_generic_jets() {
        use crate::physics::derivatives::path_differences;
        let p = [Dd::new(0.3), Dd::new(1.3)];
        for (x, y) in [
            ([0.1, -0.2, 1.5], [0.4, 0.1, 1.8]),
            ([0.1, -0.2, 0.5], [1.6, -1.1, 0.4]),
            ([3.0, -2.0, 1.6], [-1.0, 2.5, 4.1]),
        ] {
            let (x, y) = (x.map(Dd::new), y.map(Dd::new));
            for (n, err, scale) in path_differences(&EwaldWall, &x, &y, &p, 4) {
                assert!(
                    err < 1e-24 * scale,
                    "order {n} at {x:?}, {y:?}: {err:e} of {scale:e}"
                );
            }
        }
    }

    /// Inputs of the pair kernel: `xa, xb, aa, ab, eta, height, sigma`.
    fn pair_inputs(xa: [f64; 3], xb: [f64; 3], height: f64, sigma: f64) -> Vec<f64> {
        let mut v = xa.to_vec();
        v.extend(xb);
        v.extend([1.0, 0.6, 0.8, height, sigma]);
        v
    }

    /// The traced FT pair kernel (canonical frame, lowered `exp` and `erfc`, `f64`) against
    /// the direct sum in double-double by the generic jets of the closed form, pairs at heights 1.2 to 5 above the wall, lateral
    /// distances up to `5 sigma`, every block to 1e-12 of its largest entry (the lowered
    /// functions are good to 5e-15 relative; the image terms add `h^2 lap J^R(R)`, of up
    /// to `(h/R)^2` times the terms they partly cancel, and the jets sum a few hundred
    /// terms of mixed signs).
    #[test]
    fn pair_kernel_equals_the_direct_sum_in_double_double() {
        let (height, sigma) = (0.3, 1.3);
        let traced = trace(&EwaldWall, &spec(Interaction::Pair));
        for (xa, xb) in [
            ([0.1, -0.2, 1.5], [0.4, 0.1, 1.8]),
            ([0.1, -0.2, 2.3], [1.6, -1.1, 1.5]),
            ([-1.0, 0.5, 5.3], [1.5, 2.0, 3.0]),
            ([3.0, -2.0, 1.6], [-1.0, 2.5, 4.1]),
        ] {
            let inputs = pair_inputs(xa, xb, height, sigma);
            let got = traced.eval(&inputs);
            let dd: Vec<Dd> = inputs.iter().map(|&v| Dd::new(v)).collect();
            let generic = KernelSpec {
                path: Path::Generic,
                ..spec(Interaction::Pair)
            };
            let want = evaluate_direct(&EwaldWall, &generic, &dd);
            for ((g, w), s) in got.iter().zip(&want).zip(block_scales(&want)) {
                let err = (Dd::new(*g) - *w).to_f64().abs();
                assert!(err <= 1e-12 * s, "{xa:?} {xb:?}: {g:e} vs {w:?}");
            }
        }
    }

    /// As `xi -> 0` the screened image system is Blake's: `J^R - J = W = -8 xi/sqrt(pi) I +
    /// O(xi^3)`, and the image of the constant `-8 xi/sqrt(pi) I` is its opposite (Eq. 5:
    /// `-W(R)`, derivatives of `W` are `O(xi^3)`), so the pair and self FT blocks differ
    /// from the wall's (the structured path: an independent evaluation) by `O(xi^3 (r^2 +
    /// h^2 + a^2) / (8 pi eta))`, about 1e-12 at `xi = 1e-4` with lengths of order 1: here
    /// to 1e-10 absolute (the smallest blocks, the self rotation-translation coupling, are
    /// of order 1e-3; a wrong image term is off by a fraction of the block).
    #[test]
    fn the_real_part_tends_to_the_wall() {
        let (height, sigma) = (0.3, 1e4);
        let (xa, xb) = ([0.1, -0.2, 2.3], [1.6, -1.1, 1.5]);
        let dd = |v: Vec<f64>| v.into_iter().map(Dd::new).collect::<Vec<_>>();
        let sp = spec(Interaction::Pair);
        let ewald = evaluate_direct(&EwaldWall, &sp, &dd(pair_inputs(xa, xb, height, sigma)));
        let mut wall_inputs = pair_inputs(xa, xb, height, sigma);
        wall_inputs.pop();
        let wall = evaluate_direct(&Wall, &sp, &dd(wall_inputs));
        for (e, w) in ewald.iter().zip(&wall) {
            assert!((*e - *w).to_f64().abs() < 1e-10, "pair: {e:?} vs {w:?}");
        }
        let sp = spec(Interaction::SelfTerm);
        let x = [0.1, -0.2, 1.7];
        let self_inputs = |with_sigma: bool| {
            let mut v = x.to_vec();
            v.extend([0.9, 0.8, height]);
            if with_sigma {
                v.push(sigma);
            }
            dd(v)
        };
        let ewald = evaluate_direct(&EwaldWall, &sp, &self_inputs(true));
        let wall = evaluate_direct(&Wall, &sp, &self_inputs(false));
        for (e, w) in ewald.iter().zip(&wall) {
            assert!((*e - *w).to_f64().abs() < 1e-10, "self: {e:?} vs {w:?}");
        }
    }

    /// The traced self kernel (`f64`) against the direct sum in double-double, to 1e-13 of
    /// each block's largest entry (the isolated sphere dominates; the reflected terms are
    /// a few hundred products).
    #[test]
    fn self_kernel_equals_the_direct_sum_in_double_double() {
        let sp = spec(Interaction::SelfTerm);
        let traced = trace(&EwaldWall, &sp);
        for (z, sigma) in [(1.2, 1.3), (2.5, 0.7), (4.0, 2.0)] {
            let inputs = vec![0.3, -0.1, z, 0.9, 0.8, 0.3, sigma];
            let got = traced.eval(&inputs);
            let dd: Vec<Dd> = inputs.iter().map(|&v| Dd::new(v)).collect();
            let want = evaluate_direct(&EwaldWall, &sp, &dd);
            for ((g, w), s) in got.iter().zip(&want).zip(block_scales(&want)) {
                let err = (Dd::new(*g) - *w).to_f64().abs();
                assert!(err <= 1e-13 * s, "z {z}: {g:e} vs {w:?}");
            }
        }
    }
}
