//! The generator's own tests, a module per module of `kernel-gen` (`number_jet` tests
//! `kernel_gen::number::jet`, and so on). As unit tests (`#[cfg(test)]` modules) they
//! made `cargo test` compile the whole generator a second time with `cfg(test)`; as a
//! binary of their own, the generic code they instantiate (tracing, the derivative
//! paths) a second time beside this binary's (`kernel-gen/Cargo.toml`). Run one module
//! or test by its path, e.g. `cargo test --release -p integration-tests --
//! generator::number_jet`.

mod catalog;
mod catalog_scene;
mod catalog_scene_file;
mod emit_fusion;
mod emit_tokens;
mod graph;
mod graph_elementary;
mod graph_folding;
mod graph_interpret;
mod graph_lane_form;
mod graph_powers_of_two;
mod graph_squares;
mod number_dd;
mod number_jet;
mod number_poly;
mod physics_derivatives;
mod physics_derivatives_generic;
mod physics_derivatives_structured;
mod physics_fd;
mod physics_green_ewald;
mod physics_green_ewald_wall;
mod physics_operators;
mod physics_overlap;
mod physics_potential;
