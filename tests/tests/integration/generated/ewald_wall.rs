//! The kernels of the building block `ewald_wall`, the real part of the Ewald split of
//! Blake's image system (`kernel_gen::physics::green::ewald_wall`; scenes `ewald_wall_f`
//! and `ewald_wall_ft`, the real-space blocks and lane kernels of the sum along a
//! periodic wall): not a confinement, so `confinements` and `engine` do not reach them.
//! Here: the emitted scalar kernels are their traced graphs, and the F lane kernel (which
//! the fast product runs) is the scalar one. The generator's own tests check the
//! Green's function (jets against finite differences, the pair and self kernels against
//! the direct sum in double-double, Blake's image as `xi -> 0`).

use integration_tests::flat2;
use kernel_gen::catalog::Moments;
use kernel_gen::kernel::{trace, Interaction, KernelSpec, Path};
use kernel_gen::physics::green::ewald_wall::EwaldWall;
use kernel_gen::physics::operators::Basis;
use kernels::generated::{scene_ewald_wall_f as f, scene_ewald_wall_ft as ft};
use kernels::lanes::{dispatch, Lane, WithLanes};
use kernels::BlocksFT;

const ETA: f64 = 1.3;
const SIGMA: f64 = 2.5;
const HEIGHT: f64 = -0.4;

/// Field and source positions and radii `(xa, xb, aa, ab)`.
type Pair = ([f64; 3], [f64; 3], f64, f64);

/// Pairs `(xa, xb, aa, ab)` above the wall `x3 = HEIGHT`: lateral separations from 0.3
/// to 3 screening lengths (both sides of the lowered `erfc`'s switch), heights from near
/// contact with the wall to 12 radii, radii unequal and not overlapping.
fn pairs() -> Vec<Pair> {
    [0.3, 0.7, 1.2, 2.0, 3.0]
        .iter()
        .enumerate()
        .map(|(k, &p)| {
            let rho = p * SIGMA;
            let (ha, hb) = (1.1 + 2.5 * k as f64, 0.6 + 0.4 * k as f64);
            let xa = [0.3, -1.2, HEIGHT + ha];
            let xb = [0.3 - 0.6 * rho, -1.2 + 0.8 * rho, HEIGHT + hb];
            (xa, xb, 1.0, 0.5)
        })
        .collect()
}

fn ft_flat(b: &BlocksFT) -> Vec<f64> {
    [flat2(&b.uf), flat2(&b.ul), flat2(&b.of), flat2(&b.ol)].concat()
}

fn spec(moments: Moments, interaction: Interaction, equal: bool) -> KernelSpec {
    KernelSpec {
        interaction,
        basis: Basis::Orthonormal,
        equal_radii: equal,
        blocks: moments.blocks(),
        path: Path::Structured,
        product: false,
        drift: None,
    }
}

