//! Plane no-slip wall at `x3 = H`: Blake's image (Eq. 5),
//!
//! `J^w(x, y) = -J(x, y') + (y3 - H)^2 lap_{y'} J(x, y') . P
//!              + 2 (y3 - H) (P . grad_{y'} J(x, y') . e3)^T`,
//!
//! `y' = y - 2 (y3 - H) e3`, `P = I - 2 e3 e3`. Componentwise, with `R = x - y'` and
//! `grad_{y'} = -grad_R`:
//! `J^w_il = -J_il(R) + h^2 P_ll lap J_il(R) - 2 h P_ll d_l J_i3(R)`, `h = y3 - H`.

use super::{
    stokeslet, stokeslet_gradient, stokeslet_laplacian, Boundary, Condition, Green, ImageTerm,
    Mat3, Param, Plane,
};
use crate::number::scalar::Scalar;

/// The no-slip wall.
pub struct Wall;

/// `P_ll` of the mirror `P = diag(1, 1, -1)`.
pub(crate) fn mirror(l: usize) -> f64 {
    if l == 2 {
        -1.0
    } else {
        1.0
    }
}

/// Blake's image (Eq. 5) about plane `plane`, scaled by weight `weight`, as image
/// terms. Shared by the interface (Eq. 22) and the slit.
pub(crate) fn blake_terms(plane: usize, weight: usize) -> Vec<ImageTerm> {
    let mut t = Vec::new();
    for i in 0..3 {
        for l in 0..3 {
            let term = |coef: f64, h_power: u8, d: [u8; 3], j: (usize, usize)| ImageTerm {
                out: (i, l),
                coef,
                weight,
                plane,
                h_power,
                d,
                j,
            };
            // -J_il(R)
            t.push(term(-1.0, 0, [0, 0, 0], (i, l)));
            // h^2 P_ll lap J_il(R)
            for m in 0..3 {
                let mut d = [0u8; 3];
                d[m] = 2;
                t.push(term(mirror(l), 2, d, (i, l)));
            }
            // -2 h P_ll d_l J_i3(R)
            let mut d = [0u8; 3];
            d[l] = 1;
            t.push(term(-2.0 * mirror(l), 1, d, (i, 2)));
        }
    }
    t
}

/// Blake's image about the plane `x3 = height`, as ordinary Rust (Eq. 5).
pub(crate) fn blake<S: Scalar>(x: &[S; 3], y: &[S; 3], height: &S) -> Mat3<S> {
    image_system(x, y, height, |r| {
        (stokeslet(r), stokeslet_gradient(r), stokeslet_laplacian(r))
    })
}

/// `J`, its gradient `d_k J_ij` (indexed `[k][i][j]`) and its Laplacian at `R`.
pub(crate) type WithDerivatives<S> = (Mat3<S>, [Mat3<S>; 3], Mat3<S>);

/// Blake's image system (Eq. 5) about the plane `x3 = height` built from `kernel(R)`,
/// which gives a Stokeslet-like `J`, its gradient and its Laplacian at `R = x - y'`:
/// Blake's image with `J` itself ([`blake`]), or with the screened real part of an Ewald
/// split ([`super::ewald_wall`]).
pub(crate) fn image_system<S: Scalar>(
    x: &[S; 3],
    y: &[S; 3],
    height: &S,
    kernel: impl Fn(&[S; 3]) -> WithDerivatives<S>,
) -> Mat3<S> {
    let h = y[2].clone() - height.clone();
    let yp = [
        y[0].clone(),
        y[1].clone(),
        y[2].clone() - S::cst(2.0) * h.clone(),
    ];
    let r: [S; 3] = std::array::from_fn(|k| x[k].clone() - yp[k].clone());
    let (j, dj, lj) = kernel(&r);
    std::array::from_fn(|i| {
        std::array::from_fn(|l| {
            let p = S::cst(mirror(l));
            -j[i][l].clone() + h.clone() * h.clone() * p.clone() * lj[i][l].clone()
                - S::cst(2.0) * h.clone() * p * dj[l][i][2].clone()
        })
    })
}

impl Green for Wall {
    fn name(&self) -> &'static str {
        "wall"
    }
    fn title(&self) -> &'static str {
        "plane no-slip wall at x3 = height: Stokeslet plus Blake's image (Eqs. 5, 7)"
    }
    fn params(&self) -> &'static [Param] {
        &[Param::HEIGHT]
    }
    fn reflected<S: Scalar>(&self, x: &[S; 3], y: &[S; 3], p: &[S]) -> Mat3<S> {
        blake(x, y, &p[0])
    }
    fn image_terms(&self) -> Option<Vec<ImageTerm>> {
        Some(blake_terms(0, 0))
    }
    fn mirrors<S: Scalar>(&self, p: &[S]) -> Vec<Plane<S>> {
        vec![Plane::horizontal(p[0].clone())]
    }
    fn boundaries<S: Scalar>(&self, p: &[S]) -> Vec<Boundary<S>> {
        vec![Boundary::exact(
            Plane::horizontal(p[0].clone()),
            Condition::NoSlip,
        )]
    }
    /// A source on the wall has no effect: at `h = 0`, `R = r` and `J^w = -J(R)`.
    fn cancelling_image(&self) -> Option<(usize, usize)> {
        Some((0, 0))
    }
    fn axisymmetric(&self) -> bool {
        true
    }
}
