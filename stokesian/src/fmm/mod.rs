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

use crate::mobility::tiled::{ExchangingF, ExchangingFT, LaneProduct};
use crate::system::{Moments, System};
use kernels::expansion::{Mirror, NoExpansion, PotentialSource};
use kernels::lanes::{self, Isa, Lane, WithLanes};
use kernels::Confinement;
use near::{near_block, near_row, Soa};
use rayon::prelude::*;
use taylor::{Bases, Biharmonic, Indices};
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
    /// Parameters given by hand ([`System::with_fast`], [`System::apply_fast`]) out of
    /// range.
    #[error("the fast product's {0}")]
    Settings(&'static str),
}

/// The parameters of the fast product for a tolerance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FastProduct {
    /// The tolerance on `|u_fast - u_direct|_2 / |u_direct|_2`.
    pub eps: f64,
    /// The expansions' order `p`: the multipoles about each point carry `p + degree`
    /// orders (`degree`: the largest `|d| - 2 a2` of the point's rows, 2 or 3 at the
    /// sphere, up to 5 at an image), the local expansions `p` (`p + 1` for FT, whose
    /// rotation takes their gradient).
    pub order: usize,
    /// The acceptance parameter: a source cell's multipole reaches a target cell when
    /// `r_t + r_s < theta |c_t - c_s|`.
    pub theta: f64,
    /// The most particles in a leaf.
    pub leaf: usize,
}

impl FastProduct {
    /// The parameters for a tolerance `eps` in `[1e-10, 1e-3]`: `theta = 0.4`, leaves of
    /// at most 100 and the order `p = ceil(2 log10(1/eps) - 1.7)` (5, 11, 17 and 19 at
    /// 1e-3, 1e-6, 1e-9 and 1e-10) beyond the sources' degree (`degree`). Calibrated on the
    /// hardest case measured, a 3-D suspension whose far field carries most of the norm
    /// (2x10^4 spheres of radii 0.5-1 in a box of 75 above a wall, F; docs/fmm.md): the
    /// error falls by about ten for every two orders, `0.046 * 0.33^p`, and `p` keeps it
    /// below `eps/3`. The `fmm::` tests measure every confinement, F and FT, with these
    /// leaves and with leaves of 16 (whose far field is as large a share).
    pub fn new(eps: f64) -> Result<FastProduct, FmmError> {
        if !(1e-10..=1e-3).contains(&eps) {
            return Err(FmmError::Tolerance(eps));
        }
        let order = (2.0 * (1.0 / eps).log10() - 1.7).ceil() as usize;
        Ok(FastProduct {
            eps,
            order,
            theta: 0.4,
            leaf: 100,
        })
    }

    /// Whether parameters given by hand are in range: the tolerance as in
    /// [`FastProduct::new`], at least one particle per leaf, `0 < theta < 1` (the
    /// expansions converge for `r_t + r_s < |c_t - c_s|`).
    fn check(&self) -> Result<(), FmmError> {
        if !(1e-10..=1e-3).contains(&self.eps) {
            return Err(FmmError::Tolerance(self.eps));
        }
        if self.leaf == 0 {
            return Err(FmmError::Settings("leaf must hold at least one particle"));
        }
        if !(self.theta > 0.0 && self.theta < 1.0) {
            return Err(FmmError::Settings("theta must lie in (0, 1)"));
        }
        Ok(())
    }
}

/// A leaf's near field from the first pass: its own velocities, and the halves it
/// keeps for the higher leaves near it (`(leaf, velocities)`).
type NearHalves<const K: usize> = (Vec<[f64; K]>, Vec<(usize, Vec<[f64; K]>)>);

/// The wall-clock seconds of each phase of one fast product.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Phases {
    /// The tree and its lists.
    pub tree: f64,
    /// The multipoles: the leaves' from their particles, then their parents'.
    pub upward: f64,
    /// The local expansions from the multipoles that reach each cell.
    pub across: f64,
    /// The local expansions moved into the cells' children.
    pub downward: f64,
    /// The leaves: the near field by the pair kernels and the local expansions at the
    /// particles.
    pub leaves: f64,
}

