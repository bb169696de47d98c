//! The reciprocal part of the Ewald sum ([`super::ewald`]) applied to forces and
//! torques by spectral Ewald (Lindbo & Tornberg, J. Comput. Phys. 229, 8994 (2010);
//! the positively split Ewald of Fiore et al., J. Chem. Phys. 146, 124116 (2017), is the
//! same construction): `O(N P^3 + M^3 log M)` instead of the direct sum's `O(N^2 n_k)`.
//!
//! The screening `exp(-k^2/(4 xi^2))` of every reciprocal symbol is split into three
//! Gaussians, `exp(-e k^2/(8 xi^2)) exp(-(1 - e) k^2/(4 xi^2)) exp(-e k^2/(8 xi^2))`,
//! `0 < e < 1`:
//!
//! 1. spread: each sphere's force (and torque) onto a uniform grid of `M_d` points along
//!    each axis, with the Gaussian `g(x) = (2 pi s^2)^(-3/2) exp(-|x|^2/(2 s^2))`, `s^2 =
//!    e/(4 xi^2)` (the Fourier transform of `g` is the first factor), truncated to the
//!    `P^3` grid points nearest the sphere and summed over the periodic images;
//! 2. FFT; multiply by the symbols of [`super::ewald`] with `exp(-(1 - e) k^2/(4 xi^2))`
//!    in place of the screening; inverse FFT;
//! 3. interpolate: the velocity of a sphere is the grid's field integrated against the
//!    same Gaussian centred on it (the trapezoidal rule, weight `h_x h_y h_z`).
//!
//! Faxén operators: the source's `1 - a_b^2 k^2/6` and the field point's `1 - a_a^2
//! k^2/6` are part of the symbol when every radius is the same; otherwise each sphere
//! spreads `F_b` and `a_b^2 F_b/6` (two grids, the second multiplied by `-k^2`), and each
//! velocity is interpolated from `U` and `-k^2 U/6` (the second weighted by `a_a^2`).
//!
//! Grid and window, from the tolerance `tol`:
//!
//! - `M_d = ceil(k_c L_d/pi) + 2` rounded up to a product of 2, 3, 5 and 7, so that the
//!   wave vectors `|n_d| <= M_d/2 - 1` reach `k_c = 2 xi p` (`p` of
//!   [`super::ewald::truncation_parameter`], the direct sum's cut-off); the Nyquist
//!   modes are left out (the curl's symbol is odd);
//! - the window: `P` points, half-width `w = P h/2` (`h` the largest spacing), shape `m =
//!   w/s`, so `e = 4 xi^2 s^2 = (P h xi/m)^2`. Cutting the Gaussian at `w` leaves about
//!   `exp(-m^2/2)`; the grid's aliasing about `exp(-(pi^2 P^2/(2 m^2)) (1 - e/2))`
//!   (Lindbo & Tornberg 2010, Sec. 4, and J. Comput. Phys. 230, 8744 (2011): their
//!   `exp(-pi^2 P^2/(2 m^2))` at `k = 0`; the factor `1 - e/2` is the worst wave number
//!   once the middle Gaussian `exp(-(1 - e) k^2/(4 xi^2))` is all that damps the
//!   aliased modes). `m` balances the two (bisection), and `P` is the fewest points
//!   with `100 exp(-m^2/2) <= tol`, the prefactor measured against the direct sum (`P =
//!   13` to `14` at `1e-6`, `19` to `21` at `1e-10`): the product is within a third of
//!   the tolerance of the dense matrix's, relative to the largest entry of the result
//!   (tests `periodic::spectral`); without the factor `1 - e/2` (`m = sqrt(pi
//!   P)`, Lindbo & Tornberg's balance) the same `P` left two to three times more.
//!
//! Determinism: the grid is spread x-plane by x-plane (each plane summed over the
//! spheres whose window covers it, in a fixed order), the transforms line by line
//! ([`super::fft`]), the symbols point by point and the interpolation sphere by
//! sphere: no sum depends on the number of threads.

