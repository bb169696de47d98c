//! Exact resistance functions of two rigid spheres in unbounded fluid at any separation
//! and size ratio: the twin-multipole series of Jeffrey & Onishi (J. Fluid Mech. 139, 261,
//! 1984, "JO84") for the force-torque level and of Jeffrey (Phys. Fluids A 4, 16, 1992,
//! "J92") for the stresslet level, as corrected by Townsend (Phys. Fluids 35, 127126, 2023;
//! arXiv:1802.08226), summed in the "all separations" form of JO84 (their eqs. 3.17-3.20):
//! the lubrication singularities are carried by closed-form functions of `s'` and only a
//! regular remainder is summed as a power series.
//!
//! This module owns the 22 scalar functions, the JO84/J92 recurrence coefficients (made
//! by `cargo xtask gen` from [`crate::generate::two_sphere_coefficients`] and committed in
//! `src/generated/two_sphere_coefficients.bin`), and the near-contact constants
//! `K(lambda)` derived from them.
//!
//! # Geometry, normalisation and signs
//!
//! Spheres 1 (radius `a1`) and 2 (radius `a2`), centres `r` apart, `d` the unit vector from
//! sphere 1 to sphere 2, `lambda = a2/a1`, `s' = 2r/(a1 + a2)` (JO84's `s`), gap
//! `xi = s' - 2`. Kim & Karrila normalisation (Kim & Karrila 1991; JO84 eq. 1.7): every "11" and "12"
//! function is scaled with the radius of sphere 1, `A` by `6 pi mu a1`, `B` by
//! `4 pi mu a1^2`, `C` by `8 pi mu a1^3`, `G` by `4 pi mu a1^2`, `H` by `8 pi mu a1^3`, `M`
//! by `(20/3) pi mu a1^3`. (JO84's own "12" functions are scaled with `a1 + a2` instead:
//! `X12A_KK = (1 + lambda)/2 X12A_JO`, `Y12B_KK = (1 + lambda)^2/4 Y12B_JO`, `X12C_KK = (1 +
//! lambda)^3/8 X12C_JO`; at `lambda = 1` the two coincide.)
//!
//! Sign convention (Kim & Karrila 1991, sec. 7.2): the force, torque and stresslet exerted by the
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
//! of JO84 and J92 as corrected by Townsend (2023). The "12" function takes the
//! other parity of the same sequence, with the sign of the table below.
//!
//! Near contact (`t -> 1`) each function behaves like `h1/xi + h2 ln(1/xi) + K + h3 xi
//! ln(1/xi) + O(xi)` with the coefficients `g` of JO84 3.17-3.20, 4.15,
//! 5.6, 7.10 and J92 19b, 27b, 35b, 48b, 64b, 79b as corrected by Townsend (2023). Those three
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
//! them (`O(TRUNCATION^4)` operations, `O(TRUNCATION^3)` transient memory per family) and
//! keeps the `O(TRUNCATION^2)` numbers `R_{k, m-q, q}` (11 triangles of 20301 numbers,
//! 1.8 MB), which a process reads on first use. A [`PairSeries`] for one `lambda` costs
//! `O(TRUNCATION^2)` (the 11 triangles' rows interleaved and summed side by side as sums
//! of products, `row_sums`); each evaluation at a separation sums the terms that may
//! add more than 1e-17 with every remainder at its bound `REMAINDER_BOUND` (all of
//! them near contact, 37 of 101 rows at `s' = 4`, 16 at `s' = 10`), the 22 Horner sums
//! side by side, with no allocation. A series for pairs at `s'` and beyond needs only
//! those terms: [`PairSeries::cached_at`] sums no more (two fifths of the rows at
//! `s' = 4`, a sixth at `s' = 10`), with the same values bit for bit.
//!
//! The neglected remainder is largest at contact. For `lambda` near 1 the remainders
//! oscillate in sign with amplitude `~10-200/m^3` (largest for `M`), so the contact
//! constants `K` are within ~5e-6 (`A`, `B`, `C`) to ~6e-4 (`X^M`) of their limits;
//! `X^C` decays monotonically (`~2.3/m^3`), its truncated tail is 1.5e-5 at contact. For
//! small spheres (`lambda` or `1/lambda` below ~0.1) the coefficients reach their
//! asymptotic decay only for `m >> 1/lambda` and the contact constants are uncertain to
//! ~1e-3 relative; away from contact (`s' >= 2.5`) every function is converged to
//! rounding. There is no switch to the near-contact forms: they share the constants `K`
//! and drop the `O(xi)` terms, so they are nowhere more accurate than the series.
//! Measured errors: the two-sphere integration tests.
//!
//! # Modules
//!
//! `scalars` the 22 functions ([`PairScalars`], [`FtScalars`], [`NAMES`]);
//! `recurrences` the JO84/J92 recurrences and their triangles ([`Coefficients`]);
//! `functions` which triangle, factor and parity each function takes and its singular
//! coefficients ([`singular_coefficients`]); `singular` the closed forms
//! ([`SingularForms`]); `series` the series of one size ratio ([`PairSeries`]). Each
//! uses only those before it.

mod functions;
mod recurrences;
mod scalars;
mod series;
mod singular;

pub use functions::singular_coefficients;
pub use recurrences::Coefficients;
pub use scalars::{FtScalars, PairScalars, NAMES};
pub use series::{resistance_scalars, resistance_scalars_ft, PairSeries, CACHED_RATIOS};
pub use singular::SingularForms;

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

fn check_lambda(lambda: f64) -> Result<(), TwoSphereError> {
    if lambda.is_finite() && (LAMBDA_MIN..=1.0 / LAMBDA_MIN).contains(&lambda) {
        Ok(())
    } else {
        Err(TwoSphereError::SizeRatio(lambda))
    }
}
