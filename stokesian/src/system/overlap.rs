//! Overlapping spheres: what [`Overlap`] asks for, and with [`Overlap::Rpy`] the pairs
//! that take the Rotne-Prager-Yamakawa overlap forms and the damping of spheres that cut
//! a boundary ([`Rpy`]); the typed error of what the overlap forms do not cover
//! ([`OverlapError`]).
//!
//! Pairs: the generated correction kernels `kernels::overlap_f` and
//! `kernels::overlap_ft` (overlap form minus far form, zero at contact) are added to the
//! blocks of the overlapping pairs only, in a scalar pass after the lane tiles
//! (`mobility::assembly`, `mobility::tiled`): the far form is the free-space part of
//! every pair kernel, so a pair's block becomes the overlap form plus the confinement's
//! image terms. The corrections are divergence-free over either centre (the RPY tensor
//! and the far form both are: surface averages of the Stokeslet, whose curl parts
//! `k(r) [r/r]_x` have zero divergence too), so the Brownian drift of the generated
//! divergence kernels stays exact.
//!
//! Boundaries (Usabiaga et al., J. Chem. Phys. 146, 134104 (2017), Appendix 1, as
//! libMobility's NBody solver does for a wall): a sphere whose centre is at a distance
//! `0 < d < a` from a boundary is evaluated with its centre moved out along the normal
//! to `d = a`, and every block of its rows and columns (self and pair, direct and
//! image) is multiplied by `b_i = clamp(d / a, 0, 1)`: the mobility is `B M(clamped) B`,
//! `B = diag(b_i)`, symmetric positive definite whenever `M` at the clamped centres is.
//! With several boundaries each is clamped in turn and `b_i` is the product over the
//! boundaries: one boundary's factor where only one is cut (the wall's damping), a
//! smooth factor where two are (the minimum has a kink where the distances cross), and
//! still `B M B`. A sphere that cannot be moved clear of every boundary (a slit
//! narrower than its diameter) is refused.
//!
//! The drift of the damped mobility ([`Damping::drift`]): with `x~` the clamped centres
//! (`dx~_q/dx_q = P_q = I - sum_c n_c n_c^T` over the boundaries `c` that cut sphere `q`,
//! perpendicular to each other), `K_pq` the force columns of the blocks at `x~` (overlap
//! corrections included) and `D_pq = sum_j d/dx~_qj K_pq,ij` the generated divergence,
//!
//! `sum_q div_q (b_p b_q K_pq) = b_p [ sum_q b_q D_pq - sum_q b_q sum_c N^c_pq
//!     + sum_q K_pq grad b_q + [p cut] K_pp grad b_p ]`,
//!
//! where `N^c_pq = sum_jk n_j n_k d/dx~_qk K_pq,ij` (`kernels::pair_along`,
//! `kernels::self_along`, `kernels::overlap_along`) is the part of the divergence that
//! holding `q` on the plane removes, and `grad b_q = sum_c (prod_{c' != c} f_c') n_c / a_q`
//! (`f_c = d_c / a_q`, the factor of boundary `c`). A sphere cut by two boundaries that
//! are not perpendicular has no such drift ([`OverlapError::Boundary`]).

use super::input::Particle;
use super::Moments;
use kernels::Confinement;
use thiserror::Error;

/// What to do with spheres that overlap each other or cut a boundary.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Overlap {
    /// Refuse them ([`crate::InputError::Overlap`], [`crate::InputError::OverlapsBoundary`]).
    #[default]
    Refuse,
    /// Accept them and evaluate the far forms anyway (not positive definite where
    /// spheres overlap).
    Far,
    /// Accept them: overlapping pairs take the Rotne-Prager-Yamakawa overlap forms and
    /// spheres cutting a boundary are damped (module docs); symmetric positive definite.
    /// F and FT only.
    Rpy,
}

/// `false` is [`Overlap::Refuse`], `true` is [`Overlap::Far`] (what `allow_overlap`
/// meant).
impl From<bool> for Overlap {
    fn from(allow: bool) -> Overlap {
        if allow {
            Overlap::Far
        } else {
            Overlap::Refuse
        }
    }
}

