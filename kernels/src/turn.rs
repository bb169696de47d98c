//! The fixed rotation into the frame of a confinement's planes, for a confinement that
//! is another one turned (a wall normal to `e1` is the wall normal to `e3` in the frame
//! whose rows are `e2, e3, e1`): the generator finds such twins
//! (kernel_gen `catalog`, [`crate::Confinement::served`]) and emits no kernels for them;
//! the entry points rotate the points and moments into the frame, call the kernels of
//! the confinement that serves, and rotate the responses and blocks back.
//!
//! With `Q` the frame (rows `t1, t2, n`: `x' = Q x`) and `Q_5` its representation on
//! the orthonormal strain basis ([`crate::STRAIN_BASIS`]: `Q_5[p][q] = B_p : (Q B_q
//! Q^T)`), a grand vector (`U`, `Omega`, `E` or `F`, `L`, `S`) turns part by part,
//! `v' = R v` with `R = diag(Q, Q, Q_5)` (`Q` is a proper rotation, so pseudovectors turn
//! as vectors), and a block `B = R^T B' R`. The zero entries of `Q` and `Q_5` are
//! skipped: where one twin is registered its constants are known where the entry points
//! are compiled, and a signed permutation `Q` costs no multiplication on vectors.

use crate::blocks::{BlocksF, BlocksFT, Drift, Grand, Product, FT_FLAT, F_FLAT, GRAND_FLAT};
use lanes::Lane;

/// A rotation from the world into a frame of planes: `Q` and `Q_5`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Turn {
    /// `Q`: rows `t1, t2, n`, a proper rotation.
    pub q: [[f64; 3]; 3],
    /// `Q_5`, the same rotation on the orthonormal strain basis.
    pub q5: [[f64; 5]; 5],
}

/// The part of a grand vector of `k` entries (3, 6 or 11: `[3 | 3 | 5]` as fit) that
/// entry `i` belongs to: `(start, length)`.
#[inline(always)]
const fn part(i: usize) -> (usize, usize) {
    if i < 3 {
        (0, 3)
    } else if i < 6 {
        (3, 3)
    } else {
        (6, 5)
    }
}

impl Turn {
    /// Entry `(i, k)` of `R = diag(Q, Q, Q_5)` (zero across parts).
    #[inline(always)]
    fn r(&self, i: usize, k: usize) -> f64 {
        let ((si, ni), (sk, _)) = (part(i), part(k));
        if si != sk {
            0.0
        } else if ni == 3 {
            self.q[i - si][k - sk]
        } else {
            self.q5[i - si][k - sk]
        }
    }

    /// `R v` (`back`: `R^T v`) of a grand vector of `K` entries.
    #[inline(always)]
    fn vector<L: Lane, const K: usize>(&self, v: [L; K], back: bool) -> [L; K] {
        std::array::from_fn(|i| {
            let (s, n) = part(i);
            let mut acc: Option<L> = None;
            for k in s..s + n {
                let w = if back { self.r(k, i) } else { self.r(i, k) };
                if w == 0.0 {
                    continue;
                }
                let term = if w == 1.0 { v[k] } else { L::splat(w) * v[k] };
                acc = Some(acc.map_or(term, |a| a + term));
            }
            acc.unwrap_or(L::splat(0.0))
        })
    }

    /// A point, or a direction, of the world in the frame: `Q x`.
    #[inline(always)]
    pub fn point<L: Lane>(&self, x: [L; 3]) -> [L; 3] {
        self.vector(x, false)
    }

    /// Moments of the world (force, torque, stresslet as kept: `K` = 3, 6, 11) in the
    /// frame: `R v`.
    #[inline(always)]
    pub fn moments<L: Lane, const K: usize>(&self, v: [L; K]) -> [L; K] {
        self.vector(v, false)
    }

    /// Responses in the frame (velocity, rotation, strain as kept) back to the world:
    /// `R^T v`.
    #[inline(always)]
    pub fn responses<L: Lane, const K: usize>(&self, v: [L; K]) -> [L; K] {
        self.vector(v, true)
    }

    /// Two particles' responses, `a` then `b` (`K2 = 2 K` lanes), back to the world.
    #[inline(always)]
    pub fn both<L: Lane, const K: usize, const K2: usize>(&self, v: [L; K2]) -> [L; K2] {
        let a: [L; K] = self.responses(std::array::from_fn(|i| v[i]));
        let b: [L; K] = self.responses(std::array::from_fn(|i| v[K + i]));
        std::array::from_fn(|i| if i < K { a[i] } else { b[i - K] })
    }

