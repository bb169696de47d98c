//! Generated grand-mobility kernels for spheres in Stokes flow, unbounded and near
//! planar boundaries (Swan & Brady, Phys. Fluids 19, 113306, 2007).
//!
//! The functions in [`generated`] are produced by `cargo xtask gen` from the
//! `kernel-gen` crate and committed; this crate does not depend on the generator.
//! The typed entry points are [`pair`] and [`self_mobility`]: positions are
//! `[f64; 3]` with the boundary the plane `x3 = height` and the fluid above it; radii
//! and viscosity are dimensional, and so are the returned [`Grand`] blocks.
//!
//! ```
//! use kernels::{pair, self_mobility, Confinement};
//! let wall = Confinement::Wall { height: 0.0 };
//! let s = self_mobility(&wall, 1.0, [0.0, 0.0, 2.0], 1.0);
//! // Near a wall a sphere is slower than in bulk (1 / (6 pi eta a)):
//! assert!(s.uf[0][0] < 1.0 / (6.0 * std::f64::consts::PI));
//! let m = pair(&wall, 1.0, [0.0, 0.0, 2.0], 1.0, [3.0, 0.0, 2.0], 1.0);
//! assert!(m.uf[0][0] > 0.0);
//! ```
//!
//! The RPY overlap corrections ([`overlap_f`], [`overlap_ft`]: the Rotne-Prager-Yamakawa
//! form of two overlapping spheres minus the far form, which is the free-space part of
//! every pair kernel) are added by the solver to the pair kernels of overlapping spheres;
//! [`overlap_along`], [`pair_along`] and [`self_along`] differentiate the blocks along a
//! direction, for the drift of spheres held on a boundary.
//!
//! The truncated kernels ([`pair_f`], [`pair_ft`], [`self_f`], ...) return only the
//! blocks a truncation keeps, and the fused products ([`product_f`], [`product_ft`])
//! return a pair's contributions to both particles' velocities, `M^{ab} v_b` and
//! `M^{ba} v_a`, without forming the blocks. Each has a lane twin (`*_lanes`) that
//! evaluates [`lanes::Lane::WIDTH`] pairs at once, on the instruction set chosen at run
//! time: the caller's code is generic over the lane type, implements
//! [`lanes::WithLanes`] and runs through [`lanes::dispatch`]:
//!
//! ```
//! use kernels::lanes::{dispatch, Lane, WithLanes};
//! use kernels::{product_f, product_f_lanes, Confinement};
//!
//! /// The same pair in every lane; the first lane's result.
//! struct OnePair<'a>(&'a Confinement);
//!
//! impl WithLanes for OnePair<'_> {
//!     type Elem = f64;
//!     type Output = [f64; 6];
//!     #[inline(always)] // everything run with lanes inherits the target features
//!     fn run<L: Lane<Elem = f64>>(self) -> [f64; 6] {
//!         let s = L::splat;
//!         let out = product_f_lanes(
//!             self.0,
//!             1.0,
//!             [s(0.0), s(0.0), s(2.0)],
//!             s(1.0),
//!             [s(3.0), s(0.0), s(2.5)],
//!             s(0.8),
//!             [s(0.0), s(0.0), s(-1.0)],
//!             [s(1.0), s(0.0), s(0.0)],
//!         );
//!         let mut lane = vec![0.0; L::WIDTH];
//!         out.map(|v| {
//!             v.store(&mut lane);
//!             lane[0]
//!         })
//!     }
//! }
//!
//! let wall = Confinement::Wall { height: 0.0 };
//! let lanes = dispatch(OnePair(&wall));
//! let scalar = product_f(&wall, 1.0, [0.0, 0.0, 2.0], 1.0, [3.0, 0.0, 2.5], 0.8,
//!                        [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]);
//! // The lane kernels round differently from the scalar ones (fused multiply-adds,
//! // reciprocal square roots): they agree to a few ulps of the largest entry, and
//! // 1e-13 of it bounds that with room on every instruction set.
//! let scale = scalar.a.iter().chain(&scalar.b).fold(0.0f64, |m, v| m.max(v.abs()));
//! for (l, s) in lanes.iter().zip(scalar.a.iter().chain(&scalar.b)) {
//!     assert!((l - s).abs() <= 1e-13 * scale);
//! }
//! ```

/// The blocks the kernels return, their layouts and conversions (crate `kernel-blocks`).
pub use kernel_blocks as blocks;
pub mod declare;
pub mod expansion;
pub mod turn;
#[rustfmt::skip]
#[allow(clippy::all, missing_docs)]
pub mod generated;
/// Single-precision FTS self and pair kernels (`family_self`, `family_pair`, returning
/// [`single::Grand32`]), generated with the others; only with the cargo feature `f32`.
#[cfg(feature = "f32")]
#[rustfmt::skip]
#[allow(clippy::all, missing_docs)]
#[path = "generated/single.rs"]
pub mod single;

pub use blocks::{
    basis_both, basis_cols, basis_rows, grand_lanes_product, lane_by_lane, BlocksF, BlocksFT,
    Drift, Grand, GrandCartesian, Product, STRAIN_BASIS,
};
pub use declare::{
    along, declaration, readable, Boundary, Condition, Declaration, Dimension, Param, ParamError,
};
pub use generated::overlap::{overlap_along, overlap_f, overlap_ft};
pub use generated::{
    pair, pair_along, pair_divergence, pair_divergence_lanes, pair_divergence_lanes_ordered,
    pair_equal, pair_f, pair_f_lanes_ordered, pair_ft, pair_ft_lanes_ordered, pair_lanes_ordered,
    product_f, product_f_lanes, product_f_lanes_ordered, product_ft, product_ft_lanes,
    product_ft_lanes_ordered, self_along, self_divergence, self_f, self_ft, self_mobility,
    Confinement, DECLARATIONS,
};
pub use lanes;
