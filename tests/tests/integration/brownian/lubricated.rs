//! Brownian Stokesian dynamics (lubricated Brownian dynamics, `Brownian::lubrication`):
//! the random-finite-difference drift against the generated divergence kernels, the
//! short-time diffusion against the exact sphere-wall functions, and the equilibrium
//! distribution of a sedimented sphere against Boltzmann's.

use integration_tests::statistics::{boltzmann_height_cdf, ks, sample};
use integration_tests::{norm, NO_FORCES, WALL};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use std::f64::consts::PI;
use stokesian::{
    wall_functions, Brownian, BrownianError, ExternalForces, LubricatedDynamics, Lubrication,
    Moments, Noise, Particle, ResistanceError, Scheme, System,
};

/// No lubrication correction anywhere: the resistance is the inverse of the far-field
/// FT mobility, so `div R^-1` is the divergence the generated kernels compute.
const NO_CORRECTION: Lubrication = Lubrication::none();

fn three_spheres() -> System {
    let ps = vec![
        Particle {
            x: [0.0, 0.0, 1.6],
            a: 1.0,
        },
        Particle {
            x: [2.3, 0.9, 1.3],
            a: 0.8,
        },
        Particle {
            x: [-0.7, 2.6, 2.4],
            a: 1.2,
        },
    ];
    System::new(WALL, 0.7, ps, false).unwrap()
}

/// The random finite difference with the `3N` unit vectors in turn is the central
/// finite difference of `div R^-1`: it converges to the generated divergence kernels
/// as `delta^2` (errors printed; asserted: a factor over 50 from delta = 1e-2 to 1e-3,
/// where `delta^2` gives 100, and 1e-8 of the norm at delta = 1e-4, where the
/// truncation error is about 4e-10 and the round-off of two inversions of a resistance
/// of condition ~1e2 about 1e-10). The steps stay below a tenth of the smallest gap
/// (0.3 here), where `rfd_step` is used as given. With random `W~` the mean of 4000
/// estimates agrees with the kernels within 5 standard errors in every component.
#[test]
fn random_finite_difference_converges_to_the_generated_divergence() {
    let s = three_spheres();
    let n = s.len();
    let exact = s.divergence_at(Moments::FT);
    let scale = norm(&exact);
    let central = |delta: f64| -> Vec<f64> {
        let lub = LubricatedDynamics {
            lubrication: NO_CORRECTION,
            rfd_step: delta,
        };
        let mut sum = vec![0.0; 6 * n];
        for k in 0..3 * n {
            let e: Vec<f64> = (0..3 * n).map(|i| if i == k { 1.0 } else { 0.0 }).collect();
            let d = s.lubricated_divergence(&lub, &e, 0).unwrap();
            sum.iter_mut().zip(&d).for_each(|(s, d)| *s += d);
        }
        sum
    };
    let err = |delta: f64| {
        let d: Vec<f64> = central(delta)
            .iter()
            .zip(&exact)
            .map(|(a, b)| a - b)
            .collect();
        norm(&d) / scale
    };
    let (e2, e3, e4) = (err(1e-2), err(1e-3), err(1e-4));
    println!(
        "|div R^-1 (central) - kernels| / |kernels|: {e2:e} (1e-2), {e3:e} (1e-3), {e4:e} (1e-4)"
    );
    assert!(e3 < e2 / 50.0, "not second order: {e2:e} -> {e3:e}");
    assert!(e4 < 1e-8, "{e4:e}");

    let lub = LubricatedDynamics {
        lubrication: NO_CORRECTION,
        rfd_step: 1e-3,
    };
    let mut rng = ChaCha8Rng::seed_from_u64(41);
    let samples = 4000;
    let (mut sum, mut sq) = (vec![0.0; 6 * n], vec![0.0; 6 * n]);
    for _ in 0..samples {
        let w: Vec<f64> = (0..3 * n).map(|_| rng.sample(StandardNormal)).collect();
        let d = s.lubricated_divergence(&lub, &w, 0).unwrap();
        for i in 0..6 * n {
            sum[i] += d[i];
            sq[i] += d[i] * d[i];
        }
    }
    let m = samples as f64;
    for i in 0..6 * n {
        let mean = sum[i] / m;
        let se = ((sq[i] / m - mean * mean) / m).sqrt();
        assert!(
            (mean - exact[i]).abs() <= 5.0 * se,
            "component {i}: RFD mean {mean:e} +- {se:e}, kernels {:e}",
            exact[i]
        );
    }
}