    /// Blocks in grand order (`K x K`, flattened as `at` says, [`GRAND_FLAT`] and its
    /// truncations) back to the world: `B = R^T B' R`.
    #[inline(always)]
    pub fn blocks<L: Lane, const K: usize, const N: usize>(
        &self,
        m: [L; N],
        at: &[[usize; K]; K],
    ) -> [L; N] {
        // B' R, then R^T (B' R)
        let mut right = [[L::splat(0.0); K]; K];
        for (i, row) in right.iter_mut().enumerate() {
            for (j, out) in row.iter_mut().enumerate() {
                let (s, n) = part(j);
                let mut acc: Option<L> = None;
                for k in s..s + n {
                    let w = self.r(k, j);
                    if w == 0.0 {
                        continue;
                    }
                    let v = m[at[i][k]];
                    let term = if w == 1.0 { v } else { L::splat(w) * v };
                    acc = Some(acc.map_or(term, |a| a + term));
                }
                *out = acc.unwrap_or(L::splat(0.0));
            }
        }
        let mut out = [L::splat(0.0); N];
        for i in 0..K {
            let (s, n) = part(i);
            for j in 0..K {
                let mut acc: Option<L> = None;
                for (k, row) in right.iter().enumerate().skip(s).take(n) {
                    let w = self.r(k, i);
                    if w == 0.0 {
                        continue;
                    }
                    let term = if w == 1.0 {
                        row[j]
                    } else {
                        L::splat(w) * row[j]
                    };
                    acc = Some(acc.map_or(term, |a| a + term));
                }
                out[at[i][j]] = acc.unwrap_or(L::splat(0.0));
            }
        }
        out
    }

    /// [`BlocksF`] of a pair back to the world.
    pub fn blocks_f(&self, b: BlocksF) -> BlocksF {
        BlocksF::from_flat(&self.blocks(b.flat(), &F_FLAT))
    }

    /// [`BlocksFT`] of a pair back to the world.
    pub fn blocks_ft(&self, b: BlocksFT) -> BlocksFT {
        BlocksFT::from_flat(&self.blocks(b.flat(), &FT_FLAT))
    }

    /// [`Grand`] of a pair back to the world.
    pub fn grand(&self, g: Grand) -> Grand {
        Grand::from_flat(&self.blocks(g.flat(), &GRAND_FLAT))
    }

    /// [`BlocksF`] of one particle (symmetric) back to the world ([`symmetric`]).
    pub fn self_f(&self, b: BlocksF) -> BlocksF {
        BlocksF::from_flat(&symmetric(self.blocks(b.flat(), &F_FLAT), &F_FLAT))
    }

    /// [`BlocksFT`] of one particle (symmetric) back to the world ([`symmetric`]).
    pub fn self_ft(&self, b: BlocksFT) -> BlocksFT {
        BlocksFT::from_flat(&symmetric(self.blocks(b.flat(), &FT_FLAT), &FT_FLAT))
    }

    /// [`Grand`] of one particle (symmetric) back to the world ([`symmetric`]).
    pub fn self_grand(&self, g: Grand) -> Grand {
        Grand::from_flat(&symmetric(self.blocks(g.flat(), &GRAND_FLAT), &GRAND_FLAT))
    }

    /// A pair's contributions back to the world.
    pub fn product<const K: usize>(&self, p: Product<K>) -> Product<K> {
        Product {
            a: self.responses(p.a),
            b: self.responses(p.b),
        }
    }

    /// One particle's vector back to the world.
    pub fn drift<const K: usize>(&self, d: Drift<K>) -> Drift<K> {
        Drift {
            a: self.responses(d.a),
        }
    }
}

/// `(B + B^T)/2` of blocks in grand order (flattened as `at` says): a particle's own
/// blocks are symmetric, and its kernel's are so to the bit; rotated, `R^T B' R` rounds
/// `(i, j)` and `(j, i)` differently, and the mean restores the exact symmetry (the
/// solver and its tests rely on it) without moving either by more than that rounding.
#[inline(always)]
pub fn symmetric<L: Lane, const K: usize, const N: usize>(
    m: [L; N],
    at: &[[usize; K]; K],
) -> [L; N] {
    let mut out = m;
    for i in 0..K {
        for j in 0..K {
            out[at[i][j]] = (m[at[i][j]] + m[at[j][i]]) * L::splat(0.5);
        }
    }
    out
}
