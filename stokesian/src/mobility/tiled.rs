//! The tiled matrix-free product `M x`: each unordered pair evaluated once by a lane
//! kernel, `M^{ab} x_b` and `M^{ba} x_a` accumulated together, with a result that does
//! not depend on the number of threads.
//!
//! The particles are cut into blocks of `BLOCK` (positions, radii and moments as
//! structure of arrays, padded to whole blocks). A tile is a pair of blocks `(I, J)`,
//! `I <= J`: particle `i` of `I` against the particles of `J` in lanes
//! (`lanes::Lane::WIDTH` at a time; `j > i` on the diagonal; lanes past the last particle
//! masked; block `J` as fixed-size arrays, so that no load needs a bounds check), `a_i`
//! summed in lanes and reduced in lane order at the end of the row, `b_j` added
//! lane-wise to block `J`.
//! The tiles are scheduled in rounds in which every block appears at most once (the
//! diagonal tiles, then the off-diagonal ones by the circle method of round-robin
//! tournaments), so the tiles of a round run in parallel on disjoint blocks and every
//! output is accumulated in an order fixed by the schedule alone: the same bits with
//! 1, 2 or 3 threads, on any machine with the same instruction set. No allocation per
//! pair or per tile. The Brownian drift (the generated divergence kernels summed over
//! pairs) runs through the same tiles (`Divergence`).
//!
//! Near a no-slip wall the kernels evaluate `M^{ab}` with the particle nearer the wall as
//! the source (`Confinement::exchange_normal`: the wall's normal, along which they
//! compare). The particles are therefore ordered along that normal, farthest first, and
//! every tile calls the `*_lanes_ordered` kernels, which skip the per-lane exchange (its
//! comparison and selects): the same values, pair by pair.
//!
//! The lanes hold `f64` or, for the single-precision product ([`Precision::Single`]),
//! `f32`: twice the pairs per instruction. Single precision runs in units where the
//! largest radius, the viscosity and the largest moment are 1 and positions are measured
//! from the first boundary (`Confinement::in_units`), so no intermediate of the kernels
//! overflows or underflows `f32` whatever the user's units; each tile's sums are
//! carried in `f32` and every total in `f64`.
//!
//! With [`crate::Overlap::Rpy`], the overlapping pairs' corrections and the damping are
//! applied in `f64` in a scalar pass around the tiles ([`crate::system::overlap`]): the
//! tiles themselves are the same.

use crate::system::input::Particle;
use crate::system::overlap::correction;
use crate::system::{global, Moments, Precision, System, PARALLEL_MIN};
use kernels::lanes::{self, Element, Isa, Lane, WithLanes};
use kernels::Confinement;
use rayon::prelude::*;
use std::sync::Mutex;

/// Particles per block: a multiple of every lane width.
pub(crate) const BLOCK: usize = 64;

/// The most moments per particle (FTS).
const MAX_K: usize = 11;

/// A pair product over lanes: `(M^{ab} vb, M^{ba} va)` for `L::WIDTH` pairs.
pub(crate) trait LaneProduct<const K: usize>: Sync {
    /// The direction along which [`LaneProduct::eval`] wants `a` no lower than `b`
    /// (its kernels skip the exchange of roles, [`Confinement::exchange_normal`]), if
    /// any: the particles are then ordered along it, highest first.
    fn by_height(&self) -> Option<[f64; 3]>;
    /// The product of lanes of pairs.
    fn eval<L: Lane>(
        &self,
        xa: [L; 3],
        aa: L,
        xb: [L; 3],
        ab: L,
        va: [L; K],
        vb: [L; K],
    ) -> ([L; K], [L; K]);
    /// `M^{aa} v` of particle `a` alone.
    fn diagonal(&self, x: [f64; 3], a: f64, v: [f64; K]) -> [f64; K];
}

/// Split `a` then `b` of a flattened lane product.
#[inline(always)]
fn halves<L: Lane, const K: usize, const K2: usize>(o: [L; K2]) -> ([L; K], [L; K]) {
    (
        std::array::from_fn(|i| o[i]),
        std::array::from_fn(|i| o[K + i]),
    )
}

