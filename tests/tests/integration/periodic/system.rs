//! A [`System`] in a periodic box: its dense mobility is symmetric positive definite and
//! agrees with its blocks and its product; a sphere moved by a box length changes
//! nothing; a large box tends to the open mobility; what a box cannot be or do is a
//! typed error.

use super::spheres;
use nalgebra::DMatrix;
use stokesian::{
    check_spd, Brownian, BrownianError, Confinement, Lubrication, Moments, Noise, Overlap,
    Particle, PeriodicBox, PeriodicError, Scheme, System,
};

const ETA: f64 = 0.9;

fn p(x: [f64; 3], a: f64) -> Particle {
    Particle { x, a }
}

fn periodic(ps: Vec<Particle>, lengths: [f64; 3]) -> System {
    System::new(Confinement::Free, ETA, ps, Overlap::Refuse)
        .unwrap()
        .periodic(PeriodicBox::new(lengths))
        .unwrap()
}

fn max_abs(m: &DMatrix<f64>) -> f64 {
    m.iter().fold(0.0f64, |a, v| a.max(v.abs()))
}

/// Symmetric (to the rounding of the two orders of evaluation: each pair is evaluated
/// once, so exactly), positive definite, the blocks the matrix's, the product (the fast
/// one at F and FT, the direct sums at FTS) the matrix's to the box's tolerance.
#[test]
fn dense_product_and_blocks_agree_and_are_positive_definite() {
    let lengths = [8.0, 9.0, 10.0];
    let s = periodic(spheres(1, 12, lengths, None), lengths);
    for moments in [Moments::F, Moments::FT, Moments::FTS] {
        let m = s.mobility(moments);
        assert_eq!(m, m.transpose());
        assert!(check_spd(&m).positive_definite, "{moments:?}");
        let x: Vec<f64> = (0..m.nrows()).map(|i| (i as f64 * 0.37).sin()).collect();
        let mx = &m * DMatrix::from_column_slice(x.len(), 1, &x);
        let y = s.apply(moments, &x);
        // the fast product (spectral Ewald) to the box's tolerance (1e-10) of the
        // result's largest entry (`periodic::spectral`)
        let scale = mx.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for (a, b) in mx.iter().zip(&y) {
            assert!((a - b).abs() < 1e-10 * scale);
        }
        let k = moments.per_particle();
        let n = s.len();
        let b = s.block(moments, 3, 7);
        for i in 0..k {
            for j in 0..k {
                // the moment-major index of component i of particle a
                let g = |a: usize, i: usize| match i {
                    0..3 => 3 * a + i,
                    3..6 => 3 * n + 3 * a + i - 3,
                    _ => 6 * n + 5 * a + i - 6,
                };
                assert_eq!(b[(i, j)], m[(g(3, i), g(7, j))]);
            }
        }
    }
}

/// Moving a sphere by box lengths is the same system: with the coordinates on a grid
/// of `2^-20` the moves are exact, and the kernels see the wrapped positions, so the
/// dense matrix and the (fast) product are the same bits, even a million boxes away
/// (where unwrapped coordinates would round their differences to ~1e-9).
#[test]
fn a_box_length_changes_nothing() {
    let lengths = [8.0, 8.0, 16.0];
    let grid = |v: f64| (v * 1048576.0).round() / 1048576.0;
    let ps: Vec<Particle> = spheres(2, 6, lengths, None)
        .into_iter()
        .map(|q| p(q.x.map(grid), q.a))
        .collect();
    let mut moved = ps.clone();
    moved[2].x[0] += 8.0;
    moved[4].x[2] -= 32.0 * 1048576.0;
    moved[5].x[1] += 16.0;
    let (s, t) = (periodic(ps, lengths), periodic(moved, lengths));
    assert_eq!(s.mobility(Moments::FT), t.mobility(Moments::FT));
    let x: Vec<f64> = (0..36).map(|i| (i as f64 * 0.37).sin()).collect();
    assert_eq!(s.apply(Moments::FT, &x), t.apply(Moments::FT, &x));
    assert_eq!(s.mobility(Moments::FTS), t.mobility(Moments::FTS));
    let x: Vec<f64> = (0..66).map(|i| (i as f64 * 0.37).sin()).collect();
    assert_eq!(s.apply(Moments::FTS, &x), t.apply(Moments::FTS, &x));
}

