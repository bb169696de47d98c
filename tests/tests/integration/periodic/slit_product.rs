//! The fast product in a periodic slit (the two walls' fast products, less the
//! Stokeslet's sum they share, plus the remainder's modes each on its own with the
//! heights interpolated) against the dense matrix of the direct sums (checked in `slit`
//! by no slip on both walls and a second evaluation): F and FT, equal and unequal radii,
//! spheres near either wall and across the gap, a box that is not square, a box smaller
//! than the real-space cut-off, at the tolerances asked; its bits do not depend on the
//! number of threads nor on moves by box lengths.

use super::slit::{periodic as system, BOTTOM};
use super::wall::ETA;
use super::wall_product::{laterally_periodic_spheres, rows_error};
use super::{product_error, same_bits_on_one_thread_and_two};
use rand::Rng;
use stokesian::periodic::slit::SlitEwald;
use stokesian::{Moments, Particle};

/// `n` spheres at random in the slit of gap `gap`, each at least `clear` from both walls.
fn spheres(
    seed: u64,
    n: usize,
    lengths: [f64; 2],
    gap: f64,
    clear: f64,
    a: Option<f64>,
) -> Vec<Particle> {
    laterally_periodic_spheres(seed, n, lengths, a, |rng, a| {
        BOTTOM + a + clear + rng.gen_range(0.0..gap - 2.0 * (a + clear))
    })
}

/// The fast product is the dense matrix's product to the tolerance asked, `1e-6` and
/// `1e-10`, F and FT: equal radii near both walls in a square box (gaps to the walls
/// down to 0.02), unequal radii in a wide slit in a box that is not square (the Faxén
/// fields of their own), three spheres in a box smaller than `r_c` (every lateral mode
/// of the walls' sums a low mode). As along one wall (`wall_product`), `tol` of the
/// result's largest entry is the bound the tolerance promises.
#[test]
fn the_fast_product_is_the_dense_product_to_the_tolerance() {
    let cases = [
        ([12.0, 12.0], 4.0, 24, 0.02, Some(1.0)),
        ([10.0, 13.5], 9.0, 24, 0.05, None),
        ([3.0, 4.0], 5.0, 3, 0.1, None),
    ];
    for tol in [1e-6, 1e-10] {
        for (seed, &(lengths, gap, n, clear, a)) in cases.iter().enumerate() {
            let ps = spheres(seed as u64, n, lengths, gap, clear, a);
            let s = system(ps, lengths, gap, tol);
            for moments in [Moments::F, Moments::FT] {
                let e = product_error(&s, moments, 3);
                println!(
                    "tol {tol:e}, box {lengths:?}, gap {gap}, radius {a:?}, {moments:?}: {e:e}"
                );
                assert!(e < tol, "{e:e} at tolerance {tol:e}");
            }
        }
    }
}

/// A monolayer of 500 spheres at area fraction 0.3 (box `72.4^2`, gap 5): the
/// remainder's modes (about 5500 and 10000) are cheaper on the lateral grid than one by one, which
/// the small systems above take. Two rows of the dense matrix against the same rows of
/// the fast product (as along one wall, `wall_product`), F and FT, at `1e-6` and `1e-10`,
/// unequal radii; its bits do not depend on the number of threads either.
#[test]
fn the_remainder_on_the_grid_is_the_dense_product_to_the_tolerance() {
    let n = 500;
    let side = (n as f64 * std::f64::consts::PI / 0.3).sqrt();
    let lengths = [side, side];
    let gap = 5.0;
    let ps = spheres(31, n, lengths, gap, 0.05, None);
    for tol in [1e-6, 1e-10] {
        let s = system(ps.clone(), lengths, gap, tol);
        if tol == 1e-6 {
            same_bits_on_one_thread_and_two(&s, &[Moments::F, Moments::FT]);
        }
        let dense = SlitEwald::new(lengths, BOTTOM, gap, tol, None);
        for moments in [Moments::F, Moments::FT] {
            let e = rows_error(&s, moments, 7, |a, b| {
                dense.blocks(ETA, &ps[a], &ps[b], a == b)
            });
            println!("tol {tol:e}, {moments:?}: {e:e}");
            assert!(e < tol, "{e:e} at tolerance {tol:e}");
        }
    }
}

/// The same product on one thread and on two: identical bits.
#[test]
fn the_fast_product_does_not_depend_on_the_threads() {
    let lengths = [16.0, 14.0];
    let s = system(
        spheres(11, 60, lengths, 5.0, 0.05, None),
        lengths,
        5.0,
        1e-6,
    );
    same_bits_on_one_thread_and_two(&s, &[Moments::F, Moments::FT]);
}

/// Moving spheres by box lengths (exact moves: coordinates on a grid of `2^-20`) gives
/// the same bits.
#[test]
fn a_box_length_changes_nothing() {
    let lengths = [8.0, 9.0];
    let grid = |v: f64| (v * 1048576.0).round() / 1048576.0;
    let ps: Vec<Particle> = spheres(5, 10, lengths, 4.5, 0.1, None)
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
    let s = system(ps, lengths, 4.5, 1e-8);
    let t = system(moved, lengths, 4.5, 1e-8);
    for moments in [Moments::F, Moments::FT] {
        let x: Vec<f64> = (0..moments.per_particle() * s.len())
            .map(|i| (i as f64 * 0.37).sin())
            .collect();
        assert_eq!(s.apply(moments, &x), t.apply(moments, &x), "{moments:?}");
    }
}
