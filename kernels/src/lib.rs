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

pub mod blocks;
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
pub use generated::{
    pair, pair_divergence, pair_divergence_lanes, pair_divergence_lanes_ordered, pair_equal,
    pair_f, pair_f_lanes_ordered, pair_ft, pair_ft_lanes_ordered, pair_lanes_ordered, product_f,
    product_f_lanes, product_f_lanes_ordered, product_ft, product_ft_lanes,
    product_ft_lanes_ordered, self_divergence, self_f, self_ft, self_mobility, Confinement,
};
pub use lanes;
