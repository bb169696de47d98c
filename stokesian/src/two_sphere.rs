//! Exact resistance functions of two rigid spheres in unbounded fluid at any separation
//! and size ratio: the twin-multipole series of Jeffrey & Onishi (J. Fluid Mech. 139, 261,
//! 1984, "JO84") for the force-torque level and of Jeffrey (Phys. Fluids A 4, 16, 1992,
//! "J92") for the stresslet level, as corrected by Townsend (Phys. Fluids 35, 127126, 2023;
//! arXiv:1802.08226), summed in the "all separations" form of JO84 (their eqs. 3.17-3.20):
//! the lubrication singularities are carried by closed-form functions of `s'` and only a
//! regular remainder is summed as a power series.
//!
//! This module owns the 22 scalar functions, the JO84/J92 recurrence coefficients (made
//! by `cargo xtask gen` from [`generate_coefficients`] and committed in
//! `src/generated/two_sphere_coefficients.bin`), and the near-contact constants
//! `K(lambda)` derived from them.
//!
//! # Geometry, normalisation and signs
//!
//! Spheres 1 (radius `a1`) and 2 (radius `a2`), centres `r` apart, `d` the unit vector from
//! sphere 1 to sphere 2, `lambda = a2/a1`, `s' = 2r/(a1 + a2)` (JO84's `s`), gap
//! `xi = s' - 2`. Kim & Karrila normalisation (`lubrication.md` 1.3): every "11" and "12"
//! function is scaled with the radius of sphere 1, `A` by `6 pi mu a1`, `B` by
//! `4 pi mu a1^2`, `C` by `8 pi mu a1^3`, `G` by `4 pi mu a1^2`, `H` by `8 pi mu a1^3`, `M`
//! by `(20/3) pi mu a1^3`. (JO84's own "12" functions are scaled with `a1 + a2` instead:
//! `X12A_KK = (1 + lambda)/2 X12A_JO`, `Y12B_KK = (1 + lambda)^2/4 Y12B_JO`, `X12C_KK = (1 +
//! lambda)^3/8 X12C_JO`; at `lambda = 1` the two coincide.)
//!
//! Sign convention (`lubrication.md` 1.2): the force, torque and stresslet exerted by the
//! fluid on sphere 1 are `F1 = A11 (U_inf - U1) + A12 (U_inf - U2) + ...`, with the tensor
//! forms `A_ij = X^A d_i d_j + Y^A (delta_ij - d_i d_j)`, `B_ij = Y^B eps_ijk d_k`, `C` as `A`,
//! `G_ijk = X^G (d_i d_j - delta_ij/3) d_k + Y^G (d_i delta_jk + d_j delta_ik - 2 d_i d_j
//! d_k)`, `H_ijk = Y^H (eps_ikl d_l d_j + eps_jkl d_l d_i)` and `M` with `X^M, Y^M, Z^M`
//! (Kim & Karrila 1991, sec. 7.2). So the "11" functions of `A`, `C`, `M` are positive and
//! tend to 1 as `s' -> infinity`; near contact `X11A ~ 2 lambda^2/((1+lambda)^3 xi)` and
//! `Y11B ~ -lambda (4+lambda)/(5 (1+lambda)^2) ln(1/xi)`. The "21" and "22" functions follow
//! from JO84 eq. 1.9: evaluate the "12"/"11" functions with `lambda -> 1/lambda`, scale with
//! `a2`, and reverse `d` (which flips the sign of the `B` and `G` tensors).
//!
//! # Method
//!
//! With `t = 2/s'`, each function is a power series `F(t) = sum_m a_m t^m` over one parity
//! of `m` (even for `X11A`, odd for `X12A`, odd for `Y11B`, ...), whose coefficients are
//! polynomials in `lambda`:
//!
//! ```text
//! a_m = c sum_{q=0}^{m} R_{k, m-q, q} lambda^q (1 + lambda)^{-m}      (times lambda if m is odd, "shifted")
//! ```
//!
//! `R` is `P`, `Q` of the JO84/J92 recurrences (`k = 1` or 2 the multipole order read off)
//! and `c` a constant: `X^A` `P_1` (JO84 3.15), `X^G` `(3/4) P_2` of the same table (J92
//! eq. 19; Ichiki et al. 2013 eq. 94), `X^M` `P_2` with `P_{n00} = delta_{2n}` (J92 48, shifted),
//! `Y^A` `P_1`, `Y^B` `2 Q_1` (JO84 5.x), `Y^G` `(3/4) P_2` of the same table, `Y^C` `Q_1` with
//! `Q_{n00} = delta_{1n}` (JO84 7.x, shifted), `Y^H` `-(3/8) P_2` of that table (shifted),
//! `Y^M` `P_2` with `P_{n00} = delta_{2n}` (J92 58, shifted), `Z^M` its own recurrence (J92
//! 73-76, shifted) and `X^C` the axisymmetric rotlet recurrence `Q_npq = sum_s C(n+s, n) s/(n+1)
//! Q_{s,q-s-1,p-n}`, `Q_{n00} = delta_{1n}` (JO84 6.x, shifted). The recurrences are those
//! of `lubrication.md` 1.4 and Townsend's corrected list. The "12" function takes the
//! other parity of the same sequence, with the sign of the table below.
//!
//! Near contact (`t -> 1`) each function behaves like `h1/xi + h2 ln(1/xi) + K + h3 xi
//! ln(1/xi) + O(xi)` with the coefficients `g` of `lubrication.md` 1.4 (JO84 3.17-3.20, 4.15,
//! 5.6, 7.10; J92 19b, 27b, 35b, 48b, 64b, 79b as corrected by Townsend). Those three
//! singular terms are represented exactly, for every `t`, by closed forms whose Taylor
//! coefficients are known:
//!
//! ```text
//! even m:  1/(1-t^2) = sum t^m,   -ln(1-t^2) = sum_{m>=2} (2/m) t^m,
//!          -(1-t^2) ln(1-t^2) = t^2 - sum_{m>=4} 4/(m(m-2)) t^m
//! odd m:   t/(1-t^2) = sum t^m,   ln((1+t)/(1-t)) = sum (2/m) t^m,
//!          (1-t^2) ln((1+t)/(1-t)) = 2t - sum_{m>=3} 4/(m(m-2)) t^m
//! ```
//!
//! (each behaves like `1/xi`, `ln(1/xi)`, `xi ln(1/xi)` at contact) so that
//! `F = h1 S1(t) + h2 S2(t) + h3 S3(t) + sum_m r_m t^m` with `r_m = a_m - h1 s1_m - h2
//! s2_m - h3 s3_m`. The remainder is continuous at `t = 1` (its first non-analytic term is
//! `O(xi^2 ln xi)`, so `r_m = O(m^-3)`), hence the truncated series converges uniformly on
//! `0 <= t <= 1`, contact included. (JO84 and Townsend write the constant `K` with
//! `4/(m(m+2))` in place of `4/(m(m-2))`: the two sums agree at `t = 1` only, by telescoping;
//! for `t < 1` the shifted form is the Taylor series of the closed form.) The near-contact
//! constants `K` are `h1 k1 + h2 k2 + sum_m r_m` with `k1 = 3/4` (even) or `1/4` (odd) and `k2
//! = 0` (even) or `2 ln 2` (odd), the limits of `S1 - 1/xi` and `S2 - ln(1/xi)`.
//!
//! # Truncation, cost and accuracy
//!
//! The series are summed to `m <= TRUNCATION` (= 200). The coefficient tables (`P, V, Q`
//! over `n + p + q <= TRUNCATION + 2`) do not depend on `lambda`; the generator evaluates
//! them (about 10 s of CPU for the seven families, ~30 MB transient memory each) and keeps
//! the `O(TRUNCATION^2)` numbers `R_{k, m-q, q}` (11 triangles of 20301 numbers, 1.8 MB),
//! which a process reads on first use (about 2 ms). A [`PairSeries`] for one `lambda`
//! costs 60-95 us (the 11 triangles' rows interleaved and summed side by side as sums
//! of products, `row_sums`); each evaluation at a separation sums the terms that may
//! add more than 1e-17 with every remainder at its bound `REMAINDER_BOUND` (all of
//! them near contact, 37 of 101 rows at `s' = 4`, 16 at `s' = 10`), the 22 Horner sums
//! side by side: 0.27 us on average over `s'` in `[2, 4]`, 0.37 us near contact, no
//! allocation. A series for pairs at `s'` and beyond needs only those terms:
//! [`PairSeries::cached_at`] sums no more (30-37 us at `s' = 4`, 12-16 us at `s' = 10`
//! against 67-76 us for the whole series, test `cost_of_tables_and_calls`), with the
//! same values bit for bit.
//!
//! The neglected remainder is largest at contact. For `lambda` near 1 the remainders
//! oscillate in sign with amplitude `~10-200/m^3` (largest for `M`), so the contact
//! constants `K` are within ~5e-6 (`A`, `B`, `C`) to ~6e-4 (`X^M`) of their limits;
//! `X^C` decays monotonically (`~2.3/m^3`), its truncated tail is 1.5e-5 at contact. For
//! small spheres (`lambda` or `1/lambda` below ~0.1) the coefficients reach their
//! asymptotic decay only for `m >> 1/lambda` and the contact constants are uncertain to
//! ~1e-3 relative; away from contact (`s' >= 2.5`) every function is converged to
//! rounding. There is no switch to the near-contact forms: they share the constants `K`
//! and drop the `O(xi)` terms, so they are nowhere more accurate than the series
//! ([`PairSeries::near_contact`] is provided for comparison). Measured errors: tests
//! `two_sphere_exact.rs`.

