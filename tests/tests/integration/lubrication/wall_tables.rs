//! The generated sphere-wall tables (`stokesian::resistance::wall_tables`) against the bispherical
//! series they were made from, between the nodes, and their continuity.

use stokesian::resistance::wall_tables::{intervals, EPS_MAX, EPS_MIN};
use stokesian::{wall_functions, wall_series, WallFunctions};

fn values(w: &WallFunctions) -> [f64; 5] {
    [w.xa, w.ya, w.fr, w.yc, w.xc]
}

const NAMES: [&str; 5] = ["X^A", "Y^A", "F^r", "Y^C", "X^C"];

/// The difference of two values of function `f` measured against its scale: relative,
/// except for the coupling `F^r`, which decays like `(a/h)^4` while its series keeps an
/// absolute accuracy of about 4e-14 (cancellation in the torque sum, `exact` module
/// docs; 1e-10 relative at h = 10 a, none at h = 1000 a): there the scale is 1, the size
/// of `Y^A` next to which it enters the resistance.
fn scaled(f: usize, a: f64, b: f64) -> f64 {
    let scale = if f == 2 { b.abs().max(1.0) } else { b.abs() };
    (a - b).abs() / scale
}

/// Every function within 1e-10 of the series ([`scaled`]) at 7 points inside every
/// interval of `ln eps` (none of them a node: the fits interpolate the series at 18
/// Chebyshev points per interval, so the error between nodes is the fit's). The largest
/// errors are printed.
#[test]
fn tables_match_the_series_between_the_nodes() {
    let s0 = EPS_MIN.ln();
    let mut worst = [0.0f64; 5];
    for i in 0..intervals() {
        for k in 0..7 {
            let s = s0 + i as f64 + (k as f64 + 0.37) / 7.0;
            let eps = s.exp();
            if eps > EPS_MAX {
                continue;
            }
            let (t, e) = (values(&wall_functions(eps)), values(&wall_series(eps)));
            for f in 0..5 {
                let rel = scaled(f, t[f], e[f]);
                worst[f] = worst[f].max(rel);
                assert!(
                    rel <= 1e-10,
                    "{} at eps = {eps:e}: table {} series {} ({rel:e})",
                    NAMES[f],
                    t[f],
                    e[f]
                );
            }
        }
    }
    println!(
        "largest relative error of the tables: {:?}",
        NAMES.iter().zip(worst).collect::<Vec<_>>()
    );
}

/// Continuous at the joints of the intervals and at `EPS_MIN`, where the near-contact
/// forms take over: both sides agree to 1e-12 ([`scaled`]). Each side is an
/// interpolant extrapolated to the end of its interval (the Chebyshev points are
/// interior), within a few times the series' round-off of it.
#[test]
fn tables_are_continuous() {
    let s0 = EPS_MIN.ln();
    for i in 0..=intervals() {
        let eps = (s0 + i as f64).exp().min(EPS_MAX);
        let (below, above) = (
            wall_functions(eps * (1.0 - 1e-15)),
            wall_functions(eps * (1.0 + 1e-15)),
        );
        for (f, (b, a)) in values(&below).iter().zip(values(&above)).enumerate() {
            assert!(
                scaled(f, *b, a) < 1e-12,
                "{} jumps at eps = {eps:e}: {b} | {a}",
                NAMES[f]
            );
        }
    }
}
