//! The divergence of the blocks over the particle positions (the Brownian drift
//! `kT div M`), by the same derivative path run on jets of degree 1 in the positions.

use super::blocks::block_values;
use super::spec::{Interaction, KernelSpec};
use super::traced::BlockOut;
use crate::graph::Ex;
use crate::number::jet::{Jet, Layout};
use crate::number::scalar::Scalar;
use crate::physics::derivatives::Form;
use crate::physics::green::Green;
use crate::physics::operators::{Moment, Response};

/// The divergence outputs of [`KernelSpec::divergence`]: the blocks evaluated on jets
/// of degree 1 in the positions (`xa` variables 0-2, `xb` 3-5; one point for self
/// kernels), then `a_i = sum_j d/dxb_j M_ij` over the force columns of the `U` and
/// `Omega` rows, and for pairs `b_i = sum_j d/dxa_j M^{ba}_ij` with
/// `M^{ba}_{UF} = (M^{ab}_{UF})^T`, `M^{ba}_{OmegaF} = (M^{ab}_{UL})^T`.
///
/// A Green's function without image terms (`G = J`, free space) is translation
/// invariant: every block is a function of `xa - xb`, so `d/dxb_j M_ij = -d/dxa_j M_ij`,
/// and `sum_j d/dx_j M_ij = 0` for every row by incompressibility: each column of `UF` is
/// a divergence-free flow (the Stokeslet and its Laplacian, the Rotne-Prager-Yamakawa
/// correction), `OmegaF` is half the curl of `UF` (`sum_j d_j eps_ikl d_k M_lj = eps_ikl
/// d_k sum_j d_j M_jl = 0`, `UF` being symmetric) and `UL` its transpose. Its divergence
/// outputs are the constant 0, exactly, where the jets would leave rounding of ~1e-18.
#[allow(clippy::too_many_arguments)]
pub(super) fn divergence_outputs<G: Green>(
    g: &G,
    spec: &KernelSpec,
    xa: &[Ex; 3],
    xb: &[Ex; 3],
    aa: &Ex,
    ab: &Ex,
    params: &[Ex],
    order: usize,
    scale: &Ex,
    form: Form,
) -> Vec<BlockOut> {
    let pair = spec.interaction == Interaction::Pair;
    let l = Layout::get(if pair { 6 } else { 3 }, 1);
    let ja: [Jet<Ex>; 3] = std::array::from_fn(|k| Jet::variable(&l, k, xa[k]));
    let jb: [Jet<Ex>; 3] = if pair {
        std::array::from_fn(|k| Jet::variable(&l, 3 + k, xb[k]))
    } else {
        ja.clone()
    };
    let c = |e: &Ex| Jet::constant(*e);
    let jp: Vec<Jet<Ex>> = params.iter().map(c).collect();
    let values = block_values(g, spec, &ja, &jb, &c(aa), &c(ab), &jp, order, form, None);
    let block = |r: Response, m: Moment| -> Option<&Vec<Jet<Ex>>> {
        spec.blocks
            .iter()
            .position(|&b| b == (r, m))
            .map(|k| &values[k])
    };
    // d/d(variable) of entry (i, j) of a 3x3 block
    let d = |blk: &Vec<Jet<Ex>>, i: usize, j: usize, var: usize| -> Ex {
        let mut m = vec![0u8; l.nvars];
        m[var] = 1;
        blk[3 * i + j].derivative(&m)
    };
    let sum3 = |f: &dyn Fn(usize) -> Ex| (0..3).map(f).fold(Ex::cst(0.0), |acc, v| acc + v);
    let uf = block(Response::U, Moment::F).expect("divergence kernels need the UF block");
    let of = block(Response::Omega, Moment::F);
    let ul = block(Response::U, Moment::L);
    let src_var = |j: usize| if pair { 3 + j } else { j };
    let mut a: Vec<Ex> = (0..3).map(|i| sum3(&|j| d(uf, i, j, src_var(j)))).collect();
    if let Some(of) = of {
        a.extend((0..3).map(|i| sum3(&|j| d(of, i, j, src_var(j)))));
    }
    let translation_invariant = g.image_terms().is_some_and(|t| t.is_empty());
    let ids = |v: Vec<Ex>| -> Vec<_> {
        v.into_iter()
            .map(|v| match translation_invariant {
                true => Ex::cst(0.0).0,
                false => (*scale * v).0,
            })
            .collect()
    };
    let mut outs = vec![BlockOut {
        name: "a".into(),
        block: None,
        shape: vec![a.len()],
        ids: ids(a),
    }];
    if pair {
        let mut b: Vec<Ex> = (0..3).map(|i| sum3(&|j| d(uf, j, i, j))).collect();
        if of.is_some() {
            let ul = ul.expect("FT pair divergence needs the UL block");
            b.extend((0..3).map(|i| sum3(&|j| d(ul, j, i, j))));
        }
        outs.push(BlockOut {
            name: "b".into(),
            block: None,
            shape: vec![b.len()],
            ids: ids(b),
        });
    }
    outs
}
