//! The low lateral modes `0 < |k_par| < K1` of the reciprocal part along a periodic wall
//! ([`super::wall`]), each on its own and exact in `z`, so that the grid of
//! [`super::wall_spectral`] holds only `|k_par| >= K1` and its padding is `D =
//! ln(100/tol)/K1` instead of `ln(100/tol)/K0`, `K0 = 2 pi/max(Lx, Ly)`.
//!
//! **Why the padding.** A lateral mode `k_par` of the reciprocal part decays like
//! `exp(-|k_par| |z|)` away from its sources, so the trapezoidal sum in `k_z` (the box
//! periodic in `z`, [`super::wall::reciprocal_box`]) needs a padding of `ln(1/tol)/|k_par|`:
//! only the few modes with `|k_par|` near `K0` need the long box. Each of them here has
//! its own trapezoidal sum in `k_z`, of height `Lz'(|k_par|) = s + D(|k_par|)`
//! ([`super::wall::reciprocal_box`] at `k_low = |k_par|`, `s = 2 h_max`): the dense
//! blocks' sum with a padding of their own, and as exact.
//!
//! **Exact lateral phases, the heights interpolated.** The mode `k_par` of the velocity
//! of sphere `a` is `exp(i k_par . x_a) sum_kz exp(i k_z h_a) G(k) s(k)` with the
//! sources' spectrum `s(k) = sum_b exp(-i k_par . x_b) [exp(-i k_z h_b) q_b + exp(i k_z
//! h_b) T(k, h_b) q_b]` (the direct source at `h_b` and Blake's image at `-h_b`,
//! [`super::wall_spectral::Layout::symbol`]). Both phases in the heights are replaced by
//! their interpolants at `K` Chebyshev points `t_j` of the heights' interval (barycentric
//! basis `l_j`, [`super::plane_mode`]'s): `exp(-i k_z h_b) ~ sum_j l_j(h_b) exp(-i k_z
//! t_j)`, and the image's polynomial factors in `h_b` (`T` is quadratic in it) are
//! evaluated at the `t_j`. So each mode is `K` virtual sources at heights `t_j` with the
//! moments `Q_j = sum_b l_j(h_b) exp(-i k_par . x_b) q_b`, their `k_z` sum evaluated at
//! `K` virtual field points, and each sphere's velocity interpolated from those:
//! `O(N K)` per mode, `O(K n_z)` for its `n_z` terms of `k_z`.
//!
//! **`K`.** On an interval of half-width `w`, the interpolant of `exp(i k_z h)` at `K`
//! Chebyshev points of the second kind is within `4 (|k_z| w/2)^K/K!` (the remainder
//! `f^(K) prod (h - t_j)/K!`, `|prod| <= 2^(2 - K) w^K`); the symbol at `k_z` is screened
//! by `(1 + q + 2 q^2) exp(-q)`, `q = k_z^2/(4 xi^2)`, and the image's grows like `(1 + 2
//! h_max k)^2`. `K` is the fewest points whose bound times that weight is below a
//! thousandth of the tolerance at every `|k_z| <= k_c`; the source and the field point
//! each interpolate once. Where the heights need more than [`MAX_NODES`] points, no mode
//! is low (the grid alone, padded for `K0`).
//!
//! A mode and its opposite are conjugate (real sources): one of each pair is summed,
//! twice its real part taken. The lateral phases `exp(i k_par . x)`, `k_par = 2 pi
//! (n1/Lx, n2/Ly)`, are products of the powers of `exp(2 pi i x_d/L_d)` (one sine and
//! cosine per sphere and axis), and the moments of a block of modes are accumulated
//! together. Every sum is in a fixed order (the spheres in their order within a mode,
//! the modes in order within a sphere): the bits do not depend on the number of
//! threads.

use super::plane_mode::{interval, Nodes};
use super::wall::{lateral_waves, reciprocal_box, WallEwald};
use super::wall_spectral::Layout;
use crate::system::input::Particle;
use rayon::prelude::*;
use rustfft::num_complex::Complex64;
use std::f64::consts::PI;