use super::ewald::truncation_parameter;
use super::fft::Fft3;
use crate::system::input::Particle;
use kernels::STRAIN_BASIS;
use rayon::prelude::*;
use rustfft::num_complex::Complex64;
use rustfft::FftDirection;
use std::f64::consts::PI;

/// Each sphere's velocity, angular velocity and strain rate (five components).
pub(crate) type Responses = (Vec<[f64; 3]>, Vec<[f64; 3]>, Vec<[f64; 5]>);

/// The grid and window of one box at one split and tolerance.
#[derive(Clone, Debug)]
pub(crate) struct Spectral {
    pub(crate) lengths: [f64; 3],
    pub(crate) xi: f64,
    /// Grid points along each axis.
    pub(crate) m: [usize; 3],
    pub(crate) h: [f64; 3],
    /// Window points along each axis (`P` along the widest spacing).
    support: [usize; 3],
    /// The Gaussian's variance `s^2`.
    pub(crate) s2: f64,
    /// The split `e` of the screening.
    pub(crate) split: f64,
}

/// The shape `m` of a window of `p` points at `xi h = xh` that balances its truncation
/// `exp(-m^2/2)` and aliasing `exp(-(pi^2 p^2/(2 m^2)) (1 - e/2))`, `e = (p xh/m)^2`
/// (module docs); the balance is monotone in `m`, found by bisection.
fn balance(p: usize, xh: f64) -> f64 {
    let p = p as f64;
    let excess = |m: f64| {
        let e = (p * xh / m).powi(2);
        0.5 * m * m - PI * PI * p * p / (2.0 * m * m) * (1.0 - 0.5 * e)
    };
    let (mut lo, mut hi) = (p * xh * (1.0 + 1e-9), 10.0 * p.sqrt() + p * xh);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if excess(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The window at tolerance `tol` for `xi h = xh`: the fewest points `P` (at least 4)
/// whose balanced shape `m` leaves `WINDOW exp(-m^2/2) <= tol`, and that `m`.
fn shape(tol: f64, xh: f64) -> (usize, f64) {
    (4..64)
        .map(|p| (p, balance(p, xh)))
        .find(|&(_, m)| WINDOW * (-0.5 * m * m).exp() <= tol)
        .unwrap_or((64, balance(64, xh)))
}

/// The prefactor of the window's error estimate, measured against the direct sum
/// (module docs).
const WINDOW: f64 = 100.0;

/// The smallest product of 2, 3, 5 and 7 at least `n` (fast FFT lengths).
fn smooth(n: usize) -> usize {
    (n.max(1)..)
        .find(|&m| {
            let mut r = m;
            for f in [2, 3, 5, 7] {
                while r % f == 0 {
                    r /= f;
                }
            }
            r == 1
        })
        .unwrap_or(n)
}

/// One sphere's window: its first grid point and the Gaussian's weight at each of its
/// points, along each axis.
pub(crate) struct Window {
    first: [usize; 3],
    /// The grid indices of the window's points (wrapped), along each axis.
    index: [Vec<usize>; 3],
    weights: [Vec<f64>; 3],
}

impl Window {
    /// The number of grid points it covers.
    pub(crate) fn points(&self) -> usize {
        self.index.iter().map(Vec::len).product()
    }
}

/// The contiguous runs `(first grid index, first window point, length)` of a window of
/// `p` points from grid index `first` on a periodic axis of `m` points.
fn runs(first: usize, p: usize, m: usize) -> impl Iterator<Item = (usize, usize, usize)> {
    let mut next = (first, 0);
    std::iter::from_fn(move || {
        let (i, j) = next;
        (j < p).then(|| {
            let len = (m - i).min(p - j);
            next = (0, j + len);
            (i, j, len)
        })
    })
}

/// The wave number of FFT index `i` of `m`, in units of `2 pi/L`; `None` for the
/// Nyquist mode.
pub(crate) fn signed(i: usize, m: usize) -> Option<f64> {
    if 2 * i == m {
        None
    } else if 2 * i < m {
        Some(i as f64)
    } else {
        Some(i as f64 - m as f64)
    }
}

impl Spectral {
    /// The grid and window of the box `lengths` for splitting parameter `xi` at
    /// tolerance `tol`.
    pub(crate) fn new(lengths: [f64; 3], xi: f64, tol: f64) -> Spectral {
        Spectral::with_cut(lengths, xi, tol, 2.0 * xi * truncation_parameter(tol))
    }

    /// The grid and window of the box `lengths` for splitting parameter `xi` at
    /// tolerance `tol`, resolving the wave vectors up to `k_cut`.
    pub(crate) fn with_cut(lengths: [f64; 3], xi: f64, tol: f64, k_cut: f64) -> Spectral {
        let m: [usize; 3] =
            std::array::from_fn(|d| smooth((k_cut * lengths[d] / PI).ceil() as usize + 2));
        let h: [f64; 3] = std::array::from_fn(|d| lengths[d] / m[d] as f64);
        let widest = h.iter().fold(0.0f64, |a, &b| a.max(b));
        let (p, shape) = shape(tol, xi * widest);
        let w = 0.5 * p as f64 * widest;
        let s2 = (w / shape).powi(2);
        let split = 4.0 * xi * xi * s2;
        assert!(
            split < 1.0,
            "the window is wider than the screening: e = {split}"
        );
        // the same half-width along every axis (P points along the widest spacing)
        let support = std::array::from_fn(|d| ((2.0 * w / h[d]) * (1.0 - 1e-12)).ceil() as usize);
        Spectral {
            lengths,
            xi,
            m,
            h,
            support,
            s2,
            split,
        }
    }

    /// A grid along `x` and `y` only (one point along `z`, where a window is one point of
    /// weight 1 at `x3 = 0`): the Gaussian gridding of a two-dimensional non-uniform
    /// Fourier transform of the wave vectors `|k| <= k_cut` of the box `lengths` to
    /// relative error `tol`, oversampled twice (`2 pi/h >= 4 k_cut`). Its Gaussian
    /// `exp(-|x|^2/(2 s^2))`, `s = h sqrt(ln(100/tol))/pi`, aliases `exp(-s^2 (2 pi/h)^2/4)
    /// = tol/100` at `k_cut` once divided by its transform, and is cut where it is
    /// `(tol/100)^(3/2)` (the division amplifies the cut by up to `(100/tol)^(1/4)`):
    /// `P = (2 sqrt(3)/pi) ln(100/tol)` points. `xi` and `split` are not used.
    pub(crate) fn lateral(lengths: [f64; 2], tol: f64, k_cut: f64) -> Spectral {
        let m: [usize; 3] = [
            smooth((4.0 * k_cut * lengths[0] / (2.0 * PI)).ceil() as usize + 2),
            smooth((4.0 * k_cut * lengths[1] / (2.0 * PI)).ceil() as usize + 2),
            1,
        ];
        let lengths = [lengths[0], lengths[1], 1.0];
        let h: [f64; 3] = std::array::from_fn(|d| lengths[d] / m[d] as f64);
        let widest = h[0].max(h[1]);
        let log = (100.0 / tol).ln();
        let s = widest * log.sqrt() / PI;
        let w = s * (3.0 * log).sqrt();
        let support = [
            ((2.0 * w / h[0]).ceil() as usize).min(m[0]),
            ((2.0 * w / h[1]).ceil() as usize).min(m[1]),
            1,
        ];
        Spectral {
            lengths,
            xi: 0.0,
            m,
            h,
            support,
            s2: s * s,
            split: 0.0,
        }
    }

    pub(crate) fn window(&self, x: [f64; 3]) -> Window {
        let mut index: [Vec<usize>; 3] = Default::default();
        let mut weights: [Vec<f64>; 3] = Default::default();
        for d in 0..3 {
            let l = self.lengths[d];
            let xw = x[d] - l * (x[d] / l).floor();
            let (p, m) = (self.support[d] as i64, self.m[d] as i64);
            let i0 = (xw / self.h[d] - 0.5 * p as f64).floor() as i64 + 1;
            for i in i0..i0 + p {
                let r = i as f64 * self.h[d] - xw;
                index[d].push(i.rem_euclid(m) as usize);
                weights[d].push((-r * r / (2.0 * self.s2)).exp());
            }
        }
        Window {
            first: [index[0][0], index[1][0], index[2][0]],
            index,
            weights,
        }
    }

    /// The reciprocal part of the velocities (and angular velocities) of spheres `ps`
    /// in a fluid of viscosity `eta` under `forces` (and `torques`): `(U, Omega)`,
    /// `Omega` empty without torques.
    pub(crate) fn apply(
        &self,
        eta: f64,
        ps: &[Particle],
        forces: &[[f64; 3]],
        torques: Option<&[[f64; 3]]>,
    ) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
        let n = ps.len();
        let equal = ps.iter().all(|p| p.a == ps[0].a);
        let ft = torques.is_some();
        // the real fields spread: F, a^2 F/6 (unequal radii), T
        let sources: Vec<Vec<f64>> = (0..n)
            .map(|b| {
                let mut q = forces[b].to_vec();
                if !equal {
                    q.extend(forces[b].map(|f| ps[b].a * ps[b].a * f / 6.0));
                }
                if let Some(t) = torques {
                    q.extend(t[b]);
                }
                q
            })
            .collect();
        let n_in = sources.first().map_or(0, |q| q.len());
        let n_out: usize = 3 + if equal { 0 } else { 3 } + if ft { 3 } else { 0 };
        let (g_in, g_out) = (n_in.div_ceil(2), n_out.div_ceil(2));
        let windows: Vec<Window> = ps.par_iter().map(|p| self.window(p.x)).collect();
        let a0 = ps.first().map_or(0.0, |p| p.a);
        let radius = if equal { Some(a0) } else { None };
        let fields = self.convolve(&windows, &sources, g_in, g_out, |grid| {
            self.symbols(eta, grid, g_in, g_out, radius, ft)
        });
        let u = (0..n)
            .map(|a| {
                let f = &fields[a];
                let a2 = ps[a].a * ps[a].a;
                std::array::from_fn(|i| if equal { f[i] } else { f[i] + a2 * f[3 + i] })
            })
            .collect();
        let omega = if ft {
            let o = n_out - 3;
            fields.iter().map(|f| [f[o], f[o + 1], f[o + 2]]).collect()
        } else {
            Vec::new()
        };
        (u, omega)
    }

    /// The reciprocal part of the FTS product: `(U, Omega, E)` of spheres `ps` in a fluid
    /// of viscosity `eta` under `forces`, `torques` and `stresslets` (the strain rates'
    /// and stresslets' five components in the basis of `kernels::STRAIN_BASIS`). Each
    /// sphere spreads `F`, `L`, `S` (and `a^2 F/6`, `a^2 S/10` where the radii differ);
    /// the sources' symbol is the field point's functionals at `-k` applied to them
    /// ([`super::ewald::Ewald::reciprocal_grand`]), `s = f_b F + (i/2) k x L - i g_b sum_p
    /// S_p B_p k`, `u = g (I - khat khat) s`, and the field point's fields `U = f_a u`,
    /// `Omega = (1/2) i k x u`, `E_p = i g_a (B_p k) . u` (`f = 1 - a^2 k^2/6`, `g = 1 -
    /// a^2 k^2/10`; where the radii differ, `U`'s and `E`'s parts without and with the
    /// `-k^2` factor, weighted by `a^2/6` and `a^2/10` at interpolation).
    pub(crate) fn apply_fts(
        &self,
        eta: f64,
        ps: &[Particle],
        forces: &[[f64; 3]],
        torques: &[[f64; 3]],
        stresslets: &[[f64; 5]],
    ) -> Responses {
        let n = ps.len();
        let a0 = ps.first().map_or(0.0, |p| p.a);
        let equal = ps.iter().all(|p| p.a == a0).then_some(a0);
        // F, L, S, [a^2 F/6, a^2 S/10]
        let sources: Vec<Vec<f64>> = (0..n)
            .map(|b| {
                let a2 = ps[b].a * ps[b].a;
                let mut q: Vec<f64> = forces[b]
                    .iter()
                    .chain(&torques[b])
                    .chain(&stresslets[b])
                    .copied()
                    .collect();
                if equal.is_none() {
                    q.extend(forces[b].map(|f| a2 * f / 6.0));
                    q.extend(stresslets[b].map(|v| a2 * v / 10.0));
                }
                q
            })
            .collect();
        // U, Omega, E, [-k^2 U/6, -k^2 E/10]
        let (n_in, n_out): (usize, usize) = match equal {
            Some(_) => (11, 11),
            None => (19, 19),
        };
        let (g_in, g_out) = (n_in.div_ceil(2), n_out.div_ceil(2));
        let windows: Vec<Window> = ps.par_iter().map(|p| self.window(p.x)).collect();
        let fields = self.convolve(&windows, &sources, g_in, g_out, |grid| {
            self.symbols_fts(eta, grid, g_in, g_out, equal)
        });
        let mut u = Vec::with_capacity(n);
        let mut omega = Vec::with_capacity(n);
        let mut e = Vec::with_capacity(n);
        for (p, f) in ps.iter().zip(&fields) {
            let a2 = p.a * p.a;
            let extra = |o: usize| if equal.is_some() { 0.0 } else { a2 * f[o] };
            u.push(std::array::from_fn(|d| f[d] + extra(11 + d)));
            omega.push(std::array::from_fn(|d| f[3 + d]));
            e.push(std::array::from_fn(|q| f[6 + q] + extra(14 + q)));
        }
        (u, omega, e)
    }

    /// The stack of `g_out` grids of output fields from the stack `input` of `g_in` grids,
    /// wave vector by wave vector (x-plane by x-plane in parallel, each point on its own):
    /// at every `k != 0` of the grid, neither of whose components is a Nyquist mode, that
    /// `keep(k_x, k_y)` accepts, `point(k, k^2, g, spectrum, fields)` writes the `2 g_out`
    /// real output fields' spectra into `fields` (packed two per grid), where `g` is the
    /// quadratures' and the Fourier series' normalisation times the middle Gaussian
    /// `exp(-(1 - e) k^2/(4 xi^2))` and `spectrum(f, mirrored)` the spectrum of real input
    /// field `f` (from grid `f/2` at `k` and `-k`) at `k`, or at `(k_x, k_y, -k_z)`.
    pub(crate) fn each_wave(
        &self,
        input: &[Complex64],
        g_in: usize,
        g_out: usize,
        keep: impl Fn(f64, f64) -> bool + Sync,
        point: impl Fn([f64; 3], f64, f64, &dyn Fn(usize, bool) -> Complex64, &mut [Complex64]) + Sync,
    ) -> Vec<Complex64> {
        let [mx, my, mz] = self.m;
        let plane = my * mz;
        let volume = self.lengths.iter().product::<f64>();
        let cell = self.h.iter().product::<f64>();
        // h^3 for each of the two quadratures, 1/V of the Fourier series, g's norm twice
        let norm = cell * cell / volume / (2.0 * PI * self.s2).powi(3);
        let c = (1.0 - self.split) / (4.0 * self.xi * self.xi);
        // per-axis wave numbers and screenings (`None`: Nyquist)
        let axes: [Vec<Option<(f64, f64)>>; 3] = std::array::from_fn(|d| {
            (0..self.m[d])
                .map(|i| {
                    signed(i, self.m[d]).map(|s| {
                        let k = 2.0 * PI * s / self.lengths[d];
                        (k, (-c * k * k).exp())
                    })
                })
                .collect()
        });
        let at = |ix: usize, g: usize, iy: usize, iz: usize| {
            input[(ix * g_in + g) * plane + iy * mz + iz]
        };
        let i = Complex64::new(0.0, 1.0);
        let mut out = vec![Complex64::default(); mx * g_out * plane];
        out.par_chunks_mut(g_out * plane)
            .enumerate()
            .for_each(|(ix, chunk)| {
                let nx = (mx - ix) % mx;
                let Some((kx, ex)) = axes[0][ix] else { return };
                let mut fields = vec![Complex64::default(); 2 * g_out];
                for iy in 0..my {
                    let ny = (my - iy) % my;
                    let Some((ky, ey)) = axes[1][iy] else {
                        continue;
                    };
                    if !keep(kx, ky) {
                        continue;
                    }
                    for iz in 0..mz {
                        let nz = (mz - iz) % mz;
                        let Some((kz, ez)) = axes[2][iz] else {
                            continue;
                        };
                        let k2 = kx * kx + ky * ky + kz * kz;
                        if k2 == 0.0 {
                            continue;
                        }
                        // the spectrum of real field f at (ix, iy, jz), from grid f/2 at k
                        // and -k
                        let spectrum = |f: usize, mirrored: bool| {
                            let (jz, mjz) = if mirrored { (nz, iz) } else { (iz, nz) };
                            let (a, b) = (at(ix, f / 2, iy, jz), at(nx, f / 2, ny, mjz).conj());
                            if f.is_multiple_of(2) {
                                (a + b) * 0.5
                            } else {
                                (a - b) * Complex64::new(0.0, -0.5)
                            }
                        };
                        fields.fill(Complex64::default());
                        point(
                            [kx, ky, kz],
                            k2,
                            norm * ex * ey * ez,
                            &spectrum,
                            &mut fields,
                        );
                        for gi in 0..g_out {
                            chunk[gi * plane + iy * mz + iz] =
                                fields[2 * gi] + fields[2 * gi + 1] * i;
                        }
                    }
                }
            });
        out
    }

    /// The FTS symbols ([`Spectral::apply_fts`]): from the stack `input` of `g_in` grids
    /// the stack of `g_out` grids of the field point's fields.
    fn symbols_fts(
        &self,
        eta: f64,
        input: &[Complex64],
        g_in: usize,
        g_out: usize,
        equal: Option<f64>,
    ) -> Vec<Complex64> {
        let i = Complex64::new(0.0, 1.0);
        let xi2 = self.xi * self.xi;
        let keep = |_: f64, _: f64| true;
        self.each_wave(input, g_in, g_out, keep, |k, k2, norm, spectrum, fields| {
            let field = |f: usize| spectrum(f, false);
            // B_p k for each strain basis element
            let bk: [[f64; 3]; 5] = std::array::from_fn(|p| {
                let b = &STRAIN_BASIS[p];
                std::array::from_fn(|r| (0..3).map(|q| b[r][q] * k[q]).sum())
            });
            // the sources' symbol
            let mut src = [Complex64::default(); 3];
            for d in 0..3 {
                let (f, s_part) = match equal {
                    Some(a) => (field(d) * (1.0 - a * a * k2 / 6.0), 1.0 - a * a * k2 / 10.0),
                    None => (field(d) - field(11 + d) * k2, 1.0),
                };
                src[d] += f;
                // -i g_b sum_p S_p (B_p k)_d
                let mut st = Complex64::default();
                for (p, b) in bk.iter().enumerate() {
                    st += match equal {
                        Some(_) => field(6 + p) * s_part,
                        None => field(6 + p) - field(14 + p) * k2,
                    } * b[d];
                }
                src[d] -= i * st;
            }
            let l: [Complex64; 3] = std::array::from_fn(|d| field(3 + d));
            let kl = [
                l[2] * k[1] - l[1] * k[2],
                l[0] * k[2] - l[2] * k[0],
                l[1] * k[0] - l[0] * k[1],
            ];
            for d in 0..3 {
                // (i/2) k x L
                src[d] += kl[d] * (0.5 * i);
            }
            let q = k2 / (4.0 * xi2);
            let g = norm * (1.0 + q + 2.0 * q * q) / (eta * k2);
            let ks = (src[0] * k[0] + src[1] * k[1] + src[2] * k[2]) / k2;
            let u: [Complex64; 3] = std::array::from_fn(|d| (src[d] - ks * k[d]) * g);
            let (fa, ga) = match equal {
                Some(a) => (1.0 - a * a * k2 / 6.0, 1.0 - a * a * k2 / 10.0),
                None => (1.0, 1.0),
            };
            for d in 0..3 {
                fields[d] = u[d] * fa;
            }
            let ku = [
                u[2] * k[1] - u[1] * k[2],
                u[0] * k[2] - u[2] * k[0],
                u[1] * k[0] - u[0] * k[1],
            ];
            for d in 0..3 {
                fields[3 + d] = ku[d] * (0.5 * i);
            }
            for (p, b) in bk.iter().enumerate() {
                let bu: Complex64 = (0..3).map(|r| u[r] * b[r]).sum();
                fields[6 + p] = bu * i * ga;
            }
            if equal.is_none() {
                for d in 0..3 {
                    fields[11 + d] = u[d] * (-k2 / 6.0);
                }
                for p in 0..5 {
                    fields[14 + p] = fields[6 + p] * (-k2 / 10.0);
                }
            }
        })
    }

    /// Spectral Ewald's pipeline: the real fields `sources[b]` spread with the spheres'
    /// `windows` onto `g_in` grids, transformed, taken by `symbols` to `g_out` grids,
    /// transformed back, and each sphere's `2 g_out` real fields interpolated.
    pub(crate) fn convolve(
        &self,
        windows: &[Window],
        sources: &[Vec<f64>],
        g_in: usize,
        g_out: usize,
        symbols: impl FnOnce(&[Complex64]) -> Vec<Complex64>,
    ) -> Vec<Vec<f64>> {
        let mut grid = self.spread(windows, sources, g_in);
        Fft3::new(self.m, g_in, FftDirection::Forward).process(&mut grid);
        let mut out = symbols(&grid);
        drop(grid);
        Fft3::new(self.m, g_out, FftDirection::Inverse).process(&mut out);
        windows
            .par_iter()
            .map(|w| self.interpolate(w, &out, g_out))
            .collect()
    }

    /// The stack of `grids` complex grids holding the real fields `sources[b][f]`
    /// (field `2c` the real part of grid `c`, `2c + 1` its imaginary part), spread with
    /// the windows, x-plane by x-plane.
    pub(crate) fn spread(
        &self,
        windows: &[Window],
        sources: &[Vec<f64>],
        grids: usize,
    ) -> Vec<Complex64> {
        let [mx, my, mz] = self.m;
        let px = self.support[0];
        let plane = my * mz;
        // the spheres by the first x-plane of their windows
        let mut by_first = vec![Vec::new(); mx];
        for (b, w) in windows.iter().enumerate() {
            by_first[w.first[0]].push(b);
        }
        let mut grid = vec![Complex64::default(); mx * grids * plane];
        grid.par_chunks_mut(grids * plane)
            .enumerate()
            .for_each(|(ix, chunk)| {
                for j in 0..px {
                    for &b in &by_first[(ix + mx * px - j) % mx] {
                        let w = &windows[b];
                        let q = &sources[b];
                        let wx = w.weights[0][j];
                        for (&iy, &wy) in w.index[1].iter().zip(&w.weights[1]) {
                            let wxy = wx * wy;
                            for c in 0..grids {
                                let re = wxy * q[2 * c];
                                let im = wxy * q.get(2 * c + 1).copied().unwrap_or(0.0);
                                let row = &mut chunk[c * plane + iy * mz..][..mz];
                                for (z0, j0, len) in runs(w.first[2], w.weights[2].len(), mz) {
                                    let ws = &w.weights[2][j0..j0 + len];
                                    for (v, &wz) in row[z0..z0 + len].iter_mut().zip(ws) {
                                        *v += Complex64::new(wz * re, wz * im);
                                    }
                                }
                            }
                        }
                    }
                }
            });
        grid
    }

    /// The fields of one window: `2 grids` real values (the real and imaginary parts of
    /// each grid), integrated against the window.
    pub(crate) fn interpolate(&self, w: &Window, grid: &[Complex64], grids: usize) -> Vec<f64> {
        let [_, my, mz] = self.m;
        let plane = my * mz;
        let mut acc = vec![Complex64::default(); grids];
        for (&ix, &wx) in w.index[0].iter().zip(&w.weights[0]) {
            for (&iy, &wy) in w.index[1].iter().zip(&w.weights[1]) {
                let wxy = wx * wy;
                for (c, a) in acc.iter_mut().enumerate() {
                    let row = &grid[(ix * grids + c) * plane + iy * mz..][..mz];
                    let mut sum = Complex64::default();
                    for (z0, j0, len) in runs(w.first[2], w.weights[2].len(), mz) {
                        let ws = &w.weights[2][j0..j0 + len];
                        for (v, &wz) in row[z0..z0 + len].iter().zip(ws) {
                            sum += v * wz;
                        }
                    }
                    *a += sum * wxy;
                }
            }
        }
        acc.iter().flat_map(|a| [a.re, a.im]).collect()
    }

    /// The transformed fields times the symbols: from the stack `input` (`g_in` grids:
    /// `F`, `a^2 F/6` unless `equal` gives the one radius, `T` if `ft`) the stack of
    /// `g_out` grids (`U`, `-k^2 U/6` unless `equal`, `Omega` if `ft`).
    fn symbols(
        &self,
        eta: f64,
        input: &[Complex64],
        g_in: usize,
        g_out: usize,
        equal: Option<f64>,
        ft: bool,
    ) -> Vec<Complex64> {
        let n_out = 3 + if equal.is_some() { 0 } else { 3 } + if ft { 3 } else { 0 };
        let i = Complex64::new(0.0, 1.0);
        let keep = |_: f64, _: f64| true;
        self.each_wave(input, g_in, g_out, keep, |k, k2, norm, spectrum, fields| {
            let field = |f: usize| spectrum(f, false);
            let faxen = equal.map(|a| 1.0 - a * a * k2 / 6.0);
            let force: [Complex64; 3] = std::array::from_fn(|d| match faxen {
                Some(f) => field(d) * f,
                None => field(d) - field(3 + d) * k2,
            });
            let q = k2 / (4.0 * self.xi * self.xi);
            let g = norm * (1.0 + q + 2.0 * q * q) / (eta * k2);
            let project = |v: [Complex64; 3]| {
                let kv = (v[0] * k[0] + v[1] * k[1] + v[2] * k[2]) / k2;
                [v[0] - kv * k[0], v[1] - kv * k[1], v[2] - kv * k[2]]
            };
            let curl = |v: [Complex64; 3]| {
                [
                    (v[2] * k[1] - v[1] * k[2]) * i,
                    (v[0] * k[2] - v[2] * k[0]) * i,
                    (v[1] * k[0] - v[0] * k[1]) * i,
                ]
            };
            let pf = project(force);
            let mut u: [Complex64; 3] = std::array::from_fn(|d| pf[d] * g);
            // U (times the field point's Faxén factor, or with -k^2 U/6), then Omega
            if ft {
                let o = if equal.is_some() { 3 } else { 6 };
                let torque: [Complex64; 3] = std::array::from_fn(|d| field(o + d));
                let (ct, cf, pt) = (curl(torque), curl(force), project(torque));
                for d in 0..3 {
                    u[d] += ct[d] * (0.5 * g);
                    fields[n_out - 3 + d] = cf[d] * (0.5 * g) + pt[d] * (0.25 * g * k2);
                }
            }
            for d in 0..3 {
                match faxen {
                    Some(f) => fields[d] = u[d] * f,
                    None => {
                        fields[d] = u[d];
                        fields[3 + d] = u[d] * (-k2 / 6.0);
                    }
                }
            }
        })
    }
}