/// What the RPY overlap forms do not cover, asked of a system with [`Overlap::Rpy`].
#[derive(Debug, Error, PartialEq, Eq)]
pub enum OverlapError {
    /// Two spheres overlap, and `what` has no overlap form.
    #[error("particles {first} and {second} overlap: the RPY overlap forms cover forces and torques (F, FT) only, not {what}")]
    Pair {
        /// First particle.
        first: usize,
        /// Second particle.
        second: usize,
        /// What was asked for.
        what: &'static str,
    },
    /// A sphere cuts a boundary, and `what` has no damped form.
    #[error("particle {index} cuts a boundary: the damped mobility covers forces and torques (F, FT) only, not {what}")]
    Boundary {
        /// Particle index.
        index: usize,
        /// What was asked for.
        what: &'static str,
    },
}

/// What [`Overlap::Rpy`] changes in a system where something overlaps.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Rpy {
    /// The overlapping pairs `(i, j)`, `i < j`, sorted, at the evaluated centres.
    pub pairs: Vec<(usize, usize)>,
    /// The damping of spheres cutting a boundary, if any does.
    pub damping: Option<Damping>,
}

/// Spheres cutting a boundary: the centres the kernels see and the factors `b_i`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Damping {
    /// The particles with each centre moved clear of every boundary.
    pub at: Vec<Particle>,
    /// `b_i`: the product over the boundaries of `clamp(d / a, 0, 1)`.
    pub b: Vec<f64>,
    /// For each particle, the boundaries that cut it: `(normal, d / a)`.
    pub cuts: Vec<Vec<([f64; 3], f64)>>,
}

impl Damping {
    /// The damping of `particles` (every centre inside the fluid), if any sphere cuts a
    /// boundary; `Err(index)` for a sphere that cannot be moved clear of every
    /// boundary at once.
    pub fn of(conf: &Confinement, particles: &[Particle]) -> Result<Option<Damping>, usize> {
        let planes = conf.boundaries();
        let mut at = particles.to_vec();
        let mut b = vec![1.0; particles.len()];
        let mut cuts = vec![Vec::new(); particles.len()];
        let mut any = false;
        for (i, p) in at.iter_mut().enumerate() {
            for plane in &planes {
                let d = plane.distance(p.x);
                if d < p.a {
                    any = true;
                    let f = (d / p.a).clamp(0.0, 1.0);
                    b[i] *= f;
                    cuts[i].push((plane.normal, f));
                    let up = p.a - d;
                    for (x, n) in p.x.iter_mut().zip(plane.normal) {
                        *x += up * n;
                    }
                }
            }
            // clear of every plane, to the rounding of the moves
            if planes.iter().any(|q| q.distance(p.x) < p.a * (1.0 - 1e-12)) {
                return Err(i);
            }
        }
        Ok(any.then_some(Damping { at, b, cuts }))
    }
}

impl Damping {
    /// The first sphere cut by two boundaries that are not perpendicular, whose drift
    /// [`Damping::drift`] does not cover.
    pub fn oblique(&self) -> Option<usize> {
        self.cuts.iter().position(|c| {
            c.iter().enumerate().any(|(k, (n, _))| {
                c[k + 1..]
                    .iter()
                    .any(|(m, _)| (0..3).map(|i| n[i] * m[i]).sum::<f64>().abs() > 1e-12)
            })
        })
    }

