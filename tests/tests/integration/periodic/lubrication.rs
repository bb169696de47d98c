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

/// Index of component `c` (0..6: U then Omega) of sphere `a` of `n` (moment-major).
fn at(n: usize, a: usize, c: usize) -> usize {
    if c < 3 {
        3 * a + c
    } else {
        3 * n + 3 * a + c - 3
    }
}

/// Three spheres in a 6 x 8 x 9 box: the first two 0.063 apart across the face x = 0
/// (full corrections), the first and the last with their own images within the window
/// (the first's in full, the last's in the window's smooth fall-off), at a pair
/// tolerance of 1e-3 (window `s' <= 11.6`: several images of each pair).
#[test]
fn pair_corrections_cover_every_image_and_own_images() {
    let lengths = [6.0, 8.0, 9.0];
    let ps = vec![
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
    let lub = Lubrication {
        pair_tolerance: 1e-3,
        ..Lubrication::default()
    };
    let bx = PeriodicBox::new(lengths);
    let s = System::new(Confinement::Free, ETA, ps.clone(), Overlap::Refuse)
        .unwrap()
        .periodic(bx)
        .unwrap();
    let r = s.resistance(Moments::FT, &lub).unwrap();
    let m_inv = Cholesky::new(&s.mobility(Moments::FT)).unwrap().inverse();
    let correction = &r - &m_inv;

    // the reference: for every sphere a and every partner (b, n), b + n != a, within
    // the window, the open pair's correction C = R_2 - M_2^-1: its (a, a) block on a's
    // diagonal block, its (a, b) block on (a, b)
    let n = ps.len();
    let (_, s1) = lub.pair_window(Moments::FT);
    let mut want = nalgebra::DMatrix::<f64>::zeros(6 * n, 6 * n);
    let mut partners = 0;
    for a in 0..n {
        for b in 0..n {
            for n1 in -4i32..=4 {
                for n2 in -4i32..=4 {
                    for n3 in -4i32..=4 {
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
                        let pair = vec![ps[a], Particle { x: xb, a: ps[b].a }];
                        let two =
                            System::new(Confinement::Free, ETA, pair, Overlap::Refuse).unwrap();
                        let c2 = two.resistance(Moments::FT, &lub).unwrap()
                            - Cholesky::new(&two.mobility(Moments::FT)).unwrap().inverse();
                        for i in 0..6 {
                            for j in 0..6 {
                                want[(at(n, a, i), at(n, a, j))] += c2[(at(2, 0, i), at(2, 0, j))];
                                want[(at(n, a, i), at(n, b, j))] += c2[(at(2, 0, i), at(2, 1, j))];
                            }
                        }
                    }
                }
            }
        }
    }
    // the window covers images out to 1.5 box lengths: several per pair
    assert!(partners > 3 * n * n, "{partners} partners");
    // Tolerance: both sides add the same tabulated two-sphere functions; they differ by
    // the rounding of R - M^-1 (entries of M^-1 ~ 20 beside corrections up to ~300 at
    // the gap 0.063) and of the pair blocks evaluated from either end: 1e-11 of the
    // largest correction is a thousand times that, and far below any missing image's
    // share (the smallest in full weight is ~1e-3 of the largest).
    let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let worst = (&correction - &want)
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(worst <= 1e-11 * scale, "worst {worst:e} of {scale:e}");
    // and the resistance is positive definite
    assert!(Cholesky::new(&r).is_some());
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
