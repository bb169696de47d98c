//! The lateral mode `k_par = 0` of the product along a periodic wall
//! ([`super::wall`]): `u_a = sum_b K(h_a, h_b) x_b` with the entire functions `d_a^m
//! d_b^n f(h_a, h_b)` of the heights (`f = Psi(h_a - h_b) - Psi(h_a + h_b) + h_b^2
//! Psi''(h_a + h_b)`), in `O(N K + K^2)` instead of `O(N^2)`.
//!
//! The heights lie in an interval `[lo, hi]`; on it each function of `(h_a, h_b)` is
//! replaced by its interpolant at `K x K` Chebyshev points (of the second kind, `t_j =
//! (lo + hi)/2 + (hi - lo)/2 cos(j pi/(K - 1))`, barycentric Lagrange basis `l_j`):
//! `sum_b f(h_a, h_b) x_b = sum_i l_i(h_a) sum_j f(t_i, t_j) sum_b l_j(h_b) x_b`. The
//! functions are entire, so the interpolants converge geometrically; `K` is the first of
//! `9, 17, 33, ...` (each set of points inside the next) whose interpolant along the
//! lines `h_a` or `h_b` at `lo`, the middle and `hi` matches every function at the next
//! set's points to a hundredth of the tolerance of their largest value.
//!
//! The blocks (units of `1/(8 pi eta A)`, [`super::wall`]'s module docs): `U += (t00 +
//! c_a t20) F + (t02 + c_a t22) c_b F + (1/2)(t01 + c_a t21) (L_y, -L_x)` and `Omega +=
//! (-G_y, G_x) + (1/4) t11 L` on the lateral components, `G = (1/2)(t10 F + t12 c_b
//! F)`, `c = a^2/6`, `t_mn = d_a^m d_b^n f`. Every sum is in a fixed order.

use super::wall::WallEwald;
use crate::system::input::Particle;
use std::f64::consts::PI;

/// The interval of heights `[lo, hi]` widened, if need be, so that Chebyshev points on
/// it are distinct.
pub(super) fn interval(lo: f64, hi: f64) -> (f64, f64) {
    let width = (hi - lo).max(1e-3 * (1.0 + hi.abs()));
    (0.5 * (lo + hi - width), 0.5 * (lo + hi + width))
}

/// Chebyshev points of the second kind on an interval, and their barycentric weights.
pub(super) struct Nodes {
    pub(super) t: Vec<f64>,
    w: Vec<f64>,
}

impl Nodes {
    /// `k` points on `[lo, hi]`.
    pub(super) fn new(k: usize, lo: f64, hi: f64) -> Nodes {
        let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
        let t = (0..k)
            .map(|j| mid + half * (j as f64 * PI / (k - 1) as f64).cos())
            .collect();
        let w = (0..k)
            .map(|j| {
                let sign = if j.is_multiple_of(2) { 1.0 } else { -1.0 };
                if j == 0 || j == k - 1 {
                    0.5 * sign
                } else {
                    sign
                }
            })
            .collect();
        Nodes { t, w }
    }

    /// Each sphere's basis `l_j(h)` at its height `h` above the plane `x3 = height`, and
    /// its virtual sources `l_j(h) q` (`[j][f]`) of its fields `q` (`direct`).
    pub(super) fn virtual_sources(
        &self,
        ps: &[Particle],
        height: f64,
        direct: &[Vec<f64>],
    ) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
        let basis: Vec<Vec<f64>> = ps.iter().map(|p| self.basis(p.x[2] - height)).collect();
        let sources = basis
            .iter()
            .zip(direct)
            .map(|(l, q)| {
                l.iter()
                    .flat_map(|lj| q.iter().map(move |v| lj * v))
                    .collect()
            })
            .collect();
        (basis, sources)
    }

    /// The Lagrange basis `l_j(z)`.
    pub(super) fn basis(&self, z: f64) -> Vec<f64> {
        if let Some(j) = self.t.iter().position(|&t| t == z) {
            let mut l = vec![0.0; self.t.len()];
            l[j] = 1.0;
            return l;
        }
        let terms: Vec<f64> = self
            .t
            .iter()
            .zip(&self.w)
            .map(|(t, w)| w / (z - t))
            .collect();
        let sum: f64 = terms.iter().sum();
        terms.iter().map(|v| v / sum).collect()
    }
}

/// The interpolated mode `k_par = 0` for spheres with heights in one interval.
pub(crate) struct PlaneMode {
    nodes: Nodes,
    /// `t_mn(t_i, t_j)` at `[i][j]`, indexed `[m][n]`.
    table: Vec<Vec<[[f64; 3]; 3]>>,
    /// `1/(8 pi eta A)`.
    unit: f64,
}

impl PlaneMode {
    /// The interpolant of `wall`'s mode `k_par = 0` for heights in `[lo, hi]`, viscosity
    /// `eta`, to `wall`'s tolerance.
    pub(crate) fn new(wall: &WallEwald, lo: f64, hi: f64, eta: f64) -> PlaneMode {
        PlaneMode::of(
            |a, b| wall.plane_kernel(a, b),
            wall.tolerance,
            wall.lengths,
            lo,
            hi,
            eta,
        )
    }