/// A truncation whose pair products have generated lane kernels: the lane kernel and
/// the self kernel of the `kernels` crate's dispatch; `ordered`: the lane kernel wants
/// the particles ordered along the confinement's exchange normal (else it exchanges the
/// roles itself, and takes any order).
macro_rules! generated_lanes {
    ($(#[$doc:meta])* $name:ident, $k:literal, $lanes:ident, $self_kernel:ident, $ordered:literal) => {
        $(#[$doc])*
        pub(crate) struct $name<'a> {
            pub conf: &'a Confinement,
            pub eta: f64,
        }

        impl LaneProduct<$k> for $name<'_> {
            fn by_height(&self) -> Option<[f64; 3]> {
                self.conf.exchange_normal().filter(|_| $ordered)
            }
            #[inline(always)]
            fn eval<L: Lane>(
                &self,
                xa: [L; 3],
                aa: L,
                xb: [L; 3],
                ab: L,
                va: [L; $k],
                vb: [L; $k],
            ) -> ([L; $k], [L; $k]) {
                halves(kernels::$lanes(self.conf, self.eta, xa, aa, xb, ab, va, vb))
            }
            fn diagonal(&self, x: [f64; 3], a: f64, v: [f64; $k]) -> [f64; $k] {
                kernels::$self_kernel(self.conf, self.eta, x, a).product(v, v).a
            }
        }
    };
}

generated_lanes!(
    /// The F products of a confinement (generated lane kernels).
    ProductF,
    3,
    product_f_lanes_ordered,
    self_f,
    true
);
generated_lanes!(
    /// The FT products of a confinement (generated lane kernels).
    ProductFT,
    6,
    product_ft_lanes_ordered,
    self_ft,
    true
);
generated_lanes!(
    /// The F products in any order of the particles (the kernels exchange the roles
    /// where they want the lower particle as the source): the fast product's near field.
    ExchangingF,
    3,
    product_f_lanes,
    self_f,
    false
);
generated_lanes!(
    /// The FT products in any order of the particles.
    ExchangingFT,
    6,
    product_ft_lanes,
    self_ft,
    false
);

/// The FTS products of a confinement: the lane twins of the generated FTS pair blocks
/// ([`kernels::pair_lanes_ordered`]) times the moments on the same lanes.
pub(crate) struct ProductFTS<'a> {
    pub conf: &'a Confinement,
    pub eta: f64,
}

impl LaneProduct<11> for ProductFTS<'_> {
    fn by_height(&self) -> Option<[f64; 3]> {
        self.conf.exchange_normal()
    }
    #[inline(always)]
    fn eval<L: Lane>(
        &self,
        xa: [L; 3],
        aa: L,
        xb: [L; 3],
        ab: L,
        va: [L; 11],
        vb: [L; 11],
    ) -> ([L; 11], [L; 11]) {
        let m = kernels::pair_lanes_ordered(self.conf, self.eta, xa, aa, xb, ab);
        kernels::grand_lanes_product(&m, va, vb)
    }
    fn diagonal(&self, x: [f64; 3], a: f64, v: [f64; 11]) -> [f64; 11] {
        kernels::self_mobility(self.conf, self.eta, x, a)
            .product(v, v)
            .a
    }
}

/// The generated lane kernels of the pair blocks of one truncation: `K x K` blocks in
/// grand order, their `N = K^2` entries flattened as [`LaneBlocks::FLAT`] says.
pub(crate) trait LaneBlocks<const K: usize, const N: usize> {
    /// Where entry `(i, j)` of a block sits among the kernel's outputs.
    const FLAT: [[usize; K]; K];
    /// The blocks `M^{ab}` of `L::WIDTH` pairs, `b` no higher than `a` along
    /// [`Confinement::exchange_normal`] where there is one.
    fn blocks<L: Lane<Elem = f64>>(
        conf: &Confinement,
        eta: f64,
        xa: [L; 3],
        aa: L,
        xb: [L; 3],
        ab: L,
    ) -> [L; N];
}

