//! The reciprocal part of the Ewald sum along a periodic wall ([`super::wall`]) applied
//! to forces and torques by spectral Ewald ([`super::spectral`]'s grid, window and
//! transforms): the lateral wave vectors `|k_par| >= K1` and the trapezoidal sum in `k_z`
//! are the wave vectors of a box also periodic in `z`, of height `Lz' = 2 h_max + D`,
//! `O(N P^3 + M log M)` for all pairs at once. The modes `0 < |k_par| < K1` are
//! [`super::low_modes`]'s, the mode `k_par = 0` [`super::plane_mode`]'s.
//!
//! Heights `z = x_3 - H` are measured from the wall. Each sphere is two sources: the
//! direct one at `y = (y_1, y_2, h)` and Blake's image at `y* = (y_1, y_2, -h)`, whose
//! symbol is `Jhat^K(k) T(k, h)` ([`super::wall`]): a force `F` at `y*` acts as `T F = -F
//! - h^2 k^2 P F - 2 i h (k . P F) e3`, `P = diag(1, 1, -1)`. `T` is quadratic in the
//! source's own height, so the image carries the fields `F`, `h^2 F` and `h F`
//! (multiplied in Fourier space by `-1`, `-k^2 P` and `-2 i e3 (k . P)`). The source's
//! operators act on the image's explicit heights too (`d/dy_3` of `exp(-i k . y*) T(h)`
//! is `i k_3 T + T'`):
//!
//! - the Faxén operator `1 + c lap_y`, `c = a^2/6`, adds `c [-k^2 T F + 2 i k_3 T' F +
//!   T'' F]`, that is `k^2 cF + k^4 P (c h^2 F) + 2 i k^2 (k . P (c h F)) e3 - 4 i k_3
//!   k^2 P (c h F) + 4 k_3 (k . P cF) e3 - 2 k^2 P cF` (the fields `cF`, `c h^2 F`, `c h
//!   F` of their own when the radii differ; `c` times the fields above when they are
//!   equal);
//! - the rotlet `(1/2) curl_y` of a torque `L` gives `T w_1 + T' w_2` with `w_1 = (i/2)
//!   (P k x L)` and `w_2 = (1/2) (L x e3)`: the fields `L`, `h L`, `h^2 L` at `y*`.
//!
//! **The image spread at `y`.** The image's fields at `y*` are the mirror image in `z`
//! of the same fields spread at `y` (the window is even and the grid's points are
//! symmetric about `z = 0`), and a mirrored field's spectrum at `(k_par, k_z)` is the
//! field's at `(k_par, -k_z)`. So every field is spread once, at `y`, and the image's
//! factor-`1` fields (`F`, `cF`, `L`) are the direct source's: the stack holds the
//! direct fields and the image's own (`h^2 F`, `h F`, ...), three times the direct
//! fields instead of four (five complex grids at F with equal radii instead of seven).
//!
//! The sum of every source's symbol `s(k)` (the direct force times its Faxén factor, the
//! direct rotlet `(i/2) k x L`, the image terms) is projected, `u = g (I - khat khat)
//! s`, and the field point's operators are those of the triply periodic box: `U = (1 -
//! a_a^2 k^2/6) u`, `Omega = (i/2) k x u` ([`Layout::symbol`], shared with
//! [`super::low_modes`]).
//!
//! The modes `|k_par| < K1` (every `k_z`) are left out. The box's height leaves the
//! copies of every source at least `D` from every field point, and a mode of lateral
//! wave number `k_par` decays like `exp(-k_par |z|)`: `k_c` and `D` are
//! [`super::wall::reciprocal_box`]'s for `h_a + h_b = 2 h_max` and `k_low = K1`. The
//! image's symbol carries up to `(h k_c)^2` more than the direct one, so the window is
//! chosen for the tolerance divided by `(1 + 2 h_max k_c)^2`.
//!
//! Determinism as in [`super::spectral`]: every sum in a fixed order.

use super::spectral::{Spectral, Window};
use super::wall::{lateral_waves, reciprocal_box, WallEwald};
use crate::system::input::Particle;
use rayon::prelude::*;
use rustfft::num_complex::Complex64;
use std::ops::Mul;

