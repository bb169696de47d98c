//! The reciprocal part of the Ewald sum along a periodic wall ([`super::wall`]) applied
//! to forces and torques by spectral Ewald ([`super::spectral`]'s grid, window and
//! transforms): the lateral wave vectors `k_par != 0` and the trapezoidal sum in `k_z`
//! are the wave vectors of a box also periodic in `z`, of height `Lz' = 2 h_max + D`,
//! `O(N P^3 + M log M)` for all pairs at once.
//!
//! Heights `z = x_3 - H` are measured from the wall. Each sphere is two sources on the
//! grid: the direct one at `y = (y_1, y_2, h)` and Blake's image at `y* = (y_1, y_2,
//! -h)`, whose symbol is `Jhat^K(k) T(k, h)` ([`super::wall`]): a force `F` at `y*` acts
//! as `T F = -F - h^2 k^2 P F - 2 i h (k . P F) e3`, `P = diag(1, 1, -1)`. `T` is
//! quadratic in the source's own height, so the image spreads `F`, `h^2 F` and `h F` on
//! grids of their own (multiplied in Fourier space by `-1`, `-k^2 P` and `-2 i e3 (k .
//! P)`). The source's operators act on the image's explicit heights too (`d/dy_3` of
//! `exp(-i k . y*) T(h)` is `i k_3 T + T'`):
//!
//! - the Faxén operator `1 + c lap_y`, `c = a^2/6`, adds `c [-k^2 T F + 2 i k_3 T' F +
//!   T'' F]`, that is `k^2 cF + k^4 P (c h^2 F) + 2 i k^2 (k . P (c h F)) e3 - 4 i k_3
//!   k^2 P (c h F) + 4 k_3 (k . P cF) e3 - 2 k^2 P cF` (the fields `cF`, `c h^2 F`, `c h
//!   F` on grids of their own when the radii differ; `c` times the grids above when they
//!   are equal);
//! - the rotlet `(1/2) curl_y` of a torque `L` gives `T w_1 + T' w_2` with `w_1 = (i/2)
//!   (P k x L)` and `w_2 = (1/2) (L x e3)`: the fields `L`, `h L`, `h^2 L` at `y*`.
//!
//! The sum of every source's symbol `s(k)` (the direct force times its Faxén factor, the
//! direct rotlet `(i/2) k x L`, the image terms) is projected, `u = g (I - khat khat)
//! s`, and the field point's operators are those of the triply periodic box: `U = (1 -
//! a_a^2 k^2/6) u`, `Omega = (i/2) k x u`.
//!
//! The modes `k_par = 0` (every `k_z`) are left out: the exact mode is
//! [`super::plane_mode`]'s. The box's height leaves the copies of every source at least
//! `D` from every field point, and a mode of lateral wave number `k_par` decays like
//! `exp(-k_par |z|)`: `k_c` and `D` are [`super::wall::WallEwald::reciprocal_box`]'s
//! for `h_a + h_b = 2 h_max`. The image's symbol carries up to `(h k_c)^2` more than the
//! direct one, so the window is chosen for the tolerance divided by `(1 + 2 h_max
//! k_c)^2`.
//!
//! Determinism as in [`super::spectral`]: every sum in a fixed order.

use super::fft::Fft3;
use super::spectral::{signed, Spectral, Window};
use super::wall::WallEwald;
use crate::system::input::Particle;
use rayon::prelude::*;
use rustfft::num_complex::Complex64;
use rustfft::FftDirection;
use std::f64::consts::PI;

/// The grid of the reciprocal part along a periodic wall.
pub(crate) struct WallSpectral {
    grid: Spectral,
    /// The wall's plane `x3 = height`.
    height: f64,
}

type V3 = [Complex64; 3];

fn add(a: V3, b: V3) -> V3 {
    std::array::from_fn(|d| a[d] + b[d])
}

fn scale(a: V3, s: Complex64) -> V3 {
    a.map(|v| v * s)
}