/// A truncation's [`LaneBlocks`]: its block kernel in the `kernels` crate's dispatch.
macro_rules! lane_blocks {
    ($(#[$doc:meta])* $name:ident, $k:literal, $n:literal, $flat:ident, $kernel:ident) => {
        $(#[$doc])*
        pub(crate) struct $name;

        impl LaneBlocks<$k, $n> for $name {
            const FLAT: [[usize; $k]; $k] = kernels::blocks::$flat;
            #[inline(always)]
            fn blocks<L: Lane<Elem = f64>>(
                conf: &Confinement,
                eta: f64,
                xa: [L; 3],
                aa: L,
                xb: [L; 3],
                ab: L,
            ) -> [L; $n] {
                kernels::$kernel(conf, eta, xa, aa, xb, ab)
            }
        }
    };
}

lane_blocks!(
    /// The F blocks (`kernels::pair_f_lanes_ordered`).
    BlocksF,
    3,
    9,
    F_FLAT,
    pair_f_lanes_ordered
);
lane_blocks!(
    /// The FT blocks (`kernels::pair_ft_lanes_ordered`).
    BlocksFT,
    6,
    36,
    FT_FLAT,
    pair_ft_lanes_ordered
);
lane_blocks!(
    /// The FTS blocks (`kernels::pair_lanes_ordered`).
    BlocksFTS,
    11,
    121,
    GRAND_FLAT,
    pair_lanes_ordered
);

/// The blocks `M^{ab}` of particle `a` with each particle of `bs`, truncated as `T`
/// says, from the generated lane kernels, `L::WIDTH` pairs at a time: written
/// row-major (`K x K`, grand order) one after another into `out` (`K^2 bs.len()`
/// values). Where the kernels want the higher particle first (along
/// [`Confinement::exchange_normal`]) and `b` is higher, the lane computes `M^{ba}`
/// and its transpose is written (reciprocity), as the scalar kernels do.
pub(crate) struct PairBlocks<'a, T> {
    pub conf: &'a Confinement,
    pub eta: f64,
    pub a: &'a Particle,
    pub bs: &'a [Particle],
    pub out: &'a mut [f64],
    pub truncation: std::marker::PhantomData<T>,
}

impl<'a, T> PairBlocks<'a, T> {
    /// The blocks of `a` with `bs` into `out`.
    pub fn new(
        conf: &'a Confinement,
        eta: f64,
        a: &'a Particle,
        bs: &'a [Particle],
        out: &'a mut [f64],
    ) -> Self {
        PairBlocks {
            conf,
            eta,
            a,
            bs,
            out,
            truncation: std::marker::PhantomData,
        }
    }

    /// [`WithLanes::run`] for a truncation of `K x K` blocks (`N = K^2`).
    #[inline(always)]
    fn fill<L: Lane<Elem = f64>, const K: usize, const N: usize>(self)
    where
        T: LaneBlocks<K, N>,
    {
        let w = L::WIDTH;
        let normal = self.conf.exchange_normal();
        for (chunk, out) in self.bs.chunks(w).zip(self.out.chunks_mut(N * w)) {
            // x_a (3), a_a, x_b (3), a_b per lane; the last pair repeated as padding
            let mut args = [[0.0; lanes::MAX_WIDTH]; 8];
            let mut swapped = [false; lanes::MAX_WIDTH];
            for (l, s) in swapped.iter_mut().enumerate().take(w) {
                let b = &chunk[l.min(chunk.len() - 1)];
                *s = normal.is_some_and(|n| kernels::along(n, b.x) > kernels::along(n, self.a.x));
                let (p, q) = if *s { (b, self.a) } else { (self.a, b) };
                for k in 0..3 {
                    args[k][l] = p.x[k];
                    args[4 + k][l] = q.x[k];
                }
                args[3][l] = p.a;
                args[7][l] = q.a;
            }
            let v = |k: usize| L::load(&args[k]);
            let m = T::blocks(
                self.conf,
                self.eta,
                [v(0), v(1), v(2)],
                v(3),
                [v(4), v(5), v(6)],
                v(7),
            );
            let mut vals = [[0.0; lanes::MAX_WIDTH]; N];
            for (lane, dst) in m.into_iter().zip(vals.iter_mut()) {
                lane.store(dst);
            }
            for (l, blk) in out.chunks_exact_mut(N).enumerate() {
                for (i, row) in blk.chunks_exact_mut(K).enumerate() {
                    for (j, e) in row.iter_mut().enumerate() {
                        let k = if swapped[l] {
                            T::FLAT[j][i]
                        } else {
                            T::FLAT[i][j]
                        };
                        *e = vals[k][l];
                    }
                }
            }
        }
    }
}

/// One `impl WithLanes` per truncation (a generic `impl` over `K` and `N` would leave
/// them unconstrained). Without AVX-512 lanes of their own: writing the blocks bounds a
/// dense assembly (near a wall, an FTS pair's 242 entries are about 1.9 kB to write
/// against 80 ns of AVX-512 arithmetic, docs/performance.md), and AVX-512's copy of every
/// block kernel and the `f32` FTS products (`Precision::Single`) took 51 s of the
/// solver's 148 s release build (cargo `--timings`, 2-core AMD EPYC).
macro_rules! with_lanes {
    ($name:ident, $k:literal, $n:literal) => {
        impl WithLanes for PairBlocks<'_, $name> {
            type Elem = f64;
            type Output = ();
            const AVX512: bool = false;
            #[inline(always)]
            fn run<L: Lane<Elem = f64>>(self) {
                self.fill::<L, $k, $n>()
            }
        }
    };
}

