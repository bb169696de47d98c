//! The fast product (`stokesian::fmm`) against the direct one (`System::apply`): the
//! relative 2-norm error within the tolerance asked for, for every confinement (all have
//! image structure), F and FT, in 3-D boxes and in monolayers touching a wall; the same
//! bits on any number of threads; typed errors for what it does not cover.

use integration_tests::{all_confinements, falling, norm, random_spheres, rel_diff};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use stokesian::{Confinement, FastProduct, FmmError, Moments, Particle, System};

/// Moments of order one in random directions.
fn moments(rng: &mut ChaCha8Rng, n: usize, m: Moments) -> Vec<f64> {
    (0..n * m.per_particle())
        .map(|_| rng.gen_range(-1.0..1.0))
        .collect()
}

/// The fast product's error at each tolerance, printed, and asserted below it.
fn check(label: &str, system: &System, m: Moments, tolerances: &[f64]) {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let x = moments(&mut rng, system.len(), m);
    let direct = system.apply(m, &x);
    assert!(norm(&direct) > 0.0);
    for &eps in tolerances {
        // the parameters for `eps`, and the same with leaves of at most 16 particles,
        // whose many more cell pairs at the acceptance limit test the expansions at
        // these sizes (most pairs of a few thousand spheres are near with the default)
        let settings = FastProduct::new(eps).unwrap();
        for leaf in [settings.leaf, 16] {
            let fast = system
                .apply_fast(m, &x, &FastProduct { leaf, ..settings })
                .unwrap();
            let e = rel_diff(&fast, &direct);
            println!("{label:<28} {m:?} eps {eps:.0e} leaf {leaf:>3}: error {e:.1e}");
            assert!(e <= eps, "{label} {m:?} leaf {leaf}: {e:e} > {eps:e}");
        }
    }
}

/// A monolayer of `n` spheres on a jittered square lattice of area fraction 0.3 above the
/// plane `x3 = 0`, radii in `radii`, gaps to the plane from `gap.0` to `gap.1` radii.
fn monolayer(n: usize, radii: (f64, f64), gap: (f64, f64), seed: u64) -> Vec<Particle> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let amax = radii.1;
    let side = amax * (std::f64::consts::PI / 0.3).sqrt();
    let k = (n as f64).sqrt().ceil() as usize;
    let jitter = (side - 2.05 * amax) / 2.0;
    (0..n)
        .map(|i| {
            let a = rng.gen_range(radii.0..=radii.1);
            let (u, v) = ((i % k) as f64, (i / k) as f64);
            Particle {
                x: [
                    u * side + rng.gen_range(-jitter..jitter),
                    v * side + rng.gen_range(-jitter..jitter),
                    a * (1.0 + rng.gen_range(gap.0..gap.1)),
                ],
                a,
            }
        })
        .collect()
}

/// Every confinement, 600 spheres of radii 0.5 to 1 in a box of 40 (3-D), F and FT, at
/// 1e-3 and 1e-6; the wall also at 1e-9.
#[test]
fn every_confinement_keeps_the_tolerance_in_a_box() {
    for (name, conf) in all_confinements() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let ps = random_spheres(&mut rng, &conf, 600, (0.5, 1.0), 0.05, 40.0);
        let system = System::new(conf, 1.3, ps, false).unwrap();
        let tolerances: &[f64] = if name == "wall" {
            &[1e-3, 1e-6, 1e-9]
        } else {
            &[1e-3, 1e-6]
        };
        for m in [Moments::F, Moments::FT] {
            check(name, &system, m, tolerances);
        }
    }
}

