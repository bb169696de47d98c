//! The lane kernels against the scalar kernels, generic over the lanes' element `E`
//! (`f64` or `f32`): the pairs (random ones and ones straddling every branch of the
//! scalar kernels), the lane kernels run over them on an instruction set, the scalar
//! `f64` kernels' values, and the two comparisons the test binaries assert
//! ([`lanes_against_scalar`], [`ordered_lanes_equal_exchanging`]). Generic, so that each
//! binary instantiates only its own element (`tests/lanes` the `f64` lanes,
//! `tests/lanes_single` the `f32` ones) and the two compile in parallel.

use integration_tests::{all_confinements, frame_of, local_bounds, norm, placed, random_spheres};
use kernels::along;
use kernels::blocks::{FT_FLAT, F_FLAT};
use kernels::lanes::{dispatch_with, Element, Isa, Lane, WithLanes};
use kernels::{
    grand_lanes_product, pair, pair_f, pair_f_lanes_ordered, pair_ft, pair_ft_lanes_ordered,
    pair_lanes_ordered, product_f, product_f_lanes, product_f_lanes_ordered, product_ft,
    product_ft_lanes, product_ft_lanes_ordered, Confinement,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use stokesian::Moments;

/// One pair: centres, radii, moment vectors (`a`'s in `v[..11]`, `b`'s in `v[11..]`; F
/// uses the first 3 of each, FT the first 6).
#[derive(Clone, Copy)]
struct Pair {
    xa: [f64; 3],
    aa: f64,
    xb: [f64; 3],
    ab: f64,
    v: [f64; 22],
}

/// The first `K` moments of `a` and of `b`.
fn moments<const K: usize>(p: &Pair) -> ([f64; K], [f64; K]) {
    (
        std::array::from_fn(|k| p.v[k]),
        std::array::from_fn(|k| p.v[11 + k]),
    )
}

/// The direction the pairs are ordered along: the normal of the plane whose image
/// cancels the Stokeslet, along which the kernels exchange roles
/// (`Confinement::exchange_normal`), else the first boundary's.
fn up(conf: &Confinement) -> [f64; 3] {
    conf.exchange_normal().unwrap_or(frame_of(conf)[2])
}

/// `p` with `a` and `b` exchanged where `b` is higher along [`up`] (the order of the
/// tiled product).
fn ordered(conf: &Confinement, p: Pair) -> Pair {
    let n = up(conf);
    if along(n, p.xb) > along(n, p.xa) {
        let mut v = [0.0; 22];
        v[..11].copy_from_slice(&p.v[11..]);
        v[11..].copy_from_slice(&p.v[..11]);
        Pair {
            xa: p.xb,
            aa: p.ab,
            xb: p.xa,
            ab: p.aa,
            v,
        }
    } else {
        p
    }
}

/// The lane kernels over a list of pairs (a multiple of 16), outputs `a` then `b` per
/// pair, on lanes of `E` (inputs rounded to `E`). The block kernels (FTS has only those)
/// exist without the exchange of roles only: the pairs must be [`ordered`].
struct Run<'a, E> {
    conf: &'a Confinement,
    pairs: &'a [Pair],
    level: Moments,
    /// The kernels without the exchange of roles.
    ordered: bool,
    /// The block kernels times the moments, rather than the fused products.
    blocks: bool,
    elem: std::marker::PhantomData<E>,
}

/// `(M^{ab} vb, (M^{ab})^T va)` from blocks flattened as `at` says.
#[inline(always)]
fn flat_product<L: Lane, const K: usize>(
    m: &[L],
    at: &[[usize; K]; K],
    va: [L; K],
    vb: [L; K],
) -> Vec<L> {
    let mut a = [L::splat(0.0); K];
    let mut b = [L::splat(0.0); K];
    for i in 0..K {
        for j in 0..K {
            a[i] = m[at[i][j]].mul_add(vb[j], a[i]);
            b[j] = m[at[i][j]].mul_add(va[i], b[j]);
        }
    }
    [a, b].concat()
}

