//! Hash-consed expression graph: the trace that the jets build and the emitter prints.
//!
//! A [`Trace`] owns a [`Graph`] for the current thread while a kernel is being traced.
//! [`Ex`] is a `Copy` handle to a node of that graph, and implements
//! [`Scalar`], so a Green's function, a jet or an operator run on `Ex` records its
//! arithmetic instead of performing it.
//!
//! Nodes are hash-consed (an identical node is never stored twice), so shared
//! subexpressions are shared by construction. Simplifications are applied as nodes
//! are built, each one rule: constant folding, `x+0`, `x-0`, `0-x`, `x-x`, `x*1`,
//! `x*0`, `x*(-1)`, `x/1`, `0/x`, `-(-x)`, `sqrt(y) sqrt(y) = y`, `c/(x x) = c (1/x)^2`, the pushing of negations outward (so that
//! `a*(-b)` and `-(a*b)` are one node), and the merging of constant factors
//! `c*(d*x) = (cd)*x`. Operands of `+` and `*` are stored in canonical order.
//!
//! The graph is evaluated by an interpreter generic over [`Scalar`] (so in `f64` and in
//! double-double), pruned to the nodes that a chosen set of outputs needs
//! ([`Graph::live`]), and counted ([`Graph::op_count`]).

use crate::scalar::Scalar;
use rustc_hash::FxHashMap;
use std::cell::RefCell;
use std::fmt;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// Index of a node in its graph. Children always have smaller ids than their parents,
/// so id order is a topological order.
pub type Id = u32;

/// One node of the graph.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Op {
    /// The `k`-th input of the traced function.
    Input(u32),
    /// A constant, stored by its bit pattern (`-0.0` is stored as `+0.0`).
    Const(u64),
    /// `a + b`, operands in canonical order.
    Add(Id, Id),
    /// `a - b`.
    Sub(Id, Id),
    /// `a * b`, operands in canonical order.
    Mul(Id, Id),
    /// `a / b`.
    Div(Id, Id),
    /// `-a`.
    Neg(Id),
    /// `sqrt(a)`.
    Sqrt(Id),
    /// `1 / sqrt(a)`: only in the lane form of a graph ([`Graph::lane_form`]).
    Rsqrt(Id),
    /// `a^n` for an integer `n` outside `{0, 1}`.
    Powi(Id, i32),
    /// `if l > r { a } else { b }`: `Select(l, r, a, b)` (a per-lane blend in the lane
    /// kernels).
    Select(Id, Id, Id, Id),
}

impl Op {
    /// The operands, in order (none for inputs and constants).
    pub fn operands(self) -> Vec<Id> {
        match self {
            Op::Input(_) | Op::Const(_) => vec![],
            Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) | Op::Div(a, b) => vec![a, b],
            Op::Neg(a) | Op::Sqrt(a) | Op::Rsqrt(a) | Op::Powi(a, _) => vec![a],
            Op::Select(l, r, a, b) => vec![l, r, a, b],
        }
    }
}

/// A hash-consed expression graph.
#[derive(Clone, Debug, Default)]
pub struct Graph {
    nodes: Vec<Op>,
    /// Hash-consing: the id of every node by its operation (Fx hashing: the graph is
    /// built from the generator's own operations, and SipHash took 6% of `cargo xtask gen`).
    index: FxHashMap<Op, Id>,
    inputs: Vec<String>,
}

/// Operation counts of the part of a graph that a set of outputs needs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OpCount {
    /// Additions and subtractions.
    pub add: usize,
    /// Multiplications.
    pub mul: usize,
    /// Divisions.
    pub div: usize,
    /// Square roots.
    pub sqrt: usize,
    /// Integer powers.
    pub powi: usize,
    /// Negations.
    pub neg: usize,
    /// Comparisons with a choice of two values ([`Op::Select`]).
    pub select: usize,
}

impl OpCount {
    /// All floating-point operations (a negation counts as one, and so does a
    /// comparison with its choice).
    pub fn total(&self) -> usize {
        self.add + self.mul + self.div + self.sqrt + self.powi + self.neg + self.select
    }
}