/// Monolayers above a wall, a free surface and an interface: 3000 equal spheres at
/// heights 1.5 to 5 radii, and 2000 spheres of radii 0.5 to 1 within 1e-3 to 0.1 radii
/// of the plane (near contact, where the image's terms are largest).
#[test]
fn monolayers_near_planes_keep_the_tolerance() {
    let planes = [
        ("wall", Confinement::Wall { height: 0.0 }),
        ("free_surface", Confinement::FreeSurface { height: 0.0 }),
        (
            "interface",
            Confinement::Interface {
                height: 0.0,
                lambda: 0.5,
            },
        ),
    ];
    for (name, conf) in planes {
        let layers = [
            ("monolayer", monolayer(3000, (1.0, 1.0), (0.5, 4.0), 5)),
            ("near contact", monolayer(2000, (0.5, 1.0), (1e-3, 0.1), 6)),
        ];
        for (label, ps) in layers {
            let system = System::new(conf, 1.0, ps, false).unwrap();
            for m in [Moments::F, Moments::FT] {
                check(&format!("{name} {label}"), &system, m, &[1e-3, 1e-6]);
            }
        }
    }
}

/// With the fast product the drift is each sphere's own term: the pair terms, whose far
/// field cancels for every confinement (the generated divergence tables are empty), are
/// round-off in the generated pair kernels too. 600 spheres in a box for every
/// confinement, and 2000 near contact with a wall, F and FT rows.
#[test]
fn the_drift_with_the_fast_product_is_each_spheres_own_term() {
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let mut cases: Vec<(String, System)> = all_confinements()
        .into_iter()
        .map(|(name, conf)| {
            let ps = random_spheres(&mut rng, &conf, 600, (0.5, 1.0), 0.05, 40.0);
            (name.to_string(), System::new(conf, 1.3, ps, false).unwrap())
        })
        .collect();
    let wall = Confinement::Wall { height: 0.0 };
    let layer = monolayer(2000, (0.5, 1.0), (1e-3, 0.1), 6);
    cases.push((
        "wall near contact".into(),
        System::new(wall, 1.0, layer, false).unwrap(),
    ));
    for (label, system) in cases {
        assert!(system
            .confinement()
            .divergence_sources()
            .unwrap()
            .is_empty());
        let fast = system.clone().with_fmm(1e-6).unwrap();
        let (direct, own) = (
            system.divergence_at(Moments::FT),
            fast.divergence_at(Moments::FT),
        );
        // free space has no drift at all (both exactly zero); elsewhere each pair term
        // is ~1e-16 of a self term, and the sum of a few hundred of them at most ~1e-13
        if norm(&direct) == 0.0 {
            assert!(own.iter().all(|&o| o == 0.0), "{label}");
            continue;
        }
        let e = rel_diff(&own, &direct);
        println!("{label:<28} drift with the fast product: {e:.1e} of the direct sum's");
        assert!(e <= 1e-13, "{label}: {e:e}");
    }
}

/// The same bits on 1, 2 and 3 threads: the tree and every sum's order are fixed by the
/// positions alone.
#[test]
fn the_fast_product_does_not_depend_on_the_threads() {
    let ps = monolayer(1500, (0.5, 1.0), (0.1, 3.0), 8);
    let system = System::new(Confinement::Wall { height: 0.0 }, 1.0, ps, false).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let x = moments(&mut rng, system.len(), Moments::FT);
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| system.apply_fmm(Moments::FT, &x, 1e-6).unwrap())
    };
    let one = run(1);
    for threads in [2, 3] {
        let other = run(threads);
        assert!(
            one.iter()
                .zip(&other)
                .all(|(a, b)| a.to_bits() == b.to_bits()),
            "{threads} threads"
        );
    }
}