/// The outputs of a lane kernel, one row per lane: `rows[l][k]` is lane `l` of output `k`.
#[inline(always)]
pub fn per_lane<L: Lane>(outputs: &[L]) -> Vec<Vec<f64>> {
    let w = L::WIDTH;
    let mut rows = vec![vec![0.0; outputs.len()]; w];
    for (k, v) in outputs.iter().enumerate() {
        let mut buf = vec![L::Elem::default(); w];
        v.store(&mut buf);
        for (row, b) in rows.iter_mut().zip(&buf) {
            row[k] = b.to_f64();
        }
    }
    rows
}

impl<E: Element> WithLanes for Run<'_, E> {
    type Elem = E;
    type Output = Vec<Vec<f64>>;
    #[inline(always)]
    fn run<L: Lane<Elem = E>>(self) -> Vec<Vec<f64>> {
        let w = L::WIDTH;
        let mut out = Vec::new();
        for chunk in self.pairs.chunks(w) {
            let col = |f: &dyn Fn(&Pair) -> f64| {
                L::load(&chunk.iter().map(|p| E::from_f64(f(p))).collect::<Vec<E>>())
            };
            let xa: [L; 3] = std::array::from_fn(|k| col(&|p| p.xa[k]));
            let xb: [L; 3] = std::array::from_fn(|k| col(&|p| p.xb[k]));
            let (aa, ab) = (col(&|p| p.aa), col(&|p| p.ab));
            let va: [L; 11] = std::array::from_fn(|k| col(&|p| p.v[k]));
            let vb: [L; 11] = std::array::from_fn(|k| col(&|p| p.v[11 + k]));
            let first = |v: [L; 11]| -> [L; 3] { std::array::from_fn(|k| v[k]) };
            let six = |v: [L; 11]| -> [L; 6] { std::array::from_fn(|k| v[k]) };
            let (c, o) = (self.conf, self.ordered);
            assert!(
                o || !self.blocks,
                "block lanes exist without the exchange only"
            );
            let lanes: Vec<L> = match self.level {
                Moments::F if self.blocks => {
                    let m = pair_f_lanes_ordered(c, 1.3, xa, aa, xb, ab);
                    flat_product(&m, &F_FLAT, first(va), first(vb))
                }
                Moments::FT if self.blocks => {
                    let m = pair_ft_lanes_ordered(c, 1.3, xa, aa, xb, ab);
                    flat_product(&m, &FT_FLAT, six(va), six(vb))
                }
                Moments::F if o => {
                    product_f_lanes_ordered(c, 1.3, xa, aa, xb, ab, first(va), first(vb)).to_vec()
                }
                Moments::F => {
                    product_f_lanes(c, 1.3, xa, aa, xb, ab, first(va), first(vb)).to_vec()
                }
                Moments::FT if o => {
                    product_ft_lanes_ordered(c, 1.3, xa, aa, xb, ab, six(va), six(vb)).to_vec()
                }
                Moments::FT => product_ft_lanes(c, 1.3, xa, aa, xb, ab, six(va), six(vb)).to_vec(),
                Moments::FTS => {
                    assert!(self.blocks, "FTS lanes are blocks");
                    let m = pair_lanes_ordered(c, 1.3, xa, aa, xb, ab);
                    let (a, b) = grand_lanes_product(&m, va, vb);
                    [a, b].concat()
                }
            };
            out.extend(per_lane(&lanes));
        }
        out
    }
}

/// The scalar kernels' product (with `blocks`, and always at FTS, the pair blocks of
/// [`kernels::pair_f`], [`kernels::pair_ft`] or [`kernels::pair`] times the moments).
fn scalar(conf: &Confinement, p: &Pair, level: Moments, blocks: bool) -> Vec<f64> {
    let (xa, aa, xb, ab) = (p.xa, p.aa, p.xb, p.ab);
    let (a, b) = match level {
        Moments::F if blocks => {
            let (va, vb) = moments::<3>(p);
            let r = pair_f(conf, 1.3, xa, aa, xb, ab).product(va, vb);
            (r.a.to_vec(), r.b.to_vec())
        }
        Moments::FT if blocks => {
            let (va, vb) = moments::<6>(p);
            let r = pair_ft(conf, 1.3, xa, aa, xb, ab).product(va, vb);
            (r.a.to_vec(), r.b.to_vec())
        }
        Moments::F => {
            let (va, vb) = moments::<3>(p);
            let r = product_f(conf, 1.3, xa, aa, xb, ab, va, vb);
            (r.a.to_vec(), r.b.to_vec())
        }
        Moments::FT => {
            let (va, vb) = moments::<6>(p);
            let r = product_ft(conf, 1.3, xa, aa, xb, ab, va, vb);
            (r.a.to_vec(), r.b.to_vec())
        }
        Moments::FTS => {
            let (va, vb) = moments::<11>(p);
            let r = pair(conf, 1.3, xa, aa, xb, ab).product(va, vb);
            (r.a.to_vec(), r.b.to_vec())
        }
    };
    [a, b].concat()
}

