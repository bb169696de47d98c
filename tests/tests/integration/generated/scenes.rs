//! Scene kernels are the full kernels pruned: the F and FT blocks and the fused pair
//! products of every confinement equal the corresponding parts of the FTS kernels.

use integration_tests::{all_confinements, flat2, random_spheres, rel_diff};
use kernels::{
    pair, pair_f, pair_ft, product_f, product_ft, self_f, self_ft, self_mobility, BlocksFT,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Tolerance 1e-13: the pruned and full kernels sum the same terms, possibly grouped
/// differently after dead-code elimination.
#[test]
fn scene_kernels_equal_the_full_kernels_pruned() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for (name, conf) in all_confinements() {
        for equal in [false, true] {
            let radii = if equal { (0.8, 0.8) } else { (0.4, 1.4) };
            let ps = random_spheres(&mut rng, &conf, 2, radii, 0.05, 5.0);
            let (p, q) = (ps[0], ps[1]);
            let full = pair(&conf, 1.2, p.x, p.a, q.x, q.a);
            let ft = BlocksFT::from(&full);
            let f = pair_f(&conf, 1.2, p.x, p.a, q.x, q.a);
            assert!(
                rel_diff(&flat2(&f.uf), &flat2(&full.uf)) < 1e-13,
                "{name}: pair_f"
            );
            let g = pair_ft(&conf, 1.2, p.x, p.a, q.x, q.a);
            assert!(
                rel_diff(&flat2(&g.matrix()), &flat2(&ft.matrix())) < 1e-13,
                "{name}: pair_ft"
            );
            let s = self_mobility(&conf, 1.2, p.x, p.a);
            assert!(
                rel_diff(&flat2(&self_f(&conf, 1.2, p.x, p.a).uf), &flat2(&s.uf)) < 1e-13,
                "{name}: self_f"
            );
            let sft = BlocksFT::from(&s).matrix();
            assert!(
                rel_diff(
                    &flat2(&self_ft(&conf, 1.2, p.x, p.a).matrix()),
                    &flat2(&sft)
                ) < 1e-13,
                "{name}: self_ft"
            );
            let (va, vb) = (
                [0.3, -1.0, 0.7, 0.2, 0.5, -0.4],
                [1.1, 0.4, -0.6, -0.3, 0.8, 0.9],
            );
            let (fa, fb) = ([va[0], va[1], va[2]], [vb[0], vb[1], vb[2]]);
            let pf = product_f(&conf, 1.2, p.x, p.a, q.x, q.a, fa, fb);
            let want_f = kernels::BlocksF::from(&full).product(fa, fb);
            assert!(rel_diff(&pf.a, &want_f.a) < 1e-13, "{name}: product_f a");
            assert!(rel_diff(&pf.b, &want_f.b) < 1e-13, "{name}: product_f b");
            let want = ft.product(va, vb);
            let pft = product_ft(&conf, 1.2, p.x, p.a, q.x, q.a, va, vb);
            assert!(rel_diff(&pft.a, &want.a) < 1e-13, "{name}: product_ft a");
            assert!(rel_diff(&pft.b, &want.b) < 1e-13, "{name}: product_ft b");
        }
    }
}
