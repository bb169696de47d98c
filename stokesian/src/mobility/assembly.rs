//! The dense grand mobility (Eq. 1 layout, moment-major: all `U`, then all `Omega`, then
//! all `E`; particle-major within a moment) and its blocks: each unordered pair evaluated
//! once by the lane twins of the pair kernels and written twice (reciprocity), in tiles
//! of groups scheduled in the rounds of [`crate::mobility::tiled`]. With
//! [`crate::Overlap::Rpy`], the overlapping pairs' corrections are added and the damping
//! applied in a scalar pass afterwards ([`crate::system::overlap`]).

use crate::system::overlap::correction;
use crate::system::{component_of, global, Moments, System, PARALLEL_MIN};
use kernels::lanes::dispatch;
use kernels::{self_f, self_ft, self_mobility};
use nalgebra::DMatrix;
use rayon::prelude::*;
use std::sync::Mutex;

thread_local! {
    /// The tile buffer of [`System::mobility`] on this thread (the row-major blocks of
    /// one tile).
    static TILE_BUFFER: std::cell::RefCell<Vec<f64>> =
        const { std::cell::RefCell::new(Vec::new()) };
}

/// Particles per group in the dense assembly's tiles: a tile's blocks
/// (`DENSE_GROUP^2 K^2` values, 248 KB at FTS) stay in the L2 cache while they are
/// written out, and a round has enough tiles to balance a few threads at `N` of a
/// few hundred.
const DENSE_GROUP: usize = 16;

impl System {
    /// `M^{ab}` truncated to `moments` (`K x K`, `K` = 3, 6 or 11, grand order) as the
    /// dense matrix holds it ([`System::mobility`]): the self blocks for `a == b`
    /// (Eq. 17), else the lane twin of the pair kernel of that truncation on the widest
    /// instruction set of this processor (the same blocks as [`kernels::pair_f`],
    /// [`kernels::pair_ft`] and [`kernels::pair`] to a few ulps: the integration tests of
    /// the lanes). With [`crate::Overlap::Rpy`], the overlap correction and the damping
    /// as in the dense matrix; panics where [`System::check_overlap`] fails.
    pub fn block(&self, moments: Moments, a: usize, b: usize) -> DMatrix<f64> {
        self.assert_overlap(moments);
        let k = moments.per_particle();
        if let Some(p) = self.periodic_ref() {
            return DMatrix::from_row_slice(k, k, &self.periodic_block(p, moments, a, b));
        }
        let mut out = vec![0.0; k * k];
        if a == b {
            self.self_block_into(moments, a, &mut out);
        } else {
            self.pair_blocks_into(moments, a, b..b + 1, &mut out);
        }
        let mut m = DMatrix::from_row_slice(k, k, &out);
        if let Some(rpy) = self.rpy() {
            let pair = (a.min(b), a.max(b));
            if a != b && rpy.pairs.binary_search(&pair).is_ok() {
                let ps = self.evaluated();
                let mut c = [0.0; 36];
                correction(moments, self.viscosity(), &ps[pair.0], &ps[pair.1], &mut c);
                let c = DMatrix::from_row_slice(k, k, &c[..k * k]);
                m += if a < b { c } else { c.transpose() };
            }
            if let Some(d) = &rpy.damping {
                m *= d.b[a] * d.b[b];
            }
        }
        m
    }

    /// The blocks `M^{ab}` truncated to `moments` of `a` with every `b` of `bs` (none of
    /// them `a`), row-major `K x K` one after another into `out`, in lanes
    /// ([`crate::mobility::tiled::PairBlocks`]).
    fn pair_blocks_into(
        &self,
        moments: Moments,
        a: usize,
        bs: std::ops::Range<usize>,
        out: &mut [f64],
    ) {
        use crate::mobility::tiled::{BlocksF, BlocksFT, BlocksFTS, PairBlocks};
        let (conf, eta) = (self.confinement(), self.viscosity());
        let (a, bs) = (&self.evaluated()[a], &self.evaluated()[bs]);
        match moments {
            Moments::F => dispatch(PairBlocks::<BlocksF>::new(conf, eta, a, bs, out)),
            Moments::FT => dispatch(PairBlocks::<BlocksFT>::new(conf, eta, a, bs, out)),
            Moments::FTS => dispatch(PairBlocks::<BlocksFTS>::new(conf, eta, a, bs, out)),
        }
    }

