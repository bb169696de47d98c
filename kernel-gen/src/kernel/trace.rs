//! The tracing of a kernel into an expression graph.

use super::blocks::block_values;
use super::divergence::{drift_outputs, Points};
use super::product::{moments_len, product_outputs};
use super::spec::{Drift, Interaction, KernelSpec, Path};
use super::swap::exchange;
use super::traced::{Arg, ArgKind, BlockOut, FarBranch, Traced};
use crate::graph::{Ex, Trace};
use crate::number::scalar::Scalar;
use crate::physics::derivatives::{Collection, Differences, Form};
use crate::physics::frame::{Frame, Turn};
use crate::physics::green::turned::{self, Turned};
use crate::physics::green::{Green, Mat3};
use crate::physics::operators::{block_name, moment_dim, response_dim, Basis, Moment, Response};

/// `(values, rows, columns)` of a row-major block to the block rotated.
type BlockRotation<'a> = dyn Fn(&[Ex], usize, usize) -> Vec<Ex> + 'a;

fn shape(r: Response, m: Moment, b: Basis) -> Vec<usize> {
    let side = |n: usize| if n == 9 { vec![3, 3] } else { vec![n] };
    let mut s = side(response_dim(r, b));
    s.extend(side(moment_dim(m, b)));
    s
}

/// Trace kernel `spec` for Green's function `g`. With the structured path, in several
/// forms, of which the cheapest trace is kept (operations of the direct sum with its
/// branch conditions; the first of equals): each entry collected whole
/// ([`Collection::Entries`], polynomials of [`crate::number::poly`]), the same with each
/// polynomial in its cheapest form on the unit sphere ([`Collection::EntriesOnSphere`]:
/// the free-space FTS lane kernel 576 -> 565 operations, the divergence lane kernels
/// 2-6% fewer), and the atoms combined one by one ([`Collection::Atoms`]). A Green's
/// function without images (free space) is traced in the world frame as well (its pair
/// kernels otherwise in the canonical frame of [`crate::physics::frame`]): free F
/// product lanes 68 -> 58 operations, FTS pair lanes 565 -> 390. The per-centre
/// collection ([`Collection::Centres`]) is not traced: it collects a subset of what
/// `Entries` collects and costs more in every shipped kernel. Near a cancelling image
/// (the wall) the winner is traced once more with the exact difference for the leading
/// terms only ([`Differences::Leading`]) and the cheaper kept: the F kernels and the
/// divergence take it, the FT kernels do not.
///
/// A Green's function whose planes share a normal other than `e3` is traced as the
/// same confinement in its planes' own frame ([`turned`]), the points and moments
/// rotated in and the outputs rotated out: it takes the canonical frame and the lateral
/// far field like a plane normal to `e3`.
pub fn trace<G: Green>(g: &G, spec: &KernelSpec) -> Traced {
    match turned::turn(g) {
        Some(q) => trace_forms(&Turned { g, q }, spec, Some(&Turn::from_frame(&q))),
        None => trace_forms(g, spec, None),
    }
}

/// The kernel `spec` of a Green's function whose planes share a normal other than `e3`,
/// traced in its planes' frame `q` ([`turned::turn`]) and left there (points and moments
/// of that frame in, responses and blocks of that frame out): what [`trace`] rotates into
/// the world ([`crate::catalog`]'s twins compare it with other families). It
/// instantiates no generic code that [`trace`] does not.
pub fn trace_in_frame<G: Green>(g: &G, q: &Mat3<f64>, spec: &KernelSpec) -> Traced {
    trace_forms(&Turned { g, q: *q }, spec, None)
}

