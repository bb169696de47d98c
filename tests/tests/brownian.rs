//! Brownian dynamics near a wall, validated statistically (fixed seeds; confidence
//! levels stated per test).

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use stokesian::{Brownian, Confinement, ExternalForces, Moments, Noise, Particle, System};

const WALL: Confinement = Confinement::Wall { height: 0.0 };

/// A sedimented colloid: unit sphere, kT = 1, eta = 1, buoyant weight 1 kT/a (the
/// gravitational length is a), repulsion 50 kT/a with screening length 0.1 a. Chosen so
/// that the distribution without the drift, `exp(-U/kT) / mu_perp(h)`, is far from
/// Boltzmann: their Kolmogorov-Smirnov distance is 0.116 (computed from B1's mu_perp;
/// 0.091 for weight 2, 0.059 for weight 5).
const FORCES: ExternalForces = ExternalForces {
    weight: 1.0,
    strength: 50.0,
    debye: 0.1,
    trap: 0.0,
};

/// Heights visited by one sphere, sampled every `every` steps after `burn` steps, and
/// the number of steps rejected (and redrawn) because they crossed into the wall.
fn heights(drift: bool, steps: usize, every: usize, burn: usize, seed: u64) -> (Vec<f64>, usize) {
    let bd = Brownian {
        noise: stokesian::Noise::Cholesky,
        hydrodynamics: true,
        kt: 1.0,
        dt: 0.02,
        drift,
        forces: FORCES,
    };
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut s = System::new(
        WALL,
        1.0,
        vec![Particle {
            x: [0.0, 0.0, 1.4],
            a: 1.0,
        }],
        false,
    )
    .unwrap();
    let mut out = Vec::new();
    let mut rejected = 0;
    for step in 0..steps {
        s = loop {
            match s.brownian_step(&bd, &mut rng, step) {
                Ok(next) => break next,
                Err(stokesian::BrownianError::Invalid { .. }) => rejected += 1,
                Err(e) => panic!("{e}"),
            }
        };
        if step >= burn && step % every == 0 {
            out.push(s.particles()[0].x[2]);
        }
    }
    (out, rejected)
}

/// The Boltzmann CDF of the height, `P(z) ~ exp(-U(z)/kT)` for z > a, by the trapezoid
/// rule on a fine grid (step 1e-4 a; the density varies on the scale 0.1 a).
fn boltzmann_cdf() -> impl Fn(f64) -> f64 {
    let (z0, z1, n) = (1.0, 12.0, 110_000);
    let dz = (z1 - z0) / n as f64;
    let dens: Vec<f64> = (0..=n)
        .map(|k| (-FORCES.potential_above(z0 + k as f64 * dz, 1.0, 0.0)).exp())
        .collect();
    let mut cdf = vec![0.0; n + 1];
    for k in 1..=n {
        cdf[k] = cdf[k - 1] + 0.5 * (dens[k] + dens[k - 1]) * dz;
    }
    let total = cdf[n];
    move |z: f64| {
        let k = (((z - z0) / dz).floor().max(0.0) as usize).min(n - 1);
        let t = ((z - z0) / dz - k as f64).clamp(0.0, 1.0);
        (cdf[k] + t * (cdf[k + 1] - cdf[k])) / total
    }
}

/// Kolmogorov-Smirnov statistic of `samples` against `cdf`.
fn ks(mut samples: Vec<f64>, cdf: impl Fn(f64) -> f64) -> f64 {
    samples.sort_by(f64::total_cmp);
    let n = samples.len() as f64;
    samples
        .iter()
        .enumerate()
        .map(|(i, &z)| {
            let f = cdf(z);
            (f - i as f64 / n).abs().max(((i + 1) as f64 / n - f).abs())
        })
        .fold(0.0, f64::max)
}

