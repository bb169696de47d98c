//! Spheres in a slit periodic along its walls ([`stokesian::periodic::slit`]): the Green's
//! function vanishes on both walls (a point at either wall moves with it, whatever the
//! source), equals its second evaluation (all of the walls' flow in lateral modes, sharing
//! nothing with the walls' Ewald sums), is reciprocal, does not depend on the split
//! parameter, tends to the periodic wall's as the upper wall recedes, and gives Faxén's mobility of a small sphere on the mid-plane and at a
//! quarter of the gap (the superposition of two walls' images does not); the drift is
//! the divergence of the mobility; the system's matrix is symmetric positive definite,
//! agrees with its product, does not see a move by a box length; what such a box cannot
//! be or do is a typed error.

use kernels::Confinement;
use std::f64::consts::PI;
use stokesian::periodic::slit::SlitEwald;
use stokesian::periodic::wall::WallEwald;
use stokesian::{check_spd, Moments, Overlap, Particle, PeriodicBox, PeriodicError, System};

use super::wall::{difference, largest, p, ETA};

/// The lower wall's plane.
pub(super) const BOTTOM: f64 = 0.5;

/// Three spheres of unequal radii at unequal heights in a slit of gap 7.
fn spheres() -> [Particle; 3] {
    [
        p([0.4, 8.7, 1.2 + BOTTOM], 1.0),
        p([3.1, 1.2, 2.5 + BOTTOM], 0.6),
        p([-5.0, 3.0, 5.9 + BOTTOM], 0.8),
    ]
}

/// No slip on both walls: the velocity of a point (radius 0) on either wall from a force,
/// a torque or a stresslet on any sphere, and its own images, is zero to the tolerance of the
/// velocity scale, the free Stokeslet's `1/(8 pi eta d)` at the smallest distance `d`
/// from the source's lateral images (the largest term the walls' flow cancels).
#[test]
fn the_flow_vanishes_on_both_walls() {
    let lengths = [9.0, 12.0];
    let gap = 7.0;
    let slit = SlitEwald::new(lengths, BOTTOM, gap, 1e-12, None);
    for q in spheres() {
        for z in [BOTTOM, BOTTOM + gap] {
            for lateral in [[q.x[0], q.x[1]], [q.x[0] + 1.3, q.x[1] - 2.1], [7.7, 0.3]] {
                let point = p([lateral[0], lateral[1], z], 0.0);
                let b = slit.blocks(ETA, &point, &q, false);
                let d = (z - q.x[2]).abs();
                let scale = 1.0 / (8.0 * PI * ETA * d);
                let worst =
                    b.uf.iter()
                        .chain(&b.ul)
                        .flatten()
                        .fold(0.0f64, |m, v| m.max(v.abs()));
                // the FTS blocks: the stresslet's flow too (`US`)
                let g = slit.grand(ETA, &point, &q, false);
                let worst_fts = (g.uf.iter().chain(&g.ul).flatten())
                    .chain(g.us.iter().flatten())
                    .fold(0.0f64, |m, v| m.max(v.abs()));
                println!(
                    "no slip at x3 = {z}, {lateral:?}: FT {:.1e}, FTS {:.1e}",
                    worst / scale,
                    worst_fts / scale
                );
                assert!(
                    worst < 1e-11 * scale && worst_fts < 1e-11 * scale,
                    "{z} {lateral:?}: {worst:e}, {worst_fts:e} of {scale:e}"
                );
                assert!(g.es.iter().flatten().any(|v| v.abs() > 1e-3 * scale));
                // the wall's shear rotates the point: the test is not empty
                assert!(b.of.iter().flatten().any(|v| v.abs() > 1e-3 * scale));
            }
        }
    }
}