/// Brownian settings with lubrication (the defaults of `stokesian brownian
/// --lubrication`), kT = 1.
fn lubricated(moments: Moments, dt: f64, drift: bool, forces: ExternalForces) -> Brownian {
    Brownian {
        noise: Noise::Cholesky,
        hydrodynamics: true,
        moments,
        scheme: Scheme::EulerMaruyama,
        kt: 1.0,
        dt,
        drift,
        forces,
        lubrication: Some(LubricatedDynamics {
            lubrication: Lubrication::default(),
            rfd_step: 1e-3,
        }),
    }
}

/// One unit sphere at gap 0.1 a from the wall: the variances of one-step displacements
/// are 2 kT dt times the exact sphere-wall mobility of a torque-free sphere, normal
/// `1 / (6 pi eta a X^A)` and parallel `1 / (6 pi eta a (Y^A - 3/4 (F^r)^2 / Y^C))`
/// (the translation-rotation coupling eliminated), from the exact bispherical series.
/// 1e5 samples: the relative standard error of a variance is sqrt(2/n) = 0.45%;
/// tolerance 2.5% (over 5 standard errors). Without the drift (it adds O(dt^2) to a
/// variance). The far-field self mobility differs from the exact one by far more.
#[test]
fn short_time_diffusion_is_kt_times_the_exact_wall_mobility() {
    let h = 1.1;
    let s = System::new(
        WALL,
        1.0,
        vec![Particle {
            x: [0.0, 0.0, h],
            a: 1.0,
        }],
        false,
    )
    .unwrap();
    let bd = lubricated(Moments::F, 1e-3, false, NO_FORCES);
    let f = wall_functions(h - 1.0);
    let mu_perp = 1.0 / (6.0 * PI * f.xa);
    let mu_par = 1.0 / (6.0 * PI * (f.ya - 0.75 * f.fr * f.fr / f.yc));
    let far = s.mobility(Moments::F);
    println!(
        "exact mu_par {mu_par:.6}, mu_perp {mu_perp:.6}; far field {:.6}, {:.6}",
        far[(0, 0)],
        far[(2, 2)]
    );
    assert!((far[(2, 2)] / mu_perp - 1.0).abs() > 0.1);
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    let samples = 100_000;
    let (mut sx, mut sz, mut mz) = (0.0, 0.0, 0.0);
    for k in 0..samples {
        let w: Vec<f64> = (0..bd.random_numbers(1))
            .map(|_| rng.sample(StandardNormal))
            .collect();
        let dx = s.brownian_increment(&bd, &w, k).unwrap();
        sx += dx[0] * dx[0];
        sz += dx[2] * dx[2];
        mz += dx[2];
    }
    let (m, two) = (samples as f64, 2.0 * bd.kt * bd.dt);
    let var_x = sx / m;
    let var_z = sz / m - (mz / m).powi(2);
    println!(
        "D_par/kT {:.6} vs {mu_par:.6}; D_perp/kT {:.6} vs {mu_perp:.6}",
        var_x / two,
        var_z / two
    );
    assert!((var_x / two / mu_par - 1.0).abs() < 0.025);
    assert!((var_z / two / mu_perp - 1.0).abs() < 0.025);
}

/// A sedimented unit sphere held close to the wall: buoyant weight 10 kT/a, repulsion
/// 50 kT/a with screening length 0.1 a (potential minimum at h = 1.16 a). It stays in
/// the lubrication range (`P(h > 2 a) ~ 2e-4` under Boltzmann, so the switch of the
/// lubrication correction at gap = a is practically never crossed), where the normal
/// mobility falls to zero at contact, so that without the drift the scheme samples
/// `exp(-U/kT) / mu_perp(h)`, far from Boltzmann.
const SEDIMENTED: ExternalForces = ExternalForces {
    weight: 10.0,
    strength: 50.0,
    debye: 0.1,
    trap: 0.0,
    torque: [0.0; 3],
};

