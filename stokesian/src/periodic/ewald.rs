//! The triply periodic Rotne-Prager-Yamakawa mobility by Ewald summation, Beenakker's
//! split (J. Chem. Phys. 85, 1581 (1986)): the Stokeslet's `r` is written
//! `r erfc(xi r) + r erf(xi r)`; the first part, short-ranged, is summed over the periodic
//! images within `r_c` in real space (the generated kernels of `kernels::ewald_real`,
//! with the same Faxén operators as every other kernel), the second, smooth, over the
//! wave vectors `k = 2 pi (n1/Lx, n2/Ly, n3/Lz) != 0` within `k_c`:
//!
//! `M^{ab} = sum_n R^{ab}(r + n L) + (1/V) sum_{k != 0} Mhat^{ab}(k) exp(i k.r)`,
//! `r = x_a - x_b`,
//!
//! with, for `phi(k) = (1 + k^2/(4 xi^2) + k^4/(8 xi^4)) exp(-k^2/(4 xi^2))`, `P = I - khat
//! khat` and the Faxén factors `f_a = 1 - a_a^2 k^2/6`:
//!
//! - `UF: f_a f_b phi P / (eta k^2)` (the Fourier transform of the Stokeslet is `P/(eta
//!   k^2)`; the Faxén operators `1 + a^2 lap/6` become `f_a`, `f_b`);
//! - `OmegaF_mj: (i/2) eps_mnj k_n f_b phi / (eta k^2)` (half the curl at the field
//!   point);
//! - `OmegaL: phi P / (4 eta)`;
//! - `UL^{ab} = (OmegaF^{ba})^T`.
//!
//! The sum over `k` runs over half of the wave vectors, twice (every term is even under
//! `k -> -k` once the exponential is split into its cosine and sine). The term `k = 0`
//! is left out: the net force on the box is balanced by a mean pressure gradient, and
//! velocities are relative to the box's mean (Hasimoto, J. Fluid Mech. 5, 317 (1959)).
//! The self mobility is the isolated sphere, the operators applied to `J^R - J` at
//! `r = 0` (the generated self kernel), the real images `n != 0` and the reciprocal sum
//! at `r = 0`.
//!
//! The FTS blocks ([`Ewald::grand`]) take the generated FTS kernel of the real part and
//! the reciprocal symbols of every block from the Faxén functionals at both ends
//! ([`Ewald::reciprocal_grand`]); F and FT are their leading blocks, written out above.
//!
//! Truncation: both sums' errors fall like `exp(-p^2)` times a power of `p`, with `p = xi
//! r_c` in real space and `p = k_c/(2 xi)` in reciprocal space (the leading real term is
//! `(4 xi^3 r^2/sqrt(pi)) exp(-xi^2 r^2)`, the reciprocal `(k^4/(8 xi^4)) exp(-k^2/(4
//! xi^2))` times the Faxén polynomial); measured against converged sums of both parts,
//! `p = 5.0` leaves 4e-7 and `p = 5.8` 3e-11 of each block's largest pair entry, which
//! `p^2 = ln(1/tol) + 11.5` covers. `xi = sqrt(pi) / V^(1/3)` balances the two sums' terms
//! (as many real images within `r_c` as wave vectors within `k_c`).

use crate::system::input::Particle;
use kernels::generated::scene_ewald_real_ft::{ewald_real_ft_pair, ewald_real_ft_self};
use kernels::generated::scene_ewald_real_fts::{ewald_real_fts_pair, ewald_real_fts_self};
use kernels::{BlocksFT, Grand, STRAIN_BASIS};
use nalgebra::SMatrix;
use rustfft::num_complex::Complex64;
use std::f64::consts::PI;

/// The split and the truncation of one box at one tolerance.
#[derive(Clone, Debug)]
pub struct Ewald {
    /// Box lengths.
    pub lengths: [f64; 3],
    /// The splitting parameter `xi` (inverse length).
    pub xi: f64,
    /// Real-space cut-off `r_c`.
    pub r_cut: f64,
    /// Reciprocal cut-off `k_c`.
    pub k_cut: f64,
    /// Half of the wave vectors within `k_c` (`k != 0`, one of each `+-k`).
    waves: Vec<Wave>,
    /// The lattice vectors `n L` within `r_c + the box's diagonal`, nearest first.
    shifts: Vec<[f64; 3]>,
}

