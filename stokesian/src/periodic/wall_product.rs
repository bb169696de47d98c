//! The fast product `M x` (F or FT) along a periodic wall ([`super::wall`]): the real
//! part over linked cells ([`super::cells`]) with the generated `ewald_wall` kernel, the
//! reciprocal part `k_par != 0` by spectral Ewald in a box also periodic in `z`
//! ([`super::wall_spectral`]), the exact mode `k_par = 0` interpolated in the heights
//! ([`super::plane_mode`]): `O(N)` at fixed area density and tolerance where the
//! pair-by-pair sums of the dense matrix are `O(N^2)`.
//!
//! The linked cells are those of a triply periodic box whose height is the spheres'
//! span in `z` plus `r_c` and a margin: no image along `z` is within `r_c`, so the
//! cells visit the lateral images within `r_c` only.
//!
//! The split parameter is chosen for speed as in [`super::product`]: the real part
//! costs about `C_pair N (N/A) pi r_c^2` (`r_c = p/xi`, a monolayer), the reciprocal
//! part about `C_point M_x M_y M_z`, `M_d ~ k_c L_d/pi` with `k_c ~ 2 xi p` and `L_z =
//! 2 h_max + D` (the padding `D` does not depend on `xi`); `xi` minimises the sum over a
//! geometric scan. The costs per unit (`C_pair`: one real-space pair-image of the
//! generated lane kernel, about 840 operations at F and 1080 at FT; `C_point`: one grid
//! point, its transforms and symbols, with the image's grids) are ratios measured at `N
//! = 1e4` (docs/periodic.md: the time per pair-image and the slope of the reciprocal
//! part's time in the number of grid points); only their ratio matters, and the total is
//! flat near its minimum.
//!
//! Each sphere's real-space row is summed on its own over its images in the cells'
//! fixed order, so the product does not depend on the number of threads.

use super::cells::Cells;
use super::ewald::truncation_parameter;
use super::plane_mode::PlaneMode;
use super::wall::{reciprocal_box, WallEwald};
use super::wall_spectral::WallSpectral;
use crate::system::input::Particle;
use crate::system::Moments;
use kernels::generated::scene_ewald_wall_f::{ewald_wall_f_pair_lanes, ewald_wall_f_self};
use kernels::generated::scene_ewald_wall_ft::{ewald_wall_ft_pair_lanes, ewald_wall_ft_self};
use kernels::lanes::{self, Lane, WithLanes};
use rayon::prelude::*;
use std::f64::consts::PI;
use std::ops::Range;

/// Field spheres per task of the real part.
const ROWS: usize = 64;

/// Cost of one real-space pair-image, F and FT (the scalar FT kernel for both).
const C_PAIR: [f64; 2] = [1.0, 1.5];
/// Cost of one grid point (its transforms and symbols), F and FT, in the same unit.
const C_POINT: [f64; 2] = [12.0, 27.0];

/// The split of a product along a periodic wall.
pub(crate) struct WallPlan {
    /// The split at the chosen `xi`.
    pub(crate) wall: WallEwald,
    /// The reciprocal part's grid.
    pub(crate) spectral: WallSpectral,
}

impl WallPlan {
    /// The cheapest split of `wall`'s box and tolerance for `n` spheres at heights at
    /// most `h_max` above the wall, `moments` F or FT (module docs).
    pub(crate) fn new(wall: &WallEwald, n: usize, h_max: f64, moments: Moments) -> WallPlan {
        let p = truncation_parameter(wall.tolerance);
        let [lx, ly] = wall.lengths;
        let area = lx * ly;
        let ft = usize::from(moments != Moments::F);
        let cost = |xi: f64| {
            let r_cut = p / xi;
            let real = C_PAIR[ft] * n as f64 * n as f64 / area * PI * r_cut * r_cut;
            let (k_cut, lz) = reciprocal_box(wall.lengths, xi, wall.tolerance, 2.0 * h_max);
            let points: f64 = [lx, ly, lz]
                .iter()
                .map(|l| (k_cut * l / PI).ceil() + 2.0)
                .product();
            real + C_POINT[ft] * points
        };
        let (short, long) = (lx.min(ly), lx.max(ly));
        let (lo, hi) = (p / (3.0 * long), p / (1e-3 * short));
        let steps = 200;
        let xi = (0..=steps)
            .map(|s| lo * (hi / lo).powf(s as f64 / steps as f64))
            .min_by(|a, b| cost(*a).total_cmp(&cost(*b)))
            .unwrap_or(lo);
        let wall = WallEwald::new(wall.lengths, wall.height, wall.tolerance, Some(xi));
        let spectral = WallSpectral::new(&wall, h_max);
        WallPlan { wall, spectral }
    }
}