/// Heights of the sedimented sphere with lubrication, sampled every `every` steps
/// after `burn`, and the number of redrawn steps.
fn lubricated_heights(drift: bool, steps: usize, every: usize, burn: usize) -> (Vec<f64>, usize) {
    let bd = lubricated(Moments::F, 0.01, drift, SEDIMENTED);
    let start = System::new(
        WALL,
        1.0,
        vec![Particle {
            x: [0.0, 0.0, 1.2],
            a: 1.0,
        }],
        false,
    )
    .unwrap();
    sample(&bd, start, (steps, every, burn), 43, |s| {
        s.particles()[0].x[2]
    })
}

/// With the random-finite-difference drift the heights follow Boltzmann's distribution
/// (Kolmogorov-Smirnov at the 1% level, critical value 1.628/sqrt(n)); without it they
/// do not. Samples every 400 steps (4 time units, a few correlation times of the height:
/// `sigma^2 / D_perp ~ 0.01 / 0.008`).
#[test]
fn lubricated_heights_follow_boltzmann_only_with_the_drift() {
    let steps = 240_000;
    let (with, rejected) = lubricated_heights(true, steps, 400, 2000);
    let (without, _) = lubricated_heights(false, steps, 400, 2000);
    let cdf = boltzmann_height_cdf(&SEDIMENTED, 1.0);
    let critical = 1.628 / (with.len() as f64).sqrt();
    let (d_with, d_without) = (ks(with.clone(), &cdf), ks(without, &cdf));
    println!(
        "n = {}, KS with drift {d_with:.4}, without {d_without:.4} (critical {critical:.4}); {rejected} steps redrawn",
        with.len()
    );
    assert!(d_with < critical);
    assert!(d_without > critical);
    assert!(rejected < steps / 1000, "{rejected} steps redrawn");
}

/// Lubrication settings out of range are typed errors before anything is computed: a
/// negative or NaN pair tolerance and a NaN wall cutoff, from `System::resistance` and
/// from `Brownian::check`; 0 and infinity are valid (every pair, no pair).
#[test]
fn lubrication_settings_out_of_range_are_typed_errors() {
    let s = three_spheres();
    let bad = [
        Lubrication::default().with_pair_tolerance(-1e-3),
        Lubrication::default().with_pair_tolerance(f64::NAN),
        Lubrication {
            wall_cutoff: f64::NAN,
            ..Lubrication::default()
        },
    ];
    for lub in bad {
        for m in [Moments::FT, Moments::FTS] {
            match s.resistance(m, &lub) {
                Err(ResistanceError::Setting { .. }) => {}
                other => panic!("{lub:?} {m:?}: {other:?}"),
            }
        }
        let mut bd = lubricated(Moments::FT, 1e-3, true, NO_FORCES);
        bd.lubrication.as_mut().unwrap().lubrication = lub;
        match bd.check() {
            Err(BrownianError::BadSetting { name, .. }) => {
                assert!(name == "pair tolerance" || name == "wall cutoff", "{name}")
            }
            other => panic!("{lub:?}: {other:?}"),
        }
    }
    for tol in [0.0, f64::INFINITY] {
        let lub = Lubrication::default().with_pair_tolerance(tol);
        assert!(s.resistance(Moments::FT, &lub).is_ok());
        let mut bd = lubricated(Moments::FT, 1e-3, true, NO_FORCES);
        bd.lubrication.as_mut().unwrap().lubrication = lub;
        assert!(bd.check().is_ok());
    }
    // the message names the setting and its range
    let e = s
        .resistance(
            Moments::FT,
            &Lubrication::default().with_pair_tolerance(-1.0),
        )
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("pair tolerance is -1: it must be a number >= 0"),
        "{e}"
    );
}