    /// The interpolant of a mode `k_par = 0` whose derivatives `d_a^m d_b^n f` are
    /// `kernel(h_a, h_b)` (indexed `[m][n]`, entire in the heights) for heights in `[lo,
    /// hi]`, viscosity `eta`, box `lengths`, to tolerance `tol`.
    pub(crate) fn of(
        kernel: impl Fn(f64, f64) -> [[f64; 3]; 3],
        tol: f64,
        lengths: [f64; 2],
        lo: f64,
        hi: f64,
        eta: f64,
    ) -> PlaneMode {
        let (lo, hi) = interval(lo, hi);
        let table = |nodes: &Nodes| -> Vec<Vec<[[f64; 3]; 3]>> {
            (nodes.t.iter())
                .map(|&a| nodes.t.iter().map(|&b| kernel(a, b)).collect())
                .collect()
        };
        let mut k = 9;
        loop {
            let nodes = Nodes::new(k, lo, hi);
            let values = table(&nodes);
            if k >= 257 || converged(&kernel, tol, &nodes, &values, lo, hi) {
                let area = lengths[0] * lengths[1];
                return PlaneMode {
                    nodes,
                    table: values,
                    unit: 1.0 / (8.0 * PI * eta * area),
                };
            }
            k = 2 * k - 1;
        }
    }

    /// The mode's velocities (lateral, added to `u`) and, with torques, angular
    /// velocities (added to `omega`) of spheres `ps` at heights `heights` under `forces`
    /// and `torques`.
    pub(crate) fn add(
        &self,
        ps: &[Particle],
        heights: &[f64],
        forces: &[[f64; 3]],
        torques: Option<&[[f64; 3]]>,
        u: &mut [[f64; 3]],
        omega: &mut [[f64; 3]],
    ) {
        let k = self.nodes.t.len();
        let basis: Vec<Vec<f64>> = heights.iter().map(|&h| self.nodes.basis(h)).collect();
        // per node j: F, c F, L (lateral components)
        let mut q = vec![[0.0; 6]; k];
        for (b, l) in basis.iter().enumerate() {
            let c = ps[b].a * ps[b].a / 6.0;
            let (f, t) = (forces[b], torques.map_or([0.0; 3], |t| t[b]));
            let v = [f[0], f[1], c * f[0], c * f[1], t[0], t[1]];
            for (qj, lj) in q.iter_mut().zip(l) {
                for (x, y) in qj.iter_mut().zip(v) {
                    *x += lj * y;
                }
            }
        }
        // per node i: U's two parts (without and with c_a), Omega
        let nodal: Vec<[[f64; 2]; 3]> = (0..k)
            .map(|i| {
                let mut acc = [[0.0; 2]; 3];
                for (j, v) in q.iter().enumerate() {
                    let t = &self.table[i][j];
                    let rot = [v[5], -v[4]];
                    for d in 0..2 {
                        acc[0][d] += t[0][0] * v[d] + t[0][2] * v[2 + d] + 0.5 * t[0][1] * rot[d];
                        acc[1][d] += t[2][0] * v[d] + t[2][2] * v[2 + d] + 0.5 * t[2][1] * rot[d];
                    }
                    let g = [
                        0.5 * (t[1][0] * v[0] + t[1][2] * v[2]),
                        0.5 * (t[1][0] * v[1] + t[1][2] * v[3]),
                    ];
                    acc[2][0] += -g[1] + 0.25 * t[1][1] * v[4];
                    acc[2][1] += g[0] + 0.25 * t[1][1] * v[5];
                }
                acc
            })
            .collect();
        for (a, l) in basis.iter().enumerate() {
            let c = ps[a].a * ps[a].a / 6.0;
            let mut sum = [[0.0; 2]; 3];
            for (li, n) in l.iter().zip(&nodal) {
                for (s, v) in sum.iter_mut().zip(n) {
                    s[0] += li * v[0];
                    s[1] += li * v[1];
                }
            }
            for d in 0..2 {
                u[a][d] += self.unit * (sum[0][d] + c * sum[1][d]);
                if torques.is_some() {
                    omega[a][d] += self.unit * sum[2][d];
                }
            }
        }
    }
}

/// Whether the interpolant at `nodes` of every `t_mn` matches it at the next set's
/// points along the lines `h_a` or `h_b` at `lo`, the middle and `hi` (module docs).
fn converged(
    kernel: &impl Fn(f64, f64) -> [[f64; 3]; 3],
    tol: f64,
    nodes: &Nodes,
    values: &[Vec<[[f64; 3]; 3]>],
    lo: f64,
    hi: f64,
) -> bool {
    let k = nodes.t.len();
    let finer = Nodes::new(2 * k - 1, lo, hi);
    let largest = values
        .iter()
        .flatten()
        .flatten()
        .flatten()
        .fold(0.0f64, |a, v| a.max(v.abs()));
    let bound = 1e-2 * tol * largest;
    // the lines through the first, middle and last node (lo, mid, hi are nodes)
    for &fixed in &[0, (k - 1) / 2, k - 1] {
        for &z in &finer.t {
            let l = nodes.basis(z);
            for along_a in [true, false] {
                let exact = if along_a {
                    kernel(z, nodes.t[fixed])
                } else {
                    kernel(nodes.t[fixed], z)
                };
                for m in 0..3 {
                    for n in 0..3 {
                        let interpolated: f64 = (0..k)
                            .map(|j| {
                                let v = if along_a {
                                    values[j][fixed]
                                } else {
                                    values[fixed][j]
                                };
                                l[j] * v[m][n]
                            })
                            .sum();
                        if (interpolated - exact[m][n]).abs() > bound {
                            return false;
                        }
                    }
                }
            }
        }
    }
    true
}