/// `M^{ab} = (M^{ba})^T`: the walls' flow applied with the source's operators at one end
/// and the field point's at the other, both ways; FT and FTS blocks.
#[test]
fn the_sums_are_reciprocal() {
    let slit = SlitEwald::new([9.0, 12.0], BOTTOM, 7.0, 1e-12, None);
    let ps = spheres();
    for i in 0..3 {
        for j in 0..3 {
            let ab = slit.blocks(ETA, &ps[i], &ps[j], i == j).matrix();
            let ba = slit.blocks(ETA, &ps[j], &ps[i], i == j).matrix();
            let scale = largest(&ab);
            for r in 0..6 {
                for c in 0..6 {
                    let d = (ab[r][c] - ba[c][r]).abs();
                    assert!(d < 1e-12 * scale, "{i} {j} ({r}, {c}): {d:e} of {scale:e}");
                }
            }
            let ab = slit.grand(ETA, &ps[i], &ps[j], i == j).matrix();
            let ba = slit.grand(ETA, &ps[j], &ps[i], i == j).matrix();
            let d = (ab - ba.transpose()).amax();
            assert!(
                d < 1e-12 * ab.amax(),
                "FTS {i} {j}: {d:e} of {:e}",
                ab.amax()
            );
        }
    }
}

/// Two evaluations of the same sum: the two walls' periodic sums (Blake's images in real
/// space and by their symbols) with the remainder's few modes, and the Stokeslet's sum
/// with the whole of the walls' flow in lateral modes (no image in real space; its own
/// mode `k_par = 0`): at tolerance 1e-12 within 1e-11 of each block's largest entry (each
/// within a few times its tolerance there, as the periodic wall's sums), and at 1e-10 and
/// 1e-6 the blocks within the tolerance of the sum by modes at 1e-14.
#[test]
fn images_in_real_space_and_all_in_modes_agree() {
    let slit = |tol| SlitEwald::new([9.0, 12.0], BOTTOM, 7.0, tol, None);
    let reference = slit(1e-14);
    let mut ps = spheres().to_vec();
    // and a pair close to the lower wall, the hardest for the modes
    ps.push(p([1.3, 2.0, BOTTOM + 1.0001], 1.0));
    ps.push(p([3.4, 2.3, BOTTOM + 1.05], 1.0));
    let s = slit(1e-12);
    let (mut worst, mut worst_fts) = (0.0f64, 0.0f64);
    for i in 0..ps.len() {
        for j in i..ps.len() {
            let got = s.blocks(ETA, &ps[i], &ps[j], i == j);
            let modes = s.blocks_by_modes(ETA, &ps[i], &ps[j], i == j);
            let scale = largest(&modes.matrix());
            worst = worst.max(difference(&got, &modes) / scale);
            let got = s.grand(ETA, &ps[i], &ps[j], i == j).matrix();
            let modes = s.grand_by_modes(ETA, &ps[i], &ps[j], i == j).matrix();
            worst_fts = worst_fts.max((got - modes).amax() / modes.amax());
        }
    }
    println!(
        "two evaluations at 1e-12: {worst:.1e} (FT), {worst_fts:.1e} (FTS) of the largest entry"
    );
    assert!(worst < 1e-11, "{worst:e}");
    assert!(worst_fts < 1e-11, "FTS {worst_fts:e}");
    for tol in [1e-10, 1e-6] {
        let s = slit(tol);
        let mut worst = 0.0f64;
        for i in 0..ps.len() {
            for j in i..ps.len() {
                let want = reference.blocks_by_modes(ETA, &ps[i], &ps[j], i == j);
                let scale = largest(&want.matrix());
                let got = s.blocks(ETA, &ps[i], &ps[j], i == j);
                worst = worst.max(difference(&got, &want) / scale);
            }
        }
        println!("tolerance {tol:e}: worst {worst:.1e} of the largest entry");
        assert!(worst < tol, "{tol:e}: {worst:e}");
    }
}

/// `xi` a factor 6 apart: the real part, `J^K`'s sum and the mode `k_par = 0` trade
/// their shares; the walls' modes do not depend on `xi`. FT and FTS.
#[test]
fn the_split_parameter_changes_nothing() {
    let lengths = [9.0, 12.0];
    super::wall::split_changes_nothing(lengths, &spheres(), |xi| {
        let e = SlitEwald::new(lengths, BOTTOM, 7.0, 1e-12, Some(xi));
        move |a: &Particle, b: &Particle, same| e.blocks(ETA, a, b, same).flat().to_vec()
    });
    super::wall::split_changes_nothing(lengths, &spheres(), |xi| {
        let e = SlitEwald::new(lengths, BOTTOM, 7.0, 1e-12, Some(xi));
        move |a: &Particle, b: &Particle, same| e.grand(ETA, a, b, same).flat().to_vec()
    });
}

