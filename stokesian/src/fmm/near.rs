//! The near field of the fast product: the exact pair kernels (every image, the stiff
//! cases' stable forms; `kernels::product_f_lanes`, `kernels::product_ft_lanes`, which
//! exchange the roles of the particles where a kernel wants the lower one as the
//! source) between the particles of a leaf and those of the leaves near it, on SIMD
//! lanes, one target leaf at a time (only the target's half of each pair's product is
//! kept: every target leaf sums in its own fixed order, whatever the threads), and the
//! self terms.

use crate::mobility::tiled::LaneProduct;
use kernels::lanes::{self, Isa, Lane, WithLanes};

/// The particles in the tree's order as structure of arrays, padded by the widest lane
/// (copies of the last particle, never counted).
pub(super) struct Soa<const K: usize> {
    pub x: [Vec<f64>; 3],
    pub a: Vec<f64>,
    pub v: [Vec<f64>; K],
}

/// The widest lane of any instruction set (AVX-512, `f64`).
const PAD: usize = 8;

impl<const K: usize> Soa<K> {
    pub fn new(particles: &[([f64; 3], f64)], xs: &[[f64; K]]) -> Soa<K> {
        let n = particles.len();
        let at = |j: usize| j.min(n - 1);
        let len = n + PAD;
        Soa {
            x: std::array::from_fn(|k| (0..len).map(|j| particles[at(j)].0[k]).collect()),
            a: (0..len).map(|j| particles[at(j)].1).collect(),
            v: std::array::from_fn(|c| {
                (0..len)
                    .map(|j| if j < n { xs[j][c] } else { 0.0 })
                    .collect()
            }),
        }
    }
}

impl<const K: usize> Soa<K> {
    /// Particle `i` in every lane: position, radius, moments.
    #[inline(always)]
    fn splat<L: Lane<Elem = f64>>(&self, i: usize) -> ([L; 3], L, [L; K]) {
        (
            std::array::from_fn(|k| L::splat(self.x[k][i])),
            L::splat(self.a[i]),
            std::array::from_fn(|c| L::splat(self.v[c][i])),
        )
    }

    /// Particles `j..j + WIDTH`, one per lane (the padding past the last one).
    #[inline(always)]
    fn load<L: Lane<Elem = f64>>(&self, j: usize) -> ([L; 3], L, [L; K]) {
        (
            std::array::from_fn(|k| L::load(&self.x[k][j..])),
            L::load(&self.a[j..]),
            std::array::from_fn(|c| L::load(&self.v[c][j..])),
        )
    }
}

/// One target leaf against its near leaves on the lanes of the instruction set it is
/// dispatched to.
struct Row<'a, P, const K: usize> {
    soa: &'a Soa<K>,
    product: &'a P,
    target: (usize, usize),
    sources: &'a [(usize, usize)],
    out: &'a mut [[f64; K]],
}

impl<P: LaneProduct<K>, const K: usize> WithLanes for Row<'_, P, K> {
    type Elem = f64;
    type Output = ();
    #[inline(always)]
    fn run<L: Lane<Elem = f64>>(self) {
        let Row {
            soa,
            product,
            target,
            sources,
            out,
        } = self;
        let w = L::WIDTH;
        for (slot, i) in out.iter_mut().zip(target.0..target.1) {
            let (xa, aa, va) = soa.splat::<L>(i);
            let own = L::splat(i as f64);
            let mut acc = [L::splat(0.0); K];
            for &(s0, s1) in sources {
                let end = L::splat(s1 as f64);
                let mut j = s0;
                while j < s1 {
                    let index = L::iota() + L::splat(j as f64);
                    let inside = end.gt(index);
                    // j != i: above it or below it
                    let (above, below) =
                        (L::and(inside, index.gt(own)), L::and(inside, own.gt(index)));
                    let (xb, ab, vb) = soa.load::<L>(j);
                    let (p, _) = product.eval(xa, aa, xb, ab, va, vb);
                    let zero = L::splat(0.0);
                    for c in 0..K {
                        acc[c] =
                            acc[c] + L::select(above, p[c], zero) + L::select(below, p[c], zero);
                    }
                    j += w;
                }
            }
            let d = product.diagonal(
                [soa.x[0][i], soa.x[1][i], soa.x[2][i]],
                soa.a[i],
                std::array::from_fn(|c| soa.v[c][i]),
            );
            *slot = std::array::from_fn(|c| d[c] + acc[c].sum());
        }
    }
}

