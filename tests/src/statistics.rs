//! Statistics for the Brownian tests: a seeded run sampled at intervals, the
//! Kolmogorov-Smirnov statistics (one and two samples) and the Boltzmann distribution of
//! one sphere's height above a wall.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use stokesian::{Brownian, BrownianError, ExternalForces, System};

/// `steps` Brownian steps of `bd` from `start` with the ChaCha8 stream of `seed`; a step
/// that would overlap a boundary or another sphere is redrawn (and counted). Every
/// `every` steps from `burn` on, `observe` the system. Returns the observations and the
/// number of redrawn steps.
pub fn sample<T>(
    bd: &Brownian,
    start: System,
    (steps, every, burn): (usize, usize, usize),
    seed: u64,
    observe: impl Fn(&System) -> T,
) -> (Vec<T>, usize) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut s, mut out, mut redrawn) = (start, Vec::new(), 0);
    for step in 0..steps {
        s = loop {
            match s.brownian_step(bd, &mut rng, step) {
                Ok(next) => break next.system,
                Err(BrownianError::Invalid { .. }) => redrawn += 1,
                Err(e) => panic!("step {step}: {e}"),
            }
        };
        if step >= burn && step % every == 0 {
            out.push(observe(&s));
        }
    }
    (out, redrawn)
}

/// (separation, height of sphere 0) of the first two spheres.
pub fn separation_and_height(s: &System) -> (f64, f64) {
    let (p, q) = (s.particles()[0].x, s.particles()[1].x);
    let r = (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>().sqrt();
    (r, p[2])
}

/// Kolmogorov-Smirnov statistic of `samples` against `cdf`.
pub fn ks(mut samples: Vec<f64>, cdf: impl Fn(f64) -> f64) -> f64 {
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

/// Two-sample Kolmogorov-Smirnov statistic.
pub fn ks2(mut a: Vec<f64>, mut b: Vec<f64>) -> f64 {
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

/// The Boltzmann CDF of the centre height `z` of a sphere of radius `a` above a wall at
/// `z = 0` under `forces` (kT = 1), `P(z) ~ exp(-U(z))` for `z > a`, by the trapezoid
/// rule on a grid of step 1e-4 up to `z = 12 a` (the densities of the tests vary on
/// the scale 0.1 a and are negligible beyond).
pub fn boltzmann_height_cdf(forces: &ExternalForces, a: f64) -> impl Fn(f64) -> f64 {
    let (z0, z1, n) = (a, 12.0 * a, 110_000);
    let dz = (z1 - z0) / n as f64;
    // relative to the minimum on the grid, so that strong forces do not underflow
    let u: Vec<f64> = (0..=n)
        .map(|k| forces.potential_above(z0 + k as f64 * dz, a, 0.0))
        .collect();
    let umin = u.iter().copied().fold(f64::INFINITY, f64::min);
    let dens: Vec<f64> = u.iter().map(|u| (umin - u).exp()).collect();
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

/// Heights drawn from the distribution of [`boltzmann_height_cdf`]: `n` independent
/// draws by the inverse of the distribution function (bisection on `[a, 12 a]` to
/// below 1e-15 a), for runs started in equilibrium.
pub fn boltzmann_heights(
    forces: &ExternalForces,
    a: f64,
    n: usize,
    rng: &mut impl rand::Rng,
) -> Vec<f64> {
    let cdf = boltzmann_height_cdf(forces, a);
    (0..n)
        .map(|_| {
            let u = rng.gen_range(0.0..1.0);
            let (mut lo, mut hi) = (a, 12.0 * a);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if cdf(mid) < u {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            0.5 * (lo + hi)
        })
        .collect()
}