/// The low lateral modes of one split and set of heights.
pub(crate) struct LowModes {
    sum: ModeSum,
    /// The height `Lz'` of each mode's sum in `k_z`.
    lz: Vec<f64>,
    k_cut: f64,
    xi: f64,
}

/// Lateral modes `k_par` summed each on its own, exact in the lateral phases, the
/// heights interpolated at Chebyshev points (module docs): the part shared by the
/// periodic wall's low modes and the periodic slit's remainder ([`super::slit`]), which
/// differ in what one mode does to its virtual sources.
pub(crate) struct ModeSum {
    /// One of each pair `+-k_par`.
    modes: Vec<Mode>,
    /// The largest `|n_d|` of the modes.
    nmax: [usize; 2],
    lengths: [f64; 2],
    pub(crate) nodes: Nodes,
    /// Heights are measured from the plane `x3 = height`.
    height: f64,
}

/// One mode: `k_par = 2 pi (n1/Lx, n2/Ly)`.
pub(crate) struct Mode {
    n: [i64; 2],
    pub(crate) k: [f64; 2],
}

/// The modes' moments accumulated together, this many at a time (each sphere's
/// weighted fields read once per block).
const BLOCK: usize = 8;

/// `exp(i k_par . x)` of mode `m` from the powers of `x` ([`LowModes::powers`]).
fn phase(m: &Mode, powers: &[Vec<Complex64>; 2]) -> Complex64 {
    let y = powers[1][m.n[1].unsigned_abs() as usize];
    powers[0][m.n[0].unsigned_abs() as usize] * if m.n[1] < 0 { y.conj() } else { y }
}

/// The modes `0 < |k_par| < k_low` (and `<= k_cut`) of the box `lengths`, one of each pair
/// `+-k_par`, in a fixed order.
pub(crate) fn low_waves(
    lengths: [f64; 2],
    k_cut: f64,
    k_low: f64,
) -> impl Iterator<Item = [f64; 2]> {
    lateral_waves(lengths, k_cut.min(k_low))
        .filter(move |k| k[0] * k[0] + k[1] * k[1] < k_low * k_low)
}

/// The number `K` of Chebyshev points on heights `[lo, hi]` for split `xi`, tolerance
/// `tol` and cut-off `k_cut` (module docs); `None` beyond [`MAX_NODES`].
pub(crate) fn node_count(xi: f64, tol: f64, k_cut: f64, lo: f64, hi: f64) -> Option<usize> {
    let (lo, hi) = interval(lo, hi);
    let w = 0.5 * (hi - lo);
    let samples = 64;
    // ln of the weight at each sampled k_z and of k_z w/2
    let points: Vec<(f64, f64)> = (1..=samples)
        .map(|s| {
            let k = k_cut * s as f64 / samples as f64;
            let q = k * k / (4.0 * xi * xi);
            let weight = (1.0 + q + 2.0 * q * q).ln() - q + 2.0 * (1.0 + 2.0 * hi * k).ln();
            (weight, (0.5 * k * w).ln())
        })
        .collect();
    let bound = (1e-3 * tol).ln() - 4f64.ln();
    let mut ln_factorial = 0.0;
    (1..=MAX_NODES).find(|&k| {
        ln_factorial += (k as f64).ln();
        k >= 4
            && points
                .iter()
                .all(|&(weight, ln_half)| weight + k as f64 * ln_half - ln_factorial <= bound)
    })
}

/// The most Chebyshev points the low modes take; spheres spread over more heights than
/// these resolve leave every mode `k_par != 0` to the grid.
pub(crate) const MAX_NODES: usize = 255;

