//! What a kernel computes: which confinement, self or pair, which blocks, in which
//! strain basis, for equal or unequal radii; and the tracing of such a kernel into an
//! expression graph with named inputs and block-shaped outputs.
//!
//! Pair kernels (particles `a != b`) are `M^{ab}` from `G = J + J^w` (Eq. 16); self
//! kernels are the isolated sphere plus the reflected field only (Eq. 17). All blocks
//! are dimensional: the Green's functions in units of `1/(8 pi eta)` are scaled by
//! `1/(8 pi eta)` as the last step.

use crate::derivatives::{GenericJets, Part, Structured};
use crate::expr::{Ex, Graph, Id, Trace};
use crate::green::Green;
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
}

/// Shape of a kernel argument.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArgKind {
    /// `[f64; 3]`.
    Point,
    /// `f64`.
    Scalar,
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
    /// Response and moment.
    pub block: (Response, Moment),
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
}

impl Traced {
    /// All output ids in order.
    pub fn output_ids(&self) -> Vec<Id> {
        self.outputs
            .iter()
            .flat_map(|b| b.ids.iter().copied())
            .collect()
    }
}

fn shape(r: Response, m: Moment, b: Basis) -> Vec<usize> {
    let side = |n: usize| if n == 9 { vec![3, 3] } else { vec![n] };
    let mut s = side(response_dim(r, b));
    s.extend(side(moment_dim(m, b)));
    s
}

/// Trace kernel `spec` for Green's function `g`.
pub fn trace<G: Green>(g: &G, spec: &KernelSpec) -> Traced {
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

    let order = spec
        .blocks
        .iter()
        .map(|&(r, m)| max_order(r, m))
        .max()
        .unwrap_or(0);
    let mut src = Source::new(g, spec, &xa, &xb, &params, order);
    let (aa2, ab2) = (aa * aa, ab * ab);
    let scale = Ex::cst(1.0 / (8.0 * std::f64::consts::PI)) / eta;
    let mut outputs = Vec::new();
    for &(r, m) in &spec.blocks {
        let terms = operators::block(r, m, spec.basis);
        let iso = match spec.interaction {
            Interaction::SelfTerm => Some(isolated(r, m, spec.basis, &aa)),
            Interaction::Pair => None,
        };
        let mut ids = Vec::new();
        for (row, entries) in terms.iter().enumerate() {
            for (col, entry) in entries.iter().enumerate() {
                let mut v = src.entry(entry, &aa2, &ab2);
                if let Some(iso) = &iso {
                    v = iso[row][col] + v;
                }
                ids.push((scale * v).0);
            }
        }
        outputs.push(BlockOut {
            name: block_name(r, m),
            block: (r, m),
            shape: shape(r, m, spec.basis),
            ids,
        });
    }
    drop(src);
    Traced {
        graph: t.finish(),
        args,
        outputs,
    }
}

/// The derivative source for a kernel: structured when the Green's function has image
/// structure, generic otherwise.
enum Source {
    Structured(Structured<Ex>),
    Generic(GenericJets<Ex>),
}

impl Source {
    fn new<G: Green>(
        g: &G,
        spec: &KernelSpec,
        xa: &[Ex; 3],
        xb: &[Ex; 3],
        p: &[Ex],
        order: usize,
    ) -> Self {
        let pair = spec.interaction == Interaction::Pair;
        if g.image_terms().is_some() && spec.path != Path::Generic {
            let explicit = spec.path != Path::StructuredNoExplicitHeight;
            Source::Structured(Structured::new(g, xa, xb, p, order, pair, explicit))
        } else {
            let part = if pair { Part::Full } else { Part::Reflected };
            Source::Generic(GenericJets::new(g, part, xa, xb, p, order))
        }
    }

    fn entry(&mut self, terms: &[operators::Term], aa2: &Ex, ab2: &Ex) -> Ex {
        match self {
            Source::Structured(s) => apply(terms, aa2, ab2, s),
            Source::Generic(s) => apply(terms, aa2, ab2, s),
        }
    }
}
