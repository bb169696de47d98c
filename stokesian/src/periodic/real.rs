//! The real part of a fast periodic product ([`super::product`], [`super::wall_product`]):
//! each sphere's own screened kernel and the images within `r_c` of every sphere over
//! linked cells ([`super::cells`]), `WIDTH` pair-images at a time with the generated lane
//! kernels of the split's building block ([`Split`]: F, FT with torques, FTS with
//! stresslets), or its scalar kernel lane by lane ([`per_lane`]) where the lane kernel
//! costs too much to build.
//!
//! Each field sphere's images are gathered in the cells' fixed order, evaluated lane by
//! lane and summed per lane, the lanes summed in order at the end; tasks of `ROWS` field
//! spheres. The bits depend on the instruction set, not on the number of threads.

use super::cells::Cells;
use crate::system::input::Particle;
use kernels::lanes::{self, Lane, WithLanes};
use kernels::{BlocksF, BlocksFT, Grand};
use rayon::prelude::*;
use std::ops::Range;

/// Field spheres per task.
const ROWS: usize = 64;

/// The real-space kernels of an Ewald split (its viscosity, screening and geometry
/// fixed): the pair blocks in lanes and the self blocks, at F and FT.
pub(crate) trait Split: Sync {
    /// The F block `UF` of the source at `xb` seen at `xa`, row-major.
    fn pair_f<L: Lane<Elem = f64>>(&self, xa: [L; 3], xb: [L; 3], aa: L, ab: L) -> [L; 9];
    /// The FT blocks `UF, UL, OmegaF, OmegaL`, each row-major.
    fn pair_ft<L: Lane<Elem = f64>>(&self, xa: [L; 3], xb: [L; 3], aa: L, ab: L) -> [L; 36];
    /// The grand FTS block, rows `(U, Omega, E)`, columns `(F, L, S)`, row-major.
    fn pair_fts<L: Lane<Elem = f64>>(&self, xa: [L; 3], xb: [L; 3], aa: L, ab: L) -> [L; 121];
    /// A sphere's own F blocks.
    fn self_f(&self, x: [f64; 3], a: f64) -> BlocksF;
    /// A sphere's own FT blocks.
    fn self_ft(&self, x: [f64; 3], a: f64) -> BlocksFT;
    /// A sphere's own grand FTS block.
    fn self_fts(&self, x: [f64; 3], a: f64) -> Grand;
}

/// The grand FTS block as a row-major array (the layout of [`Split::pair_fts`]).
pub(crate) fn grand_rows(g: &Grand) -> [f64; 121] {
    let m = g.matrix();
    std::array::from_fn(|k| m[(k / 11, k % 11)])
}

/// The forces and, with `ft`, the torques of `n` spheres in a moment-major vector `x`
/// (as [`crate::System::apply`] takes it).
pub(crate) fn forces_and_torques(
    x: &[f64],
    n: usize,
    ft: bool,
) -> (Vec<[f64; 3]>, Option<Vec<[f64; 3]>>) {
    let forces = (0..n)
        .map(|a| [x[3 * a], x[3 * a + 1], x[3 * a + 2]])
        .collect();
    let torques = ft.then(|| {
        (0..n)
            .map(|a| std::array::from_fn(|i| x[3 * n + 3 * a + i]))
            .collect()
    });
    (forces, torques)
}

/// `[U, Omega, E]` of every sphere from the real part (`Omega` zero without torques,
/// `E` without stresslets, which come with torques).
pub(crate) fn real_part<K: Split>(
    kernel: &K,
    cells: &Cells,
    ps: &[Particle],
    forces: &[[f64; 3]],
    torques: Option<&[[f64; 3]]>,
    stresslets: Option<&[[f64; 5]]>,
) -> Vec<[f64; 11]> {
    let n = ps.len();
    let chunks: Vec<usize> = (0..n.div_ceil(ROWS)).collect();
    let parts: Vec<Vec<[f64; 11]>> = chunks
        .par_iter()
        .map(|&c| {
            lanes::dispatch(Rows {
                kernel,
                cells,
                ps,
                forces,
                torques,
                stresslets,
                rows: c * ROWS..((c + 1) * ROWS).min(n),
            })
        })
        .collect();
    parts.concat()
}

/// The real part for the field spheres `rows`.
struct Rows<'a, K> {
    kernel: &'a K,
    cells: &'a Cells,
    ps: &'a [Particle],
    forces: &'a [[f64; 3]],
    torques: Option<&'a [[f64; 3]]>,
    stresslets: Option<&'a [[f64; 5]]>,
    rows: Range<usize>,
}

