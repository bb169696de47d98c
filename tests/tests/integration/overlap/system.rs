//! The solver with [`Overlap::Rpy`]: positive-definite mobilities of overlapping
//! clusters, the damping near boundaries, the same bits as [`Overlap::Refuse`] where
//! nothing overlaps, the product and the blocks agreeing with the dense matrix, and the
//! typed errors of what the overlap forms do not cover.

use integration_tests::WALL;
use nalgebra::{DMatrix, DVector, SymmetricEigen};
use rand::{Rng, SeedableRng};
use stokesian::{
    check_spd, Brownian, Confinement, ExternalForces, InputError, Lubrication, Moments, Noise,
    Overlap, OverlapError, Particle, ResistanceError, Scheme, System, VelocityError,
};

fn p(x: [f64; 3], a: f64) -> Particle {
    Particle { x, a }
}

/// `n` spheres of radii in `[0.5, 1.5]` packed into a box of side 3 (most overlap), at
/// heights `[zmin, zmin + 3)`.
fn cluster(seed: u64, n: usize, zmin: f64) -> Vec<Particle> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            let x = [
                rng.gen_range(0.0..3.0),
                rng.gen_range(0.0..3.0),
                zmin + rng.gen_range(0.0..3.0),
            ];
            p(x, rng.gen_range(0.5..1.5))
        })
        .collect()
}

/// The smallest eigenvalue of the symmetric part.
fn smallest_eigenvalue(m: &DMatrix<f64>) -> f64 {
    let s = (m + m.transpose()) * 0.5;
    SymmetricEigen::new(s).eigenvalues.min()
}

/// Random overlapping clusters, free space and above a wall (spheres cutting it
/// damped), F and FT: the RPY mobility is symmetric (1e-12, `check_spd`) and positive
/// definite (Cholesky, and the smallest eigenvalue positive), where the far forms are
/// not.
#[test]
fn overlapping_clusters_are_positive_definite() {
    let mut far_failed = false;
    for seed in 0..4 {
        for (conf, zmin) in [(Confinement::Free, 0.0), (WALL, 0.1)] {
            let ps = cluster(seed, 12, zmin);
            let rpy = System::new(conf, 1.0, ps.clone(), Overlap::Rpy).unwrap();
            for moments in [Moments::F, Moments::FT] {
                let m = rpy.mobility(moments);
                let check = check_spd(&m);
                assert!(
                    check.passed(),
                    "{conf:?} seed {seed} {moments:?}: {check:?}"
                );
                let low = smallest_eigenvalue(&m);
                assert!(low > 0.0, "{conf:?} seed {seed} {moments:?}: {low:e}");
                let far = System::new(conf, 1.0, ps.clone(), Overlap::Far).unwrap();
                far_failed |= !check_spd(&far.mobility(moments)).positive_definite;
            }
        }
    }
    assert!(
        far_failed,
        "the clusters overlap enough that the far forms fail"
    );
}

/// Nothing overlapping: `Rpy` gives the bits `Refuse` gives, dense, product and
/// velocities, F, FT and FTS, in free space and near a wall.
#[test]
fn nothing_overlapping_is_bit_for_bit() {
    let ps = vec![
        p([0.0, 0.0, 1.5], 1.0),
        p([2.5, 0.3, 2.0], 0.8),
        p([0.2, 2.2, 1.1], 0.6),
    ];
    for conf in [Confinement::Free, WALL] {
        let refuse = System::new(conf, 1.3, ps.clone(), Overlap::Refuse).unwrap();
        let rpy = System::new(conf, 1.3, ps.clone(), Overlap::Rpy).unwrap();
        for moments in [Moments::F, Moments::FT, Moments::FTS] {
            assert_eq!(refuse.mobility(moments), rpy.mobility(moments));
            let x: Vec<f64> = (0..moments.per_particle() * 3)
                .map(|i| (i as f64).sin())
                .collect();
            assert_eq!(refuse.apply(moments, &x), rpy.apply(moments, &x));
            assert_eq!(refuse.block(moments, 0, 1), rpy.block(moments, 0, 1));
            let f = &x[..if moments == Moments::F { 9 } else { 18 }];
            let e = [0.0; 5];
            assert_eq!(
                refuse.velocities(moments, f, &e, None).unwrap().u,
                rpy.velocities(moments, f, &e, None).unwrap().u
            );
        }
    }
}

