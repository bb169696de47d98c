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

use crate::expr::Ex;
use crate::operators::{Moment, Response, STRAIN_BASIS};
use crate::scalar::Scalar;

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
        let qr = rotation(nr, c, s);
        let qm = rotation(nm, c, s);
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

    /// A grand vector (`[3 | 3 | 5]` parts as kept, `parts` their lengths) rotated by
    /// `Q^T` (into the frame, `transpose`) or by `Q` (back to the world).
    pub fn vector(&self, v: &[Ex], parts: &[usize], transpose: bool) -> Vec<Ex> {
        let mut out = Vec::with_capacity(v.len());
        let mut at = 0;
        for &n in parts {
            let q = rotation(n, &self.c, &self.s);
            for i in 0..n {
                let mut acc = Ex::cst(0.0);
                for k in 0..n {
                    let w = if transpose { q[k][i] } else { q[i][k] };
                    acc = acc + w * v[at + k];
                }
                out.push(acc);
            }
            at += n;
        }
        out
    }
}

/// The world of a product whose blocks couple 3-vectors only (forces, torques,
/// velocities, rotations), applied without the frame's rotation: the lateral separation
/// `d = (d1, d2)` unnormalised, `t = e3 x d = (-d2, d1)`, `rho^2 = |d|^2`.
///
/// With `p = d . v` and `q = t . v` for a moment `v`, a frame block `M'` (rows and
/// columns `1, 2` along `d/rho`, `t/rho`) acts in the world as
///
/// `u_par = M'22 v_par + A J v + d X + t Y`, `u3 = (M'31 p + M'32 q)/rho + M'33 v3`,
///
/// `X = B p + S q + (M'13/rho) v3`, `Y = S p + (M'23/rho) v3`, `J v = (v2, -v1)`,
/// `A = (M'12 - M'21)/2`, `B = (M'11 - M'22)/rho^2`, `S = (M'12 + M'21)/(2 rho^2)`:
/// the identities `d p + t q = rho^2 v_par` and `d q - t p = rho^2 J v` take the place
/// of `Q`, `1/rho^2` is taken of a safe `rho^2` (1 where it is 0, and there `d = t = 0`),
/// and the couplings to `e3` are divided by `rho` by the caller's `over_rho` (exactly,
/// by parity, in the near field: [`crate::expr::Graph::even_in`]).
pub struct World {
    /// `d1`, `d2`: the lateral separation `x_a - x_b`.
    pub d: [Ex; 2],
    /// `1/rho^2` (1 where `rho = 0`).
    pub inv_rho2: Ex,
}

/// What a response part gathers from the blocks acting on it ([`World`]).
#[derive(Clone, Copy)]
struct Gathered {
    lateral: [Ex; 2],
    x: Ex,
    y: Ex,
    z: Ex,
}

impl World {
    /// The world of the lateral separation `d` with `rho^2 = |d|^2` as built by [`Frame::of`].
    pub fn of(d: [Ex; 2], rho2: Ex) -> World {
        let zero = Ex::cst(0.0);
        let one = Ex::cst(1.0);
        let inv_rho2 = Ex::select_gt(rho2, zero, rho2, one).recip();
        World { d, inv_rho2 }
    }

    /// The fused product `a = M^{ab} vb`, `b = (M^{ab})^T va` from the frame blocks
    /// (`values[k]`, row-major 3 x 3, for `blocks[k]`), with `over_rho` dividing a
    /// frame entry by `rho`; the moments in the grand order of the parts kept.
    pub fn product(
        &self,
        blocks: &[(Response, Moment)],
        values: &[Vec<Ex>],
        va: &[Ex],
        vb: &[Ex],
        over_rho: &dyn Fn(Ex) -> Ex,
    ) -> (Vec<Ex>, Vec<Ex>) {
        let zero = Ex::cst(0.0);
        let empty = Gathered {
            lateral: [zero; 2],
            x: zero,
            y: zero,
            z: zero,
        };
        let parts = va.len() / 3;
        let mut a = vec![empty; parts];
        let mut b = vec![empty; parts];
        let part = |v: &[Ex], k: usize| [v[3 * k], v[3 * k + 1], v[3 * k + 2]];
        for (&(r, m), vals) in blocks.iter().zip(values) {
            assert!(r != Response::E && m != Moment::S, "3-vectors only");
            let (i, j) = (r as usize, m as usize);
            let block: [[Ex; 3]; 3] =
                std::array::from_fn(|k| std::array::from_fn(|l| vals[3 * k + l]));
            let transposed = std::array::from_fn(|k| std::array::from_fn(|l| block[l][k]));
            self.gather(&mut a[i], &block, part(vb, j), over_rho);
            self.gather(&mut b[j], &transposed, part(va, i), over_rho);
        }
        let [d1, d2] = self.d;
        let out = |g: &[Gathered]| -> Vec<Ex> {
            g.iter()
                .flat_map(|g| {
                    [
                        g.lateral[0] + d1 * g.x - d2 * g.y,
                        g.lateral[1] + d2 * g.x + d1 * g.y,
                        g.z,
                    ]
                })
                .collect()
        };
        (out(&a), out(&b))
    }

