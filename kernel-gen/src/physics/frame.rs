//! The canonical frame of a pair: rotated about `e3` so that the lateral separation
//! lies along `+x1`.
//!
//! A Green's function whose boundaries are planes normal to `e3` (free space, the wall,
//! the free surface, the interface, the slit) is invariant under rotations about `e3`
//! and lateral translations, so `M^{ab}(x_a, x_b) = Q M^{ab}(x_a', x_b') Q^T` with
//! `x_a' = (rho, 0, x_a3)`, `x_b' = (0, 0, x_b3)`, `rho = |(x_a - x_b)_{1,2}|` and `Q`
//! the rotation by the angle of the lateral separation (`Q_3` on vectors and
//! pseudovectors, its 5-dimensional representation `Q_5` on strains and stresslets
//! in the orthonormal basis). Traced in that frame, every term odd in the second
//! lateral coordinate is zero and folds away as the graph is built; the kernel
//! rotates the moments into the frame and the responses back (products), or the
//! blocks (`Q_r B' Q_m^T`, block kernels).
//!
//! With `rho = 0` every rotation is a symmetry; the frame is then the identity
//! (`c = 1`, `s = 0`), chosen by a comparison node ([`Ex::select_gt`]), and the
//! reciprocal is taken of `rho` where it is positive and of 1 elsewhere, so no kernel
//! ever forms `1/0`.
//!
//! [`Turn`] is the fixed rotation that comes before it for planes of another normal `n`
//! ([`crate::physics::green::turned`]): points and moments into the planes' own frame
//! (rows `t1, t2, n`), blocks and responses back, with the same block and vector
//! rotations.

use crate::graph::Ex;
use crate::number::scalar::Scalar;
use crate::physics::green::{clean, rotate, Mat3};
use crate::physics::operators::STRAIN_BASIS;

/// The frame of a pair: `rho^2`, `1/rho` and the rotation's `(cos, sin)`.
pub struct Frame {
    /// `rho^2 = (x_a1 - x_b1)^2 + (x_a2 - x_b2)^2`.
    pub rho2: Ex,
    /// `rho`.
    pub rho: Ex,
    /// `cos` of the lateral separation's angle (1 where `rho = 0`).
    pub c: Ex,
    /// `sin` of the lateral separation's angle (0 where `rho = 0`).
    pub s: Ex,
}

impl Frame {
    /// The frame of field point `xa` and source `xb`, and the two points in it.
    pub fn of(xa: &[Ex; 3], xb: &[Ex; 3]) -> (Frame, [Ex; 3], [Ex; 3]) {
        let dx = xa[0] - xb[0];
        let dy = xa[1] - xb[1];
        let rho2 = dx * dx + dy * dy;
        let rho = rho2.sqrt();
        let zero = Ex::cst(0.0);
        let one = Ex::cst(1.0);
        // 1/rho of a safe rho: never infinite, so that a reciprocal sharing its division
        // with others (the lane kernels) is never poisoned where rho = 0
        let inv = Ex::select_gt(rho2, zero, rho, one).recip();
        let c = Ex::select_gt(rho2, zero, dx * inv, one);
        let s = Ex::select_gt(rho2, zero, dy * inv, zero);
        let f = Frame { rho2, rho, c, s };
        (f, [rho, zero, xa[2]], [zero, zero, xb[2]])
    }

    /// `Q_r B' Q_m^T`: a block (`nr x nm`, row-major) from the frame to the world.
    pub fn block_to_world<S: Scalar>(vals: &[S], nr: usize, nm: usize, c: &S, s: &S) -> Vec<S> {
        rotate_block(vals, &rotation(nr, c, s), &rotation(nm, c, s))
    }

    /// A grand vector (`[3 | 3 | 5]` parts as kept, `parts` their lengths) rotated by
    /// `Q^T` (into the frame, `transpose`) or by `Q` (back to the world).
    pub fn vector(&self, v: &[Ex], parts: &[usize], transpose: bool) -> Vec<Ex> {
        rotate_vector(v, parts, transpose, |n| rotation(n, &self.c, &self.s))
    }
}

/// A fixed rotation from a plane's frame to the world: `Q^T` for the frame `Q` (rows
/// `t1, t2, n`, [`crate::physics::green::frame`]) of the mirror planes of a
/// [`crate::physics::green::turned::Turned`] Green's function. Its entries (and those
/// of its strain representation, computed in `f64`) are constants of the graph, so a
/// signed permutation folds to relabelled inputs and outputs.
pub struct Turn {
    /// `Q`: the frame's rows.
    frame: Mat3<f64>,
    /// `Q^T`: frame to world.
    q3: Mat3<f64>,
    /// `Q_5^T`.
    q5: Vec<Vec<f64>>,
}

