//! The two-sphere correction of Eq. 19 without a cutoff: kept in full wherever it may
//! exceed the stated tolerance, switched off by a smoothstep beyond, so the resistance
//! is continuous with continuous derivatives in the separation.

use std::f64::consts::PI;
use stokesian::{Confinement, Lubrication, Moments, Particle, System};

/// Two spheres in unbounded fluid, the larger of radius 1 at the origin, the smaller of
/// radius `small` at `s' = 2r/(1 + small)` along a direction off every axis.
fn pair(small: f64, s_dash: f64, swap: bool) -> System {
    let r = s_dash * (1.0 + small) / 2.0;
    let dir = [0.48, 0.6, 0.64];
    let mut ps = vec![
        Particle {
            x: [0.0; 3],
            a: 1.0,
        },
        Particle {
            x: dir.map(|v| r * v),
            a: small,
        },
    ];
    if swap {
        ps.swap(0, 1);
    }
    System::new(Confinement::Free, 1.0, ps, false).unwrap()
}

fn correction(s: &System, moments: Moments) -> f64 {
    let with = s.resistance(moments, &Lubrication::everywhere()).unwrap();
    let without = s.resistance(moments, &Lubrication::none()).unwrap();
    (with - without).abs().max()
}

/// Beyond the start of the window the whole correction is below the tolerance, for
/// size ratios 1e-2 to 1 (either sphere first) and both levels, at tolerance 1e-3 and
/// at the default (1e-6): the bound of the window is a measured one, so this is the
/// test that it holds (largest entry over `6 pi eta a_min`, radii up to 1).
#[test]
fn pair_correction_is_below_the_tolerance_outside_its_window() {
    for moments in [Moments::FT, Moments::FTS] {
        for tol in [1e-3, Lubrication::default().pair_tolerance] {
            let lub = Lubrication {
                pair_tolerance: tol,
                ..Lubrication::default()
            };
            let (s0, s1) = lub.pair_window(moments);
            assert!(s1 > s0 && s0 > 3.0, "{moments:?} {tol}: window {s0} {s1}");
            for small in [0.01, 0.1, 0.3, 1.0] {
                for swap in [false, true] {
                    for s_dash in [s0, 1.1 * s0, 2.0 * s0] {
                        let c =
                            correction(&pair(small, s_dash, swap), moments) / (6.0 * PI * small);
                        assert!(
                            c <= tol,
                            "{moments:?} tol {tol} lambda {small} s' {s_dash}: {c:e}"
                        );
                    }
                }
            }
            println!("{moments:?} tolerance {tol:e}: window s' in [{s0:.3}, {s1:.3}]");
        }
    }
}

/// The resistance is continuous with a continuous first derivative in the separation at
/// both ends of the window, at the old cutoff `s' = 4` and where the far-pair tables take
/// over from the series (`s' = 3`, `stokesian::resistance::pair_tables`; their difference there,
/// below 1e-12 of the functions, is far below what this resolves): the one-sided differences
/// `D+ = (R(s+h) - R(s))/h` and `D- = (R(s) - R(s-h))/h` may differ only by about
/// `h |R''|` (bounded by a central second difference over `H = 20 h`, doubled for its own
/// error) plus the rounding of the differences (`4 eps |R| / h`, `|R|` the largest
/// entry, which the Cholesky inverses repeat to ~1e2 eps). A step of the correction
/// would make `D+ - D-` of the order of the step over `h` (1e-3/h here) and a kink of
/// the order of the correction over the width of the window; both fail by orders of
/// magnitude.
#[test]
fn resistance_is_smooth_across_the_window_the_old_cutoff_and_the_tables() {
    for moments in [Moments::FT, Moments::FTS] {
        let (s0, s1) = Lubrication::default().pair_window(moments);
        for s in [
            s0,
            s1,
            0.5 * (s0 + s1),
            4.0,
            stokesian::resistance::pair_tables::S_MIN,
        ] {
            let h = 1e-4 * s;
            let big_h = 20.0 * h;
            let r = |s_dash: f64| {
                pair(0.5, s_dash, false)
                    .resistance(moments, &Lubrication::default())
                    .unwrap()
            };
            let (rm, r0, rp) = (r(s - h), r(s), r(s + h));
            let second = (r(s + big_h) - 2.0 * &r0 + r(s - big_h)).abs().max() / (big_h * big_h);
            let kink = ((&rp - &r0) / h - (&r0 - &rm) / h).abs().max();
            let jump = (&rp - &rm).abs().max();
            let scale = r0.abs().max();
            let allowed = 2.0 * h * second + 4e2 * f64::EPSILON * scale / h;
            println!("{moments:?} s' {s:.3}: |D+ - D-| {kink:.2e} (allowed {allowed:.2e}), |R(s+h) - R(s-h)| {jump:.2e}");
            assert!(
                kink <= allowed,
                "{moments:?} s' {s}: kink {kink:e} > {allowed:e}"
            );
        }
    }
}
