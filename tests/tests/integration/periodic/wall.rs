//! Spheres above a wall in a box periodic along it ([`stokesian::periodic::wall`]): the
//! Ewald sums against the brute-force sum over square shells of lateral images of the
//! open wall's kernels (`kernels::pair`, `kernels::self_mobility` with `Confinement::Wall`:
//! independent of the split), extrapolated in the shells' size; the split parameter
//! changes nothing; a large box tends to the open wall with the lattice sum of the wall's
//! far field; the system's matrix is symmetric positive definite, agrees with its product
//! and with a doubled box, and does not see a move by a box length; what such a box
//! cannot be or do is a typed error.

use kernels::{pair, self_ft, self_mobility, BlocksFT, Confinement};
use nalgebra::DMatrix;
use nalgebra::SMatrix;
use std::f64::consts::PI;
use stokesian::periodic::wall::WallEwald;
use stokesian::{check_spd, Moments, Overlap, Particle, PeriodicBox, PeriodicError, System};

pub(super) const ETA: f64 = 0.9;
const HEIGHT: f64 = 0.5;

pub(super) fn p(x: [f64; 3], a: f64) -> Particle {
    Particle { x, a }
}

pub(super) fn largest(m: &[[f64; 6]; 6]) -> f64 {
    m.iter().flatten().fold(0.0f64, |acc, v| acc.max(v.abs()))
}

pub(super) fn difference(a: &BlocksFT, b: &BlocksFT) -> f64 {
    let (ma, mb) = (a.matrix(), b.matrix());
    (0..36).fold(0.0f64, |acc, k| {
        acc.max((ma[k / 6][k % 6] - mb[k / 6][k % 6]).abs())
    })
}

/// `sum_{|n|_inf <= N}` of the open wall's grand blocks (FTS, 11 x 11 row-major) of
/// `q`'s lateral images acting on `p` (with `same`, the self block for `n = 0`), for each
/// `N` of `sizes` (increasing): shells added in order, Neumaier-compensated.
fn shells(
    wall: &Confinement,
    lengths: [f64; 2],
    (p, q): (&Particle, &Particle),
    same: bool,
    sizes: &[i64],
) -> Vec<[f64; 121]> {
    let mut sum = [0.0; 121];
    let mut carry = [0.0; 121];
    let add = |sum: &mut [f64; 121], carry: &mut [f64; 121], m: SMatrix<f64, 11, 11>| {
        for k in 0..121 {
            let v = m[(k / 11, k % 11)];
            let t = sum[k] + v;
            carry[k] += if sum[k].abs() >= v.abs() {
                (sum[k] - t) + v
            } else {
                (v - t) + sum[k]
            };
            sum[k] = t;
        }
    };
    let mut out = Vec::new();
    for n in 0..=*sizes.last().expect("sizes") {
        for n1 in -n..=n {
            for n2 in -n..=n {
                if n1.abs().max(n2.abs()) != n {
                    continue;
                }
                let xb = [
                    q.x[0] + n1 as f64 * lengths[0],
                    q.x[1] + n2 as f64 * lengths[1],
                    q.x[2],
                ];
                let m = if same && n == 0 {
                    self_mobility(wall, ETA, p.x, p.a)
                } else {
                    pair(wall, ETA, p.x, p.a, xb, q.a)
                };
                add(&mut sum, &mut carry, m.matrix());
            }
        }
        if sizes.contains(&n) {
            out.push(std::array::from_fn(|k| sum[k] + carry[k]));
        }
    }
    out
}

/// `S(N) = S + c1/N + ... + c4/N^4` solved for `S`, entry by entry.
fn extrapolate(sizes: &[i64], sums: &[[f64; 121]]) -> [f64; 121] {
    let m = DMatrix::from_fn(sizes.len(), sizes.len(), |i, j| {
        (sizes[i] as f64).powi(-(j as i32))
    });
    let lu = m.lu();
    std::array::from_fn(|k| {
        let rhs = nalgebra::DVector::from_fn(sizes.len(), |i, _| sums[i][k]);
        lu.solve(&rhs).expect("regular")[0]
    })
}

