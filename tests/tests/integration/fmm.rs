//! The fast product (`stokesian::fmm`) against the direct one: the relative 2-norm error
//! within the tolerance asked for, for every confinement with an expansion, F and FT.

use integration_tests::{all_confinements, norm, random_spheres, rel_diff};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use stokesian::{Confinement, FmmError, Moments, Particle, System};

/// Forces and torques of unit size in random directions.
fn moments(rng: &mut ChaCha8Rng, n: usize, m: Moments) -> Vec<f64> {
    (0..n * m.per_particle())
        .map(|_| rng.gen_range(-1.0..1.0))
        .collect()
}

/// The relative errors of the fast product at each tolerance.
fn errors(system: &System, m: Moments, tolerances: &[f64], seed: u64) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let x = moments(&mut rng, system.len(), m);
    let direct = system.apply(m, &x);
    assert!(norm(&direct) > 0.0);
    tolerances
        .iter()
        .map(|&eps| rel_diff(&system.apply_fmm(m, &x, eps).unwrap(), &direct))
        .collect()
}

#[test]
fn every_confinement_keeps_the_tolerance() {
    let tolerances = [1e-3, 1e-6];
    for (name, conf) in all_confinements() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let ps: Vec<Particle> = random_spheres(&mut rng, &conf, 600, (0.5, 1.0), 0.05, 40.0);
        let system = System::new(conf, 1.3, ps, false).unwrap();
        for m in [Moments::F, Moments::FT] {
            let e = errors(&system, m, &tolerances, 11);
            println!(
                "{name:<13} {m:?}: {:?}",
                e.iter().map(|v| format!("{v:.1e}")).collect::<Vec<_>>()
            );
            for (eps, e) in tolerances.iter().zip(&e) {
                assert!(e <= eps, "{name} {m:?}: {e:e} > {eps:e}");
            }
        }
    }
}

#[test]
fn bad_tolerances_and_truncations_are_errors() {
    let ps = vec![Particle {
        x: [0.0, 0.0, 2.0],
        a: 1.0,
    }];
    let system = System::new(Confinement::Wall { height: 0.0 }, 1.0, ps, false).unwrap();
    assert_eq!(
        system.apply_fmm(Moments::F, &[0.0; 3], 1e-2),
        Err(FmmError::Tolerance(1e-2))
    );
    assert_eq!(
        system.apply_fmm(Moments::FTS, &[0.0; 11], 1e-6),
        Err(FmmError::Moments(Moments::FTS))
    );
}