/// With overlaps and damping, the matrix-free product and the blocks are the dense
/// matrix's: the product to 1e-13 of its norm (the dense and tiled sums round
/// differently), the blocks exactly where they come from the same kernels.
#[test]
fn product_and_blocks_agree_with_the_matrix() {
    let ps = cluster(7, 70, 0.2);
    let s = System::new(WALL, 0.9, ps, Overlap::Rpy).unwrap();
    for moments in [Moments::F, Moments::FT] {
        let k = moments.per_particle();
        let m = s.mobility(moments);
        let x: Vec<f64> = (0..m.nrows()).map(|i| ((i * 7) as f64).cos()).collect();
        let dense = &m * DVector::from_column_slice(&x);
        let tiled = DVector::from_vec(s.apply(moments, &x));
        let e = (&tiled - &dense).norm() / dense.norm();
        assert!(e < 1e-13, "{moments:?}: {e:e}");
        let n = s.len();
        for (a, b) in [(0, 1), (1, 0), (3, 3), (5, 17)] {
            let blk = s.block(moments, a, b);
            let scale = blk.abs().max();
            for i in 0..k {
                for j in 0..k {
                    let (ri, cj) = (i / 3 * 3 * n + 3 * a + i % 3, j / 3 * 3 * n + 3 * b + j % 3);
                    let d = (blk[(i, j)] - m[(ri, cj)]).abs();
                    assert!(
                        d <= 1e-13 * scale,
                        "{moments:?} ({a}, {b}) [{i}, {j}]: {d:e}"
                    );
                }
            }
        }
    }
}

/// A sphere at height `a/2` is evaluated at height `a` with its rows and columns
/// halved: its self block is a quarter of the self block at `a` (exact: the clamped
/// height and the factor are exact in binary), and the mobility is continuous as the
/// sphere crosses `d = a` (1e-9 relative over a step of 1e-10 a).
#[test]
fn damping_near_a_wall() {
    let a = 1.0;
    let at = |h: f64, overlap: Overlap| {
        System::new(
            WALL,
            1.0,
            vec![p([0.0, 0.0, h], a), p([2.5, 0.0, 1.6], 0.7)],
            overlap,
        )
        .unwrap()
    };
    for moments in [Moments::F, Moments::FT] {
        let damped = at(0.5, Overlap::Rpy).block(moments, 0, 0);
        let touching = at(1.0, Overlap::Refuse).block(moments, 0, 0);
        assert_eq!(damped, touching * 0.25, "{moments:?}");
        let cross = at(0.5, Overlap::Rpy).block(moments, 0, 1);
        assert_eq!(cross, at(1.0, Overlap::Refuse).block(moments, 0, 1) * 0.5);
        let below = at(1.0 - 1e-10, Overlap::Rpy).mobility(moments);
        let above = at(1.0 + 1e-10, Overlap::Rpy).mobility(moments);
        let e = (&below - &above).norm() / above.norm();
        assert!(e < 1e-9, "{moments:?}: {e:e}");
    }
}

/// Two boundaries (a slit): a sphere cutting the lower wall is moved clear of it and
/// damped as near a single wall; one cutting the upper wall likewise (the product over
/// the boundaries has one factor below 1 in a slit); a sphere wider than the slit
/// cannot be moved clear of both and is refused; a centre beyond a boundary stays an
/// error.
#[test]
fn damping_in_a_slit() {
    let slit = Confinement::Slit {
        height: 0.0,
        gap: 4.0,
    };
    let other = p([3.0, 0.0, 2.0], 0.5);
    for (h, clear, b) in [(0.5, 1.0, 0.5), (3.75, 3.0, 0.25)] {
        let damped =
            System::new(slit, 1.0, vec![p([0.0, 0.0, h], 1.0), other], Overlap::Rpy).unwrap();
        let touching = System::new(
            slit,
            1.0,
            vec![p([0.0, 0.0, clear], 1.0), other],
            Overlap::Refuse,
        )
        .unwrap();
        for moments in [Moments::F, Moments::FT] {
            assert_eq!(
                damped.block(moments, 0, 0),
                touching.block(moments, 0, 0) * (b * b)
            );
            assert_eq!(
                damped.block(moments, 1, 0),
                touching.block(moments, 1, 0) * b
            );
        }
    }
    let narrow = Confinement::Slit {
        height: 0.0,
        gap: 1.5,
    };
    let e = System::new(narrow, 1.0, vec![p([0.0, 0.0, 0.7], 1.0)], Overlap::Rpy).unwrap_err();
    assert!(
        matches!(e, InputError::OverlapsBoundary { index: 0, .. }),
        "{e}"
    );
    let e = System::new(WALL, 1.0, vec![p([0.0, 0.0, -0.1], 1.0)], Overlap::Rpy).unwrap_err();
    assert!(
        matches!(e, InputError::OutsideFluid { index: 0, .. }),
        "{e}"
    );
}

