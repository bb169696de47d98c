//! The fast product `u = M x` (F and FT): a fast multipole method whose expansions are
//! the generator's (`kernels::expansion`: every confinement's far field as derivative
//! sources of the potential `|r|` at the spheres and at their images), whose near field
//! is the exact pair kernels (`near`), on an adaptive octree (`tree`) with Cartesian
//! Taylor expansions (`taylor`).
//!
//! For a target sphere `a` at `x` and the sources `b` far from it (a cell pair accepted
//! by the tree), the product is the field point's Faxén functional of the potentials
//! `Psi_k` (`kernels::expansion`), `u_k = (1 + a_a^2/6 lap) Psi_k / (8 pi eta)` and
//! `omega_m = 1/2 eps_mjk d_j Psi_k / (8 pi eta)`, taken from the local expansion of
//! `Psi` about the target's leaf. A source's image contributes through its own multipole
//! about the mirrored centre of its cell. Every sum runs in an order fixed by the tree,
//! which the positions alone fix: the result is the same on any number of threads.
//!
//! The expansion order `p` and the acceptance parameter `theta` come from the tolerance
//! `eps` on the relative 2-norm error of the product ([`FastProduct::new`]).

mod near;
mod taylor;
mod tree;

use crate::system::{Moments, System};
use kernels::expansion::{Mirror, NoExpansion, PotentialSource};
use kernels::lanes::Isa;
use kernels::Confinement;
use near::{near_row, Near, NearF, NearFT, Soa};
use rayon::prelude::*;
use taylor::Indices;
use tree::Tree;

/// Why the fast product cannot run.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FmmError {
    /// The tolerance is outside `[1e-10, 1e-3]`.
    #[error("the fast product's tolerance must be in [1e-10, 1e-3], got {0:e}")]
    Tolerance(f64),
    /// The confinement's Green's function has no expansion.
    #[error("the confinement `{confinement}` has no fast product: {reason}")]
    NoExpansion {
        /// The confinement.
        confinement: &'static str,
        /// Why.
        reason: NoExpansion,
    },
    /// The truncation has no fast product (FTS).
    #[error("the fast product covers the F and FT truncations, not {0:?}")]
    Moments(Moments),
    /// An expansion order beyond what the potential's generated derivatives serve
    /// (`kernels::expansion::RADIAL`) for this confinement's sources.
    #[error("the fast product's order must be at most {max} here, got {order}")]
    Order {
        /// The order asked for.
        order: usize,
        /// The highest for this confinement and truncation.
        max: usize,
    },
    /// A periodic system.
    #[error("the fast product does not cover periodic boxes; use the Ewald product")]
    Periodic,
}

/// The parameters of the fast product for a tolerance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FastProduct {
    /// The tolerance on `|u_fast - u_direct|_2 / |u_direct|_2`.
    pub eps: f64,
    /// The expansions' order.
    pub order: usize,
    /// The acceptance parameter: a source cell's multipole reaches a target cell when
    /// `r_t + r_s < theta |c_t - c_s|`.
    pub theta: f64,
    /// The most particles in a leaf.
    pub leaf: usize,
}

impl FastProduct {
    /// The parameters for a tolerance `eps` in `[1e-10, 1e-3]`: `theta = 0.4`, leaves of
    /// at most 64 and the order `p = 2 log10(1/eps) - 4` (at least 2) beyond the
    /// sources' highest derivative. Measured against the direct product (the `fmm::`
    /// tests, docs/fmm.md): the error falls by seven to ten for every two orders (a wall,
    /// F: 2.6e-6, 3.7e-7 and 5.3e-8 at `p = 4, 6, 8` for a monolayer of 10^4 spheres),
    /// and stays below `eps` for every confinement, F and FT.
    pub fn new(eps: f64) -> Result<FastProduct, FmmError> {
        if !(1e-10..=1e-3).contains(&eps) {
            return Err(FmmError::Tolerance(eps));
        }
        let order = ((2.0 * (1.0 / eps).log10()).ceil() as usize)
            .saturating_sub(4)
            .max(2);
        Ok(FastProduct {
            eps,
            order,
            theta: 0.4,
            leaf: 64,
        })
    }
}

/// The rows of a table grouped by `(point, channel, d)`: one derivative source per
/// group and particle.
struct Group {
    point: usize,
    channel: usize,
    alpha: usize,
    rows: Vec<PotentialSource>,
}