/// The lattice sum of the open wall's blocks converges absolutely (every block decays
/// like `rho^-3` along the wall), and square shells to `N` leave a tail with an expansion
/// in `1/N`: Richardson from `N = 32, 48, 64, 96, 128` (6.6e4 images; compensated sums),
/// against the same from `N = 24 ... 96` (one order worse), moves by 1e-10 of the largest
/// entry (measured; asserted below 5e-10). The Ewald sums at tolerance 1e-12 agree with
/// it to 1e-9 of the largest entry, the reference's own uncertainty with a margin
/// (measured 2e-11 and less): a pair of unequal spheres at different heights and the
/// self mobility, every FTS block ([`WallEwald::grand`]: translation, rotation, strain
/// and their couplings, so the image's source operators to the third derivative and the
/// mode `k_par = 0` of each) and the FT blocks ([`WallEwald::blocks`], their own sums)
/// against the same reference's leading 6 x 6.
#[test]
fn ewald_sum_equals_the_extrapolated_sum_over_shells() {
    let lengths = [10.0, 13.0];
    let wall = Confinement::Wall { height: HEIGHT };
    let a = p([1.3, 2.1, 1.7 + HEIGHT], 1.0);
    let b = p([-2.4, 0.6, 3.1 + HEIGHT], 0.6);
    let ewald = WallEwald::new(lengths, HEIGHT, 1e-12, None);
    for (p, q, same) in [(&a, &b, false), (&a, &a, true), (&b, &b, true)] {
        let sizes = [24, 32, 48, 64, 96, 128];
        let sums = shells(&wall, lengths, (p, q), same, &sizes);
        let reference = extrapolate(&sizes[1..], &sums[1..]);
        let other = extrapolate(&sizes[..5], &sums[..5]);
        let grand = ewald.grand(ETA, p, q, same).matrix();
        let ft = ewald.blocks(ETA, p, q, same).matrix();
        let scale = grand.iter().fold(0.0f64, |acc, v| acc.max(v.abs()));
        let spread = (0..121).fold(0.0f64, |acc, k| acc.max((reference[k] - other[k]).abs()));
        let worst = (0..121).fold(0.0f64, |acc, k| {
            acc.max((reference[k] - grand[(k / 11, k % 11)]).abs())
        });
        let worst_ft = (0..36).fold(0.0f64, |acc, k| {
            acc.max((reference[(k / 6) * 11 + k % 6] - ft[k / 6][k % 6]).abs())
        });
        println!("same {same}: FTS worst {worst:e}, FT worst {worst_ft:e}, spread {spread:e} of {scale:e}");
        assert!(spread < 5e-10 * scale, "same {same}: spread {spread:e}");
        assert!(worst < 1e-9 * scale, "same {same}: {worst:e} of {scale:e}");
        assert!(
            worst_ft < 1e-9 * scale,
            "same {same}: FT {worst_ft:e} of {scale:e}"
        );
    }
}

/// The real part and the reciprocal part (with its mode `k_par = 0`) move with the split
/// parameter in opposite directions; their sum must not: `xi` a factor 6 apart, a box
/// that is not a square, unequal radii, pairs near the wall and high above it, the self
/// mobility, FT and FTS blocks; at tolerance 1e-12, to 1e-11 of the largest entry
/// (measured 2e-13).
#[test]
fn the_split_parameter_changes_nothing() {
    let lengths = [9.0, 12.0];
    let ps = [
        p([0.4, 8.7, 1.2 + HEIGHT], 1.0),
        p([3.1, 1.2, 2.5 + HEIGHT], 0.6),
        p([-5.0, 3.0, 9.0 + HEIGHT], 0.8),
    ];
    split_changes_nothing(lengths, &ps, |xi| {
        let e = WallEwald::new(lengths, HEIGHT, 1e-12, Some(xi));
        move |a: &Particle, b: &Particle, same| e.blocks(ETA, a, b, same).flat().to_vec()
    });
    split_changes_nothing(lengths, &ps, |xi| {
        let e = WallEwald::new(lengths, HEIGHT, 1e-12, Some(xi));
        move |a: &Particle, b: &Particle, same| e.grand(ETA, a, b, same).flat().to_vec()
    });
}