/// The grid of the reciprocal part along a periodic wall.
pub(crate) struct WallSpectral {
    grid: Spectral,
    /// The wall's plane `x3 = height`.
    height: f64,
    /// The lateral wave numbers below this are left out (the mode `k_par = 0` always).
    k_low: f64,
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

/// The real fields a product carries (module docs): every radius the same (`equal`,
/// the radius) or not, torques or not, Blake's image or the Stokeslet alone (`image`,
/// the sum the periodic slit's two walls share, [`super::slit`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Layout {
    pub(crate) equal: Option<f64>,
    pub(crate) ft: bool,
    pub(crate) image: bool,
}

impl Layout {
    /// The layout of spheres `ps`, with torques if `ft`.
    pub(crate) fn new(ps: &[Particle], ft: bool) -> Layout {
        let a0 = ps.first().map_or(0.0, |p| p.a);
        Layout {
            equal: ps.iter().all(|p| p.a == a0).then_some(a0),
            ft,
            image: true,
        }
    }

    /// The number of a direct source's fields (`F`, `[a^2 F/6]`, `[L]`), which is also
    /// the number of a field point's (`U`, `[-k^2 U/6]`, `[Omega]`).
    pub(crate) fn fields(&self) -> usize {
        3 + if self.equal.is_some() { 0 } else { 3 } + if self.ft { 3 } else { 0 }
    }

    /// The direct source of a sphere of radius `a` under `force` and `torque`: `F`,
    /// `[a^2 F/6]` (unequal radii), `[L]`.
    pub(crate) fn direct(&self, a: f64, force: [f64; 3], torque: Option<[f64; 3]>) -> Vec<f64> {
        let mut q = force.to_vec();
        if self.equal.is_none() {
            q.extend(force.map(|f| a * a / 6.0 * f));
        }
        if let (true, Some(t)) = (self.ft, torque) {
            q.extend(t);
        }
        q
    }

    /// The image source of the direct source `direct` at height `h`: `F`, `h^2 F`, `h F`,
    /// `[c F, c h^2 F, c h F]`, `[L, h L, h^2 L]`; none without the image.
    pub(crate) fn image<T: Copy + Mul<f64, Output = T>>(&self, direct: &[T], h: f64) -> Vec<T> {
        if !self.image {
            return Vec::new();
        }
        let group = |o: usize, powers: [f64; 3]| {
            powers
                .into_iter()
                .flat_map(move |c| (0..3).map(move |d| direct[o + d] * c))
        };
        let mut q: Vec<T> = group(0, [1.0, h * h, h]).collect();
        if self.equal.is_none() {
            q.extend(group(3, [1.0, h * h, h]));
        }
        if self.ft {
            q.extend(group(self.fields() - 3, [1.0, h, h * h]));
        }
        q
    }

    /// A sphere's velocity and angular velocity (zero without torques) from its fields
    /// `U`, `[-k^2 U/6]`, `[Omega]` at radius `a`.
    pub(crate) fn velocities(&self, a: f64, f: &[f64]) -> ([f64; 3], [f64; 3]) {
        let u = std::array::from_fn(|i| match self.equal {
            Some(_) => f[i],
            None => f[i] + a * a * f[3 + i],
        });
        let o = self.fields() - 3;
        let omega = if self.ft {
            [f[o], f[o + 1], f[o + 2]]
        } else {
            [0.0; 3]
        };
        (u, omega)
    }

