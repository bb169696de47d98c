//! Time the fast product and measure its error for a monolayer of unit spheres (heights
//! 1.5 to 5 radii, area fraction 0.3): what `cargo xtask fmm` tabulates in docs/fmm.md;
//! with `box`, for spheres of radii 0.5 to 1 placed at random without overlap in a cube
//! of side `(18 N)^(1/3)` above the plane (a 3-D suspension, volume fraction about 0.1:
//! what calibrates the order, docs/fmm.md).
//!
//! `cargo run --release -p stokesian --example fmm_timing -- N EPS [F|FT] [wall|free] [box] [direct] [untimed] [brownian]`
//!
//! (`untimed`: the fast product once, without the error: for a profiler. `brownian`:
//! instead, one Euler-Maruyama step with Lanczos noise to `1e-4` and the fast product
//! to `EPS` (`stokesian brownian --lanczos 1e-4 --fmm EPS`: gravity, unit `kT`, `dt =
//! 1e-3`), timed whole and its drift alone, with the Lanczos iterations.)
//!
//! Prints the fast product's time (the median of five runs below 10^5 spheres, else
//! one) and phases, its relative 2-norm error against the direct sum (over every target
//! up to 2x10^4 spheres, else over 1000 random targets, each summed pair by pair with
//! the kernels), the direct product's time with `direct`, and the process's peak
//! resident memory; the last line, `result ...`, is what `cargo xtask fmm` reads.
//! `FMM_LEAF`, `FMM_THETA`, `FMM_ORDER` override the parameters chosen for `EPS`.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::time::Instant;
use stokesian::{Confinement, Moments, Particle, System};

/// A jittered square lattice of `n` unit spheres, area fraction 0.3, heights 1.5 to 5.
fn monolayer(n: usize, rng: &mut ChaCha8Rng) -> Vec<Particle> {
    let side = (std::f64::consts::PI / 0.3).sqrt();
    let k = (n as f64).sqrt().ceil() as usize;
    let jitter = (side - 2.05) / 2.0;
    (0..n)
        .map(|i| {
            let (a, b) = ((i % k) as f64, (i / k) as f64);
            Particle {
                x: [
                    a * side + rng.gen_range(-jitter..jitter),
                    b * side + rng.gen_range(-jitter..jitter),
                    rng.gen_range(1.5..5.0),
                ],
                a: 1.0,
            }
        })
        .collect()
}

/// `n` spheres of radii 0.5 to 1 at random without overlap in a cube of side `(18
/// n)^(1/3)` whose floor is 1.05 radii above the plane `x3 = 0`.
fn suspension(n: usize, rng: &mut ChaCha8Rng) -> Vec<Particle> {
    let side = (18.0 * n as f64).cbrt();
    let mut ps: Vec<Particle> = Vec::with_capacity(n);
    while ps.len() < n {
        let a = rng.gen_range(0.5..1.0);
        let x = [
            rng.gen_range(0.0..side),
            rng.gen_range(0.0..side),
            1.05 * a + rng.gen_range(0.0..side),
        ];
        let clear = ps.iter().all(|p| {
            let d2: f64 = (0..3).map(|k| (p.x[k] - x[k]).powi(2)).sum();
            d2 > (1.05 * (p.a + a)).powi(2)
        });
        if clear {
            ps.push(Particle { x, a });
        }
    }
    ps
}

/// The direct sum's rows `targets` (velocities, then rotations for FT), pair by pair.
fn direct_rows(
    conf: &Confinement,
    ps: &[Particle],
    m: Moments,
    x: &[f64],
    targets: &[usize],
) -> Vec<Vec<f64>> {
    let n = ps.len();
    let v = |j: usize| -> [f64; 6] {
        std::array::from_fn(|c| match (m, c) {
            (_, 0..=2) => x[3 * j + c],
            (Moments::FT, _) => x[3 * n + 3 * j + c - 3],
            _ => 0.0,
        })
    };
    targets
        .par_iter()
        .map(|&i| {
            let (xi, ai, vi) = (ps[i].x, ps[i].a, v(i));
            if m == Moments::F {
                let f = [vi[0], vi[1], vi[2]];
                let mut u = kernels::self_f(conf, 1.0, xi, ai).product(f, f).a;
                for (j, p) in ps.iter().enumerate().filter(|&(j, _)| j != i) {
                    let vj = v(j);
                    let o =
                        kernels::product_f(conf, 1.0, xi, ai, p.x, p.a, f, [vj[0], vj[1], vj[2]]);
                    (0..3).for_each(|c| u[c] += o.a[c]);
                }
                u.to_vec()
            } else {
                let mut u = kernels::self_ft(conf, 1.0, xi, ai).product(vi, vi).a;
                for (j, p) in ps.iter().enumerate().filter(|&(j, _)| j != i) {
                    let o = kernels::product_ft(conf, 1.0, xi, ai, p.x, p.a, vi, v(j));
                    (0..6).for_each(|c| u[c] += o.a[c]);
                }
                u.to_vec()
            }
        })
        .collect()
}

