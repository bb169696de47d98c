//! The generic path: the whole `G(x, y)` expanded in all six coordinates.

use crate::number::jet::{Jet, Layout};
use crate::number::scalar::Scalar;
use crate::physics::green::{self, Green, Mat3};
use crate::physics::operators::{Deriv, Derivatives};

/// Derivatives of any `G(x, y)` from one jet in all six coordinates, or, for a `G` of
/// `x - y` alone ([`Green::translation_invariant`]), in the three of `x`, with
/// `d_x^alpha d_y^beta G = (-1)^|beta| d_x^(alpha + beta) G` (the jets of the six
/// variables would hold every derivative `C(6 + D, D) / C(3 + D, D)` times over: 11
/// times at order 4).
pub struct GenericJets<S> {
    g: Mat3<Jet<S>>,
    translation_invariant: bool,
}

/// Which part of the Green's function a generic jet expands (or the finite differences
/// of [`crate::physics::fd`] difference).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// `J + J^w` (pair interactions).
    Full,
    /// `J^w` only (self interactions, Eq. 17).
    Reflected,
    /// `J` only.
    Stokeslet,
}

impl<S: Scalar> GenericJets<S> {
    /// Jets of the chosen part of `g` about `(x, y)`, truncated at total degree `degree`.
    pub fn new<G: Green>(
        g: &G,
        part: Part,
        x: &[S; 3],
        y: &[S; 3],
        p: &[S],
        degree: usize,
    ) -> Self {
        let translation_invariant = g.translation_invariant();
        let l = Layout::get(if translation_invariant { 3 } else { 6 }, degree);
        let xj: [Jet<S>; 3] = std::array::from_fn(|k| Jet::variable(&l, k, x[k].clone()));
        let yj: [Jet<S>; 3] = std::array::from_fn(|k| {
            if translation_invariant {
                Jet::constant(y[k].clone())
            } else {
                Jet::variable(&l, 3 + k, y[k].clone())
            }
        });
        let pj: Vec<Jet<S>> = p.iter().map(|v| Jet::constant(v.clone())).collect();
        let gj = match part {
            Part::Full => green::full(g, &xj, &yj, &pj),
            Part::Reflected => g.reflected(&xj, &yj, &pj),
            Part::Stokeslet => {
                let r: [Jet<S>; 3] = std::array::from_fn(|k| xj[k].clone() - yj[k].clone());
                green::stokeslet(&r)
            }
        };
        GenericJets {
            g: gj,
            translation_invariant,
        }
    }
}

impl<S: Scalar> Derivatives<S> for GenericJets<S> {
    fn get(&mut self, d: &Deriv) -> S {
        if !self.translation_invariant {
            let m: Vec<u8> = d.dx.iter().chain(&d.dy).copied().collect();
            return self.g[d.i][d.j].derivative(&m);
        }
        let m: [u8; 3] = std::array::from_fn(|k| d.dx[k] + d.dy[k]);
        let v = self.g[d.i][d.j].derivative(&m);
        if d.dy.iter().map(|&e| e as u32).sum::<u32>() % 2 == 1 {
            -v
        } else {
            v
        }
    }
}
