//! The generated kernels as the generator made them: its independent derivation paths
//! agree, the emitted code is the traced graph, the checks every confinement gets without
//! new code, the scene kernels are the full ones pruned, the stiff cases keep their
//! accuracy, and the building block `ewald_real` (not a confinement) is checked on its
//! own.

mod confinements;
mod engine;
mod ewald;
mod rotated;
mod scenes;
mod stiff_cases;
