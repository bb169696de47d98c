//! The exact two-sphere resistance functions of `stokesian::resistance::two_sphere` (Jeffrey & Onishi
//! 1984 and Jeffrey 1992 twin-multipole series, summed in the all-separations form) against
//! independent references:
//!
//! 1. `X^A` and `X^C` of equal spheres against the bispherical-coordinate solutions in
//!    `stokesian::resistance::exact` (Stimson & Jeffery 1926 with Brenner's free-surface series; Jeffery
//!    1915), gaps `1e-4 <= xi <= 10`.
//! 2. All 22 functions against Wilson's (2013) Lamb's-method computation as tabulated by
//!    Townsend (`tests/data/wilson_lamb_two_sphere.txt`, lambda = 0.01, 0.1, 1, 10).
//! 3. Near contact (lambda = 1, `1e-6 <= xi <= 1e-3`) against the near-contact forms of
//!    Jeffrey & Onishi 1984, as corrected by Townsend 2023 (published singular
//!    coefficients, constants rounded to 4-5 digits).
//! 4. Reciprocity (JO84 eq. 1.9) between lambda and 1/lambda, the contact values of `X^C`
//!    (Hurwitz zeta), and the far field: the "11" functions of A, C, M tend to 1 and the
//!    leading "12" terms are those of the point-force / point-torque fields derived below.
//!
//! The tables of largest errors print with
//! `cargo test --release -p integration-tests -- two_sphere::exact --nocapture`.

use std::f64::consts::PI;
use stokesian::resistance::exact::{two_sphere_xa, two_sphere_xc, ZETA3};
use stokesian::resistance::two_sphere::{resistance_scalars, PairSeries, NAMES, TRUNCATION};

/// Relative error, with the denominator floored at `scale` (for functions that pass
/// through zero or are tiny compared with the others of their family).
fn rel(value: f64, reference: f64, scale: f64) -> f64 {
    (value - reference).abs() / reference.abs().max(scale)
}

#[test]
fn equal_spheres_xa_xc_against_bispherical_series() {
    let series = PairSeries::new_ft(1.0).unwrap();
    let mut worst = [(0.0f64, 0.0f64); 4];
    println!("\nequal spheres vs bispherical series (relative errors)");
    println!(
        "{:>10} {:>10} {:>10} {:>10} {:>10}",
        "xi", "X11A", "X12A", "X11C", "X12C"
    );
    let n = 25;
    for i in 0..n {
        // log grid 1e-4 ..= 10
        let xi = 1e-4 * 10f64.powf(5.0 * i as f64 / (n - 1) as f64);
        let p = series.scalars(2.0 + xi).unwrap();
        let (a11, a12) = two_sphere_xa(xi);
        let (c11, c12) = two_sphere_xc(xi);
        let e = [
            rel(p.x11a, a11, 0.0),
            rel(p.x12a, a12, 0.0),
            rel(p.x11c, c11, 0.0),
            rel(p.x12c, c12, 0.0),
        ];
        println!(
            "{xi:>10.3e} {:>10.2e} {:>10.2e} {:>10.2e} {:>10.2e}",
            e[0], e[1], e[2], e[3]
        );
        for k in 0..4 {
            if e[k] > worst[k].0 {
                worst[k] = (e[k], xi);
            }
        }
    }
    for (k, name) in ["X11A", "X12A", "X11C", "X12C"].iter().enumerate() {
        println!(
            "largest {name}: {:.2e} at xi = {:.1e}",
            worst[k].0, worst[k].1
        );
    }
    // Tolerances: the series are summed to m = TRUNCATION = 200 and the neglected remainder
    // is largest at contact, where it is the error of the constant K: for X^A the remainders
    // oscillate in sign (~20/m^3) and the constants are within 5e-6 (absolute) of the
    // exact ones (near-contact forms: AX11 = 0.9953608, AX12 = -0.3502194), i.e. below
    // 5e-7 relative once X^A >= 10 and 2e-6 where |X12A| ~ 3 (xi ~ 0.1). The X^C remainders
    // decay monotonically like 2.3/m^3, so the truncated tail is ~2.3/(4 M^2) = 1.5e-5
    // absolute at contact: 1.5e-5 relative to X11C ~ 1.05, 1e-4 relative to X12C ~ -0.15.
    // The bispherical references are accurate to 3e-15 (references::exact).
    assert!(worst[0].0 < 2e-7, "X11A {:?}", worst[0]);
    assert!(worst[1].0 < 2e-7, "X12A {:?}", worst[1]);
    assert!(worst[2].0 < 2e-5, "X11C {:?}", worst[2]);
    assert!(worst[3].0 < 1.5e-4, "X12C {:?}", worst[3]);
}

