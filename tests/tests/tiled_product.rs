//! The tiled matrix-free product (`System::apply`: lane kernels, tiles of 64 particles,
//! rounds of disjoint tiles) equals the dense matrix times the vector on every
//! instruction set, for every confinement and truncation, and its result does not
//! depend on the number of threads.

use integration_tests::{all_confinements, random_spheres};
use nalgebra::DVector;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use stokesian::{Isa, Moments, System};

/// 1e-13 of `|M x|`: the same kernels summed in another order, the lanes with fused
/// multiply-adds (lanes = scalar to 1e-14 per pair, `tests/lanes.rs`).
#[test]
fn tiled_product_equals_the_dense_matrix_on_every_instruction_set() {
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    for (name, conf) in all_confinements() {
        // 150 spheres: three blocks, the last one partly padding
        let ps = random_spheres(&mut rng, &conf, 150, (0.4, 1.2), 0.05, 40.0);
        let s = System::new(conf, 0.9, ps, false).unwrap();
        for moments in [Moments::F, Moments::FT, Moments::FTS] {
            let m = s.mobility(moments);
            let x: Vec<f64> = (0..m.ncols()).map(|_| rng.gen_range(-1.0..1.0)).collect();
            let dense = &m * DVector::from_column_slice(&x);
            for isa in Isa::all_available() {
                let got = s.apply_with_isa(moments, &x, isa);
                let d = (DVector::from_column_slice(&got) - &dense).norm();
                assert!(
                    d <= 1e-13 * dense.norm(),
                    "{name} {moments:?} {isa:?}: |tiled - dense| / |dense| = {:e}",
                    d / dense.norm()
                );
            }
        }
    }
}

/// Bit for bit the same with 1, 2 and 3 threads, on every instruction set: the tiles'
/// schedule fixes the order of every sum.
#[test]
fn tiled_product_does_not_depend_on_the_number_of_threads() {
    let mut rng = ChaCha8Rng::seed_from_u64(22);
    let (_, conf) = all_confinements()
        .into_iter()
        .find(|(n, _)| *n == "wall")
        .unwrap();
    // 300 spheres: five blocks, rounds of two tiles
    let ps = random_spheres(&mut rng, &conf, 300, (0.4, 1.2), 0.05, 60.0);
    let s = System::new(conf, 1.0, ps, false).unwrap();
    for moments in [Moments::F, Moments::FT] {
        let x: Vec<f64> = (0..300 * moments.per_particle())
            .map(|_| rng.gen_range(-1.0..1.0))
            .collect();
        for isa in Isa::all_available() {
            let with = |threads: usize| {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap()
                    .install(|| s.apply_with_isa(moments, &x, isa))
            };
            let one = with(1);
            for threads in [2, 3] {
                let other = with(threads);
                let same = one
                    .iter()
                    .zip(&other)
                    .all(|(a, b)| a.to_bits() == b.to_bits());
                assert!(same, "{moments:?} {isa:?}: 1 and {threads} threads differ");
            }
        }
    }
}
