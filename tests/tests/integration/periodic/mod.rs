//! Triply periodic boxes ([`stokesian::periodic`]): the Ewald sums against Hasimoto's
//! periodic self mobility and against the windowed sum over replicas of the open RPY
//! mobility (`ewald`); the split parameter changes nothing; the system's matrices,
//! products and refusals (`system`); the resistance with lubrication over every image
//! (`lubrication`); the fast product (cells and spectral Ewald) against the dense
//! matrix, and its bits whatever the threads (`spectral`).
//! Boxes periodic along a wall: the Ewald sums against the brute-force sum over shells
//! of the open wall's images, and the system (`wall`); the fast product along the wall
//! against the dense matrix (`wall_product`). The periodic slit: its Green's function
//! (`slit`) and its fast product against the dense matrix (`slit_product`).

mod ewald;
mod fmm;
mod lubrication;
mod slit;
mod slit_product;
mod spectral;
mod system;
mod wall;
mod wall_product;

use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use stokesian::{Moments, Particle, System};

/// `n` spheres of radius `a` or, without it, radii in `[0.5, 1]`, at random in a box
/// of `lengths`, clear of each other (by `0.05`) by their nearest images.
fn spheres(seed: u64, n: usize, lengths: [f64; 3], a: Option<f64>) -> Vec<Particle> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut out: Vec<Particle> = Vec::new();
    while out.len() < n {
        let q = Particle {
            x: std::array::from_fn(|d| rng.gen_range(0.0..lengths[d])),
            a: a.unwrap_or_else(|| rng.gen_range(0.5..1.0)),
        };
        let clear = out.iter().all(|o| {
            let d2: f64 = (0..3)
                .map(|d| {
                    let r = o.x[d] - q.x[d];
                    (r - lengths[d] * (r / lengths[d]).round()).powi(2)
                })
                .sum();
            d2.sqrt() > o.a + q.a + 0.05
        });
        if clear {
            out.push(q);
        }
    }
    out
}

/// The largest difference of the fast product from the dense matrix's (of the direct
/// sums, at the same tolerance) times a random vector, relative to the largest entry of
/// the result.
fn product_error(s: &System, moments: Moments, seed: u64) -> f64 {
    let m = s.mobility(moments);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let x: Vec<f64> = (0..m.nrows()).map(|_| rng.gen_range(-1.0..1.0)).collect();
    let want = &m * DMatrix::from_column_slice(x.len(), 1, &x);
    let got = s.apply(moments, &x);
    let scale = want.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let diff = want
        .iter()
        .zip(&got)
        .fold(0.0f64, |a, (w, g)| a.max((w - g).abs()));
    diff / scale
}

/// The fast product `M x` of `s` at each of `moments` on one thread and on two:
/// identical bits.
fn same_bits_on_one_thread_and_two(s: &System, moments: &[Moments]) {
    for &moments in moments {
        let x: Vec<f64> = (0..moments.per_particle() * s.len())
            .map(|i| (i as f64 * 0.61).cos())
            .collect();
        let run = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| s.apply(moments, &x))
        };
        let (one, two) = (run(1), run(2));
        assert!(
            one.iter()
                .zip(&two)
                .all(|(a, b)| a.to_bits() == b.to_bits()),
            "{moments:?}"
        );
    }
}
