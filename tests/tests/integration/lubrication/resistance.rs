//! The FT and FTS resistance with lubrication (Eq. 19): positive definiteness down to
//! gaps of 1e-8 a, physical signs, and the assembly of the near-field tensors. The FTS
//! resistance carries the same force-torque corrections (its stresslet rows keep the
//! far-field inverse), so every check runs at both levels; the U and Omega indices are
//! the same in both layouts.

use std::f64::consts::PI;
use stokesian::resistance::two_sphere::resistance_scalars;
use stokesian::{wall_functions, Confinement, Lubrication, Moments, Particle, System};

fn sphere(x: [f64; 3]) -> Particle {
    Particle { x, a: 1.0 }
}

/// Index of component k of [U, Omega] of particle a in the FT and FTS layouts.
fn ix(n: usize, a: usize, k: usize) -> usize {
    if k < 3 {
        3 * a + k
    } else {
        3 * n + 3 * a + k - 3
    }
}

/// For two spheres in unbounded fluid with the pair correction everywhere, Eq. 19
/// collapses at every separation (inside and far beyond the old cutoff `xi = 2`) to the exact
/// two-sphere resistance (M^-1 and R^{P,inf} are the same matrix), so the assembled R
/// must show the Kim & Karrila tensor forms with the functions of
/// `stokesian::resistance::two_sphere`. Tolerance 1e-9 relative: M^-1 - R^{P,inf} cancels to
/// round-off of an inverse with condition ~1/xi.
#[test]
fn isolated_pair_resistance_is_the_two_sphere_tensor() {
    for moments in [Moments::FT, Moments::FTS] {
        for xi in [1e-3, 0.5, 2.0, 8.0, 30.0] {
            isolated_pair(moments, xi);
        }
    }
}

fn isolated_pair(moments: Moments, xi: f64) {
    let s = System::new(
        Confinement::Free,
        1.0,
        vec![sphere([0.0; 3]), sphere([2.0 + xi, 0.0, 0.0])],
        false,
    )
    .unwrap();
    let r = s.resistance(moments, &Lubrication::everywhere()).unwrap();
    let f = resistance_scalars(2.0 + xi, 1.0).unwrap();
    let (sa, sb, sc) = (6.0 * PI, 4.0 * PI, 8.0 * PI);
    let checks = [
        ("X11A", r[(ix(2, 0, 0), ix(2, 0, 0))] / sa, f.x11a),
        ("X12A", r[(ix(2, 0, 0), ix(2, 1, 0))] / sa, f.x12a),
        ("Y11A", r[(ix(2, 0, 1), ix(2, 0, 1))] / sa, f.y11a),
        ("Y12A", r[(ix(2, 0, 2), ix(2, 1, 2))] / sa, f.y12a),
        // B_ij = Y^B eps_ijk d_k, d = e_x: B_zy = -Y^B (R_LU, torque z from velocity y)
        ("Y11B", -r[(ix(2, 0, 5), ix(2, 0, 1))] / sb, f.y11b),
        ("Y12B", -r[(ix(2, 0, 5), ix(2, 1, 1))] / sb, f.y12b),
        ("X11C", r[(ix(2, 0, 3), ix(2, 0, 3))] / sc, f.x11c),
        ("X12C", r[(ix(2, 0, 3), ix(2, 1, 3))] / sc, f.x12c),
        ("Y11C", r[(ix(2, 0, 4), ix(2, 0, 4))] / sc, f.y11c),
        ("Y12C", r[(ix(2, 0, 4), ix(2, 1, 4))] / sc, f.y12c),
    ];
    for (name, got, want) in checks {
        assert!(
            (got - want).abs() <= 1e-9 * want.abs().max(1.0),
            "{moments:?} xi {xi} {name}: {got} vs {want}"
        );
    }
    // Gap shear: sphere 0 moving +y beside sphere 1 (d = e_x) feels a torque -z on it:
    // the torque on the particle is -(R U), so R_{Lz, Uy} > 0.
    assert!(r[(ix(2, 0, 5), ix(2, 0, 1))] > 0.0);
}