    /// Adds what frame block `m` does to the world moment `v` into `g`.
    fn gather(&self, g: &mut Gathered, m: &[[Ex; 3]; 3], v: [Ex; 3], over_rho: &dyn Fn(Ex) -> Ex) {
        let [d1, d2] = self.d;
        let p = d1 * v[0] + d2 * v[1];
        let q = d1 * v[1] - d2 * v[0];
        let half = Ex::cst(0.5);
        let a = (m[0][1] - m[1][0]) * half;
        let bb = (m[0][0] - m[1][1]) * self.inv_rho2;
        let s = (m[0][1] + m[1][0]) * half * self.inv_rho2;
        g.lateral[0] = g.lateral[0] + m[1][1] * v[0] + a * v[1];
        g.lateral[1] = g.lateral[1] + m[1][1] * v[1] - a * v[0];
        g.x = g.x + bb * p + s * q + over_rho(m[0][2]) * v[2];
        g.y = g.y + s * p + over_rho(m[1][2]) * v[2];
        g.z = g.z + over_rho(m[2][0]) * p + over_rho(m[2][1]) * q + m[2][2] * v[2];
    }
}

/// The rotation by `(c, s) = (cos, sin)` about `e3` on vectors (`dim = 3`) or on the
/// orthonormal strain basis (`dim = 5`: `Q_5[p][q] = B_p : (Q B_q Q^T)`), zeros as
/// exact constants.
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::expr::{Id, Trace};

    /// `World::product` equals the frame's rotation in, product, rotation out, on
    /// blocks with every entry nonzero (UF, UL, Omega F, Omega L at once), with `1/rho`
    /// taken of the real `rho`; and at `rho = 0`, where the frame is the identity, for
    /// blocks that are symmetric under rotations about `e3` there.
    #[test]
    fn world_product_equals_the_rotated_frame_product() {
        let t = Trace::begin();
        let xa: [Ex; 3] = std::array::from_fn(|k| t.input(&format!("xa{k}")));
        let xb: [Ex; 3] = std::array::from_fn(|k| t.input(&format!("xb{k}")));
        let va: Vec<Ex> = (0..6).map(|k| t.input(&format!("va{k}"))).collect();
        let vb: Vec<Ex> = (0..6).map(|k| t.input(&format!("vb{k}"))).collect();
        let entries: Vec<Vec<Ex>> = (0..4)
            .map(|b| (0..9).map(|k| t.input(&format!("m{b}_{k}"))).collect())
            .collect();
        let blocks = [
            (Response::U, Moment::F),
            (Response::U, Moment::L),
            (Response::Omega, Moment::F),
            (Response::Omega, Moment::L),
        ];
        let (f, _, _) = Frame::of(&xa, &xb);
        let w = World::of([xa[0] - xb[0], xa[1] - xb[1]], f.rho2);
        let inv = Ex::select_gt(f.rho2, Ex::cst(0.0), f.rho, Ex::cst(1.0)).recip();
        let (a, b) = w.product(&blocks, &entries, &va, &vb, &|x| x * inv);
        // the frame's way: moments rotated in, frame blocks applied, responses out
        let parts = [3, 3];
        let (fa, fb) = (f.vector(&va, &parts, true), f.vector(&vb, &parts, true));
        let mut ra = vec![Ex::cst(0.0); 6];
        let mut rb = vec![Ex::cst(0.0); 6];
        for (&(r, m), m_ab) in blocks.iter().zip(&entries) {
            let (i0, j0) = (3 * r as usize, 3 * m as usize);
            for i in 0..3 {
                for j in 0..3 {
                    ra[i0 + i] = ra[i0 + i] + m_ab[3 * i + j] * fb[j0 + j];
                    rb[j0 + j] = rb[j0 + j] + m_ab[3 * i + j] * fa[i0 + i];
                }
            }
        }
        let (ra, rb) = (f.vector(&ra, &parts, false), f.vector(&rb, &parts, false));
        let g = t.finish();
        let outs: Vec<Id> = a
            .iter()
            .chain(&b)
            .chain(&ra)
            .chain(&rb)
            .map(|e| e.0)
            .collect();
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for case in 0..20 {
            let mut inputs: Vec<f64> = (0..g.input_names().len()).map(|_| next()).collect();
            if case % 5 == 0 {
                // rho = 0: entries of a tensor invariant under rotations about e3
                inputs[3] = inputs[0];
                inputs[4] = inputs[1];
                for b in 0..4 {
                    let m = &mut inputs[18 + 9 * b..27 + 9 * b];
                    m[4] = m[0];
                    m[3] = -m[1];
                    for k in [2, 5, 6, 7] {
                        m[k] = 0.0;
                    }
                }
            }
            let v: Vec<f64> = g.eval(&inputs, &outs);
            let (world, frame) = v.split_at(12);
            let norm = frame.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            for (x, y) in world.iter().zip(frame) {
                // a few roundings of terms of the size of the largest response
                approx::assert_abs_diff_eq!(*x, *y, epsilon = 32.0 * f64::EPSILON * norm);
            }
        }
    }
}
