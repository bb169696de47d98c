//! Generated tables of the 22 two-sphere resistance functions for separations `s' =
//! 2r/(a1 + a2) >= S_MIN` (3) and size ratios `lambda = a2/a1` in `[1e-2, 1e2]`: 2-D
//! Chebyshev fits in `t = 2/s'` and `mu = lambda/(1 + lambda)`, made by `cargo xtask
//! gen` from the twin-multipole series of [`crate::two_sphere`] and committed in
//! `src/generated/two_sphere_far.bin`.
//!
//! Each function is a power series in `t` with coefficients that are polynomials in
//! `mu` ([`crate::two_sphere`], module docs): analytic on `t < 1`, so on `t <= 2/3` it
//! is fitted to round-off by a few Chebyshev terms in each variable, with no singular
//! part to take out (the lubrication singularities sit at contact, `t = 1`). The tables
//! hold `T_PATCHES x MU_PATCHES` patches (`t` in `[0, 1/3]`, `[1/3, 2/3]`; `mu` in four
//! equal parts of `[mu(1e-2), mu(1e2)]`) of `TERMS x TERMS` coefficients per function.
//! A pair then costs `TERMS^2` multiply-adds per function and no series: a
//! polydisperse suspension, where nearly every pair has its own ratio, builds no
//! series for its pairs beyond `S_MIN` (the series of a new ratio cost 5-60 us; a
//! process-wide cache holds at most [`crate::two_sphere::CACHED_RATIOS`] of them).
//! Closer pairs keep the series, which converge to contact.
//!
//! Accuracy against the series between the nodes (`tests/tests/two_sphere_tables.rs`):
//! see README ("Resistance with lubrication").

use crate::tables::{chebyshev_coefficients, chebyshev_nodes};
use crate::two_sphere::{PairScalars, PairSeries, LAMBDA_MIN};
use std::sync::OnceLock;

/// The smallest separation `s'` of the tables.
pub const S_MIN: f64 = 3.0;
/// Patches in `t = 2/s'` (equal parts of `[0, 2/S_MIN]`).
pub const T_PATCHES: usize = 2;
/// Patches in `mu = lambda/(1 + lambda)` (equal parts of `[mu(LAMBDA_MIN),
/// mu(1/LAMBDA_MIN)]`).
pub const MU_PATCHES: usize = 4;
/// Chebyshev coefficients per variable and patch (degree + 1).
pub const TERMS: usize = 16;
/// The functions, in the order of [`PairScalars::to_array`].
const FUNCTIONS: usize = 22;
/// Coefficients of one function on one patch.
const PATCH: usize = TERMS * TERMS;
/// Numbers in the tables.
const LEN: usize = FUNCTIONS * T_PATCHES * MU_PATCHES * PATCH;

/// The coefficients as written by `cargo xtask gen` from [`generate`]: for each function,
/// `t` patch, `mu` patch, `t` term, the `mu` terms; little-endian `f64`. Not typed by its
/// length, so that a file of another shape (the constants above changed, the file not yet
/// regenerated) still compiles, and `cargo xtask gen` can write the new one.
static DATA: &[u8] = include_bytes!("generated/two_sphere_far.bin");

/// The coefficients, read once; `None` if the file does not have the tables' shape
/// (then every pair takes the series, and `cargo xtask gen --check` reports the file).
fn table() -> Option<&'static [f64]> {
    static TABLE: OnceLock<Option<Vec<f64>>> = OnceLock::new();
    TABLE
        .get_or_init(|| {
            (DATA.len() == LEN * 8).then(|| {
                DATA.chunks_exact(8)
                    .map(|b| f64::from_le_bytes(b.try_into().expect("chunks of eight bytes")))
                    .collect()
            })
        })
        .as_deref()
}

/// `mu` of `lambda`.
fn mu(lambda: f64) -> f64 {
    lambda / (1.0 + lambda)
}

/// The ends of `t` patch `p`.
fn t_patch(p: usize) -> (f64, f64) {
    let w = 2.0 / S_MIN / T_PATCHES as f64;
    (p as f64 * w, (p + 1) as f64 * w)
}

/// The ends of `mu` patch `p`.
fn mu_patch(p: usize) -> (f64, f64) {
    let (lo, hi) = (mu(LAMBDA_MIN), mu(1.0 / LAMBDA_MIN));
    let w = (hi - lo) / MU_PATCHES as f64;
    (lo + p as f64 * w, lo + (p + 1) as f64 * w)
}