/// One wave vector and what its terms share.
#[derive(Clone, Debug)]
struct Wave {
    k: [f64; 3],
    k2: f64,
    /// `2 phi(k) / (V k^2)` (the factor 2: `k` and `-k`).
    g: f64,
    /// `2 phi(k) / V`.
    phi: f64,
}

/// `p` with `exp(-p^2)`-type truncation errors at `tol` (module docs).
pub fn truncation_parameter(tol: f64) -> f64 {
    (tol.recip().ln() + 11.5).sqrt()
}

impl Ewald {
    /// The split for a box of `lengths` at relative tolerance `tol` (of each block's
    /// largest pair entry), `xi` chosen to balance the sums (module docs), or `xi` given.
    pub fn new(lengths: [f64; 3], tol: f64, xi: Option<f64>) -> Ewald {
        let volume = lengths[0] * lengths[1] * lengths[2];
        let p = truncation_parameter(tol);
        let xi = xi.unwrap_or(PI.sqrt() / volume.cbrt());
        let (r_cut, k_cut) = (p / xi, 2.0 * xi * p);
        let mut waves = Vec::new();
        let nmax: [i64; 3] =
            std::array::from_fn(|d| (k_cut * lengths[d] / (2.0 * PI)).floor() as i64);
        for n1 in 0..=nmax[0] {
            for n2 in -nmax[1]..=nmax[1] {
                for n3 in -nmax[2]..=nmax[2] {
                    // one of each +-k: the first non-zero index positive
                    let half = n1 > 0 || (n1 == 0 && (n2 > 0 || (n2 == 0 && n3 > 0)));
                    if !half {
                        continue;
                    }
                    let n = [n1, n2, n3];
                    let k: [f64; 3] = std::array::from_fn(|d| 2.0 * PI * n[d] as f64 / lengths[d]);
                    let k2 = k[0] * k[0] + k[1] * k[1] + k[2] * k[2];
                    if k2 > k_cut * k_cut {
                        continue;
                    }
                    let q = k2 / (4.0 * xi * xi);
                    let phi = (1.0 + q + 2.0 * q * q) * (-q).exp();
                    waves.push(Wave {
                        k,
                        k2,
                        g: 2.0 * phi / (volume * k2),
                        phi: 2.0 * phi / volume,
                    });
                }
            }
        }
        // every lattice vector that can bring an image within r_c of a minimum-image
        // separation (whose components are at most half a box length)
        let reach =
            r_cut + 0.5 * (lengths[0].powi(2) + lengths[1].powi(2) + lengths[2].powi(2)).sqrt();
        let mmax: [i64; 3] = std::array::from_fn(|d| (reach / lengths[d]).ceil() as i64);
        let mut shifts = Vec::new();
        for m1 in -mmax[0]..=mmax[0] {
            for m2 in -mmax[1]..=mmax[1] {
                for m3 in -mmax[2]..=mmax[2] {
                    let s = [
                        m1 as f64 * lengths[0],
                        m2 as f64 * lengths[1],
                        m3 as f64 * lengths[2],
                    ];
                    if s[0] * s[0] + s[1] * s[1] + s[2] * s[2] <= reach * reach {
                        shifts.push(s);
                    }
                }
            }
        }
        shifts.sort_by(|a, b| norm2(a).total_cmp(&norm2(b)));
        Ewald {
            lengths,
            xi,
            r_cut,
            k_cut,
            waves,
            shifts,
        }
    }

