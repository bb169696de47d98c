//! The lane kernels and the tiled product built on them: the `f64` lanes equal the scalar
//! kernels on every instruction set, and the tiled product equals the dense matrix
//! whatever the number of threads (the `f32` lanes: `tests/lanes_single`); `ewald`
//! checks the lane kernels of the building block `ewald_real` (not a confinement).
//!
//! A test binary of its own: `scalar` instantiates every lane kernel of every
//! confinement for every instruction set in `f64`, most of what the tests compile, and
//! compiles alongside `tests/lanes_single`. Run one
//! module by its path, e.g. `cargo test --workspace --release -- scalar:: --nocapture`.

mod ewald;
mod layout;
mod scalar;
mod tiled_product;
