//! The Rotne-Prager-Yamakawa mobility of spheres above a plane no-slip wall in a box
//! periodic along the wall (x and y, lengths `Lx`, `Ly`, area `A = Lx Ly`): Blake's image
//! system summed over the lateral lattice by an Ewald split of every Stokeslet in it.
//!
//! Every block of the wall decays like `rho^-3` along the wall, so the lattice sum
//! converges, but slowly. Beenakker's split `J = J^R + J^K` (`J^R` screened by
//! `erfc(xi r)`, [`super::ewald`]) applied to the Stokeslet and to each of its image
//! terms (Eq. 5) gives
//!
//! - a **real part**, Blake's image system of `J^R` (the generated building block
//!   `kernels::generated::scene_ewald_wall_ft`), Gaussian in the distances to the source
//!   and to its image: summed over the lateral images within `r_c`;
//! - a **reciprocal part**, the same image system of the smooth `J^K`: the image is a
//!   source at `y' = y - 2 h e3` (`h` the source's height above the wall) with the
//!   Fourier symbol `Jhat^K(k) T(k, h)`,
//!   `T_ml = delta_ml (-1 - h^2 k^2 P_ll) - 2 i h P_ll k_l delta_m3`, `P = diag(1, 1, -1)`,
//!   next to the direct `Jhat^K(k) = phi(k) (I - khat khat)/(eta k^2)` (physical units,
//!   `phi` of [`super::ewald`]). The lateral wave vectors `k_par = 2 pi (n1/Lx, n2/Ly) != 0`
//!   are summed within `k_c`; the integral over `k_z` is a trapezoidal sum, that is the
//!   same sum in a box also periodic in `z`, of height `Lz' = h_a + h_b + D` for the pair:
//!   its copies along `z` are at least `D` from every field point, and a mode of lateral
//!   wave number `k_par` decays like `exp(-k_par |z|)` away from its sources, so the
//!   copies add about `(1 + K0 (h_a + h_b))^2 exp(-K0 D)` relative, `K0 = 2 pi / max(Lx,
//!   Ly)` (the image's symbol carries `h_b^2 k^2`): `D = (ln(100/tol) + 2 ln(1 + K0 (h_a +
//!   h_b)))/K0`. For the same reason `k_c = 2 xi sqrt(p^2 + 2 ln(1 + 2 xi p (h_a + h_b)))`,
//!   slightly above the triply periodic box's `2 xi p`;
//!   The operators act on the field point as `i k` and on the source as `d/dy`, which on
//!   the image is `-i (k1, k2, -k3)` plus `d/dh` on `T` (so the source's Faxén
//!   operator and rotlet see the image's explicit heights);
//! - the **mode `k_par = 0`** in closed form: the plane average of the whole lattice sum
//!   is that of one wall's Green's function, `8 pi min(h_a, h_b) (I - e3 e3)` per area in
//!   units of `1/(8 pi eta)` (a force sheet above a no-slip wall drives the plug flow
//!   `u = F min(z, h)/(eta A)`, which the wall's shear stress balances); minus the plane
//!   average of the real part, it leaves `(I - e3 e3) f/A` with
//!   `f = Psi(h_a - h_b) - Psi(h_a + h_b) + h_b^2 Psi''(h_a + h_b)`,
//!   `Psi(z) = -4 pi z erf(xi z) - 4 sqrt(pi) xi z^2 exp(-xi^2 z^2)` (even and entire).
//!   The blocks follow from the operators in `z` alone: `UF = (1 + a_a^2/6 d_a^2)(1 +
//!   a_b^2/6 d_b^2) f`, `OmegaF_mj = (1/2) eps_m3j d_a (1 + a_b^2/6 d_b^2) f`, `UL_ij =
//!   (1/2) eps_j3i d_b (1 + a_a^2/6 d_a^2) f`, `OmegaL = (1/4) d_a d_b f (I - e3 e3)`, with
//!   `d_a`, `d_b` the derivatives in `h_a`, `h_b`. Unlike a triply periodic box nothing is
//!   left out: a net lateral force drives a bounded plug flow.
//!
//! The self mobility is the generated self kernel (the isolated sphere, `W(0)` and the
//! screened image at `R = 2 h e3`), the real images `n != 0`, the reciprocal sum and the
//! mode `k_par = 0` at `(x, x)`.
//!
//! Truncation as in the triply periodic box: `p = xi r_c`, `p^2 = ln(1/tol) + 11.5`
//! ([`super::ewald::truncation_parameter`]), `k_c` and `D` as above; `xi = sqrt(pi/A)`.
//! Measured against the brute-force lattice sum and across `xi` a factor 6 apart
//! (`tests/tests/integration/periodic/wall.rs`), the blocks are good to the tolerance of
//! their largest entry.

use super::ewald::{functionals, levi_civita, truncation_parameter};
use crate::system::input::Particle;
use kernels::generated::scene_ewald_wall_drift::{
    ewald_wall_drift_pair_together, ewald_wall_drift_self_along,
};
use kernels::generated::scene_ewald_wall_ft::{ewald_wall_ft_pair, ewald_wall_ft_self};
use kernels::generated::scene_ewald_wall_fts::{ewald_wall_fts_pair, ewald_wall_fts_self};
use kernels::{BlocksFT, Grand, STRAIN_BASIS};
use nalgebra::SMatrix;
use rustfft::num_complex::Complex64;
use std::f64::consts::PI;
use std::ops::AddAssign;

