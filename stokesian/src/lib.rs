//! stokesian: Stokesian dynamics near walls and interfaces, linking the generated
//! kernels of the `kernels` crate.
//!
//! [`System::mobility`] assembles the dense grand mobility of `N` spheres in the layout of
//! Eq. 1 (moment-major: all `U` (3N), then all `Omega` (3N), then all `E` (5N); within a
//! moment, particle-major), truncated to `F`, `FT` or `FTS`. Input is validated first:
//! a typed [`InputError`] names the offending particle, and nothing is computed.
//!
//! # A walk through `System`
//!
//! A [`System`] is built once from a confinement, a viscosity and the spheres, and
//! validated then; every method after that is infallible for the geometry (only the
//! arguments of a call can be wrong, each with its own typed error). Bad input is an
//! error, never a panic or a partial result:
//!
//! ```
//! use stokesian::{Confinement, InputError, Particle, System};
//!
//! let wall = Confinement::Wall { height: 0.0 }; // the plane x3 = 0, fluid above it
//! let below = vec![Particle { x: [0.0, 0.0, -1.0], a: 1.0 }];
//! let err = System::new(wall, 1.0, below, false).unwrap_err();
//! assert!(matches!(err, InputError::OutsideFluid { .. }));
//! ```
//!
//! The dense grand mobility (Eq. 1 layout, symmetric positive definite) and the same
//! product without the matrix, on SIMD lanes chosen at run time:
//!
//! ```
//! use stokesian::{check_spd, Confinement, Moments, Particle, System};
//!
//! let spheres = vec![
//!     Particle { x: [0.0, 0.0, 1.5], a: 1.0 },
//!     Particle { x: [3.0, 0.0, 2.0], a: 0.8 },
//! ];
//! let system = System::new(Confinement::Wall { height: 0.0 }, 1.0, spheres, false)?;
//! let m = system.mobility(Moments::FTS); // 22 x 22: all U, all Omega, all E
//! assert!(check_spd(&m).passed());
//! let f = [0.0, 0.0, -1.0, 0.0, 0.0, -1.0]; // forces on the fluid, particle-major
//! let u = system.apply(Moments::F, &f); // M f at F, matrix-free
//! assert!(u[2] < 0.0 && u[5] < 0.0); // both sink
//! # Ok::<(), stokesian::InputError>(())
//! ```
//!
//! Velocities of given forces and torques (and an imposed strain at FTS), from the
//! far-field mobility or from the resistance with lubrication (Eq. 19), which is also
//! available whole:
//!
//! ```
//! use stokesian::{Confinement, Lubrication, Moments, Particle, System};
//!
//! let spheres = vec![
//!     Particle { x: [0.0, 0.0, 1.2], a: 1.0 },
//!     Particle { x: [2.1, 0.0, 1.2], a: 1.0 },
//! ];
//! let system = System::new(Confinement::Wall { height: 0.0 }, 1.0, spheres, false)?;
//! let ft = [0.0, 0.0, -1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
//! let lub = Lubrication::default();
//! let far = system.velocities(Moments::FT, &ft, &[0.0; 5], None)?;
//! let near = system.velocities(Moments::FT, &ft, &[0.0; 5], Some(&lub))?;
//! assert!(near.u[2].abs() < far.u[2].abs()); // lubrication slows the approach to the wall
//! let r = system.resistance(Moments::FT, &lub)?; // 12 x 12, rows (F, L), columns (U, Omega)
//! assert_eq!(r.shape(), (12, 12));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Brownian dynamics: a whole seeded run, each kept frame handed to a callback:
//!
//! ```
//! use stokesian::{Brownian, Confinement, ExternalForces, Moments, Noise, Particle, Run};
//! use stokesian::{Scheme, System};
//!
//! let spheres = vec![Particle { x: [0.0, 0.0, 3.0], a: 1.0 }];
//! let system = System::new(Confinement::Wall { height: 0.0 }, 1.0, spheres, false)?;
//! let bd = Brownian {
//!     kt: 1.0,
//!     dt: 1e-3,
//!     drift: true, // kT div M: needed near a boundary
//!     forces: ExternalForces { weight: 1.0, strength: 20.0, debye: 0.1, trap: 0.0, torque: [0.0; 3] },
//!     noise: Noise::Cholesky,
//!     hydrodynamics: true,
//!     moments: Moments::F,
//!     scheme: Scheme::EulerMaruyama,
//!     lubrication: None,
//! };
//! let run = Run { steps: 100, every: 10, seed: 1, max_rejections: 10 };
//! let mut heights = Vec::new();
//! system.brownian_run(&bd, &run, |_, s, _| heights.push(s.particles()[0].x[2]))?;
//! assert_eq!(heights.len(), 11); // step 0 and every 10th
//! assert!(heights.iter().all(|&z| z > 1.0)); // always in the fluid
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
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
//!
//! No two modules import each other: `resistance::lubrication` forms the far-field
//! mobility through `System::mobility` (`mobility::assembly`), and
//! `mobility::velocity` solves that resistance when the velocities are lubricated, but
//! `mobility::assembly` and `mobility::tiled` know nothing of the resistance. The exact
//! two-body functions (series, tables and what generates the tables) are the crate
//! `resistance_functions`, re-exported in `resistance`.
//!
//! The types most callers need are re-exported here.

pub mod dynamics;
pub mod fmm;
pub mod linalg;
pub mod mobility;
pub mod periodic;
pub mod resistance;
pub mod studies;
pub mod system;

pub use dynamics::{
    rotate, Brownian, BrownianError, ExternalForces, LubricatedDynamics, Noise, Run, RunTally,
    Scheme, Step,
};
pub use fmm::{FastProduct, FmmError, Phases};
pub use kernels::lanes::Isa;
pub use kernels::{
    declaration, Boundary, Condition, Confinement, Declaration, Dimension, Param, ParamError,
    DECLARATIONS,
};
pub use linalg::{check_spd, lanczos_sqrt, LanczosError, SpdCheck};
pub use mobility::{
    solve_fts, strain_components, SingularStressletBlock, Velocities, VelocityError, MAX_CONDITION,
};
pub use periodic::{BoxLengths, PeriodicBox, PeriodicError};
pub use resistance::{
    solve_resistance, solve_resistance_fts, wall_functions, wall_near_contact, wall_series,
    Lubrication, ResistanceError, WallFunctions,
};
pub use system::input::{validate, InputError, Particle};
pub use system::overlap::{Overlap, OverlapError};
pub use system::{Moments, Precision, System};