    /// `M^{aa}` truncated to `moments`, written row-major `K x K` into `out`.
    fn self_block_into(&self, moments: Moments, a: usize, out: &mut [f64]) {
        let p = &self.evaluated()[a];
        let (c, eta) = (self.confinement(), self.viscosity());
        let mut put = |k: usize, at: &dyn Fn(usize, usize) -> f64| {
            for i in 0..k {
                for j in 0..k {
                    out[i * k + j] = at(i, j);
                }
            }
        };
        match moments {
            Moments::F => {
                let m = self_f(c, eta, p.x, p.a);
                put(3, &|i, j| m.uf[i][j]);
            }
            Moments::FT => {
                let m = self_ft(c, eta, p.x, p.a).matrix();
                put(6, &|i, j| m[i][j]);
            }
            Moments::FTS => {
                let g = self_mobility(c, eta, p.x, p.a).matrix();
                put(11, &|i, j| g[(i, j)]);
            }
        }
    }

    /// The dense grand mobility in the layout of Eq. 1 (moment-major: all `U`, then
    /// all `Omega`, then all `E`; particle-major within a moment). Each unordered pair
    /// `a <= b` is evaluated once and written twice, `M^{ab}` into the columns of `b`
    /// and `M^{ba} = (M^{ab})^T` (reciprocity) into the columns of `a`. The particles are
    /// cut into groups of `DENSE_GROUP`; a tile is a pair of groups, and the tiles
    /// run in the rounds of `crate::mobility::tiled` (every group at most once per round), so
    /// the threads of a round own disjoint columns. Nothing is allocated but the
    /// matrix.
    pub fn mobility(&self, moments: Moments) -> DMatrix<f64> {
        let dim = moments.per_particle() * self.len();
        // zeroed by the allocator (`calloc`): the pages are mapped and cleared where the
        // tiles first write, on every thread, rather than by one thread's `memset`
        // (`DMatrix::zeros`), which took a third of the whole assembly at FTS, N = 1000
        let mut m = vec![0.0; dim * dim];
        self.mobility_into(moments, &mut m);
        DMatrix::from_vec(dim, dim, m)
    }

