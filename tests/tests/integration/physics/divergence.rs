//! The generated divergence kernels (the Brownian drift kT div M), for every
//! confinement: against central finite differences of the generated mobility
//! kernels, zero in unbounded fluid, and for one sphere above a wall against the
//! derivative of the closed form B1; and the derivatives along a direction (the drift
//! of spheres held on a boundary) against finite differences the same way.

use integration_tests::{all_confinements, random_spheres};
use kernels::{
    pair, pair_along, pair_divergence, self_along, self_divergence, self_mobility, Confinement,
    Grand,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

/// Central difference of `f` along `e_j` at `x`, step `h`.
fn d_dx(f: impl Fn([f64; 3]) -> Grand, x: [f64; 3], j: usize, h: f64) -> Grand {
    let mut p = x;
    let mut m = x;
    p[j] += h;
    m[j] -= h;
    let (gp, gm) = (f(p).matrix(), f(m).matrix());
    Grand::from_matrix(&((gp - gm) / (2.0 * h)))
}

/// `sum_j d/dx_j M_{ij}` over the force columns of U and Omega rows, by differences.
fn fd_divergence(f: impl Fn([f64; 3]) -> Grand + Copy, x: [f64; 3], h: f64) -> [f64; 6] {
    let mut out = [0.0; 6];
    for j in 0..3 {
        let d = d_dx(f, x, j, h);
        for i in 0..3 {
            out[i] += d.uf[i][j];
            out[3 + i] += d.of[i][j];
        }
    }
    out
}

/// `sum_jk v_j v_k d/dx_k M_{ij}` over the force columns of U and Omega rows, by a
/// central difference along `v`.
fn fd_along(f: impl Fn([f64; 3]) -> Grand, x: [f64; 3], v: [f64; 3], h: f64) -> [f64; 6] {
    let at = |s: f64| f(std::array::from_fn(|k| x[k] + s * h * v[k])).matrix();
    let d = (at(1.0) - at(-1.0)) / (2.0 * h);
    let d = Grand::from_matrix(&d);
    let mut out = [0.0; 6];
    for j in 0..3 {
        for i in 0..3 {
            out[i] += d.uf[i][j] * v[j];
            out[3 + i] += d.of[i][j] * v[j];
        }
    }
    out
}

fn close(got: &[f64; 6], want: &[f64; 6], scale: f64, tol: f64) -> bool {
    got.iter()
        .zip(want)
        .all(|(a, b)| (a - b).abs() <= tol * scale)
}

/// Tolerance 1e-7 of the largest entry of the mobility's gradient scale (|M| / a): the
/// central differences with step 1e-4 a have truncation error ~1e-8 relative and
/// round-off ~1e-16 / 1e-4 = 1e-12.
#[test]
fn divergence_kernels_equal_finite_differences_for_every_confinement() {
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let eta = 0.8;
    for (name, conf) in all_confinements() {
        for _ in 0..4 {
            let ps = random_spheres(&mut rng, &conf, 2, (0.5, 1.2), 0.1, 5.0);
            let (p, q) = (ps[0], ps[1]);
            let h = 1e-4;
            let scale = 1.0 / (6.0 * PI * eta * p.a.min(q.a) * p.a.min(q.a));
            // pair: a = div over xb of M^{ab}; b = div over xa of M^{ba}
            let d = pair_divergence(&conf, eta, p.x, p.a, q.x, q.a);
            let fa = fd_divergence(|xb| pair(&conf, eta, p.x, p.a, xb, q.a), q.x, h);
            let fb = fd_divergence(|xa| pair(&conf, eta, q.x, q.a, xa, p.a), p.x, h);
            assert!(
                close(&d.a, &fa, scale, 1e-7),
                "{name} pair a: {:?} vs {fa:?}",
                d.a
            );
            assert!(
                close(&d.b, &fb, scale, 1e-7),
                "{name} pair b: {:?} vs {fb:?}",
                d.b
            );
            // self: the particle moves, both arguments of M^{aa}(x, x) with it
            let s = self_divergence(&conf, eta, p.x, p.a);
            let fs = fd_divergence(|x| self_mobility(&conf, eta, x, p.a), p.x, h);
            assert!(
                close(&s.a, &fs, scale, 1e-7),
                "{name} self: {:?} vs {fs:?}",
                s.a
            );
        }
    }
}

/// The derivatives along a direction: along every boundary's normal (what the drift
/// of a sphere held on that boundary takes) and along a direction of no symmetry, for
/// every confinement, against central differences of the generated mobility kernels;
/// tolerance as for the divergence above (same step, same scale).
#[test]
fn along_kernels_equal_finite_differences_for_every_confinement() {
    let mut rng = ChaCha8Rng::seed_from_u64(10);
    let eta = 0.8;
    for (name, conf) in all_confinements() {
        let mut directions: Vec<[f64; 3]> = conf.boundaries().iter().map(|b| b.normal).collect();
        directions.push([0.48, -0.6, 0.64]);
        for _ in 0..3 {
            let ps = random_spheres(&mut rng, &conf, 2, (0.5, 1.2), 0.1, 5.0);
            let (p, q) = (ps[0], ps[1]);
            let h = 1e-4;
            let scale = 1.0 / (6.0 * PI * eta * p.a.min(q.a) * p.a.min(q.a));
            for &v in &directions {
                let d = pair_along(&conf, eta, p.x, p.a, q.x, q.a, v);
                let fa = fd_along(|xb| pair(&conf, eta, p.x, p.a, xb, q.a), q.x, v, h);
                let fb = fd_along(|xa| pair(&conf, eta, q.x, q.a, xa, p.a), p.x, v, h);
                assert!(
                    close(&d.a, &fa, scale, 1e-7),
                    "{name} pair a along {v:?}: {:?} vs {fa:?}",
                    d.a
                );
                assert!(
                    close(&d.b, &fb, scale, 1e-7),
                    "{name} pair b along {v:?}: {:?} vs {fb:?}",
                    d.b
                );
                let s = self_along(&conf, eta, p.x, p.a, v);
                let fs = fd_along(|x| self_mobility(&conf, eta, x, p.a), p.x, v, h);
                assert!(
                    close(&s.a, &fs, scale, 1e-7),
                    "{name} self along {v:?}: {:?} vs {fs:?}",
                    s.a
                );
            }
        }
    }
}

/// In unbounded fluid the far-field mobility is divergence-free (the Stokeslet and its
/// Laplacian are solenoidal; the curl of a gradient vanishes): zero up to round-off.
#[test]
fn free_space_divergence_vanishes() {
    let d = pair_divergence(
        &Confinement::Free,
        1.0,
        [0.1, 0.2, 0.3],
        1.0,
        [2.5, -1.0, 0.7],
        0.6,
    );
    let scale = 1.0 / (6.0 * PI);
    assert!(
        d.a.iter().chain(&d.b).all(|v| v.abs() < 1e-14 * scale),
        "{d:?}"
    );
    let s = self_divergence(&Confinement::Free, 1.0, [0.0, 0.0, 0.0], 1.0);
    assert_eq!(s.a, [0.0; 6]);
}

/// One sphere at height h above a wall: M^{aa} depends on x3 only, so the drift is
/// d M_{i3} / d x3. From B1, M_33 = (1/(6 pi eta a)) [1 - (9 h^-1 - 4 h^-3 + h^-5)/8]
/// with h = x3/a, hence drift_3 = (1/(6 pi eta a^2)) (9 h^-2 - 12 h^-4 + 5 h^-6)/8, and
/// the other components vanish (M_13 = M_23 = 0; M_OmegaF,i3 = 0 by B2).
/// Tolerance 1e-13 relative: the same quantity, differentiated two ways.
#[test]
fn single_sphere_drift_is_the_derivative_of_b1() {
    let (eta, a) = (1.3, 0.7);
    for h in [1.0001, 1.1, 1.5, 3.0, 10.0] {
        let s = self_divergence(
            &Confinement::Wall { height: 0.0 },
            eta,
            [0.2, -0.4, h * a],
            a,
        );
        let want = (9.0 * h.powi(-2) - 12.0 * h.powi(-4) + 5.0 * h.powi(-6))
            / 8.0
            / (6.0 * PI * eta * a * a);
        assert!(
            (s.a[2] - want).abs() < 1e-13 * want.abs(),
            "h = {h}: {} vs {want}",
            s.a[2]
        );
        for k in [0, 1, 3, 4, 5] {
            assert!(
                s.a[k].abs() < 1e-15 * want.abs(),
                "h = {h}: component {k} = {}",
                s.a[k]
            );
        }
    }
}
