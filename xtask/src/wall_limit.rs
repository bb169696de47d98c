//! `cargo xtask wall-limit [--truncation N]`: the sphere-plane resistance functions as
//! the limit of the two-sphere "11" functions when the second sphere grows into a plane
//! (size ratio `lambda = a2/a1 -> infinity` at a fixed gap `eps = (r - a1 - a2)/a1`),
//! the route issue 13 proposed for the stresslet rows of the wall (`X^G, Y^G, Y^H, X^M,
//! Y^M, Z^M`), for which no exact sphere-plane series is at hand.
//!
//! At each gap the series (`stokesian::resistance::two_sphere`, coefficients built here to `N`
//! terms) is evaluated on a ladder of `lambda`; a `lambda` is kept where the sums to `N`
//! and to `3N/4` terms agree to a tolerance (the series converges slowly as `s' -> 2`,
//! and `s' = 2 + 2 eps/(1 + lambda)`), and the values at the five largest kept `lambda`
//! are extrapolated to `u = 1/(1 + lambda + eps) = 0` by a quartic (the functions
//! converge in whole powers of `u`; a `u ln u` term only made the fits worse, tried).
//! The estimate of the error is the largest of the changes to a cubic, to a quintic, to
//! the quartic without the two largest `lambda`, and the tolerance. The force-torque
//! functions, whose exact sphere-plane values `stokesian::resistance::exact` has, calibrate it.

use anyhow::{bail, Result};
use stokesian::resistance::two_sphere::{Coefficients, PairSeries, NAMES};

/// The eleven "11" functions, as indices into [`NAMES`].
const ELEVEN: [usize; 11] = [0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20];

/// Gaps in units of the small sphere's radius.
const GAPS: [f64; 9] = [1e-3, 1e-2, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0, 30.0];

/// The exact sphere-plane values of the force-torque "11" functions in the two-sphere
/// normalisation (Kim & Karrila, `d` from the sphere to the plane), in the order of
/// [`ELEVEN`]'s first five: `X^A, Y^A, -(3/2) F^r, X^C, Y^C` (`lubrication.md` 2.1).
fn exact_wall(eps: f64) -> [f64; 5] {
    let [xa, ya, fr, yc, xc] = stokesian::resistance::exact::wall_functions_at_gap(eps);
    [xa, ya, -1.5 * fr, xc, yc]
}

/// The value at `u = 0` of the polynomial through `(u_k, f_k)` (Neville).
fn at_zero(u: &[f64], f: &[f64]) -> f64 {
    let mut p = f.to_vec();
    let n = p.len();
    for level in 1..n {
        for k in 0..n - level {
            p[k] = (u[k + level] * p[k] - u[k] * p[k + 1]) / (u[k + level] - u[k]);
        }
    }
    p[0]
}

/// The limit and its error estimate from `(u, f)` sorted by decreasing `lambda`
/// (increasing `u`), or `None` with fewer than six points.
fn extrapolate(u: &[f64], f: &[f64], tol: f64) -> Option<(f64, f64)> {
    if u.len() < 6 {
        return None;
    }
    let p =
        |start: usize, points: usize| at_zero(&u[start..start + points], &f[start..start + points]);
    let p4 = p(0, 5);
    let mut est = (p(0, 4) - p4).abs().max((p(0, 6) - p4).abs()).max(tol);
    if u.len() >= 7 {
        est = est.max((p(2, 5) - p4).abs());
    }
    Some((p4, est))
}

