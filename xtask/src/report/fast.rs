//! Section g, Brownian dynamics with the fast product: sedimented spheres above a wall,
//! far enough apart that their pairs go through the multipole expansions, moved by
//! Euler-Maruyama with Lanczos noise and the drift, every mobility product the fast one
//! (`System::with_fast`). Started from Boltzmann's distribution of heights, a chain that
//! keeps it (with the drift) must still show it after a correlation time; one without
//! the drift moves towards `exp(-U/kT) / mu_perp(h)`, measurably not Boltzmann. Its
//! 1.5 million sphere-steps of fast products take minutes, so it is measured here; the
//! test suite checks that a step with the fast product is the direct one's to the
//! tolerances (`fmm::lanczos_noise_takes_the_fast_product`) and that the direct chain
//! samples Boltzmann (`brownian::dynamics`).

use super::{Ctx, Section};
use anyhow::Result;
use integration_tests::statistics::{boltzmann_height_cdf, boltzmann_heights, ks, sample};
use integration_tests::SEDIMENTED;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::fmt::Write as _;
use std::time::Instant;
use stokesian::{
    Brownian, Confinement, ExternalForces, FastProduct, Moments, Noise, Overlap, Particle, Scheme,
    System,
};

/// The sedimented colloid of the open wall's test of the drift (`brownian::dynamics`).
const FORCES: ExternalForces = SEDIMENTED;

/// Lateral spacing of the spheres' square lattice, in radii.
const SPACING: f64 = 10.0;

/// The fast product's tolerance; leaves of at most 8 spheres, so that at this spacing
/// pairs some 80 radii apart and more (a third to a half of them) go through the
/// expansions.
fn settings() -> FastProduct {
    FastProduct {
        leaf: 8,
        ..FastProduct::new(1e-4).expect("a tolerance in range")
    }
}

/// `side^2` spheres on the lattice at heights drawn from Boltzmann's distribution.
fn start(side: usize) -> Result<System> {
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let heights = boltzmann_heights(&FORCES, 1.0, side * side, &mut rng);
    let ps = heights
        .into_iter()
        .enumerate()
        .map(|(i, z)| Particle {
            x: [SPACING * (i % side) as f64, SPACING * (i / side) as f64, z],
            a: 1.0,
        })
        .collect();
    Ok(
        System::new(Confinement::Wall { height: 0.0 }, 1.0, ps, Overlap::Refuse)?
            .with_fast(settings())?,
    )
}

/// The heights of every sphere every `steps / 3` steps (three snapshots), and the
/// redrawn steps.
fn heights(drift: bool, side: usize, steps: usize) -> Result<(Vec<f64>, usize)> {
    let bd = Brownian {
        noise: Noise::Lanczos { tol: 1e-3 },
        hydrodynamics: true,
        lubrication: None,
        moments: Moments::F,
        scheme: Scheme::EulerMaruyama,
        kt: 1.0,
        dt: 0.02,
        drift,
        forces: FORCES,
    };
    let every = (steps / 3).max(1);
    let (snapshots, redrawn) = sample(&bd, start(side)?, (steps + 1, every, every), 22, |s| {
        s.particles().iter().map(|p| p.x[2]).collect::<Vec<f64>>()
    });
    Ok((snapshots.concat(), redrawn))
}

/// Section g.
pub fn section(ctx: &Ctx) -> Result<Section> {
    ctx.progress.inc_length(1);
    ctx.progress
        .set_message("Brownian dynamics with the fast product (minutes)");
    let (side, steps) = (ctx.cfg.fast_brownian_side, ctx.cfg.fast_brownian_steps);
    let t0 = Instant::now();
    let (with, without) = std::thread::scope(|sc| {
        let without = sc.spawn(|| heights(false, side, steps));
        (heights(true, side, steps), without.join())
    });
    let ((with, redrawn_with), (without, redrawn_without)) = (
        with?,
        without.map_err(|_| anyhow::anyhow!("the run without the drift panicked"))??,
    );
    let elapsed = t0.elapsed().as_secs_f64();
    ctx.progress.inc(1);
    let cdf = boltzmann_height_cdf(&FORCES, 1.0);
    let critical = 1.628 / (with.len().max(1) as f64).sqrt();
    let (d_with, d_without) = (ks(with.clone(), &cdf), ks(without.clone(), &cdf));
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let verdict = |d: f64| {
        if d < critical {
            "Boltzmann"
        } else {
            "NOT Boltzmann"
        }
    };
    let fast = settings();
    let mut body = String::new();
    writeln!(
        body,
        "{n} unit spheres on a square lattice of spacing {SPACING} a above a no-slip wall (viscosity 1, \
         kT = 1), buoyant weight 1 kT/a, wall repulsion 50 kT/a with screening length 0.1 a, started \
         at independent heights drawn from Boltzmann's distribution; dt = 0.02, {steps} steps per \
         run, Euler-Maruyama with Lanczos noise (tolerance 1e-3) and the drift, every product the \
         fast one (tolerance {:e}, expansion order {}, leaves of at most {} spheres, acceptance \
         ratio {}); the same without the drift. Steps into the wall redrawn. The heights of every \
         sphere at steps {e}, {} and {} (each sphere's 40 time units apart, about the height's \
         correlation time); Kolmogorov-Smirnov against Boltzmann's distribution at the 1% level \
         (critical value 1.628/sqrt(n)). Both runs took {elapsed:.0} s of wall time (in \
         parallel).\n",
        fast.eps,
        fast.order,
        fast.leaf,
        fast.theta,
        2 * (steps / 3).max(1),
        3 * (steps / 3).max(1),
        n = side * side,
        e = (steps / 3).max(1),
    )?;
    writeln!(
        body,
        "| run | samples | mean height | KS distance | critical (1%) | |"
    )?;
    writeln!(body, "|---|---|---|---|---|---|")?;
    for (name, v, d) in [
        ("with the drift", &with, d_with),
        ("without the drift", &without, d_without),
    ] {
        writeln!(
            body,
            "| {name} | {} | {:.4} a | {d:.4} | {critical:.4} | {} |",
            v.len(),
            mean(v),
            verdict(d)
        )?;
    }
    writeln!(
        body,
        "\nSteps redrawn (all spheres' step, when one would cross into the wall): \
         {redrawn_with} with the drift, {redrawn_without} without, of {steps}."
    )?;
    Ok(Section {
        title: "g. Brownian dynamics with the fast product".into(),
        body,
    })
}