use std::collections::HashMap;
use std::f64::consts::LN_2;
use std::sync::OnceLock;
use thiserror::Error;

/// Largest power of `2/s'` summed (and largest total order `p + q` of the recurrence
/// coefficients kept).
pub const TRUNCATION: usize = 200;

/// Smallest supported size ratio `lambda = a2/a1` (the largest is its inverse).
pub const LAMBDA_MIN: f64 = 1e-2;

/// Bad input to the two-sphere functions.
#[derive(Debug, Error, Clone, Copy, PartialEq)]
pub enum TwoSphereError {
    /// `s' = 2r/(a1 + a2)` not finite or not above 2 (touching or overlapping spheres).
    #[error("separation s' = {0} must be finite and > 2 (s' = 2r/(a1+a2); 2 is contact)")]
    Separation(f64),
    /// `lambda = a2/a1` not finite or outside `[LAMBDA_MIN, 1/LAMBDA_MIN]`.
    #[error("size ratio lambda = {0} must be finite and within [1e-2, 1e2]")]
    SizeRatio(f64),
    /// A series summed for far pairs ([`PairSeries::cached_at`]) asked for a closer
    /// separation, which needs terms it does not hold.
    #[error("separation s' = {0} needs terms beyond those this series was summed to (it was summed for a farther pair)")]
    Truncated(f64),
}

/// The ten force-torque resistance functions (Kim & Karrila normalisation, module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FtScalars {
    /// `X^A_11`, per `6 pi mu a1`.
    pub x11a: f64,
    /// `X^A_12`, per `6 pi mu a1`.
    pub x12a: f64,
    /// `Y^A_11`, per `6 pi mu a1`.
    pub y11a: f64,
    /// `Y^A_12`, per `6 pi mu a1`.
    pub y12a: f64,
    /// `Y^B_11`, per `4 pi mu a1^2`.
    pub y11b: f64,
    /// `Y^B_12`, per `4 pi mu a1^2`.
    pub y12b: f64,
    /// `X^C_11`, per `8 pi mu a1^3`.
    pub x11c: f64,
    /// `X^C_12`, per `8 pi mu a1^3`.
    pub x12c: f64,
    /// `Y^C_11`, per `8 pi mu a1^3`.
    pub y11c: f64,
    /// `Y^C_12`, per `8 pi mu a1^3`.
    pub y12c: f64,
}

