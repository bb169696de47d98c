//! Closed forms and exact references: the free-space kernels against the literature's
//! closed forms, and the exact sphere-wall and two-sphere series of
//! `integration_tests::exact` against independent evaluations and published tables.

mod exact;
mod free_space;
