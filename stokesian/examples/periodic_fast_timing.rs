//! The fast product's option in a triply periodic box against the fast multipole method
//! in open space on the same spheres: what docs/fmm.md's periodic section measures.
//! `N` unit spheres on a jittered cubic lattice at volume fraction 0.1, forces in random
//! directions, `System::with_fmm(EPS)` with and without the box (the box's own product,
//! linked cells and spectral Ewald, against the tree's): the median of three products
//! each, twice, alternating.
//!
//! `cargo run --release -p stokesian --example periodic_fast_timing -- N EPS`

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::time::Instant;
use stokesian::{Confinement, Moments, Particle, PeriodicBox, System};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let usage = "usage: periodic_fast_timing N EPS";
    let n: usize = args.get(1).and_then(|s| s.parse().ok()).expect(usage);
    let eps: f64 = args.get(2).and_then(|s| s.parse().ok()).expect(usage);
    let side = (n as f64 * 4.0 / 3.0 * std::f64::consts::PI / 0.1).cbrt();
    let k = (n as f64).cbrt().ceil() as usize;
    let h = side / k as f64;
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    // each sphere within its lattice cell, clear of the cell's faces by 0.05
    let jitter = (h - 2.1) / 2.0;
    let ps: Vec<Particle> = (0..n)
        .map(|i| {
            let cell = [i % k, (i / k) % k, i / (k * k)];
            Particle {
                x: std::array::from_fn(|d| {
                    (cell[d] as f64 + 0.5) * h + rng.gen_range(-jitter..jitter)
                }),
                a: 1.0,
            }
        })
        .collect();
    let x: Vec<f64> = (0..3 * n).map(|_| rng.gen_range(-1.0..1.0)).collect();
    let open = System::new(Confinement::Free, 1.0, ps, false).expect("spheres clear");
    let periodic = open
        .clone()
        .periodic(PeriodicBox::new([side; 3]))
        .expect("a valid box")
        .with_fmm(eps)
        .expect("a tolerance in range");
    let tree = open.with_fmm(eps).expect("a tolerance in range");
    for _ in 0..2 {
        for (name, s) in [("periodic box", &periodic), ("open, tree", &tree)] {
            let mut times: Vec<f64> = (0..3)
                .map(|_| {
                    let t = Instant::now();
                    std::hint::black_box(s.apply(Moments::F, &x));
                    t.elapsed().as_secs_f64()
                })
                .collect();
            times.sort_by(f64::total_cmp);
            println!(
                "{name:<12} N = {n}, box {side:.1}, eps {eps:e}: {:.3} s (median of 3)",
                times[1]
            );
        }
    }
}
