//! Time the fast product against the direct one for a monolayer above a wall:
//! `cargo run --release -p stokesian --example fmm_timing -- N EPS [F|FT] [direct]`.

use std::time::Instant;
use stokesian::{Confinement, Moments, Particle, System};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).map_or(10_000, |s| s.parse().unwrap());
    let eps: f64 = args.get(2).map_or(1e-6, |s| s.parse().unwrap());
    let m = match args.get(3).map(String::as_str) {
        Some("FT") => Moments::FT,
        _ => Moments::F,
    };
    let direct = args.get(4).is_some_and(|s| s == "direct");
    // a jittered square lattice of unit spheres, area fraction 0.3, heights 1.5 to 5
    let side = (std::f64::consts::PI / 0.3).sqrt();
    let k = (n as f64).sqrt().ceil() as usize;
    let mut state = 12345u64;
    let mut uniform = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let ps: Vec<Particle> = (0..n)
        .map(|i| {
            let (a, b) = ((i % k) as f64, (i / k) as f64);
            let j = (side - 2.05) / 2.0;
            Particle {
                x: [
                    a * side + j * (2.0 * uniform() - 1.0),
                    b * side + j * (2.0 * uniform() - 1.0),
                    1.5 + 3.5 * uniform(),
                ],
                a: 1.0,
            }
        })
        .collect();
    let system = System::new(Confinement::Wall { height: 0.0 }, 1.0, ps, false).unwrap();
    let x: Vec<f64> = (0..n * m.per_particle()).map(|_| uniform() - 0.5).collect();
    let t = Instant::now();
    let mut settings = stokesian::FastProduct::new(eps).unwrap();
    if let Some(v) = std::env::var("FMM_LEAF").ok().and_then(|s| s.parse().ok()) {
        settings.leaf = v;
    }
    if let Some(v) = std::env::var("FMM_THETA").ok().and_then(|s| s.parse().ok()) {
        settings.theta = v;
    }
    if let Some(v) = std::env::var("FMM_ORDER").ok().and_then(|s| s.parse().ok()) {
        settings.order = v;
    }
    let (fast, phases) = system.apply_fast_timed(m, &x, &settings).unwrap();
    println!(
        "fast {n} {m:?} eps {eps:e}: {:.3} s ({phases:.3?})",
        t.elapsed().as_secs_f64()
    );
    if direct {
        let t = Instant::now();
        let d = system.apply(m, &x);
        println!("direct: {:.3} s", t.elapsed().as_secs_f64());
        let num: f64 = fast
            .iter()
            .zip(&d)
            .map(|(a, b)| (a - b).powi(2))
            .sum::<f64>();
        let den: f64 = d.iter().map(|b| b * b).sum::<f64>();
        println!("error {:.2e}", (num / den).sqrt());
    }
}