/// The blocks of every pair of `ps` (self blocks too) at the split parameter `xi` a
/// factor 0.4 and 2.4 of `sqrt(pi/A)` equal those at `sqrt(pi/A)` to 1e-11 of the
/// largest entry (sums at tolerance 1e-12): `sum(xi)` gives the blocks of one split,
/// flattened.
pub(super) fn split_changes_nothing<F: Fn(&Particle, &Particle, bool) -> Vec<f64>>(
    lengths: [f64; 2],
    ps: &[Particle],
    sum: impl Fn(f64) -> F,
) {
    let base = (PI / (lengths[0] * lengths[1])).sqrt();
    let sums: Vec<F> = [0.4, 1.0, 2.4].iter().map(|&f| sum(f * base)).collect();
    let largest = |v: &[f64]| v.iter().fold(0.0f64, |acc, x| acc.max(x.abs()));
    for i in 0..ps.len() {
        for j in i..ps.len() {
            let blocks: Vec<Vec<f64>> = sums.iter().map(|e| e(&ps[i], &ps[j], i == j)).collect();
            let scale = largest(&blocks[1]);
            for other in [&blocks[0], &blocks[2]] {
                let d = largest(
                    &other
                        .iter()
                        .zip(&blocks[1])
                        .map(|(x, y)| x - y)
                        .collect::<Vec<_>>(),
                );
                assert!(d < 1e-11 * scale, "{i} {j}: {d:e} of {scale:e}");
            }
        }
    }
}

/// In a large square box the lattice sum is the open wall's plus the images' far field,
/// `12 h_a h_b rho_i rho_j / rho^5` on the lateral translations (units of `1/(8 pi
/// eta)`), whose sum over the square lattice `n L != 0` is `6 h_a h_b S3 / L^3 (I - e3
/// e3)`, `S3 = sum' |n|^-3 = 4 zeta(3/2) beta(3/2)` (zeta(3/2) = 2.612375348685488,
/// Dirichlet's beta(3/2) = 0.8645026534612016). The next terms are smaller by `(h/L)^2`
/// and `(a/L)^2`: the self mobility's correction at `h = 2`, `L = 400` within 1e-3 of it.
#[test]
fn a_large_box_adds_the_lattice_sum_of_the_far_field() {
    let s3 = 4.0 * 2.612375348685488 * 0.8645026534612016;
    let h = 2.0;
    let a = p([0.3, -0.2, h + HEIGHT], 1.0);
    let wall = Confinement::Wall { height: HEIGHT };
    let open = self_ft(&wall, ETA, a.x, a.a).matrix();
    let l = 400.0;
    let got = WallEwald::new([l, l], HEIGHT, 1e-13, None)
        .blocks(ETA, &a, &a, true)
        .matrix();
    let want = 6.0 * h * h * s3 / (l * l * l) / (8.0 * PI * ETA);
    for i in 0..2 {
        let d = got[i][i] - open[i][i];
        assert!((d / want - 1.0).abs() < 1e-3, "{i}: {d:e} vs {want:e}");
    }
    // normal translation and rotation: far smaller (rho^-5 and the Faxén terms)
    assert!((got[2][2] - open[2][2]).abs() < 1e-2 * want);
}

fn periodic(ps: Vec<Particle>, lengths: [f64; 2]) -> System {
    System::new(
        Confinement::Wall { height: HEIGHT },
        ETA,
        ps,
        Overlap::Refuse,
    )
    .unwrap()
    .periodic(PeriodicBox::lateral(lengths))
    .unwrap()
}

fn max_abs(m: &DMatrix<f64>) -> f64 {
    m.iter().fold(0.0f64, |a, v| a.max(v.abs()))
}

/// Spheres above the wall, clear of each other by their nearest lateral images.
fn spheres() -> Vec<Particle> {
    vec![
        p([0.5, 0.5, 1.3 + HEIGHT], 1.0),
        p([3.0, 1.0, 2.0 + HEIGHT], 0.7),
        p([6.5, 5.5, 1.1 + HEIGHT], 0.9),
        p([1.0, 6.0, 4.0 + HEIGHT], 0.8),
        p([5.0, 3.0, 3.2 + HEIGHT], 0.6),
    ]
}