    /// The separation `x_a - x_b` brought into the box centred on the origin (each
    /// component in `[-L/2, L/2]`).
    pub fn minimum_image(&self, xa: [f64; 3], xb: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|d| {
            let r = xa[d] - xb[d];
            r - self.lengths[d] * (r / self.lengths[d]).round()
        })
    }

    /// The FT blocks `M^{ab}` of spheres `a` (field) and `b` (source) summed over every
    /// periodic image of `b`; with `same`, `b` is `a` and the result its self mobility
    /// (the generated self kernel, the images `n != 0`, the reciprocal sum at `r = 0`).
    pub fn blocks(&self, eta: f64, a: &Particle, b: &Particle, same: bool) -> BlocksFT {
        let (sigma, r) = self.pair(a, b, same);
        let mut out = if same {
            ewald_real_ft_self(a.x, a.a, eta, sigma)
        } else {
            BlocksFT::default()
        };
        // the image of the source at x_a - r_image
        let real = |ri: [f64; 3]| {
            let xb = std::array::from_fn(|d| a.x[d] - ri[d]);
            ewald_real_ft_pair(a.x, xb, a.a, b.a, eta, sigma)
        };
        self.real_sum(r, same, real, &mut out);
        self.reciprocal(r, a.a, b.a, eta, &mut out);
        out
    }

    /// The FTS blocks `M^{ab}` (all nine) of spheres `a` (field) and `b` (source) summed
    /// over every periodic image of `b`, as [`Ewald::blocks`]: the real part from the
    /// generated FTS kernels (`scene_ewald_real_fts`), the reciprocal part
    /// [`Ewald::reciprocal_grand`].
    pub fn grand(&self, eta: f64, a: &Particle, b: &Particle, same: bool) -> Grand {
        let (sigma, r) = self.pair(a, b, same);
        let mut out = if same {
            ewald_real_fts_self(a.x, a.a, eta, sigma).matrix()
        } else {
            SMatrix::zeros()
        };
        for ri in self.images(r, same) {
            let xb = std::array::from_fn(|d| a.x[d] - ri[d]);
            out += ewald_real_fts_pair(a.x, xb, a.a, b.a, eta, sigma).matrix();
        }
        self.reciprocal_grand(r, a.a, b.a, eta, &mut out);
        Grand::from_matrix(&out)
    }

    /// The reciprocal sum of the FTS blocks at separation `r = x_a - x_b`, added to
    /// `out` (the 11 x 11 grand block). Each block is a field functional at `x_a` times a
    /// source functional at `x_b` of the Stokeslet (Eqs. 8, 12-15), and in Fourier space
    /// `d/dx_a -> i k`, `d/dx_b -> -i k`: with `G(k) = phi(k) (I - khat khat)/(eta
    /// k^2)`,
    ///
    /// `M(k) = A(k) G(k) A(-k)^T`, rows of `A(k)` (response or moment `alpha`, index `i`
    /// of the velocity): `U_p: f delta_pi`; `Omega_m: (1/2) eps_mni i k_n`; `E_p: g
    /// sum_q B_p,iq i k_q` (the strain basis `B_p`, `STRAIN_BASIS`), with `f = 1 - a^2
    /// k^2/6`, `g = 1 - a^2 k^2/10` of the sphere at that end. The source's functionals
    /// are the field's at `-k` (the same operators, Eq. 8 against Eqs. 12-15), which is
    /// reciprocity. `M(-k)` is the conjugate of `M(k)`, so a pair `+-k` adds `2 Re(M(k)
    /// exp(i k.r))`. F and FT are the leading blocks of the same sum ([`Ewald::reciprocal`]
    /// writes them out).
    pub fn reciprocal_grand(
        &self,
        r: [f64; 3],
        aa: f64,
        ab: f64,
        eta: f64,
        out: &mut SMatrix<f64, 11, 11>,
    ) {
        for w in &self.waves {
            let a = functionals(w.k, w.k2, aa);
            let b = functionals(w.k, w.k2, ab);
            let kr = w.k[0] * r[0] + w.k[1] * r[1] + w.k[2] * r[2];
            // 2 G(k)/V exp(i k.r), the factor 2 of the pair +-k in `w.g`
            let phase = Complex64::from_polar(w.g / eta, kr);
            let p: [[f64; 3]; 3] = std::array::from_fn(|i| {
                std::array::from_fn(|j| f64::from(u8::from(i == j)) - w.k[i] * w.k[j] / w.k2)
            });
            // A(k) P, then times A(-k)^T = conj(A(k))^T
            let ap: [[Complex64; 3]; 11] = std::array::from_fn(|al| {
                std::array::from_fn(|j| (0..3).map(|i| a[al][i] * p[i][j]).sum())
            });
            for al in 0..11 {
                for be in 0..11 {
                    let m: Complex64 = (0..3).map(|j| ap[al][j] * b[be][j].conj()).sum();
                    out[(al, be)] += (m * phase).re;
                }
            }
        }
    }

    /// The real kernels' width `1/xi` and the minimum-image separation `x_a - x_b` of a
    /// pair (zero for a sphere and itself).
    fn pair(&self, a: &Particle, b: &Particle, same: bool) -> (f64, [f64; 3]) {
        let r = if same {
            [0.0; 3]
        } else {
            self.minimum_image(a.x, b.x)
        };
        (1.0 / self.xi, r)
    }

    /// The number of wave vectors summed (half of them, each with its opposite).
    pub fn waves(&self) -> usize {
        self.waves.len()
    }

    /// `sum_n R(r + n L)` over the images within `r_c` of the minimum-image separation
    /// `r` (the origin's own term left out when `skip_origin`), where `real(r)` gives
    /// the real-space blocks of a separation.
    pub fn real_sum(
        &self,
        r: [f64; 3],
        skip_origin: bool,
        mut real: impl FnMut([f64; 3]) -> BlocksFT,
        out: &mut BlocksFT,
    ) {
        for ri in self.images(r, skip_origin) {
            *out += &real(ri);
        }
    }

    /// The separations `r + n L` of the images within `r_c` of the minimum-image
    /// separation `r`, in the fixed order of the lattice vectors (the origin's own left
    /// out when `skip_origin`).
    fn images(&self, r: [f64; 3], skip_origin: bool) -> impl Iterator<Item = [f64; 3]> + '_ {
        self.shifts.iter().filter_map(move |s| {
            let ri = [r[0] + s[0], r[1] + s[1], r[2] + s[2]];
            let d2 = norm2(&ri);
            (d2 <= self.r_cut * self.r_cut && !(skip_origin && d2 == 0.0)).then_some(ri)
        })
    }

    /// The reciprocal sum of the FT blocks of `M^{ab}` at separation `r = x_a - x_b`,
    /// radii `aa`, `ab`, viscosity `eta` (module docs), added to `out`.
    pub fn reciprocal(&self, r: [f64; 3], aa: f64, ab: f64, eta: f64, out: &mut BlocksFT) {
        let (ca, cb) = (aa * aa / 6.0, ab * ab / 6.0);
        for w in &self.waves {
            let kr = w.k[0] * r[0] + w.k[1] * r[1] + w.k[2] * r[2];
            let (s, c) = kr.sin_cos();
            let (fa, fb) = (1.0 - ca * w.k2, 1.0 - cb * w.k2);
            let uf = fa * fb * w.g * c / eta;
            let ol = 0.25 * w.phi * c / eta;
            // OmegaF_mj = -(1/2) eps_mnj k_n f_b g sin / eta; UL^{ab}_im = (1/2)
            // eps_min k_n f_a g sin / eta
            let of = -0.5 * fb * w.g * s / eta;
            let ul = 0.5 * fa * w.g * s / eta;
            for i in 0..3 {
                for j in 0..3 {
                    let p = if i == j { 1.0 } else { 0.0 } - w.k[i] * w.k[j] / w.k2;
                    out.uf[i][j] += uf * p;
                    out.ol[i][j] += ol * p;
                }
            }
            // sum_n eps_mnj k_n, entry (m, j): the matrix of `k x`
            let cross = [
                [0.0, -w.k[2], w.k[1]],
                [w.k[2], 0.0, -w.k[0]],
                [-w.k[1], w.k[0], 0.0],
            ];
            for m in 0..3 {
                for j in 0..3 {
                    out.of[m][j] += of * cross[m][j];
                    // UL^{ab}_{jm} = (1/2) eps_{m n j} k_n f_a g sin / eta
                    out.ul[j][m] += ul * cross[m][j];
                }
            }
        }
    }
}

