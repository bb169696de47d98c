//! Flat liquid-liquid interface at `x3 = H` with viscosity ratio `lambda` (Eq. 22):
//! `G = G^F / (1 + lambda) + lambda G^W / (1 + lambda)`, so the reflected field is
//! the free-surface image weighted by `1/(1 + lambda)` plus Blake's image weighted by
//! `lambda/(1 + lambda)`. `lambda = 0` is the free surface; `lambda -> infinity` the wall.

use super::free_surface::{mirror_image, mirror_terms};
use super::wall::{blake, blake_terms};
use super::{Boundary, Condition, Dimension, Green, ImageTerm, Mat3, Param, Plane};
use crate::number::scalar::Scalar;

/// The liquid-liquid interface.
pub struct Interface;

impl Green for Interface {
    fn name(&self) -> &'static str {
        "interface"
    }
    fn title(&self) -> &'static str {
        "flat liquid-liquid interface at x3 = height, viscosity ratio lambda (Eq. 22)"
    }
    fn params(&self) -> &'static [Param] {
        &[
            Param::HEIGHT,
            Param {
                name: "lambda",
                doc: "viscosity ratio lambda of the liquid beyond the interface to this one",
                dimension: Dimension::Number,
                default: None,
                example: 2.5,
            },
        ]
    }
    fn reflected<S: Scalar>(&self, x: &[S; 3], y: &[S; 3], p: &[S]) -> Mat3<S> {
        let w = self.weights(p);
        let f = mirror_image(x, y, &p[0]);
        let b = blake(x, y, &p[0]);
        std::array::from_fn(|i| {
            std::array::from_fn(|l| w[0].clone() * f[i][l].clone() + w[1].clone() * b[i][l].clone())
        })
    }
    fn image_terms(&self) -> Option<Vec<ImageTerm>> {
        let mut t = mirror_terms(0, 0);
        t.extend(blake_terms(0, 1));
        Some(t)
    }
    fn mirrors<S: Scalar>(&self, p: &[S]) -> Vec<Plane<S>> {
        vec![Plane::horizontal(p[0].clone())]
    }
    fn boundaries<S: Scalar>(&self, p: &[S]) -> Vec<Boundary<S>> {
        vec![Boundary::exact(
            Plane::horizontal(p[0].clone()),
            Condition::Interface,
        )]
    }
    /// `[1/(1 + lambda), lambda/(1 + lambda)]`.
    fn weights<S: Scalar>(&self, p: &[S]) -> Vec<S> {
        let inv = (S::cst(1.0) + p[1].clone()).recip();
        vec![inv.clone(), p[1].clone() * inv]
    }
    fn axisymmetric(&self) -> bool {
        true
    }
}
