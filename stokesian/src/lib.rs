//! stokesian: Stokesian dynamics near walls and interfaces, linking the generated
//! kernels of the `kernels` crate.
//!
//! [`System::mobility`] assembles the dense grand mobility of `N` spheres in the layout of
//! Eq. 1 (moment-major: all `U` (3N), then all `Omega` (3N), then all `E` (5N); within a
//! moment, particle-major), truncated to `F`, `FT` or `FTS`. Input is validated first:
//! a typed [`InputError`] names the offending particle, and nothing is computed.
//!
//! The crate by subsystem:
//!
//! - [`system`]: the validated [`System`], the truncation [`Moments`], the [`Precision`]
//!   of the matrix-free product, the input's validation; its module docs list where each
//!   of `System`'s methods lives;
//! - [`linalg`]: the dense algebra through faer (Cholesky, solves, large matrices, the
//!   symmetric positive-definite check) and the Lanczos square root;
//! - [`mobility`]: the dense grand mobility, the tiled matrix-free product, the
//!   velocities of given forces, torques and strain;
//! - [`resistance`]: the resistance with lubrication (Eq. 19) and the exact sphere-wall
//!   and two-sphere resistance functions, series and tables;
//! - [`dynamics`]: Brownian dynamics, with the far-field mobility or with lubrication;
//! - [`studies`]: studies of the paper (the co-rotating doublet);
//! - [`generate`]: what `cargo xtask gen` writes into `src/generated/` (the tables and
//!   coefficients), used at generation time only.
//!
//! No two modules import each other: `resistance::lubrication` forms the far-field
//! mobility through `System::mobility` (`mobility::assembly`), and
//! `mobility::velocity` solves that resistance when the velocities are lubricated, but
//! `mobility::assembly` and `mobility::tiled` know nothing of the resistance. The tables
//! of `resistance` read the series' closed forms; what makes the tables from the series
//! is `generate`.
//!
//! The types most callers need are re-exported here.

pub mod dynamics;
pub mod generate;
pub mod linalg;
pub mod mobility;
pub mod resistance;
pub mod studies;
pub mod system;

pub use dynamics::{
    rotate, Brownian, BrownianError, ExternalForces, LubricatedDynamics, Noise, Run, RunTally,
    Scheme, Step,
};
pub use kernels::lanes::Isa;
pub use kernels::Confinement;
pub use linalg::{check_spd, lanczos_sqrt, LanczosError, SpdCheck};
pub use mobility::{
    solve_fts, strain_components, SingularStressletBlock, Velocities, VelocityError, MAX_CONDITION,
};
pub use resistance::{
    solve_resistance, solve_resistance_fts, wall_functions, wall_near_contact, wall_series,
    Lubrication, ResistanceError, WallFunctions,
};
pub use system::input::{validate, InputError, Particle};
pub use system::{Moments, Precision, System};
