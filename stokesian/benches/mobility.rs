//! Criterion benchmarks: time per pair of each scene's kernels; matrix-free products
//! near a wall (F and FT, N = 1e2, 1e3, 1e4); dense FTS assembly (N = 1e2, 1e3); Brownian
//! steps near a wall (F, N = 10, 100, 1000, Cholesky and Lanczos noise).
//! Run with `cargo bench -p stokesian`.
#![allow(missing_docs)] // criterion_group! generates undocumented items

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use kernels::{pair, pair_equal, pair_f, pair_ft, product_f, product_ft, Confinement};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::time::Duration;
use stokesian::{Moments, Particle, System};

/// `n` unit spheres at random in a box above a wall at z = 0, volume fraction about 5%
/// (hard-sphere rejection), heights from 1.1 a.
fn suspension(n: usize, seed: u64) -> Vec<Particle> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let side = (n as f64 * 4.19 / 0.05).cbrt();
    let cell = 2.2;
    let per = (side / cell).ceil() as usize;
    // jittered lattice: no overlaps by construction, O(n)
    let mut ps = Vec::with_capacity(n);
    'outer: for i in 0..per {
        for j in 0..per {
            for k in 0..per {
                if ps.len() == n {
                    break 'outer;
                }
                let jit = |r: &mut ChaCha8Rng| r.gen_range(-0.05..0.05);
                ps.push(Particle {
                    x: [
                        cell * i as f64 + jit(&mut rng),
                        cell * j as f64 + jit(&mut rng),
                        1.1 + cell * k as f64 + jit(&mut rng).abs(),
                    ],
                    a: 1.0,
                });
            }
        }
    }
    ps
}

fn per_pair(c: &mut Criterion) {
    let mut g = c.benchmark_group("pair kernel");
    let (xa, xb) = ([0.1, 0.2, 1.7], [2.9, -1.3, 2.4]);
    let confs = [
        ("free", Confinement::Free),
        ("wall", Confinement::Wall { height: 0.0 }),
        ("free_surface", Confinement::FreeSurface { height: 0.0 }),
        (
            "interface",
            Confinement::Interface {
                height: 0.0,
                lambda: 2.0,
            },
        ),
        (
            "slit",
            Confinement::Slit {
                height: 0.0,
                gap: 20.0,
            },
        ),
    ];
    for (name, conf) in confs {
        g.bench_function(BenchmarkId::new("F", name), |b| {
            b.iter(|| {
                pair_f(
                    black_box(&conf),
                    1.0,
                    black_box(xa),
                    1.0,
                    black_box(xb),
                    0.7,
                )
            })
        });
        g.bench_function(BenchmarkId::new("F product, equal", name), |b| {
            b.iter(|| {
                product_f(
                    black_box(&conf),
                    1.0,
                    black_box(xa),
                    1.0,
                    black_box(xb),
                    1.0,
                    [1.0, 0.0, 0.0],
                    [0.0, 1.0, 0.0],
                )
            })
        });
        g.bench_function(BenchmarkId::new("FT", name), |b| {
            b.iter(|| {
                pair_ft(
                    black_box(&conf),
                    1.0,
                    black_box(xa),
                    1.0,
                    black_box(xb),
                    0.7,
                )
            })
        });
        g.bench_function(BenchmarkId::new("FT product, equal", name), |b| {
            b.iter(|| {
                product_ft(
                    black_box(&conf),
                    1.0,
                    black_box(xa),
                    1.0,
                    black_box(xb),
                    1.0,
                    [1.0; 6],
                    [0.5; 6],
                )
            })
        });
        g.bench_function(BenchmarkId::new("FTS", name), |b| {
            b.iter(|| {
                pair(
                    black_box(&conf),
                    1.0,
                    black_box(xa),
                    1.0,
                    black_box(xb),
                    0.7,
                )
            })
        });
        g.bench_function(BenchmarkId::new("FTS, equal", name), |b| {
            b.iter(|| pair_equal(black_box(&conf), 1.0, black_box(xa), black_box(xb), 1.0))
        });
    }
    g.finish();
}

fn products(c: &mut Criterion) {
    let mut g = c.benchmark_group("wall product M x");
    g.sample_size(10).measurement_time(Duration::from_secs(20));
    for n in [100usize, 1000, 10000] {
        let s = System::new(
            Confinement::Wall { height: 0.0 },
            1.0,
            suspension(n, 1),
            false,
        )
        .unwrap();
        for moments in [Moments::F, Moments::FT] {
            let x: Vec<f64> = (0..moments.per_particle() * n)
                .map(|k| (k % 7) as f64 - 3.0)
                .collect();
            g.bench_with_input(BenchmarkId::new(format!("{moments:?}"), n), &x, |b, x| {
                b.iter(|| s.apply(moments, black_box(x)))
            });
        }
    }
    g.finish();
}

fn dense(c: &mut Criterion) {
    let mut g = c.benchmark_group("wall dense FTS assembly");
    g.sample_size(10).measurement_time(Duration::from_secs(20));
    for n in [100usize, 1000] {
        let s = System::new(
            Confinement::Wall { height: 0.0 },
            1.0,
            suspension(n, 2),
            false,
        )
        .unwrap();
        g.bench_function(BenchmarkId::from_parameter(n), |b| {
            b.iter(|| s.mobility(Moments::FTS))
        });
    }
    g.finish();
}

fn brownian(c: &mut Criterion) {
    use stokesian::{Brownian, ExternalForces, Noise, Scheme};
    let mut g = c.benchmark_group("wall Brownian step");
    g.sample_size(10).measurement_time(Duration::from_secs(30));
    let variants = [
        ("EM Cholesky", Scheme::EulerMaruyama, Noise::Cholesky),
        (
            "EM Lanczos 1e-6",
            Scheme::EulerMaruyama,
            Noise::Lanczos { tol: 1e-6 },
        ),
        ("Fixman Cholesky", Scheme::FixmanMidpoint, Noise::Cholesky),
    ];
    for n in [10usize, 100, 1000] {
        let s = System::new(
            Confinement::Wall { height: 0.0 },
            1.0,
            suspension(n, 3),
            false,
        )
        .unwrap();
        for moments in [Moments::F, Moments::FT] {
            for (name, scheme, noise) in variants {
                // two dense factorisations of a 6000 x 6000 FT matrix per Fixman step take
                // minutes per sample: N = 1000 FT is measured with Euler-Maruyama only
                if n == 1000 && moments == Moments::FT && scheme == Scheme::FixmanMidpoint {
                    continue;
                }
                let bd = Brownian {
                    hydrodynamics: true,
                    moments,
                    scheme,
                    kt: 1.0,
                    dt: 1e-4,
                    drift: true,
                    forces: ExternalForces {
                        weight: 1.0,
                        strength: 0.0,
                        debye: 1.0,
                        trap: 0.0,
                        torque: if moments == Moments::FT {
                            [0.0, 1.0, 0.0]
                        } else {
                            [0.0; 3]
                        },
                    },
                    noise,
                };
                let mut rng = ChaCha8Rng::seed_from_u64(5);
                let id = BenchmarkId::new(format!("{moments:?} {name}"), n);
                g.bench_function(id, |b| {
                    b.iter(|| s.brownian_step(&bd, &mut rng, 0).unwrap())
                });
            }
        }
    }
    g.finish();
}

criterion_group!(benches, per_pair, products, dense, brownian);
criterion_main!(benches);
