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

use super::boltzmann::{table, with_and_without_drift};
use super::{Ctx, Section};
use anyhow::Result;
use integration_tests::statistics::{boltzmann_heights, sample};
use integration_tests::SEDIMENTED;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::fmt::Write as _;
use stokesian::{
    Brownian, Confinement, ExternalForces, FastProduct, Moments, Noise, Overlap, Particle, Scheme,
    System,
};

/// The sedimented colloid of the open wall's test of the drift (`brownian::dynamics`).
const FORCES: ExternalForces = SEDIMENTED;

/// Lateral spacing of the spheres' square lattice, in radii.
const SPACING: f64 = 10.0;

/// The time step (40 time units, about the height's correlation time, are 2000 steps).
const DT: f64 = 0.02;

/// Lanczos's tolerance on the noise.
const LANCZOS: f64 = 1e-3;

/// Steps between the three snapshots of a run of `steps`.
fn every(steps: usize) -> usize {
    (steps / 3).max(1)
}

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

/// The heights of every sphere at three snapshots ([`every`]), and the redrawn steps.
fn heights(drift: bool, side: usize, steps: usize) -> Result<(Vec<f64>, usize)> {
    let bd = Brownian {
        noise: Noise::Lanczos { tol: LANCZOS },
        hydrodynamics: true,
        lubrication: None,
        moments: Moments::F,
        scheme: Scheme::EulerMaruyama,
        kt: 1.0,
        dt: DT,
        drift,
        forces: FORCES,
    };
    let every = every(steps);
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
    let runs = with_and_without_drift(|drift| heights(drift, side, steps))?;
    ctx.progress.inc(1);
    let (fast, e) = (settings(), every(steps));
    let mut body = String::new();
    writeln!(
        body,
        "{n} unit spheres on a square lattice of spacing {SPACING} a above a no-slip wall (viscosity 1, \
         kT = 1), buoyant weight 1 kT/a, wall repulsion 50 kT/a with screening length 0.1 a, started \
         at independent heights drawn from Boltzmann's distribution; dt = {DT}, {steps} steps per \
         run, Euler-Maruyama with Lanczos noise (tolerance {LANCZOS:e}) and the drift, every product \
         the fast one (tolerance {:e}, expansion order {}, leaves of at most {} spheres, acceptance \
         ratio {}); the same without the drift. Steps into the wall redrawn. The heights of every \
         sphere at steps {e}, {} and {} (each sphere's {} time units apart, about the height's \
         correlation time); Kolmogorov-Smirnov against Boltzmann's distribution at the 1% level \
         (critical value 1.628/sqrt(n)). Both runs took {:.0} s of wall time (in parallel).\n",
        fast.eps,
        fast.order,
        fast.leaf,
        fast.theta,
        2 * e,
        3 * e,
        e as f64 * DT,
        runs.seconds,
        n = side * side,
    )?;
    body.push_str(&table(&runs, &FORCES)?);
    writeln!(
        body,
        "\nSteps redrawn (all spheres' step, when one would cross into the wall): \
         {} with the drift, {} without, of {steps}.",
        runs.with.1, runs.without.1
    )?;
    Ok(Section {
        title: "g. Brownian dynamics with the fast product".into(),
        body,
    })
}
