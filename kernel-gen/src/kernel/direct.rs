//! The direct sum of a kernel evaluated straight in any scalar, without a graph.

use super::blocks::block_values;
use super::product::{fused, moments_len};
use super::spec::{Interaction, KernelSpec};
use crate::number::scalar::Scalar;
use crate::physics::derivatives::{Collection, Form};
use crate::physics::green::Green;

/// The direct sum of kernel `spec` evaluated straight in the scalar `S`, without an
/// expression graph: `inputs` as the traced graph's, outputs flattened as
/// [`Traced::outputs`](super::Traced::outputs) (blocks, or the fused products; not the
/// divergences). In double-double this is the stiff cases' reference: the graph's constants
/// are `f64` (a jet rule's weight such as 1/3 rounded, constants folded in `f64`), which
/// leaves about 1e-17 of the terms wherever they cancel, while here every rational weight
/// is exact ([`Scalar::ratio`]).
pub fn evaluate_direct<G: Green, S: Scalar>(g: &G, spec: &KernelSpec, inputs: &[S]) -> Vec<S> {
    assert!(spec.drift.is_none(), "the drift kernels are traced only");
    let mut rest = inputs;
    let mut take = |n: usize| {
        let (head, tail) = rest.split_at(n);
        rest = tail;
        head.to_vec()
    };
    let point = |v: Vec<S>| -> [S; 3] { std::array::from_fn(|k| v[k].clone()) };
    let xa = point(take(3));
    let xb = match spec.interaction {
        Interaction::Pair => point(take(3)),
        Interaction::SelfTerm => xa.clone(),
    };
    let (aa, ab) = match (spec.interaction, spec.equal_radii) {
        (Interaction::Pair, false) => (take(1)[0].clone(), take(1)[0].clone()),
        _ => {
            let a = take(1)[0].clone();
            (a.clone(), a)
        }
    };
    let eta = take(1)[0].clone();
    let params = take(g.params().len());
    let order = spec.order();
    let scale = S::cst(1.0 / (8.0 * std::f64::consts::PI)) / eta;
    let values = block_values(
        g,
        spec,
        &xa,
        &xb,
        &aa,
        &ab,
        &params,
        order,
        Form::collecting(Collection::Atoms),
        Some(&scale),
    );
    let blocks = values;
    if !spec.product {
        return blocks.concat();
    }
    let n = moments_len(&spec.blocks);
    let (va, vb) = (take(n), take(n));
    let (a, b) = fused(&spec.blocks, &blocks, spec.basis, &va, &vb);
    [a, b].concat()
}
