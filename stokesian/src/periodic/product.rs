//! The fast periodic product `M x` (F or FT): the real part of the Ewald split over
//! linked cells ([`super::cells`]), the reciprocal part by spectral Ewald
//! ([`super::spectral`]), `O(N)` at fixed density and tolerance where the pair-by-pair
//! sums of the dense matrix are `O(N^2)`.
//!
//! The split parameter is chosen for speed, not balanced as for the direct sums: the
//! real part costs about `C_pair N (N/V) (4 pi/3) r_c^3` (`r_c = p/xi`), the reciprocal
//! part about `C_point M_x M_y M_z` (`M_d ~ 2 xi p L_d/pi`: the transforms and the
//! symbols) plus spreading and interpolation, which do not depend on `xi` (the window
//! has `P^3` points whatever the spacing); `xi` minimises the sum over a geometric scan.
//! The costs per unit (`C_pair`: one real-space pair-image, the generated kernel on the
//! radial structured path, about 270 operations in lanes for F, 450 scalar for FT;
//! `C_point`: one grid point) are ratios measured at `N = 1e4` (docs/periodic.md);
//! only their ratio matters, and the total is flat near its minimum.
//!
//! The real part of the F product evaluates `WIDTH` pair-images at once with the lane
//! kernel; FT uses the scalar kernel (its lane twin is not instantiated in the solver,
//! to keep the build small). Each sphere's real-space row is summed on its own over its
//! images in the cells' fixed order, so the product does not depend on the number of
//! threads.

use super::cells::Cells;
use super::ewald::truncation_parameter;
use super::spectral::Spectral;
use crate::system::input::Particle;
use crate::system::Moments;
use kernels::generated::scene_ewald_real_f::{ewald_real_f_pair_lanes, ewald_real_f_self};
use kernels::generated::scene_ewald_real_ft::{ewald_real_ft_pair, ewald_real_ft_self};
use kernels::lanes::{self, Lane, WithLanes};
use rayon::prelude::*;
use std::f64::consts::PI;
use std::ops::Range;

/// Field spheres per task of the real part.
const ROWS: usize = 64;

/// Cost of one real-space pair-image, F (the lane kernel) and FT (the scalar kernel).
const C_PAIR: [f64; 2] = [1.0, 4.9];
/// Cost of one grid point (its transforms and symbols), F and FT, in the same unit.
const C_POINT: [f64; 2] = [4.5, 5.2];

/// The split and grid of a product.
pub(crate) struct Plan {
    /// The splitting parameter `xi`.
    pub(crate) xi: f64,
    /// The real-space cut-off `r_c`.
    pub(crate) r_cut: f64,
    /// The reciprocal part's grid and window.
    pub(crate) spectral: Spectral,
}

impl Plan {
    /// The cheapest split for `n` spheres in the box `lengths` at tolerance `tol`,
    /// `moments` F or FT (module docs).
    pub(crate) fn new(lengths: [f64; 3], tol: f64, n: usize, moments: Moments) -> Plan {
        let p = truncation_parameter(tol);
        let volume = lengths.iter().product::<f64>();
        let ft = usize::from(moments != Moments::F);
        let (pair, point) = (C_PAIR[ft], C_POINT[ft]);
        let cost = |xi: f64| {
            let r_cut = p / xi;
            let real = pair * n as f64 * n as f64 / volume * 4.0 * PI / 3.0 * r_cut.powi(3);
            let points: f64 = lengths
                .iter()
                .map(|l| (2.0 * xi * p * l / PI).ceil() + 2.0)
                .product();
            real + point * points
        };
        // r_c from a thousandth of the shortest side to three times the longest
        let (short, long) = (
            lengths.iter().fold(f64::INFINITY, |a, &b| a.min(b)),
            lengths.iter().fold(0.0f64, |a, &b| a.max(b)),
        );
        let (lo, hi) = (p / (3.0 * long), p / (1e-3 * short));
        let steps = 400;
        let xi = (0..=steps)
            .map(|s| lo * (hi / lo).powf(s as f64 / steps as f64))
            .min_by(|a, b| cost(*a).total_cmp(&cost(*b)))
            .unwrap_or(lo);
        Plan {
            xi,
            r_cut: p / xi,
            spectral: Spectral::new(lengths, xi, tol),
        }
    }
}

