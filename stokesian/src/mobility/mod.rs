//! The grand mobility and what is computed from it: the dense matrix in the layout of
//! Eq. 1 ([`assembly`]: `System::block`, `System::mobility`, `System::mobility_into`), the
//! matrix-free product in tiles of lane kernels whose sums do not depend on the number of
//! threads ([`tiled`]: `System::apply`, `System::apply_with`), and the velocities of given
//! forces, torques and strain ([`velocity`]: `System::velocities`, the FTS mobility
//! problem [`solve_fts`]).

pub mod assembly;
pub mod tiled;
pub mod velocity;

pub use velocity::{
    solve_fts, strain_components, SingularStressletBlock, Velocities, VelocityError, MAX_CONDITION,
};
