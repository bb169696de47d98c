//! The fast product `M x` (F or FT) along a periodic wall ([`super::wall`]): the real
//! part over linked cells ([`super::cells`]) with the generated `ewald_wall` kernel, the
//! reciprocal part in three: the lateral modes `|k_par| >= K1` by spectral Ewald in a box
//! also periodic in `z` ([`super::wall_spectral`]), the low modes `0 < |k_par| < K1` each
//! on its own, exact in `z` ([`super::low_modes`]), the exact mode `k_par = 0`
//! interpolated in the heights ([`super::plane_mode`]): `O(N)` at fixed area density and
//! tolerance where the pair-by-pair sums of the dense matrix are `O(N^2)`.
//!
//! The linked cells are those of a slab ([`Cells::slab`]) whose height is the spheres'
//! span in `z` plus `r_c` and a margin, periodic along the wall only: the cells visit
//! the lateral images within `r_c`.
//!
//! The split parameter `xi` and the threshold `K1` are chosen for speed as in
//! [`super::product`]: the real part costs about `C_pair N (N/A) pi r_c^2` (`r_c = p/xi`,
//! a monolayer), the grid about `C_point M_x M_y M_z`, `M_d ~ k_c L_d/pi` with `k_c ~ 2
//! xi p` and `L_z = 2 h_max + D(K1)` (the padding `D = ln(100/tol)/K1` and a term for
//! the heights, which does not depend on `xi`), the low modes about `C_mode N n_low K`
//! (`n_low` modes, `K` Chebyshev points of the heights); `(xi, K1)` minimises the sum
//! over a geometric scan of `xi` and a set of `K1/K0`, `K0 = 2 pi/max(Lx, Ly)` (`K1 =
//! K0`: no low mode, the only choice where the heights' span needs more than
//! [`super::low_modes::MAX_NODES`] points). The costs per unit (`C_pair`: one
//! real-space pair-image, the generated lane kernel at F, 841 operations, the scalar
//! kernel lane by lane at FT ([`real::per_lane`]), 1508 operations; `C_point`: one grid
//! point, its transforms and symbols, with the image's grids; `C_mode`: one sphere, low
//! mode and Chebyshev point, its moments and its interpolation) are ratios measured at
//! `N = 1e4` (docs/periodic.md: the time per pair-image, the slope of the grid's time in
//! the number of its points, the low modes' time per sphere, mode and point); only their
//! ratios matter, and the total is flat near its minimum. Spreading and interpolation,
//! `N P^3` with `P` fixed by the tolerance, do not depend on `xi` and are left out.
//!
//! Each sphere's real-space row is summed on its own over its images in the cells'
//! fixed order, so the product does not depend on the number of threads.

use super::cells::Cells;
use super::ewald::truncation_parameter;
use super::low_modes::{low_waves, node_count, LowModes};
use super::plane_mode::PlaneMode;
use super::product::Free;
use super::real::per_lane;
use super::real::{self, Split};
use super::wall::{lateral_waves, reciprocal_box, smallest_wave, WallEwald};
use super::wall_spectral::{Layout, WallSpectral};
use crate::system::input::Particle;
use crate::system::Moments;
use kernels::generated::scene_ewald_wall_f::{ewald_wall_f_pair_lanes, ewald_wall_f_self};
use kernels::generated::scene_ewald_wall_ft::{ewald_wall_ft_pair, ewald_wall_ft_self};
use kernels::lanes::Lane;
use kernels::{BlocksF, BlocksFT, Grand};
use std::f64::consts::PI;

/// Cost of one real-space pair-image, F and FT (the scalar FT kernel for both).
const C_PAIR: [f64; 2] = [1.0, 6.8];
/// Cost of one grid point (its transforms and symbols), F and FT, in the same unit.
const C_POINT: [f64; 2] = [8.8, 15.0];
/// Cost of one sphere, low mode and Chebyshev point (its moments and interpolation), F
/// and FT, in the same unit.
const C_MODE: [f64; 2] = [0.085, 0.17];

/// Which lattice sum a product along a periodic wall applies: the wall's (the Stokeslet
/// and Blake's image), or the Stokeslet's alone but its mode `k_par = 0`, the sum the
/// periodic slit's two walls share ([`super::slit`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Sum {
    Wall,
    Stokeslet,
}

/// The split of a product along a periodic wall.
pub(crate) struct WallPlan {
    /// The split at the chosen `xi`.
    pub(crate) wall: WallEwald,
    /// The reciprocal part's grid (`|k_par| >= K1`), if any mode is left to it.
    pub(crate) spectral: Option<WallSpectral>,
    /// The low modes `0 < |k_par| < K1`.
    pub(crate) low: LowModes,
}