/// The weight of a row at one particle, up to its coefficient: `h^h_power a^(2 a2)
/// m[moment]` at `point`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Key {
    point: usize,
    h_power: u8,
    a2: u8,
    moment: usize,
}

/// A table's rows as the multipoles' sources: every key, and for each key the rows that
/// carry it (`(channel, alpha, coef w)`, `alpha` the index of `d`).
struct Rows {
    keys: Vec<Key>,
    rows: Vec<Vec<(usize, usize, f64)>>,
    /// The keys of each point: a range of `keys` (sorted by point first).
    span: Vec<std::ops::Range<usize>>,
}

impl Rows {
    fn new(table: &[PotentialSource], weights: &[f64], ix: &Indices, kinds: usize) -> Rows {
        let key = |s: &PotentialSource| Key {
            point: s.point,
            h_power: s.h_power,
            a2: s.a2,
            moment: s.moment,
        };
        let mut keys: Vec<Key> = table.iter().map(key).collect();
        keys.sort();
        keys.dedup();
        let mut rows = vec![Vec::new(); keys.len()];
        for s in table {
            let k = keys.binary_search(&key(s)).expect("listed above");
            let w = if s.point == 0 { 1.0 } else { weights[s.weight] };
            rows[k].push((s.channel, ix.index(s.d), s.coef * w));
        }
        let span = (0..kinds)
            .map(|p| {
                let start = keys.partition_point(|k| k.point < p);
                start..keys.partition_point(|k| k.point <= p)
            })
            .collect();
        Rows { keys, rows, span }
    }
}

/// Whether the potential's generated derivatives serve `settings`' order for `table`.
fn check_order(settings: &FastProduct, table: &[PotentialSource]) -> Result<(), FmmError> {
    let max = kernels::expansion::RADIAL.len() - 1 - degree(table, None, false);
    if settings.order > max {
        return Err(FmmError::Order {
            order: settings.order,
            max,
        });
    }
    Ok(())
}

/// The orders the expansions about `point` (every point: `None`) carry beyond the fast
/// product's `order`: the largest `|d| - 2 a2` of its rows (with `heights`, `|d| - 2 a2
/// - h_power`: where the image's sources lie within the expansion's radius of the
/// mirror, `h <= rho`, its rows' `(h/R)^h_power` count as orders of `rho/R`).
///
/// A row's terms in the multipole-to-local sum are `d^(d + mu + beta) phi`, `mu` the
/// source's offset from its cell's centre and `beta` the target's: relative to the
/// Stokeslet's `1/R` they are `(rho/R)^(|mu| + |beta|)` times `(h/R)^h_power (a/R)^(2
/// a2)` (`h < R` for an image, `a < R` for a cell pair the tree accepts). Truncating
/// `|d + mu| + |beta|` at `order + degree` keeps every row to `|mu| + |beta| <= order`
/// at least (the rows whose `a^2` makes them smaller by `(a/R)^2`, to `order - 2`).
fn degree(table: &[PotentialSource], point: Option<usize>, heights: bool) -> usize {
    table
        .iter()
        .filter(|s| point.is_none_or(|p| s.point == p))
        .map(|s| {
            let h = if heights { s.h_power as usize } else { 0 };
            (s.d.iter().map(|&e| e as usize).sum::<usize>() - 2 * s.a2 as usize).saturating_sub(h)
        })
        .max()
        .unwrap_or(0)
}