/// In a large box the periodic mobility tends to the open one: the self mobility's
/// leading correction is Hasimoto's `-2.8373 a/L` (relative to the isolated sphere), the
/// pairs' `O(1/L)` too; `L M_periodic - L M_open` converges as `L` doubles, at F and at
/// FTS (every block).
#[test]
fn a_large_box_tends_to_the_open_mobility() {
    let ps = vec![p([0.0, 0.0, 0.0], 1.0), p([3.0, 1.0, -0.5], 0.8)];
    let open = System::new(Confinement::Free, ETA, ps.clone(), false).unwrap();
    let mut scaled = Vec::new();
    for moments in [Moments::F, Moments::FTS] {
        let open = open.mobility(moments);
        let by_l: Vec<DMatrix<f64>> = [50.0, 100.0, 200.0]
            .iter()
            .map(|&l| (periodic(ps.clone(), [l; 3]).mobility(moments) - &open) * l)
            .collect();
        let (d1, d2) = (
            max_abs(&(&by_l[1] - &by_l[0])),
            max_abs(&(&by_l[2] - &by_l[1])),
        );
        // the next term is O(1/L): halving L's inverse halves the change
        assert!(d2 < 0.6 * d1, "{moments:?}: {d1:e} {d2:e}");
        scaled.push(by_l);
    }
    let scaled = &scaled[0];
    // and the self entry is Hasimoto's, to its next term (4 pi/3)(a/L)^3 L (4e-5 here)
    let want = -2.8372974794806 / (6.0 * std::f64::consts::PI * ETA);
    assert!(
        (scaled[2][(0, 0)] - want).abs() < 1e-4 * want.abs(),
        "{} vs {want}",
        scaled[2][(0, 0)]
    );
}

