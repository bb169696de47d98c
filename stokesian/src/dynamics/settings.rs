//! The settings of Brownian dynamics (the integrator, the noise, the external forces, the
//! lubricated dynamics and the trajectory), their ranges ([`Brownian::check`]), the
//! result of one step and why a step or a run fails.

use crate::linalg::LanczosError;
use crate::resistance::{Lubrication, ResistanceError};
use crate::system::input::InputError;
use crate::system::{Moments, System};
use thiserror::Error;

/// External forces on every sphere (force exerted on the fluid = external force on the
/// particle, in the mobility's convention).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExternalForces {
    /// Buoyant weight: force `-weight e_z`.
    pub weight: f64,
    /// Repulsion from each boundary, `F = strength * exp(-(d - a) / debye)` along the
    /// boundary's normal into the fluid, `d` the centre-to-boundary distance; potential
    /// `strength * debye * exp(-(d - a) / debye)`.
    pub strength: f64,
    /// Screening length of the repulsion.
    pub debye: f64,
    /// Stiffness of a harmonic trap pulling each sphere towards the axis `x = y = 0`
    /// (force `-trap (x, y, 0)`; potential `trap (x^2 + y^2) / 2`); 0 for none.
    pub trap: f64,
    /// A torque on every sphere (FT level only; e.g. a rotating magnetic field driving
    /// colloidal rollers).
    pub torque: [f64; 3],
}

impl ExternalForces {
    /// No external force or torque (the repulsion's screening length 1, unused).
    pub const NONE: ExternalForces = ExternalForces {
        weight: 0.0,
        strength: 0.0,
        debye: 1.0,
        trap: 0.0,
        torque: [0.0; 3],
    };

    /// The potential energy of one sphere of radius `a` at centre height `z` above a
    /// single lower boundary at `z0` (for tests and for the Boltzmann distribution).
    pub fn potential_above(&self, z: f64, a: f64, z0: f64) -> f64 {
        self.weight * z + self.strength * self.debye * (-((z - z0) - a) / self.debye).exp()
    }

    /// Whether any force is applied.
    pub(crate) fn any(&self) -> bool {
        self.weight != 0.0 || self.strength != 0.0 || self.trap != 0.0
    }
}

/// Integration settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Brownian {
    /// Thermal energy `kT`.
    pub kt: f64,
    /// Time step.
    pub dt: f64,
    /// Include the drift `kT div M` (switching it off is wrong near a boundary; the
    /// option exists to show that it matters).
    pub drift: bool,
    /// External forces.
    pub forces: ExternalForces,
    /// How the Brownian displacement `M^{1/2} W` is formed.
    pub noise: Noise,
    /// With `false`, no hydrodynamic interactions: each sphere has the isolated Stokes
    /// mobility `1/(6 pi eta a)` (no wall or pair coupling, hence no drift). For
    /// comparison: the equilibrium distribution must not depend on it.
    pub hydrodynamics: bool,
    /// F (positions) or FT (positions and rotations).
    pub moments: Moments,
    /// The time integrator.
    pub scheme: Scheme,
    /// Lubricated dynamics (Brownian Stokesian dynamics): the resistance of Eq. 19 in
    /// place of the far-field mobility. `None`: the far-field mobility.
    pub lubrication: Option<LubricatedDynamics>,
}

/// Brownian Stokesian dynamics: velocities, noise and drift from the lubricated
/// resistance ([`crate::dynamics`]). Needs hydrodynamic interactions, Cholesky noise and the
/// Euler-Maruyama scheme.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LubricatedDynamics {
    /// Where the lubrication corrections of Eq. 19 are switched on.
    pub lubrication: Lubrication,
    /// The random finite difference's step `delta`, in units of each sphere's radius
    /// (e.g. `1e-3`: truncation error `O(delta^2)`, round-off `O(eps / delta)`, both far
    /// below the statistical error of any run). Where a gap (to a boundary or between
    /// two spheres, over the smaller radius) is below `10 delta`, the step of that
    /// configuration is a tenth of the gap instead, so that the displaced
    /// configurations never touch (a step that depends on the configuration and not on
    /// `W~` keeps the estimate unbiased).
    pub rfd_step: f64,
}

