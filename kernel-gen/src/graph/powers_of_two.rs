//! Powers of two carried beside the nodes instead of computed
//! ([`Graph::powers_of_two_carried`]).

use super::{Graph, Id, Op};

impl Graph {
    /// The graph with its power-of-two factors carried beside the nodes instead of
    /// computed, and the new id of every old node (the old node's value, the factor
    /// applied where it was not absorbed).
    ///
    /// Every old node becomes a pair `(x, s)`, its value `s x` with `s = ±2^k`: a
    /// product by a power of two is no node at all (`2 x`, `x / 4`, `-x`); products,
    /// quotients and integer powers multiply the factors; `s x + t x` is `(s + t) x`;
    /// with `through_sums` a sum keeps the factor of its first operand and takes the
    /// other's ratio into a constant multiple (one multiply-add), else it applies both
    /// factors and has factor 1; a square root takes the root of an even power; a
    /// comparison compares the unscaled operands where the factors agree (or against
    /// a rescaled constant). Anything else applies the factor first. Which variant
    /// costs fewer operations depends on the kernel ([`crate::emit::lane_function`]
    /// takes the cheapest of none and both). Scaling by a power of two is exact, so
    /// every value is rounded as before (barring overflow); what changes is that the
    /// doubling `2 e1` and the product `e1 (2 e3)` are no longer nodes of their own,
    /// and that `e1 (2 e3)` and `(2 e1) e3` become one node.
    pub fn powers_of_two_carried(&self, through_sums: bool) -> (Graph, Vec<Id>) {
        let mut g = Graph {
            inputs: self.inputs.clone(),
            ..Graph::default()
        };
        // (node of the new graph, its factor); constants always carry factor 1
        let mut pair: Vec<(Id, f64)> = Vec::with_capacity(self.nodes.len());
        let mut map: Vec<Id> = Vec::with_capacity(self.nodes.len());
        for &op in &self.nodes {
            let p = |a: Id| pair[a as usize];
            let (x, s) = match op {
                Op::Input(k) => (g.intern(Op::Input(k)), 1.0),
                Op::Const(b) => (g.intern(Op::Const(b)), 1.0),
                Op::Add(a, b) => g.sum_scaled(p(a), p(b), through_sums),
                Op::Sub(a, b) => {
                    let (y, t) = p(b);
                    g.sum_scaled(p(a), (y, -t), through_sums)
                }
                Op::Mul(a, b) => g.product_scaled(p(a), p(b)),
                Op::Div(a, b) => g.quotient_scaled(p(a), p(b)),
                Op::Neg(a) => {
                    let (y, t) = p(a);
                    match g.as_const(y) {
                        Some(c) => (g.constant(-c), 1.0),
                        None => (y, -t),
                    }
                }
                Op::Sqrt(a) | Op::Rsqrt(a) => {
                    let root = |g: &mut Graph, y: Id| match op {
                        Op::Sqrt(_) => g.sqrt(y),
                        _ => match g.as_const(y) {
                            Some(c) => g.constant(1.0 / c.sqrt()),
                            None => g.intern(Op::Rsqrt(y)),
                        },
                    };
                    let (y, t) = p(a);
                    match even_power_of_two_root(t) {
                        Some(r) => {
                            let x = root(&mut g, y);
                            (
                                x,
                                if matches!(op, Op::Sqrt(_)) {
                                    r
                                } else {
                                    1.0 / r
                                },
                            )
                        }
                        None => {
                            let y = g.scaled(y, t);
                            (root(&mut g, y), 1.0)
                        }
                    }
                }
                Op::Powi(a, n) => {
                    let (y, t) = p(a);
                    let tn = t.powi(n);
                    if g.as_const(y).is_none() && is_power_of_two(tn) {
                        (g.powi(y, n), tn)
                    } else {
                        let y = g.scaled(y, t);
                        (g.powi(y, n), 1.0)
                    }
                }
                Op::Select(l, r, a, b) => {
                    let (l, r) = g.comparison_unscaled(p(l), p(r));
                    g.choice_scaled(l, r, p(a), p(b))
                }
            };
            pair.push((x, s));
            map.push(g.scaled(x, s));
        }
        (g, map)
    }

    /// `s x`: the node itself, its negation, or a product by the constant.
    fn scaled(&mut self, x: Id, s: f64) -> Id {
        if s == 1.0 {
            return x;
        }
        let c = self.constant(s);
        self.mul(c, x)
    }