/// Random pairs, and pairs at every switch of the scalar kernels.
fn pairs(conf: &Confinement, rng: &mut ChaCha8Rng) -> Vec<Pair> {
    let v = |rng: &mut ChaCha8Rng| std::array::from_fn(|_| rng.gen_range(-1.0..1.0));
    let mut out = Vec::new();
    for _ in 0..64 {
        let ps = random_spheres(rng, conf, 2, (0.3, 1.5), 0.05, 8.0);
        out.push(Pair {
            xa: ps[0].x,
            aa: ps[0].a,
            xb: ps[1].x,
            ab: ps[1].a,
            v: v(rng),
        });
    }
    // heights over the first boundary's plane (or the origin), along its normal
    let (lo, hi) = local_bounds(conf)[2];
    let base = if lo.is_finite() { lo } else { 0.0 };
    let top = if hi.is_finite() {
        hi - 2.0
    } else {
        base + 40.0
    };
    // heights 1.5 and 2.5 over the lower boundary (or the origin), and equal heights
    for (ha, hb) in [(1.5, 2.5), (2.5, 1.5), (2.0, 2.0), (1.2, top - base)] {
        let (za, zb) = (base + ha, base + hb);
        // the lateral switch of the wall: rho^2 = 2 * 100^2 (ha^2 + hb^2)
        let switch = (2.0e4 * (ha * ha + hb * hb)).sqrt();
        for rho in [
            0.0,
            3.0,
            switch * (1.0 - 1e-12),
            switch * (1.0 + 1e-12),
            0.5 * switch,
            2.0 * switch,
        ] {
            if rho < 2.5 && (za - zb).abs() < 2.5 {
                continue; // overlapping
            }
            let phi: f64 = rng.gen_range(0.0..std::f64::consts::TAU);
            out.push(Pair {
                xa: placed(conf, [rho * phi.cos() + 0.3, rho * phi.sin() - 0.2, za]),
                aa: 1.0,
                xb: placed(conf, [0.3, -0.2, zb]),
                ab: 0.8,
                v: v(rng),
            });
        }
    }
    // shuffle so that near and far, exchanged and not, share vectors
    for i in (1..out.len()).rev() {
        let j = rng.gen_range(0..=i);
        out.swap(i, j);
    }
    while out.len() % 16 != 0 {
        out.push(out[0]);
    }
    out
}

/// The direct sum's cancellation factor `rho^2 / (h_a h_b)` of a pair where an image
/// cancels the Stokeslet (the wall's; heights over that plane, `rho` along it), 0
/// elsewhere.
fn cancellation(conf: &Confinement, p: &Pair) -> f64 {
    let Some(n) = conf.exchange_normal() else {
        return 0.0;
    };
    let plane = conf
        .boundaries()
        .into_iter()
        .find(|b| b.normal == n)
        .expect("the exchange is along a boundary's normal");
    let [t1, t2, _] = kernel_gen::physics::green::frame(n);
    let d: [f64; 3] = std::array::from_fn(|k| p.xa[k] - p.xb[k]);
    let rho2 = along(t1, d).powi(2) + along(t2, d).powi(2);
    rho2 / (plane.distance(p.xa) * plane.distance(p.xb))
}

/// Every confinement, the F and FT products and blocks and the FTS blocks, on every
/// instruction set with lanes of `E`: the
/// largest relative difference to the scalar `f64` kernels (of the larger output
/// vector's norm) must stay within `tol(cancellation factor)`; returns nothing,
/// prints the largest per case.
pub fn lanes_against_scalar<E: Element>(seed: u64, tol: impl Fn(f64) -> f64 + Send) {
    crate::on_a_large_stack(|| against_scalar::<E>(seed, tol))
}