with_lanes!(BlocksF, 3, 9);
with_lanes!(BlocksFT, 6, 36);
with_lanes!(BlocksFTS, 11, 121);

/// The Brownian drift: `a` the divergence of `M^{ab}` over the position of `b`, `b`
/// that of `M^{ba}` over the position of `a` (rows `U` then `Omega`, force columns),
/// from the generated divergence kernels; `weighted`: each multiplied by the first
/// entry of the moving particle's vector (the damping factor `b_q`, where spheres are
/// damped at a boundary), otherwise the vectors are not used.
pub(crate) struct Divergence<'a> {
    pub conf: &'a Confinement,
    pub eta: f64,
    pub weighted: bool,
}

impl LaneProduct<6> for Divergence<'_> {
    fn by_height(&self) -> Option<[f64; 3]> {
        self.conf.exchange_normal()
    }
    #[inline(always)]
    fn eval<L: Lane>(
        &self,
        xa: [L; 3],
        aa: L,
        xb: [L; 3],
        ab: L,
        va: [L; 6],
        vb: [L; 6],
    ) -> ([L; 6], [L; 6]) {
        let (a, b) = halves(kernels::pair_divergence_lanes_ordered(
            self.conf, self.eta, xa, aa, xb, ab,
        ));
        match self.weighted {
            true => (a.map(|d| d * vb[0]), b.map(|d| d * va[0])),
            false => (a, b),
        }
    }
    fn diagonal(&self, x: [f64; 3], a: f64, v: [f64; 6]) -> [f64; 6] {
        let d = kernels::self_divergence(self.conf, self.eta, x, a).a;
        match self.weighted {
            true => d.map(|d| d * v[0]),
            false => d,
        }
    }
}

/// Particles and moments as structure of arrays, padded to whole blocks.
struct Soa<E, const K: usize> {
    n: usize,
    x: [Vec<E>; 3],
    a: Vec<E>,
    v: [Vec<E>; K],
}

/// One tile `(I, J)` for the lanes of the instruction set it is dispatched to.
struct Tile<'a, P, E, const K: usize> {
    soa: &'a Soa<E, K>,
    product: &'a P,
    bi: usize,
    bj: usize,
    /// Block `I`'s accumulators (`K` rows of [`BLOCK`]); also block `J`'s on the
    /// diagonal.
    out_i: &'a mut [f64],
    /// Block `J`'s accumulators (off the diagonal).
    out_j: Option<&'a mut [f64]>,
}