impl WallPlan {
    /// The cheapest split of `wall`'s box and tolerance for `n` spheres at heights in
    /// `[lo, hi]` above the wall, `moments` F or FT, of the lattice sum `sum` (module
    /// docs; the costs are the wall's for both sums).
    pub(crate) fn new(
        wall: &WallEwald,
        n: usize,
        lo: f64,
        hi: f64,
        moments: Moments,
        sum: Sum,
    ) -> WallPlan {
        let p = truncation_parameter(wall.tolerance);
        let [lx, ly] = wall.lengths;
        let area = lx * ly;
        let ft = usize::from(moments != Moments::F);
        let k0 = smallest_wave(wall.lengths);
        let cost = |xi: f64, k_low: f64, nodes: usize| {
            let r_cut = p / xi;
            let real = C_PAIR[ft] * n as f64 * n as f64 / area * PI * r_cut * r_cut;
            let (k_cut, lz) = reciprocal_box(xi, wall.tolerance, 2.0 * hi, k_low);
            let grid = lateral_waves(wall.lengths, k_cut)
                .any(|k| k[0] * k[0] + k[1] * k[1] >= k_low * k_low);
            let points: f64 = if grid {
                [lx, ly, lz]
                    .iter()
                    .map(|l| (k_cut * l / PI).ceil() + 2.0)
                    .product()
            } else {
                0.0
            };
            let modes = low_waves(wall.lengths, k_cut, k_low).count();
            real + C_POINT[ft] * points + C_MODE[ft] * (n * modes * nodes) as f64
        };
        let (short, long) = (lx.min(ly), lx.max(ly));
        let (xi_lo, xi_hi) = (p / (3.0 * long), p / (1e-3 * short));
        let steps = 200;
        let mut best = (f64::INFINITY, xi_lo, k0, 0);
        for s in 0..=steps {
            let xi = xi_lo * (xi_hi / xi_lo).powf(s as f64 / steps as f64);
            let (k_cut, _) = reciprocal_box(xi, wall.tolerance, 2.0 * hi, k0);
            let nodes = node_count(xi, wall.tolerance, k_cut, lo, hi);
            // without enough points for the heights, no low mode
            let ks = match nodes {
                Some(_) => &K_LOW[..],
                None => &K_LOW[..1],
            };
            let nodes = nodes.unwrap_or(0);
            for f in ks {
                let c = cost(xi, f * k0, nodes);
                if c < best.0 {
                    best = (c, xi, f * k0, nodes);
                }
            }
        }
        let (_, xi, k_low, nodes) = best;
        let wall = WallEwald::new(wall.lengths, wall.height, wall.tolerance, Some(xi));
        let spectral = WallSpectral::new(&wall, hi, k_low, sum == Sum::Wall);
        let low = LowModes::new(&wall, k_low, lo, hi, nodes);
        WallPlan {
            wall,
            spectral,
            low,
        }
    }
}

/// The candidate thresholds `K1/K0` of the low modes (the first, `1`: none).
const K_LOW: [f64; 11] = [1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0];

/// `M x` at F or FT (moment-major, as [`crate::System::apply`]) of spheres `ps` (wrapped
/// into the box laterally) above the wall of `wall` (its box and tolerance), viscosity
/// `eta`, of the lattice sum `sum`; and the split parameter `xi` it chose (the
/// Stokeslet's sum without its mode `k_par = 0` depends on it, [`super::slit_product`]).
pub(crate) fn apply(
    wall: &WallEwald,
    sum: Sum,
    eta: f64,
    ps: &[Particle],
    moments: Moments,
    x: &[f64],
) -> (Vec<f64>, f64) {
    let n = ps.len();
    let ft = match moments {
        Moments::F => false,
        Moments::FT => true,
        Moments::FTS => unreachable!("the periodic product is F or FT"),
    };
    let heights: Vec<f64> = ps.iter().map(|p| p.x[2] - wall.height).collect();
    let lo = heights.iter().fold(f64::INFINITY, |a, &b| a.min(b));
    let hi = heights.iter().fold(0.0f64, |a, &b| a.max(b));
    let plan = WallPlan::new(wall, n, lo, hi, moments, sum);
    let (forces, torques) = real::forces_and_torques(x, n, ft);
    let layout = Layout {
        image: sum == Sum::Wall,
        ..Layout::new(ps, ft)
    };
    let direct: Vec<Vec<f64>> = (0..n)
        .map(|b| layout.direct(ps[b].a, forces[b], torques.as_ref().map(|t| t[b])))
        .collect();
    let mut fields = match &plan.spectral {
        Some(grid) => grid.apply(eta, ps, layout, &direct),
        None => vec![vec![0.0; layout.fields()]; n],
    };
    plan.low.add(eta, ps, layout, &direct, &mut fields);
    let (mut u, mut omega): (Vec<[f64; 3]>, Vec<[f64; 3]>) = ps
        .iter()
        .zip(&fields)
        .map(|(p, f)| layout.velocities(p.a, f))
        .unzip();
    if sum == Sum::Wall {
        PlaneMode::new(&plan.wall, lo, hi, eta).add(
            ps,
            &heights,
            &forces,
            torques.as_deref(),
            &mut u,
            &mut omega,
        );
    }
    let real = real_part(
        &plan.wall,
        sum,
        eta,
        ps,
        &forces,
        torques.as_deref(),
        lo,
        hi,
    );
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
    (out, plan.wall.xi)
}

