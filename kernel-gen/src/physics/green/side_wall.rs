//! A plane no-slip wall normal to `e1`, the side wall of a channel: `x1 = side`, the
//! fluid at `x1 > side`. Blake's image (Eq. 5) written for the plane `x3' = side` in
//! the wall's own frame `Q` (rows `e2, e3, e1`, [`super::frame`]) and rotated back,
//! `J^w(x, y) = Q^T J^w_Blake(Q x, Q y) Q`; its image terms are the wall's, in that
//! frame. Any other unit normal serves the same way: change [`NORMAL`].

use super::wall::{blake, blake_terms};
use super::{
    frame, in_frame, Boundary, Condition, Dimension, Green, ImageTerm, Mat3, Param, Plane,
};
use crate::number::scalar::Scalar;

/// The side wall.
pub struct SideWall;

/// The wall's unit normal, into the fluid.
pub const NORMAL: [f64; 3] = [1.0, 0.0, 0.0];

impl Green for SideWall {
    fn name(&self) -> &'static str {
        "side_wall"
    }
    fn title(&self) -> &'static str {
        "plane no-slip side wall at x1 = side: Stokeslet plus Blake's image in the wall's frame"
    }
    fn params(&self) -> &'static [Param] {
        &[Param {
            name: "side",
            doc: "position s of the side wall x1 = s (the fluid is x1 > s)",
            dimension: Dimension::Position(NORMAL),
            default: Some(0.0),
            example: -0.4,
        }]
    }
    fn reflected<S: Scalar>(&self, x: &[S; 3], y: &[S; 3], p: &[S]) -> Mat3<S> {
        in_frame(&frame(NORMAL), x, y, |x, y| blake(x, y, &p[0]))
    }
    fn image_terms(&self) -> Option<Vec<ImageTerm>> {
        Some(blake_terms(0, 0))
    }
    fn mirrors<S: Scalar>(&self, p: &[S]) -> Vec<Plane<S>> {
        vec![Plane {
            normal: NORMAL,
            offset: p[0].clone(),
        }]
    }
    fn boundaries<S: Scalar>(&self, p: &[S]) -> Vec<Boundary<S>> {
        let [plane] = self.mirrors(p).try_into().expect("one mirror");
        vec![Boundary::exact(plane, Condition::NoSlip)]
    }
    /// Blake's image is invariant under rotations about the wall's normal and
    /// translations along the wall.
    fn axisymmetric(&self) -> bool {
        true
    }
    /// A source on the wall has no effect: at `n.y = side`, `R = r` and `J^w = -J(R)`.
    fn cancelling_image(&self) -> Option<(usize, usize)> {
        Some((0, 0))
    }
}