impl<P: LaneProduct<K>, E: Element, const K: usize> WithLanes for Tile<'_, P, E, K> {
    type Elem = E;
    type Output = ();
    #[inline(always)]
    fn run<L: Lane<Elem = E>>(self) {
        let Tile {
            soa,
            product,
            bi,
            bj,
            out_i,
            out_j,
        } = self;
        // block J's sums over this tile, in the lanes' precision
        let mut sums_j = [[E::default(); BLOCK]; MAX_K];
        let w = L::WIDTH;
        let n = L::splat(soa.n as f64);
        let diagonal = bi == bj;
        let (i0, j0) = (bi * BLOCK, bj * BLOCK);
        // block J as arrays of one block (padded), so that no load needs a bounds check
        fn block<E>(v: &[E], j0: usize) -> &[E; BLOCK] {
            v[j0..j0 + BLOCK]
                .try_into()
                .expect("padded to whole blocks")
        }
        let xj: [&[E; BLOCK]; 3] = std::array::from_fn(|k| block(&soa.x[k], j0));
        let aj = block(&soa.a, j0);
        let vj: [&[E; BLOCK]; K] = std::array::from_fn(|c| block(&soa.v[c], j0));
        for ii in 0..BLOCK {
            let i = i0 + ii;
            if i >= soa.n {
                break;
            }
            let xa: [L; 3] = std::array::from_fn(|k| L::splat(soa.x[k][i].to_f64()));
            let aa = L::splat(soa.a[i].to_f64());
            let va: [L; K] = std::array::from_fn(|c| L::splat(soa.v[c][i].to_f64()));
            let mut acc = [L::splat(0.0); K];
            // on the diagonal, the chunks holding j > i
            let first = if diagonal { (ii + 1) / w } else { 0 };
            for chunk in first..BLOCK / w {
                let jj = chunk * w;
                let j = j0 + jj;
                let index = L::iota() + L::splat(j as f64);
                let mut valid = n.gt(index);
                if diagonal {
                    valid = L::and(valid, index.gt(L::splat(i as f64)));
                }
                if !L::any(valid) {
                    continue;
                }
                let xb: [L; 3] = std::array::from_fn(|k| L::load(&xj[k][jj..]));
                let ab = L::load(&aj[jj..]);
                let vb: [L; K] = std::array::from_fn(|c| L::load(&vj[c][jj..]));
                let (pa, pb) = product.eval(xa, aa, xb, ab, va, vb);
                let zero = L::splat(0.0);
                for c in 0..K {
                    acc[c] = acc[c] + L::select(valid, pa[c], zero);
                    let slot = &mut sums_j[c][jj..];
                    (L::load(slot) + L::select(valid, pb[c], zero)).store(slot);
                }
            }
            for c in 0..K {
                out_i[c * BLOCK + ii] += acc[c].sum();
            }
        }
        let out_j = match out_j {
            Some(o) => o,
            None => out_i,
        };
        for (o, s) in out_j.iter_mut().zip(sums_j[..K].iter().flatten()) {
            *o += s.to_f64();
        }
    }
}

/// The rounds of tiles: first the diagonal `(I, I)`, then the off-diagonal pairs by
/// the circle method, each block at most once per round.
pub fn rounds(blocks: usize) -> Vec<Vec<(usize, usize)>> {
    let mut out = vec![(0..blocks).map(|b| (b, b)).collect::<Vec<_>>()];
    if blocks < 2 {
        return out;
    }
    // an even number of seats; the extra seat (if any) is a bye
    let seats = blocks + blocks % 2;
    let mut ring: Vec<usize> = (0..seats).collect();
    for _ in 0..seats - 1 {
        let mut round = Vec::new();
        for k in 0..seats / 2 {
            let (p, q) = (ring[k], ring[seats - 1 - k]);
            if p < blocks && q < blocks {
                round.push((p.min(q), p.max(q)));
            }
        }
        round.sort_unstable();
        out.push(round);
        // rotate all seats but the first
        let last = ring.pop().expect("seats");
        ring.insert(1, last);
    }
    out
}

