//! The resistance with lubrication, Swan & Brady Eq. 19:
//! `R = M^-1 + R^P + R^W - (R^{P,inf} + R^{W,inf})` ([`lubrication`]: its settings, its
//! assembly `System::resistance` and its solves), and the exact resistance functions it
//! is built from, the modules of the crate `resistance_functions` re-exported here:
//!
//! - one sphere near a plane wall: the bispherical series ([`exact`]), the generated
//!   tables of them ([`wall_tables`]) and the five functions at any gap
//!   ([`sphere_wall`]);
//! - two spheres: the twin-multipole series at any separation and size ratio
//!   ([`two_sphere`]) and the generated tables of them ([`pair_tables`]);
//! - the resistance tensors of both from their scalar functions ([`tensors`]).

pub mod lubrication;

pub use resistance_functions::{exact, pair_tables, sphere_wall, tensors, two_sphere, wall_tables};

pub use lubrication::{solve_resistance, solve_resistance_fts, Lubrication, ResistanceError};
pub use sphere_wall::{wall_functions, wall_near_contact, wall_series, WallFunctions};