/// Signs and normalisations of every block of the exact pair resistance, stresslet
/// couplings included, against an independent path: far apart (r = 12 (a1 + a2)/2 and
/// beyond), the exact two-sphere resistance (cutoff raised to include the pair) must
/// approach the inverse of our own far-field FTS pair mobility (cutoff zero). For each
/// block of the 22 x 22 matrix (3x3, 3x5, 5x5 per ordered pair), the difference relative
/// to the block's norm is asserted below 2%: the far-field inverse is exact to the
/// orders it keeps, so the difference is O((a/r)^2) relative or smaller (largest 4.3e-4
/// measured, printed), while a wrong sign or normalisation of a function gives O(1).
/// Exempt are blocks whose difference is below 1e-7 of the whole matrix: the self
/// rotation-strain coupling, itself 1e-9 of the whole at this distance (a high-order
/// reflection the far-field truncation captures only to 5-7%).
#[test]
fn exact_pair_resistance_tends_to_the_far_field_inverse() {
    for (a2, dir) in [(1.0, [0.48, 0.6, 0.64]), (2.0, [0.0, 0.6, 0.8])] {
        let r = 12.0 * 0.5 * (1.0 + a2);
        let ps = vec![
            Particle {
                x: [0.0; 3],
                a: 1.0,
            },
            Particle {
                x: dir.map(|v| r * v),
                a: a2,
            },
        ];
        let s = System::new(Confinement::Free, 0.9, ps, false).unwrap();
        let far = s.resistance(Moments::FTS, &Lubrication::none()).unwrap();
        let exact = s
            .resistance(Moments::FTS, &Lubrication::everywhere())
            .unwrap();
        // moment-major ranges of U, Omega, E of particle a
        let range = |m: usize, a: usize| match m {
            0 => (3 * a, 3),
            1 => (6 + 3 * a, 3),
            _ => (12 + 5 * a, 5),
        };
        let mut worst = 0.0f64;
        for (a, b) in [(0, 0), (0, 1), (1, 1)] {
            for mi in 0..3 {
                for mj in 0..3 {
                    let ((r0, nr), (c0, nc)) = (range(mi, a), range(mj, b));
                    let e = exact.view((r0, c0), (nr, nc));
                    let f = far.view((r0, c0), (nr, nc));
                    let norm = e.norm();
                    if norm < 1e-12 * exact.norm() {
                        continue; // a block that vanishes (e.g. B of equal spheres, self)
                    }
                    let rel = (e - f).norm() / norm;
                    let of_whole = (e - f).norm() / exact.norm();
                    if of_whole > 1e-7 {
                        worst = worst.max(rel);
                    }
                    assert!(
                        rel < 0.02 || of_whole < 1e-7,
                        "a2 = {a2}, particles ({a},{b}), moments ({mi},{mj}): {rel:e}"
                    );
                }
            }
        }
        println!(
            "a2 = {a2}, r = {r}: largest block difference exact vs far-field inverse {worst:e}"
        );
    }
}

/// One sphere near a wall: Eq. 19 gives exactly the exact wall resistance; its sign conventions are physical: a sphere moving +x above the wall
/// gets a torque +y (gap shear at its lowest point), R_{Ly, Ux} < 0.
#[test]
fn single_sphere_wall_resistance_and_signs() {
    for moments in [Moments::FT, Moments::FTS] {
        single_sphere_wall(moments);
    }
}

fn single_sphere_wall(moments: Moments) {
    let eps = 1e-4;
    let s = System::new(
        Confinement::Wall { height: 0.0 },
        1.0,
        vec![sphere([0.3, 0.2, 1.0 + eps])],
        false,
    )
    .unwrap();
    let r = s.resistance(moments, &Lubrication::default()).unwrap();
    let w = wall_functions(eps);
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    assert!(rel(r[(2, 2)] / (6.0 * PI), w.xa) < 1e-9);
    assert!(rel(r[(0, 0)] / (6.0 * PI), w.ya) < 1e-9);
    assert!(rel(r[(3, 3)] / (8.0 * PI), w.yc) < 1e-9);
    assert!(rel(r[(5, 5)] / (8.0 * PI), w.xc) < 1e-9);
    assert!(r[(4, 0)] < 0.0, "R_Ly,Ux = {}", r[(4, 0)]);
    assert!(rel(-r[(4, 0)] / (6.0 * PI), w.fr) < 1e-9);
}

