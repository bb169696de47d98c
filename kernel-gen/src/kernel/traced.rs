//! A traced kernel: its graph, arguments and outputs, its branches, and its evaluation
//! by the interpreter, as the emitted code evaluates it.

use super::swap::Swap;
use crate::graph::{Graph, Id};
use crate::number::scalar::Scalar;
use crate::physics::operators::{Moment, Response};

/// Shape of a kernel argument.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArgKind {
    /// `[f64; 3]`.
    Point,
    /// `f64`.
    Scalar,
    /// `[f64; n]`.
    Vector(usize),
}

impl ArgKind {
    /// How many graph inputs (scalars) the argument is.
    pub fn width(self) -> usize {
        match self {
            ArgKind::Point => 3,
            ArgKind::Scalar => 1,
            ArgKind::Vector(n) => n,
        }
    }
}

/// A kernel argument and its meaning.
#[derive(Clone, Debug)]
pub struct Arg {
    /// Rust name.
    pub name: String,
    /// Shape.
    pub kind: ArgKind,
    /// One line for the documentation.
    pub doc: String,
}

/// One output block, row-major, with the array shape it is returned in.
#[derive(Clone, Debug)]
pub struct BlockOut {
    /// Block name (`uf`, `es`, ...).
    pub name: String,
    /// Response and moment (`None` for the fused product's vectors).
    pub block: Option<(Response, Moment)>,
    /// Nested array shape, outermost first (e.g. `[3, 3]`, `[3, 3, 3, 3]`).
    pub shape: Vec<usize>,
    /// Graph outputs, row-major.
    pub ids: Vec<Id>,
}

/// A traced kernel: the graph, its arguments and its outputs.
pub struct Traced {
    /// The expression graph (inputs in argument order, points as three inputs).
    pub graph: Graph,
    /// Arguments.
    pub args: Vec<Arg>,
    /// Output blocks.
    pub outputs: Vec<BlockOut>,
    /// Highest derivative order of `G` the operators needed (the jets are truncated
    /// accordingly).
    pub order: usize,
    /// The lateral far-field branch ([`crate::physics::farfield`]), where it applies.
    pub far: Option<FarBranch>,
    /// The exchange of the particles' roles, where it applies ([`Swap`]).
    pub swap: Option<Swap>,
}

/// A second set of outputs, taken where every condition `lhs > rhs` holds (the switch
/// to the lateral far-field expansion, [`crate::physics::farfield`], or to the closed-form self
/// term, [`crate::physics::self_image`]); [`Traced::outputs`] is the direct sum, taken otherwise.
pub struct FarBranch {
    /// The conditions `(lhs, rhs)`, all of which select the branch.
    pub conds: Vec<(Id, Id)>,
    /// The outputs of the branch, in the shapes of [`Traced::outputs`].
    pub outputs: Vec<BlockOut>,
    /// One line for the generated documentation: what the branch is and where it is
    /// taken.
    pub doc: String,
    /// Short name for operation-count reports (`far field`, `closed form`).
    pub label: &'static str,
}

impl FarBranch {
    /// The nodes of the conditions.
    pub fn condition_ids(&self) -> Vec<Id> {
        self.conds.iter().flat_map(|&(l, r)| [l, r]).collect()
    }
}

impl Traced {
    /// The same kernel with the run-time parameters `from` named and documented as `to`
    /// (in order): arguments and graph inputs.
    pub fn renamed(
        mut self,
        from: &[crate::physics::green::Param],
        to: &[crate::physics::green::Param],
    ) -> Traced {
        for (f, t) in from.iter().zip(to) {
            for a in self.args.iter_mut().filter(|a| a.name == f.name) {
                a.name = t.name.into();
                a.doc = t.doc.into();
            }
            self.graph.rename_input(f.name, t.name);
        }
        self
    }

    /// The same kernel on `graph`, where `map` takes every old id to its new one.
    pub(super) fn remapped(self, graph: Graph, map: &[Id]) -> Traced {
        let Traced {
            args,
            mut outputs,
            order,
            mut far,
            mut swap,
            ..
        } = self;
        let new = |id: &mut Id| *id = map[*id as usize];
        for o in outputs.iter_mut() {
            o.ids.iter_mut().for_each(new);
        }
        if let Some(f) = far.as_mut() {
            for o in f.outputs.iter_mut() {
                o.ids.iter_mut().for_each(new);
            }
            for (l, r) in f.conds.iter_mut() {
                new(l);
                new(r);
            }
        }
        if let Some(w) = swap.as_mut() {
            new(&mut w.cond.0);
            new(&mut w.cond.1);
        }
        Traced {
            graph,
            args,
            outputs,
            order,
            far,
            swap,
        }
    }

    /// All output ids in order.
    pub fn output_ids(&self) -> Vec<Id> {
        self.outputs
            .iter()
            .flat_map(|b| b.ids.iter().copied())
            .collect()
    }

    /// The far branch's output ids in order (empty without a far branch).
    pub fn far_ids(&self) -> Vec<Id> {
        self.far
            .iter()
            .flat_map(|f| f.outputs.iter().flat_map(|b| b.ids.iter().copied()))
            .collect()
    }

    /// Whether the roles are exchanged for these inputs (as the emitted code decides).
    pub fn takes_swap<S: Scalar>(&self, inputs: &[S]) -> bool {
        match &self.swap {
            None => false,
            Some(w) => {
                let v = self.graph.eval(inputs, &[w.cond.0, w.cond.1]);
                v[0].to_f64() > v[1].to_f64()
            }
        }
    }

    /// Whether the far branch is taken for these inputs (as the emitted code decides:
    /// the condition evaluated in the same scalar).
    pub fn takes_far<S: Scalar>(&self, inputs: &[S]) -> bool {
        match &self.far {
            None => false,
            Some(f) => {
                let v = self.graph.eval(inputs, &f.condition_ids());
                v.chunks(2).all(|c| c[0].to_f64() > c[1].to_f64())
            }
        }
    }

    /// The kernel as emitted: the exchange of roles, then the branch the condition
    /// selects, evaluated by the interpreter.
    pub fn eval<S: Scalar>(&self, inputs: &[S]) -> Vec<S> {
        if let Some(w) = self.swap.as_ref().filter(|_| self.takes_swap(inputs)) {
            // the graph inputs of each argument, in the exchanged argument order
            let mut first = Vec::new();
            let mut at = 0;
            for a in &self.args {
                first.push(at);
                at += a.kind.width();
            }
            let exchanged: Vec<S> = w
                .args
                .iter()
                .flat_map(|&j| inputs[first[j]..first[j] + self.args[j].kind.width()].to_vec())
                .collect();
            let out = self.eval(&exchanged);
            return w.outputs.iter().map(|&k| out[k].clone()).collect();
        }
        if self.takes_far(inputs) {
            self.graph.eval(inputs, &self.far_ids())
        } else {
            self.graph.eval(inputs, &self.output_ids())
        }
    }
}
