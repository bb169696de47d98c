//! `exp` and `erfc` lowered into the graph's ordinary nodes (arithmetic and
//! [`Op::Select`](super::Op::Select)), so that the interpreter, the emitted scalar code and
//! the lane kernels perform the same operations: lanes have no exponential, no `floor` and
//! no integers, only arithmetic, square roots, comparisons and a per-lane choice.
//!
//! - `e^{-t}`, `t >= 0` ([`exp`] of a non-positive argument): a ladder of comparisons
//!   takes out the binary digits of `t` from 32 down to 1/2, where `t > 2^k` subtracting
//!   `2^k` (exact: `2^k < t <= 2^(k+1)` once the digits above are out, Sterbenz) and
//!   multiplying by the constant `e^{-2^k}`; the rest `s in [0, 1/2]` goes to the Taylor
//!   series of `e^{-s}` to degree [`EXP_DEGREE`] (truncation `0.5^17/17! < 1e-19` of
//!   `e^{-1/2}`), by Horner's rule. Above [`EXP_ZERO`] the value is 0 (`e^{-64} = 1.6e-28`
//!   absolute). No squaring magnifies the error: about 7 roundings of the factors and the
//!   polynomial's own; measured against double-double on a dense grid of `[0, 64]`:
//!   at most 5.8e-16 relative (test in `tests/tests/integration/generator/graph_elementary.rs`).
//! - `erfc x`: for `|x| <= 1/2` ([`SERIES_END`]), `1 - x P(x^2)`, `P` the Taylor series of
//!   `erf(x)/x` to degree [`SERIES_DEGREE`] in `x^2` (truncation `5e-18`); above,
//!   `e^{-x^2} R(|x|)` with `R` a polynomial of degree [`FIT_DEGREE`] in `u = 1.8 t + 0.4`,
//!   `t = (|x| - 4)/(|x| + 4)` (`u` in `[-1, 1]` for `|x|` in `[1/2, 8]`), interpolating
//!   the scaled `erfcx x = e^{x^2} erfc x` at the Chebyshev points of `u`, computed in
//!   double-double when the kernels are generated (interpolation error `4e-18`, largest
//!   coefficient 0.21: Horner's rule loses nothing); `erfc(-x) = 2 - erfc(x)`; both
//!   branches computed and one chosen per lane. Beyond `|x| = 8` the exponential is 0
//!   (`erfc 8 = 1.1e-29`). Measured on a dense grid of `[-8, 8]`: relative error at
//!   most `(x^2 + 4.5) 2^-53` (4.2e-15 at `x = 6.9`), of which `x^2 2^-53` is the
//!   rounding of `x^2` in the argument of the exponential (same test file).
//!
//! The `e^{-x^2}` of `erfc x` is the node of `exp(-(x x))`, so the jet rule of `erfc`,
//! which forms that exponential itself, shares it.

use super::trace::Ex;
use crate::number::dd::Dd;
use crate::number::scalar::Scalar;
use std::sync::OnceLock;

/// Degree of the Taylor polynomial of `e^{-s}`, `s in [0, 1/2]`.
pub const EXP_DEGREE: usize = 16;
/// Above this `t`, `e^{-t}` is 0.
pub const EXP_ZERO: f64 = 64.0;
/// The largest binary digit the ladder of `e^{-t}` takes out (`2^5 = 32`); the smallest
/// is `2^-1`.
const LADDER_TOP: i32 = 5;
/// `erfc x` takes the series for `|x| <= SERIES_END`, the fitted `erfcx` above.
pub const SERIES_END: f64 = 0.5;
/// Degree in `x^2` of the series of `erf(x)/x`.
pub const SERIES_DEGREE: usize = 12;
/// Degree of the polynomial that interpolates `erfcx`.
pub const FIT_DEGREE: usize = 18;
/// The centre `c` of the variable `t = (x - c)/(x + c)` of the fit.
const FIT_CENTRE: f64 = 4.0;
/// `u = FIT_SCALE t + FIT_SHIFT` maps `t` of `x in [1/2, 8]`, `[-7/9, 1/3]`, to `[-1, 1]`.
const FIT_SCALE: f64 = 1.8;
const FIT_SHIFT: f64 = 0.4;

/// `c_0 + c_1 x + ...` by Horner's rule.
fn horner(x: Ex, c: &[f64]) -> Ex {
    let (last, rest) = c.split_last().expect("a coefficient");
    rest.iter()
        .rev()
        .fold(Ex::cst(*last), |acc, &ck| acc * x + Ex::cst(ck))
}