impl Brownian {
    /// Standard normal numbers one step of `n` spheres takes: `3N` at the F level, `6N`
    /// at FT; with lubrication `6N` for the noise (the resistance is FT even for
    /// torque-free spheres) and `3N` for the random finite difference.
    pub fn random_numbers(&self, n: usize) -> usize {
        match self.lubrication {
            Some(_) => 9 * n,
            None => self.moments.per_particle() * n,
        }
    }
}

/// The time integrator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scheme {
    /// Euler-Maruyama with the generated drift `kT div M`: one mobility per step.
    EulerMaruyama,
    /// Fixman's midpoint: the drift from a second mobility at a random midpoint, no
    /// divergence kernels; the deterministic part is second order (midpoint rule).
    /// Needs the Cholesky factor.
    FixmanMidpoint,
}

/// The result of one step.
#[derive(Clone, Debug)]
pub struct Step {
    /// The system at the new positions.
    pub system: System,
    /// Each sphere's rotation vector over the step (angle times axis); zero at the F
    /// level.
    pub rotation: Vec<[f64; 3]>,
    /// With Lanczos noise, the iterations the square root took.
    pub lanczos_iterations: Option<usize>,
}

/// The square root of the mobility applied to the random vector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Noise {
    /// Cholesky factor `L` of the dense `M` (`L W` has covariance `M`): N up to a few
    /// thousand.
    Cholesky,
    /// Lanczos `M^{1/2} W` from matrix-free products, to a relative tolerance.
    Lanczos {
        /// Relative change at which the iteration stops.
        tol: f64,
    },
}

