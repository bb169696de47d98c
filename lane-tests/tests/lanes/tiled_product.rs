//! The tiled matrix-free product (`System::apply`: lane kernels, tiles of 64 particles,
//! rounds of disjoint tiles) equals the dense matrix times the vector on every
//! instruction set, for every confinement and truncation, and its result does not
//! depend on the number of threads.

use integration_tests::{all_confinements, random_spheres};
use nalgebra::DVector;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use stokesian::mobility::tiled::rounds;
use stokesian::{Isa, Moments, Precision, System};

/// 1e-13 of `|M x|`: the same kernels summed in another order, the lanes with fused
/// multiply-adds (lanes = scalar to 1e-14 per pair, `scalar.rs`).
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
                let got = s.apply_with(moments, &x, isa, Precision::Double);
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

/// The dense assembly (tiles of particle groups) puts every block where the layout of
/// Eq. 1 says, exactly as `System::block` returns it (the lane kernels of each
/// truncation, which `scalar.rs` compares with the scalar kernels): `M^{ab}` for
/// `a <= b` and its transpose below, the self blocks on the diagonal, equal radii too.
/// 37 spheres: more than the serial threshold, three groups, the last one partial.
/// Compared bit for bit: the assembly copies values and computes none. The same into a
/// `LargeMatrix` filled with NaN (`System::mobility_into` writes every entry).
#[test]
fn dense_assembly_places_every_block_exactly() {
    let mut rng = ChaCha8Rng::seed_from_u64(24);
    for (name, conf) in all_confinements() {
        let mut ps = random_spheres(&mut rng, &conf, 37, (0.4, 1.2), 0.05, 40.0);
        // a few equal radii; shrinking keeps them apart
        for p in ps.iter_mut().step_by(5) {
            p.a = 0.4;
        }
        let s = System::new(conf, 0.9, ps, false).unwrap();
        let n = s.len();
        for moments in [Moments::F, Moments::FT, Moments::FTS] {
            let k = moments.per_particle();
            let m = s.mobility(moments);
            // the same matrix assembled into memory of the caller's, over NaN: every
            // entry is written
            let mut large = stokesian::linalg::LargeMatrix::zeros(k * n, k * n).unwrap();
            large.as_mut_slice().fill(f64::NAN);
            s.mobility_into(moments, large.as_mut_slice());
            assert!(
                large
                    .as_slice()
                    .iter()
                    .zip(m.as_slice())
                    .all(|(x, y)| x.to_bits() == y.to_bits()),
                "{name} {moments:?}: mobility_into differs from mobility"
            );
            // component i of particle a in the moment-major layout
            let at = |a: usize, i: usize| match i {
                0..3 => 3 * a + i,
                3..6 => 3 * n + 3 * a + i - 3,
                _ => 6 * n + 5 * a + i - 6,
            };
            for a in 0..n {
                for b in a..n {
                    let blk = s.block(moments, a, b);
                    for i in 0..k {
                        for j in 0..k {
                            let v = blk[(i, j)];
                            assert_eq!(
                                m[(at(a, i), at(b, j))].to_bits(),
                                v.to_bits(),
                                "{name} {moments:?} M^{{{a}{b}}}[{i}][{j}]"
                            );
                            assert_eq!(
                                m[(at(b, j), at(a, i))].to_bits(),
                                v.to_bits(),
                                "{name} {moments:?} M^{{{b}{a}}}[{j}][{i}]"
                            );
                        }
                    }
                }
            }
        }
    }
}

/// The first confinement whose tiles order the particles along a normal (the kernels
/// without the exchange of roles, `Confinement::exchange_normal`): the most involved
/// schedule.
fn ordering() -> kernels::Confinement {
    all_confinements()
        .into_iter()
        .map(|(_, c)| c)
        .find(|c| c.exchange_normal().is_some())
        .expect("a confinement whose kernels exchange roles")
}

/// Bit for bit the same with 1, 2 and 3 threads, on every instruction set, in double
/// and single precision: the tiles' schedule fixes the order of every sum.
#[test]
fn tiled_product_does_not_depend_on_the_number_of_threads() {
    let mut rng = ChaCha8Rng::seed_from_u64(22);
    let conf = ordering();
    // 300 spheres: five blocks, rounds of two tiles
    let ps = random_spheres(&mut rng, &conf, 300, (0.4, 1.2), 0.05, 60.0);
    let s = System::new(conf, 1.0, ps, false).unwrap();
    for moments in [Moments::F, Moments::FT] {
        let x: Vec<f64> = (0..300 * moments.per_particle())
            .map(|_| rng.gen_range(-1.0..1.0))
            .collect();
        for isa in Isa::all_available() {
            for precision in [Precision::Double, Precision::Single] {
                let with = |threads: usize| {
                    rayon::ThreadPoolBuilder::new()
                        .num_threads(threads)
                        .build()
                        .unwrap()
                        .install(|| s.apply_with(moments, &x, isa, precision))
                };
                let one = with(1);
                for threads in [2, 3] {
                    let other = with(threads);
                    let same = one
                        .iter()
                        .zip(&other)
                        .all(|(a, b)| a.to_bits() == b.to_bits());
                    assert!(
                        same,
                        "{moments:?} {isa:?} {precision:?}: 1 and {threads} threads differ"
                    );
                }
            }
        }
    }
}