/// Table value = KK value x this factor (Townsend's "SD units", data file header), in the
/// column order XA YA YB XC YC XG YG YH XM YM ZM.
const SD_FACTOR: [f64; 11] = [
    1.0,
    1.0,
    2.0 / 3.0,
    4.0 / 3.0,
    4.0 / 3.0,
    2.0 / 3.0,
    2.0 / 3.0,
    4.0 / 3.0,
    10.0 / 9.0,
    10.0 / 9.0,
    10.0 / 9.0,
];
/// Power of lambda by which the lambda > 1 rows (kept at the scale of the large sphere)
/// differ from the KK functions.
const LENGTH_POWER: [i32; 11] = [1, 1, 2, 3, 3, 2, 2, 3, 3, 3, 3];
/// Index in `PairScalars::to_array` of the "11" function of each column (the "12" is next).
const COLUMN: [usize; 11] = [0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20];

#[test]
fn all_functions_against_wilson_lamb_method() {
    let rows = integration_tests::exact::wilson_lamb_rows();
    assert_eq!(rows.len(), 62);
    let lambdas = [0.01, 0.1, 1.0, 10.0];
    // worst[band][function][lambda] = (error, s'); band 0: s' < 2.5, band 1: s' >= 2.5
    let mut worst = [[[(0.0f64, 0.0f64); 4]; 22]; 2];
    for row in &rows {
        let (s, lambda, gamma) = (row[0], row[1], row[2] as usize);
        let li = lambdas.iter().position(|&l| l == lambda).unwrap();
        let ours = resistance_scalars(s, lambda).unwrap().to_array();
        let band = usize::from(s >= 2.5);
        for c in 0..11 {
            let mut reference = row[3 + c] / SD_FACTOR[c];
            if lambda > 1.0 {
                reference *= lambda.powi(LENGTH_POWER[c]);
            }
            let k = COLUMN[c] + gamma;
            // Floor of the relative error: 1e-3 of the larger function of the family at this
            // point (a "12" coupling of a small sphere is down to 1e-6 of its "11" partner,
            // below what the table's mobility inversion resolves with 9 digits).
            let floor = 1e-3 * ours[COLUMN[c]].abs().max(ours[COLUMN[c] + 1].abs());
            let e = rel(ours[k], reference, floor);
            if e > worst[band][k][li].0 {
                worst[band][k][li] = (e, s);
            }
        }
    }
    for (band, title) in ["2.025 <= s' < 2.5", "2.5 <= s' <= 4.5"].iter().enumerate() {
        println!("\nlargest relative error against Wilson (2013) / Townsend, {title} (at s')");
        println!(
            "{:>5} {:>18} {:>18} {:>18} {:>18}",
            "", "lambda=0.01", "lambda=0.1", "lambda=1", "lambda=10"
        );
        for k in 0..22 {
            let w = worst[band][k];
            println!(
                "{:>5} {:>9.2e} ({:5.3}) {:>9.2e} ({:5.3}) {:>9.2e} ({:5.3}) {:>9.2e} ({:5.3})",
                NAMES[k], w[0].0, w[0].1, w[1].0, w[1].1, w[2].0, w[2].1, w[3].0, w[3].1
            );
        }
    }
    // Tolerances. From s' = 2.5 on our series has converged to rounding (t^200 < 1e-19) and
    // the table's 9 digits and inversion limit it: agreement to 5e-4 for lambda <= 1
    // (measured: below 6e-5 except X12M at lambda = 0.1, 2.6e-4 of the floor, i.e. 3e-7
    // absolute: the table builds X^M as x^m + (2/3) X^G x^G^T, which cancels there). The lambda = 10 rows are the "21"/"22" functions of the
    // lambda = 0.1 computation, small numbers (down to 1e-4 of the "11" functions there)
    // multiplied by lambda^k up to 1000, so they carry the absolute error of the larger
    // functions of that inversion: 2e-3 (measured: 1.6e-3, Y11H at s' = 2.5).
    // Below s' = 2.5 the reference itself degrades (Townsend: Wilson's code works down to
    // s' ~ 2.014): at lambda = 1 its X^A is off by 7e-4 at s' = 2.025 while ours agrees with
    // the exact bispherical solution to 6e-8 (first test), and at lambda = 0.01 its X12A is
    // 9 % below ours where the sphere-wall limit (Brenner, h/a2 = 2.26) is 1 % above ours,
    // the size of the curvature correction. So near contact this only checks the
    // functions to the reference's accuracy: 5e-3 for lambda = 1 (7e-4 for X^A, up to 4e-3
    // for Z12M, which is 1/15 of Z11M), 2e-2 for lambda = 0.1 and 10, 0.15 for 0.01.
    let near = [0.15, 2e-2, 5e-3, 2e-2];
    for k in 0..22 {
        for li in 0..4 {
            let (e0, s0) = worst[0][k][li];
            let (e1, s1) = worst[1][k][li];
            assert!(
                e0 < near[li],
                "{} lambda = {}: {e0:.2e} at s' = {s0}",
                NAMES[k],
                lambdas[li]
            );
            let far = if lambdas[li] > 1.0 { 2e-3 } else { 5e-4 };
            assert!(
                e1 < far,
                "{} lambda = {}: {e1:.2e} at s' = {s1}",
                NAMES[k],
                lambdas[li]
            );
        }
    }
}