/// All 22 resistance functions (Kim & Karrila normalisation, module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PairScalars {
    /// `X^A_11`, per `6 pi mu a1`.
    pub x11a: f64,
    /// `X^A_12`, per `6 pi mu a1`.
    pub x12a: f64,
    /// `Y^A_11`, per `6 pi mu a1`.
    pub y11a: f64,
    /// `Y^A_12`, per `6 pi mu a1`.
    pub y12a: f64,
    /// `Y^B_11`, per `4 pi mu a1^2`.
    pub y11b: f64,
    /// `Y^B_12`, per `4 pi mu a1^2`.
    pub y12b: f64,
    /// `X^C_11`, per `8 pi mu a1^3`.
    pub x11c: f64,
    /// `X^C_12`, per `8 pi mu a1^3`.
    pub x12c: f64,
    /// `Y^C_11`, per `8 pi mu a1^3`.
    pub y11c: f64,
    /// `Y^C_12`, per `8 pi mu a1^3`.
    pub y12c: f64,
    /// `X^G_11`, per `4 pi mu a1^2`.
    pub x11g: f64,
    /// `X^G_12`, per `4 pi mu a1^2`.
    pub x12g: f64,
    /// `Y^G_11`, per `4 pi mu a1^2`.
    pub y11g: f64,
    /// `Y^G_12`, per `4 pi mu a1^2`.
    pub y12g: f64,
    /// `Y^H_11`, per `8 pi mu a1^3`.
    pub y11h: f64,
    /// `Y^H_12`, per `8 pi mu a1^3`.
    pub y12h: f64,
    /// `X^M_11`, per `(20/3) pi mu a1^3`.
    pub x11m: f64,
    /// `X^M_12`, per `(20/3) pi mu a1^3`.
    pub x12m: f64,
    /// `Y^M_11`, per `(20/3) pi mu a1^3`.
    pub y11m: f64,
    /// `Y^M_12`, per `(20/3) pi mu a1^3`.
    pub y12m: f64,
    /// `Z^M_11`, per `(20/3) pi mu a1^3`.
    pub z11m: f64,
    /// `Z^M_12`, per `(20/3) pi mu a1^3`.
    pub z12m: f64,
}

impl PairScalars {
    /// The 22 functions in the order of the struct (`x11a, x12a, y11a, ..., z12m`).
    pub fn to_array(&self) -> [f64; 22] {
        [
            self.x11a, self.x12a, self.y11a, self.y12a, self.y11b, self.y12b, self.x11c, self.x12c,
            self.y11c, self.y12c, self.x11g, self.x12g, self.y11g, self.y12g, self.y11h, self.y12h,
            self.x11m, self.x12m, self.y11m, self.y12m, self.z11m, self.z12m,
        ]
    }

    /// The force-torque part.
    pub fn ft(&self) -> FtScalars {
        FtScalars {
            x11a: self.x11a,
            x12a: self.x12a,
            y11a: self.y11a,
            y12a: self.y12a,
            y11b: self.y11b,
            y12b: self.y12b,
            x11c: self.x11c,
            x12c: self.x12c,
            y11c: self.y11c,
            y12c: self.y12c,
        }
    }

    /// The inverse of [`PairScalars::to_array`].
    pub fn from_array(v: [f64; 22]) -> Self {
        let [x11a, x12a, y11a, y12a, y11b, y12b, x11c, x12c, y11c, y12c, x11g, x12g, y11g, y12g, y11h, y12h, x11m, x12m, y11m, y12m, z11m, z12m] =
            v;
        PairScalars {
            x11a,
            x12a,
            y11a,
            y12a,
            y11b,
            y12b,
            x11c,
            x12c,
            y11c,
            y12c,
            x11g,
            x12g,
            y11g,
            y12g,
            y11h,
            y12h,
            x11m,
            x12m,
            y11m,
            y12m,
            z11m,
            z12m,
        }
    }
}