fn cross(a: [Complex64; 3], b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `P v`, `P = diag(1, 1, -1)`.
fn mirror(v: V3) -> V3 {
    [v[0], v[1], -v[2]]
}

/// `c e3`.
fn normal(c: Complex64) -> V3 {
    [Complex64::default(), Complex64::default(), c]
}

impl WallSpectral {
    /// The grid for the split `wall` (its `xi` and tolerance) of spheres whose heights
    /// above the wall are at most `h_max`.
    pub(crate) fn new(wall: &WallEwald, h_max: f64) -> WallSpectral {
        let (k_cut, lz) = wall.reciprocal_box(2.0 * h_max);
        let amplification = (1.0 + 2.0 * h_max * k_cut).powi(2);
        let lengths = [wall.lengths[0], wall.lengths[1], lz];
        WallSpectral {
            grid: Spectral::with_cut(lengths, wall.xi, wall.tolerance / amplification, k_cut),
            height: wall.height,
        }
    }

    /// The reciprocal part (`k_par != 0`) of the velocities (and angular velocities) of
    /// spheres `ps` in a fluid of viscosity `eta` under `forces` (and `torques`): `(U,
    /// Omega)`, `Omega` empty without torques.
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
        let h = |b: usize| ps[b].x[2] - self.height;
        let times = |v: [f64; 3], c: f64| v.map(|f| c * f);
        // the direct sources: F, [a^2 F/6], [L]
        let direct: Vec<Vec<f64>> = (0..n)
            .map(|b| {
                let mut q = forces[b].to_vec();
                if !equal {
                    q.extend(times(forces[b], ps[b].a * ps[b].a / 6.0));
                }
                if let Some(t) = torques {
                    q.extend(t[b]);
                }
                q
            })
            .collect();
        // the image sources: F, h^2 F, h F, [c F, c h^2 F, c h F], [L, h L, h^2 L]
        let image: Vec<Vec<f64>> = (0..n)
            .map(|b| {
                let (f, hb) = (forces[b], h(b));
                let mut q = [f, times(f, hb * hb), times(f, hb)].concat();
                if !equal {
                    let c = ps[b].a * ps[b].a / 6.0;
                    q.extend([times(f, c), times(f, c * hb * hb), times(f, c * hb)].concat());
                }
                if let Some(t) = torques {
                    q.extend([t[b], times(t[b], hb), times(t[b], hb * hb)].concat());
                }
                q
            })
            .collect();
        let n_direct = direct.first().map_or(0, |q| q.len());
        let n_image = image.first().map_or(0, |q| q.len());
        let n_out: usize = 3 + if equal { 0 } else { 3 } + if ft { 3 } else { 0 };
        let (g_direct, g_image, g_out) =
            (n_direct.div_ceil(2), n_image.div_ceil(2), n_out.div_ceil(2));
        let at = |z: f64, b: usize| [ps[b].x[0], ps[b].x[1], z];
        let direct_windows: Vec<Window> = (0..n)
            .into_par_iter()
            .map(|b| self.grid.window(at(h(b), b)))
            .collect();
        let image_windows: Vec<Window> = (0..n)
            .into_par_iter()
            .map(|b| self.grid.window(at(-h(b), b)))
            .collect();
        let mut direct_grid = self.grid.spread(&direct_windows, &direct, g_direct);
        Fft3::new(self.grid.m, g_direct, FftDirection::Forward).process(&mut direct_grid);
        let mut image_grid = self.grid.spread(&image_windows, &image, g_image);
        Fft3::new(self.grid.m, g_image, FftDirection::Forward).process(&mut image_grid);
        let a0 = ps.first().map_or(0.0, |p| p.a);
        let mut out = self.symbols(
            eta,
            (&direct_grid, g_direct),
            (&image_grid, g_image),
            g_out,
            equal.then_some(a0),
            ft,
        );
        drop(direct_grid);
        drop(image_grid);
        Fft3::new(self.grid.m, g_out, FftDirection::Inverse).process(&mut out);
        let fields: Vec<Vec<f64>> = direct_windows
            .par_iter()
            .map(|w| self.grid.interpolate(w, &out, g_out))
            .collect();
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

    /// The transformed sources times the symbols (module docs): from the stacks `direct`
    /// and `image` (each with its number of grids) the stack of `g_out` grids (`U`, `-k^2
    /// U/6` unless `equal` gives the one radius, `Omega` if `ft`).
    fn symbols(
        &self,
        eta: f64,
        direct: (&[Complex64], usize),
        image: (&[Complex64], usize),
        g_out: usize,
        equal: Option<f64>,
        ft: bool,
    ) -> Vec<Complex64> {
        let grid = &self.grid;
        let [mx, my, mz] = grid.m;
        let plane = my * mz;
        let n_out = 3 + if equal.is_some() { 0 } else { 3 } + if ft { 3 } else { 0 };
        let volume = grid.lengths.iter().product::<f64>();
        let cell = grid.h.iter().product::<f64>();
        // h^3 for each of the two quadratures, 1/V of the Fourier series, g's norm twice
        let norm = cell * cell / volume / (2.0 * PI * grid.s2).powi(3);
        let xi2 = grid.xi * grid.xi;
        let c = (1.0 - grid.split) / (4.0 * xi2);
        let axes: [Vec<Option<(f64, f64)>>; 3] = std::array::from_fn(|d| {
            (0..grid.m[d])
                .map(|i| {
                    signed(i, grid.m[d]).map(|s| {
                        let k = 2.0 * PI * s / grid.lengths[d];
                        (k, (-c * k * k).exp())
                    })
                })
                .collect()
        });
        let i = Complex64::new(0.0, 1.0);
        let re = |v: f64| Complex64::new(v, 0.0);
        let faxen_image = equal.map(|a| a * a / 6.0);
        let (o_direct_torque, o_image_faxen, o_image_torque) = match equal {
            Some(_) => (3, 9, 9),
            None => (6, 9, 18),
        };
        let mut out = vec![Complex64::default(); mx * g_out * plane];
        out.par_chunks_mut(g_out * plane)
            .enumerate()
            .for_each(|(ix, chunk)| {
                let nx = (mx - ix) % mx;
                let Some((kx, ex)) = axes[0][ix] else { return };
                for iy in 0..my {
                    let ny = (my - iy) % my;
                    let Some((ky, ey)) = axes[1][iy] else {
                        continue;
                    };
                    if ix == 0 && iy == 0 {
                        // k_par = 0: the exact mode is added elsewhere
                        continue;
                    }
                    for iz in 0..mz {
                        let nz = (mz - iz) % mz;
                        let Some((kz, ez)) = axes[2][iz] else {
                            continue;
                        };
                        let k = [kx, ky, kz];
                        let kc = k.map(re);
                        let pk = mirror(kc);
                        let k2 = kx * kx + ky * ky + kz * kz;
                        // the spectrum of real field f of a stack, from grid f/2 at k
                        // and -k
                        let field = |(input, grids): (&[Complex64], usize), f: usize| {
                            let at = |x: usize, y: usize, z: usize| {
                                input[(x * grids + f / 2) * plane + y * mz + z]
                            };
                            let (a, b) = (at(ix, iy, iz), at(nx, ny, nz).conj());
                            if f.is_multiple_of(2) {
                                (a + b) * 0.5
                            } else {
                                (a - b) * Complex64::new(0.0, -0.5)
                            }
                        };
                        let vector = |stack, f0: usize| -> V3 {
                            std::array::from_fn(|d| field(stack, f0 + d))
                        };
                        // k . P v
                        let kp = |v: V3| v[0] * kx + v[1] * ky - v[2] * kz;
                        // the direct sources
                        let fd = vector(direct, 0);
                        let mut s = match equal {
                            Some(a) => scale(fd, re(1.0 - a * a * k2 / 6.0)),
                            None => add(fd, scale(vector(direct, 3), re(-k2))),
                        };
                        if ft {
                            let l = vector(direct, o_direct_torque);
                            s = add(s, scale(cross(kc, l), 0.5 * i));
                        }
                        // the image: T F
                        let (f0, f2, f1) = (vector(image, 0), vector(image, 3), vector(image, 6));
                        s = add(s, scale(f0, re(-1.0)));
                        s = add(s, scale(mirror(f2), re(-k2)));
                        s = add(s, normal(-2.0 * i * kp(f1)));
                        // its Faxén terms
                        let (x, y, z) = match faxen_image {
                            Some(c) => (scale(f0, re(c)), scale(f2, re(c)), scale(f1, re(c))),
                            None => (
                                vector(image, o_image_faxen),
                                vector(image, o_image_faxen + 3),
                                vector(image, o_image_faxen + 6),
                            ),
                        };
                        s = add(s, scale(x, re(k2)));
                        s = add(s, scale(mirror(y), re(k2 * k2)));
                        s = add(s, normal(2.0 * i * k2 * kp(z)));
                        s = add(s, scale(mirror(z), -4.0 * i * kz * k2));
                        s = add(s, normal(4.0 * kz * kp(x)));
                        s = add(s, scale(mirror(x), re(-2.0 * k2)));
                        // its rotlet: T w1 + T' w2
                        if ft {
                            let w1 = |v: V3| scale(cross(pk, v), 0.5 * i);
                            let w2 = |v: V3| [v[1] * 0.5, v[0] * -0.5, Complex64::default()];
                            let o = o_image_torque;
                            let (l0, l1, l2) =
                                (vector(image, o), vector(image, o + 3), vector(image, o + 6));
                            s = add(s, scale(w1(l0), re(-1.0)));
                            s = add(s, scale(mirror(w1(l2)), re(-k2)));
                            s = add(s, normal(-2.0 * i * kp(w1(l1))));
                            s = add(s, scale(mirror(w2(l1)), re(-2.0 * k2)));
                            s = add(s, normal(-2.0 * i * kp(w2(l0))));
                        }
                        let q = k2 / (4.0 * xi2);
                        let g = norm * (1.0 + q + 2.0 * q * q) * ex * ey * ez / (eta * k2);
                        let ks = (s[0] * kx + s[1] * ky + s[2] * kz) / k2;
                        let u: V3 = std::array::from_fn(|d| (s[d] - ks * k[d]) * g);
                        let mut fields = [Complex64::default(); 10];
                        for d in 0..3 {
                            match equal {
                                Some(a) => fields[d] = u[d] * (1.0 - a * a * k2 / 6.0),
                                None => {
                                    fields[d] = u[d];
                                    fields[3 + d] = u[d] * (-k2 / 6.0);
                                }
                            }
                        }
                        if ft {
                            let omega = scale(cross(kc, u), 0.5 * i);
                            fields[n_out - 3..n_out].copy_from_slice(&omega);
                        }
                        for gi in 0..g_out {
                            chunk[gi * plane + iy * mz + iz] =
                                fields[2 * gi] + fields[2 * gi + 1] * i;
                        }
                    }
                }
            });
        out
    }
}