/// The lowest derivative of a table's rows about `point` (every point: `None`).
fn lowest(table: &[PotentialSource], point: Option<usize>) -> usize {
    table
        .iter()
        .filter(|s| point.is_none_or(|p| s.point == p))
        .map(|s| s.d.iter().map(|&e| e as usize).sum::<usize>())
        .min()
        .unwrap_or(0)
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// A multipole that reaches a target cell: the source cell's, about one of its points,
/// to an order; where it starts in the cell's reduced multipoles (three channels of
/// `bh.m.count(top)` each).
#[derive(Clone, Copy, Debug)]
struct Pair {
    cell: usize,
    point: usize,
    top: usize,
    offset: usize,
}

/// Target cells' local expansions from the multipoles that reach them, on lanes, one
/// target after the other (sharing the lanes' scratch): the pairs of a target's list `W`
/// at a time, one per lane (a chunk's share their point and the multipoles' order), each
/// lane summing its pairs in the list's order and the lanes added last (a fixed order
/// for a given instruction set, whatever the threads).
struct Across<'a, F: Fn(usize, usize) -> [f64; 3]> {
    bh: &'a Biharmonic,
    /// The local expansions' full basis.
    lx: &'a Indices,
    /// Each target's centre and pairs (sorted by point and order).
    targets: &'a [([f64; 3], Vec<Pair>)],
    /// Each cell's, in the reduced basis (`bh.m`).
    multipoles: &'a [Vec<f64>],
    centre: &'a F,
}

impl<F: Fn(usize, usize) -> [f64; 3]> WithLanes for Across<'_, F> {
    type Elem = f64;
    type Output = Vec<Vec<f64>>;
    #[inline(always)]
    fn run<L: Lane<Elem = f64>>(self) -> Vec<Vec<f64>> {
        let bh = self.bh;
        let (len, rlen, w) = (bh.m.len(), bh.l.len(), L::WIDTH);
        let zero = L::splat(0.0);
        let mut l = vec![zero; 3 * rlen];
        let mut m = vec![zero; 3 * len];
        let mut d = vec![zero; bh.d.len()];
        let mut work = vec![zero; bh.d.len()];
        let mut lane = vec![0.0; w];
        let mut locals = Vec::with_capacity(self.targets.len());
        for (target, pairs) in self.targets {
            l.fill(zero);
            let mut rest = &pairs[..];
            while let Some(&Pair { point, top, .. }) = rest.first() {
                let same = rest
                    .iter()
                    .take_while(|p| (p.point, p.top) == (point, top))
                    .count();
                let (group, after) = rest.split_at(same);
                rest = after;
                let used = bh.m.count(top);
                for chunk in group.chunks(w) {
                    // a short chunk's empty lanes repeat its last pair with a zero multipole
                    let r: [L; 3] = std::array::from_fn(|k| {
                        for (j, slot) in lane.iter_mut().enumerate() {
                            let s = chunk[j.min(chunk.len() - 1)].cell;
                            *slot = target[k] - (self.centre)(s, point)[k];
                        }
                        L::load(&lane)
                    });
                    for ch in 0..3 {
                        for q in 0..used {
                            for (j, v) in lane.iter_mut().enumerate() {
                                *v = chunk.get(j).map_or(0.0, |p| {
                                    self.multipoles[p.cell][p.offset + ch * used + q]
                                });
                            }
                            m[ch * len + q] = L::load(&lane);
                        }
                    }
                    bh.d.potential_derivatives(r, top, &mut d, &mut work);
                    taylor::multipole_to_local(bh, top, &m, &d, &mut l);
                }
            }
            // the lanes' sums, the coefficients with `beta_1 >= 4`, and the `1/beta!`
            let lx = self.lx;
            let reduced: Vec<f64> = l.iter().map(|v| v.sum()).collect();
            let mut out = vec![0.0; 3 * lx.len()];
            for (ch, full) in out.chunks_exact_mut(lx.len()).enumerate() {
                bh.expand(&reduced[ch * rlen..(ch + 1) * rlen], full);
                for (v, f) in full.iter_mut().zip(&lx.inv_factorial) {
                    *v *= f;
                }
            }
            locals.push(out);
        }
        locals
    }
}

