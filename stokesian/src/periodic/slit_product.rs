//! The fast product `M x` (F or FT) in a periodic slit ([`super::slit`]), by the same
//! split as its blocks: the lower wall's periodic sum and the upper wall's (each the
//! fast product along one periodic wall, [`super::wall_product`]; the upper one on the
//! mirrored spheres and moments, its velocities mirrored back), less the Stokeslet's sum
//! both hold (the same product without Blake's image and without its mode `k_par = 0`,
//! [`Sum::Stokeslet`]), plus the remainder `R`: its mode `k_par = 0` interpolated in the
//! heights ([`PlaneMode`]) and its modes `k_par != 0` each on its own, exact in the
//! lateral phases, the heights interpolated at Chebyshev points ([`ModeSum`]).
//!
//! **The remainder's modes.** One mode of `R` between heights `h_a` and `h_b` is a sum of
//! `e^{-kappa (2 H - h_a - h_b)}`, `e^{-kappa (h_a + h_b)}` and `e^{-kappa (H + h_a -
//! h_b)}`-like terms times polynomials, no larger than `e^{-kappa s}` times the cut-off's
//! polynomial factors ([`super::slit`]), `s = 2 H - (h_max - h_min)`. Interpolating it
//! in `h_b` (and in `h_a`) at `K` Chebyshev points of the heights' interval of half-width
//! `w` leaves at most `4 (kappa w/2)^K/K!` of it; `K` is the fewest points (at least 4)
//! whose bound times `e^{-kappa s} (1 + kappa H)^3 (1 + kappa^2 a^2/6)^2` is below a
//! thousandth of the tolerance at every `kappa` up to the cut-off. Each mode's virtual
//! sources are summed into the walls' data before the one solve, so a mode costs `O(K)`
//! beside the `O(N K)` of its moments and interpolation.
//!
//! The modes are summed one by one over the spheres (`O(N n_modes K)`, `n_modes ~
//! kappa_c^2 A/(8 pi)` grows with the area) where the box is a few gaps wide, and on a
//! lateral grid otherwise ([`remainder_by_grid`]: the virtual sources spread with a
//! Gaussian, transformed, each mode taken to its virtual field points, transformed back
//! and interpolated, `O(K (N P^2 + M log M))`), whichever [`by_grid`] finds cheaper.
//!
//! Every part sums in a fixed order: the bits do not depend on the number of threads.

use super::low_modes::ModeSum;
use super::plane_mode::{interval, Nodes, PlaneMode};
use super::real::forces_and_torques;
use super::slit::{Part, SlitEwald};
use super::spectral::{signed, Spectral, Window};
use super::wall_product::{self, Sum};
use super::wall_spectral::Layout;
use crate::system::input::Particle;
use crate::system::Moments;
use rayon::prelude::*;
use rustfft::num_complex::Complex64;
use std::f64::consts::PI;

/// The most Chebyshev points of the remainder's heights.
const MAX_NODES: usize = 64;

/// `M x` at F or FT (moment-major, as [`crate::System::apply`]) of spheres `ps` (wrapped
/// into the box laterally) in the slit `slit` (its box and tolerance), viscosity `eta`.
pub(crate) fn apply(
    slit: &SlitEwald,
    eta: f64,
    ps: &[Particle],
    moments: Moments,
    x: &[f64],
) -> Vec<f64> {
    let (mut out, _) = wall_product::apply(&slit.lower, Sum::Wall, eta, ps, moments, x);
    let upper = upper_wall(slit, eta, ps, moments, x);
    let (shared, xi) = wall_product::apply(&slit.lower, Sum::Stokeslet, eta, ps, moments, x);
    let rest = remainder(slit, eta, ps, moments, x, xi);
    for (((o, u), s), r) in out.iter_mut().zip(&upper).zip(&shared).zip(&rest) {
        *o += u - s + r;
    }
    out
}

/// The upper wall's periodic sum, in its mirror: forces `P F`, torques `-P L`, and the
/// velocities mirrored back alike.
fn upper_wall(
    slit: &SlitEwald,
    eta: f64,
    ps: &[Particle],
    moments: Moments,
    x: &[f64],
) -> Vec<f64> {
    let n = ps.len();
    let mirrored: Vec<Particle> = ps.iter().map(|p| slit.mirrored(p)).collect();
    let (y, _) = wall_product::apply(
        &slit.upper,
        Sum::Wall,
        eta,
        &mirrored,
        moments,
        &mirror(x, n),
    );
    mirror(&y, n)
}