    /// `s_a a + s_b b` as `(node, factor)` ([`Graph::powers_of_two_carried`]).
    fn sum_scaled(
        &mut self,
        (a, sa): (Id, f64),
        (b, sb): (Id, f64),
        through_sums: bool,
    ) -> (Id, f64) {
        if a == b && self.as_const(a).is_none() {
            // s_a x + s_b x = (s_a + s_b) x, exact for powers of two
            return self.constant_times(sa + sb, a);
        }
        if !through_sums {
            let (a, b) = (self.scaled(a, sa), self.scaled(b, sb));
            return (self.add(a, b), 1.0);
        }
        match (self.as_const(a), self.as_const(b)) {
            (Some(x), Some(y)) => (self.constant(sa * x + sb * y), 1.0),
            (None, Some(y)) => {
                let k = self.constant(sb * y / sa);
                (self.add(a, k), sa)
            }
            (Some(x), None) => {
                let k = self.constant(sa * x / sb);
                (self.add(k, b), sb)
            }
            (None, None) if sa == sb => (self.add(a, b), sa),
            (None, None) if sa == -sb => (self.sub(a, b), sa),
            // the factor of magnitude 1 where there is one, so that factors spread
            // no further than they must
            (None, None) if sb.abs() == 1.0 && sa.abs() != 1.0 => {
                let r = self.constant(sa / sb);
                let ra = self.mul(r, a);
                (self.add(ra, b), sb)
            }
            (None, None) => {
                let r = self.constant(sb / sa);
                let rb = self.mul(r, b);
                (self.add(a, rb), sa)
            }
        }
    }

    /// `(s_a a) (s_b b)` as `(node, factor)`; a constant factor is split into its
    /// power of two and its mantissa.
    fn product_scaled(&mut self, (a, sa): (Id, f64), (b, sb): (Id, f64)) -> (Id, f64) {
        match (self.as_const(a), self.as_const(b)) {
            (Some(x), Some(y)) => (self.constant(x * y), 1.0),
            (Some(c), None) => self.constant_times(c * sb, b),
            (None, Some(c)) => self.constant_times(c * sa, a),
            (None, None) => (self.mul(a, b), sa * sb),
        }
    }

    /// `c x` as `(x, c)` for a power of two `c`, else `(c x, 1)`.
    fn constant_times(&mut self, c: f64, x: Id) -> (Id, f64) {
        if is_power_of_two(c) {
            return (x, c);
        }
        // a negative multiple carries its sign: `(-c) x` rounds as `c x` does, so
        // `-60 x` and `60 x` are one node
        let (c, s) = if c < 0.0 { (-c, -1.0) } else { (c, 1.0) };
        let c = self.constant(c);
        (self.mul(c, x), s)
    }

    /// `(s_a a) / (s_b b)` as `(node, factor)`.
    fn quotient_scaled(&mut self, (a, sa): (Id, f64), (b, sb): (Id, f64)) -> (Id, f64) {
        match (self.as_const(a), self.as_const(b)) {
            (Some(x), Some(y)) => (self.constant(x / y), 1.0),
            (None, Some(d)) if is_power_of_two(d) => (a, sa / d),
            (None, Some(_)) => (self.div(a, b), sa),
            (Some(c), None) if is_power_of_two(c / sb) => {
                let one = self.constant(1.0);
                (self.div(one, b), c / sb)
            }
            (Some(c), None) => {
                let c = self.constant(c / sb);
                (self.div(c, b), 1.0)
            }
            (None, None) => (self.div(a, b), sa / sb),
        }
    }

    /// The operands of `s_l l > s_r r` compared without their factors where that is
    /// exact (equal factors, or a constant side rescaled), else with them applied.
    fn comparison_unscaled(&mut self, (l, sl): (Id, f64), (r, sr): (Id, f64)) -> (Id, Id) {
        match (self.as_const(l), self.as_const(r)) {
            (None, Some(k)) => {
                let k = self.constant(k / sl);
                if sl > 0.0 {
                    (l, k)
                } else {
                    (k, l)
                }
            }
            (Some(k), None) => {
                let k = self.constant(k / sr);
                if sr > 0.0 {
                    (k, r)
                } else {
                    (r, k)
                }
            }
            (None, None) if sl == sr => {
                if sl > 0.0 {
                    (l, r)
                } else {
                    (r, l)
                }
            }
            _ => (self.scaled(l, sl), self.scaled(r, sr)),
        }
    }

    /// `if l > r { s_a a } else { s_b b }` as `(node, factor)`.
    fn choice_scaled(&mut self, l: Id, r: Id, (a, sa): (Id, f64), (b, sb): (Id, f64)) -> (Id, f64) {
        match (self.as_const(a), self.as_const(b)) {
            (None, Some(k)) => {
                let k = self.constant(k / sa);
                (self.select_gt(l, r, a, k), sa)
            }
            (Some(k), None) => {
                let k = self.constant(k / sb);
                (self.select_gt(l, r, k, b), sb)
            }
            (None, None) if sa == sb => (self.select_gt(l, r, a, b), sa),
            _ => {
                let (a, b) = (self.scaled(a, sa), self.scaled(b, sb));
                (self.select_gt(l, r, a, b), 1.0)
            }
        }
    }
}

/// True for `±2^k` (a normal number with a zero mantissa).
fn is_power_of_two(t: f64) -> bool {
    t.is_normal() && t.to_bits() & ((1 << 52) - 1) == 0
}

/// `sqrt(t)` where `t = 2^(2k)`, a power of two that is a square of one.
fn even_power_of_two_root(t: f64) -> Option<f64> {
    let r = t.sqrt();
    (t > 0.0 && is_power_of_two(t) && is_power_of_two(r) && r * r == t).then_some(r)
}
