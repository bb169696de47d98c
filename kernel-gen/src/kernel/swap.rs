//! The exchange of the particles' roles in a pair kernel near a cancelling image.

use super::traced::{Arg, BlockOut};
use crate::graph::Id;
use crate::physics::operators::{block_name, moment_dim, response_dim, Basis, Moment, Response};

/// The reciprocal evaluation of a wall pair kernel: `M^{ab} = (M^{ba})^T` (the grand
/// mobility is symmetric, Eq. 10), so where the source particle `b` is farther from
/// the cancelling plane than the field particle `a`, the kernel is evaluated with the
/// roles exchanged and its outputs transposed. The direct sum's leftover cancellation
/// (between the image's terms of first order in the source height, see
/// [`crate::physics::derivatives`]) is then `rho / h_max`, bounded by the far-field switch,
/// instead of `rho / h_min`, which is not.
pub struct Swap {
    /// Exchange where `lhs > rhs`: the source's height over the plane, the field's.
    pub cond: (Id, Id),
    /// For each argument, the argument passed in its place.
    pub args: Vec<usize>,
    /// For each output entry (flattened in output order), the entry of the exchanged
    /// evaluation it equals.
    pub outputs: Vec<usize>,
}

/// The exchange of particles `a` and `b` ([`Swap`]) for a pair kernel with arguments
/// `args` and outputs `outputs`: arguments `xa <-> xb`, `aa <-> ab`, `va <-> vb`;
/// block `(r, m)` entry `(i, j)` from the dual block `(m*, r*)` entry `(j, i)`
/// (`U <-> F`, `Omega <-> L`, `E <-> S`); the fused products' and the divergences'
/// outputs `a <-> b`.
pub(super) fn exchange(args: &[Arg], outputs: &[BlockOut], cond: (Id, Id)) -> Swap {
    fn partner(n: &str) -> &str {
        match n {
            "xa" => "xb",
            "xb" => "xa",
            "aa" => "ab",
            "ab" => "aa",
            "va" => "vb",
            "vb" => "va",
            other => other,
        }
    }
    let arg_perm: Vec<usize> = args
        .iter()
        .map(|a| {
            let p = partner(&a.name);
            args.iter()
                .position(|b| b.name == p)
                .expect("the partner argument exists")
        })
        .collect();
    let mut start = Vec::new();
    let mut at = 0;
    for b in outputs {
        start.push(at);
        at += b.ids.len();
    }
    let find = |name: &str| {
        outputs
            .iter()
            .position(|b| b.name == name)
            .unwrap_or_else(|| panic!("the exchanged output {name} exists"))
    };
    let mut perm = Vec::new();
    for b in outputs {
        match b.block {
            Some((r, m)) => {
                let dual = (
                    match m {
                        Moment::F => Response::U,
                        Moment::L => Response::Omega,
                        Moment::S => Response::E,
                    },
                    match r {
                        Response::U => Moment::F,
                        Response::Omega => Moment::L,
                        Response::E => Moment::S,
                    },
                );
                let k = find(&block_name(dual.0, dual.1));
                let (rows, cols) = (
                    response_dim(r, Basis::Orthonormal),
                    moment_dim(m, Basis::Orthonormal),
                );
                assert_eq!(outputs[k].ids.len(), rows * cols, "dual block shape");
                for p in 0..rows * cols {
                    let (i, j) = (p / cols, p % cols);
                    perm.push(start[k] + j * rows + i);
                }
            }
            None => {
                let k = find(match b.name.as_str() {
                    "a" => "b",
                    "b" => "a",
                    other => panic!("no partner for output {other}"),
                });
                perm.extend((0..b.ids.len()).map(|p| start[k] + p));
            }
        }
    }
    Swap {
        cond,
        args: arg_perm,
        outputs: perm,
    }
}