    /// The field point's fields `U`, `[-k^2 U/6]`, `[Omega]` (the first
    /// [`Layout::fields`]) at wave vector `k` from the spectra of the direct source's
    /// fields and the image's (module docs), `g` the scalar of the projection `u = g (I -
    /// khat khat) s`.
    pub(crate) fn symbol(
        &self,
        k: [f64; 3],
        g: f64,
        direct: &[Complex64],
        image: &[Complex64],
    ) -> [Complex64; 10] {
        let [kx, ky, kz] = k;
        let i = Complex64::new(0.0, 1.0);
        let re = |v: f64| Complex64::new(v, 0.0);
        let kc = k.map(re);
        let pk = mirror(kc);
        let k2 = kx * kx + ky * ky + kz * kz;
        let vector = |v: &[Complex64], f0: usize| -> V3 { [v[f0], v[f0 + 1], v[f0 + 2]] };
        let (o_direct_torque, o_image_faxen, o_image_torque) = match self.equal {
            Some(_) => (3, 9, 9),
            None => (6, 9, 18),
        };
        // k . P v
        let kp = |v: V3| v[0] * kx + v[1] * ky - v[2] * kz;
        // the direct sources
        let fd = vector(direct, 0);
        let mut s = match self.equal {
            Some(a) => scale(fd, re(1.0 - a * a * k2 / 6.0)),
            None => add(fd, scale(vector(direct, 3), re(-k2))),
        };
        if self.ft {
            let l = vector(direct, o_direct_torque);
            s = add(s, scale(cross(kc, l), 0.5 * i));
        }
        if !self.image {
            return self.field_point(k, g, s);
        }
        // the image: T F
        let (f0, f2, f1) = (vector(image, 0), vector(image, 3), vector(image, 6));
        s = add(s, scale(f0, re(-1.0)));
        s = add(s, scale(mirror(f2), re(-k2)));
        s = add(s, normal(-2.0 * i * kp(f1)));
        // its Faxén terms
        let (x, y, z) = match self.equal {
            Some(a) => {
                let c = re(a * a / 6.0);
                (scale(f0, c), scale(f2, c), scale(f1, c))
            }
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
        if self.ft {
            let w1 = |v: V3| scale(cross(pk, v), 0.5 * i);
            let w2 = |v: V3| [v[1] * 0.5, v[0] * -0.5, Complex64::default()];
            let o = o_image_torque;
            let (l0, l1, l2) = (vector(image, o), vector(image, o + 3), vector(image, o + 6));
            s = add(s, scale(w1(l0), re(-1.0)));
            s = add(s, scale(mirror(w1(l2)), re(-k2)));
            s = add(s, normal(-2.0 * i * kp(w1(l1))));
            s = add(s, scale(mirror(w2(l1)), re(-2.0 * k2)));
            s = add(s, normal(-2.0 * i * kp(w2(l0))));
        }
        self.field_point(k, g, s)
    }

    /// The field point's fields from the sources' symbol `s` (module docs).
    fn field_point(&self, k: [f64; 3], g: f64, s: V3) -> [Complex64; 10] {
        let [kx, ky, kz] = k;
        let i = Complex64::new(0.0, 1.0);
        let kc = k.map(|v| Complex64::new(v, 0.0));
        let k2 = kx * kx + ky * ky + kz * kz;
        let ks = (s[0] * kx + s[1] * ky + s[2] * kz) / k2;
        let u: V3 = std::array::from_fn(|d| (s[d] - ks * k[d]) * g);
        let mut fields = [Complex64::default(); 10];
        for d in 0..3 {
            match self.equal {
                Some(a) => fields[d] = u[d] * (1.0 - a * a * k2 / 6.0),
                None => {
                    fields[d] = u[d];
                    fields[3 + d] = u[d] * (-k2 / 6.0);
                }
            }
        }
        if self.ft {
            let n_out = self.fields();
            let omega = scale(cross(kc, u), 0.5 * i);
            fields[n_out - 3..n_out].copy_from_slice(&omega);
        }
        fields
    }
}

/// Where field `f` of the image ([`Layout::image`], groups of nine: a direct field's
/// three components times `1` and two powers of `h`) is among the image's own fields,
/// those that are not a direct field: `None` for the factor `1`, the direct field's.
fn own_image_field(f: usize) -> Option<usize> {
    let (group, r) = (f / 9, f % 9);
    (r >= 3).then_some(6 * group + r - 3)
}

impl WallSpectral {
    /// The grid for the split `wall` (its `xi` and tolerance) of spheres whose heights
    /// above the wall are at most `h_max`, for the lateral wave numbers at least `k_low`,
    /// with Blake's image or without it (`image`, [`Layout::image`]); `None` if no lattice
    /// wave vector `k_low <= |k_par| <= k_c` is left to it.
    pub(crate) fn new(
        wall: &WallEwald,
        h_max: f64,
        k_low: f64,
        image: bool,
    ) -> Option<WallSpectral> {
        let (k_cut, lz) = reciprocal_box(wall.xi, wall.tolerance, 2.0 * h_max, k_low);
        let any =
            lateral_waves(wall.lengths, k_cut).any(|k| k[0] * k[0] + k[1] * k[1] >= k_low * k_low);
        let amplification = if image {
            (1.0 + 2.0 * h_max * k_cut).powi(2)
        } else {
            1.0
        };
        let lengths = [wall.lengths[0], wall.lengths[1], lz];
        any.then(|| WallSpectral {
            grid: Spectral::with_cut(lengths, wall.xi, wall.tolerance / amplification, k_cut),
            height: wall.height,
            k_low,
        })
    }

