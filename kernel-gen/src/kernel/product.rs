//! The fused pair product: `a = M^{ab} vb`, `b = M^{ba} va = (M^{ab})^T va`, from the
//! entries of the blocks, in the canonical frame or in the world.

use super::traced::BlockOut;
use crate::graph::Ex;
use crate::number::scalar::Scalar;
use crate::physics::frame::{Frame, Turn};
use crate::physics::operators::{response_dim, Basis, Moment, Response};

/// Components of a response or moment kept when the blocks are `blocks`, in grand
/// order `[U|F (3), Omega|L (3), E|S (5)]`.
fn kept(blocks: &[(Response, Moment)]) -> (bool, bool) {
    let l = blocks
        .iter()
        .any(|&(r, m)| r == Response::Omega || m == Moment::L);
    let s = blocks
        .iter()
        .any(|&(r, m)| r == Response::E || m == Moment::S);
    (l, s)
}

/// Length of the fused products' moment vectors for `blocks`.
pub(super) fn moments_len(blocks: &[(Response, Moment)]) -> usize {
    let (l, s) = kept(blocks);
    3 + if l { 3 } else { 0 } + if s { 5 } else { 0 }
}

/// The fused product `a = M^{ab} vb`, `b = (M^{ab})^T va` from the entries of the
/// blocks (row-major, `values[k]` for `blocks[k]`), in the grand order of the moments
/// kept; terms are summed as they come, without adding zeros.
pub(super) fn fused<S: Scalar>(
    blocks: &[(Response, Moment)],
    values: &[Vec<S>],
    basis: Basis,
    va: &[S],
    vb: &[S],
) -> (Vec<S>, Vec<S>) {
    let n = va.len();
    // [F|U (3), L|Omega (3), S|E (5)], truncated: the last five are S|E when kept.
    let offset = |k: usize| [0, 3, n.saturating_sub(5)][k];
    let mut a: Vec<Option<S>> = vec![None; n];
    let mut b: Vec<Option<S>> = vec![None; n];
    let add = |acc: &mut Option<S>, v: S| {
        *acc = Some(match acc.take() {
            None => v,
            Some(s) => s + v,
        })
    };
    for (&(r, m), vals) in blocks.iter().zip(values) {
        let (r0, c0) = (offset(r as usize), offset(m as usize));
        let cols = vals.len() / response_dim(r, basis);
        for (k, v) in vals.iter().enumerate() {
            let (i, j) = (r0 + k / cols, c0 + k % cols);
            add(&mut a[i], v.clone() * vb[j].clone());
            add(&mut b[j], v.clone() * va[i].clone());
        }
    }
    let done = |v: Vec<Option<S>>| {
        v.into_iter()
            .map(|e| e.unwrap_or_else(|| S::cst(0.0)))
            .collect()
    };
    (done(a), done(b))
}

/// The fused product from the traced blocks of `M^{ab}` ([`fused`]); with a frame, the
/// blocks are those of the frame, the moments are rotated into it and the responses
/// back; with a turn (the frame of the planes, [`Turn`]) the same around it.
pub(super) fn product_outputs(
    blocks: &[BlockOut],
    va: &[Ex],
    vb: &[Ex],
    frame: Option<&Frame>,
    turn: Option<&Turn>,
) -> Vec<BlockOut> {
    let which: Vec<(Response, Moment)> = blocks
        .iter()
        .map(|b| b.block.expect("block outputs"))
        .collect();
    let values: Vec<Vec<Ex>> = blocks
        .iter()
        .map(|b| b.ids.iter().map(|&id| Ex(id)).collect())
        .collect();
    let (l, s) = kept(&which);
    let parts: Vec<usize> = [Some(3), l.then_some(3), s.then_some(5)]
        .into_iter()
        .flatten()
        .collect();
    let (va, vb) = match turn {
        Some(q) => (q.vector(va, &parts, true), q.vector(vb, &parts, true)),
        None => (va.to_vec(), vb.to_vec()),
    };
    let (a, b) = match frame {
        None => fused(&which, &values, Basis::Orthonormal, &va, &vb),
        Some(f) => {
            let (fa, fb) = (f.vector(&va, &parts, true), f.vector(&vb, &parts, true));
            let (a, b) = fused(&which, &values, Basis::Orthonormal, &fa, &fb);
            (f.vector(&a, &parts, false), f.vector(&b, &parts, false))
        }
    };
    let (a, b) = match turn {
        Some(q) => (q.vector(&a, &parts, false), q.vector(&b, &parts, false)),
        None => (a, b),
    };
    let out = |name: &str, v: Vec<Ex>| BlockOut {
        name: name.into(),
        block: None,
        shape: vec![v.len()],
        ids: v.into_iter().map(|e| e.0).collect(),
    };
    vec![out("a", a), out("b", b)]
}
