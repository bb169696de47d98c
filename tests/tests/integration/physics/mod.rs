//! Physics every confinement must respect: reciprocity and positive definiteness of the
//! grand mobility, the divergence that drives the Brownian drift, and a plane of any
//! orientation as the wall turned.

mod divergence;
mod rotated_planes;
mod symmetry;