/// The fast product of `K` moments per particle (`K = 3`: forces; 6: forces and
/// torques), particle-major, in the particles' order.
#[allow(clippy::too_many_arguments)]
fn product<P: LaneProduct<K>, const K: usize>(
    conf: &Confinement,
    eta: f64,
    near: &P,
    table: &[PotentialSource],
    particles: &[([f64; 3], f64)],
    xs: &[[f64; K]],
    settings: &FastProduct,
    isa: Isa,
) -> (Vec<[f64; K]>, Phases) {
    let mirrors: Vec<Mirror> = conf.mirrors();
    let weights = conf.image_weights();
    let clock = std::time::Instant::now();
    let mut phases = Phases::default();
    let mark = |slot: &mut f64, since: &mut f64| {
        let now = clock.elapsed().as_secs_f64();
        *slot = now - *since;
        *since = now;
    };
    let mut since = 0.0;
    let points: Vec<[f64; 3]> = particles.iter().map(|p| p.0).collect();
    let tree = Tree::new(&points, settings.leaf, settings.theta, &mirrors);
    mark(&mut phases.tree, &mut since);
    let sorted: Vec<([f64; 3], f64)> = tree.order.iter().map(|&i| particles[i]).collect();
    let moments: Vec<[f64; K]> = tree.order.iter().map(|&i| xs[i]).collect();
    let kinds = 1 + mirrors.len();
    // the multipoles to `order + degree` (`degree`); the local expansions to `order`,
    // one more where the rotation takes their gradient (the Laplacian of the Faxén law
    // is smaller by `(a/R)^2`)
    let tops: Vec<usize> = (0..kinds)
        .map(|k| settings.order + degree(table, Some(k), false))
        .collect();
    // a cell's sources and their images in mirror `k` about one centre (`tree::Merged`):
    // where the sources lie within half the shared radius of the mirror (`low`), the
    // image's rows need the orders they have with `h` counted as such a length
    // (`degree`), and the sum the larger of these and the sphere's; elsewhere the
    // image's own (`tops`)
    let image_tops: Vec<usize> = (0..mirrors.len())
        .map(|k| settings.order + degree(table, Some(k + 1), true))
        .collect();
    // the multipoles' and the local expansions' orders, and the sources' moments about
    // their leaf's centre: to the order their lowest derivative leaves
    let top = settings.order + degree(table, None, false);
    let bases = Bases::of((
        top,
        settings.order + usize::from(K == 6),
        top - lowest(table, None),
    ));
    let (ix, lx, mx, bh) = (&bases.ix, &bases.lx, &bases.mx, &bases.bh);
    let llen = lx.len();
    let rows = Rows::new(table, &weights, ix, kinds);
    // each point's expansion centre: the cell's, its image's, or the one its sources
    // and their images in one mirror share
    let centre = |c: usize, point: usize| {
        let cell = &tree.cells[c];
        match cell.merged {
            Some(m) if point == 0 || point == m.mirror + 1 => m.centre,
            _ if point == 0 => cell.centre,
            _ => mirrors[point - 1].image(cell.centre),
        }
    };
    // the image multipoles of a shared expansion need only its orders where every
    // ancestor's image expansion is shared with the same mirror too (a parent takes
    // its children's multipoles to its own order)
    let mirror_of = |c: usize| tree.cells[c].merged.map(|m| m.mirror);
    let low: Vec<bool> = tree
        .cells
        .iter()
        .map(|c| c.merged.is_some_and(|m| m.low()))
        .collect();
    let mut reduced = vec![false; tree.cells.len()];
    reduced[0] = low[0];
    // preorder: a parent before its children
    for (c, cell) in tree.cells.iter().enumerate() {
        for &child in &cell.children {
            reduced[child] = reduced[c] && low[child] && mirror_of(child) == mirror_of(c);
        }
    }
    let top_of = |c: usize, point: usize| match tree.cells[c].merged {
        Some(m) if reduced[c] && point == m.mirror + 1 => image_tops[m.mirror],
        _ => tops[point],
    };
    // the order each point's multipole reaches the cells it is translated to with (none
    // for an image whose multipole joins the spheres' in a shared expansion)
    let m2l_top = |c: usize, point: usize| match tree.cells[c].merged {
        Some(m) if point == m.mirror + 1 => None,
        Some(m) if point == 0 => {
            let image = if low[c] {
                image_tops[m.mirror]
            } else {
                tops[point + 1 + m.mirror]
            };
            Some(tops[0].max(image))
        }
        _ => Some(tops[point]),
    };
    // a cell's multipoles, one point after the other, three channels each: each channel
    // as long as the point's order needs (the spheres' of a shared expansion as long as
    // the sum with the images' needs)
    let width = |c: usize, point: usize| {
        let top = match tree.cells[c].merged {
            Some(m) if point == 0 => tops[0].max(top_of(c, m.mirror + 1)),
            _ => top_of(c, point),
        };
        ix.count(top)
    };
    let offset = |c: usize, point: usize| (0..point).map(|q| 3 * width(c, q)).sum::<usize>();
    // upward: the leaves' multipoles from the moments of each key's weights, then
    // their parents'
    let mut multipoles: Vec<Vec<f64>> = vec![Vec::new(); tree.cells.len()];
    let leaves: Vec<usize> = (0..tree.cells.len())
        .filter(|&c| tree.cells[c].is_leaf())
        .collect();
    let formed: Vec<(usize, Vec<f64>)> = leaves
        .par_iter()
        .map(|&c| {
            let cell = &tree.cells[c];
            let np = cell.end - cell.start;
            // each point's monomials (one column per particle) and its keys' weights
            // (one column per key): their product is the moments of each key's weights,
            // one matrix product per point
            // each point's moments to the order its rows need here: the multipoles' order
            // less the point's lowest derivative
            let orders: Vec<usize> = (0..kinds)
                .map(|p| {
                    top_of(c, p)
                        .saturating_sub(lowest(table, Some(p)))
                        .min(mx.p)
                })
                .collect();
            let mlens: Vec<usize> = orders.iter().map(|&o| mx.count(o)).collect();
            let mut monos: Vec<Vec<f64>> = mlens.iter().map(|&l| vec![0.0; l * np]).collect();
            let mut w: Vec<Vec<f64>> = (0..kinds)
                .map(|p| vec![0.0; np * rows.span[p].len()])
                .collect();
            let mut h = vec![0.0; kinds];
            for (col, s) in (cell.start..cell.end).enumerate() {
                let (y, a) = sorted[s];
                let v = &moments[s];
                for (point, mono) in monos.iter_mut().enumerate() {
                    let at = if point == 0 {
                        y
                    } else {
                        let mirror = &mirrors[point - 1];
                        h[point] = mirror.distance(y);
                        mirror.image(y)
                    };
                    let ml = mlens[point];
                    let slot = &mut mono[col * ml..(col + 1) * ml];
                    mx.monomials_to(orders[point], sub(centre(c, point), at), slot);
                }
                for (k, key) in rows.keys.iter().enumerate() {
                    let p = key.point;
                    w[p][(k - rows.span[p].start) * np + col] =
                        h[p].powi(key.h_power as i32) * (a * a).powi(key.a2 as i32) * v[key.moment];
                }
            }
            let sums: Vec<nalgebra::DMatrix<f64>> = monos
                .into_iter()
                .zip(w)
                .enumerate()
                .map(|(p, (mono, w))| {
                    let mono = nalgebra::DMatrix::from_vec(mlens[p], np, mono);
                    mono * nalgebra::DMatrix::from_vec(np, rows.span[p].len(), w)
                })
                .collect();
            let sum = |k: usize| {
                let p = rows.keys[k].point;
                let at = k - rows.span[p].start;
                &sums[p].as_slice()[at * mlens[p]..(at + 1) * mlens[p]]
            };
            let mut m = vec![0.0; offset(c, kinds)];
            for (k, (key, rows)) in rows.keys.iter().zip(&rows.rows).enumerate() {
                let (top, w) = (top_of(c, key.point), width(c, key.point));
                for &(channel, alpha, coef) in rows {
                    let off = offset(c, key.point) + channel * w;
                    taylor::add_source(ix, top, alpha, coef, sum(k), &mut m[off..off + w]);
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
                let mut m = vec![0.0; offset(c, kinds)];
                let mut mono = vec![0.0; ix.len()];
                for &child in &tree.cells[c].children {
                    for point in 0..kinds {
                        ix.monomials(sub(centre(c, point), centre(child, point)), &mut mono);
                        let (from, to) = (offset(child, point), offset(c, point));
                        let (wf, wt) = (width(child, point), width(c, point));
                        taylor::translate_multipole(
                            ix,
                            top_of(c, point),
                            (&multipoles[child][from..from + 3 * wf], wf),
                            &mono,
                            (&mut m[to..to + 3 * wt], wt),
                        );
                    }
                }
                (c, m)
            })
            .collect();
        for (c, m) in formed {
            multipoles[c] = m;
        }
    }
    // the shared expansions: the images' multipoles added to the sources' (about the
    // same centre), to be translated once
    multipoles
        .par_iter_mut()
        .zip(&tree.cells)
        .enumerate()
        .for_each(|(c, (m, cell))| {
            if let Some(merged) = cell.merged {
                let point = merged.mirror + 1;
                let (wo, wi) = (width(c, 0), width(c, point));
                let (own, rest) = m.split_at_mut(3 * wo);
                let at = offset(c, point) - 3 * wo;
                let image = &rest[at..at + 3 * wi];
                for (o, i) in own.chunks_exact_mut(wo).zip(image.chunks_exact(wi)) {
                    for (o, i) in o.iter_mut().zip(i) {
                        *o += i;
                    }
                }
            }
        });
    // in the reduced basis of the multipole-to-local translation
    // (each point the translations take, its channels as long as their order needs)
    let reduced_width = |c: usize, point: usize| m2l_top(c, point).map_or(0, |t| bh.m.count(t));
    let reduced_offset =
        |c: usize, point: usize| (0..point).map(|q| 3 * reduced_width(c, q)).sum::<usize>();
    let multipoles: Vec<Vec<f64>> = multipoles
        .into_par_iter()
        .enumerate()
        .map(|(c, mut full)| {
            let mut out = vec![0.0; reduced_offset(c, kinds)];
            for point in 0..kinds {
                let (w, rw) = (width(c, point), reduced_width(c, point));
                if rw == 0 {
                    continue;
                }
                let (f, r) = (offset(c, point), reduced_offset(c, point));
                for (f, o) in full[f..f + 3 * w]
                    .chunks_exact_mut(w)
                    .zip(out[r..r + 3 * rw].chunks_exact_mut(rw))
                {
                    bh.reduce(f, o);
                }
            }
            out
        })
        .collect();
    mark(&mut phases.upward, &mut since);
    // across: each cell's local expansion from the multipoles that reach it
    // (the cells in batches that share the lanes' scratch)
    let cells: Vec<usize> = (0..tree.cells.len()).collect();
    let pairs_of = |t: usize| {
        let mut pairs: Vec<Pair> = Vec::new();
        for &s in &tree.far[t] {
            for point in 0..kinds {
                if let Some(top) = m2l_top(s, point) {
                    pairs.push(Pair {
                        cell: s,
                        point,
                        top,
                        offset: reduced_offset(s, point),
                    });
                }
            }
        }
        // stable: the list's order within each group
        pairs.sort_by_key(|p| (p.point, p.top));
        (tree.cells[t].centre, pairs)
    };
    let mut locals: Vec<Vec<f64>> = cells
        .par_chunks(16)
        .flat_map_iter(|batch| {
            let targets: Vec<([f64; 3], Vec<Pair>)> = batch.iter().map(|&t| pairs_of(t)).collect();
            let across = Across {
                bh,
                lx,
                targets: &targets,
                multipoles: &multipoles,
                centre: &centre,
            };
            match lanes::dispatch_with(isa, across) {
                Ok(l) => l,
                Err(_) => panic!("the instruction set {isa:?} is not available on this processor"),
            }
        })
        .collect();
    mark(&mut phases.across, &mut since);
    // downward: each cell's local expansion moved into its children
    for level in &tree.levels {
        let moved: Vec<(usize, Vec<f64>)> = level
            .par_iter()
            .flat_map_iter(|&c| {
                let parent = &locals[c];
                let cell = &tree.cells[c];
                let mut mono = vec![0.0; llen];
                let mut moved = Vec::with_capacity(cell.children.len());
                for &child in &cell.children {
                    lx.monomials(sub(tree.cells[child].centre, cell.centre), &mut mono);
                    let mut add = vec![0.0; 3 * llen];
                    for ch in 0..3 {
                        let r = ch * llen..(ch + 1) * llen;
                        taylor::translate_local(lx, &parent[r.clone()], &mono, &mut add[r]);
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
    mark(&mut phases.downward, &mut since);
    // the leaves: the local expansions' Faxén functional and the near field
    let soa = Soa::new(&sorted, &moments);
    let unit = 1.0 / (8.0 * std::f64::consts::PI * eta);
    // the near field: a pair of leaves near each other both ways is evaluated once, by
    // the lower leaf, which keeps the higher one's halves for it; the others (a leaf
    // with itself, a leaf whose partner takes it through a multipole) by the target
    let range = |c: usize| (tree.cells[c].start, tree.cells[c].end);
    let mutual = |t: usize, s: usize| s != t && tree.near[s].contains(&t);
    let first: Vec<NearHalves<K>> = leaves
        .par_iter()
        .map(|&t| {
            let (t0, t1) = range(t);
            let mut out = vec![[0.0; K]; t1 - t0];
            let alone: Vec<(usize, usize)> = tree.near[t]
                .iter()
                .filter(|&&s| !mutual(t, s))
                .map(|&s| range(s))
                .collect();
            near_row(&soa, near, (t0, t1), &alone, isa, &mut out);
            let mut kept = Vec::new();
            for &s in tree.near[t].iter().filter(|&&s| s > t && mutual(t, s)) {
                let (s0, s1) = range(s);
                let mut back = vec![[0.0; K]; s1 - s0];
                near_block(&soa, near, (t0, t1), (s0, s1), isa, &mut out, &mut back);
                kept.push((s, back));
            }
            (out, kept)
        })
        .collect();
    let mut position = vec![usize::MAX; tree.cells.len()];
    for (k, &c) in leaves.iter().enumerate() {
        position[c] = k;
    }
    let (outs, kept): (Vec<_>, Vec<_>) = first.into_iter().unzip();
    let rows: Vec<(usize, Vec<[f64; K]>)> = leaves
        .par_iter()
        .zip(outs)
        .map(|(&c, mut out)| {
            let cell = &tree.cells[c];
            for &s in tree.near[c].iter().filter(|&&s| s < c && mutual(c, s)) {
                let kept = &kept[position[s]];
                let (_, back) = kept
                    .iter()
                    .find(|(t, _)| *t == c)
                    .expect("kept by the lower leaf");
                for (o, b) in out.iter_mut().zip(back) {
                    for k in 0..K {
                        o[k] += b[k];
                    }
                }
            }
            // the Faxén functional's polynomials (one column each) at every particle
            // (one column of monomials each): one matrix product per leaf
            let polys = taylor::faxen_polynomials(lx, &locals[c], K == 6);
            let parts = polys.len() / llen;
            let np = cell.end - cell.start;
            let mut monos = vec![0.0; llen * np];
            for (mono, s) in monos.chunks_exact_mut(llen).zip(cell.start..cell.end) {
                lx.monomials(sub(sorted[s].0, cell.centre), mono);
            }
            let polys = nalgebra::DMatrix::from_vec(llen, parts, polys);
            let at = polys.transpose() * nalgebra::DMatrix::from_vec(llen, np, monos);
            for (col, (o, s)) in out.iter_mut().zip(cell.start..cell.end).enumerate() {
                let a = sorted[s].1;
                for k in 0..3 {
                    o[k] += unit * (at[(k, col)] + a * a / 6.0 * at[(3 + k, col)]);
                }
                if K == 6 {
                    for m in 0..3 {
                        o[3 + m] += unit * at[(6 + m, col)];
                    }
                }
            }
            (cell.start, out)
        })
        .collect();
    mark(&mut phases.leaves, &mut since);
    let mut res = vec![[0.0; K]; particles.len()];
    for (start, out) in rows {
        for (k, o) in out.into_iter().enumerate() {
            res[tree.order[start + k]] = o;
        }
    }
    (res, phases)
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
) -> (Vec<f64>, Phases) {
    fn run<P: LaneProduct<K>, const K: usize>(
        conf: &Confinement,
        eta: f64,
        near: &P,
        table: &[PotentialSource],
        ps: &[([f64; 3], f64)],
        xs: &[f64],
        settings: &FastProduct,
        isa: Isa,
    ) -> (Vec<f64>, Phases) {
        let v: Vec<[f64; K]> = xs
            .chunks(K)
            .map(|c| std::array::from_fn(|i| c[i]))
            .collect();
        let (u, phases) = product::<P, K>(conf, eta, near, table, ps, &v, settings, isa);
        (u.concat(), phases)
    }
    if torques {
        run(
            conf,
            eta,
            &ExchangingFT { conf, eta },
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
            &ExchangingF { conf, eta },
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
    /// Brownian dynamics; the drift then takes each sphere's own terms alone (`O(N)`:
    /// where the confinement's divergence table is empty, its pair terms have no far
    /// field and are round-off, docs/fmm.md); FTS products, dense matrices, resistances
    /// and Cholesky noise stay as they are. The fast product runs in
    /// double precision whatever [`System::with_precision`] says. Refused for a tolerance
    /// outside `[1e-10, 1e-3]` or a confinement without an expansion.
    ///
    /// In a periodic box (given before or after, [`System::periodic`]) the fast product
    /// is the box's own `O(N)` product (linked cells and spectral Ewald,
    /// [`crate::periodic`]) with its lattice sums to the tolerance `eps`, which keeps the
    /// product within `eps` in the same norm (the `periodic::fmm` tests); its dense
    /// matrices keep the box's tolerance.
    pub fn with_fmm(self, eps: f64) -> Result<System, FmmError> {
        self.with_fast(FastProduct::new(eps)?)
    }

    /// [`System::with_fmm`] with the method's parameters given ([`FastProduct`]; in a
    /// periodic box its tolerance alone counts).
    pub fn with_fast(mut self, settings: FastProduct) -> Result<System, FmmError> {
        settings.check()?;
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
        Ok(self.apply_fast_timed(moments, x, settings)?.0)
    }

    /// [`System::apply_fast`] and the time each of its phases took ([`Phases`]; all
    /// zero in a periodic box, whose fast product is its own, [`System::with_fmm`]).
    pub fn apply_fast_timed(
        &self,
        moments: Moments,
        x: &[f64],
        settings: &FastProduct,
    ) -> Result<(Vec<f64>, Phases), FmmError> {
        settings.check()?;
        if moments == Moments::FTS {
            return Err(FmmError::Moments(moments));
        }
        self.assert_product(moments, x);
        if let Some(p) = self.periodic_ref() {
            let u = match self.fast_periodic() {
                Some(q) if q.bx.tolerance == settings.eps => self.periodic_apply(q, moments, x),
                _ => {
                    let q = p.at_tolerance(self.confinement(), settings.eps);
                    self.periodic_apply(&q, moments, x)
                }
            };
            return Ok((u, Phases::default()));
        }
        let torques = moments == Moments::FT;
        let table = self.table(torques)?;
        check_order(settings, table)?;
        let (conf, eta) = (self.confinement(), self.viscosity());
        let mut phases = Phases::default();
        let u = self.with_overlaps(moments, x, |ps, xs| {
            let (u, p) = apply_moments(conf, eta, torques, table, ps, xs, settings, Isa::best());
            phases = p;
            u
        });
        Ok((u, phases))
    }
}
