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

pub use blocks::{Grand, GrandCartesian, STRAIN_BASIS};

/// The confinement and its run-time parameters. The boundary is the plane
/// `x3 = height`, the fluid is `x3 > height` (for the slit, `height < x3 < height + gap`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Confinement {
    /// Unbounded fluid.
    Free,
    /// Plane no-slip wall (Blake's image, Eq. 5).
    Wall {
        /// Height of the wall.
        height: f64,
    },
    /// Flat non-deformable free surface (Eq. 21).
    FreeSurface {
        /// Height of the surface.
        height: f64,
    },
    /// Flat liquid-liquid interface with viscosity ratio `lambda` (Eq. 22).
    Interface {
        /// Height of the interface.
        height: f64,
        /// Viscosity of the other liquid over this one's.
        lambda: f64,
    },
    /// Two parallel walls, superposed single-wall images (Sec. IV approximation).
    Slit {
        /// Height of the lower wall.
        height: f64,
        /// Distance to the upper wall.
        gap: f64,
    },
}

/// `M^{ab}` for two distinct particles: the response of particle `a` (centre `xa`,
/// radius `aa`) to the force, torque and stresslet of particle `b`; viscosity `eta`.
pub fn pair(conf: &Confinement, eta: f64, xa: [f64; 3], aa: f64, xb: [f64; 3], ab: f64) -> Grand {
    use generated::*;
    match *conf {
        Confinement::Free => free::free_pair(xa, xb, aa, ab, eta),
        Confinement::Wall { height } => wall::wall_pair(xa, xb, aa, ab, eta, height),
        Confinement::FreeSurface { height } => {
            free_surface::free_surface_pair(xa, xb, aa, ab, eta, height)
        }
        Confinement::Interface { height, lambda } => {
            interface::interface_pair(xa, xb, aa, ab, eta, height, lambda)
        }
        Confinement::Slit { height, gap } => slit::slit_pair(xa, xb, aa, ab, eta, height, gap),
    }
}

/// `M^{ab}` for two distinct particles of the same radius `a` (the equal-radius
/// kernels, a little cheaper than [`pair`]).
pub fn pair_equal(conf: &Confinement, eta: f64, xa: [f64; 3], xb: [f64; 3], a: f64) -> Grand {
    use generated::*;
    match *conf {
        Confinement::Free => free::free_pair_equal(xa, xb, a, eta),
        Confinement::Wall { height } => wall::wall_pair_equal(xa, xb, a, eta, height),
        Confinement::FreeSurface { height } => {
            free_surface::free_surface_pair_equal(xa, xb, a, eta, height)
        }
        Confinement::Interface { height, lambda } => {
            interface::interface_pair_equal(xa, xb, a, eta, height, lambda)
        }
        Confinement::Slit { height, gap } => slit::slit_pair_equal(xa, xb, a, eta, height, gap),
    }
}

/// `M^{aa}`: the isolated sphere plus its reflected field (Eq. 17).
pub fn self_mobility(conf: &Confinement, eta: f64, x: [f64; 3], a: f64) -> Grand {
    use generated::*;
    match *conf {
        Confinement::Free => free::free_self(x, a, eta),
        Confinement::Wall { height } => wall::wall_self(x, a, eta, height),
        Confinement::FreeSurface { height } => free_surface::free_surface_self(x, a, eta, height),
        Confinement::Interface { height, lambda } => {
            interface::interface_self(x, a, eta, height, lambda)
        }
        Confinement::Slit { height, gap } => slit::slit_self(x, a, eta, height, gap),
    }
}
