//! The generated kernels as the generator made them: its independent derivation paths
//! agree, the emitted code is the traced graph, the checks every confinement gets without
//! new code, the scene kernels are the full ones pruned, the stiff cases keep their
//! accuracy, and the building blocks `ewald_real` and `ewald_wall` (not confinements)
//! are checked on their own.

mod confinements;
mod engine;
mod ewald;
mod ewald_wall;
mod rotated;
mod scenes;
mod stiff_cases;
