//! Reciprocity and positive definiteness of the grand mobility, for every confinement.

use integration_tests::{above, all_confinements, blocks, norm, random_spheres, with_params};
use kernels::{pair, self_mobility};
use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use stokesian::{Moments, System};

/// M^{ab} = (M^{ba})^T for every block: the pair kernel evaluated both ways round.
/// Tolerance 1e-12 of each block's norm: the two evaluations are different
/// floating-point computations of the same exact quantity.
#[test]
fn reciprocity_every_block_every_confinement() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for (name, conf) in all_confinements() {
        for _ in 0..20 {
            let ps = random_spheres(&mut rng, &conf, 2, (0.3, 1.5), 0.05, 6.0);
            let (p, q) = (ps[0], ps[1]);
            let ab = pair(&conf, 1.1, p.x, p.a, q.x, q.a);
            let ba = pair(&conf, 1.1, q.x, q.a, p.x, p.a);
            let bat = ba.transposed();
            for ((bn, x), (_, y)) in blocks(&ab).into_iter().zip(blocks(&bat)) {
                let d: Vec<f64> = x.iter().zip(&y).map(|(u, v)| u - v).collect();
                assert!(
                    norm(&d) <= 1e-12 * norm(&x),
                    "{name} {bn}: |M^ab - (M^ba)^T| = {:e}, |M^ab| = {:e}",
                    norm(&d),
                    norm(&x)
                );
            }
        }
    }
}

/// The wall's pair kernels exchange the particles where b is the higher one
/// (`kernel_gen::kernel::Swap`), which relies on reciprocity, so the test above holds
/// for them by construction. The direct sum they evaluate must be reciprocal by
/// itself: the traced FTS pair's direct branch (no exchange, no far field), evaluated
/// both ways round by the interpreter, equals its transpose to 1e-12 of each block
/// (different floating-point computations of the same exact quantity), for unequal
/// radii and heights from touching the wall to 20 a.
#[test]
fn the_wall_direct_sum_is_reciprocal_without_the_exchange() {
    use integration_tests::stiff::Kind;
    use kernel_gen::physics::green::wall::Wall;
    use nalgebra::SMatrix;
    let traced = kernel_gen::kernel::trace(&Wall, &Kind::PairFts.spec());
    let ids = traced.output_ids();
    // the 11x11 grand block from the flattened outputs (BLOCKS order, row-major)
    let grand = |v: &[f64]| {
        let (at, dim) = ([0, 3, 6], [3, 3, 5]);
        let mut m = SMatrix::<f64, 11, 11>::zeros();
        let mut k = 0;
        for r in 0..3 {
            for c in 0..3 {
                for i in 0..dim[r] {
                    for j in 0..dim[c] {
                        m[(at[r] + i, at[c] + j)] = v[k];
                        k += 1;
                    }
                }
            }
        }
        assert_eq!(k, v.len());
        m
    };
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for _ in 0..50 {
        let (aa, ab) = (rng.gen_range(0.3..1.5), rng.gen_range(0.3..1.5));
        let xa = [
            rng.gen_range(-3.0..3.0),
            rng.gen_range(-3.0..3.0),
            aa * (1.0 + 10f64.powf(rng.gen_range(-3.0..1.3))),
        ];
        let xb = [
            rng.gen_range(-3.0..3.0),
            rng.gen_range(-3.0..3.0),
            ab * (1.0 + 10f64.powf(rng.gen_range(-3.0..1.3))),
        ];
        if (0..3).map(|k| (xa[k] - xb[k]).powi(2)).sum::<f64>().sqrt() < 1.01 * (aa + ab) {
            continue;
        }
        let inputs = |p: [f64; 3], q: [f64; 3], a: f64, b: f64| {
            let mut v = p.to_vec();
            v.extend(q);
            v.extend([a, b, 1.1, 0.0]);
            v
        };
        let ab_m = grand(&traced.graph.eval(&inputs(xa, xb, aa, ab), &ids));
        let ba_m = grand(&traced.graph.eval(&inputs(xb, xa, ab, aa), &ids));
        let (at, dim) = ([0, 3, 6], [3, 3, 5]);
        for r in 0..3 {
            for c in 0..3 {
                let x = ab_m.view((at[r], at[c]), (dim[r], dim[c]));
                let y = ba_m.view((at[c], at[r]), (dim[c], dim[r])).transpose();
                assert!(
                    (x - &y).norm() <= 1e-12 * x.norm(),
                    "block ({r}, {c}) at {xa:?} {xb:?}: {:e} of {:e}",
                    (x - &y).norm(),
                    x.norm()
                );
            }
        }
    }
}

/// The self blocks: M_UL = M_OmegaF^T, and the 11x11 self matrix is symmetric.
#[test]
fn self_blocks_are_symmetric() {
    for (name, conf) in all_confinements() {
        for z in [1.0001, 1.3, 2.0, 5.0] {
            let m = self_mobility(&conf, 0.7, above(&conf, [0.2, -0.1], z), 1.0).matrix();
            let asym = (m - m.transpose()).norm() / m.norm();
            assert!(asym < 1e-14, "{name} at h = {z}: asymmetry {asym:e}");
        }
    }
}

fn smallest_eigenvalue(m: &DMatrix<f64>) -> f64 {
    m.clone().symmetric_eigenvalues().min()
}

