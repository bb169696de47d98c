//! What a kernel computes.

use crate::physics::operators::{max_order, Basis, Moment, Response};

/// Self (`alpha = alpha`, Eq. 17) or pair (Eq. 16) interaction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interaction {
    /// One particle with the reflected field of itself.
    SelfTerm,
    /// Two distinct particles.
    Pair,
}

/// How the derivatives are obtained.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Path {
    /// Jets of the Stokeslet in `r` and of each image term in `R`, Eq. 10 (production).
    Structured,
    /// The same, but the Stokeslet and its image summed directly, without the exactly
    /// evaluated difference ([`Structured::direct_sum`]) and without the generator's
    /// other branches: the reference of the stiff cases, and their "before".
    ///
    /// [`Structured::direct_sum`]: crate::physics::derivatives::Structured::direct_sum
    StructuredDirectSum,
    /// The same, but the image is differentiated as a function of `x - y'` only
    /// (Bossis et al.; wrong, asymmetric: Sec. III A).
    StructuredNoExplicitHeight,
    /// Jets of the whole `G(x, y)` in six variables.
    Generic,
}

/// One kernel to trace.
#[derive(Clone, Debug)]
pub struct KernelSpec {
    /// Self or pair.
    pub interaction: Interaction,
    /// Strain/stresslet representation.
    pub basis: Basis,
    /// One radius `a` for both particles (pair kernels only).
    pub equal_radii: bool,
    /// The blocks to compute, in output order.
    pub blocks: Vec<(Response, Moment)>,
    /// Derivative path.
    pub path: Path,
    /// Instead of the blocks, the fused symmetric pair product: inputs `va`, `vb` (the
    /// moments of particles a and b, `[F, L, S]` truncated to the blocks' moments) and
    /// outputs `a = M^{ab} vb`, `b = M^{ba} va = (M^{ab})^T va` (pair kernels only).
    pub product: bool,
    /// Instead of the blocks, a derivative of them over the particle positions
    /// ([`Drift`]), by the same derivative path run on jets of degree 1 in the
    /// positions whose coefficients are expression nodes.
    pub drift: Option<Drift>,
}

/// The derivatives of the blocks over the positions that a drift kernel computes, over
/// the force columns, rows `U` then `Omega` as kept (F: 3, FT: 6); for pairs `a` (the
/// derivative of `M^{ab}` over the source position `xb`) and `b` (that of `M^{ba} =
/// (M^{ab})^T`, with `M^{ba}_{OmegaF} = (M^{ab}_{UL})^T`, over `xa`); for a self term
/// the derivative over the one position, both arguments moving together.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Drift {
    /// The divergence, the Brownian drift `kT div M`: `a_i = sum_j d/dxb_j M^{ab}_{ij}`.
    Divergence,
    /// The derivative along a unit vector `v` (an argument of the kernel) of the column
    /// along `v`: `a_i = sum_jk v_j v_k d/dxb_k M^{ab}_{ij}`. The part of the divergence
    /// that holding a sphere's centre on a plane of normal `v` removes: the drift of
    /// spheres damped at a boundary (`stokesian`'s overlap treatment).
    Along,
    /// The derivative along a unit vector `v` of the column along `v` with both points
    /// moving together, `a_i = sum_jk v_j v_k d/dt M^{ab}_{ij}(xa + t v, xb + t v)`: on a
    /// sphere and one of its own periodic images (`xb = xa + n L`), that image's part of
    /// the derivative of the sphere's self mobility (its drift in a periodic box).
    Together,
}

impl KernelSpec {
    /// Highest derivative order of `G` that the blocks' operators need.
    pub fn order(&self) -> usize {
        self.blocks
            .iter()
            .map(|&(r, m)| max_order(r, m))
            .max()
            .unwrap_or(0)
    }
}