/// The rows of `A(k)` of [`Ewald::reciprocal_grand`] for a sphere of radius `a`: the
/// Faxén functionals of `U`, `Omega` and `E` (grand order) on a velocity `exp(i k.x)
/// e_i`, index `i` last.
pub(super) fn functionals(k: [f64; 3], k2: f64, a: f64) -> [[Complex64; 3]; 11] {
    let (f, g) = (1.0 - a * a * k2 / 6.0, 1.0 - a * a * k2 / 10.0);
    let ik = |n: usize| Complex64::new(0.0, k[n]);
    std::array::from_fn(|al| {
        std::array::from_fn(|i| match al {
            0..3 => Complex64::from(if al == i { f } else { 0.0 }),
            3..6 => {
                // (1/2) eps_m n i (i k_n)
                let m = al - 3;
                (0..3).map(|n| 0.5 * levi_civita(m, n, i) * ik(n)).sum()
            }
            _ => {
                let basis = &STRAIN_BASIS[al - 6];
                (0..3).map(|q| g * basis[i][q] * ik(q)).sum()
            }
        })
    })
}

/// `eps_ijk`, right-handed.
pub(super) fn levi_civita(i: usize, j: usize, k: usize) -> f64 {
    ((i as f64 - j as f64) * (j as f64 - k as f64) * (k as f64 - i as f64)) / 2.0
}

fn norm2(v: &[f64; 3]) -> f64 {
    v[0] * v[0] + v[1] * v[1] + v[2] * v[2]
}
