//! The single-precision lanes: the `f32` lane kernels equal the scalar `f64` kernels to
//! single precision on every instruction set, and the single-precision product with the
//! change of units it rests on; `ewald`: the `f32` lanes of the building block
//! `ewald_real` (not a confinement).
//!
//! A test binary of its own, the twin of `tests/lanes` (the `f64` lanes): each
//! instantiates every lane kernel of every confinement for every instruction set in its
//! own element, and the two compile in parallel. Run one module by its path, e.g.
//! `cargo test --workspace --release -- single_precision:: --nocapture`.

mod ewald;
mod scalar;
mod single_precision;