/// Every emitted scalar kernel of both scenes against the interpreter of its trace: the
/// same operations in the same order, so 4 ulps (allowing for `powi`) as for every
/// confinement's kernels (`engine::emitted_kernels_equal_the_interpreted_graph`).
#[test]
fn emitted_kernels_equal_the_interpreted_graph() {
    let mut checked = 0;
    for moments in [Moments::F, Moments::FT] {
        let kinds = [
            (Interaction::SelfTerm, false),
            (Interaction::Pair, false),
            (Interaction::Pair, true),
        ];
        for (interaction, equal) in kinds {
            let traced = trace(&EwaldWall, &spec(moments, interaction, equal));
            for (xa, xb, aa, ab) in pairs() {
                let mut inputs = xa.to_vec();
                if interaction == Interaction::Pair {
                    inputs.extend(xb);
                }
                if interaction == Interaction::Pair && !equal {
                    inputs.extend([aa, ab, ETA, HEIGHT, SIGMA]);
                } else {
                    inputs.extend([aa, ETA, HEIGHT, SIGMA]);
                }
                let got: Vec<f64> = match (moments, interaction, equal) {
                    (Moments::F, Interaction::SelfTerm, _) => {
                        flat2(&f::ewald_wall_f_self(xa, aa, ETA, HEIGHT, SIGMA).uf)
                    }
                    (Moments::F, _, false) => {
                        flat2(&f::ewald_wall_f_pair(xa, xb, aa, ab, ETA, HEIGHT, SIGMA).uf)
                    }
                    (Moments::F, _, true) => {
                        flat2(&f::ewald_wall_f_pair_equal(xa, xb, aa, ETA, HEIGHT, SIGMA).uf)
                    }
                    (_, Interaction::SelfTerm, _) => {
                        ft_flat(&ft::ewald_wall_ft_self(xa, aa, ETA, HEIGHT, SIGMA))
                    }
                    (_, _, false) => {
                        ft_flat(&ft::ewald_wall_ft_pair(xa, xb, aa, ab, ETA, HEIGHT, SIGMA))
                    }
                    (_, _, true) => ft_flat(&ft::ewald_wall_ft_pair_equal(
                        xa, xb, aa, ETA, HEIGHT, SIGMA,
                    )),
                };
                let want: Vec<f64> = traced.eval(&inputs);
                assert_eq!(got.len(), want.len());
                for (k, (a, b)) in got.iter().zip(&want).enumerate() {
                    let ulps = (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs();
                    assert!(
                        ulps <= 4 || a == b,
                        "{moments:?} {interaction:?} equal {equal} at {xa:?}, {xb:?}, output {k}: emitted {a:e} vs interpreted {b:e}"
                    );
                }
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 2 * 3 * pairs().len());
}

/// Every pair of [`pairs`] in its own lane (cycled to fill the width): the F lane
/// kernel's outputs, lane by lane (the one the fast product runs; the FT lane kernel is
/// not instantiated in the solver).
struct Lanes;

impl WithLanes for Lanes {
    type Elem = f64;
    type Output = Vec<Vec<f64>>;

    #[inline(always)]
    fn run<L: Lane<Elem = f64>>(self) -> Self::Output {
        let w = L::WIDTH;
        let ps = pairs();
        let column = |get: &dyn Fn(&Pair) -> f64| {
            let v: Vec<f64> = (0..w).map(|l| get(&ps[l % ps.len()])).collect();
            L::load(&v)
        };
        let xa: [L; 3] = std::array::from_fn(|i| column(&|p| p.0[i]));
        let xb: [L; 3] = std::array::from_fn(|i| column(&|p| p.1[i]));
        let (aa, ab) = (column(&|p| p.2), column(&|p| p.3));
        let (eta, height, sigma) = (L::splat(ETA), L::splat(HEIGHT), L::splat(SIGMA));
        let lanes = |out: &[L]| -> Vec<Vec<f64>> {
            let mut per = vec![vec![0.0; out.len()]; w];
            let mut lane = vec![0.0; w];
            for (k, v) in out.iter().enumerate() {
                v.store(&mut lane);
                for l in 0..w {
                    per[l][k] = lane[l];
                }
            }
            per
        };
        lanes(&f::ewald_wall_f_pair_lanes(
            xa, xb, aa, ab, eta, height, sigma,
        ))
    }
}

/// The lane kernels round differently from the scalar ones (fused multiply-adds): they
/// agree to a few ulps of the largest entry, and 1e-13 of it bounds that with room on
/// every instruction set (as in `kernels`' documentation of the lanes).
#[test]
fn lane_kernels_equal_the_scalar_kernels() {
    let ps = pairs();
    let out = dispatch(Lanes);
    assert!(!out.is_empty());
    for (l, got) in out.iter().enumerate() {
        let (xa, xb, aa, ab) = ps[l % ps.len()];
        let want = flat2(&f::ewald_wall_f_pair(xa, xb, aa, ab, ETA, HEIGHT, SIGMA).uf);
        let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (k, (g, w)) in got.iter().zip(&want).enumerate() {
            assert!(
                (g - w).abs() <= 1e-13 * scale,
                "lane {l}, output {k}: {g:e} vs {w:e}"
            );
        }
    }
}
