//! stokesian: Stokesian dynamics near walls and interfaces, linking the generated
//! kernels of the `kernels` crate.
//!
//! [`System::mobility`] assembles the dense grand mobility of `N` spheres in the layout of
//! Eq. 1 (moment-major: all `U` (3N), then all `Omega` (3N), then all `E` (5N); within a
//! moment, particle-major), truncated to `F`, `FT` or `FTS`. Input is validated first:
//! a typed [`InputError`] names the offending particle, and nothing is computed.

mod assembly;
mod brownian;
pub mod dense;
pub mod doublet;
pub mod exact;
mod input;
mod lubrication;
pub mod pair_tables;
pub mod tables;
mod tiled;
pub mod two_sphere;
mod velocity;

pub use assembly::{
    check_spd, solve_fts, Moments, Precision, SingularStressletBlock, SpdCheck, System,
};
pub use brownian::{
    lanczos_sqrt, rotate, Brownian, BrownianError, ExternalForces, LanczosError,
    LubricatedDynamics, Noise, Run, RunTally, Scheme, Step,
};
pub use input::{validate, InputError, Particle};
pub use kernels::lanes::Isa;
pub use kernels::Confinement;
pub use lubrication::{
    solve_resistance, solve_resistance_fts, wall_functions, wall_near_contact, wall_series,
    Lubrication, ResistanceError, WallFunctions,
};
pub use velocity::{strain_components, Velocities, VelocityError, MAX_CONDITION};
