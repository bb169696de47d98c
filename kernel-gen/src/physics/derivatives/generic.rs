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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::derivatives::Structured;
    use crate::physics::green::wall::Wall;

    /// The structured Eq. 10 path and the generic six-variable path agree on every
    /// derivative of Blake's image up to order 4 (f64 jets; both exact up to
    /// round-off, 1e-12 relative to the largest entry covers it).
    #[test]
    fn structured_and_generic_paths_agree_on_blake() {
        let x = [0.3, -0.7, 1.9];
        let y = [1.1, 0.4, 2.6];
        let p = [0.25];
        let order = 4;
        let mut s = Structured::new(&Wall, &x, &y, &p, order, false, true);
        let mut g = GenericJets::new(&Wall, Part::Reflected, &x, &y, &p, order);
        let l = Layout::get(6, order);
        let mut worst: f64 = 0.0;
        let mut scale: f64 = 0.0;
        for m in &l.monos {
            for i in 0..3 {
                for j in 0..3 {
                    let d = Deriv {
                        i,
                        j,
                        dx: [m[0], m[1], m[2]],
                        dy: [m[3], m[4], m[5]],
                    };
                    let (a, b) = (s.get(&d), g.get(&d));
                    worst = worst.max((a - b).abs());
                    scale = scale.max(b.abs());
                }
            }
        }
        assert!(worst <= 1e-12 * scale, "worst {worst:e} scale {scale:e}");
    }
}