/// The patch of `x` among `n` equal parts starting at `lo` of width `w`, and `x` mapped to
/// `[-1, 1]` on it (the last patch takes its right end).
fn locate(x: f64, lo: f64, w: f64, n: usize) -> (usize, f64) {
    let p = (((x - lo) / w).floor().max(0.0) as usize).min(n - 1);
    let a = lo + p as f64 * w;
    (p, 2.0 * (x - a) / w - 1.0)
}

/// `T_0(x) ... T_(TERMS-1)(x)`.
fn chebyshev_values(x: f64) -> [f64; TERMS] {
    let mut t = [1.0; TERMS];
    t[1] = x;
    for j in 2..TERMS {
        t[j] = 2.0 * x * t[j - 1] - t[j - 2];
    }
    t
}

/// The first `count` functions (10: the force-torque ones; 22: all, in the order of
/// [`PairScalars::to_array`]; the others zero) at `s_dash >= S_MIN` and `lambda` in
/// `[1e-2, 1e2]` from the tables; `None` outside (or if the committed file does not have
/// the tables' shape).
pub fn far_scalars(s_dash: f64, lambda: f64, count: usize) -> Option<PairScalars> {
    if !(s_dash >= S_MIN && (LAMBDA_MIN..=1.0 / LAMBDA_MIN).contains(&lambda)) {
        return None;
    }
    let (pt, xt) = locate(2.0 / s_dash, 0.0, t_patch(0).1, T_PATCHES);
    let (lo, hi) = mu_patch(0);
    let (pm, xm) = locate(mu(lambda), lo, hi - lo, MU_PATCHES);
    let (ct, cm) = (chebyshev_values(xt), chebyshev_values(xm));
    let data = table()?;
    let mut out = [0.0; FUNCTIONS];
    for (k, o) in out.iter_mut().enumerate().take(count.min(FUNCTIONS)) {
        let start = ((k * T_PATCHES + pt) * MU_PATCHES + pm) * PATCH;
        // sum_j T_j(mu) sum_i T_i(t) c_ij: the inner sums side by side (in vector lanes),
        // not one chain of dependent additions per row
        let mut inner = [0.0; TERMS];
        for (row, ti) in data[start..start + PATCH].chunks_exact(TERMS).zip(&ct) {
            for (s, c) in inner.iter_mut().zip(row) {
                *s += ti * c;
            }
        }
        *o = inner.iter().zip(&cm).map(|(s, mj)| s * mj).sum();
    }
    Some(PairScalars::from_array(out))
}

/// The contents of `src/generated/two_sphere_far.bin`: every function's coefficients on
/// every patch, from the series at the Chebyshev points of the first kind (the series of
/// each node's ratio built once, in parallel).
pub fn generate() -> Vec<u8> {
    use rayon::prelude::*;
    // values[pm][j][pt][i][k]: function k at mu node j of patch pm, t node i of patch pt
    let values: Vec<Vec<Vec<Vec<[f64; FUNCTIONS]>>>> = (0..MU_PATCHES)
        .map(|pm| {
            let (a, b) = mu_patch(pm);
            chebyshev_nodes(a, b, TERMS)
                .into_par_iter()
                .map(|m| {
                    let series = PairSeries::new(m / (1.0 - m)).expect("lambda in range");
                    (0..T_PATCHES)
                        .map(|pt| {
                            let (a, b) = t_patch(pt);
                            chebyshev_nodes(a, b, TERMS)
                                .into_iter()
                                .map(|t| {
                                    series
                                        .scalars(2.0 / t)
                                        .expect("separation in range")
                                        .to_array()
                                })
                                .collect()
                        })
                        .collect()
                })
                .collect()
        })
        .collect();
    let mut out = Vec::with_capacity(LEN * 8);
    for k in 0..FUNCTIONS {
        for pt in 0..T_PATCHES {
            for at_mu in &values {
                // along mu for each t node, then along t for each mu term
                let rows: Vec<Vec<f64>> = (0..TERMS)
                    .map(|i| {
                        chebyshev_coefficients(
                            &at_mu.iter().map(|v| v[pt][i][k]).collect::<Vec<_>>(),
                        )
                    })
                    .collect();
                let mut patch = vec![0.0; PATCH];
                for j in 0..TERMS {
                    let c = chebyshev_coefficients(&rows.iter().map(|r| r[j]).collect::<Vec<_>>());
                    for (i, ci) in c.into_iter().enumerate() {
                        patch[i * TERMS + j] = ci;
                    }
                }
                out.extend(patch.iter().flat_map(|v| v.to_le_bytes()));
            }
        }
    }
    out
}
