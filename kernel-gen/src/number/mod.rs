//! The numbers the generator computes with, all behind one trait.
//!
//! [`scalar::Scalar`] is the arithmetic a Green's function, a jet and an operator need;
//! it is implemented by `f64` (spot values), by the double-double [`dd::Dd`] (the
//! reference precision), by the expression nodes of [`crate::graph`] (tracing), by the
//! truncated Taylor series [`jet::Jet`] over any of these (derivatives), and by the
//! sparse polynomials [`poly::Poly`] in a symbolic unit vector (derivatives of the
//! potentials in closed form).

pub mod dd;
pub mod jet;
pub mod poly;
pub mod scalar;