impl<K: Split> WithLanes for Rows<'_, K> {
    type Elem = f64;
    type Output = Vec<[f64; 11]>;

    #[inline(always)]
    fn run<L: Lane<Elem = f64>>(self) -> Vec<[f64; 11]> {
        let w = L::WIDTH;
        // the images of one row: source position, source radius, force, torque, stresslet
        let mut cols: [Vec<f64>; 15] = std::array::from_fn(|_| Vec::new());
        let none = [0.0; 3];
        let no_stresslet = [0.0; 5];
        // the torques' columns only with torques, the stresslets' only with stresslets
        let used = match (self.torques, self.stresslets) {
            (_, Some(_)) => 15,
            (Some(_), None) => 10,
            (None, None) => 7,
        };
        let mut out = Vec::with_capacity(self.rows.len());
        for a in self.rows {
            let pa = &self.ps[a];
            for c in cols.iter_mut() {
                c.clear();
            }
            self.cells.for_each_image(a, |b, r| {
                let f = &self.forces[b];
                let l = self.torques.map_or(&none, |t| &t[b]);
                let st = self.stresslets.map_or(&no_stresslet, |s| &s[b]);
                let xb: [f64; 3] = std::array::from_fn(|d| pa.x[d] - r[d]);
                let v = [
                    xb[0],
                    xb[1],
                    xb[2],
                    self.ps[b].a,
                    f[0],
                    f[1],
                    f[2],
                    l[0],
                    l[1],
                    l[2],
                    st[0],
                    st[1],
                    st[2],
                    st[3],
                    st[4],
                ];
                for (c, v) in cols[..used].iter_mut().zip(v) {
                    c.push(v);
                }
            });
            // padding: a source one length unit along x, of unit radius, unloaded
            let mut pad = [0.0; 15];
            pad[..4].copy_from_slice(&[pa.x[0] + 1.0, pa.x[1], pa.x[2], 1.0]);
            while !cols[0].len().is_multiple_of(w) {
                for (c, v) in cols[..used].iter_mut().zip(pad) {
                    c.push(v);
                }
            }
            let (xa, aa) = (pa.x.map(L::splat), L::splat(pa.a));
            let mut acc = [L::splat(0.0); 11];
            for s in (0..cols[0].len()).step_by(w) {
                let v: [L; 15] = std::array::from_fn(|k| match k < used {
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
                if self.stresslets.is_some() {
                    // the grand block: row r, columns (F, L, S) from v[4]
                    let m = self.kernel.pair_fts(xa, xb, aa, v[3]);
                    for (r, acc) in acc.iter_mut().enumerate() {
                        for c in 0..11 {
                            *acc = m[11 * r + c].mul_add(v[4 + c], *acc);
                        }
                    }
                } else if self.torques.is_none() {
                    mul(&self.kernel.pair_f(xa, xb, aa, v[3]), 0, 0..3, 4);
                } else {
                    let m = self.kernel.pair_ft(xa, xb, aa, v[3]);
                    mul(&m, 0, 0..3, 4);
                    mul(&m, 9, 0..3, 7);
                    mul(&m, 18, 3..6, 4);
                    mul(&m, 27, 3..6, 7);
                }
            }
            let f = &self.forces[a];
            let mut row: [f64; 11] = std::array::from_fn(|i| acc[i].sum());
            match (self.torques, self.stresslets) {
                (Some(t), Some(st)) => {
                    let own = grand_rows(&self.kernel.self_fts(pa.x, pa.a));
                    let q: Vec<f64> = f.iter().chain(&t[a]).chain(&st[a]).copied().collect();
                    for (r, row) in row.iter_mut().enumerate() {
                        *row += (0..11).map(|c| own[11 * r + c] * q[c]).sum::<f64>();
                    }
                }
                (None, _) => {
                    let own = self.kernel.self_f(pa.x, pa.a);
                    for (i, row) in row.iter_mut().take(3).enumerate() {
                        *row += (0..3).map(|j| own.uf[i][j] * f[j]).sum::<f64>();
                    }
                }
                (Some(t), None) => {
                    let own = self.kernel.self_ft(pa.x, pa.a);
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

/// A scalar kernel `k(xa, xb, aa, ab)` evaluated lane by lane: the lane twin of a
/// kernel whose own lane code is not instantiated (the wall's FT pair kernel: its lane
/// code, on three instruction sets, doubled the solver's build time).
#[inline(always)]
pub(crate) fn per_lane<L: Lane<Elem = f64>, const M: usize>(
    xa: [L; 3],
    xb: [L; 3],
    aa: L,
    ab: L,
    k: impl Fn([f64; 3], [f64; 3], f64, f64) -> [f64; M],
) -> [L; M] {
    // the widest f64 lanes (AVX-512) hold 8
    const MAX: usize = 8;
    let w = L::WIDTH;
    let mut inputs = [[0.0; MAX]; 8];
    for (d, v) in xa.iter().chain(&xb).chain([&aa, &ab]).enumerate() {
        v.store(&mut inputs[d][..w]);
    }
    let mut out = [[0.0; MAX]; M];
    for l in 0..w {
        let at = |d: usize| inputs[d][l];
        let m = k([at(0), at(1), at(2)], [at(3), at(4), at(5)], at(6), at(7));
        for (o, v) in out.iter_mut().zip(m) {
            o[l] = v;
        }
    }
    std::array::from_fn(|k| L::load(&out[k][..w]))
}
