//! The fast periodic product (linked cells and spectral Ewald) against the dense
//! matrix of the direct sums: F, FT and FTS, unequal radii, a box that is not a cube, at
//! the tolerances asked; its bits do not depend on the number of threads.

use super::{product_error, same_bits_on_one_thread_and_two, spheres};
use stokesian::{Confinement, Moments, Overlap, Particle, PeriodicBox, System};

const ETA: f64 = 0.9;

fn system(ps: Vec<Particle>, lengths: [f64; 3], tolerance: f64) -> System {
    System::new(Confinement::Free, ETA, ps, Overlap::Refuse)
        .unwrap()
        .periodic(PeriodicBox {
            tolerance,
            ..PeriodicBox::new(lengths)
        })
        .unwrap()
}

/// The fast product is the dense matrix's product to the tolerance asked, `1e-6` and
/// `1e-10`, F, FT and FTS (the stresslets and strain rates through the same grid and
/// cells): equal radii in a cube, unequal radii (the Faxén factors on grids
/// of their own) in a box that is not a cube, and three spheres in a small box (the
/// real-space cut-off beyond the box: images of a sphere's own cell). Both sums are
/// truncated at `tol` of each block's largest pair entry; a product adds `N` blocks'
/// errors of either sign, and its largest entry is at least about the self mobility
/// times the largest force, so `tol` of the largest entry of the result is the bound
/// the tolerance promises (measured: a third of it or less).
#[test]
fn the_fast_product_is_the_dense_product_to_the_tolerance() {
    let cases = [
        ([10.0, 10.0, 10.0], 40, Some(1.0)),
        ([9.0, 11.0, 13.5], 40, None),
        ([3.0, 4.0, 5.0], 3, None),
    ];
    for tol in [1e-6, 1e-10] {
        for (seed, &(lengths, n, a)) in cases.iter().enumerate() {
            let s = system(spheres(seed as u64, n, lengths, a), lengths, tol);
            for moments in [Moments::F, Moments::FT, Moments::FTS] {
                let e = product_error(&s, moments, 3);
                println!("tol {tol:e}, box {lengths:?}, radius {a:?}, {moments:?}: {e:e}");
                assert!(e < tol, "{e:e} at tolerance {tol:e}");
            }
        }
    }
}

/// The same product on one thread and on two: identical bits (every sum in a fixed
/// order: the real part row by row over the cells, the grid plane by plane, the
/// transforms line by line).
#[test]
fn the_fast_product_does_not_depend_on_the_threads() {
    let lengths = [14.0, 15.0, 16.0];
    let s = system(spheres(11, 150, lengths, None), lengths, 1e-6);
    same_bits_on_one_thread_and_two(&s, &[Moments::F, Moments::FT, Moments::FTS]);
}

/// One sphere in a cube through the fast product: Hasimoto's self mobility `(1 -
/// 2.8372974794806 x + (4 pi/3) x^3)/(6 pi eta a)`, `x = a/L`, exact for the RPY tensor
/// (an independent reference; the dense sums meet it to 1e-12 in `periodic::ewald`), to
/// the tolerance 1e-10 asked; libMobility's PSE test of the same case (radius 2, box 16)
/// asks 1e-6.
#[test]
fn the_fast_product_gives_hasimotos_self_mobility() {
    for (a, l) in [(2.0, 16.0), (1.0, 10.0), (1.0, 40.0)] {
        let s = system(
            vec![Particle {
                x: [1.0, 2.0, 3.0],
                a,
            }],
            [l; 3],
            1e-10,
        );
        let u = s.apply(Moments::F, &[1.0, 0.0, 0.0]);
        let x = a / l;
        let want = (1.0 - 2.8372974794806 * x + 4.0 * std::f64::consts::PI / 3.0 * x.powi(3))
            / (6.0 * std::f64::consts::PI * ETA * a);
        assert!((u[0] - want).abs() < 1e-10 * want, "{} vs {want}", u[0]);
        assert!(u[1].abs() < 1e-10 * want && u[2].abs() < 1e-10 * want);
    }
}