/// The Taylor coefficients `(-1)^k / k!` of `e^{-s}`.
fn exp_coefficients() -> &'static [f64] {
    static C: OnceLock<Vec<f64>> = OnceLock::new();
    C.get_or_init(|| {
        let mut term = Dd::new(1.0);
        (0..=EXP_DEGREE)
            .map(|k| {
                if k > 0 {
                    term = -term / Dd::new(k as f64);
                }
                term.to_f64()
            })
            .collect()
    })
}

/// The coefficients `(2/sqrt(pi)) (-1)^n / (n! (2n + 1))` of `erf(x)/x` in `x^2`.
fn series_coefficients() -> &'static [f64] {
    static C: OnceLock<Vec<f64>> = OnceLock::new();
    C.get_or_init(|| {
        let mut alt = Dd::two_over_sqrt_pi();
        (0..=SERIES_DEGREE)
            .map(|n| {
                if n > 0 {
                    alt = -alt / Dd::new(n as f64);
                }
                (alt / Dd::new((2 * n + 1) as f64)).to_f64()
            })
            .collect()
    })
}

/// The monomial coefficients in `u` of the polynomial that interpolates `erfcx(x(u))` at
/// the Chebyshev points `u_k = cos(pi (k + 1/2)/(n + 1))` (rounded to `f64`, then
/// exact), `x(u) = c (1 + t)/(1 - t)`, `t = (u - FIT_SHIFT)/FIT_SCALE`: Newton's divided
/// differences in double-double, expanded into monomials.
fn fit_coefficients() -> &'static [f64] {
    static C: OnceLock<Vec<f64>> = OnceLock::new();
    C.get_or_init(|| {
        let n = FIT_DEGREE;
        let u: Vec<Dd> = (0..=n)
            .map(|k| Dd::new((std::f64::consts::PI * (k as f64 + 0.5) / (n + 1) as f64).cos()))
            .collect();
        let one = Dd::new(1.0);
        let mut d: Vec<Dd> = u
            .iter()
            .map(|&uk| {
                let t = (uk - Dd::new(FIT_SHIFT)) / Dd::new(FIT_SCALE);
                (Dd::new(FIT_CENTRE) * (one + t) / (one - t)).erfcx()
            })
            .collect();
        for j in 1..=n {
            for i in (j..=n).rev() {
                d[i] = (d[i] - d[i - 1]) / (u[i] - u[i - j]);
            }
        }
        // p(u) = d_0 + (u - u_0)(d_1 + (u - u_1)(d_2 + ...)), expanded from the inside
        let mut p = vec![d[n]];
        for k in (0..n).rev() {
            // p <- p (u - u_k) + d_k
            let mut q = vec![Dd::new(0.0); p.len() + 1];
            for (m, &pm) in p.iter().enumerate() {
                q[m + 1] = q[m + 1] + pm;
                q[m] = q[m] - pm * u[k];
            }
            q[0] = q[0] + d[k];
            p = q;
        }
        p.into_iter().map(Dd::to_f64).collect()
    })
}

/// `e^a` for `a <= 0`, lowered (module documentation); a constant folds.
pub fn exp(a: Ex) -> Ex {
    if let Some(c) = a.as_const() {
        return Ex::cst(Dd::new(c).exp().to_f64());
    }
    let t0 = -a;
    let mut t = t0;
    let mut factor: Option<Ex> = None;
    for k in (-1..=LADDER_TOP).rev() {
        let p = 2f64.powi(k);
        let (pe, one) = (Ex::cst(p), Ex::cst(1.0));
        let f = Ex::select_gt(t, pe, Ex::cst(Dd::new(-p).exp().to_f64()), one);
        factor = Some(match factor {
            None => f,
            Some(g) => g * f,
        });
        t = Ex::select_gt(t, pe, t - pe, t);
    }
    let v = factor.expect("a digit") * horner(t, exp_coefficients());
    Ex::select_gt(t0, Ex::cst(EXP_ZERO), Ex::cst(0.0), v)
}

/// `erfc x`, lowered (module documentation); a constant folds.
pub fn erfc(x: Ex) -> Ex {
    if let Some(c) = x.as_const() {
        return Ex::cst(Dd::new(c).erfc().to_f64());
    }
    let zero = Ex::cst(0.0);
    let x2 = x * x;
    let series = Ex::cst(1.0) - x * horner(x2, series_coefficients());
    let ax = Ex::select_gt(x, zero, x, -x);
    let c = Ex::cst(FIT_CENTRE);
    let t = (ax - c) / (ax + c);
    let u = Ex::cst(FIT_SCALE) * t + Ex::cst(FIT_SHIFT);
    let far = exp(-x2) * horner(u, fit_coefficients());
    let far = Ex::select_gt(x, zero, far, Ex::cst(2.0) - far);
    Ex::select_gt(ax, Ex::cst(SERIES_END), far, series)
}