/// The near field and self terms of the particles `target` (a range of the tree's
/// order) from the particles of `sources` (ranges), into `out` (one per target).
pub(super) fn near_row<P: LaneProduct<K>, const K: usize>(
    soa: &Soa<K>,
    product: &P,
    target: (usize, usize),
    sources: &[(usize, usize)],
    isa: Isa,
    out: &mut [[f64; K]],
) {
    let row = Row {
        soa,
        product,
        target,
        sources,
        out,
    };
    if lanes::dispatch_with(isa, row).is_err() {
        panic!("the instruction set {isa:?} is not available on this processor");
    }
}

/// The pairs between two distinct leaves, both halves: each pair's kernel once.
struct Block<'a, P, const K: usize> {
    soa: &'a Soa<K>,
    product: &'a P,
    target: (usize, usize),
    source: (usize, usize),
    out_target: &'a mut [[f64; K]],
    out_source: &'a mut [[f64; K]],
}

impl<P: LaneProduct<K>, const K: usize> WithLanes for Block<'_, P, K> {
    type Elem = f64;
    type Output = ();
    #[inline(always)]
    fn run<L: Lane<Elem = f64>>(self) {
        let Block {
            soa,
            product,
            target,
            source,
            out_target,
            out_source,
        } = self;
        let w = L::WIDTH;
        let zero = L::splat(0.0);
        let end = L::splat(source.1 as f64);
        // the source particles' halves, one lane vector per chunk of `w` of them, each
        // summed over the targets in their order
        let chunks = (source.1 - source.0).div_ceil(w);
        let mut back = vec![[zero; K]; chunks];
        for (slot, i) in out_target.iter_mut().zip(target.0..target.1) {
            let (xa, aa, va) = soa.splat::<L>(i);
            let mut acc = [zero; K];
            for (chunk, b) in back.iter_mut().enumerate() {
                let j = source.0 + chunk * w;
                let inside = end.gt(L::iota() + L::splat(j as f64));
                let (xb, ab, vb) = soa.load::<L>(j);
                let (pa, pb) = product.eval(xa, aa, xb, ab, va, vb);
                for c in 0..K {
                    acc[c] = acc[c] + L::select(inside, pa[c], zero);
                    b[c] = b[c] + L::select(inside, pb[c], zero);
                }
            }
            for c in 0..K {
                slot[c] += acc[c].sum();
            }
        }
        let mut lane = vec![0.0; w];
        for (chunk, b) in back.iter().enumerate() {
            for c in 0..K {
                b[c].store(&mut lane);
                for (u, &v) in lane.iter().enumerate() {
                    if let Some(slot) = out_source.get_mut(chunk * w + u) {
                        slot[c] += v;
                    }
                }
            }
        }
    }
}

/// The pairs between the particles `target` and `source` (ranges of the tree's order,
/// disjoint): their halves added to `out_target` and `out_source`.
pub(super) fn near_block<P: LaneProduct<K>, const K: usize>(
    soa: &Soa<K>,
    product: &P,
    target: (usize, usize),
    source: (usize, usize),
    isa: Isa,
    out_target: &mut [[f64; K]],
    out_source: &mut [[f64; K]],
) {
    let block = Block {
        soa,
        product,
        target,
        source,
        out_target,
        out_source,
    };
    if lanes::dispatch_with(isa, block).is_err() {
        panic!("the instruction set {isa:?} is not available on this processor");
    }
}