/// Names of the 22 functions in the order of [`PairScalars::to_array`].
pub const NAMES: [&str; 22] = [
    "X11A", "X12A", "Y11A", "Y12A", "Y11B", "Y12B", "X11C", "X12C", "Y11C", "Y12C", "X11G", "X12G",
    "Y11G", "Y12G", "Y11H", "Y12H", "X11M", "X12M", "Y11M", "Y12M", "Z11M", "Z12M",
];

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
    /// level (60-95 us each), then shared. A lubricated Brownian step forms three
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
    /// [`LAMBDA_MIN`] `<= lambda <= 1/LAMBDA_MIN` at the accuracy of the module docs;
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

    /// The near-contact constants `K(lambda)` (`lubrication.md` 1.4, Kim & Karrila
    /// normalisation): the `O(1)` terms of `F = h1/xi + h2 ln(1/xi) + K + h3 xi ln(1/xi) +
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

    /// The near-contact forms `h1/xi + h2 ln(1/xi) + K + h3 xi ln(1/xi)` (error `O(xi)`) with
    /// the coefficients of `lubrication.md` 1.4 and `K` from [`Self::contact_constants`];
    /// for comparison with the literature: never more accurate than [`Self::scalars`],
    /// which keeps the `O(xi)` terms and shares the constants.
    pub fn near_contact(&self, s_dash: f64) -> Result<PairScalars, TwoSphereError> {
        let geo = Geometry::new(s_dash)?;
        let xi = geo.xi;
        let l = -xi.ln();
        let k = self.contact_constants().to_array();
        let mut out = [0.0; 22];
        for j in 0..self.count {
            let h = self.singular[j];
            out[j] = h[0] / xi + h[1] * l + k[j] + h[2] * xi * l;
        }
        Ok(PairScalars::from_array(out))
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

/// The singular parts `h . S(t)` of the first `count` functions (module docs: the closed
/// forms carrying `1/xi`, `ln(1/xi)` and `xi ln(1/xi)` exactly, times the coefficients of
/// `lambda`) at `s_dash > 2`; the others zero. With [`PairSeries::regular`] they add up to
/// [`PairSeries::scalars`], bit for bit.
pub fn singular_parts(s_dash: f64, lambda: f64, count: usize) -> Result<[f64; 22], TwoSphereError> {
    check_lambda(lambda)?;
    SingularForms::new(s_dash)?.parts(lambda, count)
}

/// The closed forms carrying the singular terms (module docs) at one separation, for the
/// functions at any size ratio: the two spheres of a pair see the same separation and
/// inverse ratios, and share these (three logarithms).
pub struct SingularForms(Geometry);

impl SingularForms {
    /// The closed forms at `s_dash > 2`.
    pub fn new(s_dash: f64) -> Result<Self, TwoSphereError> {
        Geometry::new(s_dash).map(SingularForms)
    }

    /// `ln xi = ln(s' - 2)`.
    pub fn ln_gap(&self) -> f64 {
        self.0.ln_xi
    }

    /// [`singular_parts`] at `lambda`: the same numbers, bit for bit.
    pub fn parts(&self, lambda: f64, count: usize) -> Result<[f64; 22], TwoSphereError> {
        check_lambda(lambda)?;
        Ok(self.sums(count, |k| (FUNCTIONS[k].singular)(lambda)))
    }

    /// [`SingularForms::parts`] from the coefficients of [`singular_coefficients`],
    /// computed once for a size ratio: the same numbers, bit for bit.
    pub fn parts_from(&self, coefficients: &[[f64; 3]; 22], count: usize) -> [f64; 22] {
        self.sums(count, |k| coefficients[k])
    }

    /// `h . S(t)` of the first `count` functions, `h` of function `k` from
    /// `coefficient(k)`; the others zero.
    fn sums(&self, count: usize, coefficient: impl Fn(usize) -> [f64; 3]) -> [f64; 22] {
        std::array::from_fn(|k| {
            if k < count {
                singular_part(k, &coefficient(k), &self.0)
            } else {
                0.0
            }
        })
    }
}

/// `h . S(t)` of function `k`.
#[inline]
fn singular_part(k: usize, h: &[f64; 3], geo: &Geometry) -> f64 {
    let closed = if FUNCTIONS[k].odd { geo.odd } else { geo.even };
    h[0] * closed[0] + h[1] * closed[1] + h[2] * closed[2]
}

/// The singular coefficients `[h1, h2, h3]` of each function near contact (`1/xi`,
/// `ln(1/xi)`, `xi ln(1/xi)`), `lubrication.md` 1.4, in the order of [`NAMES`].
pub fn singular_coefficients(lambda: f64) -> Result<[[f64; 3]; 22], TwoSphereError> {
    check_lambda(lambda)?;
    let mut out = [[0.0; 3]; 22];
    for (k, f) in FUNCTIONS.iter().enumerate() {
        out[k] = (f.singular)(lambda);
    }
    Ok(out)
}

fn check_lambda(lambda: f64) -> Result<(), TwoSphereError> {
    if lambda.is_finite() && (LAMBDA_MIN..=1.0 / LAMBDA_MIN).contains(&lambda) {
        Ok(())
    } else {
        Err(TwoSphereError::SizeRatio(lambda))
    }
}

// ------------------------------------------------------------------ geometry and closed forms

/// `t = 2/s'` and the closed-form singular functions, written in `xi = s' - 2` so that
/// nothing cancels near contact: `1 - t^2 = xi (4 + xi)/(2 + xi)^2`.
struct Geometry {
    xi: f64,
    /// `ln xi`
    ln_xi: f64,
    t: f64,
    /// `[1/(1-t^2), -ln(1-t^2), -(1-t^2) ln(1-t^2)]`
    even: [f64; 3],
    /// `[t/(1-t^2), ln((1+t)/(1-t)), (1-t^2) ln((1+t)/(1-t))]`
    odd: [f64; 3],
}

impl Geometry {
    fn new(s_dash: f64) -> Result<Self, TwoSphereError> {
        if !(s_dash.is_finite() && s_dash > 2.0) {
            return Err(TwoSphereError::Separation(s_dash));
        }
        let xi = s_dash - 2.0; // exact for s' in (2, 4] (Sterbenz)
        let t = 2.0 / s_dash;
        let one_m_t2 = xi * (4.0 + xi) / (s_dash * s_dash);
        let (ln_xi, ln_4_xi) = (xi.ln(), (4.0 + xi).ln());
        let mln = -(ln_xi + ln_4_xi - 2.0 * s_dash.ln()); // -ln(1 - t^2)
        let lnr = ln_4_xi - ln_xi; // ln((1+t)/(1-t)) = ln((s'+2)/(s'-2))
        Ok(Geometry {
            xi,
            ln_xi,
            t,
            even: [1.0 / one_m_t2, mln, one_m_t2 * mln],
            odd: [t / one_m_t2, lnr, one_m_t2 * lnr],
        })
    }
}

/// Taylor coefficient of `t^m` in the closed forms (index 0, 1, 2 as in [`Geometry`]).
fn singular_taylor(parity_odd: bool, m: usize) -> [f64; 3] {
    let mf = m as f64;
    if parity_odd {
        let s3 = if m == 1 {
            2.0
        } else {
            -4.0 / (mf * (mf - 2.0))
        };
        [1.0, 2.0 / mf, s3]
    } else if m == 0 {
        [1.0, 0.0, 0.0]
    } else {
        let s3 = if m == 2 {
            1.0
        } else {
            -4.0 / (mf * (mf - 2.0))
        };
        [1.0, 2.0 / mf, s3]
    }
}

// ------------------------------------------------------------------ recurrences

/// The recurrence families of JO84/J92.
#[derive(Clone, Copy)]
enum Recurrence {
    /// Motion along the line of centres (JO84 3.6-3.9, `lubrication.md` 1.4 "X^A"):
    /// `P`, `V`, binomial `C(n+s, n)`.
    Axisymmetric,
    /// Motion across it (JO84 4.6-4.11, "Y^A/Y^B/Y^C"): `P`, `V`, `Q`, `C(n+s, n+1)`.
    Transverse,
    /// The `Z^M` mode (J92 73-76): `P`, `V`, `Q`, `C(n+s, n+2)`, `s >= 2`.
    Twist,
    /// Rotation about the line of centres (JO84 sec. 6): rotlets only, `Q`, `C(n+s, n)`.
    AxialRotation,
}

/// A family: recurrence, initial conditions (`P_{n00} = V_{n00} = delta_{pv n}`, `Q_{n00}
/// = delta_{q n}`; 0 for none) and which coefficients are read off.
struct Family {
    rec: Recurrence,
    init_pv: usize,
    init_q: usize,
    /// `(use Q rather than P, n)` for each output sequence
    outputs: &'static [(bool, usize)],
}

/// Output of one family: for each requested sequence the triangle `R_{n, m-q, q}`, `0 <= q
/// <= m <= TRUNCATION`, stored row by row (`m (m+1)/2 + q`).
type Triangles = Vec<Vec<f64>>;

fn tri(m: usize, q: usize) -> usize {
    m * (m + 1) / 2 + q
}

/// Flat storage of `(n, p, q)`, `n >= 1`, `p, q >= 0`, `n + p + q <= top`, ordered by `q`,
/// then `n + p`, then `n`: the recurrences read, for one coefficient, the children
/// `(s, sigma - s, r)` at fixed `sigma` and `r` for consecutive `s`, which this order
/// makes adjacent in memory (in `(n, p, q)` order every child was a cache miss, and
/// building took several times longer).
struct Tetra {
    top: usize,
    off: Vec<usize>,
    len: usize,
}

impl Tetra {
    fn new(top: usize) -> Self {
        let w = top + 1;
        let mut off = vec![usize::MAX; w * w];
        let mut len = 0;
        for q in 0..top {
            for sigma in 1..=(top - q) {
                off[q * w + sigma] = len;
                len += sigma; // n = 1..=sigma
            }
        }
        Tetra { top, off, len }
    }

    /// Index of `(n, p, q)`, or `None` when `p` or `q` is negative (those coefficients are
    /// zero). Callers only ask for totals below the current one, so the index exists.
    #[inline]
    fn at(&self, n: usize, p: i64, q: i64) -> Option<usize> {
        if p < 0 || q < 0 {
            None
        } else {
            Some(self.off[q as usize * (self.top + 1) + n + p as usize] + n - 1)
        }
    }
}

fn binomials(nmax: usize) -> Vec<Vec<f64>> {
    let mut b = vec![vec![0.0; nmax + 1]; nmax + 1];
    for n in 0..=nmax {
        b[n][0] = 1.0;
        for k in 1..=n {
            b[n][k] = b[n - 1][k - 1] + if k < n { b[n - 1][k] } else { 0.0 };
        }
    }
    b
}

/// Builds the `P, V, Q` tables of one family up to total order `truncation + 2` and
/// extracts the requested triangles.
fn build(family: &Family, truncation: usize) -> Triangles {
    let top = truncation + 2; // n = 2 outputs need n + m <= top
    let tet = Tetra::new(top);
    let binom = binomials(2 * top + 2);
    let mut p_t = vec![0.0; tet.len];
    let mut v_t = vec![0.0; tet.len];
    let mut q_t = vec![0.0; tet.len];
    let get = |v: &Vec<f64>, n: usize, p: i64, q: i64| tet.at(n, p, q).map_or(0.0, |i| v[i]);
    // The recurrence coefficients depend on (n, s) only: tabulated once (the divisions
    // would otherwise dominate the innermost loop).
    let w = top + 2;
    let table = |f: &dyn Fn(f64, f64) -> f64| -> Vec<f64> {
        (0..w * w)
            .map(|i| {
                let (n, s) = (i / w, i % w);
                if n == 0 || s == 0 {
                    0.0
                } else {
                    f(n as f64, s as f64)
                }
            })
            .collect()
    };
    let coef: Vec<Vec<f64>> = match family.rec {
        Recurrence::Axisymmetric => vec![
            table(&|nf, sf| {
                nf * (2.0 * nf + 1.0) * (2.0 * nf * sf - nf - sf + 2.0)
                    / (2.0 * (nf + 1.0) * (2.0 * sf - 1.0) * (nf + sf))
            }),
            table(&|nf, _| nf * (2.0 * nf - 1.0) / (2.0 * (nf + 1.0))),
            table(&|nf, sf| nf * (4.0 * nf * nf - 1.0) / (2.0 * (nf + 1.0) * (2.0 * sf + 1.0))),
        ],
        Recurrence::Transverse => vec![
            table(&|nf, sf| {
                (2.0 * nf + 1.0) / (2.0 * (nf + 1.0))
                    * (3.0 * (nf + sf) - (nf * sf + 1.0) * (2.0 * nf * sf - sf - nf + 2.0))
                    / (sf * (nf + sf) * (2.0 * sf - 1.0))
            }),
            table(&|nf, _| nf * (2.0 * nf - 1.0) / (2.0 * (nf + 1.0))),
            table(&|nf, sf| nf * (4.0 * nf * nf - 1.0) / (2.0 * (nf + 1.0) * (2.0 * sf + 1.0))),
            table(&|nf, _| 2.0 * (4.0 * nf * nf - 1.0) / (3.0 * (nf + 1.0))),
            table(&|nf, sf| sf / (nf + 1.0)),
            table(&|nf, sf| 3.0 / (2.0 * nf * sf * (nf + 1.0))),
        ],
        Recurrence::Twist => vec![
            table(&|nf, _| 2.0 * (2.0 * nf + 1.0) * (2.0 * nf - 1.0) / (nf + 1.0)),
            table(&|nf, sf| {
                nf * (2.0 * nf + 1.0) * (2.0 * nf - 1.0) / (2.0 * (nf + 1.0) * (2.0 * sf + 1.0))
            }),
            table(&|nf, sf| {
                (2.0 * nf + 1.0) / (nf + 1.0)
                    * (nf * sf * (nf + sf - 2.0 * nf * sf - 2.0)
                        - 4.0 * (2.0 * nf * sf - 4.0 * sf - 4.0 * nf + 2.0))
                    / (2.0 * sf * (nf + sf) * (2.0 * sf - 1.0))
            }),
            table(&|nf, _| nf * (2.0 * nf - 1.0) / (2.0 * (nf + 1.0))),
            table(&|nf, sf| sf / (nf + 1.0)),
            table(&|nf, sf| 2.0 / (nf * sf * (nf + 1.0))),
        ],
        Recurrence::AxialRotation => vec![table(&|nf, sf| sf / (nf + 1.0))],
    };
    for total in 1..=top {
        for n in 1..=total {
            let nf = n as f64;
            for p in 0..=(total - n) {
                let q = total - n - p;
                let idx = tet.at(n, p as i64, q as i64).expect("in range");
                if p == 0 && q == 0 {
                    p_t[idx] = if n == family.init_pv { 1.0 } else { 0.0 };
                    v_t[idx] = p_t[idx];
                    q_t[idx] = if n == family.init_q { 1.0 } else { 0.0 };
                    continue;
                }
                // Structural zeros: every term of P_npq, V_npq needs p >= n - 1 and every
                // term of Q_npq needs p >= n (the third index of each child is p - n + 1,
                // p - n or p - n - 1), unless it is an initial value (n, 0, 0).
                if p + 1 < n {
                    continue;
                }
                let (pi, qi, ni) = (p as i64, q as i64, n as i64);
                let (mut ps, mut vs, mut qs) = (0.0, 0.0, 0.0);
                // By the same rule a child (s, q - s - k, .) vanishes unless q - s - k >= s - 1
                // or it is the initial value (s = q - k); so s runs over 1..=(q+1)/2 and the
                // last three values.
                let s_low = q.div_ceil(2).min(q);
                let s_range = (1..=s_low).chain((q.saturating_sub(2).max(s_low + 1))..=q);
                match family.rec {
                    Recurrence::Axisymmetric => {
                        for s in s_range.clone() {
                            let si = s as i64;
                            let b = binom[n + s][n];
                            let k = n * w + s;
                            let (c1, c2, c3) = (coef[0][k], coef[1][k], coef[2][k]);
                            let pm = get(&p_t, s, qi - si, pi - ni - 1);
                            ps += b
                                * (c1 * get(&p_t, s, qi - si, pi - ni + 1)
                                    - c2 * pm
                                    - c3 * get(&v_t, s, qi - si - 2, pi - ni + 1));
                            vs += b * pm;
                        }
                        p_t[idx] = ps;
                        v_t[idx] = ps - 2.0 * nf / ((nf + 1.0) * (2.0 * nf + 3.0)) * vs;
                    }
                    Recurrence::Transverse => {
                        for s in s_range.clone() {
                            let si = s as i64;
                            let b = binom[n + s][n + 1];
                            let k = n * w + s;
                            let (c1, c2, c3, c4) = (coef[0][k], coef[1][k], coef[2][k], coef[3][k]);
                            let pm = get(&p_t, s, qi - si, pi - ni - 1);
                            ps += b
                                * (c1 * get(&p_t, s, qi - si, pi - ni + 1)
                                    + c2 * pm
                                    + c3 * get(&v_t, s, qi - si - 2, pi - ni + 1)
                                    - c4 * get(&q_t, s, qi - si - 1, pi - ni + 1));
                            qs += b
                                * (coef[4][k] * get(&q_t, s, qi - si - 1, pi - ni)
                                    - coef[5][k] * get(&p_t, s, qi - si, pi - ni));
                            vs += b * pm;
                        }
                        p_t[idx] = ps;
                        q_t[idx] = qs;
                        v_t[idx] = ps + 2.0 * nf / ((nf + 1.0) * (2.0 * nf + 3.0)) * vs;
                    }
                    Recurrence::Twist => {
                        for s in s_range.clone().filter(|&s| s >= 2) {
                            let si = s as i64;
                            let b = binom[n + s][n + 2];
                            let k = n * w + s;
                            let (c_q, c_v, c_p, c_m) =
                                (coef[0][k], coef[1][k], coef[2][k], coef[3][k]);
                            let pm = get(&p_t, s, qi - si, pi - ni - 1);
                            ps += b
                                * (-c_q * get(&q_t, s, qi - si - 1, pi - ni + 1)
                                    + c_v * get(&v_t, s, qi - si - 2, pi - ni + 1)
                                    + c_p * get(&p_t, s, qi - si, pi - ni + 1)
                                    + c_m * pm);
                            qs += b
                                * (coef[4][k] * get(&q_t, s, qi - si - 1, pi - ni)
                                    - coef[5][k] * get(&p_t, s, qi - si, pi - ni));
                            vs += b * pm;
                        }
                        p_t[idx] = ps;
                        q_t[idx] = qs;
                        v_t[idx] = ps + 2.0 * nf / ((nf + 1.0) * (2.0 * nf + 3.0)) * vs;
                    }
                    Recurrence::AxialRotation => {
                        for s in s_range.clone() {
                            let si = s as i64;
                            qs += binom[n + s][n]
                                * coef[0][n * w + s]
                                * get(&q_t, s, qi - si - 1, pi - ni);
                        }
                        q_t[idx] = qs;
                    }
                }
            }
        }
    }
    family
        .outputs
        .iter()
        .map(|&(use_q, n)| {
            let src = if use_q { &q_t } else { &p_t };
            let mut out = vec![0.0; tri(truncation, truncation) + 1];
            for m in 0..=truncation {
                for q in 0..=m {
                    out[tri(m, q)] = src[tet.at(n, (m - q) as i64, q as i64).expect("in range")];
                }
            }
            out
        })
        .collect()
}

static XA: Family = Family {
    rec: Recurrence::Axisymmetric,
    init_pv: 1,
    init_q: 0,
    outputs: &[(false, 1), (false, 2)],
};
static XM: Family = Family {
    rec: Recurrence::Axisymmetric,
    init_pv: 2,
    init_q: 0,
    outputs: &[(false, 2)],
};
static YA: Family = Family {
    rec: Recurrence::Transverse,
    init_pv: 1,
    init_q: 0,
    outputs: &[(false, 1), (true, 1), (false, 2)],
};
static YC: Family = Family {
    rec: Recurrence::Transverse,
    init_pv: 0,
    init_q: 1,
    outputs: &[(true, 1), (false, 2)],
};
static YM: Family = Family {
    rec: Recurrence::Transverse,
    init_pv: 2,
    init_q: 0,
    outputs: &[(false, 2)],
};
static ZM: Family = Family {
    rec: Recurrence::Twist,
    init_pv: 2,
    init_q: 0,
    outputs: &[(false, 2)],
};
static XC: Family = Family {
    rec: Recurrence::AxialRotation,
    init_pv: 0,
    init_q: 1,
    outputs: &[(true, 1)],
};

/// The recurrence coefficients of every family, as written by `cargo xtask gen` from
/// [`generate_coefficients`]: the triangles `R_{n, m-q, q}` (`0 <= q <= m <=
/// TRUNCATION`, row by row) of each family's outputs, families in the order of
/// [`Table::ALL`], little-endian `f64`. They do not depend on `lambda`; `gen --check`
/// fails when this file differs from a fresh evaluation of the recurrences.
static COEFFICIENTS: &[u8; 11 * TRIANGLE * 8] =
    include_bytes!("generated/two_sphere_coefficients.bin");

/// Numbers in one triangle.
const TRIANGLE: usize = TRUNCATION * (TRUNCATION + 1) / 2 + TRUNCATION + 1;

/// Each family's triangles once read, indexed by `Table as usize`.
static TRIANGLES: [OnceLock<Triangles>; 7] = [const { OnceLock::new() }; 7];

#[derive(Clone, Copy, PartialEq)]
enum Table {
    Xa,
    Xm,
    Ya,
    Yc,
    Ym,
    Zm,
    Xc,
}

impl Table {
    /// The order of the families in [`COEFFICIENTS`] (that of the declaration, which
    /// `Table as usize` follows).
    const ALL: [Table; 7] = [
        Table::Xa,
        Table::Xm,
        Table::Ya,
        Table::Yc,
        Table::Ym,
        Table::Zm,
        Table::Xc,
    ];

    fn family(self) -> &'static Family {
        match self {
            Table::Xa => &XA,
            Table::Xm => &XM,
            Table::Ya => &YA,
            Table::Yc => &YC,
            Table::Ym => &YM,
            Table::Zm => &ZM,
            Table::Xc => &XC,
        }
    }

    /// The family's triangles, read from [`COEFFICIENTS`] on first use (a copy of
    /// about 160 kB per triangle, no arithmetic).
    fn triangles(self) -> &'static Triangles {
        TRIANGLES[self as usize].get_or_init(|| {
            let before: usize = Table::ALL
                .iter()
                .take_while(|&&t| t != self)
                .map(|t| t.family().outputs.len())
                .sum();
            (0..self.family().outputs.len())
                .map(|k| {
                    let start = (before + k) * TRIANGLE * 8;
                    COEFFICIENTS[start..start + TRIANGLE * 8]
                        .chunks_exact(8)
                        .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
                        .collect()
                })
                .collect()
        })
    }
}