/// The split and truncation of one box periodic along a wall, at one tolerance.
#[derive(Clone, Debug)]
pub struct WallEwald {
    /// `[Lx, Ly]`.
    pub lengths: [f64; 2],
    /// The wall's plane `x3 = height`.
    pub height: f64,
    /// The splitting parameter `xi` (inverse length).
    pub xi: f64,
    /// Real-space cut-off `r_c`.
    pub r_cut: f64,
    /// The tolerance.
    pub(crate) tolerance: f64,
    /// The lateral lattice vectors within `r_c + ` half the box's diagonal, nearest first.
    shifts: Vec<[f64; 2]>,
}

impl WallEwald {
    /// The split for a box of lateral `lengths` above the wall `x3 = height` at relative
    /// tolerance `tol` (of each block's largest pair entry), `xi` chosen (module docs) or
    /// given.
    pub fn new(lengths: [f64; 2], height: f64, tol: f64, xi: Option<f64>) -> WallEwald {
        let area = lengths[0] * lengths[1];
        let p = truncation_parameter(tol);
        let xi = xi.unwrap_or((PI / area).sqrt());
        let r_cut = p / xi;
        let reach = r_cut + 0.5 * (lengths[0].powi(2) + lengths[1].powi(2)).sqrt();
        let mmax: [i64; 2] = std::array::from_fn(|d| (reach / lengths[d]).ceil() as i64);
        let mut shifts = Vec::new();
        for m1 in -mmax[0]..=mmax[0] {
            for m2 in -mmax[1]..=mmax[1] {
                let s = [m1 as f64 * lengths[0], m2 as f64 * lengths[1]];
                if s[0] * s[0] + s[1] * s[1] <= reach * reach {
                    shifts.push(s);
                }
            }
        }
        shifts.sort_by(|a, b| (a[0] * a[0] + a[1] * a[1]).total_cmp(&(b[0] * b[0] + b[1] * b[1])));
        WallEwald {
            lengths,
            height,
            xi,
            r_cut,
            tolerance: tol,
            shifts,
        }
    }

    /// The separation `x_a - x_b`, its lateral components brought into the box centred
    /// on the origin (each in `[-L/2, L/2]`), its normal component as it is.
    pub fn minimum_image(&self, xa: [f64; 3], xb: [f64; 3]) -> [f64; 3] {
        let lateral = |d: usize| {
            let r = xa[d] - xb[d];
            r - self.lengths[d] * (r / self.lengths[d]).round()
        };
        [lateral(0), lateral(1), xa[2] - xb[2]]
    }

    /// The separation `x_a - x_b` of the nearest lateral image ([`WallEwald::minimum_image`]),
    /// zero for a sphere and itself (`same`).
    pub(super) fn separation(&self, a: &Particle, b: &Particle, same: bool) -> [f64; 3] {
        if same {
            [0.0; 3]
        } else {
            self.minimum_image(a.x, b.x)
        }
    }

    /// The FT blocks `M^{ab}` of spheres `a` (field) and `b` (source) summed over every
    /// lateral image of `b`; with `same`, `b` is `a` and the result its self mobility.
    pub fn blocks(&self, eta: f64, a: &Particle, b: &Particle, same: bool) -> BlocksFT {
        let (mut out, r) = self.real_part(
            a,
            b,
            same,
            BlocksFT::default(),
            |sigma| ewald_wall_ft_self(a.x, a.a, eta, self.height, sigma),
            |xb, sigma| ewald_wall_ft_pair(a.x, xb, a.a, b.a, eta, self.height, sigma),
        );
        let (ha, hb) = (a.x[2] - self.height, b.x[2] - self.height);
        self.reciprocal([r[0], r[1]], ha, hb, a.a, b.a, eta, true, &mut out);
        plane_blocks(
            &self.plane_kernel(ha, hb),
            a.a,
            b.a,
            self.unit(eta),
            &mut out,
        );
        out
    }

    /// The FTS blocks (all nine, the 11 x 11 grand block) of spheres `a` (field) and `b`
    /// (source) summed over every lateral image of `b`, as [`WallEwald::blocks`]: the real
    /// part from the generated FTS kernels (`scene_ewald_wall_fts`), the reciprocal part
    /// [`WallEwald::reciprocal_grand`], the mode `k_par = 0` [`plane_grand`].
    pub fn grand(&self, eta: f64, a: &Particle, b: &Particle, same: bool) -> Grand {
        let (mut out, r) = self.real_part(
            a,
            b,
            same,
            SMatrix::zeros(),
            |sigma| ewald_wall_fts_self(a.x, a.a, eta, self.height, sigma).matrix(),
            |xb, sigma| ewald_wall_fts_pair(a.x, xb, a.a, b.a, eta, self.height, sigma).matrix(),
        );
        let (ha, hb) = (a.x[2] - self.height, b.x[2] - self.height);
        self.reciprocal_grand([r[0], r[1]], ha, hb, a.a, b.a, eta, true, &mut out);
        plane_grand(
            &self.plane_kernel(ha, hb),
            a.a,
            b.a,
            self.unit(eta),
            &mut out,
        );
        Grand::from_matrix(&out)
    }

