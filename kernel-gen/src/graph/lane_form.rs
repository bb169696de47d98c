//! The lane form of a graph: divisors made of square roots rewritten with reciprocal
//! square roots ([`Graph::lane_form`]).

use super::{Graph, Id, Op};

impl Graph {
    /// The graph rewritten for the lane kernels, and the new id of every old node: each
    /// quotient `c / x` whose divisor is made of square roots becomes a product with
    /// reciprocal square roots, so that `1/|R|`, `1/rho` and `|R|/|r|` come from
    /// `rsqrt` (one pipelined instruction and Newton steps, in parallel) instead of
    /// a square root and then a division after it (two latencies in a row). The
    /// rules, applied to the divisor recursively: `1/sqrt(y) = rsqrt(y)`,
    /// `1/rsqrt(y) = sqrt(y)`, `1/(1/y) = y`, `1/(p q) = (1/p)(1/q)`,
    /// `1/p^n = (1/p)^n` and `1/select(c, p, q) = select(c, 1/p, 1/q)`, each taken only
    /// where every factor has a reciprocal without a division (a constant counts), or,
    /// for a product, where one factor has: `c/(p q) = (c/q) (1/p)`. Everything else
    /// is copied.
    pub fn lane_form(&self) -> (Graph, Vec<Id>) {
        let mut g = Graph {
            inputs: self.inputs.clone(),
            ..Graph::default()
        };
        let mut map: Vec<Id> = Vec::with_capacity(self.nodes.len());
        for &op in &self.nodes {
            let m = |a: Id| map[a as usize];
            let id = match op {
                Op::Div(a, b) => g.quotient_by_roots(m(a), m(b)),
                _ => g.rebuilt(op, m),
            };
            map.push(id);
        }
        (g, map)
    }

    /// `a / b` by the rules of [`Graph::lane_form`]: `a (1/b)` where `1/b` needs no
    /// division, `(a/q) (1/p)` where only the factor `p` of `b = p q` has such a
    /// reciprocal, else the division itself.
    fn quotient_by_roots(&mut self, a: Id, b: Id) -> Id {
        if let Some(r) = self.cheap_reciprocal(b) {
            return self.mul(a, r);
        }
        if let Op::Mul(p, q) = self.nodes[b as usize] {
            for (root, other) in [(p, q), (q, p)] {
                if let Some(r) = self.cheap_reciprocal(root) {
                    let d = self.div(a, other);
                    return self.mul(d, r);
                }
            }
        }
        self.div(a, b)
    }

    /// `1/x` built without a division, where the rules of [`Graph::lane_form`] allow.
    fn cheap_reciprocal(&mut self, x: Id) -> Option<Id> {
        if let Some(c) = self.as_const(x) {
            return Some(self.constant(1.0 / c));
        }
        match self.nodes[x as usize] {
            Op::Sqrt(y) => Some(self.intern(Op::Rsqrt(y))),
            Op::Rsqrt(y) => Some(self.sqrt(y)),
            Op::Div(c, y) if self.as_const(c) == Some(1.0) => Some(y),
            Op::Mul(p, q) => {
                let rp = self.cheap_reciprocal(p)?;
                let rq = self.cheap_reciprocal(q)?;
                Some(self.mul(rp, rq))
            }
            Op::Powi(p, n) => {
                let rp = self.cheap_reciprocal(p)?;
                Some(self.powi(rp, n))
            }
            Op::Select(l, r, p, q) => {
                let rp = self.cheap_reciprocal(p)?;
                let rq = self.cheap_reciprocal(q)?;
                Some(self.select_gt(l, r, rp, rq))
            }
            _ => None,
        }
    }
}
