//! A validated system of spheres, and its grand mobility: dense, or applied to a vector
//! without forming the matrix.

use crate::input::{validate, InputError, Particle};
use kernels::lanes::{dispatch, Isa};
use kernels::{self_f, self_ft, self_mobility, Confinement};
use nalgebra::{DMatrix, DMatrixView};
use rayon::prelude::*;
use std::sync::Mutex;

/// Below this many particles the pair loops run on the calling thread: handing a few
/// pairs to the thread pool costs more than computing them (it dominated Brownian
/// steps of two spheres).
pub(crate) const PARALLEL_MIN: usize = 32;

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

/// Truncation of the multipole expansion: which moments the matrix couples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Moments {
    /// Forces to velocities (`3N x 3N`).
    F,
    /// Forces and torques to velocities and angular velocities (`6N x 6N`).
    FT,
    /// Forces, torques and stresslets to velocities, angular velocities and strains
    /// (`11N x 11N`).
    FTS,
}

/// The arithmetic of the matrix-free product ([`System::apply_with`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Precision {
    /// `f64` lanes: the kernels' full accuracy (about 1e-15 per pair).
    #[default]
    Double,
    /// `f32` lanes, twice as many pairs per instruction, in units where the largest
    /// radius, the viscosity and the largest moment are 1 (so any units of the input
    /// work); every total is still summed in `f64`. About 1e-7 of the product's norm
    /// (at most 2e-6 in the tests). Systems of 2^24 particles or more run in double
    /// precision (the tiles count particles in the lanes' precision).
    Single,
}

impl Moments {
    /// Rows (and columns) per particle.
    pub fn per_particle(self) -> usize {
        match self {
            Moments::F => 3,
            Moments::FT => 6,
            Moments::FTS => 11,
        }
    }

    /// `(offset within the 11x11 grand block, dimension)` of each moment kept.
    fn parts(self) -> &'static [(usize, usize)] {
        match self {
            Moments::F => &[(0, 3)],
            Moments::FT => &[(0, 3), (3, 3)],
            Moments::FTS => &[(0, 3), (3, 3), (6, 5)],
        }
    }
}

/// Spheres in a confinement, validated once on construction, so that every method is
/// infallible.
#[derive(Clone, Debug)]
pub struct System {
    confinement: Confinement,
    viscosity: f64,
    particles: Vec<Particle>,
    precision: Precision,
}

impl System {
    /// Validate and build. Overlapping spheres (with each other or a boundary) are
    /// errors unless `allow_overlap`.
    pub fn new(
        confinement: Confinement,
        viscosity: f64,
        particles: Vec<Particle>,
        allow_overlap: bool,
    ) -> Result<System, InputError> {
        validate(&confinement, viscosity, &particles, allow_overlap)?;
        Ok(System {
            confinement,
            viscosity,
            particles,
            precision: Precision::Double,
        })
    }

    /// The same system with the matrix-free product [`System::apply`] (and with it the
    /// far-field F and FT velocities, [`System::velocities`]) in `precision`. Dense
    /// matrices, resistances and Brownian dynamics stay in double precision.
    pub fn with_precision(mut self, precision: Precision) -> System {
        self.precision = precision;
        self
    }

    /// The precision of [`System::apply`].
    pub fn precision(&self) -> Precision {
        self.precision
    }

    /// The particles.
    pub fn particles(&self) -> &[Particle] {
        &self.particles
    }

    /// The confinement.
    pub fn confinement(&self) -> &Confinement {
        &self.confinement
    }

    /// The viscosity.
    pub fn viscosity(&self) -> f64 {
        self.viscosity
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.particles.len()
    }

    /// Never true for a validated system (it has at least one particle).
    pub fn is_empty(&self) -> bool {
        self.particles.is_empty()
    }

    /// `M^{ab}` truncated to `moments` (`K x K`, `K` = 3, 6 or 11, grand order) as the
    /// dense matrix holds it ([`System::mobility`]): the self blocks for `a == b`
    /// (Eq. 17), else the lane twin of the pair kernel of that truncation on the widest
    /// instruction set of this processor (the same blocks as [`kernels::pair_f`],
    /// [`kernels::pair_ft`] and [`kernels::pair`] to a few ulps; `tests/lanes.rs`).
    pub fn block(&self, moments: Moments, a: usize, b: usize) -> DMatrix<f64> {
        let k = moments.per_particle();
        let mut out = vec![0.0; k * k];
        if a == b {
            self.self_block_into(moments, a, &mut out);
        } else {
            self.pair_blocks_into(moments, a, b..b + 1, &mut out);
        }
        DMatrix::from_row_slice(k, k, &out)
    }