/// What the forms do not cover is a typed error: the stresslets (FTS) and lubrication
/// of overlapping or damped spheres; the drift of overlapping and of damped spheres is
/// available.
#[test]
fn what_is_not_covered_is_refused() {
    let pair = vec![p([0.0, 0.0, 3.0], 1.0), p([1.5, 0.0, 3.0], 1.0)];
    let s = System::new(WALL, 1.0, pair.clone(), Overlap::Rpy).unwrap();
    let e = s.check_overlap(Moments::FTS).unwrap_err();
    assert_eq!(
        e,
        OverlapError::Pair {
            first: 0,
            second: 1,
            what: "the stresslets (FTS)"
        }
    );
    assert!(s.check_overlap(Moments::FT).is_ok());
    let ft = [0.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    let v = s
        .velocities(Moments::FTS, &ft, &[0.0; 5], None)
        .unwrap_err();
    assert!(
        matches!(v, VelocityError::Overlap(OverlapError::Pair { .. })),
        "{v}"
    );
    let r = s
        .resistance(Moments::FT, &Lubrication::default())
        .unwrap_err();
    assert!(
        matches!(
            r,
            ResistanceError::Overlap(OverlapError::Pair {
                what: "lubrication",
                ..
            })
        ),
        "{r}"
    );
    let v = s
        .velocities(Moments::FT, &ft, &[0.0; 5], Some(&Lubrication::default()))
        .unwrap_err();
    assert!(
        matches!(v, VelocityError::Resistance(ResistanceError::Overlap(_))),
        "{v}"
    );

    let bd = Brownian {
        kt: 1.0,
        dt: 1e-4,
        drift: true,
        forces: ExternalForces {
            weight: 0.0,
            strength: 0.0,
            debye: 1.0,
            trap: 0.0,
            torque: [0.0; 3],
        },
        noise: Noise::Cholesky,
        hydrodynamics: true,
        moments: Moments::F,
        scheme: Scheme::EulerMaruyama,
        lubrication: None,
    };
    let w = vec![0.1; 6];
    assert!(s.brownian_increment(&bd, &w, 1).is_ok());
    let damped = System::new(
        WALL,
        1.0,
        vec![p([0.0, 0.0, 0.8], 1.0), p([4.0, 0.0, 3.0], 1.0)],
        Overlap::Rpy,
    )
    .unwrap();
    // the drift of the damped mobility is available (overlap::drift checks it)
    assert!(damped.brownian_increment(&bd, &w, 1).is_ok());
    let e = damped.check_overlap(Moments::FTS).unwrap_err();
    assert!(matches!(e, OverlapError::Boundary { index: 0, .. }), "{e}");
    let e = damped
        .resistance(Moments::FT, &Lubrication::default())
        .unwrap_err();
    assert!(
        matches!(
            e,
            ResistanceError::Overlap(OverlapError::Boundary { index: 0, .. })
        ),
        "{e}"
    );
    let fixman = Brownian {
        scheme: Scheme::FixmanMidpoint,
        ..bd
    };
    assert!(damped.brownian_increment(&fixman, &w, 1).is_ok());
}

/// The infallible dense matrix panics (with the error's message) where
/// `check_overlap` fails, rather than return far forms it was not asked for.
#[test]
#[should_panic(expected = "the stresslets (FTS)")]
fn fts_matrix_of_overlapping_spheres_panics() {
    let pair = vec![p([0.0, 0.0, 3.0], 1.0), p([1.5, 0.0, 3.0], 1.0)];
    System::new(WALL, 1.0, pair, Overlap::Rpy)
        .unwrap()
        .mobility(Moments::FTS);
}

/// `System::sqrt_apply` is a square-root factor of the damped mobility: with spheres
/// cutting the wall (`b` down to 0.05) and overlapping, `S S^T = B M_c B` from the
/// factor's columns (Lanczos to 1e-13 on each unit vector: the Krylov space is whole
/// after `3N` steps, so 1e-10 of the largest entry); without damping it is `M^{1/2}`,
/// symmetric.
#[test]
fn the_noise_factor_of_damped_spheres_squares_to_the_mobility() {
    let ps = vec![
        p([0.0, 0.0, 0.05], 1.0),
        p([1.5, 0.3, 0.7], 0.8),
        p([0.4, 2.1, 2.5], 1.0),
        p([3.5, 0.0, 1.5], 0.7),
    ];
    for (ps, damped) in [(ps.clone(), true), (cluster(5, 4, 3.0), false)] {
        let s = System::new(WALL, 1.0, ps, Overlap::Rpy).unwrap();
        for moments in [Moments::F, Moments::FT] {
            let m = s.mobility(moments);
            let n = m.nrows();
            let mut f = DMatrix::zeros(n, n);
            for j in 0..n {
                let mut e = vec![0.0; n];
                e[j] = 1.0;
                let (col, _) = s.sqrt_apply(moments, &e, 1e-13).unwrap();
                f.set_column(j, &DVector::from_vec(col));
            }
            let scale = m.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            let d = (&f * f.transpose() - &m).abs().max();
            assert!(d < 1e-10 * scale, "{moments:?} damped {damped}: {d:e}");
            if !damped {
                assert!((&f - f.transpose()).abs().max() < 1e-10 * scale.sqrt());
            }
        }
    }
}
