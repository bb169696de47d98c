//! What a kernel computes: which confinement, self or pair, which blocks, in which
//! strain basis, for equal or unequal radii; and the tracing of such a kernel into an
//! expression graph with named inputs and block-shaped outputs.
//!
//! Pair kernels (particles `a != b`) are `M^{ab}` from `G = J + J^w` (Eq. 16); self
//! kernels are the isolated sphere plus the reflected field only (Eq. 17). All blocks
//! are dimensional: the Green's functions in units of `1/(8 pi eta)` are scaled by
//! `1/(8 pi eta)` as the last step.

use crate::derivatives::{Collection, Differences, Form, GenericJets, Part, Structured};
use crate::expr::{Ex, Graph, Id, Trace};
use crate::frame::Frame;
use crate::green::Green;
use crate::jet::{Jet, Layout};
use crate::operators::{
    self, apply, block_name, isolated, max_order, moment_dim, response_dim, Basis, Moment, Response,
};
use crate::scalar::Scalar;

/// Self (`alpha = alpha`, Eq. 17) or pair (Eq. 16) interaction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interaction {
    /// One particle with the reflected field of itself.
    SelfTerm,
    /// Two distinct particles.
    Pair,
}

/// How the derivatives are obtained.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Path {
    /// Jets of the Stokeslet in `r` and of each image term in `R`, Eq. 10 (production).
    Structured,
    /// The same, but the Stokeslet and its image summed directly, without the exactly
    /// evaluated difference ([`Structured::direct_sum`]) and without the generator's
    /// other branches: the reference of the stiff cases, and their "before".
    StructuredDirectSum,
    /// The same, but the image is differentiated as a function of `x - y'` only
    /// (Bossis et al.; wrong, asymmetric: Sec. III A).
    StructuredNoExplicitHeight,
    /// Jets of the whole `G(x, y)` in six variables.
    Generic,
}

/// One kernel to trace.
#[derive(Clone, Debug)]
pub struct KernelSpec {
    /// Self or pair.
    pub interaction: Interaction,
    /// Strain/stresslet representation.
    pub basis: Basis,
    /// One radius `a` for both particles (pair kernels only).
    pub equal_radii: bool,
    /// The blocks to compute, in output order.
    pub blocks: Vec<(Response, Moment)>,
    /// Derivative path.
    pub path: Path,
    /// Instead of the blocks, the fused symmetric pair product: inputs `va`, `vb` (the
    /// moments of particles a and b, `[F, L, S]` truncated to the blocks' moments) and
    /// outputs `a = M^{ab} vb`, `b = M^{ba} va = (M^{ab})^T va` (pair kernels only).
    pub product: bool,
    /// Instead of the blocks, their divergence with respect to the particle positions
    /// (the Brownian drift `kT div M`): outputs `a_i = sum_j d/dxb_j M^{ab}_{ij}` and, for
    /// pairs, `b_i = sum_j d/dxa_j M^{ba}_{ij}` over the force columns, rows `U` then
    /// `Omega` as kept (F: 3, FT: 6). Obtained by running the same derivative path on
    /// jets, of degree 1 in the positions, whose coefficients are expression nodes.
    pub divergence: bool,
}

impl KernelSpec {
    /// Highest derivative order of `G` that the blocks' operators need.
    pub fn order(&self) -> usize {
        self.blocks
            .iter()
            .map(|&(r, m)| max_order(r, m))
            .max()
            .unwrap_or(0)
    }
}

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

/// Components of a response or moment kept when the blocks are `blocks`, in grand
/// order `[U|F (3), Omega|L (3), E|S (5)]`.
fn kept(blocks: &[(Response, Moment)]) -> (bool, bool) {
    let l = blocks
        .iter()
        .any(|&(r, m)| r == Response::Omega || m == Moment::L);
    let s = blocks
        .iter()
        .any(|&(r, m)| r == Response::E || m == Moment::S);
    (l, s)
}

/// Length of the fused products' moment vectors for `blocks`.
fn moments_len(blocks: &[(Response, Moment)]) -> usize {
    let (l, s) = kept(blocks);
    3 + if l { 3 } else { 0 } + if s { 5 } else { 0 }
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
    /// The lateral far-field branch ([`crate::farfield`]), where it applies.
    pub far: Option<FarBranch>,
    /// The exchange of the particles' roles, where it applies ([`Swap`]).
    pub swap: Option<Swap>,
}

