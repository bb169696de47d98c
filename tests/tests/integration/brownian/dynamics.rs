//! Brownian dynamics near a wall, validated statistically (fixed seeds; confidence
//! levels stated per test).

use integration_tests::statistics::{boltzmann_height_cdf, ks, ks2, sample, separation_and_height};
use integration_tests::{NO_FORCES, SEDIMENTED, WALL};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use stokesian::{Brownian, ExternalForces, Moments, Noise, Particle, Scheme, System};

/// The sedimented colloid of [`SEDIMENTED`]: chosen so that the distribution without the
/// drift is far from Boltzmann.
const FORCES: ExternalForces = SEDIMENTED;

/// Heights visited by one sphere, sampled every `every` steps after `burn` steps, and
/// the number of steps rejected (and redrawn) because they crossed into the wall.
fn heights(
    scheme: Scheme,
    drift: bool,
    steps: usize,
    every: usize,
    burn: usize,
    seed: u64,
) -> (Vec<f64>, usize) {
    let bd = Brownian {
        noise: stokesian::Noise::Cholesky,
        hydrodynamics: true,
        lubrication: None,
        moments: Moments::F,
        scheme,
        kt: 1.0,
        dt: 0.02,
        drift,
        forces: FORCES,
    };
    let start = System::new(
        WALL,
        1.0,
        vec![Particle {
            x: [0.0, 0.0, 1.4],
            a: 1.0,
        }],
        false,
    )
    .unwrap();
    sample(&bd, start, (steps, every, burn), seed, |s| {
        s.particles()[0].x[2]
    })
}