fn groups(table: &[PotentialSource], ix: &Indices) -> Vec<Group> {
    let mut out: Vec<Group> = Vec::new();
    let mut sorted: Vec<PotentialSource> = table.to_vec();
    sorted.sort_by_key(|s| (s.point, s.channel, s.d));
    for s in sorted {
        let alpha = ix.index(s.d);
        match out.last_mut() {
            Some(g) if g.point == s.point && g.channel == s.channel && g.alpha == alpha => {
                g.rows.push(s)
            }
            _ => out.push(Group {
                point: s.point,
                channel: s.channel,
                alpha,
                rows: vec![s],
            }),
        }
    }
    out
}

/// Whether the potential's generated derivatives serve `settings`' order for `table`.
fn check_order(settings: &FastProduct, table: &[PotentialSource]) -> Result<(), FmmError> {
    let max = kernels::expansion::RADIAL.len() - 1 - highest(table);
    if settings.order > max {
        return Err(FmmError::Order {
            order: settings.order,
            max,
        });
    }
    Ok(())
}

/// The highest derivative of a table's sources.
fn highest(table: &[PotentialSource]) -> usize {
    table
        .iter()
        .map(|s| s.d.iter().map(|&e| e as usize).sum::<usize>())
        .max()
        .unwrap_or(0)
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// The fast product of `K` moments per particle (`K = 3`: forces; 6: forces and
/// torques), particle-major, in the particles' order.
#[allow(clippy::too_many_arguments)]
fn product<P: Near<K>, const K: usize>(
    conf: &Confinement,
    eta: f64,
    near: &P,
    table: &[PotentialSource],
    particles: &[([f64; 3], f64)],
    xs: &[[f64; K]],
    settings: &FastProduct,
    isa: Isa,
) -> Vec<[f64; K]> {
    let mirrors: Vec<Mirror> = conf.mirrors();
    let weights = conf.image_weights();
    let points: Vec<[f64; 3]> = particles.iter().map(|p| p.0).collect();
    let tree = Tree::new(&points, settings.leaf, settings.theta, &mirrors);
    let sorted: Vec<([f64; 3], f64)> = tree.order.iter().map(|&i| particles[i]).collect();
    let moments: Vec<[f64; K]> = tree.order.iter().map(|&i| xs[i]).collect();
    // the expansions carry `order` orders beyond the sources' highest derivative
    let ix = Indices::new(settings.order + highest(table));
    let len = ix.len();
    let kinds = 1 + mirrors.len();
    let groups = groups(table, &ix);
    let centre = |c: usize, point: usize| {
        let c = tree.cells[c].centre;
        if point == 0 {
            c
        } else {
            mirrors[point - 1].image(c)
        }
    };
    // upward: the leaves' multipoles, then their parents' (3 channels per point)
    let block = kinds * 3 * len;
    let mut multipoles: Vec<Vec<f64>> = vec![Vec::new(); tree.cells.len()];
    let leaves: Vec<usize> = (0..tree.cells.len())
        .filter(|&c| tree.cells[c].is_leaf())
        .collect();
    let formed: Vec<(usize, Vec<f64>)> = leaves
        .par_iter()
        .map(|&c| {
            let cell = &tree.cells[c];
            let mut m = vec![0.0; block];
            let mut mono = vec![0.0; len];
            for s in cell.start..cell.end {
                let (y, a) = sorted[s];
                let v = &moments[s];
                for point in 0..kinds {
                    let (at, h) = if point == 0 {
                        (y, 0.0)
                    } else {
                        let mirror = &mirrors[point - 1];
                        (mirror.image(y), mirror.distance(y))
                    };
                    ix.monomials(sub(centre(c, point), at), &mut mono);
                    for g in groups.iter().filter(|g| g.point == point) {
                        let strength: f64 = g
                            .rows
                            .iter()
                            .map(|r| {
                                let w = if point == 0 { 1.0 } else { weights[r.weight] };
                                r.coef
                                    * w
                                    * h.powi(r.h_power as i32)
                                    * (a * a).powi(r.a2 as i32)
                                    * v[r.moment]
                            })
                            .sum();
                        let off = (point * 3 + g.channel) * len;
                        taylor::add_source(&ix, g.alpha, strength, &mono, &mut m[off..off + len]);
                    }
                }
            }
            (c, m)
        })
        .collect();
    for (c, m) in formed {
        multipoles[c] = m;
    }
    for level in tree.levels.iter().rev() {
        let formed: Vec<(usize, Vec<f64>)> = level
            .par_iter()
            .filter(|&&c| !tree.cells[c].is_leaf())
            .map(|&c| {
                let mut m = vec![0.0; block];
                let mut mono = vec![0.0; len];
                for &child in &tree.cells[c].children {
                    for point in 0..kinds {
                        ix.monomials(sub(centre(c, point), centre(child, point)), &mut mono);
                        let off = point * 3 * len;
                        for ch in 0..3 {
                            let r = off + ch * len..off + (ch + 1) * len;
                            taylor::translate_multipole(
                                &ix,
                                &multipoles[child][r.clone()],
                                &mono,
                                &mut m[r],
                            );
                        }
                    }
                }
                (c, m)
            })
            .collect();
        for (c, m) in formed {
            multipoles[c] = m;
        }
    }
    // across: each cell's local expansion from the multipoles that reach it
    let mut locals: Vec<Vec<f64>> = (0..tree.cells.len())
        .into_par_iter()
        .map(|t| {
            let mut l = vec![0.0; 3 * len];
            if tree.far[t].is_empty() {
                return l;
            }
            let mut d = vec![0.0; len];
            let mut work = vec![0.0; len];
            let ct = tree.cells[t].centre;
            for &s in &tree.far[t] {
                for point in 0..kinds {
                    ix.potential_derivatives(sub(ct, centre(s, point)), &mut d, &mut work);
                    let off = point * 3 * len;
                    taylor::multipole_to_local(&ix, &multipoles[s][off..off + 3 * len], &d, &mut l);
                }
            }
            l
        })
        .collect();
    // downward: each cell's local expansion moved into its children
    for level in &tree.levels {
        let moved: Vec<(usize, Vec<f64>)> = level
            .par_iter()
            .flat_map_iter(|&c| {
                let parent = &locals[c];
                let cell = &tree.cells[c];
                let mut mono = vec![0.0; len];
                let mut moved = Vec::with_capacity(cell.children.len());
                for &child in &cell.children {
                    ix.monomials(sub(tree.cells[child].centre, cell.centre), &mut mono);
                    let mut add = vec![0.0; 3 * len];
                    for ch in 0..3 {
                        let r = ch * len..(ch + 1) * len;
                        taylor::translate_local(&ix, &parent[r.clone()], &mono, &mut add[r]);
                    }
                    moved.push((child, add));
                }
                moved
            })
            .collect();
        for (child, add) in moved {
            for (l, v) in locals[child].iter_mut().zip(add) {
                *l += v;
            }
        }
    }
    // the leaves: the local expansions' Faxén functional and the near field
    let soa = Soa::new(&sorted, &moments);
    let unit = 1.0 / (8.0 * std::f64::consts::PI * eta);
    let lap = [
        ix.index([2, 0, 0]),
        ix.index([0, 2, 0]),
        ix.index([0, 0, 2]),
    ];
    let grad = [
        ix.index([1, 0, 0]),
        ix.index([0, 1, 0]),
        ix.index([0, 0, 1]),
    ];
    let rows: Vec<(usize, Vec<[f64; K]>)> = leaves
        .par_iter()
        .map(|&c| {
            let cell = &tree.cells[c];
            let mut out = vec![[0.0; K]; cell.end - cell.start];
            let sources: Vec<(usize, usize)> = tree.near[c]
                .iter()
                .map(|&s| (tree.cells[s].start, tree.cells[s].end))
                .collect();
            near_row(&soa, near, (cell.start, cell.end), &sources, isa, &mut out);
            let l = &locals[c];
            let mut mono = vec![0.0; len];
            for (o, s) in out.iter_mut().zip(cell.start..cell.end) {
                let (x, a) = sorted[s];
                ix.monomials(sub(x, cell.centre), &mut mono);
                let at = |ch: usize, k: usize| {
                    taylor::local_derivative(&ix, &l[ch * len..(ch + 1) * len], k, &mono)
                };
                for k in 0..3 {
                    let laplacian: f64 = lap.iter().map(|&q| at(k, q)).sum();
                    o[k] += unit * (at(k, 0) + a * a / 6.0 * laplacian);
                }
                if K == 6 {
                    for m in 0..3 {
                        let (j, k) = ((m + 1) % 3, (m + 2) % 3);
                        // 1/2 (d_j Psi_k - d_k Psi_j), (m, j, k) cyclic
                        o[3 + m] += unit * 0.5 * (at(k, grad[j]) - at(j, grad[k]));
                    }
                }
            }
            (cell.start, out)
        })
        .collect();
    let mut res = vec![[0.0; K]; particles.len()];
    for (start, out) in rows {
        for (k, o) in out.into_iter().enumerate() {
            res[tree.order[start + k]] = o;
        }
    }
    res
}

/// The fast product for a truncation (F: `torques` false, 3 per particle; FT: 6) of `xs`
/// (particle-major) with the confinement's checked `table`.
#[allow(clippy::too_many_arguments)]
fn apply_moments(
    conf: &Confinement,
    eta: f64,
    torques: bool,
    table: &[PotentialSource],
    particles: &[([f64; 3], f64)],
    xs: &[f64],
    settings: &FastProduct,
    isa: Isa,
) -> Vec<f64> {
    fn run<P: Near<K>, const K: usize>(
        conf: &Confinement,
        eta: f64,
        near: &P,
        table: &[PotentialSource],
        ps: &[([f64; 3], f64)],
        xs: &[f64],
        settings: &FastProduct,
        isa: Isa,
    ) -> Vec<f64> {
        let v: Vec<[f64; K]> = xs
            .chunks(K)
            .map(|c| std::array::from_fn(|i| c[i]))
            .collect();
        product::<P, K>(conf, eta, near, table, ps, &v, settings, isa).concat()
    }
    if torques {
        run(
            conf,
            eta,
            &NearFT { conf, eta },
            table,
            particles,
            xs,
            settings,
            isa,
        )
    } else {
        run(
            conf,
            eta,
            &NearF { conf, eta },
            table,
            particles,
            xs,
            settings,
            isa,
        )
    }
}

impl System {
    /// The same system with [`System::apply`] (and with it the far-field F and FT
    /// velocities, [`System::velocities`]) by the fast multipole method to the relative
    /// tolerance `eps` ([`System::apply_fmm`]), and with it the Lanczos noise and `M F` of
    /// Brownian dynamics; FTS products, dense matrices, resistances, Cholesky noise and
    /// the drift stay as they are. The fast product runs in
    /// double precision whatever [`System::with_precision`] says. Refused for a tolerance
    /// outside `[1e-10, 1e-3]`, a periodic box, or a confinement without an expansion (a
    /// box given later, [`System::periodic`], takes its own products instead).
    pub fn with_fmm(mut self, eps: f64) -> Result<System, FmmError> {
        let settings = FastProduct::new(eps)?;
        if self.periodic_ref().is_some() {
            return Err(FmmError::Periodic);
        }
        for torques in [false, true] {
            let table = self.table(torques)?;
            check_order(&settings, table)?;
        }
        self.set_fast(Some(settings));
        Ok(self)
    }

    /// The fast product's parameters if [`System::apply`] takes it.
    pub fn fmm(&self) -> Option<FastProduct> {
        self.fast()
    }

    /// The confinement's derivative sources (forces, or forces and torques).
    fn table(&self, torques: bool) -> Result<&'static [PotentialSource], FmmError> {
        self.confinement()
            .potential_sources(torques)
            .map_err(|reason| FmmError::NoExpansion {
                confinement: self.confinement().name(),
                reason,
            })
    }

    /// `M x` by the fast multipole method to the relative tolerance `eps` in the 2-norm
    /// (module docs): F and FT, any confinement whose Green's function has image
    /// structure. `x` and the result in the layout of [`System::apply`]; the same
    /// overlap handling. In double precision on the widest instruction set.
    pub fn apply_fmm(&self, moments: Moments, x: &[f64], eps: f64) -> Result<Vec<f64>, FmmError> {
        self.apply_fast(moments, x, &FastProduct::new(eps)?)
    }

    /// [`System::apply_fmm`] with the method's parameters given ([`FastProduct`]).
    pub fn apply_fast(
        &self,
        moments: Moments,
        x: &[f64],
        settings: &FastProduct,
    ) -> Result<Vec<f64>, FmmError> {
        if self.periodic_ref().is_some() {
            return Err(FmmError::Periodic);
        }
        if moments == Moments::FTS {
            return Err(FmmError::Moments(moments));
        }
        self.assert_product(moments, x);
        let torques = moments == Moments::FT;
        let table = self.table(torques)?;
        check_order(settings, table)?;
        let (conf, eta) = (self.confinement(), self.viscosity());
        Ok(self.with_overlaps(moments, x, |ps, xs| {
            apply_moments(conf, eta, torques, table, ps, xs, settings, Isa::best())
        }))
    }
}