#[test]
fn what_the_fast_product_does_not_cover_is_an_error() {
    let ps = vec![Particle {
        x: [0.0, 0.0, 2.0],
        a: 1.0,
    }];
    let system = System::new(Confinement::Wall { height: 0.0 }, 1.0, ps, false).unwrap();
    for eps in [1e-2, 1e-11, f64::NAN, 0.0] {
        assert!(matches!(
            system.apply_fmm(Moments::F, &[0.0; 3], eps),
            Err(FmmError::Tolerance(_))
        ));
    }
    assert_eq!(
        system.apply_fmm(Moments::FTS, &[0.0; 11], 1e-6),
        Err(FmmError::Moments(Moments::FTS))
    );
    let mut fast = stokesian::FastProduct::new(1e-6).unwrap();
    fast.order = 40;
    assert!(matches!(
        system.apply_fast(Moments::F, &[0.0; 3], &fast),
        Err(FmmError::Order { order: 40, .. })
    ));
    // parameters given by hand: a leaf of no particle, theta outside (0, 1), a tolerance
    // outside [1e-10, 1e-3]
    let settings = stokesian::FastProduct::new(1e-6).unwrap();
    for bad in [
        stokesian::FastProduct {
            leaf: 0,
            ..settings
        },
        stokesian::FastProduct {
            theta: 1.0,
            ..settings
        },
        stokesian::FastProduct {
            theta: f64::NAN,
            ..settings
        },
        stokesian::FastProduct {
            eps: 0.1,
            ..settings
        },
    ] {
        assert!(matches!(
            system.apply_fast(Moments::F, &[0.0; 3], &bad),
            Err(FmmError::Settings(_) | FmmError::Tolerance(_))
        ));
        assert!(system.clone().with_fast(bad).is_err());
    }
    assert_eq!(
        system.clone().with_fast(settings).unwrap().fmm(),
        Some(settings)
    );
}

/// The fast product is symmetric to its tolerance: with `|M_fast v - M v| <= eps |M v|`,
/// `|x.M_fast y - y.M_fast x| <= eps (|x| |M y| + |y| |M x|)` (M symmetric), measured and
/// printed. Lanczos noise and `M F` of a Brownian step take it (`with_fmm`), and the step
/// equals the direct one's to the tolerances (the same random numbers): Lanczos to
/// `tol = 1e-6` of `|M^(1/2) w|` either way, the products to 1e-8; 1e-5 of the step's
/// norm bounds both with room (the drift is the direct sum in both).
#[test]
fn lanczos_noise_takes_the_fast_product() {
    use stokesian::Noise;
    let ps = monolayer(300, (1.0, 1.0), (0.5, 3.0), 9);
    let system = System::new(Confinement::Wall { height: 0.0 }, 1.0, ps, false).unwrap();
    let eps = 1e-8;
    let fast = system.clone().with_fmm(eps).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let (x, y) = (
        moments(&mut rng, system.len(), Moments::F),
        moments(&mut rng, system.len(), Moments::F),
    );
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(a, b)| a * b).sum::<f64>();
    let (fx, fy) = (fast.apply(Moments::F, &x), fast.apply(Moments::F, &y));
    let (dx, dy) = (system.apply(Moments::F, &x), system.apply(Moments::F, &y));
    let asymmetry = (dot(&x, &fy) - dot(&y, &fx)).abs();
    let bound = eps * (norm(&x) * norm(&dy) + norm(&y) * norm(&dx));
    println!(
        "asymmetry of the fast product at {eps:e}: {:.1e} of |x| |M y|",
        asymmetry / (norm(&x) * norm(&dy))
    );
    assert!(asymmetry <= bound, "{asymmetry:e} > {bound:e}");
    let bd = falling(Noise::Lanczos { tol: 1e-6 });
    let w: Vec<f64> = (0..3 * system.len())
        .map(|_| rng.gen_range(-1.7..1.7))
        .collect();
    let direct = system.brownian_increment(&bd, &w, 0).unwrap();
    let step = fast.brownian_increment(&bd, &w, 0).unwrap();
    let e = rel_diff(&step, &direct);
    println!("Brownian step with the fast product: {e:.1e} of the direct one's");
    assert!(e <= 1e-5, "{e:e}");
    // the setting moves with the spheres
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let next = fast.brownian_step(&bd, &mut rng, 0).unwrap().system;
    assert_eq!(next.fmm(), fast.fmm());
}
