//! Does nothing: it exists so that `[build-dependencies]` in `Cargo.toml` take part in
//! the build, aligning the features of the proc-macros' `syn` with the workspace's.

fn main() {}