/// Bad boxes and what a box does not provide are typed errors.
#[test]
fn bad_boxes_and_what_a_box_cannot_do_are_refused() {
    let ps = vec![p([0.0, 0.0, 0.0], 1.0), p([3.0, 0.0, 0.0], 1.0)];
    let free = || System::new(Confinement::Free, 1.0, ps.clone(), false).unwrap();
    let e = free()
        .periodic(PeriodicBox::new([10.0, -1.0, 10.0]))
        .unwrap_err();
    assert_eq!(
        e,
        PeriodicError::BadLength {
            axis: 'y',
            value: -1.0
        }
    );
    let e = free()
        .periodic(PeriodicBox::new([10.0, f64::NAN, 10.0]))
        .unwrap_err();
    assert!(
        matches!(e, PeriodicError::BadLength { axis: 'y', .. }),
        "{e}"
    );
    let e = free()
        .periodic(PeriodicBox {
            tolerance: 0.5,
            ..PeriodicBox::new([10.0; 3])
        })
        .unwrap_err();
    assert_eq!(e, PeriodicError::BadTolerance(0.5));
    // a sphere overlapping its own image, two overlapping across the box
    let e = free()
        .periodic(PeriodicBox::new([10.0, 10.0, 1.5]))
        .unwrap_err();
    assert!(
        matches!(
            e,
            PeriodicError::OwnImage {
                index: 0,
                axis: 'z',
                ..
            }
        ),
        "{e}"
    );
    let e = free()
        .periodic(PeriodicBox::new([4.5, 10.0, 10.0]))
        .unwrap_err();
    assert!(
        matches!(
            e,
            PeriodicError::Overlap {
                first: 0,
                second: 1,
                ..
            }
        ),
        "{e}"
    );
    // confinements without a periodic sum, each with its reason
    let above = vec![p([0.0, 0.0, 2.0], 1.0)];
    for conf in [
        Confinement::FreeSurface { height: 0.0 },
        Confinement::Wall { height: 0.0 },
    ] {
        let e = System::new(conf, 1.0, above.clone(), false)
            .unwrap()
            .periodic(PeriodicBox::new([10.0; 3]))
            .unwrap_err();
        assert!(matches!(e, PeriodicError::Confinement { .. }), "{e}");
    }
    // FTS is available in every box, the lubricated resistance too; Brownian dynamics in
    // a trap is not
    let s = free().periodic(PeriodicBox::new([10.0; 3])).unwrap();
    let ft = [0.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    assert!(s.velocities(Moments::FTS, &ft, &[0.0; 5], None).is_ok());
    assert!(s.resistance(Moments::FTS, &Lubrication::default()).is_ok());
    let near_wall = System::new(
        Confinement::Wall { height: 0.0 },
        ETA,
        vec![p([1.0, 2.0, 3.0], 1.0), p([5.0, 2.0, 4.0], 1.0)],
        false,
    )
    .unwrap()
    .periodic(PeriodicBox::lateral([10.0, 10.0]))
    .unwrap();
    let slit = System::new(
        Confinement::Slit {
            height: 0.0,
            gap: 6.0,
        },
        ETA,
        vec![p([1.0, 2.0, 3.0], 1.0), p([5.0, 2.0, 2.5], 1.0)],
        false,
    )
    .unwrap()
    .periodic(PeriodicBox::lateral([10.0, 10.0]))
    .unwrap();
    for walls in [&near_wall, &slit] {
        assert!(walls.velocities(Moments::FTS, &ft, &[0.0; 5], None).is_ok());
        assert!(walls
            .resistance(Moments::FTS, &Lubrication::default())
            .is_ok());
    }
    let bd = Brownian {
        kt: 1.0,
        dt: 1e-3,
        drift: true,
        forces: stokesian::ExternalForces {
            trap: 1.0,
            ..integration_tests::NO_FORCES
        },
        noise: Noise::Cholesky,
        hydrodynamics: true,
        moments: Moments::F,
        scheme: Scheme::EulerMaruyama,
        lubrication: None,
    };
    let e = s.brownian_increment(&bd, &[0.1; 6], 1).unwrap_err();
    assert!(matches!(e, BrownianError::Periodic(_)), "{e}");
    // the velocities at F and FT are the product's, the drift zero
    let u = s.velocities(Moments::FT, &ft, &[0.0; 5], None).unwrap();
    assert_eq!(u.u, s.apply(Moments::FT, &ft));
    assert_eq!(s.divergence_at(Moments::FT), vec![0.0; 12]);
}

/// Brownian dynamics in a box: one sphere's Euler-Maruyama increment is `sqrt(2 kT dt M)
/// w` with Hasimoto's periodic self mobility (zero drift; the Cholesky factor of the
/// cube's isotropic self block is its square root), to its 1e-10 and the printed
/// coefficient's 1e-13; a run leaves the positions unwrapped, the box kept, and steps
/// that would overlap two spheres by their nearest images are redrawn.
#[test]
fn brownian_dynamics_in_a_box() {
    let (l, a, kt, dt) = (10.0, 1.0, 1.3, 1e-2);
    let s = periodic(vec![p([0.5, 9.9, 5.0], a)], [l; 3]);
    let bd = Brownian {
        kt,
        dt,
        drift: true,
        forces: integration_tests::NO_FORCES,
        noise: Noise::Cholesky,
        hydrodynamics: true,
        moments: Moments::F,
        scheme: Scheme::EulerMaruyama,
        lubrication: None,
    };
    let w = [0.3, -1.1, 0.7];
    let dx = s.brownian_increment(&bd, &w, 1).unwrap();
    let x = a / l;
    let m = (1.0 - 2.8372974794806 * x + 4.0 * std::f64::consts::PI / 3.0 * x.powi(3))
        / (6.0 * std::f64::consts::PI * ETA * a);
    for k in 0..3 {
        let want = (2.0 * kt * dt * m).sqrt() * w[k];
        assert!(
            (dx[k] - want).abs() < 1e-9 * want.abs(),
            "{k}: {} vs {want}",
            dx[k]
        );
    }
    // a run of a close pair (gap 0.05) at the edge of the box: unwrapped positions, the
    // box kept, overlapping steps redrawn
    let lengths = [6.0, 6.0, 6.0];
    let s = periodic(
        vec![p([0.5, 5.8, 3.0], 1.0), p([0.5, 3.75, 3.0], 1.0)],
        lengths,
    );
    let run = stokesian::Run {
        steps: 40,
        seed: 3,
        every: 40,
        max_rejections: 1000,
    };
    let bd = Brownian { dt: 0.5, ..bd };
    let mut last = None;
    let bx = s.periodic_box();
    let tally = s
        .brownian_run(&bd, &run, |_, system, _| last = Some(system.clone()))
        .unwrap();
    let last = last.unwrap();
    assert_eq!(last.periodic_box(), bx);
    println!("rejections {}", tally.rejections);
    assert!(
        tally.rejections > 0,
        "the close pair overlaps in some drawn steps"
    );
    assert!(
        last.particles()
            .iter()
            .any(|q| q.x.iter().any(|&c| !(0.0..6.0).contains(&c))),
        "some centre left the box: the positions are not wrapped"
    );
}
