//! kernel-gen: turns Green's functions of Stokes flow into flat Rust kernels for the
//! grand mobility tensor of spheres (Swan & Brady, Phys. Fluids 19, 113306, 2007).
//!
//! The layers, in the order the data flows through them:
//!
//! 1. [`number`]: the [`Scalar`](number::scalar::Scalar) trait every evaluator shares,
//!    double-double, forward-mode multivariate Taylor arithmetic (jets) and sparse
//!    polynomials in a unit vector.
//! 2. [`graph`]: the hash-consed expression graph that `Scalar` arithmetic on its nodes
//!    records, its folding rules and passes, operation counts and interpreter.
//! 3. [`physics`]: the Green's functions (generic over the scalar); their derivatives
//!    by jets (the structured path, with the image chain rules of Eq. 10, or the generic
//!    six-variable path) or by finite differences; the operators that combine the
//!    derivatives into blocks (the multipole expansion at the source, Eq. 8; the Faxén
//!    laws at the field point, Eqs. 12-15); the canonical frame of a pair; the lateral
//!    far field and the closed-form self image.
//! 4. [`kernel`]: what one kernel computes ([`kernel::KernelSpec`]) and its tracing
//!    into a graph with named inputs and block-shaped outputs ([`kernel::trace`]), the
//!    exchange of the particles' roles, and the direct evaluation in any scalar.
//! 5. [`emit`]: a traced kernel as straight-line Rust (via proc-macro2, quote and
//!    prettyplease), scalar and in lanes.
//! 6. [`catalog`]: which kernels are generated (every Green's function's family, the
//!    scenes of `scenes/`), the `Confinement` dispatch, and the files `cargo xtask gen`
//!    writes.

pub mod number;

pub mod graph;

pub mod physics;

pub mod kernel;

pub mod emit;

pub mod catalog;