/// The reciprocal evaluation of a wall pair kernel: `M^{ab} = (M^{ba})^T` (the grand
/// mobility is symmetric, Eq. 10), so where the source particle `b` is farther from
/// the cancelling plane than the field particle `a`, the kernel is evaluated with the
/// roles exchanged and its outputs transposed. The direct sum's leftover cancellation
/// (between the image's terms of first order in the source height, see
/// [`crate::derivatives`]) is then `rho / h_max`, bounded by the far-field switch,
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

/// A second set of outputs, taken where every condition `lhs > rhs` holds (the switch
/// to the lateral far-field expansion, [`crate::farfield`], or to the closed-form self
/// term, [`crate::self_image`]); [`Traced::outputs`] is the direct sum, taken otherwise.
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
    /// The same kernel on `graph`, where `map` takes every old id to its new one.
    fn remapped(self, graph: Graph, map: &[Id]) -> Traced {
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

fn shape(r: Response, m: Moment, b: Basis) -> Vec<usize> {
    let side = |n: usize| if n == 9 { vec![3, 3] } else { vec![n] };
    let mut s = side(response_dim(r, b));
    s.extend(side(moment_dim(m, b)));
    s
}

/// Trace kernel `spec` for Green's function `g`. With the structured path, three
/// times: each entry collected whole ([`Collection::Entries`], polynomials of
/// [`crate::poly`]), the same with each polynomial in its cheapest form on the unit
/// sphere ([`Collection::EntriesOnSphere`]), and the atoms combined one by one
/// ([`Collection::Atoms`]); the cheapest trace (operations of the direct sum; the
/// first of equals) is kept. The sphere forms cut the free-space FTS lane kernel from
/// 576 to 565 operations and the divergence lane kernels by 2-6%, for 0.5 s more
/// generation (6.5 s in all, 2026-12-03). A Green's function without images (free
/// space) is traced in the world frame as well (its pair kernels otherwise in the
/// canonical frame of [`crate::frame`]): free F product lanes 68 -> 58 operations, FTS
/// pair lanes 565 -> 390. The per-centre collection
/// ([`Collection::Centres`]) is not traced: it collects a subset of what `Entries`
/// collects and cost more in every shipped kernel (measured when `Entries` came,
/// 2026-12-02). Near a cancelling image (the wall) the winner is traced once more with
/// the exact difference for the leading terms only ([`Differences::Leading`]) and the
/// cheaper kept: the F kernels and the divergence take it, the FT kernels do not
/// (sixth session of 2026-12-03).
pub fn trace<G: Green>(g: &G, spec: &KernelSpec) -> Traced {
    let first = trace_with(g, spec, Form::collecting(Collection::Entries), true);
    if g.image_terms().is_none() || spec.path == Path::Generic {
        return first;
    }
    let cost = |t: &Traced| {
        let mut ids = t.output_ids();
        if let Some(f) = &t.far {
            ids.extend(f.condition_ids());
        }
        t.graph.op_count(&ids).total()
    };
    // without images nothing singles out e3: the world frame is a candidate too
    let isotropic = g.image_terms().is_some_and(|t| t.is_empty());
    let mut best = (first, Form::collecting(Collection::Entries), true);
    for canonical in [true, false] {
        if !canonical && !isotropic {
            continue;
        }
        for collect in [
            Collection::Entries,
            Collection::EntriesOnSphere,
            Collection::Atoms,
        ] {
            if canonical && collect == Collection::Entries {
                continue; // `first`
            }
            let form = Form::collecting(collect);
            let other = trace_with(g, spec, form, canonical);
            if cost(&other) < cost(&best.0) {
                best = (other, form, canonical);
            }
        }
    }
    // near a cancelling image, the winner again with the exact difference for the
    // leading terms only
    let (best, form, canonical) = best;
    if g.cancelling_image().is_none() || spec.interaction != Interaction::Pair {
        return best;
    }
    let leading = Form {
        differences: Differences::Leading,
        ..form
    };
    let other = trace_with(g, spec, leading, canonical);
    if cost(&other) < cost(&best) {
        other
    } else {
        best
    }
}

fn trace_with<G: Green>(g: &G, spec: &KernelSpec, form: Form, canonical: bool) -> Traced {
    let t = Trace::begin();
    let mut args = Vec::new();
    let mut point = |t: &Trace, name: &str, doc: &str| -> [Ex; 3] {
        args.push(Arg {
            name: name.into(),
            kind: ArgKind::Point,
            doc: doc.into(),
        });
        std::array::from_fn(|k| t.input(&format!("{name}[{k}]")))
    };
    let (xa, xb) = match spec.interaction {
        Interaction::Pair => {
            let xa = point(
                &t,
                "xa",
                "centre of particle a (the field particle), [x1, x2, x3]",
            );
            let xb = point(&t, "xb", "centre of particle b (the source particle)");
            (xa, xb)
        }
        Interaction::SelfTerm => {
            let x = point(&t, "x", "centre of the particle");
            (x, x)
        }
    };
    let mut scalar = |t: &Trace, name: &str, doc: &str| -> Ex {
        args.push(Arg {
            name: name.into(),
            kind: ArgKind::Scalar,
            doc: doc.into(),
        });
        t.input(name)
    };
    let (aa, ab) = match (spec.interaction, spec.equal_radii) {
        (Interaction::Pair, false) => (
            scalar(&t, "aa", "radius of particle a"),
            scalar(&t, "ab", "radius of particle b"),
        ),
        _ => {
            let a = scalar(&t, "a", "radius of the particle(s)");
            (a, a)
        }
    };
    let eta = scalar(&t, "eta", "viscosity of the fluid");
    let params: Vec<Ex> = g
        .params()
        .iter()
        .map(|p| scalar(&t, p, crate::green::param_doc(p)))
        .collect();

    let order = spec.order();
    // Moment vectors of the fused product, declared before any block is traced so the
    // argument order is fixed.
    let dim = moments_len(&spec.blocks);
    let vectors = if spec.product {
        let mut v = |name: &str, doc: &str| -> Vec<Ex> {
            args.push(Arg {
                name: name.into(),
                kind: ArgKind::Vector(dim),
                doc: doc.into(),
            });
            (0..dim).map(|k| t.input(&format!("{name}[{k}]"))).collect()
        };
        let va = v(
            "va",
            "moments of particle a: force, then torque, then stresslet (as kept)",
        );
        let vb = v("vb", "moments of particle b, same layout");
        Some((va, vb))
    } else {
        None
    };
    let scale = Ex::cst(1.0 / (8.0 * std::f64::consts::PI)) / eta;
    // Pair kernels of an axisymmetric Green's function are traced in the canonical
    // frame (crate::frame) and rotated back at the end.
    let frame = (canonical
        && spec.path == Path::Structured
        && spec.interaction == Interaction::Pair
        && spec.basis == Basis::Orthonormal
        && !spec.divergence
        && g.axisymmetric())
    .then(|| Frame::of(&xa, &xb));
    let (fxa, fxb) = match &frame {
        Some((_, fa, fb)) => (*fa, *fb),
        None => (xa, xb),
    };
    let frame = frame.map(|(f, _, _)| f);
    let mut outputs = Vec::new();
    let mut far = None;
    if spec.divergence {
        outputs = divergence_outputs(g, spec, &xa, &xb, &aa, &ab, &params, order, &scale, form);
    } else {
        let values = block_values(
            g,
            spec,
            &fxa,
            &fxb,
            &aa,
            &ab,
            &params,
            order,
            form,
            Some(&scale),
        );
        for (&(r, m), vals) in spec.blocks.iter().zip(values) {
            outputs.push(BlockOut {
                name: block_name(r, m),
                block: Some((r, m)),
                shape: shape(r, m, spec.basis),
                ids: vals.into_iter().map(|v| v.0).collect(),
            });
        }
        let lateral = match (&frame, spec.interaction) {
            (Some(_), Interaction::Pair) => {
                crate::farfield::lateral(g, &spec.blocks, spec.basis, order)
            }
            _ => None,
        };
        let branch = |conds: Vec<(Ex, Ex)>, vals: Vec<Vec<Ex>>, doc: String, label| FarBranch {
            conds: conds.into_iter().map(|(l, r)| (l.0, r.0)).collect(),
            outputs: outputs
                .iter()
                .zip(vals)
                .map(|(b, vals)| BlockOut {
                    ids: vals.into_iter().map(|v| (scale * v).0).collect(),
                    ..b.clone()
                })
                .collect(),
            doc,
            label,
        };
        if let (Some(lat), Some(f)) = (lateral, &frame) {
            let height = params[0];
            let ((lhs, rhs), vals) = crate::farfield::blocks(
                &lat,
                &spec.blocks,
                (&f.rho2, &f.rho),
                (&(xa[2] - height), &(xb[2] - height)),
                &aa,
                &ab,
            );
            let doc = format!(
                "Lateral far field (`rho > {} (|h_a| + |h_b|)`, kernel_gen::farfield)",
                crate::farfield::SWITCH
            );
            far = Some(branch(vec![(lhs, rhs)], vals, doc, "far field"));
        }
        let closed = match (spec.path, spec.interaction) {
            (Path::Structured, Interaction::SelfTerm) => {
                crate::self_image::expansion(g, &spec.blocks, spec.basis, order)
            }
            _ => None,
        };
        if let Some(si) = closed {
            let (conds, vals) =
                crate::self_image::blocks(&si, g, &spec.blocks, spec.basis, &xa, &aa, &params);
            let doc = "Closed-form reflected self term (centre on the fluid side of every \
                       plane, kernel_gen::self_image)"
                .to_string();
            far = Some(branch(conds, vals, doc, "closed form"));
        }
    }
    // From the frame to the world: the products rotate the moments in and the
    // responses out; the block kernels rotate the blocks.
    let to_world = |blocks: Vec<BlockOut>| -> Vec<BlockOut> {
        match (&vectors, &frame) {
            (Some((va, vb)), _) => product_outputs(&blocks, va, vb, frame.as_ref()),
            (None, Some(f)) => blocks
                .into_iter()
                .map(|b| {
                    let (r, m) = b.block.expect("block outputs");
                    let (nr, nm) = (response_dim(r, spec.basis), moment_dim(m, spec.basis));
                    let vals: Vec<Ex> = b.ids.iter().map(|&id| Ex(id)).collect();
                    let ids = Frame::block_to_world(&vals, nr, nm, &f.c, &f.s)
                        .into_iter()
                        .map(|e| e.0)
                        .collect();
                    BlockOut { ids, ..b }
                })
                .collect(),
            (None, None) => blocks,
        }
    };
    if !spec.divergence {
        outputs = to_world(outputs);
        if let Some(f) = &mut far {
            f.outputs = to_world(std::mem::take(&mut f.outputs));
        }
    }
    let swap = match (
        spec.path,
        spec.interaction,
        spec.basis,
        g.cancelling_image(),
    ) {
        (Path::Structured, Interaction::Pair, Basis::Orthonormal, Some((plane, _))) => {
            let h = &g.planes(&params)[plane];
            let cond = ((xb[2] - *h).0, (xa[2] - *h).0);
            Some(exchange(&args, &outputs, cond))
        }
        _ => None,
    };
    let traced = Traced {
        graph: t.finish(),
        args,
        outputs,
        order,
        far,
        swap,
    };
    // pair kernels only: a self block's reciprocal entries (`U` from `S` and `E` from
    // `F`) are separate nodes that round alike, so the self blocks stay symmetric to the
    // bit, and there are only `N` of them
    if spec.interaction == Interaction::SelfTerm {
        return traced;
    }
    let mut ids = traced.output_ids();
    ids.extend(traced.far_ids());
    ids.extend(traced.far.iter().flat_map(|f| f.condition_ids()));
    ids.extend(traced.swap.iter().flat_map(|w| [w.cond.0, w.cond.1]));
    let (graph, map) = traced.graph.squares_shared(&traced.graph.live(&ids));
    traced.remapped(graph, &map)
}

/// The exchange of particles `a` and `b` ([`Swap`]) for a pair kernel with arguments
/// `args` and outputs `outputs`: arguments `xa <-> xb`, `aa <-> ab`, `va <-> vb`;
/// block `(r, m)` entry `(i, j)` from the dual block `(m*, r*)` entry `(j, i)`
/// (`U <-> F`, `Omega <-> L`, `E <-> S`); the fused products' and the divergences'
/// outputs `a <-> b`.
fn exchange(args: &[Arg], outputs: &[BlockOut], cond: (Id, Id)) -> Swap {
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

/// The direct sum of kernel `spec` evaluated straight in the scalar `S`, without an
/// expression graph: `inputs` as the traced graph's, outputs flattened as
/// [`Traced::outputs`] (blocks, or the fused products; not the divergences). In
/// double-double this is the stiff cases' reference: the graph's constants are `f64`
/// (a jet rule's weight such as 1/3 rounded, constants folded in `f64`), which leaves
/// about 1e-17 of the terms wherever they cancel, while here every rational weight is
/// exact ([`Scalar::ratio`]).
pub fn evaluate_direct<G: Green, S: Scalar>(g: &G, spec: &KernelSpec, inputs: &[S]) -> Vec<S> {
    assert!(!spec.divergence, "the divergences are traced only");
    let mut rest = inputs;
    let mut take = |n: usize| {
        let (head, tail) = rest.split_at(n);
        rest = tail;
        head.to_vec()
    };
    let point = |v: Vec<S>| -> [S; 3] { std::array::from_fn(|k| v[k].clone()) };
    let xa = point(take(3));
    let xb = match spec.interaction {
        Interaction::Pair => point(take(3)),
        Interaction::SelfTerm => xa.clone(),
    };
    let (aa, ab) = match (spec.interaction, spec.equal_radii) {
        (Interaction::Pair, false) => (take(1)[0].clone(), take(1)[0].clone()),
        _ => {
            let a = take(1)[0].clone();
            (a.clone(), a)
        }
    };
    let eta = take(1)[0].clone();
    let params = take(g.params().len());
    let order = spec.order();
    let scale = S::cst(1.0 / (8.0 * std::f64::consts::PI)) / eta;
    let values = block_values(
        g,
        spec,
        &xa,
        &xb,
        &aa,
        &ab,
        &params,
        order,
        Form::collecting(Collection::Atoms),
        Some(&scale),
    );
    let blocks = values;
    if !spec.product {
        return blocks.concat();
    }
    let n = moments_len(&spec.blocks);
    let (va, vb) = (take(n), take(n));
    let (a, b) = fused(&spec.blocks, &blocks, spec.basis, &va, &vb);
    [a, b].concat()
}

/// The fused product `a = M^{ab} vb`, `b = (M^{ab})^T va` from the entries of the
/// blocks (row-major, `values[k]` for `blocks[k]`), in the grand order of the moments
/// kept; terms are summed as they come, without adding zeros.
fn fused<S: Scalar>(
    blocks: &[(Response, Moment)],
    values: &[Vec<S>],
    basis: Basis,
    va: &[S],
    vb: &[S],
) -> (Vec<S>, Vec<S>) {
    let n = va.len();
    // [F|U (3), L|Omega (3), S|E (5)], truncated: the last five are S|E when kept.
    let offset = |k: usize| [0, 3, n.saturating_sub(5)][k];
    let mut a: Vec<Option<S>> = vec![None; n];
    let mut b: Vec<Option<S>> = vec![None; n];
    let add = |acc: &mut Option<S>, v: S| {
        *acc = Some(match acc.take() {
            None => v,
            Some(s) => s + v,
        })
    };
    for (&(r, m), vals) in blocks.iter().zip(values) {
        let (r0, c0) = (offset(r as usize), offset(m as usize));
        let cols = vals.len() / response_dim(r, basis);
        for (k, v) in vals.iter().enumerate() {
            let (i, j) = (r0 + k / cols, c0 + k % cols);
            add(&mut a[i], v.clone() * vb[j].clone());
            add(&mut b[j], v.clone() * va[i].clone());
        }
    }
    let done = |v: Vec<Option<S>>| {
        v.into_iter()
            .map(|e| e.unwrap_or_else(|| S::cst(0.0)))
            .collect()
    };
    (done(a), done(b))
}

/// The fused product from the traced blocks of `M^{ab}` ([`fused`]); with a frame, the
/// blocks are those of the frame, the moments are rotated into it and the responses
/// back.
fn product_outputs(
    blocks: &[BlockOut],
    va: &[Ex],
    vb: &[Ex],
    frame: Option<&Frame>,
) -> Vec<BlockOut> {
    let which: Vec<(Response, Moment)> = blocks
        .iter()
        .map(|b| b.block.expect("block outputs"))
        .collect();
    let values: Vec<Vec<Ex>> = blocks
        .iter()
        .map(|b| b.ids.iter().map(|&id| Ex(id)).collect())
        .collect();
    let (a, b) = match frame {
        None => fused(&which, &values, Basis::Orthonormal, va, vb),
        Some(f) => {
            let (l, s) = kept(&which);
            let parts: Vec<usize> = [Some(3), l.then_some(3), s.then_some(5)]
                .into_iter()
                .flatten()
                .collect();
            let (fa, fb) = (f.vector(va, &parts, true), f.vector(vb, &parts, true));
            let (a, b) = fused(&which, &values, Basis::Orthonormal, &fa, &fb);
            (f.vector(&a, &parts, false), f.vector(&b, &parts, false))
        }
    };
    let out = |name: &str, v: Vec<Ex>| BlockOut {
        name: name.into(),
        block: None,
        shape: vec![v.len()],
        ids: v.into_iter().map(|e| e.0).collect(),
    };
    vec![out("a", a), out("b", b)]
}

/// The derivative source for a kernel: structured when the Green's function has image
/// structure, generic otherwise.
enum Source<S> {
    Structured(Structured<S>),
    Generic(GenericJets<S>),
}

impl<S: Scalar> Source<S> {
    #[allow(clippy::too_many_arguments)]
    fn new<G: Green>(
        g: &G,
        spec: &KernelSpec,
        xa: &[S; 3],
        xb: &[S; 3],
        p: &[S],
        order: usize,
        form: Form,
        scale: Option<&S>,
    ) -> Self {
        let pair = spec.interaction == Interaction::Pair;
        if g.image_terms().is_some() && spec.path != Path::Generic {
            let explicit = spec.path != Path::StructuredNoExplicitHeight;
            let s = Structured::new(g, xa, xb, p, order, pair, explicit);
            let s = s.in_form(form);
            let s = match scale {
                Some(m) => s.scaled(m.clone()),
                None => s,
            };
            Source::Structured(if spec.path == Path::StructuredDirectSum {
                s.direct_sum()
            } else {
                s
            })
        } else {
            let part = if pair { Part::Full } else { Part::Reflected };
            Source::Generic(GenericJets::new(g, part, xa, xb, p, order))
        }
    }

    fn entry(&mut self, terms: &[operators::Term], aa2: &S, ab2: &S) -> S {
        match self {
            Source::Structured(s) => apply(terms, aa2, ab2, s),
            Source::Generic(s) => apply(terms, aa2, ab2, s),
        }
    }
}

/// Every entry of every block of `spec`, row-major, in units of `1/(8 pi eta)` (self
/// kernels include the isolated sphere), for any scalar: expression nodes for the
/// kernels, jets of expression nodes for their derivatives.
#[allow(clippy::too_many_arguments)]
fn block_values<G: Green, S: Scalar>(
    g: &G,
    spec: &KernelSpec,
    xa: &[S; 3],
    xb: &[S; 3],
    aa: &S,
    ab: &S,
    params: &[S],
    order: usize,
    form: Form,
    scale: Option<&S>,
) -> Vec<Vec<S>> {
    let mut src = Source::new(g, spec, xa, xb, params, order, form, scale);
    // the structured derivatives carry the scale themselves (`Structured::scaled`)
    let outside = match (&src, scale) {
        (Source::Generic(_), Some(s)) => Some(s),
        _ => None,
    };
    let (aa2, ab2) = (aa.clone() * aa.clone(), ab.clone() * ab.clone());
    spec.blocks
        .iter()
        .map(|&(r, m)| {
            let blk = operators::exact_block(r, m, spec.basis);
            let iso = match spec.interaction {
                Interaction::SelfTerm => Some(isolated(r, m, spec.basis, aa)),
                Interaction::Pair => None,
            };
            // the Faxén factors multiply a^2 once per kernel (shared nodes)
            let (fa2, fb2) = (
                operators::faxen_factor::<S>(blk.fa) * aa2.clone(),
                operators::faxen_factor::<S>(blk.fb) * ab2.clone(),
            );
            let mut vals = Vec::new();
            for (row, entries) in blk.entries.iter().enumerate() {
                for (col, entry) in entries.iter().enumerate() {
                    let mut v = src.entry(entry, &fa2, &fb2);
                    let n = blk.norm[row][col];
                    if n != 1.0 {
                        v = S::cst(n) * v;
                    }
                    if let Some(s) = outside {
                        v = s.clone() * v;
                    }
                    vals.push(match (&iso, scale) {
                        (Some(iso), Some(s)) => s.clone() * iso[row][col].clone() + v,
                        (Some(iso), None) => iso[row][col].clone() + v,
                        (None, _) => v,
                    });
                }
            }
            vals
        })
        .collect()
}

/// The divergence outputs of [`KernelSpec::divergence`]: the blocks evaluated on jets
/// of degree 1 in the positions (`xa` variables 0-2, `xb` 3-5; one point for self
/// kernels), then `a_i = sum_j d/dxb_j M_ij` over the force columns of the `U` and
/// `Omega` rows, and for pairs `b_i = sum_j d/dxa_j M^{ba}_ij` with
/// `M^{ba}_{UF} = (M^{ab}_{UF})^T`, `M^{ba}_{OmegaF} = (M^{ab}_{UL})^T`.
#[allow(clippy::too_many_arguments)]
fn divergence_outputs<G: Green>(
    g: &G,
    spec: &KernelSpec,
    xa: &[Ex; 3],
    xb: &[Ex; 3],
    aa: &Ex,
    ab: &Ex,
    params: &[Ex],
    order: usize,
    scale: &Ex,
    form: Form,
) -> Vec<BlockOut> {
    let pair = spec.interaction == Interaction::Pair;
    let l = Layout::get(if pair { 6 } else { 3 }, 1);
    let ja: [Jet<Ex>; 3] = std::array::from_fn(|k| Jet::variable(&l, k, xa[k]));
    let jb: [Jet<Ex>; 3] = if pair {
        std::array::from_fn(|k| Jet::variable(&l, 3 + k, xb[k]))
    } else {
        ja.clone()
    };
    let c = |e: &Ex| Jet::constant(*e);
    let jp: Vec<Jet<Ex>> = params.iter().map(c).collect();
    let values = block_values(g, spec, &ja, &jb, &c(aa), &c(ab), &jp, order, form, None);
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
    let sum3 = |f: &dyn Fn(usize) -> Ex| (0..3).map(f).fold(Ex::cst(0.0), |acc, v| acc + v);
    let uf = block(Response::U, Moment::F).expect("divergence kernels need the UF block");
    let of = block(Response::Omega, Moment::F);
    let ul = block(Response::U, Moment::L);
    let src_var = |j: usize| if pair { 3 + j } else { j };
    let mut a: Vec<Ex> = (0..3).map(|i| sum3(&|j| d(uf, i, j, src_var(j)))).collect();
    if let Some(of) = of {
        a.extend((0..3).map(|i| sum3(&|j| d(of, i, j, src_var(j)))));
    }
    let mut outs = vec![BlockOut {
        name: "a".into(),
        block: None,
        shape: vec![a.len()],
        ids: a.into_iter().map(|v| (*scale * v).0).collect(),
    }];
    if pair {
        let mut b: Vec<Ex> = (0..3).map(|i| sum3(&|j| d(uf, j, i, j))).collect();
        if of.is_some() {
            let ul = ul.expect("FT pair divergence needs the UL block");
            b.extend((0..3).map(|i| sum3(&|j| d(ul, j, i, j))));
        }
        outs.push(BlockOut {
            name: "b".into(),
            block: None,
            shape: vec![b.len()],
            ids: b.into_iter().map(|v| (*scale * v).0).collect(),
        });
    }
    outs
}

/// Truncation of the multipole expansion a scene needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Moments {
    /// Forces and velocities only.
    F,
    /// Forces and torques; velocities and angular velocities.
    FT,
    /// Forces, torques and stresslets; velocities, angular velocities and strains.
    FTS,
}

impl Moments {
    /// The blocks, in output order.
    pub fn blocks(self) -> Vec<(Response, Moment)> {
        use Moment::*;
        use Response::*;
        match self {
            Moments::F => vec![(U, F)],
            Moments::FT => vec![(U, F), (U, L), (Omega, F), (Omega, L)],
            Moments::FTS => operators::BLOCKS.to_vec(),
        }
    }

    /// Components per particle (3, 6 or 11).
    pub fn per_particle(self) -> usize {
        match self {
            Moments::F => 3,
            Moments::FT => 6,
            Moments::FTS => 11,
        }
    }

    /// Lower-case name (`f`, `ft`, `fts`).
    pub fn lower(self) -> &'static str {
        match self {
            Moments::F => "f",
            Moments::FT => "ft",
            Moments::FTS => "fts",
        }
    }
}

