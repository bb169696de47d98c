//! A corner: the fluid above the floor `x3 = height` and beside the side wall
//! `x1 = side` (`x3 > height`, `x1 > side`), both no slip. Written as the superposition
//! of the two walls' Blake image systems (Eq. 5): the floor's, and the side wall's in its
//! own frame `Q` (rows `e2, e3, e1`, [`super::frame`]) rotated back,
//! `J^w(x, y) = J^w_Blake(x, y; height) + Q^T J^w_Blake(Q x, Q y; side) Q`.
//! Like the slit's, this is an approximation: each wall's image violates the other
//! wall's no slip, and the boundaries say so (`exact: false`).
//!
//! Not part of the registry: `cargo xtask check-green docs/examples/corner.rs` tries it
//! in a scratch copy of the workspace (docs/generator.md, "Trying a Green's function").

use super::wall::{blake, blake_terms};
use super::{
    frame, in_frame, Boundary, Condition, Dimension, Green, ImageTerm, Mat3, Param, Plane,
};
use crate::number::scalar::Scalar;

/// The corner of a floor and a side wall.
pub struct Corner;

/// The side wall's unit normal, into the fluid.
const SIDE: [f64; 3] = [1.0, 0.0, 0.0];

impl Green for Corner {
    fn name(&self) -> &'static str {
        "corner"
    }
    fn title(&self) -> &'static str {
        "corner of the floor x3 = height and the side wall x1 = side: the two walls' Blake images superposed"
    }
    fn params(&self) -> &'static [Param] {
        &[
            Param::HEIGHT,
            Param {
                name: "side",
                doc: "position s of the side wall x1 = s (the fluid is x1 > s)",
                dimension: Dimension::Position(SIDE),
                default: Some(0.0),
                example: -0.4,
            },
        ]
    }
    fn reflected<S: Scalar>(&self, x: &[S; 3], y: &[S; 3], p: &[S]) -> Mat3<S> {
        let floor = blake(x, y, &p[0]);
        let side = in_frame(&frame(SIDE), x, y, |x, y| blake(x, y, &p[1]));
        std::array::from_fn(|i| std::array::from_fn(|l| floor[i][l].clone() + side[i][l].clone()))
    }
    fn image_terms(&self) -> Option<Vec<ImageTerm>> {
        let mut t = blake_terms(0, 0);
        t.extend(blake_terms(1, 0));
        Some(t)
    }
    fn mirrors<S: Scalar>(&self, p: &[S]) -> Vec<Plane<S>> {
        vec![
            Plane::horizontal(p[0].clone()),
            Plane {
                normal: SIDE,
                offset: p[1].clone(),
            },
        ]
    }
    /// Each wall's image violates the other wall's no slip: neither holds exactly.
    fn boundaries<S: Scalar>(&self, p: &[S]) -> Vec<Boundary<S>> {
        self.mirrors(p)
            .into_iter()
            .map(|plane| Boundary {
                plane,
                condition: Condition::NoSlip,
                exact: false,
            })
            .collect()
    }
}