/// Why a step cannot be taken.
#[derive(Debug, Error, PartialEq)]
pub enum BrownianError {
    /// The new configuration is invalid (a sphere crossed a boundary or another
    /// sphere): the time step is too large for the forces.
    #[error("step {step}: {source}; reduce the time step")]
    Invalid {
        /// Step number.
        step: usize,
        /// What is wrong with the new configuration.
        source: InputError,
    },
    /// The mobility lost positive definiteness (cannot happen for valid input).
    #[error("step {0}: the mobility is not positive definite")]
    NotPositiveDefinite(usize),
    /// The lubricated resistance cannot be formed.
    #[error("step {step}: {source}")]
    Resistance {
        /// Step number.
        step: usize,
        /// Why.
        source: ResistanceError,
    },
    /// The random numbers given to [`System::brownian_increment`] do not match the system.
    #[error("{found} random numbers for a system with {expected} degrees of freedom")]
    RandomNumbers {
        /// Numbers a step takes ([`Brownian::random_numbers`]).
        expected: usize,
        /// Numbers given.
        found: usize,
    },
    /// The combination asked for is not implemented.
    #[error("{0} is not implemented")]
    Unsupported(&'static str),
    /// The Lanczos square root failed.
    #[error("step {step}: {source}")]
    Lanczos {
        /// Step number.
        step: usize,
        /// Why.
        source: LanczosError,
    },
    /// What the RPY overlap forms do not cover ([`crate::Overlap::Rpy`]): the drift of a
    /// sphere cut by two boundaries that are not perpendicular ([`System::check_drift`]).
    ///
    /// [`System::check_drift`]: crate::System::check_drift
    #[error("{0}")]
    Overlap(#[from] crate::system::overlap::OverlapError),
    /// What a periodic box does not provide ([`crate::periodic`]).
    #[error("{0}")]
    Periodic(#[from] crate::periodic::PeriodicError),
    /// A setting is out of range ([`Brownian::check`], [`Run`]).
    #[error("{name} = {value}: {why}")]
    BadSetting {
        /// The setting's name.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What it must be.
        why: &'static str,
    },
    /// A run redrew more steps than it allows ([`Run::max_rejections`]).
    #[error("{rejections} rejected steps, more than max_rejections = {max}: the last, at step {step}, {source}. The time step is too large for the forces and distances near contact: use a smaller dt (or raise max_rejections)")]
    TooManyRejections {
        /// Steps redrawn so far.
        rejections: usize,
        /// The limit.
        max: usize,
        /// The step of the last rejection.
        step: usize,
        /// Why the last one was rejected.
        source: InputError,
    },
}

/// A trajectory: how many steps, which of them to keep, the random numbers, and how many
/// invalid steps (a sphere through a boundary or another sphere) may be redrawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Run {
    /// Number of time steps.
    pub steps: usize,
    /// Keep every `every`-th step (step 0 always); at least 1.
    pub every: usize,
    /// Seed of the standard normal numbers (ChaCha8): the same seed, the same trajectory.
    pub seed: u64,
    /// Fail after more than this many redrawn steps in total.
    pub max_rejections: usize,
}

/// What a [`System::brownian_run`] counted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RunTally {
    /// Steps rejected (invalid new configuration) and redrawn.
    pub rejections: usize,
    /// Lanczos iterations summed over the steps (Lanczos noise).
    pub lanczos_sum: usize,
    /// The most Lanczos iterations one step took.
    pub lanczos_max: usize,
}

impl Brownian {
    /// Every number in range: `dt`, `kt` and the repulsion's `debye` positive and finite,
    /// the weight, repulsion strength and torque finite, the trap stiffness finite and
    /// non-negative, the Lanczos tolerance and the random finite difference's step
    /// positive; and no drift switched off under Fixman's scheme (its drift comes from
    /// the midpoint). The other unsupported combinations are reported by the step itself.
    pub fn check(&self) -> Result<(), BrownianError> {
        let bad = |name, value, why| Err(BrownianError::BadSetting { name, value, why });
        let positive = "must be a positive finite number";
        let finite = "must be a finite number";
        if !(self.dt > 0.0 && self.dt.is_finite()) {
            return bad(
                "dt",
                self.dt,
                "the time step must be a positive finite number",
            );
        }
        if !(self.kt > 0.0 && self.kt.is_finite()) {
            return bad(
                "kt",
                self.kt,
                "the thermal energy must be a positive finite number",
            );
        }
        let f = &self.forces;
        if !(f.debye > 0.0 && f.debye.is_finite()) {
            return bad("debye_length", f.debye, positive);
        }
        if !f.weight.is_finite() {
            return bad("weight", f.weight, finite);
        }
        if !f.strength.is_finite() {
            return bad("repulsion_strength", f.strength, finite);
        }
        if !(f.trap >= 0.0 && f.trap.is_finite()) {
            return bad(
                "trap",
                f.trap,
                "the trap stiffness must be a finite number >= 0",
            );
        }
        if let Some(&t) = f.torque.iter().find(|t| !t.is_finite()) {
            return bad("torque", t, finite);
        }
        if let Noise::Lanczos { tol } = self.noise {
            if !(tol > 0.0 && tol.is_finite()) {
                return bad(
                    "lanczos",
                    tol,
                    "the relative tolerance must be a positive finite number",
                );
            }
        }
        if let Some(lub) = &self.lubrication {
            if !(lub.rfd_step > 0.0 && lub.rfd_step.is_finite()) {
                return bad("rfd_step", lub.rfd_step, positive);
            }
            if let Err(ResistanceError::Setting { what, value, need }) = lub.lubrication.check() {
                return bad(what, value, need);
            }
        }
        if self.scheme == Scheme::FixmanMidpoint && !self.drift {
            return Err(BrownianError::Unsupported(
                "switching the drift off with Fixman's scheme (its drift comes from the \
                 midpoint)",
            ));
        }
        Ok(())
    }
}