    /// The real part of a pair's lateral lattice sum with one truncation's kernels (their
    /// width `sigma = 1/xi` the last argument): `own` at `x_a` for a sphere and itself
    /// (`same`), else `zero`, plus `pair` at each lateral image of `b` within `r_c`
    /// ([`WallEwald::images`]); and the separation of the nearest image
    /// ([`WallEwald::separation`]), which the reciprocal sum takes.
    pub(super) fn real_part<T: for<'x> AddAssign<&'x T>>(
        &self,
        a: &Particle,
        b: &Particle,
        same: bool,
        zero: T,
        own: impl FnOnce(f64) -> T,
        mut pair: impl FnMut([f64; 3], f64) -> T,
    ) -> (T, [f64; 3]) {
        let sigma = 1.0 / self.xi;
        let r = self.separation(a, b, same);
        let mut out = if same { own(sigma) } else { zero };
        for xb in self.images(a, b, r, same) {
            out += &pair(xb, sigma);
        }
        (out, r)
    }

    /// `1/(8 pi eta A)`, the unit of the modes' kernels.
    pub(super) fn unit(&self, eta: f64) -> f64 {
        1.0 / (8.0 * PI * eta * self.lengths[0] * self.lengths[1])
    }

    /// The lateral images of the source `b` within `r_c` of the field point `a` (the
    /// separation of the nearest `r`), in the order of the shifts: each image's centre, at
    /// the lateral offset `r + shift` from `x_a`; with `same`, `a`'s own position left
    /// out.
    pub(super) fn images<'a>(
        &'a self,
        a: &'a Particle,
        b: &'a Particle,
        r: [f64; 3],
        same: bool,
    ) -> impl Iterator<Item = [f64; 3]> + 'a {
        let rc2 = self.r_cut * self.r_cut;
        self.shifts.iter().filter_map(move |s| {
            let ri = [r[0] + s[0], r[1] + s[1]];
            let lateral2 = ri[0] * ri[0] + ri[1] * ri[1];
            (lateral2 + r[2] * r[2] <= rc2 && !(same && lateral2 == 0.0)).then_some([
                a.x[0] - ri[0],
                a.x[1] - ri[1],
                b.x[2],
            ])
        })
    }

    /// The reciprocal cut-off `k_c` and the height `Lz'` of the box periodic in `z` for a
    /// pair of heights `ha + hb = s` above the wall (module docs).
    pub fn reciprocal_box(&self, s: f64) -> (f64, f64) {
        reciprocal_box(self.xi, self.tolerance, s, smallest_wave(self.lengths))
    }

    /// The reciprocal sum (`k_par != 0`) of the FT blocks at lateral separation `rho`,
    /// heights `ha`, `hb` above the wall, radii `aa`, `ab`, added to `out`: the direct
    /// source's, and with `image` Blake's image's (without it, the smooth part of the
    /// Stokeslet alone, which the slit's sum shares, [`super::slit`]).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn reciprocal(
        &self,
        rho: [f64; 2],
        ha: f64,
        hb: f64,
        aa: f64,
        ab: f64,
        eta: f64,
        image: bool,
        out: &mut BlocksFT,
    ) {
        let (ca, cb) = (aa * aa / 6.0, ab * ab / 6.0);
        let mut acc = Acc::default();
        let scale = self.for_each_wave(ha + hb, eta, |k, k2, proj| {
            let lateral_phase = k[0] * rho[0] + k[1] * rho[1];
            let direct = Source {
                m0: proj.map(|row| row.map(|v| C::new(v, 0.0))),
                m1: None,
                ky: k,
            };
            let phase = cis(lateral_phase + k[2] * (ha - hb));
            add_blocks(&mut acc, phase, &direct, k, k2, ca, cb);
            if image {
                let image = image_source(proj, k, k2, hb);
                let phase = cis(lateral_phase + k[2] * (ha + hb));
                add_blocks(&mut acc, phase, &image, k, k2, ca, cb);
            }
        });
        acc.into(scale, out);
    }

    /// The reciprocal sum (`k_par != 0`) of the FTS blocks (the 11 x 11 grand block) at
    /// lateral separation `rho`, heights `ha`, `hb`, radii `aa`, `ab`, added to `out`, as
    /// [`WallEwald::reciprocal`]: the direct source's and, with `image`, Blake's image's,
    /// each block a field functional of a source functional of the symbol
    /// ([`add_grand`]).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn reciprocal_grand(
        &self,
        rho: [f64; 2],
        ha: f64,
        hb: f64,
        aa: f64,
        ab: f64,
        eta: f64,
        image: bool,
        out: &mut SMatrix<f64, 11, 11>,
    ) {
        let mut acc = SMatrix::<f64, 11, 11>::zeros();
        let scale = self.for_each_wave(ha + hb, eta, |k, k2, proj| {
            let field = functionals(k, k2, aa);
            let lateral_phase = k[0] * rho[0] + k[1] * rho[1];
            let direct = Source {
                m0: proj.map(|row| row.map(|v| C::new(v, 0.0))),
                m1: None,
                ky: k,
            };
            let phase = cis(lateral_phase + k[2] * (ha - hb));
            add_grand(&mut acc, phase, &field, &direct, ab);
            if image {
                let image = image_source(proj, k, k2, hb);
                let phase = cis(lateral_phase + k[2] * (ha + hb));
                add_grand(&mut acc, phase, &field, &image, ab);
            }
        });
        *out += acc * scale;
    }

    /// Calls `f(k, k^2, g (I - khat khat))` for one of each pair `+-k_par != 0` of the
    /// lateral wave vectors and every `k_z` of the box periodic in `z` for heights `ha +
    /// hb = s` ([`WallEwald::reciprocal_box`]) within `k_c`, in a fixed order, with `g =
    /// phi(k)/k^2`; returns the scale of the sum, `2/(A Lz' eta)` (the factor 2: each
    /// `k_par` stands for itself and its opposite, whose term is the conjugate).
    fn for_each_wave(
        &self,
        s: f64,
        eta: f64,
        mut f: impl FnMut([f64; 3], f64, &[[f64; 3]; 3]),
    ) -> f64 {
        let (k_cut, lz) = self.reciprocal_box(s);
        let kc2 = k_cut * k_cut;
        let mmax = (k_cut * lz / (2.0 * PI)).floor() as i64;
        let xi2 = self.xi * self.xi;
        for kp in lateral_waves(self.lengths, k_cut) {
            let kp2 = kp[0] * kp[0] + kp[1] * kp[1];
            for m in -mmax..=mmax {
                let k3 = 2.0 * PI * m as f64 / lz;
                let k2 = kp2 + k3 * k3;
                if k2 > kc2 {
                    continue;
                }
                let k = [kp[0], kp[1], k3];
                let q = k2 / (4.0 * xi2);
                let g = (1.0 + q + 2.0 * q * q) * (-q).exp() / k2;
                // g (I - khat khat), the direct symbol
                let proj: [[f64; 3]; 3] = std::array::from_fn(|i| {
                    std::array::from_fn(|j| g * (f64::from(u8::from(i == j)) - k[i] * k[j] / k2))
                });
                f(k, k2, &proj);
            }
        }
        2.0 / (self.lengths[0] * self.lengths[1] * lz * eta)
    }

    /// The Brownian drift of sphere `p` (its translational rows; the rotational ones
    /// vanish), `sum_j d/dx_j M^{pp}_{ij}` of its periodic self mobility `S(h)`, which
    /// depends on the height `h` alone: the column `d S_i3/dh`.
    ///
    /// The pairs of distinct spheres add nothing: the whole lattice sum is a Green's
    /// function, reciprocal and divergence-free in its field point, so `sum_j d/dxb_j
    /// M^{ab}_ij = 0` image by image (the parts of the Ewald split are not each
    /// reciprocal; their sum is). The sphere's own images move with it: each adds the
    /// derivative of its pair kernel with both points moving together (the generated
    /// `ewald_wall_drift_pair_together`), next to the self kernel's
    /// (`ewald_wall_drift_self_along`), the reciprocal sum's (the image source's phase
    /// `exp(i k_z (h_a + h_b))` and its symbol's explicit heights, differentiated at fixed
    /// truncation) and the mode `k_par = 0`'s, which is zero (its third column is).
    /// `x` and `y` components are zero up to rounding by the lattice's symmetry
    /// `rho -> -rho`; they are summed as computed.
    pub fn drift(&self, eta: f64, p: &Particle) -> [f64; 3] {
        let sigma = 1.0 / self.xi;
        let up = [0.0, 0.0, 1.0];
        let mut out = ewald_wall_drift_self_along(p.x, p.a, eta, self.height, sigma, up).a;
        let rc2 = self.r_cut * self.r_cut;
        for s in &self.shifts {
            let lateral2 = s[0] * s[0] + s[1] * s[1];
            if lateral2 > rc2 || lateral2 == 0.0 {
                continue;
            }
            let image = [p.x[0] - s[0], p.x[1] - s[1], p.x[2]];
            let d = ewald_wall_drift_pair_together(p.x, image, p.a, eta, self.height, sigma, up).a;
            for i in 0..3 {
                out[i] += d[i];
            }
        }
        // the reciprocal sum at (x, x): the image source's `uf = fa S(h)` under the phase
        // `exp(2 i k_z h)`; d/dh = phase fa (2 i k_z S + S'), `S' = (1 - cb k^2) M' - 2 i
        // cb ky_3 M''` (`M` is quadratic in `h`)
        let h = p.x[2] - self.height;
        let c = p.a * p.a / 6.0;
        let mut sum = [0.0; 3];
        let scale = self.for_each_wave(2.0 * h, eta, |k, k2, proj| {
            let image = image_source(proj, k, k2, h);
            let (m1, m2) = image.m1.expect("the image's symbol depends on its height");
            let fa = 1.0 - c * k2;
            let phase = cis(2.0 * k[2] * h);
            for (i, v) in sum.iter_mut().enumerate() {
                let s0 = image.m0[i][2].scale(1.0 - c * k2)
                    + (imaginary(-2.0 * image.ky[2]) * m1[i][2] + m2[i][2]).scale(c);
                let s1 = m1[i][2].scale(1.0 - c * k2)
                    + (imaginary(-2.0 * image.ky[2]) * m2[i][2]).scale(c);
                *v += (phase * (imaginary(2.0 * k[2]) * s0 + s1)).re * fa;
            }
        });
        for i in 0..3 {
            out[i] += scale * sum[i];
        }
        out
    }

    /// The derivatives `d_a^m d_b^n f` (`m, n < N <= 4`, indexed `[m][n]`: `N = 3` for
    /// the F and FT blocks, 4 for FTS) of the mode `k_par = 0`'s `f(h_a, h_b)` (module
    /// docs) at heights `ha`, `hb` above the wall.
    pub(crate) fn plane_kernel<const N: usize>(&self, ha: f64, hb: f64) -> [[f64; N]; N] {
        let (d, s) = (ha - hb, ha + hb);
        let psi_d = Psi::at(self.xi, d);
        let psi_s = Psi::at(self.xi, s);
        // d_a^m d_b^n f
        let t = |m: usize, n: usize| {
            let sign = if n.is_multiple_of(2) { 1.0 } else { -1.0 };
            let mut v = sign * psi_d.0[m + n] - psi_s.0[m + n];
            // d_b^n [h_b^2 Psi''(S)] by Leibniz: the derivatives of h_b^2 are 2 h_b, 2
            let heights = [hb * hb, 2.0 * hb, 2.0];
            let mut binomial = 1.0;
            for (j, c) in heights.iter().enumerate().take(n.min(2) + 1) {
                if j > 0 {
                    binomial *= (n + 1 - j) as f64 / j as f64;
                }
                v += binomial * c * psi_s.0[2 + m + n - j];
            }
            v
        };
        std::array::from_fn(|m| std::array::from_fn(|n| t(m, n)))
    }
}