/// The FT resistance of one sphere (radius 0.8, viscosity 1.3) above a wall at every
/// height, `h/a` in [1.0001, 20] (40 heights, geometric in the gap): the five exact
/// sphere-wall functions of the bispherical series (`wall_series`, the tables'
/// source), to 1e-6 relative (the coupling to 1e-6 of `Y^A`, next to which it enters;
/// measured: 4e-13). With no cutoff there is no height where Eq. 19 falls back to the
/// far field.
#[test]
fn one_sphere_reproduces_the_exact_wall_functions_at_every_height() {
    let (a, eta) = (0.8, 1.3);
    let mut worst = 0.0f64;
    for k in 0..40 {
        let eps = 1e-4 * (19.0f64 / 1e-4).powf(k as f64 / 39.0);
        let s = System::new(
            Confinement::Wall { height: 0.0 },
            eta,
            vec![Particle {
                x: [0.1, -0.2, a * (1.0 + eps)],
                a,
            }],
            false,
        )
        .unwrap();
        let r = s.resistance(Moments::FT, &Lubrication::default()).unwrap();
        let w = stokesian::wall_series(eps);
        let (t, rot) = (6.0 * PI * eta * a, 8.0 * PI * eta * a.powi(3));
        let got = [
            (r[(2, 2)] / t, w.xa, w.xa),
            (r[(0, 0)] / t, w.ya, w.ya),
            (-r[(4, 0)] / (t * a), w.fr, w.ya),
            (r[(3, 3)] / rot, w.yc, w.yc),
            (r[(5, 5)] / rot, w.xc, w.xc),
        ];
        for (i, (g, want, scale)) in got.into_iter().enumerate() {
            let e = (g - want).abs() / scale.abs();
            worst = worst.max(e);
            assert!(
                e < 1e-6,
                "function {i} at h/a = {}: {g} vs {want}",
                1.0 + eps
            );
        }
    }
    println!("largest deviation from the exact wall functions: {worst:e}");
}

/// The resistance of one sphere and its derivative in the height are continuous across
/// h = 2 a, where the wall correction used to switch on: one-sided second-order
/// differences (step 1e-4 a) from either side agree to 1e-5 of the derivative (their
/// truncation error is about step^2 times the third derivative, ~1e-7 here; a kink
/// would show as a difference of order one), and the values just below and just above
/// agree to 1e-9 (a step would show as the old 5%).
#[test]
fn wall_resistance_is_smooth_across_the_old_cutoff() {
    let r = |h: f64| {
        System::new(
            Confinement::Wall { height: 0.0 },
            1.0,
            vec![sphere([0.0, 0.0, h])],
            false,
        )
        .unwrap()
        .resistance(Moments::FT, &Lubrication::default())
        .unwrap()
    };
    let (h0, d) = (2.0, 1e-4);
    let (below, above) = (r(h0 - 1e-12), r(h0 + 1e-12));
    assert!((&below - &above).norm() < 1e-9 * above.norm());
    // f'(h0) from the left: (3 f(h0) - 4 f(h0 - d) + f(h0 - 2 d)) / (2 d); from the right
    let left = (r(h0 - 2e-12) * 3.0 - r(h0 - d) * 4.0 + r(h0 - 2.0 * d)) / (2.0 * d);
    let right = (r(h0 + 2e-12) * -3.0 + r(h0 + d) * 4.0 - r(h0 + 2.0 * d)) / (2.0 * d);
    let rel = (&left - &right).norm() / right.norm();
    println!("one-sided derivatives at h = 2a differ by {rel:e} of the derivative");
    assert!(rel < 1e-5);
}

/// R is symmetric positive definite with gaps down to 1e-8 a, to the wall and between
/// spheres: a close chain of equal spheres just above a wall, a triangle, and a sphere
/// of radius 3 beside a unit sphere.
#[test]
fn resistance_is_spd_down_to_tiny_gaps() {
    for gap in [1e-2, 1e-4, 1e-6, 1e-8] {
        let h = 1.0 + gap;
        let step = 2.0 + gap;
        let chain: Vec<Particle> = (0..5).map(|k| sphere([k as f64 * step, 0.0, h])).collect();
        let tri = vec![
            sphere([0.0, 0.0, h]),
            sphere([step, 0.0, h]),
            sphere([0.5 * step, step * 0.75f64.sqrt(), h]),
            sphere([0.5 * step, 0.3, h + step]),
        ];
        // unequal radii: a sphere of radius 3 touching a unit sphere, both near the wall
        let mixed = vec![
            Particle {
                x: [0.0, 0.0, 3.0 + gap],
                a: 3.0,
            },
            Particle {
                x: [((4.0f64 + gap).powi(2) - 4.0).sqrt(), 0.0, h],
                a: 1.0,
            },
        ];
        for ps in [chain, tri, mixed] {
            let s = System::new(Confinement::Wall { height: 0.0 }, 1.0, ps, false).unwrap();
            for moments in [Moments::FT, Moments::FTS] {
                let r = s.resistance(moments, &Lubrication::default()).unwrap();
                let c = stokesian::check_spd(&r);
                assert!(c.passed(), "{moments:?} gap {gap}: {c:?}");
            }
        }
    }
}