/// `cargo xtask wall-limit [--truncation N]`: the table of the sphere-plane functions as
/// the limit of two spheres, in Markdown on standard output.
pub fn run(args: &[&str]) -> Result<()> {
    let truncation = match args {
        [] => 400,
        ["--truncation", n] => n.parse()?,
        _ => bail!("usage: cargo xtask wall-limit [--truncation N]"),
    };
    if truncation < 40 {
        bail!("--truncation must be at least 40");
    }
    let t0 = std::time::Instant::now();
    let coefficients = Coefficients::build(truncation);
    let lower = truncation * 3 / 4;
    println!(
        "# Sphere-plane functions as the two-sphere limit lambda -> infinity\n\n\
         `cargo xtask wall-limit --truncation {truncation}` (recurrences built in {:.0} s). \
         A size ratio is kept where the sums to {truncation} and to {lower} terms agree \
         to the tolerance `tol` (per function, the smallest of 1e-10 ... 1e-2 that keeps \
         six or more); value: quartic in `u = 1/(1 + lambda + eps)` through the five \
         largest kept, extrapolated to `u = 0`; `est`: the error estimate (module \
         docs of `xtask/src/wall_limit.rs`) and `error`: the error against `exact`, the \
         sphere-plane series (`stokesian::resistance::exact`, force-torque functions only), both \
         relative to `max(|value|, 1)`. Kim & Karrila \
         normalisation, lengths in the sphere's radius, `d` from the sphere to the plane.\n",
        t0.elapsed().as_secs_f64()
    );
    let ladder: Vec<f64> = (0..28).map(|k| 2.0 * 1.4f64.powi(k)).collect();
    println!("| function | eps | value | est | exact | error | tol | lambda kept |");
    println!("|---|---|---|---|---|---|---|---|");
    // per gap: the largest error and estimate of the force-torque functions, and the
    // largest estimate of the stresslet ones (infinite where one is not established)
    let mut summary = Vec::new();
    for &eps in &GAPS {
        let (mut ft_error, mut ft_est, mut s_est) = (0.0f64, 0.0f64, 0.0f64);
        // [lambda][function]: the sums to N and to 3N/4 terms
        let mut hi = Vec::new();
        let mut lo = Vec::new();
        for &lambda in &ladder {
            let s_dash = 2.0 + 2.0 * eps / (1.0 + lambda);
            let sum = |n: usize| -> Result<[f64; 22]> {
                Ok(PairSeries::from_coefficients(&coefficients, lambda, n)?
                    .scalars(s_dash)?
                    .to_array())
            };
            hi.push(sum(truncation)?);
            lo.push(sum(lower)?);
        }
        let exact = exact_wall(eps);
        for (j, &k) in ELEVEN.iter().enumerate() {
            let mut found = None;
            for tol in [1e-10, 1e-8, 1e-6, 1e-4, 1e-3, 1e-2] {
                // kept, largest lambda first
                let kept: Vec<usize> = (0..ladder.len())
                    .rev()
                    .filter(|&i| (hi[i][k] - lo[i][k]).abs() < tol * hi[i][k].abs().max(1.0))
                    .collect();
                let u: Vec<f64> = kept
                    .iter()
                    .map(|&i| 1.0 / (1.0 + ladder[i] + eps))
                    .collect();
                let f: Vec<f64> = kept.iter().map(|&i| hi[i][k]).collect();
                if let Some((v, est)) = extrapolate(&u, &f, tol) {
                    found = Some((v, est, tol, ladder[kept[0]], ladder[kept[kept.len() - 1]]));
                    break;
                }
            }
            let scale = |v: f64| v.abs().max(1.0);
            let est = found.map_or(f64::INFINITY, |(v, est, ..)| est / scale(v));
            let (exact_s, error_s) = match exact.get(j) {
                Some(&e) => {
                    let error = found.map_or(f64::INFINITY, |(v, ..)| (v - e).abs() / scale(e));
                    ft_error = ft_error.max(error);
                    ft_est = ft_est.max(est);
                    (format!("{e:.10}"), format!("{error:.1e}"))
                }
                None => {
                    s_est = s_est.max(est);
                    (String::new(), String::new())
                }
            };
            match found {
                Some((v, _, tol, top, bottom)) => println!(
                    "| {} | {eps} | {v:.10} | {est:.1e} | {exact_s} | {error_s} | {tol:.0e} | {bottom:.0}-{top:.0} |",
                    NAMES[k]
                ),
                None => println!(
                    "| {} | {eps} | not established | | {exact_s} | | | fewer than six |",
                    NAMES[k]
                ),
            }
        }
        summary.push((eps, ft_error, ft_est, s_est));
    }
    println!(
        "\n| eps | largest error, force-torque | largest est, force-torque | largest est, \
         stresslet (G, H, M) |\n|---|---|---|---|"
    );
    for (eps, ft_error, ft_est, s_est) in summary {
        println!("| {eps} | {ft_error:.1e} | {ft_est:.1e} | {s_est:.1e} |");
    }
    eprintln!("wall-limit: {:.0} s in all", t0.elapsed().as_secs_f64());
    Ok(())
}
