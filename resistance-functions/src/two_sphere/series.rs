//! The series of the 22 functions for one size ratio ([`PairSeries`]): the regular
//! remainders summed from the recurrences' triangles, evaluated at any separation with the
//! singular closed forms added; how many terms a separation needs; the process-wide cache.

use super::functions::{FT_SOURCES, FUNCTIONS, SOURCES};
use super::recurrences::{tri, Coefficients, Table, Triangles};
use super::scalars::{FtScalars, PairScalars};
use super::singular::{singular_part, singular_taylor, Geometry};
use super::{check_lambda, TwoSphereError, TRUNCATION};
use std::collections::HashMap;
use std::f64::consts::LN_2;
use std::sync::OnceLock;

/// Number of remainder coefficients kept per function (one parity of `0..=truncation`).
fn half(truncation: usize) -> usize {
    truncation / 2 + 1
}

/// Most series [`PairSeries::cached`] keeps.
pub const CACHED_RATIOS: usize = 4096;

/// A bound on every remainder coefficient `|r_m|` of every function for `LAMBDA_MIN <=
/// lambda <= 1/LAMBDA_MIN`: ten times the largest over 401 ratios spaced evenly in
/// `ln lambda` (5.1e3, at `m = 0`; beyond `m = 50` all are below 0.5), test
/// `remainders_are_below_their_bound`. It sets how many terms a separation may need
/// before the series is summed ([`rows_for`]).
const REMAINDER_BOUND: f64 = 5.1e4;

/// How many rows of remainders (powers `t^2j`, `t = 2/s'`) add more than 1e-17 in all at
/// `t^2 = t2` when no `|r_m|` exceeds `exp(ln_largest)`: the tail beyond is below
/// `largest t^(2j) / (1 - t^2)`. Not finite at contact (`t2 = 1`).
fn rows_for(t2: f64, ln_largest: f64) -> f64 {
    ((1e-17f64.ln() + (1.0 - t2).ln() - ln_largest) / t2.ln()).ceil()
}

/// The rows a series needs for every separation `s' >= s_dash` (all of them at contact
/// or for a separation that is not valid).
fn rows_needed(s_dash: f64) -> usize {
    let all = half(TRUNCATION);
    if !(s_dash.is_finite() && s_dash > 2.0) {
        return all;
    }
    let t = 2.0 / s_dash;
    let rows = rows_for(t * t, REMAINDER_BOUND.ln());
    if rows.is_finite() {
        (rows.max(1.0) as usize).min(all)
    } else {
        all
    }
}

/// The series of all 22 functions for one size ratio: the remainders `r_m` (module docs)
/// and the singular coefficients. Building it costs `O(TRUNCATION^2)` per function;
/// evaluating it at a separation at most `O(TRUNCATION)` per function, without
/// allocating. Use it when many separations
/// share one `lambda`.
#[derive(Clone, Debug)]
pub struct PairSeries {
    lambda: f64,
    count: usize,
    /// `remainder[j][k]`: the `j`-th coefficient of function `k`, stored power by power so
    /// that the 22 Horner sums advance together (independent chains, in vector lanes):
    /// one function after another, each waited on its own chain of dependent steps.
    remainder: Vec<[f64; 22]>,
    /// Summed for far pairs only ([`PairSeries::cached_at`]): a separation that needs
    /// more rows than it holds ([`rows_needed`]) is an error.
    far_only: bool,
    singular: [[f64; 3]; 22],
    /// `ln` of the largest `|r_m|` of any function: with [`REMAINDER_BOUND`], the larger
    /// of the two, sets how many terms a separation needs (the bound, within the committed
    /// range of `lambda`: so every series of a ratio, however far it was summed, sums the
    /// same terms at a separation, and gives the same values bit for bit).
    ln_largest: f64,
}

