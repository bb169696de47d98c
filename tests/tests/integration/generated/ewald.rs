//! The kernels of the building block `ewald_real`, the real part of Beenakker's Ewald split
//! (`kernel_gen::physics::green::ewald`; scenes `ewald_real_f`, `ewald_real_ft`): not a
//! confinement, so the checks of `confinements` and `engine`, which visit the
//! confinements through `kernels::Confinement`, do not reach them. Here: the emitted
//! kernels are their traced graphs, and the pair kernels are the double-double direct sum.
//! The generator's own tests check the Green's function (jets against finite
//! differences, `W(0)` against Beenakker's closed forms, `J^R -> J` as `xi -> 0`).

use integration_tests::flat2;
use kernel_gen::catalog::Moments;
use kernel_gen::kernel::{evaluate_direct, trace, Interaction, KernelSpec, Path};
use kernel_gen::number::dd::Dd;
use kernel_gen::physics::green::ewald::EwaldReal;
use kernel_gen::physics::operators::Basis;
use kernels::generated::{scene_ewald_real_f as f, scene_ewald_real_ft as ft};
use kernels::{BlocksFT, Product};

const ETA: f64 = 1.3;
const SIGMA: f64 = 0.9;

/// Pairs `(xa, xb, aa, ab)` at `xi r` from 0.2 to 6.5, both sides of the switch of the
/// lowered `erfc` at `xi r = 1/2`, and of every digit of the lowered exponential's
/// ladder that `(xi r)^2 <= 42` reaches; radii in proportion, `a_a + a_b` from 0.55 r to
/// 0.85 r (the kernels' domain: overlapping pairs take the RPY overlap forms).
fn pairs() -> Vec<([f64; 3], [f64; 3], f64, f64)> {
    let dir = [0.48, -0.6, 0.64];
    [
        0.2, 0.449, 0.451, 0.71, 1.0, 1.42, 2.01, 2.83, 4.0, 5.66, 6.5,
    ]
    .iter()
    .enumerate()
    .map(|(k, &p)| {
        let r = p * SIGMA;
        let xa = [0.3, -1.2 + 0.1 * k as f64, 2.0];
        let xb = std::array::from_fn(|i| xa[i] - r * dir[i]);
        (xa, xb, 0.35 * r, (0.2 + 0.03 * k as f64) * r)
    })
    .collect()
}

fn ft_flat(b: &BlocksFT) -> Vec<f64> {
    [flat2(&b.uf), flat2(&b.ul), flat2(&b.of), flat2(&b.ol)].concat()
}

fn product_flat<const K: usize>(p: &Product<K>) -> Vec<f64> {
    [p.a.to_vec(), p.b.to_vec()].concat()
}

fn spec(moments: Moments, interaction: Interaction, equal: bool, product: bool) -> KernelSpec {
    KernelSpec {
        interaction,
        basis: Basis::Orthonormal,
        equal_radii: equal,
        blocks: moments.blocks(),
        path: Path::Structured,
        product,
        drift: None,
    }
}