/// Whether a scene's particles all share one radius.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Radii {
    /// One radius: only equal-radius kernels are generated.
    Equal,
    /// Any radii: unequal-radius kernels, plus the equal-radius ones as a fast path.
    Unequal,
}

/// What a simulation needs, read from a TOML file in `scenes/`:
///
/// ```toml
/// name = "wall_f"            # identifier: functions are wall_f_self, wall_f_pair, ...
/// confinement = "wall"       # a registered Green's function
/// moments = "F"              # F, FT or FTS
/// radii = "unequal"          # equal or unequal
/// outputs = ["dense", "product"]   # block kernels, fused pair-product kernels
/// description = "..."        # optional
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Identifier, prefix of the generated functions.
    pub name: String,
    /// Name of a registered Green's function.
    pub confinement: String,
    /// Truncation.
    pub moments: Moments,
    /// Radii.
    pub radii: Radii,
    /// Generate block kernels (for dense matrices).
    pub dense: bool,
    /// Generate fused pair-product kernels (`u_a += M^{ab} x_b`, `u_b += M^{ba} x_a`).
    pub product: bool,
    /// Free text for the generated documentation.
    pub description: String,
}

/// Why a scene file cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// Not valid TOML or not the scene schema.
    #[error("{file}: {message}")]
    Parse {
        /// File name.
        file: String,
        /// What the parser said.
        message: String,
    },
    /// A field has a value outside its set.
    #[error("{file}: {field} = {value:?}: {why}")]
    Value {
        /// File name.
        file: String,
        /// Field.
        field: &'static str,
        /// Value found.
        value: String,
        /// What is allowed.
        why: String,
    },
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneToml {
    name: String,
    confinement: String,
    moments: String,
    radii: String,
    outputs: Vec<String>,
    #[serde(default)]
    description: String,
}