/// The dense matrix is symmetric (each pair evaluated once: exactly) and positive
/// definite at F, FT and FTS, its product agrees with it (the fast product at F and FT,
/// the direct sums at FTS); moving spheres by box lengths changes no bit.
#[test]
fn dense_matrix_is_positive_definite_and_periodic() {
    let lengths = [8.0, 8.0];
    let s = periodic(spheres(), lengths);
    for moments in [Moments::F, Moments::FT, Moments::FTS] {
        let m = s.mobility(moments);
        assert_eq!(m, m.transpose());
        assert!(check_spd(&m).positive_definite, "{moments:?}");
        let x: Vec<f64> = (0..m.nrows()).map(|i| (i as f64 * 0.37).sin()).collect();
        let mx = &m * DMatrix::from_column_slice(x.len(), 1, &x);
        // the fast product (`periodic::wall_product`): to the tolerance of the largest
        // entry of the result
        let y = s.apply(moments, &x);
        let scale = mx.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for (a, b) in mx.iter().zip(&y) {
            assert!((a - b).abs() < PeriodicBox::TOLERANCE * scale);
        }
    }
    // the spheres' coordinates are on a coarse grid: the moves are exact, and the
    // kernels see the wrapped positions (a million boxes away too)
    let mut moved = spheres();
    moved[1].x[0] += 8.0 * 1048576.0;
    moved[3].x[1] -= 16.0;
    let (m, n) = (
        s.mobility(Moments::FT),
        periodic(moved, lengths).mobility(Moments::FT),
    );
    assert_eq!(m, n);
}

/// libMobility's check of DPStokes: a box doubled along x with every sphere replicated
/// is the same system, so the mobility of sphere `a` from the forces on `b` and its
/// replica is the original box's `M^{ab}`; to the tolerance, 1e-10 of the largest entry.
#[test]
fn a_doubled_box_with_replicated_spheres_is_the_same_system() {
    let lengths = [8.0, 8.0];
    let ps = spheres();
    let n = ps.len();
    let mut doubled = ps.clone();
    doubled.extend(ps.iter().map(|q| p([q.x[0] + 8.0, q.x[1], q.x[2]], q.a)));
    let m = periodic(ps, lengths).mobility(Moments::FT);
    let d = periodic(doubled, [16.0, 8.0]).mobility(Moments::FT);
    // moment-major: component i < 3 of sphere a at 3 a + i, else 3 N + 3 a + i - 3
    let g = |count: usize, a: usize, i: usize| {
        if i < 3 {
            3 * a + i
        } else {
            3 * count + 3 * a + i - 3
        }
    };
    let scale = max_abs(&m);
    for a in 0..n {
        for b in 0..n {
            for i in 0..6 {
                for j in 0..6 {
                    let want = m[(g(n, a, i), g(n, b, j))];
                    let got = d[(g(2 * n, a, i), g(2 * n, b, j))]
                        + d[(g(2 * n, a, i), g(2 * n, b + n, j))];
                    assert!(
                        (got - want).abs() < 1e-10 * scale,
                        "{a} {b} {i} {j}: {got:e} vs {want:e}"
                    );
                }
            }
        }
    }
}

