//! Generated tables of the exact sphere-wall resistance functions: piecewise Chebyshev
//! fits in `s = ln(eps)`, `eps = (h - a)/a` the gap over the radius, made by
//! `cargo xtask gen` from the bispherical series of [`crate::exact`] (Brenner 1961,
//! O'Neill 1964, Dean & O'Neill 1963 with Goldman, Cox & Brenner 1967, Jeffery 1915) and
//! committed in `src/generated/wall_tables.rs`.
//!
//! In `s` the near-contact singularities are smooth: `ln(1/eps) = -s` is linear, and the
//! `1/eps` of `X^A` is taken out analytically by fitting `eps X^A`. The tables span
//! `eps` in `[EPS_MIN, EPS_MAX]` = `[1e-7, 1e3]` on unit intervals of `s`; below, the
//! near-contact forms ([`crate::wall_near_contact`], continued by
//! [`crate::wall_functions`]) shifted by their constant offset
//! from the table at `EPS_MIN` (so that the functions are continuous there; the offset
//! is the error of the near-contact constants, below 2e-8 relative); above, a sphere
//! is so far from the wall (`h > 1000 a`) that the exact functions equal the inverse of
//! the far-field mobility to 1e-12 (measured: `X^A` 5e-13), and Eq. 19 needs no
//! correction. Evaluation is Clenshaw's recurrence: about 100 operations per function
//! instead of a series of up to thousands of terms.

/// Smallest gap over radius of the tables.
pub const EPS_MIN: f64 = 1e-7;
/// Largest gap over radius of the tables.
pub const EPS_MAX: f64 = 1e3;
/// Chebyshev coefficients per interval (degree + 1).
pub const TERMS: usize = 18;

#[rustfmt::skip]
#[path = "generated/wall_tables.rs"]
mod data;

/// The first interval's left end in `s`.
pub(crate) fn s_min() -> f64 {
    EPS_MIN.ln()
}

/// Unit intervals of `s` covering `[ln EPS_MIN, ln EPS_MAX]`.
pub fn intervals() -> usize {
    (EPS_MAX.ln() - s_min()).ceil() as usize
}

/// `sum_j c_j T_j(t)`, `t` in `[-1, 1]` (Clenshaw).
fn clenshaw(c: &[f64], t: f64) -> f64 {
    let (mut b1, mut b2) = (0.0, 0.0);
    for &cj in c.iter().skip(1).rev() {
        let b0 = cj + 2.0 * t * b1 - b2;
        b2 = b1;
        b1 = b0;
    }
    c[0] + t * b1 - b2
}

/// The five functions `[X^A, Y^A, F^r, Y^C, X^C]` at `eps` in `[EPS_MIN, EPS_MAX]` from
/// the tables (`X^A` from the fit of `eps X^A`).
pub(crate) fn tabulated(eps: f64) -> [f64; 5] {
    let s = eps.ln() - s_min();
    let i = (s.floor().max(0.0) as usize).min(intervals() - 1);
    let t = 2.0 * (s - i as f64) - 1.0;
    [
        clenshaw(&data::EPS_XA[i], t) / eps,
        clenshaw(&data::YA[i], t),
        clenshaw(&data::FR[i], t),
        clenshaw(&data::YC[i], t),
        clenshaw(&data::XC[i], t),
    ]
}