/// One sphere under gravity and a wall repulsion: with the drift kT div M the height
/// histogram is the Boltzmann distribution (Kolmogorov-Smirnov at the 1% level, critical
/// value 1.628/sqrt(n)); without it, it is not (the scheme then samples
/// exp(-U/kT)/mu_perp, piling up at the wall). Samples every 2000 steps (40 time units,
/// about the height's correlation time a^2 / D_perp ~ 35 at the mean height 2.2 a) after
/// a burn-in.
#[test]
fn heights_follow_boltzmann_only_with_the_drift() {
    let cdf = boltzmann_cdf();
    let steps = 1_500_000;
    let (with, rejected_with) = heights(true, steps, 2000, 10_000, 1);
    let (without, rejected_without) = heights(false, steps, 2000, 10_000, 1);
    println!("steps rejected at the wall: with drift {rejected_with}, without {rejected_without} (of {steps})");
    // With the drift, steps into the wall (rejected and redrawn) must be rare: below 0.1%
    // of the steps, so that their bias stays far below the KS resolution (~6% here).
    assert!(
        rejected_with < steps / 1000,
        "{rejected_with} rejected steps"
    );
    let critical = 1.628 / (with.len() as f64).sqrt();
    let (d_with, d_without) = (ks(with.clone(), &cdf), ks(without.clone(), &cdf));
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    println!(
        "n = {}, KS critical (1%) {critical:.4}: with drift D = {d_with:.4} (mean height {:.4}), without D = {d_without:.4} (mean height {:.4})",
        with.len(),
        mean(&with),
        mean(&without)
    );
    assert!(d_with < critical, "with drift: D = {d_with} >= {critical}");
    assert!(
        d_without > critical,
        "without drift: D = {d_without} <= {critical}"
    );
}

/// Short-time self-diffusion at h = 1.5 a, free of external forces: the variances of
/// one-step displacements are 2 kT dt times the self-mobility, parallel and normal to
/// the wall. 1e5 samples: the relative standard error of a variance is sqrt(2/n) =
/// 0.45%; tolerance 2.5% (over 5 standard errors; the O(dt) drift contributes
/// O(dt^2) to the variance).
#[test]
fn short_time_diffusion_is_kt_times_the_self_mobility() {
    for noise in [Noise::Cholesky, Noise::Lanczos { tol: 1e-10 }] {
        short_time_diffusion(noise);
    }
}

fn short_time_diffusion(noise: Noise) {
    let bd = Brownian {
        noise,
        hydrodynamics: true,
        kt: 1.0,
        dt: 1e-3,
        drift: true,
        forces: ExternalForces {
            weight: 0.0,
            strength: 0.0,
            debye: 1.0,
            trap: 0.0,
        },
    };
    let s = System::new(
        WALL,
        1.0,
        vec![Particle {
            x: [0.0, 0.0, 1.5],
            a: 1.0,
        }],
        false,
    )
    .unwrap();
    let m = s.mobility(Moments::F);
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let n = 100_000;
    let (mut sx, mut sz, mut mz) = (0.0, 0.0, 0.0);
    for k in 0..n {
        let p = s.brownian_step(&bd, &mut rng, k).unwrap().particles()[0].x;
        sx += p[0] * p[0];
        sz += (p[2] - 1.5) * (p[2] - 1.5);
        mz += p[2] - 1.5;
    }
    let (nf, two) = (n as f64, 2.0 * bd.kt * bd.dt);
    let var_x = sx / nf;
    let var_z = sz / nf - (mz / nf).powi(2);
    println!(
        "D_par/kT: {} vs mu {}; D_perp/kT: {} vs mu {}",
        var_x / two,
        m[(0, 0)],
        var_z / two,
        m[(2, 2)]
    );
    assert!((var_x / two / m[(0, 0)] - 1.0).abs() < 0.025);
    assert!((var_z / two / m[(2, 2)] - 1.0).abs() < 0.025);
    // and the normal mobility near the wall is well below the parallel one
    assert!(m[(2, 2)] < 0.8 * m[(0, 0)]);
}

/// The Lanczos square root from matrix-free products equals the exact `M^{1/2} w` of
/// the dense matrix (symmetric eigen-decomposition) for 40 spheres above a wall: the
/// iteration stops at a relative change of 1e-8, and the error is asserted below 1e-6
/// (the last change bounds the error up to a modest factor for this well-conditioned
/// M). The iteration count is printed.
#[test]
fn lanczos_square_root_matches_the_dense_square_root() {
    use rand::Rng;
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let ps = integration_tests::random_spheres(&mut rng, &WALL, 40, (0.8, 1.2), 0.2, 12.0);
    let s = System::new(WALL, 1.0, ps, false).unwrap();
    let m = s.mobility(Moments::F);
    let w: Vec<f64> = (0..m.nrows()).map(|_| rng.gen_range(-1.0..1.0)).collect();
    let (y, iters) = stokesian::lanczos_sqrt(|x| s.apply(Moments::F, x), &w, 1e-8, 200).unwrap();
    let e = m.clone().symmetric_eigen();
    let sqrt_m = &e.eigenvectors
        * nalgebra::DMatrix::from_diagonal(&e.eigenvalues.map(f64::sqrt))
        * e.eigenvectors.transpose();
    let exact = sqrt_m * nalgebra::DVector::from_column_slice(&w);
    let err = (nalgebra::DVector::from_column_slice(&y) - &exact).norm() / exact.norm();
    println!("Lanczos: {iters} iterations for N = 40 (dimension 120), relative error {err:e}");
    assert!(err < 1e-6, "relative error {err:e}");
    assert!(iters < 120, "no better than the dense dimension: {iters}");
}