impl fmt::Display for OpCount {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} flops ({} add/sub, {} mul, {} div, {} sqrt, {} powi, {} neg",
            self.total(),
            self.add,
            self.mul,
            self.div,
            self.sqrt,
            self.powi,
            self.neg
        )?;
        if self.select > 0 {
            write!(f, ", {} select", self.select)?;
        }
        write!(f, ")")
    }
}

fn cbits(c: f64) -> u64 {
    if c == 0.0 {
        0.0f64.to_bits()
    } else {
        c.to_bits()
    }
}

impl Graph {
    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// True for a graph with no nodes.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The node with id `id`.
    pub fn op(&self, id: Id) -> Op {
        self.nodes[id as usize]
    }

    /// Names of the inputs, in input order.
    pub fn input_names(&self) -> &[String] {
        &self.inputs
    }

    /// The constant value of a node, if it is a constant.
    pub fn as_const(&self, id: Id) -> Option<f64> {
        match self.nodes[id as usize] {
            Op::Const(b) => Some(f64::from_bits(b)),
            _ => None,
        }
    }

    fn intern(&mut self, op: Op) -> Id {
        if let Some(&id) = self.index.get(&op) {
            return id;
        }
        let id = Id::try_from(self.nodes.len()).expect("expression graph exceeds u32 nodes");
        self.nodes.push(op);
        self.index.insert(op, id);
        id
    }

    /// A new named input.
    pub fn input(&mut self, name: &str) -> Id {
        let k = self.inputs.len() as u32;
        self.inputs.push(name.to_string());
        self.intern(Op::Input(k))
    }

    /// The constant `c`.
    pub fn constant(&mut self, c: f64) -> Id {
        self.intern(Op::Const(cbits(c)))
    }

    fn neg_of(&self, id: Id) -> Option<Id> {
        match self.nodes[id as usize] {
            Op::Neg(a) => Some(a),
            _ => None,
        }
    }

    /// `a + b`.
    pub fn add(&mut self, a: Id, b: Id) -> Id {
        match (self.as_const(a), self.as_const(b)) {
            (Some(x), Some(y)) => return self.constant(x + y),
            (Some(0.0), None) => return b,
            (None, Some(0.0)) => return a,
            _ => {}
        }
        match (self.neg_of(a), self.neg_of(b)) {
            (Some(u), Some(v)) => {
                let s = self.add(u, v);
                return self.neg(s);
            }
            (None, Some(v)) => return self.sub(a, v),
            (Some(u), None) => return self.sub(b, u),
            _ => {}
        }
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        self.intern(Op::Add(a, b))
    }

    /// `a - b`.
    pub fn sub(&mut self, a: Id, b: Id) -> Id {
        if a == b {
            return self.constant(0.0);
        }
        match (self.as_const(a), self.as_const(b)) {
            (Some(x), Some(y)) => return self.constant(x - y),
            (None, Some(0.0)) => return a,
            (Some(0.0), None) => return self.neg(b),
            _ => {}
        }
        if let Some(v) = self.neg_of(b) {
            return self.add(a, v);
        }
        if let Some(u) = self.neg_of(a) {
            let s = self.add(u, b);
            return self.neg(s);
        }
        self.intern(Op::Sub(a, b))
    }

