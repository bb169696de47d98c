//! Lubrication at a flat free surface (Eq. 19 with `R^W` of a sphere near a shear-free
//! plane): by symmetry the sphere and its mirror image are two equal spheres, so every
//! block is exact, stresslets included. Checked against series derived independently of
//! the two-sphere twin-multipole code (Brenner 1961 for the normal translation, Jeffery's
//! image sum for the rotation about the normal, `stokesian::resistance::exact`), and every block
//! against the inverse of our own far-field free-surface mobility far from the surface.

use std::f64::consts::PI;
use stokesian::resistance::exact::{brenner_xa_free_surface, jeffery_xc_free_surface};
use stokesian::{Confinement, Lubrication, Moments, Particle, System};

const SURFACE: Confinement = Confinement::FreeSurface { height: 0.5 };

fn one_sphere(a: f64, h: f64) -> System {
    let p = Particle {
        x: [0.3, -0.2, 0.5 + h],
        a,
    };
    System::new(SURFACE, 1.3, vec![p], false).unwrap()
}

/// Normal translation and rotation about the normal reproduce the exact series at every
/// height in [1.0001, 20] radii, FT and FTS, radius 0.7, viscosity 1.3. Tolerance 1e-6
/// relative: the two-sphere series at size ratio 1 are converged to ~5e-6 in the contact
/// constant of `X^A` (module docs of `two_sphere`), which is a far smaller fraction of the
/// `1/(4 eps)` singular drag; Brenner's and Jeffery's series are converged to round-off.
#[test]
fn one_sphere_reproduces_the_exact_free_surface_functions() {
    let a = 0.7;
    let eta = 1.3;
    let mut worst = [0.0f64; 2];
    for moments in [Moments::FT, Moments::FTS] {
        for h_over_a in [1.0001, 1.001, 1.01, 1.1, 1.5, 2.0, 3.0, 5.0, 10.0, 20.0] {
            let s = one_sphere(a, h_over_a * a);
            let r = s.resistance(moments, &Lubrication::everywhere()).unwrap();
            let xa = r[(2, 2)] / (6.0 * PI * eta * a);
            let xc = r[(5, 5)] / (8.0 * PI * eta * a.powi(3));
            let (want_a, want_c) = (
                brenner_xa_free_surface(h_over_a),
                jeffery_xc_free_surface(h_over_a),
            );
            let (ea, ec) = ((xa / want_a - 1.0).abs(), (xc / want_c - 1.0).abs());
            worst = [worst[0].max(ea), worst[1].max(ec)];
            assert!(
                ea < 1e-6,
                "{moments:?} h/a {h_over_a}: X^A {xa} vs {want_a}"
            );
            assert!(
                ec < 1e-6,
                "{moments:?} h/a {h_over_a}: X^C {xc} vs {want_c}"
            );
            // lateral symmetry: translation in x and y alike, no coupling to the normal
            assert!((r[(0, 0)] - r[(1, 1)]).abs() <= 1e-12 * r[(0, 0)]);
            assert!(r[(0, 2)].abs() <= 1e-12 * r[(0, 0)]);
        }
    }
    println!(
        "largest relative error: X^A {:.1e}, X^C {:.1e}",
        worst[0], worst[1]
    );
}

/// Every block (translation, rotation, coupling, stresslet rows) of the exact
/// free-surface resistance tends to the inverse of our far-field free-surface self
/// mobility far from the surface (h = 8 a: s' = 16): the pair correction at FTS is below
/// `30 s'^-6 = 1.8e-6` of `6 pi eta a` there (`Lubrication::pair_window`'s measured
/// bound), so each block may differ by at most 2e-5 of its norm (ten times that), while a
/// wrong sign in the mirror map changes a block by its whole image part, `O((a/h)^3)` =
/// 2e-3 of the norm or more. Blocks below 1e-7 of the whole are exempt.
#[test]
fn exact_free_surface_resistance_tends_to_the_far_field_inverse() {
    let s = one_sphere(1.0, 8.0);
    let exact = s
        .resistance(Moments::FTS, &Lubrication::everywhere())
        .unwrap();
    let far = s.resistance(Moments::FTS, &Lubrication::none()).unwrap();
    let whole = exact.norm();
    let ranges = [(0, 3), (3, 3), (6, 5)];
    let mut largest = 0.0f64;
    for (r0, nr) in ranges {
        for (c0, nc) in ranges {
            let e = exact.view((r0, c0), (nr, nc));
            let f = far.view((r0, c0), (nr, nc));
            let diff = (e - f).norm();
            if diff < 1e-7 * whole {
                continue;
            }
            let rel = diff / e.norm();
            largest = largest.max(rel);
            assert!(rel < 2e-5, "block ({r0}, {c0}): {rel:e}");
        }
    }
    println!("largest block difference {largest:.1e}");
    // the correction is not empty: near the surface exact and far field differ by O(1)
    let near = one_sphere(1.0, 1.05);
    let e = near
        .resistance(Moments::FTS, &Lubrication::everywhere())
        .unwrap();
    let f = near.resistance(Moments::FTS, &Lubrication::none()).unwrap();
    assert!((e[(2, 2)] - f[(2, 2)]).abs() > 0.5 * f[(2, 2)].abs());
}

/// A sphere near a free surface with a larger one stacked on it: the lubricated
/// resistance is symmetric and positive definite at FT and FTS down to gaps of 1e-6
/// radii (both gaps).
#[test]
fn resistance_near_a_free_surface_is_positive_definite() {
    for moments in [Moments::FT, Moments::FTS] {
        for gap in [1e-2, 1e-4, 1e-6] {
            let ps = vec![
                Particle {
                    x: [0.0, 0.0, 0.5 + 1.0 + gap],
                    a: 1.0,
                },
                Particle {
                    x: [0.0, 0.0, 0.5 + 1.0 + gap + 1.0 + 1.5 + gap],
                    a: 1.5,
                },
            ];
            let s = System::new(SURFACE, 1.0, ps, false).unwrap();
            let r = s.resistance(moments, &Lubrication::default()).unwrap();
            assert!((&r - r.transpose()).norm() <= 1e-12 * r.norm());
            assert!(r.clone().cholesky().is_some(), "{moments:?} gap {gap}");
        }
    }
}