impl Scene {
    /// Parse a scene description; `file` names it in errors. `registered` lists the
    /// Green's functions the confinement may name.
    pub fn parse(file: &str, text: &str, registered: &[&str]) -> Result<Scene, SceneError> {
        let t: SceneToml = toml::from_str(text).map_err(|e| SceneError::Parse {
            file: file.into(),
            message: e.to_string(),
        })?;
        let bad = |field: &'static str, value: &str, why: &str| SceneError::Value {
            file: file.into(),
            field,
            value: value.into(),
            why: why.into(),
        };
        let ident_ok = !t.name.is_empty()
            && t.name
                .chars()
                .next()
                .is_some_and(|c| c.is_ascii_lowercase())
            && t.name
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
        if !ident_ok {
            return Err(bad(
                "name",
                &t.name,
                "must be a lower-case identifier (a-z, 0-9, _)",
            ));
        }
        if !registered.contains(&t.confinement.as_str()) {
            return Err(bad(
                "confinement",
                &t.confinement,
                &format!("must be one of {registered:?}"),
            ));
        }
        let moments = match t.moments.as_str() {
            "F" => Moments::F,
            "FT" => Moments::FT,
            "FTS" => Moments::FTS,
            other => return Err(bad("moments", other, "must be F, FT or FTS")),
        };
        let radii = match t.radii.as_str() {
            "equal" => Radii::Equal,
            "unequal" => Radii::Unequal,
            other => return Err(bad("radii", other, "must be equal or unequal")),
        };
        let mut dense = false;
        let mut product = false;
        for o in &t.outputs {
            match o.as_str() {
                "dense" => dense = true,
                "product" => product = true,
                other => return Err(bad("outputs", other, "entries must be dense or product")),
            }
        }
        if !dense && !product {
            return Err(bad("outputs", "[]", "ask for dense, product or both"));
        }
        Ok(Scene {
            name: t.name,
            confinement: t.confinement,
            moments,
            radii,
            dense,
            product,
            description: t.description,
        })
    }
}

#[cfg(test)]
mod scene_tests {
    use super::*;

    #[test]
    fn parses_and_rejects() {
        let ok = "name = \"wall_f\"\nconfinement = \"wall\"\nmoments = \"F\"\nradii = \"equal\"\noutputs = [\"product\"]\n";
        let s = Scene::parse("a.toml", ok, &["wall"]).unwrap();
        assert_eq!(s.moments, Moments::F);
        assert!(s.product && !s.dense);
        let e = Scene::parse("a.toml", &ok.replace("\"F\"", "\"FX\""), &["wall"]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "a.toml: moments = \"FX\": must be F, FT or FTS"
        );
        let e =
            Scene::parse("a.toml", &ok.replace("wall\"\nm", "moon\"\nm"), &["wall"]).unwrap_err();
        assert!(e.to_string().contains("confinement = \"moon\""), "{e}");
        let e = Scene::parse("a.toml", "name = 3", &["wall"]).unwrap_err();
        assert!(e.to_string().starts_with("a.toml: "), "{e}");
    }
}