/// `M x` at F or FT (moment-major, as [`crate::System::apply`]) of spheres `ps` (wrapped
/// into the box laterally) above the wall of `wall` (its box and tolerance), viscosity
/// `eta`.
pub(crate) fn apply(
    wall: &WallEwald,
    eta: f64,
    ps: &[Particle],
    moments: Moments,
    x: &[f64],
) -> Vec<f64> {
    let n = ps.len();
    let ft = match moments {
        Moments::F => false,
        Moments::FT => true,
        Moments::FTS => unreachable!("the periodic product is F or FT"),
    };
    let heights: Vec<f64> = ps.iter().map(|p| p.x[2] - wall.height).collect();
    let lo = heights.iter().fold(f64::INFINITY, |a, &b| a.min(b));
    let hi = heights.iter().fold(0.0f64, |a, &b| a.max(b));
    let plan = WallPlan::new(wall, n, hi, moments);
    let forces: Vec<[f64; 3]> = (0..n)
        .map(|a| [x[3 * a], x[3 * a + 1], x[3 * a + 2]])
        .collect();
    let torques: Option<Vec<[f64; 3]>> = ft.then(|| {
        (0..n)
            .map(|a| std::array::from_fn(|i| x[3 * n + 3 * a + i]))
            .collect()
    });
    let (mut u, mut omega) = plan.spectral.apply(eta, ps, &forces, torques.as_deref());
    if !ft {
        omega = vec![[0.0; 3]; n];
    }
    PlaneMode::new(&plan.wall, lo, hi, eta).add(
        ps,
        &heights,
        &forces,
        torques.as_deref(),
        &mut u,
        &mut omega,
    );
    let real = real_part(&plan.wall, eta, ps, &forces, torques.as_deref(), lo, hi);
    let k = moments.per_particle();
    let mut out = vec![0.0; k * n];
    for a in 0..n {
        for i in 0..3 {
            out[3 * a + i] = u[a][i] + real[a][i];
            if ft {
                out[3 * n + 3 * a + i] = omega[a][i] + real[a][3 + i];
            }
        }
    }
    out
}

/// The real part of the product: each sphere's own screened kernel and the lateral
/// images within `r_c` of every sphere, over linked cells (module docs), `[U, Omega]`
/// per sphere (`Omega` zero without torques), `ROWS` field spheres per task.
fn real_part(
    wall: &WallEwald,
    eta: f64,
    ps: &[Particle],
    forces: &[[f64; 3]],
    torques: Option<&[[f64; 3]]>,
    lo: f64,
    hi: f64,
) -> Vec<[f64; 6]> {
    let [lx, ly] = wall.lengths;
    let lz = (hi - lo) + wall.r_cut + 1.0;
    let cells = Cells::new([lx, ly, lz], wall.r_cut, ps.iter().map(|p| p.x));
    let n = ps.len();
    let chunks: Vec<usize> = (0..n.div_ceil(ROWS)).collect();
    let parts: Vec<Vec<[f64; 6]>> = chunks
        .par_iter()
        .map(|&c| {
            lanes::dispatch(Real {
                cells: &cells,
                ps,
                forces,
                torques,
                eta,
                height: wall.height,
                sigma: 1.0 / wall.xi,
                rows: c * ROWS..((c + 1) * ROWS).min(n),
            })
        })
        .collect();
    parts.concat()
}

/// The real part for the field spheres `rows`: each row's images gathered in the cells'
/// order, then evaluated `WIDTH` at a time by the generated lane kernel (F, or FT with
/// torques) and summed lane by lane, the lanes summed in order at the end (bits fixed by
/// the instruction set, whatever the threads).
struct Real<'a> {
    cells: &'a Cells,
    ps: &'a [Particle],
    forces: &'a [[f64; 3]],
    torques: Option<&'a [[f64; 3]]>,
    eta: f64,
    /// The wall's plane `x3 = height`.
    height: f64,
    sigma: f64,
    rows: Range<usize>,
}