/// `M x` for particles `(centre, radius)` and moments `xs` (`K` per particle, grand
/// order), by tiles on the lanes of `isa` (which this processor must have) holding
/// elements `E`; `K` accumulators per particle returned in particle order. The self
/// terms are evaluated in `f64`.
pub(crate) fn apply<P: LaneProduct<K>, E: Element, const K: usize>(
    product: &P,
    particles: &[([f64; 3], f64)],
    xs: &[[f64; K]],
    isa: Isa,
    parallel: bool,
) -> Vec<[f64; K]> {
    // the order of the lane kernels' pairs: along the exchange normal, highest first,
    // where they skip the exchange of roles (a stable sort: the order and every sum are
    // fixed by the input alone); as given otherwise
    let mut order: Vec<usize> = (0..particles.len()).collect();
    if let Some(n) = product.by_height() {
        let h = |i: usize| kernels::along(n, particles[i].0);
        order.sort_by(|&i, &j| h(j).total_cmp(&h(i)));
    }
    let particles: Vec<([f64; 3], f64)> = order.iter().map(|&i| particles[i]).collect();
    let xs: Vec<[f64; K]> = order.iter().map(|&i| xs[i]).collect();
    let n = particles.len();
    let blocks = n.div_ceil(BLOCK);
    let padded = blocks * BLOCK;
    // padding: copies of the last particle, never counted (masked lanes)
    let last = n - 1;
    let at = |j: usize| j.min(last);
    let e = E::from_f64;
    let soa = Soa::<E, K> {
        n,
        x: std::array::from_fn(|k| (0..padded).map(|j| e(particles[at(j)].0[k])).collect()),
        a: (0..padded).map(|j| e(particles[at(j)].1)).collect(),
        v: std::array::from_fn(|c| {
            (0..padded)
                .map(|j| e(if j < n { xs[j][c] } else { 0.0 }))
                .collect()
        }),
    };
    let out: Vec<Mutex<Vec<f64>>> = (0..blocks)
        .map(|b| {
            let mut acc = vec![0.0; K * BLOCK];
            for ii in 0..BLOCK.min(n - b * BLOCK) {
                let i = b * BLOCK + ii;
                let d = product.diagonal(particles[i].0, particles[i].1, xs[i]);
                for c in 0..K {
                    acc[c * BLOCK + ii] = d[c];
                }
            }
            Mutex::new(acc)
        })
        .collect();
    let tile = |&(bi, bj): &(usize, usize)| {
        // the tiles of a round touch disjoint blocks: these locks never wait
        let mut gi = out[bi].lock().expect("no tile panics");
        let mut gj = (bi != bj).then(|| out[bj].lock().expect("no tile panics"));
        let t = Tile {
            soa: &soa,
            product,
            bi,
            bj,
            out_i: &mut gi[..],
            out_j: gj.as_deref_mut().map(|v| &mut v[..]),
        };
        if lanes::dispatch_with(isa, t).is_err() {
            panic!("the instruction set {isa:?} is not available on this processor");
        }
    };
    for round in rounds(blocks) {
        if parallel {
            round.par_iter().for_each(tile);
        } else {
            round.iter().for_each(tile);
        }
    }
    let out: Vec<Vec<f64>> = out
        .into_iter()
        .map(|m| m.into_inner().expect("no tile panics"))
        .collect();
    let mut res = vec![[0.0; K]; n];
    for (s, &i) in order.iter().enumerate() {
        res[i] = std::array::from_fn(|c| out[s / BLOCK][c * BLOCK + s % BLOCK]);
    }
    res
}

