//! The fast product along a periodic wall (linked cells, spectral Ewald with Blake's
//! image sources, the mode `k_par = 0` interpolated in the heights) against the dense
//! matrix of the direct sums (checked against the brute-force lattice sum in `wall`): F
//! and FT, equal and unequal radii, a box that is not square, heights from near contact
//! to a few box lengths, a box smaller than the real-space cut-off, at the tolerances
//! asked; its bits do not depend on the number of threads nor on moves by box lengths.

use super::{product_error, same_bits_on_one_thread_and_two};
use kernels::BlocksFT;
use rand::{Rng, SeedableRng};
use rayon::prelude::*;
use stokesian::periodic::wall::WallEwald;
use stokesian::{Confinement, Moments, Overlap, Particle, PeriodicBox, System};

const ETA: f64 = 0.9;
const HEIGHT: f64 = -0.5;

fn system(ps: Vec<Particle>, lengths: [f64; 2], tolerance: f64) -> System {
    System::new(
        Confinement::Wall { height: HEIGHT },
        ETA,
        ps,
        Overlap::Refuse,
    )
    .unwrap()
    .periodic(PeriodicBox {
        tolerance,
        ..PeriodicBox::lateral(lengths)
    })
    .unwrap()
}

/// `n` spheres of radius `a` or, without it, radii in `[0.5, 1]`, at random laterally
/// in the box `lengths` with their gap to the wall in `gaps`, clear of each other (by
/// `0.05`) by their nearest lateral images.
fn spheres(
    seed: u64,
    n: usize,
    lengths: [f64; 2],
    gaps: (f64, f64),
    a: Option<f64>,
) -> Vec<Particle> {
    laterally_periodic_spheres(seed, n, lengths, a, |rng, a| {
        HEIGHT + a + rng.gen_range(gaps.0..gaps.1)
    })
}

