//! The rules every node is built by, each one identity: constant folding, `x+0`,
//! `x-0`, `0-x`, `x-x`, `x*1`, `x*0`, `x*(-1)`, `x/1`, `0/x`, `x/x`, `-(-x)`,
//! `sqrt(y) sqrt(y) = y`, `c/(x x) = c (1/x)^2`, `x^0`, `x^1`, `x^2 = x x`, the pushing
//! of negations outward (so that `a*(-b)` and `-(a*b)` are one node), and the merging of
//! constant factors `c*(d*x) = (cd)*x`. Operands of `+` and `*` are stored in canonical
//! order.

use super::{Graph, Id, Op};

impl Graph {
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
    pub(super) fn rebuilt(&mut self, op: Op, m: impl Fn(Id) -> Id) -> Id {
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
}