    /// [`System::mobility`] written into `out`, column-major (`K N` rows and columns,
    /// `K` = 3, 6 or 11): every entry is written. For a matrix in memory of the
    /// caller's choosing, such as [`crate::linalg::LargeMatrix`] (transparent huge pages:
    /// at FTS, N = 1000, the 4 KiB pages of a fresh `Vec` cost more to map and to reach
    /// than the kernels). Panics if `out` has not `(K N)^2` entries, or where
    /// [`System::check_overlap`] fails.
    pub fn mobility_into(&self, moments: Moments, out: &mut [f64]) {
        self.assert_overlap(moments);
        let n = self.len();
        let k = moments.per_particle();
        assert_eq!(
            out.len(),
            k * n * k * n,
            "a {0} x {0} matrix for {n} particles",
            k * n
        );
        if let Some(p) = self.periodic_ref() {
            return self.periodic_mobility_into(p, moments, out);
        }
        let parts = moments.parts();
        let groups = n.div_ceil(DENSE_GROUP);
        let members = |g: usize| g * DENSE_GROUP..((g + 1) * DENSE_GROUP).min(n);
        // the first row of each kept moment: its component `o + i` of particle `a` is
        // on row `first[p] + a d + i`
        let first: Vec<usize> = parts.iter().map(|&(o, _)| global(parts, n, 0, o)).collect();
        // the columns of each group, indexed by (particle in the group) * k + component
        let mut slots: Vec<Vec<Option<&mut [f64]>>> = (0..groups)
            .map(|g| (0..members(g).len() * k).map(|_| None).collect())
            .collect();
        for (c, col) in out.chunks_exact_mut(k * n).enumerate() {
            let (b, j) = component_of(parts, n, c);
            slots[b / DENSE_GROUP][(b % DENSE_GROUP) * k + j] = Some(col);
        }
        let columns: Vec<Mutex<Vec<&mut [f64]>>> = slots
            .into_iter()
            .map(|g| Mutex::new(g.into_iter().map(|c| c.expect("every column")).collect()))
            .collect();
        let kk = k * k;
        // a tile's blocks from `rows` into the matrix's columns (streamed: each column's
        // run is written once and not read again here)
        let write = |stream: &mut kernels::lanes::Streaming, rows: &[f64], ga: usize, gb: usize| {
            let (ra, rb) = (members(ga), members(gb));
            // the tiles of a round touch disjoint groups: these locks never wait
            let mut cols_a = columns[ga].lock().expect("no tile panics");
            {
                let mut cols_b = (ga != gb).then(|| columns[gb].lock().expect("no tile panics"));
                let out = match cols_b.as_mut() {
                    Some(g) => &mut g[..],
                    None => &mut cols_a[..],
                };
                // the columns of b: M^{ab} for every a of the first group, a column of
                // each block (on the diagonal tile below the diagonal, a row of M^{ba})
                for (ib, out) in out.chunks_exact_mut(k).enumerate() {
                    for (j, col) in out.iter_mut().enumerate() {
                        for (&(o, d), &f) in parts.iter().zip(&first) {
                            let run = &mut col[f + ra.start * d..f + ra.end * d];
                            let diagonal = if ga == gb { (ib + 1) * d } else { run.len() };
                            let (upper, lower) = run.split_at_mut(diagonal);
                            copy_runs(stream, upper, d, k, |ia| {
                                &rows[(ia * DENSE_GROUP + ib) * kk + o * k + j..]
                            });
                            copy_runs(stream, lower, d, 1, |x| {
                                &rows[(ib * DENSE_GROUP + ib + 1 + x) * kk + j * k + o..]
                            });
                        }
                    }
                }
            }
            if ga != gb {
                // the columns of a: M^{ba} = (M^{ab})^T for every b of the second group
                for (ia, out) in cols_a.chunks_exact_mut(k).enumerate() {
                    for (i, col) in out.iter_mut().enumerate() {
                        for (&(o, d), &f) in parts.iter().zip(&first) {
                            let run = &mut col[f + rb.start * d..f + rb.end * d];
                            copy_runs(stream, run, d, 1, |ib| {
                                &rows[(ia * DENSE_GROUP + ib) * kk + i * k + o..]
                            });
                        }
                    }
                }
            }
        };
        // the tile's blocks M^{ab} at ((a in its group) DENSE_GROUP + b in its group) k^2,
        // row-major in `rows`, written into the matrix afterwards as contiguous runs of
        // rows, column by column
        let tile = |rows: &mut Vec<f64>, &(ga, gb): &(usize, usize)| {
            let (ra, rb) = (members(ga), members(gb));
            for (ia, a) in ra.clone().enumerate() {
                // the pairs (a, b) of the tile: b from `first` of group b on
                let first = if ga == gb { ia } else { 0 };
                // the self block, then every pair in lanes
                let mut from = first;
                if ga == gb {
                    let at = (ia * DENSE_GROUP + ia) * kk;
                    self.self_block_into(moments, a, &mut rows[at..at + kk]);
                    from += 1;
                }
                let row = ia * DENSE_GROUP;
                let out = &mut rows[(row + from) * kk..(row + rb.len()) * kk];
                self.pair_blocks_into(moments, a, rb.start + from..rb.end, out);
            }
            kernels::lanes::streaming(|stream| write(stream, rows, ga, gb));
        };
        // each thread's buffer, kept from tile to tile and call to call (a tile writes
        // every value it reads, so it is never cleared)
        let len = DENSE_GROUP * DENSE_GROUP * kk;
        let fresh = || vec![0.0; len];
        let buffered = |t: &(usize, usize)| {
            TILE_BUFFER.with(|cell| match cell.try_borrow_mut() {
                Ok(mut b) => {
                    if b.len() < len {
                        *b = fresh();
                    }
                    tile(&mut b, t)
                }
                // (only if a tile ever ran inside another on this thread)
                Err(_) => tile(&mut fresh(), t),
            })
        };
        for round in crate::mobility::tiled::rounds(groups) {
            if n >= PARALLEL_MIN {
                round.par_iter().for_each(buffered);
            } else {
                round.iter().for_each(buffered);
            }
        }
        drop(columns);
        self.add_rpy(moments, out);
    }