/// The Brownian drift through the tiles (`System::divergence_at`: the divergence lane
/// kernels) equals the plain sum over pairs of the scalar divergence kernels, for every
/// confinement (1e-13 of its norm: the same kernels, lanes with fused multiply-adds,
/// summed in another order; plus a floor of 1e-13 of n times the largest pair drift
/// scale, for free space where the exact drift vanishes), and is bit for bit the same
/// with 1 and 3 threads.
#[test]
fn tiled_drift_equals_the_scalar_pair_sum_and_ignores_the_thread_count() {
    use kernels::{pair_divergence, self_divergence};
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    for (name, conf) in all_confinements() {
        let ps = random_spheres(&mut rng, &conf, 90, (0.4, 1.2), 0.05, 30.0);
        let n = ps.len();
        let mut want = vec![0.0; 6 * n];
        let mut add = |a: usize, v: &[f64; 6]| {
            for i in 0..3 {
                want[3 * a + i] += v[i];
                want[3 * n + 3 * a + i] += v[3 + i];
            }
        };
        for a in 0..n {
            add(a, &self_divergence(&conf, 0.8, ps[a].x, ps[a].a).a);
            for b in a + 1..n {
                let d = pair_divergence(&conf, 0.8, ps[a].x, ps[a].a, ps[b].x, ps[b].a);
                add(a, &d.a);
                add(b, &d.b);
            }
        }
        let s = System::new(conf, 0.8, ps, false).unwrap();
        let with = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| s.divergence_at(Moments::FT))
        };
        let got = with(1);
        let d = (DVector::from_column_slice(&got) - DVector::from_column_slice(&want)).norm();
        let scale = DVector::from_column_slice(&want).norm();
        // free space: the exact drift is zero and both sums are round-off, so the
        // floor is 1e-13 of one pair's drift scale 1 / (8 pi eta a^2) times n
        let floor = 1e-13 * n as f64 / (8.0 * std::f64::consts::PI * 0.8 * 0.16);
        assert!(
            d <= 1e-13 * scale + floor,
            "{name}: |tiled - sum| = {d:e}, |sum| = {scale:e}"
        );
        let other = with(3);
        assert!(
            got.iter()
                .zip(&other)
                .all(|(a, b)| a.to_bits() == b.to_bits()),
            "{name}: 1 and 3 threads differ"
        );
    }
}

/// A seeded Brownian run (Euler-Maruyama with the generated drift, Cholesky and Lanczos
/// noise, F and FT) is bit for bit the same with 1 and 3 threads: the drift and the
/// matrix-free products go through the tiles, the dense matrix is assembled entry by
/// entry from the same kernels.
#[test]
fn seeded_brownian_runs_do_not_depend_on_the_number_of_threads() {
    use stokesian::{Brownian, ExternalForces, Noise, Scheme};
    let mut rng = ChaCha8Rng::seed_from_u64(24);
    let conf = ordering();
    // 80 spheres: above the size from which the pair loops run in parallel
    let ps = random_spheres(&mut rng, &conf, 80, (0.5, 1.0), 0.2, 25.0);
    let s = System::new(conf, 1.0, ps, false).unwrap();
    for moments in [Moments::F, Moments::FT] {
        for noise in [Noise::Cholesky, Noise::Lanczos { tol: 1e-8 }] {
            let bd = Brownian {
                noise,
                hydrodynamics: true,
                lubrication: None,
                moments,
                scheme: Scheme::EulerMaruyama,
                kt: 1.0,
                dt: 1e-4,
                drift: true,
                forces: ExternalForces {
                    weight: 1.0,
                    strength: 0.0,
                    debye: 1.0,
                    trap: 0.0,
                    torque: if moments == Moments::FT {
                        [0.0, 0.3, 0.0]
                    } else {
                        [0.0; 3]
                    },
                },
            };
            let run = |threads: usize| {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap()
                    .install(|| {
                        let mut noise = ChaCha8Rng::seed_from_u64(7);
                        let mut sys = s.clone();
                        for step in 0..3 {
                            sys = sys.brownian_step(&bd, &mut noise, step).unwrap().system;
                        }
                        sys.particles()
                            .iter()
                            .flat_map(|p| p.x)
                            .map(f64::to_bits)
                            .collect::<Vec<u64>>()
                    })
            };
            assert_eq!(run(1), run(3), "{moments:?} {noise:?}");
        }
    }
}

/// The rounds of the tiled product: every tile of the upper triangle once, and the tiles of
/// one round touch disjoint blocks (so that a round's tiles write in parallel).
#[test]
fn rounds_cover_every_tile_once_with_disjoint_blocks() {
    for blocks in 1..12 {
        let r = rounds(blocks);
        let mut seen = std::collections::BTreeSet::new();
        for round in &r {
            let mut used = std::collections::BTreeSet::new();
            for &(i, j) in round {
                assert!(i <= j);
                assert!(
                    used.insert(i) && (i == j || used.insert(j)),
                    "{blocks}: {round:?}"
                );
                assert!(seen.insert((i, j)));
            }
        }
        assert_eq!(seen.len(), blocks * (blocks + 1) / 2);
    }
}