impl WithLanes for Real<'_> {
    type Elem = f64;
    type Output = Vec<[f64; 6]>;

    #[inline(always)]
    fn run<L: Lane<Elem = f64>>(self) -> Vec<[f64; 6]> {
        let w = L::WIDTH;
        // the images of one row: source position, source radius, force, torque
        let mut cols: [Vec<f64>; 10] = std::array::from_fn(|_| Vec::new());
        let (eta, height, sigma) = (
            L::splat(self.eta),
            L::splat(self.height),
            L::splat(self.sigma),
        );
        let zero = [0.0; 3];
        // the torques' columns only with torques
        let used = if self.torques.is_some() { 10 } else { 7 };
        let mut out = Vec::with_capacity(self.rows.len());
        for a in self.rows {
            let pa = &self.ps[a];
            for c in cols.iter_mut() {
                c.clear();
            }
            self.cells.for_each_image(a, |b, r| {
                let (pb, f) = (&self.ps[b], &self.forces[b]);
                let l = self.torques.map_or(&zero, |t| &t[b]);
                let xb = [pa.x[0] - r[0], pa.x[1] - r[1], pb.x[2]];
                let v = [
                    xb[0], xb[1], xb[2], pb.a, f[0], f[1], f[2], l[0], l[1], l[2],
                ];
                for (c, v) in cols[..used].iter_mut().zip(v) {
                    c.push(v);
                }
            });
            // padding: a source one radius along x at the same height, no force or torque
            let mut pad = [0.0; 10];
            pad[..4].copy_from_slice(&[pa.x[0] + 1.0, pa.x[1], pa.x[2], 1.0]);
            while !cols[0].len().is_multiple_of(w) {
                for (c, v) in cols[..used].iter_mut().zip(pad) {
                    c.push(v);
                }
            }
            let (xa, aa) = (pa.x.map(L::splat), L::splat(pa.a));
            let mut acc = [L::splat(0.0); 6];
            for s in (0..cols[0].len()).step_by(w) {
                let v: [L; 10] = std::array::from_fn(|k| match k < used {
                    true => L::load(&cols[k][s..s + w]),
                    false => L::splat(0.0),
                });
                let xb = [v[0], v[1], v[2]];
                // `acc[row] += sum_j m[first + 3 row + j] v[col + j]`
                let mut mul = |m: &[L], first: usize, rows: Range<usize>, col: usize| {
                    for (i, acc) in acc[rows].iter_mut().enumerate() {
                        for j in 0..3 {
                            *acc = m[first + 3 * i + j].mul_add(v[col + j], *acc);
                        }
                    }
                };
                if self.torques.is_none() {
                    let m = ewald_wall_f_pair_lanes(xa, xb, aa, v[3], eta, height, sigma);
                    mul(&m, 0, 0..3, 4);
                } else {
                    let m = ewald_wall_ft_pair_lanes(xa, xb, aa, v[3], eta, height, sigma);
                    // uf, ul, of, ol (BlocksFT's order)
                    mul(&m, 0, 0..3, 4);
                    mul(&m, 9, 0..3, 7);
                    mul(&m, 18, 3..6, 4);
                    mul(&m, 27, 3..6, 7);
                }
            }
            let f = &self.forces[a];
            let mut row: [f64; 6] = std::array::from_fn(|i| acc[i].sum());
            match self.torques {
                None => {
                    let own = ewald_wall_f_self(pa.x, pa.a, self.eta, self.height, self.sigma);
                    for (i, row) in row.iter_mut().take(3).enumerate() {
                        *row += (0..3).map(|j| own.uf[i][j] * f[j]).sum::<f64>();
                    }
                }
                Some(t) => {
                    let own = ewald_wall_ft_self(pa.x, pa.a, self.eta, self.height, self.sigma);
                    let l = &t[a];
                    for i in 0..3 {
                        for j in 0..3 {
                            row[i] += own.uf[i][j] * f[j] + own.ul[i][j] * l[j];
                            row[3 + i] += own.of[i][j] * f[j] + own.ol[i][j] * l[j];
                        }
                    }
                }
            }
            out.push(row);
        }
        out
    }
}
