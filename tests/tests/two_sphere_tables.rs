//! The generated far-pair tables of the two-sphere functions (`stokesian::pair_tables`)
//! against the twin-multipole series they are made from, between the tables' nodes.

use stokesian::pair_tables::{far_scalars, S_MIN};
use stokesian::two_sphere::PairSeries;

const NAMES: [&str; 22] = [
    "x11a", "x12a", "y11a", "y12a", "y11b", "y12b", "x11c", "x12c", "y11c", "y12c", "x11g", "x12g",
    "y11g", "y12g", "y11h", "y12h", "x11m", "x12m", "y11m", "y12m", "z11m", "z12m",
];

/// Every function, 61 size ratios from 1e-2 to 1e2 (evenly in `ln lambda`, so not at
/// the nodes, which are even in `lambda/(1 + lambda)`) by 60 separations from `S_MIN` to
/// 1e4 (evenly in `t = 2/s'`, plus the ends): the largest error in Kim & Karrila's
/// normalisation, where an isolated sphere's functions are 1 (the series itself is
/// accurate to about 1e-15 in these units, not relative to a function that vanishes far
/// apart, such as `y11h ~ t^6`); printed per function. The tolerance 1e-11 is three
/// times the largest measured (3.1e-12, `y12m` at `lambda = 100`, `s' = 360`).
#[test]
fn far_tables_equal_the_series_between_the_nodes() {
    let mut worst = [(0.0f64, 0.0, 0.0); 22];
    for i in 0..=60 {
        let lambda = 10f64.powf(-2.0 + 4.0 * f64::from(i) / 60.0);
        let series = PairSeries::new(lambda).unwrap();
        let mut separations: Vec<f64> = (0..60)
            .map(|j| 2.0 / ((2.0 / S_MIN) * (f64::from(j) + 0.5) / 60.0))
            .collect();
        separations.extend([S_MIN, 1e4]);
        for s in separations {
            let want = series.scalars(s).unwrap().to_array();
            let got = far_scalars(s, lambda, 22).unwrap().to_array();
            for k in 0..22 {
                let e = (got[k] - want[k]).abs();
                if e > worst[k].0 {
                    worst[k] = (e, lambda, s);
                }
            }
            // the force-torque functions alone are the same numbers
            let ft = far_scalars(s, lambda, 10).unwrap().to_array();
            assert_eq!(ft[..10], got[..10]);
            assert!(ft[10..].iter().all(|&v| v == 0.0));
        }
    }
    println!("\nfar tables against the series, largest error (at lambda, s'):");
    for (k, (e, l, s)) in worst.iter().enumerate() {
        println!("  {:5} {e:.1e} ({l:.3e}, {s:.4})", NAMES[k]);
        assert!(*e < 1e-11, "{}: {e:e} at lambda {l}, s' {s}", NAMES[k]);
    }
}

/// Outside their range the tables give nothing: closer than `S_MIN` (the series
/// serve there), a size ratio beyond 1e-2..1e2, or a value that is not a number.
#[test]
fn far_tables_refuse_what_they_do_not_cover() {
    assert!(far_scalars(S_MIN * (1.0 - 1e-15), 1.0, 22).is_none());
    assert!(far_scalars(2.5, 1.0, 22).is_none());
    assert!(far_scalars(4.0, 0.009, 22).is_none());
    assert!(far_scalars(4.0, 101.0, 22).is_none());
    assert!(far_scalars(f64::NAN, 1.0, 22).is_none());
    assert!(far_scalars(4.0, f64::NAN, 22).is_none());
    assert!(far_scalars(f64::INFINITY, 1.0, 22).is_some());
    assert!(far_scalars(4.0, 1e-2, 22).is_some() && far_scalars(4.0, 1e2, 22).is_some());
}