/// The process's peak resident memory in MiB (Linux), else 0.
fn peak_mib() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        })
        .map_or(0.0, |kib| kib / 1024.0)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).map_or(10_000, |s| s.parse().expect("N"));
    let eps: f64 = args.get(2).map_or(1e-6, |s| s.parse().expect("EPS"));
    let m = match args.get(3).map(String::as_str) {
        Some("FT") => Moments::FT,
        _ => Moments::F,
    };
    let (name, conf) = match args.get(4).map(String::as_str) {
        Some("free") => ("free", Confinement::Free),
        _ => ("wall", Confinement::Wall { height: 0.0 }),
    };
    let direct = args.iter().any(|s| s == "direct");
    let untimed = args.iter().any(|s| s == "untimed");
    let bulk = args.iter().any(|s| s == "box");
    let mut rng = ChaCha8Rng::seed_from_u64(12345);
    let ps = if bulk {
        suspension(n, &mut rng)
    } else {
        monolayer(n, &mut rng)
    };
    let system = System::new(conf, 1.0, ps.clone(), false).expect("a valid monolayer");
    let x: Vec<f64> = (0..n * m.per_particle())
        .map(|_| rng.gen_range(-0.5..0.5))
        .collect();
    if args.iter().any(|s| s == "brownian") {
        brownian(system, m, eps, name);
        return;
    }
    let mut settings = stokesian::FastProduct::new(eps).expect("a tolerance in range");
    let var = |k: &str| std::env::var(k).ok();
    if let Some(v) = var("FMM_LEAF").and_then(|s| s.parse().ok()) {
        settings.leaf = v;
    }
    if let Some(v) = var("FMM_THETA").and_then(|s| s.parse().ok()) {
        settings.theta = v;
    }
    if let Some(v) = var("FMM_ORDER").and_then(|s| s.parse().ok()) {
        settings.order = v;
    }
    let runs = if n < 100_000 && !untimed { 5 } else { 1 };
    let mut times = Vec::new();
    let mut out = None;
    for _ in 0..runs {
        let t = Instant::now();
        let (u, phases) = system.apply_fast_timed(m, &x, &settings).expect("covered");
        times.push(t.elapsed().as_secs_f64());
        out = Some((u, phases));
    }
    times.sort_by(f64::total_cmp);
    let time = times[runs / 2];
    let (fast, phases) = out.expect("one run at least");
    println!("fast {n} {name} {m:?} eps {eps:e}: {time:.3} s ({phases:.3?}), {settings:?}");
    if untimed {
        return;
    }
    let direct_time = direct.then(|| {
        let t = Instant::now();
        let d = system.apply(m, &x);
        (t.elapsed().as_secs_f64(), d)
    });
    let (error, over) = if n <= 20_000 {
        let d = match &direct_time {
            Some((_, d)) => d.clone(),
            None => system.apply(m, &x),
        };
        let num: f64 = fast.iter().zip(&d).map(|(a, b)| (a - b).powi(2)).sum();
        let den: f64 = d.iter().map(|b| b * b).sum();
        ((num / den).sqrt(), n)
    } else {
        let targets: Vec<usize> = (0..1000).map(|_| rng.gen_range(0..n)).collect();
        let rows = direct_rows(&conf, &ps, m, &x, &targets);
        let (mut num, mut den) = (0.0, 0.0);
        for (&i, row) in targets.iter().zip(&rows) {
            for (c, r) in row.iter().enumerate() {
                let at = if c < 3 {
                    3 * i + c
                } else {
                    3 * n + 3 * i + c - 3
                };
                num += (fast[at] - r).powi(2);
                den += r * r;
            }
        }
        ((num / den).sqrt(), targets.len())
    };
    if let Some((t, _)) = &direct_time {
        println!("direct: {t:.3} s");
    }
    println!("error {error:.2e} over {over} targets");
    println!(
        "result n={n} confinement={name} moments={m:?} eps={eps:e} time={time:.4} direct={} error={error:.3e} targets={over} peak_mib={:.0} tree={:.4} upward={:.4} across={:.4} downward={:.4} leaves={:.4}",
        direct_time.map_or("-".to_string(), |(t, _)| format!("{t:.4}")),
        peak_mib(),
        phases.tree,
        phases.upward,
        phases.across,
        phases.downward,
        phases.leaves
    );
}

/// One Brownian step of `system` with the fast product to `eps` (module docs).
fn brownian(system: System, m: Moments, eps: f64, name: &str) {
    use stokesian::{Brownian, ExternalForces, Noise, Scheme};
    let n = system.len();
    let fast = system.with_fmm(eps).expect("a tolerance in range");
    let bd = Brownian {
        kt: 1.0,
        dt: 1e-3,
        drift: true,
        forces: ExternalForces {
            weight: 1.0,
            ..ExternalForces::NONE
        },
        noise: Noise::Lanczos { tol: 1e-4 },
        hydrodynamics: true,
        moments: m,
        scheme: Scheme::EulerMaruyama,
        lubrication: None,
    };
    let t = Instant::now();
    let drift = fast.divergence_at(m);
    let drift_time = t.elapsed().as_secs_f64();
    assert_eq!(drift.len(), n * m.per_particle());
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let t = Instant::now();
    let step = fast.brownian_step(&bd, &mut rng, 0).expect("a step");
    let time = t.elapsed().as_secs_f64();
    let iterations = step.lanczos_iterations.expect("Lanczos noise");
    println!(
        "Brownian step {n} {name} {m:?} fmm {eps:e}: {time:.3} s, {iterations} Lanczos iterations, drift {drift_time:.4} s"
    );
    println!(
        "result n={n} confinement={name} moments={m:?} eps={eps:e} step={time:.4} lanczos={iterations} drift={drift_time:.4} peak_mib={:.0}",
        peak_mib()
    );
}
