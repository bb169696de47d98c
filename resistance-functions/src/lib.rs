//! resistance-functions: the exact resistance functions of the two bodies that
//! lubrication is built from, and the resistance tensors made of them (Swan & Brady
//! Eq. 19 takes `R^P` and `R^W` from these):
//!
//! - one sphere near a plane wall: the bispherical series ([`exact`]), the generated
//!   tables of them ([`wall_tables`]) and the five functions at any gap
//!   ([`sphere_wall`]);
//! - two spheres: the twin-multipole series at any separation and size ratio
//!   ([`two_sphere`]) and the generated tables of them ([`pair_tables`]);
//! - the resistance tensors of both from their scalar functions ([`tensors`]);
//! - [`generate`]: what `cargo xtask gen` writes into `src/generated/` (the tables and
//!   coefficients), used at generation time only.
//!
//! Each module uses only those listed before it (the tables read the series' closed
//! forms, never the other way; what makes the tables from the series is [`generate`]).
//! The solver (`stokesian::resistance`) re-exports these modules and assembles the
//! resistance of many spheres from them; this crate knows nothing of a system of
//! spheres, which is why its unit tests build without the solver's lane kernels.

pub mod exact;
pub mod generate;
pub mod pair_tables;
pub mod sphere_wall;
pub mod tensors;
pub mod two_sphere;
pub mod wall_tables;

pub use sphere_wall::{wall_functions, wall_near_contact, wall_series, WallFunctions};