/// The assembled FTS grand mobility of 2 to 20 random non-overlapping spheres (heights
/// down to 1.0001 a for the bounded cases) is symmetric and positive definite:
/// Cholesky succeeds. Symmetry to 1e-13 relative (each M^{ba} is the exact transpose
/// of M^{ab}; only the self blocks are computed independently).
///
/// A confinement whose boundary conditions hold only approximately (the slit: the
/// superposition of two single-wall images, Sec. IV, which double-counts reflections)
/// is tested with every length parameter 60 (a slit 60 a wide);
/// [`narrow_slit_superposition_is_indefinite`] shows where it breaks.
#[test]
fn grand_mobility_is_symmetric_positive_definite() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let confs: Vec<(String, kernels::Confinement)> = all_confinements()
        .into_iter()
        .map(|(name, conf)| {
            if conf.boundaries().iter().all(|b| b.exact) {
                (name.to_string(), conf)
            } else {
                let wide = with_params(name, |p| match p.dimension {
                    kernels::Dimension::Length => 60.0,
                    _ => p.example,
                });
                (format!("{name} (lengths 60)"), wide)
            }
        })
        .collect();
    for (name, conf) in confs {
        let mut lowest = f64::INFINITY;
        for trial in 0..12 {
            let n = rng.gen_range(2..=20);
            // a tight gap (1e-4 a) on every other trial puts spheres at h = 1.0001 a
            let gap = if trial % 2 == 0 { 1e-4 } else { 0.2 };
            let ps = random_spheres(&mut rng, &conf, n, (0.5, 1.5), gap, 8.0);
            let m = System::new(conf, 1.0, ps, false)
                .expect("valid input")
                .mobility(Moments::FTS);
            let asym = (&m - m.transpose()).norm() / m.norm();
            assert!(asym < 1e-13, "{name}: asymmetry {asym:e}");
            let sym = (&m + m.transpose()) * 0.5;
            assert!(
                sym.clone().cholesky().is_some(),
                "{name}: Cholesky fails for {n} spheres"
            );
            lowest = lowest.min(smallest_eigenvalue(&sym));
        }
        println!(
            "{name}: smallest eigenvalue of the FTS grand mobility over the trials: {lowest:e}"
        );
        assert!(lowest > 0.0);
    }
}

/// The two-wall superposition is not a Green's function of the slit: each image
/// violates no-slip on the other wall, and near one wall of a narrow slit the
/// single-sphere FTS self mobility acquires a negative eigenvalue. Measured:
/// slit 3 a wide, h = 1.5 a: smallest eigenvalue -1.26e-2 (units 1/(eta a^3)); slit
/// 6 a wide, h = 1.0001 a: -1.86e-3; slit 12 a wide: positive (3.1e-3).
#[test]
fn narrow_slit_superposition_is_indefinite() {
    let eig = |gap: f64, h: f64| {
        let c = kernels::Confinement::Slit { height: 0.0, gap };
        self_mobility(&c, 1.0, [0.0, 0.0, h], 1.0)
            .matrix()
            .symmetric_eigenvalues()
            .min()
    };
    assert!(eig(3.0, 1.5) < -1e-2);
    assert!(eig(6.0, 1.0001) < -1e-3);
    assert!(eig(12.0, 1.0001) > 3e-3);
}

/// With `allow_overlap` the kernels evaluate the far-field forms (Eqs. 8-17) where the
/// spheres overlap; nothing then guarantees positive definiteness. Measured (unit
/// spheres, eta = 1, free space; the wall at h = 5 a gives the same to 1e-3): the
/// two-sphere matrix stays positive definite at r = 1.8 a in all truncations, FTS is
/// indefinite at r = 1.5 a (smallest eigenvalue -1.2e-2), F and FT at r = 1.0 a
/// (-1.3e-2, -4.0e-2). A sphere cutting a wall: positive definite at h = 0.9 a; FT and
/// FTS indefinite at h = 0.7 a, F at h = 0.5 a (-6.6e-2).
#[test]
fn overlapping_spheres_lose_positive_definiteness() {
    use stokesian::{Particle, System};
    let min_eig = |conf: kernels::Confinement, ps: Vec<Particle>, m: Moments| {
        System::new(conf, 1.0, ps, true)
            .unwrap()
            .mobility(m)
            .symmetric_eigenvalues()
            .min()
    };
    let two = |r: f64| {
        vec![
            Particle {
                x: [0.0, 0.0, 5.0],
                a: 1.0,
            },
            Particle {
                x: [r, 0.0, 5.0],
                a: 1.0,
            },
        ]
    };
    let free = kernels::Confinement::Free;
    for m in [Moments::F, Moments::FT, Moments::FTS] {
        assert!(min_eig(free, two(1.8), m) > 0.0, "{m:?} at r = 1.8");
        assert!(min_eig(free, two(1.0), m) < 0.0, "{m:?} at r = 1.0");
    }
    assert!(min_eig(free, two(1.5), Moments::FTS) < -1e-2);
    assert!(min_eig(free, two(1.5), Moments::F) > 0.0);
    let wall = kernels::Confinement::Wall { height: 0.0 };
    let one = |h: f64| {
        vec![Particle {
            x: [0.0, 0.0, h],
            a: 1.0,
        }]
    };
    assert!(min_eig(wall, one(0.9), Moments::FTS) > 0.0);
    assert!(min_eig(wall, one(0.7), Moments::FT) < 0.0);
    assert!(min_eig(wall, one(0.7), Moments::F) > 0.0);
    assert!(min_eig(wall, one(0.5), Moments::F) < 0.0);
}
