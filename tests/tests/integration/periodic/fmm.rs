//! The fast product's option in a periodic box (`System::with_fmm`, `apply_fmm`): the box's
//! own fast product (linked cells and spectral Ewald) with its lattice sums to `eps`,
//! within `eps` of the exact product in the relative 2-norm, as in open boundaries
//! (`crate::fmm`). The reference is the dense matrix of the direct Ewald sums at `1e-13`
//! (pair by pair over images and wave vectors: independent of the grids and cells).

use super::spheres;
use super::wall_product::laterally_periodic_spheres;
use integration_tests::{falling, rel_diff};
use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use stokesian::{Confinement, FastProduct, Moments, Overlap, PeriodicBox, System};

/// The relative 2-norm error of the fast product at each tolerance, F and FT, printed and
/// asserted below the tolerance; `with_fmm` before and after the box give the same
/// product, and `apply_fmm` the one `with_fmm` makes `apply`.
fn check(label: &str, open: &System, bx: PeriodicBox) {
    let exact = open
        .clone()
        .periodic(PeriodicBox {
            tolerance: 1e-13,
            ..bx
        })
        .unwrap();
    let periodic = open.clone().periodic(bx).unwrap();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
    for moments in [Moments::F, Moments::FT] {
        let m = exact.mobility(moments);
        let x: Vec<f64> = (0..m.nrows()).map(|_| rng.gen_range(-1.0..1.0)).collect();
        let want: Vec<f64> = (&m * DMatrix::from_column_slice(x.len(), 1, &x))
            .iter()
            .copied()
            .collect();
        for eps in [1e-3, 1e-6, 1e-9] {
            let fast = periodic.clone().with_fmm(eps).unwrap();
            let got = fast.apply(moments, &x);
            let e = rel_diff(&got, &want);
            println!("{label:<8} {moments:?} eps {eps:.0e}: error {e:.1e}");
            assert!(e <= eps, "{label} {moments:?}: {e:e} > {eps:e}");
            // the option given before the box, and the product by hand
            let before = open.clone().with_fmm(eps).unwrap().periodic(bx).unwrap();
            assert_eq!(before.apply(moments, &x), got);
            assert_eq!(periodic.apply_fmm(moments, &x, eps).unwrap(), got);
            let by_hand = FastProduct::new(eps).unwrap();
            assert_eq!(periodic.apply_fast(moments, &x, &by_hand).unwrap(), got);
        }
    }
    // the dense matrix keeps the box's tolerance, and FTS products stay the box's own
    let fast = periodic.clone().with_fmm(1e-3).unwrap();
    assert_eq!(fast.mobility(Moments::F), periodic.mobility(Moments::F));
    let x: Vec<f64> = (0..11 * open.len()).map(|i| (i as f64).sin()).collect();
    assert_eq!(
        fast.apply(Moments::FTS, &x),
        periodic.apply(Moments::FTS, &x)
    );
}

/// Triply periodic: 60 spheres of radii 0.5 to 1 in a box of 12 x 14 x 13.
#[test]
fn in_a_triply_periodic_box() {
    let lengths = [12.0, 14.0, 13.0];
    let open = System::new(
        Confinement::Free,
        1.0,
        spheres(5, 60, lengths, None),
        Overlap::Refuse,
    )
    .unwrap();
    check("triply", &open, PeriodicBox::new(lengths));
}

/// Along a wall: 40 spheres of radii 0.5 to 1 within 0.05 to 6 radii of it, a box of 11 x
/// 13.
#[test]
fn along_a_wall() {
    let lengths = [11.0, 13.0];
    let ps = laterally_periodic_spheres(6, 40, lengths, None, |rng, a| {
        a * (1.05 + rng.gen_range(0.0..5.0))
    });
    let open = System::new(Confinement::Wall { height: 0.0 }, 1.0, ps, Overlap::Refuse).unwrap();
    check("wall", &open, PeriodicBox::lateral(lengths));
}

/// In a slit of gap 4.5: 30 spheres of radii 0.5 to 1, 0.05 and more from either wall, a
/// box of 10 x 12.
#[test]
fn in_a_slit() {
    let lengths = [10.0, 12.0];
    let gap = 4.5;
    let ps = laterally_periodic_spheres(7, 30, lengths, None, |rng, a| {
        a + 0.05 + rng.gen_range(0.0..gap - 2.0 * (a + 0.05))
    });
    let open = System::new(
        Confinement::Slit { height: 0.0, gap },
        1.0,
        ps,
        Overlap::Refuse,
    )
    .unwrap();
    check("slit", &open, PeriodicBox::lateral(lengths));
}

/// Brownian dynamics in a triply periodic box with the option: a step's Lanczos noise and
/// `M F` are the box's own fast product at `eps`, the same bits as the box given the
/// tolerance `eps` without the option (the drift is zero there either way), and the option
/// and the box move with the spheres.
#[test]
fn brownian_steps_take_the_boxs_product_at_the_tolerance() {
    use stokesian::Noise;
    let lengths = [12.0, 14.0, 13.0];
    let open = System::new(
        Confinement::Free,
        1.0,
        spheres(8, 40, lengths, None),
        Overlap::Refuse,
    )
    .unwrap();
    let eps = 1e-6;
    let bx = PeriodicBox::new(lengths);
    let fast = open.clone().periodic(bx).unwrap().with_fmm(eps).unwrap();
    let at_eps = open
        .periodic(PeriodicBox {
            tolerance: eps,
            ..bx
        })
        .unwrap();
    let bd = falling(Noise::Lanczos { tol: 1e-4 });
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
    let w: Vec<f64> = (0..3 * fast.len())
        .map(|_| rng.gen_range(-1.7..1.7))
        .collect();
    assert_eq!(
        fast.brownian_increment(&bd, &w, 0).unwrap(),
        at_eps.brownian_increment(&bd, &w, 0).unwrap()
    );
    let next = fast.brownian_step(&bd, &mut rng, 0).unwrap().system;
    assert_eq!(next.fmm(), fast.fmm());
    assert_eq!(next.periodic_box(), Some(bx));
}
