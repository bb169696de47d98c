//! Squares shared: `a (a x) = (a a) x` where the square is computed anyway
//! ([`Graph::squares_shared`]).

use super::{Graph, Id, Op};

impl Graph {
    /// The graph with `a (a x)` taken as `(a a) x` wherever the square `a a` is a node
    /// that `live` marks (computed anyway, so the product `a x` is saved), and the new
    /// id of every old node. Decided on the finished graph, so that it does not depend
    /// on which node was built first. The product rounds differently from before, so
    /// two entries that were equal to the bit through different nodes may no longer be
    /// ([`crate::kernel`] leaves self kernels alone for this reason).
    pub fn squares_shared(&self, live: &[bool]) -> (Graph, Vec<Id>) {
        let mut g = Graph {
            inputs: self.inputs.clone(),
            ..Graph::default()
        };
        let mut map: Vec<Id> = Vec::with_capacity(self.nodes.len());
        for &op in &self.nodes {
            let square_first = match op {
                Op::Mul(a, b) => [(a, b), (b, a)].into_iter().find_map(|(u, v)| {
                    let Op::Mul(p, q) = self.nodes[v as usize] else {
                        return None;
                    };
                    let x = if p == u {
                        q
                    } else if q == u {
                        p
                    } else {
                        return None;
                    };
                    let uu = self.find(Op::Mul(u, u))?;
                    (x != u && self.as_const(u).is_none() && live[uu as usize]).then_some((u, x))
                }),
                _ => None,
            };
            let id = match square_first {
                Some((u, x)) => {
                    let uu = g.mul(map[u as usize], map[u as usize]);
                    g.mul(uu, map[x as usize])
                }
                None => g.rebuilt(op, |a| map[a as usize]),
            };
            map.push(id);
        }
        (g, map)
    }
}