impl PairSeries {
    /// All 22 functions for `lambda = a2/a1` in `[1e-2, 1e2]`.
    pub fn new(lambda: f64) -> Result<Self, TwoSphereError> {
        Self::with_count(lambda, 22)
    }

    /// The ten force-torque functions only.
    pub fn new_ft(lambda: f64) -> Result<Self, TwoSphereError> {
        Self::with_count(lambda, 10)
    }

    /// The whole series for `lambda` (all 22 functions, or the ten force-torque ones when
    /// `force_torque_only`) from a process-wide cache: built once per size ratio and
    /// level, then shared. A lubricated Brownian step forms three
    /// resistances, each needing the series of every size ratio of its close pairs.
    /// The cache holds at most [`CACHED_RATIOS`] series (about 35 kB each); beyond, a
    /// series is built for the call alone.
    pub fn cached(
        lambda: f64,
        force_torque_only: bool,
    ) -> Result<std::sync::Arc<PairSeries>, TwoSphereError> {
        Self::cached_rows(lambda, force_torque_only, half(TRUNCATION))
    }

    /// As [`PairSeries::cached`], but summed only as far as separations `s' >= s_dash`
    /// need (`REMAINDER_BOUND`): a far pair's costs a fraction of a whole one (module
    /// docs: about 2/5 at `s' = 4`, 1/5 at `s' = 10`; every term near contact). At those separations its
    /// values equal the full series' bit for bit (the same terms, summed alike). A closer
    /// pair of the same ratio replaces the cached series by one with at least twice the
    /// terms.
    pub fn cached_at(
        lambda: f64,
        force_torque_only: bool,
        s_dash: f64,
    ) -> Result<std::sync::Arc<PairSeries>, TwoSphereError> {
        Self::cached_rows(lambda, force_torque_only, rows_needed(s_dash))
    }

    fn cached_rows(
        lambda: f64,
        force_torque_only: bool,
        rows: usize,
    ) -> Result<std::sync::Arc<PairSeries>, TwoSphereError> {
        type Cache = std::sync::Mutex<HashMap<(u64, bool), std::sync::Arc<PairSeries>>>;
        static CACHE: OnceLock<Cache> = OnceLock::new();
        let cache = CACHE.get_or_init(Default::default);
        let key = (lambda.to_bits(), force_torque_only);
        let held = cache.lock().ok().and_then(|c| c.get(&key).cloned());
        let rows = match held {
            Some(s) if s.remainder.len() >= rows => return Ok(s),
            Some(s) => rows.max(2 * s.remainder.len()).min(half(TRUNCATION)),
            None => rows,
        };
        let count = if force_torque_only { 10 } else { 22 };
        let built = std::sync::Arc::new(Self::with_rows(lambda, count, rows)?);
        if let Ok(mut c) = cache.lock() {
            if c.len() < CACHED_RATIOS || c.contains_key(&key) {
                c.insert(key, built.clone());
            }
        }
        Ok(built)
    }

    fn with_count(lambda: f64, count: usize) -> Result<Self, TwoSphereError> {
        Self::with_rows(lambda, count, half(TRUNCATION))
    }

    /// The committed series summed to its first `rows` rows (`m <= 2 rows - 1`).
    fn with_rows(lambda: f64, count: usize, rows: usize) -> Result<Self, TwoSphereError> {
        check_lambda(lambda)?;
        static ROWS: OnceLock<Vec<[f64; SOURCES]>> = OnceLock::new();
        let all = ROWS.get_or_init(|| interleave(TRUNCATION, |t| t.triangles()));
        let truncation = (2 * rows.max(1) - 1).min(TRUNCATION);
        let mut out = Self::summed(lambda, count, truncation, all);
        out.far_only = truncation < TRUNCATION;
        Ok(out)
    }

