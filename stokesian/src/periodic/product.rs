//! The fast periodic product `M x` (F, FT or FTS): the real part of the Ewald split over
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
//! radial structured path, in lanes: 269 operations for F, 327 for FT;
//! `C_point`: one grid point) are ratios measured at `N = 1e4` (docs/periodic.md);
//! only their ratio matters, and the total is flat near its minimum.
//!
//! The real part evaluates `WIDTH` pair-images at once with the lane kernels (F, or FT
//! with torques). Each sphere's real-space row is summed on its own over its
//! images in the cells' fixed order, so the product does not depend on the number of
//! threads.

use super::cells::Cells;
use super::ewald::truncation_parameter;
use super::real::{self, grand_rows, per_lane, real_part, Split};
use super::spectral::Spectral;
use crate::system::input::Particle;
use crate::system::Moments;
use kernels::generated::scene_ewald_real_f::{ewald_real_f_pair_lanes, ewald_real_f_self};
use kernels::generated::scene_ewald_real_ft::{ewald_real_ft_pair_lanes, ewald_real_ft_self};
use kernels::generated::scene_ewald_real_fts::{ewald_real_fts_pair, ewald_real_fts_self};
use kernels::lanes::Lane;
use kernels::{BlocksF, BlocksFT, Grand};
use std::f64::consts::PI;

/// Cost of one real-space pair-image, F, FT (the lane kernels) and FTS (the scalar
/// kernel lane by lane: the FTS product of `N = 1e4` spheres at volume fraction 0.2 and
/// tolerance `1e-6` took 1.88, 1.47, 1.44, 1.46 and 1.51 s with 1.3, 3, 6, 12 and 24 here,
/// docs/periodic.md).
const C_PAIR: [f64; 3] = [1.0, 1.3, 6.0];
/// Cost of one grid point (its transforms and symbols), F, FT and FTS, in the same unit.
const C_POINT: [f64; 3] = [4.5, 6.6, 6.6];

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
        let level = match moments {
            Moments::F => 0,
            Moments::FT => 1,
            Moments::FTS => 2,
        };
        let (pair, point) = (C_PAIR[level], C_POINT[level]);
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
    let ft = moments != Moments::F;
    let (forces, torques) = real::forces_and_torques(x, n, ft);
    // the stresslets' five components per sphere after the forces and torques
    let stresslets: Option<Vec<[f64; 5]>> = (moments == Moments::FTS).then(|| {
        (0..n)
            .map(|a| std::array::from_fn(|q| x[6 * n + 5 * a + q]))
            .collect()
    });
    let (mut u, omega, strain) = match (&torques, &stresslets) {
        (Some(t), Some(st)) => plan.spectral.apply_fts(eta, ps, &forces, t, st),
        _ => {
            let (u, omega) = plan.spectral.apply(eta, ps, &forces, torques.as_deref());
            (u, omega, Vec::new())
        }
    };
    let cells = Cells::new(lengths, plan.r_cut, ps.iter().map(|p| p.x));
    let sigma = 1.0 / plan.xi;
    let split = Free { eta, sigma };
    let real = real_part(
        &split,
        &cells,
        ps,
        &forces,
        torques.as_deref(),
        stresslets.as_deref(),
    );
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
        if let Some(e) = strain.get(a) {
            for q in 0..5 {
                out[6 * n + 5 * a + q] = e[q] + real[a][6 + q];
            }
        }
    }
    out
}

/// The real part of the free-space split: the lane kernels of `ewald_real_f` and
/// `ewald_real_ft`.
pub(super) struct Free {
    pub(super) eta: f64,
    pub(super) sigma: f64,
}

impl Split for Free {
    #[inline(always)]
    fn pair_f<L: Lane<Elem = f64>>(&self, xa: [L; 3], xb: [L; 3], aa: L, ab: L) -> [L; 9] {
        ewald_real_f_pair_lanes(xa, xb, aa, ab, L::splat(self.eta), L::splat(self.sigma))
    }
    #[inline(always)]
    fn pair_ft<L: Lane<Elem = f64>>(&self, xa: [L; 3], xb: [L; 3], aa: L, ab: L) -> [L; 36] {
        ewald_real_ft_pair_lanes(xa, xb, aa, ab, L::splat(self.eta), L::splat(self.sigma))
    }
    #[inline(always)]
    fn pair_fts<L: Lane<Elem = f64>>(&self, xa: [L; 3], xb: [L; 3], aa: L, ab: L) -> [L; 121] {
        // the scalar kernel lane by lane: its lane code would cost build time
        per_lane(xa, xb, aa, ab, |xa, xb, aa, ab| {
            grand_rows(&ewald_real_fts_pair(xa, xb, aa, ab, self.eta, self.sigma))
        })
    }
    fn self_f(&self, x: [f64; 3], a: f64) -> BlocksF {
        ewald_real_f_self(x, a, self.eta, self.sigma)
    }
    fn self_ft(&self, x: [f64; 3], a: f64) -> BlocksFT {
        ewald_real_ft_self(x, a, self.eta, self.sigma)
    }
    fn self_fts(&self, x: [f64; 3], a: f64) -> Grand {
        ewald_real_fts_self(x, a, self.eta, self.sigma)
    }
}