fn against_scalar<E: Element>(seed: u64, tol: impl Fn(f64) -> f64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let isas = Isa::all_available();
    println!("instruction sets on this processor: {isas:?}");
    for (name, conf) in all_confinements() {
        let list = pairs(&conf, &mut rng);
        let levels = [
            (Moments::F, false),
            (Moments::F, true),
            (Moments::FT, false),
            (Moments::FT, true),
            (Moments::FTS, true),
        ];
        for (level, blocks) in levels {
            // blocks: the kernel without the exchange, on pairs in the tiled product's
            // order
            let list: Vec<Pair> = if blocks {
                list.iter().map(|&p| ordered(&conf, p)).collect()
            } else {
                list.clone()
            };
            let expect: Vec<Vec<f64>> = list
                .iter()
                .map(|p| scalar(&conf, p, level, blocks))
                .collect();
            for &isa in &isas {
                let run = Run::<E> {
                    conf: &conf,
                    pairs: &list,
                    level,
                    ordered: blocks,
                    blocks,
                    elem: std::marker::PhantomData,
                };
                let got = dispatch_with(isa, run).ok().expect("available");
                let mut worst = (0.0f64, 0usize);
                for (k, (g, e)) in got.iter().zip(&expect).enumerate() {
                    let d: Vec<f64> = g.iter().zip(e).map(|(x, y)| x - y).collect();
                    let half = e.len() / 2;
                    let scale = norm(&e[..half]).max(norm(&e[half..]));
                    let rel = norm(&d) / scale;
                    let tol = tol(cancellation(&conf, &list[k]));
                    if rel > worst.0 {
                        worst = (rel, k);
                    }
                    assert!(
                        rel <= tol,
                        "{name} {level:?} {isa:?} blocks {blocks} pair {k}: relative difference {rel:e}\n lanes {g:?}\n scalar {e:?}"
                    );
                }
                let p = &list[worst.1];
                println!(
                    "{name:<13} {:<10} {:<7} {} pairs: largest relative difference {:.1e} (xa {:?}, xb {:?})",
                    format!("{level:?}{}", if blocks { " blocks" } else { "" }),
                    isa.name(),
                    list.len(),
                    worst.0,
                    p.xa,
                    p.xb
                );
            }
        }
    }
}

/// The kernels without the exchange of roles (`product_f_lanes_ordered`,
/// `product_ft_lanes_ordered`) on pairs with `a` at least as high as `b` (the order of the
/// tiled product) give the exchanging kernels' values bit for bit: the exchange is then
/// the identity in every lane, equal heights included. Every confinement, F and FT,
/// every instruction set, lanes of `E`.
pub fn ordered_lanes_equal_exchanging<E: Element>(seed: u64) {
    crate::on_a_large_stack(|| ordered_equal_exchanging::<E>(seed))
}

fn ordered_equal_exchanging<E: Element>(seed: u64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    for (name, conf) in all_confinements() {
        let list: Vec<Pair> = pairs(&conf, &mut rng)
            .into_iter()
            .map(|p| ordered(&conf, p))
            .collect();
        let n = up(&conf);
        assert!(
            list.iter().any(|p| along(n, p.xa) == along(n, p.xb)),
            "equal heights are tested"
        );
        for level in [Moments::F, Moments::FT] {
            for &isa in &Isa::all_available() {
                let run = |ordered| {
                    let r = Run::<E> {
                        conf: &conf,
                        pairs: &list,
                        level,
                        ordered,
                        blocks: false,
                        elem: std::marker::PhantomData,
                    };
                    dispatch_with(isa, r).ok().expect("available")
                };
                let (exchanging, ordered) = (run(false), run(true));
                for (k, (e, o)) in exchanging.iter().zip(&ordered).enumerate() {
                    let same = e.iter().zip(o).all(|(x, y)| x.to_bits() == y.to_bits());
                    assert!(same, "{name} {isa:?} {level:?} pair {k}:\n{e:?}\n{o:?}");
                }
            }
        }
    }
}
