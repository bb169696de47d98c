//! The benchmarks of the performance table live in `benches/mobility.rs` (criterion):
//! `cargo bench -p stokesian-benches`, or `cargo xtask bench`, which rewrites the table
//! in `docs/performance.md`. This library is empty.