    /// `a * b`.
    pub fn mul(&mut self, a: Id, b: Id) -> Id {
        match (self.as_const(a), self.as_const(b)) {
            (Some(x), Some(y)) => return self.constant(x * y),
            (Some(0.0), None) | (None, Some(0.0)) => return self.constant(0.0),
            (Some(1.0), None) => return b,
            (None, Some(1.0)) => return a,
            (Some(-1.0), None) => return self.neg(b),
            (None, Some(-1.0)) => return self.neg(a),
            _ => {}
        }
        if let Some(u) = self.neg_of(a) {
            let p = self.mul(u, b);
            return self.neg(p);
        }
        if let Some(v) = self.neg_of(b) {
            let p = self.mul(a, v);
            return self.neg(p);
        }
        // sqrt(y) * sqrt(y) = y: a square root squared is its argument (exact, and no
        // longer behind the square root's latency).
        if a == b {
            if let Op::Sqrt(y) = self.nodes[a as usize] {
                return y;
            }
        }
        // c * (d * x) = (c d) * x: constant factors merge.
        let (c, x) = match (self.as_const(a), self.as_const(b)) {
            (Some(c), None) => (Some(c), b),
            (None, Some(c)) => (Some(c), a),
            _ => (None, a),
        };
        if let Some(c) = c {
            if let Op::Mul(p, q) = self.nodes[x as usize] {
                let inner = match (self.as_const(p), self.as_const(q)) {
                    (Some(d), None) => Some((d, q)),
                    (None, Some(d)) => Some((d, p)),
                    _ => None,
                };
                if let Some((d, y)) = inner {
                    let cd = self.constant(c * d);
                    return self.mul(cd, y);
                }
            }
        }
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        self.intern(Op::Mul(a, b))
    }

    /// The node `op` with its operands `m(operand)`, built by the rules above.
    fn rebuilt(&mut self, op: Op, m: impl Fn(Id) -> Id) -> Id {
        match op {
            Op::Input(k) => self.intern(Op::Input(k)),
            Op::Const(b) => self.intern(Op::Const(b)),
            Op::Add(a, b) => self.add(m(a), m(b)),
            Op::Sub(a, b) => self.sub(m(a), m(b)),
            Op::Mul(a, b) => self.mul(m(a), m(b)),
            Op::Div(a, b) => self.div(m(a), m(b)),
            Op::Neg(a) => self.neg(m(a)),
            Op::Sqrt(a) => self.sqrt(m(a)),
            Op::Rsqrt(a) => self.intern(Op::Rsqrt(m(a))),
            Op::Powi(a, n) => self.powi(m(a), n),
            Op::Select(l, r, a, b) => self.select_gt(m(l), m(r), m(a), m(b)),
        }
    }

    /// The graph with `a (a x)` taken as `(a a) x` wherever the square `a a` is a node
    /// that `live` marks (computed anyway, so the product `a x` is saved), and the new
    /// id of every old node. Decided on the finished graph, so that it does not depend
    /// on which node was built first. The product rounds differently from before, so
    /// two entries that were equal to the bit through different nodes may no longer be
    /// ([`crate::scene`] leaves self kernels alone for this reason).
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

    /// `a / b`.
    pub fn div(&mut self, a: Id, b: Id) -> Id {
        match (self.as_const(a), self.as_const(b)) {
            (Some(x), Some(y)) => return self.constant(x / y),
            (Some(0.0), None) => return self.constant(0.0),
            (None, Some(1.0)) => return a,
            (None, Some(-1.0)) => return self.neg(a),
            _ => {}
        }
        if a == b {
            return self.constant(1.0);
        }
        // c / (x x) = c (1/x) (1/x): the reciprocal of a square shares the reciprocal
        // of its root (one division fewer where 1/x is needed anyway).
        if let (Some(c), Op::Mul(x, y)) = (self.as_const(a), self.nodes[b as usize]) {
            if x == y {
                let one = self.constant(1.0);
                let r = self.div(one, x);
                let r2 = self.mul(r, r);
                return if c == 1.0 { r2 } else { self.mul(a, r2) };
            }
        }
        if let Some(u) = self.neg_of(a) {
            let q = self.div(u, b);
            return self.neg(q);
        }
        if let Some(v) = self.neg_of(b) {
            let q = self.div(a, v);
            return self.neg(q);
        }
        self.intern(Op::Div(a, b))
    }

    /// `-a`.
    pub fn neg(&mut self, a: Id) -> Id {
        if let Some(x) = self.as_const(a) {
            return self.constant(-x);
        }
        match self.nodes[a as usize] {
            Op::Neg(u) => u,
            Op::Sub(u, v) => self.sub(v, u),
            _ => self.intern(Op::Neg(a)),
        }
    }