/// Every emitted kernel of both scenes against the interpreter of its trace: the same
/// operations in the same order (the lowered `exp` and `erfc` included), so 4 ulps
/// (allowing for `powi`) as for every confinement's kernels
/// (`engine::emitted_kernels_equal_the_interpreted_graph`).
#[test]
fn emitted_kernels_equal_the_interpreted_graph() {
    let va = [0.3, -1.0, 0.7, 0.2, 0.5, -0.4];
    let vb = [1.1, 0.4, -0.6, -0.3, 0.8, 0.9];
    let mut checked = 0;
    for moments in [Moments::F, Moments::FT] {
        let n = moments.per_particle();
        let kinds = [
            (Interaction::SelfTerm, false, false),
            (Interaction::Pair, false, false),
            (Interaction::Pair, true, false),
            (Interaction::Pair, false, true),
            (Interaction::Pair, true, true),
        ];
        for (interaction, equal, product) in kinds {
            let traced = trace(&EwaldReal, &spec(moments, interaction, equal, product));
            for (xa, xb, aa, ab) in pairs() {
                let mut inputs = xa.to_vec();
                if interaction == Interaction::Pair {
                    inputs.extend(xb);
                }
                if interaction == Interaction::Pair && !equal {
                    inputs.extend([aa, ab, ETA, SIGMA]);
                } else {
                    inputs.extend([aa, ETA, SIGMA]);
                }
                if product {
                    inputs.extend(&va[..n]);
                    inputs.extend(&vb[..n]);
                }
                let (fa, fb) = ([va[0], va[1], va[2]], [vb[0], vb[1], vb[2]]);
                let got: Vec<f64> = match (moments, interaction, equal, product) {
                    (Moments::F, Interaction::SelfTerm, ..) => {
                        flat2(&f::ewald_real_f_self(xa, aa, ETA, SIGMA).uf)
                    }
                    (Moments::F, _, false, false) => {
                        flat2(&f::ewald_real_f_pair(xa, xb, aa, ab, ETA, SIGMA).uf)
                    }
                    (Moments::F, _, true, false) => {
                        flat2(&f::ewald_real_f_pair_equal(xa, xb, aa, ETA, SIGMA).uf)
                    }
                    (Moments::F, _, false, true) => product_flat(&f::ewald_real_f_pair_product(
                        xa, xb, aa, ab, ETA, SIGMA, fa, fb,
                    )),
                    (Moments::F, _, true, true) => product_flat(
                        &f::ewald_real_f_pair_equal_product(xa, xb, aa, ETA, SIGMA, fa, fb),
                    ),
                    (_, Interaction::SelfTerm, ..) => {
                        ft_flat(&ft::ewald_real_ft_self(xa, aa, ETA, SIGMA))
                    }
                    (_, _, false, false) => {
                        ft_flat(&ft::ewald_real_ft_pair(xa, xb, aa, ab, ETA, SIGMA))
                    }
                    (_, _, true, false) => {
                        ft_flat(&ft::ewald_real_ft_pair_equal(xa, xb, aa, ETA, SIGMA))
                    }
                    (_, _, false, true) => product_flat(&ft::ewald_real_ft_pair_product(
                        xa, xb, aa, ab, ETA, SIGMA, va, vb,
                    )),
                    (_, _, true, true) => product_flat(&ft::ewald_real_ft_pair_equal_product(
                        xa, xb, aa, ETA, SIGMA, va, vb,
                    )),
                };
                let want: Vec<f64> = traced.eval(&inputs);
                assert_eq!(got.len(), want.len());
                for (k, (a, b)) in got.iter().zip(&want).enumerate() {
                    let ulps = (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs();
                    assert!(
                        ulps <= 4 || a == b,
                        "{moments:?} {interaction:?} equal {equal} product {product} at {xa:?}, {xb:?}, output {k}: emitted {a:e} vs interpreted {b:e}"
                    );
                }
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 2 * 5 * pairs().len());
}

/// The emitted FT pair kernel (the structured path of the radial potential) against the
/// direct sum in double-double (`kernel_gen::kernel::evaluate_direct` on the generic
/// path: jets of the closed form with `Dd`'s own `exp` and `erfc`, good to 1e-28): each
/// block to 1e-13 of its largest entry, the lowered functions' 5e-15 and the round-off of
/// the sums of a few hundred terms. The F kernel is the FT kernel's first block (the same
/// terms, grouped differently after dead-code elimination: 1e-13, as `scenes`).
#[test]
fn pair_kernel_equals_the_direct_sum_in_double_double() {
    // the reference: the generic jets of the closed form `J^R`, not the kernels' path
    let generic = KernelSpec {
        path: Path::Generic,
        ..spec(Moments::FT, Interaction::Pair, false, false)
    };
    for (xa, xb, aa, ab) in pairs() {
        let got = ft_flat(&ft::ewald_real_ft_pair(xa, xb, aa, ab, ETA, SIGMA));
        let inputs: Vec<Dd> = [xa.to_vec(), xb.to_vec(), vec![aa, ab, ETA, SIGMA]]
            .concat()
            .into_iter()
            .map(Dd::new)
            .collect();
        let want = evaluate_direct(&EwaldReal, &generic, &inputs);
        for (b, (g, w)) in got.chunks(9).zip(want.chunks(9)).enumerate() {
            let scale = w.iter().map(|v| v.to_f64().abs()).fold(0.0, f64::max);
            for (x, y) in g.iter().zip(w) {
                let err = (Dd::new(*x) - *y).to_f64().abs();
                assert!(
                    err <= 1e-13 * scale,
                    "block {b} at {xa:?}, {xb:?}: {x:e} vs {y:?}"
                );
            }
        }
        let uf = flat2(&f::ewald_real_f_pair(xa, xb, aa, ab, ETA, SIGMA).uf);
        let scale = got[..9].iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (a, b) in uf.iter().zip(&got[..9]) {
            assert!((a - b).abs() <= 1e-13 * scale, "F = FT pruned at {xa:?}");
        }
    }
}

/// Reciprocity, `M^{ba} = (M^{ab})^T` blockwise (`UF`, `OL` transposed, `UL` and `OF`
/// exchanged and transposed), with unequal radii exchanged too; and the fused products
/// equal the blocks times the moments. Both to 1e-13 of the largest entry (the kernels
/// of the two orders and the product sum the same terms in other orders).
#[test]
fn reciprocal_and_products_equal_the_blocks() {
    let va = [0.3, -1.0, 0.7, 0.2, 0.5, -0.4];
    let vb = [1.1, 0.4, -0.6, -0.3, 0.8, 0.9];
    let t = |m: &[[f64; 3]; 3]| -> [[f64; 3]; 3] {
        std::array::from_fn(|i| std::array::from_fn(|j| m[j][i]))
    };
    for (xa, xb, aa, ab) in pairs() {
        let m = ft::ewald_real_ft_pair(xa, xb, aa, ab, ETA, SIGMA);
        let back = ft::ewald_real_ft_pair(xb, xa, ab, aa, ETA, SIGMA);
        let want = BlocksFT {
            uf: t(&m.uf),
            ul: t(&m.of),
            of: t(&m.ul),
            ol: t(&m.ol),
        };
        let (g, w) = (ft_flat(&back), ft_flat(&want));
        let scale = w.iter().fold(0.0f64, |s, v| s.max(v.abs()));
        for (a, b) in g.iter().zip(&w) {
            assert!(
                (a - b).abs() <= 1e-13 * scale,
                "reciprocity at {xa:?}, {xb:?}"
            );
        }
        let p = ft::ewald_real_ft_pair_product(xa, xb, aa, ab, ETA, SIGMA, va, vb);
        let q = m.product(va, vb);
        let scale = q.a.iter().chain(&q.b).fold(0.0f64, |s, v| s.max(v.abs()));
        for (a, b) in p.a.iter().chain(&p.b).zip(q.a.iter().chain(&q.b)) {
            assert!((a - b).abs() <= 1e-13 * scale, "product at {xa:?}, {xb:?}");
        }
    }
}