/// The recurrence coefficients of every family to a chosen truncation, built at run time
/// (for [`PairSeries::from_coefficients`]; the library itself reads the committed ones,
/// [`TRUNCATION`]). Building costs `O(truncation^4)`: about 10 s of CPU at 200 terms,
/// a minute at 400, and memory `O(truncation^3)` while it runs.
pub struct Coefficients {
    truncation: usize,
    /// Indexed by `Table as usize`.
    triangles: Vec<Triangles>,
}

impl Coefficients {
    /// The recurrences of every family evaluated to `m <= truncation` (one thread per
    /// family: not rayon's pool, which the other generators of `cargo xtask gen` share).
    pub fn build(truncation: usize) -> Self {
        let triangles = std::thread::scope(|scope| {
            let jobs: Vec<_> = Table::ALL
                .iter()
                .map(|t| scope.spawn(move || build(t.family(), truncation)))
                .collect();
            jobs.into_iter()
                .map(|j| j.join().expect("the recurrences do not panic"))
                .collect()
        });
        Coefficients {
            truncation,
            triangles,
        }
    }

    /// The largest power of `2/s'` the coefficients reach.
    pub fn truncation(&self) -> usize {
        self.truncation
    }
}

/// The contents of `src/generated/two_sphere_coefficients.bin` (`COEFFICIENTS`): the
/// recurrences of every family evaluated to [`TRUNCATION`] ([`Coefficients::build`]).
pub fn generate_coefficients() -> Vec<u8> {
    Coefficients::build(TRUNCATION)
        .triangles
        .iter()
        .flatten()
        .flat_map(|tri| tri.iter().flat_map(|v| v.to_le_bytes()))
        .collect()
}

