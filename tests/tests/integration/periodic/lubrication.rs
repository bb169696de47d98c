//! The resistance with lubrication in a periodic box: the pair corrections of Eq. 19
//! for every image within the window, a sphere's own images included, against a
//! reference that forms each correction from an open two-sphere system
//! (`R_2 - M_2^-1`) and adds it row by row, every partner of every sphere (the solver
//! enumerates each unordered pair once, over half the lattice for a sphere's own
//! images).

use stokesian::linalg::Cholesky;
use stokesian::{
    Brownian, Confinement, LubricatedDynamics, Lubrication, Moments, Noise, Overlap, Particle,
    PeriodicBox, Scheme, System,
};

const ETA: f64 = 0.9;

/// Index of component `c` (0..6: U then Omega; 6..11 the strain at FTS) of sphere `a` of
/// `n` (moment-major).
fn at(n: usize, a: usize, c: usize) -> usize {
    if c < 3 {
        3 * a + c
    } else if c < 6 {
        3 * n + 3 * a + c - 3
    } else {
        6 * n + 5 * a + c - 6
    }
}

/// The correction `R - M^-1` of `ps` in `confinement` and box `bx` (periodic along the
/// axes where `lengths` is not zero) against the reference: for every sphere `a` and
/// every partner `(b, n)`, `b + n != a`, within the window, the open pair's correction
/// `R_2 - M_2^-1` less each sphere's own correction near the boundaries (`R_1 -
/// M_1^-1`, the sphere alone), its `(a, a)` block on `a`'s diagonal block and its `(a,
/// b)` block on `(a, b)`; and each sphere's own correction once. The window must hold
/// more than `partners` of them (several images per pair). At `moments` FT or FTS.
fn check(
    moments: Moments,
    confinement: Confinement,
    bx: PeriodicBox,
    lengths: [f64; 3],
    ps: &[Particle],
    partners_at_least: usize,
) {
    // a pair tolerance of 1e-3 at FT, 5e-5 at FTS (the FTS corrections decay faster):
    // window s' <= 11.6 and 11.5, several images of each pair
    let lub = Lubrication {
        pair_tolerance: if moments == Moments::FTS { 5e-5 } else { 1e-3 },
        ..Lubrication::default()
    };
    let s = System::new(confinement, ETA, ps.to_vec(), Overlap::Refuse)
        .unwrap()
        .periodic(bx)
        .unwrap();
    let r = s.resistance(moments, &lub).unwrap();
    let m_inv = Cholesky::new(&s.mobility(moments)).unwrap().inverse();
    let correction = &r - &m_inv;

    let open = |ps: Vec<Particle>| {
        let s = System::new(confinement, ETA, ps, Overlap::Refuse).unwrap();
        s.resistance(moments, &lub).unwrap()
            - Cholesky::new(&s.mobility(moments)).unwrap().inverse()
    };
    let k = moments.per_particle();
    let n = ps.len();
    let own: Vec<_> = ps.iter().map(|p| open(vec![*p])).collect();
    let (_, s1) = lub.pair_window(moments);
    let mut want = nalgebra::DMatrix::<f64>::zeros(k * n, k * n);
    for a in 0..n {
        for i in 0..k {
            for j in 0..k {
                want[(at(n, a, i), at(n, a, j))] += own[a][(i, j)];
            }
        }
    }
    let range = |d: usize| if lengths[d] > 0.0 { -4i32..=4 } else { 0..=0 };
    let mut partners = 0;
    for a in 0..n {
        for b in 0..n {
            for n1 in range(0) {
                for n2 in range(1) {
                    for n3 in range(2) {
                        let shift = [n1, n2, n3];
                        if a == b && shift == [0; 3] {
                            continue;
                        }
                        let xb: [f64; 3] =
                            std::array::from_fn(|d| ps[b].x[d] + f64::from(shift[d]) * lengths[d]);
                        let d2: f64 = (0..3).map(|d| (xb[d] - ps[a].x[d]).powi(2)).sum();
                        if 2.0 * d2.sqrt() / (ps[a].a + ps[b].a) >= s1 {
                            continue;
                        }
                        partners += 1;
                        let c2 = open(vec![ps[a], Particle { x: xb, a: ps[b].a }]);
                        for i in 0..k {
                            for j in 0..k {
                                want[(at(n, a, i), at(n, a, j))] +=
                                    c2[(at(2, 0, i), at(2, 0, j))] - own[a][(i, j)];
                                want[(at(n, a, i), at(n, b, j))] += c2[(at(2, 0, i), at(2, 1, j))];
                            }
                        }
                    }
                }
            }
        }
    }
    // the window covers images out to 1.5 box lengths: several per pair
    assert!(partners >= partners_at_least, "{partners} partners");
    // Tolerance: both sides add the same tabulated two-sphere and sphere-wall functions;
    // they differ by the rounding of R - M^-1 (entries of M^-1 ~ 20 beside corrections
    // up to ~300 at the gaps of 0.06) and of the pair blocks evaluated from either end:
    // 1e-11 of the largest correction is a thousand times that, and far below any
    // missing image's share (the smallest in full weight is ~1e-3 of the largest).
    let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let worst = (&correction - &want)
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(worst <= 1e-11 * scale, "worst {worst:e} of {scale:e}");
    // and the resistance is positive definite
    assert!(Cholesky::new(&r).is_some());
}