#[test]
fn near_contact_forms_of_lubrication_md() {
    // Near-contact forms (Jeffrey & Onishi 1984, as corrected by Townsend 2023), lambda = 1,
    // L = ln(1/xi): [1/xi, L, constant, xi L]
    let z3 = ZETA3;
    let table: [[f64; 4]; 22] = [
        [0.25, 9.0 / 40.0, 0.99536, 3.0 / 112.0],
        [-0.25, -9.0 / 40.0, -0.35022, -3.0 / 112.0],
        [0.0, 1.0 / 6.0, 0.9983, 0.0],
        [0.0, -1.0 / 6.0, -0.2737, 0.0],
        [0.0, -0.25, 0.2390, -0.125],
        [0.0, 0.25, -0.0016, 0.125],
        [0.0, 0.0, 7.0 * z3 / 8.0, -0.125],
        [0.0, 0.0, -z3 / 8.0, 0.125],
        [0.0, 0.2, 0.7028, 47.0 / 250.0],
        [0.0, 0.05, -0.0274, 31.0 / 500.0],
        [3.0 / 8.0, 27.0 / 80.0, -0.4692, 117.0 / 560.0],
        [-3.0 / 8.0, -27.0 / 80.0, 0.1955, -117.0 / 560.0],
        [0.0, 0.125, -0.1412, 1.0 / 16.0],
        [0.0, -0.125, 0.1025, -1.0 / 16.0],
        [0.0, 1.0 / 40.0, -0.0740, 137.0 / 2000.0],
        [0.0, 0.1, -0.0293, 113.0 / 2000.0],
        [3.0 / 20.0, 27.0 / 200.0, 0.7168, 353.0 / 2800.0],
        [3.0 / 20.0, 27.0 / 200.0, -0.1454, 493.0 / 2800.0],
        [0.0, 3.0 / 25.0, 0.8847, 57.0 / 2500.0],
        [0.0, 3.0 / 100.0, -0.2076, 333.0 / 2500.0],
        [0.0, 0.0, 1.0251, -3.0 / 40.0],
        [0.0, 0.0, -0.0723, 3.0 / 40.0],
    ];
    let series = PairSeries::new(1.0).unwrap();
    let k = series.contact_constants().to_array();
    println!("\nlambda = 1: near-contact constants K, ours vs the published near-contact forms");
    for j in 0..22 {
        println!(
            "{:>5} {:>12.7} {:>10.5} {:>9.1e}",
            NAMES[j],
            k[j],
            table[j][2],
            k[j] - table[j][2]
        );
    }
    let mut worst = [(0.0f64, 0.0f64); 22];
    for xi in [1e-6, 3e-6, 1e-5, 3e-5, 1e-4, 3e-4, 1e-3] {
        let ours = series.scalars(2.0 + xi).unwrap().to_array();
        let l = -f64::ln(xi);
        for j in 0..22 {
            let t = table[j];
            let form = t[0] / xi + t[1] * l + t[2] + t[3] * xi * l;
            let d = (ours[j] - form).abs();
            if d > worst[j].0 {
                worst[j] = (d, xi);
            }
        }
    }
    println!("largest |series - near-contact form|, 1e-6 <= xi <= 1e-3 (absolute)");
    for j in 0..22 {
        println!(
            "{:>5} {:>9.2e} at xi = {:.0e}",
            NAMES[j], worst[j].0, worst[j].1
        );
    }
    // The near-contact forms neglect O(xi) (<= ~1e-3 for these functions at xi = 1e-3) and
    // their constants are rounded to 4 decimals (5e-5); the series constants of M are
    // uncertain by ~6e-4 (module docs of two_sphere). Asserted: agreement to 1.5e-3 absolute, which a
    // wrong singular coefficient (changing F by >= 1e-3 ln(1e6) ~ 1e-2 over the range) or a
    // wrong sign fails.
    for j in 0..22 {
        assert!(worst[j].0 < 1.5e-3, "{}: {:?}", NAMES[j], worst[j]);
    }
}