    /// `sqrt(a)`.
    pub fn sqrt(&mut self, a: Id) -> Id {
        if let Some(x) = self.as_const(a) {
            return self.constant(x.sqrt());
        }
        self.intern(Op::Sqrt(a))
    }

    /// `a^n`.
    pub fn powi(&mut self, a: Id, n: i32) -> Id {
        match n {
            0 => return self.constant(1.0),
            1 => return a,
            _ => {}
        }
        if let Some(x) = self.as_const(a) {
            return self.constant(x.powi(n));
        }
        if n == 2 {
            // a square is a product (one node for `x x` and `x^2`)
            return self.mul(a, a);
        }
        self.intern(Op::Powi(a, n))
    }

    /// `if l > r { a } else { b }`.
    pub fn select_gt(&mut self, l: Id, r: Id, a: Id, b: Id) -> Id {
        if a == b {
            return a;
        }
        if let (Some(x), Some(y)) = (self.as_const(l), self.as_const(r)) {
            return if x > y { a } else { b };
        }
        self.intern(Op::Select(l, r, a, b))
    }

    /// The node `op`, if the graph holds it.
    pub fn find(&self, op: Op) -> Option<Id> {
        self.index.get(&op).copied()
    }

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

    /// Which nodes the outputs depend on (dead-code elimination).
    pub fn live(&self, outputs: &[Id]) -> Vec<bool> {
        let mut live = vec![false; self.nodes.len()];
        let mut stack: Vec<Id> = outputs.to_vec();
        while let Some(id) = stack.pop() {
            if live[id as usize] {
                continue;
            }
            live[id as usize] = true;
            stack.extend(self.nodes[id as usize].operands());
        }
        live
    }

    /// Operation counts of the nodes that `outputs` need.
    pub fn op_count(&self, outputs: &[Id]) -> OpCount {
        let live = self.live(outputs);
        let mut c = OpCount::default();
        for (op, _) in self.nodes.iter().zip(&live).filter(|(_, l)| **l) {
            match op {
                Op::Add(..) | Op::Sub(..) => c.add += 1,
                Op::Mul(..) => c.mul += 1,
                Op::Div(..) => c.div += 1,
                Op::Sqrt(_) | Op::Rsqrt(_) => c.sqrt += 1,
                Op::Powi(..) => c.powi += 1,
                Op::Neg(_) => c.neg += 1,
                Op::Select(..) => c.select += 1,
                Op::Input(_) | Op::Const(_) => {}
            }
        }
        c
    }

    /// The interpreter: evaluate `outputs` for the given inputs, in any [`Scalar`]
    /// (`f64` to compare with the emitted code, double-double for a reference).
    /// Only the live nodes are evaluated, in id (topological) order.
    pub fn eval<S: Scalar>(&self, inputs: &[S], outputs: &[Id]) -> Vec<S> {
        assert_eq!(inputs.len(), self.inputs.len(), "wrong number of inputs");
        let live = self.live(outputs);
        let mut val: Vec<Option<S>> = vec![None; self.nodes.len()];
        for (k, op) in self.nodes.iter().enumerate() {
            if !live[k] {
                continue;
            }
            let v = |i: &Id| val[*i as usize].clone().expect("topological order");
            let x = match op {
                Op::Input(i) => inputs[*i as usize].clone(),
                Op::Const(b) => S::cst(f64::from_bits(*b)),
                Op::Add(a, b) => v(a) + v(b),
                Op::Sub(a, b) => v(a) - v(b),
                Op::Mul(a, b) => v(a) * v(b),
                Op::Div(a, b) => v(a) / v(b),
                Op::Neg(a) => -v(a),
                Op::Sqrt(a) => v(a).sqrt(),
                Op::Rsqrt(a) => S::cst(1.0) / v(a).sqrt(),
                Op::Powi(a, n) => v(a).powi(*n),
                Op::Select(l, r, a, b) => {
                    if v(l).to_f64() > v(r).to_f64() {
                        v(a)
                    } else {
                        v(b)
                    }
                }
            };
            val[k] = Some(x);
        }
        outputs
            .iter()
            .map(|o| val[*o as usize].clone().expect("live output"))
            .collect()
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

thread_local! {
    static CURRENT: RefCell<Option<Graph>> = const { RefCell::new(None) };
}

fn with_graph<R>(f: impl FnOnce(&mut Graph) -> R) -> R {
    CURRENT.with(|g| {
        let mut g = g.borrow_mut();
        let g = g
            .as_mut()
            .expect("expression arithmetic outside a kernel_gen::expr::Trace");
        f(g)
    })
}

/// A handle to a node of the graph being traced on this thread.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Ex(pub Id);

impl fmt::Debug for Ex {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "t{}", self.0)
    }
}