/// The mode `k_par = 0` of the FT blocks from the table `t[m][n] = d_a^m d_b^n f` of its
/// kernel `f(h_a, h_b)` (units of `1/(8 pi eta A)`, `unit`; module docs), radii `aa`, `ab`,
/// added to `out`: `UF = (1 + c_a d_a^2)(1 + c_b d_b^2) f`, `OmegaF_mj = (1/2) eps_m3j d_a
/// (1 + c_b d_b^2) f`, `UL_ij = (1/2) eps_j3i d_b (1 + c_a d_a^2) f`, `OmegaL = (1/4) d_a
/// d_b f (I - e3 e3)`, `c = a^2/6`, on the lateral components.
pub(super) fn plane_blocks(table: &[[f64; 3]; 3], aa: f64, ab: f64, unit: f64, out: &mut BlocksFT) {
    let (ca, cb) = (aa * aa / 6.0, ab * ab / 6.0);
    let t = |m: usize, n: usize| table[m][n];
    let uf = unit * (t(0, 0) + ca * t(2, 0) + cb * t(0, 2) + ca * cb * t(2, 2));
    let of = 0.5 * unit * (t(1, 0) + cb * t(1, 2));
    let ul = 0.5 * unit * (t(0, 1) + ca * t(2, 1));
    let ol = 0.25 * unit * t(1, 1);
    for i in 0..2 {
        out.uf[i][i] += uf;
        out.ol[i][i] += ol;
    }
    // eps_m3j: (1, 2) -> -1, (2, 1) -> +1
    out.of[0][1] -= of;
    out.of[1][0] += of;
    // UL_ij = (1/2) eps_j3i d_b (...) f: (i, j) = (1, 2) -> eps_231 = +1
    out.ul[0][1] += ul;
    out.ul[1][0] -= ul;
}

