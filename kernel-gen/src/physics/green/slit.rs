//! Slit between two parallel no-slip walls at `x3 = H` and `x3 = H + gap`,
//! approximated as in Sec. IV by superposing the reflections of two opposing walls:
//! `J^w = J^w_Blake(H) + J^w_Blake(H + gap)`. Blake's formula holds for a source on
//! either side of its plane, so the upper wall uses it unchanged. This is an
//! approximation: each wall's image violates no-slip on the other wall.

use super::wall::{blake, blake_terms};
use super::{Boundary, Condition, Dimension, Green, ImageTerm, Mat3, Param, Plane};
use crate::number::scalar::Scalar;

/// The two-wall superposition.
pub struct Slit;

impl Green for Slit {
    fn name(&self) -> &'static str {
        "slit"
    }
    fn title(&self) -> &'static str {
        "slit between walls at x3 = height and x3 = height + gap, superposed Blake images (Sec. IV)"
    }
    fn params(&self) -> &'static [Param] {
        &[
            Param::HEIGHT,
            Param {
                name: "gap",
                doc: "distance from the lower wall to the upper wall",
                dimension: Dimension::Length,
                default: None,
                example: 12.0,
            },
        ]
    }
    fn reflected<S: Scalar>(&self, x: &[S; 3], y: &[S; 3], p: &[S]) -> Mat3<S> {
        let pl = self.mirrors(p);
        let a = blake(x, y, &pl[0].offset);
        let b = blake(x, y, &pl[1].offset);
        std::array::from_fn(|i| std::array::from_fn(|l| a[i][l].clone() + b[i][l].clone()))
    }
    fn image_terms(&self) -> Option<Vec<ImageTerm>> {
        let mut t = blake_terms(0, 0);
        t.extend(blake_terms(1, 0));
        Some(t)
    }
    fn mirrors<S: Scalar>(&self, p: &[S]) -> Vec<Plane<S>> {
        vec![
            Plane::horizontal(p[0].clone()),
            Plane::horizontal(p[0].clone() + p[1].clone()),
        ]
    }
    /// The fluid is above the lower wall and below the upper one. Each wall's image
    /// violates the other wall's no slip: neither condition holds exactly.
    fn boundaries<S: Scalar>(&self, p: &[S]) -> Vec<Boundary<S>> {
        let upper = p[0].clone() + p[1].clone();
        vec![
            Boundary {
                plane: Plane::horizontal(p[0].clone()),
                condition: Condition::NoSlip,
                exact: false,
            },
            Boundary {
                plane: Plane {
                    normal: [0.0, 0.0, -1.0],
                    offset: -upper,
                },
                condition: Condition::NoSlip,
                exact: false,
            },
        ]
    }
    fn axisymmetric(&self) -> bool {
        true
    }
}
