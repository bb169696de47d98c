//! Central finite differences of a Green's function in double-double: the reference
//! that is independent of the jets.
//!
//! A mixed partial `d_x^alpha d_y^beta G_ij` is the tensor product of one-dimensional
//! central stencils of second-order accuracy: `[1, -2, 1]` for order 2 and its
//! powers for even orders; an odd order `n` is `[-1/2, 0, 1/2]` convolved with the
//! stencil of order `n - 1`. With step `h` the truncation error is `O(h^2)` and the
//! round-off `O(eps_dd / h^n)`, `eps_dd ~ 1e-32`; `h = 1e-4` (relative to the
//! length scale of `G`) keeps both below about `1e-7` relative up to order 6.

use crate::number::dd::Dd;
use crate::number::scalar::Scalar;
use crate::physics::derivatives::Part;
use crate::physics::green::{self, Green, Mat3};
use crate::physics::operators::{Deriv, Derivatives};
use std::collections::HashMap;

/// Stencil of a central difference of order `n` with unit step: `(offset, weight)`.
pub fn stencil(n: u8) -> Vec<(i32, f64)> {
    let mut s: Vec<(i32, f64)> = vec![(0, 1.0)];
    let conv = |a: &[(i32, f64)], b: &[(i32, f64)]| {
        let mut m: HashMap<i32, f64> = HashMap::new();
        for &(oa, wa) in a {
            for &(ob, wb) in b {
                *m.entry(oa + ob).or_insert(0.0) += wa * wb;
            }
        }
        let mut v: Vec<(i32, f64)> = m.into_iter().filter(|(_, w)| *w != 0.0).collect();
        v.sort_by_key(|(o, _)| *o);
        v
    };
    for _ in 0..n / 2 {
        s = conv(&s, &[(-1, 1.0), (0, -2.0), (1, 1.0)]);
    }
    if n % 2 == 1 {
        s = conv(&s, &[(-1, -0.5), (1, 0.5)]);
    }
    s
}

/// Finite-difference derivatives of a Green's function about `(x, y)` in double-double.
pub struct FiniteDifferences<'g, G: Green> {
    g: &'g G,
    part: Part,
    x: [Dd; 3],
    y: [Dd; 3],
    p: Vec<Dd>,
    h: Dd,
    cache: HashMap<([i32; 3], [i32; 3]), Mat3<Dd>>,
}

impl<'g, G: Green> FiniteDifferences<'g, G> {
    /// Differences of `part` of `g` about `(x, y)` with step `h`.
    pub fn new(g: &'g G, part: Part, x: [f64; 3], y: [f64; 3], p: &[f64], h: f64) -> Self {
        FiniteDifferences {
            g,
            part,
            x: x.map(Dd::new),
            y: y.map(Dd::new),
            p: p.iter().map(|&v| Dd::new(v)).collect(),
            h: Dd::new(h),
            cache: HashMap::new(),
        }
    }

    fn eval(&mut self, ox: [i32; 3], oy: [i32; 3]) -> Mat3<Dd> {
        if let Some(v) = self.cache.get(&(ox, oy)) {
            return *v;
        }
        let x: [Dd; 3] = std::array::from_fn(|k| self.x[k] + self.h * Dd::new(ox[k] as f64));
        let y: [Dd; 3] = std::array::from_fn(|k| self.y[k] + self.h * Dd::new(oy[k] as f64));
        let v = match self.part {
            Part::Full => green::full(self.g, &x, &y, &self.p),
            Part::Reflected => self.g.reflected(&x, &y, &self.p),
            Part::Stokeslet => {
                let r: [Dd; 3] = std::array::from_fn(|k| x[k] - y[k]);
                green::stokeslet(&r)
            }
        };
        self.cache.insert((ox, oy), v);
        v
    }
}

impl<G: Green> Derivatives<Dd> for FiniteDifferences<'_, G> {
    fn get(&mut self, d: &Deriv) -> Dd {
        let orders: Vec<u8> = d.dx.iter().chain(&d.dy).copied().collect();
        let stencils: Vec<Vec<(i32, f64)>> = orders.iter().map(|&n| stencil(n)).collect();
        let mut acc = Dd::new(0.0);
        // odometer over the tensor-product stencil
        let mut idx = [0usize; 6];
        loop {
            let mut w = 1.0;
            let mut off = [0i32; 6];
            for v in 0..6 {
                let (o, wv) = stencils[v][idx[v]];
                off[v] = o;
                w *= wv;
            }
            let g = self.eval([off[0], off[1], off[2]], [off[3], off[4], off[5]]);
            acc = acc + Dd::new(w) * g[d.i][d.j];
            let mut v = 0;
            loop {
                if v == 6 {
                    let n: i32 = orders.iter().map(|&e| e as i32).sum();
                    return acc / self.h.powi(n);
                }
                idx[v] += 1;
                if idx[v] < stencils[v].len() {
                    break;
                }
                idx[v] = 0;
                v += 1;
            }
        }
    }
}
