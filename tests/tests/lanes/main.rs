//! The lane kernels and the tiled product built on them: lanes equal the scalar kernels on
//! every instruction set, the tiled product equals the dense matrix whatever the number of
//! threads, and the single-precision product with the change of units it rests on.
//!
//! A test binary of its own: `scalar` instantiates every lane kernel of every
//! confinement for every instruction set and precision, most of what the tests compile,
//! and compiles alongside `tests/tests/integration`. Run one module by its path, e.g.
//! `cargo test --workspace --release -- scalar:: --nocapture`.

mod layout;
mod scalar;
mod single_precision;
mod tiled_product;
