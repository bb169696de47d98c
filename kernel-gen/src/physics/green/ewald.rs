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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::{evaluate_direct, trace, Interaction, KernelSpec, Path};
    use crate::physics::derivatives::path_differences;
    use crate::physics::green::free::Free;
    use crate::physics::green::stokeslet;
    use crate::physics::operators::{Basis, Moment, Response, BLOCKS};

    fn spec(interaction: Interaction, blocks: &[(Response, Moment)]) -> KernelSpec {
        KernelSpec {
            interaction,
            basis: Basis::Orthonormal,
            equal_radii: false,
            blocks: blocks.to_vec(),
            path: Path::Structured,
            product: false,
            drift: None,
        }
    }

    const FT: [(Response, Moment); 4] = [
        (Response::U, Moment::F),
        (Response::U, Moment::L),
        (Response::Omega, Moment::F),
        (Response::Omega, Moment::L),
    ];

    /// The blocks' sizes (entries per block) of `blocks`.
    fn sizes(blocks: &[(Response, Moment)]) -> Vec<usize> {
        use crate::physics::operators::{moment_dim, response_dim};
        blocks
            .iter()
            .map(|&(r, m)| response_dim(r, Basis::Orthonormal) * moment_dim(m, Basis::Orthonormal))
            .collect()
    }

    /// Every derivative `d_x^alpha d_y^beta J^R` up to order 4 from the generic path's
    /// jets in `r` alone (`d_y = -d_x`), in double-double, against finite differences of
    /// `J^R` in all six coordinates ([`crate::physics::fd`], `h = 1e-4`: truncation about
    /// `h^2` of the next derivatives, round-off `eps_dd / h^4`): 1e-6 of the largest
    /// derivative of the same order, at `xi r = 1.1` where `erfc` and the Gaussian are
    /// both of order 1.
    #[test]
    fn jets_in_r_equal_finite_differences_in_x_and_y() {
        use crate::physics::derivatives::{GenericJets, Part};
        use crate::physics::fd::FiniteDifferences;
        use crate::physics::operators::{Deriv, Derivatives};
        let (x, y, p) = ([0.3, -0.4, 0.9], [-0.5, 0.4, 0.1], [1.2]);
        let dd = |v: [f64; 3]| v.map(Dd::new);
        let mut jets =
            GenericJets::new(&EwaldReal, Part::Full, &dd(x), &dd(y), &[Dd::new(p[0])], 4);
        let mut fd = FiniteDifferences::new(&EwaldReal, Part::Full, x, y, &p, 1e-4);
        let l = crate::number::jet::Layout::get(6, 4);
        for order in 0..=4usize {
            let mut pairs = Vec::new();
            for m in l
                .monos
                .iter()
                .filter(|m| m.iter().map(|&e| e as usize).sum::<usize>() == order)
            {
                for i in 0..3 {
                    for j in 0..3 {
                        let d = Deriv {
                            i,
                            j,
                            dx: [m[0], m[1], m[2]],
                            dy: [m[3], m[4], m[5]],
                        };
                        pairs.push((jets.get(&d), fd.get(&d)));
                    }
                }
            }
            let scale = pairs
                .iter()
                .map(|(_, b)| b.to_f64().abs())
                .fold(0.0, f64::max);
            for (a, b) in pairs {
                assert!(
                    (a - b).to_f64().abs() < 1e-6 * scale,
                    "order {order}: {a:?} vs {b:?}"
                );
            }
        }
    }

    /// `(traced in f64, direct in double-double by the generic path)` of the pair kernel of `blocks`
    /// at separation `r` (field at the origin), radii 1 and 0.6, `eta = 0.8`, `sigma`.
    fn pair_values(blocks: &[(Response, Moment)], r: [f64; 3], sigma: f64) -> (Vec<f64>, Vec<Dd>) {
        let sp = spec(Interaction::Pair, blocks);
        let inputs = [
            0.1,
            -0.2,
            0.3,
            0.1 - r[0],
            -0.2 - r[1],
            0.3 - r[2],
            1.0,
            0.6,
            0.8,
            sigma,
        ];
        let traced = trace(&EwaldReal, &sp).eval(&inputs);
        let dd: Vec<Dd> = inputs.iter().map(|&v| Dd::new(v)).collect();
        // the reference: the generic jets of the closed form, not the kernels' path
        let generic = KernelSpec {
            path: Path::Generic,
            ..sp
        };
        (traced, evaluate_direct(&EwaldReal, &generic, &dd))
    }

    /// The traced FTS pair kernel (lowered `exp`, `erfc`, `f64`) against the direct sum in
    /// double-double, at `xi r` from 0.4 to 6 (where the real part has decayed to
    /// `1e-15` of `J`), every block to 1e-13 of its largest entry: the lowered functions
    /// are good to 5e-15 relative, and the jets' sums of a few hundred terms of mixed
    /// signs lose a few digits more; a wrong lowering is off by far more.
    #[test]
    fn pair_kernel_equals_the_direct_sum_in_double_double() {
        let sigma = 1.3;
        for r in [
            [0.4, 0.2, -0.3],
            [1.1, -0.9, 0.5],
            [2.0, 2.5, -1.5],
            [4.0, -5.0, 3.0],
        ] {
            let (got, want) = pair_values(&BLOCKS, r, sigma);
            let mut at = 0;
            for (b, n) in sizes(&BLOCKS).into_iter().enumerate() {
                let (g, w) = (&got[at..at + n], &want[at..at + n]);
                at += n;
                let scale = w.iter().map(|v| v.to_f64().abs()).fold(0.0, f64::max);
                for (x, y) in g.iter().zip(w) {
                    let err = (Dd::new(*x) - *y).to_f64().abs();
                    assert!(err <= 1e-13 * scale, "block {b} at {r:?}: {x:e} vs {y:?}");
                }
            }
        }
    }

    /// As `xi = 1/sigma -> 0`: `r erf(xi r) = (2/sqrt(pi))(xi r^2 - xi^3 r^4/3 + O(xi^5))`
    /// and `(delta lap - d d)` takes `r^2` to `4 delta`, `r^4` to `16 r^2 delta - 8 r r`,
    /// whose Laplacian is `80 delta`; so the UF pair block of the real part minus that of
    /// free space (the structured path, an independent evaluation of `J`), times
    /// `8 pi eta`, is `-8 xi/sqrt(pi) delta + (2 xi^3/(3 sqrt(pi))) [16 r^2 delta - 8 r r
    /// + 80 (a_a^2 + a_b^2)/6 delta] + O(xi^5)`, here to 1e-12 of its leading term (the
    /// `xi^3` term is 4e-8 of it at `xi = 1e-4`, the `xi^5` term 1e-16; the difference is
    /// formed in double-double). The other blocks differ from free space by `O(xi^3)`.
    #[test]
    fn the_real_part_tends_to_the_stokeslet() {
        let sigma = 1e4;
        let xi = 1.0 / sigma;
        let r = [1.1, -0.9, 0.5];
        let (_, ewald) = pair_values(&FT, r, sigma);
        let sp = spec(Interaction::Pair, &FT);
        let inputs = [
            0.1,
            -0.2,
            0.3,
            0.1 - r[0],
            -0.2 - r[1],
            0.3 - r[2],
            1.0,
            0.6,
            0.8,
        ];
        let dd: Vec<Dd> = inputs.iter().map(|&v| Dd::new(v)).collect();
        let free = evaluate_direct(&Free, &sp, &dd);
        let eight_pi_eta = 8.0 * std::f64::consts::PI * 0.8;
        let sqrt_pi = std::f64::consts::PI.sqrt();
        let w0 = -8.0 * xi / sqrt_pi;
        let r2: f64 = r.iter().map(|v| v * v).sum();
        let faxen = 80.0 * (1.0 + 0.36) / 6.0;
        for i in 0..3 {
            for j in 0..3 {
                let d = (ewald[3 * i + j] - free[3 * i + j]).to_f64() * eight_pi_eta;
                let delta = if i == j { 1.0 } else { 0.0 };
                let want = w0 * delta
                    + 2.0 * xi.powi(3) / (3.0 * sqrt_pi)
                        * ((16.0 * r2 + faxen) * delta - 8.0 * r[i] * r[j]);
                assert!(
                    (d - want).abs() < 1e-12 * w0.abs(),
                    "UF {i}{j}: {d:e} vs {want:e}"
                );
            }
        }
        let scale = free.iter().map(|v| v.to_f64().abs()).fold(0.0, f64::max);
        for (e, f) in ewald.iter().zip(&free).skip(9) {
            assert!((*e - *f).to_f64().abs() < 1e-10 * scale);
        }
    }

    /// The self blocks are the isolated sphere plus the operators on `W(0)`, against the
    /// closed forms in units of `1/(8 pi eta)` (Beenakker's, with the `a_a^2 a_b^2 lap^2`
    /// term of the workspace's Faxén product): UF
    /// `(-72 xi + 160 a^2 xi^3 - 168 a^4 xi^5)/(9 sqrt(pi)) I`, Omega-L
    /// `-40 xi^3/(3 sqrt(pi)) I`, Omega-F and U-L zero. The traced self kernel (f64)
    /// to 1e-14 of the isolated sphere: the terms are a handful of products.
    #[test]
    fn self_blocks_are_the_isolated_sphere_plus_w_at_zero() {
        let (a, eta, sigma) = (0.9, 0.8, 1.3);
        let xi = 1.0 / sigma;
        let sp = spec(Interaction::SelfTerm, &FT);
        let got = trace(&EwaldReal, &sp).eval(&[0.3, -0.1, 0.7, a, eta, sigma]);
        let pi = std::f64::consts::PI;
        let unit = 1.0 / (8.0 * pi * eta);
        let uf = 1.0 / (6.0 * pi * eta * a)
            + unit * (-72.0 * xi + 160.0 * a * a * xi.powi(3) - 168.0 * a.powi(4) * xi.powi(5))
                / (9.0 * pi.sqrt());
        let ol = 1.0 / (8.0 * pi * eta * a.powi(3)) - unit * 40.0 * xi.powi(3) / (3.0 * pi.sqrt());
        let blocks: Vec<&[f64]> = [0, 9, 18, 27].iter().map(|&k| &got[k..k + 9]).collect();
        for i in 0..3 {
            for j in 0..3 {
                let d = if i == j { 1.0 } else { 0.0 };
                let (uf_tol, ol_tol) = (1e-14 * uf.abs(), 1e-14 * ol.abs());
                assert!((blocks[0][3 * i + j] - d * uf).abs() < uf_tol, "UF {i}{j}");
                assert!((blocks[3][3 * i + j] - d * ol).abs() < ol_tol, "OL {i}{j}");
                assert!(blocks[1][3 * i + j].abs() < uf_tol, "UL {i}{j}");
                assert!(blocks[2][3 * i + j].abs() < uf_tol, "OF {i}{j}");
            }
        }
    }

    /// Each declared Laplacian of the screened potential against the Laplacian of the
    /// one before, `4 s f'' + 6 f'` from its jet in `s` (double-double), for `m` up to
    /// 5 (FTS wall kernels need 5), at `xi r` from 0.3 to 3: independent of the
    /// recurrence of `Q_m` and of the closed form of `lap (r E)`. Relative to
    /// `|4 s f''| + |6 f'|`, the size of the terms that cancel (up to `(xi r)^-6` times the
    /// result at `xi r = 0.3`): 1e-26.
    #[test]
    fn each_laplacian_is_the_laplacian_of_the_one_before() {
        use crate::number::jet::{Jet, Layout};
        let sigma = Dd::new(1.3);
        let l = Layout::get(1, 2);
        for xr in [0.3, 1.0, 3.0] {
            let s0 = Dd::new(xr * 1.3) * Dd::new(xr * 1.3);
            let x = Jet::variable(&l, 0, s0);
            for m in 0..5u8 {
                let f = screened_laplacian(m, &x, &Jet::constant(sigma));
                let (f1, f2) = (f.derivative(&[1]), f.derivative(&[2]));
                let want = screened_laplacian(m + 1, &s0, &sigma);
                let (a, b) = (Dd::new(4.0) * s0 * f2, Dd::new(6.0) * f1);
                let size = a.to_f64().abs() + b.to_f64().abs();
                let err = (a + b - want).to_f64().abs();
                assert!(
                    err < 1e-26 * size,
                    "m {m} at xi r {xr}: {err:e} of {size:e}"
                );
            }
        }
    }

    /// The structured path (the atoms of `lap^m [r erfc(xi r)]`, radial coefficients
    /// times universal polynomials in the unit vector) against the generic jets of the
    /// closed form `J^R` ([`Green::full`]), every derivative `d_x^alpha d_y^beta J^R` to
    /// order 6 (FTS pair kernels), in double-double, at `xi r` from 0.05 to 5: to 1e-24
    /// of the largest derivative of its order (both are exact up to round-off of about
    /// 1e-31 times the terms, which at order 6 and `xi r = 0.05` exceed the result by up
    /// to the `(xi r)^-7` of `lap^3 J^R` against `J^R`'s own sixth derivatives).
    #[test]
    fn structured_atoms_equal_the_generic_jets() {
        let sigma = 1.3;
        let dir = [0.48, -0.6, 0.64];
        for xr in [0.05, 0.7, 2.0, 5.0] {
            let x = [0.3, -0.4, 0.9].map(Dd::new);
            let y: [Dd; 3] = std::array::from_fn(|k| x[k] - Dd::new(xr * sigma * dir[k]));
            let p = [Dd::new(sigma)];
            for (n, err, scale) in path_differences(&EwaldReal, &x, &y, &p, 6) {
                assert!(
                    err < 1e-24 * scale,
                    "order {n} at xi r {xr}: {err:e} of {scale:e}"
                );
            }
        }
    }

    /// The series of `W` (the self kernels' reflected field) against the closed form
    /// `J^R - J` at `|r| = 0.0135 sigma`, in double-double: the first terms dropped are
    /// of order `(xi r)^12 W(0) / (6! 13)`, 2e-28 of `W(0)`, and `J^R - J` loses 2 of 32
    /// digits; so 1e-24 of `W(0)`.
    #[test]
    fn series_of_w_equals_the_closed_form_near_zero() {
        let sigma = Dd::new(1.3);
        let r = [0.008, -0.006, 0.009].map(Dd::new);
        let s = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
        let series = reflected_series(&r, &s, &sigma);
        let (jr, j) = (screened(&r, &s, &sigma), stokeslet(&r));
        let w0 = 8.0 / 1.3 / std::f64::consts::PI.sqrt();
        for i in 0..3 {
            for k in 0..3 {
                let err = (series[i][k] - (jr[i][k] - j[i][k])).to_f64().abs();
                assert!(err < 1e-24 * w0, "{i}{k}: {err:e}");
            }
        }
    }
}