    /// The series of all 22 functions for any size ratio `lambda > 0`, summed to `m <=
    /// truncation` (at most `coefficients.truncation()`), from coefficients built at run
    /// time: for studies of the truncation and of large size ratios (the limit of a
    /// sphere beside a plane). The committed coefficients reach `m = 200`, enough for
    /// [`super::LAMBDA_MIN`] `<= lambda <= 1/LAMBDA_MIN` at the accuracy of the module docs;
    /// larger ratios need more terms, the more the closer the spheres.
    pub fn from_coefficients(
        coefficients: &Coefficients,
        lambda: f64,
        truncation: usize,
    ) -> Result<Self, TwoSphereError> {
        if !(lambda.is_finite() && lambda > 0.0) {
            return Err(TwoSphereError::SizeRatio(lambda));
        }
        let truncation = truncation.min(coefficients.truncation);
        let rows = interleave(truncation, |t| &coefficients.triangles[t as usize]);
        Ok(Self::summed(lambda, 22, truncation, &rows))
    }

    /// The series from the triangles' rows interleaved ([`interleave`]).
    fn summed(lambda: f64, count: usize, truncation: usize, rows: &[[f64; SOURCES]]) -> Self {
        let mut out = PairSeries {
            lambda,
            count,
            remainder: vec![[0.0; 22]; half(truncation)],
            far_only: false,
            singular: [[0.0; 3]; 22],
            ln_largest: 0.0,
        };
        for (k, f) in FUNCTIONS.iter().enumerate().take(count) {
            out.singular[k] = (f.singular)(lambda);
        }
        // `x^i` for `lambda <= 1` (`x = lambda`), else `x^(truncation - i)` (`x = 1/lambda`),
        // so that the powers of row `m` are `powers[..=m]`, or `powers[truncation - m..]`
        let x = if lambda <= 1.0 { lambda } else { 1.0 / lambda };
        // (below 1e-290 set to zero: the committed coefficients reach 5e58, so the terms
        // dropped are below 1e-231, and subnormal numbers would slow every product down)
        let mut powers = vec![1.0; truncation + 1];
        for i in 1..=truncation {
            let p = powers[i - 1] * x;
            powers[i] = if p < 1e-290 { 0.0 } else { p };
        }
        if lambda > 1.0 {
            powers.reverse();
        }
        for m in 0..=truncation {
            let p = if lambda <= 1.0 {
                &powers[..=m]
            } else {
                &powers[truncation - m..]
            };
            let row = &rows[tri(m, 0)..=tri(m, m)];
            let mut sums = [0.0; SOURCES];
            if count <= 2 * FT_SOURCES {
                sums[..FT_SOURCES].copy_from_slice(&row_sums::<FT_SOURCES>(row, p));
            } else {
                sums = row_sums::<SOURCES>(row, p);
            }
            // what every function of this parity shares
            let power = (if lambda <= 1.0 { 1.0 } else { lambda } / (1.0 + lambda)).powi(m as i32);
            let odd = m % 2 == 1;
            let s = singular_taylor(odd, m);
            for (k, f) in FUNCTIONS.iter().enumerate().take(count) {
                if f.odd != odd {
                    continue;
                }
                let h = out.singular[k];
                out.remainder[m / 2][k] = f.coefficient(sums[k / 2], power, lambda, m)
                    - h[0] * s[0]
                    - h[1] * s[1]
                    - h[2] * s[2];
            }
        }
        let largest = out
            .remainder
            .iter()
            .flatten()
            .fold(f64::MIN_POSITIVE, |m, r| m.max(r.abs()));
        out.ln_largest = largest.ln();
        out
    }

    /// The size ratio.
    pub fn lambda(&self) -> f64 {
        self.lambda
    }

    /// The functions at `s_dash = 2r/(a1+a2) > 2` (those not built by [`Self::new_ft`] are
    /// zero).
    pub fn scalars(&self, s_dash: f64) -> Result<PairScalars, TwoSphereError> {
        let geo = Geometry::new(s_dash)?;
        let regular = self.regular_at(s_dash, &geo)?;
        Ok(PairScalars::from_array(std::array::from_fn(|k| {
            if k < self.count {
                singular_part(k, &self.singular[k], &geo) + regular[k]
            } else {
                0.0
            }
        })))
    }