/// Hurwitz zeta(3, a) = sum_{k >= 0} 1/(k + a)^3, summed directly with an Euler-Maclaurin
/// tail (independent of the code under test).
fn hurwitz_zeta3(a: f64) -> f64 {
    let n = 1000;
    let head: f64 = (0..n).map(|k| (k as f64 + a).powi(-3)).sum();
    let x = n as f64 + a;
    head + 1.0 / (2.0 * x * x) + 1.0 / (2.0 * x.powi(3)) + 1.0 / (4.0 * x.powi(4))
}

#[test]
fn reciprocity_contact_values_and_far_field() {
    // JO84 eq. 1.9 with the KK scalings: the force on sphere 1 due to sphere 2 equals the
    // force on 2 due to 1, so X12A(lambda) = lambda X12A(1/lambda) (A: radius^1), the
    // couples and stresslet couplings with radius^3.
    let mut worst_recip: f64 = 0.0;
    for lambda in [0.05, 0.25, 0.5, 2.0, 4.0, 20.0] {
        for s in [2.01, 2.1, 2.5, 3.0, 6.0] {
            let a = resistance_scalars(s, lambda).unwrap();
            let b = resistance_scalars(s, 1.0 / lambda).unwrap();
            let l3 = lambda.powi(3);
            for (x, y) in [
                (a.x12a, lambda * b.x12a),
                (a.y12a, lambda * b.y12a),
                (a.x12c, l3 * b.x12c),
                (a.y12c, l3 * b.y12c),
                (a.x12m, l3 * b.x12m),
                (a.y12m, l3 * b.y12m),
                (a.z12m, l3 * b.z12m),
            ] {
                worst_recip = worst_recip.max(rel(x, y, 1e-12));
            }
        }
    }
    println!("\nreciprocity lambda <-> 1/lambda: largest relative difference {worst_recip:.2e}");
    // Both sides come from the same tables but from different polynomials in lambda (the
    // coefficients R_{m-q,q} are used in reverse order); agreement to rounding (the sums
    // have condition numbers up to ~1e2) shows the symmetry of the recurrences.
    assert!(worst_recip < 1e-11, "{worst_recip:e}");

    // Contact values of X^C (Jeffery 1915; JO84 sec. 6): X11C -> lambda^3/(1+lambda)^3
    // zeta(3, lambda/(1+lambda)), X12C -> -lambda^3/(1+lambda)^3 zeta(3).
    let mut worst_xc: f64 = 0.0;
    for lambda in [0.5, 1.0, 2.0] {
        let k = PairSeries::new_ft(lambda).unwrap().contact_constants();
        let c = lambda.powi(3) / (1.0 + lambda).powi(3);
        let e11 = rel(k.x11c, c * hurwitz_zeta3(lambda / (1.0 + lambda)), 0.0);
        let e12 = rel(k.x12c, -c * ZETA3, 0.0);
        println!("X^C contact, lambda = {lambda}: relative errors {e11:.2e} {e12:.2e}");
        worst_xc = worst_xc.max(e11).max(e12);
    }
    // Truncated tail of a monotone remainder ~ C/m^3 (see the first test): 1.5e-4. (For
    // lambda = 0.1 and 10 the contact values are within 1.2e-3, measured.)
    assert!(worst_xc < 1.5e-4, "{worst_xc:e}");

    // Far field. Point-force and point-torque fields (derived independently, e.g. from the
    // Rotne-Prager mobility): with a2/r = mu t, a1/r = nu t (t = 2/s', mu = lambda/(1+lambda),
    // nu = 1/(1+lambda)), a held sphere 1 in the flow of sphere 2 translating or rotating:
    // X12A = -(3/2) a2/r, Y12A = -(3/4) a2/r (Stokeslet, 2 and 1 times 3/4);
    // Y12B = (3/2) a1 a2/r^2 (Stokeslet vorticity (F x x)/(4 pi mu r^3), Faxen torque);
    // X12C = -(a2/r)^3, Y12C = +(1/2)(a2/r)^3 (rotlet rotation 2T/(8 pi mu r^3) on axis,
    // -T/(8 pi mu r^3) across it); X12G = -(15/4) a1 a2/r^2 (Stokeslet strain
    // (3F/(8 pi mu r^2))(dd - I/3), Faxen stresslet (20/3) pi mu a1^3 E).
    // The next corrections are smaller by t^2, so at s' = 2000 (t = 1e-3) the relative
    // differences are ~1e-6.
    let s = 2000.0;
    let t = 2.0 / s;
    let mut worst_far: f64 = 0.0;
    for lambda in [0.1, 1.0, 10.0] {
        let mu = lambda / (1.0 + lambda);
        let nu = 1.0 / (1.0 + lambda);
        let p = resistance_scalars(s, lambda).unwrap();
        let checks = [
            (p.x11a, 1.0),
            (p.y11a, 1.0),
            (p.x11c, 1.0),
            (p.y11c, 1.0),
            (p.x11m, 1.0),
            (p.y11m, 1.0),
            (p.z11m, 1.0),
            (p.x12a, -1.5 * mu * t),
            (p.y12a, -0.75 * mu * t),
            (p.y12b, 1.5 * mu * nu * t * t),
            (p.x12c, -(mu * t).powi(3)),
            (p.y12c, 0.5 * (mu * t).powi(3)),
            (p.x12g, -3.75 * mu * nu * t * t),
        ];
        for (x, y) in checks {
            worst_far = worst_far.max(rel(x, y, 0.0));
        }
    }
    println!("far field (s' = 2000): largest relative difference {worst_far:.2e}");
    assert!(worst_far < 1e-5, "{worst_far:e}");
}

