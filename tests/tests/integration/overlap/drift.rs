//! The Brownian drift of the damped mobility `B M(clamped) B` ([`Overlap::Rpy`] with
//! spheres cutting a boundary): [`System::divergence_at`] against central differences
//! of the dense damped mobility over every position (an independent path: the mobility
//! kernels, the clamping and the factors as the system applies them, differentiated
//! numerically), for every confinement with a boundary, F and FT, with spheres that cut
//! a boundary, overlap each other, or both.

use integration_tests::{all_confinements, over};
use stokesian::{Confinement, Moments, Overlap, Particle, System};

fn p(x: [f64; 3], a: f64) -> Particle {
    Particle { x, a }
}

/// `sum_{q,j} d/dx_{q,j} M_{r,(q,j)}` for every row `r` (moment-major: `U` rows, then
/// the `Omega` rows at FT), the force columns, by central differences of step `h`.
fn fd_drift(conf: Confinement, eta: f64, ps: &[Particle], moments: Moments, h: f64) -> Vec<f64> {
    let n = ps.len();
    let rows = moments.per_particle() * n;
    let mut out = vec![0.0; rows];
    for q in 0..n {
        for j in 0..3 {
            let m = |s: f64| {
                let mut moved = ps.to_vec();
                moved[q].x[j] += s * h;
                System::new(conf, eta, moved, Overlap::Rpy)
                    .expect("valid")
                    .mobility(moments)
            };
            let (plus, minus) = (m(1.0), m(-1.0));
            for (r, o) in out.iter_mut().enumerate() {
                *o += (plus[(r, 3 * q + j)] - minus[(r, 3 * q + j)]) / (2.0 * h);
            }
        }
    }
    out
}

/// Spheres that cut the first boundary (two of them overlapping each other), a free
/// sphere overlapping a cut one at the clamped centres, one far away, and with a second
/// boundary a sphere cutting it too. Every distance to a boundary is between 0.35 and
/// 0.6 radii, every centre distance 0.08 or more from contact (at the clamped
/// centres): no kink of the clamping or of the overlap forms within the step.
fn spheres(conf: &Confinement) -> Vec<Particle> {
    let planes = conf.boundaries();
    let first = planes.first();
    let mut ps = vec![
        p(over(first, [0.0, 0.0], 0.6), 1.0),
        p(over(first, [1.3, 0.2], 0.36), 0.8),
        p(over(first, [0.5, 1.4], 2.2), 1.0),
        p(over(first, [3.0, 0.0], 1.7), 0.7),
        p(over(first, [-4.0, -3.0], 3.0), 0.9),
    ];
    if let Some(last) = planes.get(1) {
        ps.push(p(over(Some(last), [-3.0, 3.0], 0.5), 1.0));
    }
    ps
}

/// Central differences of step 1e-5 leave truncation ~h^2 |M'''| ~ 1e-10 and rounding
/// ~1e-16 / 1e-5 = 1e-11 relative to the mobility's gradient scale `1/(6 pi eta a^2)`:
/// 1e-7 of it.
#[test]
fn damped_drift_equals_finite_differences_of_the_damped_mobility() {
    let eta = 0.9;
    let mut checked = 0;
    for (name, conf) in all_confinements() {
        if conf.boundaries().is_empty() {
            continue;
        }
        let ps = spheres(&conf);
        let s = System::new(conf, eta, ps.clone(), Overlap::Rpy).expect("valid");
        assert!(s.check_drift().is_ok());
        let scale = 1.0 / (6.0 * std::f64::consts::PI * eta * 0.7 * 0.7);
        for moments in [Moments::F, Moments::FT] {
            let got = s.divergence_at(moments);
            let want = fd_drift(conf, eta, &ps, moments, 1e-5);
            let largest = want.iter().fold(0.0f64, |m, w| m.max(w.abs()));
            // the damping's terms are of the order of the mobility's gradient
            assert!(largest > 1e-2 * scale, "{name}: {largest}");
            let worst = got
                .iter()
                .zip(&want)
                .fold(0.0f64, |m, (g, w)| m.max((g - w).abs()));
            println!("{name} {moments:?}: largest {largest:.3e}, worst difference {worst:.3e}, scale {scale:.3e}");
            for (k, (g, w)) in got.iter().zip(&want).enumerate() {
                assert!(
                    (g - w).abs() <= 1e-7 * scale,
                    "{name} {moments:?} row {k}: {g:e} vs {w:e}"
                );
            }
            // with the fast product each sphere's own term and the damping's alone:
            // the pair terms dropped are round-off of `1e-16` of the terms they sum
            let fast = s.clone().with_fmm(1e-6).unwrap().divergence_at(moments);
            for (k, (f, g)) in fast.iter().zip(&got).enumerate() {
                assert!(
                    (f - g).abs() <= 1e-14 * scale,
                    "{name} {moments:?} row {k} with the fast product: {f:e} vs {g:e}"
                );
            }
            checked += 1;
        }
    }
    assert_eq!(
        checked,
        2 * 5,
        "wall, free surface, interface, slit, side wall"
    );
}