/// The product for a truncation (F, FT or FTS) in `precision`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn apply_moments(
    conf: &Confinement,
    eta: f64,
    moments: Moments,
    particles: &[([f64; 3], f64)],
    xs: &[f64],
    isa: Isa,
    precision: Precision,
    parallel: bool,
) -> Vec<f64> {
    fn run<P: LaneProduct<K>, E: Element, const K: usize>(
        p: &P,
        ps: &[([f64; 3], f64)],
        xs: &[f64],
        isa: Isa,
        parallel: bool,
    ) -> Vec<f64> {
        let v: Vec<[f64; K]> = xs
            .chunks(K)
            .map(|c| std::array::from_fn(|i| c[i]))
            .collect();
        apply::<P, E, K>(p, ps, &v, isa, parallel).concat()
    }
    // the tiles' masks count particles in the lanes' precision: exact in `f32` below 2^24;
    // FTS in `f64` (Precision::Single)
    let single = precision == Precision::Single
        && moments != Moments::FTS
        && particles.len() + BLOCK < 1 << 24;
    if !single {
        return match moments {
            Moments::F => run::<_, f64, 3>(&ProductF { conf, eta }, particles, xs, isa, parallel),
            Moments::FT => run::<_, f64, 6>(&ProductFT { conf, eta }, particles, xs, isa, parallel),
            Moments::FTS => {
                run::<_, f64, 11>(&ProductFTS { conf, eta }, particles, xs, isa, parallel)
            }
        };
    }
    let k = moments.per_particle();
    let units = Units::of(conf, particles, xs, k);
    let ps: Vec<([f64; 3], f64)> = particles
        .iter()
        .map(|&(x, a)| (units.position(x), a / units.length))
        .collect();
    let scaled: Vec<f64> = xs
        .iter()
        .enumerate()
        .map(|(i, v)| v / units.moment(i % k))
        .collect();
    let conf = conf.in_units(units.origin, units.length);
    // in these units the viscosity is 1
    let (f, ft) = (
        ProductF {
            conf: &conf,
            eta: 1.0,
        },
        ProductFT {
            conf: &conf,
            eta: 1.0,
        },
    );
    let out = match moments {
        Moments::F => run::<_, f32, 3>(&f, &ps, &scaled, isa, parallel),
        Moments::FT => run::<_, f32, 6>(&ft, &ps, &scaled, isa, parallel),
        Moments::FTS => unreachable!("FTS runs in double precision (above)"),
    };
    out.iter()
        .enumerate()
        .map(|(i, y)| y * units.response(i % k, eta))
        .collect()
}

impl System {
    /// `M x` without forming `M`: `x` and the result in the layout of
    /// [`System::mobility`]. Each unordered pair is evaluated once, `M^{ab} x_b` and
    /// `M^{ba} x_a` together, by the lane kernels on the widest instruction set this
    /// processor has, in tiles whose schedule alone fixes the order of every sum: the
    /// result does not depend on the number of threads (module docs).
    /// In the system's precision ([`System::with_precision`]; double by default); F and
    /// FT by the fast multipole method where [`System::with_fmm`] asked for it.
    pub fn apply(&self, moments: Moments, x: &[f64]) -> Vec<f64> {
        self.apply_in(moments, x, self.precision())
    }

    /// [`System::apply`] with the direct product in `precision` (the fast product, where
    /// [`System::with_fmm`] asked for it, is in double precision anyway).
    pub(crate) fn apply_in(&self, moments: Moments, x: &[f64], precision: Precision) -> Vec<f64> {
        match (self.fast(), self.fast_periodic()) {
            (Some(_), Some(p)) if moments != Moments::FTS => {
                self.assert_product(moments, x);
                self.periodic_apply(p, moments, x)
            }
            (Some(fast), None) if moments != Moments::FTS => self
                .apply_fast(moments, x, &fast)
                .expect("with_fmm checked the confinement and the order"),
            _ => self.apply_with(moments, x, Isa::best(), precision),
        }
    }

    /// [`System::apply`] on the lanes of `isa` (`Isa::all_available()` lists this
    /// processor's) in `precision`; panics if this processor lacks `isa`, or where
    /// [`System::check_overlap`] fails.
    pub fn apply_with(
        &self,
        moments: Moments,
        x: &[f64],
        isa: Isa,
        precision: Precision,
    ) -> Vec<f64> {
        self.assert_product(moments, x);
        if let Some(p) = self.periodic_ref() {
            return self.periodic_apply(p, moments, x);
        }
        let (conf, eta) = (self.confinement(), self.viscosity());
        self.with_overlaps(moments, x, |ps, xs| {
            apply_moments(
                conf,
                eta,
                moments,
                ps,
                xs,
                isa,
                precision,
                ps.len() >= PARALLEL_MIN,
            )
        })
    }

    /// The checks of every product: `x` has `k` entries per particle, and the overlaps
    /// are ones the truncation's forms cover ([`System::check_overlap`]); panics
    /// otherwise.
    pub(crate) fn assert_product(&self, moments: Moments, x: &[f64]) {
        let n = self.len();
        let k = moments.per_particle();
        assert_eq!(
            x.len(),
            k * n,
            "vector length must be {} for {n} particles",
            k * n
        );
        self.assert_overlap(moments);
    }

