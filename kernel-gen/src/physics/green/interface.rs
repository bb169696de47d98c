//! Flat liquid-liquid interface at `x3 = H` with viscosity ratio `lambda` (Eq. 22):
//! `G = G^F / (1 + lambda) + lambda G^W / (1 + lambda)`, so the reflected field is
//! the free-surface image weighted by `1/(1 + lambda)` plus Blake's image weighted by
//! `lambda/(1 + lambda)`. `lambda = 0` is the free surface; `lambda -> infinity` the wall.

use super::free_surface::{mirror_image, mirror_terms};
use super::wall::{blake, blake_terms};
use super::{Boundary, Green, ImageTerm, Mat3};
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
    fn params(&self) -> &'static [&'static str] {
        &["height", "lambda"]
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
    fn planes<S: Scalar>(&self, p: &[S]) -> Vec<S> {
        vec![p[0].clone()]
    }
    /// `[1/(1 + lambda), lambda/(1 + lambda)]`.
    fn weights<S: Scalar>(&self, p: &[S]) -> Vec<S> {
        let inv = (S::cst(1.0) + p[1].clone()).recip();
        vec![inv.clone(), p[1].clone() * inv]
    }
    fn boundary(&self) -> Boundary {
        Boundary::None
    }
    fn axisymmetric(&self) -> bool {
        true
    }
}
