//! The mathematics of the grand mobility: what is differentiated, how, and what the
//! derivatives are combined into.
//!
//! [`green`] holds the Green's functions `G = J + J^w` (Eqs. 4, 5, 21, 22 and the
//! two-wall superposition), generic over the scalar. [`derivatives`] obtains the
//! derivatives `d_x^alpha d_y^beta G_ij` by Taylor jets: the structured path (the
//! Stokeslet in `r`, each image term in `R` by the chain rules of Eq. 10) or the generic
//! six-variable path; [`fd`] takes them by finite differences in double-double, the
//! reference independent of the jets. [`operators`] combines them into the blocks of
//! the grand mobility (the multipole expansion at the source, Eq. 8; the Faxén laws at
//! the field point, Eqs. 12-15). [`frame`] is the canonical frame of a pair, in which
//! the kernels of axisymmetric confinements are traced; [`farfield`] and [`self_image`]
//! are the expansions that replace the direct sum where it cancels (pairs far apart
//! along a wall; a sphere's own image). [`overlap`] holds the Rotne-Prager-Yamakawa
//! forms of overlapping spheres, whose difference from the far form is the overlap
//! correction.

pub mod derivatives;
pub mod farfield;
pub mod fd;
pub mod frame;
pub mod green;
pub mod operators;
pub mod overlap;
pub mod potential;
pub mod self_image;
