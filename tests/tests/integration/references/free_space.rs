//! The generated free-space kernels against the closed forms of unbounded Stokesian
//! dynamics (RPY with its (a_a^2 + a_b^2)/6 terms; rotlet, stresslet and strain
//! couplings of Durlofsky, Brady & Bossis 1987 / Kim & Karrila 1991), for equal radii
//! and radius ratios up to 10, at random separations 2.01 <= r/a <= 1e3.

use integration_tests::{closed_forms as cf, flat2, flat3, flat4, norm, rel_diff};
use kernels::{pair, pair_equal, Confinement};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Tolerance: 1e-12 relative in the Frobenius norm of each block. Both sides are
/// exact formulas evaluated in f64; the closed forms carry ~2e-15 (measured by the
/// helper script), the kernels' longer sums a few times more, so 1e-12 leaves a wide
/// margin while any wrong coefficient or sign is off by O(1e-3) or more. Per-entry
/// relative errors are meaningless for entries that vanish by symmetry.
const TOL: f64 = 1e-12;

#[test]
fn free_space_kernels_equal_literature_closed_forms() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let eta = 0.9;
    let mut worst: f64 = 0.0;
    for case in 0..400 {
        // radius ratio 1 for the first half, up to 10 for the rest
        let aa: f64 = rng.gen_range(0.5..2.0);
        let ratio: f64 = if case < 200 {
            1.0
        } else {
            rng.gen_range(1.0..10.0)
        };
        let ab = if rng.gen_bool(0.5) {
            aa * ratio
        } else {
            aa / ratio
        };
        let amax = aa.max(ab);
        // |r| / a_max log-uniform in [2.01, 1e3]
        let dist = amax * (2.01f64.ln() + rng.gen::<f64>() * (1e3f64.ln() - 2.01f64.ln())).exp();
        let mut dir = [0.0; 3];
        for d in &mut dir {
            *d = rng.gen_range(-1.0..1.0);
        }
        let n = norm(&dir);
        let xb = [0.3, -1.2, 0.7];
        let r: [f64; 3] = std::array::from_fn(|k| dist * dir[k] / n);
        let xa: [f64; 3] = std::array::from_fn(|k| xb[k] + r[k]);
        let g = if ratio == 1.0 {
            pair_equal(&Confinement::Free, eta, xa, xb, aa)
        } else {
            pair(&Confinement::Free, eta, xa, aa, xb, ab)
        };
        let ab = if ratio == 1.0 { aa } else { ab };
        let c = g.cartesian();
        let checks: [(&str, Vec<f64>, Vec<f64>); 9] = [
            ("UF", flat2(&c.uf), flat2(&cf::uf(r, aa, ab, eta))),
            ("UL", flat2(&c.ul), flat2(&cf::ul(r, aa, ab, eta))),
            ("US", flat3(&c.us), flat3(&cf::us(r, aa, ab, eta))),
            ("OF", flat2(&c.of), flat2(&cf::of(r, aa, ab, eta))),
            ("OL", flat2(&c.ol), flat2(&cf::ol(r, aa, ab, eta))),
            ("OS", flat3(&c.os), flat3(&cf::os(r, aa, ab, eta))),
            ("EF", flat3(&c.ef), flat3(&cf::ef(r, aa, ab, eta))),
            ("EL", flat3(&c.el), flat3(&cf::el(r, aa, ab, eta))),
            ("ES", flat4(&c.es), flat4(&cf::es(r, aa, ab, eta))),
        ];
        for (name, got, want) in checks {
            let e = rel_diff(&got, &want);
            worst = worst.max(e);
            assert!(
                e <= TOL,
                "{name}: relative error {e:e} at |r| = {dist}, aa = {aa}, ab = {ab}"
            );
        }
    }
    println!("largest relative block error vs closed forms: {worst:e}");
}
