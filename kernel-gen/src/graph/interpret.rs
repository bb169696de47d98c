//! What a set of outputs needs: the live nodes (dead-code elimination), their
//! operation counts, and the interpreter that evaluates them in any [`Scalar`].

use super::{Graph, Id, Op};
use crate::number::scalar::Scalar;
use std::fmt;

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

impl Graph {
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
