//! Flat, non-deformable free surface at `x3 = H` (Eq. 21): the image is a Stokeslet at
//! the mirror point `y'` with the reflected force, `J^w(x, y) = J(x, y') . P`, i.e.
//! `J^w_il = P_ll J_il(R)`, `R = x - y'`.

use super::wall::mirror;
use super::{stokeslet, Boundary, Condition, Green, ImageTerm, Mat3, Param, Plane};
use crate::number::scalar::Scalar;

/// The free surface.
pub struct FreeSurface;

/// The free-surface image about plane `plane`, scaled by weight `weight`.
pub(crate) fn mirror_terms(plane: usize, weight: usize) -> Vec<ImageTerm> {
    let mut t = Vec::new();
    for i in 0..3 {
        for l in 0..3 {
            t.push(ImageTerm {
                out: (i, l),
                coef: mirror(l),
                weight,
                plane,
                h_power: 0,
                d: [0, 0, 0],
                j: (i, l),
            });
        }
    }
    t
}

/// `J(x, y') . P` about the plane `x3 = height`, as ordinary Rust.
pub(crate) fn mirror_image<S: Scalar>(x: &[S; 3], y: &[S; 3], height: &S) -> Mat3<S> {
    let yp3 = S::cst(2.0) * height.clone() - y[2].clone();
    let r = [
        x[0].clone() - y[0].clone(),
        x[1].clone() - y[1].clone(),
        x[2].clone() - yp3,
    ];
    let j = stokeslet(&r);
    std::array::from_fn(|i| std::array::from_fn(|l| S::cst(mirror(l)) * j[i][l].clone()))
}

impl Green for FreeSurface {
    fn name(&self) -> &'static str {
        "free_surface"
    }
    fn title(&self) -> &'static str {
        "flat free surface at x3 = height: Stokeslet plus mirrored Stokeslet (Eq. 21)"
    }
    fn params(&self) -> &'static [Param] {
        &[Param::HEIGHT]
    }
    fn reflected<S: Scalar>(&self, x: &[S; 3], y: &[S; 3], p: &[S]) -> Mat3<S> {
        mirror_image(x, y, &p[0])
    }
    fn image_terms(&self) -> Option<Vec<ImageTerm>> {
        Some(mirror_terms(0, 0))
    }
    fn mirrors<S: Scalar>(&self, p: &[S]) -> Vec<Plane<S>> {
        vec![Plane::horizontal(p[0].clone())]
    }
    fn boundaries<S: Scalar>(&self, p: &[S]) -> Vec<Boundary<S>> {
        vec![Boundary::exact(
            Plane::horizontal(p[0].clone()),
            Condition::FreeSurface,
        )]
    }
    fn axisymmetric(&self) -> bool {
        true
    }
}