    /// The regular parts `F - h . S(t)` of the functions at `s_dash` (module docs: the
    /// remainder series `sum_m r_m t^m`), continuous up to contact: what the near-contact
    /// tables of [`crate::pair_tables`] fit.
    pub fn regular(&self, s_dash: f64) -> Result<[f64; 22], TwoSphereError> {
        self.regular_at(s_dash, &Geometry::new(s_dash)?)
    }

    fn regular_at(&self, s_dash: f64, geo: &Geometry) -> Result<[f64; 22], TwoSphereError> {
        if self.far_only && rows_needed(s_dash) > self.remainder.len() {
            return Err(TwoSphereError::Truncated(s_dash));
        }
        let t2 = geo.t * geo.t;
        // Terms beyond `j` add less than 1e-17 in all: `largest t^(2j) / (1 - t^2)`.
        let terms = rows_for(t2, self.ln_largest.max(REMAINDER_BOUND.ln()));
        let terms = if terms.is_finite() {
            (terms.max(1.0) as usize).min(self.remainder.len())
        } else {
            self.remainder.len()
        };
        // the remainder series by Horner in t^2, all functions at once
        let mut sums = [0.0; 22];
        for row in self.remainder[..terms].iter().rev() {
            for (acc, r) in sums.iter_mut().zip(row) {
                *acc = *acc * t2 + r;
            }
        }
        for (k, f) in FUNCTIONS.iter().enumerate() {
            if f.odd {
                sums[k] *= geo.t;
            }
        }
        Ok(sums)
    }

    /// The near-contact constants `K(lambda)` (JO84, J92 as corrected by Townsend 2023;
    /// Kim & Karrila normalisation): the `O(1)` terms of `F = h1/xi + h2 ln(1/xi) + K + h3 xi ln(1/xi) +
    /// O(xi)`, from the same truncated series (for `X11C`, `X12C` they equal
    /// `lambda^3/(1+lambda)^3 zeta(3, lambda/(1+lambda))` and `-lambda^3/(1+lambda)^3
    /// zeta(3)`).
    pub fn contact_constants(&self) -> PairScalars {
        let mut out = [0.0; 22];
        for (k, f) in FUNCTIONS.iter().enumerate().take(self.count) {
            let h = self.singular[k];
            // limits of S1 - 1/xi and S2 - ln(1/xi) at contact (S3 -> 0)
            let (k1, k2) = if f.odd {
                (0.25, 2.0 * LN_2)
            } else {
                (0.75, 0.0)
            };
            out[k] = h[0] * k1 + h[1] * k2 + self.remainder.iter().map(|row| row[k]).sum::<f64>();
        }
        PairScalars::from_array(out)
    }
}

/// The 22 resistance functions at separation `s_dash = 2r/(a1+a2) > 2` and size ratio
/// `lambda = a2/a1` in `[1e-2, 1e2]` ([`PairSeries::new`] then [`PairSeries::scalars`]; one
/// allocation, the series' remainders).
pub fn resistance_scalars(s_dash: f64, lambda: f64) -> Result<PairScalars, TwoSphereError> {
    Geometry::new(s_dash)?;
    PairSeries::new(lambda)?.scalars(s_dash)
}

/// The ten force-torque functions only ([`PairSeries::new_ft`]; about half the cost of
/// [`resistance_scalars`]).
pub fn resistance_scalars_ft(s_dash: f64, lambda: f64) -> Result<FtScalars, TwoSphereError> {
    Geometry::new(s_dash)?;
    Ok(PairSeries::new_ft(lambda)?.scalars(s_dash)?.ft())
}

