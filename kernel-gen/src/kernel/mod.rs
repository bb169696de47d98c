//! One kernel: what it computes ([`KernelSpec`]: which blocks, self or pair, in which
//! strain basis, for equal or unequal radii, by which derivative path; or the fused pair
//! product, or the divergence) and its tracing ([`trace()`]) into an expression graph
//! with named inputs and block-shaped outputs ([`Traced`]).
//!
//! Pair kernels (particles `a != b`) are `M^{ab}` from `G = J + J^w` (Eq. 16); self
//! kernels are the isolated sphere plus the reflected field only (Eq. 17). All blocks
//! are dimensional: the Green's functions in units of `1/(8 pi eta)` are scaled by
//! `1/(8 pi eta)` as the last step.
//!
//! - `spec`: [`KernelSpec`], [`Interaction`], [`Path`];
//! - `blocks`: every entry of a kernel's blocks, generic over the scalar (expression
//!   nodes for the kernels, jets of them for the divergences, double-double for the
//!   direct evaluation);
//! - `product`: the fused pair product `a = M^{ab} vb`, `b = M^{ba} va`;
//! - `divergence`: the divergence of the blocks over the positions (Brownian drift);
//! - `trace`: [`trace()`], the kernel traced in every form and the cheapest kept, with its
//!   far-field or closed-form branch and the exchange of roles;
//! - `traced`: [`Traced`], its arguments, outputs and branches, and its evaluation by
//!   the interpreter as the emitted code evaluates it;
//! - `swap`: [`Swap`], the exchange of the particles' roles near a cancelling image;
//! - `direct`: [`evaluate_direct`], the direct sum straight in any scalar (the stiff
//!   cases' reference).

mod blocks;
mod direct;
mod divergence;
mod product;
mod spec;
mod swap;
mod trace;
mod traced;

pub use direct::evaluate_direct;
pub use spec::{Drift, Interaction, KernelSpec, Path};
pub use swap::Swap;
pub use trace::{trace, trace_in_frame};
pub use traced::{Arg, ArgKind, BlockOut, FarBranch, Traced};
