//! Overlapping spheres the RPY way ([`stokesian::Overlap::Rpy`]): the generated overlap
//! corrections against a quadrature of the RPY definition and the closed forms of the
//! literature (`forms`); the solver's use of them (`system`): symmetric positive-definite
//! mobilities of overlapping clusters, the damping near boundaries, the same bits as
//! before where nothing overlaps, and the typed errors of what the forms do not cover.

mod drift;
mod forms;
mod system;
