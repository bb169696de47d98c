//! The types of a confinement's far field for a fast multipole method (the tables are
//! generated: `generated/potential.rs`, from `kernel_gen::physics::potential`).
//!
//! Every pair kernel's far form (the Stokeslet and its images under the multipole
//! functional at the source, Eq. 8) is a sum of derivatives of the one potential
//! `phi(r) = |r|`: row `k` of `G` applied to the moments of a source at `y` with radius
//! `a` is
//!
//! `Psi_k(x) = sum_s coef w[weight] h^h_power a^(2 a2) m[moment] d_x^d phi(x - y_point)`
//!
//! over the [`PotentialSource`]s `s` with `channel = k`, `y_point` the source or its
//! image in a [`Mirror`] (`y* = y - 2 h n`, `h = n . y - offset`). The velocity is then
//! the Faxén functional of the field point applied to `Psi` (`(1 + a^2/6 lap) Psi`, the
//! rotation `1/2 curl Psi`), in units of `1/(8 pi eta)`.

/// One derivative source of the potential `|r|` (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PotentialSource {
    /// The row of `G` (the velocity component) it adds to.
    pub channel: usize,
    /// The moment component it carries (forces `0..3`, torques `3..6`).
    pub moment: usize,
    /// 0: at the source; `1 + k`: at its image in mirror `k`.
    pub point: usize,
    /// Index into the confinement's image weights (unused at the source).
    pub weight: usize,
    /// Power of the source's distance `h` from the mirror (0 at the source).
    pub h_power: u8,
    /// Power of the source's squared radius.
    pub a2: u8,
    /// Derivative multi-index in the field point (world frame).
    pub d: [u8; 3],
    /// Coefficient (the Faxén factors included).
    pub coef: f64,
}

/// A mirror plane `n . x = offset` of the image points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mirror {
    /// Unit normal (into the fluid).
    pub normal: [f64; 3],
    /// `n . x` on the plane.
    pub offset: f64,
}

impl Mirror {
    /// The signed distance `n . y - offset` of `y`.
    pub fn distance(&self, y: [f64; 3]) -> f64 {
        self.normal[0] * y[0] + self.normal[1] * y[1] + self.normal[2] * y[2] - self.offset
    }

    /// The image `y - 2 h n` of `y`.
    pub fn image(&self, y: [f64; 3]) -> [f64; 3] {
        let h = self.distance(y);
        std::array::from_fn(|k| y[k] - 2.0 * h * self.normal[k])
    }
}

/// Why a confinement has no expansion in derivative sources.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoExpansion {
    /// Its Green's function declares its reflected field as ordinary Rust only, without
    /// image terms.
    NoImageTerms,
    /// Its terms are derivatives of another potential than the Stokeslet's.
    OtherPotential,
}

impl std::fmt::Display for NoExpansion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            NoExpansion::NoImageTerms => write!(
                f,
                "its Green's function has no image terms (Green::image_terms), so it has no expansion in sources at image points"
            ),
            NoExpansion::OtherPotential => write!(
                f,
                "its Green's function is made of another potential than the Stokeslet's |r|"
            ),
        }
    }
}

impl std::error::Error for NoExpansion {}

pub use crate::generated::potential::RADIAL;