/// The remainder `R`: its mode `k_par = 0` and its modes `k_par != 0` (module docs); the
/// mode `k_par = 0` brings the walls' and the Stokeslet's to the slit's, the Stokeslet's
/// sum split at `xi` ([`super::slit`]).
fn remainder(
    slit: &SlitEwald,
    eta: f64,
    ps: &[Particle],
    moments: Moments,
    x: &[f64],
    xi: f64,
) -> Vec<f64> {
    let n = ps.len();
    let ft = moments == Moments::FT;
    let mut out = vec![0.0; x.len()];
    let heights: Vec<f64> = ps.iter().map(|p| p.x[2] - slit.bottom()).collect();
    let lo = heights.iter().fold(f64::INFINITY, |a, &b| a.min(b));
    let hi = heights.iter().fold(f64::NEG_INFINITY, |a, &b| a.max(b));
    let (forces, torques) = forces_and_torques(x, n, ft);
    let (mut u, mut omega) = (vec![[0.0; 3]; n], vec![[0.0; 3]; n]);
    PlaneMode::of(
        |a, b| slit.plane_kernel(xi, a, b, Part::Remainder),
        slit.lower.tolerance,
        slit.lengths(),
        lo,
        hi,
        eta,
    )
    .add(
        ps,
        &heights,
        &forces,
        torques.as_deref(),
        &mut u,
        &mut omega,
    );
    let a_max = ps.iter().fold(0.0f64, |m, p| m.max(p.a));
    let k_cut = slit.mode_cutoff(lo, hi, a_max, a_max, Part::Remainder, false);
    let layout = Layout {
        image: false,
        ..Layout::new(ps, ft)
    };
    let direct: Vec<Vec<f64>> = (0..n)
        .map(|b| layout.direct(ps[b].a, forces[b], torques.as_ref().map(|t| t[b])))
        .collect();
    let mut fields = vec![vec![0.0; layout.fields()]; n];
    let (lo, hi) = interval(lo, hi);
    let nodes = Nodes::new(node_count(slit, lo, hi, a_max, k_cut), lo, hi);
    let waves: Vec<[f64; 2]> = slit.remainder_modes(k_cut).collect();
    let grid = Spectral::lateral(slit.lengths(), slit.lower.tolerance, k_cut);
    if by_grid(&grid, n, waves.len()) {
        let t = nodes.t.clone();
        remainder_by_grid(
            &grid,
            k_cut,
            ps,
            slit.bottom(),
            &nodes,
            &direct,
            &mut fields,
            |k, q| slit.remainder_nodal(eta, layout, k, &t, q),
        );
    } else {
        let modes = ModeSum::new(slit.lengths(), waves, nodes, slit.bottom());
        let t = modes.nodes.t.clone();
        modes.add(ps, layout.fields(), &direct, &mut fields, |m, q| {
            slit.remainder_nodal(eta, layout, modes.modes()[m].k, &t, q)
        });
    }
    for (a, p) in ps.iter().enumerate() {
        let (v, w) = layout.velocities(p.a, &fields[a]);
        for i in 0..3 {
            out[3 * a + i] += u[a][i] + v[i];
            if ft {
                out[3 * n + 3 * a + i] += omega[a][i] + w[i];
            }
        }
    }
    out
}

/// The mirror image `z -> -z` of a moment-major F or FT vector of `n` spheres: vectors
/// (forces, velocities) `P v`, pseudovectors (torques, angular velocities) `-P v`, `P =
/// diag(1, 1, -1)`.
fn mirror(x: &[f64], n: usize) -> Vec<f64> {
    let mut y = x.to_vec();
    for a in 0..n {
        y[3 * a + 2] = -y[3 * a + 2];
        if y.len() == 6 * n {
            y[3 * n + 3 * a] = -y[3 * n + 3 * a];
            y[3 * n + 3 * a + 1] = -y[3 * n + 3 * a + 1];
        }
    }
    y
}

/// The number `K` of Chebyshev points of the heights `[lo, hi]` for the remainder's modes
/// up to `k_cut`, radii up to `a_max` (module docs).
fn node_count(slit: &SlitEwald, lo: f64, hi: f64, a_max: f64, k_cut: f64) -> usize {
    let (h, w) = (slit.gap, 0.5 * (hi - lo));
    let s = 2.0 * h - (hi - lo);
    let c = a_max * a_max / 6.0;
    let samples = 64;
    let bound = (1e-3 * slit.lower.tolerance).ln() - 4f64.ln();
    // ln of the mode's weight and of kappa w/2 at sampled kappa
    let points: Vec<(f64, f64)> = (1..=samples)
        .map(|i| {
            let k = k_cut * i as f64 / samples as f64;
            let weight = -k * s + 3.0 * (1.0 + k * h).ln() + 2.0 * (1.0 + k * k * c).ln();
            (weight, (0.5 * k * w).ln())
        })
        .collect();
    let mut ln_factorial = 0.0;
    (1..=MAX_NODES)
        .find(|&k| {
            ln_factorial += (k as f64).ln();
            k >= 4
                && points
                    .iter()
                    .all(|&(weight, ln_half)| weight + k as f64 * ln_half - ln_factorial <= bound)
        })
        .unwrap_or(MAX_NODES)
}

