//! The generated kernels as the generator made them: its independent derivation paths
//! agree, the emitted code is the traced graph, the checks every confinement gets without
//! new code, the scene kernels are the full ones pruned, and the stiff cases keep their
//! accuracy.

mod confinements;
mod engine;
mod rotated;
mod scenes;
mod stiff_cases;