/// The real part of the product of the lattice sum `sum`: each sphere's own screened
/// kernel and the lateral images within `r_c` of every sphere, over linked cells (module
/// docs), `[U, Omega]` per sphere (`Omega` zero without torques).
#[allow(clippy::too_many_arguments)]
fn real_part(
    wall: &WallEwald,
    sum: Sum,
    eta: f64,
    ps: &[Particle],
    forces: &[[f64; 3]],
    torques: Option<&[[f64; 3]]>,
    lo: f64,
    hi: f64,
) -> Vec<[f64; 11]> {
    let [lx, ly] = wall.lengths;
    let lz = (hi - lo) + wall.r_cut + 1.0;
    // heights from the lowest sphere's, in `[0, hi - lo]`
    let bottom = wall.height + lo;
    let cells = Cells::slab(
        [lx, ly, lz],
        wall.r_cut,
        ps.iter().map(|p| [p.x[0], p.x[1], p.x[2] - bottom]),
    );
    let sigma = 1.0 / wall.xi;
    match sum {
        Sum::Wall => {
            let split = Wall {
                eta,
                height: wall.height,
                sigma,
            };
            real::real_part(&split, &cells, ps, forces, torques, None)
        }
        Sum::Stokeslet => real::real_part(&Free { eta, sigma }, &cells, ps, forces, torques, None),
    }
}

/// The real part of the wall's split: the lane kernel of `ewald_wall_f`, and
/// `ewald_wall_ft`'s scalar kernel lane by lane.
struct Wall {
    eta: f64,
    /// The wall's plane `x3 = height`.
    height: f64,
    sigma: f64,
}

impl Split for Wall {
    #[inline(always)]
    fn pair_f<L: Lane<Elem = f64>>(&self, xa: [L; 3], xb: [L; 3], aa: L, ab: L) -> [L; 9] {
        let s = L::splat;
        ewald_wall_f_pair_lanes(xa, xb, aa, ab, s(self.eta), s(self.height), s(self.sigma))
    }
    #[inline(always)]
    fn pair_ft<L: Lane<Elem = f64>>(&self, xa: [L; 3], xb: [L; 3], aa: L, ab: L) -> [L; 36] {
        per_lane(xa, xb, aa, ab, |xa, xb, aa, ab| {
            let m = ewald_wall_ft_pair(xa, xb, aa, ab, self.eta, self.height, self.sigma);
            let mut out = [0.0; 36];
            for (k, b) in [m.uf, m.ul, m.of, m.ol].iter().enumerate() {
                for i in 0..3 {
                    out[9 * k + 3 * i..9 * k + 3 * i + 3].copy_from_slice(&b[i]);
                }
            }
            out
        })
    }
    fn pair_fts<L: Lane<Elem = f64>>(&self, _: [L; 3], _: [L; 3], _: L, _: L) -> [L; 121] {
        unreachable!("FTS near a periodic wall takes the direct sums (System::periodic_apply)")
    }
    fn self_f(&self, x: [f64; 3], a: f64) -> BlocksF {
        ewald_wall_f_self(x, a, self.eta, self.height, self.sigma)
    }
    fn self_fts(&self, _: [f64; 3], _: f64) -> Grand {
        unreachable!("FTS near a periodic wall takes the direct sums (System::periodic_apply)")
    }
    fn self_ft(&self, x: [f64; 3], a: f64) -> BlocksFT {
        ewald_wall_ft_self(x, a, self.eta, self.height, self.sigma)
    }
}