/// What a box along a wall cannot be or do: typed errors with their reasons.
#[test]
fn bad_boxes_near_walls_are_refused() {
    let above = vec![p([0.0, 0.0, 2.0], 1.0), p([3.0, 0.0, 2.0], 1.0)];
    let make = |conf: Confinement| System::new(conf, 1.0, above.clone(), false).unwrap();
    let wall = Confinement::Wall { height: 0.0 };
    let reason = |e: PeriodicError| match e {
        PeriodicError::Confinement { why, .. } => why,
        other => panic!("{other}"),
    };
    // free surfaces and interfaces (1/rho), a side wall (periodic along its normal),
    // free space with two lengths, a wall with three (the slit: `periodic::slit`)
    let surface = make(Confinement::FreeSurface { height: 0.0 })
        .periodic(PeriodicBox::lateral([10.0, 10.0]))
        .unwrap_err();
    assert!(reason(surface).contains("1/rho"));
    let side = System::new(
        Confinement::SideWall { side: -2.0 },
        1.0,
        above.clone(),
        false,
    )
    .unwrap()
    .periodic(PeriodicBox::lateral([10.0, 10.0]))
    .unwrap_err();
    assert!(reason(side).contains("normal"));
    let free = make(Confinement::Free)
        .periodic(PeriodicBox::lateral([10.0, 10.0]))
        .unwrap_err();
    assert!(reason(free).contains("net lateral force"));
    let three = make(wall)
        .periodic(PeriodicBox::new([10.0; 3]))
        .unwrap_err();
    assert!(reason(three).contains("two lengths"));
    // lengths, own images, overlaps by nearest lateral images
    let e = make(wall)
        .periodic(PeriodicBox::lateral([10.0, 0.0]))
        .unwrap_err();
    assert!(
        matches!(e, PeriodicError::BadLength { axis: 'y', .. }),
        "{e}"
    );
    let e = make(wall)
        .periodic(PeriodicBox::lateral([10.0, 1.9]))
        .unwrap_err();
    assert!(
        matches!(e, PeriodicError::OwnImage { axis: 'y', .. }),
        "{e}"
    );
    let e = make(wall)
        .periodic(PeriodicBox::lateral([4.5, 10.0]))
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
    // a sphere cutting the wall (accepted in open space with the RPY overlap forms)
    let cutting = System::new(wall, 1.0, vec![p([0.0, 0.0, 0.5], 1.0)], Overlap::Rpy)
        .unwrap()
        .periodic(PeriodicBox::lateral([10.0, 10.0]))
        .unwrap_err();
    assert!(
        matches!(cutting, PeriodicError::CutsWall { index: 0, .. }),
        "{cutting}"
    );
}

/// The Brownian drift near a periodic wall, `sum_b sum_j d/dx_bj M^{ab}_ij` (translational
/// and rotational rows), against central differences of the dense FT mobility in every
/// coordinate of every sphere (Richardson-extrapolated, steps 1e-3 and 5e-4): an
/// independent path (the blocks' values only) that also checks that distinct spheres add
/// no drift and that the lateral and rotational rows vanish. Three spheres of unequal
/// radii at different heights in a box that is not square, tolerance 1e-12: the
/// differences carry the sums' truncation and rounding, ~1e-12 of the largest entry
/// (~0.06) over the step 5e-4 times the extrapolation's weights, ~1e-10 or 1e-8 of the
/// drift, and O(step^4) after extrapolation; asserted within 1e-8 of the largest drift
/// (measured: 5e-12).
#[test]
fn the_drift_is_the_divergence_of_the_periodic_mobility() {
    let spheres = vec![
        p([0.3, 0.2, 1.6], 1.0),
        p([2.9, -1.7, 2.5], 0.8),
        p([-1.1, 4.2, 4.0], 1.2),
    ];
    let bx = PeriodicBox {
        tolerance: 1e-12,
        ..PeriodicBox::lateral([9.0, 11.0])
    };
    let system = |ps: &[Particle]| {
        System::new(
            Confinement::Wall { height: HEIGHT },
            ETA,
            ps.to_vec(),
            Overlap::Refuse,
        )
        .unwrap()
        .periodic(bx)
        .unwrap()
    };
    drift_is_the_divergence(&spheres, system, "near a periodic wall");
}

/// The drift of `spheres` in `system(spheres)` against the central differences of its
/// dense FT mobility in every coordinate of every sphere (Richardson-extrapolated, steps
/// 1e-3 and 5e-4: truncation ~1e-10, rounding ~1e-16/5e-4 of the entries), lateral and
/// rotational rows included: within 1e-8 of the largest, which is not small.
pub(super) fn drift_is_the_divergence(
    spheres: &[Particle],
    system: impl Fn(&[Particle]) -> System,
    label: &str,
) {
    let n = spheres.len();
    let drift = system(spheres).divergence_at(Moments::FT);
    // d/dx_bj of the FT mobility's force columns of sphere b, by central differences
    let derivative = |b: usize, j: usize, step: f64| -> DMatrix<f64> {
        let moved = |sign: f64| {
            let mut ps = spheres.to_vec();
            ps[b].x[j] += sign * step;
            system(&ps).mobility(Moments::FT)
        };
        (moved(1.0) - moved(-1.0)) / (2.0 * step)
    };
    let mut want = vec![0.0; 6 * n];
    for b in 0..n {
        for j in 0..3 {
            let (coarse, fine) = (derivative(b, j, 1e-3), derivative(b, j, 5e-4));
            let d = (fine * 4.0 - coarse) / 3.0;
            for a in 0..n {
                for i in 0..3 {
                    want[3 * a + i] += d[(3 * a + i, 3 * b + j)];
                    want[3 * n + 3 * a + i] += d[(3 * n + 3 * a + i, 3 * b + j)];
                }
            }
        }
    }
    let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let worst = drift
        .iter()
        .zip(&want)
        .fold(0.0f64, |m, (g, w)| m.max((g - w).abs()));
    println!(
        "drift {label}: worst {:.1e} of the largest {scale:.3e}",
        worst / scale
    );
    for a in 0..n {
        println!(
            "  sphere {a}: generated {:?}, differences {:?}",
            &drift[3 * a..3 * a + 3],
            &want[3 * a..3 * a + 3]
        );
    }
    assert!(worst <= 1e-8 * scale, "worst {worst:e} of {scale:e}");
    // the drift is along the normal, and not small
    assert!(scale > 1e-3 / (8.0 * PI * ETA), "{scale:e}");
}

