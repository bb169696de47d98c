//! The grand mobility and what is computed from it: the dense matrix in the layout of
//! Eq. 1 ([`assembly`]: `System::block`, `System::mobility`, `System::mobility_into`), the
//! matrix-free product in tiles of lane kernels whose sums do not depend on the number of
//! threads ([`tiled`]: `System::apply`, `System::apply_with`), the velocities of given
//! forces, torques and strain ([`velocity`]: `System::velocities`, the FTS mobility
//! problem [`solve_fts`]), and the grand mobility in a rotated frame ([`rotation`]: the
//! rotation taking `e3` to a plane's normal and its representation on `[U, Omega, E]`).

pub mod assembly;
pub mod rotation;
pub mod tiled;
pub mod velocity;

pub use velocity::{
    solve_fts, strain_components, SingularStressletBlock, Velocities, VelocityError, MAX_CONDITION,
};
