//! Section e, lubricated Brownian dynamics at equilibrium: two spheres above a wall
//! under gravity, a wall repulsion and a lateral trap, moved by the lubricated
//! dynamics (`Brownian::lubrication`, the resistance of Eq. 19, the drift by a random
//! finite difference) and, separately, without hydrodynamic interactions. Equilibrium
//! does not depend on the dynamics: the distributions of the separation and of a
//! height must agree (two-sample Kolmogorov-Smirnov at the 1% level). A run long enough
//! for this takes minutes, so it is measured here rather than in the test suite.

use super::{Ctx, Section};
use anyhow::Result;
use integration_tests::statistics::{ks2, sample, separation_and_height};
use std::fmt::Write as _;
use std::time::Instant;
use stokesian::{
    Brownian, Confinement, ExternalForces, LubricatedDynamics, Lubrication, Moments, Noise,
    Particle, Scheme, System,
};

/// Gravity 1 kT/a, repulsion 50 kT/a over 0.1 a, lateral trap 0.5 kT/a^2 (kT / trap =
/// 2 a^2, so that the spheres meet often).
const FORCES: ExternalForces = ExternalForces {
    weight: 1.0,
    strength: 50.0,
    debye: 0.1,
    trap: 0.5,
    torque: [0.0; 3],
};

/// Samples every `every` steps after `10 every`: (separation, height of sphere 0), and
/// the redrawn steps.
fn samples(lubricated: bool, steps: usize, every: usize, seed: u64) -> (Vec<f64>, Vec<f64>, usize) {
    let bd = Brownian {
        noise: Noise::Cholesky,
        hydrodynamics: lubricated,
        moments: Moments::F,
        scheme: Scheme::EulerMaruyama,
        kt: 1.0,
        dt: 0.02,
        drift: true,
        forces: FORCES,
        lubrication: lubricated.then_some(LubricatedDynamics {
            lubrication: Lubrication::default(),
            rfd_step: 1e-3,
        }),
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
    let start =
        System::new(Confinement::Wall { height: 0.0 }, 1.0, start, false).expect("a valid start");
    let (samples, redrawn) = sample(
        &bd,
        start,
        (steps, every, 10 * every),
        seed,
        separation_and_height,
    );
    let (sep, height) = samples.into_iter().unzip();
    (sep, height, redrawn)
}

/// Section e.
pub fn section(ctx: &Ctx) -> Result<Section> {
    ctx.progress.inc_length(1);
    ctx.progress
        .set_message("lubricated Brownian dynamics at equilibrium (minutes)");
    let steps = ctx.cfg.brownian_steps;
    // 40 time units between samples: longer than the trap's relaxation without
    // hydrodynamics (1/(trap mu_0) ~ 38) and about the heights' correlation time
    let every = 2000.min(steps / 20).max(1);
    let t0 = Instant::now();
    let ((sep_l, h_l, redrawn_l), (sep_f, h_f, redrawn_f)) = std::thread::scope(|sc| {
        let free = sc.spawn(|| samples(false, steps, every, 12));
        let lub = samples(true, steps, every, 11);
        (lub, free.join().expect("the free run does not panic"))
    });
    let elapsed = t0.elapsed().as_secs_f64();
    ctx.progress.inc(1);
    let (n, m) = (sep_l.len() as f64, sep_f.len() as f64);
    let critical = 1.628 * ((n + m) / (n * m)).sqrt();
    let (d_sep, d_h) = (
        ks2(sep_l.clone(), sep_f.clone()),
        ks2(h_l.clone(), h_f.clone()),
    );
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let verdict = |d: f64| if d < critical { "agree" } else { "DIFFER" };
    let mut body = String::new();
    writeln!(
        body,
        "Two unit spheres above a no-slip wall (viscosity 1, kT = 1), buoyant weight 1 kT/a, wall repulsion \
         50 kT/a with screening length 0.1 a, lateral harmonic trap 0.5 kT/a^2, dt = 0.02, {steps} steps per run, \
         Euler-Maruyama, overlapping steps redrawn. Lubricated: `Brownian::lubrication` with `Lubrication::default()` \
         (exact sphere-wall resistance at every height, exact two-sphere resistance wherever its correction may exceed 1e-3 of the drag, a smoothstep beyond: s' < 9.31 at FT), \
         noise `L^-T W` from the Cholesky factor of the resistance, the drift `kT div R^-1` by a random finite \
         difference (step 1e-3 a). Reference: the same forces without hydrodynamic interactions (isolated Stokes \
         mobilities). Samples every {every} steps after {} steps; two-sample Kolmogorov-Smirnov at the 1% level \
         (critical value 1.628 sqrt((n + m)/(n m))). Both runs took {elapsed:.0} s of wall time (in parallel).\n",
        10 * every
    )?;
    writeln!(
        body,
        "| quantity | lubricated | no hydrodynamics | KS distance | critical (1%) | |"
    )?;
    writeln!(body, "|---|---|---|---|---|---|")?;
    writeln!(
        body,
        "| separation, mean | {:.4} a | {:.4} a | {d_sep:.4} | {critical:.4} | {} |",
        mean(&sep_l),
        mean(&sep_f),
        verdict(d_sep)
    )?;
    writeln!(
        body,
        "| height of sphere 0, mean | {:.4} a | {:.4} a | {d_h:.4} | {critical:.4} | {} |",
        mean(&h_l),
        mean(&h_f),
        verdict(d_h)
    )?;
    writeln!(
        body,
        "\nSamples: {} lubricated, {} without hydrodynamics; steps redrawn: {redrawn_l} and {redrawn_f}.",
        sep_l.len(),
        sep_f.len()
    )?;
    Ok(Section {
        title: "e. Lubricated Brownian dynamics at equilibrium".into(),
        body,
    })
}
