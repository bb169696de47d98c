//! The co-rotating doublet of Swan & Brady, Sec. III B (Figs. 2-3): two equal spheres
//! (radius `a`) at height `h` above a no-slip wall, centres `r` apart along `x`, with
//! equal and opposite torques `+T e_x` and `-T e_x` along their line of centres and
//! otherwise force- and torque-free (rigid spheres, no imposed flow: FTS with
//! `E_inf = 0`).
//!
//! Near the wall a torque about an axis parallel to it makes a sphere translate, so the
//! spheres move in opposite directions along `y` and the doublet turns about `z`
//! through its centre at the rate `Omega = (U_2 - U_1)_y / r`. If they were joined by a
//! wire, the wire would carry the tension `tau` (external force `+tau e_x` on sphere 1,
//! `-tau e_x` on sphere 2; positive = pulling them together) that keeps `r` fixed:
//! `(U_2 - U_1)_x = 0`. Both are computed for any linear solver `(F, L) -> (U, Omega)`:
//! the far-field FTS mobility (stresslets solved for zero strain, [`solve_fts`])
//! and the resistance with lubrication (Eq. 19: `(F, L) = R_{FL,U Omega} (U, Omega)`
//! since `E_inf = 0`).
//!
//! Units: `a = 1`, `eta = 1`, `T = 1`; the rate is reported as `8 pi eta a^3 Omega / T`
//! (the paper's normalisation) and the tension as `tau a / T`.

use crate::mobility::solve_fts;
use crate::resistance::{Lubrication, ResistanceError};
use crate::system::input::{InputError, Particle};
use crate::system::{Moments, System};
use kernels::Confinement;
use nalgebra::{DMatrix, DVector};
use std::f64::consts::PI;
use thiserror::Error;

/// One point of the doublet study.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DoubletPoint {
    /// Centre-to-centre distance over the radius.
    pub r: f64,
    /// Height of the centres above the wall over the radius.
    pub h: f64,
    /// `8 pi eta a^3 Omega / T` with the resistance with lubrication.
    pub rate_resistance: f64,
    /// `8 pi eta a^3 Omega / T` with the far-field mobility alone.
    pub rate_farfield: f64,
    /// `tau a / T` with the resistance with lubrication.
    pub tension_resistance: f64,
    /// `tau a / T` with the far-field mobility alone.
    pub tension_farfield: f64,
}

/// Why a doublet point cannot be computed.
#[derive(Debug, Error, PartialEq)]
pub enum DoubletError {
    /// The geometry is invalid (spheres overlapping each other or the wall).
    #[error("doublet at r = {r}, h = {h}: {source}")]
    Geometry {
        /// Separation.
        r: f64,
        /// Height.
        h: f64,
        /// Why.
        source: InputError,
    },
    /// The resistance cannot be formed.
    #[error("doublet at r = {r}, h = {h}: {source}")]
    Resistance {
        /// Separation.
        r: f64,
        /// Height.
        h: f64,
        /// Why.
        source: ResistanceError,
    },
    /// A linear solve failed (a matrix that should be positive definite is not).
    #[error("doublet at r = {r}, h = {h}: {what} is singular")]
    Singular {
        /// Separation.
        r: f64,
        /// Height.
        h: f64,
        /// Which matrix.
        what: &'static str,
    },
}

/// Rate `8 pi Omega` and tension `tau` (units a = eta = T = 1) from a solver of the
/// two-sphere force-torque problem: `solve(x)` maps forces and torques (12, moment-major:
/// `F_1, F_2, L_1, L_2`) to velocities and rotation rates (same layout). Linear: the
/// separation rate is `A + tau B` with `A` from the torques and `B` from a unit tension,
/// so `tau = -A/B`.
pub fn rate_and_tension(
    r: f64,
    mut solve: impl FnMut(&[f64; 12]) -> Option<[f64; 12]>,
) -> Option<(f64, f64)> {
    let mut torques = [0.0; 12];
    torques[6] = 1.0; // L_1 = +T e_x
    torques[9] = -1.0; // L_2 = -T e_x
    let mut tension = [0.0; 12];
    tension[0] = 1.0; // F_1 = +tau e_x (towards sphere 2)
    tension[3] = -1.0; // F_2 = -tau e_x
    let (y_t, y_f) = (solve(&torques)?, solve(&tension)?);
    let separation = |y: &[f64; 12]| y[3] - y[0];
    let tau = -separation(&y_t) / separation(&y_f);
    let turn = |y: &[f64; 12]| (y[4] - y[1]) / r;
    Some((8.0 * PI * (turn(&y_t) + tau * turn(&y_f)), tau))
}

/// Rate and tension from a 22 x 22 FTS mobility of the two spheres (moment-major layout
/// of [`System::mobility`]), stresslets solved for `E_inf = 0`.
pub fn farfield_rate_and_tension(m: &DMatrix<f64>, r: f64) -> Option<(f64, f64)> {
    rate_and_tension(r, |x| {
        let (u, _) = solve_fts(m, x, &[0.0; 5]).ok()?;
        Some(std::array::from_fn(|i| u[i]))
    })
}

/// Rate and tension from a 22 x 22 FTS resistance (rows `F, L, S`, columns
/// `U, Omega, -E_inf`): with `E_inf = 0` the motion solves `R_{FL,U Omega} y = x`.
pub fn resistance_rate_and_tension(rr: &DMatrix<f64>, r: f64) -> Option<(f64, f64)> {
    let block = rr.view((0, 0), (12, 12)).into_owned();
    let chol = block.cholesky()?;
    rate_and_tension(r, |x| {
        let y = chol.solve(&DVector::from_column_slice(x));
        Some(std::array::from_fn(|i| y[i]))
    })
}

/// The doublet at separation `r` and height `h` (over the radius), wall at 0, with the
/// given lubrication cutoffs.
pub fn doublet(r: f64, h: f64, lub: &Lubrication) -> Result<DoubletPoint, DoubletError> {
    let ps = vec![
        Particle {
            x: [-0.5 * r, 0.0, h],
            a: 1.0,
        },
        Particle {
            x: [0.5 * r, 0.0, h],
            a: 1.0,
        },
    ];
    let s = System::new(Confinement::Wall { height: 0.0 }, 1.0, ps, false)
        .map_err(|source| DoubletError::Geometry { r, h, source })?;
    let m = s.mobility(Moments::FTS);
    let (rate_farfield, tension_farfield) =
        farfield_rate_and_tension(&m, r).ok_or(DoubletError::Singular {
            r,
            h,
            what: "the stresslet block of the FTS mobility",
        })?;
    let rr = s
        .resistance(Moments::FTS, lub)
        .map_err(|source| DoubletError::Resistance { r, h, source })?;
    let (rate_resistance, tension_resistance) =
        resistance_rate_and_tension(&rr, r).ok_or(DoubletError::Singular {
            r,
            h,
            what: "the force-torque block of the resistance",
        })?;
    Ok(DoubletPoint {
        r,
        h,
        rate_resistance,
        rate_farfield,
        tension_resistance,
        tension_farfield,
    })
}
