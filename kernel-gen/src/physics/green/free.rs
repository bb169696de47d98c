//! Unbounded fluid: the Stokeslet alone (Eq. 4); the reflected field is zero.

use super::{Green, Mat3, Param};
use crate::number::scalar::Scalar;

/// Free space: `G = J`.
pub struct Free;

impl Green for Free {
    fn name(&self) -> &'static str {
        "free"
    }
    fn title(&self) -> &'static str {
        "unbounded fluid: the Stokeslet J of Eq. 4"
    }
    fn params(&self) -> &'static [Param] {
        &[]
    }
    fn reflected<S: Scalar>(&self, _x: &[S; 3], _y: &[S; 3], _p: &[S]) -> Mat3<S> {
        std::array::from_fn(|_| std::array::from_fn(|_| S::cst(0.0)))
    }
    fn image_terms(&self) -> Option<Vec<super::ImageTerm>> {
        Some(Vec::new())
    }
    fn axisymmetric(&self) -> bool {
        true
    }
}