    /// With [`crate::Overlap::Rpy`]: each overlapping pair's correction added to `M^{ab}`
    /// and its transpose to `M^{ba}`, then every entry of rows `a`, columns `b`
    /// multiplied by `b_a b_b` (the damping) in the column-major matrix `out`.
    fn add_rpy(&self, moments: Moments, out: &mut [f64]) {
        let Some(rpy) = self.rpy() else {
            return;
        };
        let (n, k, parts) = (self.len(), moments.per_particle(), moments.parts());
        let dim = k * n;
        let ps = self.evaluated();
        let mut c = [0.0; 36];
        for &(a, b) in &rpy.pairs {
            correction(moments, self.viscosity(), &ps[a], &ps[b], &mut c);
            for i in 0..k {
                for j in 0..k {
                    let (ra, rb) = (global(parts, n, a, i), global(parts, n, b, j));
                    out[rb * dim + ra] += c[i * k + j];
                    out[ra * dim + rb] += c[i * k + j];
                }
            }
        }
        if let Some(d) = &rpy.damping {
            let factor: Vec<f64> = (0..dim).map(|c| d.b[component_of(parts, n, c).0]).collect();
            for (col, fc) in out.chunks_exact_mut(dim).zip(&factor) {
                for (v, fr) in col.iter_mut().zip(&factor) {
                    *v *= fr * fc;
                }
            }
        }
    }
}

/// `run`, in chunks of `d` = 3 or 5 values (one moment of one particle), chunk `i`
/// from `src(i)`: `src(i)[0], src(i)[stride], ...`. Unrolled copies of a length known
/// at compile time (a copy of a length known only at run time is a loop or a call to
/// `memcpy`, slow for 3 values).
#[inline(always)]
fn copy_runs<'s>(
    out: &mut kernels::lanes::Streaming,
    run: &mut [f64],
    d: usize,
    stride: usize,
    src: impl Fn(usize) -> &'s [f64],
) {
    #[inline(always)]
    fn fixed<'s, const D: usize>(
        out: &mut kernels::lanes::Streaming,
        run: &mut [f64],
        stride: usize,
        src: impl Fn(usize) -> &'s [f64],
    ) {
        // gathered on the stack, then streamed into the matrix
        let mut buf = [0.0; DENSE_GROUP * 5];
        let gathered = &mut buf[..run.len()];
        let chunks = gathered.chunks_exact_mut(D).enumerate();
        if stride == 1 {
            for (i, dst) in chunks {
                dst.copy_from_slice(&src(i)[..D]);
            }
        } else {
            for (i, dst) in chunks {
                let values = &src(i)[..(D - 1) * stride + 1];
                for (x, v) in dst.iter_mut().enumerate() {
                    *v = values[x * stride];
                }
            }
        }
        out.copy(run, gathered);
    }
    match d {
        3 => fixed::<3>(out, run, stride, src),
        5 => fixed::<5>(out, run, stride, src),
        _ => unreachable!("a moment has 3 or 5 components"),
    }
}