/// Samples of (separation, height of sphere 0) for two unit spheres above the wall in a
/// weak lateral trap, with or without hydrodynamic interactions; steps that overlap the
/// wall or the other sphere are redrawn (the same hard-core rule in both runs).
fn two_sphere_samples(
    hydrodynamics: bool,
    steps: usize,
    every: usize,
    seed: u64,
) -> (Vec<f64>, Vec<f64>) {
    let bd = Brownian {
        noise: Noise::Cholesky,
        hydrodynamics,
        kt: 1.0,
        dt: 0.02,
        drift: true,
        forces: ExternalForces {
            trap: 0.5,
            ..FORCES
        },
    };
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let start = vec![
        Particle {
            x: [-1.5, 0.0, 1.5],
            a: 1.0,
        },
        Particle {
            x: [1.5, 0.0, 1.5],
            a: 1.0,
        },
    ];
    let mut s = System::new(WALL, 1.0, start, false).unwrap();
    let (mut sep, mut height) = (Vec::new(), Vec::new());
    for step in 0..steps {
        s = loop {
            match s.brownian_step(&bd, &mut rng, step) {
                Ok(next) => break next,
                Err(stokesian::BrownianError::Invalid { .. }) => {}
                Err(e) => panic!("{e}"),
            }
        };
        if step >= 10 * every && step % every == 0 {
            let (p, q) = (s.particles()[0].x, s.particles()[1].x);
            sep.push((0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>().sqrt());
            height.push(p[2]);
        }
    }
    (sep, height)
}

/// Two-sample Kolmogorov-Smirnov statistic.
fn ks2(mut a: Vec<f64>, mut b: Vec<f64>) -> f64 {
    a.sort_by(f64::total_cmp);
    b.sort_by(f64::total_cmp);
    let (n, m) = (a.len(), b.len());
    let (mut i, mut j, mut d) = (0, 0, 0.0f64);
    while i < n && j < m {
        if a[i] <= b[j] {
            i += 1;
        } else {
            j += 1;
        }
        d = d.max((i as f64 / n as f64 - j as f64 / m as f64).abs());
    }
    d
}

/// Two spheres above a wall, under gravity, a wall repulsion and a weak lateral trap
/// (kT / trap = 2 a^2, so they meet often): the equilibrium distributions of their
/// separation and of a height are the same with and without hydrodynamic interactions
/// (two-sample Kolmogorov-Smirnov at the 1% level, critical value
/// 1.628 sqrt((n + m)/(n m))). Hydrodynamics change the dynamics only; this needs the
/// pair and self drift to be right. Samples every 2000 steps (40 time units, longer
/// than the trap's relaxation time 1/(trap mu_0) ~ 38 and the heights' ~35).
#[test]
fn two_sphere_equilibrium_does_not_depend_on_hydrodynamics() {
    let steps = 1_200_000;
    let (sep_hi, h_hi) = two_sphere_samples(true, steps, 2000, 11);
    let (sep_free, h_free) = two_sphere_samples(false, steps, 2000, 12);
    let (n, m) = (sep_hi.len() as f64, sep_free.len() as f64);
    let critical = 1.628 * ((n + m) / (n * m)).sqrt();
    let d_sep = ks2(sep_hi.clone(), sep_free.clone());
    let d_h = ks2(h_hi, h_free);
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    println!(
        "n = {n}, m = {m}, critical {critical:.4}: separation D = {d_sep:.4} (means {:.3}, {:.3}), height D = {d_h:.4}",
        mean(&sep_hi),
        mean(&sep_free)
    );
    assert!(d_sep < critical, "separation: D = {d_sep}");
    assert!(d_h < critical, "height: D = {d_h}");
}