/// The mode `k_par = 0` of the FTS blocks (the 11 x 11 grand block) from the table
/// `t[m][n] = d_a^m d_b^n f` (`m, n <= 3`) of its kernel, as [`plane_blocks`]: its flow is
/// lateral and depends on the height alone, so each functional is a polynomial in the
/// height's derivative acting on a lateral component `i`: at the field point `U_j: delta_ij
/// (1 + c_a d_a^2)`, `Omega_m: (1/2) eps_m3i d_a`, `E_p: B_p,i3 (d_a + g_a d_a^3)` (of
/// `(1 + g lap) B_p,iq d_q` only `q = 3` is left; `c = a^2/6`, `g = a^2/10`), at the source
/// the same in `d_b`: `M_ab = unit sum_i sum_mn A_a,i,m B_b,i,n t[m][n]`.
pub(super) fn plane_grand(
    table: &[[f64; 4]; 4],
    aa: f64,
    ab: f64,
    unit: f64,
    out: &mut SMatrix<f64, 11, 11>,
) {
    // [functional][lateral component][power of the derivative]
    let functionals = |a: f64| -> [[[f64; 4]; 2]; 11] {
        let (c, g) = (a * a / 6.0, a * a / 10.0);
        std::array::from_fn(|al| {
            std::array::from_fn(|i| match al {
                0..3 if al == i => [1.0, 0.0, c, 0.0],
                0..3 => [0.0; 4],
                3..6 => [0.0, 0.5 * levi_civita(al - 3, 2, i), 0.0, 0.0],
                _ => {
                    let b = STRAIN_BASIS[al - 6][i][2];
                    [0.0, b, 0.0, g * b]
                }
            })
        })
    };
    let (fa, fb) = (functionals(aa), functionals(ab));
    for al in 0..11 {
        for be in 0..11 {
            let mut v = 0.0;
            for i in 0..2 {
                for (m, row) in table.iter().enumerate() {
                    for (n, t) in row.iter().enumerate() {
                        v += fa[al][i][m] * fb[be][i][n] * t;
                    }
                }
            }
            out[(al, be)] += unit * v;
        }
    }
}