impl Turn {
    /// The rotation back from the frame `q` (rows `t1, t2, n`).
    pub fn from_frame(q: &Mat3<f64>) -> Turn {
        let q3: Mat3<f64> = std::array::from_fn(|i| std::array::from_fn(|j| q[j][i]));
        let q5 = strains(&q3);
        Turn { frame: *q, q3, q5 }
    }

    fn matrix<S: Scalar>(&self, dim: usize) -> Vec<Vec<S>> {
        let m: Vec<Vec<f64>> = match dim {
            3 => self.q3.iter().map(|r| r.to_vec()).collect(),
            5 => self.q5.clone(),
            _ => panic!("vectors, pseudovectors and strains only"),
        };
        m.into_iter()
            .map(|r| r.into_iter().map(|v| S::cst(clean(v))).collect())
            .collect()
    }

    /// A point of the world in the frame: `Q x`.
    pub fn point<S: Scalar>(&self, x: &[S; 3]) -> [S; 3] {
        rotate(&self.frame, x)
    }

    /// A grand vector (`parts` as in [`Frame::vector`]) into the frame (`transpose`) or
    /// back to the world.
    pub fn vector<S: Scalar>(&self, v: &[S], parts: &[usize], transpose: bool) -> Vec<S> {
        rotate_vector(v, parts, transpose, |n| self.matrix(n))
    }

    /// A block (`nr x nm`, row-major) from the frame to the world.
    pub fn block_to_world<S: Scalar>(&self, vals: &[S], nr: usize, nm: usize) -> Vec<S> {
        rotate_block(vals, &self.matrix(nr), &self.matrix(nm))
    }
}

/// `Q_r B Q_m^T` for a block `B` (`qr.len() x qm.len()`, row-major), skipping the
/// known zeros.
fn rotate_block<S: Scalar>(vals: &[S], qr: &[Vec<S>], qm: &[Vec<S>]) -> Vec<S> {
    let (nr, nm) = (qr.len(), qm.len());
    let mut out = Vec::with_capacity(nr * nm);
    for i in 0..nr {
        for j in 0..nm {
            let mut acc = S::cst(0.0);
            for a in 0..nr {
                if qr[i][a].is_known_zero() {
                    continue;
                }
                let mut inner = S::cst(0.0);
                for b in 0..nm {
                    let v = &vals[a * nm + b];
                    if v.is_known_zero() || qm[j][b].is_known_zero() {
                        continue;
                    }
                    inner = inner + v.clone() * qm[j][b].clone();
                }
                acc = acc + qr[i][a].clone() * inner;
            }
            out.push(acc);
        }
    }
    out
}

/// A grand vector rotated part by part: `Q^T v` (`transpose`) or `Q v`, `q(n)` the
/// rotation on a part of length `n`.
fn rotate_vector<S: Scalar>(
    v: &[S],
    parts: &[usize],
    transpose: bool,
    q: impl Fn(usize) -> Vec<Vec<S>>,
) -> Vec<S> {
    let mut out = Vec::with_capacity(v.len());
    let mut at = 0;
    for &n in parts {
        let q = q(n);
        for i in 0..n {
            let mut acc = S::cst(0.0);
            for k in 0..n {
                let w = if transpose { &q[k][i] } else { &q[i][k] };
                acc = acc + w.clone() * v[at + k].clone();
            }
            out.push(acc);
        }
        at += n;
    }
    out
}

/// The rotation by `(c, s) = (cos, sin)` about `e3` on vectors (`dim = 3`) or on the
/// orthonormal strain basis (`dim = 5`: [`strains`]), zeros as exact constants.
pub fn rotation<S: Scalar>(dim: usize, c: &S, s: &S) -> Vec<Vec<S>> {
    let z = || S::cst(0.0);
    let r = [
        [c.clone(), -s.clone(), z()],
        [s.clone(), c.clone(), z()],
        [z(), z(), S::cst(1.0)],
    ];
    if dim == 3 {
        return r.iter().map(|row| row.to_vec()).collect();
    }
    assert_eq!(dim, 5, "orthonormal strain basis");
    strains(&r)
}

/// A rotation `R` on the orthonormal strain basis: `R_5[p][q] = B_p : (R B_q R^T)`.
pub fn strains<S: Scalar>(r: &Mat3<S>) -> Vec<Vec<S>> {
    let mut q = vec![vec![S::cst(0.0); 5]; 5];
    for p in 0..5 {
        for qq in 0..5 {
            let mut acc = S::cst(0.0);
            for i in 0..3 {
                for j in 0..3 {
                    if STRAIN_BASIS[p][i][j] == 0.0 {
                        continue;
                    }
                    for k in 0..3 {
                        for l in 0..3 {
                            if STRAIN_BASIS[qq][k][l] == 0.0 {
                                continue;
                            }
                            let w = STRAIN_BASIS[p][i][j] * STRAIN_BASIS[qq][k][l];
                            acc = acc + S::cst(w) * (r[i][k].clone() * r[j][l].clone());
                        }
                    }
                }
            }
            q[p][qq] = acc;
        }
    }
    q
}
