//! The expression graph: the trace that the jets build and the emitter prints.
//!
//! A [`Trace`] owns a [`Graph`] for the current thread while a kernel is being traced.
//! [`Ex`] is a `Copy` handle to a node of that graph, and implements
//! [`Scalar`](crate::number::scalar::Scalar), so a Green's function, a jet or an
//! operator run on `Ex` records its arithmetic instead of performing it.
//!
//! Nodes are hash-consed (an identical node is never stored twice), so shared
//! subexpressions are shared by construction; the identities of `folding` are applied
//! as nodes are built. Children always have smaller ids than their parents, so id order
//! is a topological order, and every pass below is one sweep in id order that builds a
//! new graph and returns the new id of every old node:
//!
//! - `folding`: the rules every node is built by (constant folding, neutral elements,
//!   negations pushed outward, constant factors merged, canonical operand order);
//! - `lane_form` ([`Graph::lane_form`]): divisors made of square roots rewritten with
//!   reciprocal square roots, for the lane kernels;
//! - `powers_of_two` ([`Graph::powers_of_two_carried`]): factors `±2^k` carried beside
//!   the nodes instead of computed (exact);
//! - `squares` ([`Graph::squares_shared`]): `a (a x) = (a a) x` where the square is
//!   computed anyway;
//! - `interpret`: the nodes a set of outputs needs (dead-code elimination,
//!   [`Graph::live`]), their operation counts ([`Graph::op_count`]) and the
//!   interpreter ([`Graph::eval`], in any scalar: `f64`, double-double);
//! - `trace`: [`Trace`] and [`Ex`], the graph of the current thread;
//! - `elementary`: `exp` and `erfc` of [`Ex`] lowered into arithmetic and choices, so
//!   that the lanes need no elementary functions of their own.

mod elementary;
mod folding;
mod interpret;
mod lane_form;
mod powers_of_two;
mod squares;
mod trace;

pub use interpret::OpCount;
pub use trace::{Ex, Trace};

use rustc_hash::FxHashMap;

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
    /// Hash-consing: the id of every node by its operation (Fx hashing: the keys are the
    /// generator's own operations, so SipHash's resistance to chosen keys buys nothing and
    /// its cost is a visible share of the generation time).
    index: FxHashMap<Op, Id>,
    inputs: Vec<String>,
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

    /// The input called `from` called `to` instead (nothing else changes).
    pub fn rename_input(&mut self, from: &str, to: &str) {
        for n in self.inputs.iter_mut().filter(|n| *n == from) {
            *n = to.to_string();
        }
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

    /// The node `op`, if the graph holds it.
    pub fn find(&self, op: Op) -> Option<Id> {
        self.index.get(&op).copied()
    }
}