/// The lateral wave vectors `k_par = 2 pi (n1/Lx, n2/Ly) != 0`, `|k_par| <= k_cut`, of the
/// box `lengths`, one of each pair `+-k_par` (the first non-zero index positive), in a
/// fixed order.
pub(crate) fn lateral_waves(lengths: [f64; 2], k_cut: f64) -> impl Iterator<Item = [f64; 2]> {
    let nmax: [i64; 2] = std::array::from_fn(|d| (k_cut * lengths[d] / (2.0 * PI)).floor() as i64);
    (0..=nmax[0])
        .flat_map(move |n1| (-nmax[1]..=nmax[1]).map(move |n2| (n1, n2)))
        .filter(|&(n1, n2)| n1 > 0 || (n1 == 0 && n2 > 0))
        .map(move |(n1, n2)| {
            [
                2.0 * PI * n1 as f64 / lengths[0],
                2.0 * PI * n2 as f64 / lengths[1],
            ]
        })
        .filter(move |k| k[0] * k[0] + k[1] * k[1] <= k_cut * k_cut)
}

/// `K0 = 2 pi/max(Lx, Ly)`, the smallest lateral wave number `k_par != 0` of the box
/// `lengths`.
pub(crate) fn smallest_wave(lengths: [f64; 2]) -> f64 {
    2.0 * PI / lengths[0].max(lengths[1])
}

/// The reciprocal cut-off `k_c` and the height `Lz'` of the box periodic in `z` for a
/// pair of heights `ha + hb = s` above the wall (module docs), at
/// split `xi` and tolerance `tol`, for lateral wave numbers at least `k_low` (`K0` for
/// every mode `k_par != 0`: the padding is `D = (ln(100/tol) + 2 ln(1 + k_low s))/k_low`).
pub(crate) fn reciprocal_box(xi: f64, tol: f64, s: f64, k_low: f64) -> (f64, f64) {
    let p = truncation_parameter(tol);
    let k_cut = 2.0 * xi * (p * p + 2.0 * (1.0 + 2.0 * xi * p * s).ln()).sqrt();
    let padding = ((100.0 / tol).ln() + 2.0 * (1.0 + k_low * s).ln()) / k_low;
    (k_cut, s + padding)
}

/// `Psi` and its derivatives to the eighth at one point: `Psi(z) = -4 pi z erf(u) - 4
/// sqrt(pi) xi z^2 e^{-u^2}`, `u = xi z`; `Psi' = -4 pi erf(u) + 8 sqrt(pi) (u^3 - 2 u)
/// e^{-u^2}`; for `n >= 2`, `Psi^(n) = 8 sqrt(pi) xi^(n-1) q_(n-2)(u) e^{-u^2}` with
/// `q_0 = -3 + 7 u^2 - 2 u^4` and `q_(j+1) = q_j' - 2 u q_j`.
pub(super) struct Psi(pub(super) [f64; 9]);

impl Psi {
    pub(super) fn at(xi: f64, z: f64) -> Psi {
        let u = xi * z;
        let gauss = (-u * u).exp();
        let root = PI.sqrt();
        let mut v = [0.0; 9];
        v[0] = -4.0 * PI * z * libm::erf(u) - 4.0 * root * xi * z * z * gauss;
        v[1] = -4.0 * PI * libm::erf(u) + 8.0 * root * (u * u * u - 2.0 * u) * gauss;
        // q as coefficients of powers of u
        let mut q = vec![-3.0, 0.0, 7.0, 0.0, -2.0];
        let mut xi_power = xi;
        for vn in v.iter_mut().skip(2) {
            let value = q.iter().rev().fold(0.0, |acc, c| acc * u + c);
            *vn = 8.0 * root * xi_power * value * gauss;
            // q' - 2 u q
            let mut next = vec![0.0; q.len() + 1];
            for (p, c) in q.iter().enumerate() {
                if p > 0 {
                    next[p - 1] += p as f64 * c;
                }
                next[p + 1] -= 2.0 * c;
            }
            q = next;
            xi_power *= xi;
        }
        Psi(v)
    }
}

/// The reciprocal sums' phases and symbols.
type C = Complex64;

/// `exp(i t)`.
fn cis(t: f64) -> C {
    let (s, c) = t.sin_cos();
    C::new(c, s)
}

