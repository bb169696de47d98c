//! Linear algebra on the solver's matrices: the dense algebra through faer ([`dense`]:
//! Cholesky, triangular solves and products, matrix-vector products, the large matrices
//! the command line writes, the symmetric positive-definite check) and the Lanczos square
//! root ([`lanczos`]).

pub mod dense;
pub mod lanczos;

pub use dense::{check_spd, mul_vec, Cholesky, LargeMatrix, SpdCheck};
pub use lanczos::{lanczos_sqrt, LanczosError};