    /// The reciprocal part (lateral wave numbers at least `k_low`) of the fields of
    /// spheres `ps` (the field point's fields of `layout`, [`Layout::symbol`]) in a fluid
    /// of viscosity `eta` under their direct sources `direct` ([`Layout::direct`]).
    pub(crate) fn apply(
        &self,
        eta: f64,
        ps: &[Particle],
        layout: Layout,
        direct: &[Vec<f64>],
    ) -> Vec<Vec<f64>> {
        let n = ps.len();
        let h = |b: usize| ps[b].x[2] - self.height;
        // the direct fields and the image's own (module docs), all spread at y
        let sources: Vec<Vec<f64>> = (0..n)
            .map(|b| {
                let image = layout.image(&direct[b], h(b));
                let own = (0..image.len()).filter(|&f| own_image_field(f).is_some());
                direct[b]
                    .iter()
                    .copied()
                    .chain(own.map(|f| image[f]))
                    .collect()
            })
            .collect();
        let n_direct = layout.fields();
        let n_in = sources.first().map_or(n_direct, Vec::len);
        let (g_in, g_out) = (n_in.div_ceil(2), n_direct.div_ceil(2));
        let windows: Vec<Window> = ps
            .par_iter()
            .map(|p| self.grid.window([p.x[0], p.x[1], p.x[2] - self.height]))
            .collect();
        let mut fields = self.grid.convolve(&windows, &sources, g_in, g_out, |grid| {
            self.symbols(eta, layout, grid, g_in, g_out)
        });
        for f in &mut fields {
            f.truncate(n_direct);
        }
        fields
    }

    /// The transformed sources times the symbols ([`Layout::symbol`]): from the stack
    /// `input` of `g_in` grids (the direct fields, then the image's own, all spread at
    /// `y`) the stack of `g_out` grids of the field point's fields.
    fn symbols(
        &self,
        eta: f64,
        layout: Layout,
        input: &[Complex64],
        g_in: usize,
        g_out: usize,
    ) -> Vec<Complex64> {
        let n_direct = layout.fields();
        let n_image = if layout.image { 3 * n_direct } else { 0 };
        let xi2 = self.grid.xi * self.grid.xi;
        let low2 = self.k_low * self.k_low;
        // k_par = 0 and the low modes are added elsewhere
        let keep = |kx: f64, ky: f64| kx * kx + ky * ky >= low2 && (kx, ky) != (0.0, 0.0);
        let grid = &self.grid;
        grid.each_wave(input, g_in, g_out, keep, |k, k2, norm, spectrum, fields| {
            let mut sd = [Complex64::default(); 9];
            let mut si = [Complex64::default(); 27];
            for (f, v) in sd[..n_direct].iter_mut().enumerate() {
                *v = spectrum(f, false);
            }
            // the image at y* is the mirror of its fields at y: their spectrum at (k_par,
            // -k_z)
            for (f, v) in si[..n_image].iter_mut().enumerate() {
                let g = own_image_field(f).map_or(f / 9 * 3 + f % 9, |o| n_direct + o);
                *v = spectrum(g, true);
            }
            let q = k2 / (4.0 * xi2);
            let g = norm * (1.0 + q + 2.0 * q * q) / (eta * k2);
            let out = layout.symbol(k, g, &sd, &si);
            let n = fields.len();
            fields.copy_from_slice(&out[..n]);
        })
    }
}
