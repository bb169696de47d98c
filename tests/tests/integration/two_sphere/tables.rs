//! The generated tables of the two-sphere functions (`stokesian::resistance::pair_tables`, far and
//! near) against the twin-multipole series they are made from, between the tables' nodes.

use stokesian::resistance::pair_tables::{far_scalars, near_scalars, scalars, S_MIN, U_MIN};
use stokesian::resistance::two_sphere::PairSeries;

const NAMES: [&str; 22] = [
    "x11a", "x12a", "y11a", "y12a", "y11b", "y12b", "x11c", "x12c", "y11c", "y12c", "x11g", "x12g",
    "y11g", "y12g", "y11h", "y12h", "x11m", "x12m", "y11m", "y12m", "z11m", "z12m",
];

/// Every function, 61 size ratios from 1e-2 to 1e2 (evenly in `ln lambda`, so not at
/// the nodes, which are even in `lambda/(1 + lambda)`) by 60 separations from `S_MIN` to
/// 1e4 (evenly in `t = 2/s'`, plus the ends): the largest error in Kim & Karrila's
/// normalisation, where an isolated sphere's functions are 1 (the series itself is
/// accurate to about 1e-15 in these units, not relative to a function that vanishes far
/// apart, such as `y11h ~ t^6`); printed per function. The tolerance 1e-10 is about
/// three times the largest measured (3.8e-11, `x12m` at `lambda = 11.7`, `s' = 4.0`).
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
    }
    for (k, (e, l, s)) in worst.iter().enumerate() {
        assert!(*e < 1e-10, "{}: {e:e} at lambda {l}, s' {s}", NAMES[k]);
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
    // the near table: at and beyond S_MIN, at or inside contact, out of range
    assert!(near_scalars(S_MIN, 1.0, 22).is_none());
    assert!(near_scalars(2.0, 1.0, 22).is_none());
    assert!(near_scalars(1.9, 1.0, 22).is_none());
    assert!(near_scalars(2.5, 0.009, 22).is_none());
    assert!(near_scalars(2.5, 101.0, 22).is_none());
    assert!(near_scalars(f64::NAN, 1.0, 22).is_none());
    assert!(near_scalars(2.5, f64::NAN, 22).is_none());
    assert!(near_scalars(2.0 + 2.0 * f64::EPSILON, 1e-2, 22).is_some());
    assert!(scalars(2.0, 1.0, 22).is_none() && scalars(2.5, 1.0, 22).is_some());
}

/// The near table with the singular closed forms, every function, 61 size ratios from
/// 1e-2 to 1e2 (evenly in `ln lambda`, between the nodes of its eight patches) by 240
/// gaps `xi = s' - 2` evenly in `ln xi` from `exp(U_MIN)` to 1, plus the smallest gap
/// of an `f64` separation (4.4e-16) and 1e-14, 1e-12, 1 - 1e-12: the
/// largest error relative to `max(|F|, 1)` (near contact the functions grow like `1/xi`
/// or `ln(1/xi)`; where one crosses zero its error is measured against an isolated
/// sphere's 1, as for the far table), printed per function. The issue asks for 1e-8;
/// the tolerance 2e-9 is about three times the largest measured (6.6e-10, `z11m` at
/// `lambda = 6.3`, `xi = 1.4e-10`).
#[test]
fn near_tables_equal_the_series_between_the_nodes() {
    let mut worst = [(0.0f64, 0.0, 0.0); 22];
    for i in 0..=60 {
        let lambda = 10f64.powf(-2.0 + 4.0 * f64::from(i) / 60.0);
        let series = PairSeries::new(lambda).unwrap();
        let mut gaps: Vec<f64> = (0..240)
            .map(|j| (U_MIN * (1.0 - (f64::from(j) + 0.5) / 240.0)).exp())
            .collect();
        gaps.extend([f64::EPSILON * 2.0, 1e-14, 1e-12, 1.0 - 1e-12]);
        for xi in gaps {
            let s = 2.0 + xi;
            let want = series.scalars(s).unwrap().to_array();
            let got = near_scalars(s, lambda, 22).unwrap().to_array();
            for k in 0..22 {
                let e = (got[k] - want[k]).abs() / want[k].abs().max(1.0);
                if e > worst[k].0 {
                    worst[k] = (e, lambda, xi);
                }
            }
            let ft = near_scalars(s, lambda, 10).unwrap().to_array();
            assert_eq!(ft[..10], got[..10]);
            assert!(ft[10..].iter().all(|&v| v == 0.0));
            assert_eq!(scalars(s, lambda, 22).unwrap().to_array(), got);
        }
    }
    println!("\nnear tables against the series, largest relative error (at lambda, xi):");
    for (k, (e, l, xi)) in worst.iter().enumerate() {
        println!("  {:5} {e:.1e} ({l:.3e}, {xi:.2e})", NAMES[k]);
    }
    for (k, (e, l, xi)) in worst.iter().enumerate() {
        assert!(*e < 2e-9, "{}: {e:e} at lambda {l}, xi {xi}", NAMES[k]);
    }
}

/// Where the near table hands over to the far one (`s' = 3`) the functions step by
/// less than the tables' errors: 3e-10 in Kim & Karrila's normalisation (the near
/// table is within 6.6e-10 of `max(|F|, 1)` of the series, the far one within 3.8e-11;
/// measured 2.9e-11).
#[test]
fn near_and_far_tables_meet_at_s_min() {
    let below = S_MIN * (1.0 - f64::EPSILON);
    let mut worst = 0.0f64;
    for i in 0..=40 {
        let lambda = 10f64.powf(-2.0 + 4.0 * f64::from(i) / 40.0);
        let near = near_scalars(below, lambda, 22).unwrap().to_array();
        let far = far_scalars(S_MIN, lambda, 22).unwrap().to_array();
        for k in 0..22 {
            worst = worst.max((near[k] - far[k]).abs());
        }
    }
    println!("largest step at s' = 3: {worst:.1e}");
    assert!(worst < 3e-10, "{worst:e}");
}