// ------------------------------------------------------------------ the 22 functions

/// One scalar function: `F = sign c sum_{m of parity} a_m t^m`, `a_m = sum_q R_{m-q,q}
/// lambda^q (1+lambda)^{-m}` (times `lambda` for odd `m` when `shifted`).
struct Function {
    table: Table,
    /// index of the triangle in the family's outputs
    output: usize,
    /// constant `c` including the sign of the function
    factor: f64,
    shifted: bool,
    odd: bool,
    /// `[h1, h2, h3]`: coefficients of `1/xi`, `ln(1/xi)`, `xi ln(1/xi)` near contact
    singular: fn(f64) -> [f64; 3],
}

/// The distinct triangles of [`FUNCTIONS`]: each "11" function shares its triangle with
/// the "12" function of the other parity, so function `k` reads triangle `k / 2`.
const SOURCES: usize = 11;

/// The triangles of the ten force-torque functions (`x11a` to `y12c`): the first five.
const FT_SOURCES: usize = 5;

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

impl Function {
    /// `a_m` for this `lambda` (the factor included) from the sum of its triangle's row
    /// `m` by [`row_sums`] and `power`: `nu^m sum R_q lambda^q` for `lambda <= 1`, and
    /// `mu^m sum R_q lambda^{q-m}` otherwise, `mu = lambda/(1+lambda)`, `nu = 1/(1+lambda)`
    /// (`power` is `nu^m` or `mu^m`).
    #[inline]
    fn coefficient(&self, sum: f64, power: f64, lambda: f64, m: usize) -> f64 {
        let shift = if self.shifted && m % 2 == 1 {
            lambda
        } else {
            1.0
        };
        self.factor * (sum * power) * shift
    }
}

