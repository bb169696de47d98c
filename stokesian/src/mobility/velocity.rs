//! Velocities of spheres from given forces, torques and an imposed strain: the mobility
//! problem at F, FT or FTS, far field or with lubrication (what `stokesian velocity`
//! computes, as a library call).

use crate::resistance::{solve_resistance, solve_resistance_fts, Lubrication, ResistanceError};
use crate::system::{Moments, System};
use nalgebra::DMatrix;
use thiserror::Error;

/// Above this condition estimate of the lubricated resistance the velocities are refused.
pub const MAX_CONDITION: f64 = 1e14;

/// The velocities and how they were obtained.
#[derive(Clone, Debug, PartialEq)]
pub struct Velocities {
    /// `U - U_inf` (`3N`) and, at FT and FTS, `Omega - Omega_inf` (`3N`), moment-major.
    pub u: Vec<f64>,
    /// With lubrication, the condition estimate of the resistance that was solved.
    pub condition: Option<f64>,
    /// At FTS without lubrication: whether the stresslet block was solved by Cholesky
    /// (`false`: by LU, as it is not positive definite; never for valid input).
    pub stresslet_cholesky: bool,
}

/// Why the velocities cannot be computed.
#[derive(Debug, Error, PartialEq)]
pub enum VelocityError {
    /// The forces (and torques) do not match the system.
    #[error("{found} forces and torques for {n} particles at {moments:?}: expected {expected} (3N forces, then 3N torques at FT and FTS)")]
    Length {
        /// The truncation.
        moments: Moments,
        /// Number of particles.
        n: usize,
        /// Numbers expected.
        expected: usize,
        /// Numbers given.
        found: usize,
    },
    /// A force, torque or strain component is NaN or infinite.
    #[error("{what} component {index} is {value}, not a finite number")]
    NonFinite {
        /// `force or torque` or `strain`.
        what: &'static str,
        /// Index in the moment-major vector.
        index: usize,
        /// The value.
        value: f64,
    },
    /// An imposed strain without stresslets: rigid spheres then follow it exactly.
    #[error("an imposed strain needs the stresslets (FTS): without them the spheres follow a uniform strain and U - U_inf does not depend on it (asked for {0:?})")]
    StrainWithoutStresslets(Moments),
    /// The resistance with lubrication cannot be formed or factored.
    #[error("{0}")]
    Resistance(#[from] ResistanceError),
    /// The resistance is too ill-conditioned to solve.
    #[error("the resistance with lubrication is too ill-conditioned to solve (condition estimate {0:e} > 1e14)")]
    IllConditioned(f64),
    /// The stresslet block cannot be solved.
    #[error("{0} (overlapping spheres accepted, or a narrow slit?)")]
    Singular(#[from] SingularStressletBlock),
    /// A Cartesian rate of strain that is not symmetric and traceless.
    #[error(
        "a rate of strain must be symmetric and traceless (to 1e-9 of its largest component): {0}"
    )]
    NotSymmetricTraceless(String),
    /// Overlapping spheres ([`crate::Overlap::Rpy`]) at FTS, where no overlap form exists.
    #[error("{0}")]
    Overlap(#[from] crate::system::overlap::OverlapError),
    /// What a periodic box does not provide ([`crate::periodic`]).
    #[error("{0}")]
    Periodic(#[from] crate::periodic::PeriodicError),
    /// The mobility or the result has entries that are not finite.
    #[error("the {0} has entries that are not finite numbers (spheres accepted although they overlap, or lengths and viscosity near the limits of double precision)")]
    NotFinite(&'static str),
}

/// The 5 components `E_m = B_m : E` in the orthonormal basis
/// [`kernels::STRAIN_BASIS`] of a Cartesian rate of strain `e` (row-major), which must be
/// symmetric and traceless to `1e-9` of its largest component.
pub fn strain_components(e: &[[f64; 3]; 3]) -> Result<[f64; 5], VelocityError> {
    let scale = e.iter().flatten().fold(0.0f64, |s, v| s.max(v.abs()));
    let tol = 1e-9 * scale;
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        if (e[i][j] - e[j][i]).abs() > tol {
            return Err(VelocityError::NotSymmetricTraceless(format!(
                "not symmetric: E{}{} = {} but E{}{} = {}",
                i + 1,
                j + 1,
                e[i][j],
                j + 1,
                i + 1,
                e[j][i]
            )));
        }
    }
    let trace = e[0][0] + e[1][1] + e[2][2];
    if trace.abs() > tol {
        return Err(VelocityError::NotSymmetricTraceless(format!(
            "not traceless: E11 + E22 + E33 = {trace} (an incompressible flow has a traceless \
             rate of strain)"
        )));
    }
    let mut out = [0.0; 5];
    for (m, b) in kernels::STRAIN_BASIS.iter().enumerate() {
        out[m] = (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|(i, j)| b[i][j] * e[i][j])
            .sum();
    }
    Ok(out)
}

/// The FTS mobility problem of rigid spheres: given forces and torques `x` (`6N`,
/// moment-major) and a uniform imposed strain `e_inf` (5 components in the orthonormal
/// basis), the strain rows of the FTS mobility `m` (`11N x 11N`) give
/// `-E_inf = M_EF F + M_EL L + M_ES S`, solved for the stresslets `S` by Cholesky of
/// `M_ES` (LU if it is not positive definite, which valid input never gives); then
/// `(U, Omega) = M_(U,Omega)(F, L, S)`. Returns the `6N` velocities (moment-major,
/// relative to the ambient flow) and whether Cholesky succeeded.
pub fn solve_fts(
    m: &DMatrix<f64>,
    x: &[f64],
    e_inf: &[f64; 5],
) -> Result<(Vec<f64>, bool), SingularStressletBlock> {
    let n = m.nrows() / 11;
    let fl = nalgebra::DVector::from_column_slice(x);
    let m_e_fl = m.view((6 * n, 0), (5 * n, 6 * n));
    let m_es = m.view((6 * n, 6 * n), (5 * n, 5 * n)).into_owned();
    let mut rhs = -(m_e_fl * &fl);
    for a in 0..n {
        for c in 0..5 {
            rhs[5 * a + c] -= e_inf[c];
        }
    }
    let (s, cholesky) = match crate::linalg::Cholesky::new(&m_es) {
        Some(ch) => (nalgebra::DVector::from_vec(ch.solve(rhs.as_slice())), true),
        None => (m_es.lu().solve(&rhs).ok_or(SingularStressletBlock)?, false),
    };
    let m_ufl = m.view((0, 0), (6 * n, 6 * n));
    let m_us = m.view((0, 6 * n), (6 * n, 5 * n));
    let u = m_ufl * &fl + m_us * &s;
    Ok((u.as_slice().to_vec(), cholesky))
}

/// The stresslet block `M_ES` of an FTS mobility is singular.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
#[error("the stresslet block M_ES is singular")]
pub struct SingularStressletBlock;

impl System {
    /// The velocities of the spheres under forces and torques `x` (`3N` at F, `6N` at FT
    /// and FTS, moment-major: what the particles exert on the fluid) and the uniform
    /// imposed strain `e_inf` (5 components in the orthonormal basis; FTS only, zero
    /// otherwise). Far field: `M x` (F, FT, matrix-free) or the FTS mobility problem
    /// ([`solve_fts`]). With `lubrication` (FT, FTS): the resistance of Eq. 19 solved by
    /// Cholesky ([`solve_resistance`], [`solve_resistance_fts`]), refused above a
    /// condition estimate of [`MAX_CONDITION`].
    pub fn velocities(
        &self,
        moments: Moments,
        x: &[f64],
        e_inf: &[f64; 5],
        lubrication: Option<&Lubrication>,
    ) -> Result<Velocities, VelocityError> {
        let n = self.len();
        let expected = if moments == Moments::F { 3 * n } else { 6 * n };
        if x.len() != expected {
            return Err(VelocityError::Length {
                moments,
                n,
                expected,
                found: x.len(),
            });
        }
        let non_finite = |what, v: &[f64]| {
            v.iter()
                .position(|v| !v.is_finite())
                .map(|index| VelocityError::NonFinite {
                    what,
                    index,
                    value: v[index],
                })
        };
        if let Some(e) = non_finite("force or torque", x).or(non_finite("strain", e_inf)) {
            return Err(e);
        }
        if moments != Moments::FTS && *e_inf != [0.0; 5] {
            return Err(VelocityError::StrainWithoutStresslets(moments));
        }
        self.check_overlap(moments)?;
        let mut out = Velocities {
            u: Vec::new(),
            condition: None,
            stresslet_cholesky: true,
        };
        match (moments, lubrication) {
            (_, Some(lub)) => {
                let r = self.resistance(moments, lub)?;
                if !r.iter().all(|v| v.is_finite()) {
                    return Err(VelocityError::NotFinite("resistance"));
                }
                let (u, cond) = if moments == Moments::FTS {
                    solve_resistance_fts(&r, x, e_inf)?
                } else {
                    solve_resistance(&r, x)?
                };
                if cond.is_nan() || cond > MAX_CONDITION {
                    return Err(VelocityError::IllConditioned(cond));
                }
                out.u = u;
                out.condition = Some(cond);
            }
            (Moments::F | Moments::FT, None) => out.u = self.apply(moments, x),
            (Moments::FTS, None) => {
                let m = self.mobility(Moments::FTS);
                if !m.iter().all(|v| v.is_finite()) {
                    return Err(VelocityError::NotFinite("mobility"));
                }
                let (u, cholesky) = solve_fts(&m, x, e_inf)?;
                out.u = u;
                out.stresslet_cholesky = cholesky;
            }
        }
        if !out.u.iter().all(|v| v.is_finite()) {
            return Err(VelocityError::NotFinite("velocity"));
        }
        Ok(out)
    }
}
