//! The integration tests, one binary with a module per theme: each theme checks one part
//! of the solver or the generator against an independent reference. The shared helpers
//! and the references themselves (configurations, closed forms, the paper's appendices,
//! exact series, statistics, the stiff cases) live in the `integration_tests` library
//! (`tests/src`).
//!
//! One binary links once where one per file linked 24 times; the lane kernels' tests are
//! in the package `lane-tests` (built without optimisation), so that their instantiation
//! of every lane kernel on every instruction set compiles quickly and alongside this one.
//! Run one theme, one file or one test by its path, e.g.
//! `cargo test --workspace --release -- two_sphere::exact::cost --nocapture`.

mod bad_input;
mod brownian;
mod fmm;
mod generated;
mod generator;
mod linalg;
mod lubrication;
mod overlap;
mod paper;
mod periodic;
mod physics;
mod references;
mod two_sphere;