/// Three spheres in a 6 x 8 x 9 box: the first two 0.063 apart across the face x = 0
/// (full corrections), the first and the last with their own images within the window
/// (the first's in full, the last's in the window's smooth fall-off); FT and FTS (the
/// stresslet and strain rows and columns of every image's correction).
#[test]
fn pair_corrections_cover_every_image_and_own_images() {
    let lengths = [6.0, 8.0, 9.0];
    let ps = [
        Particle {
            x: [0.3, 4.0, 4.5],
            a: 1.0,
        },
        Particle {
            x: [4.45, 4.2, 4.6],
            a: 0.8,
        },
        Particle {
            x: [3.0, 7.5, 1.0],
            a: 0.6,
        },
    ];
    for moments in [Moments::FT, Moments::FTS] {
        check(
            moments,
            Confinement::Free,
            PeriodicBox::new(lengths),
            lengths,
            &ps,
            28,
        );
    }
}

/// Three spheres in a 6 x 8 box near the plane `x3 = 0` (gaps 0.2 and 1.4 radii for the
/// last two), the first at height `z0`.
fn near_the_lower_wall(z0: f64) -> [Particle; 3] {
    let sphere = |x: [f64; 3], a: f64| Particle { x, a };
    [
        sphere([0.3, 4.0, z0], 1.0),
        sphere([4.45, 4.2, 0.96], 0.8),
        sphere([3.0, 7.5, 1.44], 0.6),
    ]
}

/// The same near a wall in a box periodic along it (6 x 8): pairs across the face x = 0
/// and own images along the wall, and every sphere's sphere-wall correction (gaps 0.2,
/// 0.2 and 1.4 radii); FT and FTS.
#[test]
fn near_a_periodic_wall_the_corrections_cover_the_lateral_images() {
    let ps = near_the_lower_wall(1.2);
    let wall = Confinement::Wall { height: 0.0 };
    for moments in [Moments::FT, Moments::FTS] {
        check(
            moments,
            wall,
            PeriodicBox::lateral([6.0, 8.0]),
            [6.0, 8.0, 0.0],
            &ps,
            28,
        );
    }
}

/// The same in a periodic slit: sphere-wall corrections at both walls (the first sphere
/// 0.4 radii below the upper wall), the periodic slit's exact Green's function in `M`.
/// The reference's open systems superpose two walls' images, which are positive definite
/// only in wide slits (gap 14 here). FT and FTS.
#[test]
fn in_a_periodic_slit_the_corrections_cover_both_walls() {
    // the first sphere 0.4 radii below the upper wall
    let ps = near_the_lower_wall(12.6);
    let slit = Confinement::Slit {
        height: 0.0,
        gap: 14.0,
    };
    // the first sphere far from the others: its own images alone
    for moments in [Moments::FT, Moments::FTS] {
        check(
            moments,
            slit,
            PeriodicBox::lateral([6.0, 8.0]),
            [6.0, 8.0, 0.0],
            &ps,
            20,
        );
    }
}

/// A lubricated Brownian increment in a box is available and does not change when a
/// sphere is moved by a box length (to the rounding of the shifted positions: 1e-12 of
/// the increment; the random finite difference's step and every pair correction see
/// the nearest images).
#[test]
fn a_lubricated_step_in_a_box_ignores_box_lengths() {
    let lengths = [6.0, 6.0, 6.0];
    let ps = vec![
        Particle {
            x: [0.5, 3.0, 3.0],
            a: 1.0,
        },
        Particle {
            x: [4.4, 3.1, 3.0],
            a: 1.0,
        },
    ];
    let mut moved = ps.clone();
    moved[1].x[0] -= 6.0;
    moved[0].x[2] += 12.0;
    let bd = Brownian {
        kt: 1.0,
        dt: 1e-3,
        drift: true,
        forces: integration_tests::NO_FORCES,
        noise: Noise::Cholesky,
        hydrodynamics: true,
        moments: Moments::FT,
        scheme: Scheme::EulerMaruyama,
        lubrication: Some(LubricatedDynamics {
            lubrication: Lubrication::default(),
            rfd_step: 1e-3,
        }),
    };
    let w: Vec<f64> = (0..bd.random_numbers(2))
        .map(|i| ((i * 7919) % 13) as f64 / 6.5 - 1.0)
        .collect();
    let step = |ps: Vec<Particle>| {
        System::new(Confinement::Free, ETA, ps, Overlap::Refuse)
            .unwrap()
            .periodic(PeriodicBox::new(lengths))
            .unwrap()
            .brownian_increment(&bd, &w, 1)
            .unwrap()
    };
    let (dx, dy) = (step(ps), step(moved));
    let scale = dx.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (i, (x, y)) in dx.iter().zip(&dy).enumerate() {
        assert!((x - y).abs() <= 1e-12 * scale, "{i}: {x} vs {y}");
    }
}