fn trace_forms<G: Green>(g: &G, spec: &KernelSpec, turn: Option<&Turn>) -> Traced {
    let trace_with = |g: &G, spec: &KernelSpec, form: Form, canonical: bool| {
        trace_with(g, spec, form, canonical, turn)
    };
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

fn trace_with<G: Green>(
    g: &G,
    spec: &KernelSpec,
    form: Form,
    canonical: bool,
    turn: Option<&Turn>,
) -> Traced {
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
    // the points in the frame of the planes
    let (xa, xb) = match turn {
        Some(q) => (q.point(&xa), q.point(&xb)),
        None => (xa, xb),
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
        .map(|p| scalar(&t, p.name, p.doc))
        .collect();

    // the direction of a derivative along a vector, after the parameters
    let along = matches!(spec.drift, Some(Drift::Along | Drift::Together)).then(|| {
        args.push(Arg {
            name: "v".into(),
            kind: ArgKind::Point,
            doc: "the direction of the derivative, a unit vector".into(),
        });
        let v: [Ex; 3] = std::array::from_fn(|k| t.input(&format!("v[{k}]")));
        match turn {
            Some(q) => q.point(&v),
            None => v,
        }
    });
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
    // frame (crate::physics::frame) and rotated back at the end.
    let frame = (canonical
        && spec.path == Path::Structured
        && spec.interaction == Interaction::Pair
        && spec.basis == Basis::Orthonormal
        && spec.drift.is_none()
        && g.axisymmetric())
    .then(|| Frame::of(&xa, &xb));
    let (fxa, fxb) = match &frame {
        Some((_, fa, fb)) => (*fa, *fb),
        None => (xa, xb),
    };
    let frame = frame.map(|(f, _, _)| f);
    let mut outputs = Vec::new();
    let mut far = None;
    if let Some(drift) = spec.drift {
        let at = Points {
            xa: &xa,
            xb: &xb,
            aa: &aa,
            ab: &ab,
            v: along.as_ref(),
        };
        outputs = drift_outputs(g, spec, drift, &at, &params, order, &scale, form);
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
                crate::physics::farfield::lateral(g, &spec.blocks, spec.basis, order)
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
            let m = &g.mirrors(&params)[0];
            let ((lhs, rhs), vals) = crate::physics::farfield::blocks(
                &lat,
                &spec.blocks,
                (&f.rho2, &f.rho),
                (&m.distance(&xa), &m.distance(&xb)),
                &aa,
                &ab,
            );
            let doc = format!(
                "Lateral far field (`rho > {} (|h_a| + |h_b|)`, kernel_gen::physics::farfield)",
                crate::physics::farfield::SWITCH
            );
            far = Some(branch(vec![(lhs, rhs)], vals, doc, "far field"));
        }
        let closed = match (spec.path, spec.interaction) {
            (Path::Structured, Interaction::SelfTerm) => {
                crate::physics::self_image::expansion(g, &spec.blocks, spec.basis, order)
            }
            _ => None,
        };
        if let Some(si) = closed {
            let (conds, vals) = crate::physics::self_image::blocks(
                &si,
                g,
                &spec.blocks,
                spec.basis,
                &xa,
                &aa,
                &params,
            );
            let doc = "Closed-form reflected self term (centre on the fluid side of every \
                       plane, kernel_gen::physics::self_image)"
                .to_string();
            far = Some(branch(conds, vals, doc, "closed form"));
        }
    }
    // From the frame to the world: the products rotate the moments in and the
    // responses out; the block kernels rotate the blocks.
    // each block `B` to `Q_r B Q_m^T`, by `rotate(values, rows, columns)`
    let rotated = |blocks: Vec<BlockOut>, rotate: &BlockRotation| {
        blocks
            .into_iter()
            .map(|b| {
                let (r, m) = b.block.expect("block outputs");
                let (nr, nm) = (response_dim(r, spec.basis), moment_dim(m, spec.basis));
                let vals: Vec<Ex> = b.ids.iter().map(|&id| Ex(id)).collect();
                let ids = rotate(&vals, nr, nm).into_iter().map(|e| e.0).collect();
                BlockOut { ids, ..b }
            })
            .collect::<Vec<_>>()
    };
    let to_world = |blocks: Vec<BlockOut>| -> Vec<BlockOut> {
        let blocks = match (&vectors, &frame) {
            (Some((va, vb)), _) => return product_outputs(&blocks, va, vb, frame.as_ref(), turn),
            (None, Some(f)) => rotated(blocks, &|v, nr, nm| {
                Frame::block_to_world(v, nr, nm, &f.c, &f.s)
            }),
            (None, None) => blocks,
        };
        // from the frame of the planes
        match turn {
            Some(q) => rotated(blocks, &|v, nr, nm| q.block_to_world(v, nr, nm)),
            None => blocks,
        }
    };
    if spec.drift.is_none() {
        outputs = to_world(outputs);
        if let Some(f) = &mut far {
            f.outputs = to_world(std::mem::take(&mut f.outputs));
        }
    } else if let Some(q) = turn {
        // the drift's velocities (and angular velocities) back to the world
        for b in &mut outputs {
            let vals: Vec<Ex> = b.ids.iter().map(|&id| Ex(id)).collect();
            let parts = vec![3; vals.len() / 3];
            b.ids = q
                .vector(&vals, &parts, false)
                .into_iter()
                .map(|e| e.0)
                .collect();
        }
    }
    let swap = match (
        spec.path,
        spec.interaction,
        spec.basis,
        g.cancelling_image(),
    ) {
        (Path::Structured, Interaction::Pair, Basis::Orthonormal, Some((plane, _))) => {
            let m = &g.mirrors(&params)[plane];
            let cond = (m.distance(&xb).0, m.distance(&xa).0);
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
