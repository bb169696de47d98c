//! The lane kernels of the building block `ewald_real` (the real part of the Ewald split;
//! scenes `ewald_real_f`, `ewald_real_ft`; not a confinement, so not among
//! [`crate::lane_checks`]' pairs) against its scalar `f64` kernels, generic over the
//! lanes' element `E` as [`crate::lane_checks`] is: the pair blocks and the fused pair
//! products, F and FT.

use crate::lane_checks::per_lane;
use kernels::generated::{scene_ewald_real_f as f, scene_ewald_real_ft as ft};
use kernels::lanes::{dispatch_with, Element, Isa, Lane, WithLanes};

/// `(xa, xb, aa, ab)`.
type Pair = ([f64; 3], [f64; 3], f64, f64);

const ETA: f64 = 1.3;
const SIGMA: f64 = 0.9;

/// 32 pairs at `xi r` from 0.05 to 6.5 in a geometric progression (both branches of the
/// lowered `erfc`, every digit of the exponential's ladder), mixed in every vector; radii
/// in proportion, `a_a + a_b` from 0.55 r to 0.86 r (the kernels' domain: overlapping
/// pairs take the RPY overlap forms).
fn pairs() -> Vec<Pair> {
    (0..32)
        .map(|k| {
            let p = 0.05 * (130f64).powf(((k * 13) % 32) as f64 / 31.0);
            let r = p * SIGMA;
            let dir = [0.48, -0.6, 0.64];
            let xa = [0.3 + 0.01 * k as f64, -1.2, 2.0];
            let xb = std::array::from_fn(|i| xa[i] - r * dir[i]);
            (xa, xb, 0.35 * r, (0.2 + 0.01 * k as f64) * r)
        })
        .collect()
}

const VA: [f64; 6] = [0.3, -1.0, 0.7, 0.2, 0.5, -0.4];
const VB: [f64; 6] = [1.1, 0.4, -0.6, -0.3, 0.8, 0.9];

/// The scalar kernels' outputs per pair: F blocks, F product, FT blocks, FT product.
fn scalar(p: &Pair) -> Vec<f64> {
    let (xa, xb, aa, ab) = *p;
    let (fa, fb) = ([VA[0], VA[1], VA[2]], [VB[0], VB[1], VB[2]]);
    let b = f::ewald_real_f_pair(xa, xb, aa, ab, ETA, SIGMA);
    let pf = f::ewald_real_f_pair_product(xa, xb, aa, ab, ETA, SIGMA, fa, fb);
    let c = ft::ewald_real_ft_pair(xa, xb, aa, ab, ETA, SIGMA);
    let pft = ft::ewald_real_ft_pair_product(xa, xb, aa, ab, ETA, SIGMA, VA, VB);
    let mut v: Vec<f64> = b.uf.iter().flatten().copied().collect();
    v.extend(pf.a.iter().chain(&pf.b));
    for m in [c.uf, c.ul, c.of, c.ol] {
        v.extend(m.iter().flatten());
    }
    v.extend(pft.a.iter().chain(&pft.b));
    v
}

struct Run<'a, E>(&'a [Pair], std::marker::PhantomData<E>);

/// The four output groups of the lane kernels for the pairs of one vector, one row per
/// pair (inputs rounded to `L::Elem`).
#[inline(always)]
fn one_vector<L: Lane>(chunk: &[Pair]) -> Vec<Vec<f64>> {
    let col = |g: &dyn Fn(&Pair) -> f64| {
        L::load(
            &chunk
                .iter()
                .map(|p| L::Elem::from_f64(g(p)))
                .collect::<Vec<L::Elem>>(),
        )
    };
    let xa: [L; 3] = std::array::from_fn(|k| col(&|p| p.0[k]));
    let xb: [L; 3] = std::array::from_fn(|k| col(&|p| p.1[k]));
    let (aa, ab) = (col(&|p| p.2), col(&|p| p.3));
    let (eta, sigma) = (L::splat(ETA), L::splat(SIGMA));
    let va: [L; 6] = VA.map(L::splat);
    let vb: [L; 6] = VB.map(L::splat);
    let (fa, fb): ([L; 3], [L; 3]) = (
        std::array::from_fn(|k| va[k]),
        std::array::from_fn(|k| vb[k]),
    );
    let mut lanes: Vec<L> = f::ewald_real_f_pair_lanes(xa, xb, aa, ab, eta, sigma).to_vec();
    lanes.extend(f::ewald_real_f_pair_product_lanes(
        xa, xb, aa, ab, eta, sigma, fa, fb,
    ));
    lanes.extend(ft::ewald_real_ft_pair_lanes(xa, xb, aa, ab, eta, sigma));
    lanes.extend(ft::ewald_real_ft_pair_product_lanes(
        xa, xb, aa, ab, eta, sigma, va, vb,
    ));
    per_lane(&lanes)
}

impl<E: Element> WithLanes for Run<'_, E> {
    type Elem = E;
    type Output = Vec<Vec<f64>>;
    #[inline(always)]
    fn run<L: Lane<Elem = E>>(self) -> Vec<Vec<f64>> {
        self.0.chunks(L::WIDTH).flat_map(one_vector::<L>).collect()
    }
}

/// The largest difference between the lane kernels (lanes of `E`, inputs rounded to `E`)
/// and the scalar kernels, relative to the largest entry of each output group (F blocks,
/// F product, FT blocks, FT product) of each pair, on every instruction set this
/// processor has; panics where it exceeds `tol`. Returns the worst per instruction set.
pub fn ewald_real_lanes_against_scalar<E: Element>(tol: f64) -> Vec<(Isa, f64)> {
    crate::on_a_large_stack(|| against_scalar::<E>(tol))
}

fn against_scalar<E: Element>(tol: f64) -> Vec<(Isa, f64)> {
    let ps = pairs();
    let want: Vec<Vec<f64>> = ps.iter().map(scalar).collect();
    // (offset, length) of the four output groups
    let groups = [(0, 9), (9, 6), (15, 36), (51, 12)];
    let mut out = Vec::new();
    for isa in Isa::all_available() {
        let run: Run<E> = Run(&ps, std::marker::PhantomData);
        let got = dispatch_with(isa, run).ok().expect("available");
        let mut worst: f64 = 0.0;
        for (k, (g, w)) in got.iter().zip(&want).enumerate() {
            for &(at, n) in &groups {
                let scale = w[at..at + n].iter().fold(0.0f64, |m, v| m.max(v.abs()));
                for i in at..at + n {
                    let e = (g[i] - w[i]).abs() / scale;
                    worst = worst.max(e);
                    assert!(
                        e <= tol,
                        "{isa:?} pair {k} output {i}: {} vs {}",
                        g[i],
                        w[i]
                    );
                }
            }
        }
        out.push((isa, worst));
    }
    out
}
