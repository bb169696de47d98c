//! Section f, Brownian dynamics above a wall in a box periodic along it: one sedimented
//! sphere moved by Euler-Maruyama with the periodic mobility and its generated drift
//! (`WallEwald::drift`), with and without the drift. With it the heights must follow
//! Boltzmann's distribution (Kolmogorov-Smirnov at the 1% level); without it they
//! follow `exp(-U/kT) / mu_perp(h)`, which is measurably not Boltzmann. A run long
//! enough for this takes minutes (every step sums the lattice), so it is measured here
//! rather than in the test suite, which checks the drift against differences of the
//! mobility.

use super::boltzmann::{table, with_and_without_drift};
use super::{Ctx, Section};
use anyhow::Result;
use integration_tests::statistics::sample;
use integration_tests::SEDIMENTED;
use std::fmt::Write as _;
use stokesian::{
    Brownian, Confinement, ExternalForces, Moments, Noise, Overlap, Particle, PeriodicBox, Scheme,
    System,
};

/// The sedimented colloid of the open wall's test of the drift (`brownian::dynamics`).
const FORCES: ExternalForces = SEDIMENTED;

/// The box: 8 a x 8 a, lattice sums to 1e-6.
fn periodic_box() -> PeriodicBox {
    PeriodicBox {
        tolerance: 1e-6,
        ..PeriodicBox::lateral([8.0, 8.0])
    }
}

/// Heights sampled every `every` steps after `10 every`, and the redrawn steps.
fn heights(drift: bool, steps: usize, every: usize, seed: u64) -> Result<(Vec<f64>, usize)> {
    let bd = Brownian {
        noise: Noise::Cholesky,
        hydrodynamics: true,
        lubrication: None,
        moments: Moments::F,
        scheme: Scheme::EulerMaruyama,
        kt: 1.0,
        dt: 0.02,
        drift,
        forces: FORCES,
    };
    let start = System::new(
        Confinement::Wall { height: 0.0 },
        1.0,
        vec![Particle {
            x: [0.0, 0.0, 1.4],
            a: 1.0,
        }],
        Overlap::Refuse,
    )?
    .periodic(periodic_box())?;
    Ok(sample(&bd, start, (steps, every, 10 * every), seed, |s| {
        s.particles()[0].x[2]
    }))
}

/// Section f.
pub fn section(ctx: &Ctx) -> Result<Section> {
    ctx.progress.inc_length(1);
    ctx.progress
        .set_message("Brownian dynamics above a periodic wall (minutes)");
    let steps = ctx.cfg.periodic_brownian_steps;
    // 40 time units between samples, about the heights' correlation time
    let every = 2000.min(steps / 20).max(1);
    let runs = with_and_without_drift(|drift| heights(drift, steps, every, 1))?;
    let elapsed = runs.seconds;
    ctx.progress.inc(1);
    let bx = periodic_box();
    let mut body = String::new();
    writeln!(
        body,
        "One unit sphere above a no-slip wall in a box periodic along it ({} a x {} a, lattice sums to {:e}; \
         viscosity 1, kT = 1), buoyant weight 1 kT/a, wall repulsion 50 kT/a with screening length 0.1 a, \
         dt = 0.02, {steps} steps per run, Euler-Maruyama with Cholesky noise, with the generated drift \
         (the height derivative of the periodic self mobility) and without it; steps into the wall redrawn. \
         Samples every {every} steps after {} steps; Kolmogorov-Smirnov against Boltzmann's distribution of \
         the height at the 1% level (critical value 1.628/sqrt(n)). Both runs took {elapsed:.0} s of wall \
         time (in parallel).\n",
        bx.lengths.as_slice()[0],
        bx.lengths.as_slice()[1],
        bx.tolerance,
        10 * every
    )?;
    body.push_str(&table(&runs, &FORCES)?);
    writeln!(
        body,
        "\nSteps redrawn: {} with the drift, {} without.",
        runs.with.1, runs.without.1
    )?;
    Ok(Section {
        title: "f. Brownian dynamics above a wall in a periodic box".into(),
        body,
    })
}
