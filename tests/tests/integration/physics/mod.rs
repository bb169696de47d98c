//! Physics every confinement must respect: reciprocity and positive definiteness of the
//! grand mobility, and the divergence that drives the Brownian drift.

mod divergence;
mod symmetry;
