//! A Green's function seen from the frame of its mirror planes.
//!
//! A confinement whose mirror planes share one unit normal `n` and which is invariant
//! under rotations about `n` and translations along its planes ([`Green::axisymmetric`])
//! is, in the frame `Q` of its planes ([`frame`]: rows `t1, t2, n`), a confinement of
//! planes normal to `e3`:
//!
//! `G'(x', y') = Q G(Q^T x', Q^T y') Q^T`, `x' = Q x`.
//!
//! Its image terms are already written in the planes' own frame, so in `Q`'s frame they
//! are the same terms across planes `x3' = offset`. [`turn`] says when a Green's function
//! is such a confinement and gives `Q`; [`Turned`] is `G'`. The kernels of `G` are then
//! those of `G'` with the points and moments rotated in and the responses (or blocks)
//! rotated out ([`crate::kernel`]): `M = Q^T M' Q` on forces and torques, `Q_5^T` and
//! `Q_5` on strains. The pair kernels of `G'` take the canonical frame and the lateral
//! far field of a plane normal to `e3`, so a side wall costs what the wall costs (a
//! signed permutation `Q` folds to relabelled inputs and outputs) and keeps its
//! precision far along its plane.

use super::{clean, examples, frame, in_frame, Boundary, Green, ImageTerm, Mat3, Param, Plane, E3};
use crate::number::scalar::Scalar;

/// The frame `Q` of `g`'s mirror planes where `g` is axisymmetric about their common
/// normal and that normal is not `e3`; `None` otherwise (a Green's function of planes
/// normal to `e3`, or of planes of several orientations, is traced as it is).
pub fn turn<G: Green>(g: &G) -> Option<Mat3<f64>> {
    let p = examples(g);
    let mirrors = g.mirrors(&p);
    let n = mirrors.first()?.normal;
    (g.axisymmetric() && n != E3 && mirrors.iter().all(|m| m.normal == n)).then(|| frame(n))
}

/// `g` in the frame `q` of its planes (see the module documentation).
pub struct Turned<'g, G> {
    /// The Green's function in the world frame.
    pub g: &'g G,
    /// The frame: rows `t1, t2, n`.
    pub q: Mat3<f64>,
}

impl<G> Turned<'_, G> {
    /// A plane of the world in the frame: its normal `Q n`, its offset unchanged.
    fn plane<S>(&self, p: Plane<S>) -> Plane<S> {
        let normal =
            std::array::from_fn(|k| clean((0..3).map(|j| self.q[k][j] * p.normal[j]).sum()));
        Plane {
            normal,
            offset: p.offset,
        }
    }
}

impl<G: Green> Green for Turned<'_, G> {
    fn name(&self) -> &'static str {
        self.g.name()
    }
    fn title(&self) -> &'static str {
        self.g.title()
    }
    fn params(&self) -> &'static [Param] {
        self.g.params()
    }
    /// `Q J^w(Q^T x', Q^T y') Q^T`.
    fn reflected<S: Scalar>(&self, x: &[S; 3], y: &[S; 3], p: &[S]) -> Mat3<S> {
        let qt: Mat3<f64> = std::array::from_fn(|i| std::array::from_fn(|j| self.q[j][i]));
        in_frame(&qt, x, y, |x, y| self.g.reflected(x, y, p))
    }
    fn image_terms(&self) -> Option<Vec<ImageTerm>> {
        self.g.image_terms()
    }
    fn mirrors<S: Scalar>(&self, p: &[S]) -> Vec<Plane<S>> {
        self.g
            .mirrors(p)
            .into_iter()
            .map(|m| self.plane(m))
            .collect()
    }
    fn boundaries<S: Scalar>(&self, p: &[S]) -> Vec<Boundary<S>> {
        self.g
            .boundaries(p)
            .into_iter()
            .map(|b| Boundary {
                plane: self.plane(b.plane),
                ..b
            })
            .collect()
    }
    fn weights<S: Scalar>(&self, p: &[S]) -> Vec<S> {
        self.g.weights(p)
    }
    fn cancelling_image(&self) -> Option<(usize, usize)> {
        self.g.cancelling_image()
    }
    fn axisymmetric(&self) -> bool {
        self.g.axisymmetric()
    }
    fn image_extra_order(&self) -> usize {
        self.g.image_extra_order()
    }
}