/// Whether the remainder's modes are cheaper on the grid (`2 N P^2` spreading and
/// interpolation and `5 M log2 M` transforms per virtual source's field) than one by one
/// (`C N n_modes`, `C = 3` from one measurement: a monolayer of 1000 spheres at area
/// fraction 0.3 in a gap of 5, tolerance `1e-6`, where the two estimates were equal; the
/// whole F product took 0.209 s with the grid and 0.316 s one by one, the three wall
/// products about 0.15 s of either, docs/periodic.md), so the grid about a third of the
/// time; never where the window would cover the whole grid.
fn by_grid(grid: &Spectral, n: usize, modes: usize) -> bool {
    let [mx, my, _] = grid.m;
    let p = grid.window([0.0; 3]).points();
    let points = (mx * my) as f64;
    let cost = 2.0 * (n * p) as f64 + 5.0 * points * points.log2();
    p < mx * my / 4 && cost < 3.0 * (n * modes) as f64
}

/// The remainder's modes `0 < |k| <= k_cut` on the lateral grid `grid` ([`Spectral::lateral`]):
/// each sphere's virtual sources `l_j(h_b) q_b` (`[j][f]`, [`Nodes::basis`] of its height
/// above `bottom`) spread, transformed, divided by the window's transform, taken by
/// `nodal(k, Q)` (as one by one, [`ModeSum`]) to the fields at the virtual field points,
/// divided by the window's transform again, transformed back and interpolated, and
/// added to `fields` weighted by `l_i(h_a)`. Every wave vector of the grid is summed
/// (both of each pair `+-k`: no factor 2).
#[allow(clippy::too_many_arguments)]
fn remainder_by_grid(
    grid: &Spectral,
    k_cut: f64,
    ps: &[Particle],
    bottom: f64,
    nodes: &Nodes,
    direct: &[Vec<f64>],
    fields: &mut [Vec<f64>],
    nodal: impl Fn([f64; 2], &[Complex64]) -> Vec<Complex64> + Sync,
) {
    let nf = direct.first().map_or(0, Vec::len);
    let kn = nodes.t.len();
    let nv = kn * nf;
    let (basis, sources) = nodes.virtual_sources(ps, bottom, direct);
    let windows: Vec<Window> = ps
        .par_iter()
        .map(|p| grid.window([p.x[0], p.x[1], 0.0]))
        .collect();
    let g = nv.div_ceil(2);
    let [mx, my, _] = grid.m;
    // per side: the window's normalisation times the cell (h_x h_y/(2 pi s^2)) over its
    // transform exp(-s^2 k^2/2)
    let cell = grid.h[0] * grid.h[1] / (2.0 * PI * grid.s2);
    let kc2 = k_cut * k_cut;
    let wave = |i: usize, d: usize| signed(i, grid.m[d]).map(|s| 2.0 * PI * s / grid.lengths[d]);
    let modes = |input: &[Complex64]| {
        let mut output = vec![Complex64::default(); mx * g * my];
        output
            .par_chunks_mut(g * my)
            .enumerate()
            .for_each(|(ix, chunk)| {
                let nx = (mx - ix) % mx;
                let Some(kx) = wave(ix, 0) else { return };
                for iy in 0..my {
                    let ny = (my - iy) % my;
                    let Some(ky) = wave(iy, 1) else { continue };
                    let k2 = kx * kx + ky * ky;
                    if k2 > kc2 || k2 == 0.0 {
                        continue;
                    }
                    let side = cell * (0.5 * grid.s2 * k2).exp();
                    // the spectrum of real field f at (ix, iy), from grid f/2 at k and -k
                    let q: Vec<Complex64> = (0..nv)
                        .map(|f| {
                            let at = |x: usize, y: usize| input[(x * g + f / 2) * my + y];
                            let (a, b) = (at(ix, iy), at(nx, ny).conj());
                            let v = if f.is_multiple_of(2) {
                                (a + b) * 0.5
                            } else {
                                (a - b) * Complex64::new(0.0, -0.5)
                            };
                            v * side
                        })
                        .collect();
                    let v = nodal([kx, ky], &q);
                    for c in 0..g {
                        let im = v.get(2 * c + 1).copied().unwrap_or_default();
                        chunk[c * my + iy] = (v[2 * c] + im * Complex64::new(0.0, 1.0)) * side;
                    }
                }
            });
        output
    };
    let nodal_fields = grid.convolve(&windows, &sources, g, g, modes);
    fields
        .par_iter_mut()
        .zip(nodal_fields.par_iter().zip(&basis))
        .for_each(|(out, (v, l))| {
            for (f, o) in out.iter_mut().enumerate() {
                *o += l
                    .iter()
                    .enumerate()
                    .map(|(i, li)| li * v[i * nf + f])
                    .sum::<f64>();
            }
        });
}