/// One sphere under gravity and a wall repulsion: with the drift kT div M the height
/// histogram is the Boltzmann distribution (Kolmogorov-Smirnov at the 1% level, critical
/// value 1.628/sqrt(n)); without it, it is not (the scheme then samples
/// exp(-U/kT)/mu_perp, piling up at the wall). Samples every 2000 steps (40 time units,
/// about the height's correlation time a^2 / D_perp ~ 35 at the mean height 2.2 a) after
/// a burn-in. Fixman's midpoint scheme, which makes the drift from a second mobility
/// instead of the divergence kernels, samples Boltzmann too.
#[test]
fn heights_follow_boltzmann_only_with_the_drift() {
    let cdf = boltzmann_height_cdf(&FORCES, 1.0);
    let steps = 1_500_000;
    let em = Scheme::EulerMaruyama;
    let (with, rejected_with) = heights(em, true, steps, 2000, 10_000, 1);
    let (without, rejected_without) = heights(em, false, steps, 2000, 10_000, 1);
    let (fixman, rejected_fixman) = heights(Scheme::FixmanMidpoint, true, steps, 2000, 10_000, 1);
    let d_fixman = ks(fixman.clone(), &cdf);
    let critical_fixman = 1.628 / (fixman.len() as f64).sqrt();
    println!(
        "Fixman midpoint: n = {}, D = {d_fixman:.4} (critical {critical_fixman:.4}), {rejected_fixman} steps rejected",
        fixman.len()
    );
    assert!(
        d_fixman < critical_fixman,
        "Fixman: D = {d_fixman} >= {critical_fixman}"
    );
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

/// Brownian settings without external forces (kT = 1, dt = 1e-3, drift on), for the
/// short-time and drift tests.
fn force_free(moments: Moments, scheme: Scheme, noise: Noise) -> Brownian {
    Brownian {
        noise,
        hydrodynamics: true,
        lubrication: None,
        moments,
        scheme,
        kt: 1.0,
        dt: 1e-3,
        drift: true,
        forces: NO_FORCES,
    }
}

/// One unit sphere at height 1.5 a above the wall.
fn sphere_at_one_and_a_half() -> System {
    System::new(
        WALL,
        1.0,
        vec![Particle {
            x: [0.0, 0.0, 1.5],
            a: 1.0,
        }],
        false,
    )
    .unwrap()
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
    let bd = force_free(Moments::F, Scheme::EulerMaruyama, noise);
    let s = sphere_at_one_and_a_half();
    let m = s.mobility(Moments::F);
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let n = 100_000;
    let (mut sx, mut sz, mut mz) = (0.0, 0.0, 0.0);
    for k in 0..n {
        let p = s
            .brownian_step(&bd, &mut rng, k)
            .unwrap()
            .system
            .particles()[0]
            .x;
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
        lubrication: None,
        moments: Moments::F,
        scheme: Scheme::EulerMaruyama,
        kt: 1.0,
        dt: 0.02,
        drift: true,
        forces: ExternalForces {
            trap: 0.5,
            torque: [0.0; 3],
            ..FORCES
        },
    };
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
    let start = System::new(WALL, 1.0, start, false).unwrap();
    let (samples, _) = sample(
        &bd,
        start,
        (steps, every, 10 * every),
        seed,
        separation_and_height,
    );
    samples.into_iter().unzip()
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

/// Two spheres near the wall (different heights, oblique separation, so that every
/// translational component of the drift is non-zero). The rotational rows of the drift
/// vanish: the rotation-force coupling is a curl, `(1/2) curl_a G(x_a, x_b)`, and
/// `sum_j d/dx_bj G_kj(x_a, x_b) = 0` by reciprocity and incompressibility (the Faxen
/// corrections are Laplacians of the same field).
fn drift_pair() -> System {
    let ps = vec![
        Particle {
            x: [0.0, 0.0, 1.6],
            a: 1.0,
        },
        Particle {
            x: [2.1, 0.9, 2.3],
            a: 1.0,
        },
    ];
    System::new(WALL, 1.0, ps, false).unwrap()
}

/// Fixman's midpoint scheme has no drift term; the drift `kT div M dt` must come out of
/// the midpoint evaluation (at FT: with no mean rotation). Its mean one-step displacement (no external forces) is
/// compared with `kT dt` times the generated divergence kernels, an independent path.
/// Antithetic pairs `(W, -W)` cancel the O(sqrt(dt)) noise exactly, so that 20000 pairs
/// resolve the O(dt) mean to a relative standard error of about 1% (measured, printed;
/// the test asserts it is below 2% of the drift's norm so that it can fail). Tolerance:
/// 4 standard errors per component plus the scheme's own O(dt) relative bias, bounded by
/// 2% at dt = 1e-3 (displacements of 0.01 a against mobility gradients on the scale
/// of 1 a). The half-difference `(dx(W) - dx(-W))/2` is the noise: its covariance must be
/// `2 kT dt M` (relative standard error sqrt(2/n) = 1%; tolerance 5%, relative to the
/// diagonal).
#[test]
fn fixman_midpoint_produces_the_generated_drift_and_the_covariance() {
    use rand::Rng;
    let s = drift_pair();
    for moments in [Moments::F, Moments::FT] {
        let bd = force_free(moments, Scheme::FixmanMidpoint, Noise::Cholesky);
        let dim = moments.per_particle() * s.len();
        let expected: Vec<f64> = s
            .divergence_at(moments)
            .iter()
            .map(|d| bd.kt * bd.dt * d)
            .collect();
        let mut rng = ChaCha8Rng::seed_from_u64(21);
        let n = 20_000;
        let (mut mean, mut sq) = (vec![0.0; dim], vec![0.0; dim]);
        let mut cov = nalgebra::DMatrix::<f64>::zeros(dim, dim);
        for k in 0..n {
            let w: Vec<f64> = (0..dim)
                .map(|_| rng.sample::<f64, _>(rand_distr::StandardNormal))
                .collect();
            let minus: Vec<f64> = w.iter().map(|v| -v).collect();
            let a = s.brownian_increment(&bd, &w, k).unwrap();
            let b = s.brownian_increment(&bd, &minus, k).unwrap();
            let half_sum: Vec<f64> = a.iter().zip(&b).map(|(a, b)| 0.5 * (a + b)).collect();
            let half_diff =
                nalgebra::DVector::from_iterator(dim, a.iter().zip(&b).map(|(a, b)| 0.5 * (a - b)));
            for i in 0..dim {
                mean[i] += half_sum[i] / n as f64;
                sq[i] += half_sum[i] * half_sum[i] / n as f64;
            }
            cov += &half_diff * half_diff.transpose() / n as f64;
        }
        let norm = expected.iter().map(|v| v * v).sum::<f64>().sqrt();
        let mut worst_se = 0.0f64;
        for i in 0..dim {
            let se = ((sq[i] - mean[i] * mean[i]) / n as f64).sqrt();
            worst_se = worst_se.max(se);
            assert!(
                (mean[i] - expected[i]).abs() < 4.0 * se + 0.02 * norm,
                "{moments:?} component {i}: mean {:e} vs kT dt div M {:e} (standard error {se:e})",
                mean[i],
                expected[i]
            );
        }
        println!(
            "{moments:?}: |kT dt div M| = {norm:e}, largest standard error {worst_se:e} ({:.2}%)",
            100.0 * worst_se / norm
        );
        assert!(worst_se < 0.02 * norm, "the test cannot resolve the drift");
        let m = s.mobility(moments) * (2.0 * bd.kt * bd.dt);
        let diag = (0..dim).map(|i| m[(i, i)]).fold(0.0, f64::max);
        let err = (&cov - &m).amax() / diag;
        println!("{moments:?}: covariance vs 2 kT dt M: largest error {err:.4} of the diagonal");
        assert!(err < 0.05, "{moments:?}: covariance error {err}");
    }
}

/// FT level, one sphere at h = 1.5 a with no external forces or torques: the short-time
/// covariance of (translation, rotation) over one step is `2 kT dt M_FT`, including the
/// rotation-translation coupling near the wall (U_x with the torque about y), whose
/// sign and size the far-field sphere in unbounded fluid does not have. 1e5 steps:
/// relative standard error of a variance sqrt(2/n) = 0.45%; of the coupling, about
/// 1/sqrt(n) relative to sqrt(var_x var_rot) = 0.32%, which here is 20% of the coupling
/// itself; tolerances 2.5% for the variances and 4 standard errors for the coupling.
#[test]
fn ft_short_time_rotation_and_coupling_follow_the_ft_mobility() {
    let bd = force_free(Moments::FT, Scheme::EulerMaruyama, Noise::Cholesky);
    let s = sphere_at_one_and_a_half();
    let m = s.mobility(Moments::FT);
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let n = 100_000;
    let (mut xx, mut ry, mut rz, mut xr) = (0.0, 0.0, 0.0, 0.0);
    for k in 0..n {
        let step = s.brownian_step(&bd, &mut rng, k).unwrap();
        let (x, r) = (step.system.particles()[0].x[0], step.rotation[0]);
        xx += x * x;
        ry += r[1] * r[1];
        rz += r[2] * r[2];
        xr += x * r[1];
    }
    let two = 2.0 * bd.kt * bd.dt * n as f64;
    let (var_x, var_ry, var_rz, cov) = (xx / two, ry / two, rz / two, xr / two);
    println!(
        "FT h = 1.5 a: U_x {var_x:.5} vs {:.5}; Omega_y {var_ry:.5} vs {:.5}; Omega_z {var_rz:.5} vs {:.5}; coupling {cov:.5} vs {:.5}",
        m[(0, 0)],
        m[(4, 4)],
        m[(5, 5)],
        m[(0, 4)]
    );
    assert!((var_x / m[(0, 0)] - 1.0).abs() < 0.025);
    assert!((var_ry / m[(4, 4)] - 1.0).abs() < 0.025);
    assert!((var_rz / m[(5, 5)] - 1.0).abs() < 0.025);
    let se = (m[(0, 0)] * m[(4, 4)] / n as f64).sqrt();
    assert!(
        (cov - m[(0, 4)]).abs() < 4.0 * se,
        "coupling {cov} vs {} (standard error {se})",
        m[(0, 4)]
    );
    // the coupling is resolved: its size is several standard errors
    assert!(m[(0, 4)].abs() > 4.0 * se);
}