    /// A product `core(particles, xs)` of the pair kernels' far form (`xs`: `k` moments
    /// per particle, particle-major; the result likewise) made the system's product in
    /// the layout of [`System::mobility`]: with [`crate::Overlap::Rpy`], the damping
    /// around it and the overlapping pairs' corrections added after it.
    pub(crate) fn with_overlaps(
        &self,
        moments: Moments,
        x: &[f64],
        core: impl FnOnce(&[([f64; 3], f64)], &[f64]) -> Vec<f64>,
    ) -> Vec<f64> {
        let n = self.len();
        let k = moments.per_particle();
        let parts = moments.parts();
        let rpy = self.rpy();
        let damping = rpy.and_then(|r| r.damping.as_ref());
        let b = |a: usize| damping.map_or(1.0, |d| d.b[a]);
        let xs: Vec<f64> = (0..n)
            .flat_map(|a| (0..k).map(move |i| (a, i)))
            .map(|(a, i)| b(a) * x[global(parts, n, a, i)])
            .collect();
        let ps: Vec<([f64; 3], f64)> = self.evaluated().iter().map(|p| (p.x, p.a)).collect();
        let mut acc = core(&ps, &xs);
        if let Some(rpy) = rpy {
            let ps = self.evaluated();
            let mut c = [0.0; 36];
            for &(p, q) in &rpy.pairs {
                correction(moments, self.viscosity(), &ps[p], &ps[q], &mut c);
                for i in 0..k {
                    for j in 0..k {
                        acc[p * k + i] += c[i * k + j] * xs[q * k + j];
                        acc[q * k + j] += c[i * k + j] * xs[p * k + i];
                    }
                }
            }
        }
        let mut out = vec![0.0; k * n];
        for a in 0..n {
            for i in 0..k {
                out[global(parts, n, a, i)] = b(a) * acc[a * k + i];
            }
        }
        out
    }
}

/// The units of the single-precision product: lengths in units of the largest radius,
/// measured from the centroid moved onto the first boundary along its normal (the
/// centroid in free space); the viscosity 1; moments scaled so that the largest is 1.
struct Units {
    origin: [f64; 3],
    length: f64,
    /// The largest moment, each in the new unit of length.
    scale: f64,
}

impl Units {
    fn of(conf: &Confinement, particles: &[([f64; 3], f64)], xs: &[f64], k: usize) -> Units {
        let n = particles.len() as f64;
        let centroid: [f64; 3] =
            std::array::from_fn(|c| particles.iter().map(|p| p.0[c]).sum::<f64>() / n);
        // the centroid moved onto the first boundary along its normal (exactly, for a
        // plane normal to an axis), so that positions and the planes' offsets are small
        let mut origin = centroid;
        if let Some(b) = conf.boundaries().first() {
            match (0..3).find(|&k| b.normal[k].abs() == 1.0) {
                Some(k) => origin[k] = b.offset * b.normal[k],
                None => {
                    let d = b.distance(centroid);
                    origin = std::array::from_fn(|k| centroid[k] - d * b.normal[k]);
                }
            }
        }
        let length = particles.iter().map(|p| p.1).fold(0.0, f64::max);
        let mut u = Units {
            origin,
            length,
            scale: 1.0,
        };
        let largest = xs
            .iter()
            .enumerate()
            .map(|(i, v)| (v / u.moment(i % k)).abs())
            .fold(0.0, f64::max);
        if largest > 0.0 {
            u.scale = largest;
        }
        u
    }

    fn position(&self, x: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|c| (x[c] - self.origin[c]) / self.length)
    }

    /// The unit of moment component `c` (0-2 forces; then torques and stresslets,
    /// one length more).
    fn moment(&self, c: usize) -> f64 {
        if c < 3 {
            self.scale
        } else {
            self.scale * self.length
        }
    }

    /// The unit of response component `c` (0-2 velocities; then rotations and strains,
    /// one inverse length more): `Confinement::in_units`.
    fn response(&self, c: usize, eta: f64) -> f64 {
        let q = if c < 3 { 1 } else { 2 };
        self.scale / (eta * self.length.powi(q))
    }
}
