//! Overdamped Brownian dynamics with hydrodynamic interactions, at the F level
//! (positions of torque-free spheres) or the FT level (positions and orientations,
//! external torques allowed). Euler-Maruyama:
//!
//! `x(t + dt) = x + (M F + kT div M) dt + sqrt(2 kT dt) B W`,
//!
//! with `M = B B^T` the grand mobility truncated to F or FT (Cholesky, or `M^{1/2} W`
//! by Lanczos from matrix-free products), `W` standard normal, and `div M` the
//! generated divergence kernels (the drift that position-dependent mobility requires
//! for the Boltzmann distribution to be stationary); or Fixman's midpoint scheme, which
//! produces the drift from a midpoint evaluation of `M` instead. At the FT level the
//! rotational rows give each sphere's rotation vector over the step (orientations do
//! not change the mobility of spheres; [`rotate`] updates a unit quaternion). External
//! forces: a uniform weight along `-z`, an exponential (screened-electrostatic)
//! repulsion from each boundary plane, a lateral harmonic trap, and a uniform torque.
//!
//! With lubrication (Brownian Stokesian dynamics, [`LubricatedDynamics`]) the mobility is
//! the inverse of the resistance of Eq. 19, `R = M^-1 + R_lub - R_lub^inf` (FT level;
//! the F level is the same with torque-free spheres), and
//!
//! `x(t + dt) = x + (R^-1 F + kT div R^-1) dt + sqrt(2 kT dt) L^-T W`, `R = L L^T`,
//!
//! the noise `L^-T W` having covariance `R^-1`; the drift `kT div R^-1` by a random
//! finite difference (Delong, Balboa Usabiaga & Donev 2014; Sprinkle et al. 2017):
//! `(1/delta) [R^-1(q + delta/2 D W~) - R^-1(q - delta/2 D W~)] D^-1 W~`, `W~` standard
//! normal on the translations, `D` the radii, whose mean is `div R^-1 + O(delta^2)`.
//!
//! [`settings`] holds what a run is given (the integrator, the noise, the external
//! forces, the lubricated dynamics, the trajectory) and the errors; [`brownian`] the
//! steps themselves, as methods of [`crate::System`].

pub mod brownian;
pub mod settings;

pub use brownian::rotate;
pub use settings::{
    Brownian, BrownianError, ExternalForces, LubricatedDynamics, Noise, Run, RunTally, Scheme, Step,
};