/// Brownian dynamics near a periodic wall runs with every scheme and noise (a few steps
/// of two spheres, F and FT): Euler-Maruyama with the generated drift (Cholesky and
/// Lanczos noise), Fixman's midpoint and the lubricated dynamics; the steps are finite,
/// move the spheres, and keep positions unwrapped (a sphere started outside the box stays
/// there). The drift itself is checked above; its statistics (heights Boltzmann-
/// distributed) take minutes and are in `cargo xtask report`.
#[test]
fn brownian_dynamics_runs_near_a_periodic_wall() {
    brownian_dynamics_runs(Confinement::Wall { height: HEIGHT });
}

/// The runs of [`brownian_dynamics_runs_near_a_periodic_wall`] in `confinement` (walls
/// at `x3 = HEIGHT` and, for a slit, above `4.5`).
pub(super) fn brownian_dynamics_runs(confinement: Confinement) {
    use rand::SeedableRng;
    use stokesian::{Brownian, LubricatedDynamics, Lubrication, Noise, Scheme};
    let start = System::new(
        confinement,
        ETA,
        vec![p([0.5, 0.5, 2.0], 1.0), p([13.0, 2.5, 3.1], 0.9)],
        Overlap::Refuse,
    )
    .unwrap()
    .periodic(PeriodicBox {
        tolerance: 1e-6,
        ..PeriodicBox::lateral([8.0, 9.0])
    })
    .unwrap();
    let lubricated = LubricatedDynamics {
        lubrication: Lubrication::default(),
        rfd_step: 1e-3,
    };
    let runs = [
        (Moments::F, Scheme::EulerMaruyama, Noise::Cholesky, None),
        (Moments::FT, Scheme::EulerMaruyama, Noise::Cholesky, None),
        (
            Moments::F,
            Scheme::EulerMaruyama,
            Noise::Lanczos { tol: 1e-8 },
            None,
        ),
        (Moments::F, Scheme::FixmanMidpoint, Noise::Cholesky, None),
        (
            Moments::F,
            Scheme::EulerMaruyama,
            Noise::Cholesky,
            Some(lubricated),
        ),
    ];
    for (moments, scheme, noise, lubrication) in runs {
        let bd = Brownian {
            kt: 1.0,
            dt: 1e-3,
            drift: true,
            forces: integration_tests::NO_FORCES,
            noise,
            hydrodynamics: true,
            moments,
            scheme,
            lubrication,
        };
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let mut s = start.clone();
        for step in 0..3 {
            s = s.brownian_step(&bd, &mut rng, step).unwrap().system;
        }
        for (q, q0) in s.particles().iter().zip(start.particles()) {
            let moved = (0..3)
                .map(|k| (q.x[k] - q0.x[k]).powi(2))
                .sum::<f64>()
                .sqrt();
            assert!(
                moved.is_finite() && moved > 0.0 && moved < 0.5,
                "{moments:?} {scheme:?} {noise:?}: moved {moved}"
            );
        }
        // unwrapped: the second sphere stays beyond the box's first period
        assert!(s.particles()[1].x[0] > 9.0, "{:?}", s.particles()[1].x);
    }
}