/// The rows of the [`SOURCES`] triangles to `truncation`, interleaved: entry `tri(m, q)`
/// holds `R_{m-q,q}` of every triangle, so that their sums ([`row_sums`])
/// advance side by side in vector lanes.
fn interleave<'c>(
    truncation: usize,
    triangles: impl Fn(Table) -> &'c Triangles,
) -> Vec<[f64; SOURCES]> {
    let tris: Vec<&[f64]> = (0..SOURCES)
        .map(|s| {
            let f = &FUNCTIONS[2 * s];
            &triangles(f.table)[f.output][..]
        })
        .collect();
    (0..=tri(truncation, truncation))
        .map(|i| std::array::from_fn(|s| tris[s][i]))
        .collect()
}

/// `sum_q R_{m-q,q} lambda^q` of every triangle at `m` for `lambda <= 1`, and
/// `sum_q R_{m-q,q} lambda^{q-m}` (the power `lambda^m` left to
/// [`Function::coefficient`]) otherwise, so that no power overflows: `rows` is row `m`,
/// `powers` holds `lambda^q` or `lambda^(q-m)`. A sum of products in two partial sums
/// rather than Horner's chain of dependent steps: the triangles' sums advance side by
/// side in vector lanes and the products overlap in the pipeline.
/// Only the first `N` triangles are summed (the force-torque functions read the first
/// five), each exactly as when all are.
fn row_sums<const N: usize>(rows: &[[f64; SOURCES]], powers: &[f64]) -> [f64; N] {
    let mut acc = [[0.0; N]; 2];
    let add = |acc: &mut [f64; N], c: &[f64; SOURCES], p: f64| {
        for (a, c) in acc.iter_mut().zip(c) {
            *a += c * p;
        }
    };
    let (rc, pc) = (rows.chunks_exact(2), powers.chunks_exact(2));
    let (rr, pr) = (rc.remainder(), pc.remainder());
    for (c, p) in rc.zip(pc) {
        add(&mut acc[0], &c[0], p[0]);
        add(&mut acc[1], &c[1], p[1]);
    }
    for (c, &p) in rr.iter().zip(pr) {
        add(&mut acc[0], c, p);
    }
    std::array::from_fn(|s| acc[0][s] + acc[1][s])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::two_sphere::{LAMBDA_MIN, NAMES};

    #[test]
    fn bad_input_is_a_typed_error() {
        for s in [2.0, 1.5, -3.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                resistance_scalars_ft(s, 1.0),
                Err(TwoSphereError::Separation(_))
            ));
        }
        for l in [0.0, 9e-3, 101.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                resistance_scalars_ft(3.0, l),
                Err(TwoSphereError::SizeRatio(_))
            ));
            assert!(matches!(
                PairSeries::new(l),
                Err(TwoSphereError::SizeRatio(_))
            ));
        }
        let c = Coefficients::build(4);
        for l in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(PairSeries::from_coefficients(&c, l, 4).is_err());
        }
    }

    /// [`REMAINDER_BOUND`] is ten times every remainder of every function over 401 size
    /// ratios evenly spaced in `ln lambda` across the committed range (the functions are
    /// smooth in `lambda`; the largest, 5.1e3, is at `m = 0` and the smallest ratio).
    #[test]
    fn remainders_are_below_their_bound() {
        let mut largest = 0.0f64;
        for i in 0..=400 {
            let lambda = LAMBDA_MIN.powf(1.0 - f64::from(i) / 200.0);
            let s = PairSeries::new(lambda).unwrap();
            largest = largest.max(s.ln_largest.exp());
        }
        println!("largest remainder {largest:e}, bound {REMAINDER_BOUND:e}");
        assert!(10.0 * largest <= REMAINDER_BOUND * 1.01, "{largest:e}");
        assert!(
            largest > 0.5 * REMAINDER_BOUND / 10.0,
            "the bound is loose: {largest:e}"
        );
    }

    /// A series summed for far pairs gives the full series' values bit for bit at the
    /// separation it was summed for and beyond, is cheaper (fewer rows), and refuses a
    /// closer separation with a typed error; the cache hands out a longer series for a
    /// closer pair of the same ratio. The force-torque series (which sums five of the
    /// eleven triangles) gives the full series' force-torque functions bit for bit.
    #[test]
    fn series_summed_for_far_pairs_equal_the_full_series() {
        for lambda in [0.013, 0.37, 1.0, 4.1, 77.0] {
            let full = PairSeries::new(lambda).unwrap();
            let ft = PairSeries::new_ft(lambda).unwrap();
            let ft_far = PairSeries::with_rows(lambda, 10, rows_needed(4.0)).unwrap();
            for s in [2.0001, 2.2, 4.0, 60.0] {
                let want = full.scalars(s).unwrap().ft();
                assert_eq!(ft.scalars(s).unwrap().ft(), want, "lambda {lambda} at {s}");
                if s >= 4.0 {
                    assert_eq!(ft_far.scalars(s).unwrap().ft(), want);
                }
            }
            for s_dash in [2.2, 3.0, 4.0, 10.0, 60.0] {
                let far = PairSeries::with_rows(lambda, 22, rows_needed(s_dash)).unwrap();
                assert!(far.remainder.len() <= full.remainder.len());
                if s_dash >= 4.0 {
                    // at most 40% of the rows, so at most 1/6 of the cost (37 of 101 at 4)
                    assert!(far.far_only && 5 * far.remainder.len() < 2 * full.remainder.len());
                }
                for s in [s_dash, 1.3 * s_dash, 10.0 * s_dash] {
                    assert_eq!(
                        far.scalars(s).unwrap().to_array(),
                        full.scalars(s).unwrap().to_array(),
                        "lambda {lambda} summed for {s_dash}, at {s}"
                    );
                }
                if far.far_only {
                    assert_eq!(
                        far.scalars(2.1).unwrap_err(),
                        TwoSphereError::Truncated(2.1)
                    );
                }
            }
        }
        // a ratio no other test uses, so that the cache starts without it
        let lambda = 0.123_456_7;
        let far = PairSeries::cached_at(lambda, false, 20.0).unwrap();
        let near = PairSeries::cached_at(lambda, false, 2.5).unwrap();
        assert!(far.far_only && near.remainder.len() > far.remainder.len());
        assert!(near.scalars(2.5).is_ok() && far.scalars(2.5).is_err());
        assert!(std::sync::Arc::ptr_eq(
            &near,
            &PairSeries::cached_at(lambda, false, 5.0).unwrap()
        ));
    }

    /// Coefficients built at run time to 80 terms give the committed series where 80
    /// terms suffice (`s' = 4`: `t^80 = 8e-25`), every function, both sides of 1 in
    /// `lambda`; and beyond the committed range of `lambda` the series is finite.
    #[test]
    fn run_time_coefficients_sum_to_the_committed_series() {
        let c = Coefficients::build(80);
        assert_eq!(c.truncation(), 80);
        for lambda in [0.2, 1.0, 7.0] {
            let want = PairSeries::new(lambda)
                .unwrap()
                .scalars(4.0)
                .unwrap()
                .to_array();
            let got = PairSeries::from_coefficients(&c, lambda, 80)
                .unwrap()
                .scalars(4.0)
                .unwrap()
                .to_array();
            for k in 0..22 {
                // the same terms in the same order but 80 instead of 200 of them: the
                // rest are below 1e-17 of the largest at s' = 4
                let tol = 1e-14 * want[k].abs().max(1.0);
                assert!(
                    (got[k] - want[k]).abs() <= tol,
                    "{} {lambda}: {} {}",
                    NAMES[k],
                    got[k],
                    want[k]
                );
            }
        }
        let far = PairSeries::from_coefficients(&c, 1e4, 80)
            .unwrap()
            .scalars(30.0)
            .unwrap();
        assert!(far.to_array().iter().all(|v| v.is_finite()));
    }
}