/// `i t`.
fn imaginary(t: f64) -> C {
    C::new(0.0, t)
}

type M3 = [[C; 3]; 3];

/// A source's symbol `M` at the source's height, with its first and second derivatives
/// in that height (`None` for the direct term, whose symbol does not depend on it; the
/// image's is quadratic in it), and `ky`, the wave vector that `i d/dy` gives on the
/// source's phase.
struct Source {
    m0: M3,
    m1: Option<(M3, M3)>,
    ky: [f64; 3],
}

/// `g (I - khat khat) T(k, h)` and its first and second derivatives in `h` (module docs).
fn image_source(proj: &[[f64; 3]; 3], k: [f64; 3], k2: f64, h: f64) -> Source {
    let mirror = [1.0, 1.0, -1.0];
    // T = T0 + h N - h^2 k^2 P, T0 = -I, N_3l = -2 i P_ll k_l
    let t = |i: usize, l: usize, deriv: usize| -> C {
        let diag = if i == l {
            match deriv {
                0 => -1.0 - h * h * k2 * mirror[l],
                1 => -2.0 * h * k2 * mirror[l],
                _ => -2.0 * k2 * mirror[l],
            }
        } else {
            0.0
        };
        let n = if i == 2 { -2.0 * mirror[l] * k[l] } else { 0.0 };
        let n = match deriv {
            0 => h * n,
            1 => n,
            _ => 0.0,
        };
        C::new(diag, n)
    };
    let product = |deriv: usize| -> M3 {
        std::array::from_fn(|i| {
            std::array::from_fn(|l| {
                (0..3).fold(C::default(), |acc, m| {
                    acc + t(m, l, deriv).scale(proj[i][m])
                })
            })
        })
    };
    Source {
        m0: product(0),
        m1: Some((product(1), product(2))),
        ky: [k[0], k[1], -k[2]],
    }
}

/// `Re(phase B)` added to `acc` for the FT blocks `B` of one wave vector `k` (without its
/// phase) from a source's symbol:
/// `S = (1 + a_b^2/6 lap_y) M`, `UF = (1 - a_a^2 k^2/6) S`, `OmegaF_mj = (1/2) eps_mni (i
/// k_n) S_ij`, `UL_ij = (1 - a_a^2 k^2/6) (1/2) eps_jnl (D_n M)_il`, `OmegaL_mj = (1/2)
/// eps_mni (i k_n) (1/2) eps_jpl (D_p M)_il`, with `D_n M = -i ky_n M + delta_n3 d_h M`.
/// Each block is added where it is made.
fn add_blocks(acc: &mut Acc, phase: C, src: &Source, k: [f64; 3], k2: f64, ca: f64, cb: f64) {
    const ZERO: M3 = [[C::new(0.0, 0.0); 3]; 3];
    let zero = ZERO;
    let (m1, m2) = match &src.m1 {
        Some((m1, m2)) => (m1, m2),
        None => (&ZERO, &ZERO),
    };
    let fa = 1.0 - ca * k2;
    // (filled in place: arrays built by nested `from_fn` were copied, `memmove` a quarter
    // of a dense matrix's time)
    // lap_y M = -k^2 M - 2 i ky3 M' + M''
    let mut s = ZERO;
    for i in 0..3 {
        for j in 0..3 {
            s[i][j] = src.m0[i][j].scale(1.0 - cb * k2)
                + (imaginary(-2.0 * src.ky[2]) * m1[i][j] + m2[i][j]).scale(cb);
        }
    }
    // D_n M
    let mut dm = [ZERO; 3];
    for n in 0..3 {
        for i in 0..3 {
            for l in 0..3 {
                let v = imaginary(-src.ky[n]) * src.m0[i][l];
                dm[n][i][l] = if n == 2 { v + m1[i][l] } else { v };
            }
        }
    }
    acc.add(0, phase, |i, j| s[i][j].scale(fa));
    let mut of = zero;
    let mut ul = zero;
    let mut ol = zero;
    for (a, b, c, e) in LEVI_CIVITA {
        // eps_abc = e: OmegaF_aj += (1/2) e (i k_b) S_cj
        for j in 0..3 {
            of[a][j] += imaginary(0.5 * e * k[b]) * s[c][j];
        }
        // UL_ia += (1/2) e (D_b M)_ic, fa
        for i in 0..3 {
            ul[i][a] += dm[b][i][c].scale(0.5 * e * fa);
        }
    }
    for (m, n, i, e1) in LEVI_CIVITA {
        for (j, p, l, e2) in LEVI_CIVITA {
            ol[m][j] += imaginary(0.25 * e1 * e2 * k[n]) * dm[p][i][l];
        }
    }
    acc.add(1, phase, |i, j| ul[i][j]);
    acc.add(2, phase, |i, j| of[i][j]);
    acc.add(3, phase, |i, j| ol[i][j]);
}