    /// Adds to `acc` (per particle, rows `U` then `Omega`, before the row factor `b_p`)
    /// what the damping adds to `sum_q b_q D_pq` (module docs): for every sphere `q`
    /// that a boundary cuts and every `p`, `K_pq grad b_q - b_q sum_c N^c_pq` (and
    /// `K_qq grad b_q` once more for `p = q`), with the overlap corrections of the
    /// overlapping `pairs` (sorted, at the clamped centres).
    pub fn drift(
        &self,
        conf: &Confinement,
        eta: f64,
        pairs: &[(usize, usize)],
        acc: &mut [[f64; 6]],
    ) {
        let ps = &self.at;
        for (q, cuts) in self.cuts.iter().enumerate().filter(|(_, c)| !c.is_empty()) {
            let pq = &ps[q];
            // grad b_q = sum_c (prod of the other factors) n_c / a_q
            let mut grad = [0.0; 3];
            for (c, (n, _)) in cuts.iter().enumerate() {
                let others: f64 = cuts
                    .iter()
                    .enumerate()
                    .filter(|&(k, _)| k != c)
                    .map(|(_, &(_, f))| f)
                    .product();
                for (g, nk) in grad.iter_mut().zip(n) {
                    *g += others * nk / pq.a;
                }
            }
            for (p, pp) in ps.iter().enumerate() {
                // the force columns K_pq (rows U, Omega) and sum_c N^c_pq
                let (uf, of, along) = if p == q {
                    let m = kernels::self_ft(conf, eta, pq.x, pq.a);
                    let along = |n: [f64; 3]| kernels::self_along(conf, eta, pq.x, pq.a, n).a;
                    (
                        m.uf,
                        m.of,
                        cuts.iter().map(|&(n, _)| along(n)).collect::<Vec<_>>(),
                    )
                } else {
                    let mut m = kernels::pair_ft(conf, eta, pp.x, pp.a, pq.x, pq.a);
                    let overlapping = pairs.binary_search(&(p.min(q), p.max(q))).is_ok();
                    if overlapping {
                        m += &kernels::overlap_ft(pp.x, pq.x, pp.a, pq.a, eta);
                    }
                    let along = |n: [f64; 3]| {
                        let mut d = kernels::pair_along(conf, eta, pp.x, pp.a, pq.x, pq.a, n).a;
                        if overlapping {
                            let c = kernels::overlap_along(pp.x, pq.x, pp.a, pq.a, eta, n).a;
                            for (d, c) in d.iter_mut().zip(c) {
                                *d += c;
                            }
                        }
                        d
                    };
                    (m.uf, m.of, cuts.iter().map(|&(n, _)| along(n)).collect())
                };
                let times = if p == q { 2.0 } else { 1.0 };
                for i in 0..3 {
                    let (mut u, mut o) = (0.0, 0.0);
                    for j in 0..3 {
                        u += uf[i][j] * grad[j];
                        o += of[i][j] * grad[j];
                    }
                    acc[p][i] += times * u;
                    acc[p][3 + i] += times * o;
                }
                for n in &along {
                    for (a, d) in acc[p].iter_mut().zip(n) {
                        *a -= self.b[q] * d;
                    }
                }
            }
        }
    }
}

impl Rpy {
    /// The error for `what` if this system overlaps anything.
    pub fn refuse(&self, what: &'static str) -> Result<(), OverlapError> {
        if let Some(&(first, second)) = self.pairs.first() {
            return Err(OverlapError::Pair {
                first,
                second,
                what,
            });
        }
        self.refuse_damping(what)
    }

    /// The error for `what` if a sphere is damped.
    pub fn refuse_damping(&self, what: &'static str) -> Result<(), OverlapError> {
        match self
            .damping
            .as_ref()
            .and_then(|d| d.b.iter().position(|&b| b < 1.0))
        {
            Some(index) => Err(OverlapError::Boundary { index, what }),
            None => Ok(()),
        }
    }
}

/// The RPY correction `M^{ab}` (overlap form minus far form) truncated to `moments` (F
/// or FT), row-major `K x K` in grand order into `out`.
pub(crate) fn correction(moments: Moments, eta: f64, p: &Particle, q: &Particle, out: &mut [f64]) {
    match moments {
        Moments::F => {
            let c = kernels::overlap_f(p.x, q.x, p.a, q.a, eta);
            for i in 0..3 {
                out[3 * i..3 * i + 3].copy_from_slice(&c.uf[i]);
            }
        }
        Moments::FT => {
            let m = kernels::overlap_ft(p.x, q.x, p.a, q.a, eta).matrix();
            for i in 0..6 {
                out[6 * i..6 * i + 6].copy_from_slice(&m[i]);
            }
        }
        Moments::FTS => unreachable!("refused before: no overlap form with stresslets"),
    }
}