/// The pair corrections are evaluated in parallel and added in the order of the pairs,
/// and the series of each size ratio give the same values however far they were summed
/// (`PairSeries::cached_at`): the lubricated resistance of unequal spheres near a wall is
/// the same bit for bit with 1, 2 and 3 threads, FT and FTS, every pair corrected.
#[test]
fn resistance_does_not_depend_on_the_number_of_threads() {
    // 27 spheres of radii 0.5-1.4 on a jittered lattice 1.5-6 radii above the wall,
    // gaps from 0.1 to several radii: close and far pairs, many size ratios
    let ps: Vec<Particle> = (0..27)
        .map(|i| {
            let (u, v, w) = ((i % 3) as f64, ((i / 3) % 3) as f64, (i / 9) as f64);
            let a = 0.5 + 0.9 * ((i * 7) % 11) as f64 / 10.0;
            let x = [3.1 * u + 0.2 * (i % 2) as f64, 3.2 * v, 1.6 + 3.3 * w];
            Particle { x, a }
        })
        .collect();
    let s = System::new(Confinement::Wall { height: 0.0 }, 1.0, ps, false).unwrap();
    for moments in [Moments::FT, Moments::FTS] {
        let run = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| s.resistance(moments, &Lubrication::everywhere()).unwrap())
        };
        let one = run(1);
        for threads in [2, 3] {
            assert!(
                run(threads) == one,
                "{moments:?}: {threads} threads differ from 1"
            );
        }
    }
}

/// Where many pairs share a size ratio, the resistance takes their functions from the
/// tables contracted once at that ratio (`pair_tables::AtRatio`), elsewhere from the
/// tables in two dimensions: a cluster of 16 equal spheres near a wall (240 calls at the
/// ratio 1) and the same cluster with every radius changed by at most 3.2e-12 (no ratio
/// shared by more than a few calls) give the same resistance, FT and FTS, every pair
/// corrected. The two paths give the functions to 1.4e-12 of `max(|F|, 1)`
/// (`tables_at_a_ratio_give_the_functions_of_the_tables`), and the radii change the
/// entries by about `delta a / xi`, 6e-11 relative at the smallest gap (`xi = 0.05`):
/// 1e-9 of the largest entry allows for both with a margin, and is far below what a
/// wrong function (the tables' errors are 1e-9 of the functions, any mistake in the
/// path or the ratio's orientation is of order one) would leave.
#[test]
fn shared_ratios_give_the_resistance_of_the_two_dimensional_tables() {
    let cluster = |perturb: bool| -> Vec<Particle> {
        (0..16)
            .map(|i| {
                let (u, v) = ((i % 4) as f64, (i / 4) as f64);
                let a = if perturb {
                    1.0 + 1e-13 * (((i * i * 7) % 31) + 1) as f64
                } else {
                    1.0
                };
                // gaps from 0.05 (the first row) to a few radii, heights 1.3 to 2.6
                let x = [
                    (2.05 + 0.3 * v) * u,
                    2.4 * v,
                    1.3 + 0.4 * v + 0.1 * (i % 2) as f64,
                ];
                Particle { x, a }
            })
            .collect()
    };
    for moments in [Moments::FT, Moments::FTS] {
        let r = |perturb: bool| {
            System::new(
                Confinement::Wall { height: 0.0 },
                1.0,
                cluster(perturb),
                false,
            )
            .unwrap()
            .resistance(moments, &Lubrication::everywhere())
            .unwrap()
        };
        let (equal, perturbed) = (r(false), r(true));
        let largest = equal.amax();
        let worst = (&equal - &perturbed).amax() / largest;
        println!("{moments:?}: shared against two-dimensional tables {worst:.1e}");
        assert!(worst < 1e-9, "{moments:?}: {worst:e}");
    }
}