/// Records arithmetic on [`Ex`] into a fresh graph for as long as it lives on this
/// thread; [`Trace::finish`] hands the graph back.
pub struct Trace {
    _private: (),
}

impl Trace {
    /// Start tracing on this thread. Panics if a trace is already running here.
    pub fn begin() -> Trace {
        CURRENT.with(|g| {
            let mut g = g.borrow_mut();
            assert!(g.is_none(), "a Trace is already running on this thread");
            *g = Some(Graph::default());
        });
        Trace { _private: () }
    }

    /// A new named input of the traced function.
    pub fn input(&self, name: &str) -> Ex {
        Ex(with_graph(|g| g.input(name)))
    }

    /// Stop tracing and return the graph.
    pub fn finish(self) -> Graph {
        let g = CURRENT
            .with(|g| g.borrow_mut().take())
            .expect("trace running");
        std::mem::forget(self);
        g
    }
}

impl Drop for Trace {
    fn drop(&mut self) {
        CURRENT.with(|g| g.borrow_mut().take());
    }
}

impl Ex {
    /// The constant value of this node, if it is one.
    pub fn as_const(self) -> Option<f64> {
        with_graph(|g| g.as_const(self.0))
    }
}

impl Ex {
    /// `if l > r { a } else { b }` ([`Op::Select`]).
    pub fn select_gt(l: Ex, r: Ex, a: Ex, b: Ex) -> Ex {
        Ex(with_graph(|g| g.select_gt(l.0, r.0, a.0, b.0)))
    }
}

impl Add for Ex {
    type Output = Ex;
    fn add(self, b: Ex) -> Ex {
        Ex(with_graph(|g| g.add(self.0, b.0)))
    }
}
impl Sub for Ex {
    type Output = Ex;
    fn sub(self, b: Ex) -> Ex {
        Ex(with_graph(|g| g.sub(self.0, b.0)))
    }
}
impl Mul for Ex {
    type Output = Ex;
    fn mul(self, b: Ex) -> Ex {
        Ex(with_graph(|g| g.mul(self.0, b.0)))
    }
}
impl Div for Ex {
    type Output = Ex;
    fn div(self, b: Ex) -> Ex {
        Ex(with_graph(|g| g.div(self.0, b.0)))
    }
}
impl Neg for Ex {
    type Output = Ex;
    fn neg(self) -> Ex {
        Ex(with_graph(|g| g.neg(self.0)))
    }
}