#[test]
fn cost_of_tables_and_calls() {
    let t0 = std::time::Instant::now();
    let p = resistance_scalars(2.5, 1.0).unwrap();
    let first = t0.elapsed();
    let t0 = std::time::Instant::now();
    let n = 200;
    let mut acc = 0.0;
    for i in 0..n {
        acc += resistance_scalars(2.01 + 0.01 * i as f64, 0.3)
            .unwrap()
            .x11a;
    }
    let per_call = t0.elapsed() / n;
    let series = PairSeries::new(0.3).unwrap();
    let t0 = std::time::Instant::now();
    for i in 0..n {
        acc += series.scalars(2.01 + 0.01 * i as f64).unwrap().x11a;
    }
    let per_eval = t0.elapsed() / n;
    // near contact every term is summed: the slowest separations
    let t0 = std::time::Instant::now();
    for i in 0..n {
        acc += series.scalars(2.0 + 1e-4 * (1 + i) as f64).unwrap().x11a;
    }
    let per_eval_contact = t0.elapsed() / n;
    // a new size ratio: its series built from the coefficients (read above)
    let t0 = std::time::Instant::now();
    let ratios = 50;
    for i in 0..ratios {
        let s = PairSeries::new(0.05 + 0.37 * f64::from(i)).unwrap();
        acc += s.scalars(2.5).unwrap().x11a;
    }
    let per_ratio = t0.elapsed() / ratios;
    // summed only as far as a pair at s' needs (ratios no other test asks for, so that
    // each is built here)
    let far: Vec<_> = [4.0, 10.0]
        .iter()
        .enumerate()
        .map(|(k, &s_dash)| {
            let t0 = std::time::Instant::now();
            for i in 0..500 {
                let lambda = 0.051 + 0.037 * f64::from(i) + 0.001 * k as f64;
                let s = PairSeries::cached_at(lambda, false, s_dash).unwrap();
                acc += s.scalars(s_dash).unwrap().x11a;
            }
            (s_dash, t0.elapsed() / 500)
        })
        .collect();
    // the tables: every pair its own ratio, no series; far (s' in [3, 23]) and near
    // (xi = s' - 2 from 1e-6 to 1, evenly in ln xi), both in a cache-warm loop, after
    // the files are read
    for s_dash in [2.5, 4.0] {
        acc += stokesian::resistance::pair_tables::scalars(s_dash, 1.0, 22)
            .unwrap()
            .x11a;
    }
    // time per call of `f(i, s', count)` over 2000 separations, far or near, for the
    // ten force-torque functions and all 22
    let time_calls = |f: &mut dyn FnMut(u32, f64, usize) -> f64| -> Vec<_> {
        [10, 22]
            .iter()
            .flat_map(|&count| [(count, true), (count, false)])
            .map(|(count, far)| {
                let t0 = std::time::Instant::now();
                for i in 0..2000u32 {
                    let s_dash = if far {
                        3.0 + 0.01 * f64::from(i)
                    } else {
                        2.0 + (-13.8 * (1.0 - f64::from(i) / 2000.0)).exp()
                    };
                    std::hint::black_box(f(i, s_dash, count));
                }
                (count, if far { "far" } else { "near" }, t0.elapsed() / 2000)
            })
            .collect()
    };
    let tables = time_calls(&mut |i, s_dash, count| {
        let lambda = 0.011 + 0.049 * f64::from(i);
        stokesian::resistance::pair_tables::scalars(s_dash, lambda, count)
            .unwrap()
            .x11a
    });
    println!("\ntables (functions, table, time per call): {tables:?}");
    // the tables contracted at a ratio (AtRatio): built for three ratios, then the same
    // loops cycling through them (a suspension of two sizes has three ratios)
    let t0 = std::time::Instant::now();
    let at: Vec<_> = [0.6, 1.0, 1.0 / 0.6]
        .iter()
        .map(|&l| stokesian::resistance::pair_tables::AtRatio::new(l).unwrap())
        .collect();
    let build = t0.elapsed() / 3;
    let at_ratio =
        time_calls(&mut |i, s_dash, count| at[i as usize % 3].scalars(s_dash, count).unwrap().x11a);
    println!(
        "tables at a ratio: built in {build:?} per ratio; (functions, table, time per call): \
         {at_ratio:?}"
    );
    println!(
        "\ncost (TRUNCATION = {TRUNCATION}): first call (reads the coefficients, unless another test did \
         them) {first:?}; resistance_scalars {per_call:?} per call; PairSeries::scalars \
         {per_eval:?} per call (s' in [2.01, 4]), {per_eval_contact:?} near contact (xi <= 0.02); \
         PairSeries::new {per_ratio:?} per size ratio (lambda 0.05 to 18); \
         PairSeries::cached_at, a new ratio summed for a pair at s' (and beyond): {far:?}"
    );
    assert!(acc.is_finite() && p.x11a > 1.0);
    assert!(p.x11a.is_finite() && PI > 3.0);
}
