//! The derivatives of the blocks over the particle positions ([`Drift`]): the
//! divergence (the Brownian drift `kT div M`) and the derivative along a direction, by
//! the same derivative path run on jets of degree 1 in the positions.

use super::blocks::block_values;
use super::spec::{Drift, Interaction, KernelSpec};
use super::traced::BlockOut;
use crate::graph::Ex;
use crate::number::jet::{Jet, Layout};
use crate::number::scalar::Scalar;
use crate::physics::derivatives::Form;
use crate::physics::green::Green;
use crate::physics::operators::{Moment, Response};

/// Where a drift kernel is evaluated: the centres and radii (one point for self
/// kernels, `xa == xb`), and for [`Drift::Along`] the direction `v`.
pub(super) struct Points<'a> {
    pub xa: &'a [Ex; 3],
    pub xb: &'a [Ex; 3],
    pub aa: &'a Ex,
    pub ab: &'a Ex,
    pub v: Option<&'a [Ex; 3]>,
}

/// The outputs of a drift kernel ([`KernelSpec::drift`]): the blocks evaluated on jets
/// of degree 1 in the positions, then over the force columns of the `U` and `Omega`
/// rows `a_i = sum_j c_j(M_ij)` and, for pairs, `b_i = sum_j c_j(M^{ba}_ij)` with
/// `M^{ba}_{UF} = (M^{ab}_{UF})^T`, `M^{ba}_{OmegaF} = (M^{ab}_{UL})^T`, where the column
/// term `c_j` is
/// - [`Drift::Divergence`]: `d/dx_j` (jet variables `xa` 0-2, `xb` 3-5 for pairs, the
///   one point's 0-2 for self kernels);
/// - [`Drift::Along`]: `v_j d/dt` with the points moved to `x + t v` (one variable `t`
///   per point, `xa` 0 and `xb` 1 for pairs; `t` moves both arguments of a self
///   kernel), so that `sum_j v_j d/dt M_ij = sum_jk v_j v_k d/dx_k M_ij`;
/// - [`Drift::Together`]: `v_j d/dt` with both points moved to `x + t v` by one variable
///   `t` (for a self kernel the same as [`Drift::Along`]).
///
/// A Green's function without image terms (`G = J`, free space) is translation
/// invariant: every block is a function of `xa - xb`, so `d/dxb_j M_ij = -d/dxa_j M_ij`,
/// and `sum_j d/dx_j M_ij = 0` for every row by incompressibility: each column of `UF` is
/// a divergence-free flow (the Stokeslet and its Laplacian, the Rotne-Prager-Yamakawa
/// correction), `OmegaF` is half the curl of `UF` (`sum_j d_j eps_ikl d_k M_lj = eps_ikl
/// d_k sum_j d_j M_jl = 0`, `UF` being symmetric) and `UL` its transpose. Its divergence
/// outputs are the constant 0, exactly, where the jets would leave rounding of ~1e-18.
/// (Its derivatives along a direction are not zero.)
#[allow(clippy::too_many_arguments)]
pub(super) fn drift_outputs<G: Green>(
    g: &G,
    spec: &KernelSpec,
    drift: Drift,
    at: &Points,
    params: &[Ex],
    order: usize,
    scale: &Ex,
    form: Form,
) -> Vec<BlockOut> {
    let pair = spec.interaction == Interaction::Pair;
    let points = if pair { 2 } else { 1 };
    let c = |e: &Ex| Jet::constant(*e);
    let (l, ja, jb): (_, [Jet<Ex>; 3], [Jet<Ex>; 3]) = match (drift, at.v) {
        (Drift::Divergence, _) => {
            let l = Layout::get(3 * points, 1);
            let ja: [Jet<Ex>; 3] = std::array::from_fn(|k| Jet::variable(&l, k, at.xa[k]));
            let jb = match pair {
                true => std::array::from_fn(|k| Jet::variable(&l, 3 + k, at.xb[k])),
                false => ja.clone(),
            };
            (l, ja, jb)
        }
        (Drift::Along | Drift::Together, Some(v)) => {
            let together = drift == Drift::Together;
            let l = Layout::get(if together { 1 } else { points }, 1);
            // x + t v
            let moved = |x: &[Ex; 3], var: usize| -> [Jet<Ex>; 3] {
                let t = Jet::variable(&l, var, Ex::cst(0.0));
                std::array::from_fn(|k| c(&x[k]) + c(&v[k]) * t.clone())
            };
            let ja = moved(at.xa, 0);
            let jb = match (pair, together) {
                (true, false) => moved(at.xb, 1),
                (true, true) => moved(at.xb, 0),
                (false, _) => ja.clone(),
            };
            (l, ja, jb)
        }
        (Drift::Along | Drift::Together, None) => {
            panic!("a derivative along a direction needs the direction")
        }
    };
    let jp: Vec<Jet<Ex>> = params.iter().map(c).collect();
    let values = block_values(
        g,
        spec,
        &ja,
        &jb,
        &c(at.aa),
        &c(at.ab),
        &jp,
        order,
        form,
        None,
    );
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
    // the term `c_k` of entry (i, j), moving the source (`b`) or the field point (`a`)
    let term = |blk: &Vec<Jet<Ex>>, (i, j): (usize, usize), k: usize, source: bool| -> Ex {
        // one variable moves both points of a `Together` pair
        let first = if source && pair && drift != Drift::Together {
            1
        } else {
            0
        };
        match (drift, at.v) {
            (Drift::Divergence, _) => d(blk, i, j, 3 * first + k),
            (_, Some(v)) => v[k] * d(blk, i, j, first),
            (_, None) => unreachable!("checked above"),
        }
    };
    let sum3 = |f: &dyn Fn(usize) -> Ex| (0..3).map(f).fold(Ex::cst(0.0), |acc, v| acc + v);
    let uf = block(Response::U, Moment::F).expect("drift kernels need the UF block");
    let of = block(Response::Omega, Moment::F);
    let ul = block(Response::U, Moment::L);
    let mut a: Vec<Ex> = (0..3)
        .map(|i| sum3(&|j| term(uf, (i, j), j, true)))
        .collect();
    if let Some(of) = of {
        a.extend((0..3).map(|i| sum3(&|j| term(of, (i, j), j, true))));
    }
    let zero = drift == Drift::Divergence && g.image_terms().is_some_and(|t| t.is_empty());
    let ids = |v: Vec<Ex>| -> Vec<_> {
        v.into_iter()
            .map(|v| match zero {
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
        let mut b: Vec<Ex> = (0..3)
            .map(|i| sum3(&|j| term(uf, (j, i), j, false)))
            .collect();
        if of.is_some() {
            let ul = ul.expect("FT pair drift kernels need the UL block");
            b.extend((0..3).map(|i| sum3(&|j| term(ul, (j, i), j, false))));
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