impl Scalar for Ex {
    fn cst(c: f64) -> Self {
        Ex(with_graph(|g| g.constant(c)))
    }
    fn sqrt(&self) -> Self {
        Ex(with_graph(|g| g.sqrt(self.0)))
    }
    fn powi(&self, n: i32) -> Self {
        Ex(with_graph(|g| g.powi(self.0, n)))
    }
    fn to_f64(&self) -> f64 {
        self.as_const().unwrap_or(f64::NAN)
    }
    fn is_known_zero(&self) -> bool {
        self.as_const() == Some(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dd::Dd;

    #[test]
    fn hash_consing_shares_subexpressions() {
        let t = Trace::begin();
        let x = t.input("x");
        let y = t.input("y");
        let a = x * y + x;
        let b = y * x + x; // commuted: same nodes
        assert_eq!(a, b);
        let g = t.finish();
        // inputs x, y; x*y; x*y + x
        assert_eq!(g.len(), 4);
    }

    #[test]
    fn identities_fold_as_nodes_are_built() {
        let t = Trace::begin();
        let x = t.input("x");
        let zero = Ex::cst(0.0);
        let one = Ex::cst(1.0);
        assert_eq!(x + zero, x);
        assert_eq!(x * one, x);
        assert_eq!(x * zero, zero);
        assert_eq!(-(-x), x);
        assert_eq!(x - x, zero);
        assert_eq!(x / one, x);
        assert_eq!((Ex::cst(2.0) + Ex::cst(3.0)).as_const(), Some(5.0));
        // negations are pushed outward: a*(-b) is -(a*b)
        let y = t.input("y");
        assert_eq!(x * (-y), -(x * y));
        assert_eq!(x + (-y), x - y);
        // constant factors merge
        assert_eq!(Ex::cst(2.0) * (Ex::cst(3.0) * x), Ex::cst(6.0) * x);
        drop(t);
    }

    #[test]
    fn dead_code_elimination_and_counts() {
        let t = Trace::begin();
        let x = t.input("x");
        let y = t.input("y");
        let used = (x + y).sqrt() * x;
        let _dead = x / y - y.powi(3);
        let g = t.finish();
        let c = g.op_count(&[used.0]);
        assert_eq!(
            c,
            OpCount {
                add: 1,
                mul: 1,
                sqrt: 1,
                ..OpCount::default()
            }
        );
        assert!(g.len() > 5);
    }

    #[test]
    fn interpreter_in_f64_and_double_double() {
        let t = Trace::begin();
        let x = t.input("x");
        let y = t.input("y");
        let out = (x * x - y * y) / (x - y); // = x + y, computed with cancellation
        let g = t.finish();
        let v: Vec<f64> = g.eval(&[3.0, 2.0], &[out.0]);
        assert_eq!(v[0], 5.0);
        let xd = Dd::new(1.0) + Dd::new(1e-20);
        let w: Vec<Dd> = g.eval(&[xd, Dd::new(1.0)], &[out.0]);
        assert!((w[0] - Dd::new(2.0)).to_f64().abs() < 1e-30);
    }

    #[test]
    fn lane_form_takes_reciprocals_of_square_roots_without_divisions() {
        let t = Trace::begin();
        let x = t.input("x");
        let y = t.input("y");
        let z = t.input("z");
        let (sx, sy) = (x.sqrt(), y.sqrt());
        // 1/|R|, 1/(rho |R|) guarded at rho = 0, |R|/|r| as the traces build them
        let inv = Ex::cst(1.0) / sx;
        let guarded = Ex::cst(3.0) / (Ex::select_gt(y, Ex::cst(0.0), sy, Ex::cst(2.0)) * sx);
        let ratio = Ex::cst(1.0) / (sy * inv);
        // a divisor with one factor that needs a division keeps just that one
        let mixed = z / (sx * (y + z));
        let g = t.finish();
        let outs = [inv.0, guarded.0, ratio.0, mixed.0];
        let (l, map) = g.lane_form();
        let new: Vec<Id> = outs.iter().map(|&o| map[o as usize]).collect();
        let c = l.op_count(&new[..3]);
        // rsqrt(x), rsqrt(y) and sqrt(x) (which the lanes take from rsqrt(x))
        assert_eq!((c.div, c.sqrt), (0, 3), "{c}");
        assert_eq!(l.op_count(&new[3..]).div, 1);
        assert!(l.find(Op::Rsqrt(map[x.0 as usize])).is_some());
        // the same values (to rounding), on both sides of the select
        for inputs in [[2.0, 3.0, 0.5], [5.0, 0.0, 7.0]] {
            let want: Vec<f64> = g.eval(&inputs, &outs);
            let got: Vec<f64> = l.eval(&inputs, &new);
            for (w, v) in want.iter().zip(&got) {
                assert!(
                    w == v || (w - v).abs() <= 4.0 * f64::EPSILON * w.abs(),
                    "{w} {v}"
                );
            }
        }
    }

    #[test]
    fn powers_of_two_are_carried_exactly() {
        let t = Trace::begin();
        let x = t.input("x");
        let y = t.input("y");
        let z = t.input("z");
        let two = Ex::cst(2.0);
        // e1 (2 e3) and (2 e1) e3 are one node once the doubling is carried
        let p = x * (two * y);
        let q = (two * x) * y;
        let sum = Ex::cst(0.5) * p - q; // = -x y
        let root = (Ex::cst(4.0) * (x * x + z * z)).sqrt() * Ex::cst(0.25);
        let guarded = Ex::select_gt(two * z, Ex::cst(1.0), Ex::cst(3.0) * x, -y) / Ex::cst(8.0);
        let mixed = two * x + Ex::cst(3.0) * (y * z) + Ex::cst(0.75);
        // a negative multiple carries its sign: 60 z and -60 z are one node
        let (up, down) = (Ex::cst(60.0) * z + x, y - Ex::cst(-60.0) * z);
        let g = t.finish();
        let outs = [p.0, q.0, sum.0, root.0, guarded.0, mixed.0, up.0, down.0];
        for through_sums in [false, true] {
            let (c, map) = g.powers_of_two_carried(through_sums);
            let new: Vec<Id> = outs.iter().map(|&o| map[o as usize]).collect();
            assert_eq!(new[0], new[1], "one product");
            let sixty = c.find(Op::Const(60.0f64.to_bits())).expect("60 kept");
            let z_new = map[z.0 as usize];
            assert!(c
                .find(Op::Mul(sixty, z_new))
                .or(c.find(Op::Mul(z_new, sixty)))
                .is_some());
            let live = c.live(&new);
            let minus = c.find(Op::Const((-60.0f64).to_bits()));
            assert!(minus.is_none_or(|m| !live[m as usize]), "no product by -60");
            assert!(
                c.op_count(&new).total() < g.op_count(&outs).total(),
                "{} against {}",
                c.op_count(&new),
                g.op_count(&outs)
            );
            // scaling by a power of two is exact: the same values, bit for bit, on both
            // sides of the select
            for inputs in [[0.3, 1.7, 0.9], [-2.5, 0.1, 0.2], [1e3, -7.0, 4e-3]] {
                let want: Vec<f64> = g.eval(&inputs, &outs);
                let got: Vec<f64> = c.eval(&inputs, &new);
                assert_eq!(want, got, "{inputs:?}");
            }
        }
    }

    #[test]
    fn squares_are_shared_where_they_are_live() {
        let t = Trace::begin();
        let a = t.input("a");
        let x = t.input("x");
        let square = a * a;
        let cube_x = a * (a * x); // a (a x): one product fewer as (a a) x
        let g = t.finish();
        let outs = [square.0, cube_x.0];
        let (h, map) = g.squares_shared(&g.live(&outs));
        let new: Vec<Id> = outs.iter().map(|&o| map[o as usize]).collect();
        assert_eq!(g.op_count(&outs).mul, 3);
        assert_eq!(h.op_count(&new).mul, 2);
        // the square not wanted: nothing changes
        let (k, only) = g.squares_shared(&g.live(&outs[1..]));
        let kept = k.find(Op::Mul(only[a.0 as usize], only[a.0 as usize]));
        assert!(kept.is_none_or(|aa| !k.live(&[only[cube_x.0 as usize]])[aa as usize]));
        for inputs in [[1.3, -0.7], [3e-3, 250.0]] {
            let want: Vec<f64> = g.eval(&inputs, &outs);
            let got: Vec<f64> = h.eval(&inputs, &new);
            for (w, v) in want.iter().zip(&got) {
                // two roundings of products either way
                approx::assert_relative_eq!(*w, *v, max_relative = 4.0 * f64::EPSILON);
            }
        }
    }
}
