//! The tests of `cargo xtask`'s tasks, one binary linking the `xtask` library that `cargo
//! xtask` compiled: argument parsing and registration of `check-green`, the size budget's
//! message, the performance table's formatting and rewriting, and a reduced report.

mod bench;
mod budget;
mod check_green;
mod report;
