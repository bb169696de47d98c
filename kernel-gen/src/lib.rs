//! kernel-gen: turns Green's functions of Stokes flow into flat Rust kernels for the
//! grand mobility tensor of spheres (Swan & Brady, Phys. Fluids 19, 113306, 2007).
//!
//! Data flow: [`green`] (a Green's function, generic over [`scalar::Scalar`]) ->
//! [`jet`] (forward-mode multivariate Taylor arithmetic) over [`expr`] (a hash-consed
//! expression graph) -> [`operators`] (multipole expansion at the source, Eq. 8;
//! Faxén laws at the field point, Eqs. 12-15; the image chain rule, Eq. 10) ->
//! [`emit`] (straight-line Rust via proc-macro2, quote and prettyplease).

pub mod catalog;
pub mod dd;
pub mod derivatives;
pub mod emit;
pub mod expr;
pub mod farfield;
pub mod fd;
pub mod frame;
pub mod green;
pub mod jet;
pub mod operators;
pub mod poly;
pub mod scalar;
pub mod scene;
pub mod self_image;