/// `Re(phase M)` added to `acc` for the grand block `M` of one wave vector (without its
/// phase): the field's functionals `field` (`A(k)` of
/// [`super::ewald::Ewald::reciprocal_grand`], rows `U`, `Omega`, `E` on the velocity's
/// index `i`) of the source's functionals of the symbol, which are the same operators in
/// `y` (Eq. 8 against Eqs. 12-15): `(1 + a_b^2/6 lap_y) delta_lj` on the force,
/// `(1/2) eps_jnl D_n` on the torque, `(1 + a_b^2/10 lap_y) B_p,lq D_q` on the stresslet
/// (`l` the symbol's column), where `D_n`, the derivative in `y_n`, acts on the symbol's
/// jet in the source's height: `(D_n M)^(d) = -i ky_n M^(d) + delta_n3 M^(d+1)` (`M` is
/// quadratic in the height, so `[M, M', M'']` is closed; the direct symbol does not
/// depend on it).
fn add_grand(
    acc: &mut SMatrix<f64, 11, 11>,
    phase: C,
    field: &[[C; 3]; 11],
    src: &Source,
    ab: f64,
) {
    const ZERO: M3 = [[C::new(0.0, 0.0); 3]; 3];
    type Jet = [M3; 3];
    let jet: Jet = match &src.m1 {
        Some((m1, m2)) => [src.m0, *m1, *m2],
        None => [src.m0, ZERO, ZERO],
    };
    let derivative = |n: usize, j: &Jet| -> Jet {
        let mut out = [ZERO; 3];
        for (o, m) in out.iter_mut().enumerate() {
            for i in 0..3 {
                for l in 0..3 {
                    let v = imaginary(-src.ky[n]) * j[o][i][l];
                    m[i][l] = if n == 2 && o < 2 {
                        v + j[o + 1][i][l]
                    } else {
                        v
                    };
                }
            }
        }
        out
    };
    // (1 + c lap_y) M for the force's (c = a^2/6) and the stresslet's (a^2/10) Faxén laws
    let mut lap = [ZERO; 3];
    for n in 0..3 {
        let dd = derivative(n, &derivative(n, &jet));
        for (o, m) in lap.iter_mut().enumerate() {
            for i in 0..3 {
                for l in 0..3 {
                    m[i][l] += dd[o][i][l];
                }
            }
        }
    }
    let faxen = |c: f64| -> Jet {
        let mut out = jet;
        for (o, m) in out.iter_mut().enumerate() {
            for i in 0..3 {
                for l in 0..3 {
                    m[i][l] += lap[o][i][l].scale(c);
                }
            }
        }
        out
    };
    let (force, strain) = (faxen(ab * ab / 6.0), faxen(ab * ab / 10.0));
    let rotlet: [Jet; 3] = std::array::from_fn(|n| derivative(n, &jet));
    let stresslet: [Jet; 3] = std::array::from_fn(|q| derivative(q, &strain));
    // the source's functionals, [column][velocity index]
    let mut s = [[C::new(0.0, 0.0); 3]; 11];
    for i in 0..3 {
        for j in 0..3 {
            s[j][i] = force[0][i][j];
        }
        for (m, n, l, e) in LEVI_CIVITA {
            s[3 + m][i] += rotlet[n][0][i][l].scale(0.5 * e);
        }
        for (p, basis) in STRAIN_BASIS.iter().enumerate() {
            for l in 0..3 {
                for q in 0..3 {
                    if basis[l][q] != 0.0 {
                        s[6 + p][i] += stresslet[q][0][i][l].scale(basis[l][q]);
                    }
                }
            }
        }
    }
    for (al, f) in field.iter().enumerate() {
        for (be, column) in s.iter().enumerate() {
            let m = f[0] * column[0] + f[1] * column[1] + f[2] * column[2];
            acc[(al, be)] += (phase * m).re;
        }
    }
}

/// The non-zero `eps_abc`: `(a, b, c, eps_abc)`.
const LEVI_CIVITA: [(usize, usize, usize, f64); 6] = [
    (0, 1, 2, 1.0),
    (1, 2, 0, 1.0),
    (2, 0, 1, 1.0),
    (0, 2, 1, -1.0),
    (2, 1, 0, -1.0),
    (1, 0, 2, -1.0),
];

/// The reciprocal blocks summed: `Re(phase B)` accumulated in the order of the waves.
#[derive(Default)]
struct Acc {
    sums: [[[f64; 3]; 3]; 4],
}

impl Acc {
    /// `Re(phase b(i, j))` added to block `which` (`[UF, UL, OmegaF, OmegaL]`).
    #[inline(always)]
    fn add(&mut self, which: usize, phase: C, b: impl Fn(usize, usize) -> C) {
        let sum = &mut self.sums[which];
        for i in 0..3 {
            for j in 0..3 {
                sum[i][j] += (phase * b(i, j)).re;
            }
        }
    }

    /// `scale` times the sums, added to `out` (`[UF, UL, OmegaF, OmegaL]`).
    fn into(self, scale: f64, out: &mut BlocksFT) {
        let [uf, ul, of, ol] = self.sums;
        for i in 0..3 {
            for j in 0..3 {
                out.uf[i][j] += scale * uf[i][j];
                out.ul[i][j] += scale * ul[i][j];
                out.of[i][j] += scale * of[i][j];
                out.ol[i][j] += scale * ol[i][j];
            }
        }
    }
}