/// As the upper wall recedes, the slit is the periodic wall plus the upper wall's share of
/// the mode `k_par = 0` (the slit's blocks hold the lower wall's sum: this checks the
/// upper wall's mirrored sum, the remainder and the bookkeeping of the mode `k_par = 0`
/// against what they must add up to), `-8 pi h_a h_b/(H A)` on the lateral translations and
/// its height derivatives on the rotations (`(1/2) eps_m3j d_a`, `(1/2) eps_j3i d_b`,
/// `(1/4) d_a d_b`); the modes `k_par != 0` of the upper wall are `exp(-K0 (2 H - h_a -
/// h_b))`, below 1e-30 here.
#[test]
fn a_receding_upper_wall_leaves_the_periodic_wall() {
    let lengths = [9.0, 12.0];
    let area = lengths[0] * lengths[1];
    let gap = 60.0;
    let tol = 1e-12;
    let slit = SlitEwald::new(lengths, BOTTOM, gap, tol, None);
    let wall = WallEwald::new(lengths, BOTTOM, tol, None);
    let ps = spheres();
    for i in 0..3 {
        for j in i..3 {
            let got = slit.blocks(ETA, &ps[i], &ps[j], i == j).matrix();
            let mut want = wall.blocks(ETA, &ps[i], &ps[j], i == j).matrix();
            let (ha, hb) = (ps[i].x[2] - BOTTOM, ps[j].x[2] - BOTTOM);
            let unit = 1.0 / (8.0 * PI * ETA * area);
            let c = -8.0 * PI / gap * unit;
            for d in 0..2 {
                want[d][d] += c * ha * hb;
                want[3 + d][3 + d] += 0.25 * c;
            }
            // OmegaF_mj = (1/2) eps_m3j d_a f: (m, j) = (1, 2) -> -1; d_a f = c hb
            want[3][1] -= 0.5 * c * hb;
            want[4][0] += 0.5 * c * hb;
            // UL_ij = (1/2) eps_j3i d_b f: (i, j) = (1, 2) -> +1; d_b f = c ha
            want[0][4] += 0.5 * c * ha;
            want[1][3] -= 0.5 * c * ha;
            let scale = largest(&want);
            let worst = (0..36).fold(0.0f64, |m, k| {
                m.max((got[k / 6][k % 6] - want[k / 6][k % 6]).abs())
            });
            println!(
                "slit (H = {gap}) against the wall, {i} {j}: {:.1e}",
                worst / scale
            );
            assert!(worst < 1e-11 * scale, "{i} {j}: {worst:e} of {scale:e}");
        }
    }
}

/// Faxén's mobility of a small sphere moving along the walls of a slit (Happel &
/// Brenner Sec. 7-4): `mu/mu0 = 1 - 1.004 (a/l) + ...` on the mid-plane (`l = H/2`) and
/// `1 - 0.6526 (a/l) + ...` at a quarter of the gap (`l = H/4`, the nearer wall), `l`
/// the distance to the nearer wall. The coefficient of `a/l` is the point force's, the
/// exact slit Green's function's alone; the superposition of two walls' images gives
/// `9/8` and `3/4`. A sphere of radius `1e-3 l`, in a square box `L = 60 H`, whose
/// lattice adds `O(a H/L^2)`, `O(H^2/L^2) = 3e-4` of the coefficient; the coefficients
/// are quoted to four digits: within 1e-3.
#[test]
fn a_small_sphere_has_faxens_mobility() {
    let gap = 2.0;
    let l_box = 60.0 * gap;
    let slit = SlitEwald::new([l_box, l_box], BOTTOM, gap, 1e-12, None);
    for (l, want) in [(0.5 * gap, 1.004), (0.25 * gap, 0.6526)] {
        let a = 1e-3 * l;
        let q = p([0.3, 0.1, BOTTOM + l], a);
        let b = slit.blocks(ETA, &q, &q, true);
        let mu0 = 1.0 / (6.0 * PI * ETA * a);
        for d in 0..2 {
            let coefficient = (1.0 - b.uf[d][d] / mu0) / (a / l);
            println!("l = {l}: coefficient {coefficient:.5} (Faxén {want})");
            assert!((coefficient - want).abs() < 1e-3, "{coefficient} vs {want}");
        }
    }
}