    /// The blocks `M^{ab}` truncated to `moments` of `a` with every `b` of `bs` (none of
    /// them `a`), row-major `K x K` one after another into `out`, in lanes
    /// ([`crate::tiled::PairBlocks`]).
    fn pair_blocks_into(
        &self,
        moments: Moments,
        a: usize,
        bs: std::ops::Range<usize>,
        out: &mut [f64],
    ) {
        use crate::tiled::{BlocksF, BlocksFT, BlocksFTS, PairBlocks};
        let (conf, eta) = (&self.confinement, self.viscosity);
        let (a, bs) = (&self.particles[a], &self.particles[bs]);
        match moments {
            Moments::F => dispatch(PairBlocks::<BlocksF>::new(conf, eta, a, bs, out)),
            Moments::FT => dispatch(PairBlocks::<BlocksFT>::new(conf, eta, a, bs, out)),
            Moments::FTS => dispatch(PairBlocks::<BlocksFTS>::new(conf, eta, a, bs, out)),
        }
    }

    /// `M^{aa}` truncated to `moments`, written row-major `K x K` into `out`.
    fn self_block_into(&self, moments: Moments, a: usize, out: &mut [f64]) {
        let p = &self.particles[a];
        let (c, eta) = (&self.confinement, self.viscosity);
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
    /// run in the rounds of `crate::tiled` (every group at most once per round), so
    /// the threads of a round own disjoint columns. Nothing is allocated but the
    /// matrix.
    pub fn mobility(&self, moments: Moments) -> DMatrix<f64> {
        let dim = moments.per_particle() * self.len();
        // zeroed by the allocator (`calloc`): the pages are mapped and cleared where the
        // tiles first write, on every thread, rather than by one thread's `memset`
        // (`DMatrix::zeros`), which took 0.3 s of the 0.9 s at FTS, N = 1000
        let mut m = vec![0.0; dim * dim];
        self.mobility_into(moments, &mut m);
        DMatrix::from_vec(dim, dim, m)
    }

    /// [`System::mobility`] written into `out`, column-major (`K N` rows and columns,
    /// `K` = 3, 6 or 11): every entry is written. For a matrix in memory of the
    /// caller's choosing, such as [`crate::dense::LargeMatrix`] (transparent huge pages:
    /// at FTS, N = 1000, the 4 KiB pages of a fresh `Vec` cost more to map and to reach
    /// than the kernels). Panics if `out` has not `(K N)^2` entries.
    pub fn mobility_into(&self, moments: Moments, out: &mut [f64]) {
        let n = self.len();
        let k = moments.per_particle();
        assert_eq!(
            out.len(),
            k * n * k * n,
            "a {0} x {0} matrix for {n} particles",
            k * n
        );
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
        for round in crate::tiled::rounds(groups) {
            if n >= PARALLEL_MIN {
                round.par_iter().for_each(buffered);
            } else {
                round.iter().for_each(buffered);
            }
        }
        drop(columns);
    }

    /// `M x` without forming `M`: `x` and the result in the layout of
    /// [`System::mobility`]. Each unordered pair is evaluated once, `M^{ab} x_b` and
    /// `M^{ba} x_a` together, by the lane kernels on the widest instruction set this
    /// processor has, in tiles whose schedule alone fixes the order of every sum: the
    /// result does not depend on the number of threads (`crate::tiled`).
    /// In the system's precision ([`System::with_precision`]; double by default).
    pub fn apply(&self, moments: Moments, x: &[f64]) -> Vec<f64> {
        self.apply_with(moments, x, Isa::best(), self.precision)
    }

    /// [`System::apply`] on the lanes of `isa` (`Isa::all_available()` lists this
    /// processor's) in `precision`; panics if this processor lacks `isa`.
    pub fn apply_with(
        &self,
        moments: Moments,
        x: &[f64],
        isa: Isa,
        precision: Precision,
    ) -> Vec<f64> {
        let n = self.len();
        let k = moments.per_particle();
        let parts = moments.parts();
        assert_eq!(
            x.len(),
            k * n,
            "vector length must be {} for {n} particles",
            k * n
        );
        let xs: Vec<f64> = (0..n)
            .flat_map(|a| (0..k).map(move |i| (a, i)))
            .map(|(a, i)| x[global(parts, n, a, i)])
            .collect();
        let ps: Vec<([f64; 3], f64)> = self.particles.iter().map(|p| (p.x, p.a)).collect();
        let acc = crate::tiled::apply_moments(
            &self.confinement,
            self.viscosity,
            moments,
            &ps,
            &xs,
            isa,
            precision,
            n >= PARALLEL_MIN,
        );
        let mut out = vec![0.0; k * n];
        for a in 0..n {
            for i in 0..k {
                out[global(parts, n, a, i)] = acc[a * k + i];
            }
        }
        out
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

/// `(particle, component in grand order)` of index `c` in the moment-major layout (the
/// inverse of [`global`]).
fn component_of(parts: &[(usize, usize)], n: usize, c: usize) -> (usize, usize) {
    let mut moff = 0;
    for &(o, d) in parts {
        if c < moff + d * n {
            return ((c - moff) / d, o + (c - moff) % d);
        }
        moff += d * n;
    }
    unreachable!("index {c} beyond the kept moments")
}

/// Index in the moment-major layout of component `i` (grand order within the kept
/// moments) of particle `a`.
fn global(parts: &[(usize, usize)], n: usize, a: usize, i: usize) -> usize {
    let mut moff = 0;
    for &(o, d) in parts {
        if i < o + d {
            return moff + a * d + (i - o);
        }
        moff += d * n;
    }
    unreachable!("component {i} beyond the kept moments")
}

/// The outcome of [`check_spd`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpdCheck {
    /// `||M - M^T||_F / ||M||_F`.
    pub asymmetry: f64,
    /// Whether the Cholesky factorisation of the symmetric part succeeded.
    pub positive_definite: bool,
}

impl SpdCheck {
    /// Symmetric to `1e-12` relative and positive definite. (The assembled matrix is
    /// symmetric by construction up to the round-off of the self blocks, ~1e-16.)
    pub fn passed(&self) -> bool {
        self.asymmetry <= 1e-12 && self.positive_definite
    }
}

/// Symmetry and positive-definiteness (Cholesky) of a mobility or resistance matrix
/// (`&DMatrix` or a view, such as [`crate::dense::LargeMatrix::view`]).
pub fn check_spd<'a>(m: impl Into<DMatrixView<'a, f64>>) -> SpdCheck {
    let m: DMatrixView<f64> = m.into();
    let norm = m.norm();
    let asymmetry = if norm > 0.0 {
        (m - m.transpose()).norm() / norm
    } else {
        0.0
    };
    let sym = (m + m.transpose()) * 0.5;
    SpdCheck {
        asymmetry,
        positive_definite: crate::dense::Cholesky::new(&sym).is_some(),
    }
}

/// The FTS mobility problem of rigid spheres: given forces and torques `x` (`6N`,
/// moment-major) and a uniform imposed strain `e_inf` (5 components in the orthonormal
/// basis), the strain rows of the FTS mobility `m` (`11N x 11N`) give
/// `-E_inf = M_EF F + M_EL L + M_ES S`, solved for the stresslets `S` by Cholesky of
/// `M_ES` (LU if it is not positive definite, which valid input never gives); then
/// `(U, Omega) = M_(U,Omega)(F, L, S)`. Returns the `6N` velocities (moment-major,
/// relative to the ambient flow) and whether Cholesky succeeded.
pub fn solve_fts(
    m: &DMatrix<f64>,
    x: &[f64],
    e_inf: &[f64; 5],
) -> Result<(Vec<f64>, bool), SingularStressletBlock> {
    let n = m.nrows() / 11;
    let fl = nalgebra::DVector::from_column_slice(x);
    let m_e_fl = m.view((6 * n, 0), (5 * n, 6 * n));
    let m_es = m.view((6 * n, 6 * n), (5 * n, 5 * n)).into_owned();
    let mut rhs = -(m_e_fl * &fl);
    for a in 0..n {
        for c in 0..5 {
            rhs[5 * a + c] -= e_inf[c];
        }
    }
    let (s, cholesky) = match crate::dense::Cholesky::new(&m_es) {
        Some(ch) => (nalgebra::DVector::from_vec(ch.solve(rhs.as_slice())), true),
        None => (m_es.lu().solve(&rhs).ok_or(SingularStressletBlock)?, false),
    };
    let m_ufl = m.view((0, 0), (6 * n, 6 * n));
    let m_us = m.view((0, 6 * n), (6 * n, 5 * n));
    let u = m_ufl * &fl + m_us * &s;
    Ok((u.as_slice().to_vec(), cholesky))
}

/// The stresslet block `M_ES` of an FTS mobility is singular.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
#[error("the stresslet block M_ES is singular")]
pub struct SingularStressletBlock;
