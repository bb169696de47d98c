//! The generated kernels' bodies: the self, pair and product kernels of every family
//! (one per registered Green's function) and scene (`scenes/`), the RPY overlap
//! corrections and (feature `f32`) the single-precision kernels, written by `cargo xtask
//! gen` into `kernels/src/generated/` and compiled here. Use them through the `kernels` crate, which re-exports each module under
//! `kernels::generated` and dispatches on its `Confinement`.
//!
//! A crate of their own so that their lints can be allowed crate-wide: the compiler then
//! skips the lint passes over them, where a module-level `allow` (as the generated code
//! always had) only hides the lints' output after running them. Over these long
//! straight-line functions those passes took about 30 of the 45 seconds of `cargo clippy`
//! on the kernels. Nothing is linted less than before: the generated code was never
//! linted; the generator's own code is.
#![allow(clippy::all, missing_docs)]

/// The blocks the kernels return (`crate::blocks` in the generated code).
pub use kernel_blocks as blocks;

#[rustfmt::skip]
#[path = "../../src/generated/bodies.rs"]
mod generated;

pub use generated::*;