fn cube(l: f64) -> f64 {
    (1.0 + l).powi(3)
}
fn square(l: f64) -> f64 {
    (1.0 + l).powi(2)
}

// Singular coefficients, lubrication.md 1.4 (JO84; J92; corrected by Townsend 2023).
fn s_x11a(l: f64) -> [f64; 3] {
    let inv = 1.0 / cube(l);
    [
        2.0 * l * l * inv,
        l * (1.0 + 7.0 * l + l * l) * inv * (1.0 / 5.0),
        (1.0 + 18.0 * l - 29.0 * l * l + 18.0 * l.powi(3) + l.powi(4)) * inv * (1.0 / 42.0),
    ]
}
fn s_x12a(l: f64) -> [f64; 3] {
    neg(s_x11a(l))
}
fn s_y11a(l: f64) -> [f64; 3] {
    let inv = 1.0 / cube(l);
    [
        0.0,
        4.0 * l * (2.0 + l + 2.0 * l * l) * inv * (1.0 / 15.0),
        2.0 * (16.0 - 45.0 * l + 58.0 * l * l - 45.0 * l.powi(3) + 16.0 * l.powi(4))
            * inv
            * (1.0 / 375.0),
    ]
}
fn s_y12a(l: f64) -> [f64; 3] {
    neg(s_y11a(l))
}
fn s_y11b(l: f64) -> [f64; 3] {
    let inv = 1.0 / square(l);
    [
        0.0,
        -l * (4.0 + l) * inv * (1.0 / 5.0),
        -(32.0 - 33.0 * l + 83.0 * l * l + 43.0 * l.powi(3)) * inv * (1.0 / 250.0),
    ]
}
fn s_y12b(l: f64) -> [f64; 3] {
    neg(s_y11b(l))
}
fn s_x11c(l: f64) -> [f64; 3] {
    let inv = 1.0 / (1.0 + l);
    [0.0, 0.0, -l * l * inv * (1.0 / 4.0)]
}
fn s_x12c(l: f64) -> [f64; 3] {
    neg(s_x11c(l))
}
fn s_y11c(l: f64) -> [f64; 3] {
    let inv = 1.0 / (1.0 + l);
    [
        0.0,
        2.0 * l * inv * (1.0 / 5.0),
        (8.0 + 6.0 * l + 33.0 * l * l) * inv * (1.0 / 125.0),
    ]
}
fn s_y12c(l: f64) -> [f64; 3] {
    let inv = 1.0 / (1.0 + l);
    [
        0.0,
        l * l * inv * (1.0 / 10.0),
        l * (43.0 - 24.0 * l + 43.0 * l * l) * inv * (1.0 / 500.0),
    ]
}
fn s_x11g(l: f64) -> [f64; 3] {
    let inv = 1.0 / cube(l);
    [
        3.0 * l * l * inv,
        3.0 * (l + 12.0 * l * l - 4.0 * l.powi(3)) * inv * (1.0 / 10.0),
        (5.0 + 181.0 * l - 453.0 * l * l + 566.0 * l.powi(3) - 65.0 * l.powi(4))
            * inv
            * (1.0 / 140.0),
    ]
}
fn s_x12g(l: f64) -> [f64; 3] {
    neg(s_x11g(l))
}
fn s_y11g(l: f64) -> [f64; 3] {
    let inv = 1.0 / cube(l);
    [
        0.0,
        (4.0 * l - l * l + 7.0 * l.powi(3)) * inv * (1.0 / 10.0),
        (32.0 - 179.0 * l + 532.0 * l * l - 356.0 * l.powi(3) + 221.0 * l.powi(4))
            * inv
            * (1.0 / 500.0),
    ]
}
fn s_y12g(l: f64) -> [f64; 3] {
    neg(s_y11g(l))
}
fn s_y11h(l: f64) -> [f64; 3] {
    let inv = 1.0 / square(l);
    [
        0.0,
        (2.0 * l - l * l) * inv * (1.0 / 10.0),
        (16.0 - 61.0 * l + 180.0 * l * l + 2.0 * l.powi(3)) * inv * (1.0 / 500.0),
    ]
}
fn s_y12h(l: f64) -> [f64; 3] {
    let inv = 1.0 / square(l);
    [
        0.0,
        (l * l + 7.0 * l.powi(3)) * inv * (1.0 / 20.0),
        (43.0 * l + 147.0 * l * l - 185.0 * l.powi(3) + 221.0 * l.powi(4)) * inv * (1.0 / 1000.0),
    ]
}
fn s_x11m(l: f64) -> [f64; 3] {
    let inv = 1.0 / cube(l);
    [
        6.0 * l * l * inv * (1.0 / 5.0),
        3.0 * (l + 17.0 * l * l - 9.0 * l.powi(3)) * inv * (1.0 / 25.0),
        (5.0 + 272.0 * l - 831.0 * l * l + 1322.0 * l.powi(3) - 415.0 * l.powi(4))
            * inv
            * (1.0 / 350.0),
    ]
}
fn s_x12m(l: f64) -> [f64; 3] {
    let inv = 1.0 / cube(l);
    [
        6.0 * l.powi(3) * inv * (1.0 / 5.0),
        3.0 * (-4.0 * l * l + 17.0 * l.powi(3) - 4.0 * l.powi(4)) * inv * (1.0 / 25.0),
        (-65.0 * l + 832.0 * l * l - 1041.0 * l.powi(3) + 832.0 * l.powi(4) - 65.0 * l.powi(5))
            * inv
            * (1.0 / 350.0),
    ]
}
fn s_y11m(l: f64) -> [f64; 3] {
    let inv = 1.0 / cube(l);
    [
        0.0,
        6.0 * (l - l * l + 4.0 * l.powi(3)) * inv * (1.0 / 25.0),
        (24.0 - 201.0 * l + 882.0 * l * l - 1182.0 * l.powi(3) + 591.0 * l.powi(4))
            * inv
            * (1.0 / 625.0),
    ]
}
fn s_y12m(l: f64) -> [f64; 3] {
    let inv = 1.0 / cube(l);
    [
        0.0,
        3.0 * (7.0 * l * l - 10.0 * l.powi(3) + 7.0 * l.powi(4)) * inv * (1.0 / 50.0),
        3.0 * l
            * (221.0 - 728.0 * l + 1902.0 * l * l - 728.0 * l.powi(3) + 221.0 * l.powi(4))
            * inv
            * (1.0 / 2500.0),
    ]
}
fn s_z11m(l: f64) -> [f64; 3] {
    let inv = 1.0 / cube(l);
    [0.0, 0.0, -3.0 * (l * l + l.powi(4)) * inv * (1.0 / 10.0)]
}
fn s_z12m(l: f64) -> [f64; 3] {
    neg(s_z11m(l))
}
fn neg(h: [f64; 3]) -> [f64; 3] {
    [-h[0], -h[1], -h[2]]
}

