//! The exact resistance functions of one sphere near a plane no-slip wall, `R^W` of
//! Eq. 19: the five functions ([`WallFunctions`]) from the generated tables
//! ([`crate::wall_tables`]) at every gap up to `EPS_MAX`, continued below the
//! tables by the near-contact forms ([`wall_near_contact`]) and above them by the
//! bispherical series ([`wall_series`], [`crate::exact`]).

use super::exact::{wall_functions_at_gap, ZETA3};
use super::wall_tables::{tabulated, EPS_MAX, EPS_MIN};

/// Sphere-wall resistance functions at `eps = (h - a)/a`, exact: the generated tables
/// of [`crate::wall_tables`] (piecewise Chebyshev in `ln eps`, within 1e-10 of the series,
/// the integration tests of the wall tables) for `eps` up to 1e3, the near-contact forms
/// continued from them below `1e-7`, and the series beyond `1e3`.
pub fn wall_functions(eps: f64) -> WallFunctions {
    if eps > EPS_MAX {
        return wall_series(eps);
    }
    if eps >= EPS_MIN {
        return WallFunctions::from(tabulated(eps));
    }
    // below the tables: the near-contact forms shifted by their constant offset from the
    // tables at `EPS_MIN`, so that the functions are continuous there (the offset is the
    // error of the near-contact constants, below 2e-8 relative)
    let (at, near) = (
        WallFunctions::from(tabulated(EPS_MIN)),
        wall_near_contact(EPS_MIN),
    );
    let nc = wall_near_contact(eps);
    WallFunctions {
        xa: nc.xa + (at.xa - near.xa),
        ya: nc.ya + (at.ya - near.ya),
        fr: nc.fr + (at.fr - near.fr),
        yc: nc.yc + (at.yc - near.yc),
        xc: nc.xc + (at.xc - near.xc),
    }
}

/// The exact bispherical series at `eps = (h - a)/a` ([`crate::exact`]: Brenner 1961,
/// O'Neill 1964, Dean & O'Neill 1963 as corrected by Goldman, Cox & Brenner 1967,
/// Jeffery 1915; [`wall_functions_at_gap`]): what the tables are made
/// from. Converged to round-off at every `eps >= 1e-7` (thousands of terms at the
/// smallest gaps).
pub fn wall_series(eps: f64) -> WallFunctions {
    let [xa, ya, fr, yc, xc] = wall_functions_at_gap(eps);
    WallFunctions { xa, ya, fr, yc, xc }
}

/// Near-contact sphere-wall resistance functions at `eps = (h - a)/a`, normalised as
/// `R_FU = 6 pi eta a [X^A nn + Y^A (I - nn)]`, `R_LO = 8 pi eta a^3 [X^C nn + Y^C (I - nn)]`,
/// `(R_FO)_ij = -6 pi eta a^2 F^r eps_ijk n_k`, `R_LU = R_FO^T`; `n` the wall normal
/// into the fluid. Singular and `eps ln eps` terms: Brenner 1961, Cox & Brenner 1967
/// eq. 2.49 (X^A); Goldman, Cox & Brenner 1967 eqs. 2.59, 2.65, 3.6-3.13 (Y^A, F^r,
/// Y^C); Jeffery 1915 / Cox & Brenner 1967 eq. 3.5 (X^C); checked against the
/// lambda -> infinity limits of the two-sphere functions. O(1) constants and O(eps)
/// terms: fits at `eps` = 1e-5 ... 1e-2 to the exact bispherical series, which GCB's
/// constants (0.9588, -0.2526, 0.3817) approximate at their last tabulated gap.
pub fn wall_near_contact(eps: f64) -> WallFunctions {
    let l = (1.0 / eps).ln();
    WallFunctions {
        xa: 1.0 / eps + l / 5.0 + 0.971_279_9 + eps * l / 21.0 + 0.167_02 * eps,
        ya: 8.0 / 15.0 * l + 0.954_293_7 + 64.0 / 375.0 * eps * l + 0.429_45 * eps,
        fr: 2.0 / 15.0 * l - 0.257_270_3 + 86.0 / 375.0 * eps * l + 0.134_11 * eps,
        yc: 2.0 / 5.0 * l + 0.370_892_6 + 66.0 / 125.0 * eps * l + 0.340_09 * eps,
        xc: ZETA3 - 0.5 * eps * l + 0.444_93 * eps,
    }
}

/// The five sphere-wall resistance functions (see [`wall_functions`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallFunctions {
    /// Translation normal to the wall.
    pub xa: f64,
    /// Translation parallel to the wall.
    pub ya: f64,
    /// Translation-rotation coupling.
    pub fr: f64,
    /// Rotation about an axis parallel to the wall.
    pub yc: f64,
    /// Rotation about the wall normal.
    pub xc: f64,
}

impl From<[f64; 5]> for WallFunctions {
    /// The functions in the order of the tables: `[X^A, Y^A, F^r, Y^C, X^C]`.
    fn from([xa, ya, fr, yc, xc]: [f64; 5]) -> Self {
        WallFunctions { xa, ya, fr, yc, xc }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn singular_terms_match_the_wall_limit_of_the_pair_functions() {
        // the wall's eps ln eps coefficients are the lambda -> infinity limits of the
        // two-sphere functions' (Townsend 2023); here a spot check of the wall functions'
        // slopes.
        let (e1, e2) = (1e-6, 1e-7);
        let (w1, w2) = (wall_near_contact(e1), wall_near_contact(e2));
        let dl = (1.0f64 / e2).ln() - (1.0f64 / e1).ln();
        assert!(((w2.ya - w1.ya) / dl - 8.0 / 15.0).abs() < 1e-5);
        assert!(((w2.yc - w1.yc) / dl - 2.0 / 5.0).abs() < 1e-5);
        assert!(((w2.fr - w1.fr) / dl - 2.0 / 15.0).abs() < 1e-5);
    }
}