impl LowModes {
    /// The modes `0 < |k_par| < k_low` of the split `wall` (its `xi` and tolerance) for
    /// spheres with heights in `[lo, hi]` above the wall, with `nodes` Chebyshev points
    /// ([`node_count`]).
    pub(crate) fn new(wall: &WallEwald, k_low: f64, lo: f64, hi: f64, nodes: usize) -> LowModes {
        let (lo, hi) = interval(lo, hi);
        let s = 2.0 * hi;
        let (k_cut, _) = wall.reciprocal_box(s);
        let waves: Vec<[f64; 2]> = low_waves(wall.lengths, k_cut, k_low).collect();
        let lz = waves
            .iter()
            .map(|k| {
                let kp = (k[0] * k[0] + k[1] * k[1]).sqrt();
                reciprocal_box(wall.xi, wall.tolerance, s, kp).1
            })
            .collect();
        let nodes = Nodes::new(nodes.max(4), lo, hi);
        LowModes {
            sum: ModeSum::new(wall.lengths, waves, nodes, wall.height),
            lz,
            k_cut,
            xi: wall.xi,
        }
    }

    /// Adds the modes' part of the field point's fields ([`Layout::symbol`]) of spheres
    /// `ps` in a fluid of viscosity `eta` under their direct sources `direct`
    /// ([`Layout::direct`]) to `fields`.
    pub(crate) fn add(
        &self,
        eta: f64,
        ps: &[Particle],
        layout: Layout,
        direct: &[Vec<f64>],
        fields: &mut [Vec<f64>],
    ) {
        self.sum.add(ps, layout.fields(), direct, fields, |m, q| {
            self.mode(eta, layout, m, q)
        });
    }

    /// One mode `m` (its sum in `k_z`): the field point's fields at the virtual field
    /// points, `[i][f]`, from the virtual sources' moments `q` (`[j][f]`).
    fn mode(&self, eta: f64, layout: Layout, m: usize, q: &[Complex64]) -> Vec<Complex64> {
        let nf = layout.fields();
        let t = &self.sum.nodes.t;
        let kn = t.len();
        let (k, lz) = (self.sum.modes[m].k, self.lz[m]);
        let lengths = self.sum.lengths;
        let images: Vec<Vec<Complex64>> = (0..kn)
            .map(|j| layout.image(&q[j * nf..(j + 1) * nf], t[j]))
            .collect();
        let kc2 = self.k_cut * self.k_cut;
        let kp2 = k[0] * k[0] + k[1] * k[1];
        let mmax = (self.k_cut * lz / (2.0 * PI)).floor() as i64;
        let xi2 = self.xi * self.xi;
        let scale = 1.0 / (eta * lengths[0] * lengths[1] * lz);
        let mut nodal = vec![Complex64::default(); kn * nf];
        let (mut sd, mut si) = ([Complex64::default(); 9], [Complex64::default(); 27]);
        for m in -mmax..=mmax {
            let kz = 2.0 * PI * m as f64 / lz;
            let k2 = kp2 + kz * kz;
            if k2 > kc2 {
                continue;
            }
            // exp(i k_z t_j)
            let phases: Vec<Complex64> = t
                .iter()
                .map(|&tj| {
                    let (s, c) = (kz * tj).sin_cos();
                    Complex64::new(c, s)
                })
                .collect();
            sd.fill(Complex64::default());
            si.fill(Complex64::default());
            for (j, e) in phases.iter().enumerate() {
                for (v, qv) in sd.iter_mut().zip(&q[j * nf..(j + 1) * nf]) {
                    *v += e.conj() * qv;
                }
                for (v, qv) in si.iter_mut().zip(&images[j]) {
                    *v += e * qv;
                }
            }
            let qq = k2 / (4.0 * xi2);
            let g = scale * (1.0 + qq + 2.0 * qq * qq) * (-qq).exp() / k2;
            let out = layout.symbol([k[0], k[1], kz], g, &sd, &si);
            for (i, e) in phases.iter().enumerate() {
                for (v, o) in nodal[i * nf..(i + 1) * nf].iter_mut().zip(&out) {
                    *v += e * o;
                }
            }
        }
        nodal
    }
}