macro_rules! function {
    ($table:ident, $out:expr, $factor:expr, $shifted:expr, $odd:expr, $sing:ident) => {
        Function {
            table: Table::$table,
            output: $out,
            factor: $factor,
            shifted: $shifted,
            odd: $odd,
            singular: $sing,
        }
    };
}

/// The 22 functions in the order of [`NAMES`]. The "11" function takes one parity of a
/// sequence, the "12" function the other, with the sign of JO84/J92 (module docs).
static FUNCTIONS: [Function; 22] = [
    function!(Xa, 0, 1.0, false, false, s_x11a),
    function!(Xa, 0, -1.0, false, true, s_x12a),
    function!(Ya, 0, 1.0, false, false, s_y11a),
    function!(Ya, 0, -1.0, false, true, s_y12a),
    function!(Ya, 1, 2.0, false, true, s_y11b),
    function!(Ya, 1, -2.0, false, false, s_y12b),
    function!(Xc, 0, 1.0, true, false, s_x11c),
    function!(Xc, 0, -1.0, true, true, s_x12c),
    function!(Yc, 0, 1.0, true, false, s_y11c),
    function!(Yc, 0, 1.0, true, true, s_y12c),
    function!(Xa, 1, 0.75, false, true, s_x11g),
    function!(Xa, 1, -0.75, false, false, s_x12g),
    function!(Ya, 2, 0.75, false, true, s_y11g),
    function!(Ya, 2, -0.75, false, false, s_y12g),
    function!(Yc, 1, -0.375, true, false, s_y11h),
    function!(Yc, 1, -0.375, true, true, s_y12h),
    function!(Xm, 0, 1.0, true, false, s_x11m),
    function!(Xm, 0, 1.0, true, true, s_x12m),
    function!(Ym, 0, 1.0, true, false, s_y11m),
    function!(Ym, 0, 1.0, true, true, s_y12m),
    function!(Zm, 0, 1.0, true, false, s_z11m),
    function!(Zm, 0, -1.0, true, true, s_z12m),
];

#[cfg(test)]
mod tests {
    use super::*;

    /// `TRIANGLES` is indexed by `Table as usize`, `COEFFICIENTS` ordered by `Table::ALL`.
    #[test]
    fn table_order_is_the_declaration_order() {
        assert!(Table::ALL.iter().enumerate().all(|(i, &t)| t as usize == i));
    }

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
