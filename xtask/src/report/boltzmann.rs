//! What sections f and g share: a chain run with the drift and without it, concurrently,
//! and the heights of each against Boltzmann's distribution (Kolmogorov-Smirnov at the
//! 1% level, critical value `1.628 / sqrt(n)`). With the drift the heights must follow
//! it; without, the chain samples `exp(-U/kT) / mu_perp(h)`, which a run long enough
//! tells apart.

use anyhow::Result;
use integration_tests::statistics::{boltzmann_height_cdf, ks};
use std::fmt::Write as _;
use std::time::Instant;
use stokesian::ExternalForces;

/// The heights sampled by the two runs and the steps each redrew.
pub struct DriftRuns {
    /// With the drift: heights, redrawn steps.
    pub with: (Vec<f64>, usize),
    /// Without the drift: heights, redrawn steps.
    pub without: (Vec<f64>, usize),
    /// Wall time of both (in parallel), in seconds.
    pub seconds: f64,
}

/// `heights(drift)` for both values of `drift`, on two threads.
pub fn with_and_without_drift(
    heights: impl Fn(bool) -> Result<(Vec<f64>, usize)> + Sync,
) -> Result<DriftRuns> {
    let t0 = Instant::now();
    let (with, without) = std::thread::scope(|sc| {
        let without = sc.spawn(|| heights(false));
        (heights(true), without.join())
    });
    Ok(DriftRuns {
        with: with?,
        without: without.map_err(|_| anyhow::anyhow!("the run without the drift panicked"))??,
        seconds: t0.elapsed().as_secs_f64(),
    })
}

/// The markdown table of both runs against Boltzmann's distribution of the height of a
/// unit sphere under `forces` (kT = 1): samples, mean height, KS distance, critical
/// value, verdict.
pub fn table(runs: &DriftRuns, forces: &ExternalForces) -> Result<String> {
    let cdf = boltzmann_height_cdf(forces, 1.0);
    let critical = 1.628 / (runs.with.0.len().max(1) as f64).sqrt();
    let mut body = String::new();
    writeln!(
        body,
        "| run | samples | mean height | KS distance | critical (1%) | |"
    )?;
    writeln!(body, "|---|---|---|---|---|---|")?;
    for (name, v) in [
        ("with the drift", &runs.with.0),
        ("without the drift", &runs.without.0),
    ] {
        let d = ks(v.clone(), &cdf);
        let verdict = if d < critical {
            "Boltzmann"
        } else {
            "NOT Boltzmann"
        };
        writeln!(
            body,
            "| {name} | {} | {:.4} a | {d:.4} | {critical:.4} | {verdict} |",
            v.len(),
            v.iter().sum::<f64>() / v.len().max(1) as f64,
        )?;
    }
    Ok(body)
}