/// `n` spheres of radius `a` or, without it, radii in `[0.5, 1]`, at random laterally
/// in the box `lengths`, each at the height `height(rng, radius)`, clear of each other
/// (by `0.05`) by their nearest lateral images.
pub(super) fn laterally_periodic_spheres(
    seed: u64,
    n: usize,
    lengths: [f64; 2],
    a: Option<f64>,
    mut height: impl FnMut(&mut rand_chacha::ChaCha8Rng, f64) -> f64,
) -> Vec<Particle> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut out: Vec<Particle> = Vec::new();
    while out.len() < n {
        let a = a.unwrap_or_else(|| rng.gen_range(0.5..1.0));
        let q = Particle {
            x: [
                rng.gen_range(0.0..lengths[0]),
                rng.gen_range(0.0..lengths[1]),
                height(&mut rng, a),
            ],
            a,
        };
        let clear = out.iter().all(|o| {
            let d2: f64 = (0..3)
                .map(|d| {
                    let r = o.x[d] - q.x[d];
                    match lengths.get(d) {
                        Some(l) => (r - l * (r / l).round()).powi(2),
                        None => r * r,
                    }
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

/// The fast product is the dense matrix's product to the tolerance asked, `1e-6` and
/// `1e-10`, F and FT: equal radii near contact with the wall in a square box, unequal
/// radii up to three box lengths above the wall in a box that is not square (the image
/// grids and the Faxén fields of their own; the interpolated mode `k_par = 0` over a
/// wide interval), three spheres in a box smaller than `r_c`. Both sums are truncated
/// at `tol` of each block's largest pair entry, and the product's largest entry is at
/// least about the self mobility times the largest force, so `tol` of the largest entry
/// of the result is the bound the tolerance promises.
#[test]
fn the_fast_product_is_the_dense_product_to_the_tolerance() {
    let cases = [
        ([12.0, 12.0], 30, (0.02, 2.0), Some(1.0)),
        ([10.0, 13.5], 30, (0.05, 30.0), None),
        ([3.0, 4.0], 3, (0.1, 5.0), None),
    ];
    for tol in [1e-6, 1e-10] {
        for (seed, &(lengths, n, gaps, a)) in cases.iter().enumerate() {
            let s = system(spheres(seed as u64, n, lengths, gaps, a), lengths, tol);
            for moments in [Moments::F, Moments::FT] {
                let e = product_error(&s, moments, 3);
                println!(
                    "tol {tol:e}, box {lengths:?}, radius {a:?}, gaps {gaps:?}, {moments:?}: {e:e}"
                );
                assert!(e < tol, "{e:e} at tolerance {tol:e}");
            }
        }
    }
}

/// The grid beside the low modes: 800 spheres at area fraction 0.3 (box `91.5^2`,
/// heights up to 5 radii), where the split takes the modes `|k_par| >= K1` on the grid
/// and the lower ones each on its own (the small systems above take every mode on its
/// own), equal and unequal radii, F and FT, at `1e-6` and `1e-10`. The dense matrix is
/// `O(N^2)`: two of its rows (a sphere's FT blocks with every sphere) against the same
/// rows of the fast product, relative to the fast product's largest entry. Its bits do
/// not depend on the number of threads either.
#[test]
fn the_grid_beside_the_low_modes_is_the_dense_product_to_the_tolerance() {
    let lengths = [91.5, 91.5];
    for tol in [1e-6, 1e-10] {
        for (seed, a) in [(21, Some(1.0)), (22, None)] {
            let ps = spheres(seed, 800, lengths, (0.5, 4.0), a);
            let s = system(ps.clone(), lengths, tol);
            if tol == 1e-6 {
                same_bits_on_one_thread_and_two(&s, &[Moments::F, Moments::FT]);
            }
            let dense = WallEwald::new(lengths, HEIGHT, tol, None);
            for moments in [Moments::F, Moments::FT] {
                let e = rows_error(&s, moments, seed, |a, b| {
                    dense.blocks(ETA, &ps[a], &ps[b], a == b)
                });
                println!("tol {tol:e}, radius {a:?}, {moments:?}: {e:e}");
                assert!(e < tol, "{e:e} at tolerance {tol:e}");
            }
        }
    }
}

/// The largest difference of two rows of the fast product of `s` at `moments` (its
/// first sphere's and its middle one's) from the same rows of the dense matrix, whose
/// FT blocks are `block(a, b)`, times a random vector (`seed`), relative to the fast
/// product's largest entry.
pub(super) fn rows_error(
    s: &System,
    moments: Moments,
    seed: u64,
    block: impl Fn(usize, usize) -> BlocksFT + Sync,
) -> f64 {
    let n = s.len();
    let k = moments.per_particle();
    let rows: Vec<[[[f64; 6]; 6]; 2]> = (0..n)
        .into_par_iter()
        .map(|b| [0, n / 2].map(|a| block(a, b).matrix()))
        .collect();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let x: Vec<f64> = (0..k * n).map(|_| rng.gen_range(-1.0..1.0)).collect();
    let got = s.apply(moments, &x);
    let scale = got.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut e = 0.0f64;
    for (r, a) in [0, n / 2].into_iter().enumerate() {
        for i in 0..k {
            let want: f64 = (0..n)
                .flat_map(|b| (0..k).map(move |j| (b, j)))
                .map(|(b, j)| rows[b][r][i][j] * x[3 * (j / 3) * n + 3 * b + j % 3])
                .sum();
            e = e.max((want - got[3 * (i / 3) * n + 3 * a + i % 3]).abs() / scale);
        }
    }
    e
}

/// Spheres spread over a hundred radii above the wall in a small box: the heights need
/// more Chebyshev points than the low modes take, so no mode is low and the grid, padded
/// for the box's smallest wave number, holds every mode `k_par != 0`. Against the dense
/// matrix as above.
#[test]
fn very_tall_spheres_in_a_small_box_are_the_dense_product_to_the_tolerance() {
    let lengths = [3.0, 4.0];
    let ps: Vec<Particle> = [
        [0.3, 0.5, 1.2, 0.6],
        [1.7, 2.9, 35.0, 1.0],
        [2.4, 1.1, 70.0, 0.8],
        [0.9, 3.6, 105.0, 0.5],
    ]
    .iter()
    .map(|&[x, y, h, a]| Particle {
        x: [x, y, HEIGHT + h],
        a,
    })
    .collect();
    for tol in [1e-6, 1e-10] {
        let s = system(ps.clone(), lengths, tol);
        for moments in [Moments::F, Moments::FT] {
            let e = product_error(&s, moments, 5);
            println!("tol {tol:e}, {moments:?}: {e:e}");
            assert!(e < tol, "{e:e} at tolerance {tol:e}");
        }
    }
}

/// The same product on one thread and on two: identical bits (every sum in a fixed
/// order).
#[test]
fn the_fast_product_does_not_depend_on_the_threads() {
    let lengths = [20.0, 18.0];
    let s = system(spheres(11, 120, lengths, (0.05, 4.0), None), lengths, 1e-6);
    same_bits_on_one_thread_and_two(&s, &[Moments::F, Moments::FT]);
}

/// Moving spheres by box lengths (exact moves: coordinates on a grid of `2^-20`) gives
/// the same bits, a million boxes away too: the kernels and grids see the wrapped
/// positions.
#[test]
fn a_box_length_changes_nothing() {
    let lengths = [8.0, 9.0];
    let grid = |v: f64| (v * 1048576.0).round() / 1048576.0;
    let ps: Vec<Particle> = spheres(5, 12, lengths, (0.1, 3.0), None)
        .into_iter()
        .map(|q| Particle {
            x: q.x.map(grid),
            a: q.a,
        })
        .collect();
    let mut moved = ps.clone();
    moved[2].x[0] += 8.0;
    moved[4].x[1] -= 9.0 * 1048576.0;
    moved[7].x[0] -= 16.0;
    let (s, t) = (system(ps, lengths, 1e-8), system(moved, lengths, 1e-8));
    for moments in [Moments::F, Moments::FT] {
        let x: Vec<f64> = (0..moments.per_particle() * s.len())
            .map(|i| (i as f64 * 0.37).sin())
            .collect();
        assert_eq!(s.apply(moments, &x), t.apply(moments, &x), "{moments:?}");
    }
}