/// Spheres `ps` in the slit of gap `gap` above `BOTTOM`, periodic with lateral `lengths`
/// at tolerance `tol`.
pub(super) fn periodic(ps: Vec<Particle>, lengths: [f64; 2], gap: f64, tol: f64) -> System {
    System::new(
        Confinement::Slit {
            height: BOTTOM,
            gap,
        },
        ETA,
        ps,
        Overlap::Refuse,
    )
    .unwrap()
    .periodic(PeriodicBox {
        tolerance: tol,
        ..PeriodicBox::lateral(lengths)
    })
    .unwrap()
}

/// The drift is the divergence of the periodic mobility
/// ([`super::wall::drift_is_the_divergence`]).
#[test]
fn the_drift_is_the_divergence_of_the_periodic_mobility() {
    let spheres = vec![
        p([0.3, 0.2, 1.6], 1.0),
        p([2.9, -1.7, 2.5], 0.8),
        p([-1.1, 4.2, 4.0], 1.2),
    ];
    let system = |ps: &[Particle]| periodic(ps.to_vec(), [9.0, 11.0], 5.5, 1e-12);
    super::wall::drift_is_the_divergence(&spheres, system, "in a periodic slit");
}

/// The dense matrix is symmetric positive definite at F, FT and FTS, its product is the
/// fast product's to the tolerance (`slit_product` for more), and a sphere moved by box lengths changes
/// no bit of it (dyadic coordinates: the moves are exact).
#[test]
fn dense_matrix_is_positive_definite_and_periodic() {
    let lengths = [8.0, 8.0];
    let ps = vec![
        p([0.5, 0.5, 1.7], 1.0),
        p([2.75, 0.875, 3.2], 0.7),
        p([5.5, 6.0, 2.3], 0.9),
        p([1.5, 4.5, 4.3], 1.0),
    ];
    let system = periodic(ps.clone(), lengths, 5.0, 1e-10);
    for moments in [Moments::F, Moments::FT, Moments::FTS] {
        let m = system.mobility(moments);
        let dim = m.nrows();
        let scale = m.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        assert!((&m - m.transpose())
            .iter()
            .all(|v| v.abs() <= 1e-12 * scale));
        assert!(check_spd(&m).positive_definite, "{moments:?}");
        let x: Vec<f64> = (0..dim).map(|k| (k as f64 * 0.37).sin()).collect();
        let y = system.apply(moments, &x);
        let want = &m * nalgebra::DVector::from_column_slice(&x);
        let worst = (0..dim).fold(0.0f64, |acc, k| acc.max((y[k] - want[k]).abs()));
        // the fast product (the direct sums at FTS), to the box's tolerance 1e-10 of the
        // largest entry
        assert!(worst <= 1e-10 * scale, "{worst:e}");
        let mut moved = ps.clone();
        moved[2].x[0] += 2.0 * lengths[0];
        moved[1].x[1] -= lengths[1];
        let m2 = periodic(moved, lengths, 5.0, 1e-10).mobility(moments);
        assert_eq!(m, m2, "moves by box lengths");
    }
}

/// A sphere cutting either wall, three lengths: typed errors.
#[test]
fn bad_slits_are_refused() {
    let slit = Confinement::Slit {
        height: BOTTOM,
        gap: 5.0,
    };
    let make = |ps: Vec<Particle>| System::new(slit, ETA, ps, Overlap::Refuse);
    let inside = vec![p([0.0, 0.0, 2.0], 1.0), p([3.0, 0.0, 3.0], 1.0)];
    let err = make(inside)
        .unwrap()
        .periodic(PeriodicBox::new([8.0, 8.0, 8.0]))
        .unwrap_err();
    assert!(matches!(err, PeriodicError::Confinement { .. }), "{err}");
    // 0.6 below the upper wall with radius 0.7: the open slit takes it with its overlap
    // forms, the periodic one refuses it
    if let Ok(system) = make(vec![p([0.0, 0.0, BOTTOM + 4.4], 0.7)]) {
        let err = system
            .periodic(PeriodicBox::lateral([8.0, 8.0]))
            .unwrap_err();
        assert!(matches!(err, PeriodicError::CutsWall { .. }), "{err}");
    }
}

/// Brownian dynamics in a periodic slit runs with every scheme and noise, as along one
/// wall (its statistics near one wall are in `cargo xtask report`).
#[test]
fn brownian_dynamics_runs_in_a_periodic_slit() {
    super::wall::brownian_dynamics_runs(Confinement::Slit {
        height: 0.5,
        gap: 4.5,
    });
}