/// `M x` at F or FT (moment-major, as [`crate::System::apply`]) of spheres `ps` in the
/// periodic box `lengths` at tolerance `tol`, viscosity `eta`.
pub(crate) fn apply(
    lengths: [f64; 3],
    tol: f64,
    eta: f64,
    ps: &[Particle],
    moments: Moments,
    x: &[f64],
) -> Vec<f64> {
    let n = ps.len();
    let plan = Plan::new(lengths, tol, n, moments);
    let ft = match moments {
        Moments::F => false,
        Moments::FT => true,
        Moments::FTS => unreachable!("the periodic product is F or FT"),
    };
    let forces: Vec<[f64; 3]> = (0..n)
        .map(|a| [x[3 * a], x[3 * a + 1], x[3 * a + 2]])
        .collect();
    let torques: Option<Vec<[f64; 3]>> = ft.then(|| {
        (0..n)
            .map(|a| std::array::from_fn(|i| x[3 * n + 3 * a + i]))
            .collect()
    });
    let (mut u, omega) = plan.spectral.apply(eta, ps, &forces, torques.as_deref());
    let cells = Cells::new(lengths, plan.r_cut, ps.iter().map(|p| p.x));
    let sigma = 1.0 / plan.xi;
    let real: Vec<[f64; 6]> = match &torques {
        None => {
            let rows: Vec<usize> = (0..n.div_ceil(ROWS)).collect();
            let parts: Vec<Vec<[f64; 6]>> = rows
                .par_iter()
                .map(|&c| {
                    lanes::dispatch(RealF {
                        cells: &cells,
                        ps,
                        forces: &forces,
                        eta,
                        sigma,
                        rows: c * ROWS..((c + 1) * ROWS).min(n),
                    })
                })
                .collect();
            parts.concat()
        }
        Some(t) => (0..n)
            .into_par_iter()
            .map(|a| {
                let pa = &ps[a];
                let mut acc = [0.0; 6];
                let mut add = |m: &kernels::BlocksFT, b: usize| {
                    let (f, l) = (&forces[b], &t[b]);
                    for i in 0..3 {
                        for j in 0..3 {
                            acc[i] += m.uf[i][j] * f[j] + m.ul[i][j] * l[j];
                            acc[3 + i] += m.of[i][j] * f[j] + m.ol[i][j] * l[j];
                        }
                    }
                };
                add(&ewald_real_ft_self(pa.x, pa.a, eta, sigma), a);
                cells.for_each_image(a, |b, r| {
                    add(
                        &ewald_real_ft_pair(r, [0.0; 3], pa.a, ps[b].a, eta, sigma),
                        b,
                    );
                });
                acc
            })
            .collect(),
    };
    let k = moments.per_particle();
    let mut out = vec![0.0; k * n];
    for a in 0..n {
        for i in 0..3 {
            u[a][i] += real[a][i];
            out[3 * a + i] = u[a][i];
            if ft {
                out[3 * n + 3 * a + i] = omega[a][i] + real[a][3 + i];
            }
        }
    }
    out
}

/// The real part of the F product for the field spheres `rows`: each row's images
/// gathered in the cells' order, then evaluated `WIDTH` at a time by the generated lane
/// kernel and summed lane by lane, the lanes summed in order at the end (bits fixed by
/// the instruction set, whatever the threads).
struct RealF<'a> {
    cells: &'a Cells,
    ps: &'a [Particle],
    forces: &'a [[f64; 3]],
    eta: f64,
    sigma: f64,
    rows: Range<usize>,
}

impl WithLanes for RealF<'_> {
    type Elem = f64;
    type Output = Vec<[f64; 6]>;

    #[inline(always)]
    fn run<L: Lane<Elem = f64>>(self) -> Vec<[f64; 6]> {
        let w = L::WIDTH;
        // the images of one row: separation, source radius, force
        let mut cols: [Vec<f64>; 7] = std::array::from_fn(|_| Vec::new());
        let (eta, sigma) = (L::splat(self.eta), L::splat(self.sigma));
        let zero = [L::splat(0.0); 3];
        let mut out = Vec::with_capacity(self.rows.len());
        for a in self.rows {
            let pa = &self.ps[a];
            for c in cols.iter_mut() {
                c.clear();
            }
            self.cells.for_each_image(a, |b, r| {
                let f = &self.forces[b];
                for (c, v) in
                    cols.iter_mut()
                        .zip([r[0], r[1], r[2], self.ps[b].a, f[0], f[1], f[2]])
                {
                    c.push(v);
                }
            });
            // padding: a finite separation, no force
            while !cols[0].len().is_multiple_of(w) {
                for (c, v) in cols.iter_mut().zip([1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]) {
                    c.push(v);
                }
            }
            let aa = L::splat(pa.a);
            let mut acc = [L::splat(0.0); 3];
            for s in (0..cols[0].len()).step_by(w) {
                let v: [L; 7] = std::array::from_fn(|k| L::load(&cols[k][s..s + w]));
                let m = ewald_real_f_pair_lanes([v[0], v[1], v[2]], zero, aa, v[3], eta, sigma);
                for (i, acc) in acc.iter_mut().enumerate() {
                    *acc = m[3 * i].mul_add(v[4], *acc);
                    *acc = m[3 * i + 1].mul_add(v[5], *acc);
                    *acc = m[3 * i + 2].mul_add(v[6], *acc);
                }
            }
            let own = ewald_real_f_self(pa.x, pa.a, self.eta, self.sigma).uf;
            let f = &self.forces[a];
            let mut row = [0.0; 6];
            for i in 0..3 {
                row[i] = own[i][0] * f[0] + own[i][1] * f[1] + own[i][2] * f[2] + acc[i].sum();
            }
            out.push(row);
        }
        out
    }
}