impl ModeSum {
    /// The lateral modes `waves` of the box `lengths` (one of each pair `+-k_par`, in a
    /// fixed order) with the heights above the plane `x3 = height` interpolated at
    /// `nodes`.
    pub(crate) fn new(
        lengths: [f64; 2],
        waves: Vec<[f64; 2]>,
        nodes: Nodes,
        height: f64,
    ) -> ModeSum {
        let modes: Vec<Mode> = waves
            .into_iter()
            .map(|k| Mode {
                n: std::array::from_fn(|d| (k[d] * lengths[d] / (2.0 * PI)).round() as i64),
                k,
            })
            .collect();
        let nmax = std::array::from_fn(|d| {
            modes
                .iter()
                .map(|m| m.n[d].unsigned_abs() as usize)
                .max()
                .unwrap_or(0)
        });
        ModeSum {
            modes,
            nmax,
            lengths,
            nodes,
            height,
        }
    }

    /// The modes, in order.
    pub(crate) fn modes(&self) -> &[Mode] {
        &self.modes
    }

    /// The powers `exp(i n 2 pi x_d/L_d)`, `0 <= n <= nmax_d`, of position `x`, along `x`
    /// and along `y`: every mode's lateral phase is a product of two of them.
    fn powers(&self, x: [f64; 3]) -> [Vec<Complex64>; 2] {
        std::array::from_fn(|d| {
            let (s, c) = (2.0 * PI * x[d] / self.lengths[d]).sin_cos();
            let e = Complex64::new(c, s);
            let mut z = Complex64::new(1.0, 0.0);
            (0..=self.nmax[d])
                .map(|_| {
                    let v = z;
                    z *= e;
                    v
                })
                .collect()
        })
    }

    /// Adds the modes' part of `nf` fields at the field points of spheres `ps` under
    /// their `nf` source fields `direct` to `fields`: `nodal(m, q)` takes mode `m`'s
    /// virtual sources' moments `q` (`[j][f]`, node `j`) to its fields at the virtual
    /// field points (`[i][f]`).
    pub(crate) fn add(
        &self,
        ps: &[Particle],
        nf: usize,
        direct: &[Vec<f64>],
        fields: &mut [Vec<f64>],
        nodal: impl Fn(usize, &[Complex64]) -> Vec<Complex64> + Sync,
    ) {
        if self.modes.is_empty() {
            return;
        }
        // l_j(h_b) and l_j(h_b) q_b, [j][f]
        let (basis, weighted) = self.nodes.virtual_sources(ps, self.height, direct);
        let powers: Vec<[Vec<Complex64>; 2]> = ps.par_iter().map(|p| self.powers(p.x)).collect();
        // Q_j = sum_b exp(-i k_par . x_b) l_j(h_b) q_b, BLOCK modes at a time
        let moments: Vec<Vec<Vec<Complex64>>> = self
            .modes
            .par_chunks(BLOCK)
            .map(|block| {
                let mut q = vec![vec![Complex64::default(); weighted[0].len()]; block.len()];
                for (pw, w) in powers.iter().zip(&weighted) {
                    for (m, qm) in block.iter().zip(q.iter_mut()) {
                        let e = phase(m, pw).conj();
                        for (qv, &wv) in qm.iter_mut().zip(w) {
                            *qv += e * wv;
                        }
                    }
                }
                q
            })
            .collect();
        let moments: Vec<Vec<Complex64>> = moments.into_iter().flatten().collect();
        let nodal: Vec<Vec<Complex64>> = moments
            .par_iter()
            .enumerate()
            .map(|(m, q)| nodal(m, q))
            .collect();
        let kn = self.nodes.t.len();
        fields
            .par_iter_mut()
            .zip(powers.par_iter().zip(&basis))
            .for_each(|(out, (pw, l))| {
                for (m, v) in self.modes.iter().zip(&nodal) {
                    let e = phase(m, pw);
                    for (f, o) in out.iter_mut().enumerate().take(nf) {
                        let mut acc = Complex64::default();
                        for (i, li) in l.iter().enumerate().take(kn) {
                            acc += v[i * nf + f] * li;
                        }
                        *o += 2.0 * (e * acc).re;
                    }
                }
            });
    }
}
